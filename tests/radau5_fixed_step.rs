//! Fixed-step RADAU5 (`Radau5::fixed_prepare`, `Radau5::fixed_step`) against exact
//! solutions: the 3-stage Radau IIA collocation is of order 5 at the step ends (Hairer &
//! Wanner, Solving ODEs II, 1996, Table IV.5.2: order 2s - 1), so halving h divides the
//! error by ~32; a stiff linear system converges in the fixed Newton count (its Jacobian
//! is exact); and a step too long for its Newton count is refused with the state kept.

use geared_rotor::radau5::{Error, Options, Problem, Radau5, RhsError};
use nalgebra::{SMatrix, SVector};

/// y1' = y2, y2' = -y1 (harmonic oscillator, nonstiff) plus y3' = -1000 (y3 - cos t)
/// (stiff, smooth solution); y1 = cos t, y2 = -sin t from (1, 0).
struct Oscillator;

impl Problem<3> for Oscillator {
    fn rhs(
        &mut self,
        t: f64,
        y: &SVector<f64, 3>,
        f: &mut SVector<f64, 3>,
    ) -> Result<(), RhsError> {
        f[0] = y[1];
        f[1] = -y[0];
        f[2] = -1000.0 * (y[2] - t.cos());
        Ok(())
    }
}

fn error_at_1(n: u32, jacobian_every_step: bool) -> (f64, u64) {
    let mut p = Oscillator;
    let y0 = SVector::<f64, 3>::new(1.0, 0.0, 1.0);
    let mut r = Radau5::new(&mut p, Options::default(), 0.0, y0).unwrap();
    let h = 1.0 / f64::from(n);
    r.fixed_prepare(&mut p, h).unwrap();
    for k in 1..=n {
        if jacobian_every_step {
            r.fixed_prepare(&mut p, h).unwrap();
        }
        let t_end = if k == n { 1.0 } else { f64::from(k) * h };
        r.fixed_step(&mut p, h, t_end, 3).unwrap();
    }
    assert_eq!(r.t(), 1.0);
    let y = r.y();
    let e = ((y[0] - 1f64.cos()).powi(2) + (y[1] + 1f64.sin()).powi(2)).sqrt();
    (e, r.stats().nfcn)
}

#[test]
fn fixed_steps_converge_with_order_five() {
    let (e1, w1) = error_at_1(10, false);
    let (e2, _) = error_at_1(20, false);
    let (e3, _) = error_at_1(40, false);
    // 1 evaluation at construction + 3 per Newton iteration, 3 iterations per step.
    assert_eq!(w1, 1 + 10 * 9);
    for (a, b) in [(e1, e2), (e2, e3)] {
        let order = (a / b).log2();
        assert!(
            (4.6..=5.4).contains(&order),
            "observed order {order} ({a:e} -> {b:e})"
        );
    }
    // A linear problem: the Jacobian of the start is exact everywhere, renewing it changes
    // nothing but the count.
    let (e4, _) = error_at_1(20, true);
    assert!((e4 - e2).abs() <= 1e-3 * e2, "{e4:e} vs {e2:e}");
}

/// y' = -y^2 / eps from 1 with a stale Jacobian: contraction too slow for 3 iterations at
/// a long step, the step is refused with FixedStepNewton and t stays at its start.
struct Quadratic;

impl Problem<1> for Quadratic {
    fn rhs(
        &mut self,
        _t: f64,
        y: &SVector<f64, 1>,
        f: &mut SVector<f64, 1>,
    ) -> Result<(), RhsError> {
        f[0] = -1e3 * y[0] * y[0];
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        _y: &SVector<f64, 1>,
        jac: &mut SMatrix<f64, 1, 1>,
    ) -> Result<bool, RhsError> {
        // Deliberately wrong (10 % of the true -2e3 y at y = 1): a poor simplified Newton.
        jac[(0, 0)] = -200.0;
        Ok(true)
    }
}

#[test]
fn unconverged_fixed_step_is_refused() {
    let mut p = Quadratic;
    let y0 = SVector::<f64, 1>::new(1.0);
    let mut r = Radau5::new(&mut p, Options::default(), 0.0, y0).unwrap();
    r.fixed_prepare(&mut p, 0.1).unwrap();
    let e = r.fixed_step(&mut p, 0.1, 0.1, 3).unwrap_err();
    assert!(
        matches!(e, Error::FixedStepNewton { t, iterations: 3, .. } if t == 0.0),
        "{e:?}"
    );
    assert_eq!((r.t(), r.y()[0]), (0.0, 1.0));
    // Fewer than 2 iterations and a step size other than the LU pair's are refused.
    assert!(matches!(
        r.fixed_step(&mut p, 0.1, 0.1, 1),
        Err(Error::InvalidOption { .. })
    ));
    assert!(matches!(
        r.fixed_step(&mut p, 0.05, 0.05, 3),
        Err(Error::InvalidOption { .. })
    ));
}

/// y' = t^4 (a pure quadrature): the three Radau IIA nodes integrate polynomials of degree
/// <= 2s - 2 = 4 exactly (Hairer & Wanner, Solving ODEs II, 1996, Section IV.5), so the fixed
/// step ends on y(1) = 1/5 to round-off - only if every stage is evaluated at its own time
/// t + c_k h (the oscillator above does not see the stage times of its t-dependent part).
struct QuarticQuadrature;

impl Problem<1> for QuarticQuadrature {
    fn rhs(
        &mut self,
        t: f64,
        _y: &SVector<f64, 1>,
        f: &mut SVector<f64, 1>,
    ) -> Result<(), RhsError> {
        f[0] = t.powi(4);
        Ok(())
    }
}

#[test]
fn fixed_steps_evaluate_each_stage_at_its_time() {
    let mut p = QuarticQuadrature;
    let mut r = Radau5::new(&mut p, Options::default(), 0.0, SVector::zeros()).unwrap();
    let n = 4;
    let h = 1.0 / f64::from(n);
    r.fixed_prepare(&mut p, h).unwrap();
    for k in 1..=n {
        r.fixed_step(&mut p, h, f64::from(k) * h, 3).unwrap();
    }
    assert!((r.y()[0] - 0.2).abs() <= 1e-14, "y(1) = {:e}", r.y()[0]);
}
