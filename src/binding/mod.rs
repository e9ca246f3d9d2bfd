//! The geared rotor as an FMI model: the one place that knows what the FMU's variables
//! mean (value store, parameters -> [`Params`](crate::rotor::Params), outputs, calculated parameters, inputs,
//! tunables), builds and steps the [`Simulation`], writes the model's log messages and its
//! part of an FMU state. It implements the contract [`Model`] of the model-agnostic FMI
//! layer (`crate::fmi2`).

mod error;
mod state;
pub mod values;

pub use error::BindingError;
pub use state::BindingState;

use crate::fmi2::bounds;
use crate::fmi2::logging::{Category, Logger};
use crate::fmi2::model::{Experiment, Model, Phase, Status, StepEnd};
use crate::fmi2::variables::{self, Causality, Var, VarType, Variable, N_VARIABLES};
use crate::fmt_num::Short;
use crate::sim::contact_events::Flank;
use crate::sim::{
    self, Initialization, Input, OnViolation, SimError, Simulation, RTOL_MAX, RTOL_MIN,
};
use values::{input_of, Values};

/// The geared-rotor FMU model: parameter and input values and, once initialised, the
/// simulation.
pub struct GearedRotorFmu {
    values: Values,
    /// First derivatives of the inputs (omega1, T_load) set by the master.
    input_der: [f64; 2],
    sim: Option<Simulation>,
    /// The simulation is stale w.r.t. `values` (initialisation mode only).
    dirty: bool,
    /// The outputs at the current time, computed once per time point into one value per
    /// variable (table order), so that a GetReal of an output is an index: mapping the
    /// `Outputs` struct per value reference (a match) cost ~6 ns each, 6-7 % of a
    /// closed-loop doStep at H = 1e-5 s that reads every output (perf). Valid while
    /// `outputs_valid`.
    output_values: [f64; N_VARIABLES],
    outputs_valid: bool,
}

fn sim_err(e: SimError) -> BindingError {
    BindingError::Sim(e)
}

/// `what` (with its verb, `is` or `are`) asked for before the simulation exists.
#[cold]
fn not_initialised(what: &str, verb: &str) -> BindingError {
    BindingError::NotAvailable(format!(
        "{what} {verb} not available: the model was not initialised"
    ))
}

impl GearedRotorFmu {
    /// The simulation (after initialisation).
    pub fn simulation(&self) -> Option<&Simulation> {
        self.sim.as_ref()
    }

    fn v(&self, var: Var) -> f64 {
        self.values[var as usize]
    }

    /// Builds the simulation from the store if it is stale (initialisation mode).
    fn ensure_sim(&mut self, exp: &Experiment) -> Result<(), BindingError> {
        if self.sim.is_some() && !self.dirty {
            return Ok(());
        }
        for name in values::CHECKED_AT_INIT {
            if let Some(var) = variables::by_name(name) {
                bounds::check(var, self.values[var.var as usize])
                    .map_err(BindingError::OutOfBounds)?;
            }
        }
        let params = values::params(&self.values).map_err(|e| sim_err(SimError::Param(e)))?;
        let (settings, _) = values::settings(&self.values, exp);
        let initialization =
            values::initialization(&self.values).map_err(|e| sim_err(SimError::Param(e)))?;
        let mut sim = Simulation::with_initialization(
            params,
            settings,
            exp.start,
            self.v(Var::omega1),
            self.v(Var::T_load),
            initialization,
        )?;
        sim.set_h_fixed(self.v(Var::h_fixed))?;
        if self.input_der[0] != 0.0 {
            sim.set_input_derivative(Input::Omega1, self.input_der[0])?;
        }
        if self.input_der[1] != 0.0 {
            sim.set_input_derivative(Input::TLoad, self.input_der[1])?;
        }
        self.sim = Some(sim);
        self.dirty = false;
        self.outputs_valid = false;
        Ok(())
    }

    /// [`Model::get`] for every variable (the cached outputs included).
    #[inline(never)]
    fn get_general(
        &mut self,
        var: &'static Variable,
        phase: Phase,
        exp: &Experiment,
    ) -> Result<f64, BindingError> {
        match var.causality {
            Causality::Parameter | Causality::Input | Causality::Local | Causality::Independent => {
                Ok(self.values[var.var as usize])
            }
            Causality::CalculatedParameter => {
                // From the parameters alone (the pair geometry): reading one must not build
                // the initial state (a periodic start integrates mesh periods and can fail).
                let geometry = match &self.sim {
                    Some(sim) if !self.dirty => *sim.model().geometry(),
                    _ => values::params(&self.values)
                        .and_then(|p| p.validate())
                        .map_err(|e| sim_err(SimError::Param(e)))?,
                };
                values::calculated_value(&geometry, var.var)
                    .ok_or_else(|| BindingError::NotAvailable(format!("{} has no value", var.name)))
            }
            Causality::Output => self.output(var, phase, exp),
        }
    }

    /// The value of output `var` at the current time; all outputs are computed once per
    /// time point.
    fn output(
        &mut self,
        var: &'static Variable,
        phase: Phase,
        exp: &Experiment,
    ) -> Result<f64, BindingError> {
        if phase == Phase::InitializationMode {
            self.ensure_sim(exp)?;
        }
        if !self.outputs_valid {
            let sim = self
                .sim
                .as_ref()
                .ok_or_else(|| not_initialised("outputs", "are"))?;
            values::output_values(&sim.outputs(), &mut self.output_values);
            self.outputs_valid = true;
        }
        Ok(self.output_values[var.var as usize])
    }

    /// doStep from `ccp` over `h`; with `until_event` (FMI 3.0 early return allowed) and
    /// `on_lift_off = warn`, it ends at the located start of an episode outside the validity.
    fn step(
        &mut self,
        func: &'static str,
        ccp: f64,
        h: f64,
        log: &Logger,
        until_event: bool,
    ) -> Result<StepEnd, BindingError> {
        let policy = values::on_violation(&self.values).unwrap_or_default();
        let early = until_event && policy == OnViolation::Warn;
        let max_steps = self.v(Var::max_internal_steps) as u64;
        let sim = self
            .sim
            .as_mut()
            .ok_or_else(|| BindingError::NotAvailable("no simulation".into()))?;
        let t0 = sim.time();
        // Early return: the simulation stops at the located instant as for discard.
        sim.set_on_violation(if early { OnViolation::Discard } else { policy });
        sim.set_max_internal_steps(max_steps);
        let mut r = sim.do_step(ccp, h);
        // The FMU's own policy again (it is part of an FMU state).
        sim.set_on_violation(policy);
        self.outputs_valid = false;
        // An episode that holds at the start of the step (the start state, or at once after
        // an input change at the point) is no early return (the step would not advance):
        // it is reported as with on_lift_off = warn, and the step goes on from the point.
        let mut at_start = None;
        if let Err(SimError::Validity(v)) = &r {
            if early && v.t <= ccp {
                at_start = Some(*v);
                r = sim.do_step(ccp, h);
            }
        }
        let report = match r {
            Err(SimError::Validity(v)) if early => {
                log.log(
                    Status::Warning,
                    Category::Warning,
                    &format!(
                        "{func}: {v}; returning early at t = {} s (earlyReturn, the step was to end at {} s)",
                        Short(v.t),
                        Short(ccp + h)
                    ),
                );
                return Ok(StepEnd {
                    status: Status::Warning,
                    early_return: Some(v.t),
                });
            }
            r => r?,
        };
        let mut status = Status::OK;
        for v in at_start.iter().chain(report.violations.iter().flatten()) {
            log.log(Status::Warning, Category::Warning, &format!("{func}: {v}"));
            status = Status::Warning;
        }
        if report.violations_dropped > 0 {
            log.log(
                Status::Warning,
                Category::Warning,
                &format!(
                    "{func}: {} further episodes outside the model's validity in [{t0}, {}] s",
                    report.violations_dropped,
                    ccp + h
                ),
            );
        }
        if report.contact_changes > 0 && log.enabled(Category::Events) {
            let what = if report.contact_lost {
                "lifted off (lambda < 0)"
            } else {
                "back in contact (lambda >= 0)"
            };
            log.log(
                Status::OK,
                Category::Events,
                &format!(
                    "contact_lost changed {} time(s) in [{}, {}] s, first at t = {:.12} s (located); at the end the teeth are {what}",
                    report.contact_changes,
                    Short(t0),
                    Short(ccp + h),
                    report.first_change_time
                ),
            );
        }
        if log.enabled(Category::Events) {
            for c in report.stick_changes.iter().flatten() {
                let what = if c.stick {
                    "a contact line sticks at the pitch line (its sliding stopped; the friction force that holds it is within mu times its share of Fn)"
                } else {
                    "the stuck contact line slides again (the force needed to hold it reached mu times its share of Fn)"
                };
                log.log(
                    Status::OK,
                    Category::Events,
                    &format!("t = {:.12} s (located): {what}", c.t),
                );
            }
            for c in report.contact_events.iter().flatten() {
                let flanks = match c.flank {
                    Flank::Drive => "drive",
                    Flank::Coast => "coast",
                };
                let what = if c.onset {
                    "touch (an impact; the impacts output counts it)"
                } else {
                    "no longer push (their force fell to 0; they part)"
                };
                log.log(
                    Status::OK,
                    Category::Events,
                    &format!("t = {:.12} s (located): the {flanks} flanks {what}", c.t),
                );
            }
            if report.contact_events_dropped > 0 {
                log.log(
                    Status::OK,
                    Category::Events,
                    &format!(
                        "{} further contact onsets/separations in [{}, {}] s",
                        report.contact_events_dropped,
                        Short(t0),
                        Short(ccp + h)
                    ),
                );
            }
            for c in report.creep_changes.iter().flatten() {
                let what = if c.creep {
                    "the pair rolls too slowly for the sharp sliding direction of friction laws 1 and 3: they creep like law 2 with v_reg = CREEP_SPEED = 1e-2 m/s until it rolls faster than that across a base pitch (docs/model.md 4.2)"
                } else {
                    "the pair rolls fast enough again: friction laws 1 and 3 take their sharp sliding direction again"
                };
                log.log(
                    Status::OK,
                    Category::Events,
                    &format!(
                        "t = {:.12} s: rolling speed {:.4e} m/s across a base pitch: {what}",
                        c.t, c.rolling
                    ),
                );
            }
            if report.creep_changes_dropped > 0 {
                log.log(
                    Status::OK,
                    Category::Events,
                    &format!(
                        "{} further creep switches in [{}, {}] s",
                        report.creep_changes_dropped,
                        Short(t0),
                        Short(ccp + h)
                    ),
                );
            }
            if report.stick_changes_dropped > 0 {
                log.log(
                    Status::OK,
                    Category::Events,
                    &format!(
                        "{} further stick/slip changes in [{}, {}] s",
                        report.stick_changes_dropped,
                        Short(t0),
                        Short(ccp + h)
                    ),
                );
            }
        }
        if log.enabled(Category::Solver) {
            log.log(
                Status::OK,
                Category::Solver,
                &format!(
                    "doStep [{}, {}] s{}: {}",
                    Short(t0),
                    Short(ccp + h),
                    if report.restarted { " (restart)" } else { "" },
                    report.stats
                ),
            );
        }
        Ok(StepEnd {
            status,
            early_return: None,
        })
    }

    fn log_exit_initialization(&self, func: &'static str, exp: &Experiment, log: &Logger) {
        if let (Ok(init), Some(sim)) = (values::initialization(&self.values), self.sim.as_ref()) {
            let r = sim.init_report();
            if init == Initialization::Periodic && log.enabled(Category::Solver) {
                log.log(
                    Status::OK,
                    Category::Solver,
                    &format!(
                        "initialization = periodic: orbit by chord shooting from the static equilibrium, \
                         {} iterations, scaled residual {:.2e}, largest Floquet multiplier {:.4}, \
                         {} mesh periods integrated ({} RADAU5 steps at rtol {:e})",
                        r.iterations, r.residual, r.floquet_max_abs, r.periods_integrated, r.steps, r.rtol
                    ),
                );
            }
        }
        if let Some(sim) = self.sim.as_ref() {
            for w in values::init_warnings(sim.model(), sim.time()) {
                log.log(Status::Warning, Category::Warning, &format!("{func}: {w}"));
            }
        }
        let (s, source) = values::settings(&self.values, exp);
        if let (true, Some(sim)) = (log.enabled(Category::Solver), self.sim.as_ref()) {
            log.log(
                Status::OK,
                Category::Solver,
                &format!(
                    "RADAU5: rtol = {:e} (from {source}), atol_i = rtol * scale_i with scales {:?}, h_max = {:e} s, start time {} s",
                    s.rtol,
                    sim.model().scales(),
                    s.h_max,
                    Short(exp.start)
                ),
            );
            let h_fixed = self.v(Var::h_fixed);
            if h_fixed > 0.0 {
                log.log(
                    Status::OK,
                    Category::Solver,
                    &format!(
                        "real-time mode: h_fixed = {h_fixed:e} s: per doStep of H, ceil(H/h_fixed) equal steps of {} Newton iterations, one Jacobian and LU pair (per doStep, or per 1e-4 s on a fixed time grid when H < 1e-4 s), no error control",
                        sim::realtime::NEWTON_ITERATIONS
                    ),
                );
            }
        }
    }
}

impl Model for GearedRotorFmu {
    type Error = BindingError;
    type State = BindingState;
    const TOLERANCE_RANGE: (f64, f64) = (RTOL_MIN, RTOL_MAX);
    const TOLERANCE_NAME: &'static str = "rtol";

    fn instantiate() -> Self {
        GearedRotorFmu {
            values: values::start_values(),
            input_der: [0.0; 2],
            sim: None,
            dirty: true,
            output_values: [f64::NAN; N_VARIABLES],
            outputs_valid: false,
        }
    }

    fn invalidate(&mut self) {
        self.dirty = true;
    }

    fn exit_initialization(
        &mut self,
        func: &'static str,
        exp: &Experiment,
        log: &Logger,
    ) -> Result<(), BindingError> {
        values::on_violation(&self.values).map_err(|e| sim_err(SimError::Param(e)))?;
        self.ensure_sim(exp)?;
        self.log_exit_initialization(func, exp, log);
        Ok(())
    }

    fn terminate(&self, log: &Logger) {
        if let Some(sim) = &self.sim {
            if log.enabled(Category::Solver) {
                log.log(
                    Status::OK,
                    Category::Solver,
                    &format!(
                        "RADAU5 totals at t = {}: {}",
                        Short(sim.time()),
                        sim.stats()
                    ),
                );
            }
        }
    }

    #[inline]
    fn get(
        &mut self,
        var: &'static Variable,
        phase: Phase,
        exp: &Experiment,
    ) -> Result<f64, BindingError> {
        // An output of a point whose outputs are cached: an index (a master reads every
        // output at every point; the general path is not inlined).
        if var.causality == Causality::Output
            && self.outputs_valid
            && phase != Phase::InitializationMode
        {
            return Ok(self.output_values[var.var as usize]);
        }
        self.get_general(var, phase, exp)
    }

    fn set(&mut self, var: &'static Variable, x: f64, stepping: bool) -> Result<(), BindingError> {
        if let Some(sim) = self.sim.as_mut().filter(|_| stepping) {
            match var.var {
                Var::mu => sim.set_mu(x),
                Var::d_phi => sim.set_d_phi(x),
                v => match input_of(v) {
                    Some(inp) => sim.set_input(inp, x),
                    None => Ok(()),
                },
            }?;
            self.outputs_valid = false;
        } else {
            self.dirty = true;
        }
        self.values[var.var as usize] = x;
        Ok(())
    }

    fn set_input_derivative(
        &mut self,
        var: &'static Variable,
        der: f64,
        stepping: bool,
    ) -> Result<(), BindingError> {
        let inp = input_of(var.var).ok_or_else(|| {
            BindingError::NotAvailable(format!("{} has no input derivative", var.name))
        })?;
        let k = match inp {
            Input::Omega1 => 0,
            Input::TLoad => 1,
        };
        self.input_der[k] = der;
        match self.sim.as_mut().filter(|_| stepping) {
            Some(sim) => {
                sim.set_input_derivative(inp, der)?;
                self.outputs_valid = false;
            }
            None => self.dirty = true,
        }
        Ok(())
    }

    fn output_derivatives(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), BindingError> {
        let sim = self
            .sim
            .as_mut()
            .ok_or_else(|| not_initialised("output derivatives", "are"))?;
        // Central difference on the dense output (order 1).
        let (om, op, delta) = sim.outputs_for_derivative();
        let (mut a, mut b) = ([0.0; N_VARIABLES], [0.0; N_VARIABLES]);
        values::output_values(&om, &mut a);
        values::output_values(&op, &mut b);
        for (o, &vr) in out.iter_mut().zip(vrs) {
            let var = variables::lookup(VarType::Real, vr)
                .ok_or_else(|| BindingError::NotAvailable(format!("no Real output {vr}")))?;
            let k = var.var as usize;
            *o = (b[k] - a[k]) / (2.0 * delta);
        }
        Ok(())
    }

    /// Returns Warning when an episode outside the model's validity started in the
    /// step (lift-off, drive reversal; `on_lift_off = warn`), with a message.
    fn do_step(
        &mut self,
        func: &'static str,
        ccp: f64,
        h: f64,
        log: &Logger,
    ) -> Result<Status, BindingError> {
        self.step(func, ccp, h, log, false).map(|end| end.status)
    }

    /// With `on_lift_off = warn`, the step ends early at the located start of an episode
    /// outside the validity (lift-off, drive reversal: the instant `on_lift_off = discard`
    /// stops at) when it lies inside the step, with Warning and the message; the model is at
    /// that instant and runs on from it. An episode that holds at the step's start is
    /// reported and the step completes. With `on_lift_off = discard` as [`Model::do_step`].
    fn do_step_until_event(
        &mut self,
        func: &'static str,
        ccp: f64,
        h: f64,
        log: &Logger,
    ) -> Result<StepEnd, BindingError> {
        self.step(func, ccp, h, log, true)
    }

    fn step_tolerance(t: f64, h: f64) -> f64 {
        sim::comm_tolerance(t, h)
    }

    fn time(&self) -> Option<f64> {
        self.sim.as_ref().map(Simulation::time)
    }

    fn last_successful_time(&self) -> Option<f64> {
        self.sim.as_ref().map(Simulation::last_successful_time)
    }

    fn snapshot(&self) -> BindingState {
        BindingState {
            values: self.values,
            input_der: self.input_der,
            sim: if self.dirty {
                None
            } else {
                self.sim.as_ref().map(Simulation::state)
            },
        }
    }

    fn restore(&mut self, s: &BindingState) -> Result<(), BindingError> {
        match (&s.sim, self.sim.as_mut()) {
            (Some(ss), Some(sim)) => sim.restore(ss)?,
            (Some(ss), None) => self.sim = Some(Simulation::from_state(ss)?),
            (None, _) => self.sim = None,
        }
        self.dirty = self.sim.is_none();
        self.values = s.values;
        self.input_der = s.input_der;
        self.outputs_valid = false;
        Ok(())
    }

    fn write_state(s: &BindingState, w: &mut crate::bytes::Writer) {
        s.write(w);
    }

    fn read_state(r: &mut crate::bytes::Reader<'_>) -> Result<BindingState, BindingError> {
        BindingState::read(r)
    }

    fn validate_state(s: &BindingState, phase: Phase, exp: &Experiment) -> Result<(), String> {
        s.validate(phase, exp)
    }
}
