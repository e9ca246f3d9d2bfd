//! The safe, model-agnostic FMU instance behind the C shell: the FMI 2.0 Co-Simulation
//! state machine (one allowed-state table per function, one guard), the argument checks
//! against the variable table, logging, the experiment and the FMU-state envelope. What a
//! variable means is the model's business ([`Model`]). Every error is a typed
//! [`FmuError`] whose FMI status is decided in exactly one place, [`FmuError::status`].

use super::bounds;
use super::error::FmuError;
use super::logging::{Category, Logger};
use super::model::{Experiment, Model};
use super::state_machine::{allowed, Phase};
use super::types::{Fmi2CallbackLogger, Fmi2ComponentEnvironment, Fmi2Status};
use super::variables::{self, Causality, VarType, Variability, Variable};
use crate::bytes::{self, DecodeError, Reader, Writer};
use crate::fmt_num::Short;

/// An FMU state: a complete copy of everything that defines the instance, no pointers.
#[derive(Clone)]
pub struct FmuState<M: Model> {
    phase: Phase,
    experiment: Experiment,
    model: M::State,
}

/// Magic value of a live instance (detects some use-after-free / foreign pointers).
pub const INSTANCE_MAGIC: u64 = 0x4752_5f49_4e53_5431;

/// One FMU instance of model `M`.
pub struct Instance<M: Model> {
    /// [`INSTANCE_MAGIC`] while alive.
    pub magic: u64,
    logger: Logger,
    phase: Phase,
    experiment: Experiment,
    model: M,
    /// FMU states created by this instance (addresses), for pointer validation.
    pub states: Vec<usize>,
    /// Test hook: panic at the next guarded call.
    pub panic_next_call: bool,
}

/// The variable of a value reference, or the error naming it (built only when needed:
/// the error type is large, and every value reference of every Get/Set call comes here).
#[inline]
fn lookup<E>(func: &'static str, ty: VarType, vr: u32) -> Result<&'static Variable, FmuError<E>> {
    variables::lookup(ty, vr).ok_or_else(|| FmuError::UnknownValueReference { func, vr })
}

impl<M: Model> Instance<M> {
    /// A new instance (after the shell checked GUID, type and name).
    pub fn new(
        name: &str,
        logger: Fmi2CallbackLogger,
        env: Fmi2ComponentEnvironment,
        logging_on: bool,
    ) -> Self {
        Instance {
            magic: INSTANCE_MAGIC,
            logger: Logger::new(name, logger, env, logging_on),
            phase: Phase::Instantiated,
            experiment: Experiment::DEFAULT,
            model: M::instantiate(),
            states: Vec::new(),
            panic_next_call: false,
        }
    }

    /// Current state of the state machine.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// The model.
    pub fn model(&self) -> &M {
        &self.model
    }

    /// Sends a message to the master's logger (see [`Logger::log`]).
    pub fn log(&self, status: Fmi2Status, category: Category, msg: &str) {
        self.logger.log(status, category, msg);
    }

    /// The one guard: is `func` allowed in the current state?
    ///
    /// # Errors
    /// [`FmuError::IllegalCall`] / [`FmuError::AfterFatal`].
    pub fn guard(&mut self, func: &'static str, allowed: u8) -> Result<(), FmuError<M::Error>> {
        if self.panic_next_call {
            self.panic_next_call = false;
            panic!("test hook: deliberate panic in {func}");
        }
        if self.phase == Phase::Fatal {
            return Err(FmuError::AfterFatal { func });
        }
        if allowed & self.phase.bit() == 0 {
            return Err(FmuError::IllegalCall {
                func,
                phase: self.phase,
            });
        }
        Ok(())
    }

    /// Logs an error and moves the state machine: Error -> Error state, Fatal -> Fatal,
    /// Discard -> StepFailed. Returns the status.
    pub fn fail(&mut self, e: &FmuError<M::Error>) -> Fmi2Status {
        let status = e.status();
        let cat = if status == Fmi2Status::Discard {
            Category::Warning
        } else {
            Category::Error
        };
        self.log(status, cat, &e.to_string());
        match status {
            Fmi2Status::Fatal => self.phase = Phase::Fatal,
            // An unavailable status kind changes nothing; a discarded step does.
            Fmi2Status::Discard if matches!(e, FmuError::StatusNotAvailable { .. }) => {}
            Fmi2Status::Discard => self.phase = Phase::StepFailed,
            Fmi2Status::Error if self.phase != Phase::Fatal => self.phase = Phase::Error,
            _ => {}
        }
        status
    }

    /// fmi2SetDebugLogging.
    ///
    /// # Errors
    /// Unknown category.
    pub fn set_debug_logging(&mut self, on: bool, cats: &[&str]) -> Result<(), FmuError<M::Error>> {
        let func = "fmi2SetDebugLogging";
        self.guard(func, allowed::SET_DEBUG_LOGGING)?;
        self.logger
            .set_categories(on, cats)
            .map_err(|message| FmuError::BadArgument { func, message })
    }

    /// fmi2SetupExperiment. A tolerance outside [`Model::TOLERANCE_RANGE`] is a hint the
    /// solver cannot follow: it is clamped into the range with a warning (fmi2Warning), not
    /// refused.
    ///
    /// # Errors
    /// Non-finite or non-positive tolerance, non-finite start, stop before start.
    pub fn setup_experiment(
        &mut self,
        tol: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<Fmi2Status, FmuError<M::Error>> {
        let func = "fmi2SetupExperiment";
        self.guard(func, allowed::SETUP_EXPERIMENT)?;
        let mut status = Fmi2Status::OK;
        let mut tol = tol;
        if let Some(t) = tol {
            if !(t > 0.0 && t.is_finite()) {
                return Err(FmuError::BadArgument {
                    func,
                    message: format!("tolerance = {} must be a positive finite number", Short(t)),
                });
            }
            let (lo, hi) = M::TOLERANCE_RANGE;
            let used = t.clamp(lo, hi);
            if used != t {
                self.log(
                    Fmi2Status::Warning,
                    Category::Warning,
                    &format!(
                        "{func}: tolerance = {t:e} is outside the range the solver supports, [{lo:e}, {hi:e}]; using {} = {used:e}", M::TOLERANCE_NAME
                    ),
                );
                status = Fmi2Status::Warning;
                tol = Some(used);
            }
        }
        if !start.is_finite() {
            return Err(FmuError::BadArgument {
                func,
                message: format!("startTime = {} is not finite", Short(start)),
            });
        }
        if let Some(s) = stop {
            if s.is_nan() || s < start {
                return Err(FmuError::BadArgument {
                    func,
                    message: format!(
                        "stopTime = {} is before startTime = {}",
                        Short(s),
                        Short(start)
                    ),
                });
            }
        }
        self.experiment = Experiment {
            tolerance: tol,
            start,
            stop,
        };
        self.model.invalidate();
        Ok(status)
    }

    /// fmi2EnterInitializationMode.
    ///
    /// # Errors
    /// Illegal call sequence.
    pub fn enter_initialization_mode(&mut self) -> Result<(), FmuError<M::Error>> {
        self.guard("fmi2EnterInitializationMode", allowed::ENTER_INIT)?;
        self.phase = Phase::InitializationMode;
        self.model.invalidate();
        Ok(())
    }

    /// fmi2ExitInitializationMode: the model checks its parameters (the message names the
    /// parameter and the bound) and computes the initial state.
    ///
    /// # Errors
    /// The model's reason.
    pub fn exit_initialization_mode(&mut self) -> Result<(), FmuError<M::Error>> {
        let func = "fmi2ExitInitializationMode";
        self.guard(func, allowed::EXIT_INIT)?;
        self.model
            .exit_initialization(&self.experiment, &self.logger)
            .map_err(|error| FmuError::Model { func, error })?;
        self.phase = Phase::StepComplete;
        Ok(())
    }

    /// fmi2Terminate.
    ///
    /// # Errors
    /// Illegal call sequence.
    pub fn terminate(&mut self) -> Result<(), FmuError<M::Error>> {
        self.guard("fmi2Terminate", allowed::TERMINATE)?;
        self.model.terminate(&self.logger);
        self.phase = Phase::Terminated;
        Ok(())
    }

    /// fmi2Reset: back to the state right after fmi2Instantiate (FMU states stay valid).
    ///
    /// # Errors
    /// After Fatal.
    pub fn reset(&mut self) -> Result<(), FmuError<M::Error>> {
        self.guard("fmi2Reset", allowed::RESET)?;
        self.phase = Phase::Instantiated;
        self.model = M::instantiate();
        self.experiment = Experiment::DEFAULT;
        self.logger.reset();
        Ok(())
    }

    /// An output value, or an error if it is not a finite number (never returned with a
    /// status below fmi2Error).
    fn finite_output(
        &self,
        func: &'static str,
        var: &'static Variable,
        x: f64,
    ) -> Result<f64, FmuError<M::Error>> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(FmuError::OutputNotFinite {
                func,
                name: var.name,
                t: self.model.time().unwrap_or(f64::NAN),
            })
        }
    }

    /// fmi2GetReal / GetInteger / GetBoolean (values as f64; the shell converts).
    ///
    /// # Errors
    /// Illegal call, unknown value reference, values the model cannot compute.
    pub fn get(
        &mut self,
        func: &'static str,
        ty: VarType,
        vrs: &[u32],
        mut out: impl FnMut(usize, f64),
    ) -> Result<(), FmuError<M::Error>> {
        self.guard(func, allowed::GET)?;
        // One variable after the other, the error paths out of line (a master reads every
        // output at every point: this loop is part of the cost of a communication step).
        for (i, &vr) in vrs.iter().enumerate() {
            let var = lookup(func, ty, vr)?;
            match self.model.get(var, self.phase, &self.experiment) {
                Ok(x) if x.is_finite() || var.causality != Causality::Output => out(i, x),
                Ok(x) => return self.finite_output(func, var, x).map(|_| ()),
                Err(error) => return Err(FmuError::Model { func, error }),
            }
        }
        Ok(())
    }

    /// fmi2SetReal / SetInteger / SetBoolean. All value references are checked before
    /// anything is changed.
    ///
    /// # Errors
    /// Illegal call, unknown value reference, variable not settable now, NaN/inf, not an
    /// item of its Enumeration, out of declared bounds (inputs, tunables), the model's rules.
    pub fn set(
        &mut self,
        func: &'static str,
        ty: VarType,
        vrs: &[u32],
        value: &dyn Fn(usize) -> f64,
    ) -> Result<(), FmuError<M::Error>> {
        self.guard(func, allowed::SET)?;
        let stepping = self.phase == Phase::StepComplete;
        for (i, &vr) in vrs.iter().enumerate() {
            let var = lookup(func, ty, vr)?;
            let why = match (var.causality, var.variability) {
                (Causality::Input, _) => None,
                (Causality::Parameter, Variability::Tunable) => None,
                (Causality::Parameter, _) if !stepping => None,
                (Causality::Parameter, _) => {
                    Some("it is a fixed parameter and the model is initialised")
                }
                (Causality::Output, _) => Some("it is an output"),
                (Causality::CalculatedParameter, _) => Some("it is a calculated parameter"),
                _ => Some("it is not an input or parameter"),
            };
            if let Some(why) = why {
                return Err(FmuError::NotSettable {
                    func,
                    name: var.name,
                    why,
                });
            }
            let x = value(i);
            if !x.is_finite() {
                return Err(FmuError::NonFinite {
                    func,
                    name: var.name,
                    value: x,
                });
            }
            if !var.items.is_empty() && variables::item_name(var, x).is_none() {
                return Err(FmuError::NotAnItem {
                    func,
                    name: var.name,
                    value: x,
                    items: var.items,
                });
            }
            if bounds::checked_when_set(var) {
                bounds::check(var, x).map_err(|error| FmuError::OutOfBounds { func, error })?;
            }
        }
        for (i, &vr) in vrs.iter().enumerate() {
            let var = lookup(func, ty, vr)?;
            self.model
                .set(var, value(i), stepping)
                .map_err(|error| FmuError::Model { func, error })?;
        }
        Ok(())
    }

    /// fmi2SetRealInputDerivatives (order 1 only).
    ///
    /// # Errors
    /// Illegal call, order != 1, not an input, NaN/inf.
    pub fn set_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), FmuError<M::Error>> {
        let func = "fmi2SetRealInputDerivatives";
        self.guard(func, allowed::SET_INPUT_DER)?;
        let stepping = self.phase == Phase::StepComplete;
        for (i, &vr) in vrs.iter().enumerate() {
            let var = lookup(func, VarType::Real, vr)?;
            if var.causality != Causality::Input {
                return Err(FmuError::NotSettable {
                    func,
                    name: var.name,
                    why: "it is not an input",
                });
            }
            if orders[i] != 1 {
                return Err(FmuError::BadArgument {
                    func,
                    message: format!(
                        "derivative order {} of {} is not supported (only order 1)",
                        orders[i], var.name
                    ),
                });
            }
            if !values[i].is_finite() {
                return Err(FmuError::NonFinite {
                    func,
                    name: var.name,
                    value: values[i],
                });
            }
            self.model
                .set_input_derivative(var, values[i], stepping)
                .map_err(|error| FmuError::Model { func, error })?;
        }
        Ok(())
    }

    /// fmi2GetRealOutputDerivatives (order 1).
    ///
    /// # Errors
    /// Illegal call, order != 1, not a Real output, not available, not finite.
    pub fn get_output_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        out: &mut [f64],
    ) -> Result<(), FmuError<M::Error>> {
        let func = "fmi2GetRealOutputDerivatives";
        self.guard(func, allowed::GET_OUTPUT_DER)?;
        // Check every reference first (nothing written on error), then evaluate: no
        // allocation per call.
        for (i, &vr) in vrs.iter().enumerate() {
            let var = lookup(func, VarType::Real, vr)?;
            if var.causality != Causality::Output {
                return Err(FmuError::BadArgument {
                    func,
                    message: format!("{} is not an output", var.name),
                });
            }
            if orders[i] != 1 {
                return Err(FmuError::BadArgument {
                    func,
                    message: format!(
                        "derivative order {} of {} is not supported (maxOutputDerivativeOrder = 1)",
                        orders[i], var.name
                    ),
                });
            }
        }
        self.model
            .output_derivatives(vrs, out)
            .map_err(|error| FmuError::Model { func, error })?;
        for (&o, &vr) in out.iter().zip(vrs) {
            self.finite_output(func, lookup(func, VarType::Real, vr)?, o)?;
        }
        Ok(())
    }

    /// fmi2DoStep. Returns fmi2Warning when the model says so (it logged why).
    ///
    /// # Errors
    /// Illegal call, a step past stopTime, the model's reasons (Discard or Error).
    pub fn do_step(&mut self, ccp: f64, h: f64) -> Result<Fmi2Status, FmuError<M::Error>> {
        let func = "fmi2DoStep";
        self.guard(func, allowed::DO_STEP)?;
        // FMI 2.0 section 2.1.6: computing past a defined stopTime is an error (with the
        // tolerance of the communication point, so a last step that lands on stopTime
        // up to round-off is accepted).
        if let (Some(stop), Some(t0)) = (self.experiment.stop, self.model.time()) {
            if ccp + h > stop + M::step_tolerance(t0, h) {
                return Err(FmuError::BadArgument {
                    func,
                    message: format!(
                        "the step [{}, {}] s goes past stopTime = {} s of fmi2SetupExperiment",
                        Short(ccp),
                        Short(ccp + h),
                        Short(stop)
                    ),
                });
            }
        }
        self.model
            .do_step(ccp, h, &self.logger)
            .map_err(|error| FmuError::Model { func, error })
    }

    /// Time of the last successful step (fmi2GetRealStatus(fmi2LastSuccessfulTime)).
    pub fn last_successful_time(&self) -> f64 {
        self.model
            .last_successful_time()
            .unwrap_or(self.experiment.start)
    }

    /// fmi2GetFMUstate: a snapshot of everything.
    ///
    /// # Errors
    /// Illegal call.
    pub fn get_state(&mut self) -> Result<FmuState<M>, FmuError<M::Error>> {
        self.guard("fmi2GetFMUstate", allowed::FMU_STATE)?;
        Ok(FmuState {
            phase: self.phase,
            experiment: self.experiment,
            model: self.model.snapshot(),
        })
    }

    /// fmi2SetFMUstate: restores the model (time, solver history, inputs, parameters), the
    /// experiment and the state of the call-sequence machine.
    ///
    /// # Errors
    /// Illegal call, a state that cannot be rebuilt (the instance is unchanged).
    pub fn set_state(&mut self, s: &FmuState<M>) -> Result<(), FmuError<M::Error>> {
        let func = "fmi2SetFMUstate";
        self.guard(func, allowed::FMU_STATE)?;
        self.model
            .restore(&s.model)
            .map_err(|error| FmuError::Model { func, error })?;
        self.phase = s.phase;
        self.experiment = s.experiment;
        Ok(())
    }

    /// Serialized form of a state: sealed with magic, version, GUID and checksum.
    pub fn serialize_state(s: &FmuState<M>) -> Vec<u8> {
        let mut w = Writer::default();
        w.u32(s.phase.code());
        w.bool(s.experiment.tolerance.is_some());
        w.f64(s.experiment.tolerance.unwrap_or(0.0));
        w.f64(s.experiment.start);
        w.bool(s.experiment.stop.is_some());
        w.f64(s.experiment.stop.unwrap_or(0.0));
        M::write_state(&s.model, &mut w);
        bytes::seal(variables::GUID, &w.buf)
    }

    /// Reads a serialized state and checks it before it is trusted.
    ///
    /// # Errors
    /// Foreign, corrupted, incompatible or inconsistent buffer (never panics).
    pub fn deserialize_state(buf: &[u8]) -> Result<FmuState<M>, FmuError<M::Error>> {
        let func = "fmi2DeSerializeFMUstate";
        let de = |error: DecodeError| FmuError::Decode { func, error };
        let payload = bytes::open(variables::GUID, buf).map_err(de)?;
        let mut r = Reader::new(payload);
        let phase = Phase::from_code(r.u32("phase").map_err(de)?).ok_or_else(|| {
            de(DecodeError {
                message: "unknown phase code".into(),
            })
        })?;
        let has_tol = r.bool("tolerance flag").map_err(de)?;
        let tol = r.f64("tolerance").map_err(de)?;
        let start = r.finite("start time").map_err(de)?;
        let has_stop = r.bool("stop flag").map_err(de)?;
        let stop = r.f64("stop time").map_err(de)?;
        let model = M::read_state(&mut r).map_err(|error| FmuError::Model { func, error })?;
        r.finish().map_err(de)?;
        let state = FmuState {
            phase,
            experiment: Experiment {
                tolerance: has_tol.then_some(tol),
                start,
                stop: has_stop.then_some(stop),
            },
            model,
        };
        validate(&state).map_err(|message| de(DecodeError { message }))?;
        Ok(state)
    }
}

/// Checks of a deserialized [`FmuState`] before it is trusted (docs/fmu.md "Robustness"):
/// the checksums of the blob catch accidents, these catch a blob that is consistent but
/// wrong (another build, a tool that edited it and resealed it). The FMI layer's part
/// here, the model's in [`Model::validate_state`].
fn validate<M: Model>(s: &FmuState<M>) -> Result<(), String> {
    // fmi2GetFMUstate is not allowed in the Fatal state: no state holds it.
    if s.phase == Phase::Fatal {
        return Err("phase Fatal (no FMU state can be taken there)".into());
    }
    if let Some(tol) = s.experiment.tolerance {
        let (lo, hi) = M::TOLERANCE_RANGE;
        if !(lo..=hi).contains(&tol) {
            return Err(format!(
                "experiment tolerance {} outside [{lo:e}, {hi:e}]",
                Short(tol)
            ));
        }
    }
    if let Some(stop) = s.experiment.stop {
        if stop.is_nan() || stop < s.experiment.start {
            return Err(format!(
                "stopTime {} before startTime {}",
                Short(stop),
                Short(s.experiment.start)
            ));
        }
    }
    M::validate_state(&s.model, s.phase, &s.experiment)
}
