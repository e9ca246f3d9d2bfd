//! The rotor DAE as a RADAU5 [`Problem`] and the physical scales of its state components,
//! shared by the co-simulation (`sim`) and the periodic solutions (`periodic`).

use super::{idx, GearedRotor, NY};
use crate::radau5::{Problem, RhsError};
use nalgebra::{SMatrix, SVector};

/// Physical scale of each state component; `atol_i = rtol * SCALES[i]`, so that an
/// absolute error of `rtol` relative to the typical magnitude of a component is accepted
/// even where the component itself passes through zero.
///
/// - centre displacements u (Q..Q+6): 1e-5 m, the static bearing deflection under the
///   nominal 2.7 kN contact force with k = 2e8 N/m (model.md §10);
/// - 7th position coordinate xi (transmission error along the line of action, metres, see
///   `rotor::idx::Q`): 1e-5 m, as the displacements;
/// - centre velocities (V..V+6): 1e-2 m/s, vibration of ~1e-6 m at the 1350 Hz mesh frequency;
/// - omega2 (V+6) and the filtered omega1: 1 rad/s; the filter's d(omega1)/dt: 1e3 rad/s^2;
/// - phi1: 2.5e-4 rad = 1e-5 m on a base radius of ~40 mm. phi1 grows without bound, so
///   its *relative* tolerance is also reduced to `rtol * PHI1_RTOL_FACTOR`: the allowance
///   `rtol_i |phi1|` would otherwise grow with time (phi1 sets the mesh phase);
/// - energies E_in, E_loss, E_damp, E_load: 1 J (E_in reaches ~1e3 J in 50 ms);
/// - lambda: 1e3 N, the order of the nominal contact force (RADAU5 also scales the error
///   of this index-2 variable with h, radau5.md §3).
pub const SCALES: [f64; NY] = scales();

const fn scales() -> [f64; NY] {
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
    s[idx::LAMBDA] = 1e3;
    s
}

/// The adapter that presents the rotor DAE to RADAU5 (`M y' = f(t, y)`).
#[derive(Clone)]
pub struct RotorProblem {
    /// The physics.
    pub model: GearedRotor,
}

impl Problem<NY> for RotorProblem {
    fn rhs(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        f: &mut SVector<f64, NY>,
    ) -> Result<(), RhsError> {
        // Allocation (the message) only on the error path.
        self.model.rhs(t, y, f).map_err(|e| RhsError {
            message: e.to_string(),
        })
    }
    fn jacobian(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        jac: &mut SMatrix<f64, NY, NY>,
    ) -> Result<bool, RhsError> {
        Ok(self.model.jacobian(t, y, jac))
    }
    fn mass(&self) -> Option<SMatrix<f64, NY, NY>> {
        Some(self.model.mass())
    }
}
