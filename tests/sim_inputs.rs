//! The input handling of `src/sim`: the drive-speed filter seen through `Simulation` against
//! the closed-form step and ramp responses of a critically damped second-order filter
//! (README "Input smoothing", model.md §8), the held inputs (zero-order hold unless a
//! derivative is set at the same communication point) and the energy balance of model.md
//! §9.6 over the run.

use geared_rotor::rotor::Params;
use geared_rotor::sim::{Input, Simulation, SolverSettings};
use std::f64::consts::PI;

const SETTINGS: SolverSettings = SolverSettings {
    rtol: 1e-8,
    h_max: 1e-4,
};

/// Corner of the default filter, w_c = 2 pi 1000 Hz (README "Input smoothing").
const WC: f64 = 2.0 * PI * 1000.0;

/// Response of `y'' = w^2 (r - y) - 2 w y'` from rest (y = y' = 0) to a unit step of r:
/// `1 - (1 + w t) e^{-w t}`, and its derivative `w^2 t e^{-w t}`.
fn step(t: f64) -> (f64, f64) {
    if t <= 0.0 {
        return (0.0, 0.0);
    }
    let e = (-WC * t).exp();
    (1.0 - (1.0 + WC * t) * e, WC * WC * t * e)
}

/// Response from rest to the unit ramp r = t (Laplace: w^2 / (s^2 (s + w)^2)):
/// `t - (2/w)(1 - e^{-w t}) + t e^{-w t}`, and its derivative `1 - (1 + w t) e^{-w t}`
/// (the unit step response, as it must be).
fn ramp(t: f64) -> (f64, f64) {
    if t <= 0.0 {
        return (0.0, 0.0);
    }
    let e = (-WC * t).exp();
    (t - 2.0 / WC * (1.0 - e) + t * e, step(t).0)
}

/// Energy balance of model.md §9.6 from the outputs:
/// `E_in - E_loss - E_damp - E_load - (E_kin + E_pot - E_kin0 - E_pot0)` relative to E_in.
fn energy_residual(s: &Simulation, e0: f64) -> f64 {
    let o = s.outputs();
    (o.e_in - o.e_loss - o.e_damp - o.e_load - (o.e_kin + o.e_pot - e0)) / o.e_in.abs()
}

/// A held step of the input omega1 (300 -> 310 rad/s at t = 0, zero-order hold) gives the
/// closed-form step response of the critically damped filter in `omega1_filtered` and its
/// derivative; the energy balance (model.md §9.6) holds over the run and the gap stays
/// closed (the DAE keeps the constraint).
#[test]
fn omega1_step_gives_the_critically_damped_response() {
    let mut s = Simulation::new(Params::default(), SETTINGS, 0.0, 300.0, 0.0).unwrap();
    let o0 = s.outputs();
    let e0 = o0.e_kin + o0.e_pot;
    s.set_input(Input::Omega1, 310.0).unwrap();
    let h = 5e-5;
    let (mut worst, mut worst_d) = (0.0f64, 0.0f64);
    for k in 0..60 {
        let t = k as f64 * h;
        s.do_step(t, h).unwrap();
        let o = s.outputs();
        let (y, yd) = step(t + h);
        let e = (o.omega1 - (300.0 + 10.0 * y)).abs() / 10.0;
        let ed = (o.omega1_dot - 10.0 * yd).abs() / (10.0 * WC / std::f64::consts::E);
        worst = worst.max(e);
        worst_d = worst_d.max(ed);
        assert!(
            e < 1e-5,
            "t {}: omega1 {} vs {}",
            t + h,
            o.omega1,
            300.0 + 10.0 * y
        );
        assert!(
            ed < 1e-5,
            "t {}: omega1' {} vs {}",
            t + h,
            o.omega1_dot,
            10.0 * yd
        );
        assert_eq!(s.input(Input::Omega1), 310.0);
    }
    let eb = energy_residual(&s, e0);
    let gap = s.outputs().gap;
    println!(
        "sim_inputs step: max |omega1 - closed form| / step = {worst:.2e}, omega1' {worst_d:.2e} of peak; energy residual {eb:.2e}; gap {gap:.2e} m"
    );
    assert!(eb.abs() < 1e-6, "energy balance {eb:e}");
    assert!(gap.abs() < 1e-9, "gap drift {gap:e}");
}

/// Ramp, then hold (FMI input derivatives, README "Input smoothing"):
/// - t = 0: der(omega1) = a and der(T_load) = b are set: the references are ramps
///   `omega1 + a t`, `b t` and omega1_filtered is the closed-form ramp response;
/// - t1: der(T_load) = b is set again (same ramp): nothing changes, both ramps continue;
/// - t2: omega1 is set to its current ramp value WITHOUT a derivative: from then on it is
///   held (zero-order hold), so the response is the ramp response minus the ramp response
///   delayed by t2 (superposition), while the T_load ramp, whose derivative was set at t1
///   only, is not reset by setting omega1 and continues (`input` reports `b t`).
#[test]
fn ramp_then_hold_follows_superposed_closed_forms() {
    let (w0, a, b) = (300.0, 2.0e4, 1.0e3);
    let mut s = Simulation::new(Params::default(), SETTINGS, 0.0, w0, 0.0).unwrap();
    s.set_input_derivative(Input::Omega1, a).unwrap();
    s.set_input_derivative(Input::TLoad, b).unwrap();
    let h = 1e-4;
    let (t1, t2, t_end) = (10, 20, 40);
    let mut worst: f64 = 0.0;
    for k in 0..t_end {
        let t = k as f64 * h;
        if k == t1 {
            s.set_input_derivative(Input::TLoad, b).unwrap();
        }
        if k == t2 {
            s.set_input(Input::Omega1, w0 + a * t).unwrap();
        }
        // held inputs as the FMI master sees them
        let w_ref = w0 + a * t.min(t2 as f64 * h);
        assert!(
            (s.input(Input::Omega1) - w_ref).abs() < 1e-9 * w_ref,
            "t {t}: omega1 input {} vs {w_ref}",
            s.input(Input::Omega1)
        );
        assert!(
            (s.input(Input::TLoad) - b * t).abs() < 1e-9,
            "t {t}: T_load input {} vs {}",
            s.input(Input::TLoad),
            b * t
        );
        s.do_step(t, h).unwrap();
        let te = t + h;
        let (r, rd) = ramp(te);
        let (rs, rsd) = ramp(te - t2 as f64 * h);
        let want = w0 + a * (r - rs);
        let want_d = a * (rd - rsd);
        let o = s.outputs();
        let e = (o.omega1 - want).abs() / (a * 2.0 / WC);
        worst = worst.max(e);
        assert!(e < 1e-5, "t {te}: omega1 {} vs {want}", o.omega1);
        assert!(
            (o.omega1_dot - want_d).abs() < 1e-5 * a,
            "t {te}: omega1' {} vs {want_d}",
            o.omega1_dot
        );
    }
    // T_load kept its ramp b t after omega1 was set at t2 (derivative set at t1 only)
    let t = s.time();
    assert!((s.input(Input::TLoad) - b * t).abs() < 1e-9);
    println!("sim_inputs ramp/hold: max |omega1 - closed form| / steady lag = {worst:.2e}");
}

/// A master that re-sends a ramp at every communication point (value omega1(t_n) and slope)
/// continues the same input function: the order of the two calls (FMPy sets the value
/// first) must not matter, and neither restarts the stepper (docs/fmu.md "Inputs"). Before
/// the decision was moved into doStep, value-then-derivative took 1226 f, 227 steps, 225 LU
/// over these 200 doSteps against 474 f, 77 steps, 55 LU in the other order.
#[test]
fn a_continuing_ramp_is_no_change_in_either_call_order() {
    let (w0, slope, h) = (200.0, 1000.0, 1e-5);
    let settings = SolverSettings {
        rtol: 1e-6,
        h_max: 1e-4,
    };
    let run = |order: u8| {
        let mut s = Simulation::new(Params::default(), settings, 0.0, w0, 0.0).unwrap();
        for k in 0..200 {
            let t = k as f64 * h;
            let w = w0 + slope * t;
            match order {
                0 => {
                    s.set_input(Input::Omega1, w).unwrap();
                    s.set_input_derivative(Input::Omega1, slope).unwrap();
                }
                1 => {
                    s.set_input_derivative(Input::Omega1, slope).unwrap();
                    s.set_input(Input::Omega1, w).unwrap();
                }
                // the slope once at the start, the value never again
                _ => {
                    if k == 0 {
                        s.set_input_derivative(Input::Omega1, slope).unwrap();
                    }
                }
            }
            s.do_step(t, h).unwrap();
        }
        s
    };
    let (a, b, c) = (run(0), run(1), run(2));
    let (sa, sb, sc) = (a.stats(), b.stats(), c.stats());
    println!("value first: {sa}\nderivative first: {sb}\nonce: {sc}");
    assert_eq!(sa, sb);
    for i in 0..a.y().len() {
        assert_eq!(a.y()[i].to_bits(), b.y()[i].to_bits(), "component {i}");
    }
    // No more work than the ramp given once (the re-sent values differ from the FMU's own
    // extrapolation by round-off only: no restart).
    assert_eq!((sa.nfcn, sa.nstep, sa.ndec), (sc.nfcn, sc.nstep, sc.ndec));
    let t1 = |s: &Simulation| s.outputs().t1;
    assert!(
        (t1(&a) - t1(&c)).abs() <= 1e-9 * t1(&c).abs(),
        "{} vs {}",
        t1(&a),
        t1(&c)
    );
}
