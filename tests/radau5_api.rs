//! Step-based API of the RADAU5 stepper (issue 3, tests 1, 3, 4, 5): dense output,
//! snapshots, stop times without restart, typed errors.

mod common;

use common::radau5::{check_snapshots_continue, opts, pendulum2, pendulum2_opts};
use common::radau5_problems::{Robertson, VanDerPol};
use geared_rotor::radau5::{
    Error, Options, Problem, Radau5, Retake, RhsError, Snapshot, SnapshotError, Tolerance,
};
use nalgebra::{SMatrix, SVector};

/// Harmonic oscillator y1' = y2, y2' = -y1 (linear: simplified Newton with the exact
/// Jacobian solves the collocation equations to round-off in one iteration).
struct Harmonic;

impl Problem<2> for Harmonic {
    fn rhs(
        &mut self,
        _t: f64,
        y: &SVector<f64, 2>,
        f: &mut SVector<f64, 2>,
    ) -> Result<(), RhsError> {
        f[0] = y[1];
        f[1] = -y[0];
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        _y: &SVector<f64, 2>,
        j: &mut SMatrix<f64, 2, 2>,
    ) -> Result<bool, RhsError> {
        *j = SMatrix::<f64, 2, 2>::new(0.0, 1.0, -1.0, 0.0);
        Ok(true)
    }
}

/// radau5.md §6: the dense output is the collocation polynomial: it passes through y_n
/// and y_{n+1}, and satisfies u'(t_n + c_k h) = f(u(t_n + c_k h)) at the Radau nodes.
#[test]
fn dense_output_is_the_collocation_polynomial() {
    let mut p = Harmonic;
    let y0 = SVector::<f64, 2>::new(1.0, 0.0);
    let mut s = Radau5::new(&mut p, opts(1e-8), 0.0, y0).unwrap();
    let s6 = 6.0f64.sqrt();
    let nodes = [(4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0];
    for _ in 0..20 {
        let y_prev = *s.y();
        let t = s.step(&mut p, 10.0).unwrap();
        let (t0, h) = (s.t_prev(), t - s.t_prev());
        let mut u = SVector::zeros();
        s.dense_output(t0, &mut u);
        assert!((u - y_prev).norm() <= 1e-13, "u(t_n) = {u:?} vs {y_prev:?}");
        s.dense_output(t, &mut u);
        assert!((u - s.y()).norm() <= 1e-15);
        for c in nodes {
            let tk = t0 + c * h;
            let mut du = SVector::zeros();
            let mut f = SVector::zeros();
            s.dense_output(tk, &mut u);
            s.dense_derivative(tk, &mut du);
            p.rhs(tk, &u, &mut f).unwrap();
            assert!(
                (du - f).norm() <= 1e-9 * (1.0 + f.norm()),
                "t {tk}: u' {du:?} f {f:?}"
            );
            // and it is close to the exact solution (cos t, -sin t)
            assert!((u[0] - tk.cos()).abs() < 1e-6);
        }
    }
}

/// The dense output reproduces the stage values: `Y_k = u(t_n + c_k h)` satisfy the
/// Radau IIA stage equations `Y_k = y_n + h sum_j a_kj f(Y_j)` (A from radau5.md §1, not
/// from the code's transformed form), here on a nonlinear stiff problem (van der Pol) where
/// they hold to the Newton tolerance.
#[test]
fn dense_output_reproduces_the_stage_values() {
    use geared_rotor::radau5::tableau::Tableau;
    let a = Tableau::butcher_a();
    let s6 = 6.0f64.sqrt();
    let nodes = [(4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0];
    let mut p = VanDerPol { eps: 1e-3 };
    let tol = 1e-10;
    let mut s = Radau5::new(&mut p, opts(tol), 0.0, SVector::<f64, 2>::new(2.0, 0.0)).unwrap();
    for _ in 0..50 {
        let y_n = *s.y();
        let t = s.step(&mut p, 1.0).unwrap();
        let (t0, h) = (s.t_prev(), t - s.t_prev());
        let mut stage = [SVector::<f64, 2>::zeros(); 3];
        let mut f = [SVector::<f64, 2>::zeros(); 3];
        for k in 0..3 {
            s.dense_output(t0 + nodes[k] * h, &mut stage[k]);
            p.rhs(t0 + nodes[k] * h, &stage[k], &mut f[k]).unwrap();
        }
        assert_eq!(stage[2], *s.y(), "stiffly accurate: Y_3 = y_n+1");
        for k in 0..3 {
            let rk = y_n + h * (a[k][0] * f[0] + a[k][1] * f[1] + a[k][2] * f[2]);
            // Newton stops at kappa * sc (radau5.md §3/§4), sc = rtol' (1 + |y|); the
            // residual of the stage equations is that times ||I - h A J|| (a few units).
            let rtol_t = 0.1 * tol.powf(2.0 / 3.0);
            let kappa = (10.0 * 1e-16 / rtol_t).max(0.03f64.min(rtol_t.sqrt()));
            let bound = 100.0 * kappa * rtol_t * (1.0 + y_n.norm());
            let res = (stage[k] - rk).norm();
            assert!(res <= bound, "stage {k}: {res:e} > {bound:e}");
            // not trivially small: the stage increments are far larger
            assert!((stage[k] - y_n).norm() > 1e3 * bound || h < 1e-6);
        }
    }
}

/// Run from a snapshot twice: bit-identical; bytes round trip bit-identically.
#[test]
fn snapshot_restores_bit_identically() {
    let mut p = VanDerPol { eps: 1e-6 };
    let y0 = SVector::<f64, 2>::new(2.0, 0.0);
    let mut s = Radau5::new(&mut p, opts(1e-6), 0.0, y0).unwrap();
    s.integrate_to(&mut p, 0.5).unwrap();
    let snap = s.snapshot();
    s.integrate_to(&mut p, 1.5).unwrap();
    let (y_a, st_a, h_a) = (*s.y(), *s.stats(), s.h());

    s.restore(&snap);
    s.integrate_to(&mut p, 1.5).unwrap();
    assert_eq!(s.y()[0].to_bits(), y_a[0].to_bits());
    assert_eq!(s.y()[1].to_bits(), y_a[1].to_bits());
    assert_eq!(*s.stats(), st_a);
    assert_eq!(s.h().to_bits(), h_a.to_bits());

    // bytes
    let bytes = snap.to_bytes();
    assert_eq!(bytes.len(), Snapshot::<2>::serialized_len());
    let back = Snapshot::<2>::from_bytes(&bytes).unwrap();
    assert_eq!(back.to_bytes(), bytes);
    let mut s2 = Radau5::new(&mut p, opts(1e-3), 0.0, SVector::zeros()).unwrap();
    s2.restore(&back);
    s2.integrate_to(&mut p, 1.5).unwrap();
    assert_eq!(s2.y()[0].to_bits(), y_a[0].to_bits());
    assert_eq!(s2.y()[1].to_bits(), y_a[1].to_bits());
    assert_eq!(*s2.stats(), st_a);
}

#[test]
fn corrupted_foreign_or_truncated_snapshots_are_errors() {
    let mut p = VanDerPol { eps: 1e-6 };
    let mut s = Radau5::new(&mut p, opts(1e-6), 0.0, SVector::<f64, 2>::new(2.0, 0.0)).unwrap();
    s.integrate_to(&mut p, 0.1).unwrap();
    let bytes = s.snapshot().to_bytes();
    // every single flipped byte is detected
    for i in 0..bytes.len() {
        let mut b = bytes.clone();
        b[i] ^= 0x5a;
        assert!(
            Snapshot::<2>::from_bytes(&b).is_err(),
            "flip at {i} not detected"
        );
    }
    // every truncation
    for n in 0..bytes.len() {
        assert!(Snapshot::<2>::from_bytes(&bytes[..n]).is_err());
    }
    let mut longer = bytes.clone();
    longer.push(0);
    assert!(matches!(
        Snapshot::<2>::from_bytes(&longer),
        Err(SnapshotError::TrailingBytes { .. })
    ));
    assert!(matches!(
        Snapshot::<3>::from_bytes(&bytes),
        Err(SnapshotError::DimensionMismatch {
            expected: 3,
            found: 2
        })
    ));
    let mut b = bytes.clone();
    b[0] = b'X';
    assert_eq!(Snapshot::<2>::from_bytes(&b), Err(SnapshotError::BadMagic));
    assert!(Snapshot::<2>::from_bytes(&[]).is_err());
}

/// [0, T] in one call vs 1000 stop times: same result to tolerance, no restart.
#[test]
fn stop_times_do_not_restart_the_method() {
    let tol = 1e-6;
    let y0 = SVector::<f64, 3>::new(1.0, 0.0, 0.0);
    let o = Options {
        rtol: Tolerance::Scalar(tol),
        atol: Tolerance::Scalar(1e-6 * tol),
        ..Options::default()
    };
    let t_end = 40.0;
    let mut p = Robertson;
    let mut one = Radau5::new(&mut p, o, 0.0, y0).unwrap();
    one.integrate_to(&mut p, t_end).unwrap();
    let mut many = Radau5::new(&mut p, o, 0.0, y0).unwrap();
    let n_stops = 1000;
    for k in 1..=n_stops {
        many.integrate_to(&mut p, t_end * f64::from(k) / f64::from(n_stops))
            .unwrap();
    }
    assert_eq!(many.t(), t_end);
    let (a, b) = (one.stats(), many.stats());
    println!("one call: {a}\n1000 stops: {b}");
    for i in 0..3 {
        let d = (one.y()[i] - many.y()[i]).abs();
        assert!(
            d <= 10.0 * (1e-6 * tol + tol * one.y()[i].abs()),
            "component {i}: {d}"
        );
    }
    // At most one extra step per stop time, no rejection storm, Jacobians not per stop.
    assert!(
        b.nstep <= a.nstep + n_stops as u64,
        "nstep {} vs {}",
        b.nstep,
        a.nstep
    );
    assert!(b.nrejct <= a.nrejct + 5);
    assert!(b.njac <= a.njac + n_stops as u64 / 2);
}

/// Co-simulation with communication steps far below the natural step size (an FMU
/// doStep of 1e-5 s): about one internal step per call, LU pair reused.
#[test]
fn tiny_stop_intervals_cost_about_one_step_each() {
    // Also late in a run (t0 = 1000 s: the intervals t_stop - t then differ by the rounding
    // of t, 1.1e-13 s, 1.1e-8 of dt; a plain relative test of 1e-9 lost the LU reuse there:
    // 890 decompositions).
    for t0 in [0.0, 1000.0] {
        tiny_stop_intervals_from(t0);
    }
}

fn tiny_stop_intervals_from(t0: f64) {
    let (mut p, y0) = pendulum2();
    let o = pendulum2_opts(1e-6);
    let mut s = Radau5::new(&mut p, o, t0, y0).unwrap();
    s.integrate_to(&mut p, t0 + 0.5).unwrap();
    let before = *s.stats();
    let calls = 2000u64;
    let dt = 1e-5;
    for k in 1..=calls {
        s.integrate_to(&mut p, t0 + 0.5 + dt * k as f64).unwrap();
    }
    let d = *s.stats();
    let steps = d.nstep - before.nstep;
    println!(
        "{calls} calls of {dt}: {steps} steps, ndec {}, njac {}, nrejct {}",
        d.ndec - before.ndec,
        d.njac - before.njac,
        d.nrejct - before.nrejct
    );
    assert!(steps as f64 <= 1.5 * calls as f64);
    assert!(
        d.ndec - before.ndec <= calls / 10,
        "LU pair should be reused"
    );
    // still on the constraint |q| = 1 and close to a plain run
    let q = s.y();
    assert!(((q[0] * q[0] + q[1] * q[1]).sqrt() - 1.0).abs() < 1e-5);
    let mut r = Radau5::new(&mut p, o, t0, y0).unwrap();
    r.integrate_to(&mut p, t0 + 0.5 + dt * calls as f64)
        .unwrap();
    assert!((r.y() - s.y()).rows(0, 4).norm() < 1e-5);
}

/// Stop intervals of alternating length d and 1.1 d: an LU pair is never reused for a step
/// of another h (the Newton matrix would be wrong by 1 - h_lu/h, up to 0.17 within the
/// Fortran's [1, 1.2] window): every step decomposes. With d alone the pair is reused.
#[test]
fn clipped_steps_reuse_only_an_lu_pair_of_their_own_step_size() {
    let (mut p, y0) = pendulum2();
    let o = pendulum2_opts(1e-6);
    for (ratio, reused) in [(1.1, false), (1.0, true)] {
        let mut s = Radau5::new(&mut p, o, 0.0, y0).unwrap();
        s.integrate_to(&mut p, 0.5).unwrap();
        let before = *s.stats();
        let d = 1e-3;
        let mut t = 0.5;
        for k in 0..1000 {
            t += if k % 2 == 0 { d } else { ratio * d };
            s.integrate_to(&mut p, t).unwrap();
        }
        let st = s.stats().since(&before);
        println!(
            "spacing d, {ratio} d: {} steps, {} decompositions",
            st.nstep, st.ndec
        );
        if reused {
            assert!(st.ndec < st.nstep / 10, "{st}");
        } else {
            assert_eq!(st.ndec, st.nstep, "{st}");
        }
    }
}

/// A stop time one ulp ahead (rounded communication point) is reached without a step.
#[test]
fn stop_time_within_rounding_is_snapped() {
    let mut p = Harmonic;
    let mut s = Radau5::new(&mut p, opts(1e-8), 0.0, SVector::<f64, 2>::new(1.0, 0.0)).unwrap();
    s.integrate_to(&mut p, 0.3).unwrap();
    let n = s.stats().nstep;
    let next = f64::from_bits(0.3f64.to_bits() + 1);
    s.integrate_to(&mut p, next).unwrap();
    assert_eq!(s.t(), next);
    assert_eq!(s.stats().nstep, n);
    s.integrate_to(&mut p, 0.6).unwrap();
    assert!((s.y()[0] - 0.6f64.cos()).abs() < 1e-7);
}

#[test]
fn restart_after_a_jump_continues() {
    let mut p = Harmonic;
    let mut s = Radau5::new(&mut p, opts(1e-8), 0.0, SVector::<f64, 2>::new(1.0, 0.0)).unwrap();
    s.integrate_to(&mut p, 1.0).unwrap();
    let njac = s.stats().njac;
    s.restart(&mut p, SVector::<f64, 2>::new(0.0, 1.0), None)
        .unwrap();
    s.integrate_to(&mut p, 2.0).unwrap();
    assert!(s.stats().njac > njac, "restart must mark J stale");
    // exact: (sin(t - 1), cos(t - 1))
    assert!((s.y()[0] - 1.0f64.sin()).abs() < 1e-7);
    assert!((s.y()[1] - 1.0f64.cos()).abs() < 1e-7);
}

// ---------------------------------------------------------------- errors (test 5)

struct Blowup;
impl Problem<1> for Blowup {
    fn rhs(
        &mut self,
        _t: f64,
        y: &SVector<f64, 1>,
        f: &mut SVector<f64, 1>,
    ) -> Result<(), RhsError> {
        f[0] = y[0] * y[0];
        Ok(())
    }
}

#[test]
fn step_size_too_small() {
    let mut p = Blowup;
    let mut s = Radau5::new(&mut p, opts(1e-6), 0.0, SVector::<f64, 1>::new(1.0)).unwrap();
    let e = s.integrate_to(&mut p, 2.0).unwrap_err();
    println!("{e}");
    match e {
        // The pole is at t = 1; the implicit method may step slightly past it first.
        Error::StepSizeTooSmall { t, h } => assert!(t > 0.99 && t < 1.01 && h < 1e-12),
        other => panic!("unexpected {other:?}"),
    }
}

/// 0 * y' = 0: every iteration matrix is zero.
struct Singular;
impl Problem<2> for Singular {
    fn rhs(
        &mut self,
        _t: f64,
        _y: &SVector<f64, 2>,
        f: &mut SVector<f64, 2>,
    ) -> Result<(), RhsError> {
        f.fill(0.0);
        Ok(())
    }
    fn mass(&self) -> Option<SMatrix<f64, 2, 2>> {
        Some(SMatrix::zeros())
    }
}

#[test]
fn repeatedly_singular_matrix() {
    let mut p = Singular;
    let mut s = Radau5::new(&mut p, opts(1e-6), 0.0, SVector::zeros()).unwrap();
    assert!(
        matches!(s.integrate_to(&mut p, 1.0), Err(Error::SingularMatrix { t, .. }) if t == 0.0)
    );
}

/// f is fine at t = 0 (construction) and NaN / an error everywhere else.
struct Broken {
    nan: bool,
}
impl Problem<2> for Broken {
    fn rhs(
        &mut self,
        t: f64,
        y: &SVector<f64, 2>,
        f: &mut SVector<f64, 2>,
    ) -> Result<(), RhsError> {
        if t > 0.0 {
            if self.nan {
                f.fill(f64::NAN);
            } else {
                return Err(RhsError::new("outside the domain"));
            }
        } else {
            *f = -y;
        }
        Ok(())
    }
}

#[test]
fn non_finite_f_and_failing_f() {
    let y0 = SVector::<f64, 2>::new(1.0, 2.0);
    let mut p = Broken { nan: true };
    let mut s = Radau5::new(&mut p, opts(1e-6), 0.0, y0).unwrap();
    assert!(matches!(s.step(&mut p, 1.0), Err(Error::NonFinite { t, h }) if t == 0.0 && h > 0.0));
    let mut p = Broken { nan: false };
    let mut s = Radau5::new(&mut p, opts(1e-6), 0.0, y0).unwrap();
    match s.step(&mut p, 1.0) {
        Err(Error::Rhs { message, .. }) => assert_eq!(message, "outside the domain"),
        other => panic!("unexpected {other:?}"),
    }
}

#[test]
fn too_many_steps_and_bad_input() {
    let mut p = VanDerPol { eps: 1e-6 };
    let y0 = SVector::<f64, 2>::new(2.0, 0.0);
    let o = Options {
        max_steps: 10,
        ..opts(1e-6)
    };
    let mut s = Radau5::new(&mut p, o, 0.0, y0).unwrap();
    assert!(matches!(
        s.integrate_to(&mut p, 2.0),
        Err(Error::TooManySteps { max_steps: 10, .. })
    ));
    let mut s = Radau5::new(&mut p, opts(1e-6), 0.0, y0).unwrap();
    s.integrate_to(&mut p, 0.1).unwrap();
    assert!(matches!(
        s.integrate_to(&mut p, 0.05),
        Err(Error::StopTimeBehind { .. })
    ));
    assert!(matches!(
        s.step(&mut p, f64::NAN),
        Err(Error::StopTimeBehind { .. })
    ));
    let bad = Options {
        rtol: Tolerance::Scalar(0.0),
        ..opts::<2>(1e-6)
    };
    assert!(matches!(
        Radau5::new(&mut p, bad, 0.0, y0),
        Err(Error::InvalidOption { name: "rtol", .. })
    ));
    let bad = Options {
        n2: 1,
        ..opts::<2>(1e-6)
    };
    assert!(matches!(
        Radau5::new(&mut p, bad, 0.0, y0),
        Err(Error::InvalidOption { .. })
    ));
    assert!(s
        .set_tolerances(Tolerance::Scalar(1e-6), Tolerance::Scalar(-1.0))
        .is_err());
}

/// A wrong (zero) Jacobian on a very stiff problem at t = 0: Newton diverges until h is
/// tiny; the stepper gives up with a typed error instead of looping.
struct WrongJacobian;
impl Problem<1> for WrongJacobian {
    fn rhs(
        &mut self,
        _t: f64,
        y: &SVector<f64, 1>,
        f: &mut SVector<f64, 1>,
    ) -> Result<(), RhsError> {
        f[0] = -1e14 * y[0];
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        _y: &SVector<f64, 1>,
        j: &mut SMatrix<f64, 1, 1>,
    ) -> Result<bool, RhsError> {
        j[(0, 0)] = 0.0;
        Ok(true)
    }
}

#[test]
fn newton_failure_is_typed() {
    let mut p = WrongJacobian;
    let mut s = Radau5::new(&mut p, opts(1e-6), 0.0, SVector::<f64, 1>::new(1.0)).unwrap();
    let r = s.integrate_to(&mut p, 1.0);
    println!("{r:?}");
    assert!(matches!(r, Err(Error::NewtonFailure { t, h }) if t == 0.0 && h < 1e-10));
}

/// Snapshots taken after every step of an index-2 DAE (mass matrix, LU reuse, rejections)
/// and restored through bytes into a differently configured solver continue exactly like
/// the original: nothing of the state is missing from the snapshot.
#[test]
fn snapshot_is_complete_at_every_step() {
    let (mut p, y0) = pendulum2();
    let o = pendulum2_opts(1e-5);
    let mut s = Radau5::new(&mut p, o, 0.0, y0).unwrap();
    check_snapshots_continue(&mut p, &mut s, 60, 3.0, 1e-3);
}

/// `Radau5::retake` (co-simulation, radau5 module docs): the last accepted step redone so
/// that it ends on an earlier time gives a solution point there (harmonic oscillator:
/// against cos t, -sin t), the integration goes on from it, and what the retake needs
/// (y and f at t_prev) survives a snapshot in bytes.
#[test]
fn retake_ends_the_last_step_on_an_earlier_time() {
    let mut p = Harmonic;
    let y0 = SVector::<f64, 2>::new(1.0, 0.0);
    let mut s = Radau5::new(&mut p, opts(1e-8), 0.0, y0).unwrap();
    for _ in 0..15 {
        s.step(&mut p, 10.0).unwrap();
    }
    let (tp, t) = (s.t_prev(), s.t());
    assert!(
        t - tp > 0.05,
        "steps of the oscillator are long: {}",
        t - tp
    );
    let tc = tp + 0.37 * (t - tp);
    let bytes = s.snapshot().to_bytes();
    let untouched = s.snapshot();
    // Outside the last step: typed errors, nothing changed; at its end: nothing to do.
    for bad in [tp, tp - 1e-3, t + 1e-3, f64::NAN] {
        assert!(matches!(
            s.retake(&mut p, bad),
            Err(Error::InvalidOption { name: "t_stop", .. })
        ));
    }
    assert_eq!(s.retake(&mut p, t).unwrap(), Retake::Exact);
    assert!(s.snapshot() == untouched);

    let before = *s.stats();
    assert_eq!(s.retake(&mut p, tc).unwrap(), Retake::Exact);
    assert_eq!(s.t(), tc);
    assert_eq!(s.t_prev(), tp);
    assert_eq!(s.stats().naccpt, before.naccpt + 1);
    assert!(
        (s.y()[0] - tc.cos()).abs() < 1e-7,
        "{} vs {}",
        s.y()[0],
        tc.cos()
    );
    assert!((s.y()[1] + tc.sin()).abs() < 1e-7);
    // The dense output now belongs to [tp, tc].
    let mut u = SVector::zeros();
    s.dense_output(tp + 0.5 * (tc - tp), &mut u);
    assert!((u[0] - (tp + 0.5 * (tc - tp)).cos()).abs() < 1e-7);
    let y_tc = *s.y();
    s.integrate_to(&mut p, 10.0).unwrap();
    assert!((s.y()[0] - 10f64.cos()).abs() < 1e-6);

    // From bytes: the same retake, bit for bit.
    let mut q = Radau5::new(&mut p, opts(1e-8), 0.0, y0).unwrap();
    q.restore(&Snapshot::from_bytes(&bytes).unwrap());
    assert_eq!(q.retake(&mut p, tc).unwrap(), Retake::Exact);
    assert_eq!(q.y()[0].to_bits(), y_tc[0].to_bits());
    assert_eq!(q.y()[1].to_bits(), y_tc[1].to_bits());
}

/// A retake on a stiff, nonlinear problem lands where a step with that stop time from the
/// same point lands (the same collocation equations; only the Newton start and the
/// controller history differ), well within the tolerance.
#[test]
fn retake_matches_a_stop_time_step_on_van_der_pol() {
    let mut p = VanDerPol { eps: 1e-3 };
    let tol = 1e-6;
    let mut s = Radau5::new(&mut p, opts(tol), 0.0, SVector::<f64, 2>::new(2.0, 0.0)).unwrap();
    for k in 0..80 {
        let pre = s.snapshot();
        s.step(&mut p, 2.0).unwrap();
        if k % 8 != 7 {
            continue;
        }
        let tc = s.t_prev() + 0.6 * (s.t() - s.t_prev());
        let mut r = Radau5::new(&mut p, opts(tol), 0.0, SVector::<f64, 2>::new(2.0, 0.0)).unwrap();
        r.restore(&pre);
        r.integrate_to(&mut p, tc).unwrap();
        let post = s.snapshot();
        s.retake(&mut p, tc).unwrap();
        for i in 0..2 {
            let d = (s.y()[i] - r.y()[i]).abs() / (tol * (1.0 + r.y()[i].abs()));
            assert!(d < 1.0, "step {k}, component {i}: {d} tolerances apart");
        }
        // Carry on from the un-retaken state, so that the run covers the whole interval.
        s.restore(&post);
    }
}

/// `reset_step_count` renews the `max_steps` budget for a caller that never reaches its
/// (far) stop time.
#[test]
fn reset_step_count_renews_the_budget() {
    let mut p = Harmonic;
    let o = Options {
        max_steps: 5,
        ..opts(1e-8)
    };
    let y0 = SVector::<f64, 2>::new(1.0, 0.0);
    let mut s = Radau5::new(&mut p, o, 0.0, y0).unwrap();
    for _ in 0..4 {
        s.step(&mut p, 1e3).unwrap();
        s.reset_step_count();
        s.step(&mut p, 1e3).unwrap();
        s.reset_step_count();
    }
    let mut s = Radau5::new(&mut p, o, 0.0, y0).unwrap();
    let r = (0..8).try_for_each(|_| s.step(&mut p, 1e3).map(|_| ()));
    assert!(
        matches!(r, Err(Error::TooManySteps { max_steps: 5, .. })),
        "{r:?}"
    );
}

/// y' = -k y + u with a held input u (enters f additively; J = -k does not see it), which
/// may jump at `t_j` (e.g. a hair after a stop time, as a predicted event lands a hair
/// before the true one).
struct ForcedDecay {
    k: f64,
    u: f64,
    /// u jumps to `u_after` at `t_j` (never by default: infinity).
    t_j: f64,
    u_after: f64,
    /// f is evaluated at t + ahead (the limit from after the jump when ahead > t_j - t).
    ahead: f64,
}

impl ForcedDecay {
    fn new(k: f64, u: f64) -> Self {
        ForcedDecay {
            k,
            u,
            t_j: f64::INFINITY,
            u_after: u,
            ahead: 0.0,
        }
    }
}

impl Problem<1> for ForcedDecay {
    fn rhs(
        &mut self,
        t: f64,
        y: &SVector<f64, 1>,
        f: &mut SVector<f64, 1>,
    ) -> Result<(), RhsError> {
        let u = if t + self.ahead < self.t_j {
            self.u
        } else {
            self.u_after
        };
        f[0] = -self.k * y[0] + u;
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        _y: &SVector<f64, 1>,
        j: &mut SMatrix<f64, 1, 1>,
    ) -> Result<bool, RhsError> {
        j[(0, 0)] = -self.k;
        Ok(true)
    }
}

/// `Radau5::refresh` after a jump of an additive input: no new Jacobian, no first-step
/// treatment, and the solution follows the exact `u/k + (y_c - u/k) exp(-k (t - t_c))`.
#[test]
fn refresh_after_an_input_jump_keeps_the_jacobian() {
    let (k, tol) = (50.0, 1e-8);
    let mut p = ForcedDecay::new(k, 1.0);
    let mut s = Radau5::new(&mut p, opts(tol), 0.0, SVector::<f64, 1>::new(0.0)).unwrap();
    // In the transient (steps of ~1e-3 s, well below the time constant 1/k = 0.02 s),
    // so the step after the jump needs no smaller h.
    let t_c = 0.02;
    s.integrate_to(&mut p, t_c).unwrap();
    let y_c = s.y()[0];
    assert!((y_c - (1.0 - (-k * t_c).exp()) / k).abs() < 1e-9);
    p.u = 1.5;
    let before = *s.stats();
    s.refresh(&mut p, *s.y()).unwrap();
    assert_eq!(s.stats().nfcn, before.nfcn + 1, "refresh evaluates f once");
    assert_eq!(s.t_prev(), t_c, "nothing left to retake");
    let h_before = s.h();
    let at_c = s.snapshot();
    s.step(&mut p, 1.0).unwrap();
    assert_eq!(s.stats().njac, before.njac, "J kept across the refresh");
    assert_eq!(s.stats().ndec, before.ndec, "LU pair kept (same h)");
    // The full restart from the same point pays a Jacobian for its first step.
    let mut r = Radau5::new(&mut p, opts(tol), 0.0, SVector::<f64, 1>::new(0.0)).unwrap();
    r.restore(&at_c);
    r.restart(&mut p, *r.y(), None).unwrap();
    r.step(&mut p, 1.0).unwrap();
    assert_eq!(r.stats().njac, before.njac + 1);
    assert!(s.h() > 0.1 * h_before, "no first-step treatment");
    for t in [0.31, 0.35, 0.5, 1.0] {
        s.integrate_to(&mut p, t).unwrap();
        let y_inf = p.u / k;
        let exact = y_inf + (y_c - y_inf) * (-k * (t - t_c)).exp();
        assert!(
            (s.y()[0] - exact).abs() < 10.0 * tol,
            "t = {t}: {} vs {exact}",
            s.y()[0]
        );
    }
    assert!(matches!(
        s.refresh(&mut p, SVector::<f64, 1>::new(f64::NAN)),
        Err(Error::InvalidOption { name: "y", .. })
    ));
}

/// `Radau5::refresh_f`: after landing just before a jump of f, f re-evaluated as the limit
/// from after it lets the next steps go through without the rejections a stale f(t, y)
/// causes (its error estimate combines f(t, y) with stages that all lie after the jump);
/// it costs one f evaluation, keeps y and the last step (retake still possible), and the
/// solution follows the exact `u/k + (y_c - u/k) exp(-k (t - t_c))`, u = 1.5.
#[test]
fn refresh_f_after_landing_before_a_jump() {
    let (k, tol, t_c) = (50.0, 1e-8, 0.02);
    let run = |with: bool| {
        let mut p = ForcedDecay {
            t_j: t_c + 1e-15,
            u_after: 1.5,
            ..ForcedDecay::new(k, 1.0)
        };
        let mut s = Radau5::new(&mut p, opts(tol), 0.0, SVector::<f64, 1>::new(0.0)).unwrap();
        s.integrate_to(&mut p, t_c).unwrap();
        assert_eq!(s.t(), t_c);
        let (y_c, t_prev) = (*s.y(), s.t_prev());
        let before = *s.stats();
        if with {
            p.ahead = 1e-12;
            s.refresh_f(&mut p, y_c).unwrap();
            p.ahead = 0.0;
            assert_eq!(s.stats().nfcn, before.nfcn + 1, "one f evaluation");
            assert_eq!(
                (*s.y(), s.t_prev()),
                (y_c, t_prev),
                "y and the last step kept"
            );
        }
        let at_c = s.snapshot();
        for _ in 0..5 {
            s.step(&mut p, 1.0).unwrap();
        }
        let rejected = s.stats().nrejct - before.nrejct;
        s.integrate_to(&mut p, 0.3).unwrap();
        let y_inf = 1.5 / k;
        let exact = y_inf + (y_c[0] - y_inf) * (-k * (0.3 - t_c)).exp();
        assert!(
            (s.y()[0] - exact).abs() < 10.0 * tol,
            "{} vs {exact}",
            s.y()[0]
        );
        // The last step before t_c can still be retaken after refresh_f.
        s.restore(&at_c);
        let t_mid = 0.5 * (t_prev + t_c);
        assert!(s.retake(&mut p, t_mid).is_ok());
        assert_eq!(s.t(), t_mid);
        rejected
    };
    let stale = run(false);
    let fresh = run(true);
    println!(
        "rejected in 5 steps after the stop: {stale} with the stale f, {fresh} with refresh_f"
    );
    assert!(
        stale >= 1,
        "a stale f(t, y) before the jump gets steps rejected"
    );
    assert_eq!(
        fresh, 0,
        "f from after the jump: no rejection ({stale} without)"
    );
}
