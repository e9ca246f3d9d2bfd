//! The physical scale of each state component, from which the absolute tolerances follow
//! (`atol_i = rtol scale_i`): an error of `rtol` relative to the typical size of a component
//! is accepted even where the component passes through zero.
//!
//! The values were chosen for the default pair (model.md §10) at its default start (3000
//! rpm, no load torque) from its physics ([`DEFAULT_PAIR_SCALES`]); for another pair or
//! start each is scaled by the ratio of the physical quantity behind it to the default's
//! ([`error_scales`]), fixed at the start (the stepper's tolerances do not change during a
//! run):
//!
//! - load: the nominal normal force at the start inputs (`GearedRotor::nominal_lambda`:
//!   damper and load torque), taken between 0.3 and 100 times what the pair's size
//!   carries (load capacity ~ face width times module at the default's tooth stress),
//!   over the default's 2.68 kN;
//! - deflection: that load on the bearings, `D = L / K` with `K` the transverse bearing
//!   stiffness of both rotors in series (each the mean of x and y) over the default's;
//! - vibration speed: the deflection times the bearings' natural frequency, `D W` with
//!   `W = sqrt(K / Mr)`, `Mr` the rotors' masses in series over the default's (deflection
//!   and speed ratios kept within 1e-6..1e2);
//! - energies: load times deflection; the last slot: the load where it is the multiplier
//!   lambda (rigid teeth), the energies' scale where it is the work stored in the mesh
//!   springs (elastic teeth, `Contact::last_slot`); phi1: the deflection on gear 1's base
//!   circle.
//!
//! For the default pair at its default start every ratio is exactly 1, so its results do
//! not change; a start at 1500 rpm gets half the deflection scales, a start from rest 0.3
//! of them, a lightly loaded small pair correspondingly tighter ones.

use super::{idx, GearedRotor, Inputs, Params, NY};

/// The scales of the default pair and what they stand for:
/// - centre displacements u (Q..Q+6) and the transmission error xi: 1e-5 m, the static
///   bearing deflection under its nominal 2.7 kN contact force with k = 2e8 N/m;
/// - centre velocities (V..V+6): 1e-2 m/s, a vibration of ~1e-6 m at the 1350 Hz mesh
///   frequency;
/// - omega2 (V+6) and the filtered omega1: 1 rad/s; the filter's d(omega1)/dt: 1e3 rad/s^2;
/// - phi1: 2.5e-4 rad = 1e-5 m on a base radius of ~40 mm. phi1 grows without bound, so
///   its *relative* tolerance is also reduced (`sim::PHI1_RTOL_FACTOR`);
/// - energies E_in, E_loss, E_damp, E_load: 1 J (E_in reaches ~1e3 J in 50 ms);
/// - lambda: 1e3 N, the order of the nominal contact force (RADAU5 also scales the error
///   of this index-2 variable with h, radau5.md §3); the layout of rigid teeth, whose last
///   slot is lambda (elastic teeth hold an energy there: [`error_scales`]).
pub const DEFAULT_PAIR_SCALES: [f64; NY] = default_pair();

/// Alias of [`DEFAULT_PAIR_SCALES`] for code that works with the default pair (tests).
pub const SCALES: [f64; NY] = DEFAULT_PAIR_SCALES;

const fn default_pair() -> [f64; NY] {
    let mut s = [1.0; NY];
    let mut i = 0;
    while i < 6 {
        s[idx::Q + i] = 1e-5;
        s[idx::V + i] = 1e-2;
        i += 1;
    }
    s[idx::Q + 6] = 1e-5;
    s[idx::V + 6] = 1.0;
    s[idx::PHI1] = 2.5e-4;
    s[idx::OMEGA1] = 1.0;
    s[idx::OMEGA1_DOT] = 1e3;
    s[idx::E_IN] = 1.0;
    s[idx::E_LOSS] = 1.0;
    s[idx::E_DAMP] = 1.0;
    s[idx::E_LOAD] = 1.0;
    s[idx::E_MESH_DAMP] = 1.0;
    s[idx::LAMBDA] = 1e3;
    s
}

/// The calibration point of [`DEFAULT_PAIR_SCALES`]: the default pair at its default
/// drive speed (3000 rpm) without load torque.
pub const CALIBRATION_OMEGA1: f64 = 314.159;

/// The start load is taken within these multiples of the load-capacity scale: below, a
/// start from standstill without load torque has no nominal load at all, and tolerances
/// set by a tiny start load would stay 100 times too tight for the run that follows (a
/// run-up from rest to 3000 rpm took 14 064 steps instead of 5 537 with a 1 % floor, for
/// the same T1 to 1e-8); above, a load no gear of that size carries (an absurd input) would
/// make the tolerances absurd too.
const LOAD_RANGE: (f64, f64) = (0.3, 1e2);

/// The deflection and speed ratios are kept within these bounds (a pair without transverse
/// bearing stiffness has no static deflection at all).
const RATIO_RANGE: (f64, f64) = (1e-6, 1e2);

/// Transverse bearing stiffness seen by the mesh: both rotors' bearings in series, each
/// the mean of its x and y stiffness (N/m).
fn mesh_stiffness(q: &Params) -> f64 {
    let k1 = 0.5 * (q.rotor1.k[0] + q.rotor1.k[1]);
    let k2 = 0.5 * (q.rotor2.k[0] + q.rotor2.k[1]);
    if k1 > 0.0 && k2 > 0.0 {
        1.0 / (1.0 / k1 + 1.0 / k2)
    } else {
        0.0
    }
}

/// The rotors' masses in series (the mass of their relative motion, kg).
fn relative_mass(q: &Params) -> f64 {
    let (m1, m2) = (q.rotor1.m, q.rotor2.m);
    m1 * m2 / (m1 + m2)
}

/// The ratios of [`error_scales`] against the default pair at its calibration point: load,
/// deflection, vibration speed, and the angle of a deflection on the base circle of gear 1
/// (phi1 is its angle).
fn ratios(model: &GearedRotor, t0: f64, cal: &GearedRotor) -> [f64; 4] {
    let (p, d) = (model.params(), cal.params());
    let (g, dg) = (model.geometry(), cal.geometry());
    let lam0 = cal.nominal_lambda(0.0).abs();
    // The start load, within LOAD_RANGE of what the pair's size carries (load capacity ~
    // b m_n at the default's tooth stress).
    let capacity = lam0 * (g.data.b * g.data.m_n) / (dg.data.b * dg.data.m_n);
    let start = model.nominal_lambda(t0).abs();
    let load = start.clamp(LOAD_RANGE.0 * capacity, LOAD_RANGE.1 * capacity) / lam0;
    let k = mesh_stiffness(p) / mesh_stiffness(d);
    let clamp = |x: f64| {
        if x.is_finite() {
            x.clamp(RATIO_RANGE.0, RATIO_RANGE.1)
        } else {
            RATIO_RANGE.1
        }
    };
    let defl = clamp(load / k);
    let speed = clamp(defl * (k / (relative_mass(p) / relative_mass(d))).sqrt());
    let angle = defl * (dg.rb1 / g.rb1);
    [load, defl, speed, angle]
}

/// The scales for `model` started at t0 (its parameters and start inputs):
/// [`DEFAULT_PAIR_SCALES`] times the ratios of the module docs, the last slot in the unit
/// the contact gives it. Exactly [`DEFAULT_PAIR_SCALES`] for the default pair (rigid
/// teeth) at its calibration point.
pub fn error_scales(model: &GearedRotor, t0: f64) -> [f64; NY] {
    let Ok(mut cal) = GearedRotor::new(Params::default()) else {
        return DEFAULT_PAIR_SCALES;
    };
    cal.set_inputs(Inputs {
        omega1: CALIBRATION_OMEGA1,
        ..Inputs::default()
    });
    let [load, defl, speed, angle] = ratios(model, t0, &cal);
    let mut s = DEFAULT_PAIR_SCALES;
    for i in 0..6 {
        s[idx::Q + i] *= defl;
        s[idx::V + i] *= speed;
    }
    s[idx::Q + 6] *= defl;
    s[idx::PHI1] *= angle;
    for i in [
        idx::E_IN,
        idx::E_LOSS,
        idx::E_DAMP,
        idx::E_LOAD,
        idx::E_MESH_DAMP,
    ] {
        s[i] *= load * defl;
    }
    // A force or an energy, as the contact's last slot is (`Contact::last_slot`).
    s[idx::LAMBDA] = model
        .contact()
        .last_slot()
        .scale(s[idx::LAMBDA] * load, s[idx::E_IN]);
    s
}
