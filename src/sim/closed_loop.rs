//! Closed loop in the adaptive mode: inputs new at every communication point. Such a
//! doStep is not taken ahead (`Simulation::do_step`), so it ends exactly on the
//! communication point; two choices make that cheap (measured with
//! `examples/closed_loop_bench.rs`, default pair, omega1 = 314.159 (1 + 0.01 sin(2 pi 50 t))
//! held and new at every point, 1 s, work per doStep of H = 1e-4 s):
//!
//! - the interval is cut into equal internal steps ([`Simulation::closed_loop_stop`]) instead of
//!   natural steps and a short clipped one: the LU pair is reused between equal steps and
//!   from one doStep to the next (clipped steps of equal length, radau5 `step`), and no
//!   sliver step follows a long one;
//! - mesh-event stops are used when H exceeds [`EVENT_STOPS_MIN_SPAN`] of the mean event
//!   spacing (they were only used from one spacing up).
//!
//! | per doStep | before | events | equal steps | both |
//! |---|---|---|---|---|
//! | f evaluations | 28.3 | 20.8 | 25.6 | 20.4 |
//! | rejections | 1.49 | 0.43 | 0.85 | 0.011 |
//! | Jacobians | 1.17 | 0.46 | 0.64 | 0.16 |
//! | LU pairs | 5.04 | 3.68 | 2.73 | 1.94 |
//!
//! The parts are those of the interval up to the next mesh event (or the point), so that
//! no sliver step is left before an event: f per doStep 20.41 -> 20.14 (with input
//! derivatives 16.10 -> 15.05) against cutting [t, t_end] and stopping at events in
//! between.
//!
//! Not kept: parts up to 1.1, 1.2, 1.3, 1.5 times the proposal (fewer, longer steps):
//! rejections 0.011 -> 0.28-0.35 and LU pairs 1.94 -> 2.6-3.2 per doStep, f 20.4 -> 20.9-21.2.
//! What remains against constant inputs (11.6 f, 2.2 steps per doStep with look-ahead) is
//! the step count: 3.6 internal steps per doStep of about the same cost each, as every
//! doStep must end on its communication point (the input changes there).
//!
//! Since a step after a mesh-event stop measures its own Newton rate (accuracy, docs/fmu.md
//! "Mesh events"): 21.6 f, 0.20 Jacobians, 1.92 LU pairs per doStep (rigid, the `omega1`
//! case). Since a clipped step reuses only an LU pair of its own h (radau5 `step`; the
//! parts of intervals cut at mesh events differ in length, and an LU pair of another h
//! slowed Newton to a contraction of up to 0.17, which also renewed J): 19.7 f, 0.036
//! Jacobians, 2.03 LU pairs per doStep (elastic teeth: 27.6 f, 0.39 J, 2.51 LU -> 25.5 f,
//! 0.23 J, 2.74 LU), and 8-10 % less CPU. With the split Jacobian of the elastic contact
//! (radau5.md §8): 25.6 f, 0.046 full J and 0.20 renewals of its fast part, 2.77 LU pairs
//! per doStep, 2.82 ms per simulated 10 ms against the rigid 2.06 ms.
//!
//! At H = 1e-5 s (one internal step per doStep either way) event stops cost more than they
//! save (f 5.65 -> 5.85, LU pairs 0.035 -> 0.22 per doStep), hence the threshold; the equal
//! steps change nothing there (5.63 f, 0.022 LU pairs).
//!
//! What the remaining steps are for (docs/fmu.md "Closed loop"): with a held omega1 the
//! error estimate is dominated by the drive filter's state omega1' (the largest term in 88 %
//! of the steps), whose response to the staircase input has ~10x the error per h^4 of a
//! smooth input; even with that state left out of the norm the f count stays 1.5x that of
//! constant inputs. A Newton start shifted by the jump of y' at the change was measured and
//! not kept (fewer iterations at H = 1e-5 s, but more Jacobians and LU pairs, and worse at
//! H = 1e-4 s).

use super::Simulation;

/// Mesh-event stops in a doStep without look-ahead from this fraction of the mean spacing
/// of the events (6 per base pitch; 123 us at the default speed, so H = 1e-4 s uses them
/// and H = 1e-5 s does not).
pub(super) const EVENT_STOPS_MIN_SPAN: f64 = 0.5;

impl Simulation {
    /// Next stop time of a doStep that ends exactly on `t_end` (no look-ahead), and
    /// whether it is a mesh event: the interval up to the next event (with `use_events`)
    /// or to `t_end` cut into the fewest equal parts not longer than the stepper's
    /// proposal (1e-9 relative slack, so that a proposal equal to the part gives no extra
    /// step).
    pub(super) fn closed_loop_stop(&self, t_end: f64, use_events: bool) -> (f64, bool) {
        let stop = if use_events {
            self.next_mesh_event(t_end)
        } else {
            t_end
        };
        let t = self.solver.t();
        let rem = stop - t;
        let n = (rem / self.solver.h() * (1.0 - 1e-9)).ceil();
        if n <= 1.0 {
            (stop, stop < t_end)
        } else {
            (t + rem / n, false)
        }
    }
}
