//! Runs every problem and tolerance of `../shared/data/radau5/reference.md` and prints one
//! JSON object per line: counters, max abs error against the reference solution and the
//! median time per solve (>= 7 measurements, each repeating the solve for >= 0.2 s).
//!
//! `cargo run --release --example radau5_parity`

use std::hint::black_box;
use std::time::{Duration, Instant};

use geared_rotor::radau5::test_problems::{all_rows, run_row, ReferenceRow};
use geared_rotor::radau5::Controller;

const MEASUREMENTS: usize = 7;
const MIN_MEASUREMENT: Duration = Duration::from_millis(200);

fn seconds_per_solve(r: &ReferenceRow) -> f64 {
    let mut samples = Vec::with_capacity(MEASUREMENTS);
    for _ in 0..MEASUREMENTS {
        let start = Instant::now();
        let mut n = 0u32;
        while start.elapsed() < MIN_MEASUREMENT {
            black_box(run_row(black_box(r)).ok());
            n += 1;
        }
        samples.push(start.elapsed().as_secs_f64() / f64::from(n));
    }
    samples.sort_by(f64::total_cmp);
    samples[MEASUREMENTS / 2]
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
        let secs = seconds_per_solve(&r);
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
        line.push_str(&format!(
            ",\"counters_equal_fortran\":{},\"fortran_seconds_per_solve\":{:.3e},\"time_ratio_vs_fortran\":{:.2}}}",
            s == r.fortran,
            r.fortran_seconds,
            secs / r.fortran_seconds
        ));
        println!("{line}");
    }
}
