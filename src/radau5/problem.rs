//! The problem interface `M y' = f(t, y)` (radau5.md, problem form).

use nalgebra::{SMatrix, SVector};

use super::RhsError;

/// A problem `M y' = f(t, y)` with constant mass matrix `M`.
///
/// Components must be ordered index-1, then index-2, then index-3 (see
/// [`super::Options::n1`]). The stepper is generic over the problem type, so calls are
/// static (no dynamic dispatch in the inner loop).
pub trait Problem<const N: usize> {
    /// f(t, y). `Err` for a point where f is undefined (the stepper then shrinks h;
    /// persistent -> [`super::Error::Rhs`]).
    ///
    /// # Errors
    /// Whatever the problem cannot evaluate.
    fn rhs(&mut self, t: f64, y: &SVector<f64, N>, f: &mut SVector<f64, N>)
        -> Result<(), RhsError>;

    /// Analytic `df/dy` into `jac`; `Ok(false)` = not provided (the stepper then uses
    /// forward differences, radau5.md problem form).
    ///
    /// # Errors
    /// Whatever the problem cannot evaluate.
    fn jacobian(
        &mut self,
        _t: f64,
        _y: &SVector<f64, N>,
        _jac: &mut SMatrix<f64, N, N>,
    ) -> Result<bool, RhsError> {
        Ok(false)
    }

    /// The part of `df/dy` that changes fast along a solution, evaluated apart from the
    /// rest (radau5.md §8 "Split Jacobian"): `Ok(true)` with `fast` = F(t, y) where the
    /// full Jacobian is `J = S + F` and S, the rest, changes slowly enough to be carried
    /// from the last full evaluation. `Ok(false)` (the default): no such split, every
    /// renewal is a full [`Problem::jacobian`]. Asked right after every analytic J, at
    /// the same point (where it must give the split of that J), and where J is renewed:
    /// there S is the one of the last analytic J, even if [`Problem::jacobian`] would
    /// decline at this point; after a J by differences there is no S until the next
    /// analytic J (every renewal full).
    ///
    /// # Errors
    /// Whatever the problem cannot evaluate.
    fn jacobian_fast(
        &mut self,
        _t: f64,
        _y: &SVector<f64, N>,
        _fast: &mut SMatrix<f64, N, N>,
    ) -> Result<bool, RhsError> {
        Ok(false)
    }

    /// Constant mass matrix M of `M y' = f`; `None` = identity. Called once at construction.
    fn mass(&self) -> Option<SMatrix<f64, N, N>> {
        None
    }
}
