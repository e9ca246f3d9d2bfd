//! The co-simulation functions: output derivatives, doStep (with early return), step mode.

use super::{call, slice, slice_mut, FmuError, OK};
use crate::fmi3::check_n_values;
use crate::fmi3::types::*;

/// fmi3GetOutputDerivatives (order 1, from the dense output).
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3GetOutputDerivatives(
    c: Fmi3Instance,
    vr: *const Fmi3ValueReference,
    nvr: usize,
    orders: *const Fmi3Int32,
    values: *mut Fmi3Float64,
    n_values: usize,
) -> Fmi3Status {
    let func = "fmi3GetOutputDerivatives";
    unsafe {
        call(c, func, |inst| {
            check_n_values(func, nvr, n_values)?;
            let vrs = slice(func, "valueReferences", vr, nvr)?;
            let ord = slice(func, "orders", orders, nvr)?;
            let out = slice_mut(func, "values", values, nvr)?;
            inst.inner.get_output_derivatives(vrs, ord, out)?;
            OK
        })
    }
}

/// fmi3DoStep: integrates to currentCommunicationPoint + communicationStepSize, or, when
/// earlyReturnAllowed was set at instantiation, up to an event of the model inside the step
/// (lift-off, drive reversal; docs/fmu.md "FMI 3.0"), with `*earlyReturn = true` and
/// `*lastSuccessfulTime` there. For a live instance of this FMU the out-arguments are
/// written whatever the status (false and the model time when the call fails before
/// stepping; NULL ones are an error); a NULL or foreign instance leaves them untouched (there
/// is no model time to write).
///
/// # Safety
/// Valid instance; the out-pointers NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    c: Fmi3Instance,
    current_communication_point: Fmi3Float64,
    communication_step_size: Fmi3Float64,
    _no_set_fmu_state_prior_to_current_point: Fmi3Boolean,
    event_handling_needed: *mut Fmi3Boolean,
    terminate_simulation: *mut Fmi3Boolean,
    early_return: *mut Fmi3Boolean,
    last_successful_time: *mut Fmi3Float64,
) -> Fmi3Status {
    let func = "fmi3DoStep";
    unsafe {
        call(c, func, |inst| {
            // Defined out-arguments whatever happens next (the model time, no event).
            let t = inst.inner.time();
            for p in [event_handling_needed, terminate_simulation, early_return] {
                if !p.is_null() {
                    *p = FMI3_FALSE;
                }
            }
            if !last_successful_time.is_null() {
                *last_successful_time = t;
            }
            for (p, arg) in [
                (event_handling_needed.is_null(), "eventHandlingNeeded"),
                (terminate_simulation.is_null(), "terminateSimulation"),
                (early_return.is_null(), "earlyReturn"),
                (last_successful_time.is_null(), "lastSuccessfulTime"),
            ] {
                if p {
                    inst.inner.guard(func, crate::fmi3::FMI3.do_step.allowed)?;
                    return Err(FmuError::NullPointer { func, arg });
                }
            }
            let (r, out) = inst.do_step(current_communication_point, communication_step_size);
            let b = |x: bool| if x { FMI3_TRUE } else { FMI3_FALSE };
            *event_handling_needed = b(out.event_handling_needed);
            *terminate_simulation = b(out.terminate_simulation);
            *early_return = b(out.early_return);
            *last_successful_time = out.last_successful_time;
            r
        })
    }
}

/// fmi3EnterStepMode: only after event mode, which this FMU does not have
/// (hasEventMode = false): fmi3Error.
///
/// # Safety
/// Valid instance.
#[no_mangle]
pub unsafe extern "C" fn fmi3EnterStepMode(c: Fmi3Instance) -> Fmi3Status {
    let func = "fmi3EnterStepMode";
    unsafe {
        call(c, func, |_inst| {
            Err(FmuError::Unsupported {
                func,
                what:
                    "hasEventMode = false: the FMU is in Step Mode after fmi3ExitInitializationMode",
            })
        })
    }
}
