//! Solver settings fixed at initialisation: rtol, h_max and the RADAU5 options the
//! simulation runs with (per-component tolerances from the physical scales).

use super::mesh_events::MESH_EVENT_RESUME;
use crate::parameter::ParamError;
use crate::radau5::{Options, Tolerance};
use crate::rotor::{dae_structure, idx, ToothContact, NY};
use nalgebra::SVector;

/// Factor on rtol for phi1 (see `rotor::DEFAULT_PAIR_SCALES`): with 1e-3 the relative part stays below the
/// absolute one for |phi1| < 250 rad (0.8 s at the default speed) and grows slowly after.
pub const PHI1_RTOL_FACTOR: f64 = 1e-3;

/// The range of rtol (the declared min and max of the parameter `rtol`).
pub const RTOL_MIN: f64 = 1e-13;
/// See [`RTOL_MIN`].
pub const RTOL_MAX: f64 = 0.1;

/// Floor of phi1's relative tolerance: RADAU5 needs rtol > 10 uround = 1e-15 for every
/// component, and `rtol * PHI1_RTOL_FACTOR` would go below it for rtol < 1e-12 (the
/// declared rtol goes down to 1e-13).
pub(super) const PHI1_RTOL_MIN: f64 = 1e-14;

/// Most internal steps one communication interval may take before the stepper gives up
/// (radau5 `max_steps` counts since the last stop time): 1e6 steps of the default
/// h_max = 1e-4 s cover 100 s of simulated time in one doStep.
pub const MAX_STEPS_PER_INTERVAL: u64 = 1_000_000;

/// Solver settings fixed at initialisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// Relative tolerance (from fmi2SetupExperiment if defined, else the `rtol` parameter).
    pub rtol: f64,
    /// Maximum internal step size in s.
    pub h_max: f64,
}

impl SolverSettings {
    /// Validates the settings, naming the parameter and the bound.
    ///
    /// # Errors
    /// rtol outside [1e-13, 0.1], h_max not positive.
    pub fn validate(&self) -> Result<(), ParamError> {
        if !(self.rtol >= RTOL_MIN && self.rtol <= RTOL_MAX) {
            return Err(ParamError {
                name: "rtol",
                value: self.rtol,
                requirement: "1e-13 <= rtol <= 0.1 (the declared min and max)".into(),
            });
        }
        if !(self.h_max > 0.0 && self.h_max.is_finite()) {
            return Err(ParamError {
                name: "h_max",
                value: self.h_max,
                requirement: "0 < h_max < inf".into(),
            });
        }
        Ok(())
    }

    /// The RADAU5 options the simulation runs with: tolerances from the physical scales of
    /// the state components (`scales`: `GearedRotor::scales`), the DAE's structure
    /// (`rotor::dae_structure`), h_max, the step budget and the resumption after a stop.
    pub fn options(&self, scales: &[f64; NY]) -> Options<NY> {
        self.options_for(scales, ToothContact::Rigid)
    }

    /// [`SolverSettings::options`] for the contact model `contact` (the index counts of
    /// `rotor::dae_structure`).
    pub fn options_for(&self, scales: &[f64; NY], contact: ToothContact) -> Options<NY> {
        Options::<NY> {
            rtol: Tolerance::PerComponent(SVector::<f64, NY>::from_fn(|i, _| {
                if i == idx::PHI1 {
                    (self.rtol * PHI1_RTOL_FACTOR).max(PHI1_RTOL_MIN)
                } else {
                    self.rtol
                }
            })),
            atol: Tolerance::PerComponent(SVector::<f64, NY>::from_fn(|i, _| {
                self.rtol * scales[i]
            })),
            h_max: self.h_max,
            max_steps: MAX_STEPS_PER_INTERVAL,
            // Clipped steps end on mesh events (kinks of f) here, not on smooth points.
            resume_after_stop: MESH_EVENT_RESUME,
            ..dae_structure(contact)
        }
    }
}
