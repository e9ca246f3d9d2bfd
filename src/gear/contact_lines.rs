//! Contact lines in the plane of action (`model.md` §3.4): the drive flank of tooth k of
//! gear 1 meets the plane of action on the straight line
//!
//! `sigma_k(Z) = r_b1 (phi1 - theta + alpha + inv alpha_wt) - (Z - u1z) tan beta_b + (k + psi0) p_bt`,
//!
//! clipped to the active rectangle `[sigma_A, sigma_E] x [Z_lo, Z_hi]`.

use super::geometry::PairGeometry;
use super::mesh::Mesh;

/// Upper bound of the lines visited per evaluation (validation keeps
/// eps_alpha + eps_beta <= 60, so at most 62 lines can touch the rectangle).
pub const MAX_LINES: i64 = 64;

/// One contact line clipped to the active rectangle, from its end with the smaller Z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Tooth index k (relative to the reduced phase; only its differences mean anything).
    pub k: i64,
    /// sigma of the start point P_k0 (along t, from T1).
    pub sigma0: f64,
    /// Inertial axial coordinate Z of P_k0.
    pub z0: f64,
    /// Length L_k = dZ_k / cos beta_b; the segment runs along +c.
    pub length: f64,
}

/// Total contact length and number of pairs in contact.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactSummary {
    /// l = sum L_k.
    pub length: f64,
    /// Number of non-empty segments.
    pub pairs: i32,
}

/// `x` reduced to [0, p) like `rem_euclid`, but by one fused multiply-add instead of the
/// exact `fmod` (a bit-by-bit long division in software, 3 % of a whole simulation's CPU):
/// the error is one rounding of the result plus `n` times that of `p`, of the order of the
/// rounding error `x` itself carries.
#[inline]
pub fn reduce(x: f64, p: f64) -> f64 {
    let r = (-(x / p).floor()).mul_add(p, x);
    let r = if r < 0.0 { r + p } else { r };
    // r + p rounds to p for r just below 0; r >= p after a quotient rounded down.
    if r >= p {
        (r - p).max(0.0)
    } else {
        r
    }
}

impl PairGeometry {
    /// Mesh phase `s = r_b1 (phi1 - theta + alpha + inv alpha_wt) + psi0 p_bt`, reduced to
    /// [0, p_bt) (`model.md` §3.4).
    ///
    /// phi1 grows without bound, so it is reduced modulo the mesh period 2 pi / z1 before
    /// it is multiplied out: the phase then keeps its absolute accuracy however long the run.
    pub fn mesh_phase(&self, m: &Mesh, phi1: f64, psi0: f64) -> f64 {
        let phi_red = reduce(phi1, self.phi1_period);
        let s = self.rb1 * (phi_red - m.theta + m.alpha + self.inv_alpha_wt)
            + reduce(psi0, 1.0) * self.p_bt;
        reduce(s, self.p_bt)
    }

    /// Visits every non-empty contact segment of the current mesh phase (`model.md` §3.4)
    /// and returns the total length and the number of pairs in contact. No allocation.
    ///
    /// Spur gears (beta_b = 0): a line is in contact over the whole face when
    /// `sigma_A <= sigma_k < sigma_E` (half-open so that a line on the boundary is counted once).
    pub fn for_each_segment<F: FnMut(&Segment)>(
        &self,
        m: &Mesh,
        phi1: f64,
        psi0: f64,
        mut f: F,
    ) -> ContactSummary {
        let mut sum = ContactSummary::default();
        let (z_lo, z_hi) = (m.z_lo, m.z_hi);
        if !(z_hi > z_lo) {
            return sum;
        }
        let s_ph = self.mesh_phase(m, phi1, psi0);
        let p = self.p_bt;
        let tau = self.tan_beta_b;
        let u1z = m.c1.z;
        let (sa, se) = (m.sigma_a, m.sigma_e);
        // sigma_k(Z) = s_k - (Z - u1z) tau with s_k = s_ph + k p.
        let w1 = (z_lo - u1z) * tau;
        let w2 = (z_hi - u1z) * tau;
        let (w_lo, w_hi) = (w1.min(w2), w1.max(w2));
        if !(s_ph.is_finite() && sa.is_finite() && w_lo.is_finite() && w_hi.is_finite()) {
            return sum;
        }
        // Saturating: absurd (but finite) displacements must not overflow the tooth index.
        let k_min = (((sa + w_lo - s_ph) / p).ceil() as i64).saturating_sub(1);
        let k_max = (((se + w_hi - s_ph) / p).floor() as i64).saturating_add(1);
        let k_max = k_max.min(k_min.saturating_add(MAX_LINES));
        let inv_cb = 1.0 / self.cos_beta_b;
        for k in k_min..=k_max {
            let s_k = s_ph + k as f64 * p;
            let (z0, z1) = if tau == 0.0 {
                if s_k >= sa && s_k < se {
                    (z_lo, z_hi)
                } else {
                    continue;
                }
            } else {
                let za = u1z + (s_k - sa) / tau;
                let ze = u1z + (s_k - se) / tau;
                (za.min(ze).max(z_lo), za.max(ze).min(z_hi))
            };
            if z1 > z0 {
                let seg = Segment {
                    k,
                    sigma0: s_k - (z0 - u1z) * tau,
                    z0,
                    length: (z1 - z0) * inv_cb,
                };
                sum.length += seg.length;
                sum.pairs += 1;
                f(&seg);
            }
        }
        sum
    }

    /// Total contact length and pairs in contact (`model.md` §3.4).
    pub fn contact_summary(&self, m: &Mesh, phi1: f64, psi0: f64) -> ContactSummary {
        self.for_each_segment(m, phi1, psi0, |_| {})
    }
}
