//! The geared-rotor index-2 DAE of `model.md` §5-§8 in first-order form
//! `M_ext y' = f(t, y)`, its consistent initial values (§7) and outputs (§6).
//! No solver, no FMI.

// `!(a > b)` is used on purpose throughout: it also rejects NaN, which `a <= b` would let pass.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod contact;
mod dae;
pub mod param_table;
pub(crate) mod params;
mod problem;
mod scales;

pub use crate::gear::FrictionLaw;
pub use contact::{Contact, LastSlot, OVERLOAD_FRACTION};
pub use dae::{
    ElasticContact, ElasticMesh, GearedRotor, InitialConditions, CREEP_ENTRY, CREEP_SPEED,
    RELEASE_BAND, STICK_RELAXATION,
};
pub use params::{Inputs, Params, RotorData, ToothContact};
pub use problem::{dae_structure, RotorProblem};
pub use scales::{error_scales, DEFAULT_PAIR_SCALES, SCALES};

use crate::fmt_num::Short;
use std::fmt;

/// Length of the state vector y.
pub const NY: usize = 23;

/// Layout of y. `M_ext = diag(I7, M, 1, 1, 1, 1, 1, 1, 1, 1, 0)`.
pub mod idx {
    /// 7 positions: u1x u1y u1z u2x u2y u2z, then `xi`.
    ///
    /// The 7th coordinate is NOT phi2 but the transmission error along the line of action
    /// `xi = r_b2 (phi2 - phi2(0)) - r_b1 (phi1 - phi1(0))` in metres (`model.md` §5, §6).
    /// Why: phi1 and phi2 grow without bound and RADAU5 scales errors with
    /// `atol + rtol |y|`, so a growing angle would get a growing error allowance (tens of
    /// micrometres of mesh position after 1 s at rtol 1e-6). xi stays bounded (micrometres),
    /// is measured in the same unit as the displacements, and its derivative
    /// `xi' = r_b2 omega2 - r_b1 omega1` is linear in the state. f does not depend on xi
    /// at all (only the gap diagnostic does); phi2 is recovered in the outputs.
    pub const Q: usize = 0;
    /// 7 velocities: u1x' u1y' u1z' u2x' u2y' u2z', omega2 (= phi2', V+6).
    pub const V: usize = 7;
    /// Angle of gear 1 (integral of the filtered omega1). It enters the mesh phase only
    /// reduced modulo the mesh period 2 pi / z1 (see `PairGeometry::mesh_phase`).
    pub const PHI1: usize = 14;
    /// Filtered drive speed omega1 (`model.md` §8).
    pub const OMEGA1: usize = 15;
    /// Its derivative omega1' (filter state).
    pub const OMEGA1_DOT: usize = 16;
    /// Energy supplied by the drive, E_in' = T1 omega1.
    pub const E_IN: usize = 17;
    /// Energy dissipated by tooth friction, E_loss' = P_loss.
    pub const E_LOSS: usize = 18;
    /// Energy dissipated by the dampers, E_damp' = d_phi omega2^2 + sum d u'^2.
    pub const E_DAMP: usize = 19;
    /// Energy taken by the load torque, E_load' = T_load omega2.
    pub const E_LOAD: usize = 20;
    /// Energy dissipated by the mesh damping of elastic teeth (`model.md` §3.5), E_md' =
    /// `Fn delta' - k delta delta'` of both flanks; 0 for rigid teeth (where it stays out
    /// of the solver's norms: `ToothContact::norm_count`).
    pub const E_MESH_DAMP: usize = 21;
    /// Rigid contact: the Lagrange multiplier lambda = normal contact force (index-2
    /// variable). Elastic contact (`model.md` §3.5): the work stored in the mesh spring,
    /// `E_s' = k delta delta'` (a quadrature; the normal force is a function of the state).
    pub const LAMBDA: usize = 22;
}

/// Number of index-1 (differential) components for RADAU5.
pub const N_INDEX1: usize = 22;
/// Number of index-2 components for RADAU5 (lambda).
pub const N_INDEX2: usize = 1;

/// Why f, the initial values or the outputs cannot be evaluated.
#[derive(Debug, Clone, PartialEq)]
pub enum ModelError {
    /// The centres came too close: no line of action (`model.md` §3.1).
    CentreDistanceTooSmall {
        /// Time of the evaluation.
        t: f64,
        /// Actual transverse centre distance.
        a: f64,
        /// r_b1 + r_b2.
        r_sum: f64,
    },
    /// No contact line lies in the active area (l = 0): the line load mu |lambda| / l is undefined.
    NoContact {
        /// Time of the evaluation.
        t: f64,
    },
    /// NaN or infinity in the state or in f.
    NonFinite {
        /// Time of the evaluation.
        t: f64,
        /// What was non-finite.
        what: &'static str,
    },
    /// The hidden constraint has no consistent solution for lambda (friction so strong
    /// that both sign assumptions fail or both hold: a Painleve-type situation, §7).
    InconsistentLambda {
        /// Time of the evaluation.
        t: f64,
        /// lambda under the assumption lambda >= 0.
        lambda_pos: f64,
        /// lambda under the assumption lambda < 0.
        lambda_neg: f64,
    },
    /// A requested start state does not exist (e.g. static equilibrium with a zero stiffness).
    NoStaticEquilibrium {
        /// Reason.
        reason: &'static str,
    },
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModelError::CentreDistanceTooSmall { t, a, r_sum } => write!(
                f,
                "t = {}: centre distance a = {} m must exceed r_b1 + r_b2 = {} m",
                Short(*t),
                Short(*a),
                Short(*r_sum)
            ),
            ModelError::NoContact { t } => {
                write!(
                    f,
                    "t = {}: no contact line in the active area (l = 0)",
                    Short(*t)
                )
            }
            ModelError::NonFinite { t, what } => {
                write!(f, "t = {}: non-finite {what}", Short(*t))
            }
            ModelError::InconsistentLambda {
                t,
                lambda_pos,
                lambda_neg,
            } => write!(
                f,
                "t = {}: no unique consistent contact force (lambda >= 0 gives {}, \
                 lambda < 0 gives {})",
                Short(*t),
                Short(*lambda_pos),
                Short(*lambda_neg)
            ),
            ModelError::NoStaticEquilibrium { reason } => {
                write!(f, "no static equilibrium: {reason}")
            }
        }
    }
}

impl std::error::Error for ModelError {}

/// Outputs of `model.md` §6 (all inertial, SI).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Outputs {
    /// Driving torque on gear 1, `T1 = lambda r_b1 cos beta_b - M1_z + J1 omega1'`.
    pub t1: f64,
    /// Filtered drive speed.
    pub omega1: f64,
    /// Its derivative.
    pub omega1_dot: f64,
    /// Angle of gear 1.
    pub phi1: f64,
    /// Speed of gear 2 (about -e_z).
    pub omega2: f64,
    /// Angle of gear 2 (about -e_z).
    pub phi2: f64,
    /// Normal force lambda.
    pub fn_: f64,
    /// Transmission error `r_b2 phi2 - r_b1 phi1` relative to t = 0.
    pub te: f64,
    /// Gap drift g (should stay ~0).
    pub gap: f64,
    /// Input power T1 omega1.
    pub p_in: f64,
    /// Friction loss.
    pub p_loss: f64,
    /// Load-weighted mean friction coefficient along the lines (`1/l int mu_loc ds`).
    pub mu_eff: f64,
    /// ISO/TR 14179-2 mean coefficient at the current load and speed (law 3's mu).
    pub mu_mz: f64,
    /// Damper power d_phi omega2^2 + u'^T D u'.
    pub p_damp: f64,
    /// Torque of the rotational damper on gear 2, d_phi omega2 (a load beside T_load).
    pub t_damp: f64,
    /// Its power, d_phi omega2^2 (the part of `p_damp` that is the load damper).
    pub p_damp_phi: f64,
    /// Energy states.
    pub e_in: f64,
    /// Cumulative friction loss.
    pub e_loss: f64,
    /// Cumulative damper loss.
    pub e_damp: f64,
    /// Energy dissipated by the mesh damping of elastic teeth (part of `e_damp`), J; 0
    /// for rigid teeth.
    pub e_mesh_damp: f64,
    /// Cumulative load energy.
    pub e_load: f64,
    /// 1/2 q'^T M q' + 1/2 J1 omega1^2.
    pub e_kin: f64,
    /// 1/2 q^T K q (+ the mesh spring energy 1/2 k delta^2 of the elastic contact).
    pub e_pot: f64,
    /// Total contact length l.
    pub contact_length: f64,
    /// Pairs in contact.
    pub pairs_in_contact: i32,
    /// lambda < 0: the single-flank assumption is violated.
    pub contact_lost: bool,
    /// A spur contact line sticks at the pitch line (`model.md` §4.1).
    pub stick: bool,
    /// Mesh spring energy `k delta^2 / 2` (elastic contact; part of `e_pot`), J.
    pub e_mesh_spring: f64,
    /// Work done on the mesh spring by the variation of its stiffness, `int k' delta^2 / 2
    /// dt` (elastic contact: the spring energy minus the work the bodies stored in it), J.
    pub w_mesh_stiffness: f64,
    /// Normal approach of the drive flanks delta (elastic contact, `model.md` §3.5), m;
    /// 0 for rigid teeth.
    pub mesh_deflection: f64,
    /// Mesh stiffness `k = c_l l` of the flanks in contact (elastic contact; 0 in free
    /// flight), N/m; 0 for rigid teeth.
    pub mesh_stiffness: f64,
    /// 1: the drive flanks touch, 0: free flight, -1: the coast flanks touch (elastic
    /// contact, `model.md` §3.6); 1 for rigid teeth.
    pub mesh_state: i32,
    /// Normal force of the coast flanks (elastic contact, `model.md` §3.6), N; 0 for
    /// rigid teeth.
    pub fn_coast: f64,
    /// Contact onsets of the elastic flanks since the start (set by the simulation, which
    /// locates them: `sim::contact_events`); 0 for rigid teeth.
    pub impacts: u64,
    /// Displacement of centre 1.
    pub u1: [f64; 3],
    /// Displacement of centre 2.
    pub u2: [f64; 3],
    /// Velocity of centre 1.
    pub v1: [f64; 3],
    /// Velocity of centre 2.
    pub v2: [f64; 3],
    /// Bearing force of rotor 1 on the housing, K1 u1 + D1 u1'.
    pub f_bearing1: [f64; 3],
    /// Bearing force of rotor 2 on the housing.
    pub f_bearing2: [f64; 3],
    /// Friction force on gear 1.
    pub f_friction1: [f64; 3],
    /// Friction force on gear 2.
    pub f_friction2: [f64; 3],
    /// Friction moment on gear 1 about c1.
    pub m_friction1: [f64; 3],
    /// Friction moment on gear 2 about c2.
    pub m_friction2: [f64; 3],
    /// Total contact force on gear 1 (normal -lambda n + friction).
    pub f_contact1: [f64; 3],
    /// Total contact force on gear 2 (normal +lambda n + friction).
    pub f_contact2: [f64; 3],
    /// Total contact moment on gear 1 about c1 (normal load distributed along the lines + friction).
    pub m_contact1: [f64; 3],
    /// Total contact moment on gear 2 about c2.
    pub m_contact2: [f64; 3],
}
