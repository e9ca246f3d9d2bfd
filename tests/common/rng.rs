//! A small deterministic random generator for the randomised tests: SplitMix64
//! (Steele, Lea, Flood 2014), independent of any crate so that a seed always gives the same
//! states.

/// SplitMix64 state; `Rng(seed)`.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1) with 53 random bits.
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [-a, a).
    pub fn sym(&mut self, a: f64) -> f64 {
        a * (2.0 * self.next() - 1.0)
    }

    /// Log-uniform in [10^lo, 10^hi).
    pub fn log(&mut self, lo: f64, hi: f64) -> f64 {
        10f64.powf(lo + (hi - lo) * self.next())
    }

    /// -1 or +1 with equal probability.
    pub fn sign(&mut self) -> f64 {
        if self.next() < 0.5 {
            -1.0
        } else {
            1.0
        }
    }
}
