//! The contract between the model-agnostic FMI layer ([`super::instance::Instance`]) and
//! one model (in the spirit of the Reference FMUs' `model.h`).
//!
//! The FMI layer owns the state machine, the argument checks (value references, types,
//! causality and variability, finite values, Enumeration items, declared bounds), logging,
//! the experiment, the FMU-state envelope and the status mapping. The model alone knows
//! what a variable means: it keeps the parameter and input values, computes outputs and
//! calculated parameters, steps, logs its own physics messages and writes its part of an
//! FMU state.

use super::error::ModelError;
use super::logging::Logger;
use super::state_machine::Phase;
use super::types::Fmi2Status;
use super::variables::Variable;
use crate::bytes::{Reader, Writer};

/// The experiment of fmi2SetupExperiment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Experiment {
    /// The master's tolerance (clamped into [`Model::TOLERANCE_RANGE`]), if defined.
    pub tolerance: Option<f64>,
    /// startTime.
    pub start: f64,
    /// stopTime, if defined.
    pub stop: Option<f64>,
}

impl Experiment {
    /// Before fmi2SetupExperiment (and after fmi2Reset).
    pub const DEFAULT: Experiment = Experiment {
        tolerance: None,
        start: 0.0,
        stop: None,
    };
}

/// One model behind the FMI layer. Every function is called after the FMI layer checked
/// the call sequence and the arguments; errors are the model's own type, mapped to a status
/// by [`super::error::FmuError::status`].
pub trait Model: Sized {
    /// The model's error.
    type Error: ModelError;
    /// The model's part of an FMU state: plain data, no pointers.
    type State: Clone;
    /// The range of relative tolerances the model's solver supports; a tolerance of
    /// fmi2SetupExperiment outside it is clamped into it with a warning.
    const TOLERANCE_RANGE: (f64, f64);
    /// The name of the model's relative-tolerance parameter that the experiment's
    /// tolerance stands in for (for messages).
    const TOLERANCE_NAME: &'static str;

    /// The model with every variable at its start value (fmi2Instantiate, fmi2Reset).
    fn instantiate() -> Self;
    /// Parameters, inputs or the experiment may have changed (fmi2SetupExperiment,
    /// fmi2EnterInitializationMode): whatever was built from them is stale.
    fn invalidate(&mut self);
    /// fmi2ExitInitializationMode: check the parameters and compute the initial state.
    ///
    /// # Errors
    /// The model's reason (invalid parameters, no consistent initial state).
    fn exit_initialization(&mut self, exp: &Experiment, log: &Logger) -> Result<(), Self::Error>;
    /// fmi2Terminate (e.g. log totals).
    fn terminate(&self, log: &Logger);
    /// The value of `var` (any causality); `phase` tells whether it is computed from
    /// parameters that may still change (initialization mode).
    ///
    /// # Errors
    /// The value cannot be computed (e.g. not initialised).
    fn get(
        &mut self,
        var: &'static Variable,
        phase: Phase,
        exp: &Experiment,
    ) -> Result<f64, Self::Error>;
    /// Sets an input or parameter the FMI layer checked (settable now, finite, an item of
    /// its Enumeration, within its declared bounds if those are checked when set).
    /// `stepping`: the model is initialised and runs (inputs and tunables reach it at once).
    ///
    /// # Errors
    /// The model refuses the value (its own rules).
    fn set(&mut self, var: &'static Variable, x: f64, stepping: bool) -> Result<(), Self::Error>;
    /// Sets the first time derivative of an input (fmi2SetRealInputDerivatives, order 1).
    ///
    /// # Errors
    /// The model refuses it.
    fn set_input_derivative(
        &mut self,
        var: &'static Variable,
        der: f64,
        stepping: bool,
    ) -> Result<(), Self::Error>;
    /// First derivatives of the Real outputs `vrs` (checked by the FMI layer) into `out`.
    ///
    /// # Errors
    /// Not available (e.g. not initialised).
    fn output_derivatives(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), Self::Error>;
    /// fmi2DoStep from `t` over `h` (the FMI layer checked the call sequence and stopTime).
    /// Returns OK or Warning (the model logged why).
    ///
    /// # Errors
    /// The model's reason; [`ModelError::is_discard`] decides Discard or Error.
    fn do_step(&mut self, t: f64, h: f64, log: &Logger) -> Result<Fmi2Status, Self::Error>;
    /// Accepted deviation of the communication point from the model time for a step `h`.
    fn step_tolerance(t: f64, h: f64) -> f64;
    /// The model time, if the model runs.
    fn time(&self) -> Option<f64>;
    /// Time of the last successful step, if the model runs.
    fn last_successful_time(&self) -> Option<f64>;
    /// The model's part of an FMU state.
    fn snapshot(&self) -> Self::State;
    /// Restores a snapshot (all or nothing).
    ///
    /// # Errors
    /// The state cannot be rebuilt.
    fn restore(&mut self, s: &Self::State) -> Result<(), Self::Error>;
    /// Appends the byte layout of `s`.
    fn write_state(s: &Self::State, w: &mut Writer);
    /// Reads what [`Model::write_state`] wrote.
    ///
    /// # Errors
    /// Truncated or impossible values.
    fn read_state(r: &mut Reader<'_>) -> Result<Self::State, Self::Error>;
    /// Checks a deserialized state before it is trusted (consistent but wrong blobs: another
    /// build, a tool that edited and resealed it).
    ///
    /// # Errors
    /// What is wrong, for the log.
    fn validate_state(s: &Self::State, phase: Phase, exp: &Experiment) -> Result<(), String>;
}
