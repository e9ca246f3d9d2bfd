//! The tooth contact as the rest of the code sees it (issue 27, item 8: "a contact model
//! owns its state layout, scales, consistent initial values, event functions and what
//! counts as a validity violation; the rest asks it").
//!
//! The two contacts of [`ToothContact`] differ in exactly the questions a simulation has to
//! ask about the mesh, and [`Contact`] answers them in physical terms, dispatching on the
//! model's contact kind:
//! - rigid teeth (`model.md` §3.3, §7): an index-2 constraint; the last slot of y is its
//!   Lagrange multiplier lambda, the normal force. The stepper controls lambda's error only
//!   scaled by h, so the force that counts is lambda projected on the hidden constraint. A
//!   negative force (the flanks pulled together) is outside the model's validity: lift-off.
//!   The contact never sets in or lets go: no contact events;
//! - elastic teeth (`model.md` §3.5, §3.6): no constraint; the last slot is the work stored
//!   in the mesh springs (a quadrature, a differential state like any other), and the
//!   normal force `Fn = l max(0, c_l delta + d_l delta')` is a function of the state,
//!   never negative: flanks that part are free flight within the model, not a violation.
//!   The onsets and separations of the drive and the coast flanks are state events.
//!
//! The layout of y is shared (23 components; the last slot `idx::LAMBDA` means what
//! [`Contact::last_slot`] says; `idx::E_MESH_DAMP` stays 0 with rigid teeth). What differs
//! is answered here, and the rest asks:
//! - the solver structure (`rotor::dae_structure`): the index counts and whether the last
//!   slot is a quadrature ([`LastSlot::index_counts`], [`LastSlot::is_quadrature`]), how
//!   many components the solver's norms count ([`ToothContact::norm_count`]). These
//!   depend on the kind alone, so they are answered by [`LastSlot`] and [`ToothContact`]
//!   (the solver options are made from the kind, `sim::SolverSettings::options_for`), and
//!   the view [`Contact`] forwards them;
//! - the error scale of the last slot, a force or an energy ([`LastSlot::scale`],
//!   `rotor::error_scales`);
//! - the consistent state: the last slot at the start ([`Contact::start_value`]) and
//!   where the stepper restarts ([`Contact::consistent_state`]); the zero row of the mass
//!   matrix and whether the outputs take the force from the state
//!   ([`Contact::has_multiplier`]);
//! - the normal force, the outputs' state, lift-off, the contact events and the overload
//!   margin (the validity, `sim`);
//! - which coordinates of the mesh are free, and so which components a periodic orbit has
//!   ([`Contact::mesh_coordinates_free`], `periodic`).
//!
//! What stays with the model is its physics: f, the Jacobian and the outputs of each
//! contact (`GearedRotor::rhs`, `dae/elastic.rs`, `dae/coast.rs`).

use super::{idx, GearedRotor, ModelError, ToothContact, NY};
use crate::gear::Mesh;
use nalgebra::SVector;

/// What the last slot of y (`idx::LAMBDA`) holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LastSlot {
    /// Rigid teeth: the Lagrange multiplier lambda of the contact constraint, in N (an
    /// algebraic, index-2 component: zero row of the mass matrix).
    Multiplier,
    /// Elastic teeth: the work stored in the mesh springs, `E_s' = k delta delta'`, in J (a
    /// quadrature).
    StoredSpringWork,
}

impl LastSlot {
    /// RADAU5's counts of index-1 and index-2 components of y, `(n1, n2)`: the multiplier
    /// is the one index-2 component (the stepper scales its error with h); the stored work
    /// is differential like the rest (an ODE, `n2 = 0`).
    pub fn index_counts(self) -> (usize, usize) {
        match self {
            LastSlot::Multiplier => (super::N_INDEX1, super::N_INDEX2),
            LastSlot::StoredSpringWork => (NY, 0),
        }
    }

    /// Whether the last slot is a quadrature: the stored work enters no right-hand side
    /// (radau5 `Options::quadrature`); the multiplier enters those of the velocities.
    pub fn is_quadrature(self) -> bool {
        self == LastSlot::StoredSpringWork
    }

    /// The error scale of the last slot, given the scale of the load (`force`, N) and of
    /// the energies (`energy`, J): the multiplier is a force, the stored work an energy.
    pub fn scale(self, force: f64, energy: f64) -> f64 {
        match self {
            LastSlot::Multiplier => force,
            LastSlot::StoredSpringWork => energy,
        }
    }
}

/// The answers that depend on the contact kind alone (the solver options are made from
/// it); [`Contact`] forwards them for a model.
impl ToothContact {
    /// What the last slot of y holds with this contact.
    pub fn last_slot(self) -> LastSlot {
        match self {
            ToothContact::Rigid => LastSlot::Multiplier,
            ToothContact::Elastic => LastSlot::StoredSpringWork,
        }
    }

    /// Whether the teeth have a mesh damping whose energy `idx::E_MESH_DAMP` accumulates:
    /// the elastic teeth; rigid teeth leave it at 0.
    pub fn has_mesh_damping(self) -> bool {
        self == ToothContact::Elastic
    }

    /// How many components the solver's error and Newton norms average over (radau5
    /// `Options::norm_count`): all but `idx::E_MESH_DAMP` where it stays 0 (rigid teeth),
    /// so that the steps are those of the 22 other components.
    pub fn norm_count(self) -> usize {
        if self.has_mesh_damping() {
            NY
        } else {
            NY - 1
        }
    }
}

/// The tooth contact of a [`GearedRotor`], asked in physical terms (see the module docs).
/// A view: cheap to make, holds nothing of its own.
#[derive(Debug, Clone, Copy)]
pub struct Contact<'a> {
    model: &'a GearedRotor,
}

impl GearedRotor {
    /// The tooth contact of this model, to be asked about the normal force, the contact
    /// events and lift-off ([`Contact`]).
    pub fn contact(&self) -> Contact<'_> {
        Contact { model: self }
    }
}

impl Contact<'_> {
    /// Which contact model (`Params::tooth_contact`).
    pub fn kind(&self) -> ToothContact {
        self.model.params().tooth_contact
    }

    /// What the last slot of y holds.
    pub fn last_slot(&self) -> LastSlot {
        self.kind().last_slot()
    }

    /// Whether the normal force is a Lagrange multiplier of a constraint (rigid teeth):
    /// then the state must satisfy the constraint, and the stepper's value of the force is
    /// only a first guess of the consistent one.
    pub fn has_multiplier(&self) -> bool {
        self.last_slot() == LastSlot::Multiplier
    }

    /// Whether the mesh's own coordinates, the transmission error xi and omega2, are free
    /// states (elastic teeth: the flanks approach and part), or fixed by the centres
    /// through the constraint g = 0 and its velocity form (rigid teeth). A periodic orbit
    /// has 14 components in the first case, the 12 of the centres in the second
    /// (`periodic`).
    pub fn mesh_coordinates_free(&self) -> bool {
        !self.has_multiplier()
    }

    /// Whether the contact can leave the model's validity by lift-off: only rigid teeth,
    /// whose single-flank constraint would pull the flanks together where real teeth part.
    /// Elastic flanks part within the model (free flight, the coast flanks).
    pub fn lift_off_possible(&self) -> bool {
        self.has_multiplier()
    }

    /// Whether the contact sets in and lets go during a run, at located state events
    /// ([`Contact::event_functions`]): the elastic flanks. Rigid teeth are always in
    /// contact.
    pub fn has_contact_events(&self) -> bool {
        self.kind() == ToothContact::Elastic
    }

    /// The last slot of y at a start, for y consistent in every other component (`m` its
    /// mesh): rigid teeth, lambda from the hidden constraint; elastic teeth, the work stored
    /// in the mesh springs starts as their energy `k delta^2 / 2` (drive and coast flanks).
    ///
    /// # Errors
    /// Rigid teeth: the mesh cannot be evaluated or no consistent lambda exists.
    pub fn start_value(&self, t: f64, y: &SVector<f64, NY>, m: &Mesh) -> Result<f64, ModelError> {
        match self.last_slot() {
            LastSlot::Multiplier => self.model.consistent_lambda(t, y),
            LastSlot::StoredSpringWork => Ok(self.model.elastic_contact(y, m).energy
                + self.model.coast_contact_at(t, y).map_or(0.0, |c| c.energy)),
        }
    }

    /// The normal contact force of the drive flanks at (t, y), in N, as the outputs report
    /// it (`fn_`). Rigid teeth: lambda from the hidden constraint for the differential
    /// states of y (`GearedRotor::consistent_lambda`: the stepper's lambda can be off by
    /// ~1e-3 relative after a short step, the consistent one is as accurate as q and v), or
    /// the stepper's lambda where the model cannot decide (friction-induced ambiguity) or
    /// the value is not finite. Elastic teeth: `Fn` of (3.16) from the approach of the
    /// flanks and its rate; NaN where the mesh cannot be evaluated.
    pub fn normal_force(&self, t: f64, y: &SVector<f64, NY>) -> f64 {
        match self.kind() {
            ToothContact::Rigid => match self.model.consistent_lambda(t, y) {
                Ok(l) if l.is_finite() => l,
                _ => y[idx::LAMBDA],
            },
            ToothContact::Elastic => self
                .model
                .elastic_contact_at(t, y)
                .map_or(f64::NAN, |c| c.fn_),
        }
    }

    /// The state the outputs are evaluated at: rigid teeth, y with lambda replaced by
    /// [`Contact::normal_force`] (model.md §7); elastic teeth, y itself (the stored work is
    /// a differential state, accurate to the tolerance, and the outputs take Fn from the
    /// state).
    pub fn output_state(&self, t: f64, y: &SVector<f64, NY>) -> SVector<f64, NY> {
        let mut z = *y;
        if self.has_multiplier() {
            z[idx::LAMBDA] = self.normal_force(t, y);
        }
        z
    }

    /// y with its last slot consistent with the rest, where the stepper restarts (new
    /// inputs or tunables, a new stick mode): rigid teeth, lambda from the hidden constraint
    /// (lambda is algebraic: a new d_phi, mu, T_load or stick mode moves it at once);
    /// elastic teeth, y unchanged (the stored work is a state with a history).
    ///
    /// # Errors
    /// Rigid teeth: the mesh cannot be evaluated or no consistent lambda exists
    /// (`GearedRotor::consistent_lambda`).
    pub fn consistent_state(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
    ) -> Result<SVector<f64, NY>, ModelError> {
        let mut z = *y;
        if self.has_multiplier() {
            z[idx::LAMBDA] = self.model.consistent_lambda(t, y)?;
        }
        Ok(z)
    }

    /// The cheap lift-off test on the stepper's own state: the multiplier is negative
    /// (rigid teeth); never for elastic teeth. A change it signals is to be confirmed with
    /// [`Contact::normal_force`] ([`Contact::lifted_off`]).
    pub fn stepper_lift_off(&self, y: &SVector<f64, NY>) -> bool {
        self.lift_off_possible() && y[idx::LAMBDA] < 0.0
    }

    /// Whether the flanks have lifted off at (t, y), given whether they had at the last
    /// check (`was`): the stepper's multiplier decides cheaply; a change is confirmed with
    /// the consistent normal force, as the outputs report it (rigid teeth). Never for
    /// elastic teeth.
    pub fn lifted_off(&self, t: f64, y: &SVector<f64, NY>, was: bool) -> bool {
        let lost = self.stepper_lift_off(y);
        if lost != was && self.lift_off_possible() {
            return self.normal_force(t, y) < 0.0;
        }
        lost
    }

    /// The contact event functions of the drive and the coast flanks,
    /// `phi = min(delta, delta + (d_l / c_l) delta')` in m (`model.md` (3.28)): positive
    /// exactly where the flanks push, so their sign changes are the onsets and separations
    /// (`GearedRotor::flank_event_functions`). None for rigid teeth (no events) or where the
    /// mesh cannot be evaluated; the coast entry is `-inf` without coast flanks.
    pub fn event_functions(&self, t: f64, y: &SVector<f64, NY>) -> Option<[f64; 2]> {
        if !self.has_contact_events() {
            return None;
        }
        self.model.flank_event_functions(t, y)
    }

    /// How far the flanks are from overload, in m: `m_n / 20 - max(delta, delta_c)`
    /// (`model.md` §12), negative where the elastic teeth overlap by more than a twentieth
    /// of the module. +inf for rigid teeth (no deflection) or where the mesh cannot be
    /// evaluated. Why m_n / 20: ISO 6336-1's mesh stiffness is a linear fit for loads up
    /// to a pair's rating, where the deflection stays below ~0.03 m_n (a face load of 1000
    /// N/mm over c_gamma ~ 18 N/(mm um) is 56 um, 0.028 m_n for the default pair); beyond
    /// m_n / 20 the load is several times any rating and the teeth would break or scuff.
    pub fn overload_margin(&self, t: f64, y: &SVector<f64, NY>) -> f64 {
        if !self.has_contact_events() {
            return f64::INFINITY;
        }
        let Some(m) = self.model.mesh(t, y).ok() else {
            return f64::INFINITY;
        };
        let g = self.model.geometry();
        let xi = y[crate::rotor::idx::Q + 6];
        let delta = -g.cos_beta_b * (g.gap_raw(&m, xi) + self.model.gap_offset());
        let delta_c = self.model.coast_approach_at(&m, xi);
        OVERLOAD_FRACTION * g.data.m_n - delta.max(delta_c)
    }
}

/// The flanks' overlap, as a fraction of the normal module, beyond which the elastic
/// contact is outside its validity ([`Contact::overload_margin`]).
pub const OVERLOAD_FRACTION: f64 = 0.05;
