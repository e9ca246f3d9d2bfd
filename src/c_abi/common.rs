//! The common functions: version, logging, instantiate/free, experiment,
//! initialisation, terminate, reset.

use super::{call, slice, OK};
use super::{FmuError, FmuState, Instance};
use crate::fmi2::instance::INSTANCE_MAGIC;
use crate::fmi2::logging::Category;
use crate::fmi2::model::Status;
use crate::fmi2::types::*;
use crate::fmi2::variables::{self};
use std::ffi::{c_int, c_void, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

/// `const char* fmi2GetTypesPlatform(void)` = "default".
#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> Fmi2String {
    c"default".as_ptr()
}

/// `const char* fmi2GetVersion(void)` = "2.0".
#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> Fmi2String {
    c"2.0".as_ptr()
}

/// fmi2SetDebugLogging.
///
/// # Safety
/// FMI 2.0 caller contract: valid component, `categories` holds `n` C strings.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: Fmi2Component,
    logging_on: Fmi2Boolean,
    n: usize,
    categories: *const Fmi2String,
) -> Fmi2Status {
    let func = "fmi2SetDebugLogging";
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
            inst.set_debug_logging(logging_on != FMI2_FALSE, &names)?;
            OK
        })
    }
}

/// fmi2Instantiate: checks type, GUID and name; `fmuResourceLocation` and the memory
/// callbacks may be NULL (nothing is read from disk; canNotUseMemoryManagementFunctions).
///
/// # Safety
/// FMI 2.0 caller contract: NULL or valid C strings, `functions` NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: Fmi2String,
    fmu_type: c_int,
    fmu_guid: Fmi2String,
    _fmu_resource_location: Fmi2String,
    functions: *const Fmi2CallbackFunctions,
    _visible: Fmi2Boolean,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    let r = catch_unwind(|| {
        // SAFETY: caller contract.
        let cb = unsafe { functions.as_ref() }.copied();
        let logger = cb.and_then(|c| c.logger);
        let env = cb.map_or(ptr::null_mut(), |c| c.component_environment);
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
        let inst = Instance::new(
            name.as_deref().unwrap_or("?"),
            logger,
            env,
            logging_on != FMI2_FALSE,
        );
        let err = |msg: String| {
            inst.log(
                Status::Error,
                Category::Error,
                &format!("fmi2Instantiate: {msg}"),
            );
            ptr::null_mut()
        };
        if cb.is_none() {
            return ptr::null_mut();
        }
        if name.is_none() {
            return err("instanceName is a NULL pointer".into());
        }
        if fmu_type != FMI2_CO_SIMULATION {
            return err(format!(
                "fmuType = {fmu_type} is not fmi2CoSimulation (1); this FMU is Co-Simulation only"
            ));
        }
        if fmu_guid.is_null() {
            return err("fmuGUID is a NULL pointer".into());
        }
        // SAFETY: caller contract.
        let guid = unsafe { CStr::from_ptr(fmu_guid) }.to_string_lossy();
        if guid != variables::GUID {
            return err(format!(
                "fmuGUID {guid} does not match this binary's {} (modelDescription.xml from another build?)",
                variables::GUID
            ));
        }
        Box::into_raw(Box::new(inst)).cast::<c_void>()
    });
    r.unwrap_or(ptr::null_mut())
}

/// fmi2FreeInstance: frees the instance and the FMU states it still owns.
///
/// # Safety
/// `c` NULL or a live instance; not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
    if c.is_null() {
        return;
    }
    let inst = c.cast::<Instance>();
    // SAFETY: caller contract.
    if unsafe { (*inst).magic } != INSTANCE_MAGIC {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: created by Box::into_raw in fmi2Instantiate.
        let mut b = unsafe { Box::from_raw(inst) };
        b.magic = 0;
        for s in b.states.drain(..) {
            // SAFETY: registered states were created by Box::into_raw and not yet freed.
            drop(unsafe { Box::from_raw(s as *mut FmuState) });
        }
    }));
}

/// fmi2SetupExperiment.
///
/// # Safety
/// Valid component.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: Fmi2Component,
    tolerance_defined: Fmi2Boolean,
    tolerance: Fmi2Real,
    start_time: Fmi2Real,
    stop_time_defined: Fmi2Boolean,
    stop_time: Fmi2Real,
) -> Fmi2Status {
    unsafe {
        call(c, "fmi2SetupExperiment", |inst| {
            inst.setup_experiment(
                (tolerance_defined != FMI2_FALSE).then_some(tolerance),
                start_time,
                (stop_time_defined != FMI2_FALSE).then_some(stop_time),
            )
        })
    }
}

/// fmi2EnterInitializationMode.
///
/// # Safety
/// Valid component.
#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Fmi2Component) -> Fmi2Status {
    unsafe {
        call(c, "fmi2EnterInitializationMode", |inst| {
            inst.enter_initialization_mode().and(OK)
        })
    }
}

/// fmi2ExitInitializationMode (parameter validation happens here).
///
/// # Safety
/// Valid component.
#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2Status {
    unsafe {
        call(c, "fmi2ExitInitializationMode", |inst| {
            inst.exit_initialization_mode().and(OK)
        })
    }
}

/// fmi2Terminate.
///
/// # Safety
/// Valid component.
#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2Status {
    unsafe { call(c, "fmi2Terminate", |inst| inst.terminate().and(OK)) }
}

/// fmi2Reset.
///
/// # Safety
/// Valid component.
#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2Status {
    unsafe { call(c, "fmi2Reset", |inst| inst.reset().and(OK)) }
}
