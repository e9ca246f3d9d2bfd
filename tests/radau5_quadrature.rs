//! `Options::quadrature`: components that enter no right-hand side are solved by forward
//! substitution instead of being factorised (block lower-triangular E1, E2). The results
//! must match the closed-form solution, with analytic and difference Jacobians, with and
//! without a mass matrix; bad declarations must be rejected.

use geared_rotor::radau5::{Error, JacobianMode, Options, Problem, Radau5, RhsError, Tolerance};
use nalgebra::{SMatrix, SVector};

/// y = (a, q1, b, q2): a' = -50 a, b' = -2 b + a, q1' = a^2, q2' = b; the quadratures sit
/// between the other components to exercise the index mapping.
struct Linear {
    with_jac: bool,
    mass: Option<SMatrix<f64, 4, 4>>,
}

impl Problem<4> for Linear {
    fn rhs(
        &mut self,
        _t: f64,
        y: &SVector<f64, 4>,
        f: &mut SVector<f64, 4>,
    ) -> Result<(), RhsError> {
        f[0] = -50.0 * y[0];
        f[1] = y[0] * y[0];
        f[2] = -2.0 * y[2] + y[0];
        f[3] = y[2];
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        y: &SVector<f64, 4>,
        j: &mut SMatrix<f64, 4, 4>,
    ) -> Result<bool, RhsError> {
        if !self.with_jac {
            return Ok(false);
        }
        j.fill(0.0);
        j[(0, 0)] = -50.0;
        j[(1, 0)] = 2.0 * y[0];
        j[(2, 2)] = -2.0;
        j[(2, 0)] = 1.0;
        j[(3, 2)] = 1.0;
        Ok(true)
    }
    fn mass(&self) -> Option<SMatrix<f64, 4, 4>> {
        self.mass
    }
}

/// Closed form at t for y(0) = (1, 0, 1, 0).
fn exact(t: f64) -> [f64; 4] {
    let a = (-50.0 * t).exp();
    let c = 1.0 + 1.0 / 48.0;
    let b = c * (-2.0 * t).exp() - a / 48.0;
    let q1 = (1.0 - (-100.0 * t).exp()) / 100.0;
    let q2 = c * (1.0 - (-2.0 * t).exp()) / 2.0 - (1.0 - a) / 2400.0;
    [a, q1, b, q2]
}

fn options(quad: bool, jac: JacobianMode) -> Options<4> {
    Options {
        rtol: Tolerance::Scalar(1e-9),
        atol: Tolerance::Scalar(1e-12),
        jacobian: jac,
        quadrature: [false, quad, false, quad],
        ..Options::default()
    }
}

fn run(p: &mut Linear, o: Options<4>) -> Radau5<4> {
    let y0 = SVector::<f64, 4>::new(1.0, 0.0, 1.0, 0.0);
    let mut s = Radau5::new(p, o, 0.0, y0).expect("valid options");
    // Many stop times, as a co-simulation master would.
    for k in 1..=20 {
        s.integrate_to(p, 0.05 * f64::from(k)).expect("integrates");
    }
    s
}

#[test]
fn quadratures_match_the_closed_form() {
    let mass = Some(SMatrix::<f64, 4, 4>::identity());
    for (with_jac, jac) in [
        (true, JacobianMode::Analytic),
        (false, JacobianMode::Analytic),
        (true, JacobianMode::FiniteDifference),
    ] {
        for m in [None, mass] {
            let mut p = Linear { with_jac, mass: m };
            let full = run(&mut p, options(false, jac));
            let quad = run(&mut p, options(true, jac));
            let e = exact(1.0);
            for (i, &ei) in e.iter().enumerate() {
                let scale = 1e-9 * ei.abs() + 1e-12;
                let err_q = (quad.y()[i] - ei).abs();
                let err_f = (full.y()[i] - ei).abs();
                assert!(
                    err_q < 100.0 * scale,
                    "component {i}: quadrature path error {err_q:e} (full LU {err_f:e}), jac {jac:?} {with_jac}, mass {}",
                    m.is_some()
                );
            }
            // Same method, only the linear algebra differs: similar work.
            let (sq, sf) = (quad.stats(), full.stats());
            assert!(
                sq.naccpt.abs_diff(sf.naccpt) <= 2 + sf.naccpt / 20
                    && sq.nsol.abs_diff(sf.nsol) <= 2 + sf.nsol / 10,
                "{sq:?} vs {sf:?}"
            );
        }
    }
}

#[test]
fn bad_quadrature_declarations_are_rejected() {
    let y0 = SVector::<f64, 4>::new(1.0, 0.0, 1.0, 0.0);
    // Non-identity mass row of a declared quadrature.
    let mut m = SMatrix::<f64, 4, 4>::identity();
    m[(1, 1)] = 2.0;
    let mut p = Linear {
        with_jac: true,
        mass: Some(m),
    };
    let r = Radau5::new(&mut p, options(true, JacobianMode::Analytic), 0.0, y0);
    assert!(matches!(
        r,
        Err(Error::InvalidOption {
            name: "quadrature",
            ..
        })
    ));
    // Coupled through M (off-diagonal entry in the quadrature's column).
    let mut m = SMatrix::<f64, 4, 4>::identity();
    m[(0, 3)] = 0.5;
    p.mass = Some(m);
    let r = Radau5::new(&mut p, options(true, JacobianMode::Analytic), 0.0, y0);
    assert!(r.is_err());
    // A quadrature must be an index-1 component.
    p.mass = None;
    let o = Options {
        n1: 3,
        n2: 1,
        ..options(true, JacobianMode::Analytic)
    };
    let r = Radau5::new(&mut p, o, 0.0, y0);
    assert!(matches!(
        r,
        Err(Error::InvalidOption {
            name: "quadrature",
            ..
        })
    ));
}

/// Damped oscillator x' = v, v' = -k x - c v, plus q' = v^2 (a quadrature):
/// y = (x, v, q) with the second-order structure (m1, m2) = (1, 1).
struct Oscillator {
    k: f64,
    c: f64,
    with_jac: bool,
    mass: Option<SMatrix<f64, 3, 3>>,
}

impl Problem<3> for Oscillator {
    fn rhs(
        &mut self,
        _t: f64,
        y: &SVector<f64, 3>,
        f: &mut SVector<f64, 3>,
    ) -> Result<(), RhsError> {
        f[0] = y[1];
        f[1] = -self.k * y[0] - self.c * y[1];
        f[2] = y[1] * y[1];
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        y: &SVector<f64, 3>,
        j: &mut SMatrix<f64, 3, 3>,
    ) -> Result<bool, RhsError> {
        if !self.with_jac {
            return Ok(false);
        }
        j.fill(0.0);
        j[(0, 1)] = 1.0;
        j[(1, 0)] = -self.k;
        j[(1, 1)] = -self.c;
        j[(2, 1)] = 2.0 * y[1];
        Ok(true)
    }
    fn mass(&self) -> Option<SMatrix<f64, 3, 3>> {
        self.mass
    }
}

#[test]
fn second_order_elimination_matches_closed_form_and_energy_balance() {
    let (k, c) = (1.0e4, 20.0);
    // Underdamped: x = e^(-z w t) (cos(wd t) + z w / wd sin(wd t)), x(0) = 1, v(0) = 0.
    let w = f64::sqrt(k);
    let zw = c / 2.0;
    let wd = (w * w - zw * zw).sqrt();
    let t_end = 0.3;
    let x_exact = (-zw * t_end).exp() * ((wd * t_end).cos() + zw / wd * (wd * t_end).sin());
    let v_exact = -(-zw * t_end).exp() * (w * w / wd) * (wd * t_end).sin();
    // Energy balance: d/dt (v^2/2 + k x^2/2) = -c v^2, so int v^2 = (E0 - E)/c.
    let q_exact = (0.5 * k - 0.5 * v_exact * v_exact - 0.5 * k * x_exact * x_exact) / c;
    for (with_jac, jac) in [
        (true, JacobianMode::Analytic),
        (true, JacobianMode::FiniteDifference),
    ] {
        for mass in [None, Some(SMatrix::<f64, 3, 3>::identity())] {
            let mut p = Oscillator {
                k,
                c,
                with_jac,
                mass,
            };
            let o = |structured: bool| Options {
                rtol: Tolerance::Scalar(1e-10),
                atol: Tolerance::Scalar(1e-12),
                jacobian: jac,
                quadrature: [false, false, structured],
                second_order: structured.then_some((1, 1)),
                ..Options::default()
            };
            let y0 = SVector::<f64, 3>::new(1.0, 0.0, 0.0);
            let mut full = Radau5::new(&mut p, o(false), 0.0, y0).expect("valid");
            full.integrate_to(&mut p, t_end).expect("integrates");
            let mut red = Radau5::new(&mut p, o(true), 0.0, y0).expect("valid");
            red.integrate_to(&mut p, t_end).expect("integrates");
            let y = red.y();
            let errs = [
                (y[0] - x_exact).abs(),
                (y[1] - v_exact).abs() / w,
                (y[2] - q_exact).abs() / q_exact,
            ];
            for e in errs {
                assert!(
                    e < 1e-7,
                    "errors {errs:?}, jac {jac:?}, mass {}",
                    mass.is_some()
                );
            }
            let (sr, sf) = (red.stats(), full.stats());
            assert!(
                sr.naccpt.abs_diff(sf.naccpt) <= 2 + sf.naccpt / 20
                    && sr.nsol.abs_diff(sf.nsol) <= 2 + sf.nsol / 10,
                "{sr:?} vs {sf:?}"
            );
        }
    }
    // Partners must come after the eliminated block.
    let mut p = Oscillator {
        k,
        c,
        with_jac: true,
        mass: None,
    };
    let o = Options {
        second_order: Some((2, 1)),
        ..Options::default()
    };
    assert!(matches!(
        Radau5::new(&mut p, o, 0.0, SVector::<f64, 3>::new(1.0, 0.0, 0.0)),
        Err(Error::InvalidOption {
            name: "second_order",
            ..
        })
    ));
}

/// y = (a, b) of `Linear` without its quadratures, for the norm-count check.
struct Pair;

impl Problem<2> for Pair {
    fn rhs(
        &mut self,
        _t: f64,
        y: &SVector<f64, 2>,
        f: &mut SVector<f64, 2>,
    ) -> Result<(), RhsError> {
        f[0] = -50.0 * y[0];
        f[1] = -2.0 * y[1] + y[0];
        Ok(())
    }
}

/// (a, b, z) with z' = 0 from z(0) = 0: a component that stays zero.
struct PairAndZero;

impl Problem<3> for PairAndZero {
    fn rhs(
        &mut self,
        _t: f64,
        y: &SVector<f64, 3>,
        f: &mut SVector<f64, 3>,
    ) -> Result<(), RhsError> {
        f[0] = -50.0 * y[0];
        f[1] = -2.0 * y[1] + y[0];
        f[2] = 0.0;
        Ok(())
    }
}

/// `Options::norm_count`: a quadrature that stays zero, left out of the norms
/// (norm_count = 2 of 3), gives the steps of the system without it and its values;
/// counted (the default 3), it makes the norms smaller and the steps different. Out of
/// range counts are refused.
#[test]
fn norm_count_leaves_a_zero_component_out_of_the_norms() {
    let o2 = Options::<2> {
        rtol: Tolerance::Scalar(1e-6),
        atol: Tolerance::Scalar(1e-9),
        jacobian: JacobianMode::FiniteDifference,
        ..Options::default()
    };
    let o3 = |count: usize| Options::<3> {
        rtol: Tolerance::Scalar(1e-6),
        atol: Tolerance::Scalar(1e-9),
        jacobian: JacobianMode::FiniteDifference,
        quadrature: [false, false, true],
        norm_count: count,
        ..Options::default()
    };
    let mut p2 = Pair;
    let mut s2 = Radau5::new(&mut p2, o2, 0.0, SVector::<f64, 2>::new(1.0, 1.0)).unwrap();
    s2.integrate_to(&mut p2, 1.0).unwrap();
    let run3 = |count: usize| {
        let mut p3 = PairAndZero;
        let y0 = SVector::<f64, 3>::new(1.0, 1.0, 0.0);
        let mut s3 = Radau5::new(&mut p3, o3(count), 0.0, y0).unwrap();
        s3.integrate_to(&mut p3, 1.0).unwrap();
        s3
    };
    let left_out = run3(2);
    let counted = run3(3);
    println!(
        "2 components: {}; 3 with norm_count 2: {}; with 3: {}",
        s2.stats(),
        left_out.stats(),
        counted.stats()
    );
    assert_eq!(left_out.stats().naccpt, s2.stats().naccpt);
    assert_eq!(left_out.stats().nrejct, s2.stats().nrejct);
    // (The same steps; the values to rounding: a quadrature block is eliminated by
    // forward substitution, which rounds differently from one LU of the whole system.)
    for i in 0..2 {
        assert!((left_out.y()[i] - s2.y()[i]).abs() <= 1e-15, "{i}");
    }
    assert_eq!(left_out.y()[2], 0.0);
    assert_ne!(counted.stats().nstep, s2.stats().nstep);
    for bad in [0usize, 4] {
        let mut p3 = PairAndZero;
        let r = Radau5::new(&mut p3, o3(bad), 0.0, SVector::<f64, 3>::zeros());
        assert!(
            matches!(
                r,
                Err(Error::InvalidOption {
                    name: "norm_count",
                    ..
                })
            ),
            "{bad}"
        );
    }
}
