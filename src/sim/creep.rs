//! The creep of friction laws 1 and 3 near standstill (`model.md` §4.2) as a mode of f
//! that the simulation switches at located instants: on where the rolling speed across a
//! base pitch falls below [`CREEP_ENTRY`], off where it rises above [`CREEP_SPEED`]. The
//! instant is located on the dense output of the step in which the speed crosses, the step
//! is retaken to end there, and the stepper restarts with the other law (f jumps there).
//! Leaving the creep, a spur line on the pitch line gets its start mode
//! (`stick::start_mode`: it sticks if it holds, else it is released in its sense).
//!
//! In the real-time mode (`h_fixed`) the switch is taken at the end of the fixed step in
//! which the speed crossed, not located (fixed steps cannot be retaken).

// `!(a >= b)` on purpose: NaN counts as outside, which `a < b` would let pass.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::stick::StickChange;
use super::validity::locate;
use super::{SimError, Simulation, StepReport};
use crate::rotor::{GearedRotor, CREEP_ENTRY, CREEP_SPEED, NY};
use nalgebra::SVector;

/// Most creep switches one communication interval lists (further ones are counted).
pub const MAX_CREEP_REPORTED: usize = 2;

/// A located switch of the creep mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CreepChange {
    /// The instant in s.
    pub t: f64,
    /// true: the flanks start to creep; false: the sharp law again.
    pub creep: bool,
    /// The rolling speed across a base pitch there (m/s).
    pub rolling: f64,
}

/// How far the state y is past the switch of the current mode (> 0: switch): creeping,
/// the rolling speed above CREEP_SPEED; else below CREEP_ENTRY.
fn past_switch(model: &GearedRotor, y: &SVector<f64, NY>) -> f64 {
    let u = model.rolling_speed(y);
    if model.creeps() {
        u - CREEP_SPEED
    } else {
        CREEP_ENTRY - u
    }
}

/// The creep mode of a start state (creeping where the pair, rolling rigidly at the
/// state's omega1, rolls slower than CREEP_ENTRY across a base pitch: the same test as the
/// periodic module's, whose orbit the start may be), and the state made consistent with
/// it.
///
/// # Errors
/// The consistent state cannot be computed.
pub(super) fn start_creep(
    model: &mut GearedRotor,
    t: f64,
    y: SVector<f64, NY>,
) -> Result<SVector<f64, NY>, SimError> {
    // The state's (filtered) omega1: the input's at a start and on an orbit; after new
    // inputs at t0 the filter has not moved yet, and the located switches follow it.
    let on = model.creeps_at(y[crate::rotor::idx::OMEGA1]);
    if on == model.creeps() {
        return Ok(y);
    }
    model.set_creep(on);
    model
        .contact()
        .consistent_state(t, &y)
        .map_err(SimError::Model)
}

impl Simulation {
    /// A switch of the creep mode in the step just accepted (the stepper at its end):
    /// located, the step retaken to end there, the mode switched and the stepper restarted.
    /// On a look-ahead step a switch past `t_end` is not taken: the step is retaken to end
    /// on `t_end`, and the next doStep meets the switch again.
    pub(super) fn creep_transitions(
        &mut self,
        t_end: f64,
        report: &mut StepReport,
    ) -> Result<(), SimError> {
        let model = &self.problem.model;
        if !model.creep_possible() {
            return Ok(());
        }
        let (tp, tn) = (self.solver.t_prev(), self.solver.t());
        let y_n = *self.solver.y();
        let g_n = past_switch(model, &y_n);
        if !(g_n > 0.0) {
            return Ok(());
        }
        if !(tp < tn) {
            // The stick or contact checks of this step restarted the stepper at an event
            // of theirs, past the switch already: switch there.
            return self.switch_creep(report);
        }
        let solver = &self.solver;
        let mut ys = SVector::<f64, NY>::zeros();
        let mut g = |s: f64| {
            solver.dense_output(s, &mut ys);
            -past_switch(model, &ys)
        };
        // (Past the switch already at the step's start, which the last step's end did not
        // show: taken as the step's start.)
        let g_p = g(tp).max(0.0);
        let at = locate(g, tp, g_p, tn, -g_n);
        if at > t_end {
            return self.retake_to(t_end);
        }
        if at < tn {
            if let Err(e) = self.solver.retake(&mut self.problem, at) {
                self.restart_pending = true;
                return Err(super::error::solver_err(e, self.solver.t()));
            }
        }
        self.switch_creep(report)
    }

    /// Switches the creep mode at the stepper's current point and restarts it there with
    /// the state consistent with the new mode; a stick phase it ends is reported too.
    pub(super) fn switch_creep(&mut self, report: &mut StepReport) -> Result<(), SimError> {
        let t = self.solver.t();
        let mut y = *self.solver.y();
        let model = &mut self.problem.model;
        let on = !model.creeps();
        if on && model.stick() {
            report.note_stick(StickChange { t, stick: false });
        }
        report.note_creep(CreepChange {
            t,
            creep: on,
            rolling: model.rolling_speed(&y),
        });
        model.set_creep(on);
        if let Ok(z) = model.contact().consistent_state(t, &y) {
            y = z;
        }
        if !on {
            y = super::stick::start_mode(model, t, y)?;
            if model.stick() {
                report.note_stick(StickChange { t, stick: true });
            }
        }
        self.solver
            .restart(&mut self.problem, y, None)
            .map_err(|e| {
                self.restart_pending = true;
                super::error::solver_err(e, t)
            })
    }

    /// The real-time mode: whether the fixed step just taken ended past the switch of the
    /// creep mode (taken there by the caller with a new J).
    pub(super) fn creep_switch_due(&self) -> bool {
        let model = &self.problem.model;
        model.creep_possible() && past_switch(model, self.solver.y()) > 0.0
    }
}

impl StepReport {
    /// Records a creep switch (the first [`MAX_CREEP_REPORTED`], the rest counted).
    pub(super) fn note_creep(&mut self, c: CreepChange) {
        if let Some(slot) = self.creep_changes.iter_mut().find(|s| s.is_none()) {
            *slot = Some(c);
        } else {
            self.creep_changes_dropped += 1;
        }
    }
}
