//! Gear pair geometry after ISO 21771 / DIN 3960 (`model.md` §2) and the analytic
//! gear loss factor H_V (`model.md` §9.7).

use super::geometry_repair as repair;
pub(crate) use super::geometry_repair::Rule;
use crate::fmt_num::Short;
use crate::parameter::{self, Kind, Parameter};
use std::f64::consts::PI;

/// Engineering data of the gear pair (`model.md` §2, defaults §10).
///
/// Angles in rad, lengths in m. `a_w = 0` means: derive the operating centre
/// distance from the profile shifts `x1 + x2` (zero-backlash condition).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearData {
    /// Number of teeth of gear 1 (driving).
    pub z1: i32,
    /// Number of teeth of gear 2 (driven).
    pub z2: i32,
    /// Normal module m_n.
    pub m_n: f64,
    /// Normal pressure angle alpha_n.
    pub alpha_n: f64,
    /// Helix angle beta at the reference cylinder; the sign selects the hand (§1).
    pub beta: f64,
    /// Common face width b.
    pub b: f64,
    /// Profile shift coefficient of gear 1.
    pub x1: f64,
    /// Profile shift coefficient of gear 2.
    pub x2: f64,
    /// Addendum coefficient h_aP* of the basic rack (1.0).
    pub ha_coef: f64,
    /// Operating centre distance; 0 = derive from x1 + x2.
    pub a_w: f64,
    /// Dedendum coefficient h_fP* of the basic rack (1.25); used only by the mesh
    /// stiffness of ISO 6336-1 ([`super::stiffness`]), not by the rigid model.
    pub h_fp: f64,
    /// Mean mesh stiffness per unit face width c_gamma in N/m^2; 0 = from ISO 6336-1
    /// ([`super::stiffness`]). Reported only until the elastic contact (issue 27).
    pub c_gamma: f64,
    /// Normal backlash j_bn at the operating centre distance a_w, m: the play between the
    /// coast flanks when the drive flanks touch undeflected ([`super::backlash`]); used
    /// only by the elastic contact (`model.md` §3.6).
    pub j_bn: f64,
}

/// 20 degrees in rad, as `20f64.to_radians()` computes it.
const DEG20: f64 = 20.0 * (PI / 180.0);
/// The declared bound of the angles: the double just below pi/4 (45 degrees excluded).
const BELOW_45_DEG: f64 = 0.785_398_163_397_448_2;

/// The gear parameters, each described once (FMI name, unit, default = the default
/// automotive-size helical pair of `model.md` §10, declared bounds); their rules are
/// those of [`PairGeometry::new`].
#[rustfmt::skip]
pub static GEAR_PARAMETERS: [Parameter<GearData>; 13] = [
    gear_param("z1", "", Kind::Integer, 27.0, Some(5.0), None, |g| f64::from(g.z1), |g, x| g.z1 = x as i32),
    gear_param("z2", "", Kind::Integer, 41.0, Some(5.0), None, |g| f64::from(g.z2), |g, x| g.z2 = x as i32),
    gear_param("m_n", "m", Kind::Real, 2.0e-3, Some(1e-300), None, |g| g.m_n, |g, x| g.m_n = x),
    gear_param("alpha_n", "rad", Kind::Real, DEG20, Some(1e-300), Some(BELOW_45_DEG), |g| g.alpha_n, |g, x| g.alpha_n = x),
    gear_param("beta", "rad", Kind::Real, DEG20, Some(-BELOW_45_DEG), Some(BELOW_45_DEG), |g| g.beta, |g, x| g.beta = x),
    gear_param("b", "m", Kind::Real, 18.0e-3, Some(1e-300), None, |g| g.b, |g, x| g.b = x),
    gear_param("x1", "1", Kind::Real, 0.0, None, None, |g| g.x1, |g, x| g.x1 = x),
    gear_param("x2", "1", Kind::Real, 0.0, None, None, |g| g.x2, |g, x| g.x2 = x),
    gear_param("h_aP", "1", Kind::Real, 1.0, Some(1e-300), None, |g| g.ha_coef, |g, x| g.ha_coef = x),
    gear_param("a_w_set", "m", Kind::Real, 0.0, Some(0.0), None, |g| g.a_w, |g, x| g.a_w = x),
    gear_param("h_fP", "1", Kind::Real, 1.25, Some(1e-300), Some(2.0), |g| g.h_fp, |g, x| g.h_fp = x),
    gear_param("c_gamma", "N/m2", Kind::Real, 0.0, Some(0.0), None, |g| g.c_gamma, |g, x| g.c_gamma = x),
    gear_param("j_bn", "m", Kind::Real, 1.0e-4, Some(0.0), None, |g| g.j_bn, |g, x| g.j_bn = x),
];

#[allow(clippy::too_many_arguments)]
const fn gear_param(
    name: &'static str,
    unit: &'static str,
    kind: Kind,
    default: f64,
    min: Option<f64>,
    max: Option<f64>,
    get: fn(&GearData) -> f64,
    put: fn(&mut GearData, f64),
) -> Parameter<GearData> {
    Parameter {
        name,
        unit,
        kind,
        default,
        min,
        max,
        rule: parameter::Rule::Elsewhere,
        get,
        put,
    }
}

impl Default for GearData {
    /// The defaults of [`GEAR_PARAMETERS`].
    fn default() -> Self {
        let mut g = GearData {
            z1: 0,
            z2: 0,
            m_n: 0.0,
            alpha_n: 0.0,
            beta: 0.0,
            b: 0.0,
            x1: 0.0,
            x2: 0.0,
            ha_coef: 0.0,
            a_w: 0.0,
            h_fp: 0.0,
            c_gamma: 0.0,
            j_bn: 0.0,
        };
        for p in &GEAR_PARAMETERS {
            (p.put)(&mut g, p.default);
        }
        g
    }
}

/// The error of a violated parameter rule (also for the pair's rules of `model.md` §2).
pub use crate::parameter::ParamError;

/// Involute function inv x = tan x - x.
#[inline]
pub fn inv(x: f64) -> f64 {
    x.tan() - x
}

/// Inverse of the involute function on (0, pi/2) by Newton's method.
///
/// inv'(x) = tan^2 x; the start (3 v)^(1/3) is the leading term of the series
/// inv x = x^3/3 + ..., from which Newton converges monotonically (inv is convex).
/// Returns None for v <= 0 or non-finite v.
pub fn inv_inverse(v: f64) -> Option<f64> {
    if !(v > 0.0 && v.is_finite()) {
        return None;
    }
    let mut x = (3.0 * v).cbrt().min(1.5);
    for _ in 0..100 {
        let tx = x.tan();
        let dx = (tx - x - v) / (tx * tx);
        x -= dx;
        if !(x > 0.0 && x < PI / 2.0) {
            return None;
        }
        if dx.abs() <= 1e-16 * x {
            break;
        }
    }
    Some(x)
}

/// All derived quantities of the pair at its nominal position (`model.md` §2).
///
/// Besides the fields fixed by the API, the trigonometric values of beta_b and the
/// quantities needed in every mesh evaluation are cached here.
#[derive(Debug, Clone, Copy)]
pub struct PairGeometry {
    /// The engineering data this geometry was derived from.
    pub data: GearData,
    /// Transverse pressure angle alpha_t = atan(tan alpha_n / cos beta).
    pub alpha_t: f64,
    /// Reference radius r_1 = z1 m_n / (2 cos beta).
    pub r1: f64,
    /// Reference radius r_2.
    pub r2: f64,
    /// Base radius r_b1 = r_1 cos alpha_t.
    pub rb1: f64,
    /// Base radius r_b2.
    pub rb2: f64,
    /// Base helix angle beta_b = asin(sin beta cos alpha_n), signed like beta.
    pub beta_b: f64,
    /// Transverse base pitch p_bt = 2 pi r_b1 / z1.
    pub p_bt: f64,
    /// Working transverse pressure angle alpha_wt.
    pub alpha_wt: f64,
    /// Operating centre distance a_w (given or derived).
    pub a_w: f64,
    /// Tip radius r_a1 = r_1 + m_n (h_aP* + x1).
    pub ra1: f64,
    /// Tip radius r_a2.
    pub ra2: f64,
    /// Start of contact sigma_A (from T1 along the line of action).
    pub sigma_a: f64,
    /// End of contact sigma_E.
    pub sigma_e: f64,
    /// Pitch point sigma_C = r_b1 tan alpha_wt.
    pub sigma_c: f64,
    /// Transverse contact ratio.
    pub eps_alpha: f64,
    /// Overlap ratio eps_beta = b |tan beta_b| / p_bt.
    pub eps_beta: f64,
    /// Approach part of the contact ratio (sigma_C - sigma_A)/p_bt.
    pub eps_1: f64,
    /// Recess part of the contact ratio (sigma_E - sigma_C)/p_bt.
    pub eps_2: f64,
    /// Analytic gear loss factor H_V (`model.md` §9.7); see [`PairGeometry::loss_factor`].
    pub h_v: f64,
    /// cos beta_b.
    pub cos_beta_b: f64,
    /// sin beta_b (signed).
    pub sin_beta_b: f64,
    /// tan beta_b (signed).
    pub tan_beta_b: f64,
    /// inv alpha_wt (the phase origin of `model.md` §3.4).
    pub inv_alpha_wt: f64,
    /// R = r_b1 + r_b2.
    pub r_sum: f64,
    /// sqrt(r_a2^2 - r_b2^2): sigma_A = a sin alpha - this, in any displaced state.
    pub rho_a2: f64,
    /// Mesh period in phi1: 2 pi / z1.
    pub phi1_period: f64,
}

fn err(name: &'static str, value: f64, requirement: String) -> ParamError {
    ParamError {
        name,
        value,
        requirement,
    }
}

fn tagged(rule: Rule, name: &'static str, value: f64, requirement: String) -> (Rule, ParamError) {
    (rule, err(name, value, requirement))
}

impl PairGeometry {
    /// Derives and validates the pair geometry (`model.md` §2).
    ///
    /// # Errors
    /// A [`ParamError`] naming the first violated rule of §2: `z_j >= 5`, `m_n > 0`,
    /// `0 < alpha_n < 45 deg`, `|beta| < 45 deg`, `b > 0`, `h_aP > 0`, `h_fP > 0`,
    /// `c_gamma >= 0` (the stiffness parameters of `model.md` §2.1), finite shifts,
    /// `r_aj > r_bj`, a valid working pressure angle (`x1+x2` resp. `a_w > r_b1 + r_b2`),
    /// `0 <= sigma_A < sigma_E <= a_w sin alpha_wt`, `eps_alpha + eps_beta > 1`, and
    /// (buffer bound of the contact-line loop) `eps_alpha + eps_beta <= 60`. For the
    /// derived rules the error names the first parameter that repairs the set alone and
    /// lists every such single-parameter repair with its computed limit value
    /// (`geometry_repair`).
    pub fn new(data: &GearData) -> Result<Self, ParamError> {
        Self::check(data).map_err(|(rule, e)| repair::explain(data, rule, e))
    }

    /// [`PairGeometry::new`] without the repair advice: the violated rule and the plain
    /// message (used by `repair` to test candidate values).
    pub(crate) fn check(data: &GearData) -> Result<Self, (Rule, ParamError)> {
        let err = |name, value, requirement| (Rule::Plain, err(name, value, requirement));
        let d = *data;
        let deg45 = PI / 4.0;
        if d.z1 < 5 {
            return Err(err("z1", d.z1 as f64, "z1 >= 5".into()));
        }
        if d.z2 < 5 {
            return Err(err("z2", d.z2 as f64, "z2 >= 5".into()));
        }
        if !(d.m_n > 0.0 && d.m_n.is_finite()) {
            return Err(err("m_n", d.m_n, "0 < m_n < inf".into()));
        }
        if !(d.alpha_n > 0.0 && d.alpha_n < deg45) {
            return Err(err(
                "alpha_n",
                d.alpha_n,
                "0 < alpha_n < 45 deg (0.7853981634 rad)".into(),
            ));
        }
        if !(d.beta.abs() < deg45) {
            return Err(err(
                "beta",
                d.beta,
                "|beta| < 45 deg (0.7853981634 rad)".into(),
            ));
        }
        if !(d.b > 0.0 && d.b.is_finite()) {
            return Err(err("b", d.b, "0 < b < inf".into()));
        }
        if !(d.ha_coef > 0.0 && d.ha_coef.is_finite()) {
            return Err(err("h_aP", d.ha_coef, "0 < h_aP < inf".into()));
        }
        // The two stiffness parameters (`stiffness`): not used by the rigid model, but a
        // set the elastic contact could not use is refused now.
        // (ISO 6336-1's basic rack factor C_B = [1 + 0.5 (1.2 - h_fP)] [...] falls to 0 at
        // h_fP = 3.2; basic racks have 1.0..1.4.)
        if !(d.h_fp > 0.0 && d.h_fp <= 2.0) {
            return Err(err(
                "h_fP",
                d.h_fp,
                "0 < h_fP <= 2 (basic racks: 1.0..1.4)".into(),
            ));
        }
        if !(d.c_gamma >= 0.0 && d.c_gamma.is_finite()) {
            return Err(err(
                "c_gamma",
                d.c_gamma,
                "c_gamma >= 0 (0 = from ISO 6336-1)".into(),
            ));
        }
        // Backlash (`backlash`, `model.md` §3.6): each gear is thinned by half of it, and
        // half a module of thinning per gear leaves no tooth of a usual rack to speak of.
        if !(d.j_bn >= 0.0 && d.j_bn <= 0.5 * d.m_n) {
            return Err(err(
                "j_bn",
                d.j_bn,
                format!("0 <= j_bn <= m_n / 2 = {} m", Short(0.5 * d.m_n)),
            ));
        }
        if !d.x1.is_finite() {
            return Err(err("x1", d.x1, "x1 finite".into()));
        }
        if !d.x2.is_finite() {
            return Err(err("x2", d.x2, "x2 finite".into()));
        }
        if !(d.a_w >= 0.0 && d.a_w.is_finite()) {
            return Err(err(
                "a_w",
                d.a_w,
                "a_w >= 0 (0 = derive from x1 + x2)".into(),
            ));
        }
        let (z1, z2) = (d.z1 as f64, d.z2 as f64);
        let cb = d.beta.cos();
        let alpha_t = (d.alpha_n.tan() / cb).atan();
        let r1 = z1 * d.m_n / (2.0 * cb);
        let r2 = z2 * d.m_n / (2.0 * cb);
        let rb1 = r1 * alpha_t.cos();
        let rb2 = r2 * alpha_t.cos();
        let beta_b = (d.beta.sin() * d.alpha_n.cos()).asin();
        let p_bt = 2.0 * PI * rb1 / z1;
        let ra1 = r1 + d.m_n * (d.ha_coef + d.x1);
        let ra2 = r2 + d.m_n * (d.ha_coef + d.x2);
        if !(ra1 > rb1) {
            return Err(tagged(
                Rule::TipBelowBase1,
                "x1",
                d.x1,
                format!(
                    "tip radius r_a1 = {} > base radius r_b1 = {}",
                    Short(ra1),
                    Short(rb1)
                ),
            ));
        }
        if !(ra2 > rb2) {
            return Err(tagged(
                Rule::TipBelowBase2,
                "x2",
                d.x2,
                format!(
                    "tip radius r_a2 = {} > base radius r_b2 = {}",
                    Short(ra2),
                    Short(rb2)
                ),
            ));
        }
        let r_sum = rb1 + rb2;
        let (alpha_wt, a_w) = if d.a_w == 0.0 {
            let v = inv(alpha_t) + 2.0 * d.alpha_n.tan() * (d.x1 + d.x2) / (z1 + z2);
            match inv_inverse(v) {
                Some(awt) => (awt, r_sum / awt.cos()),
                None => {
                    return Err(tagged(
                        Rule::WorkingAngle,
                        "x1+x2",
                        d.x1 + d.x2,
                        format!(
                        "inv alpha_wt = inv alpha_t + 2 tan alpha_n (x1 + x2)/(z1 + z2) = {} > 0",
                        Short(v)
                    ),
                    ))
                }
            }
        } else {
            if !(d.a_w > r_sum) {
                return Err(err(
                    "a_w",
                    d.a_w,
                    format!("a_w > r_b1 + r_b2 = {} (or a_w = 0)", Short(r_sum)),
                ));
            }
            ((r_sum / d.a_w).acos(), d.a_w)
        };
        let loa = a_w * alpha_wt.sin();
        let rho_a2 = (ra2 * ra2 - rb2 * rb2).sqrt();
        let sigma_e = (ra1 * ra1 - rb1 * rb1).sqrt();
        let sigma_a = loa - rho_a2;
        let sigma_c = rb1 * alpha_wt.tan();
        if !(sigma_a >= 0.0) {
            return Err(tagged(
                Rule::Interference1,
                "x2",
                d.x2,
                format!(
                    "sigma_A = a_w sin alpha_wt - sqrt(r_a2^2 - r_b2^2) = {} >= 0 \
                     (tip of gear 2 must not pass T1: interference)",
                    Short(sigma_a)
                ),
            ));
        }
        if !(sigma_e <= loa) {
            return Err(tagged(
                Rule::Interference2,
                "x1",
                d.x1,
                format!(
                    "sigma_E = sqrt(r_a1^2 - r_b1^2) = {} <= a_w sin alpha_wt = {} \
                     (tip of gear 1 must not pass T2: interference)",
                    Short(sigma_e),
                    Short(loa)
                ),
            ));
        }
        if !(sigma_a < sigma_e) {
            return Err(tagged(
                Rule::TipsApart,
                "h_aP",
                d.ha_coef,
                format!(
                    "sigma_A = {} < sigma_E = {} (the tips must overlap)",
                    Short(sigma_a),
                    Short(sigma_e)
                ),
            ));
        }
        let eps_alpha = (sigma_e - sigma_a) / p_bt;
        let eps_1 = (sigma_c - sigma_a) / p_bt;
        let eps_2 = (sigma_e - sigma_c) / p_bt;
        let tan_beta_b = beta_b.tan();
        let eps_beta = d.b * tan_beta_b.abs() / p_bt;
        if !(eps_alpha + eps_beta > 1.0) {
            let (name, value) = if d.beta == 0.0 {
                ("h_aP", d.ha_coef)
            } else {
                ("b", d.b)
            };
            return Err(tagged(
                Rule::ContactRatio,
                name,
                value,
                format!(
                    "eps_alpha + eps_beta = {} > 1 (the contact must never vanish)",
                    Short(eps_alpha + eps_beta)
                ),
            ));
        }
        if !(eps_alpha + eps_beta <= 60.0) {
            return Err(err(
                "b",
                d.b,
                format!(
                    "eps_alpha + eps_beta = {} <= 60 (bound of the contact-line loop): \
                     b <= {:.4e} m ({:.1} mm) for this pair and helix angle",
                    Short(eps_alpha + eps_beta),
                    (60.0 - eps_alpha) * p_bt / tan_beta_b.abs(),
                    1e3 * (60.0 - eps_alpha) * p_bt / tan_beta_b.abs()
                ),
            ));
        }
        let mut g = Self {
            data: d,
            alpha_t,
            r1,
            r2,
            rb1,
            rb2,
            beta_b,
            p_bt,
            alpha_wt,
            a_w,
            ra1,
            ra2,
            sigma_a,
            sigma_e,
            sigma_c,
            eps_alpha,
            eps_beta,
            eps_1,
            eps_2,
            h_v: 0.0,
            cos_beta_b: beta_b.cos(),
            sin_beta_b: beta_b.sin(),
            tan_beta_b,
            inv_alpha_wt: inv(alpha_wt),
            r_sum,
            rho_a2,
            phi1_period: 2.0 * PI / z1,
        };
        g.h_v = g.loss_factor();
        Ok(g)
    }

    /// Gear ratio u = z2 / z1.
    pub fn ratio(&self) -> f64 {
        self.data.z2 as f64 / self.data.z1 as f64
    }

    /// Analytic gear loss factor H_V (`model.md` §9.7), defined by
    /// `<P_loss> = mu <P_in> H_V` for a rigid pair in uniform rotation.
    ///
    /// Why these formulas: the sliding speed along the line of action is
    /// `(omega1 + omega2)(sigma - sigma_C)` and the line load is `lambda / l`.
    /// - helical (beta != 0): `pi (u+1)/(z1 u cos beta_b) (eps_1^2 + eps_2^2)/eps_alpha`,
    ///   the phase average of `int |sigma - sigma_C| dl / l`; exact when `l` is
    ///   constant (integer eps_beta), an approximation otherwise.
    /// - spur (beta = 0, 1 < eps_alpha < 2, load shared equally in double contact):
    ///   `pi (u+1)/(2 z1 u) [eps_1^2 + eps_2^2 + (1-eps_1)|1-eps_1| + (1-eps_2)|1-eps_2|]`,
    ///   which is Ohlendorf's formula when eps_1, eps_2 <= 1. Valid for 1 < eps_alpha < 2
    ///   (at most two pairs in contact), which covers ordinary spur pairs.
    ///
    /// Kinematic check (tests/gear_loss_factor.rs): both are exact to round-off for the
    /// cases they are stated for; for the default pair (eps_beta = 0.98) the exact phase
    /// average lies 5.7e-5 below the helical formula.
    pub fn loss_factor(&self) -> f64 {
        let u = self.ratio();
        let z1 = self.data.z1 as f64;
        let (e1, e2) = (self.eps_1, self.eps_2);
        if self.data.beta == 0.0 {
            PI * (u + 1.0) / (2.0 * z1 * u)
                * (e1 * e1
                    + e2 * e2
                    + (1.0 - e1) * (1.0 - e1).abs()
                    + (1.0 - e2) * (1.0 - e2).abs())
        } else {
            PI * (u + 1.0) / (z1 * u * self.cos_beta_b) * (e1 * e1 + e2 * e2) / self.eps_alpha
        }
    }
}
