//! Runs every problem and tolerance of `data/radau5/reference.md` and prints one
//! JSON object per line: counters, max abs error against the reference solution and the
//! median time per solve (>= 7 measurements, each repeating the solve for >= 0.2 s).
//!
//! `seconds_per_solve` is wall time. The machine is shared, so each line also carries the
//! thread's CPU time per solve (`/proc/thread-self/schedstat`, Linux), which excludes the
//! time spent descheduled, and both ratios against the Fortran's time in the reference file.
//!
//! `cargo run --release --example radau5_parity`

#[allow(dead_code)]
#[path = "../tests/common/radau5_problems.rs"]
mod radau5_problems;

use std::hint::black_box;
use std::time::{Duration, Instant};

use geared_rotor::radau5::Controller;
use radau5_problems::{all_rows, run_row, ReferenceRow};

const MEASUREMENTS: usize = 7;
const MIN_MEASUREMENT: Duration = Duration::from_millis(200);

/// CPU time this thread has run so far (Linux; `None` elsewhere).
fn thread_cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// (wall, cpu) seconds per solve: medians of the measurements.
fn seconds_per_solve(r: &ReferenceRow) -> (f64, Option<f64>) {
    let mut wall = Vec::with_capacity(MEASUREMENTS);
    let mut cpu = Vec::with_capacity(MEASUREMENTS);
    for _ in 0..MEASUREMENTS {
        let c0 = thread_cpu_seconds();
        let start = Instant::now();
        let mut n = 0u32;
        while start.elapsed() < MIN_MEASUREMENT {
            black_box(run_row(black_box(r)).ok());
            n += 1;
        }
        wall.push(start.elapsed().as_secs_f64() / f64::from(n));
        if let (Some(a), Some(b)) = (c0, thread_cpu_seconds()) {
            cpu.push((b - a) / f64::from(n));
        }
    }
    let cpu = (cpu.len() == MEASUREMENTS).then(|| median(cpu));
    (median(wall), cpu)
}

fn main() {
    for r in all_rows() {
        let out = match run_row(&r) {
            Ok(o) => o,
            Err(e) => {
                println!(
                    "{{\"problem\":\"{}\",\"rtol\":{:e},\"error\":\"{}\"}}",
                    r.problem, r.rtol, e
                );
                continue;
            }
        };
        let (secs, cpu) = seconds_per_solve(&r);
        let s = out.stats;
        let mut line = format!(
            "{{\"problem\":\"{}\",\"rtol\":{:e},\"atol\":{:e},\"t_end\":{:e},\"nfcn\":{},\"njac\":{},\"nstep\":{},\"naccpt\":{},\"nrejct\":{},\"ndec\":{},\"nsol\":{},\"max_abs_err\":{:.3e},\"seconds_per_solve\":{:.3e}",
            r.problem, r.rtol, r.atol, r.t_end, s.nfcn, s.njac, s.nstep, s.naccpt, s.nrejct, s.ndec,
            s.nsol, out.max_abs_err, secs
        );
        if r.controller == Controller::Classical {
            line.push_str(",\"controller\":\"classical\"");
        }
        if let Some(e) = out.err_lambda {
            line.push_str(&format!(",\"err_lambda\":{e:.3e}"));
        }
        // The errors to the three digits reference.md gives them.
        let digits = |x: f64| format!("{x:.2e}");
        let mut err_equal = digits(out.max_abs_err) == digits(r.fortran_err);
        if let (Some(a), Some(b)) = (out.err_lambda, r.fortran_err_lambda) {
            err_equal &= digits(a) == digits(b);
        }
        line.push_str(&format!(
            ",\"fortran_max_abs_err\":{:.2e},\"err_equal_fortran_3_digits\":{err_equal}",
            r.fortran_err
        ));
        line.push_str(&format!(
            ",\"counters_equal_fortran\":{},\"fortran_seconds_per_solve\":{:.3e},\"time_ratio_vs_fortran\":{:.2}",
            s == r.fortran,
            r.fortran_seconds,
            secs / r.fortran_seconds
        ));
        if let Some(c) = cpu {
            line.push_str(&format!(
                ",\"cpu_seconds_per_solve\":{c:.3e},\"cpu_time_ratio_vs_fortran\":{:.2}",
                c / r.fortran_seconds
            ));
        }
        line.push('}');
        println!("{line}");
    }
}
