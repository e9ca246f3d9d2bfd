//! Typed errors of the integrator (radau5.md §8: "typed errors carrying t and h").
//!
//! The Fortran reports failures through `IDID < 0` and a line on unit 6; here each failure
//! is a variant carrying the time and step size where it happened.

use std::fmt;

/// Returned by [`super::Problem::rhs`] / [`super::Problem::jacobian`] for a point where the
/// function is undefined. The stepper treats it like a Newton failure (halves `h`); if it
/// persists, the step fails with [`Error::Rhs`].
#[derive(Debug, Clone, PartialEq)]
pub struct RhsError {
    pub message: String,
}

impl RhsError {
    pub fn new(message: impl Into<String>) -> Self {
        RhsError {
            message: message.into(),
        }
    }
}

impl fmt::Display for RhsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "right-hand side undefined: {}", self.message)
    }
}

impl std::error::Error for RhsError {}

/// Failures of construction and of a step.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// An option violates its documented bound (the Fortran's "CURIOUS INPUT" checks).
    InvalidOption {
        name: &'static str,
        value: f64,
        requirement: &'static str,
    },
    /// `0.1 |h| <= |t| uround` (Fortran IDID = -3).
    StepSizeTooSmall { t: f64, h: f64 },
    /// Newton failed to converge many times in a row within one step (the Fortran would
    /// halve h until "step size too small"; at t = 0 that never triggers, hence this limit).
    NewtonFailure { t: f64, h: f64 },
    /// The iteration matrix was singular five times (Fortran IDID = -4).
    SingularMatrix { t: f64, h: f64 },
    /// More than `max_steps` attempts since the last stop time (Fortran IDID = -2).
    TooManySteps { t: f64, h: f64, max_steps: u64 },
    /// f (or the Newton iterate) stayed NaN/inf although h was halved repeatedly.
    NonFinite { t: f64, h: f64 },
    /// The problem's `rhs`/`jacobian` returned an error that halving h did not cure.
    Rhs { t: f64, h: f64, message: String },
    /// `t_stop` lies behind the current time (only forward integration is supported).
    StopTimeBehind { t: f64, t_stop: f64 },
    /// A fixed step ([`super::Radau5::fixed_step`]) whose simplified Newton iteration had
    /// not converged after its fixed number of iterations: `contraction` is the last ratio
    /// of increments, `increment` the last increment in units of the Newton tolerance.
    FixedStepNewton {
        t: f64,
        h: f64,
        iterations: u32,
        contraction: f64,
        increment: f64,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidOption {
                name,
                value,
                requirement,
            } => write!(f, "option {name} = {value} violates {requirement}"),
            Error::StepSizeTooSmall { t, h } => {
                write!(f, "step size too small at t = {t:e} (h = {h:e})")
            }
            Error::NewtonFailure { t, h } => write!(
                f,
                "Newton iteration failed repeatedly at t = {t:e} (h = {h:e})"
            ),
            Error::SingularMatrix { t, h } => {
                write!(f, "matrix is repeatedly singular at t = {t:e} (h = {h:e})")
            }
            Error::TooManySteps { t, h, max_steps } => write!(
                f,
                "more than {max_steps} steps needed at t = {t:e} (h = {h:e})"
            ),
            Error::NonFinite { t, h } => write!(
                f,
                "non-finite values from f or the solution at t = {t:e} (h = {h:e})"
            ),
            Error::Rhs { t, h, message } => write!(
                f,
                "right-hand side failed at t = {t:e} (h = {h:e}): {message}"
            ),
            Error::StopTimeBehind { t, t_stop } => {
                write!(f, "stop time {t_stop:e} lies behind the current time {t:e}")
            }
            Error::FixedStepNewton {
                t,
                h,
                iterations,
                contraction,
                increment,
            } => write!(
                f,
                "the Newton iteration of the fixed step h = {h:e} s at t = {t:e} s has not converged in {iterations} iterations (contraction {contraction:.3}, last increment {increment:.3e} times the Newton tolerance); a smaller fixed step converges faster"
            ),
        }
    }
}

impl std::error::Error for Error {}

/// Why [`super::Snapshot::from_bytes`] refused a buffer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SnapshotError {
    /// Fewer bytes than the header or the declared layout needs.
    Truncated { needed: usize, found: usize },
    /// The buffer does not start with the snapshot magic.
    BadMagic,
    /// A layout version this build does not read.
    UnsupportedVersion { found: u32 },
    /// Written for a different system dimension N.
    DimensionMismatch { expected: u32, found: u32 },
    /// More bytes than the layout has.
    TrailingBytes { extra: usize },
    /// Checksum over header and payload does not match.
    Checksum,
    /// A field holds a value no solver state can have (e.g. pivot index >= N).
    InvalidField { name: &'static str },
}

impl fmt::Display for SnapshotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SnapshotError::Truncated { needed, found } => {
                write!(f, "snapshot truncated: {found} bytes, need {needed}")
            }
            SnapshotError::BadMagic => write!(f, "not a RADAU5 snapshot (bad magic)"),
            SnapshotError::UnsupportedVersion { found } => {
                write!(f, "unsupported snapshot version {found}")
            }
            SnapshotError::DimensionMismatch { expected, found } => write!(
                f,
                "snapshot is for N = {found}, this solver has N = {expected}"
            ),
            SnapshotError::TrailingBytes { extra } => {
                write!(f, "snapshot has {extra} unexpected trailing bytes")
            }
            SnapshotError::Checksum => write!(f, "snapshot checksum mismatch (corrupted)"),
            SnapshotError::InvalidField { name } => {
                write!(f, "snapshot field {name} holds an impossible value")
            }
        }
    }
}

impl std::error::Error for SnapshotError {}
