//! Geared rotor with tooth friction as an FMI 2.0 Co-Simulation unit.
//!
//! Layers (no circles: physics and solver know nothing of FMI; the FMI layer knows no model;
//! the binding joins them; the C ABI exports the binding through the FMI layer):
//! - [`gear`]: pair geometry (ISO 21771), mesh kinematics of the displaced centres,
//!   contact lines and distributed Coulomb friction (`model.md` §2–§4).
//! - [`rotor`]: the index-2 geared-rotor DAE in first-order form, its outputs and
//!   consistent initial values (`model.md` §5–§8).
//! - [`radau5`]: Hairer & Wanner's RADAU5 for `M y' = f(t, y)`, step-based; knows nothing of gears.
//! - [`sim`]: the rotor DAE driven by RADAU5 across communication points (safe Rust API).
//! - [`periodic`]: the periodic steady state by shooting (Floquet multipliers) and by the
//!   n-th order harmonic approach (`model.md` §11, the paper's Fig. 3).
//! - [`binding`]: the geared rotor as an FMI model (the only code that maps the FMU's
//!   variables to physics), behind the contract `fmi2::model::Model`.
//! - [`fmi2`]: the model-agnostic FMI 2.0 Co-Simulation layer: a safe, generic instance
//!   (state machine, argument checks, logging, FMU-state envelope) and the contract
//!   `fmi2::model::Model`. It names no model.
//! - [`fmi3`]: the FMI 3.0 Co-Simulation layer over the same contract (and the same
//!   generic instance with the FMI 3.0 table of names and states), with the typed value
//!   dispatch and the doStep of 3.0 (early return).
//! - [`c_abi`]: the thin unsafe C shell, every FMI 2.0 function for [`FmuModel`].
//! - [`c_abi3`]: the same for FMI 3.0 (the names differ, so one library exports both).
//! - [`parameter`]: how a parameter is described (name, unit, default, bounds, rule) and
//!   [`parameter::ParamError`]; the tables are with the layers (`rotor::param_table`).
//! - [`bytes`]: the one byte reader/writer (FMU state, RADAU5 snapshot).
//! - [`fmt_num`]: short numbers for messages (used by every layer).
//! - [`hash`]: 64-bit FNV-1a: the checksums of saved states and the GUID (also in `build.rs`).

pub mod binding;
pub mod bytes;
pub mod c_abi;
pub mod c_abi3;
pub mod fmi2;
pub mod fmi3;
/// The build-time generator of the FMI 3.0 model description (build.rs includes the same
/// file); compiled here only for its unit tests.
#[cfg(test)]
#[path = "../build/fmi3_description.rs"]
mod fmi3_description;
pub mod fmt_num;
pub mod gear;
pub mod hash;
/// The build-time checker of the model description (build.rs includes the same file);
/// compiled here only for its unit tests, not into the FMU library.
#[cfg(test)]
#[path = "../build/model_description_check.rs"]
mod model_description_check;
pub mod parameter;
pub mod periodic;
pub mod radau5;
pub mod rotor;
pub mod sim;

/// The model this library exports through the FMI functions of [`fmi2`].
pub type FmuModel = binding::GearedRotorFmu;
