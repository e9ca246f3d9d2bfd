//! The model-agnostic FMI 3.0 Co-Simulation layer, generic over the same contract
//! [`crate::fmi2::model::Model`] as the FMI 2.0 layer. It reuses the version-neutral
//! machinery of `crate::fmi2` (the instance with its argument checks, the errors and their
//! one status mapping, logging, bounds, the variable table) through the FMI 3.0 table
//! [`FMI3`] (function names, allowed states, instance magic, FMU-state tag), and adds what
//! 3.0 has of its own: the value-reference dispatch of the typed getters and setters
//! (Float64, Int32, Int64 for Enumerations, Boolean; the number of values checked), the
//! experiment of fmi3EnterInitializationMode and fmi3DoStep with its out-arguments and
//! early return ([`Instance3::do_step`]). The C functions are in `crate::c_abi3`.

pub mod types;

use crate::fmi2::error::FmuError;
use crate::fmi2::instance::Instance;
use crate::fmi2::logging::Sink;
use crate::fmi2::model::{Model, Status};
use crate::fmi2::state_machine::{allowed, Call, Dialect};
use crate::fmi2::variables::{self, VarType};
use types::{Fmi3InstanceEnvironment, Fmi3LogMessageCallback};

const fn call(name: &'static str, allowed: u8) -> Call {
    Call { name, allowed }
}

/// The FMI 3.0 table. Without event mode, configuration mode and intermediate update, the
/// FMI 3.0 Co-Simulation state machine (section 4.2.1) allows each function in the same
/// states as its FMI 2.0 counterpart: Instantiated, Initialization Mode, Step Mode
/// (`StepComplete`), Step Discarded (`StepFailed`), Terminated, and the error states.
pub const FMI3: Dialect = Dialect {
    version: "3.0",
    fmu_file: "GearedRotor-fmi3.fmu",
    magic: 0x4752_5f49_4e53_5433,
    state_tag: " FMI 3.0",
    set_debug_logging: call("fmi3SetDebugLogging", allowed::SET_DEBUG_LOGGING),
    setup_experiment: call("fmi3EnterInitializationMode", allowed::ENTER_INIT),
    enter_init: call("fmi3EnterInitializationMode", allowed::ENTER_INIT),
    exit_init: call("fmi3ExitInitializationMode", allowed::EXIT_INIT),
    terminate: call("fmi3Terminate", allowed::TERMINATE),
    reset: call("fmi3Reset", allowed::RESET),
    get: allowed::GET,
    set: allowed::SET,
    set_input_der: call("fmi3SetInputDerivatives", allowed::NONE),
    get_output_der: call("fmi3GetOutputDerivatives", allowed::GET_OUTPUT_DER),
    do_step: call("fmi3DoStep", allowed::DO_STEP),
    get_state: call("fmi3GetFMUState", allowed::FMU_STATE),
    set_state: call("fmi3SetFMUState", allowed::FMU_STATE),
    deserialize: call("fmi3DeserializeFMUState", allowed::FMU_STATE),
};

/// Value reference of the independent variable `time`, which the FMI 3.0 description
/// declares (FMI 3.0 requires one; `build/fmi3_description.rs`) and FMI 2.0 leaves
/// implicit: read with fmi3GetFloat64, never set.
pub const TIME_VR: u32 = 0;

/// The integer types of FMI 3.0 this FMU has variables of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IntKind {
    /// fmi3Int32: the Integer variables of the description.
    Int32,
    /// fmi3Int64: the Enumeration variables (FMI 3.0 reads and writes Enumerations as Int64).
    Int64,
}

/// What fmi3DoStep reports besides its status.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOutcome {
    /// eventHandlingNeeded (always false: no event mode).
    pub event_handling_needed: bool,
    /// terminateSimulation (false: the model never asks to stop; after an Error the
    /// status says it).
    pub terminate_simulation: bool,
    /// earlyReturn: the step ended before its end at an event of the model.
    pub early_return: bool,
    /// lastSuccessfulTime: the model time after the call.
    pub last_successful_time: f64,
}

/// One FMI 3.0 Co-Simulation instance of model `M`: the generic instance with the FMI 3.0
/// table, and the options of fmi3InstantiateCoSimulation. `repr(C)` with the generic
/// instance (and so its magic) first.
#[repr(C)]
pub struct Instance3<M: Model> {
    /// The generic instance (its `magic` is [`FMI3`]'s).
    pub inner: Instance<M>,
    /// earlyReturnAllowed of fmi3InstantiateCoSimulation.
    pub early_return_allowed: bool,
}

impl<M: Model> Instance3<M> {
    /// A new instance (after the shell checked the token and the name).
    pub fn new(
        name: &str,
        logger: Fmi3LogMessageCallback,
        env: Fmi3InstanceEnvironment,
        logging_on: bool,
        early_return_allowed: bool,
    ) -> Self {
        Instance3 {
            inner: Instance::with_dialect(name, Sink::Fmi3(logger, env), logging_on, &FMI3),
            early_return_allowed,
        }
    }

    /// fmi3EnterInitializationMode: the experiment, then initialization mode.
    ///
    /// # Errors
    /// Illegal call, bad experiment (nothing changed then).
    pub fn enter_initialization_mode(
        &mut self,
        tol: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<Status, FmuError<M::Error>> {
        let status = self.inner.setup_experiment(tol, start, stop)?;
        self.inner.enter_initialization_mode()?;
        Ok(status)
    }

    /// Checks that every value reference is one of an `kind` variable: fmi3GetInt32 of an
    /// Enumeration (or fmi3GetInt64 of an Integer) is refused with a message naming the
    /// function to use. Unknown value references are left to the generic lookup.
    ///
    /// # Errors
    /// [`FmuError::BadArgument`].
    pub fn check_int_kind(
        &self,
        func: &'static str,
        kind: IntKind,
        vrs: &[u32],
    ) -> Result<(), FmuError<M::Error>> {
        for &vr in vrs {
            if let Some(var) = variables::lookup(VarType::Integer, vr) {
                let is_enum = !var.items.is_empty();
                let (wrong, right) = match (kind, is_enum) {
                    (IntKind::Int32, true) => ("an Enumeration", "Int64"),
                    (IntKind::Int64, false) => ("an Int32 variable", "Int32"),
                    _ => continue,
                };
                let verb = if func.starts_with("fmi3Get") {
                    "Get"
                } else {
                    "Set"
                };
                return Err(FmuError::BadArgument {
                    func,
                    message: format!(
                        "{} (value reference {vr}) is {wrong}: use fmi3{verb}{right}",
                        var.name
                    ),
                });
            }
        }
        Ok(())
    }

    /// fmi3GetFloat64: the Real variables, and the independent variable `time`
    /// ([`TIME_VR`]; a master reads the other variables without the per-reference test of
    /// the general path).
    ///
    /// # Errors
    /// As [`Instance::get`].
    pub fn get_float64(
        &mut self,
        func: &'static str,
        vrs: &[u32],
        out: &mut [f64],
    ) -> Result<(), FmuError<M::Error>> {
        if !vrs.contains(&TIME_VR) {
            return self.inner.get(func, VarType::Real, vrs, |i, x| out[i] = x);
        }
        self.inner.guard(func, self.inner.dialect().get)?;
        for (i, &vr) in vrs.iter().enumerate() {
            if vr == TIME_VR {
                out[i] = self.inner.time();
            } else {
                self.inner
                    .get(func, VarType::Real, &[vr], |_, x| out[i] = x)?;
            }
        }
        Ok(())
    }

    /// fmi3SetFloat64: the independent variable `time` cannot be set.
    ///
    /// # Errors
    /// As [`Instance::set`]; [`FmuError::NotSettable`] for `time`.
    pub fn set_float64(
        &mut self,
        func: &'static str,
        vrs: &[u32],
        values: &[f64],
    ) -> Result<(), FmuError<M::Error>> {
        if vrs.contains(&TIME_VR) {
            self.inner.guard(func, self.inner.dialect().set)?;
            return Err(FmuError::NotSettable {
                func,
                name: "time",
                why: "it is the independent variable (fmi3EnterInitializationMode and fmi3DoStep set it)",
            });
        }
        self.inner.set(func, VarType::Real, vrs, &|i| values[i])
    }

    /// fmi3DoStep: integrates to `ccp + h`; with earlyReturnAllowed it may end earlier at an
    /// event of the model (docs/fmu.md "FMI 3.0"). The outcome is defined whatever the
    /// result (lastSuccessfulTime is the model time).
    pub fn do_step(
        &mut self,
        ccp: f64,
        h: f64,
    ) -> (Result<Status, FmuError<M::Error>>, StepOutcome) {
        let (r, early) = if self.early_return_allowed {
            match self.inner.do_step_until_event(ccp, h) {
                Ok(end) => (Ok(end.status), end.early_return.is_some()),
                Err(e) => (Err(e), false),
            }
        } else {
            (self.inner.do_step(ccp, h), false)
        };
        let last = self.inner.last_successful_time();
        (
            r,
            StepOutcome {
                event_handling_needed: false,
                terminate_simulation: false,
                early_return: early,
                last_successful_time: last,
            },
        )
    }
}

/// The error of a getter or setter of a type this FMU has no variables of (every value
/// reference is unknown), after the call-sequence check.
///
/// # Errors
/// Illegal call, the first value reference (unknown), or a value count that does not match.
pub fn no_variables_of_type<M: Model>(
    inst: &mut Instance<M>,
    func: &'static str,
    allowed: u8,
    vrs: &[u32],
    n_values: usize,
) -> Result<Status, FmuError<M::Error>> {
    inst.guard(func, allowed)?;
    check_n_values(func, vrs.len(), n_values)?;
    match vrs.first() {
        Some(&vr) => Err(FmuError::UnknownValueReference { func, vr }),
        None => Ok(Status::OK),
    }
}

/// nValues of a getter or setter: this FMU has no array variables, so one value per value
/// reference.
///
/// # Errors
/// [`FmuError::BadArgument`] naming both numbers.
pub fn check_n_values<E>(
    func: &'static str,
    nvr: usize,
    n_values: usize,
) -> Result<(), FmuError<E>> {
    if n_values != nvr {
        return Err(FmuError::BadArgument {
            func,
            message: format!(
                "nValues = {n_values} differs from nValueReferences = {nvr} (every variable of this FMU is a scalar)"
            ),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn time_value_reference_is_the_description_s() {
        assert_eq!(super::TIME_VR, crate::fmi3_description::TIME_VR);
    }
}
