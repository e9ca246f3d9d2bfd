//! A right-hand side that overflows inside the simplified Newton iteration: the counters
//! follow radau5.f's rule (docs/radau5.md §7, "non-finite f").
//!
//! radau5.f has no finiteness check. In every Newton iteration it calls FCN at the three
//! stages (NFCN += 3), solves (NSOL += 1), computes DYNO, and only then tests convergence;
//! from the second iteration on an infinite or NaN f makes DYNO non-finite, THETA is then
//! not < 0.99 and it jumps to label 78: h halved, an unexpected rejection (not counted in
//! NREJCT). So the expected counters follow from the calls the problem itself saw,
//! independently of the stepper's bookkeeping: every call of f is one NFCN; the calls that
//! are Newton stages come in triples at `x + c1 h`, `x + c2 h`, `x + h`, one NSOL each, also
//! the triple in which f overflowed; the next attempt starts from the same x with h/2.

use geared_rotor::radau5::{Options, Problem, Radau5, RhsError, Tolerance};
use nalgebra::{SMatrix, SVector};

/// y' = y, y(0) = 1, except that f overflows (a genuine floating-point overflow to inf)
/// wherever |y| > `y_cliff`. Records every call: (t, f came out non-finite).
struct Overflowing {
    y_cliff: f64,
    calls: Vec<(f64, bool)>,
}

impl Problem<1> for Overflowing {
    fn rhs(
        &mut self,
        t: f64,
        y: &SVector<f64, 1>,
        f: &mut SVector<f64, 1>,
    ) -> Result<(), RhsError> {
        f[0] = y[0];
        if y[0].abs() > self.y_cliff {
            let big = std::hint::black_box(1e200);
            f[0] *= big * big; // overflows to +-inf
        }
        self.calls.push((t, !f[0].is_finite()));
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        _y: &SVector<f64, 1>,
        j: &mut SMatrix<f64, 1, 1>,
    ) -> Result<bool, RhsError> {
        j[(0, 0)] = 1.0;
        Ok(true)
    }
}

/// Radau IIA (order 5) coefficients, Hairer & Wanner, Solving ODEs II (1996), Table 5.6.
fn radau_iia() -> ([[f64; 3]; 3], [f64; 3]) {
    let s = 6.0f64.sqrt();
    let a = [
        [
            (88.0 - 7.0 * s) / 360.0,
            (296.0 - 169.0 * s) / 1800.0,
            (-2.0 + 3.0 * s) / 225.0,
        ],
        [
            (296.0 + 169.0 * s) / 1800.0,
            (88.0 + 7.0 * s) / 360.0,
            (-2.0 - 3.0 * s) / 225.0,
        ],
        [(16.0 - s) / 36.0, (16.0 + s) / 36.0, 1.0 / 9.0],
    ];
    (a, [(4.0 - s) / 10.0, (4.0 + s) / 10.0, 1.0])
}

/// Stage values after the first simplified Newton iteration from zero on y' = lambda y
/// (linear, exact Jacobian): Y = (I - lambda h A)^-1 y0 (Cramer's rule).
fn first_iterate(lambda_h: f64, y0: f64) -> [f64; 3] {
    let (a, _) = radau_iia();
    let m: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| f64::from(u8::from(i == j)) - lambda_h * a[i][j])
    });
    let det = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(&m);
    std::array::from_fn(|k| {
        let mut mk = m;
        for row in &mut mk {
            row[k] = y0;
        }
        det(&mk) / d
    })
}

/// One Newton iteration's three calls, or a single call (f at the new point, or the error
/// estimate's extra f at the step's start).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Call {
    /// (h of the attempt, iteration number within the attempt, f non-finite in one of the
    /// three calls).
    Iteration(f64, u32, bool),
    Single,
}

/// Splits the calls of one `step` from x into stage triples (t = x + c1 h, x + c2 h,
/// x + h) and single calls (t = x, or t = x + h of the triple before).
fn classify(calls: &[(f64, bool)], x: f64) -> Vec<Call> {
    let (_, c) = radau_iia();
    let mut out: Vec<Call> = Vec::new();
    let mut i = 0;
    let mut prev_end = f64::NAN;
    while i < calls.len() {
        let t = calls[i].0;
        if t == x || t == prev_end {
            out.push(Call::Single);
            i += 1;
            continue;
        }
        assert!(
            i + 2 < calls.len(),
            "incomplete stage triple at {i}: {calls:?}"
        );
        let (ta, tb, tc) = (calls[i].0, calls[i + 1].0, calls[i + 2].0);
        let h = tc - x;
        assert!(
            ((ta - x) / h - c[0]).abs() < 1e-9 && ((tb - x) / h - c[1]).abs() < 1e-9,
            "calls {i}.. are not a stage triple: {ta} {tb} {tc} from x = {x}"
        );
        let newt = match out.last() {
            Some(&Call::Iteration(hp, k, _)) if ((hp - h) / h).abs() < 1e-12 => k + 1,
            _ => 1,
        };
        let nonfinite = calls[i].1 || calls[i + 1].1 || calls[i + 2].1;
        out.push(Call::Iteration(h, newt, nonfinite));
        prev_end = tc;
        i += 3;
    }
    out
}

#[test]
fn overflow_in_the_second_newton_iteration_counts_as_in_radau5_f() {
    let (h0, y_cliff, t_end): (f64, f64, f64) = (3.6, 100.0, 4.0);
    // Independent prediction: the first attempt (h0, Newton from zero) evaluates f at y0 in
    // its first iteration, then at the stage values Y(h0) of the linear collocation
    // solution; 122.8 and 482.5 lie above the cliff, so f overflows in iteration 2 (where
    // radau5.f has its THETA test). At h0/2 all stage values lie below it.
    let y_first = first_iterate(h0, 1.0);
    assert!(y_first.iter().any(|v| v.abs() > y_cliff), "{y_first:?}");
    assert!(first_iterate(h0 / 2.0, 1.0)
        .iter()
        .all(|v| v.abs() < y_cliff));
    assert!(
        t_end.exp() < y_cliff,
        "the solution itself stays below the cliff"
    );

    let tol = 1e-6;
    let opts = Options::<1> {
        rtol: Tolerance::Scalar(tol),
        atol: Tolerance::Scalar(tol),
        h_init: h0,
        ..Options::default()
    };
    let nit = opts.max_newton;
    let mut p = Overflowing {
        y_cliff,
        calls: Vec::new(),
    };
    let mut s = Radau5::new(&mut p, opts, 0.0, SVector::<f64, 1>::new(1.0)).unwrap();
    assert_eq!(s.stats().nfcn, p.calls.len() as u64);
    let mut events = Vec::new();
    let mut first_segment = Vec::new();
    while s.t() < t_end {
        let x = s.t();
        let before = *s.stats();
        let first_call = p.calls.len();
        s.step(&mut p, t_end)
            .expect("the step succeeds after halving");
        let after = *s.stats();
        let seg = classify(&p.calls[first_call..], x);
        // Every call of f is one NFCN, every stage triple one NSOL (radau5.f's rule).
        assert_eq!(
            after.nfcn - before.nfcn,
            (p.calls.len() - first_call) as u64
        );
        let iterations = seg
            .iter()
            .filter(|c| matches!(c, Call::Iteration(..)))
            .count();
        assert_eq!(after.nsol - before.nsol, iterations as u64);
        for (k, call) in seg.iter().enumerate() {
            if let &Call::Iteration(h, newt, true) = call {
                events.push((x, h, newt));
                // Label 78: the next attempt starts from the same x with h/2.
                match seg.get(k + 1) {
                    Some(&Call::Iteration(h_next, 1, _)) => {
                        assert!((h_next / h - 0.5).abs() < 1e-12, "h {h} -> {h_next}")
                    }
                    other => panic!("after an overflow at x = {x}: {other:?}"),
                }
            }
        }
        if x == 0.0 {
            first_segment = seg;
        }
    }
    // The predicted overflow, and no other: iteration 2 of the first attempt.
    assert_eq!(events, vec![(0.0, h0, 2)]);
    assert!(events.iter().all(|&(_, _, newt)| newt > 1 && newt < nit));
    assert_eq!(
        first_segment[..3],
        [
            Call::Iteration(h0, 1, false),
            Call::Iteration(h0, 2, true),
            Call::Iteration(h0 / 2.0, 1, false)
        ]
    );
    // The unexpected rejection is not a rejection in NREJCT (no step accepted yet anyway).
    let y_end = s.y()[0];
    assert!(
        (y_end / t_end.exp() - 1.0).abs() < 1e-4,
        "y({t_end}) = {y_end}"
    );
}

/// Our deliberate difference: f non-finite already in the first Newton iteration. radau5.f
/// has no convergence test there and would carry the NaN on into the error estimate; here
/// the attempt is rejected like in the later iterations (3 f calls and the solve counted,
/// h halved), and 10 such rejections in a row end the step with `Error::NonFinite`.
#[test]
fn non_finite_f_in_the_first_iteration_is_rejected_after_counting() {
    // f(t0, y0 = 1) is finite at construction; then the cliff is lowered below y0, so the
    // first iteration of every attempt (stages at y0, Newton from zero) overflows.
    let mut p = Overflowing {
        y_cliff: 2.0,
        calls: Vec::new(),
    };
    let opts = Options::<1> {
        h_init: 0.1,
        ..Options::default()
    };
    let mut s = Radau5::new(&mut p, opts, 0.0, SVector::<f64, 1>::new(1.0)).unwrap();
    p.y_cliff = 0.5;
    let r = s.step(&mut p, 1.0);
    assert!(
        matches!(r, Err(geared_rotor::radau5::Error::NonFinite { .. })),
        "{r:?}"
    );
    // 1 call at construction, then 10 attempts of 3 calls and one solve each.
    assert_eq!(p.calls.len(), 1 + 10 * 3);
    assert_eq!(s.stats().nfcn, 1 + 10 * 3);
    assert_eq!(s.stats().nsol, 10);
    let hs: Vec<f64> = p.calls[1..]
        .chunks(3)
        .map(|c| c[2].0) // x + h with x = 0
        .collect();
    for w in hs.windows(2) {
        assert_eq!(w[1], w[0] * 0.5);
    }
}
