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
