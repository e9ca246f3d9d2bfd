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
use super::validate::STEP_RESOLUTION;
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

/// The contact event functions at a state: (t, y, `[phi, phi_c]`).
pub(super) type EventValues = (f64, SVector<f64, NY>, [f64; 2]);

/// 0 for the drive, 1 for the coast flanks (the order of the event functions).
fn flank_index(f: Flank) -> usize {
    usize::from(f == Flank::Coast)
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
    /// doStep meets it again) and renews f there. A crossing at the very start of the step
    /// (a landing that fell a hair short of it) keeps the step and counts at once; another
    /// crossing later in the same step is then landed on as usual.
    pub(super) fn contact_events(
        &mut self,
        t_end: f64,
        report: &mut StepReport,
    ) -> Result<(), SimError> {
        // Flanks whose crossing at the step's start was counted already (a retake to t_end
        // keeps that start, and its crossing, in the retaken step).
        let mut counted = [false; 2];
        for pass in 0..2 {
            let [a, b] = self.contact_crossings();
            let skip = |e: Option<ContactEvent>| e.filter(|e| !counted[flank_index(e.flank)]);
            let (first, second) = match (skip(a), skip(b)) {
                (Some(a), Some(b)) if b.t < a.t => (Some(b), Some(a)),
                (a, b) => (a.or(b), a.and(b)),
            };
            let Some(mut ev) = first else {
                return Ok(());
            };
            let (tp, tn) = (self.solver.t_prev(), self.solver.t());
            // (A retake must leave a step t can resolve: `validate::STEP_RESOLUTION`.)
            let sliver = |e: &ContactEvent| {
                (e.t - tp) <= (1e-9 * (tn - tp)).max(1e3 * STEP_RESOLUTION * tn.abs())
            };
            if sliver(&ev) {
                self.count_contact(ev, report);
                counted[flank_index(ev.flank)] = true;
                match second {
                    Some(s) if !sliver(&s) => ev = s,
                    rest => {
                        if let Some(s) = rest {
                            self.count_contact(s, report);
                        }
                        return self.renew_f();
                    }
                }
            }
            if ev.t > t_end {
                // On the look-ahead part: end this doStep on t_end; the next meets it
                // again. The retaken step may end just across (the crossing within its
                // local error of t_end): looked at once more.
                self.retake_to(t_end)?;
                if pass == 0 {
                    continue;
                }
                return Ok(());
            }
            self.retake_to(ev.t)?;
            self.renew_f()?;
            // The retaken step ends within the local error of the dense output's crossing:
            // if its end is not yet across, the next step (a sliver) crosses and counts it.
            let k = flank_index(ev.flank);
            let t = self.solver.t();
            let across = self
                .problem
                .model
                .contact()
                .event_functions(t, self.solver.y())
                .is_some_and(|e| (e[k] > 0.0) == ev.onset);
            if across {
                self.count_contact(ContactEvent { t, ..ev }, report);
            }
            return Ok(());
        }
        Ok(())
    }

    /// f jumps at a contact event: a fresh f where the stepper stands. J and the step-size
    /// history are kept (the stepper renews J when Newton slows down): rattle, 0.1 s at
    /// rtol 1e-6: 39636 f, 939 J, 4119 LU instead of 41284, 1043, 4359 with a full restart.
    /// The Newton rate from before is forgotten (`Radau5::refresh` does it): the mesh
    /// spring appears or vanishes here, so the old J no longer describes f and only a
    /// measured rate may end the iteration.
    /// Measured (no test can tell it apart): rattle at rtol 1e-6 against rtol 1e-12, TE
    /// error 1.1e-7 -> 7.7e-8 m; reversal energy balance at rtol 1e-9 3.1e-9 -> 2.3e-9.
    fn renew_f(&mut self) -> Result<(), SimError> {
        let y = *self.solver.y();
        self.solver.refresh(&mut self.problem, y).map_err(|e| {
            let ts = self.solver.t();
            self.restart_pending = true;
            solver_err(e, ts)
        })
    }

    /// Reports a contact event; an onset is an impact.
    fn count_contact(&mut self, ev: ContactEvent, report: &mut StepReport) {
        if ev.onset {
            self.impacts += 1;
        }
        report.note_contact(ev);
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
        // The start values are the last step's end values, unless the stepper was moved
        // (a retake, a restart, a restored state): the cache is keyed by the exact state.
        let e_p = match self.event_values.get() {
            Some((t, y, e))
                if t == tp
                    && y.iter()
                        .zip(y_p.iter())
                        .all(|(a, b)| a.to_bits() == b.to_bits()) =>
            {
                Some(e)
            }
            _ => contact.event_functions(tp, y_p),
        };
        let e_n = contact.event_functions(tn, y_n);
        if let Some(e) = e_n {
            self.event_values.set(Some((tn, *y_n, e)));
        }
        let (Some(e_n), Some(e_p)) = (e_n, e_p) else {
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
            self.count_contact(ev, report);
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
