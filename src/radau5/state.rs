//! The complete mutable state of the integrator as plain data (radau5.md §8): everything
//! `RADCOR` keeps in its locals and work arrays between two steps, plus what the
//! step-based API adds. A [`super::Snapshot`] is a copy of this struct.

use nalgebra::{SMatrix, SVector};

use super::linalg::{ComplexLu, RealLu};
use super::options::Params;
use super::tableau::Tableau;
use super::Statistics;

/// What the next attempt has to do first: the Fortran's labels 10 (new Jacobian),
/// 20 (new LU pair) and 30 (step with the current LU pair).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Action {
    Jacobian = 0,
    Decompose = 1,
    Step = 2,
    /// Renew only the fast part of a split Jacobian (then decompose).
    JacobianFast = 3,
}

impl Action {
    pub fn from_u8(v: u8) -> Option<Self> {
        match v {
            0 => Some(Action::Jacobian),
            1 => Some(Action::Decompose),
            2 => Some(Action::Step),
            3 => Some(Action::JacobianFast),
            _ => None,
        }
    }
}

/// Solver state (names of the Fortran variables in brackets).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct State<const N: usize> {
    pub params: Params<N>,
    /// Mass matrix (`FMAS`); only used when `has_mass`.
    pub has_mass: bool,
    pub mass: SMatrix<f64, N, N>,
    /// Current point (`X`, `Y`) and the start of the last accepted step (`XOLD`).
    pub t: f64,
    pub y: SVector<f64, N>,
    pub t_prev: f64,
    /// `y` and `f(t, y)` at `t_prev`: what [`super::Radau5::retake`] starts the last step
    /// again from (the Fortran has no use for them).
    pub y_prev: SVector<f64, N>,
    pub f_prev: SVector<f64, N>,
    /// `f(t, y)` (`Y0`); invalid after a step that landed on a stop time (the Fortran does
    /// not evaluate it after its last step either), then evaluated lazily.
    pub f0: SVector<f64, N>,
    pub f0_valid: bool,
    /// Controller proposal for the next step (`HNEW` after the h_max clip).
    pub h_next: f64,
    /// Size of the last accepted step (`HOLD`).
    pub h_old: f64,
    /// Step size the current LU pair was built with.
    pub h_lu: f64,
    /// Factor for the index-2/3 scaling (`HHFAC`).
    pub hhfac: f64,
    /// Gustafsson history (`HACC`, `ERRACC`).
    pub h_acc: f64,
    pub err_acc: f64,
    /// Newton history (`FACCON`, `THETA`, `DYNOLD`, `THQOLD`).
    pub faccon: f64,
    pub theta: f64,
    pub dynold: f64,
    pub thqold: f64,
    /// Error scale (`SCAL`).
    pub scal: SVector<f64, N>,
    /// Dense output (`CONT`, `XSOL`, `HSOL`): `u(s) = c0 + s (c1 + (s - c2m1)(c2 + (s - c1m1) c3))`.
    pub cont: [SVector<f64, N>; 4],
    pub xsol: f64,
    pub hsol: f64,
    /// Jacobian (`FJAC`) and the LU pair (`E1`, `IP1`; `E2R + i E2I`, `IP2`).
    pub jac: SMatrix<f64, N, N>,
    pub lu1: RealLu<N>,
    pub lu2: ComplexLu<N>,
    /// `FIRST`: no step accepted since the start or the last restart.
    pub first: bool,
    /// `REJECT`: the current step had a rejection or an unexpected failure.
    pub reject: bool,
    /// `CALJAC`: the Jacobian was evaluated at the current point.
    pub caljac: bool,
    pub jac_valid: bool,
    /// Split Jacobian (radau5.md §8): `jac_slow` = J - F at the last full evaluation,
    /// valid while `split`; `calfast`: the fast part F was renewed at the current point;
    /// `theta_full`: the contraction of the step right after the last full J;
    /// `fast_stale`: a step right after a renewal of F contracted slower than `thet` and
    /// than twice `theta_full`, so the slow part has aged too: the next renewal is full.
    pub jac_slow: SMatrix<f64, N, N>,
    pub split: bool,
    pub calfast: bool,
    pub theta_full: f64,
    pub fast_stale: bool,
    pub lu_valid: bool,
    /// The last accepted step was shortened to land on its stop time.
    pub prev_clipped: bool,
    pub action: Action,
    /// Singular LUs since the last accepted step (`NSING`).
    pub nsing: u32,
    /// Accepted steps since the start / last restart (gates the Gustafsson controller).
    pub naccpt_local: u64,
    /// Step attempts since the last stop time reached (compared with `max_steps`).
    pub steps_since_stop: u64,
    pub stats: Statistics,
}

impl<const N: usize> State<N> {
    /// The dense output of the step of size `h` just accepted, which ended at (`t`, `y`):
    /// the divided differences of its collocation polynomial from the stage increments
    /// z1, z2, z3 (`CONT` after label 40 of `RADCOR`). Shared by the adaptive and the
    /// fixed step.
    pub fn set_dense_output(
        &mut self,
        tab: &Tableau,
        z1: &SVector<f64, N>,
        z2: &SVector<f64, N>,
        z3: &SVector<f64, N>,
        h: f64,
    ) {
        for i in 0..N {
            let z1i = z1[i];
            let z2i = z2[i];
            self.cont[1][i] = (z2i - z3[i]) / tab.c2m1;
            let ak = (z1i - z2i) / tab.c1mc2;
            let mut acont3 = z1i / tab.c1;
            acont3 = (ak - acont3) / tab.c2;
            self.cont[2][i] = (ak - self.cont[1][i]) / tab.c1m1;
            self.cont[3][i] = self.cont[2][i] - acont3;
        }
        self.cont[0] = self.y;
        self.xsol = self.t;
        self.hsol = h;
    }

    /// A solver that has taken no step yet, at `(t, y)` with the step size `h` to try
    /// first: the state after `RADCOR`'s initialisation (FACCON = 1, THETA = |THET|, no
    /// Jacobian, zero counters), with f(t, y) not evaluated yet (`f0_valid` false) and the
    /// dense output the constant y. `mass = None` is the identity. The one place a fresh
    /// state is built: [`super::Radau5::new`], an explicit restart (which then keeps what
    /// it keeps) and the reading of a snapshot (which overwrites every field).
    pub fn fresh(
        params: Params<N>,
        mass: Option<SMatrix<f64, N, N>>,
        t: f64,
        y: SVector<f64, N>,
        h: f64,
    ) -> Self {
        let zero = SVector::zeros();
        State {
            params,
            has_mass: mass.is_some(),
            mass: mass.unwrap_or_else(SMatrix::identity),
            t,
            y,
            t_prev: t,
            y_prev: y,
            f_prev: zero,
            f0: zero,
            f0_valid: false,
            h_next: h,
            h_old: h,
            h_lu: h,
            hhfac: h,
            h_acc: 0.0,
            err_acc: 0.0,
            faccon: 1.0,
            theta: params.thet.abs(),
            dynold: 0.0,
            thqold: 0.0,
            scal: zero,
            cont: [y, zero, zero, zero],
            xsol: t,
            hsol: h,
            jac: SMatrix::zeros(),
            lu1: RealLu::zeros(),
            lu2: ComplexLu::zeros(),
            first: true,
            reject: false,
            caljac: false,
            jac_valid: false,
            jac_slow: SMatrix::zeros(),
            split: false,
            calfast: false,
            theta_full: 0.0,
            fast_stale: false,
            lu_valid: false,
            prev_clipped: false,
            action: Action::Jacobian,
            nsing: 0,
            naccpt_local: 0,
            steps_since_stop: 0,
            stats: Statistics::default(),
        }
    }
}
