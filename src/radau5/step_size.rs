//! The one non-elementary operation of the step-size controller: `x^0.25`.
//!
//! radau5.f computes the step-size factor as `ERR**0.25D0` and the Gustafsson factor as
//! `(ERR**2/ERRACC)**0.25D0` (`RADCOR`, after the error estimate). gfortran at -O2 without
//! fast-math compiles a real exponent to a call of the C library's `pow` (only
//! `-funsafe-math-optimizations` would turn `x**0.25` into two square roots); Rust's
//! `f64::powf` lowers to the same `pow` (glibc 2.28+: nearly correctly rounded, worst
//! error about 0.52 ulp), so ours rounds exactly as the
//! Fortran's on the same machine. `sqrt(sqrt(x))` rounds twice: it differs from `pow` by one
//! ulp for about an eighth of the arguments (test below), and a one-ulp difference in h can
//! flip a later accept/reject or Jacobian-reuse decision of a sensitive problem.

/// `x^0.25` exactly as radau5.f's `x**0.25D0` (libm `pow`), for `x >= 0`.
#[inline]
pub(super) fn quarter_power(x: f64) -> f64 {
    x.powf(0.25)
}

/// Relative margin by which an estimate of `x^0.25` must clear a decision before the
/// decision is taken without `pow`. `pow` (glibc: about 0.52 ulp at worst) and two correctly
/// rounded square roots (below 1 ulp together) differ by at most a few ulps, ~1e-15
/// relative; 1e-12 leaves room for the division and multiplications around them.
const DECIDED: f64 = 1e-12;

/// `quot = max(facr, min(facl, err^0.25/fac))`, radau5.f's
/// `QUOT=MAX(FACR,MIN(FACL,ERR**.25D0/FAC))`, for finite `err > 0`.
///
/// When the clamp decides the value (a clearly small or large error), two square roots
/// are enough to know it and `pow` is skipped; the result is the clamp bound, bit for bit
/// the same as with `pow`. Otherwise `pow` as the Fortran.
#[inline]
pub(super) fn step_quotient(err: f64, fac: f64, facr: f64, facl: f64) -> f64 {
    let estimate = err.sqrt().sqrt() / fac;
    if estimate < facr * (1.0 - DECIDED) {
        return facr;
    }
    if estimate > facl * (1.0 + DECIDED) {
        return facl;
    }
    facr.max(facl.min(quarter_power(err) / fac))
}

/// The predictive controller of Gustafsson in radau5.f:
/// `FACGUS=(HACC/H)*(ERR**2/ERRACC)**0.25D0/SAFE`, `FACGUS=MAX(FACR,MIN(FACL,FACGUS))`,
/// `QUOT=MAX(QUOT,FACGUS)`; returns the new `quot` (`facr <= quot <= facl` on entry).
///
/// `pow` is skipped when two square roots already show that `quot` stays (the predicted
/// factor is clearly smaller) or that `facl` wins; the result is then bit for bit the
/// one with `pow`.
#[inline]
#[allow(clippy::too_many_arguments)] // the Fortran's eight scalars, named as there
pub(super) fn gustafsson_quotient(
    quot: f64,
    h_acc: f64,
    h: f64,
    err: f64,
    err_acc: f64,
    safe: f64,
    facr: f64,
    facl: f64,
) -> f64 {
    let x = err * err / err_acc;
    let ratio = h_acc / h;
    let estimate = ratio * x.sqrt().sqrt() / safe;
    if estimate < quot * (1.0 - DECIDED) {
        return quot;
    }
    if estimate > facl * (1.0 + DECIDED) {
        return quot.max(facl);
    }
    let facgus = facr.max(facl.min(ratio * quarter_power(x) / safe));
    quot.max(facgus)
}

#[cfg(test)]
mod tests {
    use super::{gustafsson_quotient, quarter_power, step_quotient};
    use std::hint::black_box;

    extern "C" {
        /// The C library's `pow`, the function gfortran's `x**0.25D0` calls.
        fn pow(x: f64, y: f64) -> f64;
    }

    /// Deterministic log-uniform arguments over the range the controller sees
    /// (`err` is clamped below at 1e-10; `err^2/err_acc` reaches 1e-20 .. 1e8).
    fn arguments(n: usize) -> impl Iterator<Item = f64> {
        let mut s: u64 = 0x2545_f491_4f6c_dd1d;
        (0..n).map(move |_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            10f64.powf(-20.0 + 28.0 * u)
        })
    }

    #[test]
    fn quarter_power_is_libm_pow_as_in_radau5_f() {
        let n = 200_000;
        let mut differs_from_sqrt_sqrt = 0usize;
        for x in arguments(n) {
            let x = black_box(x);
            // The exponent through black_box: the reference call can not be rewritten by
            // the compiler into anything but the library call.
            let reference = unsafe { pow(x, black_box(0.25)) };
            let ours = quarter_power(x);
            assert_eq!(
                ours.to_bits(),
                reference.to_bits(),
                "x = {x:e}: ours {ours:e}, libm pow {reference:e}"
            );
            let two_roots = x.sqrt().sqrt();
            if two_roots.to_bits() != reference.to_bits() {
                differs_from_sqrt_sqrt += 1;
                // Never more than one ulp apart: both are good approximations.
                assert!(two_roots.to_bits().abs_diff(reference.to_bits()) <= 1);
            }
        }
        // The test can tell the two operations apart: two square roots differ on a
        // measurable fraction of these arguments (12-13 % here).
        let fraction = differs_from_sqrt_sqrt as f64 / n as f64;
        assert!(
            (0.05..0.25).contains(&fraction),
            "sqrt(sqrt) differs from pow on {fraction:.3} of the arguments"
        );
    }

    #[test]
    fn quarter_power_on_exact_fourth_powers() {
        // Exact cases: the controller's clamps facr/facl see these.
        for (x, r) in [
            (1.0, 1.0),
            (16.0, 2.0),
            (0.0625, 0.5),
            (1e-8, 1e-2),
            (0.0, 0.0),
        ] {
            assert_eq!(quarter_power(x), r, "{x}");
        }
    }

    /// The formulas exactly as radau5.f writes them, `pow` every time.
    fn fortran_quot(err: f64, fac: f64, facr: f64, facl: f64) -> f64 {
        facr.max(facl.min(unsafe { pow(err, 0.25) } / fac))
    }

    #[allow(clippy::too_many_arguments)]
    fn fortran_gustafsson(
        quot: f64,
        h_acc: f64,
        h: f64,
        err: f64,
        err_acc: f64,
        safe: f64,
        facr: f64,
        facl: f64,
    ) -> f64 {
        let facgus = (h_acc / h) * unsafe { pow(err * err / err_acc, 0.25) } / safe;
        quot.max(facr.max(facl.min(facgus)))
    }

    /// The shortcuts never change a bit: random arguments over the whole range, and
    /// arguments a few ulps around each clamp boundary.
    #[test]
    fn shortcuts_equal_the_fortran_formulas() {
        let (safe, facr, facl): (f64, f64, f64) = (0.9, 0.125, 5.0);
        let mut xs = arguments(500_000);
        let mut next = move || xs.next().unwrap();
        for k in 0..100_000u32 {
            let err = next().max(1e-10);
            // fac = min(safe, safe (1 + 2 nit)/(newt + 2 nit)), nit = 7, newt = 1..7
            let fac = safe.min(safe * 15.0 / f64::from(14 + 1 + k % 7));
            let q = step_quotient(err, fac, facr, facl);
            assert_eq!(
                q.to_bits(),
                fortran_quot(err, fac, facr, facl).to_bits(),
                "{err:e}"
            );
            let (h_acc, h, err_acc) = (next() * 1e10, next() * 1e10, next().max(1e-2));
            assert_eq!(
                gustafsson_quotient(q, h_acc, h, err, err_acc, safe, facr, facl).to_bits(),
                fortran_gustafsson(q, h_acc, h, err, err_acc, safe, facr, facl).to_bits(),
                "{err:e} {h_acc:e} {h:e} {err_acc:e}"
            );
        }
        // err at the clamp boundaries (facr fac)^4 and (facl fac)^4, +- 64 ulps.
        let fac = safe;
        for bound in [facr * fac, facl * fac] {
            let e0 = bound.powi(4);
            for k in -64i64..=64 {
                let err = f64::from_bits((e0.to_bits() as i64 + k) as u64);
                assert_eq!(
                    step_quotient(err, fac, facr, facl).to_bits(),
                    fortran_quot(err, fac, facr, facl).to_bits(),
                    "{err:e}"
                );
                // Gustafsson boundaries: h_acc/h chosen so the factor sits at quot / facl.
                for target in [0.5, bound / fac, facl] {
                    let ratio = target * safe / quarter_power(err * err / 0.37);
                    let q = 0.5;
                    assert_eq!(
                        gustafsson_quotient(q, ratio, 1.0, err, 0.37, safe, facr, facl).to_bits(),
                        fortran_gustafsson(q, ratio, 1.0, err, 0.37, safe, facr, facl).to_bits(),
                        "{err:e} {ratio:e}"
                    );
                }
            }
        }
    }
}
