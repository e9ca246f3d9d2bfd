//! The initial state of a simulation (FMU parameter `initialization`):
//! - [`Initialization::Rest`]: centres undeflected, rigid rotation at the start inputs
//!   (`GearedRotor::initialize`); the bearings then take the load in a transient that decays
//!   with the slowest Floquet multiplier (-0.89 per mesh period at the defaults, 50-100 ms);
//! - [`Initialization::StaticEquilibrium`]: centres at the deflection of the frictionless
//!   static equilibrium for the start inputs (`GearedRotor::static_equilibrium`), at rest;
//!   with mu = 0 this is an equilibrium of the DAE and every output stays constant;
//! - [`Initialization::Periodic`]: on the periodic orbit at the constant start inputs, entered
//!   at the mesh phase of the start (phi1 = 0), found by shooting on the period map
//!   (`periodic::PeriodicSystem`); with elastic teeth on the 14-component orbit of
//!   `periodic::elastic` ([`periodic_orbit_elastic`]).
//!
//! In all three the references of the transmission error and the gap (g0, phi1(0)) are those
//! of the undeflected state, so TE and the centre positions of a `periodic` start are the
//! values a long run from rest settles to.
//!
//! Shooting here is the chord variant of the Newton iteration of `periodic::shooting`: the
//! monodromy matrix is computed once, by forward differences around the static equilibrium
//! (the warm start), and reused. The period map is close to linear in the nanometre
//! vibration about the static deflection, so the chord iteration contracts fast, and each
//! further iteration costs one period integration instead of thirteen.

// `!(a > b)` on purpose: it also counts NaN as outside, which `a <= b` would let pass.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::periodic::elastic::{self, ElasticMatrix, ElasticReduced, NZE};
use crate::periodic::{PeriodicError, PeriodicSystem, Reduced, NZ};
use crate::rotor::{idx, GearedRotor, InitialConditions, ModelError, NY};
use nalgebra::{Complex, SMatrix, SVector};
use std::fmt;

/// How the initial state is set (FMU Enumeration `initialization`; values as in the model
/// description).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Initialization {
    /// 1: undeflected centres (the transient from rest follows).
    #[default]
    Rest = 1,
    /// 2: frictionless static equilibrium.
    StaticEquilibrium = 2,
    /// 3: on the periodic orbit.
    Periodic = 3,
}

impl Initialization {
    /// From the FMU's Enumeration value (None outside 1..=3).
    pub fn from_code(code: i32) -> Option<Self> {
        match code {
            1 => Some(Initialization::Rest),
            2 => Some(Initialization::StaticEquilibrium),
            3 => Some(Initialization::Periodic),
            _ => None,
        }
    }

    /// The Enumeration value.
    pub fn code(self) -> i32 {
        self as i32
    }

    /// The item name of the model description.
    pub fn name(self) -> &'static str {
        match self {
            Initialization::Rest => "rest",
            Initialization::StaticEquilibrium => "static_equilibrium",
            Initialization::Periodic => "periodic",
        }
    }
}

/// Why the requested initial state could not be set.
#[derive(Debug, Clone, PartialEq)]
pub enum InitError {
    /// The model cannot evaluate the start state (static equilibrium, lift).
    Model(ModelError),
    /// The periodic orbit could not be computed (no constant positive speed, solver failure,
    /// singular Newton matrix, no convergence).
    Periodic(PeriodicError),
    /// The periodic orbit could not be computed for a pair whose contact lines can stick at
    /// the pitch line (spur pair, friction law 1 or 3): likely the cause.
    PeriodicStick(PeriodicError),
    /// The orbit exists but is not asymptotically stable: a Floquet multiplier on or outside
    /// the unit circle; a run started on it would not stay there.
    Unstable {
        /// Largest modulus of the Floquet multipliers.
        multiplier: f64,
    },
}

impl fmt::Display for InitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InitError::Model(e) => write!(f, "{e}"),
            InitError::Periodic(e) => write!(
                f,
                "no periodic orbit: {e}; use initialization = rest or static_equilibrium"
            ),
            InitError::PeriodicStick(e) => write!(
                f,
                "no periodic orbit: {e}. On this spur pair (friction law 1 or 3) a contact line \
                 can stick at the pitch line, and the periodic start does not resolve stick \
                 phases; use initialization = rest or static_equilibrium (the simulation \
                 locates stick and slip) and let the transient decay"
            ),
            InitError::Unstable { multiplier } => write!(
                f,
                "the periodic orbit is unstable (largest Floquet multiplier |mu| = {multiplier:.4} >= 1): \
                 a run started on it would leave it; use initialization = rest or static_equilibrium"
            ),
        }
    }
}

impl From<ModelError> for InitError {
    fn from(e: ModelError) -> Self {
        InitError::Model(e)
    }
}

impl From<PeriodicError> for InitError {
    fn from(e: PeriodicError) -> Self {
        InitError::Periodic(e)
    }
}

/// What the periodic initialisation did (for the log and the benchmarks).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct InitReport {
    /// Chord iterations after the monodromy (0 for rest and static equilibrium).
    pub iterations: usize,
    /// Scaled max-norm of `P(z) - z` at the start state.
    pub residual: f64,
    /// Largest modulus of the Floquet multipliers (monodromy at the warm start).
    pub floquet_max_abs: f64,
    /// Mesh periods integrated (each is one RADAU5 run over T_m).
    pub periods_integrated: usize,
    /// RADAU5 steps over all of them.
    pub steps: u64,
    /// RADAU5 relative tolerance of the period integrations.
    pub rtol: f64,
}

/// Chord iterations at most with one monodromy and one period tolerance (a stage).
const MAX_CHORD: usize = 12;

/// Times the period integrations' tolerance is tightened (10x each) when the chord
/// iteration stalls.
const MAX_TIGHTEN: usize = 2;

/// Stop when the scaled residual `max_i |P(z) - z|_i / scale_i` is at most this (scales:
/// the static deflection, 1.35e-5 m at the defaults, and that times the mesh frequency,
/// `PeriodicSystem::scales`). The period map is only as smooth as RADAU5's step-size
/// sequence, so the residual stalls at a floor set by the tolerance (measured on the
/// default pair: ~2e-8 at rtol 1e-9, ~5e-11 at 1e-13); the iteration also stops when it no
/// longer halves the residual, and accepts the best state if that is below
/// [`RESIDUAL_ACCEPT`].
const RESIDUAL_TOL: f64 = 1e-11;

/// A stalled iteration is accepted when its residual is at the level of the error of a
/// period integration: `max_i |P(z) - z|_i / (rtol (scale_i + |z_i|))` (the units of
/// RADAU5's local error test; one period takes ~100-200 steps) at most this, or the scaled
/// residual at most [`RESIDUAL_ACCEPT`]. Measured stalls: 0.3 on the default pair at rtol
/// 1e-13, 350 on a 23/61 pair at 20 N m and d_phi = 0.05 at rtol 1e-9.
const NOISE_ACCEPT: f64 = 1e3;

/// Largest scaled residual accepted when the iteration stalls above [`NOISE_ACCEPT`].
const RESIDUAL_ACCEPT: f64 = 1e-6;

/// Forward-difference step of the monodromy, relative to the scales: 1e-4 of the static
/// deflection is ~3 % of the orbit's peak to peak at the defaults, well inside the range
/// where the period map is linear; never below the noise floor of
/// `PeriodicSystem::fd_steps` (small loads).
const FD_STEP: f64 = 1e-4;

/// RADAU5 tolerance of the monodromy integrations: the chord iteration only needs the
/// matrix to a few digits (it converges with the rate ||(I - M)^-1 dM||), but the Floquet
/// check needs its eigenvalues. Measured: 1e-6 is cheaper on the default pair (653 instead
/// of 901 steps) but called the orbit of a lightly loaded 23/61 pair (20 N m, d_phi 0.05)
/// unstable (|mu| = 1.09 from forward differences of a noisy map); 1e-8 gives 0.897 for
/// the default pair (shooting program at 1e-13: 0.891).
const MONODROMY_RTOL: f64 = 1e-8;

/// Tolerance of the second monodromy when the chord iteration stalls with the first or
/// the first calls the orbit unstable (forward differences of a noisy period map).
const MONODROMY_RTOL_RETRY: f64 = 1e-10;

/// RADAU5 tolerance of the period integrations of the chord iteration, relative to the
/// simulation's rtol, and its bounds: the orbit comes out ~1e3 times more accurate than
/// what the FMU then integrates with (a start state more accurate than that would be lost
/// in the first steps), 1e-13 at most (RADAU5's floor), 1e-8 at least.
const SHOOTING_RTOL_FACTOR: f64 = 1e-3;
/// See [`SHOOTING_RTOL_FACTOR`].
const SHOOTING_RTOL_RANGE: (f64, f64) = (1e-13, 1e-8);

/// The consistent state at `t` for centre displacements `u` and velocities `u_dot`, phi1
/// = 0 (`GearedRotor::consistent_state`; xi relative to the gap offset of the undeflected
/// state after `GearedRotor::initialize`).
///
/// # Errors
/// Mesh, contact or lambda errors.
pub fn lift(
    model: &GearedRotor,
    t: f64,
    u: &[f64; 6],
    u_dot: &[f64; 6],
) -> Result<SVector<f64, NY>, ModelError> {
    model.consistent_state(
        t,
        &InitialConditions {
            u: *u,
            u_dot: *u_dot,
            phi1: 0.0,
        },
    )
}

/// The initial state of `init` for a model set up by `GearedRotor::initialize(t)` (inputs
/// and references set), with `rtol` the simulation's relative tolerance.
///
/// # Errors
/// See [`InitError`].
pub fn initial_state(
    model: &GearedRotor,
    t: f64,
    init: Initialization,
    rtol: f64,
) -> Result<(SVector<f64, NY>, InitReport), InitError> {
    match init {
        Initialization::Rest => {
            let y = lift(model, t, &[0.0; 6], &[0.0; 6])?;
            Ok((y, InitReport::default()))
        }
        Initialization::StaticEquilibrium => {
            let (ic, _) = model.static_equilibrium(t, 0.0)?;
            let y = lift(model, t, &ic.u, &ic.u_dot)?;
            Ok((y, InitReport::default()))
        }
        Initialization::Periodic => {
            let inputs = model.inputs();
            let mut sys =
                PeriodicSystem::new(*model.params(), inputs.omega1_at(t), inputs.t_load_at(t))?;
            let rtol =
                (rtol * SHOOTING_RTOL_FACTOR).clamp(SHOOTING_RTOL_RANGE.0, SHOOTING_RTOL_RANGE.1);
            if sys.is_elastic() {
                let (z, report) = periodic_orbit_elastic(&mut sys, rtol)?;
                let y = elastic::lift_elastic_with(model, t, &z)?;
                return Ok((y, report));
            }
            let (z, report) = periodic_orbit(&mut sys, rtol).map_err(|e| match e {
                InitError::Periodic(p) if model.stick_possible() => InitError::PeriodicStick(p),
                e => e,
            })?;
            let ic = InitialConditions {
                u: std::array::from_fn(|i| z[i]),
                u_dot: std::array::from_fn(|i| z[6 + i]),
                phi1: 0.0,
            };
            let y = lift(model, t, &ic.u, &ic.u_dot)?;
            Ok((y, report))
        }
    }
}

/// The residual in units of RADAU5's error test at `rtol` (see [`NOISE_ACCEPT`]), with the
/// state scales of the model (`GearedRotor::scales`).
fn noise_norm(r: &Reduced, z: &Reduced, rtol: f64, scales: &[f64; NY]) -> f64 {
    (0..NZ).fold(0.0f64, |m, i| {
        let s = if i < 6 {
            scales[idx::Q + i]
        } else {
            scales[idx::V + i - 6]
        };
        m.max(r[i].abs() / (rtol * (s + z[i].abs())))
    })
}

fn scaled_norm(r: &Reduced, s: &Reduced) -> f64 {
    r.iter()
        .zip(s.iter())
        .fold(0.0f64, |m, (a, b)| m.max((a / b).abs()))
}

/// Start of the periodic orbit (reduced state at phi1 = 0) by chord shooting from the
/// static equilibrium (see the module docs), the period maps at `rtol`, the monodromy at
/// `MONODROMY_RTOL` (1e-8, or `rtol` if larger; once more at `MONODROMY_RTOL_RETRY` when
/// the chord iteration stalls or the first calls the orbit unstable); checks the stability
/// of the orbit with the eigenvalues of the monodromy.
///
/// # Errors
/// Solver or model errors, singular Newton matrix, unstable orbit, no convergence.
pub fn periodic_orbit(
    sys: &mut PeriodicSystem,
    rtol: f64,
) -> Result<(Reduced, InitReport), InitError> {
    let scales = sys.scales();
    let (mut z, _) = sys.static_equilibrium()?;
    let mut report = InitReport {
        rtol,
        ..InitReport::default()
    };
    // The cheap monodromy first. When the chord iteration stalls (or uses up MAX_CHORD
    // iterations) above the accepted residual: once more with the monodromy at the tighter
    // tolerance around the best state so far; then, as the residual's floor is the
    // roughness of the period map, set by the period integrations' tolerance, on from the
    // best state with that tolerance 10 times tighter (MAX_TIGHTEN times at most, not below
    // RADAU5's floor). The acceptance is judged at `rtol` all the same. Measured: 3500 rpm,
    // mu 0.03, 20 N m stalled at a scaled residual of 1.6e-6 (20 times the error allowance
    // of the FMU's steps) and converges to 1.2e-9 after one tightening.
    let tols = [MONODROMY_RTOL.max(rtol), MONODROMY_RTOL_RETRY.max(rtol)];
    let mut retried = false;
    let mut tightened = 0;
    let mut rtol_p = rtol;
    let (mut lu, mut p) = match chord_matrix(sys, &z, tols[0], rtol, &mut report) {
        Err(InitError::Unstable { .. }) if tols[1] < tols[0] => {
            retried = true;
            chord_matrix(sys, &z, tols[1], rtol, &mut report)?
        }
        r => r?,
    };
    let mut best = (f64::INFINITY, z, f64::INFINITY);
    let mut stage_iterations = 0;
    loop {
        let r = p - z;
        let res = scaled_norm(&r, &scales);
        let stalled = res > 0.5 * best.0;
        if res < best.0 {
            best = (res, z, noise_norm(&r, &z, rtol, sys.model().scales()));
        }
        let acceptable = best.0 <= RESIDUAL_ACCEPT || best.2 <= NOISE_ACCEPT;
        if best.0 <= RESIDUAL_TOL || (stalled && acceptable) {
            report.residual = best.0;
            return Ok((best.1, report));
        }
        if stalled || stage_iterations >= MAX_CHORD {
            if !retried && tols[1] < tols[0] {
                retried = true;
                z = best.1;
                (lu, p) = chord_matrix(sys, &z, tols[1], rtol_p, &mut report)?;
            } else if tightened < MAX_TIGHTEN && rtol_p > SHOOTING_RTOL_RANGE.0 {
                tightened += 1;
                rtol_p = (rtol_p * 0.1).max(SHOOTING_RTOL_RANGE.0);
                z = best.1;
                p = integrate(sys, &z, rtol_p, &mut report)?;
            } else {
                return Err(PeriodicError::NoConvergence {
                    method: "shooting (chord)",
                    iterations: report.iterations,
                    residual: best.0,
                }
                .into());
            }
            best.0 = f64::INFINITY;
            stage_iterations = 0;
            continue;
        }
        let dz = lu.solve(&(-r)).ok_or(PeriodicError::Singular {
            method: "shooting (chord)",
        })?;
        z += dz;
        report.iterations += 1;
        stage_iterations += 1;
        p = integrate(sys, &z, rtol_p, &mut report)?;
    }
}

/// One period integration from z at `tol`, counted in the report.
fn integrate(
    sys: &mut PeriodicSystem,
    z: &Reduced,
    tol: f64,
    report: &mut InitReport,
) -> Result<Reduced, PeriodicError> {
    let (p, stats) = sys.integrate(z, 1, tol, None)?;
    report.periods_integrated += 1;
    report.steps += stats.naccpt;
    Ok(p)
}

/// The LU of `M - I` (M the forward-difference monodromy around z at `tol_m`) after the
/// stability check of its eigenvalues, and `P(z)` at `rtol`.
fn chord_matrix(
    sys: &mut PeriodicSystem,
    z: &Reduced,
    tol_m: f64,
    rtol: f64,
    report: &mut InitReport,
) -> Result<
    (
        nalgebra::LU<f64, nalgebra::Const<NZ>, nalgebra::Const<NZ>>,
        Reduced,
    ),
    InitError,
> {
    let p0 = integrate(sys, z, tol_m, report)?;
    let steps = sys.fd_steps(FD_STEP, tol_m);
    let mut m = SMatrix::<f64, NZ, NZ>::zeros();
    for i in 0..NZ {
        let d = steps[i];
        let mut zi = *z;
        zi[i] += d;
        let pi = integrate(sys, &zi, tol_m, report)?;
        m.set_column(i, &((pi - p0) / d));
    }
    let floquet: Vec<Complex<f64>> = m.complex_eigenvalues().iter().copied().collect();
    report.floquet_max_abs = floquet.iter().map(|c| c.norm()).fold(0.0, f64::max);
    if !(report.floquet_max_abs < 1.0) {
        return Err(InitError::Unstable {
            multiplier: report.floquet_max_abs,
        });
    }
    let p = if tol_m == rtol {
        p0
    } else {
        integrate(sys, z, rtol, report)?
    };
    Ok(((m - SMatrix::<f64, NZ, NZ>::identity()).lu(), p))
}

/// [`periodic_orbit`] with the elastic contact (`model.md` §3.5): the 14-component periodic
/// state of `periodic::elastic`, chord shooting from the elastic start (static equilibrium,
/// flanks at the static approach) with one forward-difference monodromy at
/// `MONODROMY_RTOL` (its eigenvalues checked for stability), the period maps at `rtol`.
/// Stops at `RESIDUAL_TOL`, or when the iteration stalls with the best residual at most
/// `RESIDUAL_ACCEPT`.
///
/// # Errors
/// Solver or model errors, singular Newton matrix, unstable orbit, no convergence.
pub fn periodic_orbit_elastic(
    sys: &mut PeriodicSystem,
    rtol: f64,
) -> Result<(ElasticReduced, InitReport), InitError> {
    let scales = sys.scales_elastic();
    let mut z = sys.elastic_start()?;
    let mut report = InitReport {
        rtol,
        ..InitReport::default()
    };
    let tol_m = MONODROMY_RTOL.max(rtol);
    let period = |sys: &mut PeriodicSystem,
                  z: &ElasticReduced,
                  tol: f64,
                  report: &mut InitReport|
     -> Result<ElasticReduced, PeriodicError> {
        let (p, stats) = sys.integrate_elastic(z, 1, tol, None)?;
        report.periods_integrated += 1;
        report.steps += stats.naccpt;
        Ok(p)
    };
    let p0 = period(sys, &z, tol_m, &mut report)?;
    let steps = sys.fd_steps_elastic(FD_STEP, tol_m);
    let mut m = ElasticMatrix::zeros();
    for i in 0..NZE {
        let mut zi = z;
        zi[i] += steps[i];
        let pi = period(sys, &zi, tol_m, &mut report)?;
        m.set_column(i, &((pi - p0) / steps[i]));
    }
    report.floquet_max_abs = m
        .complex_eigenvalues()
        .iter()
        .map(|c| c.norm())
        .fold(0.0, f64::max);
    if !(report.floquet_max_abs < 1.0) {
        return Err(InitError::Unstable {
            multiplier: report.floquet_max_abs,
        });
    }
    let lu = (m - ElasticMatrix::identity()).lu();
    let mut p = if tol_m == rtol {
        p0
    } else {
        period(sys, &z, rtol, &mut report)?
    };
    let mut best = (f64::INFINITY, z);
    for _ in 0..2 * MAX_CHORD {
        let r = p - z;
        let res = r
            .iter()
            .zip(scales.iter())
            .fold(0.0f64, |a, (x, s)| a.max((x / s).abs()));
        let stalled = res > 0.5 * best.0;
        if res < best.0 {
            best = (res, z);
        }
        if best.0 <= RESIDUAL_TOL || (stalled && best.0 <= RESIDUAL_ACCEPT) {
            report.residual = best.0;
            return Ok((best.1, report));
        }
        if stalled {
            break;
        }
        let dz = lu.solve(&(-r)).ok_or(PeriodicError::Singular {
            method: "shooting (chord, elastic)",
        })?;
        z += dz;
        report.iterations += 1;
        p = period(sys, &z, rtol, &mut report)?;
    }
    Err(PeriodicError::NoConvergence {
        method: "shooting (chord, elastic)",
        iterations: report.iterations,
        residual: best.0,
    }
    .into())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::periodic::shooting::{shoot, ShootingOptions};
    use crate::rotor::Params;

    #[test]
    fn chord_shooting_finds_the_orbit_of_full_newton_shooting() {
        // reference: src/periodic's Newton with a fresh monodromy per iteration, started
        // after a 20-period transient; here: chord from the static equilibrium
        let mut sys = PeriodicSystem::new(Params::default(), 314.159, 0.0).unwrap();
        let (z0, _) = sys.static_equilibrium().unwrap();
        let reference = shoot(&mut sys, &z0, &ShootingOptions::default()).unwrap();
        let (z, report) = periodic_orbit(&mut sys, 1e-13).unwrap();
        let pp = reference
            .orbit
            .iter()
            .map(|p| p.u[0])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            });
        let pp = pp.1 - pp.0;
        for i in 0..6 {
            assert!((z[i] - reference.z[i]).abs() <= 1e-6 * pp, "u[{i}]");
        }
        assert!((report.floquet_max_abs - reference.floquet_max_abs()).abs() < 0.02);
        assert!(report.periods_integrated <= 20, "{report:?}");
    }

    #[test]
    fn no_orbit_without_a_positive_speed_says_why() {
        let mut model = GearedRotor::new(crate::rotor::Params::default()).unwrap();
        model.set_inputs(crate::rotor::Inputs::default());
        model.initialize(0.0).unwrap();
        let e = initial_state(&model, 0.0, Initialization::Periodic, 1e-6).unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("0 < omega1") && msg.contains("initialization = rest"),
            "{msg}"
        );
    }
}
