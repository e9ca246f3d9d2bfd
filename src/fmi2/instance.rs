//! The safe FMU instance behind the C shell: the FMI 2.0 Co-Simulation state machine (one
//! allowed-state table per function, one guard), the parameter store, logging by category,
//! the simulation, FMU states. Every error is a typed [`FmuError`] whose FMI status is
//! decided in exactly one place, [`FmuError::status`].

use super::bounds::{self, OutOfBounds};
use super::types::{Fmi2CallbackLogger, Fmi2ComponentEnvironment, Fmi2Status};
use super::variables::{
    self, Causality, Var, VarType, Variability, Variable, LOG_CATEGORIES, N_VARIABLES, VARIABLES,
};
use crate::bytes::{self as codec, DecodeError, Reader, Writer};
use crate::fmt_num::Short;
use crate::gear::FrictionParams;
use crate::gear::{GearData, ParamError};
use crate::rotor::{FrictionLaw, Outputs, Params, RotorData};
use crate::sim::{
    Initialization, Input, OnViolation, SimError, SimState, Simulation, SolverSettings, RTOL_MAX,
    RTOL_MIN,
};
use std::ffi::CString;
use std::fmt;

/// States of the FMI 2.0 Co-Simulation state machine (fmi-standard 2.0, section 4.2.4;
/// no asynchronous stepping, so no stepInProgress/stepCanceled).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// After fmi2Instantiate / fmi2Reset.
    Instantiated,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    InitializationMode,
    /// Ready for fmi2DoStep.
    StepComplete,
    /// fmi2DoStep returned fmi2Discard.
    StepFailed,
    /// After fmi2Terminate.
    Terminated,
    /// A function returned fmi2Error: getters, fmi2SetFMUstate, fmi2Reset, fmi2FreeInstance.
    Error,
    /// A function returned fmi2Fatal: only fmi2FreeInstance.
    Fatal,
}

impl Phase {
    const fn bit(self) -> u8 {
        match self {
            Phase::Instantiated => 1,
            Phase::InitializationMode => 2,
            Phase::StepComplete => 4,
            Phase::StepFailed => 8,
            Phase::Terminated => 16,
            Phase::Error => 32,
            Phase::Fatal => 64,
        }
    }
    fn code(self) -> u32 {
        self.bit().trailing_zeros()
    }
    fn from_code(c: u32) -> Option<Phase> {
        [
            Phase::Instantiated,
            Phase::InitializationMode,
            Phase::StepComplete,
            Phase::StepFailed,
            Phase::Terminated,
            Phase::Error,
            Phase::Fatal,
        ]
        .into_iter()
        .find(|p| p.code() == c)
    }
}

/// Allowed-state sets (bit masks of the phases: Instantiated = 1, InitializationMode = 2,
/// StepComplete = 4, StepFailed = 8, Terminated = 16, Error = 32).
pub mod allowed {
    const INST: u8 = 1;
    const INIT: u8 = 2;
    const STEP: u8 = 4;
    const FAIL: u8 = 8;
    const TERM: u8 = 16;
    const ERR: u8 = 32;
    /// fmi2SetDebugLogging
    pub const SET_DEBUG_LOGGING: u8 = INST | INIT | STEP | FAIL | TERM | ERR;
    /// fmi2SetupExperiment
    pub const SETUP_EXPERIMENT: u8 = INST;
    /// fmi2EnterInitializationMode
    pub const ENTER_INIT: u8 = INST;
    /// fmi2ExitInitializationMode
    pub const EXIT_INIT: u8 = INIT;
    /// fmi2Terminate
    pub const TERMINATE: u8 = STEP | FAIL | ERR;
    /// fmi2Reset
    pub const RESET: u8 = INST | INIT | STEP | FAIL | TERM | ERR;
    /// fmi2GetReal/Integer/Boolean/String
    pub const GET: u8 = INIT | STEP | FAIL | TERM | ERR;
    /// fmi2SetReal/Integer/Boolean/String
    pub const SET: u8 = INST | INIT | STEP;
    /// fmi2Get/Set/Free/Serialize/DeSerialize FMU state
    pub const FMU_STATE: u8 = INST | INIT | STEP | FAIL | TERM | ERR;
    /// fmi2GetDirectionalDerivative
    pub const DIRECTIONAL: u8 = INIT | STEP | FAIL | TERM | ERR;
    /// fmi2SetRealInputDerivatives
    pub const SET_INPUT_DER: u8 = INST | INIT | STEP;
    /// fmi2GetRealOutputDerivatives
    pub const GET_OUTPUT_DER: u8 = STEP | FAIL | TERM | ERR;
    /// fmi2DoStep
    pub const DO_STEP: u8 = STEP;
    /// fmi2CancelStep
    pub const CANCEL_STEP: u8 = STEP;
    /// fmi2GetStatus and friends
    pub const STATUS: u8 = STEP | FAIL | TERM | ERR;
    /// Model-Exchange functions (this FMU is CS only)
    pub const NONE: u8 = 0;
}

/// Log categories (same order as in the model description's LogCategories).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Category {
    /// logStatusError
    Error,
    /// logStatusWarning
    Warning,
    /// logEvents
    Events,
    /// logSolver
    Solver,
}

impl Category {
    fn name(self) -> &'static str {
        match self {
            Category::Error => "logStatusError",
            Category::Warning => "logStatusWarning",
            Category::Events => "logEvents",
            Category::Solver => "logSolver",
        }
    }
}

/// Every error an FMI call can produce.
#[derive(Debug, Clone, PartialEq)]
pub enum FmuError {
    /// Called in a state where the function is not allowed.
    IllegalCall {
        /// FMI function
        func: &'static str,
        /// current state
        phase: Phase,
    },
    /// A required pointer argument is NULL.
    NullPointer {
        /// FMI function
        func: &'static str,
        /// argument name
        arg: &'static str,
    },
    /// No variable of this type has this value reference.
    UnknownValueReference {
        /// FMI function
        func: &'static str,
        /// the value reference
        vr: u32,
    },
    /// The variable may not be set (now).
    NotSettable {
        /// FMI function
        func: &'static str,
        /// variable
        name: &'static str,
        /// why
        why: &'static str,
    },
    /// Any other bad argument.
    BadArgument {
        /// FMI function
        func: &'static str,
        /// what is wrong
        message: String,
    },
    /// A fmi2Get*Status kind this FMU cannot report (FMI 2.0 section 4.2.3: "If a status is
    /// required which cannot be retrieved by the slave it returns fmi2Discard"). Harmless:
    /// the instance keeps its state.
    StatusNotAvailable {
        /// FMI function
        func: &'static str,
        /// the fmi2StatusKind asked for
        kind: i32,
        /// why it is not available
        why: &'static str,
    },
    /// Optional function this FMU does not provide.
    Unsupported {
        /// FMI function
        func: &'static str,
        /// explanation
        what: &'static str,
    },
    /// From the simulation layer.
    Sim {
        /// FMI function
        func: &'static str,
        /// the error
        error: SimError,
    },
    /// A panic was caught at the C boundary.
    Panic {
        /// FMI function
        func: &'static str,
        /// panic payload
        message: String,
    },
    /// The instance is in the Fatal state.
    AfterFatal {
        /// FMI function
        func: &'static str,
    },
    /// A value outside the declared bounds of its variable (nothing was changed).
    OutOfBounds {
        /// FMI function
        func: &'static str,
        /// the variable, value and bounds
        error: OutOfBounds,
    },
    /// An output that cannot be computed at the current state (not a finite number).
    OutputNotFinite {
        /// FMI function
        func: &'static str,
        /// the output
        name: &'static str,
        /// the FMU time
        t: f64,
    },
}

impl FmuError {
    /// THE mapping of errors to FMI statuses: solver and model failures in fmi2DoStep are
    /// fmi2Discard (the state is that of the last successful time, the master may roll back and retry
    /// with a smaller step), panics and calls after them fmi2Fatal, everything else
    /// fmi2Error.
    pub fn status(&self) -> Fmi2Status {
        use crate::radau5::Error as R;
        match self {
            // Only fmi2DoStep may return fmi2Discard; a solver failure while setting up the
            // initial state (fmi2ExitInitializationMode) is an error.
            FmuError::Sim {
                func: "fmi2DoStep",
                error: SimError::Solver { error, .. },
            } => match error {
                R::InvalidOption { .. } | R::StopTimeBehind { .. } => Fmi2Status::Error,
                _ => Fmi2Status::Discard,
            },
            // The model cannot continue from the current state (e.g. no consistent lambda
            // after a parameter change): nothing was stepped, the state is that of the last
            // successful time (fmu.md: "the assumptions of the model violated").
            FmuError::Sim {
                func: "fmi2DoStep",
                error: SimError::Model(_) | SimError::WorkLimit { .. },
            } => Fmi2Status::Discard,
            // The run left the model's validity with on_lift_off = discard (sim::validity).
            FmuError::Sim {
                func: "fmi2DoStep",
                error: SimError::Validity(_),
            } => Fmi2Status::Discard,
            FmuError::StatusNotAvailable { .. } => Fmi2Status::Discard,
            FmuError::Panic { .. } | FmuError::AfterFatal { .. } => Fmi2Status::Fatal,
            _ => Fmi2Status::Error,
        }
    }
}

impl fmt::Display for FmuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FmuError::IllegalCall { func, phase } => {
                write!(
                    f,
                    "{func}: illegal call sequence (the instance is in state {phase:?})"
                )
            }
            FmuError::NullPointer { func, arg } => {
                write!(f, "{func}: argument {arg} is a NULL pointer")
            }
            FmuError::UnknownValueReference { func, vr } => {
                write!(
                    f,
                    "{func}: unknown value reference {vr} (no variable of this type has it)"
                )
            }
            FmuError::NotSettable { func, name, why } => {
                write!(f, "{func}: variable {name} cannot be set: {why}")
            }
            FmuError::BadArgument { func, message } => write!(f, "{func}: {message}"),
            FmuError::Unsupported { func, what } => {
                write!(f, "{func}: not supported by this FMU ({what})")
            }
            FmuError::StatusNotAvailable { func, kind, why } => {
                write!(
                    f,
                    "{func}: status kind {kind} is not available ({why}); returning fmi2Discard"
                )
            }
            FmuError::Sim { func, error } => write!(f, "{func}: {error}"),
            FmuError::Panic { func, message } => {
                write!(f, "{func}: internal error (caught panic: {message}); the instance is unusable, free it")
            }
            FmuError::AfterFatal { func } => write!(
                f,
                "{func}: the instance is in the Fatal state; only fmi2FreeInstance is allowed"
            ),
            FmuError::OutOfBounds { func, error } => {
                write!(f, "{func}: {error}; nothing was changed")
            }
            FmuError::OutputNotFinite { func, name, t } => write!(
                f,
                "{func}: output {name} cannot be computed at t = {} s (not a finite number)",
                Short(*t)
            ),
        }
    }
}

/// Make a message safe for a C logger that treats it as a printf format: '%' -> "%%",
/// NUL -> "\0" (two characters).
pub fn escape_message(s: &str) -> CString {
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        match c {
            '%' => out.push_str("%%"),
            '\0' => out.push_str("\\0"),
            c => out.push(c),
        }
    }
    // No NUL is left, so this cannot fail; fall back to an empty string rather than panic.
    CString::new(out).unwrap_or_default()
}

/// Experiment set up by fmi2SetupExperiment.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Experiment {
    tolerance: Option<f64>,
    start: f64,
    stop: Option<f64>,
}

const DEFAULT_EXPERIMENT: Experiment = Experiment {
    tolerance: None,
    start: 0.0,
    stop: None,
};

/// An FMU state: a complete copy of everything that defines the instance, no pointers.
#[derive(Clone)]
pub struct FmuState {
    phase: Phase,
    values: [f64; N_VARIABLES],
    input_der: [f64; 2],
    experiment: Experiment,
    sim: Option<SimState>,
}

/// Magic value of a live instance (detects some use-after-free / foreign pointers).
pub const INSTANCE_MAGIC: u64 = 0x4752_5f49_4e53_5431;

/// One FMU instance.
pub struct Instance {
    /// [`INSTANCE_MAGIC`] while alive.
    pub magic: u64,
    name: CString,
    logger: Fmi2CallbackLogger,
    env: Fmi2ComponentEnvironment,
    categories: [bool; 4],
    categories_at_instantiate: [bool; 4],
    phase: Phase,
    values: [f64; N_VARIABLES],
    input_der: [f64; 2],
    experiment: Experiment,
    sim: Option<Simulation>,
    /// Simulation is stale w.r.t. `values` (initialisation mode only).
    dirty: bool,
    outputs: Option<Outputs>,
    /// FMU states created by this instance (addresses), for pointer validation.
    pub states: Vec<usize>,
    /// Test hook: panic at the next guarded call.
    pub panic_next_call: bool,
}

fn start_values() -> [f64; N_VARIABLES] {
    let mut v = [0.0; N_VARIABLES];
    for (x, var) in v.iter_mut().zip(VARIABLES.iter()) {
        *x = var.start.unwrap_or(0.0);
    }
    v
}

fn vec3(o: &[f64; 3], ax: usize) -> f64 {
    o[ax]
}

/// Value of an output variable in an [`Outputs`] (None if `var` is not an output).
pub fn output_value(o: &Outputs, var: Var) -> Option<f64> {
    use Var::*;
    Some(match var {
        T1 => o.t1,
        omega1_filtered => o.omega1,
        omega2 => o.omega2,
        phi1 => o.phi1,
        phi2 => o.phi2,
        Fn => o.fn_,
        TE => o.te,
        gap => o.gap,
        P_in => o.p_in,
        P_loss => o.p_loss,
        mu_eff => o.mu_eff,
        mu_mz => o.mu_mz,
        P_damp => o.p_damp,
        E_in => o.e_in,
        E_loss => o.e_loss,
        E_damp => o.e_damp,
        E_load => o.e_load,
        E_kin => o.e_kin,
        E_pot => o.e_pot,
        contact_length => o.contact_length,
        pairs_in_contact => f64::from(o.pairs_in_contact),
        contact_lost => f64::from(u8::from(o.contact_lost)),
        u1_x => vec3(&o.u1, 0),
        u1_y => vec3(&o.u1, 1),
        u1_z => vec3(&o.u1, 2),
        u2_x => vec3(&o.u2, 0),
        u2_y => vec3(&o.u2, 1),
        u2_z => vec3(&o.u2, 2),
        v1_x => vec3(&o.v1, 0),
        v1_y => vec3(&o.v1, 1),
        v1_z => vec3(&o.v1, 2),
        v2_x => vec3(&o.v2, 0),
        v2_y => vec3(&o.v2, 1),
        v2_z => vec3(&o.v2, 2),
        F_bearing1_x => vec3(&o.f_bearing1, 0),
        F_bearing1_y => vec3(&o.f_bearing1, 1),
        F_bearing1_z => vec3(&o.f_bearing1, 2),
        F_bearing2_x => vec3(&o.f_bearing2, 0),
        F_bearing2_y => vec3(&o.f_bearing2, 1),
        F_bearing2_z => vec3(&o.f_bearing2, 2),
        F_friction1_x => vec3(&o.f_friction1, 0),
        F_friction1_y => vec3(&o.f_friction1, 1),
        F_friction1_z => vec3(&o.f_friction1, 2),
        F_friction2_x => vec3(&o.f_friction2, 0),
        F_friction2_y => vec3(&o.f_friction2, 1),
        F_friction2_z => vec3(&o.f_friction2, 2),
        M_friction1_x => vec3(&o.m_friction1, 0),
        M_friction1_y => vec3(&o.m_friction1, 1),
        M_friction1_z => vec3(&o.m_friction1, 2),
        M_friction2_x => vec3(&o.m_friction2, 0),
        M_friction2_y => vec3(&o.m_friction2, 1),
        M_friction2_z => vec3(&o.m_friction2, 2),
        F_contact1_x => vec3(&o.f_contact1, 0),
        F_contact1_y => vec3(&o.f_contact1, 1),
        F_contact1_z => vec3(&o.f_contact1, 2),
        F_contact2_x => vec3(&o.f_contact2, 0),
        F_contact2_y => vec3(&o.f_contact2, 1),
        F_contact2_z => vec3(&o.f_contact2, 2),
        M_contact1_x => vec3(&o.m_contact1, 0),
        M_contact1_y => vec3(&o.m_contact1, 1),
        M_contact1_z => vec3(&o.m_contact1, 2),
        M_contact2_x => vec3(&o.m_contact2, 0),
        M_contact2_y => vec3(&o.m_contact2, 1),
        M_contact2_z => vec3(&o.m_contact2, 2),
        _ => return None,
    })
}

/// Value of a calculated parameter from the pair geometry (model.md §2, §9.7).
fn calculated_value(g: &crate::gear::PairGeometry, var: Var) -> Option<f64> {
    Some(match var {
        Var::r_b1 => g.rb1,
        Var::r_b2 => g.rb2,
        Var::a_w => g.a_w,
        Var::alpha_wt => g.alpha_wt,
        Var::beta_b => g.beta_b,
        Var::p_bt => g.p_bt,
        Var::eps_alpha => g.eps_alpha,
        Var::eps_beta => g.eps_beta,
        Var::H_V => g.h_v,
        _ => return None,
    })
}

/// The error for an Enumeration value outside its items, listing them.
fn enum_error(var: Var, x: f64) -> ParamError {
    let v = variables::variable(var);
    let items: Vec<String> = v
        .items
        .iter()
        .enumerate()
        .map(|(k, n)| format!("{} = {n}", k + 1))
        .collect();
    ParamError {
        name: v.name,
        value: x,
        requirement: format!("one of {}", items.join(", ")),
    }
}

fn input_of(var: Var) -> Option<Input> {
    match var {
        Var::omega1 => Some(Input::Omega1),
        Var::T_load => Some(Input::TLoad),
        _ => None,
    }
}

impl Instance {
    /// A new instance (after the shell checked GUID, type and name).
    pub fn new(
        name: &str,
        logger: Fmi2CallbackLogger,
        env: Fmi2ComponentEnvironment,
        logging_on: bool,
    ) -> Instance {
        Instance {
            magic: INSTANCE_MAGIC,
            // Passed to the logger as it came (only the message is a printf format).
            name: CString::new(name).unwrap_or_else(|_| escape_message(name)),
            logger,
            env,
            categories: [logging_on; 4],
            categories_at_instantiate: [logging_on; 4],
            phase: Phase::Instantiated,
            values: start_values(),
            input_der: [0.0; 2],
            experiment: DEFAULT_EXPERIMENT,
            sim: None,
            dirty: true,
            outputs: None,
            states: Vec::new(),
            panic_next_call: false,
        }
    }

    /// Current state of the state machine.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// The simulation (after initialisation).
    pub fn simulation(&self) -> Option<&Simulation> {
        self.sim.as_ref()
    }

    /// Sends a message to the master's logger. Errors, discards and warnings (the reason
    /// for a status other than OK) are always sent; other messages only when their category
    /// is enabled by fmi2SetDebugLogging.
    pub fn log(&self, status: Fmi2Status, category: Category, msg: &str) {
        let forced = matches!(
            status,
            Fmi2Status::Error | Fmi2Status::Fatal | Fmi2Status::Discard | Fmi2Status::Warning
        );
        if !forced && !self.categories[category as usize] {
            return;
        }
        if let Some(logger) = self.logger {
            let cat = escape_message(category.name());
            let m = escape_message(msg);
            // SAFETY: the master's callback with NUL-terminated strings that outlive the call;
            // the message contains no '%' conversion, so a printf-style logger reads no varargs.
            unsafe {
                logger(
                    self.env,
                    self.name.as_ptr(),
                    status,
                    cat.as_ptr(),
                    m.as_ptr(),
                )
            };
        }
    }

    /// Whether a category is enabled (to skip formatting work).
    pub fn enabled(&self, category: Category) -> bool {
        self.categories[category as usize]
    }

    /// The one guard: is `func` allowed in the current state?
    ///
    /// # Errors
    /// [`FmuError::IllegalCall`] / [`FmuError::AfterFatal`].
    pub fn guard(&mut self, func: &'static str, allowed: u8) -> Result<(), FmuError> {
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
    pub fn fail(&mut self, e: &FmuError) -> Fmi2Status {
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
    pub fn set_debug_logging(&mut self, on: bool, cats: &[&str]) -> Result<(), FmuError> {
        let func = "fmi2SetDebugLogging";
        self.guard(func, allowed::SET_DEBUG_LOGGING)?;
        if cats.is_empty() {
            self.categories = [on; 4];
            return Ok(());
        }
        // FMI 2.0 (2.1.5): loggingOn with categories logs only those categories;
        // loggingOn = false switches the listed ones off and leaves the others.
        let mut new = if on { [false; 4] } else { self.categories };
        for c in cats {
            match *c {
                "logAll" => new = [on; 4],
                "logStatusError" => new[Category::Error as usize] = on,
                "logStatusWarning" => new[Category::Warning as usize] = on,
                "logEvents" => new[Category::Events as usize] = on,
                "logSolver" => new[Category::Solver as usize] = on,
                other => {
                    return Err(FmuError::BadArgument {
                        func,
                        message: format!(
                            "unknown log category \"{other}\" (known: {})",
                            LOG_CATEGORIES.join(", ")
                        ),
                    })
                }
            }
        }
        self.categories = new;
        Ok(())
    }

    /// fmi2SetupExperiment. A tolerance outside the range of the `rtol` parameter is a
    /// hint the solver cannot follow: it is clamped into [`RTOL_MIN`], [`RTOL_MAX`] with a
    /// warning (fmi2Warning), not refused.
    ///
    /// # Errors
    /// Non-finite or non-positive tolerance, non-finite start, stop before start.
    pub fn setup_experiment(
        &mut self,
        tol: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<Fmi2Status, FmuError> {
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
            let used = t.clamp(RTOL_MIN, RTOL_MAX);
            if used != t {
                self.log(
                    Fmi2Status::Warning,
                    Category::Warning,
                    &format!(
                        "{func}: tolerance = {t:e} is outside the range the solver supports, [{RTOL_MIN:e}, {RTOL_MAX:e}]; using rtol = {used:e}"
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
        self.dirty = true;
        Ok(status)
    }

    /// fmi2EnterInitializationMode.
    ///
    /// # Errors
    /// Illegal call sequence.
    pub fn enter_initialization_mode(&mut self) -> Result<(), FmuError> {
        self.guard("fmi2EnterInitializationMode", allowed::ENTER_INIT)?;
        self.phase = Phase::InitializationMode;
        self.dirty = true;
        Ok(())
    }

    fn v(&self, var: Var) -> f64 {
        self.values[var as usize]
    }

    /// Parameters from the store; the friction-law code is checked here, the rest by
    /// `Params::validate` (names the parameter and the bound).
    fn params(&self) -> Result<Params, ParamError> {
        use Var::*;
        let law = self.v(friction_law);
        let Some(law_kind) = FrictionLaw::from_code(law as i32).filter(|_| law.fract() == 0.0)
        else {
            return Err(ParamError {
                name: "friction_law",
                value: law,
                requirement: "friction_law in 1..=4 (1 Coulomb, 2 regularised, 3 ISO/TR 14179-2, 4 local EHL)".into(),
            });
        };
        let gear = GearData {
            z1: self.v(z1) as i32,
            z2: self.v(z2) as i32,
            m_n: self.v(m_n),
            alpha_n: self.v(alpha_n),
            beta: self.v(beta),
            b: self.v(b),
            x1: self.v(x1),
            x2: self.v(x2),
            ha_coef: self.v(h_aP),
            a_w: self.v(a_w_set),
        };
        let rotor1 = RotorData {
            m: self.v(m1),
            j: self.v(J1),
            k: [self.v(k1_x), self.v(k1_y), self.v(k1_z)],
            d: [self.v(d1_x), self.v(d1_y), self.v(d1_z)],
        };
        let rotor2 = RotorData {
            m: self.v(m2),
            j: self.v(J2),
            k: [self.v(k2_x), self.v(k2_y), self.v(k2_z)],
            d: [self.v(d2_x), self.v(d2_y), self.v(d2_z)],
        };
        Ok(Params {
            gear,
            rotor1,
            rotor2,
            d_phi: self.v(d_phi),
            mu: self.v(mu),
            psi0: self.v(psi0),
            friction_law: law_kind,
            omega1_filter_hz: self.v(omega1_filter_frequency),
            friction: FrictionParams {
                v_reg: self.v(v_reg),
                eta_oil: self.v(eta_oil),
                ra: self.v(Ra),
                x_l: self.v(X_L),
                e1: self.v(E1),
                nu1: self.v(nu1),
                e2: self.v(E2),
                nu2: self.v(nu2),
            },
        })
    }

    /// The Enumeration parameter `initialization` (values checked at the set as well).
    fn initialization(&self) -> Result<Initialization, ParamError> {
        let x = self.v(Var::initialization);
        Initialization::from_code(x as i32)
            .filter(|_| x.fract() == 0.0)
            .ok_or_else(|| enum_error(Var::initialization, x))
    }

    /// The Enumeration parameter `on_lift_off`.
    fn on_violation(&self) -> Result<OnViolation, ParamError> {
        let x = self.v(Var::on_lift_off);
        OnViolation::from_code(x as i32)
            .filter(|_| x.fract() == 0.0)
            .ok_or_else(|| enum_error(Var::on_lift_off, x))
    }

    fn settings(&self) -> (SolverSettings, &'static str) {
        match self.experiment.tolerance {
            Some(t) => (
                SolverSettings {
                    rtol: t,
                    h_max: self.v(Var::h_max),
                },
                "fmi2SetupExperiment",
            ),
            None => (
                SolverSettings {
                    rtol: self.v(Var::rtol),
                    h_max: self.v(Var::h_max),
                },
                "the parameter rtol",
            ),
        }
    }

    /// Builds the simulation from the store if it is stale (initialisation mode).
    fn ensure_sim(&mut self, func: &'static str) -> Result<(), FmuError> {
        if self.sim.is_some() && !self.dirty {
            return Ok(());
        }
        let sim_err = |error| FmuError::Sim { func, error };
        for name in bounds::CHECKED_AT_INIT {
            if let Some(var) = variables::by_name(name) {
                bounds::check(var, self.values[var.var as usize])
                    .map_err(|error| FmuError::OutOfBounds { func, error })?;
            }
        }
        let params = self.params().map_err(|e| sim_err(SimError::Param(e)))?;
        let (settings, _) = self.settings();
        let initialization = self
            .initialization()
            .map_err(|e| sim_err(SimError::Param(e)))?;
        let mut sim = Simulation::with_initialization(
            params,
            settings,
            self.experiment.start,
            self.v(Var::omega1),
            self.v(Var::T_load),
            initialization,
        )
        .map_err(sim_err)?;
        sim.set_h_fixed(self.v(Var::h_fixed)).map_err(sim_err)?;
        if self.input_der[0] != 0.0 {
            sim.set_input_derivative(Input::Omega1, self.input_der[0])
                .map_err(sim_err)?;
        }
        if self.input_der[1] != 0.0 {
            sim.set_input_derivative(Input::TLoad, self.input_der[1])
                .map_err(sim_err)?;
        }
        self.sim = Some(sim);
        self.dirty = false;
        self.outputs = None;
        Ok(())
    }

    /// fmi2ExitInitializationMode: validates the parameters (message names the parameter
    /// and the bound) and computes the consistent initial state.
    ///
    /// # Errors
    /// Invalid parameter set, no consistent initial state.
    pub fn exit_initialization_mode(&mut self) -> Result<(), FmuError> {
        let func = "fmi2ExitInitializationMode";
        self.guard(func, allowed::EXIT_INIT)?;
        self.on_violation().map_err(|e| FmuError::Sim {
            func,
            error: SimError::Param(e),
        })?;
        self.ensure_sim(func)?;
        if let (Ok(init), Some(sim)) = (self.initialization(), self.sim.as_ref()) {
            let r = sim.init_report();
            if init == Initialization::Periodic && self.enabled(Category::Solver) {
                self.log(
                    Fmi2Status::OK,
                    Category::Solver,
                    &format!(
                        "initialization = periodic: orbit by chord shooting from the static equilibrium, \
                         {} iterations, scaled residual {:.2e}, largest Floquet multiplier {:.4}, \
                         {} mesh periods integrated ({} RADAU5 steps at rtol {:e})",
                        r.iterations, r.residual, r.floquet_max_abs, r.periods_integrated, r.steps, r.rtol
                    ),
                );
            }
        }
        let (s, source) = self.settings();
        if self.enabled(Category::Solver) {
            self.log(
                Fmi2Status::OK,
                Category::Solver,
                &format!(
                    "RADAU5: rtol = {:e} (from {source}), atol_i = rtol * scale_i with scales {:?}, h_max = {:e} s, start time {} s",
                    s.rtol,
                    crate::sim::SCALES,
                    s.h_max,
                    Short(self.experiment.start)
                ),
            );
            let h_fixed = self.v(Var::h_fixed);
            if h_fixed > 0.0 {
                self.log(
                    Fmi2Status::OK,
                    Category::Solver,
                    &format!(
                        "real-time mode: h_fixed = {h_fixed:e} s: per doStep of H, ceil(H/h_fixed) equal steps of {} Newton iterations, one Jacobian and LU pair, no error control",
                        crate::sim::realtime::NEWTON_ITERATIONS
                    ),
                );
            }
        }
        self.phase = Phase::StepComplete;
        Ok(())
    }

    /// fmi2Terminate.
    ///
    /// # Errors
    /// Illegal call sequence.
    pub fn terminate(&mut self) -> Result<(), FmuError> {
        self.guard("fmi2Terminate", allowed::TERMINATE)?;
        if let Some(sim) = &self.sim {
            if self.enabled(Category::Solver) {
                self.log(
                    Fmi2Status::OK,
                    Category::Solver,
                    &format!(
                        "RADAU5 totals at t = {}: {}",
                        Short(sim.time()),
                        sim.stats()
                    ),
                );
            }
        }
        self.phase = Phase::Terminated;
        Ok(())
    }

    /// fmi2Reset: back to the state right after fmi2Instantiate (FMU states stay valid).
    ///
    /// # Errors
    /// After Fatal.
    pub fn reset(&mut self) -> Result<(), FmuError> {
        self.guard("fmi2Reset", allowed::RESET)?;
        self.phase = Phase::Instantiated;
        self.values = start_values();
        self.input_der = [0.0; 2];
        self.experiment = DEFAULT_EXPERIMENT;
        self.sim = None;
        self.dirty = true;
        self.outputs = None;
        self.categories = self.categories_at_instantiate;
        Ok(())
    }

    fn lookup(func: &'static str, ty: VarType, vr: u32) -> Result<&'static Variable, FmuError> {
        variables::lookup(ty, vr).ok_or(FmuError::UnknownValueReference { func, vr })
    }

    /// The outputs at the current time, computed once per time point and cached; returned
    /// by reference (the struct is ~0.5 kB: copying it per value reference made a GetReal
    /// of all outputs cost as much as an internal step).
    fn current_outputs(&mut self, func: &'static str) -> Result<&Outputs, FmuError> {
        if self.phase == Phase::InitializationMode {
            self.ensure_sim(func)?;
        }
        if self.outputs.is_none() {
            let sim = self.sim.as_ref().ok_or_else(|| FmuError::BadArgument {
                func,
                message: "outputs are not available: the model was not initialised".into(),
            })?;
            self.outputs = Some(sim.outputs());
        }
        self.outputs.as_ref().ok_or_else(|| FmuError::BadArgument {
            func,
            message: "outputs are not available".into(),
        })
    }

    /// An output value, or an error if it is not a finite number (never returned with a
    /// status below fmi2Error).
    fn finite_output(
        &self,
        func: &'static str,
        var: &'static Variable,
        x: f64,
    ) -> Result<f64, FmuError> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(FmuError::OutputNotFinite {
                func,
                name: var.name,
                t: self.sim.as_ref().map_or(f64::NAN, Simulation::time),
            })
        }
    }

    fn value_of(&mut self, func: &'static str, var: &'static Variable) -> Result<f64, FmuError> {
        match var.causality {
            Causality::Parameter | Causality::Input | Causality::Local | Causality::Independent => {
                Ok(self.values[var.var as usize])
            }
            Causality::CalculatedParameter => {
                if self.phase == Phase::InitializationMode {
                    self.ensure_sim(func)?;
                }
                let sim = self.sim.as_ref().ok_or_else(|| FmuError::BadArgument {
                    func,
                    message: format!(
                        "{} is not available: the model was not initialised",
                        var.name
                    ),
                })?;
                calculated_value(sim.model().geometry(), var.var).ok_or_else(|| {
                    FmuError::BadArgument {
                        func,
                        message: format!("{} has no value", var.name),
                    }
                })
            }
            Causality::Output => {
                let o = self.current_outputs(func)?;
                let x = output_value(o, var.var).ok_or_else(|| FmuError::BadArgument {
                    func,
                    message: format!("{} has no value", var.name),
                })?;
                self.finite_output(func, var, x)
            }
        }
    }

    /// fmi2GetReal / GetInteger / GetBoolean (values as f64; the shell converts).
    ///
    /// # Errors
    /// Illegal call, unknown value reference, outputs before initialisation.
    pub fn get(
        &mut self,
        func: &'static str,
        ty: VarType,
        vrs: &[u32],
        out: &mut dyn FnMut(usize, f64),
    ) -> Result<(), FmuError> {
        self.guard(func, allowed::GET)?;
        for (i, &vr) in vrs.iter().enumerate() {
            let var = Self::lookup(func, ty, vr)?;
            let x = self.value_of(func, var)?;
            out(i, x);
        }
        Ok(())
    }

    /// fmi2SetReal / SetInteger / SetBoolean. All value references are checked before
    /// anything is changed.
    ///
    /// # Errors
    /// Illegal call, unknown value reference, variable not settable now, NaN/inf,
    /// tunable parameter out of bounds.
    pub fn set(
        &mut self,
        func: &'static str,
        ty: VarType,
        vrs: &[u32],
        value: &dyn Fn(usize) -> f64,
    ) -> Result<(), FmuError> {
        self.guard(func, allowed::SET)?;
        let stepping = self.phase == Phase::StepComplete;
        for (i, &vr) in vrs.iter().enumerate() {
            let var = Self::lookup(func, ty, vr)?;
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
                return Err(FmuError::Sim {
                    func,
                    error: SimError::NonFinite {
                        name: var.name,
                        value: x,
                    },
                });
            }
            if !var.items.is_empty() && variables::item_name(var, x).is_none() {
                return Err(FmuError::Sim {
                    func,
                    error: SimError::Param(enum_error(var.var, x)),
                });
            }
            if bounds::checked_when_set(var) {
                bounds::check(var, x).map_err(|error| FmuError::OutOfBounds { func, error })?;
            }
        }
        for (i, &vr) in vrs.iter().enumerate() {
            let var = Self::lookup(func, ty, vr)?;
            let x = value(i);
            if let Some(sim) = self.sim.as_mut().filter(|_| stepping) {
                let r = match var.var {
                    Var::mu => sim.set_mu(x),
                    Var::d_phi => sim.set_d_phi(x),
                    v => match input_of(v) {
                        Some(inp) => sim.set_input(inp, x),
                        None => Ok(()),
                    },
                };
                r.map_err(|error| FmuError::Sim { func, error })?;
                self.outputs = None;
            } else {
                self.dirty = true;
            }
            self.values[var.var as usize] = x;
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
    ) -> Result<(), FmuError> {
        let func = "fmi2SetRealInputDerivatives";
        self.guard(func, allowed::SET_INPUT_DER)?;
        for (i, &vr) in vrs.iter().enumerate() {
            let var = Self::lookup(func, VarType::Real, vr)?;
            let inp = input_of(var.var).ok_or(FmuError::NotSettable {
                func,
                name: var.name,
                why: "it is not an input",
            })?;
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
                return Err(FmuError::Sim {
                    func,
                    error: SimError::NonFinite {
                        name: var.name,
                        value: values[i],
                    },
                });
            }
            let k = match inp {
                Input::Omega1 => 0,
                Input::TLoad => 1,
            };
            self.input_der[k] = values[i];
            match self
                .sim
                .as_mut()
                .filter(|_| self.phase == Phase::StepComplete)
            {
                Some(sim) => {
                    sim.set_input_derivative(inp, values[i])
                        .map_err(|error| FmuError::Sim { func, error })?;
                    self.outputs = None;
                }
                None => self.dirty = true,
            }
        }
        Ok(())
    }

    /// fmi2GetRealOutputDerivatives (order 1, central difference on the dense output).
    ///
    /// # Errors
    /// Illegal call, order != 1, not a Real output.
    pub fn get_output_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        out: &mut [f64],
    ) -> Result<(), FmuError> {
        let func = "fmi2GetRealOutputDerivatives";
        self.guard(func, allowed::GET_OUTPUT_DER)?;
        // Check every reference first (nothing written on error), then evaluate: no
        // allocation per call.
        for (i, &vr) in vrs.iter().enumerate() {
            let var = Self::lookup(func, VarType::Real, vr)?;
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
        let sim = self.sim.as_mut().ok_or_else(|| FmuError::BadArgument {
            func,
            message: "the model was not initialised".into(),
        })?;
        let (om, op, delta) = sim.outputs_for_derivative();
        for (o, &vr) in out.iter_mut().zip(vrs) {
            let var = Self::lookup(func, VarType::Real, vr)?;
            let a = output_value(&om, var.var).unwrap_or(0.0);
            let b = output_value(&op, var.var).unwrap_or(0.0);
            *o = self.finite_output(func, var, (b - a) / (2.0 * delta))?;
        }
        Ok(())
    }

    /// fmi2DoStep. Returns fmi2Warning when an episode outside the model's validity
    /// started in the step (lift-off, drive reversal; `on_lift_off = warn`), with a message.
    ///
    /// # Errors
    /// Illegal call, bad h or communication point (Error), solver failure or a violation
    /// with `on_lift_off = discard` (Discard).
    pub fn do_step(&mut self, ccp: f64, h: f64) -> Result<Fmi2Status, FmuError> {
        let func = "fmi2DoStep";
        self.guard(func, allowed::DO_STEP)?;
        let policy = self.on_violation().unwrap_or_default();
        let sim = self.sim.as_mut().ok_or_else(|| FmuError::BadArgument {
            func,
            message: "no simulation".into(),
        })?;
        let t0 = sim.time();
        // FMI 2.0 section 2.1.6: computing past a defined stopTime is an error (with the
        // tolerance of the communication point, so a last step that lands on stopTime
        // up to round-off is accepted).
        if let Some(stop) = self.experiment.stop {
            if ccp + h > stop + crate::sim::comm_tolerance(t0, h) {
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
        sim.set_on_violation(policy);
        sim.set_max_internal_steps(self.values[Var::max_internal_steps as usize] as u64);
        let r = sim.do_step(ccp, h);
        self.outputs = None;
        let report = r.map_err(|error| FmuError::Sim { func, error })?;
        let mut status = Fmi2Status::OK;
        for v in report.violations.iter().flatten() {
            self.log(
                Fmi2Status::Warning,
                Category::Warning,
                &format!("{func}: {v}"),
            );
            status = Fmi2Status::Warning;
        }
        if report.violations_dropped > 0 {
            self.log(
                Fmi2Status::Warning,
                Category::Warning,
                &format!(
                    "{func}: {} further episodes outside the model's validity in [{t0}, {}] s",
                    report.violations_dropped,
                    ccp + h
                ),
            );
        }
        if report.contact_changes > 0 && self.enabled(Category::Events) {
            let what = if report.contact_lost {
                "lifted off (lambda < 0)"
            } else {
                "back in contact (lambda >= 0)"
            };
            self.log(
                Fmi2Status::OK,
                Category::Events,
                &format!(
                    "contact_lost changed {} time(s) in [{}, {}] s, first at t = {} s; at the end the teeth are {what}",
                    report.contact_changes,
                    Short(t0),
                    Short(ccp + h),
                    Short(report.first_change_time)
                ),
            );
        }
        if self.enabled(Category::Solver) {
            self.log(
                Fmi2Status::OK,
                Category::Solver,
                &format!(
                    "doStep [{}, {}] s{}: {}",
                    Short(t0),
                    Short(ccp + h),
                    if report.restarted { " (restart)" } else { "" },
                    report.stats
                ),
            );
        }
        Ok(status)
    }

    /// Time of the last successful step (fmi2GetRealStatus(fmi2LastSuccessfulTime)).
    pub fn last_successful_time(&self) -> f64 {
        self.sim
            .as_ref()
            .map_or(self.experiment.start, |s| s.last_successful_time())
    }

    /// fmi2GetFMUstate: a snapshot of everything.
    ///
    /// # Errors
    /// Illegal call.
    pub fn get_state(&mut self) -> Result<FmuState, FmuError> {
        self.guard("fmi2GetFMUstate", allowed::FMU_STATE)?;
        Ok(self.snapshot())
    }

    fn snapshot(&self) -> FmuState {
        FmuState {
            phase: self.phase,
            values: self.values,
            input_der: self.input_der,
            experiment: self.experiment,
            sim: if self.dirty {
                None
            } else {
                self.sim.as_ref().map(Simulation::state)
            },
        }
    }

    /// fmi2SetFMUstate: restores time, solver history, inputs, parameters and the state of
    /// the call-sequence machine.
    ///
    /// # Errors
    /// Illegal call, a state that cannot be rebuilt.
    pub fn set_state(&mut self, s: &FmuState) -> Result<(), FmuError> {
        let func = "fmi2SetFMUstate";
        self.guard(func, allowed::FMU_STATE)?;
        match (&s.sim, self.sim.as_mut()) {
            (Some(ss), Some(sim)) => sim
                .restore(ss)
                .map_err(|error| FmuError::Sim { func, error })?,
            (Some(ss), None) => {
                self.sim = Some(
                    Simulation::from_state(ss).map_err(|error| FmuError::Sim { func, error })?,
                )
            }
            (None, _) => self.sim = None,
        }
        self.dirty = self.sim.is_none();
        self.phase = s.phase;
        self.values = s.values;
        self.input_der = s.input_der;
        self.experiment = s.experiment;
        self.outputs = None;
        Ok(())
    }

    /// Serialized form of a state: sealed with magic, version, GUID and checksum.
    pub fn serialize_state(s: &FmuState) -> Vec<u8> {
        let mut w = Writer::default();
        w.u32(s.phase.code());
        w.u32(N_VARIABLES as u32);
        for x in s.values {
            w.f64(x);
        }
        w.f64(s.input_der[0]);
        w.f64(s.input_der[1]);
        w.bool(s.experiment.tolerance.is_some());
        w.f64(s.experiment.tolerance.unwrap_or(0.0));
        w.f64(s.experiment.start);
        w.bool(s.experiment.stop.is_some());
        w.f64(s.experiment.stop.unwrap_or(0.0));
        w.bool(s.sim.is_some());
        if let Some(ss) = &s.sim {
            ss.write(&mut w);
        }
        codec::seal(variables::GUID, &w.buf)
    }

    /// Reads a serialized state.
    ///
    /// # Errors
    /// Foreign, corrupted or incompatible buffer (never panics).
    pub fn deserialize_state(bytes: &[u8]) -> Result<FmuState, FmuError> {
        let func = "fmi2DeSerializeFMUstate";
        let de = |e: DecodeError| FmuError::Sim {
            func,
            error: SimError::Decode(e),
        };
        let payload = codec::open(variables::GUID, bytes).map_err(de)?;
        let mut r = Reader::new(payload);
        let phase = Phase::from_code(r.u32("phase").map_err(de)?).ok_or_else(|| {
            de(DecodeError {
                message: "unknown phase code".into(),
            })
        })?;
        if r.u32("variable count").map_err(de)? as usize != N_VARIABLES {
            return Err(de(DecodeError {
                message: "variable count differs".into(),
            }));
        }
        let mut values = [0.0; N_VARIABLES];
        for x in values.iter_mut() {
            *x = r.finite("variable value").map_err(de)?;
        }
        let input_der = [
            r.finite("input derivative").map_err(de)?,
            r.finite("input derivative").map_err(de)?,
        ];
        let has_tol = r.bool("tolerance flag").map_err(de)?;
        let tol = r.f64("tolerance").map_err(de)?;
        let start = r.finite("start time").map_err(de)?;
        let has_stop = r.bool("stop flag").map_err(de)?;
        let stop = r.f64("stop time").map_err(de)?;
        let sim = if r.bool("simulation flag").map_err(de)? {
            Some(SimState::read(&mut r).map_err(|error| FmuError::Sim { func, error })?)
        } else {
            None
        };
        r.finish().map_err(de)?;
        let state = FmuState {
            phase,
            values,
            input_der,
            experiment: Experiment {
                tolerance: has_tol.then_some(tol),
                start,
                stop: has_stop.then_some(stop),
            },
            sim,
        };
        restored::validate(&state).map_err(|message| de(DecodeError { message }))?;
        Ok(state)
    }
}

/// Checks of a deserialized [`FmuState`] before it is trusted (docs/fmu.md "Robustness"):
/// the checksums of the blob catch accidents, these catch a blob that is consistent but
/// wrong (another build, a tool that edited it and resealed it).
mod restored {
    use super::{bounds, variables, FmuState, Instance, Phase, Var, RTOL_MAX, RTOL_MIN};
    use crate::fmt_num::Short;

    /// What is wrong with `s`, if anything.
    pub fn validate(s: &FmuState) -> Result<(), String> {
        // fmi2GetFMUstate is not allowed in the Fatal state: no state holds it.
        if s.phase == Phase::Fatal {
            return Err("phase Fatal (no FMU state can be taken there)".into());
        }
        // Inputs and tunables are checked when set, whatever the phase; the solver
        // parameters by fmi2ExitInitializationMode (rtol only if it is used), so only once
        // a simulation exists; the other parameters are compared with the simulation's
        // below.
        for (var, &x) in variables::VARIABLES.iter().zip(s.values.iter()) {
            let at_init = bounds::CHECKED_AT_INIT.contains(&var.name)
                || (var.var == Var::rtol && s.experiment.tolerance.is_none());
            if bounds::checked_when_set(var) || (at_init && s.sim.is_some()) {
                bounds::check(var, x).map_err(|e| format!("variable {e}"))?;
            }
        }
        if let Some(tol) = s.experiment.tolerance {
            if !(RTOL_MIN..=RTOL_MAX).contains(&tol) {
                return Err(format!(
                    "experiment tolerance {} outside [{RTOL_MIN:e}, {RTOL_MAX:e}]",
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
        let Some(sim) = &s.sim else {
            return match s.phase {
                Phase::StepComplete | Phase::StepFailed => {
                    Err(format!("phase {:?} without a simulation", s.phase))
                }
                _ => Ok(()),
            };
        };
        sim.validate().map_err(|e| match e {
            crate::sim::SimError::Decode(d) => d.message,
            e => e.to_string(),
        })?;
        // The simulation's own values: within the declared bounds, and the tunables and
        // solver settings equal to the parameter store.
        for (name, x) in sim.named_values() {
            if let Some(var) = variables::by_name(name) {
                bounds::check(var, x).map_err(|e| format!("simulation value {e}"))?;
            }
        }
        let v = |var: Var| s.values[var as usize];
        let [(_, _), (_, mu), (_, _), (_, d_phi), (_, f_c), (_, rtol), (_, h_max), ..] =
            sim.named_values();
        let mut pairs = vec![
            ("mu", mu, v(Var::mu)),
            ("d_phi", d_phi, v(Var::d_phi)),
            ("h_max", h_max, v(Var::h_max)),
        ];
        if !matches!(s.phase, Phase::Instantiated | Phase::InitializationMode) {
            pairs.push((
                "omega1_filter_frequency",
                f_c,
                v(Var::omega1_filter_frequency),
            ));
            pairs.push(("rtol", rtol, s.experiment.tolerance.unwrap_or(v(Var::rtol))));
        }
        // The fixed parameters of the store are those the simulation was initialised with
        // (the tunables compared above may have changed since).
        let mut probe = Instance::new("validate", None, std::ptr::null_mut(), false);
        probe.values = s.values;
        let mut stored = probe
            .params()
            .map_err(|e| format!("stored parameters: {e}"))?;
        let init = sim.init_params();
        stored.mu = init.mu;
        stored.d_phi = init.d_phi;
        if stored != *init {
            return Err(
                "the stored parameters differ from those the simulation was initialised with"
                    .into(),
            );
        }
        for (name, in_sim, stored) in pairs {
            if in_sim != stored {
                return Err(format!(
                    "{name} of the simulation ({}) differs from the stored parameter ({})",
                    Short(in_sim),
                    Short(stored)
                ));
            }
        }
        Ok(())
    }
}
