//! Guards of the simulation against masters and stored states (docs/fmu.md "Robustness"):
//! bounded work per doStep, progress of every internal step, and the checks a restored
//! [`SimState`] passes before it is trusted.

use super::{idx, DecodeError, SimError, SimState, Simulation, NY};
use crate::fmt_num::Short;
use nalgebra::SVector;

/// Default of the parameter `max_internal_steps`: most internal steps (RADAU5 steps and
/// landings on stop times) one doStep may take. At the default h_max = 1e-4 s that is at
/// least 5 s of simulated time per doStep (in steady state RADAU5 takes ~40 us steps,
/// so ~2 s of it). Measured: 100 000 steps took up to 1.3 s of wall time on the shared
/// 2-core VM under load, so 50 000 keep every doStep well below a second. A doStep that
/// needs more returns fmi2Discard where it stopped.
pub const DEFAULT_MAX_INTERNAL_STEPS: u64 = 50_000;

/// radau5.f's rule ("step size too small", `0.1 |h| <= uround |t|`): a step must advance
/// t by more than 10 uround |t| (uround = 1e-16), else t cannot resolve it.
pub const STEP_RESOLUTION: f64 = 10.0 * 1e-16;

/// Whether an internal step from `t_before` to `tn` made progress: it ends on `t_end`
/// (a communication point the stepper snapped onto) or advances t by more than
/// [`STEP_RESOLUTION`] |t|.
pub(super) fn advanced(t_before: f64, tn: f64, t_end: f64) -> bool {
    tn > t_before && (tn >= t_end || tn - t_before > STEP_RESOLUTION * t_before.abs())
}

/// The velocity-level contact constraint (model.md §3.3, `f[LAMBDA] = 0` of the DAE) must
/// hold at a restored state within this many times `rtol (v_scale + r_b1 |omega1|)`
/// (v_scale the velocity scale of `GearedRotor::scales`, 1e-2 m/s for the default pair): RADAU5 solves it at every accepted step to the Newton
/// tolerance. Measured over 60 communication points each of 5 runs (helical at rtol 1e-3,
/// 1e-6, 1e-9, frictionless, spur; a load change): at most 1.2e-4 of that scale (spur),
/// 2.2e-7 (helical), so 10 leaves a margin of ~1e5; a state that violates it is not one of
/// the stepper's solutions.
const CONSTRAINT_FACTOR: f64 = 10.0;

impl Simulation {
    /// Sets the most internal steps one [`Simulation::do_step`] may take (at least 1).
    pub fn set_max_internal_steps(&mut self, n: u64) {
        self.max_internal_steps = n.max(1);
    }

    /// The current limit of internal steps per doStep.
    pub fn max_internal_steps(&self) -> u64 {
        self.max_internal_steps
    }

    /// The work bound of one doStep, checked before each internal step: after `taken`
    /// steps, one more is allowed below `max_internal_steps`; otherwise the doStep stops at
    /// the last step taken with [`SimError::WorkLimit`]. Used by the adaptive and the
    /// real-time loop.
    pub(super) fn check_work(&mut self, taken: u64, t_end: f64) -> Result<(), SimError> {
        if taken < self.max_internal_steps {
            return Ok(());
        }
        let t = self.solver.t();
        Err(self.stop_at_last_step(
            t_end,
            SimError::WorkLimit {
                limit: self.max_internal_steps,
                t,
                t_end,
            },
        ))
    }

    /// Ends a doStep to `t_end` early: the FMU time and the last successful time become
    /// those of the last accepted step (t_end if that step went past it, look-ahead), and
    /// `e` is returned for the caller to pass on.
    pub(super) fn stop_at_last_step(&mut self, t_end: f64, e: SimError) -> SimError {
        let ts = self.solver.t().min(t_end);
        self.set_comm(ts);
        self.last_successful_time = ts;
        if !matches!(e, SimError::WorkLimit { .. }) {
            // As after any solver failure: the history after it is not trusted.
            self.restart_pending = true;
        }
        e
    }
}

fn refuse(message: String) -> SimError {
    SimError::Decode(DecodeError { message })
}

impl SimState {
    /// Checks a state read from outside before it is trusted: the RADAU5 snapshot is one
    /// the stepper could have produced with these settings ([`crate::radau5::Snapshot::check`]),
    /// the FMU time is the last successful time, and the stepper's state satisfies the
    /// contact constraint.
    ///
    /// # Errors
    /// [`SimError::Decode`] saying what is wrong.
    pub fn validate(&self) -> Result<(), SimError> {
        let mass = self.model.mass();
        // After a failure the next doStep restarts the stepper at its current point
        // before anything reads its history (no retake: the FMU time is the stepper's).
        let restart_due = self.restart_pending && self.t_comm == self.solver.t();
        self.solver
            .check(
                &self
                    .settings
                    .options_for(self.model.scales(), self.model.params().tooth_contact),
                Some(&mass),
                restart_due,
            )
            .map_err(|e| refuse(format!("RADAU5 snapshot: {e}")))?;
        super::realtime::check_h_fixed(self.h_fixed)
            .map_err(|e| refuse(format!("real-time mode: {e}")))?;
        if self.last_successful_time != self.t_comm {
            return Err(refuse(format!(
                "last successful time {} differs from the FMU time {}",
                Short(self.last_successful_time),
                Short(self.t_comm)
            )));
        }
        for (what, i) in [
            ("inputs", &self.inputs),
            ("input reference", &self.inputs_ref),
        ] {
            if i.t_ref > self.solver.t() {
                return Err(refuse(format!(
                    "{what} refer to t = {}, after the solver time {}",
                    Short(i.t_ref),
                    Short(self.solver.t())
                )));
            }
        }
        let (t, y) = (self.solver.t(), self.solver.y());
        if self.model.contact().has_multiplier() && y[idx::E_MESH_DAMP] != 0.0 {
            // Rigid teeth have no mesh damping: the slot stays 0 (and out of the norms).
            return Err(refuse(format!(
                "mesh damping energy {} with rigid teeth (must be 0)",
                Short(y[idx::E_MESH_DAMP])
            )));
        }
        if !self.model.contact().has_multiplier() {
            // No constraint with the elastic contact (model.md §3.5): the model must only
            // evaluate the state.
            let mut model = self.model.clone();
            let mut f = SVector::<f64, NY>::zeros();
            return model.rhs(t, y, &mut f).map(|_| ()).map_err(|e| {
                refuse(format!(
                    "the model rejects the state at t = {}: {e}",
                    Short(t)
                ))
            });
        }
        let residual = self.constraint_residual(t, y)?;
        let g = self.model.geometry();
        let tol = CONSTRAINT_FACTOR
            * self.settings.rtol
            * (self.model.scales()[idx::V] + g.rb1 * y[idx::OMEGA1].abs());
        if residual.is_nan() || residual.abs() > tol {
            return Err(refuse(format!(
                "the state at t = {} violates the contact constraint: residual {} m/s, tolerance {} m/s",
                Short(t),
                Short(residual),
                Short(tol)
            )));
        }
        Ok(())
    }

    /// `G(q) v - r_b1 cos(beta_b) omega1` at (t, y) (the DAE's last row). Rigid teeth only:
    /// this is the algebra of their index-2 DAE, whose constraint row is the row of the
    /// multiplier, `idx::LAMBDA`, in f.
    fn constraint_residual(&self, t: f64, y: &SVector<f64, NY>) -> Result<f64, SimError> {
        let mut model = self.model.clone();
        let mut f = SVector::<f64, NY>::zeros();
        model.rhs(t, y, &mut f).map_err(|e| {
            refuse(format!(
                "the state violates the contact constraint (the model rejects it: {e})"
            ))
        })?;
        Ok(f[idx::LAMBDA])
    }

    /// The parameters the simulation was initialised with (tunables at their initial
    /// values).
    pub fn init_params(&self) -> &crate::rotor::Params {
        &self.init.params
    }

    /// The values of the state that have declared bounds as FMU variables (name as in the
    /// model description, value), for the FMU layer to check against them.
    pub fn named_values(&self) -> [(&'static str, f64); 11] {
        let p0 = &self.init.params;
        let p = self.model.params();
        let i0 = &self.init.inputs;
        let i = &self.inputs;
        [
            ("mu", p0.mu),
            ("mu", p.mu),
            ("d_phi", p0.d_phi),
            ("d_phi", p.d_phi),
            ("omega1_filter_frequency", p0.omega1_filter_hz),
            ("rtol", self.settings.rtol),
            ("h_max", self.settings.h_max),
            ("omega1", i0.omega1),
            ("omega1", i.omega1_at(self.t_comm)),
            ("T_load", i0.t_load),
            ("T_load", i.t_load_at(self.t_comm)),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotor::Params;
    use crate::sim::{Input, SolverSettings};

    /// The states the stepper produces pass the constraint check with a wide margin
    /// (helical and spur, with and without friction, a load change, communication steps of
    /// 1 ms and 37 us): the largest residual relative to `rtol (v_scale + r_b1 |omega1|)`.
    #[test]
    fn states_of_the_stepper_pass_the_checks_with_margin() {
        let mut spur = Params::default();
        spur.gear.beta = 0.0;
        let cases = [
            (Params::default(), 1e-6),
            (Params::default(), 1e-9),
            (Params::default(), 1e-3),
            (
                Params {
                    mu: 0.0,
                    ..Params::default()
                },
                1e-6,
            ),
            (spur, 1e-6),
        ];
        let mut worst_all = 0.0f64;
        for (params, rtol) in cases {
            let settings = SolverSettings { rtol, h_max: 1e-4 };
            let mut sim = Simulation::new(params, settings, 0.0, 314.159, 0.0).unwrap();
            let mut worst = 0.0f64;
            let mut t = 0.0;
            for k in 0..60 {
                if k == 30 {
                    sim.set_input(Input::TLoad, 50.0).unwrap();
                }
                let h = if k % 3 == 0 { 3.7e-5 } else { 1e-3 };
                sim.do_step(t, h).unwrap();
                t += h;
                let s = sim.state();
                s.validate().unwrap();
                let (ts, y) = (s.solver.t(), s.solver.y());
                let r = s.constraint_residual(ts, y).unwrap();
                let scale = rtol
                    * (s.model.scales()[idx::V] + s.model.geometry().rb1 * y[idx::OMEGA1].abs());
                worst = worst.max(r.abs() / scale);
            }
            eprintln!(
                "rtol {rtol:e}, mu {}, beta {}: worst residual {worst:.3e} rtol-scales",
                params.mu, params.gear.beta
            );
            worst_all = worst_all.max(worst);
        }
        assert!(worst_all < 1e-2 * CONSTRAINT_FACTOR, "{worst_all:e}");
    }

    #[test]
    fn progress_rule() {
        // Lands on the communication point: progress, however short.
        assert!(advanced(1.0, 1.0 + f64::EPSILON, 1.0 + f64::EPSILON));
        // A few ulps short of it at t = 1: below 10 uround |t|.
        assert!(!advanced(1.0, 1.0 + 2.0 * f64::EPSILON, 2.0));
        assert!(!advanced(1.0, 1.0, 2.0));
        assert!(advanced(1.0, 1.0 + 1e-14, 2.0));
        // At t = 0 any advance counts (radau5.f: |t| uround = 0).
        assert!(advanced(0.0, 1e-300, 1.0));
    }
}
