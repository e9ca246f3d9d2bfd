//! The binding's error: what the model behind the FMI layer can refuse or fail at, and
//! whether that is a discard of fmi2DoStep.

use crate::fmi2::bounds::OutOfBounds;
use crate::fmi2::error::ModelError;
use crate::sim::SimError;
use std::fmt;

/// An error of the geared-rotor model as the FMI layer sees it.
#[derive(Debug, Clone, PartialEq)]
pub enum BindingError {
    /// From the simulation (parameters, initialisation, stepping, serialized state).
    Sim(SimError),
    /// A fixed parameter outside its declared bounds, found at fmi2ExitInitializationMode.
    OutOfBounds(OutOfBounds),
    /// A value that does not exist yet (e.g. outputs before initialisation).
    NotAvailable(String),
}

impl fmt::Display for BindingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BindingError::Sim(e) => write!(f, "{e}"),
            BindingError::OutOfBounds(e) => write!(f, "{e}; nothing was changed"),
            BindingError::NotAvailable(what) => f.write_str(what),
        }
    }
}

impl std::error::Error for BindingError {}

impl ModelError for BindingError {
    fn is_discard(&self) -> bool {
        matches!(self, BindingError::Sim(e) if e.is_discard())
    }
}

impl From<SimError> for BindingError {
    fn from(e: SimError) -> Self {
        BindingError::Sim(e)
    }
}
