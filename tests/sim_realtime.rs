//! Real-time mode (`h_fixed > 0`, `sim::realtime`): equal counted work per doStep, accuracy
//! against an adaptive reference at rtol 1e-8 driven by the same held inputs, energy
//! balance, non-convergence reported, never silent.

use geared_rotor::rotor::Params;
use geared_rotor::sim::realtime::NEWTON_ITERATIONS;
use geared_rotor::sim::{Input, SimError, Simulation, SolverSettings};
use std::f64::consts::PI;

const W0: f64 = 314.159;

fn sim(rtol: f64, h_fixed: f64) -> Simulation {
    sim_from(0.0, rtol, h_fixed)
}

/// The default pair from rest at `t0` in real-time mode `h_fixed`.
fn sim_from(t0: f64, rtol: f64, h_fixed: f64) -> Simulation {
    let mut s = Simulation::new(
        Params::default(),
        SolverSettings { rtol, h_max: 1e-4 },
        t0,
        W0,
        0.0,
    )
    .unwrap();
    s.set_h_fixed(h_fixed).unwrap();
    s
}

/// The master's input at the communication point t: omega1 = W0 (1 + 0.01 sin(2 pi 50 t)).
fn omega1(t: f64) -> f64 {
    W0 * (1.0 + 0.01 * (2.0 * PI * 50.0 * t).sin())
}

/// Energy balance of model.md §9.6 from the outputs, relative to E_in:
/// `E_in - E_loss - E_damp - E_load - (E_kin + E_pot - E_kin0 - E_pot0)`.
fn energy_residual(s: &Simulation, e0: f64) -> f64 {
    let o = s.outputs();
    (o.e_in - o.e_loss - o.e_damp - o.e_load - (o.e_kin + o.e_pot - e0)) / o.e_in.abs()
}

/// Every doStep of a run costs exactly the same counted work, whatever the inputs do
/// (omega1 and T_load new at every point, then held, then a ramp with derivatives): with
/// H = 1e-4 s and h_fixed = 2.5e-5 s, 4 internal steps of 3 Newton iterations (36 f
/// evaluations, 12 solves), 1 Jacobian, 1 LU pair, no rejection.
#[test]
fn work_per_do_step_is_the_same_for_every_do_step() {
    let h = 1e-4;
    let mut s = sim(1e-6, 2.5e-5);
    let mut first = None;
    for k in 0..600 {
        let t = k as f64 * h;
        if k < 300 {
            s.set_input(Input::Omega1, omega1(t)).unwrap();
            s.set_input(Input::TLoad, 5.0 * (2.0 * PI * 50.0 * t).sin())
                .unwrap();
        } else if k >= 450 {
            s.set_input(Input::Omega1, W0 + 100.0 * (t - 0.045))
                .unwrap();
            s.set_input_derivative(Input::Omega1, 100.0).unwrap();
        }
        let r = s.do_step(t, h).unwrap();
        let w = r.stats;
        assert_eq!(w.nrejct, 0, "doStep {k}: rejections {w}");
        let n = 4;
        let nit = u64::from(NEWTON_ITERATIONS);
        assert_eq!(
            (w.nfcn, w.nsol, w.njac, w.ndec, w.nstep, w.naccpt),
            (3 * nit * n, nit * n, 1, 1, n, n),
            "doStep {k}: {w}"
        );
        match first {
            None => first = Some(w),
            Some(f) => assert_eq!(w, f, "doStep {k}"),
        }
    }
}

/// Shorter doSteps renew J and the LU pair on a fixed schedule of the time grid, not at
/// every doStep: with H = 1e-5 s (= h_fixed, one internal step) on the doSteps from
/// t = k H with k a multiple of 10 (J at most 1e-4 s old, as with one J per doStep of
/// 1e-4 s), plus the doStep after a new tunable (mu, which changes J); the f evaluations
/// and solves are the same for every doStep (9 and 3), whatever the inputs do.
#[test]
fn shorter_do_steps_renew_the_jacobian_on_a_fixed_schedule() {
    let h = 1e-5;
    let mut s = sim(1e-6, 1e-5);
    let nit = u64::from(NEWTON_ITERATIONS);
    for k in 0..300u64 {
        let t = k as f64 * h;
        s.set_input(Input::Omega1, omega1(t)).unwrap();
        if k >= 150 {
            s.set_input(Input::TLoad, 5.0 * (2.0 * PI * 50.0 * t).sin())
                .unwrap();
        }
        // A new tunable off the schedule: J changes, renewed at once.
        if k == 203 {
            s.set_mu(0.06).unwrap();
        }
        let w = s.do_step(t, h).unwrap().stats;
        let renew = u64::from(k % 10 == 0 || k == 203);
        assert_eq!(
            (w.nfcn, w.nsol, w.njac, w.ndec, w.nstep, w.nrejct),
            (3 * nit, nit, renew, renew, 1, 0),
            "doStep {k}: {w}"
        );
    }
    // From t = 100 s (the master's t + H differs from H by ulps of t, 1.4e-9 of H): the
    // same schedule, the LU pair kept across the round-off.
    let t0 = 100.0;
    let mut s = sim_from(t0, 1e-6, 1e-5);
    for k in 0..200u64 {
        let t = t0 + k as f64 * h;
        s.set_input(Input::Omega1, omega1(t)).unwrap();
        let w = s.do_step(t, h).unwrap().stats;
        let renew = u64::from(((t / h).round() as u64).is_multiple_of(10));
        assert_eq!(
            (w.nfcn, w.njac, w.ndec),
            (3 * nit, renew, renew),
            "t = {t}: {w}"
        );
    }
}

/// H = 1e-4 s, h_fixed = 2.5e-5 s, omega1 changing at every point: T1 within 1e-3 of the
/// mean reference T1 of an adaptive run at rtol 1e-8 driven by the same held input at the
/// same points (sampled at every point over 0.1 s, incl. the start-up transient); Fn and
/// TE within the same fraction of their reference scales; the energy balance within 1e-4
/// of E_in.
#[test]
fn fixed_step_run_matches_the_adaptive_reference() {
    let h = 1e-4;
    let mut rt = sim(1e-6, 2.5e-5);
    let mut reference = sim(1e-8, 0.0);
    let o0 = rt.outputs();
    let e0 = o0.e_kin + o0.e_pot;
    let n = 1000;
    let (mut d_t1, mut d_fn, mut d_te) = (0.0f64, 0.0f64, 0.0f64);
    let (mut sum_t1, mut sum_fn, mut max_te) = (0.0, 0.0, 0.0f64);
    let mut worst_energy = 0.0f64;
    for k in 0..n {
        let t = k as f64 * h;
        for s in [&mut rt, &mut reference] {
            s.set_input(Input::Omega1, omega1(t)).unwrap();
            s.do_step(t, h).unwrap();
        }
        let (a, b) = (rt.outputs(), reference.outputs());
        d_t1 = d_t1.max((a.t1 - b.t1).abs());
        d_fn = d_fn.max((a.fn_ - b.fn_).abs());
        d_te = d_te.max((a.te - b.te).abs());
        sum_t1 += b.t1;
        sum_fn += b.fn_;
        max_te = max_te.max(b.te.abs());
        worst_energy = worst_energy.max(energy_residual(&rt, e0).abs());
    }
    let (mean_t1, mean_fn) = (sum_t1 / n as f64, sum_fn / n as f64);
    assert!(mean_t1 > 1.0 && mean_fn > 100.0, "{mean_t1} {mean_fn}");
    assert!(
        d_t1 <= 1e-3 * mean_t1,
        "max |T1 - T1_ref| = {d_t1:e} N m, mean T1_ref = {mean_t1} N m"
    );
    assert!(
        d_fn <= 1e-3 * mean_fn,
        "max |Fn - Fn_ref| = {d_fn:e} N, mean Fn_ref = {mean_fn} N"
    );
    assert!(
        d_te <= 1e-3 * max_te,
        "max |TE - TE_ref| = {d_te:e} m, max |TE_ref| = {max_te:e} m"
    );
    assert!(
        worst_energy <= 1e-4,
        "energy balance residual {worst_energy:e} of E_in"
    );
}

/// A fixed step too large for its Newton iteration count (h_fixed = H = 1e-3 s from the
/// consistent start) is a solver error naming h_fixed, with the state kept at the last
/// successful time; a negative or non-finite h_fixed is refused naming the parameter.
#[test]
fn non_convergence_is_an_error_never_a_silent_result() {
    let mut s = sim(1e-6, 1e-3);
    let e = s.do_step(0.0, 1e-3).unwrap_err();
    let msg = e.to_string();
    assert!(
        matches!(e, SimError::Solver { last_successful_time, .. } if last_successful_time == 0.0),
        "{e:?}"
    );
    assert!(
        msg.contains("h_fixed") && msg.contains("not converged"),
        "{msg}"
    );
    assert_eq!(s.time(), 0.0);
    for bad in [-1e-5, f64::NAN, f64::INFINITY] {
        let e = s.set_h_fixed(bad).unwrap_err();
        assert!(
            matches!(&e, SimError::Param(p) if p.name == "h_fixed"),
            "{e:?}"
        );
    }
}

/// The internal step lands on every communication point exactly and divides it: with
/// H = 3e-5 s and h_fixed = 2e-5 s, 2 steps of 1.5e-5 s per doStep (no sliver); with
/// H = h_fixed = 1e-5 s from t = 100 s, where `t_end - t` differs from H by ulps of t,
/// one step per doStep.
#[test]
fn internal_step_divides_the_communication_step() {
    let mut s = sim(1e-6, 2e-5);
    for k in 0..20 {
        let t = k as f64 * 3e-5;
        let r = s.do_step(t, 3e-5).unwrap();
        assert_eq!(r.stats.naccpt, 2);
        assert_eq!(s.stepper_time(), t + 3e-5);
    }
    let t0 = 100.0;
    let mut s = sim_from(t0, 1e-6, 1e-5);
    for k in 0..200 {
        let t = t0 + k as f64 * 1e-5;
        let r = s.do_step(t, 1e-5).unwrap();
        assert_eq!(r.stats.naccpt, 1, "doStep at {t}");
    }
}

/// The real-time mode keeps the model's validity watch and the work bound of the adaptive
/// mode: a load that makes the teeth lift off is reported once (Warn) or stops the doStep
/// at the located instant (Discard), where the adaptive mode locates it too; a doStep that
/// needs more internal steps than `max_internal_steps` stops where it got.
#[test]
fn real_time_mode_reports_lift_off_and_honours_the_work_bound() {
    use geared_rotor::sim::{OnViolation, ViolationKind};
    let h = 1e-4;
    // Warn: one episode, reported in the doStep in which the load turns around.
    let mut s = sim(1e-6, 2.5e-5);
    for k in 0..20 {
        s.do_step(k as f64 * h, h).unwrap();
    }
    // Fn falls through zero ~0.25 ms after the load turns around (from 3339 N).
    s.set_input(Input::TLoad, -200.0).unwrap();
    let mut seen = Vec::new();
    for k in 20..30 {
        let r = s.do_step(k as f64 * h, h).unwrap();
        seen.extend(r.violations.iter().flatten().map(|v| (k, *v)));
    }
    assert_eq!(seen.len(), 1, "one episode, reported once: {seen:?}");
    let (k, v) = seen[0];
    assert_eq!(v.kind, ViolationKind::LiftOff);
    assert!(v.value < 0.0, "{v:?}");
    assert!(
        (k as f64 * h..=(k + 1) as f64 * h).contains(&v.t),
        "{v:?} in doStep {k}"
    );

    // Discard: the FMU time is the located instant, the same instant the adaptive mode
    // finds for the same run (both locate the sign change of Fn to ~1e-12 s).
    let located = |h_fixed: f64| {
        let mut s = sim(1e-8, h_fixed);
        s.set_on_violation(OnViolation::Discard);
        for k in 0..20 {
            s.do_step(k as f64 * h, h).unwrap();
        }
        s.set_input(Input::TLoad, -200.0).unwrap();
        for k in 20..30 {
            match s.do_step(k as f64 * h, h) {
                Ok(_) => continue,
                Err(SimError::Validity(v)) => {
                    assert_eq!(s.last_successful_time(), v.t);
                    return v.t;
                }
                Err(e) => panic!("expected a validity stop, got {e}"),
            }
        }
        panic!("no lift-off found")
    };
    let (t_rt, t_ad) = (located(2.5e-5), located(0.0));
    assert!(
        (t_rt - t_ad).abs() < 1e-7,
        "real-time {t_rt} vs adaptive {t_ad}"
    );

    // Work bound: 4 internal steps needed, 2 allowed.
    let mut s = sim(1e-6, 2.5e-5);
    s.set_max_internal_steps(2);
    match s.do_step(0.0, h) {
        Err(SimError::WorkLimit { limit: 2, t, .. }) => {
            assert!((t - 5e-5).abs() < 1e-15, "stopped at {t}");
            assert_eq!(s.last_successful_time(), t);
        }
        other => panic!("expected the work limit, got {other:?}"),
    }
}
