//! Mesh events: where a contact line end crosses sigma_A, sigma_C or sigma_E (f has a kink,
//! or a jump for spur pairs). The stepper asks [`Simulation::next_mesh_event`] where to end
//! its next internal step; the events are predicted from the mesh phase and located on the
//! collocation polynomial.

use super::Simulation;
use crate::radau5::{self, Problem, RhsError};
use crate::rotor::{idx, RotorProblem, NY};
use nalgebra::{SMatrix, SVector};

/// The kind of mesh event ([`Simulation::event_phases`]) where the sliding on a line
/// reverses (the pitch line).
pub(super) const REVERSAL: usize = 1;

/// Mesh events closer than this fraction of a base-pitch passage to the current time are
/// skipped (the kink then lies within the first 74 ns of a step at the default speed).
/// 1e-6 before: two events that nearly coincide cost a sliver step of ~2 ns and a new LU.
/// Measured with [`MESH_EVENT_RESUME`] over 7 cases (default, spur, mu 0.01, omega1 100
/// and 600 rad/s, rtol 1e-4 and 1e-8; 0..100 ms): see `MESH_EVENT_RESUME`.
pub(super) const MESH_EVENT_MERGE: f64 = 1e-4;

/// Spur pairs (f jumps at the events): events closer than this fraction of a base pitch
/// are skipped, and f is taken from after them ([`Simulation::f_after_event`]).
pub(super) const JUMP_MERGE: f64 = 1e-6;

/// Spur pairs: a step stops this fraction of a base pitch before a located jump (74 ps at
/// the default speed), so that it never ends a hair after it.
pub(super) const JUMP_MARGIN: f64 = 1e-7;

/// RADAU5 `resume_after_stop` for the simulation: after a step that ended on a mesh event
/// (a kink of f), the next starts at no more than 0.8 of the proposal from before the
/// event, which was made on the smoother side and got ~10 % of all steps rejected.
/// Work over the 7 cases of [`MESH_EVENT_MERGE`] (f evaluations + 15 per Jacobian + 8.6 per
/// LU pair + 4.1 per Newton solve + 1.8 per step, weights from callgrind instruction counts
/// of the default case): 646k with 1.0 and 1e-6, 609k with 1.0 and 1e-3, 585k with 0.8
/// and 1e-4 (default case alone 60.5k to 52.9k: 308 to 179 Jacobians, 250 to 168
/// rejections); flat between 0.5 and 0.8; errors against rtol/1000 runs unchanged in size.
pub(super) const MESH_EVENT_RESUME: f64 = 0.8;

/// Mesh-event stops only above this friction coefficient (laws 1 and 2, whose coefficient
/// is the parameter mu; laws 3 and 4 ignore mu and always use them). Measured CPU per 10 ms
/// (default case, one doStep) without / with stops: mu = 0.001: 1.6 / 2.3 ms; 0.003: 2.3 / 2.5;
/// 0.01: 3.5 / 3.1; 0.02: 4.3 / 3.4; 0.05: 5.5 / 3.5; 0.1: 6.4 / 4.2.
pub(super) const MESH_EVENT_MIN_MU: f64 = 0.005;

/// [`RotorProblem`] with f evaluated at phi1 + dphi (the right-hand limit at a mesh event
/// of a spur pair, [`Simulation::f_after_event`]).
pub(super) struct PhaseAhead<'a> {
    inner: &'a mut RotorProblem,
    dphi: f64,
}

impl Problem<NY> for PhaseAhead<'_> {
    fn rhs(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        f: &mut SVector<f64, NY>,
    ) -> Result<(), RhsError> {
        let mut ya = *y;
        ya[idx::PHI1] += self.dphi;
        self.inner.rhs(t, &ya, f)
    }
    fn jacobian(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        jac: &mut SMatrix<f64, NY, NY>,
    ) -> Result<bool, RhsError> {
        self.inner.jacobian(t, y, jac)
    }
    fn jacobian_fast(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        fast: &mut SMatrix<f64, NY, NY>,
    ) -> Result<bool, RhsError> {
        self.inner.jacobian_fast(t, y, fast)
    }
    fn mass(&self) -> Option<SMatrix<f64, NY, NY>> {
        self.inner.mass()
    }
}

impl Simulation {
    /// Time of the next mesh event before `t_end` (else `t_end`): an end of a contact line
    /// crossing sigma_A, sigma_C or sigma_E (model.md §3.4, §4). There f has a kink (the
    /// contact length or the sliding direction on a segment changes its law), and a RADAU5
    /// step straddling it is rejected or needs new Jacobians; a step that ends on it is not.
    /// The mesh phase s advances at r_b1 omega1 (the theta, alpha rates of the centre motion
    /// are ~1e-5 of that); predicted from the current state after every step, so the error
    /// does not accumulate. Events closer than [`MESH_EVENT_MERGE`] of a base-pitch passage
    /// are skipped. Spur pairs (jumps, not kinks): the reversal at sigma* instead of
    /// sigma_C, jumps located on the collocation polynomial ([`Simulation::locate_event`])
    /// and landed on from before, [`JUMP_MERGE`] instead (docs/fmu.md "Mesh events").
    /// Measured (default case, rtol 1e-6, 10 ms in one doStep): 291 accepted + 120 rejected
    /// steps, 87 Jacobians, 5.5 ms CPU without (when the stops were introduced); with them
    /// as the code stands 317 + 16, 26 Jacobians, 2.4 ms (docs/fmu.md "Mesh events").
    pub(super) fn next_mesh_event(&self, t_end: f64) -> f64 {
        let t = self.solver.t();
        let jumps = self.events_jump();
        let merge = if jumps { JUMP_MERGE } else { MESH_EVENT_MERGE };
        let Some((gap, rate, p, which)) = self.mesh_event_gap(merge) else {
            return t_end;
        };
        let eps = merge * p;
        let mut te = t + gap / rate;
        // A jump must be landed on from before it, to a small fraction of a step: the
        // linear prediction is off by ~0.2 % of the gap at sigma* (it moves with the
        // velocities), so when the next step can reach the event, locate it on the
        // collocation polynomial of the last step and stop JUMP_MARGIN before it.
        if jumps && te - t < 2.0 * self.solver.h() {
            if let Some(tr) = self.locate_event(which, t, te) {
                te = (tr - JUMP_MARGIN * p / rate).max(t + 0.5 * (tr - t));
            }
        }
        // An event just before t_end would leave a sliver of a step: end at t_end then.
        if te < t_end - eps / rate {
            te
        } else {
            t_end
        }
    }

    /// Spur pairs: f jumps at the mesh events (a whole line enters, leaves or reverses
    /// its sliding at once); helical pairs have kinks there.
    pub(super) fn events_jump(&self) -> bool {
        self.problem.model.geometry().tan_beta_b == 0.0
    }

    /// The mesh phase s of `y` and the positions of the events of kind `which` (0:
    /// sigma_A, 1: sliding reversal, 2: sigma_E) at both face ends, or None where events
    /// are not used (see [`Simulation::next_mesh_event`]).
    pub(super) fn event_phases(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
    ) -> Option<(f64, [[f64; 2]; 3])> {
        let model = &self.problem.model;
        let g = model.geometry();
        let m = model.mesh(t, y).ok()?;
        // Without friction f has no kinks there (the normal force does not depend on the
        // contact lines); with little friction the kinks are mild and the stops cost more
        // steps than they save (see MESH_EVENT_MIN_MU).
        let usable = y[idx::OMEGA1] > 0.0
            && m.z_hi > m.z_lo
            && model.coulomb_mu().is_none_or(|mu| mu > MESH_EVENT_MIN_MU);
        if !usable {
            return None;
        }
        let s_ph = g.mesh_phase(&m, y[idx::PHI1], model.params().psi0);
        let u1z = m.c1.z;
        let w = [(m.z_lo - u1z) * g.tan_beta_b, (m.z_hi - u1z) * g.tan_beta_b];
        // The sliding on a line reverses where x(sigma) = x_base + (omega1 + omega2) sigma
        // = 0 (friction.rs): at the pitch point r_b1 tan(alpha) in rigid rotation. For spur
        // pairs, where the whole line reverses at once, the centre velocities and the speed
        // fluctuation move it by ~1e-5 m (~1 us) at the defaults, far more than a landing
        // may miss; for helical pairs (kinks, not jumps) the pitch point is close enough.
        let v = idx::V;
        let (w1, w2) = (y[idx::OMEGA1], y[v + 6]);
        let sigma_rev = if self.events_jump() && w1 + w2 > 0.0 {
            let dv_w = (y[v + 3] - y[v]) * m.cos_psi + (y[v + 4] - y[v + 1]) * m.sin_psi;
            (w2 * m.len_t1t2 - dv_w) / (w1 + w2)
        } else {
            g.rb1 * m.alpha.tan()
        };
        // Laws without a sign jump at the reversal (regularised, EHL): no event there
        // (a NaN phase is never the nearest event); none either while a line sticks there
        // (`sim::stick`: the stuck line sits on it, and its end is a located state event).
        let sigma_rev = if model.params().friction_law.sharp_reversal() && !model.stick() {
            sigma_rev
        } else {
            f64::NAN
        };
        let sig = [m.sigma_a, sigma_rev, m.sigma_e];
        Some((s_ph, sig.map(|s| [s + w[0], s + w[1]])))
    }

    /// Mesh phase from the current state to the next mesh event at least `skip` base
    /// pitches ahead, the phase rate r_b1 omega1, p_bt, and the kind of that event (see
    /// [`Simulation::event_phases`]); None where events are not used.
    pub(super) fn mesh_event_gap(&self, skip: f64) -> Option<(f64, f64, f64, usize)> {
        let (t, y) = (self.solver.t(), self.solver.y());
        let (s_ph, ev) = self.event_phases(t, y)?;
        let g = self.problem.model.geometry();
        let (p, rate) = (g.p_bt, g.rb1 * y[idx::OMEGA1]);
        let eps = skip * p;
        let mut best = (f64::INFINITY, 0);
        for (kind, pair) in ev.iter().enumerate() {
            for &e in pair {
                let mut gap = crate::gear::contact_lines::reduce(e - s_ph, p);
                if gap < eps {
                    gap += p;
                }
                if gap < best.0 {
                    best = (gap, kind);
                }
            }
        }
        Some((best.0, rate, p, best.1))
    }

    /// Time of the next event of kind `which` as the root of its signed phase distance
    /// along the collocation polynomial of the last step (extrapolated), by the secant
    /// method from the linear prediction `te`. None if it does not converge to 1e-9 of a
    /// pitch or leaves (t, t + 2 (te - t)) (e.g. right after a restart, when the
    /// polynomial is flat).
    pub(super) fn locate_event(&self, which: usize, t: f64, te: f64) -> Option<f64> {
        let g = self.problem.model.geometry();
        let p = g.p_bt;
        let dist = |tau: f64| -> Option<f64> {
            let mut y = SVector::<f64, NY>::zeros();
            self.solver.dense_output(tau, &mut y);
            let (s_ph, ev) = self.event_phases(tau, &y)?;
            // Signed, in (-p/2, p/2]; the nearer face end (equal for spur pairs).
            let d = |e: f64| crate::gear::contact_lines::reduce(e - s_ph + 0.5 * p, p) - 0.5 * p;
            let (a, b) = (d(ev[which][0]), d(ev[which][1]));
            Some(if a.abs() <= b.abs() { a } else { b })
        };
        let (mut t0, mut d0) = (t, dist(t)?);
        let (mut t1, mut d1) = (te, dist(te)?);
        for _ in 0..8 {
            if d1.abs() <= 1e-12 * p {
                break;
            }
            let slope = (d1 - d0) / (t1 - t0);
            if slope.is_nan() || slope >= 0.0 {
                return None;
            }
            let t2 = t1 - d1 / slope;
            (t0, d0) = (t1, d1);
            t1 = t2;
            d1 = dist(t1)?;
        }
        (d1.abs() <= 1e-9 * p && t1 > t && t1 < t + 2.0 * (te - t)).then_some(t1)
    }

    /// Spur pairs: after a step that landed on a mesh event (from before it, by
    /// JUMP_MARGIN), f there is still the value from before the jump, and the next step,
    /// whose stages all lie after it, would compare against it in its error estimate and
    /// be rejected again and again. Replace f by its limit from after the event: f at the
    /// same state with phi1 advanced past the event (by at most JUMP_MERGE of a pitch, the
    /// events closer than that being skipped next).
    pub(super) fn f_after_event(&mut self) -> Result<(), radau5::Error> {
        if !self.events_jump() {
            return Ok(());
        }
        let Some((gap, _, p, _)) = self.mesh_event_gap(0.0) else {
            return Ok(());
        };
        if gap >= JUMP_MERGE * p {
            return Ok(());
        }
        let dphi = (gap + 1e-9 * p) / self.problem.model.geometry().rb1;
        // lambda jumps with the friction too (through B of the hidden constraint, model.md
        // §7), but re-projecting it here measured worse (spur, 0..100 ms: 279 instead of
        // 1005 rejections, yet 5387 instead of 4422 accepted steps and twice the
        // Jacobians): the stepper's own lambda is kept.
        let y = *self.solver.y();
        let mut after = PhaseAhead {
            inner: &mut self.problem,
            dphi,
        };
        self.solver.refresh_f(&mut after, y)
    }
}
