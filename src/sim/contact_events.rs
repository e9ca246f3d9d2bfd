//! Contact onset and separation of the elastic flanks (docs/model.md §3.6, docs/fmu.md
//! "Contact events"): state events where the force of the drive or the coast flanks sets
//! in or falls to zero, the sign changes of the contact's event functions
//! (`Contact::event_functions`; rigid teeth have none). There f
//! has a jump (the mesh damping's force `d_l l delta'` sets in at an onset) or a kink (the
//! force reaches 0 where the damping would pull, just before the flanks part); a step
//! across it would smear the impact over the step, so the stepper lands on it: after each accepted step the approaches at both ends are compared,
//! a sign change is located on the step's collocation polynomial (to
//! [`LOCATE_TOL`](super::validity::LOCATE_TOL)), the step is retaken to end just after it
//! and f is renewed there. Every onset counts as an impact.

use super::error::{solver_err, SimError};
use super::stepping::StepReport;
use super::validity::locate;
use super::Simulation;
use crate::rotor::NY;
use nalgebra::SVector;

/// Most contact events one communication interval lists (further ones are counted).
pub const MAX_CONTACT_REPORTED: usize = 8;

/// Which flanks a contact event concerns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flank {
    /// The drive flanks (gear 1 pushes gear 2).
    Drive,
    /// The coast flanks (gear 2 pushes gear 1, after the play is used up).
    Coast,
}

/// A located contact onset or separation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactEvent {
    /// The instant in s (the first time known to be past the crossing).
    pub t: f64,
    /// The flanks.
    pub flank: Flank,
    /// true: the flanks push from here (an impact); false: their force has fallen to 0 (they
    /// part: the approach follows, with the damping no longer pushing).
    pub onset: bool,
}

impl Simulation {
    /// Contact onsets and separations in the step just accepted (the stepper at its end);
    /// `t_end` is the FMU time this doStep steps to. Lands on the first one: retakes the
    /// step to end there (or, on the look-ahead part past `t_end`, on `t_end`: the next
    /// doStep meets it again) and renews f there.
    pub(super) fn contact_events(
        &mut self,
        t_end: f64,
        report: &mut StepReport,
    ) -> Result<(), SimError> {
        let [a, b] = self.contact_crossings();
        let first = match (a, b) {
            (Some(a), Some(b)) => Some(if b.t < a.t { b } else { a }),
            (a, b) => a.or(b),
        };
        let Some(ev) = first else {
            return Ok(());
        };
        let (tp, tn) = (self.solver.t_prev(), self.solver.t());
        if ev.t > t_end {
            // On the look-ahead part: end this doStep on t_end; the next meets it again.
            return self.retake_to(t_end);
        }
        // A crossing at the very start of the step (the landing of the last step fell a
        // hair short of it): the step is kept, as a retake would be a sliver; the event
        // counts at its located instant and f is renewed at the step's end.
        let sliver = (ev.t - tp) <= (1e-9 * (tn - tp)).max(4.0 * f64::EPSILON * tn.abs());
        if !sliver {
            self.retake_to(ev.t)?;
        }
        let y = *self.solver.y();
        // f jumps here: a fresh f. J and the step-size history are kept (the stepper renews
        // J when Newton slows down): rattle, 0.1 s at rtol 1e-6: 39636 f, 939 J, 4119 LU
        // instead of 41284, 1043, 4359 with a full restart.
        if let Err(e) = self.solver.refresh(&mut self.problem, y) {
            let ts = self.solver.t();
            self.restart_pending = true;
            return Err(solver_err(e, ts));
        }
        // The retaken step ends within the local error of the dense output's crossing: if
        // its end is not yet across, the next step (a sliver) crosses and reports it.
        let k = usize::from(ev.flank == Flank::Coast);
        let t = self.solver.t();
        let across = sliver
            || self
                .problem
                .model
                .contact()
                .event_functions(t, self.solver.y())
                .is_some_and(|e| (e[k] > 0.0) == ev.onset);
        if !across {
            return Ok(());
        }
        if ev.onset {
            self.impacts += 1;
        }
        report.note_contact(ContactEvent {
            t: if sliver { ev.t } else { self.solver.t() },
            ..ev
        });
        Ok(())
    }

    /// The sign changes of the drive and the coast flanks' force functions in the step
    /// just accepted, each located on its collocation polynomial (to `LOCATE_TOL`); none
    /// for rigid teeth.
    fn contact_crossings(&self) -> [Option<ContactEvent>; 2] {
        let mut out = [None, None];
        let contact = self.problem.model.contact();
        if !contact.has_contact_events() {
            return out;
        }
        let (tp, tn) = (self.solver.t_prev(), self.solver.t());
        if tp >= tn || tp.is_nan() {
            return out;
        }
        // The step's own start state, not the dense output at t_prev: a landing that ended a
        // hair short of a crossing (phi = -0.0) must still count as before it, and the new
        // polynomial's value there may round to the other side.
        let (y_p, y_n) = (self.solver.y_prev(), self.solver.y());
        let (Some(e_n), Some(e_p)) = (
            contact.event_functions(tn, y_n),
            contact.event_functions(tp, y_p),
        ) else {
            return out;
        };
        for (k, flank) in [Flank::Drive, Flank::Coast].into_iter().enumerate() {
            let (a, b) = (e_p[k], e_n[k]);
            let onset = a <= 0.0 && b > 0.0;
            if !(onset || (a > 0.0 && b <= 0.0)) {
                continue;
            }
            // g >= 0 before the crossing, < 0 after it.
            let sign = if onset { -1.0 } else { 1.0 };
            let solver = &self.solver;
            let g = |s: f64| {
                let mut z = SVector::<f64, NY>::zeros();
                solver.dense_output(s, &mut z);
                let d = contact.event_functions(s, &z).map_or(0.0, |e| e[k]);
                if onset && d == 0.0 {
                    // delta = 0 is still apart: the onset is where delta > 0.
                    f64::MIN_POSITIVE
                } else {
                    sign * d
                }
            };
            let ga = if onset { -a } else { a };
            let gb = sign * b;
            let t_c = locate(g, tp, ga.max(0.0), tn, gb.min(-f64::MIN_POSITIVE));
            out[k] = Some(ContactEvent {
                t: t_c,
                flank,
                onset,
            });
        }
        out
    }

    /// Real-time mode (`realtime`): the fixed step just taken is kept whatever it
    /// crossed (the work per doStep stays bounded); the crossings are still located on
    /// its polynomial, reported and, for an onset, counted.
    pub(super) fn note_contact_crossings(&mut self, report: &mut StepReport) {
        let [a, b] = self.contact_crossings();
        let mut evs = [a, b];
        if let [Some(x), Some(y)] = evs {
            if y.t < x.t {
                evs = [Some(y), Some(x)];
            }
        }
        for ev in evs.into_iter().flatten() {
            if ev.onset {
                self.impacts += 1;
            }
            report.note_contact(ev);
        }
    }
}

impl StepReport {
    /// Records a contact event (the first [`MAX_CONTACT_REPORTED`], then counts).
    pub(super) fn note_contact(&mut self, e: ContactEvent) {
        match self.contact_events.iter_mut().find(|s| s.is_none()) {
            Some(slot) => *slot = Some(e),
            None => self.contact_events_dropped += 1,
        }
    }
}
