//! In-process speed of the FMU at the default case and tolerance (issue 4 "Speed"):
//! - CPU per simulated 10 ms through the exported C functions (fmi2DoStep with H = 1e-5 s and
//!   fmi2GetReal of every Real output after each step, as a master does), and through
//!   `sim::Simulation` directly;
//! - cost of one fmi2DoStep of H = 1e-5 s relative to one internal RADAU5 step, the latter
//!   measured by one single doStep over 10 ms (CPU / accepted+rejected steps).
//!
//! Run: `cargo run --release --example fmu_bench`.

use geared_rotor::fmi2::types::*;
use geared_rotor::fmi2::variables::{Causality, VarType, GUID, VARIABLES};
use geared_rotor::fmi2::*;
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

fn main() {
    let h = 1e-5;
    let n = 1000; // 10 ms
                  // 1. Simulation directly, H = 1e-5, two consecutive 10 ms windows.
    let mut sim = new_sim();
    for window in 0..2 {
        let s0 = *sim.stats();
        let c0 = cpu_seconds();
        for k in 0..n {
            let t = (window * n + k) as f64 * h;
            sim.do_step(t, h).expect("step");
        }
        let c = cpu_seconds() - c0;
        let s = sim.stats();
        let steps = (s.naccpt - s0.naccpt) + (s.nrejct - s0.nrejct);
        println!(
            "sim, H = 1e-5, window {window}: CPU {:.4} s per simulated 10 ms ({:.1}x faster than real time); \
             internal steps {} (accepted {}, rejected {}), {:.3} internal steps per doStep, nfcn {} njac {} ndec {}",
            c,
            0.01 / c,
            steps,
            s.naccpt - s0.naccpt,
            s.nrejct - s0.nrejct,
            steps as f64 / n as f64,
            s.nfcn - s0.nfcn,
            s.njac - s0.njac,
            s.ndec - s0.ndec
        );
    }
    // 2. One doStep over 10 ms from the same state (after 10 ms of H = 1e-5).
    let mut sim2 = new_sim();
    for k in 0..n {
        sim2.do_step(k as f64 * h, h).expect("step");
    }
    let s0 = *sim2.stats();
    let c0 = cpu_seconds();
    sim2.do_step(0.01, 0.01).expect("one big step");
    let c_big = cpu_seconds() - c0;
    let s = sim2.stats();
    let steps_big = (s.naccpt - s0.naccpt) + (s.nrejct - s0.nrejct);
    let per_internal = c_big / steps_big as f64;
    println!(
        "sim, one doStep over 10 ms: CPU {:.4} s, {} internal steps ({} rejected), {:.2} us per internal step",
        c_big,
        steps_big,
        s.nrejct - s0.nrejct,
        per_internal * 1e6
    );
    // Cost of one doStep of 1e-5 s relative to one internal step (window 1 of part 1 rerun).
    let s0 = *sim.stats();
    let c0 = cpu_seconds();
    for k in 0..n {
        sim.do_step(0.02 + k as f64 * h, h).expect("step");
    }
    let c_small = (cpu_seconds() - c0) / n as f64;
    let s = sim.stats();
    println!(
        "one doStep of H = 1e-5 s: {:.2} us = {:.2} internal steps (by CPU), {:.3} internal steps (by count)",
        c_small * 1e6,
        c_small / per_internal,
        ((s.naccpt - s0.naccpt) + (s.nrejct - s0.nrejct)) as f64 / n as f64
    );

    // 3. Through the C ABI.
    let outs: Vec<u32> = VARIABLES
        .iter()
        .filter(|v| v.causality == Causality::Output && v.ty == VarType::Real)
        .map(|v| v.vr)
        .collect();
    let mut vals = vec![0.0; outs.len()];
    let name = CString::new("bench").unwrap();
    let guid = CString::new(GUID).unwrap();
    let cb = Fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: ptr::null_mut(),
    };
    unsafe {
        let c = fmi2Instantiate(name.as_ptr(), 1, guid.as_ptr(), ptr::null(), &cb, 0, 0);
        assert!(!c.is_null());
        assert_eq!(fmi2SetupExperiment(c, 1, 1e-6, 0.0, 0, 0.0), Fmi2Status::OK);
        assert_eq!(fmi2EnterInitializationMode(c), Fmi2Status::OK);
        assert_eq!(fmi2ExitInitializationMode(c), Fmi2Status::OK);
        for hc in [1e-5f64, 1e-4, 1e-3] {
            // Two 10 ms windows at this communication step, continuing in time.
            let m = (0.01 / hc).round() as usize;
            let mut t = 0.0;
            let mut st: Fmi2Status;
            for window in 0..2 {
                let c0 = cpu_seconds();
                for _ in 0..m {
                    st = fmi2DoStep(c, t, hc, 1);
                    assert_eq!(st, Fmi2Status::OK);
                    t += hc;
                    assert_eq!(
                        fmi2GetReal(c, outs.as_ptr(), outs.len(), vals.as_mut_ptr()),
                        Fmi2Status::OK
                    );
                }
                let cpu = cpu_seconds() - c0;
                println!(
                    "C ABI (doStep + GetReal of {} outputs), H = {hc:e}, window {window}: CPU {:.4} s per simulated 10 ms ({:.1}x faster than real time)",
                    outs.len(),
                    cpu,
                    0.01 / cpu
                );
            }
            assert_eq!(fmi2Reset(c), Fmi2Status::OK);
            assert_eq!(fmi2SetupExperiment(c, 1, 1e-6, 0.0, 0, 0.0), Fmi2Status::OK);
            assert_eq!(fmi2EnterInitializationMode(c), Fmi2Status::OK);
            assert_eq!(fmi2ExitInitializationMode(c), Fmi2Status::OK);
        }
        fmi2FreeInstance(c);
    }
}
