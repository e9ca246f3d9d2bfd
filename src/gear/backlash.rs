//! Backlash and the coast flanks (`model.md` §3.6): the play between the coast flanks at
//! the operating centre distance and in a displaced state, and where gear 1's coast flank
//! sits relative to its drive flank (the phase of the coast contact lines).
//!
//! Lengths in m, angles in rad. The coast side is the mirror image of the drive side in
//! the plane through both axes; `rotor::dae::coast` evaluates it as the drive contact of
//! the mirrored pair (helix hand and senses of rotation reversed).

use super::geometry::{inv, PairGeometry};
use std::f64::consts::FRAC_PI_2;

/// Minimum normal backlash recommended for ferrous gears in a ferrous housing by
/// ISO/TR 10064-2:1996 (clause 4, backlash): `j_bn,min = 2/3 (0.06 + 0.0005 a + 0.03 m_n)`
/// with all lengths in mm. Here in m for `a_w`, `m_n` in m. The default `j_bn` = 0.1 mm
/// is this value for the default pair (0.104 mm), rounded.
pub fn iso_min_backlash(a_w: f64, m_n: f64) -> f64 {
    2.0 / 3.0 * (0.06 + 0.0005 * a_w * 1e3 + 0.03 * m_n * 1e3) * 1e-3
}

impl PairGeometry {
    /// Transverse play between the coast flanks along the line of action when the drive
    /// flanks touch undeflected at the operating centre distance: `j_t = j_bn / cos beta_b`
    /// (`model.md` (3.26)), m.
    pub fn play(&self) -> f64 {
        self.data.j_bn / self.cos_beta_b
    }

    /// The play at the working pressure angle `alpha` of a displaced state:
    /// `j_t + 2 R (inv alpha - inv alpha_wt)` (`model.md` (3.25)); `d/da` of it is
    /// `2 sin alpha`, the textbook `Delta j = 2 Delta a sin alpha`.
    pub fn play_at(&self, alpha: f64) -> f64 {
        self.play() + 2.0 * self.r_sum * (inv(alpha) - self.inv_alpha_wt)
    }

    /// Base tooth thickness (arc on the base circle) of gear `j` (1 or 2) without
    /// thinning, from its profile shift (ISO 21771: `s_t = m_t (pi/2 + 2 x tan alpha_n)`,
    /// `s_bt = d_b (s_t / d + inv alpha_t)`), m (`model.md` (3.27)).
    pub fn base_tooth_thickness0(&self, j: usize) -> f64 {
        let d = &self.data;
        let (x, r, rb) = if j == 1 {
            (d.x1, self.r1, self.rb1)
        } else {
            (d.x2, self.r2, self.rb2)
        };
        let m_t = d.m_n / d.beta.cos();
        let s_t = m_t * (FRAC_PI_2 + 2.0 * x * d.alpha_n.tan());
        rb * (s_t / r + 2.0 * inv(self.alpha_t))
    }

    /// The thinning of both gears together that gives the backlash `j_bn` at a_w, along
    /// the line of action: `j_t` minus the play that a_w alone opens for teeth of the
    /// thickness of [`PairGeometry::base_tooth_thickness0`] (0 when a_w follows from the
    /// shifts, (2.6)), m (`model.md` §3.6, below (3.27)). Negative when `a_w_set` opens more play than
    /// `j_bn` (teeth thicker than their shifts say).
    pub fn thinning(&self) -> f64 {
        let d = &self.data;
        let (z1, z2) = (f64::from(d.z1), f64::from(d.z2));
        let inv_w0 = inv(self.alpha_t) + 2.0 * d.alpha_n.tan() * (d.x1 + d.x2) / (z1 + z2);
        self.play() - 2.0 * self.r_sum * (self.inv_alpha_wt - inv_w0)
    }

    /// The initial phase (in base pitches) of the coast contact lines in the mirrored pair
    /// (`model.md` §3.6, "How the model evaluates it"; (3.27)): gear 1's tooth whose drive flank lies at `s_d` on the drive
    /// line lies at `s_c = 2 r_b1 alpha + s_b1 - s_d` on the coast line, with gear 1's base
    /// tooth thickness `s_b1` less half the thinning.
    pub fn coast_phase(&self, psi0: f64) -> f64 {
        let s_b1 = self.base_tooth_thickness0(1) - 0.5 * self.thinning();
        (s_b1 - 2.0 * self.rb1 * self.inv_alpha_wt) / self.p_bt - psi0
    }

    /// Gap offset of the coast flanks (`model.md` (3.26)): with the drive gap offset g0,
    /// `g_c0 = j_t - 2 R inv alpha_wt - g0`, so that `g + g_c` is the play of
    /// [`PairGeometry::play_at`].
    pub fn coast_gap_offset(&self, g0: f64) -> f64 {
        self.play() - 2.0 * self.r_sum * self.inv_alpha_wt - g0
    }
}
