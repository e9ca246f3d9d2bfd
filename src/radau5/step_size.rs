//! The one non-elementary operation of the step-size controller: `x^0.25`.
//!
//! radau5.f computes the step-size factor as `ERR**0.25D0` and the Gustafsson factor as
//! `(ERR**2/ERRACC)**0.25D0` (`RADCOR`, after the error estimate). gfortran at -O2 without
//! fast-math compiles a real exponent to a call of the C library's `pow` (only
//! `-funsafe-math-optimizations` would turn `x**0.25` into two square roots); Rust's
//! `f64::powf` lowers to the same `pow`. On glibc that `pow` is the correctly rounded one
//! in practice (glibc 2.28+, worst error 0.52 ulp), so ours rounds exactly as the
//! Fortran's on the same machine. `sqrt(sqrt(x))` rounds twice: it differs from `pow` by one
//! ulp for about an eighth of the arguments (test below), and a one-ulp difference in h can
//! flip a later accept/reject or Jacobian-reuse decision of a sensitive problem.

/// `x^0.25` exactly as radau5.f's `x**0.25D0` (libm `pow`), for `x >= 0`.
#[inline]
pub(super) fn quarter_power(x: f64) -> f64 {
    x.powf(0.25)
}

#[cfg(test)]
mod tests {
    use super::quarter_power;
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
}
