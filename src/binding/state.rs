//! The model's part of an FMU state: the value store, the input derivatives and the
//! simulation's snapshot; its byte layout and the checks of a deserialized one.

use super::error::BindingError;
use super::values::{self, Values};
use crate::bytes::{DecodeError, Reader, Writer};
use crate::fmi2::bounds;
use crate::fmi2::model::Experiment;
use crate::fmi2::model::Phase;
use crate::fmi2::variables::{self, Var, N_VARIABLES};
use crate::fmt_num::Short;
use crate::sim::{SimError, SimState};

/// The geared rotor's part of an FMU state (plain data).
#[derive(Clone)]
pub struct BindingState {
    pub(super) values: Values,
    pub(super) input_der: [f64; 2],
    /// None while the simulation is stale or not built (before initialisation).
    pub(super) sim: Option<SimState>,
}

fn de(message: &str) -> BindingError {
    BindingError::Sim(SimError::Decode(DecodeError {
        message: message.into(),
    }))
}

impl BindingState {
    /// Appends the layout: variable count, values, input derivatives, simulation flag and
    /// the simulation's snapshot.
    pub fn write(&self, w: &mut Writer) {
        w.u32(N_VARIABLES as u32);
        for x in self.values {
            w.f64(x);
        }
        w.f64(self.input_der[0]);
        w.f64(self.input_der[1]);
        w.bool(self.sim.is_some());
        if let Some(ss) = &self.sim {
            ss.write(w);
        }
    }

    /// Reads what [`BindingState::write`] wrote.
    ///
    /// # Errors
    /// Truncated buffer, another variable count, non-finite values, a bad simulation part.
    pub fn read(r: &mut Reader<'_>) -> Result<BindingState, BindingError> {
        let d = |e: DecodeError| BindingError::Sim(SimError::Decode(e));
        if r.u32("variable count").map_err(d)? as usize != N_VARIABLES {
            return Err(de("variable count differs"));
        }
        let mut values = [0.0; N_VARIABLES];
        for x in values.iter_mut() {
            *x = r.finite("variable value").map_err(d)?;
        }
        let input_der = [
            r.finite("input derivative").map_err(d)?,
            r.finite("input derivative").map_err(d)?,
        ];
        let sim = if r.bool("simulation flag").map_err(d)? {
            Some(SimState::read(r)?)
        } else {
            None
        };
        Ok(BindingState {
            values,
            input_der,
            sim,
        })
    }

    /// What is wrong with a deserialized state, if anything (docs/fmu.md "Robustness").
    pub fn validate(&self, phase: Phase, exp: &Experiment) -> Result<(), String> {
        // Inputs and tunables are checked when set, whatever the phase; the solver
        // parameters by fmi2ExitInitializationMode (rtol only if it is used), so only once
        // a simulation exists; the other parameters are compared with the simulation's
        // below.
        for (var, &x) in variables::VARIABLES.iter().zip(self.values.iter()) {
            let at_init = values::CHECKED_AT_INIT.contains(&var.name)
                || (var.var == Var::rtol && exp.tolerance.is_none());
            if bounds::checked_when_set(var) || (at_init && self.sim.is_some()) {
                bounds::check(var, x).map_err(|e| format!("variable {e}"))?;
            }
        }
        let Some(sim) = &self.sim else {
            return match phase {
                Phase::StepComplete | Phase::StepFailed => {
                    Err(format!("phase {phase:?} without a simulation"))
                }
                _ => Ok(()),
            };
        };
        sim.validate().map_err(|e| match e {
            SimError::Decode(d) => d.message,
            e => e.to_string(),
        })?;
        // The simulation's own values: within the declared bounds, and the tunables and
        // solver settings equal to the parameter store.
        for (name, x) in sim.named_values() {
            if let Some(var) = variables::by_name(name) {
                bounds::check(var, x).map_err(|e| format!("simulation value {e}"))?;
            }
        }
        let v = |var: Var| self.values[var as usize];
        let [(_, _), (_, mu), (_, _), (_, d_phi), (_, f_c), (_, rtol), (_, h_max), ..] =
            sim.named_values();
        let mut pairs = vec![
            ("mu", mu, v(Var::mu)),
            ("d_phi", d_phi, v(Var::d_phi)),
            ("h_max", h_max, v(Var::h_max)),
        ];
        if !matches!(phase, Phase::Instantiated | Phase::InitializationMode) {
            pairs.push((
                "omega1_filter_frequency",
                f_c,
                v(Var::omega1_filter_frequency),
            ));
            pairs.push(("rtol", rtol, exp.tolerance.unwrap_or(v(Var::rtol))));
        }
        // The fixed parameters of the store are those the simulation was initialised with
        // (the tunables compared above may have changed since).
        let mut stored =
            values::params(&self.values).map_err(|e| format!("stored parameters: {e}"))?;
        let init = sim.init_params();
        stored.mu = init.mu;
        stored.d_phi = init.d_phi;
        if stored != *init {
            return Err(
                "the stored parameters differ from those the simulation was initialised with"
                    .into(),
            );
        }
        for (name, in_sim, stored) in pairs {
            if in_sim != stored {
                return Err(format!(
                    "{name} of the simulation ({}) differs from the stored parameter ({})",
                    Short(in_sim),
                    Short(stored)
                ));
            }
        }
        Ok(())
    }
}
