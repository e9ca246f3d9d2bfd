//! The elastic drive-flank contact (`model.md` §3.5, issue 27): the normal force from
//! the normal approach of the flanks and its rate, a function of the state. No constraint
//! and no multiplier: the last slot of y (the rigid model's lambda) holds the work stored
//! in the mesh spring, `E_s' = k delta delta'`, a quadrature.

use super::friction::Asker;
use super::GearedRotor;
use crate::gear::{stiffness, Friction, Mesh, PairGeometry, StuckLine};
use crate::rotor::{idx, ModelError, NY};
use nalgebra::{SVector, Vector3};

/// Stiffness and damping of the elastic mesh per unit contact length (`model.md` (3.20),
/// (3.21)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElasticMesh {
    /// `c_l = c_gamma cos(beta_b) / eps_alpha`, N/m^2 (stiffness per unit contact length).
    pub c_l: f64,
    /// `d_l = 2 zeta_mesh sqrt(c_gamma b m_eq) / l_mean`, N s/m^2.
    pub d_l: f64,
    /// Mean mesh stiffness `c_gamma b`, N/m.
    pub k_mean: f64,
    /// Equivalent mass of the mesh mode at the undeflected state, `1 / (G M^-1 G^T)`, kg.
    pub m_eq: f64,
    /// Mean contact length `b eps_alpha / cos(beta_b)`, m.
    pub l_mean: f64,
}

impl ElasticMesh {
    /// The mesh of pair `g` with the diagonal mass matrix `mass` (order of q) and damping
    /// ratio `zeta`; None when the pair's undeflected mesh cannot be evaluated.
    pub fn new(g: &PairGeometry, mass: &[f64; 7], zeta: f64) -> Option<Self> {
        let c_gamma = stiffness::c_gamma_used(g);
        let c_l = c_gamma * g.cos_beta_b / g.eps_alpha;
        let m = g.mesh(&Vector3::zeros(), &Vector3::zeros()).ok()?;
        let grow = g.constraint_row(&m);
        let a: f64 = (0..7).map(|i| grow[i] * grow[i] / mass[i]).sum();
        let m_eq = 1.0 / a;
        let k_mean = c_gamma * g.data.b;
        let l_mean = g.data.b * g.eps_alpha / g.cos_beta_b;
        let d_l = 2.0 * zeta * (k_mean * m_eq).sqrt() / l_mean;
        Some(Self {
            c_l,
            d_l,
            k_mean,
            m_eq,
            l_mean,
        })
    }
}

/// The elastic contact at a state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ElasticContact {
    /// Normal approach `delta = -cos(beta_b) g`, m (> 0: the flanks overlap).
    pub delta: f64,
    /// Its rate `delta' = -(G q' - r_b1 cos(beta_b) omega1)`, m/s.
    pub delta_dot: f64,
    /// Contact length l (3.12), m.
    pub length: f64,
    /// Mesh stiffness `k = c_l l`, N/m.
    pub stiffness: f64,
    /// Normal force `Fn = l max(0, c_l delta + d_l delta')` for delta > 0, else 0, N.
    pub fn_: f64,
    /// Spring energy `k delta^2 / 2` while delta > 0, else 0, J.
    pub energy: f64,
    /// Power dissipated by the mesh damping, `Fn delta' - k delta delta'` while delta > 0
    /// (>= 0: `d_l l delta'^2`, or `-k delta delta'` where the damping would pull), W.
    pub p_damp: f64,
    /// Power stored in the mesh spring, `k delta delta'` while delta > 0, else 0, W (the
    /// rate of the last slot of y in the elastic contact).
    pub p_spring: f64,
    /// Whether the drive flanks touch (delta > 0).
    pub in_contact: bool,
}

impl GearedRotor {
    /// The elastic mesh, if the contact is elastic.
    pub fn elastic_mesh(&self) -> Option<&ElasticMesh> {
        self.elastic.as_ref()
    }

    /// Whether the tooth contact is elastic (`model.md` §3.5).
    pub fn is_elastic(&self) -> bool {
        self.elastic.is_some()
    }

    /// The elastic contact at (t, y) (None for rigid teeth or when the mesh cannot be
    /// evaluated).
    pub fn elastic_contact_at(&self, t: f64, y: &SVector<f64, NY>) -> Option<ElasticContact> {
        self.elastic.as_ref()?;
        self.mesh(t, y).ok().map(|m| self.elastic_contact(y, &m))
    }

    /// The elastic contact at y (mesh `m` of y). Zero stiffness quantities in the rigid
    /// model.
    pub(crate) fn elastic_contact(&self, y: &SVector<f64, NY>, m: &Mesh) -> ElasticContact {
        self.elastic_contact_with(y, m, self.g0)
    }

    /// [`GearedRotor::elastic_contact`] with the gap offset `g0` given (the coast flank,
    /// `coast`, evaluates the mirrored pair with the coast offset (3.26)).
    pub(crate) fn elastic_contact_with(
        &self,
        y: &SVector<f64, NY>,
        m: &Mesh,
        g0: f64,
    ) -> ElasticContact {
        if self.elastic.is_none() {
            return ElasticContact {
                in_contact: true,
                ..ElasticContact::default()
            };
        }
        let length = self
            .geom
            .contact_summary(m, y[idx::PHI1], self.params.psi0)
            .length;
        self.flank_contact(y, m, g0, length)
    }

    /// The elastic contact at y and its friction resultants at Fn for f
    /// (`Asker::Integrator`); the contact's length is the one the friction evaluation has
    /// anyway (`GearedRotor::friction_for_load`; one contact summary instead of two or
    /// three per f). The same values as [`GearedRotor::elastic_contact`] followed by
    /// [`GearedRotor::friction`] at its Fn and `FrictionSums::resultants`.
    ///
    /// Without a drive force (free flight, or no drive line active: l = 0, so Fn = l q = 0)
    /// there is no friction and no contact line is needed.
    ///
    /// In the stick mode the stuck line is left out of the resultants and returned: its
    /// force (4.13) needs every other force, the coast flanks' too
    /// (`GearedRotor::add_stick_force`).
    ///
    /// # Errors
    /// Non-finite friction terms of the friction evaluation.
    pub(crate) fn elastic_friction(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &Mesh,
    ) -> Result<(ElasticContact, Friction, Option<StuckLine>), ModelError> {
        // Free flight (delta <= 0): no force, no friction, and f needs neither the contact
        // length nor the friction sums (a quarter of a rattle's instructions). The
        // contact's `length` and `stiffness` are then 0: not evaluated.
        // The approach once per f (the gap's involute costs a tan).
        let delta = self.approach(y, m, self.g0);
        if !(delta > 0.0) {
            return Ok((
                self.flank_contact_with(y, m, delta, 0.0),
                Friction::default(),
                None,
            ));
        }
        let mut c = ElasticContact::default();
        match self.friction_for_load(t, y, m, Asker::Integrator, self.stick, |length| {
            c = self.flank_contact_with(y, m, delta, length);
            c.fn_
        }) {
            Ok((sums, mu, fn_)) => Ok((c, sums.resultants(mu, fn_), sums.stuck)),
            // No drive line active (a vibration that moves the centres far): l = 0.
            Err(ModelError::NoContact { .. }) => Ok((
                self.flank_contact_with(y, m, delta, 0.0),
                Friction::default(),
                None,
            )),
            Err(e) => Err(e),
        }
    }

    /// The elastic contact at y (mesh `m`, gap offset `g0`) with its contact length given.
    /// Elastic models only.
    fn flank_contact(
        &self,
        y: &SVector<f64, NY>,
        m: &Mesh,
        g0: f64,
        length: f64,
    ) -> ElasticContact {
        self.flank_contact_with(y, m, self.approach(y, m, g0), length)
    }

    /// The normal approach delta (3.13) at y (mesh `m`, gap offset `g0`), m.
    fn approach(&self, y: &SVector<f64, NY>, m: &Mesh, g0: f64) -> f64 {
        let g = &self.geom;
        -g.cos_beta_b * (g.gap_raw(m, y[idx::Q + 6]) + g0)
    }

    /// [`GearedRotor::flank_contact`] with its approach `delta` given.
    fn flank_contact_with(
        &self,
        y: &SVector<f64, NY>,
        m: &Mesh,
        delta: f64,
        length: f64,
    ) -> ElasticContact {
        let Some(e) = self.elastic.as_ref() else {
            return ElasticContact::default();
        };
        let g = &self.geom;
        let grow = g.constraint_row(m);
        let mut gv = 0.0;
        for (i, gi) in grow.iter().enumerate() {
            gv += gi * y[idx::V + i];
        }
        let delta_dot = -(gv - g.rb1 * g.cos_beta_b * y[idx::OMEGA1]);
        let stiffness = e.c_l * length;
        let mut c = ElasticContact {
            delta,
            delta_dot,
            length,
            stiffness,
            ..ElasticContact::default()
        };
        if delta > 0.0 {
            let q = (e.c_l * delta + e.d_l * delta_dot).max(0.0);
            c.fn_ = length * q;
            c.energy = 0.5 * stiffness * delta * delta;
            c.p_spring = stiffness * delta * delta_dot;
            c.p_damp = c.fn_ * delta_dot - c.p_spring;
            c.in_contact = true;
        }
        c
    }

    /// The static approach for the normal force `lam` at the mesh `m` and phase phi1:
    /// `lam / (c_l l)` (0 for lam <= 0 or the rigid model).
    pub(crate) fn static_approach(
        &self,
        t: f64,
        m: &Mesh,
        phi1: f64,
        lam: f64,
    ) -> Result<f64, ModelError> {
        let Some(e) = self.elastic.as_ref() else {
            return Ok(0.0);
        };
        if !(lam > 0.0) {
            return Ok(0.0);
        }
        let l = self.geom.contact_summary(m, phi1, self.params.psi0).length;
        if !(l > 0.0) {
            return Err(ModelError::NoContact { t });
        }
        Ok(lam / (e.c_l * l))
    }
}
