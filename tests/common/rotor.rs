//! Set-up shared by the geared-rotor model tests.

use geared_rotor::rotor::{GearedRotor, Inputs, Params};

/// Diagonal of the mass matrix of the velocity block v = (u1', u2', phi2') (model.md §5):
/// m1 three times, m2 three times, J2.
pub fn masses(p: &Params) -> [f64; 7] {
    [
        p.rotor1.m, p.rotor1.m, p.rotor1.m, p.rotor2.m, p.rotor2.m, p.rotor2.m, p.rotor2.j,
    ]
}

/// The model with parameters `p`, driven at constant omega1 with all other inputs at their
/// defaults (no load).
pub fn driven(p: Params, omega1: f64) -> GearedRotor {
    let mut model = GearedRotor::new(p).unwrap();
    model.set_inputs(Inputs {
        omega1,
        ..Inputs::default()
    });
    model
}

/// Largest deviation of `a` from `b` in units of the physical scales of the simulation
/// (`sim::SCALES`, the atol of each component divided by rtol; 1e-3 of |b| where that is
/// larger), lambda excluded (an algebraic component; the outputs re-project it). Returns
/// the deviation and the component.
pub fn scaled_dev(
    a: &nalgebra::SVector<f64, { geared_rotor::rotor::NY }>,
    b: &nalgebra::SVector<f64, { geared_rotor::rotor::NY }>,
) -> (f64, usize) {
    use geared_rotor::rotor::{idx, NY};
    use geared_rotor::sim::SCALES;
    let mut worst = (0.0, 0);
    for i in 0..NY {
        if i == idx::LAMBDA {
            continue;
        }
        let d = (a[i] - b[i]).abs() / SCALES[i].max(1e-3 * b[i].abs());
        if d > worst.0 {
            worst = (d, i);
        }
    }
    worst
}
