//! The stepper: `RADCOR` of `radau5.f` (radau5.md §3-§5) as a step-based state machine
//! (radau5.md §8).
//!
//! One call of [`Radau5::step`] runs the Fortran's loop from the step-size decision after
//! the previous accepted step (labels 10/20/30) until the next accepted step. Everything
//! the Fortran keeps between steps lives in [`State`], so a step never depends on how the
//! integration was cut into calls, except where a stop time shortens a step.

use nalgebra::{Complex, SMatrix, SVector};

use super::linear_systems::{Blocks, Elimination, MassPattern};
use super::options::{transform_tolerances, Params};
use super::state::State;
use super::tableau::Tableau;
use super::{Error, Options, Problem, RhsError, Statistics, Tolerance};

/// Consecutive failures of f (an `Err` or non-finite values) within one step after which
/// the step gives up (each failure halves h like a Newton failure).
pub(super) const MAX_RHS_FAILURES: u32 = 10;
/// Consecutive unexpected rejections (Newton divergence, singular LU, failing f) within
/// one step after which the step gives up with [`Error::NewtonFailure`]. The Fortran has no
/// such limit (it relies on "step size too small", which never triggers at t = 0).
pub(super) const MAX_UNEXPECTED: u32 = 20;
/// Singular LU pairs in a row -> [`Error::SingularMatrix`] (`NSING >= 5` in `RADCOR`).
pub(super) const MAX_SINGULAR: u32 = 5;

/// How [`Radau5::retake`] reached its stop time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Retake {
    /// By a step from the start of the last step (the normal case).
    Exact,
    /// That step failed; continued from the dense output with an explicit restart.
    Interpolated,
}

/// The RADAU5 integrator for `M y' = f(t, y)` with N components, fixed-size storage.
#[derive(Debug, Clone)]
pub struct Radau5<const N: usize> {
    pub(crate) st: State<N>,
    pub(crate) tab: Tableau,
    /// Nonzero columns of each row of M (derived from `st.mass`, not part of the state).
    pub(crate) pattern: MassPattern<N>,
    /// Split into factorised and quadrature components (from `Options::quadrature`; a
    /// property of the problem, not part of the state: a restored snapshot keeps it).
    pub(crate) blocks: Blocks<N>,
    /// The blocks of J the reduced solves read, packed with every decomposition.
    pub(crate) elim: Elimination<N>,
}

/// Why an attempt failed "unexpectedly" (the Fortran's label 78).
pub(super) enum Failure {
    Newton,
    Singular,
    Rhs(RhsError),
    NonFinite,
}

/// A state handed to the stepper from outside must be finite (named `name` in the error).
pub(super) fn check_finite<const N: usize>(
    name: &'static str,
    y: &SVector<f64, N>,
) -> Result<(), Error> {
    match y.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(Error::InvalidOption {
            name,
            value: *v,
            requirement: "finite",
        }),
        None => Ok(()),
    }
}

/// Evaluates f and checks it for NaN/inf.
#[inline]
pub(super) fn eval<P: Problem<N>, const N: usize>(
    problem: &mut P,
    t: f64,
    y: &SVector<f64, N>,
    f: &mut SVector<f64, N>,
) -> Result<(), Failure> {
    problem.rhs(t, y, f).map_err(Failure::Rhs)?;
    if f.as_slice().iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Failure::NonFinite)
    }
}

impl<const N: usize> Radau5<N> {
    /// Sets up the integrator at `(t0, y0)` (the initialisation part of `RADCOR`):
    /// validates the options, reads the mass matrix, evaluates `f(t0, y0)` (1 call).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a bad option or non-finite `t0`/`y0`; [`Error::Rhs`] /
    /// [`Error::NonFinite`] if f cannot be evaluated at the initial point.
    pub fn new<P: Problem<N>>(
        problem: &mut P,
        options: Options<N>,
        t0: f64,
        y0: SVector<f64, N>,
    ) -> Result<Self, Error> {
        let params = Params::new(&options)?;
        if !t0.is_finite() {
            return Err(Error::InvalidOption {
                name: "t0",
                value: t0,
                requirement: "finite",
            });
        }
        check_finite("y0", &y0)?;
        let mass = problem.mass();
        let blocks = if options.quadrature.iter().any(|&q| q) || options.second_order.is_some() {
            Blocks::new(
                &options.quadrature,
                options.second_order,
                mass.as_ref(),
                params.n1,
            )?
        } else {
            Blocks::none()
        };
        let tab = Tableau::new();
        let h = params.h_init;
        let mut st = State::fresh(params, mass, t0, y0, h);
        let mut f0 = SVector::zeros();
        let r = eval(problem, t0, &y0, &mut f0);
        st.stats.nfcn += 1;
        Self::point_eval_error(r, t0, h)?;
        st.f0 = f0;
        st.f_prev = f0;
        st.f0_valid = true;
        let pattern = MassPattern::new(&st.mass);
        Ok(Radau5 {
            st,
            tab,
            pattern,
            blocks,
            elim: Elimination::zeros(),
        })
    }

    /// Maps a failed evaluation of f at an accepted point (start, restart, after a stop
    /// time) to the typed error: there is no step to shrink there.
    pub(super) fn point_eval_error(r: Result<(), Failure>, t: f64, h: f64) -> Result<(), Error> {
        match r {
            Ok(()) => Ok(()),
            Err(Failure::Rhs(e)) => Err(Error::Rhs {
                t,
                h,
                message: e.message,
            }),
            Err(_) => Err(Error::NonFinite { t, h }),
        }
    }

    /// Current time (end of the last accepted step).
    pub fn t(&self) -> f64 {
        self.st.t
    }
    /// Current state.
    pub fn y(&self) -> &SVector<f64, N> {
        &self.st.y
    }
    /// Start of the last accepted step.
    pub fn t_prev(&self) -> f64 {
        self.st.t_prev
    }
    /// The state at [`Radau5::t_prev`] as the last step started from it (exact, not the
    /// dense output there, which differs by its interpolation error).
    pub fn y_prev(&self) -> &SVector<f64, N> {
        &self.st.y_prev
    }
    /// Step size the next step will try (the controller's proposal, before any stop-time
    /// clipping).
    pub fn h(&self) -> f64 {
        self.st.h_next
    }
    /// Work counters (radau5.md §7).
    pub fn stats(&self) -> &Statistics {
        &self.st.stats
    }

    /// Steps until `t == t_stop` exactly. Nothing is reset at `t_stop`: h, J, the LUs,
    /// FACCON and the error history carry over into the next call.
    ///
    /// # Errors
    /// See [`Radau5::step`].
    pub fn integrate_to<P: Problem<N>>(
        &mut self,
        problem: &mut P,
        t_stop: f64,
    ) -> Result<(), Error> {
        if t_stop.is_nan() || t_stop < self.st.t {
            return Err(Error::StopTimeBehind {
                t: self.st.t,
                t_stop,
            });
        }
        while self.st.t < t_stop {
            self.step(problem, t_stop)?;
        }
        Ok(())
    }

    /// Replaces the tolerances (transformed like at construction, radau5.md §3); takes
    /// effect from the next step.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for `atol <= 0` or `rtol <= 10 uround`.
    pub fn set_tolerances(&mut self, rtol: Tolerance<N>, atol: Tolerance<N>) -> Result<(), Error> {
        let p = &mut self.st.params;
        let (r, a) = transform_tolerances(&rtol, &atol, p.uround)?;
        p.rtol = r;
        p.atol = a;
        let tolst = r[0];
        p.fnewt = (10.0 * p.uround / tolst).max(0.03f64.min(tolst.powf(0.5)));
        Ok(())
    }

    /// Explicit restart at the current t with state `y` (after an input discontinuity):
    /// evaluates `f(t, y)`, marks J stale, forgets the Newton extrapolation, FACCON and the
    /// Gustafsson error history (the next step is treated like the Fortran's first step);
    /// keeps the proposed h unless `h` is given.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a non-finite `y` or non-positive `h`; [`Error::Rhs`] /
    /// [`Error::NonFinite`] if f cannot be evaluated at the new point.
    pub fn restart<P: Problem<N>>(
        &mut self,
        problem: &mut P,
        y: SVector<f64, N>,
        h: Option<f64>,
    ) -> Result<(), Error> {
        check_finite("y", &y)?;
        if let Some(h) = h {
            if !(h > 0.0 && h.is_finite()) {
                return Err(Error::InvalidOption {
                    name: "h",
                    value: h,
                    requirement: "0 < h < inf",
                });
            }
        }
        let mut f0 = SVector::zeros();
        let r = eval(problem, self.st.t, &y, &mut f0);
        self.st.stats.nfcn += 1;
        Self::point_eval_error(r, self.st.t, self.st.h_next)?;
        let old = &self.st;
        // A fresh start at (t, y) (treated like the Fortran's first step; the old
        // collocation polynomial does not pass through the new y, so the dense output is
        // the constant y until the next step) that keeps the counters, J and the LU pair
        // (both marked stale), and the step-size history the first step does not read.
        let mut s = State::fresh(
            old.params,
            old.has_mass.then_some(old.mass),
            old.t,
            y,
            h.unwrap_or(old.h_next),
        );
        s.stats = old.stats;
        s.jac = old.jac;
        s.lu1 = old.lu1;
        s.lu2 = old.lu2;
        s.h_old = old.h_old;
        s.h_lu = old.h_lu;
        s.hhfac = old.hhfac;
        s.dynold = old.dynold;
        s.thqold = old.thqold;
        s.scal = old.scal;
        s.hsol = old.hsol;
        s.f0 = f0;
        s.f0_valid = true;
        s.f_prev = f0;
        self.st = s;
        Ok(())
    }

    /// Co-simulation: f changed at the current point in a way its Jacobian does not see (a
    /// new value of an input that enters f additively, like a held reference or a load),
    /// and `y` may carry re-projected algebraic components. Evaluates `f(t, y)`; h, J, the
    /// LU pair, the Newton start (extrapolated from the last step's collocation polynomial)
    /// and the controller history are kept, so the next step is an ordinary step of the
    /// new right-hand side from `t`. Cheaper than [`Radau5::restart`], which also discards
    /// J and starts like a first step; use that when J changes (a new parameter).
    /// The last step can no longer be retaken (`t_prev = t`).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a non-finite `y`; [`Error::Rhs`] / [`Error::NonFinite`]
    /// if f cannot be evaluated there.
    pub fn refresh<P: Problem<N>>(
        &mut self,
        problem: &mut P,
        y: SVector<f64, N>,
    ) -> Result<(), Error> {
        self.refresh_f(problem, y)?;
        let s = &mut self.st;
        s.cont[0] = y;
        s.t_prev = s.t;
        s.y_prev = y;
        s.f_prev = s.f0;
        Ok(())
    }

    /// Replaces `y` at the current point (e.g. re-projected algebraic components) and
    /// re-evaluates the stored `f(t, y)` with `problem`; keeps h, J, the LU pair, the
    /// controller, the dense output and the last step for [`Radau5::retake`] (which starts
    /// from `t_prev` and discards both). For a caller whose f jumps at t, where the step
    /// just ended: f evaluated as its limit from after the jump (and the algebraic
    /// components that jump with it) lets the next step start consistently, whereas its
    /// error estimate would combine the f from before with stages that all lie after.
    /// f changed here, so the Newton rate measured before is forgotten too
    /// ([`Radau5::forget_convergence_rate`]): the next step starts from a polynomial that
    /// no longer fits and must measure its own contraction.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a non-finite `y`; [`Error::Rhs`] / [`Error::NonFinite`]
    /// if f cannot be evaluated there (nothing changed then).
    pub fn refresh_f<P: Problem<N>>(
        &mut self,
        problem: &mut P,
        y: SVector<f64, N>,
    ) -> Result<(), Error> {
        check_finite("y", &y)?;
        let s = &mut self.st;
        let mut f0 = SVector::zeros();
        let r = eval(problem, s.t, &y, &mut f0);
        s.stats.nfcn += 1;
        Self::point_eval_error(r, s.t, s.h_next)?;
        s.y = y;
        s.f0 = f0;
        s.f0_valid = true;
        self.forget_convergence_rate();
        Ok(())
    }

    /// Co-simulation: replaces the last accepted step `[t_prev, t]` by a step from `t_prev`
    /// that lands exactly on `t_stop` (`t_prev < t_stop <= t`), as if `t_stop` had been its
    /// stop time. For a caller that stepped past a point at which f is about to change (an
    /// FMU whose step went beyond the communication point and whose input then changed):
    /// the state at `t_stop` is then a solution point, not the dense output.
    ///
    /// The step starts from the stored `y`, `f` at `t_prev` with the accepted step size as
    /// the proposal (the clip to `t_stop` keeps it, like any stop time); J is kept, the LU
    /// pair is rebuilt for the shorter h. Counted in the statistics like any step. Should
    /// that step fail (it is shorter than one that succeeded, so only in pathological
    /// cases), the stepper continues instead from the collocation polynomial's value at
    /// `t_stop` with an explicit [`Radau5::restart`] ([`Retake::Interpolated`]).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] if `t_stop` is not inside the last accepted step; the
    /// errors of [`Radau5::restart`] if even the fallback cannot evaluate f.
    pub fn retake<P: Problem<N>>(&mut self, problem: &mut P, t_stop: f64) -> Result<Retake, Error> {
        if t_stop == self.st.t {
            return Ok(Retake::Exact);
        }
        if !(t_stop > self.st.t_prev && t_stop < self.st.t) {
            return Err(Error::InvalidOption {
                name: "t_stop",
                value: t_stop,
                requirement: "t_prev < t_stop <= t (inside the last accepted step)",
            });
        }
        let mut y_fallback = SVector::zeros();
        self.dense_output(t_stop, &mut y_fallback);
        let (t_prev, y_prev, f_prev, h_old) = (
            self.st.t_prev,
            self.st.y_prev,
            self.st.f_prev,
            self.st.h_old,
        );
        let saved = self.snapshot();
        {
            let s = &mut self.st;
            s.t = t_prev;
            s.y = y_prev;
            s.f0 = f_prev;
            s.f0_valid = true;
            s.h_next = h_old;
            // The LU pair belongs to h_old; a shorter step needs its own.
            s.prev_clipped = false;
            s.reject = false;
        }
        let mut failed = false;
        while self.st.t < t_stop {
            if self.step(problem, t_stop).is_err() {
                failed = true;
                break;
            }
        }
        if !failed {
            return Ok(Retake::Exact);
        }
        let stats = self.st.stats;
        self.restore(&saved);
        self.st.stats = stats;
        self.st.t = t_stop;
        self.restart(problem, y_fallback, None)?;
        Ok(Retake::Interpolated)
    }

    /// The caller stopped on a point where the problem's Jacobian jumps (a kink of f; a
    /// jump or a new f goes through [`Radau5::refresh_f`], which does this itself): the
    /// Newton convergence rate measured
    /// before it (`FACCON`, docs/radau5.md §4) says nothing about the iteration after it.
    /// Resets it to its value at the start (1), so that the next step accepts its first
    /// iterate only if that iterate's increment is itself within the Newton tolerance
    /// (`||dW|| <= kappa`), and otherwise iterates until it has measured its own
    /// contraction.
    /// J, the LU pair, h and the controller history are kept.
    ///
    /// Why: with a rate of ~1e-3 from the smooth part, FACCON ||dW|| <= kappa accepts the
    /// first iterate of a step whose increment is up to ~30 tolerances, and across a kink
    /// the old J makes that iterate wrong by a fraction of the increment, which the error
    /// estimate (5.1) does not see (it measures the collocation polynomial against f at
    /// the start, not the unsolved collocation equations).
    pub fn forget_convergence_rate(&mut self) {
        self.st.faccon = 1.0;
    }

    /// Co-simulation: starts a new budget of `max_steps` step attempts. The budget is
    /// otherwise renewed only when a stop time is reached, which a caller that steps with a
    /// far stop time (and interpolates the dense output) may never do.
    pub fn reset_step_count(&mut self) {
        self.st.steps_since_stop = 0;
    }

    /// Forward-difference or analytic Jacobian at the current point (label 10).
    pub(super) fn compute_jacobian<P: Problem<N>>(
        &mut self,
        problem: &mut P,
        h: f64,
    ) -> Result<(), Error> {
        let s = &mut self.st;
        s.stats.njac += 1;
        // J is overwritten from here on: should f fail half-way, neither J nor the LU pair
        // (which belongs to the old J) may be used until a new J is decomposed.
        s.jac_valid = false;
        s.lu_valid = false;
        let t = s.t;
        let to_err = |e: RhsError| Error::Rhs {
            t,
            h,
            message: e.message,
        };
        // A new full J: no split (and nothing aged) unless this one is analytic and split.
        s.split = false;
        s.fast_stale = false;
        if s.params.analytic_jac && problem.jacobian(t, &s.y, &mut s.jac).map_err(to_err)? {
            // Split Jacobian (radau5.md §8): keep the slow part S = J - F for the renewals
            // of F alone.
            let mut fast = SMatrix::<f64, N, N>::zeros();
            if problem.jacobian_fast(t, &s.y, &mut fast).map_err(to_err)? {
                s.jac_slow = s.jac - fast;
                s.split = true;
            }
            return Ok(());
        }
        let mut ytmp = s.y;
        let mut ft = SVector::<f64, N>::zeros();
        for &i in &self.blocks.quad_idx[..self.blocks.nq] {
            s.jac.column_mut(i).fill(0.0);
        }
        let quads = &self.blocks.quad_idx[..self.blocks.nq];
        for i in 0..N {
            if quads.contains(&i) {
                continue;
            }
            let ysafe = ytmp[i];
            let delt = (s.params.uround * 1.0e-5f64.max(ysafe.abs())).sqrt();
            ytmp[i] = ysafe + delt;
            problem.rhs(t, &ytmp, &mut ft).map_err(to_err)?;
            for j in 0..N {
                s.jac[(j, i)] = (ft[j] - s.f0[j]) / delt;
            }
            ytmp[i] = ysafe;
        }
        Ok(())
    }

    /// Renews only the fast part of a split Jacobian at the current point, `J = S + F(t,
    /// y)` (radau5.md §8), and returns true; a full [`Radau5::compute_jacobian`] where the
    /// problem declines (false).
    pub(super) fn compute_jacobian_fast<P: Problem<N>>(
        &mut self,
        problem: &mut P,
        h: f64,
    ) -> Result<bool, Error> {
        let s = &mut self.st;
        let t = s.t;
        let mut fast = SMatrix::<f64, N, N>::zeros();
        let given = problem
            .jacobian_fast(t, &s.y, &mut fast)
            .map_err(|e| Error::Rhs {
                t,
                h,
                message: e.message,
            })?;
        if !given {
            self.compute_jacobian(problem, h)?;
            return Ok(false);
        }
        s.stats.njac_fast += 1;
        s.jac = s.jac_slow + fast;
        // J changed: the LU pair belongs to the old one.
        s.lu_valid = false;
        Ok(true)
    }

    /// Builds and factorises `E1 = (gamma/h) M - J` and `E2 = ((alpha + i beta)/h) M - J`
    /// (`DECOMR`, `DECOMC`, full matrices).
    pub(super) fn decompose(&mut self, h: f64) -> Result<(), ()> {
        let s = &mut self.st;
        let fac1 = self.tab.gamma / h;
        let alphn = self.tab.alpha / h;
        let betan = self.tab.beta / h;
        let blk = &self.blocks;
        if !blk.full() {
            blk.pack(&s.jac, &mut self.elim);
            if blk.decompose(s, fac1, (alphn, betan)).is_err() {
                s.lu_valid = false;
                return Err(());
            }
            s.stats.ndec += 1;
            s.h_lu = h;
            s.lu_valid = true;
            return Ok(());
        }
        if s.has_mass {
            for j in 0..N {
                for i in 0..N {
                    let bb = s.mass[(i, j)];
                    s.lu1.a[(i, j)] = bb * fac1 - s.jac[(i, j)];
                    s.lu2.a[(i, j)] = Complex::new(bb * alphn - s.jac[(i, j)], bb * betan);
                }
            }
        } else {
            for j in 0..N {
                for i in 0..N {
                    s.lu1.a[(i, j)] = -s.jac[(i, j)];
                    s.lu2.a[(i, j)] = Complex::new(-s.jac[(i, j)], 0.0);
                }
                s.lu1.a[(j, j)] += fac1;
                let d = s.lu2.a[(j, j)];
                s.lu2.a[(j, j)] = Complex::new(d.re + alphn, betan);
            }
        }
        let r1 = s.lu1.factor();
        if r1.is_err() {
            s.lu_valid = false;
            return Err(());
        }
        if s.lu2.factor().is_err() {
            s.lu_valid = false;
            return Err(());
        }
        s.stats.ndec += 1;
        s.h_lu = h;
        s.lu_valid = true;
        Ok(())
    }

    /// `max(sqrt(sum (e_i/sc_i)^2 / n), 1e-10)` in the Fortran's summation order, with
    /// `n = Options::norm_count` (N in the Fortran).
    #[inline]
    pub(super) fn scaled_rms(e: &SVector<f64, N>, scal: &SVector<f64, N>, n: usize) -> f64 {
        let mut err = 0.0;
        for i in 0..N {
            let q = e[i] / scal[i];
            err += q * q;
        }
        (err / n as f64).sqrt().max(1.0e-10)
    }

    /// Value of the collocation polynomial of the last accepted step at `t`
    /// (`CONTR5`, radau5.md §6); meant for `t` in `[t_prev, t]`.
    pub fn dense_output(&self, t: f64, y: &mut SVector<f64, N>) {
        let s = &self.st;
        let c2m1 = self.tab.c2m1;
        let c1m1 = self.tab.c1m1;
        let x = (t - s.xsol) / s.hsol;
        for i in 0..N {
            y[i] = s.cont[0][i]
                + x * (s.cont[1][i] + (x - c2m1) * (s.cont[2][i] + (x - c1m1) * s.cont[3][i]));
        }
    }

    /// First derivative in t of the collocation polynomial of the last accepted step.
    pub fn dense_derivative(&self, t: f64, dy: &mut SVector<f64, N>) {
        let s = &self.st;
        let c2m1 = self.tab.c2m1;
        let c1m1 = self.tab.c1m1;
        let x = (t - s.xsol) / s.hsol;
        let a = x - c2m1;
        let b = x - c1m1;
        for i in 0..N {
            let (c1, c2, c3) = (s.cont[1][i], s.cont[2][i], s.cont[3][i]);
            let inner = c2 + b * c3;
            let du = c1 + a * inner + x * (inner + a * c3);
            dy[i] = du / s.hsol;
        }
    }
}
