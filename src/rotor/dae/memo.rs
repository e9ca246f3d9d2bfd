//! One-entry memo of the mesh and the friction sums of the last kinematic state.
//!
//! Why: with inputs that change at every communication point, the same positions and
//! velocities are evaluated three times in a row - the outputs at the end of a doStep
//! (consistent lambda), the consistent lambda of the next doStep's new inputs, and the f
//! with which the stepper restarts - and the mesh plus the friction sums are ~80 % of an f
//! evaluation. The mesh depends on the displacements only; the sums of laws 1-3 on the
//! displacements, phi1 and the velocities (not on lambda, the inputs or the time), so a
//! memo keyed by the bits of those components returns exactly what a new evaluation
//! would; law 4's depend on lambda as well (the line load), which its key adds. For law
//! 4 the memo also links the scalar solve of the consistent lambda to what follows it:
//! the outputs at the root, and the stepper's f after an input change at the same
//! state and lambda. Only the
//! evaluations at a communication point (consistent lambda, outputs) are kept; the
//! integrator's stages and Jacobian columns read the memo but do not write it. Not part of
//! any state: a pure cache (the parameters it depends on - geometry, psi0, the law and
//! v_reg - are fixed for the model's life; the tunables mu and d_phi do not enter).

use super::super::{idx, NY};
use crate::gear::{FrictionSums, Mesh};
use nalgebra::SVector;
use std::cell::RefCell;

/// Components of y the friction sums depend on: u1, u2, phi1, the velocities, omega1.
const SUM_KEY: [usize; 15] = [
    0,
    1,
    2,
    3,
    4,
    5,
    idx::PHI1,
    idx::V,
    idx::V + 1,
    idx::V + 2,
    idx::V + 3,
    idx::V + 4,
    idx::V + 5,
    idx::V + 6,
    idx::OMEGA1,
];

#[derive(Debug, Clone, Copy, Default)]
struct Entries {
    mesh: Option<([u64; 6], Mesh)>,
    sums: Option<([u64; 16], FrictionSums)>,
}

/// The memo (interior mutability: f and the outputs take `&GearedRotor`).
#[derive(Debug, Clone, Default)]
pub(super) struct KinematicMemo(RefCell<Entries>);

fn mesh_key(y: &SVector<f64, NY>) -> [u64; 6] {
    std::array::from_fn(|i| y[i].to_bits())
}

fn sums_key(y: &SVector<f64, NY>, variant: u64) -> [u64; 16] {
    let mut k = [variant; 16];
    for (ki, &i) in k.iter_mut().zip(&SUM_KEY) {
        *ki = y[i].to_bits();
    }
    k
}

impl KinematicMemo {
    /// The mesh of y: from the memo or from `eval` (kept when it succeeds and `keep`).
    pub(super) fn mesh<E>(
        &self,
        y: &SVector<f64, NY>,
        keep: bool,
        eval: impl FnOnce() -> Result<Mesh, E>,
    ) -> Result<Mesh, E> {
        let key = mesh_key(y);
        if let Some((k, m)) = &self.0.borrow().mesh {
            if *k == key {
                return Ok(*m);
            }
        }
        let m = eval()?;
        if keep {
            self.0.borrow_mut().mesh = Some((key, m));
        }
        Ok(m)
    }

    /// The friction sums of y (`variant` tells apart sums of the same state that differ:
    /// law 2's mean coefficient integrated for the outputs, law 4's lambda): from the memo or
    /// from `eval` (kept when `keep`).
    pub(super) fn sums(
        &self,
        y: &SVector<f64, NY>,
        variant: u64,
        keep: bool,
        eval: impl FnOnce() -> FrictionSums,
    ) -> FrictionSums {
        let key = sums_key(y, variant);
        if let Some((k, s)) = &self.0.borrow().sums {
            if *k == key {
                return *s;
            }
        }
        let s = eval();
        if keep {
            self.0.borrow_mut().sums = Some((key, s));
        }
        s
    }
}
