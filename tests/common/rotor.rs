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
