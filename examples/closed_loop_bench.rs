//! Closed-loop co-simulation through the C ABI (issue 11): a master that sets the inputs
//! at every communication point, calls fmi2DoStep and reads every Real output.
//!
//! Cases, each over 1 s of simulated time from the consistent start (default pair):
//! - `const`: omega1 = 314.159 rad/s, T_load = 0 held (set once, as a master re-sending the
//!   same values would: re-setting the same value costs nothing);
//! - `omega1`: omega1 = 314.159 (1 + 0.01 sin(2 pi 50 t)) set at every point (held);
//! - `omega1+der`: the same with fmi2SetRealInputDerivatives (the exact slope at t);
//! - `omega1+T_load`: omega1 as above and T_load = sin(2 pi 50 t) N m, both set at every
//!   point (held);
//! - `rt h=...`: the real-time mode (`h_fixed`, value reference 130) with omega1 changing,
//!   when the FMU has that parameter.
//!
//! Printed per case and H (1e-4 s, 1e-5 s): CPU per simulated 10 ms (whole second, median
//! of the repeats) and the multiple of real time, the ratio to `const`; the wall time of one
//! call (SetReal [+ SetRealInputDerivatives] + DoStep + GetReal of all Real outputs): median,
//! p99, p99.9 and max (each the median over the repeats; max also the best of them); and
//! the RADAU5 work per doStep from the instance's counters (internal step attempts,
//! rejections, Newton iterations = linear solves, Jacobians, renewals of only their fast
//! part (`jfast`, the split Jacobian of docs/radau5.md §8), LU pairs, f evaluations; mean
//! and the largest of any doStep), and with a third argument `cpu`: `cpumx`, the largest
//! process CPU time of one call (best of the runs; unlike the wall time it excludes
//! preemption by other processes; the clock reads, ~1 us each, then inflate the CPU column).
//! The counters are deterministic: use them to judge a
//! change when the machine is loaded.
//!
//! Run: `cargo run --release --example closed_loop_bench [repeats] [case-filter] [cpu]`
//! (filter: a substring of the case names, or `=name,name` for exactly those cases;
//! `BENCH_H=1e-4` or `1e-5` runs one communication step size only; `BENCH_OUTPUTS=T1`
//! reads only that output (the others' cost by difference); `BENCH_LAW=4` runs friction law 4; `BENCH_JITTER=1` adds
//! the machine's jitter floor next to `rt 2.5e-5 omega1`, see [`jitter_floor`]).
//!
//! `BENCH_FMI=3` runs the same master through the FMI 3.0 functions (`fmi3SetFloat64`,
//! `fmi3DoStep`, `fmi3GetFloat64`; the same library, `c_abi3`); `BENCH_FMI=both` runs every
//! case through both, the runs of the two alternated, and prints both rows and the ratio
//! of their median CPU times (FMI 3.0 has no input derivatives: `omega1+der` is 2.0 only).
//!
//! `BENCH_CONTACT=elastic` runs the elastic tooth contact (`tooth_contact = elastic`,
//! docs/model.md §3.5) instead of the rigid one; `BENCH_CONTACT=both` runs every case with
//! both, the runs alternated, and prints the ratio elastic / rigid of the median CPU times
//! (with `BENCH_FMI=both` too: FMI 2.0 only, one comparison at a time).

use geared_rotor::c_abi::Instance;
use geared_rotor::c_abi::*;
use geared_rotor::c_abi3 as c3;
use geared_rotor::fmi2::types::*;
use geared_rotor::fmi2::variables::{Causality, VarType, GUID, VARIABLES};
use geared_rotor::fmi3::types::Fmi3Status;
use geared_rotor::radau5::Statistics;
use std::f64::consts::PI;
use std::ffi::CString;
use std::ptr;
use std::time::Instant;

fn cpu_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: valid out pointer.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// The Real outputs the bench reads: all, or with `BENCH_OUTPUTS=T1` only T1 (the cost of
/// the other outputs by difference).
fn bench_outputs() -> Vec<u32> {
    let only = std::env::var("BENCH_OUTPUTS").ok();
    VARIABLES
        .iter()
        .filter(|v| v.causality == Causality::Output && v.ty == VarType::Real)
        .filter(|v| only.as_deref().is_none_or(|o| o == v.name))
        .map(|v| v.vr)
        .collect()
}

/// The value reference of the Enumeration parameter friction_law (BENCH_LAW=N).
fn law_vr() -> u32 {
    enum_vr("friction_law")
}

/// The value reference of an Enumeration parameter.
fn enum_vr(name: &str) -> u32 {
    VARIABLES
        .iter()
        .find(|v| v.name == name)
        .expect("parameter")
        .vr
}

/// `tooth_contact = elastic` (Enumeration value 2).
const ELASTIC: i32 = 2;

fn vr_of(name: &str) -> Option<u32> {
    VARIABLES
        .iter()
        .find(|v| v.name == name && v.ty == VarType::Real)
        .map(|v| v.vr)
}

const W0: f64 = 314.159;
const T_END: f64 = 1.0;

#[derive(Clone, Copy, PartialEq)]
enum Drive {
    Constant,
    Omega1,
    Omega1Der,
    Omega1TLoad,
}

#[derive(Clone, Copy)]
struct Case {
    name: &'static str,
    drive: Drive,
    h_fixed: f64,
}

fn omega1(t: f64) -> (f64, f64) {
    let a = 2.0 * PI * 50.0;
    (
        W0 * (1.0 + 0.01 * (a * t).sin()),
        W0 * 0.01 * a * (a * t).cos(),
    )
}

fn t_load(t: f64) -> f64 {
    (2.0 * PI * 50.0 * t).sin()
}

struct Fmu {
    c: Fmi2Component,
    /// Through the FMI 3.0 functions.
    v3: bool,
    outs: Vec<u32>,
    vals: Vec<f64>,
}

impl Fmu {
    fn new(h_fixed: f64, v3: bool, elastic: bool) -> Fmu {
        if v3 {
            return Fmu::new3(h_fixed, elastic);
        }
        let outs = bench_outputs();
        let vals = vec![0.0; outs.len()];
        let name = CString::new("closed_loop").unwrap();
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
            // BENCH_LAW=N: friction law N (the Enumeration parameter friction_law).
            if let Some(law) = std::env::var("BENCH_LAW").ok().and_then(|s| s.parse().ok()) {
                let vr = law_vr();
                assert_eq!(fmi2SetInteger(c, &vr, 1, &law), Fmi2Status::OK);
            }
            if elastic {
                let vr = enum_vr("tooth_contact");
                assert_eq!(fmi2SetInteger(c, &vr, 1, &ELASTIC), Fmi2Status::OK);
            }
            if h_fixed > 0.0 {
                let vr = vr_of("h_fixed").expect("h_fixed");
                assert_eq!(fmi2SetReal(c, &vr, 1, &h_fixed), Fmi2Status::OK);
            }
            assert_eq!(fmi2ExitInitializationMode(c), Fmi2Status::OK);
            Fmu {
                c,
                v3: false,
                outs,
                vals,
            }
        }
    }

    /// The same instance through the FMI 3.0 functions.
    fn new3(h_fixed: f64, elastic: bool) -> Fmu {
        let outs = bench_outputs();
        let vals = vec![0.0; outs.len()];
        let name = CString::new("closed_loop").unwrap();
        let guid = CString::new(GUID).unwrap();
        // SAFETY: valid strings; the instance is freed in Drop.
        unsafe {
            let c = c3::fmi3InstantiateCoSimulation(
                name.as_ptr(),
                guid.as_ptr(),
                ptr::null(),
                0,
                0,
                0,
                0,
                ptr::null(),
                0,
                ptr::null_mut(),
                None,
                None,
            );
            assert!(!c.is_null());
            if let Some(law) = std::env::var("BENCH_LAW")
                .ok()
                .and_then(|s| s.parse::<i32>().ok())
            {
                let vr = law_vr();
                assert_eq!(c3::fmi3SetInt32(c, &vr, 1, &law, 1), Fmi3Status::OK);
            }
            if elastic {
                let vr = enum_vr("tooth_contact");
                assert_eq!(c3::fmi3SetInt32(c, &vr, 1, &ELASTIC, 1), Fmi3Status::OK);
            }
            if h_fixed > 0.0 {
                let vr = vr_of("h_fixed").expect("h_fixed");
                assert_eq!(c3::fmi3SetFloat64(c, &vr, 1, &h_fixed, 1), Fmi3Status::OK);
            }
            assert_eq!(
                c3::fmi3EnterInitializationMode(c, 1, 1e-6, 0.0, 0, 0.0),
                Fmi3Status::OK
            );
            assert_eq!(c3::fmi3ExitInitializationMode(c), Fmi3Status::OK);
            Fmu {
                c,
                v3: true,
                outs,
                vals,
            }
        }
    }

    /// SetReal / fmi3SetFloat64 of inputs.
    ///
    /// # Safety
    /// Live instance.
    #[inline]
    unsafe fn set(&mut self, vrs: &[u32], v: &[f64]) {
        // SAFETY: caller contract; slices of equal length.
        unsafe {
            if self.v3 {
                let st = c3::fmi3SetFloat64(self.c, vrs.as_ptr(), vrs.len(), v.as_ptr(), v.len());
                assert_eq!(st, Fmi3Status::OK);
            } else {
                let st = fmi2SetReal(self.c, vrs.as_ptr(), vrs.len(), v.as_ptr());
                assert_eq!(st, Fmi2Status::OK);
            }
        }
    }

    /// DoStep, then GetReal / fmi3GetFloat64 of the outputs; whether the step was OK.
    ///
    /// # Safety
    /// Live instance.
    #[inline]
    unsafe fn step_and_get(&mut self, t: f64, h: f64) -> bool {
        // SAFETY: caller contract; out-pointers and buffers valid.
        unsafe {
            if self.v3 {
                let (mut ev, mut term, mut early, mut last) = (0u8, 0u8, 0u8, 0.0);
                let st = c3::fmi3DoStep(self.c, t, h, 1, &mut ev, &mut term, &mut early, &mut last);
                let n = self.outs.len();
                let g =
                    c3::fmi3GetFloat64(self.c, self.outs.as_ptr(), n, self.vals.as_mut_ptr(), n);
                st == Fmi3Status::OK && g == Fmi3Status::OK
            } else {
                let st = fmi2DoStep(self.c, t, h, 1);
                let g = fmi2GetReal(
                    self.c,
                    self.outs.as_ptr(),
                    self.outs.len(),
                    self.vals.as_mut_ptr(),
                );
                st == Fmi2Status::OK && g == Fmi2Status::OK
            }
        }
    }

    /// RADAU5 counters of the instance (read outside the timed calls).
    fn stats(&self) -> Statistics {
        if self.v3 {
            // SAFETY: fmi3InstantiateCoSimulation returns a boxed Instance3; no call is
            // running.
            let inst = unsafe { &*(self.c as *const c3::Instance3) };
            return *inst
                .inner
                .model()
                .simulation()
                .expect("initialised")
                .stats();
        }
        // SAFETY: fmi2Instantiate returns a boxed Instance; no call is running.
        let inst = unsafe { &*(self.c as *const Instance) };
        *inst.model().simulation().expect("initialised").stats()
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: instance created by fmi2Instantiate / fmi3InstantiateCoSimulation, freed
        // once.
        unsafe {
            if self.v3 {
                c3::fmi3FreeInstance(self.c);
            } else {
                fmi2FreeInstance(self.c);
            }
        }
    }
}

struct RunResult {
    cpu_per_10ms: f64,
    wall: Vec<f64>,
    /// Largest CPU time of one call (process CPU: excludes time the process was preempted
    /// on a loaded machine, which the wall time includes).
    cpu_max: f64,
    /// Sums and per-doStep maxima of the counter deltas.
    sum: Statistics,
    max: Statistics,
    min_nfcn: u64,
    n: usize,
    /// Whether each call renewed the Jacobian (for the real-time schedule).
    with_jac: Vec<bool>,
}

fn acc(s: &mut Statistics, m: &mut Statistics, d: &Statistics) {
    s.nfcn += d.nfcn;
    s.njac += d.njac;
    s.njac_fast += d.njac_fast;
    s.nstep += d.nstep;
    s.naccpt += d.naccpt;
    s.nrejct += d.nrejct;
    s.ndec += d.ndec;
    s.nsol += d.nsol;
    m.nfcn = m.nfcn.max(d.nfcn);
    m.njac = m.njac.max(d.njac);
    m.njac_fast = m.njac_fast.max(d.njac_fast);
    m.nstep = m.nstep.max(d.nstep);
    m.naccpt = m.naccpt.max(d.naccpt);
    m.nrejct = m.nrejct.max(d.nrejct);
    m.ndec = m.ndec.max(d.ndec);
    m.nsol = m.nsol.max(d.nsol);
}

fn run(case: Case, h: f64, per_call_cpu: bool, v3: bool, elastic: bool) -> RunResult {
    let mut f = Fmu::new(case.h_fixed, v3, elastic);
    let n = (T_END / h).round() as usize;
    let (vr_w, vr_tl) = (vr_of("omega1").unwrap(), vr_of("T_load").unwrap());
    let mut wall = Vec::with_capacity(n);
    let mut sum = Statistics::default();
    let mut max = Statistics::default();
    let mut min_nfcn = u64::MAX;
    let mut with_jac = Vec::with_capacity(n);
    let mut cpu = 0.0;
    let mut cpu_max = 0.0f64;
    let one = 1i32;
    let cpu0 = cpu_seconds();
    for k in 0..n {
        let t = k as f64 * h;
        let (w, wd) = omega1(t);
        let tl = t_load(t);
        let s0 = f.stats();
        let c0 = if per_call_cpu { cpu_seconds() } else { 0.0 };
        let w0 = Instant::now();
        // SAFETY: live instance, buffers of the right length.
        unsafe {
            match case.drive {
                Drive::Constant => {}
                Drive::Omega1 => f.set(&[vr_w], &[w]),
                Drive::Omega1Der => {
                    f.set(&[vr_w], &[w]);
                    assert!(!f.v3, "FMI 3.0 has no input derivatives");
                    assert_eq!(
                        fmi2SetRealInputDerivatives(f.c, &vr_w, 1, &one, &wd),
                        Fmi2Status::OK
                    );
                }
                Drive::Omega1TLoad => f.set(&[vr_w, vr_tl], &[w, tl]),
            }
            let ok = f.step_and_get(t, h);
            assert!(ok, "{} H = {h:e} at t = {t}", case.name);
        }
        let dt = w0.elapsed().as_secs_f64();
        if per_call_cpu {
            cpu_max = cpu_max.max(cpu_seconds() - c0);
        }
        wall.push(dt);
        let d = f.stats().since(&s0);
        acc(&mut sum, &mut max, &d);
        min_nfcn = min_nfcn.min(d.nfcn);
        with_jac.push(d.njac > 0);
    }
    // The whole loop (incl. reading the counters, ~1 ns per call): the process CPU clock
    // is a system call (~1 us), too slow to read around every call.
    cpu += cpu_seconds() - cpu0;
    RunResult {
        cpu_per_10ms: cpu / (T_END / 0.01),
        wall,
        cpu_max,
        sum,
        max,
        min_nfcn,
        n,
        with_jac,
    }
}

/// The machine's own jitter: `n` "calls" of a fixed amount of pure arithmetic (no memory
/// beyond registers, no system call), calibrated to last about `target` seconds each, timed
/// exactly as the FMU calls are. What its maximum shows is added to any call by the VM
/// (preemption, interrupts, frequency changes), not by the FMU.
fn jitter_floor(n: usize, target: f64) -> Vec<f64> {
    fn spin(iters: u64, x: f64) -> f64 {
        let mut x = x;
        for _ in 0..iters {
            x = std::hint::black_box(x * 0.999_999_9 + 1e-9);
        }
        x
    }
    // Calibrate: the median of a few timings of a known count.
    let probe = 100_000u64;
    let mut t = Vec::new();
    let mut x = 1.0;
    for _ in 0..7 {
        let w0 = Instant::now();
        x = spin(probe, x);
        t.push(w0.elapsed().as_secs_f64());
    }
    let iters = ((target / median(t)) * probe as f64).max(1.0) as u64;
    let mut wall = Vec::with_capacity(n);
    for _ in 0..n {
        let w0 = Instant::now();
        x = spin(iters, x);
        wall.push(w0.elapsed().as_secs_f64());
    }
    std::hint::black_box(x);
    wall
}

/// Largest per-call time over the first 50 ms of simulated time and over the rest.
fn max_split(wall: &[f64], h: f64) -> (f64, f64) {
    let k = ((0.05 / h).round() as usize).min(wall.len());
    let mx = |w: &[f64]| w.iter().cloned().fold(0.0, f64::max);
    (mx(&wall[..k]), mx(&wall[k..]))
}

fn quantile(sorted: &[f64], q: f64) -> f64 {
    let i = ((sorted.len() as f64 - 1.0) * q).round() as usize;
    sorted[i]
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let repeats: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(3);
    let filter = args.get(2).cloned().unwrap_or_default();
    let per_call_cpu = args.get(3).is_some_and(|a| a == "cpu");
    // With a case filter that selects "rt 2.5e-5 omega1": also the jitter floor of the
    // machine, an arithmetic loop as long as that case's median call, timed the same way.
    let jitter = std::env::var("BENCH_JITTER").is_ok_and(|v| v == "1");
    let has_rt = vr_of("h_fixed").is_some();
    // BENCH_FMI=3: through the FMI 3.0 functions; both: 2.0 and 3.0 side by side.
    let versions: Vec<bool> = match std::env::var("BENCH_FMI").as_deref() {
        Ok("3") => vec![true],
        Ok("both") => vec![false, true],
        _ => vec![false],
    };
    // BENCH_CONTACT=elastic: the elastic tooth contact; both: rigid and elastic side by side.
    let contacts: Vec<bool> = match std::env::var("BENCH_CONTACT").as_deref() {
        Ok("elastic") => vec![true],
        Ok("both") => vec![false, true],
        _ => vec![false],
    };
    // The variants (FMI 3.0?, elastic?) whose runs alternate: one comparison at a time.
    let variants: Vec<(bool, bool)> = if contacts.len() > 1 {
        contacts.iter().map(|&e| (versions[0], e)).collect()
    } else {
        versions.iter().map(|&v3| (v3, contacts[0])).collect()
    };
    println!(
        "closed-loop benchmark: default pair, rtol 1e-6, {T_END} s simulated per run, {repeats} repeats (medians; max also best of runs), {} online CPUs",
        std::thread::available_parallelism().map_or(0, |n| n.get())
    );
    println!(
        "{:<22} {:>7} {:>9} {:>6} {:>6} | {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} | {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>5}",
        "case", "H [s]", "CPU/10ms", "x RT", "ratio", "med us", "p99", "p99.9", "max", "bestmx", "cpumx",
        "steps", "rej", "newt", "jac", "jfast", "lu", "nfcn", "mxfcn"
    );
    // BENCH_H=1e-5 (or 1e-4) restricts the run to one communication step size.
    let only_h: Option<f64> = std::env::var("BENCH_H").ok().and_then(|s| s.parse().ok());
    for h in [1e-4, 1e-5] {
        if only_h.is_some_and(|o| o != h) {
            continue;
        }
        let mut cases = vec![
            Case {
                name: "const",
                drive: Drive::Constant,
                h_fixed: 0.0,
            },
            Case {
                name: "omega1",
                drive: Drive::Omega1,
                h_fixed: 0.0,
            },
            Case {
                name: "omega1+der",
                drive: Drive::Omega1Der,
                h_fixed: 0.0,
            },
            Case {
                name: "omega1+T_load",
                drive: Drive::Omega1TLoad,
                h_fixed: 0.0,
            },
        ];
        if has_rt {
            for (name, hf) in [
                ("rt 2.5e-5 omega1", 2.5e-5),
                ("rt 5e-5 omega1", 5e-5),
                ("rt 1e-4 omega1", 1e-4),
            ] {
                cases.push(Case {
                    name,
                    drive: Drive::Omega1,
                    h_fixed: hf,
                });
            }
            cases.push(Case {
                name: "rt 2.5e-5 const",
                drive: Drive::Constant,
                h_fixed: 2.5e-5,
            });
        }
        let mut cpu_const = [f64::NAN; 2];
        for case in cases {
            // "=a,b": exactly these cases; otherwise a substring of the name.
            let selected = match filter.strip_prefix('=') {
                Some(names) => names.split(',').any(|n| n == case.name),
                None => case.name.contains(filter.as_str()),
            };
            if !selected {
                continue;
            }
            // The elastic contact's mesh mode (2.9 kHz) needs h_fixed <= 5e-5 s: at 1e-4 s
            // (3 steps per period) its fixed Newton iteration fails (docs/model.md §3.6).
            let vs: Vec<(bool, bool)> = variants
                .iter()
                .copied()
                .filter(|&(v3, _)| !(v3 && case.drive == Drive::Omega1Der))
                .filter(|&(_, elastic)| !(elastic && case.h_fixed > 5e-5))
                .collect();
            // The runs of the versions alternated, so that a change of the machine's load
            // hits both alike.
            let mut all: Vec<Vec<RunResult>> = vs.iter().map(|_| Vec::new()).collect();
            for _ in 0..repeats {
                for (i, &(v3, elastic)) in vs.iter().enumerate() {
                    all[i].push(run(case, h, per_call_cpu, v3, elastic));
                }
            }
            let mut cpus = Vec::new();
            for (runs, &(v3, elastic)) in all.iter().zip(&vs) {
                let label = if contacts.len() > 1 || elastic {
                    format!(
                        "{} [{}]",
                        case.name,
                        if elastic { "elastic" } else { "rigid" }
                    )
                } else if versions.len() > 1 {
                    format!("{} [{}]", case.name, if v3 { "3.0" } else { "2.0" })
                } else {
                    case.name.to_string()
                };
                let cpu = median(runs.iter().map(|r| r.cpu_per_10ms).collect());
                cpus.push(cpu);
                if case.name == "const" && !elastic {
                    cpu_const[usize::from(v3)] = cpu;
                }
                let mut q = [Vec::new(), Vec::new(), Vec::new(), Vec::new()];
                for r in runs.iter() {
                    let mut w = r.wall.clone();
                    w.sort_by(f64::total_cmp);
                    for (k, p) in [0.5, 0.99, 0.999, 1.0].into_iter().enumerate() {
                        q[k].push(quantile(&w, p) * 1e6);
                    }
                }
                let best_max = q[3].iter().cloned().fold(f64::INFINITY, f64::min);
                let r = &runs[0];
                let n = r.n as f64;
                let per = |x: u64| x as f64 / n;
                println!(
                "{:<22} {:>7.0e} {:>8.2}ms {:>6.1} {:>6.2} | {:>7.1} {:>7.1} {:>7.1} {:>7.1} {:>7.1} {:>7.1} | {:>6.3} {:>6.3} {:>6.2} {:>6.3} {:>6.3} {:>6.3} {:>6.2} {:>5}",
                label,
                h,
                cpu * 1e3,
                0.01 / cpu,
                cpu / cpu_const[usize::from(v3)],
                median(q[0].clone()),
                median(q[1].clone()),
                median(q[2].clone()),
                median(q[3].clone()),
                best_max,
                runs.iter().map(|r| r.cpu_max * 1e6).fold(f64::INFINITY, f64::min),
                per(r.sum.nstep),
                per(r.sum.nrejct),
                per(r.sum.nsol),
                per(r.sum.njac),
                per(r.sum.njac_fast),
                per(r.sum.ndec),
                per(r.sum.nfcn),
                r.max.nfcn,
            );
                if case.h_fixed > 0.0 {
                    println!(
                    "{:<22} per doStep: nfcn {}..{}, LU pairs max {}, Jacobians max {}, rejections max {}",
                    "", r.min_nfcn, r.max.nfcn, r.max.ndec, r.max.njac, r.max.nrejct
                );
                    // Median call with and without a Jacobian + LU renewal (the schedule's
                    // slowest and typical doStep), medians over the runs.
                    let part = |j: bool| {
                        median(
                            runs.iter()
                                .map(|r| {
                                    median(
                                        r.wall
                                            .iter()
                                            .zip(&r.with_jac)
                                            .filter(|(_, &w)| w == j)
                                            .map(|(x, _)| *x * 1e6)
                                            .collect(),
                                    )
                                })
                                .collect(),
                        )
                    };
                    if r.with_jac.iter().any(|&w| !w) {
                        println!(
                            "{:<22} median call with J + LU {:.1} us, without {:.1} us",
                            "",
                            part(true),
                            part(false)
                        );
                    }
                }
                let splits: Vec<(f64, f64)> = runs.iter().map(|r| max_split(&r.wall, h)).collect();
                println!(
                    "{:<22} max per call [us], first 50 ms / after, per run: {}",
                    "",
                    splits
                        .iter()
                        .map(|(a, b)| format!("{:.0}/{:.0}", a * 1e6, b * 1e6))
                        .collect::<Vec<_>>()
                        .join(", ")
                );
                if jitter && case.name == "rt 2.5e-5 omega1" {
                    let target = median(q[0].clone()) * 1e-6;
                    let mut q = [Vec::new(), Vec::new(), Vec::new(), Vec::new()];
                    for _ in 0..repeats {
                        let mut w = jitter_floor(r.n, target);
                        w.sort_by(f64::total_cmp);
                        for (k, p) in [0.5, 0.99, 0.999, 1.0].into_iter().enumerate() {
                            q[k].push(quantile(&w, p) * 1e6);
                        }
                    }
                    println!(
                    "{:<22} {:>7.0e} {:>9} {:>6} {:>6} | {:>7.1} {:>7.1} {:>7.1} {:>7.1} {:>7.1}",
                    "arithmetic loop",
                    h,
                    "",
                    "",
                    "",
                    median(q[0].clone()),
                    median(q[1].clone()),
                    median(q[2].clone()),
                    median(q[3].clone()),
                    q[3].iter().cloned().fold(f64::INFINITY, f64::min),
                );
                }
            }
            if let [c2, c3] = cpus[..] {
                let per: Vec<String> = all[0]
                    .iter()
                    .zip(&all[1])
                    .map(|(a, b)| format!("{:.3}", b.cpu_per_10ms / a.cpu_per_10ms))
                    .collect();
                let what = if contacts.len() > 1 {
                    "elastic / rigid"
                } else {
                    "FMI 3.0 / 2.0"
                };
                println!(
                    "{:<22} {what}: ratio of the median CPU {:.3}; per alternated pair {}",
                    "",
                    c3 / c2,
                    per.join(", ")
                );
            }
        }
    }
}
