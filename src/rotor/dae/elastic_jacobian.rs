//! The Jacobian of f in the elastic contact (`model.md` §3.5) by the chain rule.
//!
//! f depends on the normal force `Fn(y)` of (3.16) exactly as the rigid f depends on lambda
//! (`lambda G^T`, the friction, the `E_in` row), so df/dy is the rigid Jacobian at
//! `lambda := Fn(y)` (partial derivatives at fixed lambda) plus its lambda column times
//! `dFn/dy`. f does not depend on the last slot (the work stored in the mesh spring, a
//! quadrature): its column is zero, and its row and the mesh damping's part of `E_damp`
//! come from the derivatives of the two powers. Against the stepper's forward differences
//! of f (22 evaluations) it takes the derivative of the active branch at the kinks of
//! (3.15) and costs less, 14-19 f (the friction columns are differences of the friction
//! evaluation, as in the rigid model; docs/model.md §3.5 "Cost"). Its fast part (the split
//! of radau5.md §8, `GearedRotor::jacobian_fast`) leaves out those columns and dl/dy,
//! about 2.5 f.
//!
//! The force law and the chain rule take one flank contact given by its approach, rate and
//! contact length with their gradients ([`FlankState`]), so that a second contact (a coast
//! flank) adds its terms the same way with its own state and lambda column.

use super::{ElasticMesh, GearedRotor, JacobianPart};
use crate::rotor::{idx, ModelError, NY};
use nalgebra::{SMatrix, SVector};

/// A gradient d/dy.
type Grad = SVector<f64, NY>;

/// A flank contact's kinematics at y with their gradients.
#[derive(Debug, Clone, Copy)]
pub(super) struct FlankState {
    /// Normal approach delta (3.13), m.
    pub delta: f64,
    /// Its rate delta' (3.14), m/s.
    pub delta_dot: f64,
    /// Contact length l (3.12), m.
    pub length: f64,
    /// d delta / dy.
    pub d_delta: Grad,
    /// d delta' / dy.
    pub d_delta_dot: Grad,
    /// dl / dy.
    pub d_length: Grad,
}

/// Normal force of a flank, `Fn = l max(0, c_l delta + d_l delta')` for delta > 0, else 0
/// (`model.md` (3.15), (3.16)), N.
pub(super) fn flank_force(e: &ElasticMesh, delta: f64, delta_dot: f64, length: f64) -> f64 {
    if delta > 0.0 {
        length * (e.c_l * delta + e.d_l * delta_dot).max(0.0)
    } else {
        0.0
    }
}

/// The gradients of a flank's force and of the powers of its spring and damper (§3.5).
/// At the kinks (delta = 0, the damping clipped where it would pull) the derivative of the
/// active branch: the zero branch is the one f takes at the kink itself.
#[derive(Debug, Clone, Copy)]
pub(super) struct FlankGradients {
    /// dFn/dy of (3.16).
    pub d_fn: Grad,
    /// d/dy of the power into the mesh spring, `p_spring = k delta delta'`, `k = c_l l`
    /// (the rate of the last slot of y).
    pub d_p_spring: Grad,
    /// d/dy of the mesh damping's power, `p_damp = Fn delta' - k delta delta'`.
    pub d_p_damp: Grad,
}

impl FlankGradients {
    /// The gradients for the flank state `s` of the mesh `e`.
    pub(super) fn new(e: &ElasticMesh, s: &FlankState) -> Self {
        let mut out = FlankGradients {
            d_fn: Grad::zeros(),
            d_p_spring: Grad::zeros(),
            d_p_damp: Grad::zeros(),
        };
        if !(s.delta > 0.0) {
            // Free flight: no force, no spring power, no damping.
            return out;
        }
        let (c, d, l) = (e.c_l, e.d_l, s.length);
        let q = c * s.delta + d * s.delta_dot;
        let fn_ = if q > 0.0 {
            // d(l q) = q dl + l (c_l d delta + d_l d delta').
            out.d_fn = s.d_length * q + (s.d_delta * c + s.d_delta_dot * d) * l;
            l * q
        } else {
            0.0
        };
        // d(c_l l delta delta').
        out.d_p_spring = s.d_length * (c * s.delta * s.delta_dot)
            + (s.d_delta * s.delta_dot + s.d_delta_dot * s.delta) * (c * l);
        out.d_p_damp = out.d_fn * s.delta_dot + s.d_delta_dot * fn_ - out.d_p_spring;
        out
    }
}

/// Adds the chain-rule columns of a contact force F(y): `jac += col dF/dy^T`, with `col`
/// = df/dF at fixed F. Nothing where dF/dy = 0 (free flight, damping clipped), so that a
/// non-finite entry of `col` there does not spread.
pub(super) fn add_force_columns(jac: &mut SMatrix<f64, NY, NY>, col: &Grad, d_fn: &Grad) {
    let col = col.as_slice();
    // On the column-major storage (column j is the j-th chunk of NY): nalgebra's element
    // iterators are strided loops, half of this Jacobian's cost.
    for (jcol, &dj) in jac.as_mut_slice().chunks_exact_mut(NY).zip(d_fn.as_slice()) {
        if dj != 0.0 {
            for (x, &ci) in jcol.iter_mut().zip(col) {
                *x += ci * dj;
            }
        }
    }
}

impl GearedRotor {
    /// df/dy in the elastic contact of the mesh `e` (module docs). No allocation.
    ///
    /// # Errors
    /// The mesh or the friction cannot be evaluated, or a non-finite entry (the caller then
    /// takes differences of f).
    pub(super) fn eval_elastic_jacobian(
        &self,
        e: &ElasticMesh,
        t: f64,
        y: &SVector<f64, NY>,
        jac: &mut SMatrix<f64, NY, NY>,
        part: JacobianPart,
    ) -> Result<(), ModelError> {
        let g = &self.geom;
        let lam_i = idx::LAMBDA;
        let m = self.mesh_for_f(t, y)?;
        let grow = g.constraint_row(&m);
        // (3.13) with the gap (3.7) and the offset g0; (3.14).
        let delta = -g.cos_beta_b * (g.gap_raw(&m, y[idx::Q + 6]) + self.g0);
        let mut gv = 0.0;
        for (i, gi) in grow.iter().enumerate() {
            gv += gi * y[idx::V + i];
        }
        let delta_dot = -(gv - g.rb1 * g.cos_beta_b * y[idx::OMEGA1]);
        let length = g.contact_summary(&m, y[idx::PHI1], self.params.psi0).length;
        let mut z = *y;
        z[lam_i] = flank_force(e, delta, delta_dot, length);
        let mut dl = [0.0; NY];
        // The fast part (`GearedRotor::jacobian_fast`) has no friction columns and no dl.
        self.eval_jacobian(t, &z, jac, &mut dl, part)?;
        // d delta/dy: -G for u (G = cos beta_b dg/dq, (3.9)); -cos beta_b for xi (dg/dxi = 1
        // in (3.7)); delta does not depend on phi1.
        let mut d_delta = Grad::zeros();
        for i in 0..6 {
            d_delta[idx::Q + i] = -grow[i];
        }
        d_delta[idx::Q + 6] = -g.cos_beta_b;
        // d delta'/dy: the rigid Jacobian's last row is the gradient of the velocity-level
        // constraint (5.2), `G(q) v - r_b1 cos beta_b omega1 = -delta'`, dG/dq v included.
        let d_delta_dot = -jac.row(lam_i).transpose();
        // dl/dy: a helical pair's l is piecewise linear in u and phi1 (the friction columns'
        // one-sided differences). A spur pair's is the pairs in contact times the face
        // overlap: steps in the mesh phase (u_x, u_y, phi1), 0 between them (a difference
        // across a step would be a spike, not a derivative); linear in the axial offset.
        let spur = g.tan_beta_b == 0.0;
        let axial = |j: usize| j == idx::Q + 2 || j == idx::Q + 5;
        let d_length = Grad::from_fn(|j, _| if !spur || axial(j) { dl[j] } else { 0.0 });
        let s = FlankState {
            delta,
            delta_dot,
            length,
            d_delta,
            d_delta_dot,
            d_length,
        };
        let grads = FlankGradients::new(e, &s);
        // df/dFn at fixed Fn: the rigid lambda column (rows of v, E_in, E_loss).
        let col = jac.column(lam_i).into_owned();
        jac.column_mut(lam_i).fill(0.0);
        add_force_columns(jac, &col, &grads.d_fn);
        // The last slot's rate is p_spring; E_MESH_DAMP's is p_damp (§3.5).
        jac.row_mut(lam_i).copy_from(&grads.d_p_spring.transpose());
        let mut r = jac.row_mut(idx::E_MESH_DAMP);
        r += grads.d_p_damp.transpose();
        if !jac.as_slice().iter().all(|x| x.is_finite()) {
            return Err(ModelError::NonFinite {
                t,
                what: "Jacobian",
            });
        }
        Ok(())
    }
}
