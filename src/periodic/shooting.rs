//! Shooting for the periodic orbit (`model.md` §11): Newton on the reduced state z at the
//! start of a mesh period, `r(z) = P(z) - z = 0` with P the period map (one RADAU5
//! integration over T_m from the consistent lift of z). The Jacobian `dP/dz` (the
//! monodromy matrix of the reduced map) comes from forward differences; its eigenvalues are
//! the Floquet multipliers: the orbit is asymptotically stable when all lie inside the
//! unit circle.

use super::{OrbitPoint, PeriodicError, PeriodicSystem, Reduced, NZ};
use crate::radau5::Statistics;
use nalgebra::{Complex, DMatrix, DVector, SMatrix, SVector};

/// Settings of [`shoot`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShootingOptions {
    /// RADAU5 relative tolerance of the period integrations. The period map is only as
    /// smooth as the step-size sequence: measured on the default pair, Newton stalls at a
    /// scaled residual of ~2e-8 with rtol 1e-9 and ~2e-9 with 1e-11, and reaches 5e-11
    /// with 1e-13 (222 steps per period).
    pub rtol: f64,
    /// Mesh periods integrated from the start state before Newton (the transient decays by
    /// the bearing damping, ~5 ms at the defaults).
    pub transient_periods: usize,
    /// Newton stops when the scaled max-norm of `P(z) - z` is at most this.
    pub tol: f64,
    /// Newton iterations at most.
    pub max_newton: usize,
    /// Forward-difference step, relative to the scale of each reduced coordinate.
    pub fd_step: f64,
    /// Equidistant samples of the converged orbit (for pictures and comparisons).
    pub samples: usize,
}

impl Default for ShootingOptions {
    fn default() -> Self {
        ShootingOptions {
            rtol: 1e-13,
            transient_periods: 20,
            tol: 1e-10,
            max_newton: 15,
            fd_step: 1e-6,
            samples: 400,
        }
    }
}

/// The converged periodic orbit.
#[derive(Debug, Clone)]
pub struct ShootingResult<const M: usize = NZ> {
    /// Periodic state at the start of the period (rigid teeth: the reduced state (u, u');
    /// elastic teeth: `elastic::ElasticReduced`).
    pub z: SVector<f64, M>,
    /// Scaled max-norm of `P(z) - z` at the solution.
    pub residual: f64,
    /// Scaled residual before each Newton update (the first is after the transient).
    pub residual_history: Vec<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Monodromy matrix dP/dz of the period map at the solution (forward differences).
    pub monodromy: SMatrix<f64, M, M>,
    /// Its eigenvalues, the Floquet multipliers, by decreasing modulus.
    pub floquet: Vec<Complex<f64>>,
    /// The orbit sampled at `ShootingOptions::samples` equidistant times over one period.
    pub orbit: Vec<OrbitPoint>,
    /// RADAU5 steps of one period integration at the solution.
    pub steps_per_period: u64,
}

impl<const M: usize> ShootingResult<M> {
    /// Largest modulus of the Floquet multipliers.
    pub fn floquet_max_abs(&self) -> f64 {
        self.floquet.first().map_or(0.0, |c| c.norm())
    }
}

fn scaled_norm<const M: usize>(r: &SVector<f64, M>, s: &SVector<f64, M>) -> f64 {
    r.iter()
        .zip(s.iter())
        .fold(0.0f64, |m, (a, b)| m.max((a / b).abs()))
}

/// A period map `z -> P(z)` of dimension M, as the shooting Newton sees it: the rigid
/// contact's reduced state (`NZ`) or the elastic contact's (`elastic::NZE`).
pub(super) trait PeriodMap<const M: usize> {
    /// `periods` periods from `z` at `rtol`, the orbit sampled if asked.
    fn integrate(
        &mut self,
        z: &SVector<f64, M>,
        periods: usize,
        rtol: f64,
        samples: Option<(usize, &mut Vec<OrbitPoint>)>,
    ) -> Result<(SVector<f64, M>, Statistics), PeriodicError>;
    /// The scale of each component (the residual's norm).
    fn scales(&self) -> SVector<f64, M>;
    /// Forward-difference steps, `rel` times the scales (not below the noise at `rtol`).
    fn fd_steps(&self, rel: f64, rtol: f64) -> SVector<f64, M>;
}

/// The rigid contact's period map on the reduced state.
struct Rigid<'a>(&'a mut PeriodicSystem);

impl PeriodMap<NZ> for Rigid<'_> {
    fn integrate(
        &mut self,
        z: &Reduced,
        periods: usize,
        rtol: f64,
        samples: Option<(usize, &mut Vec<OrbitPoint>)>,
    ) -> Result<(Reduced, Statistics), PeriodicError> {
        self.0.integrate(z, periods, rtol, samples)
    }
    fn scales(&self) -> Reduced {
        self.0.scales()
    }
    fn fd_steps(&self, rel: f64, rtol: f64) -> Reduced {
        self.0.fd_steps(rel, rtol)
    }
}

/// Forward-difference monodromy `dP/dz` around `z` with `p = P(z)` known.
pub(super) fn monodromy_of<const M: usize>(
    map: &mut impl PeriodMap<M>,
    z: &SVector<f64, M>,
    p: &SVector<f64, M>,
    rel: f64,
    rtol: f64,
) -> Result<SMatrix<f64, M, M>, PeriodicError> {
    let steps = map.fd_steps(rel, rtol);
    let mut m = SMatrix::<f64, M, M>::zeros();
    for i in 0..M {
        let d = steps[i];
        let mut zi = *z;
        zi[i] += d;
        let (pi, _) = map.integrate(&zi, 1, rtol, None)?;
        m.set_column(i, &((pi - p) / d));
    }
    Ok(m)
}

/// Periodic orbit by shooting from the reduced state `start` (e.g. the static
/// equilibrium): a transient integration, then Newton on `P(z) - z`.
///
/// # Errors
/// Solver or model errors, a singular Newton matrix, or no convergence.
pub fn shoot(
    sys: &mut PeriodicSystem,
    start: &Reduced,
    opts: &ShootingOptions,
) -> Result<ShootingResult, PeriodicError> {
    newton(&mut Rigid(sys), start, opts, "shooting")
}

/// Shooting on any period map (`method` names it in errors): a transient of
/// `opts.transient_periods` periods, then Newton on `P(z) - z` with a forward-difference
/// monodromy; at the solution the orbit sampled and the Floquet multipliers by
/// decreasing modulus.
///
/// # Errors
/// Solver or model errors, a singular Newton matrix, or no convergence.
pub(super) fn newton<const M: usize>(
    map: &mut impl PeriodMap<M>,
    start: &SVector<f64, M>,
    opts: &ShootingOptions,
    method: &'static str,
) -> Result<ShootingResult<M>, PeriodicError> {
    let scales = map.scales();
    let mut z = *start;
    if opts.transient_periods > 0 {
        z = map
            .integrate(&z, opts.transient_periods, opts.rtol, None)?
            .0;
    }
    let mut history = Vec::new();
    let mut iterations = 0;
    loop {
        let (p, _) = map.integrate(&z, 1, opts.rtol, None)?;
        let r = p - z;
        let res = scaled_norm(&r, &scales);
        history.push(res);
        let m = monodromy_of(map, &z, &p, opts.fd_step, opts.rtol)?;
        if res <= opts.tol {
            let mut orbit = Vec::with_capacity(opts.samples);
            let (_, stats) = map.integrate(&z, 1, opts.rtol, Some((opts.samples, &mut orbit)))?;
            // (Through a dynamic matrix: nalgebra's eigen and LU routines are generic over
            // the dimension, and a const-generic M would need their trait bounds spelled out.)
            let md = DMatrix::from_column_slice(M, M, m.as_slice());
            let mut floquet: Vec<Complex<f64>> = md.complex_eigenvalues().iter().copied().collect();
            floquet.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
            return Ok(ShootingResult {
                z,
                residual: res,
                residual_history: history,
                iterations,
                monodromy: m,
                floquet,
                orbit,
                steps_per_period: stats.naccpt,
            });
        }
        if iterations >= opts.max_newton {
            return Err(PeriodicError::NoConvergence {
                method,
                iterations,
                residual: res,
            });
        }
        let jac = m - SMatrix::<f64, M, M>::identity();
        let jac = DMatrix::from_column_slice(M, M, jac.as_slice());
        let dz = jac
            .lu()
            .solve(&DVector::from_column_slice((-r).as_slice()))
            .ok_or(PeriodicError::Singular { method })?;
        z += SVector::<f64, M>::from_column_slice(dz.as_slice());
        iterations += 1;
    }
}
