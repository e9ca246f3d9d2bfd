//! Real-time mode (`h_fixed > 0`): every doStep does the same, bounded amount of work.
//!
//! A doStep over `[t, t + H]` takes `n = ceil(H / h_fixed)` internal steps of exactly
//! `H / n` (the largest divisor of H not above `h_fixed`), each a fixed-step RADAU5 step
//! with [`NEWTON_ITERATIONS`] simplified Newton iterations (`Radau5::fixed_step`): no error
//! control, no rejection, no look-ahead, no mesh-event stops. The Jacobian and the LU pair
//! are renewed (`Radau5::fixed_prepare`) at the start of a doStep on a fixed schedule of
//! the time grid ([`jacobian_period`]): every doStep when H >= [`JACOBIAN_INTERVAL`], else
//! every m-th, so that J is never older than [`JACOBIAN_INTERVAL`] (as with one J per
//! doStep of H = 1e-4 s). So the work of every doStep is `3 n NEWTON_ITERATIONS` f
//! evaluations and `n NEWTON_ITERATIONS` linear solves, plus 1 Jacobian and 1 LU pair on
//! the scheduled doSteps (all of them for H >= 1e-4 s), whatever the inputs do; off the
//! schedule also after a new tunable, a failed doStep or a new internal step size (more
//! than round-off of t away from the LU pair's). A new input function
//! (or tunable) at the communication point re-projects lambda onto the hidden constraint
//! as in the adaptive mode, without an f evaluation (the fixed step needs none at its
//! start). A Newton iteration that has not converged within its fixed count ends the
//! doStep with [`SimError::Solver`] (`fmi2Discard`), the state at the last completed
//! internal step - except with elastic teeth, where such a step is first taken once more
//! with a new Jacobian and [`RETRY_ITERATIONS`] (a flank setting in or letting go, the
//! mesh mode's start transient): up to 1 Jacobian, 1 LU pair and `3 RETRY_ITERATIONS` f
//! more per failed step, a bound still.
//!
//! Accuracy against the adaptive mode: docs/fmu.md "Real-time mode".

use super::{solver_err, SimError, Simulation, StepReport, NY};
use crate::parameter::ParamError;
use crate::rotor::GearedRotor;
use nalgebra::SVector;

/// Simplified Newton iterations per internal step (fixed, never fewer, never more).
/// Measured at the default case, rtol 1e-6, omega1 changing at every point: 2 iterations
/// fail the convergence test (at t = 0 for h >= 5e-5 s, where the Newton start is zero,
/// and at t = 0.59 s for H = 1e-4 s, h_fixed = 2.5e-5 s with constant inputs); 3 pass for
/// H in {1e-5, 1e-4, 1e-3} s and h_fixed in {1e-5, 2.5e-5, 5e-5, 1e-4} s, and change T1 by
/// less than 1e-9 relative against 2 where both pass.
pub const NEWTON_ITERATIONS: u32 = 3;

/// Newton iterations of the one retry of a fixed step of the elastic contact whose
/// iteration failed (with a new Jacobian). Measured: the elastic default pair from rest
/// under 50 N m at h_fixed = 2.5e-5 s failed at t = 0.125 ms with 3 (scaled increment 131
/// after the third, contraction 0.026: converging, but from far away).
pub const RETRY_ITERATIONS: u32 = 7;

/// Longest time (s) one Jacobian and LU pair serve in the real-time mode: with one J
/// per doStep of H = 1e-4 s (4 steps of h_fixed = 2.5e-5 s) the 3 Newton iterations
/// converge (docs/fmu.md "Real-time mode"); shorter doSteps renew J at the same age, not
/// at every doStep. Measured at H = 1e-5 s, h_fixed = 2.5e-5 s (`closed_loop_bench`,
/// omega1 new at every point): J + LU are ~7 us of a ~15 us doStep; with them on every
/// 10th doStep the median call is 7.9-8.0 us (was 15.0-15.1), CPU per 10 ms 9.1-9.3 ms
/// (was 15.2-15.4; 0.65x -> 1.1x real time); the doSteps that renew them stay at ~15 us.
/// Measured and not kept: 4e-4 s, which would renew J on every 4th doStep of H = 1e-4 s
/// too (h_fixed = 2.5e-5 s: median call 32.5 -> 26.4 us, CPU per 10 ms 3.29 -> 2.76 ms;
/// h_fixed = 1e-4 s: 15.0 -> 8.2 us; the accuracy figures of `realtime_accuracy` equal to
/// 3 digits), but gives up equal work per doStep at the H = 1e-4 s.
pub const JACOBIAN_INTERVAL: f64 = 1e-4;

/// Every how many doSteps of length `span` the Jacobian and the LU pair are renewed: the
/// largest m with `m span <= JACOBIAN_INTERVAL` (relative slack 1e-6 for the master's
/// rounding of the span, ulps of t), at least 1. A doStep from t renews them when `round(t / span)` is a multiple
/// of m (derived from time, so a restored or deserialised state follows the same
/// schedule).
pub fn jacobian_period(span: f64) -> u64 {
    ((JACOBIAN_INTERVAL / span) * (1.0 + 1e-6)).floor().max(1.0) as u64
}

/// Whether the doStep `[t, t + span]` is on the schedule of [`jacobian_period`]. The grid
/// index `round(t / span)` carries the round-off of the span (ulps of t over H): exact to
/// well below 1/2 up to t / H ~ 1e7 (100 s at H = 1e-5 s); beyond, a renewal may come one
/// doStep early or late (J then at most (m + 1) H old).
pub fn jacobian_due(t: f64, span: f64) -> bool {
    let m = jacobian_period(span);
    m == 1 || ((t / span).round() as i64).rem_euclid(m as i64) == 0
}

/// Whether an LU pair for the internal step `h_lu` serves a doStep ending at `t_end` with
/// n internal steps of h: the spans `t_end - t` of a master's grid differ from H and from
/// each other by round-off of t only (a few ulps of t: 1.4e-9 of H = 1e-5 s at t = 100 s),
/// so h and h_lu may differ by that over n and no more (the step is then taken with
/// `h_lu`, landing on `t_end` exactly all the same).
fn lu_serves(h_lu: f64, h: f64, n: u64, t_end: f64) -> bool {
    (h_lu - h).abs() <= 8.0 * f64::EPSILON * (t_end.abs() / n as f64 + h)
}

/// Number of internal steps of a doStep of length `span`: the smallest n with
/// `span - slack <= n h_fixed`. `slack` absorbs the master's rounding of the
/// communication points (`t_end - t` differs from its H by up to a few ulps of t, which
/// at t = 100 s is 1e-9 of H = 1e-5 s), so that `H = k h_fixed` gives exactly k steps.
pub fn internal_steps(span: f64, h_fixed: f64, slack: f64) -> u64 {
    ((span - slack) / h_fixed).ceil().max(1.0) as u64
}

impl Simulation {
    /// The real-time step size `h_fixed` (0: adaptive mode).
    pub fn h_fixed(&self) -> f64 {
        self.h_fixed
    }

    /// Selects the mode: `h_fixed = 0` adaptive RADAU5 (the default), `h_fixed > 0` the
    /// real-time mode (module docs). Meant to be set once before the first step.
    ///
    /// # Errors
    /// [`SimError::Param`] for a negative or non-finite value.
    pub fn set_h_fixed(&mut self, h_fixed: f64) -> Result<(), SimError> {
        check_h_fixed(h_fixed)?;
        check_pair(&self.problem.model, h_fixed, "h_fixed", h_fixed)?;
        self.h_fixed = h_fixed;
        Ok(())
    }

    /// doStep in the real-time mode over `[t, t_end]` (checked by the caller).
    pub(super) fn do_step_fixed(&mut self, t: f64, t_end: f64) -> Result<StepReport, SimError> {
        let stats0 = *self.solver.stats();
        let mut report = StepReport {
            first_change_time: f64::NAN,
            ..StepReport::default()
        };
        let fail = |sim: &mut Simulation, e: SimError| {
            sim.last_successful_time = sim.time();
            sim.restart_pending = true;
            Err(e)
        };
        // A new tunable (J changes) or a failed doStep: renew J and the LU pair now.
        let renew_now = self.restart_pending;
        if self.change_pending() {
            // Only after a switch from the adaptive mode can the stepper be ahead.
            let y = match self.restart_state(t) {
                Ok(y) => y,
                Err(e) => return fail(self, e),
            };
            if let Err(e) = self.solver.fixed_set_point(y) {
                return fail(self, solver_err(e, t));
            }
            self.set_comm(t);
            self.restart_pending = false;
            report.restarted = true;
        }
        self.inputs_ref = *self.problem.model.inputs();
        self.der_set = [false; 2];
        // Validity (validity.rs) as in the adaptive mode: conditions of the start state.
        if self.validity.pending_lift_off
            || self.validity.pending_reversal
            || self.validity.pending_overload
        {
            self.start_violations(&mut report)?;
        }
        let slack = super::comm_tolerance(t_end, t_end - t);
        let n = internal_steps(t_end - t, self.h_fixed, slack);
        let mut h = (t_end - t) / n as f64;
        // Progress (radau5.f's rule, as in the adaptive loop): t must resolve the step.
        if h.is_nan() || h <= super::STEP_RESOLUTION * t.abs() {
            let e = crate::radau5::Error::StepSizeTooSmall { t, h };
            return fail(self, solver_err(e, t));
        }
        // J and the LU pair: renewed on the schedule, else kept (with their h, which
        // differs from this doStep's by rounding only).
        let kept = self
            .solver
            .fixed_lu_step()
            .filter(|&h_lu| lu_serves(h_lu, h, n, t_end));
        match kept {
            Some(h_lu) if !renew_now && !jacobian_due(t, t_end - t) => h = h_lu,
            _ => {
                if let Err(e) = self.solver.fixed_prepare(&mut self.problem, h) {
                    return fail(self, solver_err(e, t));
                }
            }
        }
        for k in 1..=n {
            // Bounded work per doStep (`max_internal_steps`), as in the adaptive mode.
            self.check_work(k - 1, t_end)?;
            let tk = if k == n { t_end } else { t + k as f64 * h };
            let mut r = self
                .solver
                .fixed_step(&mut self.problem, h, tk, NEWTON_ITERATIONS);
            if matches!(r, Err(crate::radau5::Error::FixedStepNewton { .. }))
                && self.problem.model.contact().has_contact_events()
            {
                // An elastic flank set in or let go inside the step (the contact stiffness
                // in J appeared or vanished), or the mesh mode's start transient: once, a
                // new J and LU pair here and the step again with RETRY_ITERATIONS (the
                // state is unchanged after a failed fixed step; the work stays bounded).
                r = self
                    .solver
                    .fixed_prepare(&mut self.problem, h)
                    .and_then(|()| {
                        self.solver
                            .fixed_step(&mut self.problem, h, tk, RETRY_ITERATIONS)
                    });
            }
            match r {
                Ok(tn) => {
                    let y: SVector<f64, NY> = *self.solver.y();
                    // Contact onsets and separations: crossed, located for the report.
                    self.note_contact_crossings(&mut report);
                    self.track_contact(tn, &y, &mut report);
                    self.check_validity(tn, &y, &mut report)?;
                    // Creep of laws 1 and 3 (`creep`): switched at the end of the step in
                    // which the rolling speed crossed, with a new J and LU pair.
                    if self.creep_switch_due() {
                        let r = self.switch_creep(&mut report).and_then(|()| {
                            self.solver
                                .fixed_prepare(&mut self.problem, h)
                                .map_err(|e| solver_err(e, tn))
                        });
                        if let Err(e) = r {
                            self.set_comm(tn);
                            return fail(self, e);
                        }
                    }
                }
                Err(e) => {
                    let ts = self.solver.t();
                    self.set_comm(ts);
                    return fail(self, solver_err(e, ts));
                }
            }
        }
        self.set_comm(t_end);
        self.last_successful_time = t_end;
        report.stats = self.solver.stats().since(&stats0);
        report.contact_lost = self.contact_lost;
        Ok(report)
    }
}

/// `h_fixed` must be 0 (adaptive) or a positive finite step size.
/// The real-time mode (`h_fixed > 0`) refuses a spur pair with friction: its friction jumps
/// where a contact line enters, leaves or crosses the pitch line, and a line can stick
/// there, which fixed steps cannot locate. Checked when the mode is set and when mu is tuned
/// (a spur pair started with mu = 0).
/// The error names `name` with `value` (the parameter that was just set).
pub(super) fn check_pair(
    model: &GearedRotor,
    h_fixed: f64,
    name: &'static str,
    value: f64,
) -> Result<(), ParamError> {
    let friction = model.coulomb_mu().is_none_or(|mu| mu > 0.0);
    if h_fixed > 0.0 && model.geometry().tan_beta_b == 0.0 && friction {
        return Err(ParamError {
            name,
            value,
            requirement: "no real-time mode (h_fixed > 0) for a spur pair with friction \
                          (beta = 0): its friction jumps where a contact line enters, leaves or \
                          crosses the pitch line, and a line can stick there; fixed steps cannot \
                          locate these events (the first steps fail the Newton test whatever \
                          h_fixed). Use the adaptive mode (h_fixed = 0), a helical pair \
                          (beta != 0) or mu = 0"
                .into(),
        });
    }
    Ok(())
}

pub(super) fn check_h_fixed(h_fixed: f64) -> Result<(), ParamError> {
    if h_fixed >= 0.0 && h_fixed.is_finite() {
        Ok(())
    } else {
        Err(ParamError {
            name: "h_fixed",
            value: h_fixed,
            requirement: "h_fixed = 0 (adaptive RADAU5) or 0 < h_fixed < inf (real-time mode)"
                .into(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{internal_steps, jacobian_due, jacobian_period};

    #[test]
    fn jacobian_schedule_keeps_its_age_below_the_interval() {
        assert_eq!(jacobian_period(1e-4), 1);
        assert_eq!(jacobian_period(1e-3), 1);
        assert_eq!(jacobian_period(5e-5), 2);
        assert_eq!(jacobian_period(1e-5), 10);
        assert_eq!(jacobian_period(3e-5), 3);
        // Spans with the round-off of t (at t = 0.1 s and t = 100 s; the latter 1.4e-9 of H).
        assert_eq!(jacobian_period(0.1 + 1e-5 - 0.1), 10);
        assert_eq!(jacobian_period((100.0 + 1e-5) - 100.0), 10);
        assert_eq!(jacobian_period(1e-5 * (1.0 + 1e-8)), 10);
        let due: Vec<bool> = (0..21)
            .map(|k| jacobian_due(k as f64 * 1e-5, 1e-5))
            .collect();
        for (k, d) in due.iter().enumerate() {
            assert_eq!(*d, k % 10 == 0, "doStep {k}");
        }
        assert!((0..50).all(|k| jacobian_due(k as f64 * 1e-4, 1e-4)));
    }

    #[test]
    fn internal_step_is_the_largest_divisor_not_above_h_fixed() {
        let n =
            |span: f64, hf: f64| internal_steps(span, hf, super::super::comm_tolerance(1.0, span));
        assert_eq!(n(1e-4, 2.5e-5), 4);
        assert_eq!(n(1e-4, 3e-5), 4);
        assert_eq!(n(1e-4, 1e-4), 1);
        assert_eq!(n(1e-5, 2.5e-5), 1);
        assert_eq!(n(1e-3, 1e-5), 100);
        assert_eq!(n(1.1e-4, 1e-4), 2);
        // 0.1 + 0.2 = 0.30000000000000004 in floating point; the master meant 0.3.
        assert_eq!(n(0.1 + 0.2, 0.1), 3);
        // A communication step at t = 100 s: t_end - t is H up to ulps of t.
        let (t, h) = (100.0, 1e-5);
        assert_eq!(
            internal_steps((t + h) - t, h, super::super::comm_tolerance(t + h, h)),
            1
        );
    }
}
