//! fmi3Get/Set of every FMI 3.0 type: Float64, Int32 (the Integer variables), Int64 (the
//! Enumerations), Boolean; the types this FMU has no variables of refuse every value
//! reference.

use super::{call, slice, slice_mut, OK};
use crate::fmi2::state_machine::allowed;
use crate::fmi2::variables::VarType;
use crate::fmi3::types::*;
use crate::fmi3::{check_n_values, no_variables_of_type, IntKind};

/// fmi3GetFloat64.
///
/// # Safety
/// FMI 3.0 caller contract (`vr` holds `nvr` references, `values` `n_values` elements).
#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(
    c: Fmi3Instance,
    vr: *const Fmi3ValueReference,
    nvr: usize,
    values: *mut Fmi3Float64,
    n_values: usize,
) -> Fmi3Status {
    let func = "fmi3GetFloat64";
    unsafe {
        call(c, func, |inst| {
            check_n_values(func, nvr, n_values)?;
            let vrs = slice(func, "valueReferences", vr, nvr)?;
            let out = slice_mut(func, "values", values, nvr)?;
            inst.get_float64(func, vrs, out)?;
            OK
        })
    }
}

/// fmi3SetFloat64.
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(
    c: Fmi3Instance,
    vr: *const Fmi3ValueReference,
    nvr: usize,
    values: *const Fmi3Float64,
    n_values: usize,
) -> Fmi3Status {
    let func = "fmi3SetFloat64";
    unsafe {
        call(c, func, |inst| {
            check_n_values(func, nvr, n_values)?;
            let vrs = slice(func, "valueReferences", vr, nvr)?;
            let vals = slice(func, "values", values, nvr)?;
            inst.set_float64(func, vrs, vals)?;
            OK
        })
    }
}

macro_rules! get_int {
    ($name:ident, $ty:ty, $kind:expr) => {
        /// Getter of the integer variables of this kind (Int32: Integer, Int64: Enumeration).
        ///
        /// # Safety
        /// FMI 3.0 caller contract.
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            c: Fmi3Instance,
            vr: *const Fmi3ValueReference,
            nvr: usize,
            values: *mut $ty,
            n_values: usize,
        ) -> Fmi3Status {
            let func = stringify!($name);
            unsafe {
                call(c, func, |inst| {
                    check_n_values(func, nvr, n_values)?;
                    let vrs = slice(func, "valueReferences", vr, nvr)?;
                    let out = slice_mut(func, "values", values, nvr)?;
                    inst.check_int_kind(func, $kind, vrs)?;
                    inst.inner
                        .get(func, VarType::Integer, vrs, |i, x| out[i] = x as $ty)?;
                    OK
                })
            }
        }
    };
}

macro_rules! set_int {
    ($name:ident, $ty:ty, $kind:expr) => {
        /// Setter of the integer variables of this kind (Int32: Integer, Int64: Enumeration).
        ///
        /// # Safety
        /// FMI 3.0 caller contract.
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            c: Fmi3Instance,
            vr: *const Fmi3ValueReference,
            nvr: usize,
            values: *const $ty,
            n_values: usize,
        ) -> Fmi3Status {
            let func = stringify!($name);
            unsafe {
                call(c, func, |inst| {
                    check_n_values(func, nvr, n_values)?;
                    let vrs = slice(func, "valueReferences", vr, nvr)?;
                    let vals = slice(func, "values", values, nvr)?;
                    inst.check_int_kind(func, $kind, vrs)?;
                    // Int64 values beyond 2^53 are not exact as f64, but none is an item.
                    inst.inner
                        .set(func, VarType::Integer, vrs, &|i| vals[i] as f64)?;
                    OK
                })
            }
        }
    };
}

get_int!(fmi3GetInt32, Fmi3Int32, IntKind::Int32);
get_int!(fmi3GetInt64, Fmi3Int64, IntKind::Int64);
set_int!(fmi3SetInt32, Fmi3Int32, IntKind::Int32);
set_int!(fmi3SetInt64, Fmi3Int64, IntKind::Int64);

/// fmi3GetBoolean.
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetBoolean(
    c: Fmi3Instance,
    vr: *const Fmi3ValueReference,
    nvr: usize,
    values: *mut Fmi3Boolean,
    n_values: usize,
) -> Fmi3Status {
    let func = "fmi3GetBoolean";
    unsafe {
        call(c, func, |inst| {
            check_n_values(func, nvr, n_values)?;
            let vrs = slice(func, "valueReferences", vr, nvr)?;
            let out = slice_mut(func, "values", values, nvr)?;
            inst.inner.get(func, VarType::Boolean, vrs, |i, x| {
                out[i] = if x != 0.0 { FMI3_TRUE } else { FMI3_FALSE }
            })?;
            OK
        })
    }
}

/// fmi3SetBoolean.
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetBoolean(
    c: Fmi3Instance,
    vr: *const Fmi3ValueReference,
    nvr: usize,
    values: *const Fmi3Boolean,
    n_values: usize,
) -> Fmi3Status {
    let func = "fmi3SetBoolean";
    unsafe {
        call(c, func, |inst| {
            check_n_values(func, nvr, n_values)?;
            let vrs = slice(func, "valueReferences", vr, nvr)?;
            let vals = slice(func, "values", values, nvr)?;
            inst.inner.set(func, VarType::Boolean, vrs, &|i| {
                if vals[i] != FMI3_FALSE {
                    1.0
                } else {
                    0.0
                }
            })?;
            OK
        })
    }
}

macro_rules! no_vars {
    ($name:ident, $ptr:ty, $allowed:expr) => {
        /// A type this FMU has no variables of: every value reference is unknown (fmi3Error).
        ///
        /// # Safety
        /// FMI 3.0 caller contract.
        #[no_mangle]
        pub unsafe extern "C" fn $name(
            c: Fmi3Instance,
            vr: *const Fmi3ValueReference,
            nvr: usize,
            values: $ptr,
            n_values: usize,
        ) -> Fmi3Status {
            let func = stringify!($name);
            let _ = values;
            unsafe {
                call(c, func, |inst| {
                    let vrs = slice(func, "valueReferences", vr, nvr)?;
                    no_variables_of_type(&mut inst.inner, func, $allowed, vrs, n_values)
                })
            }
        }
    };
}

no_vars!(fmi3GetFloat32, *mut Fmi3Float32, allowed::GET);
no_vars!(fmi3GetInt8, *mut i8, allowed::GET);
no_vars!(fmi3GetUInt8, *mut u8, allowed::GET);
no_vars!(fmi3GetInt16, *mut i16, allowed::GET);
no_vars!(fmi3GetUInt16, *mut u16, allowed::GET);
no_vars!(fmi3GetUInt32, *mut u32, allowed::GET);
no_vars!(fmi3GetUInt64, *mut Fmi3UInt64, allowed::GET);
no_vars!(fmi3GetString, *mut Fmi3String, allowed::GET);
no_vars!(fmi3SetFloat32, *const Fmi3Float32, allowed::SET);
no_vars!(fmi3SetInt8, *const i8, allowed::SET);
no_vars!(fmi3SetUInt8, *const u8, allowed::SET);
no_vars!(fmi3SetInt16, *const i16, allowed::SET);
no_vars!(fmi3SetUInt16, *const u16, allowed::SET);
no_vars!(fmi3SetUInt32, *const u32, allowed::SET);
no_vars!(fmi3SetUInt64, *const Fmi3UInt64, allowed::SET);
no_vars!(fmi3SetString, *const Fmi3String, allowed::SET);

/// fmi3GetBinary: no Binary variables.
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetBinary(
    c: Fmi3Instance,
    vr: *const Fmi3ValueReference,
    nvr: usize,
    _value_sizes: *mut usize,
    _values: *mut Fmi3Binary,
    n_values: usize,
) -> Fmi3Status {
    let func = "fmi3GetBinary";
    unsafe {
        call(c, func, |inst| {
            let vrs = slice(func, "valueReferences", vr, nvr)?;
            no_variables_of_type(&mut inst.inner, func, allowed::GET, vrs, n_values)
        })
    }
}

/// fmi3SetBinary: no Binary variables.
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3SetBinary(
    c: Fmi3Instance,
    vr: *const Fmi3ValueReference,
    nvr: usize,
    _value_sizes: *const usize,
    _values: *const Fmi3Binary,
    n_values: usize,
) -> Fmi3Status {
    let func = "fmi3SetBinary";
    unsafe {
        call(c, func, |inst| {
            let vrs = slice(func, "valueReferences", vr, nvr)?;
            no_variables_of_type(&mut inst.inner, func, allowed::SET, vrs, n_values)
        })
    }
}
