//! The FMI 3.0 functions this Co-Simulation FMU does not provide, as error stubs (a 3.0
//! binary exports all of them): model exchange, scheduled execution, event mode,
//! configuration mode, clocks, directional and adjoint derivatives, variable dependencies.

use super::{call, FmuError};
use crate::fmi3::types::*;
use std::ffi::c_void;
use std::ptr;

macro_rules! stub {
    ($name:ident, $what:expr, ( $($arg:ident : $ty:ty),* )) => {
        /// Not provided by this FMU: returns fmi3Error with a message.
        ///
        /// # Safety
        /// Valid instance.
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: Fmi3Instance $(, $arg: $ty)*) -> Fmi3Status {
            $(let _ = $arg;)*
            let func = stringify!($name);
            unsafe {
                call(c, func, |_inst| Err(FmuError::Unsupported { func, what: $what }))
            }
        }
    };
}

const ME: &str = "Model Exchange; this FMU is Co-Simulation only";
const EVENTS: &str = "hasEventMode = false";
const CLOCKS: &str = "this FMU has no clocks";
const CONFIG: &str = "this FMU has no structural parameters";
const DERIV: &str = "providesDirectionalDerivative = false, providesAdjointDerivatives = false";
const DEPS: &str =
    "providesPerElementDependencies = false; the dependencies are in modelDescription.xml";
const SE: &str = "Scheduled Execution; this FMU is Co-Simulation only";

stub!(fmi3EnterEventMode, EVENTS, ());
stub!(fmi3EvaluateDiscreteStates, EVENTS, ());
stub!(fmi3UpdateDiscreteStates, EVENTS, (a: *mut Fmi3Boolean, b: *mut Fmi3Boolean, d: *mut Fmi3Boolean, e: *mut Fmi3Boolean, f: *mut Fmi3Boolean, g: *mut Fmi3Float64));
stub!(fmi3EnterConfigurationMode, CONFIG, ());
stub!(fmi3ExitConfigurationMode, CONFIG, ());
stub!(fmi3GetClock, CLOCKS, (vr: *const Fmi3ValueReference, nvr: usize, values: *mut Fmi3Clock));
stub!(fmi3SetClock, CLOCKS, (vr: *const Fmi3ValueReference, nvr: usize, values: *const Fmi3Clock));
stub!(fmi3GetIntervalDecimal, CLOCKS, (vr: *const Fmi3ValueReference, nvr: usize, intervals: *mut Fmi3Float64, qualifiers: *mut i32));
stub!(fmi3GetIntervalFraction, CLOCKS, (vr: *const Fmi3ValueReference, nvr: usize, counters: *mut Fmi3UInt64, resolutions: *mut Fmi3UInt64, qualifiers: *mut i32));
stub!(fmi3GetShiftDecimal, CLOCKS, (vr: *const Fmi3ValueReference, nvr: usize, shifts: *mut Fmi3Float64));
stub!(fmi3GetShiftFraction, CLOCKS, (vr: *const Fmi3ValueReference, nvr: usize, counters: *mut Fmi3UInt64, resolutions: *mut Fmi3UInt64));
stub!(fmi3SetIntervalDecimal, CLOCKS, (vr: *const Fmi3ValueReference, nvr: usize, intervals: *const Fmi3Float64));
stub!(fmi3SetIntervalFraction, CLOCKS, (vr: *const Fmi3ValueReference, nvr: usize, counters: *const Fmi3UInt64, resolutions: *const Fmi3UInt64));
stub!(fmi3SetShiftDecimal, CLOCKS, (vr: *const Fmi3ValueReference, nvr: usize, shifts: *const Fmi3Float64));
stub!(fmi3SetShiftFraction, CLOCKS, (vr: *const Fmi3ValueReference, nvr: usize, counters: *const Fmi3UInt64, resolutions: *const Fmi3UInt64));
stub!(fmi3GetDirectionalDerivative, DERIV, (unknowns: *const Fmi3ValueReference, n_unknowns: usize, knowns: *const Fmi3ValueReference, n_knowns: usize, seed: *const Fmi3Float64, n_seed: usize, sensitivity: *mut Fmi3Float64, n_sensitivity: usize));
stub!(fmi3GetAdjointDerivative, DERIV, (unknowns: *const Fmi3ValueReference, n_unknowns: usize, knowns: *const Fmi3ValueReference, n_knowns: usize, seed: *const Fmi3Float64, n_seed: usize, sensitivity: *mut Fmi3Float64, n_sensitivity: usize));
stub!(fmi3GetNumberOfVariableDependencies, DEPS, (vr: Fmi3ValueReference, n: *mut usize));
stub!(fmi3GetVariableDependencies, DEPS, (dependent: Fmi3ValueReference, element_indices_of_dependent: *mut usize, independents: *mut Fmi3ValueReference, element_indices_of_independents: *mut usize, dependency_kinds: *mut i32, n_dependencies: usize));
stub!(fmi3EnterContinuousTimeMode, ME, ());
stub!(fmi3CompletedIntegratorStep, ME, (no_set: Fmi3Boolean, enter_event_mode: *mut Fmi3Boolean, terminate: *mut Fmi3Boolean));
stub!(fmi3SetTime, ME, (time: Fmi3Float64));
stub!(fmi3SetContinuousStates, ME, (x: *const Fmi3Float64, nx: usize));
stub!(fmi3GetContinuousStateDerivatives, ME, (dx: *mut Fmi3Float64, nx: usize));
stub!(fmi3GetEventIndicators, ME, (z: *mut Fmi3Float64, nz: usize));
stub!(fmi3GetContinuousStates, ME, (x: *mut Fmi3Float64, nx: usize));
stub!(fmi3GetNominalsOfContinuousStates, ME, (x: *mut Fmi3Float64, nx: usize));
stub!(fmi3GetNumberOfEventIndicators, ME, (n: *mut usize));
stub!(fmi3GetNumberOfContinuousStates, ME, (n: *mut usize));
stub!(fmi3ActivateModelPartition, SE, (clock: Fmi3ValueReference, activation_time: Fmi3Float64));

/// fmi3InstantiateModelExchange: this FMU is Co-Simulation only; logs why and returns NULL.
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    _instance_name: Fmi3String,
    _instantiation_token: Fmi3String,
    _resource_path: Fmi3String,
    _visible: Fmi3Boolean,
    _logging_on: Fmi3Boolean,
    instance_environment: Fmi3InstanceEnvironment,
    log_message: Fmi3LogMessageCallback,
) -> Fmi3Instance {
    refuse(
        instance_environment,
        log_message,
        "fmi3InstantiateModelExchange",
        ME,
    )
}

/// fmi3InstantiateScheduledExecution: this FMU is Co-Simulation only; logs why and
/// returns NULL.
///
/// # Safety
/// FMI 3.0 caller contract.
#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _instance_name: Fmi3String,
    _instantiation_token: Fmi3String,
    _resource_path: Fmi3String,
    _visible: Fmi3Boolean,
    _logging_on: Fmi3Boolean,
    instance_environment: Fmi3InstanceEnvironment,
    log_message: Fmi3LogMessageCallback,
    _clock_update: Fmi3ClockUpdateCallback,
    _lock_preemption: Fmi3PreemptionCallback,
    _unlock_preemption: Fmi3PreemptionCallback,
) -> Fmi3Instance {
    refuse(
        instance_environment,
        log_message,
        "fmi3InstantiateScheduledExecution",
        SE,
    )
}

fn refuse(
    env: Fmi3InstanceEnvironment,
    log: Fmi3LogMessageCallback,
    func: &'static str,
    what: &str,
) -> *mut c_void {
    let _ = std::panic::catch_unwind(|| {
        let logger = crate::fmi2::logging::Logger::new(
            func,
            crate::fmi2::logging::Sink::Fmi3(log, env),
            true,
        );
        logger.log(
            crate::fmi2::model::Status::Error,
            crate::fmi2::logging::Category::Error,
            &format!("{func}: not supported by this FMU ({what})"),
        );
    });
    ptr::null_mut()
}
