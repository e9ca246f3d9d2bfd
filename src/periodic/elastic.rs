//! Periodic solutions with the elastic drive-flank contact (`tooth_contact = elastic`,
//! `model.md` §3.5, issue 27 item 6).
//!
//! Without the rigid constraint the transmission-error coordinate xi and omega2 are free
//! states: the mesh spring is a degree of freedom of its own (the mesh mode, natural
//! frequency (3.19)). The periodic state is therefore the 14 components
//! `z = (u1x u1y u1z u2x u2y u2z xi, their velocities with omega2)`, i.e. `y[Q..Q+7]` and
//! `y[V..V+7]`. Left out, as in the rigid version: phi1 (the phase of the period), the drive
//! filter (at rest at the constant speed), the energy accumulators and the last slot of y,
//! which holds the work stored in the mesh spring (a quadrature that grows by the work of
//! the stiffness variation, not periodic).
//!
//! The start of shooting is the elastic start of §3.5: the centres at the frictionless static
//! equilibrium, the flanks at the static approach of the nominal load, `delta' = 0`.

use super::shooting::ShootingOptions;
use super::{OrbitPoint, PeriodicError, PeriodicSystem};
use crate::radau5::Statistics;
use crate::rotor::{idx, InitialConditions, NY};
use nalgebra::{Complex, SMatrix, SVector};
use std::f64::consts::PI;

/// Number of periodic state components in elastic mode: seven positions (the centres and
/// xi) and seven velocities (the centres and omega2).
pub const NZE: usize = 14;

/// Periodic state at the start of a mesh period in elastic mode.
pub type ElasticReduced = SVector<f64, NZE>;

/// A 14 x 14 matrix (monodromy in elastic mode).
pub type ElasticMatrix = SMatrix<f64, NZE, NZE>;

/// Index of y for component `i` of the elastic periodic state.
fn y_index(i: usize) -> usize {
    if i < 7 {
        idx::Q + i
    } else {
        idx::V + i - 7
    }
}

impl PeriodicSystem {
    fn require_elastic(&self) -> Result<(), PeriodicError> {
        if self.is_elastic() {
            return Ok(());
        }
        Err(PeriodicError::Param(crate::parameter::ParamError {
            name: "tooth_contact",
            value: f64::from(self.model().params().tooth_contact.code()),
            requirement: "tooth_contact = elastic for periodic::elastic; with rigid teeth use \
                          the 12 reduced coordinates (PeriodicSystem::lift, shooting::shoot)"
                .into(),
        }))
    }

    /// The elastic start (`model.md` §3.5 "Start"): centres at the frictionless static
    /// equilibrium, at rest, the flanks at the static approach of the nominal load
    /// (`delta = lambda_nom / (c_l l(0))`), `delta' = 0`.
    ///
    /// # Errors
    /// Rigid teeth; static equilibrium or mesh errors.
    pub fn elastic_start(&self) -> Result<ElasticReduced, PeriodicError> {
        self.require_elastic()?;
        let (ic, _) = self.model().static_equilibrium(0.0, 0.0)?;
        let y = self.model().consistent_state(0.0, &ic)?;
        Ok(Self::reduce_elastic(&y))
    }

    /// The full state at t = 0, phi1 = 0 from the elastic periodic state: the centres, xi,
    /// their velocities and omega2 as given, the drive filter at rest at omega1, the energy
    /// accumulators zero and the last slot the spring energy `k delta^2 / 2` (as the
    /// elastic start of §3.5).
    ///
    /// # Errors
    /// Rigid teeth; mesh errors.
    pub fn lift_elastic(&self, z: &ElasticReduced) -> Result<SVector<f64, NY>, PeriodicError> {
        self.require_elastic()?;
        lift_elastic_with(self.model(), 0.0, z)
    }

    /// The elastic periodic state of a full state.
    pub fn reduce_elastic(y: &SVector<f64, NY>) -> ElasticReduced {
        ElasticReduced::from_fn(|i, _| y[y_index(i)])
    }

    /// Scales of the elastic periodic state: the centres as [`PeriodicSystem::scales`], xi by
    /// the static mesh deflection `lambda_nom / (c_gamma b cos(beta_b))` (at least 1 nm), the
    /// velocities by those times the mesh frequency, omega2 that divided by r_b2.
    pub fn scales_elastic(&self) -> ElasticReduced {
        let s = self.scales();
        let model = self.model();
        let g = model.geometry();
        let w = 2.0 * PI / self.period();
        let k = model.elastic_mesh().map_or(f64::INFINITY, |e| e.k_mean);
        let xi = (model.nominal_lambda(0.0).abs() / (k * g.cos_beta_b)).max(1e-9);
        let mut z = ElasticReduced::zeros();
        for i in 0..6 {
            z[i] = s[i];
            z[7 + i] = s[6 + i];
        }
        z[6] = xi;
        z[13] = xi * w / g.rb2;
        z
    }

    /// Forward-difference steps as [`PeriodicSystem::fd_steps`] for the elastic state.
    pub fn fd_steps_elastic(&self, rel: f64, rtol: f64) -> ElasticReduced {
        let s = self.scales_elastic();
        let scale = self.model().scales();
        ElasticReduced::from_fn(|i, _| {
            (rel * s[i]).max(super::FD_NOISE_FACTOR * scale[y_index(i)] * rtol)
        })
    }

    /// Integrates from the lift of `z` over `periods` mesh periods at `rtol` (see
    /// [`PeriodicSystem::integrate`]); the samples' `lambda` is the normal force Fn.
    ///
    /// # Errors
    /// Lift or solver errors.
    pub fn integrate_elastic(
        &mut self,
        z: &ElasticReduced,
        periods: usize,
        rtol: f64,
        samples: Option<(usize, &mut Vec<OrbitPoint>)>,
    ) -> Result<(ElasticReduced, Statistics), PeriodicError> {
        let y0 = self.lift_elastic(z)?;
        let (y, stats) = self.integrate_state(y0, periods, rtol, samples)?;
        Ok((Self::reduce_elastic(&y), stats))
    }

    /// The linear map from a change of the positions (the first seven components) to the
    /// change of the normal approach delta at `z` (central differences of (3.13)).
    fn delta_row(&self, z: &ElasticReduced) -> Result<[f64; 7], PeriodicError> {
        let s = self.scales_elastic();
        let mut row = [0.0; 7];
        for (i, r) in row.iter_mut().enumerate() {
            let h = 1e-4 * s[i];
            let (mut zp, mut zm) = (*z, *z);
            zp[i] += h;
            zm[i] -= h;
            let d = |z: &ElasticReduced| -> Result<f64, PeriodicError> {
                let y = self.lift_elastic(z)?;
                self.model()
                    .elastic_contact_at(0.0, &y)
                    .map(|c| c.delta)
                    .ok_or(PeriodicError::Singular { method: "mesh mode" })
            };
            *r = (d(&zp)? - d(&zm)?) / (2.0 * h);
        }
        Ok(row)
    }
}

/// [`PeriodicSystem::lift_elastic`] for any elastic model at time `t` (phi1 = 0): the FMU's
/// `initialization = periodic` lifts the orbit with its own model.
///
/// # Errors
/// Mesh errors.
pub fn lift_elastic_with(
    model: &crate::rotor::GearedRotor,
    t: f64,
    z: &ElasticReduced,
) -> Result<SVector<f64, NY>, PeriodicError> {
    let ic = InitialConditions {
        u: std::array::from_fn(|i| z[i]),
        u_dot: std::array::from_fn(|i| z[7 + i]),
        phi1: 0.0,
    };
    let mut y = model.consistent_state(t, &ic)?;
    y[idx::Q + 6] = z[6];
    y[idx::V + 6] = z[13];
    y[idx::LAMBDA] = model
        .elastic_contact_at(t, &y)
        .map_or(0.0, |c| c.energy);
    Ok(y)
}

/// The converged periodic orbit in elastic mode.
#[derive(Debug, Clone)]
pub struct ElasticShootingResult {
    /// Periodic state at the start of the period.
    pub z: ElasticReduced,
    /// Scaled max-norm of `P(z) - z` at the solution ([`PeriodicSystem::scales_elastic`]).
    pub residual: f64,
    /// Scaled residual before each Newton update.
    pub residual_history: Vec<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Forward-difference monodromy matrix dP/dz at the solution.
    pub monodromy: ElasticMatrix,
    /// Its eigenvalues, the Floquet multipliers, by decreasing modulus.
    pub floquet: Vec<Complex<f64>>,
    /// The orbit sampled at `ShootingOptions::samples` equidistant times (lambda = Fn).
    pub orbit: Vec<OrbitPoint>,
    /// RADAU5 steps of one period integration at the solution.
    pub steps_per_period: u64,
}

impl ElasticShootingResult {
    /// Largest modulus of the Floquet multipliers.
    pub fn floquet_max_abs(&self) -> f64 {
        self.floquet.first().map_or(0.0, |c| c.norm())
    }

    /// Largest and smallest normal force over the sampled orbit, N.
    pub fn fn_range(&self) -> (f64, f64) {
        self.orbit
            .iter()
            .fold((f64::NEG_INFINITY, f64::INFINITY), |(hi, lo), p| {
                (hi.max(p.lambda), lo.min(p.lambda))
            })
    }
}

fn scaled_norm(r: &ElasticReduced, s: &ElasticReduced) -> f64 {
    r.iter()
        .zip(s.iter())
        .fold(0.0f64, |m, (a, b)| m.max((a / b).abs()))
}

/// Forward-difference monodromy of the elastic period map around `z`, `p = P(z)` known,
/// steps `rel` times the scales (not below the noise floor at `rtol`).
///
/// # Errors
/// Solver or mesh errors.
pub fn monodromy_elastic(
    sys: &mut PeriodicSystem,
    z: &ElasticReduced,
    p: &ElasticReduced,
    rel: f64,
    rtol: f64,
) -> Result<ElasticMatrix, PeriodicError> {
    let steps = sys.fd_steps_elastic(rel, rtol);
    let mut m = ElasticMatrix::zeros();
    for i in 0..NZE {
        let d = steps[i];
        let mut zi = *z;
        zi[i] += d;
        let (pi, _) = sys.integrate_elastic(&zi, 1, rtol, None)?;
        m.set_column(i, &((pi - p) / d));
    }
    Ok(m)
}

/// Periodic orbit in elastic mode by shooting from `start` (e.g.
/// [`PeriodicSystem::elastic_start`] or a neighbouring speed's orbit): a transient of
/// `opts.transient_periods` periods, then Newton on `P(z) - z` with a forward-difference
/// monodromy (the same method as [`super::shooting::shoot`], on the 14 components).
///
/// # Errors
/// Rigid teeth; solver or model errors, a singular Newton matrix, or no convergence.
pub fn shoot_elastic(
    sys: &mut PeriodicSystem,
    start: &ElasticReduced,
    opts: &ShootingOptions,
) -> Result<ElasticShootingResult, PeriodicError> {
    sys.require_elastic()?;
    let scales = sys.scales_elastic();
    let mut z = *start;
    if opts.transient_periods > 0 {
        z = sys
            .integrate_elastic(&z, opts.transient_periods, opts.rtol, None)?
            .0;
    }
    let mut history = Vec::new();
    let mut iterations = 0;
    loop {
        let (p, _) = sys.integrate_elastic(&z, 1, opts.rtol, None)?;
        let r = p - z;
        let res = scaled_norm(&r, &scales);
        history.push(res);
        let m = monodromy_elastic(sys, &z, &p, opts.fd_step, opts.rtol)?;
        if res <= opts.tol {
            let mut orbit = Vec::with_capacity(opts.samples);
            let (_, stats) =
                sys.integrate_elastic(&z, 1, opts.rtol, Some((opts.samples, &mut orbit)))?;
            let mut floquet: Vec<Complex<f64>> = m.complex_eigenvalues().iter().copied().collect();
            floquet.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
            return Ok(ElasticShootingResult {
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
                method: "shooting (elastic)",
                iterations,
                residual: res,
            });
        }
        let jac = m - ElasticMatrix::identity();
        let dz = jac.lu().solve(&(-r)).ok_or(PeriodicError::Singular {
            method: "shooting (elastic)",
        })?;
        z += dz;
        iterations += 1;
    }
}

/// Shooting settings for the elastic contact: RADAU5 at rtol 1e-10 (the elastic contact's
/// Jacobian is taken by finite differences of f, so a period costs more than in the rigid
/// model), Newton to a scaled residual of 1e-8, 30 transient periods.
pub fn default_options() -> ShootingOptions {
    ShootingOptions {
        rtol: 1e-10,
        transient_periods: 30,
        tol: 1e-8,
        max_newton: 15,
        fd_step: 1e-5,
        samples: 400,
    }
}

/// The closed-form mesh mode of `model.md` (3.18)-(3.19): `(omega_m, zeta_mesh)` with
/// `omega_m = sqrt(c_gamma b / m_eq)` in rad/s (None with rigid teeth).
pub fn closed_form_mesh_mode(sys: &PeriodicSystem) -> Option<(f64, f64)> {
    let e = sys.model().elastic_mesh()?;
    Some(((e.k_mean / e.m_eq).sqrt(), sys.model().params().zeta_mesh))
}

/// The mesh mode of an elastic orbit, from its Floquet multipliers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshMode {
    /// Floquet multiplier `rho = exp(s T_m)`.
    pub multiplier: Complex<f64>,
    /// Characteristic exponent `s = (ln rho + 2 pi i k) / T_m` with the branch k nearest the
    /// closed-form `i omega_m`, 1/s.
    pub s: Complex<f64>,
    /// `Im(s) / 2 pi`, Hz.
    pub freq_hz: f64,
    /// `-Re(s) / |s|`.
    pub zeta: f64,
    /// Share of the mesh spring in the potential energy of the mode shape,
    /// `k |d delta|^2 / (k |d delta|^2 + sum k_i |u_i|^2)`.
    pub mesh_share: f64,
}

/// Eigenvalues of a 14 x 14 matrix and right eigenvectors by inverse iteration (as
/// `modal::eigen`).
fn eigen14(a: &ElasticMatrix) -> Vec<(Complex<f64>, SVector<Complex<f64>, NZE>)> {
    type C = SMatrix<Complex<f64>, NZE, NZE>;
    type V = SVector<Complex<f64>, NZE>;
    let ac: C = a.map(|x| Complex::new(x, 0.0));
    let norm = a.abs().max().max(f64::MIN_POSITIVE);
    a.complex_eigenvalues()
        .iter()
        .map(|&lam| {
            let mu = lam + Complex::new(1e-10 * norm, 1e-10 * norm);
            let lu = (ac - C::identity() * mu).lu();
            let mut x = V::from_fn(|i, _| Complex::new(1.0 + 0.1 * i as f64, 0.3));
            for _ in 0..3 {
                if let Some(y) = lu.solve(&x) {
                    let n = y.norm();
                    if n > 0.0 && n.is_finite() {
                        x = y / Complex::new(n, 0.0);
                    }
                }
            }
            (lam, x)
        })
        .collect()
}

/// The mesh mode of the orbit starting at `z` with monodromy `m`: of the multipliers with
/// positive imaginary part (one per complex pair), the one whose eigenvector puts the largest
/// share of its potential energy into the mesh spring (bearing springs `k_i u_i^2` against the
/// mean mesh spring `c_gamma b delta^2`); its exponent on the branch nearest the closed-form
/// `omega_m`. None with rigid teeth or without a complex pair.
///
/// # Errors
/// Mesh errors.
pub fn mesh_mode(
    sys: &PeriodicSystem,
    z: &ElasticReduced,
    m: &ElasticMatrix,
) -> Result<Option<MeshMode>, PeriodicError> {
    let Some((omega_m, _)) = closed_form_mesh_mode(sys) else {
        return Ok(None);
    };
    let k_mesh = sys.model().elastic_mesh().map_or(0.0, |e| e.k_mean);
    let p = sys.model().params();
    let k_b = [
        p.rotor1.k[0],
        p.rotor1.k[1],
        p.rotor1.k[2],
        p.rotor2.k[0],
        p.rotor2.k[1],
        p.rotor2.k[2],
    ];
    let row = sys.delta_row(z)?;
    let t = sys.period();
    let mut best: Option<MeshMode> = None;
    for (rho, v) in eigen14(m) {
        if !(rho.im > 1e-12 * rho.norm()) {
            continue;
        }
        let dd: Complex<f64> = (0..7).map(|i| v[i] * row[i]).sum();
        let e_mesh = k_mesh * dd.norm_sqr();
        let e_bear: f64 = (0..6).map(|i| k_b[i] * v[i].norm_sqr()).sum();
        let share = if e_mesh + e_bear > 0.0 {
            e_mesh / (e_mesh + e_bear)
        } else {
            0.0
        };
        if best.is_some_and(|b| b.mesh_share >= share) {
            continue;
        }
        let ln = rho.ln();
        let k = ((omega_m * t - ln.im) / (2.0 * PI)).round();
        let s = Complex::new(ln.re / t, (ln.im + 2.0 * PI * k) / t);
        best = Some(MeshMode {
            multiplier: rho,
            s,
            freq_hz: s.im / (2.0 * PI),
            zeta: if s.norm() > 0.0 { -s.re / s.norm() } else { 0.0 },
            mesh_share: share,
        });
    }
    Ok(best)
}
