//! The C ABI of the FMI 3.0 Co-Simulation FMU: every FMI 3.0 function with its standard
//! name (`#[no_mangle]`; the common and co-simulation functions, and as error stubs the
//! model-exchange, scheduled-execution and clock functions, which a 3.0 binary exports
//! too), for the model [`FmuModel`] through [`crate::fmi3::Instance3`]. The names differ
//! from the FMI 2.0 ones of `crate::c_abi`, so one library serves both `.fmu` files.
//! As there: each function only checks the instance pointer (an FMI 2.0 instance is
//! refused by its magic), turns C pointers into slices after NULL checks, calls the safe
//! layer inside `catch_unwind` (a panic must never cross `extern "C"`) and maps the typed
//! result to an `fmi3Status` via [`crate::fmi2::error::FmuError::status`].

mod common;
mod cosim;
mod state;
mod stubs;
mod values;

pub use common::*;
pub use cosim::*;
pub use state::*;
pub use stubs::*;
pub use values::*;

use crate::c_abi::{slice, slice_mut};
use crate::fmi2::model::Status;
use crate::fmi3::types::*;
use crate::fmi3::FMI3;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// The model behind this library's FMI functions (chosen at the crate root).
pub use crate::FmuModel;
/// An FMI 3.0 instance of [`FmuModel`].
pub type Instance3 = crate::fmi3::Instance3<FmuModel>;
/// An FMU state of [`FmuModel`] (the same type as in FMI 2.0; its serialized form is not).
pub type FmuState = crate::fmi2::instance::FmuState<FmuModel>;
/// The errors of the FMI functions.
pub type FmuError = crate::fmi2::error::FmuError<<FmuModel as crate::fmi2::model::Model>::Error>;

fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic payload".to_string()
    }
}

/// The instance behind `c`, if it is a live FMI 3.0 instance of this library.
///
/// # Safety
/// `c` must be NULL or a pointer returned by [`fmi3InstantiateCoSimulation`] (or, refused
/// by the magic, another instance of this library) and not yet freed.
unsafe fn instance<'a>(c: Fmi3Instance) -> Option<&'a mut Instance3> {
    if c.is_null() {
        return None;
    }
    let inst = c.cast::<Instance3>();
    // SAFETY: caller contract; both versions' instances begin with a readable magic word
    // only as far as this read goes when the pointer is one of ours, which the magic checks.
    if unsafe { (*inst).inner.magic } != FMI3.magic {
        return None;
    }
    // SAFETY: as above; the importer serialises calls on one instance.
    Some(unsafe { &mut *inst })
}

/// Runs `f` on the instance behind `c`, catching panics and mapping errors to a status.
///
/// # Safety
/// As [`instance`].
unsafe fn call(
    c: Fmi3Instance,
    func: &'static str,
    f: impl FnOnce(&mut Instance3) -> Result<Status, FmuError>,
) -> Fmi3Status {
    // SAFETY: caller contract.
    let Some(inst) = (unsafe { instance(c) }) else {
        return Fmi3Status::Error;
    };
    let inst_ptr: *mut Instance3 = inst;
    // SAFETY: inst_ptr is the live instance; `f` gets it for the call only.
    let r = catch_unwind(AssertUnwindSafe(|| f(unsafe { &mut *inst_ptr })));
    // SAFETY: as above (the closure has returned).
    let inst = unsafe { &mut *inst_ptr };
    let status = match r {
        Ok(Ok(s)) => s,
        Ok(Err(e)) => inst.inner.fail_status(&e),
        Err(p) => inst.inner.fail_status(&FmuError::Panic {
            func,
            message: panic_message(p),
        }),
    };
    status.into()
}

const OK: Result<Status, FmuError> = Ok(Status::OK);

/// Test hook (Rust only, not exported from the shared library): the next guarded call on
/// this instance panics, to prove that panics are caught at the C boundary.
///
/// # Safety
/// `c` must be a live FMI 3.0 instance.
#[doc(hidden)]
pub unsafe fn test_hook_panic_next_call3(c: Fmi3Instance) {
    // SAFETY: caller contract.
    if let Some(inst) = unsafe { instance(c) } {
        inst.inner.panic_next_call = true;
    }
}
