//! Periodic solutions with the elastic drive-flank contact (`tooth_contact = elastic`,
//! `model.md` §3.5, issue 27 item 6).
//!
//! Without the rigid constraint the transmission-error coordinate xi and omega2 are free
//! states: the mesh spring is a degree of freedom of its own (the mesh mode, natural
//! frequency (3.19)). The periodic state is therefore the 14 components
//! `z = (u1x u1y u1z u2x u2y u2z xi, u1x' .. u2z', xi')`, i.e. `y[Q..Q+7]`, `y[V..V+6]` and
//! the rate of the transmission error `xi' = r_b2 omega2 - r_b1 omega1` in place of omega2
//! (the same at every drive speed for the same vibration, so that an orbit continues to a
//! neighbouring speed; omega2 itself is the rigid rotation's plus that). Left out, as in the rigid version: phi1 (the phase of the period), the drive
//! filter (at rest at the constant speed), the energy accumulators and the last slot of y,
//! which holds the work stored in the mesh spring (a quadrature that grows by the work of
//! the stiffness variation, not periodic).
//!
//! The start of shooting is the elastic start of §3.5: the centres at the frictionless static
//! equilibrium, the flanks at the static approach of the nominal load, `delta' = 0`.

// `!(a > b)` on purpose: it also counts NaN as outside, which `a <= b` would let pass.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::shooting::{monodromy_of, newton, PeriodMap, ShootingOptions, ShootingResult};
use super::{OrbitPoint, PeriodicError, PeriodicSystem};
use crate::radau5::Statistics;
use crate::rotor::{idx, InitialConditions, NY};
use nalgebra::{Complex, SMatrix, SVector};
use std::f64::consts::PI;

/// Number of periodic state components in elastic mode: seven positions (the centres and
/// xi) and seven velocities (the centres and xi').
pub const NZE: usize = 14;

/// Periodic state at the start of a mesh period in elastic mode.
pub type ElasticReduced = SVector<f64, NZE>;

/// A 14 x 14 matrix (monodromy in elastic mode).
pub type ElasticMatrix = SMatrix<f64, NZE, NZE>;

/// Index of y for component `i` of the elastic periodic state (omega2 for xi').
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
        Ok(self.reduce_elastic(&y))
    }

    /// The full state at t = 0, phi1 = 0 from the elastic periodic state: the centres, xi,
    /// their velocities and xi' as given (omega2 = (xi' + r_b1 omega1) / r_b2), the drive filter at rest at omega1, the energy
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
    pub fn reduce_elastic(&self, y: &SVector<f64, NY>) -> ElasticReduced {
        let g = self.model().geometry();
        let mut z = ElasticReduced::from_fn(|i, _| y[y_index(i)]);
        z[13] = g.rb2 * y[idx::V + 6] - g.rb1 * y[idx::OMEGA1];
        z
    }

    /// Scales of the elastic periodic state: the centres as [`PeriodicSystem::scales`], xi by
    /// the static mesh deflection `lambda_nom / (c_gamma b cos(beta_b))` (at least 1 nm), the
    /// velocities by those times the mesh frequency.
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
        z[13] = xi * w;
        z
    }

    /// Forward-difference steps as [`PeriodicSystem::fd_steps`] for the elastic state (the
    /// noise floor from [`PeriodicSystem::integration_scales`]).
    pub fn fd_steps_elastic(&self, rel: f64, rtol: f64) -> ElasticReduced {
        let s = self.scales_elastic();
        let scale = self.integration_scales();
        let g = self.model().geometry();
        ElasticReduced::from_fn(|i, _| {
            // xi' = r_b2 omega2 - r_b1 omega1: omega2's error allowance times r_b2.
            let unit = if i == 13 { g.rb2 } else { 1.0 };
            (rel * s[i]).max(super::FD_NOISE_FACTOR * unit * scale[y_index(i)] * rtol)
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
        Ok((self.reduce_elastic(&y), stats))
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
                    .ok_or(PeriodicError::Singular {
                        method: "mesh mode",
                    })
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
    let g = model.geometry();
    y[idx::V + 6] = (z[13] + g.rb1 * y[idx::OMEGA1]) / g.rb2;
    // The spring work slot starts as the springs' energy (drive and coast flanks).
    y[idx::LAMBDA] = model.elastic_contact_at(t, &y).map_or(0.0, |c| c.energy)
        + model.coast_contact_at(t, &y).map_or(0.0, |c| c.energy);
    Ok(y)
}

/// The converged periodic orbit in elastic mode (the state is [`ElasticReduced`], the
/// orbit's lambda is Fn).
pub type ElasticShootingResult = ShootingResult<NZE>;

impl ShootingResult<NZE> {
    /// Largest and smallest normal force over the sampled orbit, N.
    pub fn fn_range(&self) -> (f64, f64) {
        self.orbit
            .iter()
            .fold((f64::NEG_INFINITY, f64::INFINITY), |(hi, lo), p| {
                (hi.max(p.lambda), lo.min(p.lambda))
            })
    }
}

/// The elastic contact's period map on [`ElasticReduced`].
struct Elastic<'a>(&'a mut PeriodicSystem);

impl PeriodMap<NZE> for Elastic<'_> {
    fn integrate(
        &mut self,
        z: &ElasticReduced,
        periods: usize,
        rtol: f64,
        samples: Option<(usize, &mut Vec<OrbitPoint>)>,
    ) -> Result<(ElasticReduced, Statistics), PeriodicError> {
        self.0.integrate_elastic(z, periods, rtol, samples)
    }
    fn scales(&self) -> ElasticReduced {
        self.0.scales_elastic()
    }
    fn fd_steps(&self, rel: f64, rtol: f64) -> ElasticReduced {
        self.0.fd_steps_elastic(rel, rtol)
    }
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
    monodromy_of(&mut Elastic(sys), z, p, rel, rtol)
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
    newton(&mut Elastic(sys), start, opts, "shooting (elastic)")
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
            zeta: if s.norm() > 0.0 {
                -s.re / s.norm()
            } else {
                0.0
            },
            mesh_share: share,
        });
    }
    Ok(best)
}

/// Settings of [`continuation`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinuationOptions {
    /// Shooting at each point; `transient_periods` are integrated at the new speed from the
    /// neighbour's orbit before Newton (the slow sweep of an experiment: the state stays in
    /// the basin of the attractor it was on).
    pub shooting: ShootingOptions,
    /// Where shooting fails or finds an unstable orbit (contact loss makes the period map
    /// non-smooth; near a jump the orbit may be unstable or not of period one): mesh periods
    /// integrated further from the end of the transient ...
    pub fallback_periods: usize,
    /// ... and then sampled (`shooting.samples` per period) for the force range.
    pub sample_periods: usize,
}

impl Default for ContinuationOptions {
    fn default() -> Self {
        ContinuationOptions {
            // Newton to 1e-6 of the scales (the force range to ~1e-6 of the static force;
            // where the flanks separate, the step-size control crossing the kinks makes the
            // period map rougher than 1e-8), 8 iterations at most.
            shooting: ShootingOptions {
                transient_periods: 60,
                tol: 1e-6,
                max_newton: 8,
                ..default_options()
            },
            fallback_periods: 300,
            sample_periods: 20,
        }
    }
}

/// One point of a [`continuation`] in the drive speed.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuationPoint {
    /// Drive speed, rad/s.
    pub omega1: f64,
    /// Whether shooting found a stable periodic orbit (else the force range is that of the
    /// fallback simulation's last `sample_periods` periods).
    pub periodic: bool,
    /// Scaled shooting residual (NaN for the fallback).
    pub residual: f64,
    /// Largest Floquet multiplier modulus (NaN for the fallback).
    pub floquet_max_abs: f64,
    /// Largest and smallest normal force Fn over the sampled period(s), N.
    pub fn_max: f64,
    /// See `fn_max`.
    pub fn_min: f64,
    /// The static normal force of the load, `GearedRotor::nominal_lambda`, N.
    pub fn_static: f64,
    /// Share of the samples in free flight (Fn = 0): contact loss.
    pub free_flight: f64,
    /// Mesh periods integrated at this point (a failed Newton's not counted).
    pub periods: usize,
    /// The state at the start of a period the next point starts from.
    pub z: ElasticReduced,
    /// Why shooting was not used (empty when it was).
    pub note: String,
}

impl ContinuationPoint {
    /// The dynamic factor `max Fn / F_static`.
    pub fn dynamic_factor(&self) -> f64 {
        self.fn_max / self.fn_static
    }
}

/// Sweeps the drive speed through `speeds` (rad/s, in the order given: ascending for a
/// sweep up, descending for one down) at the load torque `t_load`, each point started from
/// its neighbour's orbit (the first from the elastic start): the slow sweep of an experiment,
/// which shows the jump of a softening resonance (contact loss near the mesh resonance) as
/// a hysteresis between the two directions. `on_point` sees each point when it is done.
///
/// # Errors
/// Rigid teeth, invalid parameters or speeds, solver failures of the fallback simulation.
pub fn continuation(
    params: crate::rotor::Params,
    t_load: f64,
    speeds: &[f64],
    opts: &ContinuationOptions,
    mut on_point: impl FnMut(&ContinuationPoint),
) -> Result<Vec<ContinuationPoint>, PeriodicError> {
    let mut out: Vec<ContinuationPoint> = Vec::with_capacity(speeds.len());
    for &omega1 in speeds {
        let mut sys = PeriodicSystem::new(params, omega1, t_load)?;
        sys.require_elastic()?;
        let start = match out.last() {
            Some(p) => p.z,
            None => sys.elastic_start()?,
        };
        let fn_static = sys.model().nominal_lambda(0.0);
        let so = opts.shooting;
        let free = |orbit: &[OrbitPoint]| {
            orbit.iter().filter(|p| !(p.lambda > 0.0)).count() as f64 / orbit.len().max(1) as f64
        };
        let newton_periods = |iterations: usize| (iterations + 1) * (NZE + 1) + 1;
        let point = match shoot_elastic(&mut sys, &start, &so) {
            Ok(sh) if sh.floquet_max_abs() < 1.0 => {
                let (hi, lo) = sh.fn_range();
                ContinuationPoint {
                    omega1,
                    periodic: true,
                    residual: sh.residual,
                    floquet_max_abs: sh.floquet_max_abs(),
                    fn_max: hi,
                    fn_min: lo,
                    fn_static,
                    free_flight: free(&sh.orbit),
                    periods: so.transient_periods + newton_periods(sh.iterations),
                    z: sh.z,
                    note: String::new(),
                }
            }
            other => {
                let note = match other {
                    Ok(sh) => format!(
                        "shooting found an unstable orbit (|mu| = {:.4})",
                        sh.floquet_max_abs()
                    ),
                    // Invalid inputs are the caller's; anything else (no convergence, a
                    // singular matrix, a Newton step into a state the solver or the mesh
                    // cannot evaluate) is the non-smooth period map's, and the simulation
                    // from the neighbour's orbit decides.
                    Err(e @ (PeriodicError::Param(_) | PeriodicError::InvalidSpeed { .. })) => {
                        return Err(e)
                    }
                    Err(e) => e.to_string(),
                };
                let n = opts.fallback_periods + so.transient_periods;
                let (mut z, _) = sys.integrate_elastic(&start, n, so.rtol, None)?;
                let mut samples = Vec::new();
                let mut orbit = Vec::new();
                for _ in 0..opts.sample_periods.max(1) {
                    let (zn, _) =
                        sys.integrate_elastic(&z, 1, so.rtol, Some((so.samples, &mut orbit)))?;
                    samples.extend_from_slice(&orbit);
                    z = zn;
                }
                let (hi, lo) = samples
                    .iter()
                    .fold((f64::NEG_INFINITY, f64::INFINITY), |(h, l), p| {
                        (h.max(p.lambda), l.min(p.lambda))
                    });
                ContinuationPoint {
                    omega1,
                    periodic: false,
                    residual: f64::NAN,
                    floquet_max_abs: f64::NAN,
                    fn_max: hi,
                    fn_min: lo,
                    fn_static,
                    free_flight: free(&samples),
                    periods: n + opts.sample_periods.max(1),
                    z,
                    note,
                }
            }
        };
        on_point(&point);
        out.push(point);
    }
    Ok(out)
}
