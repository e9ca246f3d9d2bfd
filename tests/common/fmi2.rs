//! Helpers for the in-process tests of the C ABI: a logger that records messages per
//! instance (through componentEnvironment), a driver for the usual call sequence and call
//! shorthands.

use geared_rotor::c_abi::*;
use geared_rotor::fmi2::types::*;
use geared_rotor::fmi2::variables::{by_name, GUID};
use std::ffi::{c_void, CStr, CString};
use std::sync::Mutex;

/// One recorded log call: (status, category, message, instance name).
pub type Log = Mutex<Vec<(Fmi2Status, String, String, String)>>;

extern "C" fn record(
    env: *mut c_void,
    name: Fmi2String,
    status: Fmi2Status,
    cat: Fmi2String,
    msg: Fmi2String,
) {
    // SAFETY: env is the Box<Log> of the test; strings are NUL-terminated from the FMU.
    let log = unsafe { &*(env as *const Log) };
    let cat = unsafe { CStr::from_ptr(cat) }
        .to_string_lossy()
        .into_owned();
    let msg = unsafe { CStr::from_ptr(msg) }
        .to_string_lossy()
        .into_owned();
    let name = unsafe { CStr::from_ptr(name) }
        .to_string_lossy()
        .into_owned();
    log.lock().unwrap().push((status, cat, msg, name));
}

/// The logger as the variadic C type (on x86_64 SysV a non-variadic callee reads the fixed
/// arguments from the same registers; the FMU never passes varargs).
pub fn logger() -> Fmi2CallbackLogger {
    // SAFETY: see above; both are extern "C" function pointers of the same fixed arguments.
    Some(unsafe {
        std::mem::transmute::<
            extern "C" fn(*mut c_void, Fmi2String, Fmi2Status, Fmi2String, Fmi2String),
            unsafe extern "C" fn(*mut c_void, Fmi2String, Fmi2Status, Fmi2String, Fmi2String, ...),
        >(record)
    })
}

/// An instance with its log.
pub struct Fmu {
    pub c: Fmi2Component,
    pub log: Box<Log>,
    _cb: Box<Fmi2CallbackFunctions>,
}

impl Fmu {
    pub fn new(name: &str, logging_on: bool) -> Fmu {
        let log: Box<Log> = Box::new(Mutex::new(Vec::new()));
        let cb = Box::new(Fmi2CallbackFunctions {
            logger: logger(),
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: &*log as *const Log as *mut c_void,
        });
        let n = CString::new(name).unwrap();
        let g = CString::new(GUID).unwrap();
        let c = unsafe {
            fmi2Instantiate(
                n.as_ptr(),
                1,
                g.as_ptr(),
                std::ptr::null(),
                &*cb,
                0,
                i32::from(logging_on),
            )
        };
        assert!(
            !c.is_null(),
            "instantiate failed: {:?}",
            log.lock().unwrap()
        );
        Fmu { c, log, _cb: cb }
    }

    /// Instantiated -> StepComplete with the default experiment (tolerance from rtol).
    pub fn init(&self) {
        unsafe {
            assert_eq!(
                fmi2SetupExperiment(self.c, 0, 0.0, 0.0, 0, 0.0),
                Fmi2Status::OK
            );
            assert_eq!(fmi2EnterInitializationMode(self.c), Fmi2Status::OK);
            assert_eq!(
                fmi2ExitInitializationMode(self.c),
                Fmi2Status::OK,
                "{:?}",
                self.messages()
            );
        }
    }

    /// (status, category, message) of every log call so far.
    pub fn messages(&self) -> Vec<(Fmi2Status, String, String)> {
        self.log
            .lock()
            .unwrap()
            .iter()
            .map(|m| (m.0, m.1.clone(), m.2.clone()))
            .collect()
    }

    /// The instance name passed with every log call so far.
    pub fn names(&self) -> Vec<String> {
        self.log
            .lock()
            .unwrap()
            .iter()
            .map(|m| m.3.clone())
            .collect()
    }

    pub fn last_message(&self) -> String {
        self.log
            .lock()
            .unwrap()
            .last()
            .map(|m| m.2.clone())
            .unwrap_or_default()
    }

    pub fn clear(&self) {
        self.log.lock().unwrap().clear();
    }

    pub fn real(&self, name: &str) -> f64 {
        let vr = by_name(name).unwrap().vr;
        let mut v = [0.0];
        assert_eq!(
            unsafe { fmi2GetReal(self.c, &vr, 1, v.as_mut_ptr()) },
            Fmi2Status::OK,
            "{}",
            self.last_message()
        );
        v[0]
    }

    pub fn set_real(&self, name: &str, x: f64) -> Fmi2Status {
        let vr = by_name(name).unwrap().vr;
        unsafe { fmi2SetReal(self.c, &vr, 1, &x) }
    }

    pub fn step(&self, t: f64, h: f64) -> Fmi2Status {
        unsafe { fmi2DoStep(self.c, t, h, 1) }
    }

    /// All Real outputs, by value reference order of the table.
    pub fn all_real_outputs(&self) -> Vec<f64> {
        use geared_rotor::fmi2::variables::{Causality, VarType, VARIABLES};
        let vrs: Vec<u32> = VARIABLES
            .iter()
            .filter(|v| v.ty == VarType::Real && v.causality == Causality::Output)
            .map(|v| v.vr)
            .collect();
        let mut out = vec![0.0; vrs.len()];
        assert_eq!(
            unsafe { fmi2GetReal(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) },
            Fmi2Status::OK
        );
        out
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        unsafe { fmi2FreeInstance(self.c) };
    }
}

/// fmi2SetDebugLogging(c, loggingOn, 1 category): switch on logging of `category` only.
pub fn log_category(c: Fmi2Component, category: &str) -> Fmi2Status {
    let cat = CString::new(category).unwrap();
    let p = cat.as_ptr();
    // SAFETY: c comes from fmi2Instantiate; p points to one NUL-terminated string that
    // outlives the call.
    unsafe { fmi2SetDebugLogging(c, 1, 1, &p) }
}
