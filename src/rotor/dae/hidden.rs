//! The hidden constraint (`model.md` §7): the time derivative of the velocity constraint
//! (5.2) with the accelerations of (5.1) put in, `lambda A + G M^-1 Q_f(lambda) = r`. One
//! assembly for the closed form of laws 1 and 2 and the scalar solve of laws 3 and 4.

use super::{kinematics, GearedRotor};
use crate::gear::{Mesh, StuckLine};
use crate::rotor::{idx, NY};
use nalgebra::SVector;

/// `G' M^-1 (...)` data of the hidden constraint at a state: the (projected) constraint row
/// `gp`, `A = G' M^-1 G^T` and `r = r_b1 cos(beta_b) omega1' - G' v - G' M^-1 F (+ c
/// x0_free)`, F the forces of (5.1) without contact (dampers, springs, load torque).
/// Without a stuck line `G' = G`; with one, the stick force is eliminated first
/// (`model.md` (4.14)).
#[derive(Debug, Clone, Copy)]
pub(crate) struct HiddenConstraint {
    pub(crate) gp: [f64; 7],
    pub(crate) a: f64,
    pub(crate) r: f64,
}

impl GearedRotor {
    /// The hidden constraint's row, A and r at y (mesh `m` of y), with the stick force of
    /// `stuck` eliminated when a line sticks.
    pub(crate) fn hidden_constraint(
        &self,
        t: f64,
        y: &SVector<f64, NY>,
        m: &Mesh,
        stuck: Option<&StuckLine>,
    ) -> HiddenConstraint {
        let g = &self.geom;
        let grow = g.constraint_row(m);
        let kin = kinematics(y);
        let v = idx::V;
        let t_load = self.inputs.t_load_at(t);
        let (gp, r_stick) = self.projected_row(y, m, &grow, stuck);
        let (mut a, mut r) = (0.0, r_stick);
        for i in 0..7 {
            let mut force = -self.damp[i] * y[v + i] - self.stiff[i] * y[i];
            if i == 6 {
                force -= t_load;
            }
            a += gp[i] * grow[i] / self.mass[i];
            r -= gp[i] * force / self.mass[i];
        }
        r += g.rb1 * g.cos_beta_b * y[idx::OMEGA1_DOT] - g.constraint_row_dot_v(m, &kin);
        HiddenConstraint { gp, a, r }
    }

    /// The constraint row with the stick force of `stuck` eliminated (`model.md` (4.14)):
    /// `G' = G - c w` with `c = (G M^-1 w) / (w^T M^-1 w)`, and the term `c x0_free` that r
    /// gains; `(G, 0)` without a stuck line.
    fn projected_row(
        &self,
        y: &SVector<f64, NY>,
        m: &Mesh,
        grow: &[f64; 7],
        stuck: Option<&StuckLine>,
    ) -> ([f64; 7], f64) {
        let Some(st) = stuck else {
            return (*grow, 0.0);
        };
        let row = self.stick_row(y, m, st);
        let gw: f64 = (0..7).map(|i| grow[i] * row.w[i] / self.mass[i]).sum();
        let c = gw / row.a_w;
        (
            std::array::from_fn(|i| grow[i] - c * row.w[i]),
            c * row.free,
        )
    }
}
