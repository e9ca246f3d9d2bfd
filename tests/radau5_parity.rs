//! Counter parity with the Fortran RADAU5 (`radau5.f` 2002, gfortran -O2) on every row of
//! `reference.md` (issue 3, test 2): the seven counters must be equal and the error
//! against the reference solution equal to the Fortran's in the three digits the file
//! gives (and so within a factor 2 of it).
//!
//! All 26 rows match exactly. (Round-off: amp1t is written with the literal coefficients
//! 0.01 and 0.99 of `reference.md`; writing `1 - 0.99` instead changes the last bits of f
//! and, at tol 1e-10 only, moves the counters by a few units -- the Fortran run is that
//! sensitive, which is why a few units would be acceptable at tol <= 1e-8.)

mod common;

use common::radau5_problems::{all_rows, run_row};

/// The error rounded to the three significant digits `reference.md` gives. With the
/// Fortran's arithmetic (err^0.25 by `pow`) all 26 rows agree to these digits; with
/// `sqrt(sqrt(err))` five rows (rob at t_end 1e11, rtol 1e-6..1e-10; amp1t at 1e-4 and
/// 1e-10) do not, although their counters are equal.
fn same_digits(ours: f64, fortran: f64) -> bool {
    format!("{ours:.2e}") == format!("{fortran:.2e}")
}

#[test]
fn counters_and_errors_match_fortran() {
    let mut failures = Vec::new();
    for r in all_rows() {
        let out = run_row(&r).expect("solve");
        let ok_counters = out.stats == r.fortran;
        let ratio = out.max_abs_err / r.fortran_err;
        let ok_err = (0.5..=2.0).contains(&ratio) && same_digits(out.max_abs_err, r.fortran_err);
        let ok_lambda = match (out.err_lambda, r.fortran_err_lambda) {
            (Some(a), Some(b)) => (0.5..=2.0).contains(&(a / b)) && same_digits(a, b),
            _ => true,
        };
        println!(
            "{:6} tol {:e} t_end {:e} {:?}\n  ours    {}\n  fortran {}\n  err {:.3e} (fortran {:.3e}) lambda {:?} / {:?}",
            r.problem,
            r.rtol,
            r.t_end,
            r.controller,
            out.stats,
            r.fortran,
            out.max_abs_err,
            r.fortran_err,
            out.err_lambda,
            r.fortran_err_lambda
        );
        if !(ok_counters && ok_err && ok_lambda) {
            failures.push(format!(
                "{} rtol {:e} t_end {:e} {:?}: counters {} err {} lambda {}",
                r.problem, r.rtol, r.t_end, r.controller, ok_counters, ok_err, ok_lambda
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
