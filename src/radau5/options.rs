//! User options and their validation; defaults are those of `radau5.f` (radau5.md §2).

use nalgebra::SVector;

use super::Error;

/// A tolerance: one value for all components (Fortran `ITOL = 0`) or one per component
/// (`ITOL = 1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tolerance<const N: usize> {
    Scalar(f64),
    PerComponent(SVector<f64, N>),
}

impl<const N: usize> Tolerance<N> {
    pub(crate) fn component(&self, i: usize) -> f64 {
        match self {
            Tolerance::Scalar(v) => *v,
            Tolerance::PerComponent(v) => v[i],
        }
    }
}

/// Step-size controller (Fortran `IWORK(8)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Controller {
    /// Predictive controller of Gustafsson (`IWORK(8) <= 1`, the default).
    Gustafsson,
    /// Classical controller `h_new = h / quot` only (`IWORK(8) = 2`).
    Classical,
}

/// Where the Jacobian comes from (Fortran `IJAC`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JacobianMode {
    /// Ask the problem; forward differences if it answers `Ok(false)`.
    Analytic,
    /// Always forward differences (`IJAC = 0`), column j perturbed by
    /// `sqrt(uround max(1e-5, |y_j|))`.
    FiniteDifference,
}

/// Starting values of the Newton iteration (Fortran `IWORK(4)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NewtonStart {
    /// Extrapolated collocation polynomial of the last step (`IWORK(4) = 0`, default).
    Extrapolate,
    /// Zero (`IWORK(4) != 0`).
    Zero,
}

/// Options; `Default` gives the `radau5.f` defaults (radau5.md §2), each documented below
/// with the `WORK`/`IWORK` entry it corresponds to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options<const N: usize> {
    /// Relative tolerance as given by the user (transformed internally, radau5.md §3).
    /// Default 1e-6 (the Fortran has no default).
    pub rtol: Tolerance<N>,
    /// Absolute tolerance as given by the user. Default 1e-6.
    pub atol: Tolerance<N>,
    /// Initial step size; `h_init <= 10 uround` means 1e-6 (Fortran: `H` input, "1e-6 if
    /// none given").
    pub h_init: f64,
    /// Maximal step size (`WORK(7)`). `f64::INFINITY` = no limit besides the stop time: the
    /// Fortran's default "remaining interval" `XEND - X` is applied per stop time by landing
    /// exactly on it.
    pub h_max: f64,
    /// Maximal number of step attempts (`IWORK(2)`, default 100000), counted since the
    /// last stop time that was reached (or since construction / restart).
    pub max_steps: u64,
    /// Number of index-1, index-2, index-3 components (`IWORK(5..7)`); default `N, 0, 0`.
    pub n1: usize,
    pub n2: usize,
    pub n3: usize,
    /// Jacobian source (`IJAC`); default analytic if the problem provides it.
    pub jacobian: JacobianMode,
    /// Step-size controller (`IWORK(8)`); default Gustafsson.
    pub controller: Controller,
    /// Newton starting values (`IWORK(4)`); default extrapolation.
    pub newton_start: NewtonStart,
    /// Rounding unit (`WORK(1)`, default 1e-16).
    pub uround: f64,
    /// Safety factor of the step-size prediction (`WORK(2)`, default 0.9).
    pub safety: f64,
    /// Jacobian-reuse threshold theta-bar (`WORK(3)`, default 0.001).
    pub theta_jac: f64,
    /// Maximal Newton iterations per step (`IWORK(3)`, default 7).
    pub max_newton: u32,
    /// Lower bound of `h_new / h` (`WORK(8)`, default 0.2).
    pub fac_min: f64,
    /// Upper bound of `h_new / h` (`WORK(9)`, default 8).
    pub fac_max: f64,
    /// Keep h (and both LUs) when `keep_h_lo <= h_new/h <= keep_h_hi` and Newton
    /// converged fast (`WORK(5)`, `WORK(6)`: defaults 1.0 and 1.2).
    pub keep_h_lo: f64,
    pub keep_h_hi: f64,
    /// After a step shortened to land on a stop time (not in the Fortran; default 1), the
    /// next step starts at `max(h_new, resume_after_stop * h_planned)`, `h_planned` being
    /// the proposal from before the shortening and `h_new` the shortened step's own. 1 suits
    /// communication points (f as smooth after the stop as before); below 1 suits stops at
    /// kinks of f, after which the old proposal is too long (the gear model's mesh
    /// events: `sim`); 0 takes `h_new` alone. `0 <= resume_after_stop <= 1`.
    pub resume_after_stop: f64,
    /// Pure quadrature components (not in the Fortran; default none): `quadrature[i]` says
    /// that y_i enters no right-hand side (column i of J is zero) and has an identity row
    /// and column in M (index-1, `y_i' = f_i(t, y)`), e.g. energy accumulators. Then
    /// `E1`, `E2` are block lower-triangular: the stepper factorises only the block of the
    /// other components and gets y_i by forward substitution (radau5.md §4), and a
    /// difference Jacobian skips column i. Entries of J in such a column are ignored.
    /// Changes rounding (not the method): keep it off for Fortran parity.
    pub quadrature: [bool; N],
    /// Second-order structure `(m1, m2)` (the Fortran's `IWORK(9)`, `IWORK(10)`; default
    /// none): `y_i' = y_(i+m2)` for `i < m1`, with identity rows and columns of M there.
    /// The stepper then eliminates these components from the linear systems (LUs of
    /// size N - m1 - #quadratures). Rows `i < m1` of J are taken as `e_(i+m2)` whatever the
    /// Jacobian says. Changes rounding (not the method): keep it off for Fortran parity.
    pub second_order: Option<(usize, usize)>,
    /// The number of components the error and Newton norms average over (radau5.f: N,
    /// the default; `1 <= norm_count <= N`). A problem with components that stay zero in
    /// some configurations (e.g. an energy that only one contact model accumulates) gives
    /// the count of the others there, so that its steps are those of the smaller system.
    pub norm_count: usize,
}

impl<const N: usize> Default for Options<N> {
    fn default() -> Self {
        Options {
            rtol: Tolerance::Scalar(1e-6),
            atol: Tolerance::Scalar(1e-6),
            h_init: 1e-6,
            h_max: f64::INFINITY,
            max_steps: 100_000,
            n1: N,
            n2: 0,
            n3: 0,
            jacobian: JacobianMode::Analytic,
            controller: Controller::Gustafsson,
            newton_start: NewtonStart::Extrapolate,
            uround: 1e-16,
            safety: 0.9,
            theta_jac: 0.001,
            max_newton: 7,
            fac_min: 0.2,
            fac_max: 8.0,
            keep_h_lo: 1.0,
            keep_h_hi: 1.2,
            resume_after_stop: 1.0,
            quadrature: [false; N],
            second_order: None,
            norm_count: N,
        }
    }
}

/// The validated, internal form of the options (what `RADAU5` hands to `RADCOR`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Params<const N: usize> {
    /// Transformed tolerances `rtol' = 0.1 rtol^(2/3)`, `atol' = rtol' atol/rtol` (§3).
    pub rtol: SVector<f64, N>,
    pub atol: SVector<f64, N>,
    /// Newton stopping tolerance `kappa = max(10 uround/rtol'_1, min(0.03, sqrt(rtol'_1)))`.
    pub fnewt: f64,
    pub h_init: f64,
    pub h_max: f64,
    pub nmax: u64,
    pub n1: usize,
    pub n2: usize,
    pub n3: usize,
    pub analytic_jac: bool,
    pub pred: bool,
    pub startn: bool,
    pub uround: f64,
    pub safe: f64,
    pub thet: f64,
    pub nit: u32,
    /// `FACL = 1/fac_min`, `FACR = 1/fac_max` (bounds of `quot = h/h_new`).
    pub facl: f64,
    pub facr: f64,
    pub quot1: f64,
    pub quot2: f64,
    /// `Options::resume_after_stop`.
    pub resume: f64,
    /// `Options::norm_count`.
    pub norm_count: usize,
}

fn invalid(name: &'static str, value: f64, requirement: &'static str) -> Error {
    Error::InvalidOption {
        name,
        value,
        requirement,
    }
}

/// Transforms user tolerances like `RADAU5` does (radau5.md §3); rejects `atol <= 0` and
/// `rtol <= 10 uround` ("TOLERANCES ARE TOO SMALL").
pub(crate) fn transform_tolerances<const N: usize>(
    rtol: &Tolerance<N>,
    atol: &Tolerance<N>,
    uround: f64,
) -> Result<(SVector<f64, N>, SVector<f64, N>), Error> {
    let expm = 2.0 / 3.0;
    let mut r = SVector::<f64, N>::zeros();
    let mut a = SVector::<f64, N>::zeros();
    for i in 0..N {
        let ri = rtol.component(i);
        let ai = atol.component(i);
        if ai.is_nan() || ai <= 0.0 {
            return Err(invalid("atol", ai, "atol > 0"));
        }
        if ri.is_nan() || ri <= 10.0 * uround || !ri.is_finite() {
            return Err(invalid("rtol", ri, "10 uround < rtol < inf"));
        }
        if !ai.is_finite() {
            return Err(invalid("atol", ai, "atol finite"));
        }
        let quot = ai / ri;
        r[i] = 0.1 * ri.powf(expm);
        a[i] = r[i] * quot;
    }
    Ok((r, a))
}

impl<const N: usize> Params<N> {
    /// Checks every option (the Fortran's "CURIOUS INPUT" tests) and derives the internals.
    pub fn new(o: &Options<N>) -> Result<Self, Error> {
        if !(o.uround > 1e-19 && o.uround < 1.0) {
            return Err(invalid("uround", o.uround, "1e-19 < uround < 1"));
        }
        if !(o.safety > 0.001 && o.safety < 1.0) {
            return Err(invalid("safety", o.safety, "0.001 < safety < 1"));
        }
        if o.theta_jac.is_nan() || o.theta_jac >= 1.0 {
            return Err(invalid("theta_jac", o.theta_jac, "theta_jac < 1"));
        }
        if o.max_newton == 0 || o.max_newton > 1000 {
            return Err(invalid(
                "max_newton",
                f64::from(o.max_newton),
                "1 <= max_newton <= 1000",
            ));
        }
        if o.max_steps == 0 {
            return Err(invalid("max_steps", 0.0, "max_steps >= 1"));
        }
        if !(o.keep_h_lo <= 1.0 && o.keep_h_lo > 0.0) {
            return Err(invalid("keep_h_lo", o.keep_h_lo, "0 < keep_h_lo <= 1"));
        }
        if o.keep_h_hi.is_nan() || o.keep_h_hi < 1.0 {
            return Err(invalid("keep_h_hi", o.keep_h_hi, "keep_h_hi >= 1"));
        }
        if !(1..=N).contains(&o.norm_count) {
            return Err(invalid(
                "norm_count",
                o.norm_count as f64,
                "1 <= norm_count <= N",
            ));
        }
        if !(0.0..=1.0).contains(&o.resume_after_stop) {
            return Err(invalid(
                "resume_after_stop",
                o.resume_after_stop,
                "0 <= resume_after_stop <= 1",
            ));
        }
        if !(o.fac_min > 0.0 && o.fac_min <= 1.0) {
            return Err(invalid("fac_min", o.fac_min, "0 < fac_min <= 1"));
        }
        if o.fac_max.is_nan() || o.fac_max < 1.0 {
            return Err(invalid("fac_max", o.fac_max, "fac_max >= 1"));
        }
        if o.h_max.is_nan() || o.h_max <= 0.0 {
            return Err(invalid("h_max", o.h_max, "h_max > 0"));
        }
        if !(o.h_init >= 0.0 && o.h_init.is_finite()) {
            return Err(invalid("h_init", o.h_init, "0 <= h_init < inf"));
        }
        if o.n1 + o.n2 + o.n3 != N {
            return Err(invalid("n1", o.n1 as f64, "n1 + n2 + n3 = N"));
        }
        let (rtol, atol) = transform_tolerances(&o.rtol, &o.atol, o.uround)?;
        let tolst = rtol[0];
        let fnewt = (10.0 * o.uround / tolst).max(0.03f64.min(tolst.powf(0.5)));
        let h_init = if o.h_init.abs() <= 10.0 * o.uround {
            1.0e-6
        } else {
            o.h_init
        };
        Ok(Params {
            rtol,
            atol,
            fnewt,
            h_init,
            h_max: o.h_max,
            nmax: o.max_steps,
            n1: o.n1,
            n2: o.n2,
            n3: o.n3,
            analytic_jac: o.jacobian == JacobianMode::Analytic,
            pred: o.controller == Controller::Gustafsson,
            startn: o.newton_start == NewtonStart::Zero,
            uround: o.uround,
            safe: o.safety,
            thet: o.theta_jac,
            nit: o.max_newton,
            facl: 1.0 / o.fac_min,
            facr: 1.0 / o.fac_max,
            quot1: o.keep_h_lo,
            quot2: o.keep_h_hi,
            resume: o.resume_after_stop,
            norm_count: o.norm_count,
        })
    }
}
