//! Stick of a spur contact line at the pitch line (`model.md` §4.1): the tangential force
//! that keeps a stuck line from sliding (Filippov's equivalent force), its place in f and
//! in the hidden constraint, and the indicators the simulation locates entry and exit
//! with.
//!
//! While line k sticks, its Coulomb force is replaced by an unknown force `F_w e_w` on gear
//! 2 (and `-F_w e_w` on gear 1) fixed by `d(x0)/dt = -x0 / STICK_RELAXATION` (the sliding
//! speed stays zero; the relaxation only removes the integration's drift). `x0` is linear
//! in the velocities with the gradient `w` = [`StuckLine::generalised`], which is also the
//! direction of the force in q, so with `M q'' = F + F_w w`:
//!
//! `F_w = -(x0_free + w^T M^-1 F) / (w^T M^-1 w)`                                   (4.13)
//!
//! where `F` holds every other force (springs, dampers, load, `lambda G^T`, the friction of
//! the other lines) and `x0_free` the part of `d(x0)/dt` that does not come from
//! accelerations of q: the turning of e_w and the motion of the line along the line of
//! action (positions moving at fixed velocities), `sigma0 omega1'` and the relaxation.
//! The line sticks while `|F_w| <= mu |lambda| L_k / l` (its share of the normal force).
//!
//! Rigid teeth: lambda itself depends on `F_w` (the hidden constraint), so the two are
//! solved together (`consistent_lambda_mode` in the stick mode). Elastic teeth (§3.5): the
//! normal force `Fn` is a function of positions and velocities, `Fn G^T` and the coast
//! flanks' forces are parts of `F` like the springs, and (4.13) is explicit. Under a
//! reversed load the coast flanks' line sticks the same way: it is the drive line of the
//! mirrored pair (§3.6), whose stick flags hold it, held against the drive flanks' forces
//! and the load seen through the mirror (`GearedRotor::mirrored_forces`).

use super::{kinematics, GearedRotor};
use crate::gear::contact_lines::reduce;
use crate::gear::{Friction, FrictionLaw, FrictionSums, Mesh, PitchLine, StickAction, StuckLine};
use crate::rotor::{idx, NY};
use nalgebra::SVector;

/// Time constant (s) with which a drift of the stuck line's sliding speed is pulled back to
/// zero in (4.13). Far below the bearing periods (~0.1 ms) so that it decides nothing
/// physical, above the step sizes so that it adds no stiffness the steps would have to
/// resolve: the drift it removes is of the order of the velocity tolerance (1e-8 m/s at
/// rtol 1e-6), a force of ~1e-3 m/s^2 times the effective mass.
pub const STICK_RELAXATION: f64 = 1e-3;

/// Band of sliding speeds around zero, as a fraction of the rolling speed across a base
/// pitch `(omega1 + omega2) p_bt`, in which a line just released from sticking keeps the
/// sense of sliding its stick force set (`PitchLine::Released`). Why: at the release the
/// stick force equals its bound and the sliding starts from zero with zero acceleration
/// (the force needed grows through the bound), while the integration leaves a sliding
/// speed of either sign of the order of the velocity tolerance; Coulomb's law taken at
/// that sign pushed the line back and forth across zero at every step (measured: 1000 rpm,
/// mu 0.3, rtol 1e-9: 810 steps and 250 Jacobians in the 10 us after one release). 1e-5
/// is ~100 times the speeds the stick phase leaves (3e-8 m/s at 100 rpm) and far below
/// any sliding that matters for the loss.
pub const RELEASE_BAND: f64 = 1e-5;

/// The part of (4.13) fixed by the state: `w`, `w^T M^-1 w` and `x0_free`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StickRow {
    pub(crate) w: [f64; 7],
    pub(crate) a_w: f64,
    pub(crate) free: f64,
}

impl GearedRotor {
    /// Whether a contact line can stick at all: a spur pair (the sliding is then the same
    /// along a line) with a law whose force jumps at zero sliding (laws 1 and 3) and
    /// friction (law 1: mu > 0); rigid or elastic teeth (the drive flanks).
    pub fn stick_possible(&self) -> bool {
        let law = self.params.friction_law;
        self.geom.tan_beta_b == 0.0
            && law.sharp_reversal()
            && (law != FrictionLaw::Coulomb || self.params.mu > 0.0)
    }

    /// Whether a contact line sticks at the pitch line (the stick mode of f), on either
    /// flank.
    pub fn stick(&self) -> bool {
        self.stick || self.coast_sticks()
    }

    /// Whether the stick mode and the release refer to the line of the coast flanks
    /// (elastic teeth under a reversed load; the mirrored pair holds their flags, §3.6).
    pub fn stick_flank_is_coast(&self) -> bool {
        self.stick_coast
    }

    /// Chooses the flank whose line [`GearedRotor::set_stick`] acts on: the coast flanks'
    /// (only with coast flanks) or the drive flanks'. The simulation takes the one that
    /// carries the load where a line starts to stick ([`GearedRotor::coast_carries`]).
    pub fn set_stick_flank(&mut self, coast: bool) {
        self.stick_coast = coast && self.has_coast_flanks();
    }

    /// Whether the model has coast flanks (elastic teeth, §3.6).
    pub fn has_coast_flanks(&self) -> bool {
        self.coast.is_some()
    }

    /// Whether the coast flanks carry the load at y: they push and the drive flanks are
    /// apart (elastic teeth; false where the mesh cannot be evaluated).
    pub fn coast_carries(&self, t: f64, y: &SVector<f64, NY>) -> bool {
        self.coast.is_some()
            && self.mesh(t, y).is_ok_and(|m| {
                let g = &self.geom;
                let xi = y[idx::Q + 6];
                -g.cos_beta_b * (g.gap_raw(&m, xi) + self.g0) <= 0.0
                    && self.coast_approach(&m, xi) > 0.0
            })
    }

    /// Enters or leaves the stick mode on the chosen flank's line
    /// ([`GearedRotor::set_stick_flank`]; the simulation decides, at located instants).
    /// The lambda of a state is then no longer consistent: re-project it with
    /// [`GearedRotor::consistent_lambda`]. Leaving it, `release` is the sense (+1 or -1) in
    /// which the line starts to slide (`PitchLine::Released`); entering clears it.
    pub fn set_stick(&mut self, on: bool, release: f64) {
        if self.stick_coast {
            if let Some(c) = self.coast.as_mut() {
                c.mirror_mut().set_stick(on, release);
            }
            self.stick = false;
            self.released = 0.0;
            return;
        }
        if let Some(c) = self.coast.as_mut() {
            c.mirror_mut().set_stick(false, 0.0);
        }
        self.stick = on && self.stick_possible();
        // (f64::signum(0.0) is 1: a zero release sense must stay 0.)
        self.released = if self.stick || !self.stick_possible() || release == 0.0 {
            0.0
        } else {
            release.signum()
        };
    }

    /// The sense (+1, -1) in which a just released line slides while its sliding speed is
    /// within the release band, 0 when none is released.
    pub fn released(&self) -> f64 {
        match self.coast.as_ref() {
            Some(c) if self.stick_coast => c.mirror().released,
            _ => self.released,
        }
    }

    /// Ends the release (the line left the band; the simulation decides).
    pub fn clear_release(&mut self) {
        self.released = 0.0;
        if let Some(c) = self.coast.as_mut() {
            c.mirror_mut().released = 0.0;
        }
    }

    /// Whether the stick questions at y ([`GearedRotor::stick_state`],
    /// [`GearedRotor::pitch_line_sliding`]) are about the coast flanks' line: the line that
    /// sticks or was released, else the flanks that carry the load. A line that starts to
    /// stick at y is on this flank ([`GearedRotor::set_stick_flank`]).
    pub fn watches_coast(&self, t: f64, y: &SVector<f64, NY>) -> bool {
        if self.stick() || self.released() != 0.0 {
            self.stick_coast
        } else {
            self.coast_carries(t, y)
        }
    }

    /// Half-width (m/s) of the band of `PitchLine::Released` at y: [`RELEASE_BAND`] of the
    /// rolling speed across a base pitch.
    pub fn release_band(&self, y: &SVector<f64, NY>) -> f64 {
        RELEASE_BAND * (y[idx::OMEGA1] + y[idx::V + 6]).abs() * self.geom.p_bt
    }

    /// How the line nearest zero sliding enters the friction sums at y in the given mode.
    pub(crate) fn pitch_line(&self, y: &SVector<f64, NY>, stick: bool) -> PitchLine {
        if !self.stick_possible() {
            PitchLine::Slide
        } else if stick {
            PitchLine::Stick
        } else if self.released != 0.0 && !self.creep {
            PitchLine::Released {
                sign: self.released,
                band: self.release_band(y),
            }
        } else {
            PitchLine::Slide
        }
    }

    /// (4.13)'s state part for the stuck line `st` of the mesh `m` of y.
    pub(crate) fn stick_row(&self, y: &SVector<f64, NY>, m: &Mesh, st: &StuckLine) -> StickRow {
        self.stick_row_with(y, m, st, &st.action(m, &self.geom))
    }

    /// [`GearedRotor::stick_row`] with the line's action already at hand.
    fn stick_row_with(
        &self,
        y: &SVector<f64, NY>,
        m: &Mesh,
        st: &StuckLine,
        action: &StickAction,
    ) -> StickRow {
        let g = &self.geom;
        let k = kinematics(y);
        let w = action.generalised;
        let a_w: f64 = w.iter().zip(&self.mass).map(|(wi, m)| wi * wi / m).sum();
        // Rates of the line of action at fixed velocities (model.md §3.1): a, theta, alpha,
        // psi = theta - alpha, |T1 T2| = sqrt(a^2 - R^2), and the line's sigma0 =
        // r_b1 (phi1 - psi) + const (3.10) for a spur pair.
        let d = m.c2 - m.c1;
        let dv = k.v2 - k.v1;
        let a = m.a;
        let l = m.len_t1t2;
        let a_dot = (d.x * dv.x + d.y * dv.y) / a;
        let theta_dot = (d.x * dv.y - d.y * dv.x) / (a * a);
        let alpha_dot = g.r_sum * a_dot / (a * l);
        let psi_dot = theta_dot - alpha_dot;
        let sigma_dot = g.rb1 * (k.omega1 - psi_dot);
        let l_dot = a * a_dot / l;
        let t_dv = m.t.x * dv.x + m.t.y * dv.y;
        let turning = psi_dot * t_dv + (k.omega1 + k.omega2) * sigma_dot - k.omega2 * l_dot;
        let free = turning + st.sigma0 * y[idx::OMEGA1_DOT] + st.x0 / STICK_RELAXATION;
        StickRow { w, a_w, free }
    }

    /// The stick force `F_w` of (4.13) at y with the normal force `lam` (rigid teeth: y's
    /// lambda; elastic: Fn of y), given the friction of the other lines and any other
    /// contact force `rest` (generalised, as in f).
    pub(crate) fn stick_force(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        row: &StickRow,
        lam: f64,
        grow: &[f64; 7],
        rest: &[f64; 7],
    ) -> f64 {
        let v = idx::V;
        let mut wf = 0.0;
        for i in 0..7 {
            let mut f = -self.damp[i] * y[v + i] - self.stiff[i] * y[i] + lam * grow[i] + rest[i];
            if i == 6 {
                f -= self.inputs.t_load_at(t);
            }
            wf += row.w[i] * f / self.mass[i];
        }
        -(row.free + wf) / row.a_w
    }

    /// Adds the stick force `f_w` on the line `st` to the friction of the other lines: force
    /// `+f_w e_w` on gear 2, `-f_w e_w` on gear 1, their moments, and its power
    /// `-f_w x0` to the loss (zero while the line sticks; it closes the energy balance of
    /// the drift).
    pub(crate) fn add_stick(fr: &mut Friction, st: &StuckLine, action: &StickAction, f_w: f64) {
        fr.f2 += action.e_w * f_w;
        fr.f1 -= action.e_w * f_w;
        fr.m1 += action.moment1 * f_w;
        fr.m2 += action.moment2 * f_w;
        fr.p_loss -= f_w * st.x0;
    }

    /// The friction resultants of sums from [`GearedRotor::friction`] at the normal force
    /// `lam` = y's lambda, the stick force included when a line sticks (as f applies them),
    /// held against `other` besides the forces of y (the other flanks', elastic teeth).
    pub(crate) fn friction_resultants(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &Mesh,
        sums: &FrictionSums,
        mu: f64,
        other: &[f64; 7],
    ) -> Friction {
        let lam = y[idx::LAMBDA];
        let mut fr = sums.resultants(mu, lam);
        if let Some(st) = &sums.stuck {
            self.add_stick_force(t, y, m, st, lam, other, &mut fr);
        }
        fr
    }

    /// Adds to `fr`, the friction of the sliding lines at the normal force `lam`, the stick
    /// force (4.13) of the stuck line `st`, with `other` the generalised forces of any
    /// other contact (the coast flanks of elastic teeth); returns that force `F_w`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn add_stick_force(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &Mesh,
        st: &StuckLine,
        lam: f64,
        other: &[f64; 7],
        fr: &mut Friction,
    ) -> f64 {
        let action = st.action(m, &self.geom);
        let row = self.stick_row_with(y, m, st, &action);
        let grow = self.geom.constraint_row(m);
        let mut rest = fr.generalised();
        for (r, o) in rest.iter_mut().zip(other) {
            *r += o;
        }
        let f_w = self.stick_force(t, y, &row, lam, &grow, &rest);
        Self::add_stick(fr, st, &action, f_w);
        f_w
    }

    /// How far the stuck line is from slipping at y, in N: `mu |lambda| L_k / l - |F_w|`
    /// with lambda from the hidden constraint (as the outputs report it; elastic teeth: Fn
    /// of y); negative once the
    /// force needed exceeds what friction can give, or when no line is near zero sliding
    /// (the stuck line left the contact). Evaluated as if the mode were stick, whatever
    /// [`GearedRotor::stick`] is: at a reversal of the sliding it says whether the line
    /// would stick. None where no line can stick (also while laws 1 and 3 creep near
    /// standstill, [`GearedRotor::creeps`]) or the state cannot be evaluated.
    pub fn stick_margin(&self, t: f64, y: &SVector<f64, NY>) -> Option<f64> {
        self.stick_state(t, y).map(|(g, _)| g)
    }

    /// [`GearedRotor::stick_margin`] and the stick force `F_w` (N, on gear 2 along e_w;
    /// the coast flanks' line: in the mirrored pair's terms).
    pub fn stick_state(&self, t: f64, y: &SVector<f64, NY>) -> Option<(f64, f64)> {
        // (Creeping, no line sticks: model.md §4.2.)
        if !self.stick_possible() || self.creep {
            return None;
        }
        if self.watches_coast(t, y) {
            let mir = self.coast.as_ref()?.mirror();
            let z = super::coast::mirror_state(y);
            let mz = mir.mesh(t, &z).ok()?;
            let lam = mir.elastic_contact_with(&z, &mz, self.coast_offset()).fn_;
            let other = self.mirrored_forces(t, &self.drive_forces(t, y).ok()?);
            return mir.stick_state_at(t, &z, &mz, lam, &other);
        }
        let m = self.mesh(t, y).ok()?;
        let mut z = *y;
        // The normal force and the other contact's forces: the coast flanks' (elastic).
        let (lam, other) = if self.elastic.is_some() {
            let c = self.elastic_contact(y, &m);
            (c.fn_, self.coast_terms(t, y, &m, &[0.0; 7]).ok()?.q)
        } else {
            z[idx::LAMBDA] = self.consistent_lambda_mode(t, y, &m, true).ok()?;
            (z[idx::LAMBDA], [0.0; 7])
        };
        self.stick_state_at(t, &z, &m, lam, &other)
    }

    /// [`GearedRotor::stick_state`] at z (mesh `m`) with the normal force `lam` and the
    /// other forces `other` (generalised) given.
    fn stick_state_at(
        &self,
        t: f64,
        z: &SVector<f64, NY>,
        m: &Mesh,
        lam: f64,
        other: &[f64; 7],
    ) -> Option<(f64, f64)> {
        let (sums, mu) = self
            .friction_mode(t, z, m, lam, super::friction::Asker::Point, true)
            .ok()?;
        let st = sums.stuck?;
        let f_w = self.add_stick_force(t, z, m, &st, lam, other, &mut sums.resultants(mu, lam));
        // A line whose sliding is more than a thousandth of the rolling speed across a base
        // pitch from zero is not the stuck one (the stuck line left the contact).
        let far = 1e-3 * (z[idx::OMEGA1] + z[idx::V + 6]).abs() * self.geom.p_bt;
        if !(st.x0.abs() <= far) {
            return Some((-1.0, f_w));
        }
        let share = lam.abs() * st.length / sums.contact.length;
        Some((mu * share - f_w.abs(), f_w))
    }

    /// Sliding speed `x0` (m/s) of the contact line nearest to the pitch line (where the
    /// sliding is zero), signed, for a pair whose lines can stick
    /// ([`GearedRotor::stick_possible`]): its sign changes when a line crosses the pitch
    /// line. From the mesh and the velocities alone (no friction sums: the simulation asks
    /// after every step): on a spur pair line k lies at `sigma_k = s + k p_bt` (`s` the mesh
    /// phase, (3.10)) and slides with `x0 = x_base + (omega1 + omega2) sigma_k` (4.12). None
    /// otherwise.
    pub fn pitch_line_sliding(&self, t: f64, y: &SVector<f64, NY>) -> Option<f64> {
        if !self.stick_possible() {
            return None;
        }
        if self.watches_coast(t, y) {
            // The coast flanks' line, in the mirrored pair (§3.6).
            let z = super::coast::mirror_state(y);
            return self.coast.as_ref()?.mirror().pitch_line_sliding(t, &z);
        }
        let m = self.mesh(t, y).ok()?;
        let g = &self.geom;
        let k = kinematics(y);
        let dv = k.v2 - k.v1;
        let x_base = dv.x * m.cos_psi + dv.y * m.sin_psi - k.omega2 * m.len_t1t2;
        let wsum = k.omega1 + k.omega2;
        if !(wsum.abs() > 0.0) {
            return Some(x_base);
        }
        let p = g.p_bt;
        let s = g.mesh_phase(&m, y[idx::PHI1], self.params.psi0);
        let offset = reduce(s + x_base / wsum + 0.5 * p, p) - 0.5 * p;
        Some(wsum * offset)
    }
}
