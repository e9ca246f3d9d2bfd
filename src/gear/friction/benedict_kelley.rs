//! Law 5: the instantaneous coefficient of Benedict & Kelley (1961) along every contact
//! line.
//!
//! G. H. Benedict, B. W. Kelley, "Instantaneous coefficients of gear tooth friction",
//! ASLE Transactions 4 (1961) 59-70, fitted to disc-machine measurements; in the form the
//! gear dynamics literature uses it (He, Cho & Singh 2008, J. Sound Vib. 309, and the
//! efficiency study of Xu et al. 2007, which lists it among the published formulas):
//!
//! `mu = 0.0127 C_R log10(3.17e8 W / (nu0 V_s V_r^2))`,  `C_R = 50 / (50 - S)`,
//!
//! in the original's imperial units: W (lbf/in) the normal load per unit length of the
//! contact line, nu0 (cP) the dynamic viscosity of the oil at its inlet temperature,
//! V_s (in/s) the sliding speed, V_r (in/s) the rolling (sum) speed `V_1 + V_2` of the two
//! surfaces, S (micro-inch) the average roughness of the two flanks. The equation
//! number of the primary text could not be checked here (its text was not available);
//! `docs/friction.md` says what rests on secondary sources.
//!
//! In SI (W in N/m, V in m/s, viscosity still in cP = mPa s): 1 lbf/in = 175.126835 N/m,
//! 1 in/s = 0.0254 m/s, so the constant becomes
//! `3.17e8 * 0.0254^3 / 175.126835 = 29.6625` ([`K_SI`]); a restatement in SI with another
//! constant has converted differently (e.g. with the entraining speed `V_r / 2`, which
//! multiplies the argument by 4). S = Ra (m) / 0.0254e-6.
//!
//! Along a line, at the distance sigma from T1 (line of action of length L_t):
//! `V_r = omega1 sigma + omega2 (L_t - sigma)` (floored at [`V_R_MIN`]), `V_s = |v_T|`
//! (the sliding speed of the Coulomb line integrals), `W = q = |lambda| / l`.
//!
//! Near the pitch line (V_s -> 0) the formula diverges logarithmically. Here the
//! coefficient is bounded and the force made continuous: below the speed `v_reg`
//! (parameter of law 2) the force per unit length falls off linearly with the sliding,
//! `mu_loc = mu_BK(v_reg) V_s / v_reg`, above it `mu_loc = mu_BK(V_s)`. The force density
//! is `-q mu_BK(max(V_s, v_reg)) v_T / max(V_s, v_reg)`, continuous in v_T, so law 5 has
//! no jump at the sliding reversal (not "sharp"). mu_BK is floored at 0 (the logarithm
//! turns negative at light loads and high speeds, outside the fit).
//! No allocation.

use super::ehl::batch_math;
use super::ehl::quadrature::Acc;
use super::ehl::rules::{GL8_W, GL8_X};
use super::LineIntegrals;

/// Benedict & Kelley's leading factor 0.0127.
pub const BK_FACTOR: f64 = 0.0127;
/// The constant of the argument in the original's imperial units (W lbf/in, nu0 cP,
/// V in/s).
pub const BK_ARG_IMPERIAL: f64 = 3.17e8;
/// The roughness constant of `C_R = 50 / (50 - S)` (micro-inch).
pub const BK_S0_MICROINCH: f64 = 50.0;
/// 1 inch in m (exact).
pub const INCH: f64 = 0.0254;
/// 1 lbf in N (exact: 0.45359237 kg x 9.80665 m/s^2).
pub const LBF: f64 = 4.448_221_615_260_5;
/// The constant of the argument with W in N/m, V in m/s and nu0 in cP:
/// `3.17e8 INCH^3 / (LBF / INCH)` = 29.6625.
pub const K_SI: f64 = BK_ARG_IMPERIAL * INCH * INCH * INCH * INCH / LBF;
/// Floor of the rolling (sum) speed V_r (m/s) (standstill).
pub const V_R_MIN: f64 = 1e-3;
/// The largest roughness the formula admits, S < 50 micro-inch = 1.27e-6 m.
pub const RA_MAX: f64 = BK_S0_MICROINCH * INCH * 1e-6;

/// `C_R = 50 / (50 - S)` for the roughness Ra (m) (S in micro-inch); None for
/// Ra >= 1.27e-6 m, where the formula has no value.
pub fn roughness_factor(ra: f64) -> Option<f64> {
    let s = ra / (INCH * 1e-6);
    (s < BK_S0_MICROINCH).then(|| BK_S0_MICROINCH / (BK_S0_MICROINCH - s))
}

/// Benedict & Kelley's coefficient in SI units (W N/m, eta Pa s, V_s and V_r m/s, Ra m),
/// literally (no bound at small sliding, no floor at 0): the reference of the tests.
pub fn mu_benedict_kelley(w: f64, eta: f64, v_s: f64, v_r: f64, ra: f64) -> f64 {
    let c_r = roughness_factor(ra).unwrap_or(f64::NAN);
    BK_FACTOR * c_r * (K_SI * w / (eta * 1e3 * v_s * v_r * v_r)).log10()
}

/// Law 5 for one evaluation: the line load, the speeds and the oil fixed, constants folded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BkLine {
    /// `0.0127 C_R / ln 10`.
    b: f64,
    /// `ln(K_SI q / nu0[cP])`.
    ln_k: f64,
    /// The speed below which the force falls off linearly (m/s).
    v_reg: f64,
    omega1: f64,
    omega2: f64,
    /// L_t = a sin alpha (m).
    lt: f64,
    sin_beta_b: f64,
}

impl BkLine {
    /// Law 5 at line load `q = |lambda| / l` (N/m), viscosity `eta` (Pa s), roughness
    /// `ra` (m, < [`RA_MAX`]), bound speed `v_reg` (m/s, > 0), speeds omega1, omega2
    /// (rad/s), on the line of action of length `lt` (m) with base helix angle beta_b.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        q: f64,
        eta: f64,
        ra: f64,
        v_reg: f64,
        omega1: f64,
        omega2: f64,
        lt: f64,
        sin_beta_b: f64,
    ) -> Self {
        let c_r = roughness_factor(ra).unwrap_or(0.0);
        BkLine {
            b: BK_FACTOR * c_r / std::f64::consts::LN_10,
            ln_k: (K_SI * q.abs() / (eta * 1e3)).ln(),
            v_reg,
            omega1,
            omega2,
            lt,
            sin_beta_b,
        }
    }

    /// `mu_BK(max(r, v_reg)) / max(r, v_reg)` at sigma for the sliding speed r >= 0: the
    /// force density per unit line load and unit sliding velocity (`mu_loc = r` times this).
    #[inline]
    pub fn g_at(&self, sigma: f64, r: f64) -> f64 {
        let re = r.max(self.v_reg);
        let vr = (self.omega1 * sigma + self.omega2 * (self.lt - sigma))
            .abs()
            .max(V_R_MIN);
        let mu = self.b * (self.ln_k - (re * vr * vr).ln());
        mu.max(0.0) / re
    }

    /// The local coefficient `mu_loc` at sigma for the sliding speed r >= 0.
    pub fn mu_at(&self, sigma: f64, r: f64) -> f64 {
        r * self.g_at(sigma, r)
    }

    /// The five integrals of `mu_loc(s) v_T / |v_T|` (and `int mu_loc r ds` as W) for one
    /// segment starting at sigma0, per unit line load, and `int mu_loc ds`.
    ///
    /// Quadrature: the integrand is `g v_T` with `g` smooth in s except where the
    /// sliding is small: a kink where `|v_T| = v_reg` and, beyond it, `ln |v_T|` with its
    /// branch points at `x = +-i|y|`. With d the distance (in s) from the point x = 0 of the
    /// line, the segment is split at `d_k = sqrt(v_reg^2 - y^2)/|kappa|` (the kink, when
    /// |y| < v_reg), at `d_y = |y|/|kappa|`, and from `max(d_k, d_y)` on into graded panels
    /// [a, 4a] (the nearest singularity a away from a panel of length 3a: Bernstein
    /// ellipse rho = 3, 8 Gauss-Legendre points, error ~3^-16 = 2e-8 of a panel);
    /// 8 points on each panel. Spur lines (kappa = 0 and beta_b = 0) need one evaluation.
    pub fn segment_integrals(
        &self,
        x0: f64,
        y: f64,
        kappa: f64,
        len: f64,
        sigma0: f64,
    ) -> (LineIntegrals, f64) {
        if !(len > 0.0) {
            return (LineIntegrals::default(), 0.0);
        }
        let mut acc = Acc::default();
        if kappa == 0.0 {
            if self.sin_beta_b == 0.0 {
                // Spur line: sigma, v_T and so mu are constant along it.
                let r = x0.hypot(y);
                let g = self.g_at(sigma0, r);
                let k = 0.5 * len * len;
                return (
                    LineIntegrals {
                        ix: len * g * x0,
                        iy: len * g * y,
                        kx: k * g * x0,
                        ky: k * g * y,
                        w: len * g * r * r,
                    },
                    len * g * r,
                );
            }
            // v_T constant, only V_r varies (smoothly) along the line.
            self.panel(&mut acc, x0, y, 0.0, sigma0, 0.0, len);
            return acc.finish(y);
        }
        let ak = kappa.abs();
        let s_p = x0 / kappa;
        let d_k = if y.abs() < self.v_reg {
            (self.v_reg * self.v_reg - y * y).sqrt() / ak
        } else {
            0.0
        };
        let d_y = y.abs() / ak;
        let a0 = d_k.max(d_y);
        // t = s - s_p; the segment covers t in [t0, t1].
        let (t0, t1) = (-s_p, len - s_p);
        // A segment on one side of x = 0 that one panel covers (ratio <= 4, no break
        // inside): integrated in s directly. The same panel as below, but without mapping
        // through s_p, which cancels when kappa is tiny (near standstill, |s_p| >> len).
        if t0 >= 0.0 || t1 <= 0.0 {
            let (d_lo, d_hi) = if t0 >= 0.0 { (t0, t1) } else { (-t1, -t0) };
            let inside = |d: f64| d_lo < d && d < d_hi;
            if d_hi <= 4.0 * d_lo.max(a0) && !inside(d_k) && !inside(d_y) {
                self.panel(&mut acc, x0, y, kappa, sigma0, 0.0, len);
                return acc.finish(y);
            }
        }
        for side in [1.0f64, -1.0] {
            // distances d >= 0 on this side: t = side d
            let (d_lo, d_hi) = if side > 0.0 {
                (t0.max(0.0), t1)
            } else {
                ((-t1).max(0.0), -t0)
            };
            if !(d_hi > d_lo) {
                continue;
            }
            let mut lo = d_lo;
            while lo < d_hi {
                let b = if d_k > lo {
                    d_k
                } else if d_y > lo {
                    d_y
                } else {
                    4.0 * lo.max(a0)
                };
                let hi = b.min(d_hi);
                let (sa, sb) = (s_p + side * lo, s_p + side * hi);
                let (sa, sb) = if sa < sb { (sa, sb) } else { (sb, sa) };
                self.panel(&mut acc, x0, y, kappa, sigma0, sa.max(0.0), sb.min(len));
                lo = hi;
            }
        }
        acc.finish(y)
    }

    /// 8-point Gauss-Legendre on [sa, sb] in s, added to `acc`. The nodes are evaluated
    /// together, one loop per step, with the branch-free `ln` of law 4 (vectorised).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn panel(&self, acc: &mut Acc, x0: f64, y: f64, kappa: f64, sigma0: f64, sa: f64, sb: f64) {
        if !(sb > sa) {
            return;
        }
        let len = sb - sa;
        let y2 = y * y;
        let (mut s, mut x, mut r2, mut r, mut re, mut arg) =
            ([0.0; 8], [0.0; 8], [0.0; 8], [0.0; 8], [0.0; 8], [0.0; 8]);
        for i in 0..8 {
            s[i] = sa + len * GL8_X[i];
            x[i] = x0 - kappa * s[i];
            r2[i] = x[i] * x[i] + y2;
            r[i] = r2[i].sqrt();
            re[i] = r[i].max(self.v_reg);
            let sigma = sigma0 - self.sin_beta_b * s[i];
            let vr = (self.omega1 * sigma + self.omega2 * (self.lt - sigma))
                .abs()
                .max(V_R_MIN);
            arg[i] = re[i] * vr * vr;
        }
        let mut lnv = [0.0; 8];
        for i in 0..8 {
            lnv[i] = batch_math::ln(arg[i]);
        }
        for i in 0..8 {
            let mu = (self.b * (self.ln_k - lnv[i])).max(0.0);
            let wg = len * GL8_W[i] * mu / re[i];
            acc.ix += wg * x[i];
            acc.iy += wg;
            acc.kx += wg * x[i] * s[i];
            acc.ky += wg * s[i];
            acc.w += wg * r2[i];
            acc.mu += wg * r[i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The SI constant from the conversions, by hand: 3.17e8 x 0.0254^3 / 175.126835.
    #[test]
    fn si_constant_by_hand() {
        let lbf_per_in = LBF / INCH; // 175.126835 N/m
        assert!((lbf_per_in - 175.126_835_3).abs() < 1e-6);
        assert!((K_SI - 29.662_5).abs() < 1e-4, "{K_SI}");
    }
}
