//! Stick and slip of a spur contact line at the pitch line (`model.md` §4.1) as state events
//! of the simulation: the instants are located on the dense output of the step in which
//! they happen, the step is retaken to end there, and the stepper restarts with the other
//! mode of f.
//!
//! - Entry: a line's sliding speed `x0` changes sign (it crosses the pitch line) and, at the
//!   crossing, the force that would hold it there is within its friction bound
//!   ([`GearedRotor::stick_margin`](crate::rotor::GearedRotor::stick_margin) >= 0). Also
//!   taken where a step lands on a predicted sliding reversal (`mesh_events`): there the
//!   spur pair's mesh-event handling would otherwise hop to the other side.
//! - Exit: the margin becomes negative (the force needed exceeds the bound, e.g. as the
//!   line moves away from the pitch point or a second pair takes part of the load).
//!
//! A transition located after the FMU time being stepped to (on a look-ahead step), or any
//! other change of f found at the end of such a step (a landing at the pitch line, the end
//! of a release), is not taken there: the step is retaken to end on the FMU time instead,
//! and the next doStep finds the transition again. So the stepper never stands past the FMU
//! time in another mode than its step was taken with, and a retake at the next
//! communication point (`sync`) always runs with the f of its step.

// `!(a >= b)` on purpose: NaN counts as outside, which `a < b` would let pass.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::validity::locate;
use super::{SimError, Simulation, StepReport};
use crate::radau5::{self, Retake};
use crate::rotor::{GearedRotor, NY};
use nalgebra::SVector;

/// Most stick transitions one communication interval lists (further ones are counted).
pub const MAX_STICK_REPORTED: usize = 4;

/// A line whose sliding speed is at most this fraction of the rolling speed across a base
/// pitch, `(omega1 + omega2) p_bt`, is at the pitch line (1e-6: ten times the margin by
/// which a step lands before a predicted reversal, `mesh_events::JUMP_MARGIN`).
const AT_PITCH_LINE: f64 = 1e-6;

/// A located change of the stick mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StickChange {
    /// The instant in s.
    pub t: f64,
    /// true: a line started to stick; false: it slips again.
    pub stick: bool,
}

/// The friction mode of a start state that puts a spur contact line on the pitch line (the
/// default phase psi0 = 0 does in rigid rotation: x0 ~ 1e-15 m/s). A line that holds there
/// (its stick margin >= 0 while the pair rolls) sticks from t0 on, on the flank that
/// carries the load; the first doStep reports the entry at t0. Left to
/// [`Simulation::stick_transitions`], it was found only if the first step showed a sign
/// change of x0, which the rounding left in x0 (~1e-17 m/s) decided (an elastic coast line
/// at 100 rpm slid through: entry at 0.35 ms, T1 off by 1.84 N m at rtol 1e-6). A line that
/// slides through starts released in the sense it slides from t0 on (opposite to the force
/// that would hold it, as after a stick phase), so that f at t0, the stages of the first
/// step and the friction columns of J (one-sided differences of the friction) all see its
/// force from after t0; the release ends where the line leaves the band. Left as it was, f
/// at t0 was Coulomb's from before the reversal and J's differences straddled the jump of
/// the line's force (entries ~1e10-1e11 instead of ~1e7): the first step's Newton iteration
/// stopped on an increment that the false stiffness kept small, its error estimate was
/// filtered by the same matrix, and the step was accepted with its collocation equations
/// unsolved (elastic spur pair from rest, rtol 1e-6: the centre velocities off by 3e-2 of
/// their scale after 1 us, the first separation 0.50 us early). Returns the start state,
/// consistent with the mode (rigid teeth: lambda). At standstill (no rolling, no pitch-line
/// band) no line is made to stick here.
///
/// # Errors
/// The consistent state of the chosen mode cannot be computed.
pub(super) fn start_mode(
    model: &mut GearedRotor,
    t: f64,
    y: SVector<f64, NY>,
) -> Result<SVector<f64, NY>, SimError> {
    if !model.stick_possible() || model.stick() || model.released() != 0.0 {
        return Ok(y);
    }
    let Some(x0) = model.pitch_line_sliding(t, &y) else {
        return Ok(y);
    };
    let rolling = model.rolling_speed(&y);
    if !(x0.abs() <= AT_PITCH_LINE * rolling) {
        return Ok(y);
    }
    let (stick, release) = match model.stick_state(t, &y) {
        Some((margin, f_w)) if margin < 0.0 && f_w != 0.0 => (false, -f_w.signum()),
        // Only while the pair rolls: the pitch-line band is a fraction of the rolling speed.
        Some((margin, _)) if margin >= 0.0 && rolling > 0.0 => (true, 0.0),
        _ => return Ok(y),
    };
    let coast = model.watches_coast(t, &y);
    model.set_stick_flank(coast);
    model.set_stick(stick, release);
    model
        .contact()
        .consistent_state(t, &y)
        .map_err(SimError::Model)
}

impl Simulation {
    /// Stick transitions in the step just accepted (the stepper at its end); `t_end` is
    /// the FMU time this doStep steps to.
    pub(super) fn stick_transitions(
        &mut self,
        t_end: f64,
        report: &mut StepReport,
    ) -> Result<(), SimError> {
        let model = &self.problem.model;
        if !model.stick_possible() {
            return Ok(());
        }
        let (tp, tn) = (self.solver.t_prev(), self.solver.t());
        if !(tp < tn) {
            return Ok(());
        }
        let y_n = *self.solver.y();
        let mut ys = SVector::<f64, NY>::zeros();
        if model.released() != 0.0 && !model.stick() {
            // A released line leaves the band: the law applies as usual from here; f is the
            // same there when it slides in the released sense, else it jumps (restart). On
            // a look-ahead step the step is first retaken to end on t_end (a retake there
            // must run with the f the step was taken with).
            if let Some(x_n) = model.pitch_line_sliding(tn, &y_n) {
                if x_n.abs() > model.release_band(&y_n) {
                    if tn > t_end {
                        return self.retake_to(t_end);
                    }
                    let same = x_n.signum() == model.released();
                    self.problem.model.clear_release();
                    if !same {
                        let r = self.solver.restart(&mut self.problem, y_n, None);
                        r.map_err(|e| super::error::solver_err(e, tn))?;
                    }
                    return Ok(());
                }
            }
        }
        let model = &self.problem.model;
        let at = if model.stick() {
            let g_n = model.stick_margin(tn, &y_n).unwrap_or(-1.0);
            if g_n >= 0.0 {
                return Ok(());
            }
            let solver = &self.solver;
            let mut g = |s: f64| {
                solver.dense_output(s, &mut ys);
                model.stick_margin(s, &ys).unwrap_or(-1.0)
            };
            // (A margin already negative at the step's start, which the check of the last
            // step end did not see, is taken as zero there: the first crossing after it.)
            let g_p = g(tp).max(0.0);
            locate(g, tp, g_p, tn, g_n)
        } else {
            let Some(x_n) = model.pitch_line_sliding(tn, &y_n) else {
                return Ok(());
            };
            // At the pitch line already (a step that ended there, e.g. on a predicted
            // reversal): stick from here if the line holds.
            let rolling = model.rolling_speed(&y_n);
            if x_n.abs() <= AT_PITCH_LINE * rolling {
                if model.stick_margin(tn, &y_n).is_some_and(|g| g >= 0.0) {
                    if tn > t_end {
                        return self.retake_to(t_end);
                    }
                    return self.switch_stick(tn, true, report).map_err(|e| {
                        self.restart_pending = true;
                        super::error::solver_err(e, tn)
                    });
                }
                return Ok(());
            }
            self.solver.dense_output(tp, &mut ys);
            let Some(x_p) = model.pitch_line_sliding(tp, &ys) else {
                return Ok(());
            };
            // A sign change of the same line: both ends within a quarter pitch of rolling
            // (when the nearest line changes, x0 jumps by the rolling speed across a pitch).
            let quarter = 0.25 * rolling;
            if x_p == 0.0
                || (x_p < 0.0) == (x_n < 0.0)
                || x_p.abs() > quarter
                || x_n.abs() > quarter
            {
                return Ok(());
            }
            let sign = x_p.signum();
            let solver = &self.solver;
            let g = |s: f64| {
                let mut z = SVector::<f64, NY>::zeros();
                solver.dense_output(s, &mut z);
                let x = model.pitch_line_sliding(s, &z).unwrap_or(0.0) * sign;
                if x == 0.0 {
                    -f64::MIN_POSITIVE
                } else {
                    x
                }
            };
            let t_c = locate(g, tp, x_p.abs(), tn, -x_n.abs());
            self.solver.dense_output(t_c, &mut ys);
            if !(model.stick_margin(t_c, &ys).unwrap_or(-1.0) >= 0.0) {
                return Ok(());
            }
            t_c
        };
        let on = !self.problem.model.stick();
        if at > t_end {
            // On the look-ahead part: end this doStep's stepping on t_end in the current
            // mode; the next doStep meets the transition again.
            self.retake_to(t_end)?;
            return Ok(());
        }
        self.switch_stick(at, on, report).map_err(|e| {
            let ts = self.solver.t();
            self.restart_pending = true;
            super::error::solver_err(e, ts)
        })
    }

    /// The last step retaken to end on `t` (no-op at its end).
    pub(super) fn retake_to(&mut self, t: f64) -> Result<(), SimError> {
        if t >= self.solver.t() {
            return Ok(());
        }
        match self.solver.retake(&mut self.problem, t) {
            Ok(Retake::Exact) => Ok(()),
            Ok(Retake::Interpolated) => {
                self.restart_pending = true;
                Ok(())
            }
            Err(e) => {
                self.restart_pending = true;
                Err(super::error::solver_err(e, t))
            }
        }
    }

    /// Switches the stick mode at `t` (inside the last step or at its end): the step is
    /// retaken to end there, lambda re-projected for the new mode, the stepper restarted.
    fn switch_stick(
        &mut self,
        t: f64,
        on: bool,
        report: &mut StepReport,
    ) -> Result<(), radau5::Error> {
        if t < self.solver.t() {
            self.solver.retake(&mut self.problem, t)?;
        }
        self.enter_mode(on)?;
        report.note_stick(StickChange {
            t: self.solver.t(),
            stick: on,
        });
        Ok(())
    }

    /// Sets the stick mode at the stepper's current point and restarts it there with the
    /// consistent lambda of the new mode. Leaving it, the line slides in the sense opposite
    /// to its stick force there (the force is at its bound: it now resists that sliding).
    pub(super) fn enter_mode(&mut self, on: bool) -> Result<(), radau5::Error> {
        let t = self.solver.t();
        let model = &mut self.problem.model;
        let release = match model.stick_state(t, self.solver.y()) {
            Some((_, f_w)) if !on && f_w != 0.0 => -f_w.signum(),
            _ => 0.0,
        };
        if on {
            // The line that sticks: the one the margin that decided the entry was asked
            // about (the coast flanks' while they carry the load).
            let coast = model.watches_coast(t, self.solver.y());
            model.set_stick_flank(coast);
        }
        model.set_stick(on, release);
        let mut y = *self.solver.y();
        if let Ok(z) = model.contact().consistent_state(t, &y) {
            y = z;
        }
        self.solver.restart(&mut self.problem, y, None)
    }

    /// After a step that landed on a predicted mesh event: whether it is a sliding reversal
    /// at which a line sticks (`mesh_events` lands on it from before, by a hair). Then the
    /// stick mode starts here instead of the hop to the other side of the jump.
    pub(super) fn sticks_at_landing(&self) -> bool {
        let model = &self.problem.model;
        // (The predicted reversals are the drive flanks' lines'.)
        if model.stick()
            || !model.stick_possible()
            || model.coast_carries(self.solver.t(), self.solver.y())
        {
            return false;
        }
        let Some((gap, _, p, which)) = self.mesh_event_gap(0.0) else {
            return false;
        };
        which == super::mesh_events::REVERSAL
            && gap < super::mesh_events::JUMP_MERGE * p
            && model
                .stick_margin(self.solver.t(), self.solver.y())
                .is_some_and(|g| g >= 0.0)
    }
}

impl StepReport {
    /// Records a stick transition (the first [`MAX_STICK_REPORTED`], the rest counted).
    pub(super) fn note_stick(&mut self, c: StickChange) {
        if let Some(slot) = self.stick_changes.iter_mut().find(|s| s.is_none()) {
            *slot = Some(c);
        } else {
            self.stick_changes_dropped += 1;
        }
    }
}
