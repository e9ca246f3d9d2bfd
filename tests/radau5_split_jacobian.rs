//! The split Jacobian of RADAU5 (radau5.md §8, `Problem::jacobian_fast`): a problem that
//! gives the fast part F of `J = S + F` gets renewals of F alone where the last J has merely
//! aged, full renewals where that does not restore the Newton contraction, and the
//! snapshot carries the split. On a parametrically excited oscillator
//! `x'' + c(t) x' + k(t) x = cos t` whose stiffness k(t) (in F) changes fast.

mod common;

use common::radau5::check_snapshots_continue;
use geared_rotor::radau5::{Error, Options, Problem, Radau5, RhsError, Statistics, Tolerance};
use nalgebra::{SMatrix, SVector};

/// `y = (x, x')`; `k(t) = K (1 + 0.5 sin(W t))` is the fast part of J; the damping
/// `c(t) = C (1 + a_c sin(W t))` is in S (with `a_c` > 0, S ages as fast as F: the split
/// must fall back to full renewals). `split` = false: no split (every renewal full).
struct Parametric {
    a_c: f64,
    split: bool,
    /// `jacobian` declines (the stepper takes differences of f) for t in this interval.
    declines: (f64, f64),
    /// `jacobian_fast` fails from this time on.
    fast_fails_from: f64,
}

impl Parametric {
    fn new(a_c: f64, split: bool) -> Self {
        Parametric {
            a_c,
            split,
            declines: (f64::INFINITY, f64::INFINITY),
            fast_fails_from: f64::INFINITY,
        }
    }
}

const K: f64 = 1e6;
const C: f64 = 2e3;
const W: f64 = 300.0;

impl Parametric {
    fn k(t: f64) -> f64 {
        K * (1.0 + 0.5 * (W * t).sin())
    }
    fn c(&self, t: f64) -> f64 {
        C * (1.0 + self.a_c * (W * t).sin())
    }
}

impl Problem<2> for Parametric {
    fn rhs(
        &mut self,
        t: f64,
        y: &SVector<f64, 2>,
        f: &mut SVector<f64, 2>,
    ) -> Result<(), RhsError> {
        f[0] = y[1];
        f[1] = -Self::k(t) * y[0] - self.c(t) * y[1] + t.cos();
        Ok(())
    }
    fn jacobian(
        &mut self,
        t: f64,
        _y: &SVector<f64, 2>,
        j: &mut SMatrix<f64, 2, 2>,
    ) -> Result<bool, RhsError> {
        *j = SMatrix::<f64, 2, 2>::new(0.0, 1.0, -Self::k(t), -self.c(t));
        Ok(!(self.declines.0..=self.declines.1).contains(&t))
    }
    fn jacobian_fast(
        &mut self,
        t: f64,
        _y: &SVector<f64, 2>,
        fast: &mut SMatrix<f64, 2, 2>,
    ) -> Result<bool, RhsError> {
        if t >= self.fast_fails_from {
            return Err(RhsError::new("fast part undefined"));
        }
        *fast = SMatrix::<f64, 2, 2>::new(0.0, 0.0, -Self::k(t), 0.0);
        Ok(self.split)
    }
}

const T_END: f64 = 0.2;

/// rtol and an absolute tolerance of 1e-6 of the solution's size (x ~ 1e-6).
fn tolerances(rtol: f64) -> Options<2> {
    Options {
        rtol: Tolerance::Scalar(rtol),
        atol: Tolerance::Scalar(1e-12),
        ..Options::default()
    }
}

fn run(a_c: f64, split: bool, rtol: f64) -> (SVector<f64, 2>, Statistics) {
    let mut p = Parametric::new(a_c, split);
    let y0 = SVector::<f64, 2>::new(0.0, 0.0);
    let mut s = Radau5::new(&mut p, tolerances(rtol), 0.0, y0).unwrap();
    s.integrate_to(&mut p, T_END).unwrap();
    (*s.y(), *s.stats())
}

/// Error of x and x' against the run at rtol 1e-11, relative to their sizes at the end.
fn error(y: &SVector<f64, 2>, reference: &SVector<f64, 2>) -> f64 {
    ((y[0] - reference[0]).abs() / reference[0].abs())
        .max((y[1] - reference[1]).abs() / reference[1].abs())
}

/// Full renewals of J that did not follow a rejection (radau5.f renews J after each).
fn full_without_rejection(s: &Statistics) -> u64 {
    s.njac - s.nrejct
}

/// With S constant the split J equals the full one: the same accuracy as the run with
/// full renewals (rtol 1e-6: within 3 times each other's error, below 1e-6 of the
/// solution), Newton iterations within 10 % of it, and of the renewals not forced by a
/// rejection at most one in six is full.
#[test]
fn split_renews_the_fast_part_alone_when_the_rest_is_constant() {
    let (reference, _) = run(0.0, false, 1e-11);
    let (whole, sw) = run(0.0, false, 1e-6);
    let (split, ss) = run(0.0, true, 1e-6);
    let (ew, es) = (error(&whole, &reference), error(&split, &reference));
    println!("whole: {sw}, error {ew:.2e}\nsplit: {ss}, error {es:.2e}");
    assert!(ew < 1e-6 && es < 1e-6, "{ew:e} {es:e}");
    assert!(es < 3.0 * ew && ew < 3.0 * es, "{ew:e} {es:e}");
    assert_eq!(sw.njac_fast, 0);
    assert!(4 * ss.njac <= sw.njac, "{ss} vs {sw}");
    assert!(5 * full_without_rejection(&ss) <= ss.njac_fast, "{ss}");
    assert!(10 * ss.nsol <= 11 * sw.nsol, "{ss} vs {sw}");
}

/// With S ageing as fast as F (the damping varies by 90 % at the stiffness' frequency
/// and is not in F), renewals of F alone leave the contraction above thet: the stepper
/// falls back to full renewals, at least three times as often as with S constant, and
/// keeps the accuracy and, within 10 %, the Newton iterations of the run with full
/// renewals (without the fall-back: 1.7 times as many).
#[test]
fn split_falls_back_to_full_renewals_when_the_rest_ages() {
    let (reference, _) = run(0.9, false, 1e-11);
    let (whole, sw) = run(0.9, false, 1e-6);
    let (split, ss) = run(0.9, true, 1e-6);
    let (_, constant) = run(0.0, true, 1e-6);
    let (ew, es) = (error(&whole, &reference), error(&split, &reference));
    println!("whole: {sw}, error {ew:.2e}\nsplit: {ss}, error {es:.2e}");
    println!("S constant: {constant}");
    assert!(ew < 1e-6 && es < 1e-6, "{ew:e} {es:e}");
    assert!(es < 3.0 * ew && ew < 3.0 * es, "{ew:e} {es:e}");
    assert!(ss.njac_fast > 0, "{ss}");
    assert!(
        full_without_rejection(&ss) >= 3 * full_without_rejection(&constant),
        "{ss} vs {constant}"
    );
    assert!(10 * ss.nsol <= 11 * sw.nsol, "{ss} vs {sw}");
}

/// A snapshot in bytes taken before any step of a split run (with S ageing, so that fast
/// renewals, their fall-backs and the stale flag all occur) continues bit-identically.
#[test]
fn snapshot_carries_the_split() {
    let mut p = Parametric::new(0.5, true);
    let y0 = SVector::<f64, 2>::new(0.0, 0.0);
    let mut s = Radau5::new(&mut p, tolerances(1e-6), 0.0, y0).unwrap();
    check_snapshots_continue(&mut p, &mut s, 80, T_END, 1e-4);
    let st = *s.stats();
    assert!(st.njac_fast > 0 && st.njac > 1, "{st}");
}

/// Steps of a split run, each with its start time and the full and fast renewals it took.
fn renewals(p: &mut Parametric, options: Options<2>) -> Vec<(f64, u64, u64)> {
    let mut s = Radau5::new(p, options, 0.0, SVector::zeros()).unwrap();
    let mut out = Vec::new();
    while s.t() < T_END {
        let (t, before) = (s.t(), *s.stats());
        s.step(p, T_END).unwrap();
        let d = s.stats().since(&before);
        out.push((t, d.njac, d.njac_fast));
    }
    out
}

/// Where the problem gives no analytic J (here for 0.05 <= t <= 0.1) the stepper takes
/// differences of f, and S (from the last analytic J) must not be combined with a new F
/// until the next analytic J: no fast renewal from the first J by differences until a full
/// J after the interval; before and after it, fast renewals.
#[test]
fn differences_end_the_split_until_the_next_analytic_jacobian() {
    let mut p = Parametric::new(0.0, true);
    p.declines = (0.05, 0.1);
    let steps = renewals(&mut p, tolerances(1e-6));
    let first_fd = steps
        .iter()
        .position(|&(t, nj, _)| t >= 0.05 && nj > 0)
        .expect("a J in the interval");
    let next_analytic = first_fd
        + steps[first_fd..]
            .iter()
            .position(|&(t, nj, _)| t > 0.1 && nj > 0)
            .expect("a full J after the interval");
    let fast_between: u64 = steps[first_fd..next_analytic].iter().map(|s| s.2).sum();
    let fast_before: u64 = steps[..first_fd].iter().map(|s| s.2).sum();
    let fast_after: u64 = steps[next_analytic..].iter().map(|s| s.2).sum();
    println!(
        "fast renewals before {fast_before}, with differences {fast_between} ({} steps), \
         after {fast_after}",
        next_analytic - first_fd
    );
    assert_eq!(fast_between, 0);
    assert!(next_analytic - first_fd > 10);
    assert!(fast_before > 0 && fast_after > 0);
}

/// A negative `theta_jac` asks for a J after every accepted step (radau5.f's meaning):
/// full ones, also where the problem splits J.
#[test]
fn negative_theta_jac_renews_the_whole_jacobian() {
    let mut p = Parametric::new(0.0, true);
    let options = Options {
        theta_jac: -1.0,
        ..tolerances(1e-6)
    };
    let steps = renewals(&mut p, options);
    let fast: u64 = steps.iter().map(|s| s.2).sum();
    let full: u64 = steps.iter().map(|s| s.1).sum();
    assert_eq!(fast, 0);
    assert!(
        full as usize >= steps.len(),
        "{full} J in {} steps",
        steps.len()
    );
}

/// A fast part that cannot be evaluated ends the step with the problem's error (typed,
/// with t), as a failing J does.
#[test]
fn failing_fast_part_is_a_typed_error() {
    let mut p = Parametric::new(0.0, true);
    p.fast_fails_from = 0.05;
    let mut s = Radau5::new(&mut p, tolerances(1e-6), 0.0, SVector::zeros()).unwrap();
    let e = s.integrate_to(&mut p, T_END).unwrap_err();
    match e {
        Error::Rhs { t, message, .. } => {
            assert!((0.05..0.06).contains(&t), "{t}");
            assert!(message.contains("fast part undefined"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}
