//! Look-ahead across communication points (`sim` module docs): while the inputs stay the
//! same, RADAU5 steps past the FMU time and the outputs come from its dense output; when an
//! input or a tunable changes, the step that went past is retaken to end on the FMU time.
//! Checked against RADAU5 driven directly with stop times (no look-ahead involved).

mod common;

use common::rotor::{driven, scaled_dev};
use geared_rotor::radau5::Radau5;
use geared_rotor::rotor::RotorProblem;
use geared_rotor::rotor::{idx, GearedRotor, Params, NY};
use geared_rotor::sim::{Simulation, SolverSettings};
use nalgebra::SVector;

const OMEGA1: f64 = 314.159;
const SETTINGS: SolverSettings = SolverSettings {
    rtol: 1e-6,
    h_max: 1e-4,
};

fn sim() -> Simulation {
    Simulation::new(Params::default(), SETTINGS, 0.0, OMEGA1, 0.0).unwrap()
}

/// The reference: RADAU5 on the same problem and options, stopping exactly at `t_c`, where
/// `change` is applied (lambda re-projected, explicit restart), then on to `t_end`.
fn reference(
    t_c: f64,
    t_end: f64,
    change: impl FnOnce(&mut GearedRotor),
) -> (SVector<f64, NY>, SVector<f64, NY>) {
    let mut model = driven(Params::default(), OMEGA1);
    let y0 = model.initialize(0.0).unwrap();
    let mut p = RotorProblem { model };
    let mut s = Radau5::new(
        &mut p,
        SETTINGS.options(&geared_rotor::rotor::SCALES),
        0.0,
        y0,
    )
    .unwrap();
    s.integrate_to(&mut p, t_c).unwrap();
    let at_c = *s.y();
    change(&mut p.model);
    let mut y = *s.y();
    y[idx::LAMBDA] = p.model.consistent_lambda(t_c, &y).unwrap();
    s.restart(&mut p, y, None).unwrap();
    s.integrate_to(&mut p, t_end).unwrap();
    (at_c, *s.y())
}

/// With unchanged inputs, 1e-5 s communication steps cost a fraction of an internal step
/// each (the solver's own steps are ~4e-5 s), and the state at the communication points
/// (dense output where the stepper is ahead) is that of RADAU5 stopping at each of them.
#[test]
fn small_communication_steps_interpolate() {
    let h = 1e-5;
    let n = 2000;
    let mut a = sim();
    let mut model = driven(Params::default(), OMEGA1);
    let y0 = model.initialize(0.0).unwrap();
    let mut p = RotorProblem { model };
    let mut r = Radau5::new(
        &mut p,
        SETTINGS.options(&geared_rotor::rotor::SCALES),
        0.0,
        y0,
    )
    .unwrap();
    let (mut ahead, mut checked, mut worst) = (0, 0, 0.0f64);
    for k in 0..n {
        a.do_step(k as f64 * h, h).unwrap();
        if a.stepper_time() > a.time() {
            ahead += 1;
        }
        if k % 50 == 49 {
            r.integrate_to(&mut p, a.time()).unwrap();
            let (d, i) = scaled_dev(a.y(), r.y());
            // Two step sequences of tolerance 1e-6 over up to 27 mesh periods with kinks in
            // f: measured up to 1.6e-4 of a scale (the centre velocity u1x' at 18 ms), the
            // same with look-ahead off (stop at every point). A state one communication
            // step (1e-5 s) stale is off by ~0.08 of a scale at the 1350 Hz mesh frequency.
            assert!(
                d < 1e-3,
                "t = {}: component {i} deviates by {d:e}",
                a.time()
            );
            worst = worst.max(d);
            if a.stepper_time() > a.time() {
                checked += 1;
            }
        }
    }
    eprintln!("largest scaled deviation {worst:e}, {checked} of 40 checks interpolated");
    assert!(
        checked >= 20,
        "only {checked} checks on an interpolated state"
    );
    let st = *a.stats();
    let per_do_step = (st.naccpt + st.nrejct) as f64 / n as f64;
    assert!(
        per_do_step < 0.5,
        "{per_do_step} internal steps per doStep of 1e-5 s ({st:?})"
    );
    assert!(
        ahead > n / 2,
        "stepper ahead of the FMU time after {ahead} of {n} doSteps"
    );
    assert_eq!(a.time(), (n - 1) as f64 * h + h);
}

/// A held step of omega1 set while the stepper is ahead: the state at the FMU time is a
/// solution point (as with a stop time there), and the run goes on as if RADAU5 had stopped
/// there. Stepping on with the new input from the stepper's later time instead would shift
/// phi1 by ~20 rad/s times a step (~7e-4 rad, ~3 scales); interpolating without retake
/// would leave the position constraint violated by the dense-output error.
#[test]
fn input_change_retakes_the_step_that_went_past() {
    let h = 1e-5;
    let n_c = 517; // t_c = 5.17 ms, inside a solver step
    let t_c = n_c as f64 * h;
    let t_end = t_c + 2e-3;
    let mut a = sim();
    for k in 0..n_c {
        a.do_step(k as f64 * h, h).unwrap();
    }
    assert!(
        a.stepper_time() > a.time(),
        "test needs the stepper ahead at t_c"
    );
    let before = *a.stats();
    a.set_input(geared_rotor::sim::Input::Omega1, 320.0)
        .unwrap();
    // Nothing is decided at the set (the master may still set a derivative that makes it
    // the same function): the next doStep retakes the step to end on t_c first.
    assert!(a.stepper_time() > a.time(), "nothing retaken at the set");
    assert_eq!(*a.stats(), before);
    let (ref_c, ref_end) = reference(t_c, t_end, |m| {
        let mut i = *m.inputs();
        i.omega1 = 320.0;
        i.omega1_der = 0.0;
        i.t_ref = t_c;
        m.set_inputs(i);
    });
    let (d, i) = scaled_dev(a.y(), &ref_c);
    assert!(d < 1e-4, "at t_c: component {i} off by {d:e} of its scale");
    let mut t = t_c;
    while t < t_end - 0.5 * h {
        a.do_step(t, h).unwrap();
        if t == t_c {
            // The retake (an accepted step ending on t_c) and the restart there.
            assert!(a.stats().naccpt > before.naccpt);
        }
        t += h;
    }
    let (d, i) = scaled_dev(a.y(), &ref_end);
    assert!(
        d < 1e-3,
        "at t_end: component {i} off by {d:e} of its scale"
    );
    assert!((a.y()[idx::OMEGA1] - 320.0).abs() < 1e-3);
}

/// The same for a tunable (mu) changed while the stepper is ahead.
#[test]
fn tunable_change_retakes_the_step_that_went_past() {
    let h = 1e-5;
    let n_c = 433;
    let t_c = n_c as f64 * h;
    let t_end = t_c + 2e-3;
    let mut a = sim();
    for k in 0..n_c {
        a.do_step(k as f64 * h, h).unwrap();
    }
    assert!(
        a.stepper_time() > a.time(),
        "test needs the stepper ahead at t_c"
    );
    let mu_new = 0.1;
    a.set_mu(mu_new).unwrap();
    assert_eq!(a.stepper_time(), a.time());
    // A rejected value changes nothing and retakes nothing.
    assert!(a.set_mu(-1.0).is_err());
    let (_, ref_end) = reference(t_c, t_end, |m| m.set_mu(mu_new).unwrap());
    let mut t = t_c;
    while t < t_end - 0.5 * h {
        a.do_step(t, h).unwrap();
        t += h;
    }
    let (d, i) = scaled_dev(a.y(), &ref_end);
    assert!(d < 1e-3, "component {i} off by {d:e} of its scale");
}

/// A snapshot taken while the stepper is ahead restores and serialises bit-identically.
#[test]
fn snapshot_while_ahead_restores_bit_identically() {
    let h = 1e-5;
    let mut a = sim();
    for k in 0..300 {
        a.do_step(k as f64 * h, h).unwrap();
    }
    let mut k0 = 300;
    while a.stepper_time() == a.time() {
        a.do_step(k0 as f64 * h, h).unwrap();
        k0 += 1;
    }
    let snap = a.state();
    let mut w = geared_rotor::bytes::Writer::default();
    snap.write(&mut w);
    let bytes = w.buf;
    let run = |s: &mut Simulation| {
        let t0 = s.time();
        for k in 0..100 {
            s.do_step(t0 + k as f64 * h, h).unwrap();
            if k == 37 {
                s.set_input(geared_rotor::sim::Input::Omega1, 330.0)
                    .unwrap();
            }
        }
        (*s.y(), s.outputs().t1)
    };
    let first = run(&mut a);
    a.restore(&snap).unwrap();
    let second = run(&mut a);
    let mut r = geared_rotor::bytes::Reader::new(&bytes);
    let decoded = geared_rotor::sim::SimState::read(&mut r).unwrap();
    let mut c = Simulation::from_state(&decoded).unwrap();
    let third = run(&mut c);
    for other in [second, third] {
        for i in 0..NY {
            assert_eq!(first.0[i].to_bits(), other.0[i].to_bits(), "component {i}");
        }
        assert_eq!(first.1.to_bits(), other.1.to_bits());
    }
}

/// Tooth lift-off (model.md §9: lambda < 0 when the load drives gear 2 harder than the
/// damper brakes it, T_load < -d_phi omega2 ~ -103 N m) seen through the look-ahead: a load
/// ramp (one input function, so RADAU5 steps across the 1e-5 s points) crosses it at
/// ~5 ms. The flag agrees with the outputs at every communication point, and the change is
/// reported by the doStep whose interval contains it, not by an earlier one whose
/// look-ahead step went past it.
#[test]
fn contact_changes_are_reported_in_their_interval() {
    let p = Params {
        mu: 0.0,
        ..Params::default()
    };
    let mut a = Simulation::new(p, SETTINGS, 0.0, OMEGA1, 0.0).unwrap();
    a.set_input_derivative(geared_rotor::sim::Input::TLoad, -2e4)
        .unwrap();
    let h = 1e-5;
    let mut changes = 0;
    for _ in 0..1000 {
        let t0 = a.time();
        let r = a.do_step(t0, h).unwrap();
        if r.contact_changes > 0 {
            changes += r.contact_changes;
            assert!(
                r.first_change_time > t0 && r.first_change_time <= a.time(),
                "change at {} reported for [{t0}, {}]",
                r.first_change_time,
                a.time()
            );
        }
        assert_eq!(
            a.contact_lost(),
            a.outputs().contact_lost,
            "t = {}",
            a.time()
        );
    }
    assert!(changes >= 1 && a.contact_lost());
    assert!(
        a.stats().naccpt < 600,
        "look-ahead was active: {:?}",
        a.stats()
    );
}
