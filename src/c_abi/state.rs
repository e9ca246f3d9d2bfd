//! FMU states: get, set, free, serialize, deserialize (registered per instance);
//! directional derivatives (not provided).

use super::{call, slice, slice_mut, OK};
use super::{FmuError, FmuState, Instance};
use crate::fmi2::state_machine::allowed;
use crate::fmi2::types::*;
use std::ptr;

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
