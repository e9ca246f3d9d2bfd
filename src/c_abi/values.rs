//! fmi2Get/Set Real, Integer, Boolean, String.

use super::FmuError;
use super::{call, slice, slice_mut, OK};
use crate::fmi2::state_machine::allowed;
use crate::fmi2::types::*;
use crate::fmi2::variables::VarType;

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
            inst.get(func, VarType::Real, vrs, |i, x| out[i] = x)?;
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
            inst.get(func, VarType::Integer, vrs, |i, x| {
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
            inst.get(func, VarType::Boolean, vrs, |i, x| {
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
