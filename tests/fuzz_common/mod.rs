//! What the FMI 2.0 and FMI 3.0 fuzzers share: the seeded generator, the hang limit, the
//! random values for a variable, the checks of a returned message, and the mutation and
//! resealing of serialized states. Included by `tests/fuzz_fmi2/driver.rs` and
//! `tests/fuzz_fmi3/driver.rs`.

use geared_rotor::fmi2::variables::{Causality, Variability, Variable};
use std::time::Duration;

/// A call that takes longer than this counts as a hang.
pub const CALL_LIMIT: Duration = Duration::from_secs(2);

/// Most internal steps per doStep the fuzzer allows (parameter max_internal_steps): the
/// default, 50 000, took up to 2.4 s of wall time on the shared 2-core VM under load,
/// which a hang detector of 2 s cannot tell from a hang. 5 000 took at most 0.3 s.
pub const MAX_WORK: usize = 5_000;

/// SplitMix64 (Steele, Lea, Flood 2014): the same seed gives the same run.
pub struct Rng(pub u64);

impl Rng {
    pub fn u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn f(&mut self) -> f64 {
        (self.u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.u64() % n.max(1) as u64) as usize
    }
    pub fn chance(&mut self, p: f64) -> bool {
        self.f() < p
    }
    pub fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }
    pub fn log(&mut self, lo: f64, hi: f64) -> f64 {
        10f64.powf(lo + (hi - lo) * self.f())
    }
}

/// Whether `m` holds a number of more than 17 significant digits (runs of digits and
/// points; leading zeros do not count).
pub fn has_long_number(m: &str) -> bool {
    m.split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .any(|d| d.replace('.', "").trim_start_matches('0').len() > 17)
}

pub fn comm_tolerance(t: f64, h: f64) -> f64 {
    1e-8 * h.abs() + 16.0 * f64::EPSILON * t.abs()
}

/// A Real value for `v`: mostly plausible, sometimes at or beyond its bounds, sometimes
/// special.
pub fn real_value(rng: &mut Rng, v: &Variable) -> f64 {
    let start = v.start.unwrap_or(1.0);
    match rng.below(10) {
        0 => *rng.pick(&[
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MAX,
            -f64::MAX,
            1e300,
            -1e300,
            1e-300,
            0.0,
            -0.0,
            5e-324,
        ]),
        1 => v.min.unwrap_or(-1e30),
        2 => v.max.unwrap_or(1e30),
        3 => v
            .min
            .map_or(-1e40, |m| m - m.abs().max(1.0) * rng.log(-6.0, 3.0)),
        4 => v
            .max
            .map_or(1e40, |m| m + m.abs().max(1.0) * rng.log(-6.0, 3.0)),
        5 => -start,
        _ => start * (1.0 + 0.5 * (2.0 * rng.f() - 1.0)),
    }
}

pub fn out_of_declared(v: &Variable, x: f64) -> bool {
    v.min.is_some_and(|m| x < m) || v.max.is_some_and(|m| x > m)
}

/// Variables whose declared bounds are checked at the set (inputs and tunables: the new
/// value reaches the running model at once).
pub fn bounds_checked_at_set(v: &Variable) -> bool {
    v.causality == Causality::Input || v.variability == Variability::Tunable
}

pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// Recomputes the checksums of the RADAU5 snapshot inside the blob and of the blob.
pub fn reseal(blob: &mut [u8], snapshot_len: usize) {
    if let Some(s) = blob.windows(8).position(|w| w == b"RADAU5SN") {
        if s + snapshot_len <= blob.len() {
            let sum = fnv1a(&blob[s..s + snapshot_len - 8]);
            blob[s + snapshot_len - 8..s + snapshot_len].copy_from_slice(&sum.to_le_bytes());
        }
    }
    let m = blob.len();
    if m >= 8 {
        let sum = fnv1a(&blob[..m - 8]);
        blob[m - 8..].copy_from_slice(&sum.to_le_bytes());
    }
}

pub fn mutate(rng: &mut Rng, blob: &mut [u8]) {
    let n = blob.len();
    match rng.below(5) {
        0 => {
            let i = rng.below(n);
            blob[i] ^= 1 << rng.below(8);
        }
        1 | 2 => {
            let x: f64 = *rng.pick(&[
                f64::NAN,
                f64::INFINITY,
                -f64::INFINITY,
                0.0,
                -0.0,
                1e300,
                -1e300,
                1e-300,
                -1.0,
                f64::MAX,
                5e-324,
                1e9,
            ]);
            let i = rng.below(n - 8);
            blob[i..i + 8].copy_from_slice(&x.to_bits().to_le_bytes());
        }
        3 => {
            let k = 1 + rng.below(16);
            let i = rng.below(n - k);
            for b in &mut blob[i..i + k] {
                *b = rng.u64() as u8;
            }
        }
        _ => {
            // Scale an existing f64 at a random position (a plausible-looking wrong value).
            let i = rng.below(n - 8);
            let x = f64::from_le_bytes(blob[i..i + 8].try_into().unwrap());
            let y = x * *rng.pick(&[-1.0, 2.0, 0.5, 1e3, 1e-3, 1.0 + 1e-9]);
            blob[i..i + 8].copy_from_slice(&y.to_bits().to_le_bytes());
        }
    }
}
