//! Shooting for the periodic orbit (`model.md` §11): Newton on the reduced state z at the
//! start of a mesh period, `r(z) = P(z) - z = 0` with P the period map (one RADAU5
//! integration over T_m from the consistent lift of z). The Jacobian `dP/dz` (the
//! monodromy matrix of the reduced map) comes from forward differences; its eigenvalues are
//! the Floquet multipliers: the orbit is asymptotically stable when all lie inside the
//! unit circle.

use super::{OrbitPoint, PeriodicError, PeriodicSystem, Reduced, NZ};
use nalgebra::{Complex, SMatrix};

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
pub struct ShootingResult {
    /// Reduced state (u, u') at the start of the period.
    pub z: Reduced,
    /// Scaled max-norm of `P(z) - z` at the solution.
    pub residual: f64,
    /// Scaled residual before each Newton update (the first is after the transient).
    pub residual_history: Vec<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Monodromy matrix dP/dz of the reduced period map at the solution.
    pub monodromy: SMatrix<f64, NZ, NZ>,
    /// Its eigenvalues, the Floquet multipliers, by decreasing modulus.
    pub floquet: Vec<Complex<f64>>,
    /// The orbit sampled at `ShootingOptions::samples` equidistant times over one period.
    pub orbit: Vec<OrbitPoint>,
    /// RADAU5 steps of one period integration at the solution.
    pub steps_per_period: u64,
}

impl ShootingResult {
    /// Largest modulus of the Floquet multipliers.
    pub fn floquet_max_abs(&self) -> f64 {
        self.floquet.first().map_or(0.0, |c| c.norm())
    }
}

fn scaled_norm(r: &Reduced, s: &Reduced) -> f64 {
    r.iter()
        .zip(s.iter())
        .fold(0.0f64, |m, (a, b)| m.max((a / b).abs()))
}

/// Forward-difference monodromy `dP/dz` around `z` with `p = P(z)` known.
fn monodromy(
    sys: &mut PeriodicSystem,
    z: &Reduced,
    p: &Reduced,
    opts: &ShootingOptions,
) -> Result<SMatrix<f64, NZ, NZ>, PeriodicError> {
    let steps = sys.fd_steps(opts.fd_step, opts.rtol);
    let mut m = SMatrix::<f64, NZ, NZ>::zeros();
    for i in 0..NZ {
        let d = steps[i];
        let mut zi = *z;
        zi[i] += d;
        let (pi, _) = sys.integrate(&zi, 1, opts.rtol, None)?;
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
    let scales = sys.scales();
    let mut z = *start;
    if opts.transient_periods > 0 {
        z = sys
            .integrate(&z, opts.transient_periods, opts.rtol, None)?
            .0;
    }
    let mut history = Vec::new();
    let mut iterations = 0;
    loop {
        let (p, _) = sys.integrate(&z, 1, opts.rtol, None)?;
        let r = p - z;
        let res = scaled_norm(&r, &scales);
        history.push(res);
        let m = monodromy(sys, &z, &p, opts)?;
        if res <= opts.tol {
            let mut orbit = Vec::with_capacity(opts.samples);
            let (_, stats) = sys.integrate(&z, 1, opts.rtol, Some((opts.samples, &mut orbit)))?;
            let mut floquet: Vec<Complex<f64>> = m.complex_eigenvalues().iter().copied().collect();
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
                method: "shooting",
                iterations,
                residual: res,
            });
        }
        let jac = m - SMatrix::<f64, NZ, NZ>::identity();
        let dz = jac
            .lu()
            .solve(&(-r))
            .ok_or(PeriodicError::Singular { method: "shooting" })?;
        z += dz;
        iterations += 1;
    }
}
