//! Consistency of a [`Snapshot`] read from outside (a serialized FMU state that a tool may
//! have edited and resealed): checksums catch accidents, not a buffer that is consistent
//! but wrong. Before a snapshot is trusted, [`Snapshot::check`] verifies what every state
//! the stepper itself produces satisfies: the options are those the caller runs with, every
//! number is finite, step sizes are positive, times are ordered and the counters lie in
//! their ranges. A snapshot that passes may still describe a state the problem rejects;
//! the caller checks the problem's own invariants (e.g. an algebraic constraint).

use nalgebra::SMatrix;

use super::options::Params;
use super::snapshot::{visit, Io};
use super::{Options, Snapshot, SnapshotError};

/// Singular LU pairs in a row that end a step (`MAX_SINGULAR` of the stepper); a state
/// holds at most that many (after the failure it reports, until the next restart).
const MAX_SINGULAR: u32 = 5;

/// Visits every f64 of a state and records the first that is not finite.
struct FiniteCheck {
    index: usize,
    bad: Option<usize>,
}

impl Io for FiniteCheck {
    fn f64(&mut self, v: &mut f64) -> Result<(), SnapshotError> {
        if self.bad.is_none() && !v.is_finite() {
            self.bad = Some(self.index);
        }
        self.index += 1;
        Ok(())
    }
    fn u64(&mut self, _: &mut u64) -> Result<(), SnapshotError> {
        Ok(())
    }
    fn u8(&mut self, _: &mut u8) -> Result<(), SnapshotError> {
        Ok(())
    }
}

fn require(ok: bool, name: &'static str) -> Result<(), SnapshotError> {
    if ok {
        Ok(())
    } else {
        Err(SnapshotError::InvalidField { name })
    }
}

impl<const N: usize> Snapshot<N> {
    /// Checks that this snapshot is one the stepper could have produced when run with
    /// `options` and the mass matrix `mass` (None: identity). `restart_due`: the caller
    /// restarts the stepper ([`super::Radau5::restart`]) before its next step and reads
    /// no dense output before that (as after a failed step); the history a restart
    /// forgets (Jacobian, LU pair, f0, dense output, Newton and controller history,
    /// y and f at the start of the last step) is then not checked for finiteness.
    ///
    /// # Errors
    /// [`SnapshotError::InvalidField`] naming the first field that is wrong.
    pub fn check(
        &self,
        options: &Options<N>,
        mass: Option<&SMatrix<f64, N, N>>,
        restart_due: bool,
    ) -> Result<(), SnapshotError> {
        let s = &self.state;
        let expected = Params::new(options).map_err(|_| SnapshotError::InvalidField {
            name: "options (the caller's own are invalid)",
        })?;
        require(
            s.params == expected,
            "solver options (differ from those of the settings)",
        )?;
        match mass {
            Some(m) => require(s.has_mass && s.mass == *m, "mass matrix")?,
            None => require(!s.has_mass, "mass matrix")?,
        }
        // Every number the next step or the dense output reads must be finite; the
        // Jacobian, the LU pair and f0 only while they are flagged valid (a failed step
        // may leave them non-finite, and they are recomputed before use).
        let vec_ok = |v: &nalgebra::SVector<f64, N>| v.iter().all(|x| x.is_finite());
        let scalars = [
            s.t, s.t_prev, s.h_next, s.h_old, s.h_lu, s.hhfac, s.xsol, s.hsol,
        ];
        require(
            scalars.iter().all(|x| x.is_finite()),
            "a time or step size (must be finite)",
        )?;
        require(vec_ok(&s.y), "y (must be finite)")?;
        require(vec_ok(&s.scal), "scal (must be finite)")?;
        let history = [
            s.h_acc,
            s.err_acc,
            s.faccon,
            s.theta,
            s.dynold,
            s.thqold,
            s.theta_full,
        ];
        let mut copy = s.clone();
        if restart_due {
            copy.lu1 = super::linalg::RealLu::zeros();
            copy.lu2 = super::linalg::ComplexLu::zeros();
            copy.jac = SMatrix::zeros();
            copy.jac_slow = SMatrix::zeros();
            copy.theta_full = 0.0;
            copy.f0 = nalgebra::SVector::zeros();
            copy.cont = [nalgebra::SVector::zeros(); 4];
            copy.y_prev = nalgebra::SVector::zeros();
            copy.f_prev = nalgebra::SVector::zeros();
            copy.h_acc = 0.0;
            copy.err_acc = 0.0;
            copy.faccon = 0.0;
            copy.theta = 0.0;
            copy.dynold = 0.0;
            copy.thqold = 0.0;
        } else {
            require(
                history.iter().all(|x| x.is_finite()),
                "Newton or controller history (must be finite)",
            )?;
            require(vec_ok(&s.y_prev), "y_prev (must be finite)")?;
            require(vec_ok(&s.f_prev), "f_prev (must be finite)")?;
            require(s.cont.iter().all(vec_ok), "dense output (must be finite)")?;
            require(!s.f0_valid || vec_ok(&s.f0), "f0 (must be finite)")?;
            require(
                !s.jac_valid || s.jac.iter().all(|x| x.is_finite()),
                "Jacobian (must be finite)",
            )?;
            // The LU pair, and J and f0 while flagged stale, are recomputed before use.
            if !s.lu_valid {
                copy.lu1 = super::linalg::RealLu::zeros();
                copy.lu2 = super::linalg::ComplexLu::zeros();
            }
            if !s.jac_valid {
                copy.jac = SMatrix::zeros();
            }
            // The slow part of a split J is read only with a valid J and the split flag.
            if !(s.jac_valid && s.split) {
                copy.jac_slow = SMatrix::zeros();
            }
            if !s.f0_valid {
                copy.f0 = nalgebra::SVector::zeros();
            }
        }
        let mut fc = FiniteCheck {
            index: 0,
            bad: None,
        };
        visit(&mut fc, &mut copy)?;
        require(fc.bad.is_none(), "a number (must be finite)")?;
        let positive = |x: f64| x > 0.0 && x.is_finite();
        require(positive(s.h_next), "h_next (must be > 0)")?;
        require(positive(s.h_old), "h_old (must be > 0)")?;
        require(positive(s.h_lu), "h_lu (must be > 0)")?;
        require(positive(s.hsol), "hsol (must be > 0)")?;
        require(positive(s.hhfac), "hhfac (must be > 0)")?;
        require(
            restart_due
                || (s.h_acc >= 0.0
                    && s.err_acc >= 0.0
                    && s.faccon >= 0.0
                    && s.theta >= 0.0
                    && s.dynold >= 0.0
                    && s.thqold >= 0.0
                    && s.theta_full >= 0.0),
            "Newton or controller history (must be >= 0)",
        )?;
        require(s.t_prev <= s.t, "t_prev (must be <= t)")?;
        require(
            s.xsol >= s.t_prev && s.xsol <= s.t,
            "xsol (must lie in the last step)",
        )?;
        require(s.nsing <= MAX_SINGULAR, "nsing (singular LUs in a row)")?;
        // One over the limit after the failure that reports it.
        require(
            s.steps_since_stop <= s.params.nmax.saturating_add(1),
            "steps_since_stop (must be <= max_steps + 1)",
        )?;
        let st = &s.stats;
        require(
            s.naccpt_local <= st.naccpt,
            "naccpt_local (must be <= naccpt)",
        )?;
        require(
            st.naccpt
                .checked_add(st.nrejct)
                .is_some_and(|n| n <= st.nstep),
            "naccpt + nrejct (must be <= nstep)",
        )?;
        let scal_ok = s.scal.iter().all(|&x| x >= 0.0);
        require(scal_ok, "scal (must be >= 0)")?;
        Ok(())
    }
}
