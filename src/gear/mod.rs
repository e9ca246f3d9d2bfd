//! Gear pair geometry, mesh kinematics of the displaced centres, contact lines,
//! distributed Coulomb friction and the mesh stiffness of ISO 6336-1 (`model.md` §2-§4,
//! §9.7). No solver, no FMI.

// `!(a > b)` is used on purpose throughout: it also rejects NaN, which `a <= b` would let pass.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod backlash;
pub mod contact_lines;
pub mod friction;
pub mod geometry;
mod geometry_repair;
pub mod mesh;
pub mod stiffness;

pub use contact_lines::{ContactSummary, Segment};
pub use friction::law_params::FRICTION_PARAMETERS;
pub use friction::{
    line_integrals, EhlLine, Friction, FrictionLaw, FrictionParams, FrictionSums, IsoMean,
    LineIntegrals, LineLaw, Lubricant, PitchLine, StickAction, StuckLine,
};
pub use geometry::{inv, inv_inverse, GearData, PairGeometry, ParamError, GEAR_PARAMETERS};
pub use mesh::{Kinematics, Mesh, MeshError};
pub use stiffness::{c_gamma_used, MeshStiffness};
