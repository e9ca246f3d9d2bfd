//! The FMI 3.0 C ABI in process (`geared_rotor::c_abi3`): every FMI 3.0 function exported
//! by the shared library, the call sequence of a master, null pointers and a caught panic,
//! instances of the other FMI version refused, FMU-state round trips bit-identical, the
//! blob of the other version refused, the value types, and early return against the
//! discard instant.

use geared_rotor::c_abi as c2;
use geared_rotor::c_abi3::*;
use geared_rotor::fmi2::types::Fmi2Status;
use geared_rotor::fmi2::variables::{by_name, GUID, VARIABLES};
use geared_rotor::fmi2::variables::{Causality, VarType};
use geared_rotor::fmi3::types::*;
use geared_rotor::fmi3::TIME_VR;
use std::ffi::{c_void, CStr, CString};
use std::sync::Mutex;

type Log = Mutex<Vec<(Fmi3Status, String, String)>>;

extern "C" fn record(env: *mut c_void, status: Fmi3Status, cat: Fmi3String, msg: Fmi3String) {
    // SAFETY: env is the Box<Log> of the test; strings are NUL-terminated from the FMU.
    let log = unsafe { &*(env as *const Log) };
    let cat = unsafe { CStr::from_ptr(cat) }
        .to_string_lossy()
        .into_owned();
    let msg = unsafe { CStr::from_ptr(msg) }
        .to_string_lossy()
        .into_owned();
    log.lock().unwrap().push((status, cat, msg));
}

struct Fmu {
    c: Fmi3Instance,
    log: Box<Log>,
}

impl Fmu {
    fn new(early: bool) -> Fmu {
        let log: Box<Log> = Box::new(Mutex::new(Vec::new()));
        let n = CString::new("fmi3").unwrap();
        let g = CString::new(GUID).unwrap();
        // SAFETY: valid strings; the log outlives the instance (dropped after it).
        let c = unsafe {
            fmi3InstantiateCoSimulation(
                n.as_ptr(),
                g.as_ptr(),
                std::ptr::null(),
                0,
                0,
                0,
                u8::from(early),
                std::ptr::null(),
                0,
                (&*log as *const Log).cast_mut().cast(),
                Some(record),
                None,
            )
        };
        assert!(!c.is_null());
        Fmu { c, log }
    }
    fn init(&self, params: &[(&str, f64)]) {
        for &(name, x) in params {
            self.set(name, x);
        }
        // SAFETY: valid instance.
        unsafe {
            assert_eq!(
                fmi3EnterInitializationMode(self.c, 1, 1e-9, 0.0, 0, 0.0),
                Fmi3Status::OK
            );
            assert_eq!(fmi3ExitInitializationMode(self.c), Fmi3Status::OK);
        }
    }
    fn set(&self, name: &str, x: f64) -> Fmi3Status {
        let v = by_name(name).unwrap();
        // SAFETY: one reference and value.
        unsafe {
            match (v.ty, v.items.is_empty()) {
                (VarType::Real, _) => fmi3SetFloat64(self.c, &v.vr, 1, &x, 1),
                (VarType::Integer, true) => fmi3SetInt32(self.c, &v.vr, 1, &(x as i32), 1),
                (VarType::Integer, false) => fmi3SetInt64(self.c, &v.vr, 1, &(x as i64), 1),
                (VarType::Boolean, _) => fmi3SetBoolean(self.c, &v.vr, 1, &u8::from(x != 0.0), 1),
            }
        }
    }
    fn get(&self, name: &str) -> f64 {
        let vr = if name == "time" {
            TIME_VR
        } else {
            by_name(name).unwrap().vr
        };
        let mut x = f64::NAN;
        // SAFETY: one reference and output.
        assert_eq!(
            unsafe { fmi3GetFloat64(self.c, &vr, 1, &mut x, 1) },
            Fmi3Status::OK
        );
        x
    }
    fn outputs(&self) -> Vec<f64> {
        let vrs: Vec<u32> = VARIABLES
            .iter()
            .filter(|v| v.ty == VarType::Real && v.causality == Causality::Output)
            .map(|v| v.vr)
            .collect();
        let mut y = vec![0.0; vrs.len()];
        // SAFETY: as many references as outputs.
        let s = unsafe { fmi3GetFloat64(self.c, vrs.as_ptr(), vrs.len(), y.as_mut_ptr(), y.len()) };
        assert_eq!(s, Fmi3Status::OK);
        y
    }
    /// (status, earlyReturn, lastSuccessfulTime)
    fn step(&self, t: f64, h: f64) -> (Fmi3Status, bool, f64) {
        let (mut ev, mut term, mut early, mut last) = (9u8, 9u8, 9u8, f64::NAN);
        // SAFETY: valid instance and out-pointers.
        let s = unsafe { fmi3DoStep(self.c, t, h, 1, &mut ev, &mut term, &mut early, &mut last) };
        assert_eq!((ev, term), (0, 0));
        (s, early == 1, last)
    }
    fn messages(&self) -> String {
        let log = self.log.lock().unwrap();
        log.iter()
            .map(|(_, _, m)| m.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: own instance.
        unsafe { fmi3FreeInstance(self.c) };
    }
}

const FUNCTIONS: &[&str] = &[
    "fmi3GetVersion",
    "fmi3SetDebugLogging",
    "fmi3InstantiateModelExchange",
    "fmi3InstantiateCoSimulation",
    "fmi3InstantiateScheduledExecution",
    "fmi3FreeInstance",
    "fmi3EnterInitializationMode",
    "fmi3ExitInitializationMode",
    "fmi3EnterEventMode",
    "fmi3Terminate",
    "fmi3Reset",
    "fmi3GetFloat32",
    "fmi3GetFloat64",
    "fmi3GetInt8",
    "fmi3GetUInt8",
    "fmi3GetInt16",
    "fmi3GetUInt16",
    "fmi3GetInt32",
    "fmi3GetUInt32",
    "fmi3GetInt64",
    "fmi3GetUInt64",
    "fmi3GetBoolean",
    "fmi3GetString",
    "fmi3GetBinary",
    "fmi3GetClock",
    "fmi3SetFloat32",
    "fmi3SetFloat64",
    "fmi3SetInt8",
    "fmi3SetUInt8",
    "fmi3SetInt16",
    "fmi3SetUInt16",
    "fmi3SetInt32",
    "fmi3SetUInt32",
    "fmi3SetInt64",
    "fmi3SetUInt64",
    "fmi3SetBoolean",
    "fmi3SetString",
    "fmi3SetBinary",
    "fmi3SetClock",
    "fmi3GetNumberOfVariableDependencies",
    "fmi3GetVariableDependencies",
    "fmi3GetFMUState",
    "fmi3SetFMUState",
    "fmi3FreeFMUState",
    "fmi3SerializedFMUStateSize",
    "fmi3SerializeFMUState",
    "fmi3DeserializeFMUState",
    "fmi3GetDirectionalDerivative",
    "fmi3GetAdjointDerivative",
    "fmi3EnterConfigurationMode",
    "fmi3ExitConfigurationMode",
    "fmi3GetIntervalDecimal",
    "fmi3GetIntervalFraction",
    "fmi3GetShiftDecimal",
    "fmi3GetShiftFraction",
    "fmi3SetIntervalDecimal",
    "fmi3SetIntervalFraction",
    "fmi3SetShiftDecimal",
    "fmi3SetShiftFraction",
    "fmi3EvaluateDiscreteStates",
    "fmi3UpdateDiscreteStates",
    "fmi3EnterContinuousTimeMode",
    "fmi3CompletedIntegratorStep",
    "fmi3SetTime",
    "fmi3SetContinuousStates",
    "fmi3GetContinuousStateDerivatives",
    "fmi3GetEventIndicators",
    "fmi3GetContinuousStates",
    "fmi3GetNominalsOfContinuousStates",
    "fmi3GetNumberOfEventIndicators",
    "fmi3GetNumberOfContinuousStates",
    "fmi3EnterStepMode",
    "fmi3GetOutputDerivatives",
    "fmi3DoStep",
    "fmi3ActivateModelPartition",
];

#[test]
fn the_cdylib_exports_every_fmi3_function_beside_the_fmi2_ones() {
    let exe = std::env::current_exe().unwrap();
    let so = exe
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .join("libgeared_rotor.so");
    let target_dir = so.parent().unwrap().parent().unwrap();
    let release = so.parent().unwrap().file_name().unwrap() == "release";
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut cmd = std::process::Command::new(cargo);
    cmd.args(["build", "--lib", "--manifest-path"])
        .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml"))
        .env("CARGO_TARGET_DIR", target_dir);
    if release {
        cmd.arg("--release");
    }
    assert!(cmd.status().expect("cargo build --lib").success());
    let path = CString::new(so.to_str().unwrap()).unwrap();
    // SAFETY: dlopen of the crate's own library; symbols only looked up, one called.
    unsafe {
        let h = libc::dlopen(path.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL);
        assert!(!h.is_null(), "dlopen {}", so.display());
        let missing: Vec<&str> = FUNCTIONS
            .iter()
            .copied()
            .filter(|n| libc::dlsym(h, CString::new(*n).unwrap().as_ptr()).is_null())
            .collect();
        assert!(missing.is_empty(), "missing exports: {missing:?}");
        let both = ["fmi2DoStep", "fmi3DoStep"];
        assert!(both
            .iter()
            .all(|n| !libc::dlsym(h, CString::new(*n).unwrap().as_ptr()).is_null()));
        let f: extern "C" fn() -> *const std::ffi::c_char =
            std::mem::transmute(libc::dlsym(h, c"fmi3GetVersion".as_ptr()));
        assert_eq!(CStr::from_ptr(f()).to_str().unwrap(), "3.0");
        libc::dlclose(h);
    }
}

#[test]
fn bad_calls_get_errors_with_messages_and_panics_are_caught() {
    let f = Fmu::new(false);
    // doStep before initialisation; then NULL out-arguments
    assert_eq!(f.step(0.0, 1e-3).0, Fmi3Status::Error);
    assert!(
        f.messages().contains("fmi3DoStep: illegal call sequence"),
        "{}",
        f.messages()
    );
    let f = Fmu::new(false);
    f.init(&[]);
    let (mut a, mut b, mut d) = (0u8, 0u8, 0.0);
    // SAFETY: a NULL earlyReturn pointer on purpose.
    let s = unsafe {
        fmi3DoStep(
            f.c,
            0.0,
            1e-3,
            1,
            &mut a,
            &mut b,
            std::ptr::null_mut(),
            &mut d,
        )
    };
    assert_eq!(s, Fmi3Status::Error);
    assert!(
        f.messages()
            .contains("argument earlyReturn is a NULL pointer"),
        "{}",
        f.messages()
    );
    // nValues that does not match, an Enumeration read as Int32, Float32 of anything
    let f = Fmu::new(false);
    f.init(&[]);
    let vr = by_name("T1").unwrap().vr;
    let mut y = [0.0; 2];
    // SAFETY: 2 outputs, nValues 2 for one reference on purpose.
    assert_eq!(
        unsafe { fmi3GetFloat64(f.c, &vr, 1, y.as_mut_ptr(), 2) },
        Fmi3Status::Error
    );
    assert!(f
        .messages()
        .contains("nValues = 2 differs from nValueReferences = 1"));
    let f = Fmu::new(false);
    f.init(&[]);
    let vr = by_name("on_lift_off").unwrap().vr;
    let mut i = 0i32;
    // SAFETY: one reference and output.
    assert_eq!(
        unsafe { fmi3GetInt32(f.c, &vr, 1, &mut i, 1) },
        Fmi3Status::Error
    );
    assert!(f
        .messages()
        .contains("on_lift_off (value reference 1011) is an Enumeration: use fmi3GetInt64"));
    let f = Fmu::new(false);
    f.init(&[]);
    let mut x = 0f32;
    // SAFETY: one reference and output.
    assert_eq!(
        unsafe { fmi3GetFloat32(f.c, &1, 1, &mut x, 1) },
        Fmi3Status::Error
    );
    // an out-of-bounds input names the variable and the bound, nothing changes
    let f = Fmu::new(false);
    f.init(&[]);
    assert_eq!(f.set("T_load", 2e6), Fmi3Status::Error);
    assert!(
        f.messages()
            .contains("T_load = 2000000 is above its declared max 1000000"),
        "{}",
        f.messages()
    );
    // a panic inside becomes fmi3Fatal, and only FreeInstance is left
    let f = Fmu::new(false);
    f.init(&[]);
    // SAFETY: a live instance.
    unsafe { test_hook_panic_next_call3(f.c) };
    assert_eq!(f.step(0.0, 1e-3).0, Fmi3Status::Fatal);
    assert_eq!(f.step(0.0, 1e-3).0, Fmi3Status::Fatal);
    assert!(
        f.messages().contains("only fmi3FreeInstance is allowed"),
        "{}",
        f.messages()
    );
}

#[test]
fn instances_of_the_other_version_are_refused() {
    let f3 = Fmu::new(false);
    let n = CString::new("fmi2").unwrap();
    let g = CString::new(GUID).unwrap();
    let cb = geared_rotor::fmi2::types::Fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    };
    // SAFETY: valid arguments; each version's functions get the other's instance on
    // purpose and must refuse it by its magic.
    unsafe {
        let c2i = c2::fmi2Instantiate(n.as_ptr(), 1, g.as_ptr(), std::ptr::null(), &cb, 0, 0);
        assert!(!c2i.is_null());
        assert_eq!(fmi3ExitInitializationMode(c2i), Fmi3Status::Error);
        fmi3FreeInstance(c2i); // ignored: not an FMI 3.0 instance
        assert_eq!(c2::fmi2ExitInitializationMode(f3.c), Fmi2Status::Error);
        c2::fmi2FreeInstance(f3.c); // ignored
        assert_eq!(
            c2::fmi2SetupExperiment(c2i, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::OK
        );
        c2::fmi2FreeInstance(c2i);
    }
    f3.init(&[]);
    assert_eq!(f3.step(0.0, 1e-4).0, Fmi3Status::OK);
}

#[test]
fn state_round_trips_are_bit_identical() {
    let f = Fmu::new(false);
    f.init(&[]);
    let h = 1e-4;
    for k in 0..50 {
        assert_eq!(f.step(f64::from(k) * h, h).0, Fmi3Status::OK);
    }
    let t1 = 50.0 * h;
    let mut st: Fmi3FMUState = std::ptr::null_mut();
    let mut size = 0usize;
    // SAFETY: own instance and state; buffer of the reported size.
    let blob = unsafe {
        assert_eq!(fmi3GetFMUState(f.c, &mut st), Fmi3Status::OK);
        assert_eq!(
            fmi3SerializedFMUStateSize(f.c, st, &mut size),
            Fmi3Status::OK
        );
        let mut buf = vec![0u8; size];
        assert_eq!(
            fmi3SerializeFMUState(f.c, st, buf.as_mut_ptr(), size),
            Fmi3Status::OK
        );
        buf
    };
    let run = |f: &Fmu| {
        let mut rows = Vec::new();
        let mut t = t1;
        for _ in 0..30 {
            assert_eq!(f.step(t, h).0, Fmi3Status::OK);
            t += h;
            rows.push(
                f.outputs()
                    .iter()
                    .map(|x| x.to_bits())
                    .collect::<Vec<u64>>(),
            );
        }
        rows
    };
    let first = run(&f);
    // SAFETY: own state.
    assert_eq!(unsafe { fmi3SetFMUState(f.c, st) }, Fmi3Status::OK);
    assert_eq!(run(&f), first, "get/set");
    let g = Fmu::new(false);
    let mut back: Fmi3FMUState = std::ptr::null_mut();
    // SAFETY: a buffer of blob.len() bytes; a fresh instance.
    unsafe {
        assert_eq!(
            fmi3DeserializeFMUState(g.c, blob.as_ptr(), blob.len(), &mut back),
            Fmi3Status::OK
        );
        assert_eq!(fmi3SetFMUState(g.c, back), Fmi3Status::OK);
    }
    assert_eq!(g.get("time"), t1);
    assert_eq!(run(&g), first, "serialize/deserialize in another instance");
    // The same state through the FMI 2.0 functions is refused, saying why.
    let log2: Box<Mutex<Vec<String>>> = Box::new(Mutex::new(Vec::new()));
    extern "C" fn rec2(
        env: *mut c_void,
        _: *const std::ffi::c_char,
        _: Fmi2Status,
        _: *const std::ffi::c_char,
        m: *const std::ffi::c_char,
    ) {
        // SAFETY: env is the test's Box; m NUL-terminated.
        let l = unsafe { &*(env as *const Mutex<Vec<String>>) };
        l.lock()
            .unwrap()
            .push(unsafe { CStr::from_ptr(m) }.to_string_lossy().into_owned());
    }
    let cb = geared_rotor::fmi2::types::Fmi2CallbackFunctions {
        // SAFETY: non-variadic callee with the same fixed arguments (the FMU passes no varargs).
        logger: Some(unsafe {
            std::mem::transmute::<
                extern "C" fn(
                    *mut c_void,
                    *const std::ffi::c_char,
                    Fmi2Status,
                    *const std::ffi::c_char,
                    *const std::ffi::c_char,
                ),
                unsafe extern "C" fn(
                    *mut c_void,
                    *const std::ffi::c_char,
                    Fmi2Status,
                    *const std::ffi::c_char,
                    *const std::ffi::c_char,
                    ...
                ),
            >(rec2)
        }),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: (&*log2 as *const Mutex<Vec<String>>).cast_mut().cast(),
    };
    let n = CString::new("fmi2").unwrap();
    let gd = CString::new(GUID).unwrap();
    // SAFETY: valid arguments; the blob is handed to the FMI 2.0 functions on purpose.
    unsafe {
        let c = c2::fmi2Instantiate(n.as_ptr(), 1, gd.as_ptr(), std::ptr::null(), &cb, 0, 0);
        let mut s2: geared_rotor::fmi2::types::Fmi2FMUstate = std::ptr::null_mut();
        let s = c2::fmi2DeSerializeFMUstate(c, blob.as_ptr().cast(), blob.len(), &mut s2);
        assert_eq!(s, Fmi2Status::Error);
        c2::fmi2FreeInstance(c);
    }
    let msgs = log2.lock().unwrap().join("\n");
    assert!(
        msgs.contains("fmi2DeSerializeFMUstate: invalid serialized FMU state: this is a state of the FMI 3.0 FMU (GearedRotor-fmi3.fmu); the FMI 2.0 FMU (GearedRotor.fmu) reads only its own states"),
        "{msgs}"
    );
    // SAFETY: own states.
    unsafe {
        fmi3FreeFMUState(f.c, &mut st);
        fmi3FreeFMUState(g.c, &mut back);
    }
}

/// From the static equilibrium, 2 ms at zero load, then a coasting load of -200 N m: the
/// contact force falls through zero inside a later step of 1 ms.
fn to_lift_off(f: &Fmu) -> (Fmi3Status, bool, f64, f64) {
    let h = 1e-3;
    let mut t = 0.0;
    for _ in 0..2 {
        assert_eq!(f.step(t, h).0, Fmi3Status::OK);
        t += h;
    }
    assert_eq!(f.set("T_load", -200.0), Fmi3Status::OK);
    for _ in 0..20 {
        let (s, early, last) = f.step(t, h);
        if s != Fmi3Status::OK || early {
            return (s, early, last, t);
        }
        t += h;
    }
    panic!("no lift-off");
}

#[test]
fn early_return_stops_at_the_discard_instant_and_goes_on() {
    // the instant where on_lift_off = discard stops
    let d = Fmu::new(false);
    d.init(&[("initialization", 2.0), ("on_lift_off", 2.0)]);
    let (s, early, t_discard, t0) = to_lift_off(&d);
    assert_eq!((s, early), (Fmi3Status::Discard, false));
    assert!(t0 < t_discard && t_discard < t0 + 1e-3);
    // early return: the same instant, Warning, and the master goes on from it
    let e = Fmu::new(true);
    e.init(&[("initialization", 2.0)]);
    let (s, early, t_early, _) = to_lift_off(&e);
    assert_eq!((s, early), (Fmi3Status::Warning, true));
    assert_eq!(
        t_early, t_discard,
        "early return and discard stop at the same instant"
    );
    assert_eq!(e.get("time"), t_early);
    assert!(
        e.get("Fn").abs() < 1.0,
        "Fn = {} at the instant",
        e.get("Fn")
    );
    assert!(
        e.messages().contains("returning early at t = "),
        "{}",
        e.messages()
    );
    let (s, early, end) = e.step(t_early, 1e-3);
    assert_eq!((s, early, end), (Fmi3Status::OK, false, t_early + 1e-3));
    // without earlyReturnAllowed: the step completes with a warning (as FMI 2.0)
    let w = Fmu::new(false);
    w.init(&[("initialization", 2.0)]);
    let (s, early, end, t0) = to_lift_off(&w);
    assert_eq!((s, early, end), (Fmi3Status::Warning, false, t0 + 1e-3));
    // a lift-off at the start of a step (at once after the input change) is no early
    // return: reported, and the step completes
    let z = Fmu::new(true);
    z.init(&[]);
    assert_eq!(z.set("T_load", -1000.0), Fmi3Status::OK);
    let (s, early, end) = z.step(0.0, 1e-4);
    assert_eq!((s, early, end), (Fmi3Status::Warning, false, 1e-4));
    assert!(
        z.messages().contains("lift-off at t = 0.0"),
        "{}",
        z.messages()
    );
}

/// The same run through both versions' functions: outputs, output derivatives, the Integer
/// and Boolean outputs and the Enumeration parameters equal to the bit.
#[test]
fn both_versions_give_the_same_values() {
    let f3 = Fmu::new(false);
    f3.init(&[("mu", 0.07)]);
    let n = CString::new("fmi2").unwrap();
    let g = CString::new(GUID).unwrap();
    let cb = geared_rotor::fmi2::types::Fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    };
    let h = 2e-4;
    let reals: Vec<u32> = VARIABLES
        .iter()
        .filter(|v| v.ty == VarType::Real && v.causality == Causality::Output)
        .map(|v| v.vr)
        .collect();
    let (vr_pairs, vr_lost, vr_init) = (
        by_name("pairs_in_contact").unwrap().vr,
        by_name("contact_lost").unwrap().vr,
        by_name("initialization").unwrap().vr,
    );
    let ones = vec![1i32; reals.len()];
    // SAFETY: valid arguments and buffers of the right lengths; both instances freed.
    unsafe {
        let c = c2::fmi2Instantiate(n.as_ptr(), 1, g.as_ptr(), std::ptr::null(), &cb, 0, 0);
        let mu = 0.07;
        let vr_mu = by_name("mu").unwrap().vr;
        c2::fmi2SetReal(c, &vr_mu, 1, &mu);
        c2::fmi2SetupExperiment(c, 1, 1e-9, 0.0, 0, 0.0);
        c2::fmi2EnterInitializationMode(c);
        c2::fmi2ExitInitializationMode(c);
        for k in 0..40 {
            let t = f64::from(k) * h;
            assert_eq!(c2::fmi2DoStep(c, t, h, 1), Fmi2Status::OK);
            assert_eq!(f3.step(t, h).0, Fmi3Status::OK);
            let (mut y2, mut d2) = (vec![0.0; reals.len()], vec![0.0; reals.len()]);
            c2::fmi2GetReal(c, reals.as_ptr(), reals.len(), y2.as_mut_ptr());
            c2::fmi2GetRealOutputDerivatives(
                c,
                reals.as_ptr(),
                reals.len(),
                ones.as_ptr(),
                d2.as_mut_ptr(),
            );
            let mut d3 = vec![0.0; reals.len()];
            let s = fmi3GetOutputDerivatives(
                f3.c,
                reals.as_ptr(),
                reals.len(),
                ones.as_ptr(),
                d3.as_mut_ptr(),
                d3.len(),
            );
            assert_eq!(s, Fmi3Status::OK);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&f3.outputs()), bits(&y2), "outputs at step {k}");
            assert_eq!(bits(&d3), bits(&d2), "output derivatives at step {k}");
            let (mut p2, mut l2, mut e2) = (0i32, 0i32, 0i32);
            c2::fmi2GetInteger(c, &vr_pairs, 1, &mut p2);
            c2::fmi2GetBoolean(c, &vr_lost, 1, &mut l2);
            c2::fmi2GetInteger(c, &vr_init, 1, &mut e2);
            let (mut p3, mut l3, mut e3) = (0i32, 7u8, 0i64);
            assert_eq!(fmi3GetInt32(f3.c, &vr_pairs, 1, &mut p3, 1), Fmi3Status::OK);
            assert_eq!(
                fmi3GetBoolean(f3.c, &vr_lost, 1, &mut l3, 1),
                Fmi3Status::OK
            );
            assert_eq!(fmi3GetInt64(f3.c, &vr_init, 1, &mut e3, 1), Fmi3Status::OK);
            assert_eq!((p3, i32::from(l3), e3), (p2, l2, i64::from(e2)));
        }
        c2::fmi2FreeInstance(c);
    }
}

/// The FMU declares hasEventMode = false: an instantiation with eventModeUsed = true is
/// refused with a message (a master would otherwise be stopped at fmi3EnterStepMode), and
/// the standard log categories logStatusDiscard and logStatusFatal are known (a generic
/// master enables them; an unknown category is an error).
#[test]
fn event_mode_is_refused_and_the_standard_log_categories_are_known() {
    let log: Box<Log> = Box::new(Mutex::new(Vec::new()));
    let n = CString::new("fmi3ev").unwrap();
    let g = CString::new(GUID).unwrap();
    // SAFETY: valid strings; the log outlives the call.
    let c = unsafe {
        fmi3InstantiateCoSimulation(
            n.as_ptr(),
            g.as_ptr(),
            std::ptr::null(),
            0,
            0,
            1,
            0,
            std::ptr::null(),
            0,
            (&*log as *const Log).cast_mut().cast(),
            Some(record),
            None,
        )
    };
    assert!(c.is_null());
    let msgs = log.lock().unwrap();
    assert!(
        msgs.iter()
            .any(|m| m.2.contains("eventModeUsed") && m.2.contains("hasEventMode = false")),
        "{msgs:?}"
    );
    drop(msgs);
    let f = Fmu::new(false);
    let cats = [
        CString::new("logStatusDiscard").unwrap(),
        CString::new("logStatusFatal").unwrap(),
    ];
    let ptrs: Vec<Fmi3String> = cats.iter().map(|c| c.as_ptr()).collect();
    // SAFETY: a live instance, two valid strings.
    let s = unsafe { fmi3SetDebugLogging(f.c, 1, 2, ptrs.as_ptr()) };
    assert_eq!(s, Fmi3Status::OK, "{}", f.messages());
    f.init(&[]);
}
