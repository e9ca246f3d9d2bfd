//! Fixed-step RADAU5 with a fixed number of simplified Newton iterations: the same
//! collocation method as [`Radau5::step`] (3-stage Radau IIA, order 5, radau5.md §2-§4),
//! without error control, for callers that need the same, bounded amount of work for every
//! step (a real-time co-simulation master at a fixed rate).
//!
//! Per step of size h: exactly `iterations` simplified Newton iterations with the LU pair
//! the caller prepared with [`Radau5::fixed_prepare`] (3 f evaluations and one pair of
//! linear solves each), no error estimate, no rejection, and no f at the new point. The
//! caller decides when J and the LU pair are renewed ([`Radau5::fixed_prepare`]), so the
//! schedule is fixed too.
//!
//! Convergence is checked after the last iteration with the stopping rule of the adaptive
//! stepper (radau5.md §4): the contraction estimate `theta = |dz_k| / |dz_(k-1)|` must be
//! below 1 and the predicted remaining error `theta / (1 - theta) |dz_k|` below the Newton
//! tolerance `kappa` (the same weighted norm, index-2 components scaled by h). Otherwise the
//! step fails with [`Error::FixedStepNewton`] and the state stays at the start of the step:
//! never a silent, unconverged result.
//!
//! The step updates everything a following adaptive or fixed step, the dense output and a
//! [`super::Snapshot`] use (t, y, the collocation polynomial, the counters), so rollback
//! and serialisation work as for adaptive steps.

use nalgebra::SVector;

use super::step_phases::{accumulate, newton_increment, stage_rhs};
use super::stepper::check_finite;
use super::tableau::TI;
use super::{Error, Problem, Radau5};

/// Fewest Newton iterations per fixed step: the contraction test needs two increments.
pub const MIN_FIXED_ITERATIONS: u32 = 2;

/// A last Newton increment below this fraction of the Newton tolerance kappa counts as
/// converged whatever the contraction ratio (see [`Radau5::fixed_step`]).
const NEGLIGIBLE_INCREMENT: f64 = 1e-3;

impl<const N: usize> Radau5<N> {
    /// Renews the Jacobian at the current point and factorises the LU pair for the step
    /// size `h` (1 Jacobian, 1 LU pair; plus 1 f evaluation when the problem has no
    /// analytic Jacobian and the finite differences need f at the point).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a non-positive h; [`Error::Rhs`] / [`Error::NonFinite`]
    /// if f or J cannot be evaluated; [`Error::SingularMatrix`] for a singular pair.
    pub fn fixed_prepare<P: Problem<N>>(&mut self, problem: &mut P, h: f64) -> Result<(), Error> {
        if !(h > 0.0 && h.is_finite()) {
            return Err(Error::InvalidOption {
                name: "h",
                value: h,
                requirement: "0 < h < inf",
            });
        }
        let t = self.st.t;
        let rhs_err = |e: super::RhsError| Error::Rhs {
            t,
            h,
            message: e.message,
        };
        let s = &mut self.st;
        // As in `compute_jacobian`: J is overwritten from here on.
        s.jac_valid = false;
        s.lu_valid = false;
        // Fixed steps renew the whole J on their schedule (no split, radau5.md §8).
        s.split = false;
        let analytic =
            s.params.analytic_jac && problem.jacobian(t, &s.y, &mut s.jac).map_err(rhs_err)?;
        if analytic {
            s.stats.njac += 1;
        } else {
            // Finite differences need f at the point (not kept after a fixed step).
            if !s.f0_valid {
                let mut f0 = SVector::zeros();
                let r = problem.rhs(t, &s.y, &mut f0);
                s.stats.nfcn += 1;
                r.map_err(rhs_err)?;
                if f0.iter().any(|v| !v.is_finite()) {
                    return Err(Error::NonFinite { t, h });
                }
                s.f0 = f0;
                s.f0_valid = true;
            }
            self.compute_jacobian(problem, h)?;
        }
        self.st.jac_valid = true;
        if self.decompose(h).is_err() {
            return Err(Error::SingularMatrix { t, h });
        }
        Ok(())
    }

    /// The step size of the LU pair if there is a valid one (a fixed step must use it, see
    /// [`Radau5::fixed_step`]).
    pub fn fixed_lu_step(&self) -> Option<f64> {
        (self.st.lu_valid && self.st.jac_valid).then_some(self.st.h_lu)
    }

    /// Replaces `y` at the current point (a caller's re-projected algebraic components or
    /// a state after a jump of f) without evaluating anything: the next fixed step starts
    /// from it. The Newton start of that step is still extrapolated from the last step's
    /// collocation polynomial (its increments, not its values).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a non-finite `y`.
    pub fn fixed_set_point(&mut self, y: SVector<f64, N>) -> Result<(), Error> {
        check_finite("y", &y)?;
        let s = &mut self.st;
        s.y = y;
        s.f0_valid = false;
        s.cont[0] = y;
        Ok(())
    }

    /// One step from the current t of exactly `h` with exactly `iterations` simplified
    /// Newton iterations, ending at `t_end` (`t + h` up to rounding; given so that a caller
    /// lands on its own time grid exactly). Needs an LU pair for this `h` from
    /// [`Radau5::fixed_prepare`]. Work: `3 iterations` f evaluations, `iterations` solves.
    /// Allocates nothing.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for `iterations` below [`MIN_FIXED_ITERATIONS`], a step
    /// size that differs from the LU pair's, or `t_end` not after t;
    /// [`Error::FixedStepNewton`] when the iteration has not converged (see the module
    /// docs); [`Error::Rhs`] / [`Error::NonFinite`] from f. The state is then unchanged.
    pub fn fixed_step<P: Problem<N>>(
        &mut self,
        problem: &mut P,
        h: f64,
        t_end: f64,
        iterations: u32,
    ) -> Result<f64, Error> {
        if iterations < MIN_FIXED_ITERATIONS {
            return Err(Error::InvalidOption {
                name: "iterations",
                value: f64::from(iterations),
                requirement: "at least 2 Newton iterations per fixed step",
            });
        }
        let t = self.st.t;
        if !(self.st.lu_valid && self.st.h_lu == h) {
            return Err(Error::InvalidOption {
                name: "h",
                value: h,
                requirement: "the step size of the LU pair from fixed_prepare",
            });
        }
        if !(t_end > t && t_end.is_finite()) {
            return Err(Error::InvalidOption {
                name: "t_end",
                value: t_end,
                requirement: "after the current time",
            });
        }
        let p = self.st.params;
        let tab = self.tab;
        let pat = &self.pattern;
        let blk = &self.blocks;
        let el = &self.elim;
        let s = &mut self.st;
        // Error weights (SCAL), index-2/3 components scaled by h as in the adaptive step.
        let mut scal = SVector::<f64, N>::zeros();
        for i in 0..N {
            scal[i] = p.atol[i] + p.rtol[i] * s.y[i].abs();
        }
        for i in p.n1..p.n1 + p.n2 {
            scal[i] /= h;
        }
        for i in p.n1 + p.n2..N {
            scal[i] /= h * h;
        }
        let fac1 = tab.gamma / h;
        let alphn = tab.alpha / h;
        let betan = tab.beta / h;

        // Newton start: the last step's collocation polynomial extrapolated (as the
        // adaptive stepper does), zero after a start.
        let mut z1 = SVector::<f64, N>::zeros();
        let mut z2 = SVector::<f64, N>::zeros();
        let mut z3 = SVector::<f64, N>::zeros();
        let mut f1 = SVector::<f64, N>::zeros();
        let mut f2 = SVector::<f64, N>::zeros();
        let mut f3 = SVector::<f64, N>::zeros();
        let c3q = h / s.h_old;
        if !(s.first || p.startn || c3q > 1.0 / p.facr) {
            let c1q = tab.c1 * c3q;
            let c2q = tab.c2 * c3q;
            for i in 0..N {
                let (ak1, ak2, ak3) = (s.cont[1][i], s.cont[2][i], s.cont[3][i]);
                let z1i = c1q * (ak1 + (c1q - tab.c2m1) * (ak2 + (c1q - tab.c1m1) * ak3));
                let z2i = c2q * (ak1 + (c2q - tab.c2m1) * (ak2 + (c2q - tab.c1m1) * ak3));
                let z3i = c3q * (ak1 + (c3q - tab.c2m1) * (ak2 + (c3q - tab.c1m1) * ak3));
                z1[i] = z1i;
                z2[i] = z2i;
                z3[i] = z3i;
                f1[i] = TI[0][0] * z1i + TI[0][1] * z2i + TI[0][2] * z3i;
                f2[i] = TI[1][0] * z1i + TI[1][1] * z2i + TI[1][2] * z3i;
                f3[i] = TI[2][0] * z1i + TI[2][1] * z2i + TI[2][2] * z3i;
            }
        }

        let mut cont = SVector::<f64, N>::zeros();
        let mut a1 = SVector::<f64, N>::zeros();
        let mut a2 = SVector::<f64, N>::zeros();
        let mut a3 = SVector::<f64, N>::zeros();
        let (mut dyn_prev, mut dyn_last) = (f64::NAN, f64::NAN);
        let rhs_err = |e: super::RhsError| Error::Rhs {
            t,
            h,
            message: e.message,
        };
        for _ in 0..iterations {
            stage_rhs(
                problem,
                &s.y,
                [t + tab.c1 * h, t + tab.c2 * h, t_end],
                [&z1, &z2, &z3],
                &mut cont,
                [&mut a1, &mut a2, &mut a3],
            )
            .map_err(rhs_err)?;
            s.stats.nfcn += 3;
            let dyno = newton_increment(
                s,
                blk,
                el,
                pat,
                (fac1, alphn, betan),
                [&a1, &a2, &a3],
                [&f1, &f2, &f3],
                [&mut z1, &mut z2, &mut z3],
                &scal,
            );
            s.stats.nsol += 1;
            if !dyno.is_finite() {
                return Err(Error::NonFinite { t, h });
            }
            (dyn_prev, dyn_last) = (dyn_last, dyno);
            accumulate([&mut f1, &mut f2, &mut f3], [&mut z1, &mut z2, &mut z3]);
        }
        // Converged: contraction below 1 and the predicted remaining error below kappa, or
        // a last increment below NEGLIGIBLE_INCREMENT kappa whatever the ratio (at that
        // level the increments are rounding noise of large components such as a growing
        // angle, and their ratio means nothing: seen as 1.1-1.5 at 1e-6 kappa).
        let theta = dyn_last / dyn_prev.max(p.uround);
        let remaining = if theta < 1.0 {
            theta / (1.0 - theta) * dyn_last
        } else {
            f64::INFINITY
        };
        if !(remaining <= p.fnewt || dyn_last <= NEGLIGIBLE_INCREMENT * p.fnewt) {
            return Err(Error::FixedStepNewton {
                t,
                h,
                iterations,
                contraction: theta,
                increment: dyn_last / p.fnewt,
            });
        }
        // Commit (the same bookkeeping as an accepted adaptive step).
        s.stats.nstep += 1;
        s.stats.naccpt += 1;
        s.first = false;
        s.reject = false;
        s.caljac = false;
        s.prev_clipped = false;
        s.t_prev = t;
        s.y_prev = s.y;
        s.f_prev = s.f0;
        s.h_old = h;
        s.h_next = h;
        s.hhfac = h;
        s.scal = scal;
        s.theta = theta;
        s.t = t_end;
        s.y += &z3;
        s.set_dense_output(&tab, &z1, &z2, &z3, h);
        s.f0_valid = false;
        s.naccpt_local += 1;
        Ok(s.t)
    }
}
