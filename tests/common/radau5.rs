//! Set-up shared by the RADAU5 tests.

use super::radau5_problems::Pendulum2;
use geared_rotor::radau5::{Options, Tolerance};
use nalgebra::SVector;

/// Default options with rtol = atol = tol.
pub fn opts<const N: usize>(tol: f64) -> Options<N> {
    Options {
        rtol: Tolerance::Scalar(tol),
        atol: Tolerance::Scalar(tol),
        ..Options::default()
    }
}

/// The index-2 pendulum (g = 9.81) and a consistent start: angle 1 rad from the downward
/// vertical, at rest, lambda = g cos(1) (unit mass and length).
pub fn pendulum2() -> (Pendulum2, SVector<f64, 5>) {
    let g = 9.81;
    let y0 = SVector::<f64, 5>::new(1.0f64.sin(), -(1.0f64.cos()), 0.0, 0.0, g * 1.0f64.cos());
    (Pendulum2 { g }, y0)
}

/// `opts(tol)` for the pendulum: 4 index-1 components (positions, velocities), 1 index-2
/// component (lambda).
pub fn pendulum2_opts(tol: f64) -> Options<5> {
    Options {
        n1: 4,
        n2: 1,
        ..opts(tol)
    }
}
