//! A contact line that sticks (`model.md` §4.1): the geometry the DAE needs to replace
//! Coulomb's force on it by the force that keeps it from sliding.
//!
//! On a spur pair the sliding speed is the same along a whole contact line, `x0 e_w`, and
//! it passes through zero when the line crosses the pitch line. There the Coulomb force on
//! the line, `-mu (|lambda| L / l) sign(x0) e_w` on gear 2, jumps by twice its size, and
//! when the bearings' motion can hold `x0` at zero while the force that does so stays within
//! `mu |lambda| L / l`, the line sticks: a sliding mode of Filippov's theory, with the
//! equivalent force in place of the sign. The DAE computes that force (`rotor::dae::stick`);
//! this type carries where it acts.

use super::super::contact_lines::Segment;
use super::super::geometry::PairGeometry;
use super::super::mesh::Mesh;
use nalgebra::Vector3;

/// How the contact line nearest zero sliding is treated in the friction sums
/// (`PairGeometry::sums_with_stick`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PitchLine {
    /// Like every other line (the friction law as it is).
    Slide,
    /// It sticks: left out of the sums, described in `FrictionSums::stuck`.
    Stick,
    /// It has just been released from sticking and slides in the sense of `sign` (+1: x0 >
    /// 0): while |x0| and the axial sliding |y| are within `band` (m/s), its Coulomb force
    /// is `e_w` times that sense, whatever the signs of the tiny x0 and y the integration
    /// leaves at the release (the force is continuous there: it equals the bound the stick
    /// force reached, which has no axial part). Why the axial part: Coulomb's direction
    /// `v_T / |v_T|` makes an axial sliding y next to a tiny x0 meet a friction force
    /// `mu N y / |x0|`, a damper of ~1e10 N s/m on the centres' z motion that the Newton
    /// iteration cannot follow (measured: a new Jacobian and 3-5 failed iterations per
    /// step after every release). Beyond the band the law applies as usual.
    Released {
        /// Sense of the sliding, +1 or -1.
        sign: f64,
        /// Half-width of the band in m/s.
        band: f64,
    },
}

/// The segment nearest zero sliding, held back until all segments are seen.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Held {
    /// Its contribution by the law.
    pub(crate) c: Contribution,
    /// Its contribution in the released sense (`PitchLine::Released`).
    pub(crate) hinted: Option<Contribution>,
    pub(crate) seg: Segment,
    pub(crate) x0: f64,
}

/// One segment's share of the friction sums in local components (e_w, t, e_z).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Contribution {
    /// I_x e_w + I_y c.
    pub(crate) f: [f64; 3],
    /// (P_k0 - c1) x (I_x e_w + I_y c) + K_x n.
    pub(crate) m1: [f64; 3],
    /// (P_k0 - c2) x (I_x e_w + I_y c) + K_x n.
    pub(crate) m2: [f64; 3],
    /// W.
    pub(crate) w: f64,
}

impl Contribution {
    pub(crate) fn add(&mut self, o: &Contribution) {
        for i in 0..3 {
            self.f[i] += o.f[i];
            self.m1[i] += o.m1[i];
            self.m2[i] += o.m2[i];
        }
        self.w += o.w;
    }
}

/// The stuck segment (kept small: the friction sums that carry it are copied through the
/// memo on every f; its action follows from the mesh when needed, [`StuckLine::action`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StuckLine {
    /// Sliding speed `x0 = e_w . v_rel` on the segment in m/s (0 while it sticks, up to the
    /// integration's drift).
    pub x0: f64,
    /// sigma of the segment's start point (along t from T1) in m.
    pub sigma0: f64,
    /// Inertial axial coordinate Z of its start point in m.
    pub z0: f64,
    /// Its length in m.
    pub length: f64,
}

/// What a unit tangential force on the stuck segment does: `+e_w` on gear 2 and `-e_w` on
/// gear 1, spread evenly along the segment (the even spread only decides the moments about
/// x and y, which act on no degree of freedom).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StickAction {
    /// e_w (inertial).
    pub e_w: Vector3<f64>,
    /// Moment about c1 of the unit force on gear 1, `(P_mid - c1) x (-e_w)`, in m.
    pub moment1: Vector3<f64>,
    /// Moment about c2 of the unit force on gear 2, `(P_mid - c2) x e_w`, in m.
    pub moment2: Vector3<f64>,
    /// The generalised force of the unit force on q = (u1, u2, phi2): `(-e_w, e_w,
    /// -moment2 . e_z)`. It is also the gradient of `x0` with respect to the velocities
    /// (u1', u2', omega2): the force does work `x0` per unit, as it must.
    pub generalised: [f64; 7],
}

impl StuckLine {
    pub(crate) fn new(seg: Segment, x0: f64) -> Self {
        StuckLine {
            x0,
            sigma0: seg.sigma0,
            z0: seg.z0,
            length: seg.length,
        }
    }

    /// The action of a unit force on this segment in the mesh `m` of pair `g` (the frame
    /// of `PairGeometry::friction_sums_line`).
    pub fn action(&self, m: &Mesh, g: &PairGeometry) -> StickAction {
        let (cb, sb) = (g.cos_beta_b, g.sin_beta_b);
        let h = 0.5 * self.length;
        // P_mid - c_j in local components; r x e_w = (0, r_z, -r_t).
        let r1 = [g.rb1, self.sigma0 - h * sb, self.z0 + h * cb - m.c1.z];
        let r2 = [
            -g.rb2,
            self.sigma0 - m.len_t1t2 - h * sb,
            self.z0 + h * cb - m.c2.z,
        ];
        let moment1 = m.to_inertial(0.0, -r1[2], r1[1]);
        let moment2 = m.to_inertial(0.0, r2[2], -r2[1]);
        let e_w = m.e_w;
        StickAction {
            e_w,
            moment1,
            moment2,
            generalised: [-e_w.x, -e_w.y, -e_w.z, e_w.x, e_w.y, e_w.z, -moment2.z],
        }
    }
}
