//! The geared-rotor DAE driven by RADAU5 across communication points (safe Rust, no FMI).
//!
//! [`Simulation`] owns a [`GearedRotor`] (physics, model.md §5-§8) and a [`Radau5`] stepper
//! (radau5.md) and adds what a co-simulation needs:
//! - time bookkeeping without drift: the FMU time is exactly the last
//!   `t_end = currentCommunicationPoint + h` (the master's own arithmetic), so no round-off
//!   of ours accumulates; the communication point is compared with the FMU time with a
//!   tolerance relative to `h` ([`comm_tolerance`]);
//! - `do_step` continues the stepper (h, Jacobian, LU, error history survive) and sub-steps
//!   internally until `t_end`; a single call over the whole horizon works;
//! - look-ahead: while the input function stays the same, RADAU5 takes its own steps across
//!   communication points and the state at `t_end` comes from its dense output (a step
//!   shorter than the solver's natural step costs an interpolation, not a step). When an
//!   input or a tunable then changes, the step that went past the FMU time is retaken to end
//!   exactly on it ([`Radau5::retake`]) before the change applies, so the result is that of
//!   a stepper stopped at every point where the inputs changed;
//! - held inputs with optional first derivatives (FMI `canInterpolateInputs`); only when the
//!   input function really changes is f re-evaluated ([`Radau5::refresh`], J and LU kept:
//!   the inputs enter f additively); new tunables restart the stepper;
//! - tunable parameters (mu, d_phi), per-component absolute tolerances from physical scales
//!   ([`SCALES`]), output derivatives from the dense output;
//! - a plain-data snapshot ([`SimState`]) and its versioned serialisation ([`codec`]);
//! - on a solver failure the state stays at the last accepted step (the "last successful
//!   time" of FMI's `fmi2Discard`);
//! - a real-time mode with equal, bounded work per doStep ([`realtime`], `h_fixed > 0`).

mod closed_loop;
pub mod codec;
pub mod init;
pub mod realtime;
mod validate;
pub mod validity;

pub use validate::{DEFAULT_MAX_INTERNAL_STEPS, STEP_RESOLUTION};

use crate::fmt_num::Short;
use crate::gear::{FrictionParams, GearData, ParamError};
use crate::radau5::{
    self, Options, Problem, Radau5, Retake, RhsError, Snapshot, Statistics, Tolerance,
};
use crate::rotor::{
    idx, FrictionLaw, GearedRotor, Inputs, ModelError, Outputs, Params, RotorData, NY,
};
/// Moved to `rotor` (shared with `periodic`); re-exported here for existing code.
pub use crate::rotor::{RotorProblem, SCALES};
use codec::{DecodeError, Reader, Writer};
pub use init::{InitError, InitReport, Initialization};
use nalgebra::{SMatrix, SVector};
use std::fmt;
use validity::Monitor;
pub use validity::{OnViolation, Violation, ViolationKind};

/// Factor on rtol for phi1 (see [`SCALES`]): with 1e-3 the relative part stays below the
/// absolute one for |phi1| < 250 rad (0.8 s at the default speed) and grows slowly after.
pub const PHI1_RTOL_FACTOR: f64 = 1e-3;

/// The range of rtol (the declared min and max of the parameter `rtol`).
pub const RTOL_MIN: f64 = 1e-13;
/// See [`RTOL_MIN`].
pub const RTOL_MAX: f64 = 0.1;

/// Floor of phi1's relative tolerance: RADAU5 needs rtol > 10 uround = 1e-15 for every
/// component, and `rtol * PHI1_RTOL_FACTOR` would go below it for rtol < 1e-12 (the
/// declared rtol goes down to 1e-13).
const PHI1_RTOL_MIN: f64 = 1e-14;

/// Stop RADAU5 steps at predicted mesh events (see `Simulation::next_mesh_event`).
const MESH_EVENT_STOPS: bool = true;

/// Step across communication points while the input function is unchanged (see the module
/// docs). Measured (default case, rtol 1e-6, steady state, H = 1e-5 s): without 5.1 ms CPU
/// and ~1020 internal steps per simulated 10 ms; with: see docs/development.md "Benchmarks".
const LOOKAHEAD: bool = true;

/// Stop time given to the stepper in look-ahead mode: far enough never to be reached,
/// finite so that `t_stop - t` stays finite.
const NO_STOP: f64 = f64::MAX;

/// Mesh events closer than this fraction of a base-pitch passage to the current time are
/// skipped (the kink then lies within the first 74 ns of a step at the default speed).
/// 1e-6 before: two events that nearly coincide cost a sliver step of ~2 ns and a new LU.
/// Measured with [`MESH_EVENT_RESUME`] over 7 cases (default, spur, mu 0.01, omega1 100
/// and 600 rad/s, rtol 1e-4 and 1e-8; 0..100 ms): see `MESH_EVENT_RESUME`.
const MESH_EVENT_MERGE: f64 = 1e-4;

/// Spur pairs (f jumps at the events): events closer than this fraction of a base pitch
/// are skipped, and f is taken from after them ([`Simulation::f_after_event`]).
const JUMP_MERGE: f64 = 1e-6;

/// Spur pairs: a step stops this fraction of a base pitch before a located jump (74 ps at
/// the default speed), so that it never ends a hair after it.
const JUMP_MARGIN: f64 = 1e-7;

/// RADAU5 `resume_after_stop` for the simulation: after a step that ended on a mesh event
/// (a kink of f), the next starts at no more than 0.8 of the proposal from before the
/// event, which was made on the smoother side and got ~10 % of all steps rejected.
/// Work over the 7 cases of [`MESH_EVENT_MERGE`] (f evaluations + 15 per Jacobian + 8.6 per
/// LU pair + 4.1 per Newton solve + 1.8 per step, weights from callgrind instruction counts
/// of the default case): 646k with 1.0 and 1e-6, 609k with 1.0 and 1e-3, 585k with 0.8
/// and 1e-4 (default case alone 60.5k to 52.9k: 308 to 179 Jacobians, 250 to 168
/// rejections); flat between 0.5 and 0.8; errors against rtol/1000 runs unchanged in size.
const MESH_EVENT_RESUME: f64 = 0.8;

/// Mesh-event stops only above this friction coefficient. Measured CPU per 10 ms (default
/// case, one doStep) without / with stops: mu = 0.001: 1.6 / 2.3 ms; 0.003: 2.3 / 2.5;
/// 0.01: 3.5 / 3.1; 0.02: 4.3 / 3.4; 0.05: 5.5 / 3.5; 0.1: 6.4 / 4.2.
const MESH_EVENT_MIN_MU: f64 = 0.005;

/// Most internal steps one communication interval may take before the stepper gives up
/// (radau5 `max_steps` counts since the last stop time): 1e6 steps of the default
/// h_max = 1e-4 s cover 100 s of simulated time in one doStep.
pub const MAX_STEPS_PER_INTERVAL: u64 = 1_000_000;

/// Relative width of the central difference on the dense output used for output
/// derivatives: delta = 1e-3 (t - t_prev). The collocation polynomial is cubic, so the
/// truncation error is ~1e-7 relative, far below the solver tolerance.
const DERIVATIVE_DELTA: f64 = 1e-3;

/// Tolerance for `|currentCommunicationPoint - t| `: 1e-8 of the step, plus a few ulps of
/// t (masters compute `start + n h` or sum steps; both differ from ours by round-off only).
pub fn comm_tolerance(t: f64, h: f64) -> f64 {
    1e-8 * h.abs() + 16.0 * f64::EPSILON * t.abs()
}

/// Solver settings fixed at initialisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// Relative tolerance (from fmi2SetupExperiment if defined, else the `rtol` parameter).
    pub rtol: f64,
    /// Maximum internal step size in s.
    pub h_max: f64,
}

impl SolverSettings {
    /// Validates the settings, naming the parameter and the bound.
    ///
    /// # Errors
    /// rtol outside [1e-13, 0.1], h_max not positive.
    pub fn validate(&self) -> Result<(), ParamError> {
        if !(self.rtol >= RTOL_MIN && self.rtol <= RTOL_MAX) {
            return Err(ParamError {
                name: "rtol",
                value: self.rtol,
                requirement: "1e-13 <= rtol <= 0.1 (the declared min and max)".into(),
            });
        }
        if !(self.h_max > 0.0 && self.h_max.is_finite()) {
            return Err(ParamError {
                name: "h_max",
                value: self.h_max,
                requirement: "0 < h_max < inf".into(),
            });
        }
        Ok(())
    }

    /// The RADAU5 options the simulation runs with (tolerances from [`SCALES`], index
    /// counts, the quadrature and second-order structure of the rotor DAE).
    pub fn options(&self) -> Options<NY> {
        Options::<NY> {
            rtol: Tolerance::PerComponent(SVector::<f64, NY>::from_fn(|i, _| {
                if i == idx::PHI1 {
                    (self.rtol * PHI1_RTOL_FACTOR).max(PHI1_RTOL_MIN)
                } else {
                    self.rtol
                }
            })),
            atol: Tolerance::PerComponent(SVector::<f64, NY>::from_fn(|i, _| {
                self.rtol * SCALES[i]
            })),
            h_max: self.h_max,
            max_steps: MAX_STEPS_PER_INTERVAL,
            n1: crate::rotor::N_INDEX1,
            n2: crate::rotor::N_INDEX2,
            n3: 0,
            // E_IN..E_LOAD enter no right-hand side (zero Jacobian columns, identity rows
            // of M_ext): factorise 18 x 18 instead of 22 x 22 (radau5 `Options::quadrature`).
            quadrature: std::array::from_fn(|i| (idx::E_IN..=idx::E_LOAD).contains(&i)),
            // u_i' = v_i (i < 6, v = y[7..]): eliminated from the linear systems, which
            // leaves 12 x 12 LUs (radau5 `Options::second_order`, Fortran IWORK(9..10)).
            second_order: Some((6, idx::V)),
            // Clipped steps end on mesh events (kinks of f) here, not on smooth points.
            resume_after_stop: MESH_EVENT_RESUME,
            ..Options::default()
        }
    }
}

/// One of the two model inputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// Reference speed of rotor 1 [rad/s].
    Omega1,
    /// Load torque on gear 2 [N m].
    TLoad,
}

impl Input {
    fn name(self) -> &'static str {
        match self {
            Input::Omega1 => "omega1",
            Input::TLoad => "T_load",
        }
    }
    fn index(self) -> usize {
        match self {
            Input::Omega1 => 0,
            Input::TLoad => 1,
        }
    }
}

/// Everything that can go wrong in the simulation layer.
#[derive(Debug, Clone, PartialEq)]
pub enum SimError {
    /// A parameter violates a bound (the model's or the solver settings').
    Param(ParamError),
    /// The model could not set up a consistent initial state.
    Model(ModelError),
    /// RADAU5 could not continue; the state is that of `last_successful_time`.
    Solver {
        /// The stepper's error (with t and h).
        error: radau5::Error,
        /// Time of the last accepted step (the FMU's time now).
        last_successful_time: f64,
    },
    /// Communication step size not positive, not finite, or below the resolution of t.
    StepSize {
        /// The step size.
        h: f64,
        /// The current time.
        t: f64,
    },
    /// The communication point does not match the FMU's time.
    CommunicationPoint {
        /// FMU time.
        expected: f64,
        /// What the master passed.
        got: f64,
        /// Accepted deviation.
        tolerance: f64,
    },
    /// NaN or infinite input or parameter value.
    NonFinite {
        /// Variable name.
        name: &'static str,
        /// The value.
        value: f64,
    },
    /// A serialized state could not be read.
    Decode(DecodeError),
    /// The requested initial state (`initialization`) could not be set.
    Init(InitError),
    /// The run left the model's validity (lift-off, drive reversal) and the policy is
    /// [`OnViolation::Discard`]: the FMU time is the located instant.
    Validity(Violation),
    /// The doStep took `max_internal_steps` internal steps without reaching its end; the
    /// state is that of the last of them (`t`).
    WorkLimit {
        /// The limit (parameter max_internal_steps).
        limit: u64,
        /// Where the doStep stopped (the last successful time).
        t: f64,
        /// The end of the communication interval.
        t_end: f64,
    },
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Param(e) => write!(f, "{e}"),
            SimError::Model(e) => write!(f, "model error: {e}"),
            SimError::Solver { error, last_successful_time } => {
                write!(f, "RADAU5 cannot continue: {error}; state kept at the last successful time t = {last_successful_time:e} s")?;
                if matches!(error, radau5::Error::FixedStepNewton { .. }) {
                    write!(f, " (real-time mode: choose a smaller h_fixed, or a larger rtol, which sets the Newton tolerance)")?;
                }
                Ok(())
            }
            SimError::StepSize { h, t } => {
                write!(f, "communication step size h = {h:e} s is not a positive finite step that advances t = {t:e} s")
            }
            SimError::CommunicationPoint { expected, got, tolerance } => write!(
                f,
                "currentCommunicationPoint = {} s does not match the FMU time {} s (tolerance {tolerance:e} s)",
                Short(*got),
                Short(*expected)
            ),
            SimError::NonFinite { name, value } => write!(f, "{name} = {value} is not a finite number"),
            SimError::Decode(e) => write!(f, "invalid serialized FMU state: {e}"),
            SimError::Init(e) => write!(f, "initialization: {e}"),
            SimError::Validity(v) => write!(f, "{v}"),
            SimError::WorkLimit { limit, t, t_end } => write!(
                f,
                "stopped after {limit} internal steps (parameter max_internal_steps) at t = {} s, before the end of the communication step at {} s; state kept there (raise max_internal_steps or take shorter steps)",
                Short(*t),
                Short(*t_end)
            ),
        }
    }
}

impl std::error::Error for SimError {}

impl From<ParamError> for SimError {
    fn from(e: ParamError) -> Self {
        SimError::Param(e)
    }
}

impl From<DecodeError> for SimError {
    fn from(e: DecodeError) -> Self {
        SimError::Decode(e)
    }
}

/// [`RotorProblem`] with f evaluated at phi1 + dphi (the right-hand limit at a mesh event
/// of a spur pair, [`Simulation::f_after_event`]).
struct PhaseAhead<'a> {
    inner: &'a mut RotorProblem,
    dphi: f64,
}

impl Problem<NY> for PhaseAhead<'_> {
    fn rhs(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        f: &mut SVector<f64, NY>,
    ) -> Result<(), RhsError> {
        let mut ya = *y;
        ya[idx::PHI1] += self.dphi;
        self.inner.rhs(t, &ya, f)
    }
    fn jacobian(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        jac: &mut SMatrix<f64, NY, NY>,
    ) -> Result<bool, RhsError> {
        self.inner.jacobian(t, y, jac)
    }
    fn mass(&self) -> Option<SMatrix<f64, NY, NY>> {
        self.inner.mass()
    }
}

/// What happened during one communication interval (for logging).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepReport {
    /// RADAU5 counters of this interval only.
    pub stats: Statistics,
    /// How often `contact_lost` (lambda < 0) changed at internal steps.
    pub contact_changes: u32,
    /// Time of the first change in this interval (NaN if none).
    pub first_change_time: f64,
    /// `contact_lost` at the end of the interval.
    pub contact_lost: bool,
    /// Whether f changed at the start (new inputs: `Radau5::refresh`; new tunables or after
    /// a failure: `Radau5::restart`).
    pub restarted: bool,
    /// Episodes outside the model's validity that started in this interval (policy
    /// [`OnViolation::Warn`]), in the order found.
    pub violations: [Option<Violation>; validity::MAX_REPORTED],
    /// Further ones not listed.
    pub violations_dropped: u32,
}

/// The model state at initialisation; replayed when a serialized state is loaded, so that
/// whatever `GearedRotor::initialize` sets internally (e.g. the gap offset g0) is rebuilt
/// bit-identically without reaching into the model.
#[derive(Debug, Clone, Copy, PartialEq)]
struct InitRecord {
    params: Params,
    inputs: Inputs,
    t_start: f64,
    /// The consistent initial state (recomputed by the replay for `Rest`, serialized for
    /// the others, whose computation is not repeated).
    y0: SVector<f64, NY>,
    /// How y0 was set.
    initialization: Initialization,
}

/// A complete, plain-data snapshot of a [`Simulation`].
#[derive(Clone)]
pub struct SimState {
    solver: Snapshot<NY>,
    t_comm: f64,
    model: GearedRotor,
    settings: SolverSettings,
    init: InitRecord,
    inputs: Inputs,
    inputs_ref: Inputs,
    der_set: [bool; 2],
    restart_pending: bool,
    contact_lost: bool,
    last_successful_time: f64,
    validity: Monitor,
    /// Real-time mode (`realtime`): the fixed internal step bound, 0 = adaptive.
    h_fixed: f64,
}

/// The rotor and its stepper.
pub struct Simulation {
    problem: RotorProblem,
    solver: Radau5<NY>,
    /// The FMU time: the last communication point reached. The stepper is at or past it
    /// (`solver.t_prev() < t_comm <= solver.t()` after a look-ahead step).
    t_comm: f64,
    /// The state at `t_comm` (the stepper's y, or its dense output there).
    y_comm: SVector<f64, NY>,
    settings: SolverSettings,
    init: InitRecord,
    /// Per input: a derivative was set at the current communication point.
    der_set: [bool; 2],
    /// The input function the stepper was last (re)started with; a doStep restarts RADAU5
    /// only if the inputs now describe a different function.
    inputs_ref: Inputs,
    restart_pending: bool,
    contact_lost: bool,
    last_successful_time: f64,
    /// Episodes outside the model's validity (`validity`).
    validity: Monitor,
    /// What the initialisation did (not part of snapshots).
    init_report: InitReport,
    /// Most internal steps per doStep (see [`Simulation::set_max_internal_steps`]).
    max_internal_steps: u64,
    /// Real-time mode (`realtime`): the fixed internal step bound, 0 = adaptive.
    h_fixed: f64,
}

fn solver_err(error: radau5::Error, t: f64) -> SimError {
    SimError::Solver {
        error,
        last_successful_time: t,
    }
}

impl Simulation {
    /// Validates the parameters, builds the model, computes the consistent initial state at
    /// `t_start` for the given inputs (model.md §7) and starts RADAU5 there.
    ///
    /// # Errors
    /// [`SimError::Param`] naming the violated bound, [`SimError::NonFinite`] for bad inputs,
    /// [`SimError::Model`] / [`SimError::Solver`] if no consistent start exists.
    pub fn new(
        params: Params,
        settings: SolverSettings,
        t_start: f64,
        omega1: f64,
        t_load: f64,
    ) -> Result<Self, SimError> {
        Self::with_initialization(
            params,
            settings,
            t_start,
            omega1,
            t_load,
            Initialization::Rest,
        )
    }

    /// [`Simulation::new`] with the initial state chosen by `initialization` (see
    /// [`init`]).
    ///
    /// # Errors
    /// As [`Simulation::new`]; [`SimError::Init`] when the requested state cannot be set
    /// (e.g. no stable periodic orbit).
    pub fn with_initialization(
        params: Params,
        settings: SolverSettings,
        t_start: f64,
        omega1: f64,
        t_load: f64,
        initialization: Initialization,
    ) -> Result<Self, SimError> {
        settings.validate()?;
        if !t_start.is_finite() {
            return Err(SimError::NonFinite {
                name: "startTime",
                value: t_start,
            });
        }
        for (name, value) in [("omega1", omega1), ("T_load", t_load)] {
            if !value.is_finite() {
                return Err(SimError::NonFinite { name, value });
            }
        }
        let inputs = Inputs {
            omega1,
            omega1_der: 0.0,
            t_load,
            t_load_der: 0.0,
            t_ref: t_start,
        };
        let mut init = InitRecord {
            params,
            inputs,
            t_start,
            y0: SVector::zeros(),
            initialization,
        };
        let (mut problem, mut y0) = Self::replay(&init)?;
        let mut init_report = InitReport::default();
        if initialization != Initialization::Rest {
            (y0, init_report) =
                init::initial_state(&problem.model, t_start, initialization, settings.rtol)
                    .map_err(SimError::Init)?;
        }
        init.y0 = y0;
        let solver = Radau5::new(&mut problem, settings.options(), t_start, y0)
            .map_err(|e| solver_err(e, t_start))?;
        let contact_lost = y0[idx::LAMBDA] < 0.0;
        let validity = Monitor::new(t_start, y0[idx::LAMBDA], y0[idx::OMEGA1]);
        Ok(Simulation {
            problem,
            solver,
            t_comm: t_start,
            y_comm: y0,
            settings,
            init,
            der_set: [false; 2],
            inputs_ref: inputs,
            restart_pending: false,
            contact_lost,
            last_successful_time: t_start,
            validity,
            init_report,
            max_internal_steps: DEFAULT_MAX_INTERNAL_STEPS,
            h_fixed: 0.0,
        })
    }

    /// What the initialisation did (zero counters for `rest` and `static_equilibrium`,
    /// and after a state was restored from a serialized snapshot).
    pub fn init_report(&self) -> &InitReport {
        &self.init_report
    }

    fn replay(init: &InitRecord) -> Result<(RotorProblem, SVector<f64, NY>), SimError> {
        let mut model = GearedRotor::new(init.params)?;
        model.set_inputs(init.inputs);
        let y0 = model.initialize(init.t_start).map_err(SimError::Model)?;
        Ok((RotorProblem { model }, y0))
    }

    /// The FMU time (exactly the last `t_end`).
    pub fn time(&self) -> f64 {
        self.t_comm
    }

    /// Time the stepper has reached: the FMU time, or later after a look-ahead step.
    pub fn stepper_time(&self) -> f64 {
        self.solver.t()
    }

    /// Whether the stepper has stepped past the FMU time (look-ahead).
    fn ahead(&self) -> bool {
        self.solver.t() > self.t_comm
    }

    /// Sets the FMU time and the state there from the stepper.
    fn set_comm(&mut self, t: f64) {
        self.t_comm = t;
        if t == self.solver.t() {
            self.y_comm = *self.solver.y();
        } else {
            self.solver.dense_output(t, &mut self.y_comm);
        }
    }

    /// Before f changes at the FMU time: a look-ahead step is retaken so that the stepper
    /// ends exactly on the FMU time with the function it was taken with.
    fn sync(&mut self) -> Result<(), SimError> {
        if !self.ahead() {
            return Ok(());
        }
        let t = self.t_comm;
        match self.solver.retake(&mut self.problem, t) {
            Ok(how) => {
                if how == Retake::Interpolated {
                    self.restart_pending = true;
                }
                self.set_comm(t);
                Ok(())
            }
            Err(e) => {
                self.restart_pending = true;
                Err(solver_err(e, t))
            }
        }
    }

    /// Time of the last accepted step (after a failed `do_step`: how far it got).
    pub fn last_successful_time(&self) -> f64 {
        self.last_successful_time
    }

    /// The solver settings in use.
    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    /// The model (parameters, geometry, inputs).
    pub fn model(&self) -> &GearedRotor {
        &self.problem.model
    }

    /// RADAU5 counters since the start.
    pub fn stats(&self) -> &Statistics {
        self.solver.stats()
    }

    /// The state vector at the FMU time.
    pub fn y(&self) -> &SVector<f64, NY> {
        &self.y_comm
    }

    /// Whether lambda < 0 (tooth lift-off) at the current time.
    pub fn contact_lost(&self) -> bool {
        self.contact_lost
    }

    /// The inputs rebased to time t: value(t) = value + der (t - t_ref).
    fn rebased(&self, t: f64) -> Inputs {
        rebase(self.problem.model.inputs(), t)
    }

    /// Whether f changes at the FMU time before the next step: the input function differs
    /// from the one the last step used (re-setting the same values, or values that continue
    /// the same ramp, is no change), or a tunable changed or a failure left a restart due.
    fn change_pending(&self) -> bool {
        let t = self.time();
        self.restart_pending || !same_function(&rebase(&self.inputs_ref, t), &self.rebased(t))
    }

    /// Value of an input at the current time (what the master set, extrapolated with its
    /// derivative).
    pub fn input(&self, which: Input) -> f64 {
        let i = self.rebased(self.time());
        match which {
            Input::Omega1 => i.omega1,
            Input::TLoad => i.t_load,
        }
    }

    fn apply_inputs(&mut self, new: Inputs) -> Result<(), SimError> {
        let t = self.time();
        let old = self.rebased(t);
        if !same_function(&old, &new) {
            self.sync()?;
        }
        if !identical_function(&old, &new) {
            self.problem.model.set_inputs(new);
        }
        Ok(())
    }

    /// Sets an input at the current communication point. Without a derivative set at the
    /// same communication point, the input is held constant (zero-order hold).
    ///
    /// # Errors
    /// NaN or infinite value.
    pub fn set_input(&mut self, which: Input, value: f64) -> Result<(), SimError> {
        if !value.is_finite() {
            return Err(SimError::NonFinite {
                name: which.name(),
                value,
            });
        }
        let mut i = self.rebased(self.time());
        let keep_der = self.der_set[which.index()];
        match which {
            Input::Omega1 => {
                i.omega1 = value;
                if !keep_der {
                    i.omega1_der = 0.0;
                }
            }
            Input::TLoad => {
                i.t_load = value;
                if !keep_der {
                    i.t_load_der = 0.0;
                }
            }
        }
        self.apply_inputs(i)
    }

    /// Sets the first time derivative of an input at the current communication point
    /// (fmi2SetRealInputDerivatives, order 1): value(t) = value(t_c) + der (t - t_c).
    ///
    /// # Errors
    /// NaN or infinite value.
    pub fn set_input_derivative(&mut self, which: Input, der: f64) -> Result<(), SimError> {
        if !der.is_finite() {
            return Err(SimError::NonFinite {
                name: which.name(),
                value: der,
            });
        }
        let mut i = self.rebased(self.time());
        match which {
            Input::Omega1 => i.omega1_der = der,
            Input::TLoad => i.t_load_der = der,
        }
        self.der_set[which.index()] = true;
        self.apply_inputs(i)
    }

    /// Changes the friction coefficient (tunable) at the current communication point.
    ///
    /// # Errors
    /// The model's bound on mu.
    pub fn set_mu(&mut self, mu: f64) -> Result<(), SimError> {
        if mu != self.problem.model.params().mu {
            crate::rotor::params::check_mu(mu)?;
            self.sync()?;
            self.problem.model.set_mu(mu)?;
            self.restart_pending = true;
        }
        Ok(())
    }

    /// Changes the rotational damper on gear 2 (tunable).
    ///
    /// # Errors
    /// The model's bound on d_phi.
    pub fn set_d_phi(&mut self, d: f64) -> Result<(), SimError> {
        if d != self.problem.model.params().d_phi {
            crate::rotor::params::check_d_phi(d)?;
            self.sync()?;
            self.problem.model.set_d_phi(d)?;
            self.restart_pending = true;
        }
        Ok(())
    }

    /// Integrates from the current time to exactly `ccp + h`, continuing the stepper.
    ///
    /// # Errors
    /// [`SimError::StepSize`], [`SimError::CommunicationPoint`] (nothing changed), or
    /// [`SimError::Solver`] (also "step size too small" when a step cannot advance t) or
    /// [`SimError::WorkLimit`] (more than `max_internal_steps` steps): the state is then
    /// that of the last accepted step.
    pub fn do_step(&mut self, ccp: f64, h: f64) -> Result<StepReport, SimError> {
        let t = self.time();
        if !(h > 0.0 && h.is_finite()) {
            return Err(SimError::StepSize { h, t });
        }
        let tol = comm_tolerance(t, h);
        if !ccp.is_finite() || (ccp - t).abs() > tol {
            return Err(SimError::CommunicationPoint {
                expected: t,
                got: ccp,
                tolerance: tol,
            });
        }
        let t_end = ccp + h;
        if t_end <= t {
            return Err(SimError::StepSize { h, t });
        }
        if self.h_fixed > 0.0 {
            return self.do_step_fixed(t, t_end);
        }
        let stats0 = *self.solver.stats();
        let mut report = StepReport {
            first_change_time: f64::NAN,
            ..StepReport::default()
        };
        // The right-hand side changes at t if the input function changed: restart the
        // stepper (fresh f, Jacobian marked stale, h kept). Re-setting the same values (or
        // values that continue the same ramp) costs nothing.
        let change = self.change_pending();
        self.inputs_ref = *self.problem.model.inputs();
        if change {
            // The setters have already retaken a look-ahead step (`sync`); a no-op then.
            if let Err(e) = self.sync() {
                self.last_successful_time = t;
                return Err(e);
            }
            // lambda is algebraic: a new d_phi, mu or T_load moves it at once, so go on
            // from its consistent value (hidden constraint, model.md §7), not the stale one.
            let mut y = *self.solver.y();
            match self.problem.model.consistent_lambda(t, &y) {
                Ok(l) => y[idx::LAMBDA] = l,
                Err(e) => {
                    self.last_successful_time = t;
                    return Err(SimError::Model(e));
                }
            }
            // Inputs enter f additively (the filter's reference, the load torque; J sees
            // T_load only in the E_load quadrature row, T_load omega2, which the simplified
            // Newton iteration absorbs), so J and the LU pair stay usable: only f is
            // re-evaluated (`Radau5::refresh`). A new tunable changes J, and a failed step
            // leaves nothing to trust: full restart.
            let r = if self.restart_pending {
                self.solver.restart(&mut self.problem, y, None)
            } else {
                self.solver.refresh(&mut self.problem, y)
            };
            if let Err(e) = r {
                self.last_successful_time = t;
                return Err(solver_err(e, t));
            }
            self.set_comm(t);
            self.restart_pending = false;
            report.restarted = true;
        }
        // A derivative set at this point applies until the master sets a new one or a value.
        self.der_set = [false; 2];
        // Look ahead unless the inputs changed here: a master that changes them at every
        // point would pay for a retake at every point.
        let lookahead = LOOKAHEAD && !report.restarted;
        // Mesh-event stops pay when the steps are not already ended by communication points
        // closer than the mean spacing of the events (6 per base pitch): there, extra stops
        // would only force new LU decompositions (measured at H = 1e-5 s without look-ahead:
        // 5.5 ms per 10 ms without, 8-11 ms with); without look-ahead they are used from
        // half the spacing up (H = 1e-4 s: see `closed_loop`).
        let rate = self.problem.model.geometry().rb1 * self.solver.y()[idx::OMEGA1];
        let spacing = self.problem.model.geometry().p_bt / (6.0 * rate);
        let use_events = MESH_EVENT_STOPS
            && rate > 0.0
            && (lookahead || t_end - t > closed_loop::EVENT_STOPS_MIN_SPAN * spacing);
        let horizon = if lookahead { NO_STOP } else { t_end };
        // Validity (validity.rs): conditions of the start state, then the end of a
        // look-ahead step of the last interval before the next step replaces its polynomial.
        if self.validity.pending_lift_off || self.validity.pending_reversal {
            self.start_violations(&mut report)?;
        }
        let ts = self.solver.t();
        if ts > self.validity.t_checked && ts <= t_end {
            let y = *self.solver.y();
            self.check_validity(ts, &y, &mut report)?;
        }
        self.solver.reset_step_count();
        let mut steps = 0u64;
        while self.solver.t() < t_end {
            // Bounded work per doStep (stop where it got, a defined state) and progress:
            // every step advances time by more than the resolution of t (radau5.f's rule)
            // or ends on t_end, else "step size too small".
            let t_before = self.solver.t();
            self.check_work(steps, t_end)?;
            steps += 1;
            let (target, at_event) = if lookahead {
                let target = if use_events {
                    self.next_mesh_event(horizon)
                } else {
                    horizon
                };
                (target, target < horizon)
            } else {
                self.closed_loop_stop(t_end, use_events)
            };
            let r = self.solver.step(&mut self.problem, target).and_then(|tn| {
                if use_events && at_event && tn == target {
                    self.f_after_event()?;
                }
                Ok(tn)
            });
            match r {
                Ok(tn) if !validate::advanced(t_before, tn, t_end) => {
                    let e = radau5::Error::StepSizeTooSmall {
                        t: t_before,
                        h: tn - t_before,
                    };
                    return Err(self.stop_at_last_step(solver_err(e, t_before)));
                }
                Ok(tn) if tn <= t_end => {
                    // Cheap test on the stepper's lambda; a change of sign is confirmed with
                    // the consistent lambda (see `output_state`), as the outputs report it.
                    let y = *self.solver.y();
                    self.track_contact(tn, &y, &mut report);
                    self.check_validity(tn, &y, &mut report)?;
                }
                // A look-ahead step: its end belongs to a later interval; the state at
                // t_end is checked below.
                Ok(_) => {}
                Err(e) => {
                    // The stepper keeps its last accepted step; restart from there before
                    // the next step (its history after a failure is not trusted).
                    let ts = self.solver.t();
                    self.set_comm(ts);
                    self.last_successful_time = ts;
                    self.restart_pending = true;
                    return Err(solver_err(e, ts));
                }
            }
        }
        self.set_comm(t_end);
        if self.ahead() {
            let y = self.y_comm;
            self.track_contact(t_end, &y, &mut report);
        }
        if self.validity.t_checked < t_end {
            let y = self.y_comm;
            self.check_validity(t_end, &y, &mut report)?;
        }
        self.last_successful_time = t_end;
        report.stats = self.solver.stats().since(&stats0);
        report.contact_lost = self.contact_lost;
        Ok(report)
    }

    /// Updates `contact_lost` (lambda < 0) at a state on the trajectory and counts a change
    /// in the report. The stepper's lambda decides cheaply; a change is confirmed with the
    /// consistent lambda (see `output_state`), as the outputs report it.
    fn track_contact(&mut self, t: f64, y: &SVector<f64, NY>, report: &mut StepReport) {
        let mut lost = y[idx::LAMBDA] < 0.0;
        if lost != self.contact_lost {
            lost = self.output_state(t, y)[idx::LAMBDA] < 0.0;
        }
        if lost != self.contact_lost {
            if report.contact_changes == 0 {
                report.first_change_time = t;
            }
            report.contact_changes += 1;
            self.contact_lost = lost;
        }
    }

    /// Time of the next mesh event before `t_end` (else `t_end`): an end of a contact line
    /// crossing sigma_A, sigma_C or sigma_E (model.md §3.4, §4). There f has a kink (the
    /// contact length or the sliding direction on a segment changes its law), and a RADAU5
    /// step straddling it is rejected or needs new Jacobians; a step that ends on it is not.
    /// The mesh phase s advances at r_b1 omega1 (the theta, alpha rates of the centre motion
    /// are ~1e-5 of that); predicted from the current state after every step, so the error
    /// does not accumulate. Events closer than [`MESH_EVENT_MERGE`] of a base-pitch passage
    /// are skipped. Spur pairs (jumps, not kinks): the reversal at sigma* instead of
    /// sigma_C, jumps located on the collocation polynomial ([`Simulation::locate_event`])
    /// and landed on from before, [`JUMP_MERGE`] instead (docs/fmu.md "Mesh events").
    /// Measured (default case, rtol 1e-6, 10 ms in one doStep): 291 accepted + 120 rejected
    /// steps, 87 Jacobians, 5.5 ms CPU without; 273 + 16, 30 Jacobians, 3.7 ms with.
    fn next_mesh_event(&self, t_end: f64) -> f64 {
        let t = self.solver.t();
        let jumps = self.events_jump();
        let merge = if jumps { JUMP_MERGE } else { MESH_EVENT_MERGE };
        let Some((gap, rate, p, which)) = self.mesh_event_gap(merge) else {
            return t_end;
        };
        let eps = merge * p;
        let mut te = t + gap / rate;
        // A jump must be landed on from before it, to a small fraction of a step: the
        // linear prediction is off by ~0.2 % of the gap at sigma* (it moves with the
        // velocities), so when the next step can reach the event, locate it on the
        // collocation polynomial of the last step and stop JUMP_MARGIN before it.
        if jumps && te - t < 2.0 * self.solver.h() {
            if let Some(tr) = self.locate_event(which, t, te) {
                te = (tr - JUMP_MARGIN * p / rate).max(t + 0.5 * (tr - t));
            }
        }
        // An event just before t_end would leave a sliver of a step: end at t_end then.
        if te < t_end - eps / rate {
            te
        } else {
            t_end
        }
    }

    /// Spur pairs: f jumps at the mesh events (a whole line enters, leaves or reverses
    /// its sliding at once); helical pairs have kinks there.
    fn events_jump(&self) -> bool {
        self.problem.model.geometry().tan_beta_b == 0.0
    }

    /// The mesh phase s of `y` and the positions of the events of kind `which` (0:
    /// sigma_A, 1: sliding reversal, 2: sigma_E) at both face ends, or None where events
    /// are not used (see [`Simulation::next_mesh_event`]).
    fn event_phases(&self, t: f64, y: &SVector<f64, NY>) -> Option<(f64, [[f64; 2]; 3])> {
        let model = &self.problem.model;
        let g = model.geometry();
        let m = model.mesh(t, y).ok()?;
        // Without friction f has no kinks there (the normal force does not depend on the
        // contact lines); with little friction the kinks are mild and the stops cost more
        // steps than they save (see MESH_EVENT_MIN_MU).
        let usable =
            y[idx::OMEGA1] > 0.0 && m.z_hi > m.z_lo && model.params().mu > MESH_EVENT_MIN_MU;
        if !usable {
            return None;
        }
        let s_ph = g.mesh_phase(&m, y[idx::PHI1], model.params().psi0);
        let u1z = m.c1.z;
        let w = [(m.z_lo - u1z) * g.tan_beta_b, (m.z_hi - u1z) * g.tan_beta_b];
        // The sliding on a line reverses where x(sigma) = x_base + (omega1 + omega2) sigma
        // = 0 (friction.rs): at the pitch point r_b1 tan(alpha) in rigid rotation. For spur
        // pairs, where the whole line reverses at once, the centre velocities and the speed
        // fluctuation move it by ~1e-5 m (~1 us) at the defaults, far more than a landing
        // may miss; for helical pairs (kinks, not jumps) the pitch point is close enough.
        let v = idx::V;
        let (w1, w2) = (y[idx::OMEGA1], y[v + 6]);
        let sigma_rev = if self.events_jump() && w1 + w2 > 0.0 {
            let dv_w = (y[v + 3] - y[v]) * m.cos_psi + (y[v + 4] - y[v + 1]) * m.sin_psi;
            (w2 * m.len_t1t2 - dv_w) / (w1 + w2)
        } else {
            g.rb1 * m.alpha.tan()
        };
        // Laws without a sign jump at the reversal (regularised, EHL): no event there
        // (a NaN phase is never the nearest event).
        let sigma_rev = if model.params().friction_law.sharp_reversal() {
            sigma_rev
        } else {
            f64::NAN
        };
        let sig = [m.sigma_a, sigma_rev, m.sigma_e];
        Some((s_ph, sig.map(|s| [s + w[0], s + w[1]])))
    }

    /// Mesh phase from the current state to the next mesh event at least `skip` base
    /// pitches ahead, the phase rate r_b1 omega1, p_bt, and the kind of that event (see
    /// [`Simulation::event_phases`]); None where events are not used.
    fn mesh_event_gap(&self, skip: f64) -> Option<(f64, f64, f64, usize)> {
        let (t, y) = (self.solver.t(), self.solver.y());
        let (s_ph, ev) = self.event_phases(t, y)?;
        let g = self.problem.model.geometry();
        let (p, rate) = (g.p_bt, g.rb1 * y[idx::OMEGA1]);
        let eps = skip * p;
        let mut best = (f64::INFINITY, 0);
        for (kind, pair) in ev.iter().enumerate() {
            for &e in pair {
                let mut gap = crate::gear::contact_lines::reduce(e - s_ph, p);
                if gap < eps {
                    gap += p;
                }
                if gap < best.0 {
                    best = (gap, kind);
                }
            }
        }
        Some((best.0, rate, p, best.1))
    }

    /// Time of the next event of kind `which` as the root of its signed phase distance
    /// along the collocation polynomial of the last step (extrapolated), by the secant
    /// method from the linear prediction `te`. None if it does not converge to 1e-9 of a
    /// pitch or leaves (t, t + 2 (te - t)) (e.g. right after a restart, when the
    /// polynomial is flat).
    fn locate_event(&self, which: usize, t: f64, te: f64) -> Option<f64> {
        let g = self.problem.model.geometry();
        let p = g.p_bt;
        let dist = |tau: f64| -> Option<f64> {
            let mut y = SVector::<f64, NY>::zeros();
            self.solver.dense_output(tau, &mut y);
            let (s_ph, ev) = self.event_phases(tau, &y)?;
            // Signed, in (-p/2, p/2]; the nearer face end (equal for spur pairs).
            let d = |e: f64| crate::gear::contact_lines::reduce(e - s_ph + 0.5 * p, p) - 0.5 * p;
            let (a, b) = (d(ev[which][0]), d(ev[which][1]));
            Some(if a.abs() <= b.abs() { a } else { b })
        };
        let (mut t0, mut d0) = (t, dist(t)?);
        let (mut t1, mut d1) = (te, dist(te)?);
        for _ in 0..8 {
            if d1.abs() <= 1e-12 * p {
                break;
            }
            let slope = (d1 - d0) / (t1 - t0);
            if slope.is_nan() || slope >= 0.0 {
                return None;
            }
            let t2 = t1 - d1 / slope;
            (t0, d0) = (t1, d1);
            t1 = t2;
            d1 = dist(t1)?;
        }
        (d1.abs() <= 1e-9 * p && t1 > t && t1 < t + 2.0 * (te - t)).then_some(t1)
    }

    /// Spur pairs: after a step that landed on a mesh event (from before it, by
    /// JUMP_MARGIN), f there is still the value from before the jump, and the next step,
    /// whose stages all lie after it, would compare against it in its error estimate and
    /// be rejected again and again. Replace f by its limit from after the event: f at the
    /// same state with phi1 advanced past the event (by at most JUMP_MERGE of a pitch, the
    /// events closer than that being skipped next).
    fn f_after_event(&mut self) -> Result<(), radau5::Error> {
        if !self.events_jump() {
            return Ok(());
        }
        let Some((gap, _, p, _)) = self.mesh_event_gap(0.0) else {
            return Ok(());
        };
        if gap >= JUMP_MERGE * p {
            return Ok(());
        }
        let dphi = (gap + 1e-9 * p) / self.problem.model.geometry().rb1;
        // lambda jumps with the friction too (through B of the hidden constraint, model.md
        // §7), but re-projecting it here measured worse (spur, 0..100 ms: 279 instead of
        // 1005 rejections, yet 5387 instead of 4422 accepted steps and twice the
        // Jacobians): the stepper's own lambda is kept.
        let y = *self.solver.y();
        let mut after = PhaseAhead {
            inner: &mut self.problem,
            dphi,
        };
        self.solver.refresh_f(&mut after, y)
    }

    /// All outputs at the current time (model.md §6), with lambda from the hidden
    /// constraint (see [`Simulation::output_state`]).
    pub fn outputs(&self) -> Outputs {
        let t = self.time();
        // = outputs(t, output_state(t, y)) with one mesh/friction evaluation instead of two.
        self.problem.model.outputs_consistent(t, &self.y_comm)
    }

    /// The state for the outputs: y with lambda replaced by the value the hidden constraint
    /// gives for the differential states (model.md §7, `GearedRotor::consistent_lambda`).
    ///
    /// Why: lambda is an index-2 variable; RADAU5 controls its error only scaled by h, and
    /// the step that lands on a communication point is clipped and may be very short, so the
    /// lambda of the stepper there can be off by ~1e-3 relative (seen at the frictionless
    /// static equilibrium with 10 ms communication steps: spikes of +-8.5e-4 while the
    /// consistent value is within 1e-8). The consistent value depends only on q, v and the
    /// filter state, which are accurate to the tolerance. Falls back to the stepper's
    /// lambda where the model cannot decide (friction-induced ambiguity).
    pub fn output_state(&self, t: f64, y: &SVector<f64, NY>) -> SVector<f64, NY> {
        let mut z = *y;
        if let Ok(l) = self.problem.model.consistent_lambda(t, y) {
            if l.is_finite() {
                z[idx::LAMBDA] = l;
            }
        }
        z
    }

    /// Outputs at `time() - delta` and `time() + delta` on the collocation polynomial of the
    /// last step, and `delta`, for central-difference output derivatives (order 1). Before
    /// the first step, and when an input or a tunable changed at the FMU time (the
    /// polynomial is that of the old f: the derivative from after the change is wanted), the
    /// state is extrapolated with y' from M y' = f (lambda from the hidden constraint, held).
    pub fn outputs_for_derivative(&mut self) -> (Outputs, Outputs, f64) {
        let t = self.time();
        let tp = self.solver.t_prev();
        let mut ym = SVector::<f64, NY>::zeros();
        let mut yp = SVector::<f64, NY>::zeros();
        let delta;
        if tp < t && self.solver.stats().naccpt > 0 && !self.change_pending() {
            delta = DERIVATIVE_DELTA * (self.solver.t() - tp);
            self.solver.dense_output(t - delta, &mut ym);
            self.solver.dense_output(t + delta, &mut yp);
        } else {
            delta = 1e-9;
            // lambda consistent with the current inputs and tunables: it enters M y' = f.
            let y = self.output_state(t, &self.y_comm);
            let mut f = SVector::<f64, NY>::zeros();
            let m = self.problem.model.mass();
            let ydot = match self.problem.model.rhs(t, &y, &mut f) {
                Ok(()) => SVector::<f64, NY>::from_fn(|i, _| {
                    if m[(i, i)] != 0.0 {
                        f[i] / m[(i, i)]
                    } else {
                        0.0
                    }
                }),
                Err(_) => SVector::<f64, NY>::zeros(),
            };
            ym = y - ydot * delta;
            yp = y + ydot * delta;
        }
        let ym = self.output_state(t - delta, &ym);
        let yp = self.output_state(t + delta, &yp);
        let om = self.problem.model.outputs(t - delta, &ym);
        let op = self.problem.model.outputs(t + delta, &yp);
        (om, op, delta)
    }

    /// A complete snapshot (plain data; restoring it continues bit-identically).
    pub fn state(&self) -> SimState {
        SimState {
            solver: self.solver.snapshot(),
            t_comm: self.t_comm,
            model: self.problem.model.clone(),
            settings: self.settings,
            init: self.init,
            inputs: *self.problem.model.inputs(),
            inputs_ref: self.inputs_ref,
            der_set: self.der_set,
            restart_pending: self.restart_pending,
            contact_lost: self.contact_lost,
            last_successful_time: self.last_successful_time,
            validity: self.validity,
            h_fixed: self.h_fixed,
        }
    }

    /// Restores a snapshot in place when it belongs to the same parameter set and settings,
    /// else rebuilds the simulation from it.
    ///
    /// # Errors
    /// Rebuilding failed (cannot happen for a state this build produced).
    pub fn restore(&mut self, s: &SimState) -> Result<(), SimError> {
        if s.settings == self.settings && s.init == self.init {
            self.problem.model = s.model.clone();
            self.solver.restore(&s.solver);
            self.set_comm(s.t_comm);
            self.der_set = s.der_set;
            self.inputs_ref = s.inputs_ref;
            self.restart_pending = s.restart_pending;
            self.contact_lost = s.contact_lost;
            self.last_successful_time = s.last_successful_time;
            self.validity = s.validity;
            self.h_fixed = s.h_fixed;
        } else {
            *self = Simulation::from_state(s)?;
        }
        Ok(())
    }

    /// Builds a simulation from a snapshot.
    ///
    /// # Errors
    /// Invalid settings or a stepper that cannot be constructed.
    pub fn from_state(s: &SimState) -> Result<Self, SimError> {
        s.settings.validate()?;
        let mut problem = RotorProblem {
            model: s.model.clone(),
        };
        let mut solver = Radau5::new(
            &mut problem,
            s.settings.options(),
            s.init.t_start,
            s.init.y0,
        )
        .map_err(|e| solver_err(e, s.init.t_start))?;
        solver.restore(&s.solver);
        let mut sim = Simulation {
            problem,
            solver,
            t_comm: s.t_comm,
            y_comm: SVector::zeros(),
            settings: s.settings,
            init: s.init,
            der_set: s.der_set,
            inputs_ref: s.inputs_ref,
            restart_pending: s.restart_pending,
            contact_lost: s.contact_lost,
            last_successful_time: s.last_successful_time,
            validity: s.validity,
            init_report: InitReport::default(),
            max_internal_steps: DEFAULT_MAX_INTERNAL_STEPS,
            h_fixed: s.h_fixed,
        };
        sim.set_comm(s.t_comm);
        Ok(sim)
    }
}

/// Inputs rebased to time t: value(t) = value + der (t - t_ref).
fn rebase(i: &Inputs, t: f64) -> Inputs {
    Inputs {
        omega1: i.omega1 + i.omega1_der * (t - i.t_ref),
        omega1_der: i.omega1_der,
        t_load: i.t_load + i.t_load_der * (t - i.t_ref),
        t_load_der: i.t_load_der,
        t_ref: t,
    }
}

/// Whether two input records (rebased to the same time) describe the same input function,
/// up to round-off (1e-12 relative): a master that re-sends u(t_n) and u'(t_n) of a ramp
/// computes the value in its own arithmetic, and a restart for an ulp is wasted work.
fn same_function(a: &Inputs, b: &Inputs) -> bool {
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * x.abs().max(y.abs());
    close(a.omega1, b.omega1)
        && close(a.omega1_der, b.omega1_der)
        && close(a.t_load, b.t_load)
        && close(a.t_load_der, b.t_load_der)
}

/// Exact equality of the input function (decides whether the model's record is updated).
fn identical_function(a: &Inputs, b: &Inputs) -> bool {
    a.omega1 == b.omega1
        && a.omega1_der == b.omega1_der
        && a.t_load == b.t_load
        && a.t_load_der == b.t_load_der
}

fn write_params(w: &mut Writer, p: &Params) {
    let g = &p.gear;
    w.i32(g.z1);
    w.i32(g.z2);
    for x in [g.m_n, g.alpha_n, g.beta, g.b, g.x1, g.x2, g.ha_coef, g.a_w] {
        w.f64(x);
    }
    for r in [&p.rotor1, &p.rotor2] {
        w.f64(r.m);
        w.f64(r.j);
        for x in r.k.iter().chain(r.d.iter()) {
            w.f64(*x);
        }
    }
    w.f64(p.d_phi);
    w.f64(p.mu);
    w.f64(p.psi0);
    w.i32(p.friction_law.code());
    w.f64(p.omega1_filter_hz);
    let fp = &p.friction;
    for x in [
        fp.v_reg, fp.eta_oil, fp.ra, fp.x_l, fp.e1, fp.nu1, fp.e2, fp.nu2,
    ] {
        w.f64(x);
    }
}

fn read_params(r: &mut Reader) -> Result<Params, DecodeError> {
    let z1 = r.i32("z1")?;
    let z2 = r.i32("z2")?;
    let mut g = [0.0; 8];
    for x in g.iter_mut() {
        *x = r.finite("gear data")?;
    }
    let gear = GearData {
        z1,
        z2,
        m_n: g[0],
        alpha_n: g[1],
        beta: g[2],
        b: g[3],
        x1: g[4],
        x2: g[5],
        ha_coef: g[6],
        a_w: g[7],
    };
    let mut rot = [RotorData {
        m: 0.0,
        j: 0.0,
        k: [0.0; 3],
        d: [0.0; 3],
    }; 2];
    for rd in rot.iter_mut() {
        rd.m = r.finite("rotor mass")?;
        rd.j = r.finite("rotor inertia")?;
        for k in rd.k.iter_mut() {
            *k = r.finite("bearing stiffness")?;
        }
        for d in rd.d.iter_mut() {
            *d = r.finite("bearing damping")?;
        }
    }
    let d_phi = r.finite("d_phi")?;
    let mu = r.finite("mu")?;
    let psi0 = r.finite("psi0")?;
    let code = r.i32("friction_law")?;
    let Some(friction_law) = FrictionLaw::from_code(code) else {
        return Err(DecodeError {
            message: format!("unknown friction law {code}"),
        });
    };
    let omega1_filter_hz = r.finite("omega1_filter_frequency")?;
    let mut fp = [0.0; 8];
    for x in fp.iter_mut() {
        *x = r.finite("friction law parameters")?;
    }
    let friction = FrictionParams {
        v_reg: fp[0],
        eta_oil: fp[1],
        ra: fp[2],
        x_l: fp[3],
        e1: fp[4],
        nu1: fp[5],
        e2: fp[6],
        nu2: fp[7],
    };
    Ok(Params {
        gear,
        rotor1: rot[0],
        rotor2: rot[1],
        d_phi,
        mu,
        psi0,
        friction_law,
        omega1_filter_hz,
        friction,
    })
}

fn write_inputs(w: &mut Writer, i: &Inputs) {
    for x in [i.omega1, i.omega1_der, i.t_load, i.t_load_der, i.t_ref] {
        w.f64(x);
    }
}

fn read_inputs(r: &mut Reader) -> Result<Inputs, DecodeError> {
    Ok(Inputs {
        omega1: r.finite("omega1")?,
        omega1_der: r.finite("omega1 derivative")?,
        t_load: r.finite("T_load")?,
        t_load_der: r.finite("T_load derivative")?,
        t_ref: r.finite("input reference time")?,
    })
}

impl SimState {
    /// Time of this snapshot.
    pub fn last_successful_time(&self) -> f64 {
        self.last_successful_time
    }

    /// Appends the payload (not sealed; the FMU layer adds magic, version, GUID, checksum).
    pub fn write(&self, w: &mut Writer) {
        write_params(w, &self.init.params);
        write_inputs(w, &self.init.inputs);
        w.f64(self.init.t_start);
        w.f64(self.settings.rtol);
        w.f64(self.settings.h_max);
        let p = self.model.params();
        w.f64(p.mu);
        w.f64(p.d_phi);
        write_inputs(w, &self.inputs);
        write_inputs(w, &self.inputs_ref);
        w.bool(self.der_set[0]);
        w.bool(self.der_set[1]);
        w.bool(self.restart_pending);
        w.bool(self.contact_lost);
        w.f64(self.last_successful_time);
        w.f64(self.t_comm);
        w.f64(self.h_fixed);
        w.bytes(&self.solver.to_bytes());
        w.i32(self.init.initialization.code());
        if self.init.initialization != Initialization::Rest {
            for x in self.init.y0.iter() {
                w.f64(*x);
            }
        }
        w.u32(self.validity.bits());
        w.f64(self.validity.t_checked);
    }

    /// Reads what [`SimState::write`] wrote; the model is rebuilt by replaying its
    /// initialisation, then the tunables and inputs of the snapshot are applied.
    ///
    /// # Errors
    /// Truncated or inconsistent data, or parameters the model rejects.
    pub fn read(r: &mut Reader) -> Result<SimState, SimError> {
        let params = read_params(r)?;
        let inputs0 = read_inputs(r)?;
        let t_start = r.finite("start time")?;
        let settings = SolverSettings {
            rtol: r.finite("rtol")?,
            h_max: r.finite("h_max")?,
        };
        settings.validate()?;
        let mu = r.finite("mu")?;
        let d_phi = r.finite("d_phi")?;
        let inputs = read_inputs(r)?;
        let inputs_ref = read_inputs(r)?;
        let der_set = [r.bool("derivative flag")?, r.bool("derivative flag")?];
        let restart_pending = r.bool("restart flag")?;
        let contact_lost = r.bool("contact flag")?;
        let last_successful_time = r.finite("last successful time")?;
        let t_comm = r.finite("FMU time")?;
        let h_fixed = r.finite("h_fixed")?;
        realtime::check_h_fixed(h_fixed)?;
        let solver =
            Snapshot::<NY>::from_bytes(r.bytes("solver snapshot")?).map_err(|e| DecodeError {
                message: format!("RADAU5 snapshot: {e:?}"),
            })?;
        // The FMU time lies on the stepper's last step (look-ahead) or at its end.
        if !(t_comm <= solver.t() && (t_comm > solver.t_prev() || t_comm == solver.t())) {
            return Err(DecodeError {
                message: format!(
                    "FMU time {} outside the solver's last step ending at {}",
                    Short(t_comm),
                    Short(solver.t())
                ),
            }
            .into());
        }
        let initialization =
            Initialization::from_code(r.i32("initialization")?).ok_or_else(|| DecodeError {
                message: "unknown initialization".into(),
            })?;
        let mut init = InitRecord {
            params,
            inputs: inputs0,
            t_start,
            y0: SVector::zeros(),
            initialization,
        };
        let (mut problem, mut y0) = Simulation::replay(&init)?;
        if initialization != Initialization::Rest {
            for x in y0.iter_mut() {
                *x = r.finite("initial state")?;
            }
        }
        init.y0 = y0;
        let bits = r.u32("validity flags")?;
        let validity = Monitor::from_bits(bits, r.finite("validity check time")?);
        problem.model.set_mu(mu)?;
        problem.model.set_d_phi(d_phi)?;
        problem.model.set_inputs(inputs);
        Ok(SimState {
            solver,
            t_comm,
            model: problem.model,
            settings,
            init,
            inputs,
            inputs_ref,
            der_set,
            restart_pending,
            contact_lost,
            last_successful_time,
            validity,
            h_fixed,
        })
    }
}
