//! Mesh kinematics of the displaced centres (`model.md` §3.1-§3.3): line of action,
//! contact normal, gap function and constraint row.

use super::geometry::{inv, PairGeometry};
use nalgebra::Vector3;
use std::fmt;

/// Why the mesh of a displaced state cannot be evaluated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MeshError {
    /// The centres came so close that no line of action exists (`a <= R`, §3.1).
    CentreDistanceTooSmall {
        /// Actual transverse centre distance a.
        a: f64,
        /// R = r_b1 + r_b2.
        r_sum: f64,
    },
    /// A displacement was NaN or infinite.
    NonFinite,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::CentreDistanceTooSmall { a, r_sum } => write!(
                f,
                "centre distance a = {a} m must exceed r_b1 + r_b2 = {r_sum} m"
            ),
            MeshError::NonFinite => write!(f, "non-finite centre displacement"),
        }
    }
}

impl std::error::Error for MeshError {}

/// Line of action and plane-of-action frame of a displaced state (`model.md` §3.1, §3.2).
///
/// The right-handed local frame (e_w, t, e_z) is the transverse frame rotated by
/// `psi = theta - alpha` about e_z; `c` and `n` lie in the (t, e_z) plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mesh {
    /// Centre of gear 1, c1 = u1.
    pub c1: Vector3<f64>,
    /// Centre of gear 2, c2 = a_w e_x + u2.
    pub c2: Vector3<f64>,
    /// Transverse centre distance a = |d|.
    pub a: f64,
    /// Direction angle theta of d = (c2 - c1)_xy.
    pub theta: f64,
    /// Working pressure angle alpha = acos(R / a).
    pub alpha: f64,
    /// cos(theta - alpha).
    pub cos_psi: f64,
    /// sin(theta - alpha).
    pub sin_psi: f64,
    /// e_w = (cos(theta-alpha), sin(theta-alpha), 0): from c1 to T1.
    pub e_w: Vector3<f64>,
    /// t = e_z x e_w: line of action, T1 -> T2.
    pub t: Vector3<f64>,
    /// n = cos beta_b t + sin beta_b e_z: outward normal of gear 1's flank.
    pub n: Vector3<f64>,
    /// c = -sin beta_b t + cos beta_b e_z: direction of a contact line.
    pub c: Vector3<f64>,
    /// T1 = c1 + r_b1 e_w, taken at Z = 0.
    pub t1: Vector3<f64>,
    /// |T1 T2| = a sin alpha.
    pub len_t1t2: f64,
    /// Start of contact sigma_A = a sin alpha - sqrt(r_a2^2 - r_b2^2) (§2 in the displaced state).
    pub sigma_a: f64,
    /// End of contact sigma_E = sqrt(r_a1^2 - r_b1^2).
    pub sigma_e: f64,
    /// Lower bound of the active face: max(u1z, u2z) - b/2.
    pub z_lo: f64,
    /// Upper bound of the active face: min(u1z, u2z) + b/2.
    pub z_hi: f64,
}

impl Mesh {
    /// The point P(sigma, Z) = T1 + sigma t + Z e_z of the plane of action (§3.4).
    pub fn point(&self, sigma: f64, z: f64) -> Vector3<f64> {
        self.t1 + sigma * self.t + Vector3::new(0.0, 0.0, z)
    }

    /// Rotates local plane-of-action components (along e_w, t, e_z) into the inertial frame.
    #[inline]
    pub fn to_inertial(&self, w: f64, t: f64, z: f64) -> Vector3<f64> {
        Vector3::new(
            w * self.cos_psi - t * self.sin_psi,
            w * self.sin_psi + t * self.cos_psi,
            z,
        )
    }
}

/// Rigid-body velocities of the two gears (`model.md` §4).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Kinematics {
    /// Centre velocity of gear 1, du1/dt.
    pub v1: Vector3<f64>,
    /// Centre velocity of gear 2, du2/dt.
    pub v2: Vector3<f64>,
    /// Speed of gear 1 about +e_z.
    pub omega1: f64,
    /// Speed of gear 2 about -e_z (phi2 dot).
    pub omega2: f64,
}

impl PairGeometry {
    /// Line of action of the displaced state (`model.md` §3.1, §3.2).
    ///
    /// # Errors
    /// [`MeshError::CentreDistanceTooSmall`] when `a <= r_b1 + r_b2`,
    /// [`MeshError::NonFinite`] for NaN/inf displacements.
    pub fn mesh(&self, u1: &Vector3<f64>, u2: &Vector3<f64>) -> Result<Mesh, MeshError> {
        let dx = self.a_w + u2.x - u1.x;
        let dy = u2.y - u1.y;
        if !(dx.is_finite() && dy.is_finite() && u1.z.is_finite() && u2.z.is_finite()) {
            return Err(MeshError::NonFinite);
        }
        let a = (dx * dx + dy * dy).sqrt();
        if !(a > self.r_sum) {
            return Err(MeshError::CentreDistanceTooSmall {
                a,
                r_sum: self.r_sum,
            });
        }
        let theta = dy.atan2(dx);
        let cos_a = self.r_sum / a;
        let alpha = cos_a.acos();
        let sin_a = (1.0 - cos_a * cos_a).sqrt();
        // cos/sin(theta - alpha) from the components of d: no extra trig calls.
        let (ct, st) = (dx / a, dy / a);
        let cos_psi = ct * cos_a + st * sin_a;
        let sin_psi = st * cos_a - ct * sin_a;
        let e_w = Vector3::new(cos_psi, sin_psi, 0.0);
        let t = Vector3::new(-sin_psi, cos_psi, 0.0);
        let (cb, sb) = (self.cos_beta_b, self.sin_beta_b);
        let n = Vector3::new(-cb * sin_psi, cb * cos_psi, sb);
        let c = Vector3::new(sb * sin_psi, -sb * cos_psi, cb);
        let len_t1t2 = a * sin_a;
        let half_b = 0.5 * self.data.b;
        Ok(Mesh {
            c1: *u1,
            c2: Vector3::new(self.a_w + u2.x, u2.y, u2.z),
            a,
            theta,
            alpha,
            cos_psi,
            sin_psi,
            e_w,
            t,
            n,
            c,
            t1: Vector3::new(u1.x + self.rb1 * cos_psi, u1.y + self.rb1 * sin_psi, 0.0),
            len_t1t2,
            sigma_a: len_t1t2 - self.rho_a2,
            sigma_e: self.sigma_e,
            z_lo: u1.z.max(u2.z) - half_b,
            z_hi: u1.z.min(u2.z) + half_b,
        })
    }

    /// Gap along the line of action without the offset g0 (`model.md` §3.3):
    ///
    /// `g - g0 = R (inv alpha + theta) + te + tan beta_b (u2z - u1z)`,
    /// with `te = r_b2 phi2 - r_b1 phi1` the transmission-error coordinate.
    pub fn gap_raw(&self, m: &Mesh, te: f64) -> f64 {
        self.r_sum * (inv(m.alpha) + m.theta) + te + self.tan_beta_b * (m.c2.z - m.c1.z)
    }

    /// Constraint row `G(q) = [-n, n, r_b2 cos beta_b] = cos beta_b dg/dq` (`model.md` §3.3),
    /// for q = [u1, u2, phi2].
    pub fn constraint_row(&self, m: &Mesh) -> [f64; 7] {
        [
            -m.n.x,
            -m.n.y,
            -m.n.z,
            m.n.x,
            m.n.y,
            m.n.z,
            self.rb2 * self.cos_beta_b,
        ]
    }

    /// Normal relative velocity `G q' - r_b1 cos beta_b omega1` (`model.md` §3.3).
    pub fn normal_velocity(&self, m: &Mesh, k: &Kinematics) -> f64 {
        m.n.dot(&(k.v2 - k.v1)) + self.cos_beta_b * (self.rb2 * k.omega2 - self.rb1 * k.omega1)
    }

    /// `dG/dt q'` for the hidden constraint (`model.md` §7): G_xy = cos beta_b t(psi) with
    /// psi = theta - alpha, dt/dpsi = -e_w, so `G' q' = -cos beta_b (e_w . d') psi'`, where
    /// `theta' = (d x d')_z / a^2` and `alpha' = R a' / (a^2 sin alpha)`, `a' = d . d' / a`.
    pub fn constraint_row_dot_v(&self, m: &Mesh, k: &Kinematics) -> f64 {
        let dd = k.v2 - k.v1;
        let (ddx, ddy) = (dd.x, dd.y);
        let d = m.c2 - m.c1;
        let a2 = m.a * m.a;
        let theta_dot = (d.x * ddy - d.y * ddx) / a2;
        let a_dot = (d.x * ddx + d.y * ddy) / m.a;
        let alpha_dot = self.r_sum * a_dot / (a2 * m.alpha.sin());
        let psi_dot = theta_dot - alpha_dot;
        -self.cos_beta_b * (m.e_w.x * ddx + m.e_w.y * ddy) * psi_dot
    }

    /// Relative velocity `v_rel = v2(P) - v1(P)` of the material points at P (`model.md` §4),
    /// with v1(P) = u1' + omega1 e_z x (P - c1) and v2(P) = u2' - omega2 e_z x (P - c2).
    pub fn relative_velocity(&self, m: &Mesh, k: &Kinematics, p: &Vector3<f64>) -> Vector3<f64> {
        let ez = Vector3::z();
        let v1 = k.v1 + k.omega1 * ez.cross(&(p - m.c1));
        let v2 = k.v2 - k.omega2 * ez.cross(&(p - m.c2));
        v2 - v1
    }
}
