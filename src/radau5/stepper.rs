//! The stepper: `RADCOR` of `radau5.f` (radau5.md §3-§5) as a step-based state machine
//! (radau5.md §8).
//!
//! One call of [`Radau5::step`] runs the Fortran's loop from the step-size decision after
//! the previous accepted step (labels 10/20/30) until the next accepted step. Everything
//! the Fortran keeps between steps lives in [`State`], so a step never depends on how the
//! integration was cut into calls, except where a stop time shortens a step.

use nalgebra::{Complex, SMatrix, SVector};

use super::linalg::{ComplexLu, RealLu};
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
}

/// Components split by [`Options::quadrature`] and [`Options::second_order`]:
/// `dyn_idx[..nd]` are factorised; `kin_idx[..nk]` obey `y_i' = y_{p(i)}`,
/// `p(i) = i + m2` (second-order structure); `quad_idx[..nq]` are pure quadratures.
/// Writing `E = c M - J` (c = gamma/h, or (alpha + i beta)/h for E2) in the order
/// (K, D, Q) gives, with `P` the 0/1 matrix picking the partners p(i),
///
/// ```text
/// [ c I     -P     0  ] [x_k]   [b_k]
/// [ -J_dk   E_dd   0  ] [x_d] = [b_d]
/// [ -J_qk   -J_qd  c I] [x_q]   [b_q]
/// ```
///
/// because row i of J is `e_p(i)` for K (and M has identity rows/columns there), and the
/// columns of J are zero for Q. Eliminating `x_k = (b_k + P x_d)/c`:
/// `(E_dd - J_dk P^T / c) x_d = b_d + J_dk b_k / c`, then x_k, then
/// `x_q = (b_q + J_qk x_k + J_qd x_d)/c`. The LUs shrink from N to nd (cost ~nd^3), which
/// is what the Fortran's `IWORK(9..10)` option does for second-order systems.
#[derive(Debug, Clone)]
pub(crate) struct Blocks<const N: usize> {
    nd: usize,
    dyn_idx: [usize; N],
    nq: usize,
    quad_idx: [usize; N],
    nk: usize,
    kin_idx: [usize; N],
    /// Position in `dyn_idx` of the partner of each K component.
    kin_partner: [usize; N],
    /// For each position r in `dyn_idx`: the K component whose partner it is (or N).
    kin_of_dyn: [usize; N],
}

impl<const N: usize> Blocks<N> {
    /// Checks the declared structure against M and the index counts.
    fn new(
        quad: &[bool; N],
        second_order: Option<(usize, usize)>,
        mass: Option<&SMatrix<f64, N, N>>,
        n1: usize,
    ) -> Result<Self, Error> {
        let mut b = Self::none();
        b.nd = 0;
        let (m1, m2) = second_order.unwrap_or((0, 0));
        if m1 > 0 && (m2 < m1 || m1 + m2 > N || m1 + m2 > n1) {
            return Err(Error::InvalidOption {
                name: "second_order",
                value: m1 as f64,
                requirement: "m1 <= m2, m1 + m2 <= n1 (the partners are index-1 components)",
            });
        }
        let identity_row_col = |i: usize| {
            mass.is_none_or(|m| {
                (0..N).all(|j| {
                    let e = if i == j { 1.0 } else { 0.0 };
                    m[(i, j)] == e && m[(j, i)] == e
                })
            })
        };
        let mut pos = [N; N];
        for i in 0..N {
            if i < m1 {
                if !identity_row_col(i) || quad[i] || quad[i + m2] {
                    return Err(Error::InvalidOption {
                        name: "second_order",
                        value: i as f64,
                        requirement:
                            "y_i' = y_(i+m2) with identity row and column of M, no quadrature",
                    });
                }
                b.kin_idx[b.nk] = i;
                b.nk += 1;
            } else if quad[i] {
                if i >= n1 || !identity_row_col(i) {
                    return Err(Error::InvalidOption {
                        name: "quadrature",
                        value: i as f64,
                        requirement: "an index-1 component with an identity row and column of M",
                    });
                }
                b.quad_idx[b.nq] = i;
                b.nq += 1;
            } else {
                pos[i] = b.nd;
                b.dyn_idx[b.nd] = i;
                b.nd += 1;
            }
        }
        b.kin_of_dyn = [N; N];
        for k in 0..b.nk {
            let r = pos[b.kin_idx[k] + m2];
            b.kin_partner[k] = r;
            b.kin_of_dyn[r] = b.kin_idx[k];
        }
        Ok(b)
    }

    /// No structure declared (the Fortran's full LUs).
    pub(crate) fn none() -> Self {
        Blocks {
            nd: N,
            dyn_idx: std::array::from_fn(|i| i),
            nq: 0,
            quad_idx: [0; N],
            nk: 0,
            kin_idx: [0; N],
            kin_partner: [0; N],
            kin_of_dyn: [N; N],
        }
    }

    fn full(&self) -> bool {
        self.nd == N
    }

    /// Builds the reduced `E1 = fac1 M_dd - J_dd + J_dk P^T / fac1` and
    /// `E2 = c2 M_dd - J_dd + J_dk P^T / c2` (c2 = alphn + i betan) and factorises them.
    #[inline(never)]
    fn decompose(&self, s: &mut State<N>, fac1: f64, (alphn, betan): (f64, f64)) -> Result<(), ()> {
        let di = &self.dyn_idx[..self.nd];
        let den = alphn * alphn + betan * betan;
        // 1/c2 = (alphn - i betan)/den.
        let (ir, ii) = (alphn / den, -betan / den);
        let inv1 = 1.0 / fac1;
        for (c, &j) in di.iter().enumerate() {
            let kj = self.kin_of_dyn[c];
            for (r, &i) in di.iter().enumerate() {
                let bb = if s.has_mass {
                    s.mass[(i, j)]
                } else if i == j {
                    1.0
                } else {
                    0.0
                };
                let mut e1 = bb * fac1 - s.jac[(i, j)];
                let mut e2 = Complex::new(bb * alphn - s.jac[(i, j)], bb * betan);
                if kj < N {
                    let jk = s.jac[(i, kj)];
                    e1 -= jk * inv1;
                    e2 = Complex::new(e2.re - jk * ir, e2.im - jk * ii);
                }
                s.lu1.a[(r, c)] = e1;
                s.lu2.a[(r, c)] = e2;
            }
        }
        if s.lu1.factor_leading(self.nd).is_ok() && s.lu2.factor_leading(self.nd).is_ok() {
            Ok(())
        } else {
            Err(())
        }
    }

    /// Solves `E1 x = b` in place (`E1 = fac1 M - J` factorised by [`Radau5::decompose`]).
    /// Inlined so that the default (full) path is the plain `SOL` call it always was.
    #[inline(always)]
    pub(super) fn solve1(
        &self,
        lu: &RealLu<N>,
        jac: &SMatrix<f64, N, N>,
        fac1: f64,
        b: &mut SVector<f64, N>,
    ) {
        if self.full() {
            lu.solve(b);
        } else {
            self.solve1_reduced(lu, jac, fac1, b);
        }
    }

    /// [`Blocks::solve1`] with eliminated components.
    #[inline(never)]
    fn solve1_reduced(
        &self,
        lu: &RealLu<N>,
        jac: &SMatrix<f64, N, N>,
        fac1: f64,
        b: &mut SVector<f64, N>,
    ) {
        let (nd, di) = (self.nd, &self.dyn_idx);
        let ki = &self.kin_idx[..self.nk];
        // b_k / fac1 once per K component (not per row: divisions are slow).
        let mut q = [0.0; N];
        for (n, &k) in ki.iter().enumerate() {
            q[n] = b[k] / fac1;
        }
        let mut c = SVector::<f64, N>::zeros();
        for r in 0..nd {
            let i = di[r];
            let mut sum = b[i];
            for (n, &k) in ki.iter().enumerate() {
                sum += jac[(i, k)] * q[n];
            }
            c[r] = sum;
        }
        lu.solve_leading(nd, &mut c);
        for r in 0..nd {
            b[di[r]] = c[r];
        }
        for (n, &k) in ki.iter().enumerate() {
            b[k] = (b[k] + c[self.kin_partner[n]]) / fac1;
        }
        for &i in &self.quad_idx[..self.nq] {
            let mut sum = b[i];
            for r in 0..nd {
                sum += jac[(i, di[r])] * c[r];
            }
            for &k in ki {
                sum += jac[(i, k)] * b[k];
            }
            b[i] = sum / fac1;
        }
    }

    /// Solves `E2 (xr + i xi) = br + i bi` in place (`E2 = (alphn + i betan) M - J`).
    #[inline(always)]
    pub(super) fn solve2(
        &self,
        lu: &ComplexLu<N>,
        jac: &SMatrix<f64, N, N>,
        ab: (f64, f64),
        br: &mut SVector<f64, N>,
        bi: &mut SVector<f64, N>,
    ) {
        if self.full() {
            lu.solve(br, bi);
        } else {
            self.solve2_reduced(lu, jac, ab, br, bi);
        }
    }

    /// [`Blocks::solve2`] with eliminated components.
    #[inline(never)]
    fn solve2_reduced(
        &self,
        lu: &ComplexLu<N>,
        jac: &SMatrix<f64, N, N>,
        (alphn, betan): (f64, f64),
        br: &mut SVector<f64, N>,
        bi: &mut SVector<f64, N>,
    ) {
        let (nd, di) = (self.nd, &self.dyn_idx);
        let ki = &self.kin_idx[..self.nk];
        let den = alphn * alphn + betan * betan;
        // 1/c2 = (ir + i ii).
        let (ir, ii) = (alphn / den, -betan / den);
        // b_k / c2 for the K components.
        let mut qr = [0.0; N];
        let mut qi = [0.0; N];
        for (n, &k) in ki.iter().enumerate() {
            qr[n] = br[k] * ir - bi[k] * ii;
            qi[n] = bi[k] * ir + br[k] * ii;
        }
        let mut cr = SVector::<f64, N>::zeros();
        let mut ci = SVector::<f64, N>::zeros();
        for r in 0..nd {
            let i = di[r];
            let (mut sr, mut si) = (br[i], bi[i]);
            for (n, &k) in ki.iter().enumerate() {
                let jv = jac[(i, k)];
                sr += jv * qr[n];
                si += jv * qi[n];
            }
            cr[r] = sr;
            ci[r] = si;
        }
        lu.solve_leading(nd, &mut cr, &mut ci);
        for r in 0..nd {
            br[di[r]] = cr[r];
            bi[di[r]] = ci[r];
        }
        for (n, &k) in ki.iter().enumerate() {
            // x_k = (b_k + x_p)/c2 = b_k/c2 + x_p/c2
            let (xr, xi) = (cr[self.kin_partner[n]], ci[self.kin_partner[n]]);
            br[k] = qr[n] + (xr * ir - xi * ii);
            bi[k] = qi[n] + (xi * ir + xr * ii);
        }
        for &i in &self.quad_idx[..self.nq] {
            let (mut sr, mut si) = (br[i], bi[i]);
            for r in 0..nd {
                let jv = jac[(i, di[r])];
                sr += jv * cr[r];
                si += jv * ci[r];
            }
            for &k in ki {
                let jv = jac[(i, k)];
                sr += jv * br[k];
                si += jv * bi[k];
            }
            br[i] = (sr * alphn + si * betan) / den;
            bi[i] = (si * alphn - sr * betan) / den;
        }
    }
}

/// Row-wise nonzero pattern of the mass matrix. Products `M x` skip the structural
/// zeros; this changes no bit of the result (the Fortran's sums start at +0 and adding
/// `0 * x_j = +-0` to a sum that is never -0 leaves it unchanged), but saves most of the
/// N^2 work for the (block-)diagonal masses of mechanical DAEs.
#[derive(Debug, Clone)]
pub(crate) struct MassPattern<const N: usize> {
    cols: [[usize; N]; N],
    len: [usize; N],
}

impl<const N: usize> MassPattern<N> {
    pub(crate) fn new(m: &SMatrix<f64, N, N>) -> Self {
        let mut cols = [[0usize; N]; N];
        let mut len = [0usize; N];
        for i in 0..N {
            for j in 0..N {
                if m[(i, j)] != 0.0 {
                    cols[i][len[i]] = j;
                    len[i] += 1;
                }
            }
        }
        MassPattern { cols, len }
    }

    #[inline]
    pub(super) fn row(&self, i: usize) -> &[usize] {
        &self.cols[i][..self.len[i]]
    }
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
    if f.iter().all(|v| v.is_finite()) {
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
        let t = s.t;
        let to_err = |e: RhsError| Error::Rhs {
            t,
            h,
            message: e.message,
        };
        if s.params.analytic_jac && problem.jacobian(t, &s.y, &mut s.jac).map_err(to_err)? {
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

    /// Builds and factorises `E1 = (gamma/h) M - J` and `E2 = ((alpha + i beta)/h) M - J`
    /// (`DECOMR`, `DECOMC`, full matrices).
    pub(super) fn decompose(&mut self, h: f64) -> Result<(), ()> {
        let s = &mut self.st;
        let fac1 = self.tab.gamma / h;
        let alphn = self.tab.alpha / h;
        let betan = self.tab.beta / h;
        let blk = &self.blocks;
        if !blk.full() {
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

    /// `max(sqrt(sum (e_i/sc_i)^2 / N), 1e-10)` in the Fortran's summation order.
    #[inline]
    pub(super) fn scaled_rms(e: &SVector<f64, N>, scal: &SVector<f64, N>) -> f64 {
        let mut err = 0.0;
        for i in 0..N {
            let q = e[i] / scal[i];
            err += q * q;
        }
        (err / N as f64).sqrt().max(1.0e-10)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// N = 6: y0' = y3 (second-order, m1 = 1, m2 = 3), y5 a quadrature, y4 with a zero mass
    /// (index-1 algebraic), the rest dense. Only the structure matters here.
    struct Structured;

    impl Problem<6> for Structured {
        fn rhs(
            &mut self,
            _t: f64,
            y: &SVector<f64, 6>,
            f: &mut SVector<f64, 6>,
        ) -> Result<(), RhsError> {
            f.copy_from(y);
            Ok(())
        }
        fn mass(&self) -> Option<SMatrix<f64, 6, 6>> {
            let mut m = SMatrix::<f64, 6, 6>::identity();
            m[(1, 2)] = 0.3;
            m[(2, 1)] = -0.2;
            m[(4, 4)] = 0.0;
            Some(m)
        }
    }

    /// The block elimination solves `E1 x = b` and `E2 x = b` exactly (to rounding) for
    /// a Jacobian with the declared structure: residuals computed with the full matrices.
    #[test]
    fn block_elimination_solves_the_full_systems() {
        let o = Options {
            quadrature: [false, false, false, false, false, true],
            second_order: Some((1, 3)),
            ..Options::default()
        };
        let mut p = Structured;
        let mut r = Radau5::new(&mut p, o, 0.0, SVector::zeros()).expect("valid");
        assert_eq!((r.blocks.nd, r.blocks.nk, r.blocks.nq), (4, 1, 1));
        let mut jac = SMatrix::<f64, 6, 6>::from_fn(|i, j| {
            (((i * 5 + j * 3) % 7) as f64 - 3.0) * if i == j { 10.0 } else { 1.0 }
        });
        jac.row_mut(0).fill(0.0);
        jac[(0, 3)] = 1.0;
        jac.column_mut(5).fill(0.0);
        r.st.jac = jac;
        let h = 0.01;
        let tab = r.tab;
        let (fac1, alphn, betan) = (tab.gamma / h, tab.alpha / h, tab.beta / h);
        r.blocks
            .decompose(&mut r.st, fac1, (alphn, betan))
            .expect("regular");
        let m = r.st.mass;
        let b = SVector::<f64, 6>::from_fn(|i, _| 1.0 + i as f64 * 0.7);
        let bi = SVector::<f64, 6>::from_fn(|i, _| (i as f64 - 2.0) * 0.3);
        let mut x = b;
        r.blocks.solve1(&r.st.lu1, &r.st.jac, fac1, &mut x);
        let res = (m * fac1 - jac) * x - b;
        assert!(res.amax() < 1e-13 * b.amax(), "real residual {res}");
        let (mut xr, mut xi) = (b, bi);
        r.blocks
            .solve2(&r.st.lu2, &r.st.jac, (alphn, betan), &mut xr, &mut xi);
        // (alphn + i betan) M - J applied to xr + i xi.
        let er = m * alphn - jac;
        let ei = m * betan;
        let rr = er * xr - ei * xi - b;
        let ri = er * xi + ei * xr - bi;
        assert!(
            rr.amax().max(ri.amax()) < 1e-13 * b.amax(),
            "complex residual {rr} {ri}"
        );
    }
}
