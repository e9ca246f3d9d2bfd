//! Every error an FMI call can produce, as one typed enum, and THE mapping of errors to FMI
//! statuses ([`FmuError::status`]). Errors of the model behind the FMI layer are carried
//! as [`FmuError::Model`]; the model error says itself whether it is a discard
//! ([`ModelError::is_discard`]).

use super::bounds::OutOfBounds;
use super::model::Status;
use super::state_machine::Phase;
use crate::bytes::DecodeError;
use crate::fmt_num::Short;
use std::fmt;

/// What the FMI layer needs to know of a model's error.
pub trait ModelError: fmt::Display + fmt::Debug {
    /// Whether this error, from a doStep, means Discard (the state is that of the
    /// last successful time; the master may roll back and retry with a smaller step). From
    /// any other function every model error is fmi2Error.
    fn is_discard(&self) -> bool;
}

/// Every error an FMI call can produce.
#[derive(Debug, Clone, PartialEq)]
pub enum FmuError<E> {
    /// Called in a state where the function is not allowed.
    IllegalCall {
        /// FMI function
        func: &'static str,
        /// current state
        phase: Phase,
    },
    /// A required pointer argument is NULL.
    NullPointer {
        /// FMI function
        func: &'static str,
        /// argument name
        arg: &'static str,
    },
    /// No variable of this type has this value reference.
    UnknownValueReference {
        /// FMI function
        func: &'static str,
        /// the value reference
        vr: u32,
    },
    /// The variable may not be set (now).
    NotSettable {
        /// FMI function
        func: &'static str,
        /// variable
        name: &'static str,
        /// why
        why: &'static str,
    },
    /// Any other bad argument.
    BadArgument {
        /// FMI function
        func: &'static str,
        /// what is wrong
        message: String,
    },
    /// A fmi2Get*Status kind this FMU cannot report (FMI 2.0 section 4.2.3: "If a status is
    /// required which cannot be retrieved by the slave it returns fmi2Discard"). Harmless:
    /// the instance keeps its state.
    StatusNotAvailable {
        /// FMI function
        func: &'static str,
        /// the fmi2StatusKind asked for
        kind: i32,
        /// why it is not available
        why: &'static str,
    },
    /// Optional function this FMU does not provide.
    Unsupported {
        /// FMI function
        func: &'static str,
        /// explanation
        what: &'static str,
    },
    /// From the model behind the FMI layer.
    Model {
        /// FMI function
        func: &'static str,
        /// the error
        error: E,
    },
    /// NaN or infinite value of a variable or an input derivative.
    NonFinite {
        /// FMI function
        func: &'static str,
        /// variable name
        name: &'static str,
        /// the value
        value: f64,
    },
    /// An Enumeration value that is none of its items.
    NotAnItem {
        /// FMI function
        func: &'static str,
        /// variable name
        name: &'static str,
        /// the value
        value: f64,
        /// the items, in order (item k has the value k + 1)
        items: &'static [&'static str],
    },
    /// A serialized FMU state that cannot be read (foreign, corrupted, inconsistent).
    Decode {
        /// FMI function
        func: &'static str,
        /// what is wrong
        error: DecodeError,
    },
    /// A panic was caught at the C boundary.
    Panic {
        /// FMI function
        func: &'static str,
        /// panic payload
        message: String,
    },
    /// The instance is in the Fatal state.
    AfterFatal {
        /// FMI function
        func: &'static str,
    },
    /// A value outside the declared bounds of its variable (nothing was changed).
    OutOfBounds {
        /// FMI function
        func: &'static str,
        /// the variable, value and bounds
        error: OutOfBounds,
    },
    /// An output that cannot be computed at the current state (not a finite number).
    OutputNotFinite {
        /// FMI function
        func: &'static str,
        /// the output
        name: &'static str,
        /// the FMU time
        t: f64,
    },
}

impl<E: ModelError> FmuError<E> {
    /// THE mapping of errors to FMI statuses: model failures in fmi2DoStep that the model
    /// calls discards ([`ModelError::is_discard`]: solver failures, the model's validity,
    /// the work limit) are fmi2Discard (the state is that of the last successful time, the
    /// master may roll back and retry with a smaller step); an unavailable status kind is
    /// fmi2Discard (FMI 2.0 section 4.2.3); panics and calls after them fmi2Fatal;
    /// everything else fmi2Error (only fmi2DoStep may return fmi2Discard: a solver failure
    /// while setting up the initial state is an error).
    ///
    /// The same for FMI 3.0 (`fmi3DoStep`), whose statuses have the same names.
    pub fn status(&self) -> Status {
        match self {
            FmuError::Model {
                func: "fmi2DoStep" | "fmi3DoStep",
                error,
            } if error.is_discard() => Status::Discard,
            FmuError::StatusNotAvailable { .. } => Status::Discard,
            FmuError::Panic { .. } | FmuError::AfterFatal { .. } => Status::Fatal,
            _ => Status::Error,
        }
    }
}

impl<E: fmt::Display> fmt::Display for FmuError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FmuError::IllegalCall { func, phase } => {
                write!(
                    f,
                    "{func}: illegal call sequence (the instance is in state {phase:?})"
                )
            }
            FmuError::NullPointer { func, arg } => {
                write!(f, "{func}: argument {arg} is a NULL pointer")
            }
            FmuError::UnknownValueReference { func, vr } => {
                write!(
                    f,
                    "{func}: unknown value reference {vr} (no variable of this type has it)"
                )
            }
            FmuError::NotSettable { func, name, why } => {
                write!(f, "{func}: variable {name} cannot be set: {why}")
            }
            FmuError::BadArgument { func, message } => write!(f, "{func}: {message}"),
            FmuError::Unsupported { func, what } => {
                write!(f, "{func}: not supported by this FMU ({what})")
            }
            FmuError::StatusNotAvailable { func, kind, why } => {
                write!(
                    f,
                    "{func}: status kind {kind} is not available ({why}); returning fmi2Discard"
                )
            }
            FmuError::Model { func, error } => write!(f, "{func}: {error}"),
            FmuError::NonFinite { func, name, value } => {
                write!(f, "{func}: {name} = {value} is not a finite number")
            }
            FmuError::NotAnItem {
                func,
                name,
                value,
                items,
            } => {
                write!(
                    f,
                    "{func}: parameter {name} = {} violates one of ",
                    Short(*value)
                )?;
                for (k, item) in items.iter().enumerate() {
                    let sep = if k == 0 { "" } else { ", " };
                    write!(f, "{sep}{} = {item}", k + 1)?;
                }
                Ok(())
            }
            FmuError::Decode { func, error } => {
                write!(f, "{func}: invalid serialized FMU state: {error}")
            }
            FmuError::Panic { func, message } => {
                write!(f, "{func}: internal error (caught panic: {message}); the instance is unusable, free it")
            }
            FmuError::AfterFatal { func } => write!(
                f,
                "{func}: the instance is in the Fatal state; only {}FreeInstance is allowed",
                func.get(..4).unwrap_or("fmi2")
            ),
            FmuError::OutOfBounds { func, error } => {
                write!(f, "{func}: {error}; nothing was changed")
            }
            FmuError::OutputNotFinite { func, name, t } => write!(
                f,
                "{func}: output {name} cannot be computed at t = {} s (not a finite number)",
                Short(*t)
            ),
        }
    }
}
