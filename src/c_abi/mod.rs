//! The C ABI of this library: every FMI 2.0 function with its standard name
//! (`#[no_mangle]`; all common, all co-simulation and, as error stubs, all model-exchange
//! functions, because masters refuse libraries that lack any of them), for the model
//! [`FmuModel`] through the generic [`crate::fmi2::instance::Instance`]. Grouped by job.
//! Each only checks the component pointer, turns C pointers into slices after NULL
//! checks, calls the safe instance inside `catch_unwind` (a panic must never cross
//! `extern "C"`) and maps the typed result to an `fmi2Status` via
//! [`crate::fmi2::error::FmuError::status`] (the one place where that mapping lives).

mod common;
mod cosim;
mod me_stubs;
mod state;
mod values;

pub use common::*;
pub use cosim::*;
pub use me_stubs::*;
pub use state::*;
pub use values::*;

use crate::fmi2::types::*;

/// The model behind this library's FMI functions (chosen at the crate root).
pub use crate::FmuModel;
/// An instance of [`FmuModel`].
pub type Instance = crate::fmi2::instance::Instance<FmuModel>;
/// An FMU state of [`FmuModel`].
pub type FmuState = crate::fmi2::instance::FmuState<FmuModel>;
/// The errors of the FMI functions.
pub type FmuError = crate::fmi2::error::FmuError<<FmuModel as crate::fmi2::model::Model>::Error>;
use crate::fmi2::instance::INSTANCE_MAGIC;
use crate::fmi2::model::Status;
use std::panic::{catch_unwind, AssertUnwindSafe};

fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic payload".to_string()
    }
}

/// Runs `f` on the instance behind `c`, catching panics and mapping errors to a status.
///
/// # Safety
/// `c` must be NULL or a pointer returned by [`fmi2Instantiate`] and not yet freed.
unsafe fn call(
    c: Fmi2Component,
    func: &'static str,
    f: impl FnOnce(&mut Instance) -> Result<Status, FmuError>,
) -> Fmi2Status {
    if c.is_null() {
        return Fmi2Status::Error;
    }
    let inst = c.cast::<Instance>();
    // SAFETY: c came from fmi2Instantiate (caller contract); the magic catches some misuse.
    if unsafe { (*inst).magic } != INSTANCE_MAGIC {
        return Fmi2Status::Error;
    }
    // SAFETY: as above; the master serialises calls on one instance (FMI 2.0 2.1.5).
    let r = catch_unwind(AssertUnwindSafe(|| f(unsafe { &mut *inst })));
    let inst = unsafe { &mut *inst };
    match r {
        Ok(Ok(s)) => s.into(),
        Ok(Err(e)) => inst.fail(&e),
        Err(p) => inst.fail(&FmuError::Panic {
            func,
            message: panic_message(p),
        }),
    }
}

/// `(p, n)` as a slice; NULL is fine when n = 0 (shared by the FMI 2.0 and 3.0 shells).
///
/// # Safety
/// Non-NULL `p` must point to `n` valid elements.
pub(crate) unsafe fn slice<'a, T>(
    func: &'static str,
    arg: &'static str,
    p: *const T,
    n: usize,
) -> Result<&'a [T], FmuError> {
    if n == 0 {
        Ok(&[])
    } else if p.is_null() {
        Err(FmuError::NullPointer { func, arg })
    } else {
        // SAFETY: caller contract.
        Ok(unsafe { std::slice::from_raw_parts(p, n) })
    }
}

/// Mutable variant of [`slice`].
///
/// # Safety
/// Non-NULL `p` must point to `n` valid, writable elements.
pub(crate) unsafe fn slice_mut<'a, T>(
    func: &'static str,
    arg: &'static str,
    p: *mut T,
    n: usize,
) -> Result<&'a mut [T], FmuError> {
    if n == 0 {
        Ok(&mut [])
    } else if p.is_null() {
        Err(FmuError::NullPointer { func, arg })
    } else {
        // SAFETY: caller contract.
        Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
    }
}

const OK: Result<Status, FmuError> = Ok(Status::OK);

/// Test hook (Rust only, not exported from the shared library): the next guarded call on
/// this instance panics, to prove that panics are caught at the C boundary.
///
/// # Safety
/// `c` must be a live instance.
#[doc(hidden)]
pub unsafe fn test_hook_panic_next_call(c: Fmi2Component) {
    if !c.is_null() {
        // SAFETY: caller contract.
        unsafe { (*c.cast::<Instance>()).panic_next_call = true };
    }
}
