//! The model-exchange functions, as error stubs (this FMU is Co-Simulation only; masters
//! refuse libraries that lack any of them).

use super::call;
use super::FmuError;
use crate::fmi2::types::*;

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
