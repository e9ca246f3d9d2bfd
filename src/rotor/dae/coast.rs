//! The coast flanks of the elastic contact (`model.md` §3.6, issue 27): backlash, and the
//! contact of the flanks that touch when the torque reverses.
//!
//! The coast side is the drive side seen in a mirror: reflecting the pair in the plane
//! through both axes (y -> -y) turns each coast flank into a drive flank, reverses both
//! senses of rotation and the helix hand, and keeps the involute geometry. So the coast
//! contact is the drive contact of the mirrored pair (`beta -> -beta`, the coast phase of
//! from (3.27), the coast gap offset of (3.26)) at the mirrored state `S y`; its generalised
//! forces come back through `S` (S = S^-1 = S^T flips u_y, xi, their rates, phi1, omega1
//! and omega1'), forces through the reflection R and moments through -R (a moment is an
//! axial vector). Every friction law applies unchanged on the coast lines.

use super::elastic::ElasticContact;
use super::friction::Asker;
use super::GearedRotor;
use crate::gear::{inv, Friction};
use crate::rotor::{idx, ModelError, Outputs, Params, NY};
use nalgebra::SVector;

/// Components of y whose sign the mirror flips: u1y, u2y, xi, their rates, phi1, omega1,
/// omega1'.
const FLIPPED: [usize; 9] = [
    1,
    4,
    6,
    idx::V + 1,
    idx::V + 4,
    idx::V + 6,
    idx::PHI1,
    idx::OMEGA1,
    idx::OMEGA1_DOT,
];

/// A generalised force (order of q) through the mirror: `S q` flips u1y, u2y and gear 2's
/// rotation (S = S^-1, so the same map takes it back).
pub(crate) fn mirror_generalised(mut q: [f64; 7]) -> [f64; 7] {
    for i in [1, 4, 6] {
        q[i] = -q[i];
    }
    q
}

/// The generalised force of a contact: its normal force `fn_` along the constraint row
/// `grow` plus its friction `fr`.
pub(crate) fn contact_generalised(fn_: f64, grow: &[f64; 7], fr: &Friction) -> [f64; 7] {
    let qf = fr.generalised();
    std::array::from_fn(|i| fn_ * grow[i] + qf[i])
}

/// The mirrored state `S y`.
pub(crate) fn mirror_state(y: &SVector<f64, NY>) -> SVector<f64, NY> {
    let mut z = *y;
    for i in FLIPPED {
        z[i] = -z[i];
    }
    z
}

/// The mirrored pair that carries the coast contact.
#[derive(Debug, Clone)]
pub(crate) struct CoastFlank {
    /// The pair reflected in the plane of the axes: helix hand reversed, contact lines at
    /// the coast phase, elastic contact like the drive side's.
    mirror: Box<GearedRotor>,
}

/// What the coast contact adds to f at a state (`model.md` §3.6: (3.23), (3.24) with (3.15)-(3.16)).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct CoastTerms {
    /// The coast contact: approach, rate, length, stiffness, force, energies.
    pub contact: ElasticContact,
    /// Generalised force of the coast contact (normal force and friction) in the order
    /// of q, real (not mirrored) coordinates.
    pub q: [f64; 7],
    /// Torque of the coast contact on gear 1 about +e_z that the drive has to supply
    /// (its share of T1), N m.
    pub t1: f64,
    /// Friction power of the coast contact, W.
    pub p_loss: f64,
}

impl CoastFlank {
    /// The mirrored pair of `params` (elastic contact), or None when it cannot be built.
    pub(crate) fn new(params: &Params) -> Option<Self> {
        let g = params.validate().ok()?;
        let mut p = *params;
        p.gear.beta = -params.gear.beta;
        p.psi0 = g.coast_phase(params.psi0);
        let mirror = GearedRotor::new_flank(p, false).ok()?;
        Some(Self {
            mirror: Box::new(mirror),
        })
    }
}

impl CoastFlank {
    /// The mirrored pair (its stick flags are the coast line's, `rotor::dae::stick`; its
    /// tunables follow the drive side's: `GearedRotor::set_mu`, `GearedRotor::set_d_phi`).
    pub(crate) fn mirror(&self) -> &GearedRotor {
        &self.mirror
    }

    /// The mirrored pair, to set its stick flags.
    pub(crate) fn mirror_mut(&mut self) -> &mut GearedRotor {
        &mut self.mirror
    }

    /// Changes the friction coefficient of the coast side with the drive side's (tunable
    /// `mu`).
    pub(crate) fn set_mu(&mut self, mu: f64) -> Result<(), crate::parameter::ParamError> {
        self.mirror.set_mu(mu)
    }
}

impl GearedRotor {
    /// The generalised direction of the coast force at the centre displacements `u` (real
    /// coordinates, order of q): `S G'` of the mirrored pair, the force on the bodies per
    /// newton of `Fn_coast` (`model.md` (3.24)).
    ///
    /// # Errors
    /// The mirrored mesh cannot be evaluated.
    pub(crate) fn coast_row(&self, t: f64, u: &[f64; 6]) -> Result<Option<[f64; 7]>, ModelError> {
        let Some(coast) = self.coast.as_ref() else {
            return Ok(None);
        };
        let mut z = SVector::<f64, NY>::zeros();
        z.fixed_rows_mut::<6>(0).copy_from_slice(u);
        let z = mirror_state(&z);
        let m = coast.mirror.mesh(t, &z)?;
        Ok(Some(mirror_generalised(
            coast.mirror.geom.constraint_row(&m),
        )))
    }

    /// The coast gap offset g_c0 of (3.26) at the model's drive offset g0.
    pub(crate) fn coast_offset(&self) -> f64 {
        self.geom.coast_gap_offset(self.g0)
    }

    /// The normal approach of the coast flanks `delta_c = -cos(beta_b) g_c` (`model.md`
    /// (3.23)) from the drive side's mesh `m` (no mirrored mesh needed):
    /// `g_c = R (inv alpha - theta) - xi - tan(beta_b) (u2z - u1z) + g_c0`, m.
    pub(crate) fn coast_approach(&self, m: &crate::gear::Mesh, xi: f64) -> f64 {
        let g = &self.geom;
        let gc = g.r_sum * (inv(m.alpha) - m.theta) - xi - g.tan_beta_b * (m.c2.z - m.c1.z)
            + self.coast_offset();
        -g.cos_beta_b * gc
    }

    /// The coast approach `delta_c` at the drive mesh `m` and transmission-error
    /// coordinate `xi` (`model.md` (3.23)); `-inf` without coast flanks.
    pub(crate) fn coast_approach_at(&self, m: &crate::gear::Mesh, xi: f64) -> f64 {
        if self.coast.is_some() {
            self.coast_approach(m, xi)
        } else {
            f64::NEG_INFINITY
        }
    }

    /// Whether the coast flanks overlap at y (`delta_c > 0`; false without coast flanks or
    /// when the mesh cannot be evaluated).
    pub(crate) fn coast_touches(&self, t: f64, y: &SVector<f64, NY>) -> bool {
        self.coast.is_some()
            && self
                .mesh_for_f(t, y)
                .is_ok_and(|m| self.coast_approach(&m, y[idx::Q + 6]) > 0.0)
    }

    /// The coast contact's terms of f at y (zero while the coast flanks are apart).
    /// `m` is the drive side's mesh of y; `drive` the drive flanks' generalised forces
    /// (normal force and friction, real coordinates), which a stuck coast line is held
    /// against (read only then).
    ///
    /// # Errors
    /// Mesh or contact errors of the mirrored pair.
    pub(crate) fn coast_terms(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &crate::gear::Mesh,
        drive: &[f64; 7],
    ) -> Result<CoastTerms, ModelError> {
        let mut out = CoastTerms::default();
        let Some(coast) = self.coast.as_ref() else {
            return Ok(out);
        };
        if !(self.coast_approach(m, y[idx::Q + 6]) > 0.0) {
            return Ok(out);
        }
        let mir = &coast.mirror;
        let z = mirror_state(y);
        let mz = mir.mesh_for_f(t, &z)?;
        let c = mir.elastic_contact_with(&z, &mz, self.coast_offset());
        out.contact = c;
        if c.fn_ > 0.0 {
            let (sums, mu) = mir.friction(t, &z, &mz, c.fn_, Asker::Integrator)?;
            let mut fr = sums.resultants(mu, c.fn_);
            if let Some(st) = &sums.stuck {
                let other = self.mirrored_forces(t, drive);
                mir.add_stick_force(t, &z, &mz, st, c.fn_, &other, &mut fr);
            }
            let grow = mir.geom.constraint_row(&mz);
            out.q = mirror_generalised(contact_generalised(c.fn_, &grow, &fr));
            out.t1 = -(c.fn_ * mir.geom.rb1 * mir.geom.cos_beta_b - fr.m1.z);
            out.p_loss = fr.p_loss;
        }
        Ok(out)
    }

    /// The coast contact at y (None for rigid teeth, a drive-only model or when the
    /// mesh cannot be evaluated); zero force while the coast flanks are apart.
    pub fn coast_contact_at(&self, t: f64, y: &SVector<f64, NY>) -> Option<ElasticContact> {
        let coast = self.coast.as_ref()?;
        let z = mirror_state(y);
        let mz = coast.mirror.mesh(t, &z).ok()?;
        Some(
            coast
                .mirror
                .elastic_contact_with(&z, &mz, self.coast_offset()),
        )
    }

    /// Adds the coast contact to the outputs `o` of the drive side at y (`model.md` §6,
    /// §3.6): forces through R, moments through -R, its share of T1, P_in and P_loss,
    /// its spring energy in E_pot; while only the coast flanks touch, the contact
    /// quantities (length, pairs, coefficients, stiffness) are the coast's.
    pub(crate) fn add_coast_outputs(&self, t: f64, y: &SVector<f64, NY>, o: &mut Outputs) {
        let Some(coast) = self.coast.as_ref() else {
            return;
        };
        let z0 = mirror_state(y);
        let Ok(mz) = coast.mirror.mesh(t, &z0) else {
            return;
        };
        let c = coast
            .mirror
            .elastic_contact_with(&z0, &mz, self.coast_offset());
        o.fn_coast = c.fn_;
        o.e_mesh_spring += c.energy;
        o.e_pot += c.energy;
        if !c.in_contact {
            return;
        }
        let mut z = z0;
        z[idx::LAMBDA] = c.fn_;
        let res = match coast.mirror.friction(t, &z, &mz, c.fn_, Asker::Outputs) {
            Ok((s, mu)) => Ok((mz, s, mu)),
            // Overlap but no coast line active (absurd axial offsets): no force, and the
            // outputs without coast friction rather than NaN, as on the drive side.
            Err(ModelError::NoContact { .. }) if c.fn_ == 0.0 => {
                Ok((mz, crate::gear::FrictionSums::default(), 0.0))
            }
            Err(e) => Err(e),
        };
        // A stuck coast line: held against the drive flanks' forces and the load.
        let other = coast.mirror.stick.then(|| {
            let drive = self.drive_forces(t, y).unwrap_or([f64::NAN; 7]);
            self.mirrored_forces(t, &drive)
        });
        let om = coast.mirror.outputs_with_other(t, &z, res, other.as_ref());
        let j1_dot = self.params.rotor1.j * y[idx::OMEGA1_DOT];
        // The mirrored T1 holds J1 omega1' of the mirrored (negated) acceleration.
        let t1_contact = -(om.t1 + j1_dot);
        o.t1 += t1_contact;
        o.p_in = o.t1 * y[idx::OMEGA1];
        o.p_loss += om.p_loss;
        let force = |a: &mut [f64; 3], b: [f64; 3]| {
            a[0] += b[0];
            a[1] -= b[1];
            a[2] += b[2];
        };
        let moment = |a: &mut [f64; 3], b: [f64; 3]| {
            a[0] -= b[0];
            a[1] += b[1];
            a[2] -= b[2];
        };
        force(&mut o.f_friction1, om.f_friction1);
        force(&mut o.f_friction2, om.f_friction2);
        force(&mut o.f_contact1, om.f_contact1);
        force(&mut o.f_contact2, om.f_contact2);
        moment(&mut o.m_friction1, om.m_friction1);
        moment(&mut o.m_friction2, om.m_friction2);
        moment(&mut o.m_contact1, om.m_contact1);
        moment(&mut o.m_contact2, om.m_contact2);
        if o.mesh_state != 1 {
            o.mesh_state = -1;
            o.mesh_stiffness = c.stiffness;
            o.contact_length = om.contact_length;
            o.pairs_in_contact = om.pairs_in_contact;
            o.mu_eff = om.mu_eff;
            o.mu_mz = om.mu_mz;
        }
    }

    /// Whether the coast flanks' line sticks.
    pub(crate) fn coast_sticks(&self) -> bool {
        self.coast.as_ref().is_some_and(|c| c.mirror.stick)
    }

    /// The forces a stuck coast line is held against besides the coast's own, in the
    /// mirrored coordinates: the drive flanks' generalised forces `drive` through S, and
    /// the load torque (the mirrored pair holds no inputs; S flips gear 2's rotation, so
    /// `-T_load` becomes `+T_load`).
    pub(crate) fn mirrored_forces(&self, t: f64, drive: &[f64; 7]) -> [f64; 7] {
        let mut q = mirror_generalised(*drive);
        q[6] += self.inputs.t_load_at(t);
        q
    }

    /// The drive flanks' generalised forces at y (normal force and friction, real
    /// coordinates; no stuck drive line: used while the coast line sticks).
    ///
    /// # Errors
    /// The mesh or the friction cannot be evaluated.
    pub(crate) fn drive_forces(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
    ) -> Result<[f64; 7], ModelError> {
        let m = self.mesh(t, y)?;
        let (c, fr, _) = self.elastic_friction(t, y, &m)?;
        Ok(contact_generalised(
            c.fn_,
            &self.geom.constraint_row(&m),
            &fr,
        ))
    }

    /// The static approach of the coast flanks for the normal force `f` (> 0) at y's
    /// positions: `f / (c_l l_c)` with the coast contact length l_c.
    pub(crate) fn coast_static_approach(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        f: f64,
    ) -> Result<f64, ModelError> {
        let Some(coast) = self.coast.as_ref() else {
            return Ok(0.0);
        };
        let z = mirror_state(y);
        let mz = coast.mirror.mesh(t, &z)?;
        coast.mirror.static_approach(t, &mz, z[idx::PHI1], f)
    }
}

impl GearedRotor {
    /// The contact event functions of the drive and the coast flanks at y,
    /// `phi = min(delta, delta + (d_l / c_l) delta')` in m (`model.md` (3.28)): positive
    /// exactly where the flanks push (`delta > 0` and `c_l delta + d_l delta' > 0`, (3.15)),
    /// so its sign changes are the jumps and kinks of f: an onset (delta crosses 0 with
    /// `delta' > 0`, where the damping force sets in) and the instant the force falls to 0
    /// (where the damping would start to pull, just before the flanks separate). None for
    /// rigid teeth or when the mesh cannot be evaluated; `-inf` for the coast without
    /// coast flanks.
    pub fn flank_event_functions(&self, t: f64, y: &SVector<f64, NY>) -> Option<[f64; 2]> {
        let e = self.elastic.as_ref()?;
        let m = self.mesh(t, y).ok()?;
        let g = &self.geom;
        let xi = y[idx::Q + 6];
        let v = idx::V;
        let grow = g.constraint_row(&m);
        let gv: f64 = (0..7).map(|i| grow[i] * y[v + i]).sum();
        let delta = -g.cos_beta_b * (g.gap_raw(&m, xi) + self.g0);
        let delta_dot = -(gv - g.rb1 * g.cos_beta_b * y[idx::OMEGA1]);
        let tau = e.d_l / e.c_l;
        let phi = |d: f64, d_dot: f64| d.min(d + tau * d_dot);
        let phi_c = if self.coast.is_some() {
            // delta_c = -cos(beta_b) play(alpha) - delta ((3.25), (3.26)), and
            // d play / dt = 2 sin(alpha) a' with a' = d . d' / a.
            let d = m.c2 - m.c1;
            let a_dot = (d.x * (y[v + 3] - y[v]) + d.y * (y[v + 4] - y[v + 1])) / m.a;
            let delta_c = self.coast_approach(&m, xi);
            let delta_c_dot = -g.cos_beta_b * 2.0 * m.alpha.sin() * a_dot - delta_dot;
            phi(delta_c, delta_c_dot)
        } else {
            f64::NEG_INFINITY
        };
        Some([phi(delta, delta_dot), phi_c])
    }
}
