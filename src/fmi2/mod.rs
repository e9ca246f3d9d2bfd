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

use instance::INSTANCE_MAGIC;
use logging::Category;
use state_machine::allowed;

/// The model behind this library's FMI functions: chosen at the crate root, so that this
/// layer names no model.
pub use crate::FmuModel;
/// An instance of [`FmuModel`].
pub type Instance = instance::Instance<FmuModel>;
/// An FMU state of [`FmuModel`].
pub type FmuState = instance::FmuState<FmuModel>;
/// The errors of the FMI functions.
pub type FmuError = error::FmuError<<FmuModel as model::Model>::Error>;
use std::ffi::{c_int, c_void, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;
use types::*;
use variables::VarType;

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
    f: impl FnOnce(&mut Instance) -> Result<Fmi2Status, FmuError>,
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
        Ok(Ok(s)) => s,
        Ok(Err(e)) => inst.fail(&e),
        Err(p) => inst.fail(&FmuError::Panic {
            func,
            message: panic_message(p),
        }),
    }
}

/// `(p, n)` as a slice; NULL is fine when n = 0.
///
/// # Safety
/// Non-NULL `p` must point to `n` valid elements.
unsafe fn slice<'a, T>(
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
unsafe fn slice_mut<'a, T>(
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

const OK: Result<Fmi2Status, FmuError> = Ok(Fmi2Status::OK);

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

// ---------------------------------------------------------------- common functions

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
                Fmi2Status::Error,
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

// ---------------------------------------------------------------- getters and setters

/// fmi2GetReal.
///
/// # Safety
/// FMI 2.0 caller contract (arrays of length nvr).
#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Real,
) -> Fmi2Status {
    let func = "fmi2GetReal";
    unsafe {
        call(c, func, |inst| {
            let vrs = slice(func, "vr", vr, nvr)?;
            let out = slice_mut(func, "value", value, nvr)?;
            inst.get(func, VarType::Real, vrs, &mut |i, x| out[i] = x)?;
            OK
        })
    }
}

/// fmi2GetInteger.
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Integer,
) -> Fmi2Status {
    let func = "fmi2GetInteger";
    unsafe {
        call(c, func, |inst| {
            let vrs = slice(func, "vr", vr, nvr)?;
            let out = slice_mut(func, "value", value, nvr)?;
            inst.get(func, VarType::Integer, vrs, &mut |i, x| {
                out[i] = x as Fmi2Integer
            })?;
            OK
        })
    }
}

/// fmi2GetBoolean.
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    let func = "fmi2GetBoolean";
    unsafe {
        call(c, func, |inst| {
            let vrs = slice(func, "vr", vr, nvr)?;
            let out = slice_mut(func, "value", value, nvr)?;
            inst.get(func, VarType::Boolean, vrs, &mut |i, x| {
                out[i] = if x != 0.0 { FMI2_TRUE } else { FMI2_FALSE }
            })?;
            OK
        })
    }
}

/// fmi2GetString (this FMU has no String variables: any value reference is unknown).
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2String,
) -> Fmi2Status {
    let func = "fmi2GetString";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::GET)?;
            let vrs = slice(func, "vr", vr, nvr)?;
            let _ = slice_mut(func, "value", value, nvr)?;
            match vrs.first() {
                Some(&v) => Err(FmuError::UnknownValueReference { func, vr: v }),
                None => OK,
            }
        })
    }
}

/// fmi2SetReal.
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Real,
) -> Fmi2Status {
    let func = "fmi2SetReal";
    unsafe {
        call(c, func, |inst| {
            let vrs = slice(func, "vr", vr, nvr)?;
            let vals = slice(func, "value", value, nvr)?;
            inst.set(func, VarType::Real, vrs, &|i| vals[i])?;
            OK
        })
    }
}

/// fmi2SetInteger.
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Integer,
) -> Fmi2Status {
    let func = "fmi2SetInteger";
    unsafe {
        call(c, func, |inst| {
            let vrs = slice(func, "vr", vr, nvr)?;
            let vals = slice(func, "value", value, nvr)?;
            inst.set(func, VarType::Integer, vrs, &|i| f64::from(vals[i]))?;
            OK
        })
    }
}

/// fmi2SetBoolean.
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Boolean,
) -> Fmi2Status {
    let func = "fmi2SetBoolean";
    unsafe {
        call(c, func, |inst| {
            let vrs = slice(func, "vr", vr, nvr)?;
            let vals = slice(func, "value", value, nvr)?;
            inst.set(func, VarType::Boolean, vrs, &|i| {
                if vals[i] != FMI2_FALSE {
                    1.0
                } else {
                    0.0
                }
            })?;
            OK
        })
    }
}

/// fmi2SetString (no String variables).
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2String,
) -> Fmi2Status {
    let func = "fmi2SetString";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::SET)?;
            let vrs = slice(func, "vr", vr, nvr)?;
            let _ = slice(func, "value", value, nvr)?;
            match vrs.first() {
                Some(&v) => Err(FmuError::UnknownValueReference { func, vr: v }),
                None => OK,
            }
        })
    }
}

// ---------------------------------------------------------------- FMU state

fn check_state(inst: &Instance, func: &'static str, s: Fmi2FMUstate) -> Result<(), FmuError> {
    if s.is_null() {
        return Err(FmuError::NullPointer {
            func,
            arg: "FMUstate",
        });
    }
    if !inst.states.contains(&(s as usize)) {
        return Err(FmuError::BadArgument {
            func,
            message: "FMUstate was not created by this instance or was already freed".into(),
        });
    }
    Ok(())
}

/// fmi2GetFMUstate: creates a state (`*state == NULL`) or overwrites one of this instance.
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Fmi2Component, state: *mut Fmi2FMUstate) -> Fmi2Status {
    let func = "fmi2GetFMUstate";
    unsafe {
        call(c, func, |inst| {
            if state.is_null() {
                return Err(FmuError::NullPointer {
                    func,
                    arg: "FMUstate",
                });
            }
            let s = inst.get_state()?;
            let old = *state;
            if !old.is_null() && inst.states.contains(&(old as usize)) {
                *old.cast::<FmuState>() = s;
            } else {
                let p = Box::into_raw(Box::new(s));
                inst.states.push(p as usize);
                *state = p.cast();
            }
            OK
        })
    }
}

/// fmi2SetFMUstate.
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Fmi2Component, state: Fmi2FMUstate) -> Fmi2Status {
    let func = "fmi2SetFMUstate";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::FMU_STATE)?;
            check_state(inst, func, state)?;
            let s = &*state.cast::<FmuState>();
            inst.set_state(s)?;
            OK
        })
    }
}

/// fmi2FreeFMUstate (NULL or `*state == NULL`: nothing to do).
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: Fmi2Component,
    state: *mut Fmi2FMUstate,
) -> Fmi2Status {
    let func = "fmi2FreeFMUstate";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::FMU_STATE)?;
            if state.is_null() || (*state).is_null() {
                return OK;
            }
            check_state(inst, func, *state)?;
            let p = *state as usize;
            inst.states.retain(|&x| x != p);
            drop(Box::from_raw((*state).cast::<FmuState>()));
            *state = ptr::null_mut();
            OK
        })
    }
}

/// fmi2SerializedFMUstateSize.
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: Fmi2Component,
    state: Fmi2FMUstate,
    size: *mut usize,
) -> Fmi2Status {
    let func = "fmi2SerializedFMUstateSize";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::FMU_STATE)?;
            check_state(inst, func, state)?;
            if size.is_null() {
                return Err(FmuError::NullPointer { func, arg: "size" });
            }
            *size = Instance::serialize_state(&*state.cast::<FmuState>()).len();
            OK
        })
    }
}

/// fmi2SerializeFMUstate.
///
/// # Safety
/// FMI 2.0 caller contract (`serialized_state` holds `size` bytes).
#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Fmi2Component,
    state: Fmi2FMUstate,
    serialized_state: *mut Fmi2Byte,
    size: usize,
) -> Fmi2Status {
    let func = "fmi2SerializeFMUstate";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::FMU_STATE)?;
            check_state(inst, func, state)?;
            let bytes = Instance::serialize_state(&*state.cast::<FmuState>());
            if size < bytes.len() {
                return Err(FmuError::BadArgument {
                    func,
                    message: format!(
                        "buffer of {size} bytes is smaller than the state ({} bytes)",
                        bytes.len()
                    ),
                });
            }
            let out = slice_mut(
                func,
                "serializedState",
                serialized_state.cast::<u8>(),
                bytes.len(),
            )?;
            out.copy_from_slice(&bytes);
            OK
        })
    }
}

/// fmi2DeSerializeFMUstate: a foreign or corrupted buffer gives fmi2Error.
///
/// # Safety
/// FMI 2.0 caller contract (`serialized_state` holds `size` bytes).
#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Fmi2Component,
    serialized_state: *const Fmi2Byte,
    size: usize,
    state: *mut Fmi2FMUstate,
) -> Fmi2Status {
    let func = "fmi2DeSerializeFMUstate";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::FMU_STATE)?;
            if state.is_null() {
                return Err(FmuError::NullPointer {
                    func,
                    arg: "FMUstate",
                });
            }
            let bytes = slice(func, "serializedState", serialized_state.cast::<u8>(), size)?;
            let s = Instance::deserialize_state(bytes)?;
            let p = Box::into_raw(Box::new(s));
            inst.states.push(p as usize);
            *state = p.cast();
            OK
        })
    }
}

/// fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative = false).
///
/// # Safety
/// Valid component.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: Fmi2Component,
    _v_unknown: *const Fmi2ValueReference,
    _n_unknown: usize,
    _v_known: *const Fmi2ValueReference,
    _n_known: usize,
    _dv_known: *const Fmi2Real,
    _dv_unknown: *mut Fmi2Real,
) -> Fmi2Status {
    let func = "fmi2GetDirectionalDerivative";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::DIRECTIONAL)?;
            Err(FmuError::Unsupported {
                func,
                what: "providesDirectionalDerivative = false",
            })
        })
    }
}

// ---------------------------------------------------------------- co-simulation

/// fmi2SetRealInputDerivatives (order 1).
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    order: *const Fmi2Integer,
    value: *const Fmi2Real,
) -> Fmi2Status {
    let func = "fmi2SetRealInputDerivatives";
    unsafe {
        call(c, func, |inst| {
            let vrs = slice(func, "vr", vr, nvr)?;
            let ord = slice(func, "order", order, nvr)?;
            let vals = slice(func, "value", value, nvr)?;
            inst.set_input_derivatives(vrs, ord, vals)?;
            OK
        })
    }
}

/// fmi2GetRealOutputDerivatives (order 1, from the dense output).
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    order: *const Fmi2Integer,
    value: *mut Fmi2Real,
) -> Fmi2Status {
    let func = "fmi2GetRealOutputDerivatives";
    unsafe {
        call(c, func, |inst| {
            let vrs = slice(func, "vr", vr, nvr)?;
            let ord = slice(func, "order", order, nvr)?;
            let out = slice_mut(func, "value", value, nvr)?;
            inst.get_output_derivatives(vrs, ord, out)?;
            OK
        })
    }
}

/// fmi2DoStep: integrates exactly to currentCommunicationPoint + communicationStepSize.
///
/// # Safety
/// Valid component.
#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: Fmi2Component,
    current_communication_point: Fmi2Real,
    communication_step_size: Fmi2Real,
    _no_set_fmu_state_prior_to_current_point: Fmi2Boolean,
) -> Fmi2Status {
    unsafe {
        call(c, "fmi2DoStep", |inst| {
            inst.do_step(current_communication_point, communication_step_size)
        })
    }
}

/// fmi2CancelStep: no asynchronous doStep, so nothing to cancel.
///
/// # Safety
/// Valid component.
#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2Status {
    let func = "fmi2CancelStep";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::CANCEL_STEP)?;
            Err(FmuError::Unsupported {
                func,
                what: "fmi2DoStep never returns fmi2Pending (canRunAsynchronuously = false)",
            })
        })
    }
}

/// fmi2GetStatus: no kind is available: fmi2DoStepStatus and fmi2PendingStatus concern an
/// fmi2DoStep that returned fmi2Pending, which this FMU never does (steps are synchronous;
/// the Reference FMUs answer the same). fmi2Discard (FMI 2.0 section 4.2.3), the instance
/// keeps its state.
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Status,
) -> Fmi2Status {
    let func = "fmi2GetStatus";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::STATUS)?;
            if value.is_null() {
                return Err(FmuError::NullPointer { func, arg: "value" });
            }
            Err(FmuError::StatusNotAvailable {
                func,
                kind,
                why: "it concerns an fmi2DoStep that returned fmi2Pending, and steps here are never asynchronous (the status of fmi2DoStep is its return value)",
            })
        })
    }
}

/// fmi2GetRealStatus(fmi2LastSuccessfulTime).
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Real,
) -> Fmi2Status {
    let func = "fmi2GetRealStatus";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::STATUS)?;
            if value.is_null() {
                return Err(FmuError::NullPointer { func, arg: "value" });
            }
            if kind != status_kind::LAST_SUCCESSFUL_TIME {
                return Err(FmuError::StatusNotAvailable {
                    func,
                    kind,
                    why: "only fmi2LastSuccessfulTime (2) is a Real status",
                });
            }
            *value = inst.last_successful_time();
            OK
        })
    }
}

/// fmi2GetIntegerStatus: FMI 2.0 defines no integer status: fmi2Discard.
///
/// # Safety
/// Valid component.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: Fmi2Component,
    kind: c_int,
    _value: *mut Fmi2Integer,
) -> Fmi2Status {
    let func = "fmi2GetIntegerStatus";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::STATUS)?;
            Err(FmuError::StatusNotAvailable {
                func,
                kind,
                why: "FMI 2.0 defines no integer status",
            })
        })
    }
}

/// fmi2GetBooleanStatus(fmi2Terminated) = fmi2False (the model never asks to stop).
///
/// # Safety
/// FMI 2.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    let func = "fmi2GetBooleanStatus";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::STATUS)?;
            if value.is_null() {
                return Err(FmuError::NullPointer { func, arg: "value" });
            }
            if kind != status_kind::TERMINATED {
                return Err(FmuError::StatusNotAvailable {
                    func,
                    kind,
                    why: "only fmi2Terminated (3) is a Boolean status",
                });
            }
            *value = FMI2_FALSE;
            OK
        })
    }
}

/// fmi2GetStringStatus: only fmi2PendingStatus would have one, and steps never pend:
/// fmi2Discard.
///
/// # Safety
/// Valid component.
#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: Fmi2Component,
    kind: c_int,
    _value: *mut Fmi2String,
) -> Fmi2Status {
    let func = "fmi2GetStringStatus";
    unsafe {
        call(c, func, |inst| {
            inst.guard(func, allowed::STATUS)?;
            Err(FmuError::StatusNotAvailable {
                func,
                kind,
                why: "fmi2PendingStatus exists only for asynchronous steps, which this FMU never makes",
            })
        })
    }
}

// ---------------------------------------------------------------- model exchange stubs

macro_rules! me_stub {
    ($name:ident ( $($arg:ident : $ty:ty),* )) => {
        /// Model-Exchange function: this FMU is Co-Simulation only, returns fmi2Error.
        ///
        /// # Safety
        /// Valid component.
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: Fmi2Component $(, $arg: $ty)*) -> Fmi2Status {
            $(let _ = $arg;)*
            let func = stringify!($name);
            unsafe {
                call(c, func, |_inst| {
                    Err(FmuError::Unsupported { func, what: "Model Exchange; this FMU is Co-Simulation only" })
                })
            }
        }
    };
}

me_stub!(fmi2EnterEventMode());
me_stub!(fmi2NewDiscreteStates(event_info: *mut Fmi2EventInfo));
me_stub!(fmi2EnterContinuousTimeMode());
me_stub!(fmi2CompletedIntegratorStep(no_set: Fmi2Boolean, enter_event_mode: *mut Fmi2Boolean, terminate: *mut Fmi2Boolean));
me_stub!(fmi2SetTime(time: Fmi2Real));
me_stub!(fmi2SetContinuousStates(x: *const Fmi2Real, nx: usize));
me_stub!(fmi2GetDerivatives(derivatives: *mut Fmi2Real, nx: usize));
me_stub!(fmi2GetEventIndicators(indicators: *mut Fmi2Real, ni: usize));
me_stub!(fmi2GetContinuousStates(x: *mut Fmi2Real, nx: usize));
me_stub!(fmi2GetNominalsOfContinuousStates(x_nominal: *mut Fmi2Real, nx: usize));
