//! 64-bit FNV-1a (Fowler, Noll & Vo), the one small non-cryptographic hash of the crate.
//!
//! Used for the checksums that seal an FMU state and a RADAU5 snapshot (they detect
//! corruption, not tampering) and, by `build.rs`, for the GUID derived from the model
//! description. `build.rs` includes this file with `#[path]`, so it depends on nothing.

/// The FNV-1a 64-bit offset basis.
pub const OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;

/// The FNV 64-bit prime.
const PRIME: u64 = 0x0000_0100_0000_01b3;

/// 64-bit FNV-1a of `bytes` with the standard offset basis.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    fnv1a64_with_basis(bytes, OFFSET_BASIS)
}

/// 64-bit FNV-1a of `bytes` started from `basis` instead of the standard offset basis
/// (two different bases give two independent 64-bit words, as the GUID needs).
pub fn fnv1a64_with_basis(bytes: &[u8], basis: u64) -> u64 {
    let mut h = basis;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(PRIME);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv_reference_values() {
        // Published FNV-1a 64 test vectors (Fowler/Noll/Vo): "" and "a".
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn with_basis_of_the_offset_basis_is_the_standard_hash() {
        for s in [&b""[..], b"a", b"foobar"] {
            assert_eq!(fnv1a64_with_basis(s, OFFSET_BASIS), fnv1a64(s));
        }
        // Published vector for "foobar".
        assert_eq!(fnv1a64(b"foobar"), 0x8594_4171_f739_67e8);
    }
}
