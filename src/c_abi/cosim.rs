//! The co-simulation functions: input and output derivatives, doStep, cancel, status.

use super::FmuError;
use super::{call, slice, slice_mut, OK};
use crate::fmi2::state_machine::allowed;
use crate::fmi2::types::*;
use std::ffi::c_int;

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
