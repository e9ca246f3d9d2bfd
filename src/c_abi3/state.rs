//! FMU states: get, set, free, serialize, deserialize (registered per instance; the
//! serialized form is sealed for FMI 3.0 and refused by the FMI 2.0 functions, and the other
//! way round).

use super::{call, slice, slice_mut, FmuError, FmuState, Instance3, OK};
use crate::fmi2::instance::Instance;
use crate::fmi3::types::*;
use crate::fmi3::FMI3;
use std::ptr;

fn check_state(inst: &Instance3, func: &'static str, s: Fmi3FMUState) -> Result<(), FmuError> {
    if s.is_null() {
        return Err(FmuError::NullPointer {
            func,
            arg: "FMUState",
        });
    }
    if !inst.inner.states.contains(&(s as usize)) {
        return Err(FmuError::BadArgument {
            func,
            message: "FMUState was not created by this instance or was already freed".into(),
        });
    }
    Ok(())
}

/// fmi3GetFMUState: creates a state (`*state == NULL`) or overwrites one of this instance.
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(c: Fmi3Instance, state: *mut Fmi3FMUState) -> Fmi3Status {
    let func = "fmi3GetFMUState";
    unsafe {
        call(c, func, |inst| {
            if state.is_null() {
                return Err(FmuError::NullPointer {
                    func,
                    arg: "FMUState",
                });
            }
            let s = inst.inner.get_state()?;
            let old = *state;
            if !old.is_null() && inst.inner.states.contains(&(old as usize)) {
                *old.cast::<FmuState>() = s;
            } else {
                let p = Box::into_raw(Box::new(s));
                inst.inner.states.push(p as usize);
                *state = p.cast();
            }
            OK
        })
    }
}

/// fmi3SetFMUState.
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(c: Fmi3Instance, state: Fmi3FMUState) -> Fmi3Status {
    let func = "fmi3SetFMUState";
    unsafe {
        call(c, func, |inst| {
            inst.inner.guard(func, FMI3.set_state.allowed)?;
            check_state(inst, func, state)?;
            let s = &*state.cast::<FmuState>();
            inst.inner.set_state(s)?;
            OK
        })
    }
}

/// fmi3FreeFMUState (NULL or `*state == NULL`: nothing to do).
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(c: Fmi3Instance, state: *mut Fmi3FMUState) -> Fmi3Status {
    let func = "fmi3FreeFMUState";
    unsafe {
        call(c, func, |inst| {
            inst.inner.guard(func, FMI3.get_state.allowed)?;
            if state.is_null() || (*state).is_null() {
                return OK;
            }
            check_state(inst, func, *state)?;
            let p = *state as usize;
            inst.inner.states.retain(|&x| x != p);
            drop(Box::from_raw((*state).cast::<FmuState>()));
            *state = ptr::null_mut();
            OK
        })
    }
}

/// fmi3SerializedFMUStateSize.
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    c: Fmi3Instance,
    state: Fmi3FMUState,
    size: *mut usize,
) -> Fmi3Status {
    let func = "fmi3SerializedFMUStateSize";
    unsafe {
        call(c, func, |inst| {
            inst.inner.guard(func, FMI3.get_state.allowed)?;
            check_state(inst, func, state)?;
            if size.is_null() {
                return Err(FmuError::NullPointer { func, arg: "size" });
            }
            *size = Instance::serialize_state_as(&*state.cast::<FmuState>(), &FMI3).len();
            OK
        })
    }
}

/// fmi3SerializeFMUState.
///
/// # Safety
/// FMI 3.0 caller contract (`serialized_state` holds `size` bytes).
#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    c: Fmi3Instance,
    state: Fmi3FMUState,
    serialized_state: *mut Fmi3Byte,
    size: usize,
) -> Fmi3Status {
    let func = "fmi3SerializeFMUState";
    unsafe {
        call(c, func, |inst| {
            inst.inner.guard(func, FMI3.get_state.allowed)?;
            check_state(inst, func, state)?;
            let bytes = Instance::serialize_state_as(&*state.cast::<FmuState>(), &FMI3);
            if size < bytes.len() {
                return Err(FmuError::BadArgument {
                    func,
                    message: format!(
                        "buffer of {size} bytes is smaller than the state ({} bytes)",
                        bytes.len()
                    ),
                });
            }
            let out = slice_mut(func, "serializedState", serialized_state, bytes.len())?;
            out.copy_from_slice(&bytes);
            OK
        })
    }
}

/// fmi3DeserializeFMUState: a foreign, corrupted or FMI 2.0 buffer gives fmi3Error.
///
/// # Safety
/// FMI 3.0 caller contract (`serialized_state` holds `size` bytes).
#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    c: Fmi3Instance,
    serialized_state: *const Fmi3Byte,
    size: usize,
    state: *mut Fmi3FMUState,
) -> Fmi3Status {
    let func = "fmi3DeserializeFMUState";
    unsafe {
        call(c, func, |inst| {
            inst.inner.guard(func, FMI3.deserialize.allowed)?;
            if state.is_null() {
                return Err(FmuError::NullPointer {
                    func,
                    arg: "FMUState",
                });
            }
            let bytes = slice(func, "serializedState", serialized_state, size)?;
            let s: FmuState = Instance::deserialize_state_as(bytes, &FMI3)?;
            let p = Box::into_raw(Box::new(s));
            inst.inner.states.push(p as usize);
            *state = p.cast();
            OK
        })
    }
}
