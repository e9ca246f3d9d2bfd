//! Short numbers for messages: Rust's `{}` of an f64 prints every digit of its decimal
//! expansion (1e300 becomes 301 characters, 1e-300 a run of 300 zeros). [`Short`] prints
//! the shortest representation that reads back to the same f64 (at most 17 significant
//! digits), plainly for magnitudes in [1e-4, 1e16) and in exponent notation otherwise.

use std::fmt;

/// Display wrapper: `format!("{}", Short(x))`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Short(pub f64);

impl fmt::Display for Short {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        let a = x.abs();
        if !x.is_finite() || a == 0.0 || (1e-4..1e16).contains(&a) {
            // Shortest round-trip digits; no exponent needed in this range (at most 16
            // integer digits, at most 4 leading zeros).
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Short;

    #[test]
    fn short_forms() {
        let s = |x: f64| Short(x).to_string();
        assert_eq!(s(1e300), "1e300");
        assert_eq!(s(-1e-300), "-1e-300");
        assert_eq!(s(f64::MAX), "1.7976931348623157e308");
        assert_eq!(s(f64::MIN_POSITIVE), "2.2250738585072014e-308");
        assert_eq!(s(5e-324), "5e-324");
        assert_eq!(s(314.159), "314.159");
        assert_eq!(s(0.05), "0.05");
        assert_eq!(s(1e-4), "0.0001");
        assert_eq!(s(1e16), "1e16");
        assert_eq!(s(0.0), "0");
        assert_eq!(s(f64::NAN), "NaN");
        assert_eq!(s(f64::NEG_INFINITY), "-inf");
        // Every finite value reads back exactly and has at most 17 significant digits.
        let mut x = 1.234_567_890_123_46e-310;
        while x < 1e308 {
            for v in [x, -x, x * 0.1 + 1.0 / 3.0] {
                let t = s(v);
                assert_eq!(t.parse::<f64>().unwrap(), v, "{t}");
                let mantissa = t.split('e').next().unwrap();
                let digits = mantissa
                    .chars()
                    .filter(char::is_ascii_digit)
                    .collect::<String>();
                let significant = digits.trim_start_matches('0');
                assert!(significant.len() <= 17, "{t}");
                assert!(t.len() <= 24, "{t}");
            }
            x *= 7.77;
        }
    }
}
