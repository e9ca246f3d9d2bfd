//! [`Radau5::step`] in the phases of `RADCOR` (radau5.md §3-§5): the step-size choice
//! after the previous accepted step, then per attempt the matrices (labels 10/20), the
//! simplified Newton iteration (label 30 onwards), the error estimate (`ESTRAD`), and the
//! accept or reject decision. Every phase returns what happened; only `step` loops, and
//! the Fortran's label 78 ("unexpected step rejection") is the method
//! [`Radau5::unexpected_rejection`].

use nalgebra::SVector;

use super::linear_systems::{Blocks, Elimination, MassPattern};
use super::state::{Action, State};
use super::step_size::{gustafsson_quotient, step_quotient};
use super::stepper::{eval, Failure, MAX_RHS_FAILURES, MAX_SINGULAR, MAX_UNEXPECTED};
use super::tableau::{T, TI};
use super::{Error, Problem, Radau5, RhsError};

/// The attempt under way: its step size and whether it ends on the stop time.
struct Attempt {
    h: f64,
    last: bool,
}

/// Failures counted within one call of `step` (they end it when they pile up).
#[derive(Default)]
struct FailureCounts {
    unexpected: u32,
    rhs: u32,
    nonfinite: u32,
}

/// Stage increments `Z_k` and the transformed iterate `F_k` (Fortran's Z1..Z3, F1..F3).
struct Stages<const N: usize> {
    z: [SVector<f64, N>; 3],
    f: [SVector<f64, N>; 3],
}

/// How the simplified Newton iteration ended.
enum Newton {
    /// Converged after `newt` iterations.
    Converged(u32),
    /// Predicted not to converge in time: retry with `h * hhfac` (not a rejection).
    Restart,
    /// Diverged, or f failed: an unexpected rejection.
    Failed(Failure),
}

impl<const N: usize> Radau5<N> {
    /// One accepted step towards `t_stop`; never passes `t_stop` and lands on it exactly
    /// when it is within reach (radau5.md §5 "the last step lands exactly on it", applied to
    /// every stop time). When the stop time shortens a step that then succeeds without
    /// trouble, the controller's unclipped proposal is kept for the following step, so a
    /// sequence of tiny stop intervals costs about one step each. Returns the new t.
    ///
    /// # Errors
    /// [`Error::StopTimeBehind`], [`Error::StepSizeTooSmall`], [`Error::TooManySteps`],
    /// [`Error::SingularMatrix`], [`Error::NewtonFailure`], [`Error::NonFinite`],
    /// [`Error::Rhs`]; the state is then that of the failed attempt (not meant to continue).
    pub fn step<P: Problem<N>>(&mut self, problem: &mut P, t_stop: f64) -> Result<f64, Error> {
        if t_stop.is_nan() || t_stop < self.st.t {
            return Err(Error::StopTimeBehind {
                t: self.st.t,
                t_stop,
            });
        }
        if t_stop == self.st.t {
            return Ok(self.st.t);
        }
        // A stop time within a few ulps of t (a master's rounded communication point) can not
        // be reached by a step (h would fail the "step size too small" test): snap onto it.
        if t_stop - self.st.t <= 4.0 * f64::EPSILON * self.st.t.abs().max(t_stop.abs()) {
            self.st.t = t_stop;
            self.st.steps_since_stop = 0;
            return Ok(t_stop);
        }
        let t = self.st.t;
        if !self.st.f0_valid {
            let mut f0 = SVector::zeros();
            let r = eval(problem, t, &self.st.y, &mut f0);
            self.st.stats.nfcn += 1;
            Self::point_eval_error(r, t, self.st.h_next)?;
            self.st.f0 = f0;
            self.st.f0_valid = true;
        }

        let (mut at, h_planned) = self.choose_step_size(t_stop);
        let mut failures = FailureCounts::default();
        loop {
            if let Err(kind) = self.prepare_matrices(problem, at.h)? {
                self.unexpected_rejection(kind, &mut failures, &mut at)?;
                continue;
            }
            self.count_attempt(at.h)?;
            let mut stages = self.newton_start(at.h);
            let newt = match self.newton_iteration(problem, &mut stages, &at, t_stop) {
                Newton::Converged(newt) => newt,
                Newton::Restart => {
                    self.restart_attempt(&mut at);
                    continue;
                }
                Newton::Failed(kind) => {
                    self.unexpected_rejection(kind, &mut failures, &mut at)?;
                    continue;
                }
            };
            let err = match self.error_estimate(problem, &stages, at.h) {
                Ok(e) => e,
                Err(kind) => {
                    self.unexpected_rejection(kind, &mut failures, &mut at)?;
                    continue;
                }
            };
            // ---- new step size; 1/fac_max <= h/h_new <= 1/fac_min
            let p = &self.st.params;
            let cfac = p.safe * f64::from(1 + 2 * p.nit);
            let fac = p.safe.min(cfac / f64::from(newt + 2 * p.nit));
            let quot = step_quotient(err, fac, p.facr, p.facl);
            if err < 1.0 {
                match self.accept(problem, &stages, &at, err, quot, h_planned, t_stop) {
                    Ok(t_new) => return Ok(t_new),
                    Err(kind) => {
                        self.unexpected_rejection(kind, &mut failures, &mut at)?;
                        continue;
                    }
                }
            }
            let hnew = at.h / quot;
            self.reject(&mut at, hnew);
        }
    }

    /// The step-size decision at the end of the accepted branch of `RADCOR` (or its
    /// initialisation): h, whether the step lands on `t_stop`, whether J and the LU pair
    /// can be reused; the scales from the current y. Returns the attempt and the step size
    /// planned before any clipping by `t_stop`.
    fn choose_step_size(&mut self, t_stop: f64) -> (Attempt, f64) {
        let s = &mut self.st;
        let p = &s.params;
        let t = s.t;
        let mut h;
        let last;
        let h_planned;
        if s.first {
            // Initialisation: H = min(|H|, HMAXN); the last step if x + 1.0001 h >= xend.
            h_planned = s.h_next.min(p.h_max);
            h = h_planned.min(t_stop - t);
            if t + h * 1.0001 >= t_stop {
                h = t_stop - t;
                last = true;
            } else {
                last = false;
            }
            s.action = Action::Jacobian;
        } else {
            let hnew = s.h_next;
            h_planned = hnew;
            let reuse_j = s.theta <= p.thet && s.jac_valid;
            // A J that has merely aged (the last step contracted slower than thet) gets
            // its fast part renewed where the problem splits it (radau5.md §8); a negative
            // thet asks for a full J after every step, as in the Fortran.
            let renew = if s.split && s.jac_valid && !s.fast_stale && p.thet >= 0.0 {
                Action::JacobianFast
            } else {
                Action::Jacobian
            };
            if t + hnew / p.quot1 >= t_stop {
                h = t_stop - t;
                last = true;
                // The Fortran always refactors before its last step. Between two stop
                // times of the same spacing, reuse the LU pair instead: the same to 1e-9
                // and to the rounding of t (h = t_stop - t carries a few ulps of t: at t =
                // 100 s that is 1e-9 of h = 1e-5 s, and a plain relative test lost the reuse
                // there, 0.03 -> 0.47 LU pairs per doStep).
                // Not for a merely similar spacing: an LU pair of another h makes the
                // Newton matrix wrong by 1 - h_lu/h (the iteration then contracts by about
                // that much, up to 0.17 within radau5.f's [quot1, quot2] window) and the
                // error estimate (5.1) solves with the wrong matrix. Measured (closed loop,
                // omega1 new every 0.1 ms, steps cut at mesh events): with that window
                // 0.20 / 0.39 Jacobians per doStep (rigid / elastic teeth), the elastic T1
                // error stuck at 5e-5 N m from rtol 1e-7 on; with equal spacing only 0.036
                // / 0.23 Jacobians, 8-10 % less CPU, and 3.8e-6 N m at rtol 1e-8.
                let reuse_lu = s.prev_clipped
                    && s.lu_valid
                    && (h - s.h_lu).abs() <= 1e-9 * h + 8.0 * f64::EPSILON * t_stop.abs();
                s.action = if !reuse_j {
                    renew
                } else if reuse_lu {
                    Action::Step
                } else {
                    Action::Decompose
                };
            } else {
                last = false;
                let qt = hnew / s.h_old;
                if reuse_j && qt >= p.quot1 && qt <= p.quot2 && s.lu_valid {
                    h = s.h_old;
                    s.action = Action::Step;
                } else {
                    h = hnew;
                    s.action = if reuse_j { Action::Decompose } else { renew };
                }
            }
        }
        s.hhfac = h;
        // SCAL from the current y (identical to the Fortran's recomputation after the
        // accepted step); the index-2/3 division by HHFAC follows per attempt.
        for i in 0..N {
            s.scal[i] = p.atol[i] + p.rtol[i] * s.y[i].abs();
        }
        (Attempt { h, last }, h_planned)
    }

    /// Labels 10 and 20: a new Jacobian and/or LU pair as `action` asks. The outer error
    /// ends the step (f failing in a difference Jacobian); the inner one is a singular LU
    /// (an unexpected rejection).
    fn prepare_matrices<P: Problem<N>>(
        &mut self,
        problem: &mut P,
        h: f64,
    ) -> Result<Result<(), Failure>, Error> {
        if self.st.action == Action::Jacobian {
            self.compute_jacobian(problem, h)?;
            self.st.caljac = true;
            self.st.jac_valid = true;
            self.st.action = Action::Decompose;
        }
        if self.st.action == Action::JacobianFast {
            // A declined split gives a full J.
            if self.compute_jacobian_fast(problem, h)? {
                self.st.calfast = true;
            } else {
                self.st.caljac = true;
            }
            self.st.jac_valid = true;
            self.st.action = Action::Decompose;
        }
        if self.st.action == Action::Decompose {
            if self.decompose(h).is_err() {
                return Ok(Err(Failure::Singular));
            }
            self.st.action = Action::Step;
        }
        Ok(Ok(()))
    }

    /// Label 30: counts the attempt (NSTEP), checks the step limits, and divides the
    /// scales of index-2/3 components by HHFAC.
    fn count_attempt(&mut self, h: f64) -> Result<(), Error> {
        let s = &mut self.st;
        let p = &s.params;
        let t = s.t;
        s.stats.nstep += 1;
        s.steps_since_stop += 1;
        if s.steps_since_stop > p.nmax {
            return Err(Error::TooManySteps {
                t,
                h,
                max_steps: p.nmax,
            });
        }
        if 0.1 * h.abs() <= t.abs() * p.uround {
            return Err(Error::StepSizeTooSmall { t, h });
        }
        for i in p.n1..p.n1 + p.n2 {
            s.scal[i] /= s.hhfac;
        }
        for i in p.n1 + p.n2..N {
            s.scal[i] /= s.hhfac * s.hhfac;
        }
        Ok(())
    }

    /// Starting values of the Newton iteration: zero on a first step (or when asked), else
    /// the collocation polynomial of the last step extrapolated (radau5.md §4, §6).
    fn newton_start(&self, h: f64) -> Stages<N> {
        let s = &self.st;
        let p = &s.params;
        let tab = &self.tab;
        let zero = SVector::<f64, N>::zeros();
        let mut st = Stages {
            z: [zero; 3],
            f: [zero; 3],
        };
        let c3q = h / s.h_old;
        // A ratio above 1/facr never occurs in the Fortran (h_new <= h/facr); it appears
        // here only after a step shortened by a stop time, where extrapolating the tiny
        // step's polynomial would be wild: start from zero instead.
        if !(s.first || p.startn || c3q > 1.0 / p.facr) {
            let c1q = tab.c1 * c3q;
            let c2q = tab.c2 * c3q;
            for i in 0..N {
                let ak1 = s.cont[1][i];
                let ak2 = s.cont[2][i];
                let ak3 = s.cont[3][i];
                let z1i = c1q * (ak1 + (c1q - tab.c2m1) * (ak2 + (c1q - tab.c1m1) * ak3));
                let z2i = c2q * (ak1 + (c2q - tab.c2m1) * (ak2 + (c2q - tab.c1m1) * ak3));
                let z3i = c3q * (ak1 + (c3q - tab.c2m1) * (ak2 + (c3q - tab.c1m1) * ak3));
                st.z[0][i] = z1i;
                st.z[1][i] = z2i;
                st.z[2][i] = z3i;
                st.f[0][i] = TI[0][0] * z1i + TI[0][1] * z2i + TI[0][2] * z3i;
                st.f[1][i] = TI[1][0] * z1i + TI[1][1] * z2i + TI[1][2] * z3i;
                st.f[2][i] = TI[2][0] * z1i + TI[2][1] * z2i + TI[2][2] * z3i;
            }
        }
        st
    }

    /// The simplified Newton iteration (radau5.md §4) from `stages`; on convergence
    /// `stages` holds the stage increments Z.
    fn newton_iteration<P: Problem<N>>(
        &mut self,
        problem: &mut P,
        stages: &mut Stages<N>,
        at: &Attempt,
        t_stop: f64,
    ) -> Newton {
        let Radau5 {
            st: s,
            tab,
            pattern: pat,
            blocks: blk,
            elim: el,
        } = self;
        let p = &s.params;
        let nit = p.nit;
        let (t, h) = (s.t, at.h);
        let xph = if at.last { t_stop } else { t + h };
        let fac1 = tab.gamma / h;
        let alphn = tab.alpha / h;
        let betan = tab.beta / h;
        let [z1, z2, z3] = &mut stages.z;
        let [f1, f2, f3] = &mut stages.f;
        let mut newt: u32 = 0;
        // FACCON = MAX(FACCON,UROUND)**0.8 (radau5.f), by the same pow, but only when its
        // value is needed: the first iteration's convergence test (unless a bound already
        // decides it), or the end of the iteration. Most attempts overwrite it with
        // THETA/(1-THETA) in their second iteration first.
        let mut faccon_pending = Some(s.faccon.max(p.uround));
        s.theta = p.thet.abs();
        let mut cont = SVector::<f64, N>::zeros();
        let mut a1 = SVector::<f64, N>::zeros();
        let mut a2 = SVector::<f64, N>::zeros();
        let mut a3 = SVector::<f64, N>::zeros();
        let outcome = loop {
            if newt >= nit {
                break Newton::Failed(Failure::Newton);
            }
            // All three stages are evaluated and counted even when one of them is not
            // finite, as in radau5.f (which has no finiteness check: NFCN += 3, the solve,
            // DYNO, and then the convergence test rejects). f is not checked here: a NaN
            // or inf in any F_k reaches every transformed component it enters (T^-1 has no
            // zero entry), survives the solves (0*inf is NaN too) and makes DYNO, a sum of
            // squares over all components, non-finite; the test on DYNO below catches it.
            if let Err(e) = stage_rhs(
                problem,
                &s.y,
                [t + tab.c1 * h, t + tab.c2 * h, xph],
                [&*z1, &*z2, &*z3],
                &mut cont,
                [&mut a1, &mut a2, &mut a3],
            ) {
                break Newton::Failed(Failure::Rhs(e));
            }
            s.stats.nfcn += 3;
            let dyno = newton_increment(
                s,
                blk,
                el,
                pat,
                (fac1, alphn, betan),
                [&a1, &a2, &a3],
                [&*f1, &*f2, &*f3],
                [&mut *z1, &mut *z2, &mut *z3],
                &s.scal,
            );
            s.stats.nsol += 1;
            newt += 1;
            // A non-finite f (or increment) rejects the attempt after its 3 f calls and its
            // solve have been counted. For 1 < NEWT < NIT this is radau5.f's own path: DYNO
            // is inf or NaN, so THETA = DYNO/DYNOLD (or its geometric mean with THQOLD) is
            // not < 0.99 and it jumps to label 78 (h halved, an unexpected rejection). In
            // the first and the NIT-th iteration the Fortran has no convergence test and
            // would carry the NaN on into the error estimate; here the attempt is rejected
            // the same way instead (docs/radau5.md §7, "non-finite f").
            if !dyno.is_finite() {
                break Newton::Failed(Failure::NonFinite);
            }
            if newt > 1 && newt < nit {
                let thq = dyno / s.dynold;
                if newt == 2 {
                    s.theta = thq;
                } else {
                    s.theta = (thq * s.thqold).sqrt();
                }
                s.thqold = thq;
                if s.theta < 0.99 {
                    s.faccon = s.theta / (1.0 - s.theta);
                    faccon_pending = None;
                    let dyth = s.faccon * dyno * s.theta.powi((nit - 1 - newt) as i32) / p.fnewt;
                    if dyth >= 1.0 {
                        // Predicted non-convergence: restart with a smaller h (not a
                        // rejection).
                        let qnewt = 1.0e-4f64.max(20.0f64.min(dyth));
                        s.hhfac =
                            0.8 * qnewt.powf(-1.0 / (4.0 + f64::from(nit) - 1.0 - f64::from(newt)));
                        break Newton::Restart;
                    }
                } else {
                    break Newton::Failed(Failure::Newton);
                }
            }
            s.dynold = dyno.max(p.uround);
            accumulate(
                [&mut *f1, &mut *f2, &mut *f3],
                [&mut *z1, &mut *z2, &mut *z3],
            );
            let converged = match faccon_pending {
                // base^0.8 >= min(base, 1): clearly not converged whatever the pow gives.
                Some(base) if base.min(1.0) * dyno * (1.0 - 1e-12) > p.fnewt => false,
                Some(base) => {
                    s.faccon = base.powf(0.8);
                    faccon_pending = None;
                    s.faccon * dyno <= p.fnewt
                }
                None => s.faccon * dyno <= p.fnewt,
            };
            if converged {
                break Newton::Converged(newt);
            }
        };
        if let Some(base) = faccon_pending {
            s.faccon = base.powf(0.8);
        }
        outcome
    }

    /// `ESTRAD` (radau5.md §5): the scaled error of the converged attempt (improved once
    /// by an extra f on a first step or after a rejection when it is >= 1).
    fn error_estimate<P: Problem<N>>(
        &mut self,
        problem: &mut P,
        stages: &Stages<N>,
        h: f64,
    ) -> Result<f64, Failure> {
        let Radau5 {
            st: s,
            tab,
            pattern: pat,
            blocks: blk,
            elim: el,
        } = self;
        let [z1, z2, z3] = &stages.z;
        let fac1 = tab.gamma / h;
        let hee1 = tab.dd1 / h;
        let hee2 = tab.dd2 / h;
        let hee3 = tab.dd3 / h;
        let mut cont = SVector::<f64, N>::zeros();
        let mut fm = SVector::<f64, N>::zeros(); // Fortran F2: M (d1 Z1 + d2 Z2 + d3 Z3)/h
        if s.has_mass {
            let mut fz = SVector::<f64, N>::zeros();
            for i in 0..N {
                fz[i] = hee1 * z1[i] + hee2 * z2[i] + hee3 * z3[i];
            }
            for i in 0..N {
                let mut sum = 0.0;
                for &j in pat.row(i) {
                    sum += s.mass[(i, j)] * fz[j];
                }
                fm[i] = sum;
                cont[i] = sum + s.f0[i];
            }
        } else {
            for i in 0..N {
                fm[i] = hee1 * z1[i] + hee2 * z2[i] + hee3 * z3[i];
                cont[i] = fm[i] + s.f0[i];
            }
        }
        blk.solve1(&s.lu1, el, fac1, &mut cont);
        let mut err = Self::scaled_rms(&cont, &s.scal, s.params.norm_count);
        if (err.is_nan() || err >= 1.0) && (s.first || s.reject) {
            let mut y1 = s.y;
            y1 += &cont;
            let mut f1 = SVector::<f64, N>::zeros();
            let r = eval(problem, s.t, &y1, &mut f1);
            s.stats.nfcn += 1;
            r?;
            for i in 0..N {
                cont[i] = f1[i] + fm[i];
            }
            blk.solve1(&s.lu1, el, fac1, &mut cont);
            err = Self::scaled_rms(&cont, &s.scal, s.params.norm_count);
        }
        if err.is_nan() {
            return Err(Failure::NonFinite);
        }
        Ok(err)
    }

    /// The accepted branch of `RADCOR`: f at the new point (evaluated before committing,
    /// so that a failing f shrinks h instead), the Gustafsson controller, the new state,
    /// the dense output and the next step size. Returns the new t.
    #[allow(clippy::too_many_arguments)]
    fn accept<P: Problem<N>>(
        &mut self,
        problem: &mut P,
        stages: &Stages<N>,
        at: &Attempt,
        err: f64,
        mut quot: f64,
        h_planned: f64,
        t_stop: f64,
    ) -> Result<f64, Failure> {
        let tab = &self.tab;
        let s = &mut self.st;
        let p = &s.params;
        let [z1, z2, z3] = &stages.z;
        let (t, h, last) = (s.t, at.h, at.last);
        let xph = if last { t_stop } else { t + h };
        let mut ynew = s.y;
        ynew += z3;
        let mut fnew = SVector::<f64, N>::zeros();
        if !last {
            let r = eval(problem, xph, &ynew, &mut fnew);
            s.stats.nfcn += 1;
            r?;
        }
        s.first = false;
        s.stats.naccpt += 1;
        s.naccpt_local += 1;
        let clipped = last && h < h_planned;
        let clean_clip = clipped && !s.reject;
        if p.pred && !clean_clip {
            // Predictive controller of Gustafsson
            if s.naccpt_local > 1 {
                quot =
                    gustafsson_quotient(quot, s.h_acc, h, err, s.err_acc, p.safe, p.facr, p.facl);
            }
            s.h_acc = h;
            s.err_acc = 1.0e-2f64.max(err);
        }
        let mut hnew = h / quot;
        s.t_prev = t;
        s.y_prev = s.y;
        s.f_prev = s.f0;
        s.h_old = h;
        s.t = xph;
        s.y = ynew;
        s.set_dense_output(tab, z1, z2, z3, h);
        // A renewal of the fast part that left the contraction above thet and well above
        // that after the last full J (which a J changing within the step can leave above
        // thet by itself): the slow part has aged too.
        if s.caljac {
            // Capped: a full J whose step still contracted slowly must not switch the
            // fall-back off.
            s.theta_full = s.theta.min(THETA_FULL_MAX);
        } else if s.calfast && s.theta > s.params.thet && s.theta > 2.0 * s.theta_full {
            s.fast_stale = true;
        }
        s.caljac = false;
        s.calfast = false;
        if last {
            s.f0_valid = false;
        } else {
            s.f0 = fnew;
            s.f0_valid = true;
        }
        hnew = hnew.min(s.params.h_max);
        if s.reject {
            hnew = hnew.min(h);
        }
        s.reject = false;
        s.h_next = if clean_clip && hnew >= h {
            hnew.max(s.params.resume * h_planned)
        } else {
            hnew
        };
        s.prev_clipped = last;
        s.nsing = 0;
        if last {
            s.steps_since_stop = 0;
        }
        Ok(s.t)
    }

    /// The rejected branch of `RADCOR` (err >= 1): retry with `h_new` (with h/10 on the
    /// very first step); counted in NREJCT once a step has been accepted.
    fn reject(&mut self, at: &mut Attempt, hnew: f64) {
        let s = &mut self.st;
        s.reject = true;
        at.last = false;
        if s.first {
            at.h *= 0.1;
            s.hhfac = 0.1;
        } else {
            s.hhfac = hnew / at.h;
            at.h = hnew;
        }
        if s.stats.naccpt >= 1 {
            s.stats.nrejct += 1;
        }
        // As radau5.f: a new J after every rejection (a full one also where J is split:
        // renewing only its fast part here was measured and dropped, radau5.md §8).
        s.action = next_matrices(s);
    }

    /// Newton predicted not to converge in time: retry with `h * hhfac` (set by the
    /// iteration), not counted as a rejection.
    fn restart_attempt(&mut self, at: &mut Attempt) {
        let s = &mut self.st;
        at.h *= s.hhfac;
        s.reject = true;
        at.last = false;
        s.action = next_matrices(s);
    }

    /// Label 78 of `RADCOR`: an unexpected rejection (Newton divergence, singular LU, f
    /// failing or non-finite) halves h and retries (not counted in NREJCT). Too many in a
    /// row end the step with the error of their kind.
    fn unexpected_rejection(
        &mut self,
        kind: Failure,
        n: &mut FailureCounts,
        at: &mut Attempt,
    ) -> Result<(), Error> {
        let s = &mut self.st;
        let (t, h) = (s.t, at.h);
        match kind {
            Failure::Singular => {
                s.nsing += 1;
                if s.nsing >= MAX_SINGULAR {
                    return Err(Error::SingularMatrix { t, h });
                }
            }
            Failure::Rhs(e) => {
                n.rhs += 1;
                if n.rhs >= MAX_RHS_FAILURES {
                    return Err(Error::Rhs {
                        t,
                        h,
                        message: e.message,
                    });
                }
            }
            Failure::NonFinite => {
                n.nonfinite += 1;
                if n.nonfinite >= MAX_RHS_FAILURES {
                    return Err(Error::NonFinite { t, h });
                }
            }
            Failure::Newton => {}
        }
        n.unexpected += 1;
        if n.unexpected >= MAX_UNEXPECTED {
            return Err(Error::NewtonFailure { t, h });
        }
        at.h *= 0.5;
        s.hhfac = 0.5;
        s.reject = true;
        at.last = false;
        s.action = next_matrices(s);
        Ok(())
    }
}

/// Cap of the contraction after a full J against which a renewal of the fast part of a
/// split J is judged (radau5.md §8).
const THETA_FULL_MAX: f64 = 0.1;

/// After a failed attempt: a new LU pair if J was computed in this step, else a new J
/// (`IF (CALJAC) GOTO 20; GOTO 10`).
fn next_matrices<const N: usize>(s: &State<N>) -> Action {
    if s.caljac {
        Action::Decompose
    } else {
        Action::Jacobian
    }
}

/// One simplified-Newton increment (`SLVRAD`): from f at the three stages (`a`) and the
/// accumulated stage values F (`f`) to the increments `z` in the eigenbasis of the Radau IIA
/// matrix, solved with the current LU pair (`fac`: gamma/h, alpha/h, beta/h); returns
/// `DYNO`, their RMS norm scaled by `scal`. Shared by the adaptive and the fixed step.
#[allow(clippy::too_many_arguments)]
pub(super) fn newton_increment<const N: usize>(
    s: &State<N>,
    blk: &Blocks<N>,
    el: &Elimination<N>,
    pat: &MassPattern<N>,
    (fac1, alphn, betan): (f64, f64, f64),
    [a1, a2, a3]: [&SVector<f64, N>; 3],
    [f1, f2, f3]: [&SVector<f64, N>; 3],
    [z1, z2, z3]: [&mut SVector<f64, N>; 3],
    scal: &SVector<f64, N>,
) -> f64 {
    for i in 0..N {
        let (x1, x2, x3) = (a1[i], a2[i], a3[i]);
        z1[i] = TI[0][0] * x1 + TI[0][1] * x2 + TI[0][2] * x3;
        z2[i] = TI[1][0] * x1 + TI[1][1] * x2 + TI[1][2] * x3;
        z3[i] = TI[2][0] * x1 + TI[2][1] * x2 + TI[2][2] * x3;
    }
    if s.has_mass {
        for i in 0..N {
            let (mut s1, mut s2, mut s3) = (0.0, 0.0, 0.0);
            for &j in pat.row(i) {
                let bb = s.mass[(i, j)];
                s1 -= bb * f1[j];
                s2 -= bb * f2[j];
                s3 -= bb * f3[j];
            }
            z1[i] += s1 * fac1;
            z2[i] = z2[i] + s2 * alphn - s3 * betan;
            z3[i] = z3[i] + s3 * alphn + s2 * betan;
        }
    } else {
        for i in 0..N {
            let s2 = -f2[i];
            let s3 = -f3[i];
            z1[i] -= f1[i] * fac1;
            z2[i] = z2[i] + s2 * alphn - s3 * betan;
            z3[i] = z3[i] + s3 * alphn + s2 * betan;
        }
    }
    blk.solve1(&s.lu1, el, fac1, z1);
    blk.solve2(&s.lu2, el, (alphn, betan), z2, z3);
    let mut dyno = 0.0;
    for i in 0..N {
        let denom = scal[i];
        let q1 = z1[i] / denom;
        let q2 = z2[i] / denom;
        let q3 = z3[i] / denom;
        dyno = dyno + q1 * q1 + q2 * q2 + q3 * q3;
    }
    (dyno / (3 * s.params.norm_count) as f64).sqrt()
}

/// `F_k = f(t_k, y + Z_k)` at the three collocation stages (radau5.f's three FCN calls per
/// Newton iteration, `cont` the work vector); stops at the first failing evaluation. Shared
/// by the adaptive and the fixed step.
pub(super) fn stage_rhs<P: Problem<N>, const N: usize>(
    problem: &mut P,
    y: &SVector<f64, N>,
    times: [f64; 3],
    z: [&SVector<f64, N>; 3],
    cont: &mut SVector<f64, N>,
    f: [&mut SVector<f64, N>; 3],
) -> Result<(), RhsError> {
    for ((tk, zk), fk) in times.into_iter().zip(z).zip(f) {
        cont.copy_from(y);
        *cont += zk;
        problem.rhs(tk, cont, fk)?;
    }
    Ok(())
}

/// F += Z, and Z = T F: the new stage values back from the eigenbasis.
pub(super) fn accumulate<const N: usize>(
    [f1, f2, f3]: [&mut SVector<f64, N>; 3],
    [z1, z2, z3]: [&mut SVector<f64, N>; 3],
) {
    for i in 0..N {
        let f1i = f1[i] + z1[i];
        let f2i = f2[i] + z2[i];
        let f3i = f3[i] + z3[i];
        f1[i] = f1i;
        f2[i] = f2i;
        f3[i] = f3i;
        z1[i] = T[0][0] * f1i + T[0][1] * f2i + T[0][2] * f3i;
        z2[i] = T[1][0] * f1i + T[1][1] * f2i + T[1][2] * f3i;
        z3[i] = T[2][0] * f1i + f2i;
    }
}
