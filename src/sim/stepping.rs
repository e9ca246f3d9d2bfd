//! Stepping across communication points: `Simulation::do_step` continues the stepper,
//! stops internal steps at the mesh events the `mesh_events` part predicts, looks ahead
//! across points while the input function stays the same, and reports what happened.

use super::contact_events::{ContactEvent, MAX_CONTACT_REPORTED};
use super::creep::{CreepChange, MAX_CREEP_REPORTED};
use super::error::{solver_err, SimError};
use super::stick::{StickChange, MAX_STICK_REPORTED};
use super::validity::{self, Violation};
use super::{closed_loop, validate, Simulation};
use crate::radau5;
use crate::radau5::Statistics;
use crate::rotor::{idx, NY};
use nalgebra::SVector;

/// Stop time given to the stepper in look-ahead mode: far enough never to be reached,
/// finite so that `t_stop - t` stays finite.
pub(super) const NO_STOP: f64 = f64::MAX;

/// Tolerance for `|currentCommunicationPoint - t| `: 1e-8 of the step, plus a few ulps of
/// t (masters compute `start + n h` or sum steps; both differ from ours by round-off only).
pub fn comm_tolerance(t: f64, h: f64) -> f64 {
    1e-8 * h.abs() + 16.0 * f64::EPSILON * t.abs()
}

/// What happened during one communication interval (for logging).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepReport {
    /// RADAU5 counters of this interval only.
    pub stats: Statistics,
    /// How often `contact_lost` (lift-off, a negative normal force) changed at internal
    /// steps.
    pub contact_changes: u32,
    /// Time of the first change in this interval (NaN if none).
    pub first_change_time: f64,
    /// `contact_lost` at the end of the interval.
    pub contact_lost: bool,
    /// Whether f changed at the start (new inputs: `Radau5::refresh`; new tunables or after
    /// a failure: `Radau5::restart`).
    pub restarted: bool,
    /// Episodes outside the model's validity that started in this interval (policy
    /// [`OnViolation::Warn`](super::OnViolation::Warn)), in the order found.
    pub violations: [Option<Violation>; validity::MAX_REPORTED],
    /// Further ones not listed.
    pub violations_dropped: u32,
    /// Stick transitions of a spur contact line at the pitch line in this interval, in
    /// order (`sim::stick`).
    pub stick_changes: [Option<StickChange>; MAX_STICK_REPORTED],
    /// Further ones not listed.
    pub stick_changes_dropped: u32,
    /// Contact onsets and separations of the elastic flanks in this interval, in order
    /// (`sim::contact_events`).
    pub contact_events: [Option<ContactEvent>; MAX_CONTACT_REPORTED],
    /// Further ones not listed.
    pub contact_events_dropped: u32,
    /// Switches of the creep of friction laws 1 and 3 near standstill in this interval, in
    /// order (`sim::creep`).
    pub creep_changes: [Option<CreepChange>; MAX_CREEP_REPORTED],
    /// Further ones not listed.
    pub creep_changes_dropped: u32,
}

impl Simulation {
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
        if change {
            let y = match self.restart_state(t) {
                Ok(y) => y,
                Err(e) => {
                    self.last_successful_time = t;
                    return Err(e);
                }
            };
            // Inputs enter f additively (the filter's reference, the load torque; J sees
            // T_load only in the E_load quadrature row, T_load omega2, which the simplified
            // Newton iteration absorbs), so J and the LU pair stay usable: only f is
            // re-evaluated (`Radau5::refresh`). A new tunable changes J, and a failed step
            // leaves nothing to trust: full restart.
            //
            // The Newton rate measured before is not (`refresh` forgets it): the next step
            // starts from the old polynomial, off by the input's effect, and an iterate
            // accepted on that rate left the energy balance of the reversal
            // run off by 3.4e-4 J in one free-flight step at rtol 1e-8 (1.4e-6 of E_in in
            // all, 7.2e-9 with the reset; the same f count), and T1 of the elastic closed
            // loop off by 0.094 N m at rtol 1e-5 (1.0e-4 with it).
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
        self.inputs_ref = *self.problem.model.inputs();
        // A derivative set at this point applies until the master sets a new one or a value.
        self.der_set = [false; 2];
        // Look ahead unless the inputs changed here: a master that changes them at every
        // point would pay for a retake at every point.
        let lookahead = !report.restarted;
        // Mesh-event stops pay when the steps are not already ended by communication points
        // closer than the mean spacing of the events (6 per base pitch): there, extra stops
        // would only force new LU decompositions (measured at H = 1e-5 s without look-ahead:
        // 5.5 ms per 10 ms without, 8-11 ms with); without look-ahead they are used from
        // half the spacing up (H = 1e-4 s: see `closed_loop`).
        let rate = self.problem.model.geometry().rb1 * self.solver.y()[idx::OMEGA1];
        let spacing = self.problem.model.geometry().p_bt / (6.0 * rate);
        let use_events =
            rate > 0.0 && (lookahead || t_end - t > closed_loop::EVENT_STOPS_MIN_SPAN * spacing);
        let horizon = if lookahead { NO_STOP } else { t_end };
        // Validity (validity.rs): conditions of the start state, then the end of a
        // look-ahead step of the last interval before the next step replaces its polynomial.
        if self.validity.pending_lift_off
            || self.validity.pending_reversal
            || self.validity.pending_overload
        {
            self.start_violations(&mut report)?;
        }
        let ts = self.solver.t();
        if report.restarted {
            // New inputs or tunables change lambda at once: a condition that now holds at
            // the start is an episode starting here (with the stepper still here, so that
            // a Discard leaves a state whose FMU time is the stepper's).
            let y = self.y_comm;
            self.check_validity(t, &y, &mut report)?;
        } else if ts > self.validity.t_checked && ts <= t_end {
            let y = *self.solver.y();
            self.check_validity(ts, &y, &mut report)?;
        }
        if self.solver.stats().naccpt == 0 && t == self.init.t_start && self.problem.model.stick() {
            // A line that holds on the pitch line from the start (`stick::start_mode`).
            report.note_stick(StickChange { t, stick: true });
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
            let (mut entered, mut defer) = (false, false);
            let r = self.solver.step(&mut self.problem, target).and_then(|tn| {
                if use_events && at_event && tn == target {
                    if !self.sticks_at_landing() {
                        // J jumps here (f has a kink, or a jump for spur pairs): the next
                        // step measures its Newton rate anew (docs/fmu.md "Mesh events").
                        self.solver.forget_convergence_rate();
                        self.f_after_event()?;
                    } else if tn <= t_end {
                        self.enter_mode(true)?;
                        entered = true;
                    } else {
                        // On the look-ahead part: the next doStep lands here again.
                        defer = true;
                    }
                }
                Ok(tn)
            });
            if defer {
                self.retake_to(t_end)?;
            }
            if entered {
                report.note_stick(StickChange {
                    t: self.solver.t(),
                    stick: true,
                });
            }
            // Stick transitions inside the step (located; the step may be retaken to end
            // at one).
            let r = match r {
                Ok(_) if !entered => match self
                    .stick_transitions(t_end, &mut report)
                    .and_then(|()| self.contact_events(t_end, &mut report))
                    .and_then(|()| self.creep_transitions(t_end, &mut report))
                {
                    Ok(()) => Ok(self.solver.t()),
                    Err(e) => return Err(self.stop_at_last_step(t_end, e)),
                },
                r => r,
            };
            match r {
                Ok(tn) if !validate::advanced(t_before, tn, t_end) => {
                    let e = radau5::Error::StepSizeTooSmall {
                        t: t_before,
                        h: tn - t_before,
                    };
                    return Err(self.stop_at_last_step(t_end, solver_err(e, t_before)));
                }
                Ok(tn) if tn <= t_end => {
                    // Lift-off as the contact decides it (`Contact::lifted_off`).
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
        // The state at t_end is checked before the FMU time moves there: a violation located
        // inside this doStep (also one before t_end on a look-ahead step that went past it)
        // then sets the FMU time to its instant, which must not lie before the FMU time.
        let mut y_end = SVector::<f64, NY>::zeros();
        self.state_at(t_end, &mut y_end);
        if self.solver.t() > t_end {
            self.track_contact(t_end, &y_end, &mut report);
        }
        if self.validity.t_checked < t_end {
            self.check_validity(t_end, &y_end, &mut report)?;
        }
        self.set_comm(t_end);
        self.last_successful_time = t_end;
        report.stats = self.solver.stats().since(&stats0);
        report.contact_lost = self.contact_lost;
        Ok(report)
    }

    /// Updates `contact_lost` (lift-off: a negative normal force) at a state on the
    /// trajectory and counts a change in the report. The contact decides
    /// (`Contact::lifted_off`: the stepper's lambda cheaply, a change confirmed with the
    /// consistent force, as the outputs report it; never for elastic teeth).
    pub(super) fn track_contact(&mut self, t: f64, y: &SVector<f64, NY>, report: &mut StepReport) {
        let lost = self
            .problem
            .model
            .contact()
            .lifted_off(t, y, self.contact_lost);
        if lost != self.contact_lost {
            if report.contact_changes == 0 {
                report.first_change_time = self.locate_contact_change(t, y, lost);
            }
            report.contact_changes += 1;
            self.contact_lost = lost;
        }
    }
}
