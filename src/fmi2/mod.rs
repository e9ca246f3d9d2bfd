//! The FMI 2.0 Co-Simulation C ABI: a thin unsafe shell over a safe, model-agnostic
//! [`instance::Instance`] of the one model this library is built for ([`FmuModel`],
//! chosen at the crate root; the contract is [`model::Model`]).
//!
//! Every exported function (standard names, no prefix; all common, all co-simulation and,
//! as error stubs, all model-exchange functions, because masters refuse libraries that
//! lack any of them) does only this: check the component pointer, turn C pointers into
//! slices after NULL checks, call the instance inside `catch_unwind` (a panic must never
//! cross `extern "C"`), and map the typed result to an `fmi2Status` via
//! [`error::FmuError::status`] (the one place where that mapping lives).

pub mod bounds;
pub mod error;
pub mod instance;
pub mod logging;
pub mod model;
pub mod state_machine;
pub mod types;
pub mod variables;

/// The model behind this library's FMI functions: chosen at the crate root, so that this
/// layer names no model.
pub use crate::FmuModel;
/// An instance of [`FmuModel`].
pub type Instance = instance::Instance<FmuModel>;
/// An FMU state of [`FmuModel`].
pub type FmuState = instance::FmuState<FmuModel>;
/// The errors of the FMI functions.
pub type FmuError = error::FmuError<<FmuModel as model::Model>::Error>;

mod c_abi;
pub use c_abi::*;
