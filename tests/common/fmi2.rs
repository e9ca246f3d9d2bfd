//! FMI 2.0 call shorthands shared by the C ABI tests (the instance driver itself is
//! `tests/fmi2_common`).

use geared_rotor::fmi2::fmi2SetDebugLogging;
use geared_rotor::fmi2::types::{Fmi2Component, Fmi2Status};
use std::ffi::CString;

/// fmi2SetDebugLogging(c, loggingOn, 1 category): switch on logging of `category` only.
pub fn log_category(c: Fmi2Component, category: &str) -> Fmi2Status {
    let cat = CString::new(category).unwrap();
    let p = cat.as_ptr();
    // SAFETY: c comes from fmi2Instantiate; p points to one NUL-terminated string that
    // outlives the call.
    unsafe { fmi2SetDebugLogging(c, 1, 1, &p) }
}
