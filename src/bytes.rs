//! The crate's one byte reader/writer: little-endian primitives ([`Writer`], [`Reader`],
//! used by the FMU state and by the RADAU5 snapshot), and the FMU-state container
//! `magic | version | guid | payload length | payload | checksum` whose reader rejects a
//! foreign or corrupted buffer with a message instead of panicking.

use std::fmt;

/// Magic number at the start of every serialized FMU state ("GRFMUST1").
pub const MAGIC: [u8; 8] = *b"GRFMUST1";
/// Layout version; bump when the payload layout changes.
/// 2: the FMU time (look-ahead) after the last successful time; RADAU5 snapshot v2.
/// 3: `h_fixed` (real-time mode) after the FMU time; the friction law (code 1..=4) and its
///    eight parameters after the filter frequency; after the solver bytes the
///    initialization code, its initial state (non-rest starts) and the validity monitor.
/// 4: the FMI layer's part first (phase, experiment), then the model's (variable count,
///    values, input derivatives, simulation flag and snapshot).
/// 5: after the validity monitor, the contact-line stick mode (flag) and the release sense.
/// 6: `zeta_mesh` in the parameter table, `tooth_contact` after it (elastic contact), and
///    the parameters of the ISO 6336-1 stiffness (`c_gamma`, `h_fP`).
/// 7: the backlash `j_bn` in the parameter table (coast flanks of the elastic contact).
/// 8: 23 state components (the mesh damping's energy before lambda); RADAU5's norm count.
/// 9: after the impact count, the flank (drive/coast) whose line sticks or was released.
/// 10: RADAU5 snapshot v5 (the split Jacobian's slow part and flags, `njac_fast`).
/// 11: after the stick flank, the creep mode of friction laws 1 and 3 (flag).
pub const VERSION: u32 = 11;

/// Why a byte buffer was rejected.
#[derive(Debug, Clone, PartialEq)]
pub struct DecodeError {
    /// What was wrong, for the log.
    pub message: String,
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for DecodeError {}

fn err(message: impl Into<String>) -> DecodeError {
    DecodeError {
        message: message.into(),
    }
}

/// 64-bit FNV-1a; the same small hash build.rs uses for the GUID. Detects corruption
/// (not tampering, which is out of scope for an FMU state).
pub use crate::hash::fnv1a64;

/// Appends little-endian primitives to a buffer.
#[derive(Debug, Default)]
pub struct Writer {
    /// The bytes written so far.
    pub buf: Vec<u8>,
}

impl Writer {
    /// Appends an f64 (bit pattern, so NaN payloads and -0.0 survive).
    pub fn f64(&mut self, x: f64) {
        self.buf.extend_from_slice(&x.to_bits().to_le_bytes());
    }
    /// Appends a u64.
    pub fn u64(&mut self, x: u64) {
        self.buf.extend_from_slice(&x.to_le_bytes());
    }
    /// Appends a u32.
    pub fn u32(&mut self, x: u32) {
        self.buf.extend_from_slice(&x.to_le_bytes());
    }
    /// Appends an i32.
    pub fn i32(&mut self, x: i32) {
        self.buf.extend_from_slice(&x.to_le_bytes());
    }
    /// Appends a byte.
    pub fn u8(&mut self, x: u8) {
        self.buf.push(x);
    }
    /// Appends a bool as one byte.
    pub fn bool(&mut self, x: bool) {
        self.buf.push(u8::from(x));
    }
    /// Appends a length-prefixed byte block.
    pub fn bytes(&mut self, b: &[u8]) {
        self.u64(b.len() as u64);
        self.buf.extend_from_slice(b);
    }
}

/// Reads what [`Writer`] wrote; every read is bounds-checked.
#[derive(Debug)]
pub struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    /// A reader at the start of `buf`.
    pub fn new(buf: &'a [u8]) -> Self {
        Reader { buf, pos: 0 }
    }
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], DecodeError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.buf.len());
        match end {
            Some(e) => {
                let s = &self.buf[self.pos..e];
                self.pos = e;
                Ok(s)
            }
            None => Err(err(format!("truncated while reading {what}"))),
        }
    }
    fn arr<const K: usize>(&mut self, what: &str) -> Result<[u8; K], DecodeError> {
        self.array()
            .ok_or_else(|| err(format!("truncated while reading {what}")))
    }
    /// The next `K` bytes, or None (nothing consumed) if fewer are left: for callers with
    /// error types of their own.
    pub fn array<const K: usize>(&mut self) -> Option<[u8; K]> {
        let s = self.buf.get(self.pos..self.pos.checked_add(K)?)?;
        let mut a = [0u8; K];
        a.copy_from_slice(s);
        self.pos += K;
        Some(a)
    }
    /// Bytes consumed so far.
    pub fn position(&self) -> usize {
        self.pos
    }
    /// Reads an f64.
    ///
    /// # Errors
    /// Truncated buffer.
    pub fn f64(&mut self, what: &str) -> Result<f64, DecodeError> {
        Ok(f64::from_bits(u64::from_le_bytes(self.arr(what)?)))
    }
    /// Reads an f64 that must be finite.
    ///
    /// # Errors
    /// Truncated buffer or a non-finite value.
    pub fn finite(&mut self, what: &str) -> Result<f64, DecodeError> {
        let x = self.f64(what)?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(err(format!("{what} is not finite")))
        }
    }
    /// Reads a u64.
    ///
    /// # Errors
    /// Truncated buffer.
    pub fn u64(&mut self, what: &str) -> Result<u64, DecodeError> {
        Ok(u64::from_le_bytes(self.arr(what)?))
    }
    /// Reads a u32.
    ///
    /// # Errors
    /// Truncated buffer.
    pub fn u32(&mut self, what: &str) -> Result<u32, DecodeError> {
        Ok(u32::from_le_bytes(self.arr(what)?))
    }
    /// Reads an i32.
    ///
    /// # Errors
    /// Truncated buffer.
    pub fn i32(&mut self, what: &str) -> Result<i32, DecodeError> {
        Ok(i32::from_le_bytes(self.arr(what)?))
    }
    /// Reads a bool (byte 0 or 1).
    ///
    /// # Errors
    /// Truncated buffer or another byte value.
    pub fn bool(&mut self, what: &str) -> Result<bool, DecodeError> {
        match self.arr::<1>(what)?[0] {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(err(format!("{what}: bad boolean byte {b}"))),
        }
    }
    /// Reads a length-prefixed byte block.
    ///
    /// # Errors
    /// Truncated buffer.
    pub fn bytes(&mut self, what: &str) -> Result<&'a [u8], DecodeError> {
        let n = self.u64(what)?;
        let n = usize::try_from(n).map_err(|_| err(format!("{what}: length too large")))?;
        self.take(n, what)
    }
    /// Succeeds when every byte has been consumed.
    ///
    /// # Errors
    /// Trailing bytes.
    pub fn finish(&self) -> Result<(), DecodeError> {
        if self.pos == self.buf.len() {
            Ok(())
        } else {
            Err(err(format!("{} trailing bytes", self.buf.len() - self.pos)))
        }
    }
}

/// Wraps a payload: magic, version, GUID, payload length, payload, FNV-1a checksum of
/// everything before the checksum.
pub fn seal(guid: &str, payload: &[u8]) -> Vec<u8> {
    let mut w = Writer::default();
    w.buf.extend_from_slice(&MAGIC);
    w.u32(VERSION);
    w.bytes(guid.as_bytes());
    w.bytes(payload);
    let sum = fnv1a64(&w.buf);
    w.u64(sum);
    w.buf
}

/// Checks a sealed buffer and returns its payload.
///
/// # Errors
/// Wrong magic (foreign buffer), other version, other GUID (another model), wrong
/// length or checksum (corrupted).
pub fn open<'a>(guid: &str, buf: &'a [u8]) -> Result<&'a [u8], DecodeError> {
    if buf.len() < MAGIC.len() + 4 + 8 + 8 + 8 {
        return Err(err(format!(
            "buffer of {} bytes is too short to be a GearedRotor FMU state",
            buf.len()
        )));
    }
    if buf[..8] != MAGIC {
        return Err(err("not a GearedRotor FMU state (wrong magic number)"));
    }
    let body = &buf[..buf.len() - 8];
    let mut sum = [0u8; 8];
    sum.copy_from_slice(&buf[buf.len() - 8..]);
    if fnv1a64(body) != u64::from_le_bytes(sum) {
        return Err(err(
            "checksum mismatch: the serialized FMU state is corrupted",
        ));
    }
    let mut r = Reader::new(&body[8..]);
    let version = r.u32("version")?;
    if version != VERSION {
        return Err(err(format!(
            "serialized FMU state has layout version {version}, this FMU reads {VERSION}"
        )));
    }
    let g = r.bytes("GUID")?;
    if g != guid.as_bytes() {
        return Err(err(format!(
            "serialized FMU state belongs to GUID {}, this FMU is {guid}",
            String::from_utf8_lossy(g)
        )));
    }
    let payload = r.bytes("payload")?;
    r.finish()?;
    Ok(payload)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seal_open_round_trip_and_rejections() {
        let sealed = seal("{g}", b"hello");
        assert_eq!(open("{g}", &sealed).unwrap(), b"hello");
        assert!(open("{h}", &sealed).unwrap_err().message.contains("GUID"));
        for i in 0..sealed.len() {
            let mut bad = sealed.clone();
            bad[i] ^= 0x40;
            assert!(open("{g}", &bad).is_err(), "flip at byte {i} accepted");
        }
        assert!(open("{g}", &sealed[..sealed.len() - 1]).is_err());
        assert!(open("{g}", &[]).is_err());
    }
}
