//! The shared library exports every FMI 2.0 function (common, co-simulation and the
//! model-exchange ones as stubs) under its standard name: masters refuse a library that
//! lacks any. Loads the cdylib built next to this test with dlopen and looks each name up.

use std::ffi::CString;

const NAMES: &[&str] = &[
    // common
    "fmi2GetTypesPlatform",
    "fmi2GetVersion",
    "fmi2SetDebugLogging",
    "fmi2Instantiate",
    "fmi2FreeInstance",
    "fmi2SetupExperiment",
    "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode",
    "fmi2Terminate",
    "fmi2Reset",
    "fmi2GetReal",
    "fmi2GetInteger",
    "fmi2GetBoolean",
    "fmi2GetString",
    "fmi2SetReal",
    "fmi2SetInteger",
    "fmi2SetBoolean",
    "fmi2SetString",
    "fmi2GetFMUstate",
    "fmi2SetFMUstate",
    "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize",
    "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative",
    // co-simulation
    "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives",
    "fmi2DoStep",
    "fmi2CancelStep",
    "fmi2GetStatus",
    "fmi2GetRealStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
    // model exchange (stubs)
    "fmi2EnterEventMode",
    "fmi2NewDiscreteStates",
    "fmi2EnterContinuousTimeMode",
    "fmi2CompletedIntegratorStep",
    "fmi2SetTime",
    "fmi2SetContinuousStates",
    "fmi2GetDerivatives",
    "fmi2GetEventIndicators",
    "fmi2GetContinuousStates",
    "fmi2GetNominalsOfContinuousStates",
];

#[test]
fn the_cdylib_exports_every_fmi2_function() {
    let exe = std::env::current_exe().unwrap();
    // target/<profile>/deps/<test> -> target/<profile>/libgeared_rotor.so
    let so = exe
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .join("libgeared_rotor.so");
    assert!(so.exists(), "{} not built", so.display());
    let path = CString::new(so.to_str().unwrap()).unwrap();
    unsafe {
        let h = libc::dlopen(path.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL);
        assert!(!h.is_null(), "dlopen {}", so.display());
        let mut missing = Vec::new();
        for n in NAMES {
            let c = CString::new(*n).unwrap();
            if libc::dlsym(h, c.as_ptr()).is_null() {
                missing.push(*n);
            }
        }
        assert!(missing.is_empty(), "missing exports: {missing:?}");
        // Call through the loaded library: the version string.
        let c = CString::new("fmi2GetVersion").unwrap();
        let f: extern "C" fn() -> *const std::ffi::c_char =
            std::mem::transmute(libc::dlsym(h, c.as_ptr()));
        assert_eq!(std::ffi::CStr::from_ptr(f()).to_str().unwrap(), "2.0");
        libc::dlclose(h);
    }
}
