//! The safe, model-agnostic FMU instance behind the C shells: the Co-Simulation state
//! machine (one allowed-state table per function and FMI version, a [`Dialect`], one
//! guard), the argument checks
//! against the variable table, logging, the experiment and the FMU-state envelope. What a
//! variable means is the model's business ([`Model`]). Every error is a typed
//! [`FmuError`] whose FMI status is decided in exactly one place, [`FmuError::status`].

use super::bounds;
use super::error::FmuError;
use super::logging::{Category, Logger, Sink};
use super::model::{Experiment, Model, Status, StepEnd};
use super::state_machine::{Dialect, Phase, FMI2};
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

/// Magic value of a live FMI 2.0 instance (detects some use-after-free / foreign pointers;
/// an FMI 3.0 instance has [`Dialect::magic`] of its own).
pub const INSTANCE_MAGIC: u64 = FMI2.magic;

/// One FMU instance of model `M`. `repr(C)` with the magic first, so that the C shells of
/// both FMI versions read the magic at the same place and refuse the other's instances.
#[repr(C)]
pub struct Instance<M: Model> {
    /// [`Dialect::magic`] of its FMI version while alive.
    pub magic: u64,
    dialect: &'static Dialect,
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
    /// A new FMI 2.0 instance (after the shell checked GUID, type and name).
    pub fn new(
        name: &str,
        logger: Fmi2CallbackLogger,
        env: Fmi2ComponentEnvironment,
        logging_on: bool,
    ) -> Self {
        Self::with_dialect(name, Sink::Fmi2(logger, env), logging_on, &FMI2)
    }

    /// A new instance of the FMI version `dialect` logging to `sink`.
    pub fn with_dialect(
        name: &str,
        sink: Sink,
        logging_on: bool,
        dialect: &'static Dialect,
    ) -> Self {
        Instance {
            magic: dialect.magic,
            dialect,
            logger: Logger::new(name, sink, logging_on),
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

    /// The instance's time: the model's once it runs, else the experiment's start time.
    pub fn time(&self) -> f64 {
        self.model.time().unwrap_or(self.experiment.start)
    }

    /// The model.
    pub fn model(&self) -> &M {
        &self.model
    }

    /// The FMI version's table.
    pub fn dialect(&self) -> &'static Dialect {
        self.dialect
    }

    /// Sends a message to the master's logger (see [`Logger::log`]).
    pub fn log(&self, status: Status, category: Category, msg: &str) {
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

    /// [`Instance::fail_status`] as an `fmi2Status`.
    pub fn fail(&mut self, e: &FmuError<M::Error>) -> Fmi2Status {
        self.fail_status(e).into()
    }

    /// Logs an error and moves the state machine: Error -> Error state, Fatal -> Fatal,
    /// Discard -> StepFailed. Returns the status.
    pub fn fail_status(&mut self, e: &FmuError<M::Error>) -> Status {
        let status = e.status();
        let cat = match status {
            Status::Discard => Category::Discard,
            Status::Fatal => Category::Fatal,
            _ => Category::Error,
        };
        self.log(status, cat, &e.to_string());
        match status {
            Status::Fatal => self.phase = Phase::Fatal,
            // An unavailable status kind changes nothing; a discarded step does.
            Status::Discard if matches!(e, FmuError::StatusNotAvailable { .. }) => {}
            Status::Discard => self.phase = Phase::StepFailed,
            Status::Error if self.phase != Phase::Fatal => self.phase = Phase::Error,
            _ => {}
        }
        status
    }

    /// fmi2SetDebugLogging.
    ///
    /// # Errors
    /// Unknown category.
    pub fn set_debug_logging(&mut self, on: bool, cats: &[&str]) -> Result<(), FmuError<M::Error>> {
        let func = self.dialect.set_debug_logging.name;
        self.guard(func, self.dialect.set_debug_logging.allowed)?;
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
    ) -> Result<Status, FmuError<M::Error>> {
        let func = self.dialect.setup_experiment.name;
        self.guard(func, self.dialect.setup_experiment.allowed)?;
        let mut status = Status::OK;
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
                    Status::Warning,
                    Category::Warning,
                    &format!(
                        "{func}: tolerance = {t:e} is outside the range the solver supports, [{lo:e}, {hi:e}]; using {} = {used:e}", M::TOLERANCE_NAME
                    ),
                );
                status = Status::Warning;
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
        let c = self.dialect.enter_init;
        self.guard(c.name, c.allowed)?;
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
        let func = self.dialect.exit_init.name;
        self.guard(func, self.dialect.exit_init.allowed)?;
        self.model
            .exit_initialization(func, &self.experiment, &self.logger)
            .map_err(|error| FmuError::Model { func, error })?;
        self.phase = Phase::StepComplete;
        Ok(())
    }

    /// fmi2Terminate.
    ///
    /// # Errors
    /// Illegal call sequence.
    pub fn terminate(&mut self) -> Result<(), FmuError<M::Error>> {
        let c = self.dialect.terminate;
        self.guard(c.name, c.allowed)?;
        self.model.terminate(&self.logger);
        self.phase = Phase::Terminated;
        Ok(())
    }

    /// fmi2Reset: back to the state right after fmi2Instantiate (FMU states stay valid).
    ///
    /// # Errors
    /// After Fatal.
    pub fn reset(&mut self) -> Result<(), FmuError<M::Error>> {
        let c = self.dialect.reset;
        self.guard(c.name, c.allowed)?;
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
        self.guard(func, self.dialect.get)?;
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
        self.guard(func, self.dialect.set)?;
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
        let func = self.dialect.set_input_der.name;
        self.guard(func, self.dialect.set_input_der.allowed)?;
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
        let func = self.dialect.get_output_der.name;
        self.guard(func, self.dialect.get_output_der.allowed)?;
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
    pub fn do_step(&mut self, ccp: f64, h: f64) -> Result<Status, FmuError<M::Error>> {
        let func = self.check_step(ccp, h)?;
        self.model
            .do_step(func, ccp, h, &self.logger)
            .map_err(|error| FmuError::Model { func, error })
    }

    /// A doStep that may end early at an event of the model (FMI 3.0 early return,
    /// [`Model::do_step_until_event`]).
    ///
    /// # Errors
    /// As [`Instance::do_step`].
    pub fn do_step_until_event(&mut self, ccp: f64, h: f64) -> Result<StepEnd, FmuError<M::Error>> {
        let func = self.check_step(ccp, h)?;
        self.model
            .do_step_until_event(func, ccp, h, &self.logger)
            .map_err(|error| FmuError::Model { func, error })
    }

    /// The checks of a doStep before the model steps: call sequence, stopTime.
    fn check_step(&mut self, ccp: f64, h: f64) -> Result<&'static str, FmuError<M::Error>> {
        let func = self.dialect.do_step.name;
        self.guard(func, self.dialect.do_step.allowed)?;
        // FMI 2.0 section 2.1.6: computing past a defined stopTime is an error (with the
        // tolerance of the communication point, so a last step that lands on stopTime
        // up to round-off is accepted).
        if let (Some(stop), Some(t0)) = (self.experiment.stop, self.model.time()) {
            if ccp + h > stop + M::step_tolerance(t0, h) {
                return Err(FmuError::BadArgument {
                    func,
                    message: format!(
                        "the step [{}, {}] s goes past stopTime = {} s of {}",
                        Short(ccp),
                        Short(ccp + h),
                        Short(stop),
                        self.dialect.setup_experiment.name
                    ),
                });
            }
        }
        Ok(func)
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
        let c = self.dialect.get_state;
        self.guard(c.name, c.allowed)?;
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
        let func = self.dialect.set_state.name;
        self.guard(func, self.dialect.set_state.allowed)?;
        self.model
            .restore(&s.model)
            .map_err(|error| FmuError::Model { func, error })?;
        self.phase = s.phase;
        self.experiment = s.experiment;
        Ok(())
    }

    /// Serialized form of a state of the FMI 2.0 FMU ([`Instance::serialize_state_as`]).
    pub fn serialize_state(s: &FmuState<M>) -> Vec<u8> {
        Self::serialize_state_as(s, &FMI2)
    }

    /// Serialized form of a state: sealed with magic, version, GUID (with the tag of the FMI
    /// version, [`Dialect::state_tag`]) and checksum.
    pub fn serialize_state_as(s: &FmuState<M>, dialect: &Dialect) -> Vec<u8> {
        let mut w = Writer::default();
        w.u32(s.phase.code());
        w.bool(s.experiment.tolerance.is_some());
        w.f64(s.experiment.tolerance.unwrap_or(0.0));
        w.f64(s.experiment.start);
        w.bool(s.experiment.stop.is_some());
        w.f64(s.experiment.stop.unwrap_or(0.0));
        M::write_state(&s.model, &mut w);
        bytes::seal(&state_guid(dialect), &w.buf)
    }

    /// Reads a serialized state of the FMI 2.0 FMU ([`Instance::deserialize_state_as`]).
    ///
    /// # Errors
    /// Foreign, corrupted, incompatible or inconsistent buffer (never panics).
    pub fn deserialize_state(buf: &[u8]) -> Result<FmuState<M>, FmuError<M::Error>> {
        Self::deserialize_state_as(buf, &FMI2)
    }

    /// Reads a serialized state of the FMI version `dialect` and checks it before it is
    /// trusted; a state of the other FMI version is refused with a message saying so.
    ///
    /// # Errors
    /// Foreign, corrupted, incompatible or inconsistent buffer (never panics).
    pub fn deserialize_state_as(
        buf: &[u8],
        dialect: &Dialect,
    ) -> Result<FmuState<M>, FmuError<M::Error>> {
        let func = dialect.deserialize.name;
        let de = |error: DecodeError| FmuError::Decode { func, error };
        if let Some(other) = other_version(buf, dialect) {
            return Err(de(DecodeError {
                message: format!(
                    "this is a state of the FMI {} FMU ({}); the FMI {} FMU ({}) reads only its own states \
                     (the two are versioned separately)",
                    other.version, other.fmu_file, dialect.version, dialect.fmu_file
                ),
            }));
        }
        let payload = bytes::open(&state_guid(dialect), buf).map_err(de)?;
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

/// The GUID a serialized state of `dialect` is sealed with.
fn state_guid(dialect: &Dialect) -> String {
    format!("{}{}", variables::GUID, dialect.state_tag)
}

/// The other FMI version whose state `buf` is (same model and build), if it is one.
fn other_version(buf: &[u8], dialect: &Dialect) -> Option<&'static Dialect> {
    let mut r = Reader::new(buf.get(bytes::MAGIC.len()..)?);
    if buf.get(..bytes::MAGIC.len())? != bytes::MAGIC || r.u32("version").is_err() {
        return None;
    }
    let guid = r.bytes("GUID").ok()?;
    [&FMI2, &crate::fmi3::FMI3]
        .into_iter()
        .find(|d| d.version != dialect.version && guid == state_guid(d).as_bytes())
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
