//! Periodic steady state of the geared rotor at constant drive speed (`model.md` §9.9,
//! §9.10, §11): the paper's second result.
//!
//! With constant omega1 (drive filter at rest) the equations depend on time only through
//! the mesh phase phi1 mod 2 pi / z1, so the steady state is periodic with the mesh
//! period `T_m = 2 pi / (z1 omega1)`. Two independent ways to compute it:
//! - [`shooting`]: Newton on the state at the start of a period, integrated over one period
//!   with RADAU5; the monodromy matrix of the period map gives the Floquet multipliers;
//! - [`harmonic`]: the n-th order harmonic approach, truncated Fourier series for the
//!   displacements, the transmission error and lambda, with residuals evaluated in the time
//!   domain (alternating frequency/time) and Newton on the Fourier coefficients.
//!
//! Both work on the reduced coordinates of [`PeriodicSystem`]: the six centre
//! displacements and their velocities. The transmission-error coordinate xi follows from
//! the position-level constraint g = 0 (the "non-holonomic" constraint of the paper is
//! integrable, `model.md` §3.3), omega2 from the velocity-level constraint, lambda from the
//! hidden constraint (§7); phi1 is the phase of the period and so not an unknown.
//!
//! With elastic teeth (`tooth_contact = elastic`, `model.md` §3.5) xi and omega2 are free:
//! [`elastic`] works on 14 components (the centres, xi, their rates), shoots from the
//! elastic start, names the mesh mode among the Floquet multipliers and continues orbits in
//! the drive speed (docs/dynamic_factor.md). The 12-coordinate functions ([`PeriodicSystem::lift`],
//! [`shooting::shoot`], [`modal`]) refuse an elastic system by name; [`harmonic`] takes
//! either.

pub mod elastic;
pub mod harmonic;
pub mod modal;
pub mod shooting;

use crate::parameter::ParamError;
use crate::radau5::{self, Options, Radau5, Statistics, Tolerance};
use crate::rotor::{
    dae_structure, idx, GearedRotor, InitialConditions, Inputs, ModelError, Params, RotorProblem,
    NY,
};
use nalgebra::SVector;
use std::f64::consts::PI;
use std::fmt;

/// Number of reduced coordinates: u1x u1y u1z u2x u2y u2z and their velocities.
pub const NZ: usize = 12;

/// Most RADAU5 step attempts per mesh period of a period integration. A period takes ~100-250 steps
/// (222 for the default pair at rtol 1e-13); a period that needs more than this does not
/// have the smooth orbit these methods assume (e.g. a spur contact line that sticks at the
/// pitch line, whose stick phases only the simulation's event handling resolves), and
/// stopping here ends a failing periodic start in ~0.1 s instead of 7-9 s (1e6 before).
pub const MAX_STEPS_PER_PERIOD: u64 = 20_000;

/// A monodromy's difference step is at least this many times the absolute error RADAU5
/// allows per step ([`PeriodicSystem::fd_steps`]): a period takes ~100-200 steps, so the
/// noise of the period map is up to ~1e2 of that, and 1e4 leaves the columns accurate to
/// ~1e-2 or better (1e-9 m for the displacements at rtol 1e-8, inside the range where the
/// period map is linear: the orbits' peak to peak is ~1e-7..1e-6 m).
pub const FD_NOISE_FACTOR: f64 = 1e4;

/// Reduced state at the start of a mesh period.
pub type Reduced = SVector<f64, NZ>;

/// Why a periodic solution could not be computed.
#[derive(Debug, Clone, PartialEq)]
pub enum PeriodicError {
    /// A parameter violates its bound.
    Param(ParamError),
    /// The model cannot be evaluated (e.g. no contact, inconsistent lambda).
    Model(ModelError),
    /// RADAU5 failed during a period integration.
    Solver(radau5::Error),
    /// omega1 must be positive and finite.
    InvalidSpeed {
        /// The rejected value [rad/s].
        omega1: f64,
    },
    /// Newton did not reach the tolerance.
    NoConvergence {
        /// "shooting" or "harmonic balance".
        method: &'static str,
        /// Iterations taken.
        iterations: usize,
        /// Scaled residual reached.
        residual: f64,
    },
    /// The Newton matrix is singular.
    Singular {
        /// "shooting" or "harmonic balance".
        method: &'static str,
    },
}

impl fmt::Display for PeriodicError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PeriodicError::Param(e) => write!(f, "{e}"),
            PeriodicError::Model(e) => write!(f, "model: {e}"),
            PeriodicError::Solver(e) => write!(f, "RADAU5: {e}"),
            PeriodicError::InvalidSpeed { omega1 } => {
                write!(f, "omega1 = {omega1} rad/s: a periodic orbit needs 0 < omega1 < inf")
            }
            PeriodicError::NoConvergence {
                method,
                iterations,
                residual,
            } => write!(
                f,
                "{method}: Newton did not converge in {iterations} iterations (scaled residual {residual:.3e})"
            ),
            PeriodicError::Singular { method } => write!(f, "{method}: singular Newton matrix"),
        }
    }
}

impl std::error::Error for PeriodicError {}

impl From<ParamError> for PeriodicError {
    fn from(e: ParamError) -> Self {
        PeriodicError::Param(e)
    }
}
impl From<ModelError> for PeriodicError {
    fn from(e: ModelError) -> Self {
        PeriodicError::Model(e)
    }
}
impl From<radau5::Error> for PeriodicError {
    fn from(e: radau5::Error) -> Self {
        PeriodicError::Solver(e)
    }
}

/// One sample of an orbit: time within the period and the centre displacements, the
/// transmission-error coordinate xi and lambda.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitPoint {
    /// Time since the start of the period in s.
    pub t: f64,
    /// u1x u1y u1z u2x u2y u2z in m.
    pub u: [f64; 6],
    /// Transmission-error coordinate xi in m (`rotor::idx::Q`).
    pub xi: f64,
    /// Normal contact force lambda in N.
    pub lambda: f64,
}

/// The geared rotor at one constant operating point, set up for periodic solutions.
#[derive(Clone)]
pub struct PeriodicSystem {
    problem: RotorProblem,
    omega1: f64,
    period: f64,
}

impl PeriodicSystem {
    /// The rotor with constant inputs `omega1`, `t_load`; phi1 = 0 at the start of a period,
    /// g0 from the undisplaced state.
    ///
    /// # Errors
    /// Invalid parameters or speed; a model that cannot be initialised.
    pub fn new(params: Params, omega1: f64, t_load: f64) -> Result<Self, PeriodicError> {
        if !(omega1 > 0.0 && omega1.is_finite()) {
            return Err(PeriodicError::InvalidSpeed { omega1 });
        }
        let mut model = GearedRotor::new(params)?;
        model.set_inputs(Inputs {
            omega1,
            t_load,
            ..Inputs::default()
        });
        // Laws 1 and 3 creep on an orbit as slow as a start that creeps (`model.md` §4.2).
        let creep = model.creeps_at(omega1);
        model.set_creep(creep);
        model.initialize(0.0)?;
        let period = 2.0 * PI / (f64::from(params.gear.z1) * omega1);
        Ok(PeriodicSystem {
            problem: RotorProblem { model },
            omega1,
            period,
        })
    }

    /// The mesh period `T_m = 2 pi / (z1 omega1)` in s.
    pub fn period(&self) -> f64 {
        self.period
    }

    /// Drive speed [rad/s].
    pub fn omega1(&self) -> f64 {
        self.omega1
    }

    /// The rotor model.
    pub fn model(&self) -> &GearedRotor {
        &self.problem.model
    }

    /// The frictionless static equilibrium (`GearedRotor::static_equilibrium`) as a
    /// reduced state, and its lambda: the start of the transient and of the harmonic
    /// approach.
    ///
    /// # Errors
    /// See `GearedRotor::static_equilibrium`.
    pub fn static_equilibrium(&self) -> Result<(Reduced, f64), PeriodicError> {
        let (ic, lambda) = self.model().static_equilibrium(0.0, 0.0)?;
        let mut z = Reduced::zeros();
        for i in 0..6 {
            z[i] = ic.u[i];
        }
        Ok((z, lambda))
    }

    /// Scales of the reduced coordinates: displacements by the static deflection under the
    /// nominal load of damper and load torque (`GearedRotor::nominal_lambda`; at least 1 nm),
    /// velocities by that times the mesh frequency 2 pi / T_m.
    pub fn scales(&self) -> Reduced {
        let p = self.model().params();
        let lambda = self.model().nominal_lambda(0.0).abs();
        let k = [p.rotor1.k, p.rotor2.k];
        let mut s = Reduced::zeros();
        let w = 2.0 * PI / self.period;
        for j in 0..2 {
            for a in 0..3 {
                let d = if k[j][a] > 0.0 { lambda / k[j][a] } else { 0.0 };
                s[3 * j + a] = d.max(1e-9);
                s[6 + 3 * j + a] = s[3 * j + a] * w;
            }
        }
        s
    }

    /// Forward-difference steps of a monodromy matrix whose period maps are integrated at
    /// `rtol`: `rel` times [`PeriodicSystem::scales`], but never below
    /// [`FD_NOISE_FACTOR`] times the absolute error RADAU5 allows per step (`rtol` times the
    /// FMU's scale of the component, `GearedRotor::scales`). Why the floor: with little load the
    /// deflection scale is small (none at all without damper and load torque: the 1 nm
    /// floor), and a difference step of 1e-13 m sits in the integration noise, which made
    /// stable orbits look unstable (d_phi = 0, T_load = 100 N m: |mu| = 4.45 before).
    pub fn fd_steps(&self, rel: f64, rtol: f64) -> Reduced {
        let s = self.scales();
        Reduced::from_fn(|i, _| {
            let scale = self.model().scales();
            let noise = if i < 6 {
                scale[idx::Q + i]
            } else {
                scale[idx::V + i - 6]
            } * rtol;
            (rel * s[i]).max(FD_NOISE_FACTOR * noise)
        })
    }

    /// Full consistent state at the start of a period (t = 0, phi1 = 0) from the reduced
    /// coordinates: xi from g = 0, omega2 from the velocity constraint, lambda from the
    /// hidden constraint (`model.md` §3.3, §7), filter at rest, energies zero.
    ///
    /// # Errors
    /// Mesh, contact or lambda errors.
    pub fn lift(&self, z: &Reduced) -> Result<SVector<f64, NY>, PeriodicError> {
        self.require_rigid("the 12 reduced coordinates (shooting::shoot, modal)")?;
        let ic = InitialConditions {
            u: std::array::from_fn(|i| z[i]),
            u_dot: std::array::from_fn(|i| z[6 + i]),
            phi1: 0.0,
        };
        Ok(self.model().consistent_state(0.0, &ic)?)
    }

    /// The reduced coordinates of a full state.
    pub fn reduce(y: &SVector<f64, NY>) -> Reduced {
        let mut z = Reduced::zeros();
        for i in 0..6 {
            z[i] = y[idx::Q + i];
            z[6 + i] = y[idx::V + i];
        }
        z
    }

    /// RADAU5 options for the period integrations: scalar rtol, atol = rtol times the
    /// physical scales of the FMU (`GearedRotor::scales`), the DAE's structure
    /// (`rotor::dae_structure`, as the FMU's stepper) and the step budget.
    fn options(&self, rtol: f64, periods: usize) -> Options<NY> {
        let scales = self.integration_scales();
        Options {
            rtol: Tolerance::Scalar(rtol),
            atol: Tolerance::PerComponent(SVector::<f64, NY>::from_fn(|i, _| rtol * scales[i])),
            max_steps: MAX_STEPS_PER_PERIOD * periods.max(1) as u64,
            ..dae_structure(self.model().params().tooth_contact)
        }
    }

    /// The physical scales of the period integrations' absolute tolerance: the FMU's
    /// (`GearedRotor::scales`), except with the elastic contact xi and omega2, which take the
    /// static mesh deflection and its rate ([`PeriodicSystem::scales_elastic`]) where those are
    /// smaller: the FMU scales xi like the centre displacements, and with soft bearings the
    /// mesh deflection is far smaller than those, so the period map's noise in xi (and the
    /// difference monodromy's) would be set by the bearings, not by the mesh.
    pub fn integration_scales(&self) -> [f64; NY] {
        let mut scales = *self.model().scales();
        if self.is_elastic() {
            let s = self.scales_elastic();
            let rb2 = self.model().geometry().rb2;
            scales[idx::Q + 6] = scales[idx::Q + 6].min(s[6]);
            scales[idx::V + 6] = scales[idx::V + 6].min(s[13] / rb2);
        }
        scales
    }

    /// Integrates from the consistent lift of `z` over `periods` mesh periods with RADAU5
    /// at `rtol` and returns the reduced end state and the solver statistics. When
    /// `samples` is given, the last period is sampled at that many equidistant times
    /// (dense output, the steps are not changed by the sampling).
    ///
    /// # Errors
    /// Lift or solver errors.
    pub fn integrate(
        &mut self,
        z: &Reduced,
        periods: usize,
        rtol: f64,
        samples: Option<(usize, &mut Vec<OrbitPoint>)>,
    ) -> Result<(Reduced, Statistics), PeriodicError> {
        let y0 = self.lift(z)?;
        let (y, stats) = self.integrate_state(y0, periods, rtol, samples)?;
        Ok((Self::reduce(&y), stats))
    }

    /// [`PeriodicSystem::integrate`] from a full state `y0` at t = 0 (phi1 = 0): the full
    /// end state. The sampled `lambda` is the multiplier (rigid) or the elastic contact's
    /// normal force Fn (`model.md` (3.16); the last slot of y holds the spring's work there).
    ///
    /// # Errors
    /// Solver errors.
    pub fn integrate_state(
        &mut self,
        y0: SVector<f64, NY>,
        periods: usize,
        rtol: f64,
        samples: Option<(usize, &mut Vec<OrbitPoint>)>,
    ) -> Result<(SVector<f64, NY>, Statistics), PeriodicError> {
        let options = self.options(rtol, periods);
        // The elastic normal force is a function of the state, evaluated on a copy of the
        // model (the solver holds the problem).
        let fn_model =
            (!self.problem.model.contact().has_multiplier()).then(|| self.problem.model.clone());
        let mut solver = Radau5::new(&mut self.problem, options, 0.0, y0)?;
        let t_end = periods as f64 * self.period;
        let t_last = t_end - self.period;
        match samples {
            None => solver.integrate_to(&mut self.problem, t_end)?,
            Some((n, out)) => {
                out.clear();
                solver.integrate_to(&mut self.problem, t_last)?;
                let mut next = 0usize;
                let mut y = SVector::<f64, NY>::zeros();
                let mut push = |s: &Radau5<NY>, next: &mut usize, upto: f64| {
                    while *next < n {
                        let ts = t_last + self.period * (*next as f64) / (n as f64);
                        if ts > upto {
                            break;
                        }
                        if ts == s.t() {
                            y.copy_from(s.y());
                        } else {
                            s.dense_output(ts, &mut y);
                        }
                        let mut u = [0.0; 6];
                        for (i, ui) in u.iter_mut().enumerate() {
                            *ui = y[idx::Q + i];
                        }
                        let lambda = match &fn_model {
                            Some(m) => m.contact().normal_force(ts, &y),
                            None => y[idx::LAMBDA],
                        };
                        out.push(OrbitPoint {
                            t: ts - t_last,
                            u,
                            xi: y[idx::Q + 6],
                            lambda,
                        });
                        *next += 1;
                    }
                };
                push(&solver, &mut next, t_last);
                while solver.t() < t_end {
                    solver.step(&mut self.problem, t_end)?;
                    push(&solver, &mut next, solver.t());
                }
            }
        }
        Ok((*solver.y(), *solver.stats()))
    }

    /// Whether the tooth contact is elastic (`model.md` §3.5): its mesh coordinates are
    /// free (`Contact::mesh_coordinates_free`), so the periodic state has 14 components
    /// ([`elastic`]) instead of the 12 of the centres.
    pub fn is_elastic(&self) -> bool {
        self.model().contact().mesh_coordinates_free()
    }

    /// A typed refusal of the rigid-only parts (`what`) in elastic mode.
    pub(crate) fn require_rigid(&self, what: &str) -> Result<(), PeriodicError> {
        if self.is_elastic() {
            return Err(PeriodicError::Param(ParamError {
                name: "tooth_contact",
                value: f64::from(self.model().params().tooth_contact.code()),
                requirement: format!(
                    "tooth_contact = rigid for {what}; with tooth_contact = elastic the \
                     periodic state has 14 components (transmission error and omega2 are \
                     free): use periodic::elastic (shoot_elastic, lift_elastic)"
                ),
            }));
        }
        Ok(())
    }
}

/// Largest deviation of the centre positions (x-y plane, both gears) of an approximate
/// orbit from a reference orbit sampled at the same times, relative to the reference
/// orbit's peak-to-peak size: `max_t max_j |c_j(t) - c_j_ref(t)| / max_j pp_j`, with
/// `pp_j` the larger of the x and y peak-to-peak ranges of gear j's centre.
pub fn max_rel_deviation(approx: &[OrbitPoint], reference: &[OrbitPoint]) -> f64 {
    let mut pp: f64 = 0.0;
    for j in 0..2 {
        for a in 0..2 {
            let k = 3 * j + a;
            let (lo, hi) = reference
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p.u[k]), hi.max(p.u[k]))
                });
            pp = pp.max(hi - lo);
        }
    }
    let mut dev: f64 = 0.0;
    for (p, r) in approx.iter().zip(reference) {
        for j in 0..2 {
            let dx = p.u[3 * j] - r.u[3 * j];
            let dy = p.u[3 * j + 1] - r.u[3 * j + 1];
            dev = dev.max(dx.hypot(dy));
        }
    }
    dev / pp
}
