//! The C types of fmi2TypesPlatform.h and fmi2FunctionTypes.h (FMI 2.0.x, "default" platform).

use std::ffi::{c_char, c_int, c_uint, c_void};

/// `fmi2Component` (pointer to an instance).
pub type Fmi2Component = *mut c_void;
/// `fmi2ComponentEnvironment` (the master's pointer, passed back to callbacks).
pub type Fmi2ComponentEnvironment = *mut c_void;
/// `fmi2FMUstate`.
pub type Fmi2FMUstate = *mut c_void;
/// `fmi2ValueReference` (unsigned int).
pub type Fmi2ValueReference = c_uint;
/// `fmi2Real` (double).
pub type Fmi2Real = f64;
/// `fmi2Integer` (int).
pub type Fmi2Integer = c_int;
/// `fmi2Boolean` (int; fmi2True = 1, fmi2False = 0).
pub type Fmi2Boolean = c_int;
/// `fmi2Char`.
pub type Fmi2Char = c_char;
/// `fmi2String` (const fmi2Char*).
pub type Fmi2String = *const Fmi2Char;
/// `fmi2Byte` (char).
pub type Fmi2Byte = c_char;
/// fmi2True
pub const FMI2_TRUE: Fmi2Boolean = 1;
/// fmi2False
pub const FMI2_FALSE: Fmi2Boolean = 0;

/// `fmi2Status`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Fmi2Status {
    /// fmi2OK
    OK = 0,
    /// fmi2Warning
    Warning = 1,
    /// fmi2Discard
    Discard = 2,
    /// fmi2Error
    Error = 3,
    /// fmi2Fatal
    Fatal = 4,
    /// fmi2Pending
    Pending = 5,
}

impl From<crate::fmi2::model::Status> for Fmi2Status {
    fn from(s: crate::fmi2::model::Status) -> Self {
        use crate::fmi2::model::Status as S;
        match s {
            S::OK => Fmi2Status::OK,
            S::Warning => Fmi2Status::Warning,
            S::Discard => Fmi2Status::Discard,
            S::Error => Fmi2Status::Error,
            S::Fatal => Fmi2Status::Fatal,
        }
    }
}

/// `fmi2Type`: fmi2ModelExchange = 0, fmi2CoSimulation = 1 (received as int, never as a
/// Rust enum, so an out-of-range value from C is not undefined behaviour).
pub const FMI2_CO_SIMULATION: c_int = 1;
/// `fmi2StatusKind` values (received as int).
pub mod status_kind {
    /// fmi2DoStepStatus
    pub const DO_STEP_STATUS: i32 = 0;
    /// fmi2PendingStatus
    pub const PENDING_STATUS: i32 = 1;
    /// fmi2LastSuccessfulTime
    pub const LAST_SUCCESSFUL_TIME: i32 = 2;
    /// fmi2Terminated
    pub const TERMINATED: i32 = 3;
}

/// `fmi2CallbackLogger` (variadic: the message is a printf format).
pub type Fmi2CallbackLogger = Option<
    unsafe extern "C" fn(
        Fmi2ComponentEnvironment,
        Fmi2String,
        Fmi2Status,
        Fmi2String,
        Fmi2String,
        ...
    ),
>;
/// `fmi2CallbackAllocateMemory`.
pub type Fmi2CallbackAllocateMemory = Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>;
/// `fmi2CallbackFreeMemory`.
pub type Fmi2CallbackFreeMemory = Option<unsafe extern "C" fn(*mut c_void)>;
/// `fmi2StepFinished`.
pub type Fmi2StepFinished = Option<unsafe extern "C" fn(Fmi2ComponentEnvironment, Fmi2Status)>;

/// `fmi2CallbackFunctions` (passed by pointer to fmi2Instantiate).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct Fmi2CallbackFunctions {
    /// logger
    pub logger: Fmi2CallbackLogger,
    /// allocateMemory (may be NULL: canNotUseMemoryManagementFunctions)
    pub allocate_memory: Fmi2CallbackAllocateMemory,
    /// freeMemory (may be NULL)
    pub free_memory: Fmi2CallbackFreeMemory,
    /// stepFinished (unused: no asynchronous doStep)
    pub step_finished: Fmi2StepFinished,
    /// componentEnvironment
    pub component_environment: Fmi2ComponentEnvironment,
}

/// `fmi2EventInfo` (Model Exchange only; declared for the exported stubs).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct Fmi2EventInfo {
    /// newDiscreteStatesNeeded
    pub new_discrete_states_needed: Fmi2Boolean,
    /// terminateSimulation
    pub terminate_simulation: Fmi2Boolean,
    /// nominalsOfContinuousStatesChanged
    pub nominals_of_continuous_states_changed: Fmi2Boolean,
    /// valuesOfContinuousStatesChanged
    pub values_of_continuous_states_changed: Fmi2Boolean,
    /// nextEventTimeDefined
    pub next_event_time_defined: Fmi2Boolean,
    /// nextEventTime
    pub next_event_time: Fmi2Real,
}
