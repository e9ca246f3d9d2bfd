//! `ln` and `exp` written out as branch-free arithmetic, so that the quadrature of law 4
//! can evaluate them for all nodes of a panel in one loop that the compiler vectorises
//! (SSE2, two nodes per instruction, the baseline of every x86-64; no target-specific
//! flags). The library functions are calls that cannot be vectorised and carry checks
//! for arguments the quadrature never passes (zero, negative, subnormal, infinite).
//!
//! Accuracy: a few units in the last place (relative 1e-15 and better, checked against
//! the library in the tests below), far below the 1e-10 the quadrature needs.
//!
//! Method (textbook argument reduction, series written out here):
//! - `ln x = k ln 2 + ln m` with `x = 2^k m`, `m` in [sqrt(1/2), sqrt(2)), and
//!   `ln m = 2 atanh(s) = 2 (s + s^3/3 + s^5/5 + ...)`, `s = (m - 1)/(m + 1)`, |s| <= 0.172:
//!   11 terms leave a truncation below 1e-18.
//! - Both series are summed by Estrin's scheme, whose dependency chain is short.
//! - `exp x = 2^k exp(r)` with `k = round(x / ln 2)`, |r| <= ln 2 / 2, and the Taylor
//!   series of exp(r) to degree 13 (truncation below 1e-17); ln 2 is split into a head
//!   with trailing zero bits (k ln2_hi exact) and a tail.

/// Head of ln 2 with 11 trailing zero bits (k ln2_hi is exact for |k| < 2^11).
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
/// ln 2 - LN2_HI.
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
/// 1.5 * 2^52: adding it rounds to an integer held in the low bits of the mantissa.
const ROUND_MAGIC: f64 = 6_755_399_441_055_744.0;

/// Natural logarithm for positive normal finite x (the quadrature floors its arguments
/// away from zero; other arguments give meaningless results, not a panic).
#[inline(always)]
pub(crate) fn ln(x: f64) -> f64 {
    let bits = x.to_bits();
    // Biased so that the exponent field of (bits + shift) is k + 1023 with m in
    // [sqrt(1/2), sqrt(2)): shift = bits(1.0) - bits(sqrt(1/2)).
    let kb = bits.wrapping_add(0x3ff0_0000_0000_0000 - 0x3fe6_a09e_667f_3bcd) >> 52;
    let m = f64::from_bits(
        bits.wrapping_sub(kb << 52)
            .wrapping_add(0x3ff0_0000_0000_0000),
    );
    // k + 1023 as a float without an integer conversion (none is vectorised in SSE2).
    let k = f64::from_bits(kb | 0x4330_0000_0000_0000) - (4_503_599_627_370_496.0 + 1023.0);
    let f = m - 1.0;
    let s = f / (2.0 + f);
    let s2 = s * s;
    // 1/3 + s2/5 + ... + s2^9/21 by Estrin's scheme (pairs, then powers of s2): four
    // dependent multiplications deep instead of nine (the latency is what limits).
    let s4 = s2 * s2;
    let s8 = s4 * s4;
    let q0 = 1.0 / 3.0 + s2 * (1.0 / 5.0);
    let q1 = 1.0 / 7.0 + s2 * (1.0 / 9.0);
    let q2 = 1.0 / 11.0 + s2 * (1.0 / 13.0);
    let q3 = 1.0 / 15.0 + s2 * (1.0 / 17.0);
    let q4 = 1.0 / 19.0 + s2 * (1.0 / 21.0);
    let p = (q0 + s4 * q1) + s8 * ((q2 + s4 * q3) + s8 * q4);
    let ln_m = 2.0 * s + 2.0 * s * s2 * p;
    k * LN2_HI + (k * LN2_LO + ln_m)
}

/// Exponential for x <= 700 (clamped there); 0 below -700 (exp(-700) = 1e-304, which
/// the quadrature never needs to resolve), so that exp(-inf) = 0 as for the library.
#[inline(always)]
pub(crate) fn exp(x: f64) -> f64 {
    let below = x < -700.0;
    let x = x.clamp(-700.0, 700.0);
    let t = x * std::f64::consts::LOG2_E + ROUND_MAGIC;
    let k = t - ROUND_MAGIC;
    let r = (x - k * LN2_HI) - k * LN2_LO;
    // sum_{j <= 13} r^j / j! by Estrin's scheme (as in `ln`).
    let r2 = r * r;
    let r4 = r2 * r2;
    let r8 = r4 * r4;
    let q0 = 1.0 + r;
    let q1 = 0.5 + r * (1.0 / 6.0);
    let q2 = 1.0 / 24.0 + r * (1.0 / 120.0);
    let q3 = 1.0 / 720.0 + r * (1.0 / 5_040.0);
    let q4 = 1.0 / 40_320.0 + r * (1.0 / 362_880.0);
    let q5 = 1.0 / 3_628_800.0 + r * (1.0 / 39_916_800.0);
    let q6 = 1.0 / 479_001_600.0 + r * (1.0 / 6_227_020_800.0);
    let p = ((q0 + r2 * q1) + r4 * (q2 + r2 * q3)) + r8 * ((q4 + r2 * q5) + r4 * q6);
    // 2^k: k sits in the low bits of t; shifted into the exponent field of p.
    let e = f64::from_bits(p.to_bits().wrapping_add(t.to_bits() << 52));
    if below {
        0.0
    } else {
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the library over the ranges the quadrature uses (and beyond), relative.
    #[test]
    fn ln_and_exp_match_the_library() {
        let mut worst_ln: f64 = 0.0;
        let mut worst_exp: f64 = 0.0;
        let mut u: u64 = 0x9e37_79b9_7f4a_7c15;
        for _ in 0..200_000 {
            u ^= u << 13;
            u ^= u >> 7;
            u ^= u << 17;
            let v = (u >> 11) as f64 / (1u64 << 53) as f64;
            let x = 10f64.powf(-300.0 + 600.0 * v);
            let l = ln(x);
            worst_ln = worst_ln.max((l - x.ln()).abs() / x.ln().abs().max(1.0));
            let e = -699.0 + 1398.0 * v;
            worst_exp = worst_exp.max((exp(e) - e.exp()).abs() / e.exp());
            let e = -3.0 + 6.0 * v;
            worst_exp = worst_exp.max((exp(e) - e.exp()).abs() / e.exp());
        }
        for x in [
            1.0,
            0.5,
            2.0,
            std::f64::consts::FRAC_1_SQRT_2,
            std::f64::consts::SQRT_2,
        ] {
            worst_ln = worst_ln.max((ln(x) - x.ln()).abs());
        }
        println!(
            "batch ln/exp against the library: worst {worst_ln:.1e} (ln), {worst_exp:.1e} (exp)"
        );
        assert!(worst_ln < 1e-15, "ln: {worst_ln:e}");
        assert!(worst_exp < 1e-15, "exp: {worst_exp:e}");
        assert_eq!(exp(f64::NEG_INFINITY), 0.0);
        assert_eq!(exp(-701.0), 0.0);
    }
}
