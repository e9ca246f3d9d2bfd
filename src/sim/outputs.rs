//! Outputs at the FMU time, with lambda from the hidden constraint, and their first
//! derivatives from the dense output.

use super::Simulation;
use crate::rotor::{Outputs, NY};
use nalgebra::SVector;

/// Relative width of the central difference on the dense output used for output
/// derivatives: delta = 1e-3 (t - t_prev). The collocation polynomial is cubic, so the
/// truncation error is ~1e-7 relative, far below the solver tolerance.
pub(super) const DERIVATIVE_DELTA: f64 = 1e-3;

impl Simulation {
    /// All outputs at the current time (model.md §6), with lambda from the hidden
    /// constraint (see [`Simulation::output_state`]).
    pub fn outputs(&self) -> Outputs {
        let t = self.time();
        // = outputs(t, output_state(t, y)) with one mesh/friction evaluation instead of two.
        let mut o = self.problem.model.outputs_consistent(t, &self.y_comm);
        o.impacts = self.impacts;
        o
    }

    /// The state for the outputs, as the contact gives it (`Contact::output_state`): for
    /// rigid teeth y with lambda replaced by the value the hidden constraint gives for the
    /// differential states (model.md §7, `GearedRotor::consistent_lambda`); for elastic
    /// teeth y itself.
    ///
    /// Why: lambda is an index-2 variable; RADAU5 controls its error only scaled by h, and
    /// the step that lands on a communication point is clipped and may be very short, so the
    /// lambda of the stepper there can be off by ~1e-3 relative (seen at the frictionless
    /// static equilibrium with 10 ms communication steps: spikes of +-8.5e-4 while the
    /// consistent value is within 1e-8). The consistent value depends only on q, v and the
    /// filter state, which are accurate to the tolerance. Falls back to the stepper's
    /// lambda where the model cannot decide (friction-induced ambiguity). The elastic
    /// contact has no multiplier: its last slot, the work stored in the mesh springs, is a
    /// differential state (writing Fn there, as before this seam, made the output
    /// derivative of `w_mesh_stiffness` that of `e_mesh_spring - Fn`).
    pub fn output_state(&self, t: f64, y: &SVector<f64, NY>) -> SVector<f64, NY> {
        self.problem.model.contact().output_state(t, y)
    }

    /// Outputs at `time() - delta` and `time() + delta` on the collocation polynomial of the
    /// last step, and `delta`, for central-difference output derivatives (order 1). Before
    /// the first step, and when an input or a tunable changed at the FMU time (the
    /// polynomial is that of the old f: the derivative from after the change is wanted), the
    /// state is extrapolated with y' from M y' = f (lambda from the hidden constraint, held).
    pub fn outputs_for_derivative(&mut self) -> (Outputs, Outputs, f64) {
        let t = self.time();
        let tp = self.solver.t_prev();
        let mut ym = SVector::<f64, NY>::zeros();
        let mut yp = SVector::<f64, NY>::zeros();
        let delta;
        if tp < t && self.solver.stats().naccpt > 0 && !self.change_pending() {
            delta = DERIVATIVE_DELTA * (self.solver.t() - tp);
            self.solver.dense_output(t - delta, &mut ym);
            self.solver.dense_output(t + delta, &mut yp);
        } else {
            delta = 1e-9;
            // The contact's state for the current inputs and tunables (rigid: lambda
            // consistent with them, it enters M y' = f).
            let y = self.output_state(t, &self.y_comm);
            let mut f = SVector::<f64, NY>::zeros();
            let m = self.problem.model.mass();
            let ydot = match self.problem.model.rhs(t, &y, &mut f) {
                Ok(()) => SVector::<f64, NY>::from_fn(|i, _| {
                    if m[(i, i)] != 0.0 {
                        f[i] / m[(i, i)]
                    } else {
                        0.0
                    }
                }),
                Err(_) => SVector::<f64, NY>::zeros(),
            };
            ym = y - ydot * delta;
            yp = y + ydot * delta;
        }
        let ym = self.output_state(t - delta, &ym);
        let yp = self.output_state(t + delta, &yp);
        let om = self.problem.model.outputs(t - delta, &ym);
        let op = self.problem.model.outputs(t + delta, &yp);
        (om, op, delta)
    }
}
