//! The contract between the model-agnostic FMI layer ([`super::instance::Instance`]) and
//! one model (in the spirit of the Reference FMUs' `model.h`). It is version-neutral: the
//! FMI 2.0 shell (`crate::c_abi`) and the FMI 3.0 shell (`crate::c_abi3`, through
//! `crate::fmi3`) drive the same model through it; function names reach the model only as
//! the `func` of a call, for its messages.
//!
//! The FMI layer owns the state machine, the argument checks (value references, types,
//! causality and variability, finite values, Enumeration items, declared bounds), logging,
//! the experiment, the FMU-state envelope and the status mapping. The model alone knows
//! what a variable means: it keeps the parameter and input values, computes outputs and
//! calculated parameters, steps, logs its own physics messages and writes its part of an
//! FMU state.

use super::error::ModelError;
use super::logging::Logger;
use super::variables::Variable;
use crate::bytes::{Reader, Writer};

/// The phase of an instance as the model sees it (defined with the state machine, which
/// both FMI versions share: FMI 3.0's Step Mode and Step Discarded are
/// [`Phase::StepComplete`] and [`Phase::StepFailed`]).
pub use super::state_machine::Phase;

/// The status of an FMI call, in words common to FMI 2.0 and 3.0 (`fmi2Status` and
/// `fmi3Status` have the same first five values); each C shell converts it to its own type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    /// fmi2OK / fmi3OK
    OK = 0,
    /// fmi2Warning / fmi3Warning
    Warning = 1,
    /// fmi2Discard / fmi3Discard
    Discard = 2,
    /// fmi2Error / fmi3Error
    Error = 3,
    /// fmi2Fatal / fmi3Fatal
    Fatal = 4,
}

/// How a doStep ended when the master allowed it to end early (FMI 3.0 early return).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepEnd {
    /// OK or Warning (the model logged why).
    pub status: Status,
    /// `Some(t)`: the step ended early at `t` at an event of the model (the model time is
    /// `t`); `None`: it reached the end of the communication step.
    pub early_return: Option<f64>,
}

/// The experiment: fmi2SetupExperiment, or the arguments of fmi3EnterInitializationMode.
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
    /// Before the experiment is set (and after a reset).
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
    /// the experiment outside it is clamped into it with a warning.
    const TOLERANCE_RANGE: (f64, f64);
    /// The name of the model's relative-tolerance parameter that the experiment's
    /// tolerance stands in for (for messages).
    const TOLERANCE_NAME: &'static str;

    /// The model with every variable at its start value (instantiate, reset).
    fn instantiate() -> Self;
    /// Parameters, inputs or the experiment may have changed (experiment set, initialization
    /// mode entered): whatever was built from them is stale.
    fn invalidate(&mut self);
    /// Exit initialization mode: check the parameters and compute the initial state.
    ///
    /// # Errors
    /// The model's reason (invalid parameters, no consistent initial state).
    /// `func` is the FMI function, for messages.
    fn exit_initialization(
        &mut self,
        func: &'static str,
        exp: &Experiment,
        log: &Logger,
    ) -> Result<(), Self::Error>;
    /// Terminate (e.g. log totals).
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
    /// Sets the first time derivative of an input (fmi2SetRealInputDerivatives, order 1; FMI 3.0 has no such function).
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
    /// doStep from `t` over `h` (the FMI layer checked the call sequence and stopTime);
    /// `func` is the FMI function, for messages. Returns OK or Warning (the model logged why).
    ///
    /// # Errors
    /// The model's reason; [`ModelError::is_discard`] decides Discard or Error.
    fn do_step(
        &mut self,
        func: &'static str,
        t: f64,
        h: f64,
        log: &Logger,
    ) -> Result<Status, Self::Error>;
    /// A doStep that may end early at an event of the model (FMI 3.0 `earlyReturnAllowed`):
    /// where [`Model::do_step`] would only report the event (with a warning), it stops
    /// there instead. The default never returns early.
    ///
    /// # Errors
    /// As [`Model::do_step`].
    fn do_step_until_event(
        &mut self,
        func: &'static str,
        t: f64,
        h: f64,
        log: &Logger,
    ) -> Result<StepEnd, Self::Error> {
        self.do_step(func, t, h, log).map(|status| StepEnd {
            status,
            early_return: None,
        })
    }
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
