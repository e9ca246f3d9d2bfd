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
//!   a stepper stopped at every point where the inputs changed (measured at the default
//!   case, rtol 1e-6, steady state, H = 1e-5 s: without look-ahead 5.1 ms CPU and ~1020
//!   internal steps per simulated 10 ms; with it see docs/development.md "Benchmarks");
//! - held inputs with optional first derivatives (FMI `canInterpolateInputs`); only when the
//!   input function really changes is f re-evaluated ([`Radau5::refresh`], J and LU kept:
//!   the inputs enter f additively); new tunables restart the stepper;
//! - tunable parameters (mu, d_phi), per-component absolute tolerances from physical scales
//!   (`GearedRotor::scales`), output derivatives from the dense output;
//! - a plain-data snapshot ([`SimState`]) and its versioned serialisation ([`crate::bytes`]);
//! - on a solver failure the state stays at the last accepted step (the "last successful
//!   time" of FMI's `fmi2Discard`);
//! - a real-time mode with equal, bounded work per doStep ([`realtime`], `h_fixed > 0`).

mod closed_loop;
pub mod contact_events;
mod creep;
mod error;
mod fmu_state;
pub mod init;
mod inputs;
mod mesh_events;
mod outputs;
pub mod realtime;
mod settings;
mod stepping;
mod stick;
mod validate;
pub mod validity;

pub use creep::{CreepChange, MAX_CREEP_REPORTED};
pub use error::SimError;
pub use fmu_state::SimState;
pub use inputs::Input;
pub use settings::{SolverSettings, MAX_STEPS_PER_INTERVAL, PHI1_RTOL_FACTOR, RTOL_MAX, RTOL_MIN};
pub use stepping::{comm_tolerance, StepReport};
pub use stick::{StickChange, MAX_STICK_REPORTED};
pub use validate::{DEFAULT_MAX_INTERNAL_STEPS, STEP_RESOLUTION};

use crate::bytes::DecodeError;
use crate::radau5::{Radau5, Retake, Statistics};
use crate::rotor::{idx, GearedRotor, Inputs, Params, RotorProblem, NY};
use error::solver_err;
use fmu_state::InitRecord;
pub use init::{InitError, InitReport, Initialization};
use inputs::{rebase, same_function};
use nalgebra::SVector;
use validity::Monitor;
pub use validity::{OnViolation, Violation, ViolationKind};

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
    /// Contact onsets of the elastic flanks so far (`contact_events`; output `impacts`).
    impacts: u64,
    /// The contact event functions at the end of the last step looked at (t, y, values):
    /// the next step starts there, so its start values need no second evaluation
    /// (`contact_events`). A pure cache, keyed by the exact state.
    event_values: std::cell::Cell<Option<contact_events::EventValues>>,
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
        // A start near standstill (`creep`), or on the pitch line of a spur contact line
        // (`stick::start_mode`).
        y0 = creep::start_creep(&mut problem.model, t_start, y0)?;
        y0 = stick::start_mode(&mut problem.model, t_start, y0)?;
        init.y0 = y0;
        let options =
            settings.options_for(problem.model.scales(), problem.model.params().tooth_contact);
        let solver =
            Radau5::new(&mut problem, options, t_start, y0).map_err(|e| solver_err(e, t_start))?;
        // The start state's own force decides (it is consistent: model.md §7).
        let contact_lost = problem.model.contact().stepper_lift_off(&y0);
        let margin = problem.model.contact().overload_margin(t_start, &y0);
        let overload = margin.is_nan() || margin < 0.0;
        let validity = Monitor::new(t_start, contact_lost, y0[idx::OMEGA1], overload);
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
            impacts: 0,
            event_values: std::cell::Cell::new(None),
        })
    }

    /// Contact onsets of the elastic flanks (drive or coast) since the start, each a
    /// located state event (`contact_events`); 0 for rigid teeth.
    pub fn impacts(&self) -> u64 {
        self.impacts
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

    /// The stepper's state at t (its y at its own time, else its dense output).
    fn state_at(&self, t: f64, y: &mut SVector<f64, NY>) {
        if t == self.solver.t() {
            y.copy_from(self.solver.y());
        } else {
            self.solver.dense_output(t, y);
        }
    }

    /// Sets the FMU time and the state there from the stepper.
    fn set_comm(&mut self, t: f64) {
        self.t_comm = t;
        let mut y = SVector::<f64, NY>::zeros();
        self.state_at(t, &mut y);
        self.y_comm = y;
    }

    /// Before f changes at the FMU time: a look-ahead step is retaken so that the stepper
    /// ends exactly on the FMU time with the function it was taken with. That is the input
    /// function of `inputs_ref` (the master may have set new inputs since, which apply from
    /// the FMU time on), with the tunables as they are (a tunable setter calls this before
    /// it changes one).
    fn sync(&mut self) -> Result<(), SimError> {
        if !self.ahead() {
            return Ok(());
        }
        let t = self.t_comm;
        let current = *self.problem.model.inputs();
        self.problem.model.set_inputs(self.inputs_ref);
        let retaken = self.solver.retake(&mut self.problem, t);
        self.problem.model.set_inputs(current);
        match retaken {
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

    /// Where a doStep whose right-hand side changed at the FMU time t restarts from (both
    /// modes): the stepper's state there, a look-ahead step retaken to end on t with the
    /// old function (`sync`), made consistent by the contact for the new inputs and
    /// tunables (rigid teeth: lambda from the hidden constraint, as lambda is algebraic and
    /// a new d_phi, mu or T_load moves it at once; model.md §7; `Contact::consistent_state`).
    ///
    /// At the start, before the first step, the start's friction mode (`stick::start_mode`)
    /// is decided again with the new inputs, and the adaptive stepper restarts if it changed
    /// (built with T_load = 50 and set to -50 N m before the first doStep, an elastic spur
    /// pair at 100 rpm kept the release sense of +50: T1 off by 0.76 N m over 20 ms at rtol
    /// 1e-6).
    fn restart_state(&mut self, t: f64) -> Result<SVector<f64, NY>, SimError> {
        self.sync()?;
        let y = *self.solver.y();
        let m = &mut self.problem.model;
        let at_start = t == self.init.t_start && self.solver.stats().naccpt == 0;
        let before = (
            m.released(),
            m.stick(),
            m.stick_flank_is_coast(),
            m.creeps(),
        );
        if at_start {
            m.set_stick(false, 0.0);
            m.clear_release();
            m.set_creep(false);
        }
        let y = m
            .contact()
            .consistent_state(t, &y)
            .map_err(SimError::Model)?;
        if !at_start {
            return Ok(y);
        }
        let y = creep::start_creep(m, t, y)?;
        let y = stick::start_mode(m, t, y)?;
        if (
            m.released(),
            m.stick(),
            m.stick_flank_is_coast(),
            m.creeps(),
        ) != before
        {
            self.restart_pending = true;
        }
        Ok(y)
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

    /// Test switch: forward differences of f for every Jacobian
    /// ([`GearedRotor::set_difference_jacobian`]).
    #[doc(hidden)]
    pub fn set_difference_jacobian(&mut self, on: bool) {
        self.problem.model.set_difference_jacobian(on);
    }

    /// Test switch: every renewal of J a full one ([`GearedRotor::set_whole_jacobian`]).
    #[doc(hidden)]
    pub fn set_whole_jacobian(&mut self, on: bool) {
        self.problem.model.set_whole_jacobian(on);
    }

    /// RADAU5 counters since the start.
    pub fn stats(&self) -> &Statistics {
        self.solver.stats()
    }

    /// The state vector at the FMU time.
    pub fn y(&self) -> &SVector<f64, NY> {
        &self.y_comm
    }

    /// Whether the normal force is negative (tooth lift-off, rigid teeth only:
    /// `Contact::lifted_off`) at the current time.
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

    /// Records the input function the master describes at the FMU time. Nothing is decided
    /// here: the next doStep compares it with the function the stepper runs with
    /// (`change_pending`) and retakes a look-ahead step only then, so the order in which a
    /// master sets a value and its derivative (FMPy: value first) does not matter, nor do
    /// intermediate records that a later call at the same point undoes.
    /// The record is always the one rebased to the FMU time, whatever was set before at the
    /// same point, so that equal functions give equal bits in f.
    fn apply_inputs(&mut self, new: Inputs) {
        self.problem.model.set_inputs(new);
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
        self.apply_inputs(i);
        Ok(())
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
        self.apply_inputs(i);
        Ok(())
    }

    /// Changes the friction coefficient (tunable) at the current communication point.
    ///
    /// # Errors
    /// The model's bound on mu.
    pub fn set_mu(&mut self, mu: f64) -> Result<(), SimError> {
        if mu != self.problem.model.params().mu {
            crate::rotor::params::check_mu(mu)?;
            if self.h_fixed > 0.0 {
                // The real-time mode refuses spur pairs with friction (`set_h_fixed`).
                let mut m = self.problem.model.clone();
                m.set_mu(mu)?;
                realtime::check_pair(&m, self.h_fixed, "mu", mu)?;
            }
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
}
