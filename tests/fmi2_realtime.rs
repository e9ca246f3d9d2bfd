//! The real-time mode through the C ABI: the parameter `h_fixed` (value reference 130),
//! rollback and serialisation bit-identical in both modes with inputs changing at every
//! point, the mode carried by the FMU state, non-convergence as fmi2Discard.

mod common;

use common::fmi2::Fmu;
use geared_rotor::c_abi::*;
use geared_rotor::fmi2::types::*;
use geared_rotor::fmi2::variables::by_name;
use std::f64::consts::PI;
use std::ptr;

const H: f64 = 1e-4;

fn instance(name: &str, h_fixed: f64) -> Fmu {
    let f = Fmu::new(name, false);
    unsafe {
        assert_eq!(
            fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::OK
        );
        assert_eq!(fmi2EnterInitializationMode(f.c), Fmi2Status::OK);
    }
    assert_eq!(f.set_real("h_fixed", h_fixed), Fmi2Status::OK);
    assert_eq!(
        unsafe { fmi2ExitInitializationMode(f.c) },
        Fmi2Status::OK,
        "{}",
        f.last_message()
    );
    f
}

/// n doSteps of h from point k0 with omega1 and T_load set at every point (omega1 with
/// its derivative); the Real outputs after each.
fn run_h(f: &Fmu, h: f64, k0: usize, n: usize) -> Vec<Vec<f64>> {
    let vr = by_name("omega1").unwrap().vr;
    (k0..k0 + n)
        .map(|k| {
            let t = k as f64 * h;
            let a = 2.0 * PI * 50.0;
            assert_eq!(
                f.set_real("omega1", 314.159 * (1.0 + 0.01 * (a * t).sin())),
                Fmi2Status::OK
            );
            let der = 314.159 * 0.01 * a * (a * t).cos();
            assert_eq!(
                unsafe { fmi2SetRealInputDerivatives(f.c, &vr, 1, &1, &der) },
                Fmi2Status::OK
            );
            assert_eq!(f.set_real("T_load", (a * t).sin()), Fmi2Status::OK);
            assert_eq!(f.step(t, h), Fmi2Status::OK, "{}", f.last_message());
            f.all_real_outputs()
        })
        .collect()
}

fn bits(v: &[Vec<f64>]) -> Vec<u64> {
    v.iter().flatten().map(|x| x.to_bits()).collect()
}

/// In both modes: a rollback with fmi2GetFMUstate/fmi2SetFMUstate and a serialised state
/// loaded into a fresh instance (whose own h_fixed is the default 0) continue
/// bit-identically; the real-time run differs from the adaptive one (the mode is in the
/// state, not taken from the fresh instance). Also at H = 1e-5 s, where the real-time mode
/// renews J and the LU pair on every 10th doStep only: the state is taken after doStep
/// 103, between two renewals, so the continuation runs on the LU pair of the state, and
/// the continuations are 57 doSteps long, so that a schedule kept anywhere but in the
/// time grid would be out of phase after the rollback.
#[test]
fn rollback_and_serialisation_are_bit_identical_in_both_modes() {
    let mut continuations = Vec::new();
    for (h_fixed, h, k0, n) in [
        (0.0, H, 100, 100),
        (2.5e-5, H, 100, 100),
        (1e-5, 1e-5, 103, 57),
    ] {
        let f = instance("mode", h_fixed);
        run_h(&f, h, 0, k0);
        let mut st: Fmi2FMUstate = ptr::null_mut();
        assert_eq!(unsafe { fmi2GetFMUstate(f.c, &mut st) }, Fmi2Status::OK);
        let a = run_h(&f, h, k0, n);
        assert_eq!(unsafe { fmi2SetFMUstate(f.c, st) }, Fmi2Status::OK);
        let b = run_h(&f, h, k0, n);
        assert_eq!(bits(&a), bits(&b), "rollback, h_fixed = {h_fixed}");
        let mut size = 0usize;
        assert_eq!(
            unsafe { fmi2SerializedFMUstateSize(f.c, st, &mut size) },
            Fmi2Status::OK
        );
        let mut buf = vec![0 as Fmi2Byte; size];
        assert_eq!(
            unsafe { fmi2SerializeFMUstate(f.c, st, buf.as_mut_ptr(), size) },
            Fmi2Status::OK
        );
        let g = Fmu::new("fresh", false);
        let mut st2: Fmi2FMUstate = ptr::null_mut();
        assert_eq!(
            unsafe { fmi2DeSerializeFMUstate(g.c, buf.as_ptr(), size, &mut st2) },
            Fmi2Status::OK,
            "{}",
            g.last_message()
        );
        assert_eq!(unsafe { fmi2SetFMUstate(g.c, st2) }, Fmi2Status::OK);
        assert_eq!(g.real("h_fixed"), h_fixed);
        let c = run_h(&g, h, k0, n);
        assert_eq!(bits(&a), bits(&c), "serialised, h_fixed = {h_fixed}");
        unsafe {
            fmi2FreeFMUstate(f.c, &mut st);
            fmi2FreeFMUstate(g.c, &mut st2);
        }
        continuations.push(a);
    }
    assert_ne!(bits(&continuations[0]), bits(&continuations[1]));
}

/// A fixed step that does not converge within the Newton count is fmi2Discard with a
/// message naming h_fixed; the last successful time is the start of the doStep. h_fixed
/// is a fixed parameter (not settable after initialisation) and a negative value is
/// refused at initialisation with its name.
#[test]
fn non_convergence_is_discard_and_h_fixed_is_checked() {
    let f = instance("coarse", 1e-3);
    assert_eq!(f.step(0.0, 1e-3), Fmi2Status::Discard);
    let msg = f.last_message();
    assert!(
        msg.contains("h_fixed") && msg.contains("not converged"),
        "{msg}"
    );
    let mut t = f64::NAN;
    assert_eq!(
        unsafe { fmi2GetRealStatus(f.c, status_kind::LAST_SUCCESSFUL_TIME, &mut t) },
        Fmi2Status::OK
    );
    assert_eq!(t, 0.0);

    let g = instance("fixed", 2.5e-5);
    assert_eq!(g.set_real("h_fixed", 1e-5), Fmi2Status::Error);

    let b = Fmu::new("negative", false);
    unsafe {
        assert_eq!(
            fmi2SetupExperiment(b.c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::OK
        );
        assert_eq!(fmi2EnterInitializationMode(b.c), Fmi2Status::OK);
    }
    assert_eq!(b.set_real("h_fixed", -1e-5), Fmi2Status::OK);
    assert_eq!(
        unsafe { fmi2ExitInitializationMode(b.c) },
        Fmi2Status::Error
    );
    assert!(b.last_message().contains("h_fixed"), "{}", b.last_message());
}

/// What the FMU promises in the adaptive mode holds in the real-time mode too: output
/// derivatives (from the last fixed step's collocation polynomial) satisfy the model's
/// independent relations E_in' = P_in, E_loss' = P_loss, phi2' = omega2; T_load acts on
/// the lambda-following outputs at once (direct feedthrough: Fn changes before any
/// doStep) and leaves omega2 alone; a run with H = 1e-4 s and one with H = 5e-5 s take
/// the same internal steps (h_fixed = 2.5e-5 s) and agree to 1e-6 relative at 20 ms (the
/// Jacobians differ: renewed per doStep).
#[test]
fn derivatives_feedthrough_and_step_independence_hold_in_the_real_time_mode() {
    let f = instance("rt_der", 2.5e-5);
    for k in 0..100 {
        assert_eq!(f.step(k as f64 * H, H), Fmi2Status::OK);
    }
    let names = ["E_in", "E_loss", "phi2"];
    let vrs: Vec<u32> = names.iter().map(|n| by_name(n).unwrap().vr).collect();
    let mut d = [0.0; 3];
    assert_eq!(
        unsafe {
            fmi2GetRealOutputDerivatives(f.c, vrs.as_ptr(), 3, [1, 1, 1].as_ptr(), d.as_mut_ptr())
        },
        Fmi2Status::OK
    );
    let expect = [f.real("P_in"), f.real("P_loss"), f.real("omega2")];
    for i in 0..3 {
        assert!(
            (d[i] - expect[i]).abs() <= 1e-6 * expect[i].abs(),
            "{}: {} vs {}",
            names[i],
            d[i],
            expect[i]
        );
    }
    let (fn0, w0) = (f.real("Fn"), f.real("omega2"));
    assert_eq!(f.set_real("T_load", 30.0), Fmi2Status::OK);
    assert!(
        (f.real("Fn") - fn0).abs() > 1e-3 * fn0,
        "Fn {fn0} unchanged"
    );
    assert_eq!(f.real("omega2"), w0);

    let a = instance("rt_a", 2.5e-5);
    let b = instance("rt_b", 2.5e-5);
    for k in 0..200 {
        assert_eq!(a.step(k as f64 * H, H), Fmi2Status::OK);
    }
    for k in 0..400 {
        assert_eq!(b.step(k as f64 * H / 2.0, H / 2.0), Fmi2Status::OK);
    }
    for name in ["T1", "Fn", "omega2", "E_in"] {
        let (x, y) = (a.real(name), b.real(name));
        assert!((x - y).abs() <= 1e-6 * x.abs(), "{name}: {x} vs {y}");
    }
}
