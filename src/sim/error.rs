//! Everything that can go wrong in the simulation layer, as one typed enum.

use super::init::InitError;
use super::validity::Violation;
use crate::bytes::DecodeError;
use crate::fmt_num::Short;
use crate::parameter::ParamError;
use crate::radau5;
use crate::rotor::ModelError;
use std::fmt;

/// Everything that can go wrong in the simulation layer.
#[derive(Debug, Clone, PartialEq)]
pub enum SimError {
    /// A parameter violates a bound (the model's or the solver settings').
    Param(ParamError),
    /// The model could not set up a consistent initial state.
    Model(ModelError),
    /// RADAU5 could not continue; the state is that of `last_successful_time`.
    Solver {
        /// The stepper's error (with t and h).
        error: radau5::Error,
        /// Time of the last accepted step (the FMU's time now).
        last_successful_time: f64,
    },
    /// Communication step size not positive, not finite, or below the resolution of t.
    StepSize {
        /// The step size.
        h: f64,
        /// The current time.
        t: f64,
    },
    /// The communication point does not match the FMU's time.
    CommunicationPoint {
        /// FMU time.
        expected: f64,
        /// What the master passed.
        got: f64,
        /// Accepted deviation.
        tolerance: f64,
    },
    /// NaN or infinite input or parameter value.
    NonFinite {
        /// Variable name.
        name: &'static str,
        /// The value.
        value: f64,
    },
    /// A serialized state could not be read.
    Decode(DecodeError),
    /// The requested initial state (`initialization`) could not be set.
    Init(InitError),
    /// The run left the model's validity (lift-off, drive reversal) and the policy is
    /// [`OnViolation::Discard`](super::OnViolation::Discard): the FMU time is the located instant.
    Validity(Violation),
    /// The doStep took `max_internal_steps` internal steps without reaching its end; the
    /// state is that of the last of them (`t`).
    WorkLimit {
        /// The limit (parameter max_internal_steps).
        limit: u64,
        /// Where the doStep stopped (the last successful time).
        t: f64,
        /// The end of the communication interval.
        t_end: f64,
    },
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Param(e) => write!(f, "{e}"),
            SimError::Model(e) => write!(f, "model error: {e}"),
            SimError::Solver { error, last_successful_time } => {
                write!(f, "RADAU5 cannot continue: {error}; state kept at the last successful time t = {last_successful_time:e} s")?;
                if matches!(error, radau5::Error::FixedStepNewton { .. }) {
                    write!(f, " (real-time mode: choose a smaller h_fixed, or a larger rtol, which sets the Newton tolerance)")?;
                }
                Ok(())
            }
            SimError::StepSize { h, t } => {
                write!(f, "communication step size h = {h:e} s is not a positive finite step that advances t = {t:e} s")
            }
            SimError::CommunicationPoint { expected, got, tolerance } => write!(
                f,
                "currentCommunicationPoint = {} s does not match the FMU time {} s (tolerance {tolerance:e} s)",
                Short(*got),
                Short(*expected)
            ),
            SimError::NonFinite { name, value } => write!(f, "{name} = {value} is not a finite number"),
            SimError::Decode(e) => write!(f, "invalid serialized FMU state: {e}"),
            SimError::Init(e) => write!(f, "initialization: {e}"),
            SimError::Validity(v) => write!(f, "{v}"),
            SimError::WorkLimit { limit, t, t_end } => write!(
                f,
                "stopped after {limit} internal steps (parameter max_internal_steps) at t = {} s, before the end of the communication step at {} s; state kept there (raise max_internal_steps or take shorter steps)",
                Short(*t),
                Short(*t_end)
            ),
        }
    }
}

impl std::error::Error for SimError {}

impl SimError {
    /// Whether the error leaves the simulation at its last successful time with a reason a
    /// master can act on by rolling back and retrying with a smaller step (FMI's
    /// fmi2Discard, when it comes from a step): the solver could not continue (except for
    /// an invalid option or a stop time behind t, which are errors of the set-up), the model
    /// has no consistent state after a change, the work limit, or the run left the model's
    /// validity with `on_lift_off = discard`.
    pub fn is_discard(&self) -> bool {
        match self {
            SimError::Solver { error, .. } => !matches!(
                error,
                radau5::Error::InvalidOption { .. } | radau5::Error::StopTimeBehind { .. }
            ),
            SimError::Model(_) | SimError::WorkLimit { .. } | SimError::Validity(_) => true,
            _ => false,
        }
    }
}

impl From<ParamError> for SimError {
    fn from(e: ParamError) -> Self {
        SimError::Param(e)
    }
}

impl From<DecodeError> for SimError {
    fn from(e: DecodeError) -> Self {
        SimError::Decode(e)
    }
}

pub(super) fn solver_err(error: radau5::Error, t: f64) -> SimError {
    SimError::Solver {
        error,
        last_successful_time: t,
    }
}
