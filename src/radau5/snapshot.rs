//! Complete, plain-data snapshot of the solver state and its byte layout (radau5.md §8).
//!
//! Layout (all little-endian): magic `b"RADAU5SN"`, `u32` version, `u32` N, `u64` payload
//! length, payload, `u64` FNV-1a checksum over everything before it. The payload lists
//! every field of the state in a fixed order: `f64` as IEEE bits, `u64`/`u32` counters,
//! `u8` flags and enums, matrices column-major.

use nalgebra::{Complex, SMatrix, SVector};

use super::options::Params;
use super::state::{Action, State};
use super::stepper::Radau5;
use super::{SnapshotError, Statistics};
use crate::bytes::{fnv1a64, Reader, Writer};

const MAGIC: [u8; 8] = *b"RADAU5SN";
/// 2: `y_prev`, `f_prev` (for `Radau5::retake`) after `t_prev`.
/// 3: `resume_after_stop` after `quot2`.
/// 4: `norm_count` after `resume_after_stop`.
/// 5: the split Jacobian (`jac_slow`, `split`, `calfast`, `theta_full`, `fast_stale` after
/// `jac_valid`;
/// `njac_fast` after `njac`; action 3).
const VERSION: u32 = 5;
const HEADER_LEN: usize = 8 + 4 + 4 + 8;
const CHECKSUM_LEN: usize = 8;

/// A copy of the complete solver state; [`Radau5::restore`] continues bit-identically.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot<const N: usize> {
    pub(crate) state: State<N>,
}

impl<const N: usize> Radau5<N> {
    /// Copies the complete state (h, J, both LUs with pivots, FACCON, error history,
    /// dense output, counters, flags, options).
    pub fn snapshot(&self) -> Snapshot<N> {
        Snapshot {
            state: self.st.clone(),
        }
    }

    /// Continues from a snapshot as if the steps since it had never been taken.
    pub fn restore(&mut self, s: &Snapshot<N>) {
        self.st = s.state.clone();
        self.pattern = super::linear_systems::MassPattern::new(&self.st.mass);
        // J and the LU pair travel together in the state; the packed blocks follow J.
        if !self.blocks.full() {
            self.blocks.pack(&self.st.jac, &mut self.elim);
        }
    }
}

/// Sequential writer/reader of the payload; the same field order is used both ways by
/// [`visit`], so the two can not drift apart.
pub(super) trait Io {
    fn f64(&mut self, v: &mut f64) -> Result<(), SnapshotError>;
    fn u64(&mut self, v: &mut u64) -> Result<(), SnapshotError>;
    fn u8(&mut self, v: &mut u8) -> Result<(), SnapshotError>;

    fn u32(&mut self, v: &mut u32) -> Result<(), SnapshotError> {
        let mut w = u64::from(*v);
        self.u64(&mut w)?;
        *v = u32::try_from(w).map_err(|_| SnapshotError::InvalidField { name: "u32" })?;
        Ok(())
    }
    fn usize(&mut self, v: &mut usize, name: &'static str) -> Result<(), SnapshotError> {
        let mut w = *v as u64;
        self.u64(&mut w)?;
        *v = usize::try_from(w).map_err(|_| SnapshotError::InvalidField { name })?;
        Ok(())
    }
    fn bool(&mut self, v: &mut bool, name: &'static str) -> Result<(), SnapshotError> {
        let mut w = u8::from(*v);
        self.u8(&mut w)?;
        *v = match w {
            0 => false,
            1 => true,
            _ => return Err(SnapshotError::InvalidField { name }),
        };
        Ok(())
    }
    fn vec<const N: usize>(&mut self, v: &mut SVector<f64, N>) -> Result<(), SnapshotError> {
        for x in v.iter_mut() {
            self.f64(x)?;
        }
        Ok(())
    }
    fn mat<const N: usize>(&mut self, m: &mut SMatrix<f64, N, N>) -> Result<(), SnapshotError> {
        for x in m.iter_mut() {
            self.f64(x)?;
        }
        Ok(())
    }
    fn cmat<const N: usize>(
        &mut self,
        m: &mut SMatrix<Complex<f64>, N, N>,
    ) -> Result<(), SnapshotError> {
        for x in m.iter_mut() {
            self.f64(&mut x.re)?;
            self.f64(&mut x.im)?;
        }
        Ok(())
    }
    fn pivots<const N: usize>(&mut self, ip: &mut [usize; N]) -> Result<(), SnapshotError> {
        for p in ip.iter_mut() {
            self.usize(p, "pivot")?;
            if *p >= N.max(1) {
                return Err(SnapshotError::InvalidField { name: "pivot" });
            }
        }
        Ok(())
    }
}

impl Io for Writer {
    fn f64(&mut self, v: &mut f64) -> Result<(), SnapshotError> {
        Writer::f64(self, *v);
        Ok(())
    }
    fn u64(&mut self, v: &mut u64) -> Result<(), SnapshotError> {
        Writer::u64(self, *v);
        Ok(())
    }
    fn u8(&mut self, v: &mut u8) -> Result<(), SnapshotError> {
        Writer::u8(self, *v);
        Ok(())
    }
}

/// Counts bytes only (for the layout length).
struct Counter(usize);

impl Io for Counter {
    fn f64(&mut self, _: &mut f64) -> Result<(), SnapshotError> {
        self.0 += 8;
        Ok(())
    }
    fn u64(&mut self, _: &mut u64) -> Result<(), SnapshotError> {
        self.0 += 8;
        Ok(())
    }
    fn u8(&mut self, _: &mut u8) -> Result<(), SnapshotError> {
        self.0 += 1;
        Ok(())
    }
}

/// The next `K` bytes of `r`, or [`SnapshotError::Truncated`].
fn take<const K: usize>(r: &mut Reader<'_>, len: usize) -> Result<[u8; K], SnapshotError> {
    r.array::<K>().ok_or(SnapshotError::Truncated {
        needed: r.position() + K,
        found: len,
    })
}

/// A reader over a whole snapshot buffer (the length for the error message).
struct SnapshotReader<'a> {
    r: Reader<'a>,
    len: usize,
}

impl Io for SnapshotReader<'_> {
    fn f64(&mut self, v: &mut f64) -> Result<(), SnapshotError> {
        *v = f64::from_bits(u64::from_le_bytes(take::<8>(&mut self.r, self.len)?));
        Ok(())
    }
    fn u64(&mut self, v: &mut u64) -> Result<(), SnapshotError> {
        *v = u64::from_le_bytes(take::<8>(&mut self.r, self.len)?);
        Ok(())
    }
    fn u8(&mut self, v: &mut u8) -> Result<(), SnapshotError> {
        *v = take::<1>(&mut self.r, self.len)?[0];
        Ok(())
    }
}

fn visit_params<const N: usize, I: Io>(io: &mut I, p: &mut Params<N>) -> Result<(), SnapshotError> {
    io.vec(&mut p.rtol)?;
    io.vec(&mut p.atol)?;
    io.f64(&mut p.fnewt)?;
    io.f64(&mut p.h_init)?;
    io.f64(&mut p.h_max)?;
    io.u64(&mut p.nmax)?;
    io.usize(&mut p.n1, "n1")?;
    io.usize(&mut p.n2, "n2")?;
    io.usize(&mut p.n3, "n3")?;
    if p.n1.checked_add(p.n2).and_then(|s| s.checked_add(p.n3)) != Some(N) {
        return Err(SnapshotError::InvalidField { name: "n1+n2+n3" });
    }
    io.bool(&mut p.analytic_jac, "analytic_jac")?;
    io.bool(&mut p.pred, "pred")?;
    io.bool(&mut p.startn, "startn")?;
    io.f64(&mut p.uround)?;
    io.f64(&mut p.safe)?;
    io.f64(&mut p.thet)?;
    io.u32(&mut p.nit)?;
    io.f64(&mut p.facl)?;
    io.f64(&mut p.facr)?;
    io.f64(&mut p.quot1)?;
    io.f64(&mut p.quot2)?;
    io.f64(&mut p.resume)?;
    io.usize(&mut p.norm_count, "norm_count")?;
    if !(1..=N).contains(&p.norm_count) {
        return Err(SnapshotError::InvalidField { name: "norm_count" });
    }
    Ok(())
}

fn visit_stats<I: Io>(io: &mut I, s: &mut Statistics) -> Result<(), SnapshotError> {
    io.u64(&mut s.nfcn)?;
    io.u64(&mut s.njac)?;
    io.u64(&mut s.njac_fast)?;
    io.u64(&mut s.nstep)?;
    io.u64(&mut s.naccpt)?;
    io.u64(&mut s.nrejct)?;
    io.u64(&mut s.ndec)?;
    io.u64(&mut s.nsol)
}

/// Every field of the state, in layout order.
pub(super) fn visit<const N: usize, I: Io>(
    io: &mut I,
    s: &mut State<N>,
) -> Result<(), SnapshotError> {
    visit_params(io, &mut s.params)?;
    io.bool(&mut s.has_mass, "has_mass")?;
    io.mat(&mut s.mass)?;
    io.f64(&mut s.t)?;
    io.vec(&mut s.y)?;
    io.f64(&mut s.t_prev)?;
    io.vec(&mut s.y_prev)?;
    io.vec(&mut s.f_prev)?;
    io.vec(&mut s.f0)?;
    io.bool(&mut s.f0_valid, "f0_valid")?;
    io.f64(&mut s.h_next)?;
    io.f64(&mut s.h_old)?;
    io.f64(&mut s.h_lu)?;
    io.f64(&mut s.hhfac)?;
    io.f64(&mut s.h_acc)?;
    io.f64(&mut s.err_acc)?;
    io.f64(&mut s.faccon)?;
    io.f64(&mut s.theta)?;
    io.f64(&mut s.dynold)?;
    io.f64(&mut s.thqold)?;
    io.vec(&mut s.scal)?;
    for c in s.cont.iter_mut() {
        io.vec(c)?;
    }
    io.f64(&mut s.xsol)?;
    io.f64(&mut s.hsol)?;
    io.mat(&mut s.jac)?;
    io.mat(&mut s.lu1.a)?;
    io.pivots(&mut s.lu1.ip)?;
    io.pivots(&mut s.lu1.perm)?;
    io.cmat(&mut s.lu2.a)?;
    io.pivots(&mut s.lu2.ip)?;
    io.pivots(&mut s.lu2.perm)?;
    io.bool(&mut s.first, "first")?;
    io.bool(&mut s.reject, "reject")?;
    io.bool(&mut s.caljac, "caljac")?;
    io.bool(&mut s.jac_valid, "jac_valid")?;
    io.mat(&mut s.jac_slow)?;
    io.bool(&mut s.split, "split")?;
    io.bool(&mut s.calfast, "calfast")?;
    io.f64(&mut s.theta_full)?;
    io.bool(&mut s.fast_stale, "fast_stale")?;
    io.bool(&mut s.lu_valid, "lu_valid")?;
    io.bool(&mut s.prev_clipped, "prev_clipped")?;
    let mut a = s.action as u8;
    io.u8(&mut a)?;
    s.action = Action::from_u8(a).ok_or(SnapshotError::InvalidField { name: "action" })?;
    io.u32(&mut s.nsing)?;
    io.u64(&mut s.naccpt_local)?;
    io.u64(&mut s.steps_since_stop)?;
    visit_stats(io, &mut s.stats)
}

fn zero_state<const N: usize>() -> State<N> {
    use super::Options;
    // Any valid parameter set will do; every field is overwritten when reading.
    let params = Params::new(&Options::<N>::default()).unwrap_or(Params {
        rtol: SVector::zeros(),
        atol: SVector::zeros(),
        fnewt: 0.0,
        h_init: 0.0,
        h_max: 0.0,
        nmax: 0,
        n1: N,
        n2: 0,
        n3: 0,
        analytic_jac: false,
        pred: false,
        startn: false,
        uround: 0.0,
        safe: 0.0,
        thet: 0.0,
        nit: 0,
        facl: 0.0,
        facr: 0.0,
        quot1: 0.0,
        quot2: 0.0,
        resume: 0.0,
        norm_count: N,
    });
    State::fresh(params, None, 0.0, SVector::zeros(), 0.0)
}

impl<const N: usize> Snapshot<N> {
    /// Length in bytes of [`Snapshot::to_bytes`] for this N.
    pub fn serialized_len() -> usize {
        let mut c = Counter(0);
        let mut s = zero_state::<N>();
        // Counting never fails.
        let _ = visit(&mut c, &mut s);
        HEADER_LEN + c.0 + CHECKSUM_LEN
    }

    /// Serialises to the versioned little-endian layout described in the module docs.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = Writer {
            buf: Vec::with_capacity(Self::serialized_len()),
        };
        w.buf.extend_from_slice(&MAGIC);
        w.u32(VERSION);
        w.u32(N as u32);
        w.u64((Self::serialized_len() - HEADER_LEN - CHECKSUM_LEN) as u64);
        let mut s = self.state.clone();
        // Writing never fails.
        let _ = visit(&mut w, &mut s);
        let sum = fnv1a64(&w.buf);
        w.u64(sum);
        w.buf
    }

    /// Reads a buffer written by [`Snapshot::to_bytes`].
    ///
    /// # Errors
    /// [`SnapshotError`] for a truncated, foreign (magic, version, N), corrupted
    /// (checksum) or impossible (field values) buffer; never panics.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, SnapshotError> {
        let total = Self::serialized_len();
        if bytes.len() < HEADER_LEN {
            return Err(SnapshotError::Truncated {
                needed: total,
                found: bytes.len(),
            });
        }
        if bytes[..8] != MAGIC {
            return Err(SnapshotError::BadMagic);
        }
        let mut r = Reader::new(bytes);
        take::<8>(&mut r, bytes.len())?;
        let version = u32::from_le_bytes(take::<4>(&mut r, bytes.len())?);
        if version != VERSION {
            return Err(SnapshotError::UnsupportedVersion { found: version });
        }
        let n = u32::from_le_bytes(take::<4>(&mut r, bytes.len())?);
        if n as usize != N {
            return Err(SnapshotError::DimensionMismatch {
                expected: N as u32,
                found: n,
            });
        }
        let payload_len = u64::from_le_bytes(take::<8>(&mut r, bytes.len())?);
        if payload_len != (total - HEADER_LEN - CHECKSUM_LEN) as u64 {
            return Err(SnapshotError::InvalidField {
                name: "payload length",
            });
        }
        if bytes.len() < total {
            return Err(SnapshotError::Truncated {
                needed: total,
                found: bytes.len(),
            });
        }
        if bytes.len() > total {
            return Err(SnapshotError::TrailingBytes {
                extra: bytes.len() - total,
            });
        }
        let body = &bytes[..total - CHECKSUM_LEN];
        let mut sum = [0u8; 8];
        sum.copy_from_slice(&bytes[total - CHECKSUM_LEN..]);
        if fnv1a64(body) != u64::from_le_bytes(sum) {
            return Err(SnapshotError::Checksum);
        }
        let mut state = zero_state::<N>();
        visit(
            &mut SnapshotReader {
                r,
                len: bytes.len(),
            },
            &mut state,
        )?;
        Ok(Snapshot { state })
    }
}

impl<const N: usize> Snapshot<N> {
    /// Time of the snapshot.
    pub fn t(&self) -> f64 {
        self.state.t
    }
    /// Start of the last accepted step.
    pub fn t_prev(&self) -> f64 {
        self.state.t_prev
    }
    /// State at [`Snapshot::t`].
    pub fn y(&self) -> &SVector<f64, N> {
        &self.state.y
    }
    /// Counters at the snapshot.
    pub fn stats(&self) -> &Statistics {
        &self.state.stats
    }
}
