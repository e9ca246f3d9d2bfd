//! The Co-Simulation state machine: its states and, per function, the set of states the
//! function is allowed in (one table per FMI version, a [`Dialect`], checked by one guard,
//! `Instance::guard`). The states are those both versions share (this FMU has no
//! asynchronous steps in 2.0, no event mode, configuration mode or intermediate update in
//! 3.0); the FMI 2.0 table is [`FMI2`], the FMI 3.0 one is `crate::fmi3::FMI3`.

/// States of the Co-Simulation state machine (fmi-standard 2.0, section 4.2.4, with no
/// asynchronous stepping, so no stepInProgress/stepCanceled; FMI 3.0 section 4.2.1 without
/// event mode: Step Mode is `StepComplete`, Step Discarded is `StepFailed`).
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
    /// The state's bit in the allowed-state masks.
    pub const fn bit(self) -> u8 {
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

/// One FMI function: its name (for messages) and the states it is allowed in.
#[derive(Debug, Clone, Copy)]
pub struct Call {
    /// The function's name, e.g. "fmi2DoStep".
    pub name: &'static str,
    /// Allowed-state mask ([`Phase::bit`] of each allowed state).
    pub allowed: u8,
}

/// What differs between the FMI versions in the generic instance: the function names and
/// allowed states, the instance magic and the tag of a serialized FMU state.
#[derive(Debug)]
pub struct Dialect {
    /// "2.0" or "3.0".
    pub version: &'static str,
    /// The file a user knows this version as (for messages).
    pub fmu_file: &'static str,
    /// Magic number of a live instance of this version (an instance of the other version
    /// passed to these functions is refused).
    pub magic: u64,
    /// Appended to the GUID when a serialized FMU state is sealed: the states of the two
    /// versions are versioned separately and each FMU refuses the other's.
    pub state_tag: &'static str,
    /// SetDebugLogging
    pub set_debug_logging: Call,
    /// SetupExperiment (FMI 3.0: the experiment part of EnterInitializationMode)
    pub setup_experiment: Call,
    /// EnterInitializationMode
    pub enter_init: Call,
    /// ExitInitializationMode
    pub exit_init: Call,
    /// Terminate
    pub terminate: Call,
    /// Reset
    pub reset: Call,
    /// Getters (the name is passed per call)
    pub get: u8,
    /// Setters (the name is passed per call)
    pub set: u8,
    /// SetRealInputDerivatives (FMI 2.0 only)
    pub set_input_der: Call,
    /// GetRealOutputDerivatives / GetOutputDerivatives
    pub get_output_der: Call,
    /// DoStep
    pub do_step: Call,
    /// GetFMUstate
    pub get_state: Call,
    /// SetFMUstate
    pub set_state: Call,
    /// DeSerializeFMUstate (and the other FMU-state functions' mask)
    pub deserialize: Call,
}

const fn call(name: &'static str, allowed: u8) -> Call {
    Call { name, allowed }
}

/// The FMI 2.0 table.
pub const FMI2: Dialect = Dialect {
    version: "2.0",
    fmu_file: "GearedRotor.fmu",
    magic: 0x4752_5f49_4e53_5431,
    state_tag: "",
    set_debug_logging: call("fmi2SetDebugLogging", allowed::SET_DEBUG_LOGGING),
    setup_experiment: call("fmi2SetupExperiment", allowed::SETUP_EXPERIMENT),
    enter_init: call("fmi2EnterInitializationMode", allowed::ENTER_INIT),
    exit_init: call("fmi2ExitInitializationMode", allowed::EXIT_INIT),
    terminate: call("fmi2Terminate", allowed::TERMINATE),
    reset: call("fmi2Reset", allowed::RESET),
    get: allowed::GET,
    set: allowed::SET,
    set_input_der: call("fmi2SetRealInputDerivatives", allowed::SET_INPUT_DER),
    get_output_der: call("fmi2GetRealOutputDerivatives", allowed::GET_OUTPUT_DER),
    do_step: call("fmi2DoStep", allowed::DO_STEP),
    get_state: call("fmi2GetFMUstate", allowed::FMU_STATE),
    set_state: call("fmi2SetFMUstate", allowed::FMU_STATE),
    deserialize: call("fmi2DeSerializeFMUstate", allowed::FMU_STATE),
};

/// Allowed-state sets of FMI 2.0 (bit masks of the phases: Instantiated = 1, InitializationMode = 2,
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
