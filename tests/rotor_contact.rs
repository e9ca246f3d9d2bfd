//! The contact seam (`rotor::Contact`, issue 27 item 8): what the simulation asks the tooth
//! contact, checked against values computed here from f and the outputs alone:
//! - rigid teeth: the normal force is the lambda that keeps the constraint's rate at zero
//!   along the flow (the hidden constraint), found from two trial lambdas through the
//!   constraint row of f; lift-off where it is negative; no contact events;
//! - elastic teeth: the normal force is Fn of model.md (3.16),
//!   `l max(0, c_l delta + d_l delta')`, with delta from the gap output and delta' its
//!   difference quotient along the flow; the drive event function is positive exactly
//!   where that force is; never a lift-off.

use geared_rotor::rotor::{idx, FrictionLaw, GearedRotor, LastSlot, Params, ToothContact, NY};
use geared_rotor::sim::{Initialization, Input, Simulation, SolverSettings};
use nalgebra::SVector;

const OMEGA1: f64 = 314.159;
const SETTINGS: SolverSettings = SolverSettings {
    rtol: 1e-8,
    h_max: 1e-4,
};

/// A run from the static equilibrium over `n` doSteps of 0.1 ms (a state off the start,
/// with the centres vibrating).
fn run(p: Params, t_load: f64, n: usize) -> Simulation {
    let init = Initialization::StaticEquilibrium;
    let mut s = Simulation::with_initialization(p, SETTINGS, 0.0, OMEGA1, t_load, init).unwrap();
    for k in 0..n {
        s.do_step(k as f64 * 1e-4, 1e-4).unwrap();
    }
    s
}

/// y' from `M y' = f` at (t, y), with 0 for the algebraic component (M_ii = 0).
fn flow(model: &GearedRotor, t: f64, y: &SVector<f64, NY>) -> SVector<f64, NY> {
    let mut m = model.clone();
    let mut f = SVector::<f64, NY>::zeros();
    m.rhs(t, y, &mut f).unwrap();
    let mass = model.mass();
    SVector::from_fn(|i, _| {
        if mass[(i, i)] != 0.0 {
            f[i] / mass[(i, i)]
        } else {
            0.0
        }
    })
}

/// The rate of the rigid constraint `G(q) v - r_b1 cos(beta_b) omega1` (the last row of f)
/// along the flow from y with lambda = `lam`, by a central difference of step `eps`.
fn constraint_rate(model: &GearedRotor, t: f64, y: &SVector<f64, NY>, lam: f64) -> f64 {
    let mut z = *y;
    z[idx::LAMBDA] = lam;
    let yd = flow(model, t, &z);
    let eps = 1e-7;
    let row = |s: f64, w: SVector<f64, NY>| {
        let mut m = model.clone();
        let mut f = SVector::<f64, NY>::zeros();
        m.rhs(s, &w, &mut f).unwrap();
        f[idx::LAMBDA]
    };
    (row(t + eps, z + yd * eps) - row(t - eps, z - yd * eps)) / (2.0 * eps)
}

/// The lambda at which the constraint's rate vanishes, from two trial values of the same
/// sign (the rate is affine in lambda there: friction laws 1 and 2 are linear in |lambda|).
fn hidden_lambda(model: &GearedRotor, t: f64, y: &SVector<f64, NY>, l0: f64, l1: f64) -> f64 {
    let (d0, d1) = (
        constraint_rate(model, t, y, l0),
        constraint_rate(model, t, y, l1),
    );
    l0 - d0 * (l1 - l0) / (d1 - d0)
}

#[test]
fn rigid_contact_answers_with_the_consistent_multiplier() {
    let p = Params {
        mu: 0.05,
        friction_law: FrictionLaw::Coulomb,
        ..Params::default()
    };
    let mut s = run(p, 100.0, 30);
    let (t, y) = (s.time(), *s.y());
    let model = s.model();
    let c = model.contact();
    assert_eq!(c.kind(), ToothContact::Rigid);
    assert_eq!(c.last_slot(), LastSlot::Multiplier);
    assert!(c.has_multiplier() && c.lift_off_possible() && !c.has_contact_events());
    assert_eq!(
        c.event_functions(t, &y),
        None,
        "rigid teeth have no contact events"
    );

    let fn_ = c.normal_force(t, &y);
    let expected = hidden_lambda(model, t, &y, 1e3, 4e3);
    println!(
        "rigid: normal force {fn_:.9e} N, hidden constraint {expected:.9e} N, stepper {:.9e} N",
        y[idx::LAMBDA]
    );
    assert!(
        (fn_ - expected).abs() <= 1e-6 * expected.abs(),
        "{fn_} vs {expected}"
    );
    // What the outputs report, and the state they are evaluated at.
    assert_eq!(s.outputs().fn_, fn_);
    let z = c.output_state(t, &y);
    assert_eq!(z[idx::LAMBDA], fn_);
    assert_eq!(z.rows(0, idx::LAMBDA), y.rows(0, idx::LAMBDA));
    assert_eq!(c.consistent_state(t, &y).unwrap()[idx::LAMBDA], fn_);
    assert!(!c.lifted_off(t, &y, false) && !c.stepper_lift_off(&y));

    // A load torque that drives gear 2: the consistent force is negative, a lift-off.
    s.set_input(Input::TLoad, -1000.0).unwrap();
    s.do_step(t, 1e-4).unwrap();
    let (t, y) = (s.time(), *s.y());
    let c = s.model().contact();
    let fn_ = c.normal_force(t, &y);
    let expected = hidden_lambda(s.model(), t, &y, -1e3, -4e3);
    println!("rigid, driven load: normal force {fn_:.9e} N, hidden constraint {expected:.9e} N");
    assert!(fn_ < 0.0);
    assert!(
        (fn_ - expected).abs() <= 1e-6 * expected.abs(),
        "{fn_} vs {expected}"
    );
    assert!(c.lifted_off(t, &y, false) && c.lifted_off(t, &y, true));
    assert!(s.contact_lost());
}

#[test]
fn elastic_contact_answers_with_the_force_of_the_flanks() {
    let p = Params {
        tooth_contact: ToothContact::Elastic,
        mu: 0.05,
        ..Params::default()
    };
    let s = run(p, 100.0, 30);
    let (t, y) = (s.time(), *s.y());
    let model = s.model();
    let c = model.contact();
    assert_eq!(c.kind(), ToothContact::Elastic);
    assert_eq!(c.last_slot(), LastSlot::StoredSpringWork);
    assert!(!c.has_multiplier() && !c.lift_off_possible() && c.has_contact_events());

    // (3.16) from the gap output and the flow.
    let e = *model.elastic_mesh().unwrap();
    let cos_bb = model.geometry().cos_beta_b;
    let delta = |z: &SVector<f64, NY>| -cos_bb * model.outputs(t, z).gap;
    let yd = flow(model, t, &y);
    let eps = 1e-8;
    let d = delta(&y);
    let d_dot = (delta(&(y + yd * eps)) - delta(&(y - yd * eps))) / (2.0 * eps);
    let l = model.outputs(t, &y).contact_length;
    let expected = if d > 0.0 {
        l * (e.c_l * d + e.d_l * d_dot).max(0.0)
    } else {
        0.0
    };
    let fn_ = c.normal_force(t, &y);
    println!("elastic: normal force {fn_:.9e} N, (3.16) {expected:.9e} N (delta {d:.4e} m)");
    assert!(expected > 0.0);
    assert!(
        (fn_ - expected).abs() <= 1e-6 * expected,
        "{fn_} vs {expected}"
    );
    assert_eq!(s.outputs().fn_, fn_);

    // The drive flanks push: their event function is positive.
    let ev = c.event_functions(t, &y).unwrap();
    assert!(ev[0] > 0.0, "{ev:?}");
    // No multiplier: the output and the restart state are y; never a lift-off, whatever
    // the last slot.
    assert_eq!(c.output_state(t, &y), y);
    assert_eq!(c.consistent_state(t, &y).unwrap(), y);
    let mut neg = y;
    neg[idx::LAMBDA] = -1.0;
    assert!(!c.stepper_lift_off(&neg) && !c.lifted_off(t, &neg, false));
}
