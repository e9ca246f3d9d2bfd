//! The model-agnostic FMI 2.0 Co-Simulation layer: a safe [`instance::Instance`] generic
//! over the model behind the contract [`model::Model`] (state machine, argument checks
//! against the variable table, logging, experiment, FMU-state envelope), the errors and
//! the one error -> status mapping ([`error::FmuError::status`]), the C types
//! ([`types`]) and the variable table generated from the model description
//! ([`variables`]: the interface of this FMU, like the Reference FMUs' `config.h`). It names
//! no model: the C functions for this library's model are in `crate::c_abi`.

pub mod bounds;
pub mod error;
pub mod instance;
pub mod logging;
pub mod model;
pub mod state_machine;
pub mod types;
pub mod variables;
