//! The rotor DAE as a RADAU5 [`Problem`] and the solver structure it has, shared by the
//! co-simulation (`sim`) and the periodic solutions (`periodic`).

use super::{idx, GearedRotor, ToothContact, NY};
use crate::radau5::{Options, Problem, RhsError};
use nalgebra::{SMatrix, SVector};

/// The adapter that presents the rotor DAE to RADAU5 (`M y' = f(t, y)`).
#[derive(Clone)]
pub struct RotorProblem {
    /// The physics.
    pub model: GearedRotor,
}

impl Problem<NY> for RotorProblem {
    fn rhs(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        f: &mut SVector<f64, NY>,
    ) -> Result<(), RhsError> {
        // Allocation (the message) only on the error path.
        self.model.rhs(t, y, f).map_err(|e| RhsError {
            message: e.to_string(),
        })
    }
    fn jacobian(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        jac: &mut SMatrix<f64, NY, NY>,
    ) -> Result<bool, RhsError> {
        Ok(self.model.jacobian(t, y, jac))
    }
    fn mass(&self) -> Option<SMatrix<f64, NY, NY>> {
        Some(self.model.mass())
    }
}

/// The RADAU5 options that describe the rotor DAE's structure, the one source for the
/// co-simulation and the periodic solutions (tolerances, h_max and step limits are theirs
/// to add): index-1 and index-2 counts (lambda); the energies as quadratures (they enter no
/// right-hand side: zero Jacobian columns and identity rows of `M_ext`, so 18 x 18 instead
/// of 23 x 23 factorisations, radau5 `Options::quadrature`); `u_i' = v_i` (i < 6)
/// eliminated from the linear systems, which leaves 12 x 12 LUs (radau5
/// `Options::second_order`, Fortran IWORK(9..10)).
///
/// With the elastic contact (`model.md` §3.5) there is no constraint: an ODE (`n1 = 23`,
/// `n2 = 0`), whose last component, the work stored in the mesh spring, is a quadrature;
/// the mesh damping's energy (`idx::E_MESH_DAMP`) is a quadrature in both, counted in the
/// solver's norms only with elastic teeth (it is 0 with rigid ones).
pub fn dae_structure(contact: ToothContact) -> Options<NY> {
    let (n1, n2) = match contact {
        ToothContact::Rigid => (super::N_INDEX1, super::N_INDEX2),
        ToothContact::Elastic => (NY, 0),
    };
    Options {
        n1,
        n2,
        n3: 0,
        quadrature: std::array::from_fn(|i| {
            (idx::E_IN..=idx::E_MESH_DAMP).contains(&i)
                || (i == idx::LAMBDA && contact == ToothContact::Elastic)
        }),
        second_order: Some((6, idx::V)),
        // Rigid teeth have no mesh damping: E_MESH_DAMP stays 0 and out of the norms, so
        // that the steps are those of the 22 other components.
        norm_count: match contact {
            ToothContact::Rigid => NY - 1,
            ToothContact::Elastic => NY,
        },
        ..Options::default()
    }
}
