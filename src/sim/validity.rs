//! Where the model leaves its validity during a run, located on the dense output.
//!
//! Three conditions are watched at every accepted RADAU5 step end and at every communication
//! point (docs/validity.md lists them with everything else the code detects):
//! - lift-off: the normal contact force Fn = lambda (consistent value of the hidden
//!   constraint, as the outputs report it) becomes negative. The rigid single-flank contact
//!   then pulls the flanks together; real teeth would separate (or change flanks across the
//!   backlash), which this model cannot represent;
//! - drive reversal: the filtered drive speed omega1_filtered becomes negative. The model
//!   is set up for gear 1 driving in the positive sense (the mesh phase advances with phi1,
//!   mesh events and the loss figures assume it); standstill (omega1_filtered = 0) is
//!   inside it since friction laws 1 and 3 creep there (`model.md` §4.2);
//! - tooth overload (elastic teeth): the drive or the coast flanks overlap by more than
//!   m_n / 20 (`Contact::overload_margin`), several times any rating, where the linear
//!   mesh stiffness no longer holds. Reported once per run (it does not end).
//!
//! An episode starts when a condition turns true; its instant is located on the
//! collocation polynomial of the step in which it happened (Illinois regula falsi on the
//! indicator, to [`LOCATE_TOL`]), and it is reported once: with [`OnViolation::Warn`] in the
//! [`StepReport`](super::StepReport) (the FMU returns fmi2Warning with a message), with
//! [`OnViolation::Discard`] as [`SimError::Validity`]: the FMU time
//! and the last successful time are set to the instant and fmi2DoStep returns fmi2Discard.
//! An episode ends when the condition turns false again; the next start is a new episode.
//! A condition that holds at the start state is an episode starting there (reported by the
//! first doStep). Episodes shorter than one internal step can be missed (the indicator is
//! sampled at step ends); steps are at most h_max.

// `!(a > b)` on purpose: it also counts NaN as outside, which `a <= b` would let pass.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{SimError, Simulation};
use crate::radau5::Radau5;
use crate::rotor::{idx, NY};
use nalgebra::SVector;
use std::fmt;

/// Width of the bracket at which the location stops, in s (or 8 ulps of t, where that is
/// more: beyond t ~ 500 s).
pub const LOCATE_TOL: f64 = 1e-12;

/// Most violations one communication interval reports (further ones are counted only).
pub const MAX_REPORTED: usize = 4;

/// What to do when the model leaves its validity (FMU Enumeration `on_lift_off`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OnViolation {
    /// 1: complete the step, report fmi2Warning with a message (once per episode).
    #[default]
    Warn = 1,
    /// 2: stop at the located instant, fmi2Discard.
    Discard = 2,
}

impl OnViolation {
    /// From the FMU's Enumeration value (None outside 1..=2).
    pub fn from_code(code: i32) -> Option<Self> {
        match code {
            1 => Some(OnViolation::Warn),
            2 => Some(OnViolation::Discard),
            _ => None,
        }
    }
}

/// Which assumption broke.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ViolationKind {
    /// Fn < 0.
    LiftOff,
    /// omega1_filtered < 0.
    DriveReversal,
    /// Elastic teeth deflected by more than m_n / 20.
    ToothOverload,
}

/// The start of an episode outside the model's validity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Violation {
    /// Which assumption.
    pub kind: ViolationKind,
    /// The located instant in s.
    pub t: f64,
    /// Time of the state that revealed it (a step end or communication point) in s.
    pub t_seen: f64,
    /// Fn in N, omega1_filtered in rad/s, or the flanks' largest overlap in m there.
    pub value: f64,
}

/// A located instant in a message: 12 decimals (the location's resolution) while that
/// stays within 17 significant digits (|t| < 1e4 s), else the shortest round-trip form.
struct Instant(f64);

impl fmt::Display for Instant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.abs() < 1e4 {
            write!(f, "{:.12}", self.0)
        } else {
            write!(f, "{}", crate::fmt_num::Short(self.0))
        }
    }
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (t, ts, v) = (Instant(self.t), self.t_seen, self.value);
        match self.kind {
            ViolationKind::LiftOff => write!(
                f,
                "lift-off at t = {t} s: the normal contact force Fn became negative (Fn = {v:.6e} N at t = {ts} s). \
                 Real teeth would separate here; the rigid single-flank contact of this model instead pulls them \
                 together, so the results from this instant on are outside the model's validity \
                 (reported once per episode; on_lift_off = discard stops the step here)"
            ),
            ViolationKind::DriveReversal => write!(
                f,
                "drive reversal at t = {t} s: the filtered drive speed omega1_filtered became negative \
                 (omega1_filtered = {v:.6e} rad/s at t = {ts} s). The model assumes gear 1 drives in the positive \
                 sense, so the results from this instant on are outside the model's validity \
                 (reported once per episode; on_lift_off = discard stops the step here)"
            ),
            ViolationKind::ToothOverload => write!(
                f,
                "tooth overload at t = {t} s: the elastic teeth overlap by more than m_n/20 ({v:.6e} m at \
                 t = {ts} s). That is several times the load any gear rating allows; the linear mesh stiffness \
                 of ISO 6336-1 no longer holds there and real teeth would break, so the results from this \
                 instant on are outside the model's validity (reported once per run; on_lift_off = \
                 discard stops the step here)"
            ),
        }
    }
}

/// Episode state, part of a simulation snapshot.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Monitor {
    /// Fn < 0 at the last check.
    pub(super) lift_off: bool,
    /// omega1_filtered < 0 at the last check.
    pub(super) reversed: bool,
    /// Episodes that hold at the start state and are not reported yet.
    pub(super) pending_lift_off: bool,
    /// See `pending_lift_off`.
    pub(super) pending_reversal: bool,
    /// Elastic teeth overloaded at the last check.
    pub(super) overload: bool,
    /// See `pending_lift_off`.
    pub(super) pending_overload: bool,
    /// Time of the last check.
    pub(super) t_checked: f64,
    /// The policy (set by the FMU before every doStep).
    pub(super) policy: OnViolation,
}

impl Monitor {
    /// The monitor for a start state (conditions that already hold are pending): whether
    /// the flanks have lifted off there, and the filtered drive speed.
    pub(super) fn new(t: f64, lift_off: bool, omega1: f64, overload: bool) -> Self {
        let reversed = !(omega1 >= 0.0);
        Monitor {
            lift_off,
            reversed,
            pending_lift_off: lift_off,
            pending_reversal: reversed,
            overload,
            pending_overload: overload,
            t_checked: t,
            policy: OnViolation::Warn,
        }
    }

    /// Flags as bits (serialization): lift_off, reversed, pending_lift_off,
    /// pending_reversal, policy == Discard, overload, pending_overload.
    pub(super) fn bits(&self) -> u32 {
        u32::from(self.lift_off)
            | u32::from(self.reversed) << 1
            | u32::from(self.pending_lift_off) << 2
            | u32::from(self.pending_reversal) << 3
            | u32::from(self.policy == OnViolation::Discard) << 4
            | u32::from(self.overload) << 5
            | u32::from(self.pending_overload) << 6
    }

    /// Inverse of [`Monitor::bits`].
    pub(super) fn from_bits(b: u32, t_checked: f64) -> Self {
        Monitor {
            lift_off: b & 1 != 0,
            reversed: b & 2 != 0,
            pending_lift_off: b & 4 != 0,
            pending_reversal: b & 8 != 0,
            overload: b & 32 != 0,
            pending_overload: b & 64 != 0,
            t_checked,
            policy: if b & 16 != 0 {
                OnViolation::Discard
            } else {
                OnViolation::Warn
            },
        }
    }
}

/// Illinois regula falsi for the first sign change of `g` in `(a, b]` with `g(a) >= 0 >
/// g(b)` (values `ga`, `gb` given), to a bracket of [`LOCATE_TOL`]; returns the right end
/// (the first time known to be outside).
pub(super) fn locate(
    mut g: impl FnMut(f64) -> f64,
    mut a: f64,
    mut ga: f64,
    mut b: f64,
    mut gb: f64,
) -> f64 {
    let mut side = 0i32;
    // Far from t = 0 the bracket cannot shrink below a few ulps of t.
    let tol = LOCATE_TOL.max(8.0 * f64::EPSILON * b.abs());
    for _ in 0..200 {
        if b - a <= tol {
            break;
        }
        let mut c = b - gb * (b - a) / (gb - ga);
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        // Keep the bracket shrinking from both sides: bisect when one end stalls.
        if side.abs() >= 3 {
            c = 0.5 * (a + b);
            side = 0;
        }
        let gc = g(c);
        if gc < 0.0 {
            b = c;
            gb = gc;
            if side < 0 {
                ga *= 0.5;
            }
            side = side.min(0) - 1;
        } else {
            a = c;
            ga = gc;
            if side > 0 {
                gb *= 0.5;
            }
            side = side.max(0) + 1;
        }
    }
    b
}

impl Simulation {
    /// The policy for the following doSteps.
    pub fn set_on_violation(&mut self, policy: OnViolation) {
        self.validity.policy = policy;
    }

    /// Indicator of a condition: negative outside the validity (Fn; omega1_filtered,
    /// with 0 counted as outside).
    fn indicator(&self, kind: ViolationKind, t: f64, y: &SVector<f64, NY>) -> f64 {
        match kind {
            ViolationKind::LiftOff => self.problem.model.contact().normal_force(t, y),
            ViolationKind::DriveReversal => {
                let w = y[idx::OMEGA1];
                // < 0 is outside (NaN too).
                if w.is_nan() {
                    -f64::MIN_POSITIVE
                } else {
                    w
                }
            }
            ViolationKind::ToothOverload => self.problem.model.contact().overload_margin(t, y),
        }
    }

    /// The instant at which the sign of the consistent normal force (lambda for rigid
    /// teeth, `Contact::normal_force`) changed to `lost` (< 0) within the last step, located on its dense output as a lift-off is; `th` (the state
    /// that revealed it) where there is no polynomial to search (before the first step).
    pub(super) fn locate_contact_change(&self, th: f64, y: &SVector<f64, NY>, lost: bool) -> f64 {
        let lo = self.solver.t_prev().max(self.t_comm);
        if !(lo < th) || self.solver.stats().naccpt == 0 {
            return th;
        }
        // Indicator >= 0 on the side left, < 0 on the side entered.
        let sign = if lost { 1.0 } else { -1.0 };
        // (lambda = 0 counts as in contact: on the entered side when contact is regained.)
        let ind = |l: f64| {
            let v = sign * l;
            if !lost && v == 0.0 {
                -f64::MIN_POSITIVE
            } else {
                v
            }
        };
        let solver: &Radau5<NY> = &self.solver;
        let contact = self.problem.model.contact();
        let mut ys = SVector::<f64, NY>::zeros();
        let mut g = |s: f64| {
            solver.dense_output(s, &mut ys);
            ind(contact.normal_force(s, &ys))
        };
        let ga = g(lo);
        let gb = ind(contact.normal_force(th, y));
        if ga < 0.0 {
            // Already changed at the start of the search (e.g. an input set there).
            return lo;
        }
        if !(ga >= 0.0 && gb < 0.0) {
            return th;
        }
        locate(g, lo, ga, th, gb)
    }

    /// Reports the conditions that hold at the start state (first doStep after the start).
    pub(super) fn start_violations(
        &mut self,
        report: &mut super::StepReport,
    ) -> Result<(), SimError> {
        let t = self.time();
        let y = self.y_comm;
        let mut found = [None, None, None];
        if self.validity.pending_overload {
            let contact = self.problem.model.contact();
            let m_n = self.problem.model.params().gear.m_n;
            found[2] = Some(Violation {
                kind: ViolationKind::ToothOverload,
                t,
                t_seen: t,
                value: crate::rotor::OVERLOAD_FRACTION * m_n - contact.overload_margin(t, &y),
            });
        }
        if self.validity.pending_reversal {
            found[0] = Some(Violation {
                kind: ViolationKind::DriveReversal,
                t,
                t_seen: t,
                value: y[idx::OMEGA1],
            });
        }
        if self.validity.pending_lift_off {
            found[1] = Some(Violation {
                kind: ViolationKind::LiftOff,
                t,
                t_seen: t,
                value: self.problem.model.contact().normal_force(t, &y),
            });
        }
        self.validity.pending_lift_off = false;
        self.validity.pending_reversal = false;
        self.validity.pending_overload = false;
        self.emit(found, report)
    }

    /// Checks the state `y` at `th` (a step end not after the FMU time being stepped to, or
    /// that time on the dense output) against the last check; a new episode is located on
    /// the last step's dense output and reported.
    pub(super) fn check_validity(
        &mut self,
        th: f64,
        y: &SVector<f64, NY>,
        report: &mut super::StepReport,
    ) -> Result<(), SimError> {
        let was = [
            self.validity.reversed,
            self.validity.lift_off,
            self.validity.overload,
        ];
        let kinds = [
            ViolationKind::DriveReversal,
            ViolationKind::LiftOff,
            ViolationKind::ToothOverload,
        ];
        // Cheap decisions first; lift-off as the contact decides it (`Contact::lifted_off`:
        // the stepper's lambda, a change confirmed with the consistent force; never for
        // elastic teeth).
        let now = [
            !(y[idx::OMEGA1] >= 0.0),
            self.problem.model.contact().lifted_off(th, y, was[1]),
            // An overload is reported once per run: the teeth vibrate through the limit
            // at the mesh frequency, and what follows the first is outside the model anyway.
            was[2] || !(self.problem.model.contact().overload_margin(th, y) >= 0.0),
        ];
        let lo = self.validity.t_checked.max(self.solver.t_prev());
        let mut found = [None, None, None];
        for k in 0..3 {
            if now[k] && !was[k] {
                let kind = kinds[k];
                let value = self.indicator(kind, th, y);
                // (The indicator is the margin; an overload reports the overlap itself.)
                let shown = if kind == ViolationKind::ToothOverload {
                    crate::rotor::OVERLOAD_FRACTION * self.problem.model.params().gear.m_n - value
                } else {
                    value
                };
                let t = if lo < th && self.solver.stats().naccpt > 0 {
                    let solver: &Radau5<NY> = &self.solver;
                    let mut ys = SVector::<f64, NY>::zeros();
                    let mut g = |s: f64| {
                        solver.dense_output(s, &mut ys);
                        self.indicator(kind, s, &ys)
                    };
                    let ga = g(lo);
                    if ga < 0.0 {
                        lo
                    } else {
                        locate(g, lo, ga, th, value)
                    }
                } else {
                    th
                };
                found[k] = Some(Violation {
                    kind,
                    t,
                    t_seen: th,
                    value: shown,
                });
            }
        }
        self.validity.reversed = now[0];
        self.validity.lift_off = now[1];
        self.validity.overload = now[2];
        self.validity.t_checked = th;
        self.emit(found, report)
    }

    /// Warn: adds the violations to the report. Discard: stops at the earliest one (FMU
    /// time and last successful time there) with [`SimError::Validity`].
    fn emit(
        &mut self,
        found: [Option<Violation>; 3],
        report: &mut super::StepReport,
    ) -> Result<(), SimError> {
        let mut first: Option<Violation> = None;
        let overload = found[2].is_some();
        for v in found.into_iter().flatten() {
            if first.is_none_or(|f| v.t < f.t) {
                first = Some(v);
            }
            if self.validity.policy == OnViolation::Warn {
                if let Some(slot) = report.violations.iter_mut().find(|s| s.is_none()) {
                    *slot = Some(v);
                } else {
                    report.violations_dropped += 1;
                }
            }
        }
        match (self.validity.policy, first) {
            (OnViolation::Discard, Some(v)) => {
                if overload && v.kind != ViolationKind::ToothOverload {
                    // Reported once per run, so it must not be latched unreported: the
                    // check after this stop finds it again (located from there on).
                    self.validity.overload = false;
                    self.validity.pending_overload = false;
                }
                if v.t < self.t_comm || v.t > self.solver.t() {
                    // Not expected: the instant is located within [t_checked, th], and the
                    // FMU time is still the doStep's start here; keep the state then.
                    self.last_successful_time = self.t_comm;
                } else {
                    self.set_comm(v.t);
                    self.last_successful_time = v.t;
                }
                self.validity.t_checked = self.t_comm;
                Err(SimError::Validity(v))
            }
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locate_finds_the_first_sign_change_to_the_tolerance() {
        // cos(t) - 0.5 falls through 0 at pi/3; a steep and a flat end of the bracket
        let g = |t: f64| t.cos() - 0.5;
        let (a, b) = (0.0, 2.0);
        let t = locate(g, a, g(a), b, g(b));
        let root = std::f64::consts::FRAC_PI_3;
        assert!(t >= root && t - root <= LOCATE_TOL, "{t} vs {root}");
        // a kink (|.|-like, as lambda at a mesh event) and a function stuck at the ends
        let h = |t: f64| {
            if t < 0.3 {
                1.0 - t
            } else {
                0.7 - 100.0 * (t - 0.3)
            }
        };
        let t = locate(h, 0.0, h(0.0), 1.0, h(1.0));
        assert!((t - 0.307).abs() <= 2.0 * LOCATE_TOL, "{t}");
    }

    #[test]
    fn monitor_flags_survive_their_encoding() {
        for b in 0..128u32 {
            let m = Monitor::from_bits(b, 1.5);
            assert_eq!(m.bits(), b);
            assert_eq!(m.t_checked, 1.5);
        }
        let m = Monitor::new(0.0, true, -1.0, true);
        assert!(m.lift_off && m.reversed && m.pending_lift_off && m.pending_reversal);
        // Standstill is inside the model (laws 1 and 3 creep there).
        assert!(!Monitor::new(0.0, false, 0.0, false).reversed);
        assert!(m.overload && m.pending_overload);
        let m = Monitor::new(0.0, false, f64::NAN, false);
        assert!(!m.lift_off && m.reversed, "NaN speed counts as outside");
    }
}
