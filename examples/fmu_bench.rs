//! In-process speed of the FMU at the default case and tolerance (issue 4 "Speed").
//!
//! CPU per simulated 10 ms, as medians over 5 repeats of:
//! - "default experiment": 0 .. 50 ms from the consistent start (includes the start-up
//!   transient), averaged per 10 ms;
//! - "steady": the median 10 ms window of 50 .. 150 ms;
//!
//! for `sim::Simulation::do_step` with H = 1e-5 s and with one doStep per 10 ms, and through
//! the exported C functions (fmi2DoStep and fmi2GetReal of every Real output after each
//! step, as a master does) with H = 1e-5, 1e-4, 1e-3 s; plus the worst case for the
//! look-ahead: a master that sets a new omega1 at every point of H = 1e-5 s. Also internal
//! RADAU5 steps per doStep of 1e-5 s and the CPU of such a doStep relative to one internal
//! step of the one-doStep run.
//!
//! Run: `cargo run --release --example fmu_bench`.

use geared_rotor::c_abi::*;
use geared_rotor::fmi2::types::*;
use geared_rotor::fmi2::variables::{Causality, VarType, GUID, VARIABLES};
use geared_rotor::rotor::Params;
use geared_rotor::sim::{Simulation, SolverSettings};
use std::ffi::CString;
use std::ptr;

fn cpu_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: valid out pointer.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

const WINDOW: f64 = 0.01;
const DEFAULT_END: f64 = 0.05;
const STEADY_END: f64 = 0.15;
const REPEATS: usize = 5;

/// One run: `step(t, h)` advances one communication step; returns (CPU per 10 ms over the
/// default experiment, median CPU of the steady 10 ms windows).
fn run(h: f64, mut step: impl FnMut(f64, f64)) -> (f64, f64) {
    let per_window = (WINDOW / h).round() as usize;
    let n_default = (DEFAULT_END / WINDOW).round() as usize;
    let n_steady = ((STEADY_END - DEFAULT_END) / WINDOW).round() as usize;
    let mut k = 0usize;
    let c0 = cpu_seconds();
    for _ in 0..n_default * per_window {
        step(k as f64 * h, h);
        k += 1;
    }
    let default = (cpu_seconds() - c0) / n_default as f64;
    let mut windows = Vec::new();
    for _ in 0..n_steady {
        let c = cpu_seconds();
        for _ in 0..per_window {
            step(k as f64 * h, h);
            k += 1;
        }
        windows.push(cpu_seconds() - c);
    }
    (default, median(windows))
}

fn report(what: &str, r: Vec<(f64, f64)>, extra: &str) {
    let d = median(r.iter().map(|x| x.0).collect());
    let s = median(r.iter().map(|x| x.1).collect());
    println!(
        "{what}: default experiment {:.2} ms per 10 ms ({:.1}x real time), steady {:.2} ms ({:.1}x){extra}",
        d * 1e3,
        WINDOW / d,
        s * 1e3,
        WINDOW / s
    );
}

fn new_sim() -> Simulation {
    Simulation::new(
        Params::default(),
        SolverSettings {
            rtol: 1e-6,
            h_max: 1e-4,
        },
        0.0,
        314.159,
        0.0,
    )
    .expect("default case")
}

fn sim_case(h: f64) -> (Vec<(f64, f64)>, f64) {
    let mut out = Vec::new();
    let mut steps_per_do_step = 0.0;
    for _ in 0..REPEATS {
        let mut sim = new_sim();
        out.push(run(h, |t, h| {
            sim.do_step(t, h).expect("step");
        }));
        let s = sim.stats();
        steps_per_do_step = (s.naccpt + s.nrejct) as f64 / (STEADY_END / h).round();
    }
    (out, steps_per_do_step)
}

struct Fmu {
    c: Fmi2Component,
    outs: Vec<u32>,
    vals: Vec<f64>,
}

impl Fmu {
    fn new() -> Fmu {
        let outs: Vec<u32> = VARIABLES
            .iter()
            .filter(|v| v.causality == Causality::Output && v.ty == VarType::Real)
            .map(|v| v.vr)
            .collect();
        let vals = vec![0.0; outs.len()];
        let name = CString::new("bench").unwrap();
        let guid = CString::new(GUID).unwrap();
        let cb = Fmi2CallbackFunctions {
            logger: None,
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: ptr::null_mut(),
        };
        // SAFETY: valid strings and callbacks; the instance is freed in Drop.
        unsafe {
            let c = fmi2Instantiate(name.as_ptr(), 1, guid.as_ptr(), ptr::null(), &cb, 0, 0);
            assert!(!c.is_null());
            assert_eq!(fmi2SetupExperiment(c, 1, 1e-6, 0.0, 0, 0.0), Fmi2Status::OK);
            assert_eq!(fmi2EnterInitializationMode(c), Fmi2Status::OK);
            assert_eq!(fmi2ExitInitializationMode(c), Fmi2Status::OK);
            Fmu { c, outs, vals }
        }
    }

    fn step(&mut self, t: f64, h: f64, omega1: Option<(u32, f64)>) {
        // SAFETY: live instance, buffers of the right length.
        unsafe {
            if let Some((vr, w)) = omega1 {
                assert_eq!(fmi2SetReal(self.c, &vr, 1, &w), Fmi2Status::OK);
            }
            assert_eq!(fmi2DoStep(self.c, t, h, 1), Fmi2Status::OK);
            assert_eq!(
                fmi2GetReal(
                    self.c,
                    self.outs.as_ptr(),
                    self.outs.len(),
                    self.vals.as_mut_ptr()
                ),
                Fmi2Status::OK
            );
        }
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: instance created by fmi2Instantiate, freed once.
        unsafe { fmi2FreeInstance(self.c) };
    }
}

fn main() {
    // 1. Simulation directly.
    let (r, spd) = sim_case(1e-5);
    report(
        "sim, H = 1e-5 s",
        r,
        &format!(", {spd:.3} internal steps per doStep (count, 0..150 ms)"),
    );
    let (r_big, spd_big) = sim_case(WINDOW);
    let steps_per_window = spd_big; // one doStep per window
    let steady_big = median(r_big.iter().map(|x| x.1).collect());
    report(
        "sim, one doStep per 10 ms",
        r_big,
        &format!(", {steps_per_window:.0} internal steps per 10 ms"),
    );
    let per_internal = steady_big / steps_per_window;
    // 2. Through the C ABI.
    let outs = Fmu::new().outs.len();
    for h in [1e-5, 1e-4, 1e-3] {
        let r = (0..REPEATS)
            .map(|_| {
                let mut f = Fmu::new();
                run(h, |t, h| f.step(t, h, None))
            })
            .collect();
        report(
            &format!("C ABI doStep + GetReal of {outs} outputs, H = {h:e} s"),
            r,
            "",
        );
    }
    // 3. A master that sets a new omega1 at every communication point (no look-ahead).
    let vr_omega1 = VARIABLES
        .iter()
        .find(|v| v.name == "omega1")
        .map(|v| v.vr)
        .expect("omega1");
    let r = (0..REPEATS)
        .map(|_| {
            let mut f = Fmu::new();
            let mut k = 0u64;
            run(1e-5, |t, h| {
                k += 1;
                // A slow 1 rad/s ripple: a new input value at every point.
                let w = 314.159 + (k as f64 * 1e-3).sin();
                f.step(t, h, Some((vr_omega1, w)));
            })
        })
        .collect();
    report(
        &format!(
            "C ABI SetReal(omega1, new value) + doStep + GetReal of {outs} outputs, H = 1e-5 s"
        ),
        r,
        "",
    );
    // 4. One doStep of 1e-5 s relative to one internal step of the one-doStep run.
    let (r_small, _) = sim_case(1e-5);
    let steady_small = median(r_small.iter().map(|x| x.1).collect()) / 1000.0;
    println!(
        "one doStep of H = 1e-5 s (steady): {:.2} us = {:.2} internal steps by CPU ({:.2} us per internal step of the one-doStep run)",
        steady_small * 1e6,
        steady_small / per_internal,
        per_internal * 1e6
    );
}
