//! The common functions: version, logging, instantiate/free, initialisation, terminate,
//! reset.

use super::{call, instance, slice, FmuError, FmuState, Instance3, OK};
use crate::fmi2::logging::Category;
use crate::fmi2::model::Status;
use crate::fmi2::variables;
use crate::fmi3::types::*;
use std::ffi::{c_void, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

/// `const char* fmi3GetVersion(void)` = "3.0".
#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> Fmi3String {
    c"3.0".as_ptr()
}

/// fmi3SetDebugLogging.
///
/// # Safety
/// FMI 3.0 caller contract: valid instance, `categories` holds `n` C strings.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    c: Fmi3Instance,
    logging_on: Fmi3Boolean,
    n: usize,
    categories: *const Fmi3String,
) -> Fmi3Status {
    let func = "fmi3SetDebugLogging";
    unsafe {
        call(c, func, |inst| {
            let cats = slice(func, "categories", categories, n)?;
            let mut names = Vec::with_capacity(cats.len());
            for &p in cats {
                if p.is_null() {
                    return Err(FmuError::NullPointer {
                        func,
                        arg: "categories[i]",
                    });
                }
                names.push(CStr::from_ptr(p).to_str().unwrap_or("<not UTF-8>"));
            }
            inst.inner
                .set_debug_logging(logging_on != FMI3_FALSE, &names)?;
            OK
        })
    }
}

/// fmi3InstantiateCoSimulation: checks the instantiation token and the name;
/// `resourcePath` may be NULL (nothing is read from disk). `eventModeUsed` is accepted and
/// ignored (hasEventMode = false: the FMU never asks for event mode);
/// `earlyReturnAllowed` enables the early return of fmi3DoStep (docs/fmu.md "FMI 3.0");
/// required intermediate variables are refused (providesIntermediateUpdate = false).
///
/// # Safety
/// FMI 3.0 caller contract: NULL or valid C strings and arrays.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instance_name: Fmi3String,
    instantiation_token: Fmi3String,
    _resource_path: Fmi3String,
    _visible: Fmi3Boolean,
    logging_on: Fmi3Boolean,
    event_mode_used: Fmi3Boolean,
    early_return_allowed: Fmi3Boolean,
    _required_intermediate_variables: *const Fmi3ValueReference,
    n_required_intermediate_variables: usize,
    instance_environment: Fmi3InstanceEnvironment,
    log_message: Fmi3LogMessageCallback,
    _intermediate_update: Fmi3IntermediateUpdateCallback,
) -> Fmi3Instance {
    let r = catch_unwind(|| {
        let name = if instance_name.is_null() {
            None
        } else {
            // SAFETY: caller contract.
            Some(
                unsafe { CStr::from_ptr(instance_name) }
                    .to_string_lossy()
                    .into_owned(),
            )
        };
        let inst = Instance3::new(
            name.as_deref().unwrap_or("?"),
            log_message,
            instance_environment,
            logging_on != FMI3_FALSE,
            early_return_allowed != FMI3_FALSE,
        );
        let err = |msg: String| {
            inst.inner.log(
                Status::Error,
                Category::Error,
                &format!("fmi3InstantiateCoSimulation: {msg}"),
            );
            ptr::null_mut()
        };
        if name.as_deref().is_none_or(|n| n.trim().is_empty()) {
            return err("instanceName is a NULL pointer or empty".into());
        }
        if instantiation_token.is_null() {
            return err("instantiationToken is a NULL pointer".into());
        }
        // SAFETY: caller contract.
        let token = unsafe { CStr::from_ptr(instantiation_token) }.to_string_lossy();
        if token != variables::GUID {
            return err(format!(
                "instantiationToken {token} does not match this binary's {} (modelDescription.xml from another build?)",
                variables::GUID
            ));
        }
        if event_mode_used != FMI3_FALSE {
            return err(
                "eventModeUsed = true: this FMU has no event mode (hasEventMode = false); \
                 instantiate with eventModeUsed = false (contact events end a step early \
                 when earlyReturnAllowed = true)"
                    .into(),
            );
        }
        if n_required_intermediate_variables > 0 {
            return err(format!(
                "nRequiredIntermediateVariables = {n_required_intermediate_variables}: this FMU provides no intermediate update (providesIntermediateUpdate = false)"
            ));
        }
        Box::into_raw(Box::new(inst)).cast::<c_void>()
    });
    r.unwrap_or(ptr::null_mut())
}

/// fmi3FreeInstance: frees the instance and the FMU states it still owns.
///
/// # Safety
/// `c` NULL or a live instance; not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(c: Fmi3Instance) {
    // SAFETY: caller contract.
    if unsafe { instance(c) }.is_none() {
        return;
    }
    let inst = c.cast::<Instance3>();
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: created by Box::into_raw in fmi3InstantiateCoSimulation.
        let mut b = unsafe { Box::from_raw(inst) };
        b.inner.magic = 0;
        for s in b.inner.states.drain(..) {
            // SAFETY: registered states were created by Box::into_raw and not yet freed.
            drop(unsafe { Box::from_raw(s as *mut FmuState) });
        }
    }));
}

/// fmi3EnterInitializationMode: the experiment (tolerance, start and stop time) and
/// initialization mode.
///
/// # Safety
/// Valid instance.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    c: Fmi3Instance,
    tolerance_defined: Fmi3Boolean,
    tolerance: Fmi3Float64,
    start_time: Fmi3Float64,
    stop_time_defined: Fmi3Boolean,
    stop_time: Fmi3Float64,
) -> Fmi3Status {
    unsafe {
        call(c, "fmi3EnterInitializationMode", |inst| {
            inst.enter_initialization_mode(
                (tolerance_defined != FMI3_FALSE).then_some(tolerance),
                start_time,
                (stop_time_defined != FMI3_FALSE).then_some(stop_time),
            )
        })
    }
}

/// fmi3ExitInitializationMode (parameter validation happens here).
///
/// # Safety
/// Valid instance.
#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(c: Fmi3Instance) -> Fmi3Status {
    unsafe {
        call(c, "fmi3ExitInitializationMode", |inst| {
            inst.inner.exit_initialization_mode().and(OK)
        })
    }
}

/// fmi3Terminate.
///
/// # Safety
/// Valid instance.
#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(c: Fmi3Instance) -> Fmi3Status {
    unsafe { call(c, "fmi3Terminate", |inst| inst.inner.terminate().and(OK)) }
}

/// fmi3Reset.
///
/// # Safety
/// Valid instance.
#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(c: Fmi3Instance) -> Fmi3Status {
    unsafe { call(c, "fmi3Reset", |inst| inst.inner.reset().and(OK)) }
}
