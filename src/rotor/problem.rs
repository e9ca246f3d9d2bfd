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
    fn jacobian_fast(
        &mut self,
        t: f64,
        y: &SVector<f64, NY>,
        fast: &mut SMatrix<f64, NY, NY>,
    ) -> Result<bool, RhsError> {
        Ok(self.model.jacobian_fast(t, y, fast))
    }
    fn mass(&self) -> Option<SMatrix<f64, NY, NY>> {
        Some(self.model.mass())
    }
}

/// The RADAU5 options that describe the rotor DAE's structure, the one source for the
/// co-simulation and the periodic solutions (tolerances, h_max and step limits are theirs
/// to add): the index counts of the contact (`contact`); the energies as quadratures (they
/// enter no right-hand side: zero Jacobian columns and identity rows of `M_ext`, so 18 x 18
/// instead of 23 x 23 factorisations, radau5 `Options::quadrature`), and the last slot
/// where the contact makes it one; `u_i' = v_i` (i < 6) eliminated from the linear
/// systems, which leaves 12 x 12 LUs (radau5 `Options::second_order`, Fortran
/// IWORK(9..10)); the norm count of the contact.
///
/// What depends on the contact is its answer (`rotor::contact`): rigid teeth, an index-2
/// DAE whose multiplier lambda is the last slot; elastic teeth (`model.md` §3.5), an ODE
/// (`n1 = 23`, `n2 = 0`) whose last slot, the work stored in the mesh spring, is a
/// quadrature; the mesh damping's energy (`idx::E_MESH_DAMP`) is a quadrature in both,
/// counted in the solver's norms only where the teeth have a mesh damping.
pub fn dae_structure(contact: ToothContact) -> Options<NY> {
    let last = contact.last_slot();
    let (n1, n2) = last.index_counts();
    Options {
        n1,
        n2,
        n3: 0,
        quadrature: std::array::from_fn(|i| {
            (idx::E_IN..=idx::E_MESH_DAMP).contains(&i)
                || (i == idx::LAMBDA && last.is_quadrature())
        }),
        second_order: Some((6, idx::V)),
        norm_count: contact.norm_count(),
        ..Options::default()
    }
}
