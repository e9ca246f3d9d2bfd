//! Counter parity with the Fortran RADAU5 on every row of `reference.md` (issue 3, test 2).

use geared_rotor::radau5::test_problems::{all_rows, run_row};

#[test]
fn counters_and_errors_match_fortran() {
    let mut failures = Vec::new();
    for r in all_rows() {
        let out = run_row(&r).expect("solve");
        let ok_counters = out.stats == r.fortran;
        println!(
            "{:6} tol {:e} t_end {:e} {:?}\n  ours    {}\n  fortran {}\n  err {:.3e} (fortran {:.3e}) {}",
            r.problem, r.rtol, r.t_end, r.controller, out.stats, r.fortran, out.max_abs_err, r.fortran_err,
            if ok_counters { "OK" } else { "MISMATCH" }
        );
        if !ok_counters {
            failures.push(format!("{} {:e} {:e}", r.problem, r.rtol, r.t_end));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}
