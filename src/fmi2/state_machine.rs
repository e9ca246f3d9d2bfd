//! The FMI 2.0 Co-Simulation state machine: its states and, per function, the set of
//! states the function is allowed in (one table, checked by one guard,
//! `Instance::guard`).

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
    pub(crate) const fn bit(self) -> u8 {
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
    pub(crate) fn code(self) -> u32 {
        self.bit().trailing_zeros()
    }
    pub(crate) fn from_code(c: u32) -> Option<Phase> {
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
