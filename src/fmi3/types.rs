//! The C types of the FMI 3.0 headers (fmi3PlatformTypes.h, fmi3FunctionTypes.h), declared
//! from the standard (the headers are not needed to build).

use std::ffi::{c_char, c_void};

/// `fmi3Instance` (pointer to an instance).
pub type Fmi3Instance = *mut c_void;
/// `fmi3InstanceEnvironment` (the importer's pointer, passed back to callbacks).
pub type Fmi3InstanceEnvironment = *mut c_void;
/// `fmi3FMUState`.
pub type Fmi3FMUState = *mut c_void;
/// `fmi3ValueReference` (uint32_t).
pub type Fmi3ValueReference = u32;
/// `fmi3Float64` (double).
pub type Fmi3Float64 = f64;
/// `fmi3Float32` (float).
pub type Fmi3Float32 = f32;
/// `fmi3Int32`.
pub type Fmi3Int32 = i32;
/// `fmi3Int64`.
pub type Fmi3Int64 = i64;
/// `fmi3UInt64`.
pub type Fmi3UInt64 = u64;
/// `fmi3Boolean`: C99 `bool`, one byte. Received and written as a byte (0 = false, any
/// other value = true), so a byte other than 0 or 1 from C is not undefined behaviour.
pub type Fmi3Boolean = u8;
/// fmi3True
pub const FMI3_TRUE: Fmi3Boolean = 1;
/// fmi3False
pub const FMI3_FALSE: Fmi3Boolean = 0;
/// `fmi3Char`.
pub type Fmi3Char = c_char;
/// `fmi3String` (const fmi3Char*).
pub type Fmi3String = *const Fmi3Char;
/// `fmi3Byte` (uint8_t).
pub type Fmi3Byte = u8;
/// `fmi3Binary` (const fmi3Byte*).
pub type Fmi3Binary = *const Fmi3Byte;
/// `fmi3Clock` (bool, as a byte).
pub type Fmi3Clock = u8;

/// `fmi3Status`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Fmi3Status {
    /// fmi3OK
    OK = 0,
    /// fmi3Warning
    Warning = 1,
    /// fmi3Discard
    Discard = 2,
    /// fmi3Error
    Error = 3,
    /// fmi3Fatal
    Fatal = 4,
}

impl From<crate::fmi2::model::Status> for Fmi3Status {
    fn from(s: crate::fmi2::model::Status) -> Self {
        use crate::fmi2::model::Status as S;
        match s {
            S::OK => Fmi3Status::OK,
            S::Warning => Fmi3Status::Warning,
            S::Discard => Fmi3Status::Discard,
            S::Error => Fmi3Status::Error,
            S::Fatal => Fmi3Status::Fatal,
        }
    }
}

/// `fmi3LogMessageCallback(instanceEnvironment, status, category, message)` (not variadic:
/// the message is plain text).
pub type Fmi3LogMessageCallback =
    Option<unsafe extern "C" fn(Fmi3InstanceEnvironment, Fmi3Status, Fmi3String, Fmi3String)>;

/// `fmi3IntermediateUpdateCallback(instanceEnvironment, intermediateUpdateTime,
/// intermediateVariableSetRequested, intermediateVariableGetAllowed,
/// intermediateStepFinished, canReturnEarly, *earlyReturnRequested, *earlyReturnTime)`:
/// accepted and never called (providesIntermediateUpdate = false).
pub type Fmi3IntermediateUpdateCallback = Option<
    unsafe extern "C" fn(
        Fmi3InstanceEnvironment,
        Fmi3Float64,
        Fmi3Boolean,
        Fmi3Boolean,
        Fmi3Boolean,
        Fmi3Boolean,
        *mut Fmi3Boolean,
        *mut Fmi3Float64,
    ),
>;

/// `fmi3ClockUpdateCallback(instanceEnvironment)` (Scheduled Execution; never called).
pub type Fmi3ClockUpdateCallback = Option<unsafe extern "C" fn(Fmi3InstanceEnvironment)>;
/// `fmi3LockPreemptionCallback` / `fmi3UnlockPreemptionCallback` (never called).
pub type Fmi3PreemptionCallback = Option<unsafe extern "C" fn()>;
