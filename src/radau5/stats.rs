//! Counters with the meaning of the Fortran's `IWORK(14..20)` (radau5.md §7).

use std::fmt;

/// Work counters, same meaning as `radau5.f`:
/// - `nfcn`: calls of f (1 initial + 3 per Newton iteration + 1 per accepted step that is
///   followed by another step + error-estimate refinements; not the calls inside a
///   finite-difference Jacobian),
/// - `njac`: Jacobian evaluations, `nstep`: step attempts, `naccpt`: accepted steps,
/// - `njac_fast`: renewals of only the fast part of a split Jacobian
///   ([`super::Problem::jacobian_fast`]; not in `njac`, no Fortran counterpart),
/// - `nrejct`: rejected steps (error test, counted after the first accepted step),
/// - `ndec`: LU pairs (real + complex), `nsol`: Newton solves (pairs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Statistics {
    pub nfcn: u64,
    pub njac: u64,
    pub njac_fast: u64,
    pub nstep: u64,
    pub naccpt: u64,
    pub nrejct: u64,
    pub ndec: u64,
    pub nsol: u64,
}

impl Statistics {
    /// The work done since `earlier` (a copy of these counters taken before it).
    pub fn since(&self, earlier: &Statistics) -> Statistics {
        Statistics {
            nfcn: self.nfcn - earlier.nfcn,
            njac: self.njac - earlier.njac,
            njac_fast: self.njac_fast - earlier.njac_fast,
            nstep: self.nstep - earlier.nstep,
            naccpt: self.naccpt - earlier.naccpt,
            nrejct: self.nrejct - earlier.nrejct,
            ndec: self.ndec - earlier.ndec,
            nsol: self.nsol - earlier.nsol,
        }
    }
}

impl fmt::Display for Statistics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "nfcn={} njac={} njac_fast={} nstep={} naccpt={} nrejct={} ndec={} nsol={}",
            self.nfcn,
            self.njac,
            self.njac_fast,
            self.nstep,
            self.naccpt,
            self.nrejct,
            self.ndec,
            self.nsol
        )
    }
}
