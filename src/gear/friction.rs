//! Distributed friction along the contact lines (`model.md` §4).
//!
//! Along a contact line P = P_k0 + s c (0 <= s <= L) the tangential sliding velocity is
//! `v_T(s) = x(s) e_w + y c` with `x(s) = x0 - kappa s`. Coulomb friction with uniform
//! line load needs the five line integrals (r = sqrt(x^2 + y^2))
//!
//! `I_x = int x/r ds, I_y = int y/r ds, K_x = int s x/r ds, K_y = int s y/r ds, W = int r ds`.

use super::contact_lines::ContactSummary;
use super::geometry::PairGeometry;
use super::mesh::{Kinematics, Mesh};
use nalgebra::Vector3;

pub mod benedict_kelley;
pub mod ehl;
pub mod iso_mean;
pub mod law_params;
pub mod regularised;
pub mod stick;

pub use benedict_kelley::BkLine;
pub use ehl::{EhlLine, Lubricant};
pub use iso_mean::{mu_mz, IsoMean};
pub use law_params::FrictionParams;
pub use regularised::regularised_integrals;
use stick::{Contribution, Held};
pub use stick::{PitchLine, StickAction, StuckLine};

/// The friction law (FMI parameter `friction_law`): the single seam through which the
/// local friction model enters. `docs/friction.md` gives each law's formula and source.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrictionLaw {
    /// 1: Coulomb friction with constant mu (`model.md` §4), the paper's law.
    #[default]
    Coulomb,
    /// 2: Coulomb with the sliding direction regularised, `v / sqrt(|v|^2 + v_reg^2)`.
    RegularisedCoulomb,
    /// 3: Coulomb with the mean coefficient mu_mz of ISO/TR 14179-2 (Schlenk's formula),
    /// following the operating point (load, speed) during the run.
    IsoMean,
    /// 4: local EHL coefficient mu(s) along every contact line (Xu et al. 2007).
    LocalEhl,
    /// 5: Benedict & Kelley's (1961) coefficient mu(s) along every contact line, from the
    /// line load, the local sliding and rolling speeds, viscosity and roughness; bounded
    /// below the sliding speed v_reg, where the force falls off linearly.
    BenedictKelley,
}

impl FrictionLaw {
    /// The law from its FMI code 1..=5 (None for any other code).
    pub fn from_code(code: i32) -> Option<Self> {
        match code {
            1 => Some(FrictionLaw::Coulomb),
            2 => Some(FrictionLaw::RegularisedCoulomb),
            3 => Some(FrictionLaw::IsoMean),
            4 => Some(FrictionLaw::LocalEhl),
            5 => Some(FrictionLaw::BenedictKelley),
            _ => None,
        }
    }

    /// The FMI code 1..=5 of the law.
    pub fn code(self) -> i32 {
        match self {
            FrictionLaw::Coulomb => 1,
            FrictionLaw::RegularisedCoulomb => 2,
            FrictionLaw::IsoMean => 3,
            FrictionLaw::LocalEhl => 4,
            FrictionLaw::BenedictKelley => 5,
        }
    }

    /// Whether the friction force jumps where the sliding on a line reverses (the pitch
    /// line): true for the laws with a sign function (1, 3), false for the regularised
    /// law (smooth there), the EHL law (mu(s) -> 0 like |x|^1.036 at the pitch line) and
    /// Benedict & Kelley's law (force linear in the sliding below v_reg).
    pub fn sharp_reversal(self) -> bool {
        matches!(self, FrictionLaw::Coulomb | FrictionLaw::IsoMean)
    }

    /// Whether the coefficient depends on the normal force (then lambda needs a scalar
    /// solve, `model.md` §7): laws 3, 4 and 5.
    pub fn load_dependent(self) -> bool {
        matches!(
            self,
            FrictionLaw::IsoMean | FrictionLaw::LocalEhl | FrictionLaw::BenedictKelley
        )
    }

    /// Whether the sums carry a local coefficient mu(s) that depends on the line load
    /// (laws 4 and 5): then the lambda column of the Jacobian differentiates the friction
    /// evaluation.
    pub fn local_load_dependent(self) -> bool {
        matches!(self, FrictionLaw::LocalEhl | FrictionLaw::BenedictKelley)
    }

    /// The five integrals of one segment, per unit of `mu |lambda| / l`, for the laws whose
    /// sums do not depend on parameters (Coulomb; the ISO mean coefficient shares them).
    #[inline]
    pub fn segment_integrals(self, x0: f64, y: f64, kappa: f64, len: f64) -> LineIntegrals {
        line_integrals(x0, y, kappa, len)
    }
}

/// The local law along the lines with its parameters for one evaluation (what
/// [`PairGeometry::friction_sums_line`] integrates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LineLaw {
    /// Coulomb, unit coefficient (laws 1 and 3).
    Coulomb,
    /// Regularised Coulomb (law 2) with the regularising speed v_reg > 0 (m/s).
    Regularised {
        /// v_reg (m/s).
        v_reg: f64,
        /// Also accumulate `mu_len` (outputs only: 20 more square roots per line).
        with_mean: bool,
    },
    /// The local EHL coefficient (law 4) at the current line load.
    Ehl(EhlLine),
    /// Benedict & Kelley's coefficient (law 5) at the current line load.
    BenedictKelley(BkLine),
}

/// The five line integrals of one segment (`model.md` §4).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LineIntegrals {
    /// int_0^L x/r ds.
    pub ix: f64,
    /// int_0^L y/r ds.
    pub iy: f64,
    /// int_0^L s x/r ds.
    pub kx: f64,
    /// int_0^L s y/r ds.
    pub ky: f64,
    /// int_0^L r ds.
    pub w: f64,
}

/// asinh(z) without cancellation for small |z| and without overflow for large |z|:
/// asinh|z| = log1p(|z| + z^2 / (1 + sqrt(1 + z^2))), and ln(2|z|) + 1/(4 z^2) beyond 1e8.
#[inline]
fn asinh_stable(z: f64) -> f64 {
    let a = z.abs();
    let r = if a > 1e8 {
        (2.0 * a).ln() + 0.25 / (a * a)
    } else {
        (a + a * a / (1.0 + (1.0 + a * a).sqrt())).ln_1p()
    };
    r.copysign(z)
}

/// asinh(x / ay) for ay > 0, also when x / ay would overflow (ay tiny): then
/// asinh(x/ay) = sign(x) (ln 2|x| - ln ay) to relative 1e-16.
#[inline]
fn asinh_ratio(x: f64, ay: f64) -> f64 {
    let a = x.abs();
    if a <= 1e8 * ay {
        asinh_stable(x / ay)
    } else {
        ((2.0 * a).ln() - ay.ln()).copysign(x)
    }
}

/// Gauss-Legendre 10-point nodes (positive half) on [-1, 1] (QUADPACK qk21's Gauss part),
/// kept with their published digits.
#[allow(clippy::excessive_precision)]
pub(crate) const GL_X: [f64; 5] = [
    0.148_874_338_981_631_210_884_826_001_129_720,
    0.433_395_394_129_247_190_799_265_943_165_784,
    0.679_409_568_299_024_406_234_327_365_114_874,
    0.865_063_366_688_984_510_732_096_688_423_493,
    0.973_906_528_517_171_720_077_964_012_084_452,
];
/// Gauss-Legendre 10-point weights matching [`GL_X`].
#[allow(clippy::excessive_precision)]
pub(crate) const GL_W: [f64; 5] = [
    0.295_524_224_714_752_870_173_892_994_651_338,
    0.269_266_719_309_996_355_091_226_921_569_469,
    0.219_086_362_515_982_043_995_534_934_228_163,
    0.149_451_349_150_580_593_145_776_339_657_697,
    0.066_671_344_308_688_137_593_568_809_893_332,
];

/// Gauss-Legendre is used when the branch points x = +-i|y| of the integrand lie at least
/// this many half-lengths from the segment midpoint (in s). Then the Bernstein ellipse
/// parameter is rho >= 4 + sqrt(15) = 7.87 and the 10-point rule errs by ~rho^-20 = 1e-18
/// relative; closer to the sign change the closed forms are well conditioned.
pub(crate) const GL_RATIO: f64 = 4.0;

/// The five line integrals of `model.md` §4 for `x(s) = x0 - kappa s`, constant `y`,
/// `0 <= s <= len`, evaluated stably in every regime:
///
/// - `kappa L` negligible against `r_mid = sqrt(x_mid^2 + y^2)` (smooth integrand; incl.
///   kappa = 0 and y >> kappa L): 10-point Gauss-Legendre, where the closed forms would
///   cancel catastrophically (19 % error at kappa = 1e-6, §4).
/// - otherwise the closed forms in the stable rewriting (x1 = x0 - kappa L, r0, r1 ends):
///   `I_x = L (x0 + x1)/(r0 + r1)` (= (r0 - r1)/kappa without the cancellation),
///   `D = asinh(x0/|y|) - asinh(x1/|y|)`, for x0 x1 > 0 as
///   `asinh(kappa L (x0 + x1)/(x0 r1 + x1 r0))` (sinh(A - B) rule), `J0 = D / kappa`,
///   `I_y = y J0`, `K_y = y (x0 J0 - I_x)/kappa`,
///   `W = (x0 r0 - x1 r1 + y^2 D)/(2 kappa)`, `K_x = (W - L r1)/kappa` (by parts,
///   x/r = -(1/kappa) dr/ds).
///
/// y = 0 gives I_y = K_y = 0 exactly (v_T parallel to e_w); r = 0 means v_hat = 0.
pub fn line_integrals(x0: f64, y: f64, kappa: f64, len: f64) -> LineIntegrals {
    if !(len > 0.0) {
        return LineIntegrals::default();
    }
    let half = 0.5 * kappa.abs() * len;
    let xm = x0 - 0.5 * kappa * len;
    let y2 = y * y;
    let rm = (xm * xm + y2).sqrt();
    if half == 0.0 {
        // v_T constant along the segment.
        if rm == 0.0 {
            return LineIntegrals::default();
        }
        let (ux, uy) = (x0 / rm, y / rm);
        let k = 0.5 * len * len;
        return LineIntegrals {
            ix: len * ux,
            iy: len * uy,
            kx: k * ux,
            ky: k * uy,
            w: len * rm,
        };
    }
    if rm > GL_RATIO * half {
        return gauss_legendre(x0, y, kappa, len);
    }
    let x1 = x0 - kappa * len;
    let r0 = (x0 * x0 + y2).sqrt();
    let r1 = (x1 * x1 + y2).sqrt();
    let rs = r0 + r1;
    let ix = if rs > 0.0 { len * (x0 + x1) / rs } else { 0.0 };
    let (iy, ky, ydd) = if y != 0.0 {
        let ay = y.abs();
        let d = if x0 * x1 > 0.0 {
            asinh_stable(kappa * len * (x0 + x1) / (x0 * r1 + x1 * r0))
        } else {
            asinh_ratio(x0, ay) - asinh_ratio(x1, ay)
        };
        let j0 = d / kappa;
        let j1 = (x0 * j0 - ix) / kappa;
        (y * j0, y * j1, y2 * d)
    } else {
        (0.0, 0.0, 0.0)
    };
    let w = (x0 * r0 - x1 * r1 + ydd) / (2.0 * kappa);
    let kx = (w - len * r1) / kappa;
    LineIntegrals { ix, iy, kx, ky, w }
}

/// 10-point Gauss-Legendre for the smooth regime of [`line_integrals`].
fn gauss_legendre(x0: f64, y: f64, kappa: f64, len: f64) -> LineIntegrals {
    let h = 0.5 * len;
    let y2 = y * y;
    let (mut ix, mut iy, mut kx, mut ky, mut w) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 0..5 {
        for sgn in [-1.0, 1.0] {
            let s = h * (1.0 + sgn * GL_X[i]);
            let x = x0 - kappa * s;
            let r = (x * x + y2).sqrt();
            if r == 0.0 {
                continue;
            }
            let wi = GL_W[i] / r;
            ix += wi * x;
            iy += wi;
            kx += wi * x * s;
            ky += wi * s;
            w += GL_W[i] * r;
        }
    }
    LineIntegrals {
        ix: h * ix,
        iy: h * y * iy,
        kx: h * kx,
        ky: h * y * ky,
        w: h * w,
    }
}

/// Friction resultants per unit pressure `p = mu |lambda| / l` and the geometric sums the
/// normal-force moments need (`model.md` §4, §6). All vectors inertial.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrictionSums {
    /// Contact length and pairs.
    pub contact: ContactSummary,
    /// sum (I_x e_w + I_y c) (friction force on gear 2 is -p times this).
    pub force: Vector3<f64>,
    /// sum [(P_k0 - c1) x (I_x e_w + I_y c) + K_x n]  (M1 = +p times this).
    pub moment1: Vector3<f64>,
    /// sum [(P_k0 - c2) x (I_x e_w + I_y c) + K_x n]  (M2 = -p times this).
    pub moment2: Vector3<f64>,
    /// sum W (P_loss = p times this).
    pub w: f64,
    /// sum over segments of int (P - c1) ds (normal-force moment of gear 1 is -(lambda/l) this x n).
    pub arm1: Vector3<f64>,
    /// sum over segments of int (P - c2) ds.
    pub arm2: Vector3<f64>,
    /// int mu_loc(s) ds over all lines per unit scalar coefficient (= l for Coulomb; for
    /// the regularised law only when asked for, [`regularised::mean_factor`]).
    pub mu_len: f64,
    /// The line left out of the sums above because it sticks (`model.md` §4.1), when asked
    /// for (`PairGeometry::sums_with_stick`).
    pub stuck: Option<StuckLine>,
}

/// Friction forces, moments and loss for a given normal force (`model.md` §4).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Friction {
    /// Friction force on gear 1, F1 = -F2.
    pub f1: Vector3<f64>,
    /// Friction force on gear 2.
    pub f2: Vector3<f64>,
    /// Friction moment on gear 1 about c1.
    pub m1: Vector3<f64>,
    /// Friction moment on gear 2 about c2.
    pub m2: Vector3<f64>,
    /// Dissipated power P_loss >= 0.
    pub p_loss: f64,
    /// Line pressure factor p = mu |lambda| / l (0 when l = 0).
    pub p: f64,
}

impl Friction {
    /// The generalised friction force `Q_f = (F1, F2, -M2 . e_z)` on q = (u1, u2, phi2)
    /// (`model.md` (4.11); phi2 turns about -e_z).
    pub fn generalised(&self) -> [f64; 7] {
        let (f1, f2) = (self.f1, self.f2);
        [f1.x, f1.y, f1.z, f2.x, f2.y, f2.z, -self.m2.z]
    }
}

impl FrictionSums {
    /// Scales the unit sums with `p = mu |lambda| / l` (`model.md` §4 resultants).
    pub fn resultants(&self, mu: f64, lambda: f64) -> Friction {
        let l = self.contact.length;
        let p = if l > 0.0 { mu * lambda.abs() / l } else { 0.0 };
        Friction {
            f1: p * self.force,
            f2: -p * self.force,
            m1: p * self.moment1,
            m2: -p * self.moment2,
            p_loss: p * self.w,
            p,
        }
    }

    /// Generalised friction force per unit p, `Q_f / p = [F1, F2, -M2_z] / p`
    /// (phi2 is about -e_z, `model.md` §4).
    pub fn generalised_unit(&self) -> [f64; 7] {
        let f = self.force;
        [f.x, f.y, f.z, -f.x, -f.y, -f.z, self.moment2.z]
    }
}

impl PairGeometry {
    /// Sums the friction integrals over all contact segments (`model.md` §3.4, §4) for the
    /// mesh `m`, gear-1 angle `phi1`, initial phase `psi0` and the velocities `k`.
    ///
    /// Works in the right-handed local frame (e_w, t, e_z): there
    /// `P - c1 = (r_b1, sigma, Z - u1z)`, `P - c2 = (-r_b2, sigma - a sin alpha, Z - u2z)`,
    /// `c = (0, -sin beta_b, cos beta_b)`, `n = (0, cos beta_b, sin beta_b)`, and
    /// `v_rel(P) = (u2' - u1') + (omega2 r_b2 - omega1 r_b1) t + ((omega1 + omega2) sigma - omega2 a sin alpha) e_w`,
    /// so x0 = e_w . v_rel(P_k0), y = c . v_rel(P_k0), kappa = (omega1 + omega2) sin beta_b.
    /// No allocation.
    pub fn friction_sums(
        &self,
        m: &Mesh,
        phi1: f64,
        psi0: f64,
        k: &Kinematics,
        law: FrictionLaw,
    ) -> FrictionSums {
        let _ = law;
        self.friction_sums_line(m, phi1, psi0, k, &LineLaw::Coulomb)
    }

    /// [`PairGeometry::friction_sums`] for any local law: the segment integrals come from
    /// `law` (`mu(s) v_T / |v_T|` weighted, per unit `|lambda| / l` times the scalar
    /// coefficient of [`FrictionSums::resultants`]). `FrictionSums::mu_len` is
    /// `int mu_loc(s) ds` per unit scalar coefficient (the load-weighted mean
    /// coefficient is `mu mu_len / l`). No allocation.
    pub fn friction_sums_line(
        &self,
        m: &Mesh,
        phi1: f64,
        psi0: f64,
        k: &Kinematics,
        law: &LineLaw,
    ) -> FrictionSums {
        self.sums_with_stick(m, phi1, psi0, k, law, PitchLine::Slide)
    }

    /// [`PairGeometry::friction_sums_line`] with the segment whose sliding `x0` is nearest
    /// zero (a spur line at the pitch line, `model.md` §4.1) treated as `pitch` says: with
    /// [`PitchLine::Stick`] it is left out of the friction sums and described in
    /// [`FrictionSums::stuck`] instead (its force is the one that keeps it from sliding,
    /// which the DAE computes); with [`PitchLine::Released`] it slides in the given sense
    /// while its |x0| is within the band (Coulomb law, unit coefficient). The normal load
    /// acts on it in every case (arms, contact length). No allocation.
    pub(crate) fn sums_with_stick(
        &self,
        m: &Mesh,
        phi1: f64,
        psi0: f64,
        k: &Kinematics,
        law: &LineLaw,
        pitch: PitchLine,
    ) -> FrictionSums {
        // Two instances: the one for `Slide` (every f of a helical pair) has no test for the
        // line nearest zero sliding in its loop (measured: +8 % instructions per f with it).
        if pitch == PitchLine::Slide {
            self.sums_generic::<false>(m, phi1, psi0, k, law, pitch)
        } else {
            self.sums_generic::<true>(m, phi1, psi0, k, law, pitch)
        }
    }

    /// [`PairGeometry::sums_with_stick`] with `NEAR = (pitch != Slide)` known at compile time.
    fn sums_generic<const NEAR: bool>(
        &self,
        m: &Mesh,
        phi1: f64,
        psi0: f64,
        k: &Kinematics,
        law: &LineLaw,
        pitch: PitchLine,
    ) -> FrictionSums {
        let (cb, sb) = (self.cos_beta_b, self.sin_beta_b);
        let dv = k.v2 - k.v1;
        // Local components of u2' - u1'.
        let dv_w = dv.x * m.cos_psi + dv.y * m.sin_psi;
        let dv_t = -dv.x * m.sin_psi + dv.y * m.cos_psi;
        let dv_z = dv.z;
        let wsum = k.omega1 + k.omega2;
        let kappa = wsum * sb;
        let y = -sb * (dv_t + k.omega2 * self.rb2 - k.omega1 * self.rb1) + cb * dv_z;
        let x_base = dv_w - k.omega2 * m.len_t1t2;
        let (rb1, rb2, lt) = (self.rb1, self.rb2, m.len_t1t2);
        let (u1z, u2z) = (m.c1.z, m.c2.z);
        // Local accumulators: force (w, t, z), moments (w, t, z), arms.
        let mut acc = Contribution::default();
        let mut a1 = [0.0f64; 3];
        let mut a2 = [0.0f64; 3];
        let mut mu_len = 0.0;
        // Unless `Slide`: the segment nearest zero sliding so far, held back from the sums.
        let near = NEAR;
        let mut held: Option<Held> = None;
        let contact = self.for_each_segment(m, phi1, psi0, |seg| {
            let x0 = x_base + wsum * seg.sigma0;
            let li = match law {
                LineLaw::Coulomb => {
                    mu_len += seg.length;
                    line_integrals(x0, y, kappa, seg.length)
                }
                LineLaw::Regularised { v_reg, with_mean } => {
                    if *with_mean {
                        mu_len += regularised::mean_factor(x0, y, kappa, seg.length, *v_reg);
                    }
                    regularised_integrals(x0, y, kappa, seg.length, *v_reg)
                }
                LineLaw::Ehl(e) => {
                    let (li, mu_int) = e.segment_integrals(x0, y, kappa, seg.length, seg.sigma0);
                    mu_len += mu_int;
                    li
                }
                LineLaw::BenedictKelley(e) => {
                    let (li, mu_int) = e.segment_integrals(x0, y, kappa, seg.length, seg.sigma0);
                    mu_len += mu_int;
                    li
                }
            };
            let z1 = seg.z0 - u1z;
            let z2 = seg.z0 - u2z;
            let s0 = seg.sigma0;
            // F = I_x e_w + I_y c in local components; r x F + K_x n for r = P_k0 - c_j.
            let contribution = |li: &LineIntegrals| {
                let (gw, gt, gz) = (li.ix, -sb * li.iy, cb * li.iy);
                let cross = |r: [f64; 3]| {
                    [
                        r[1] * gz - r[2] * gt,
                        r[2] * gw - r[0] * gz + li.kx * cb,
                        r[0] * gt - r[1] * gw + li.kx * sb,
                    ]
                };
                Contribution {
                    f: [gw, gt, gz],
                    m1: cross([rb1, s0, z1]),
                    m2: cross([-rb2, s0 - lt, z2]),
                    w: li.w,
                }
            };
            let c = contribution(&li);
            if near && held.as_ref().is_none_or(|h| x0.abs() < h.x0.abs()) {
                // A released line (`PitchLine::Released`) slides in the given sense while
                // it is within the band: unit direction `sign`, power `sign x0` per unit.
                let hinted = match pitch {
                    PitchLine::Released { sign, .. } => {
                        let l = seg.length;
                        Some(contribution(&LineIntegrals {
                            ix: l * sign,
                            iy: 0.0,
                            kx: 0.5 * l * l * sign,
                            ky: 0.0,
                            w: l * sign * x0,
                        }))
                    }
                    _ => None,
                };
                if let Some(h) = held.replace(Held {
                    c,
                    hinted,
                    seg: *seg,
                    x0,
                }) {
                    acc.add(&h.c);
                }
            } else {
                acc.add(&c);
            }
            // int (P - c_j) ds = L (P_k0 - c_j) + L^2/2 c.
            let l = seg.length;
            let h = 0.5 * l * l;
            a1[0] += l * rb1;
            a1[1] += l * s0 - h * sb;
            a1[2] += l * z1 + h * cb;
            a2[0] += -l * rb2;
            a2[1] += l * (s0 - lt) - h * sb;
            a2[2] += l * z2 + h * cb;
        });
        let mut stuck = None;
        if let Some(h) = held {
            match pitch {
                PitchLine::Stick => stuck = Some(StuckLine::new(h.seg, h.x0)),
                PitchLine::Released { band, .. } if h.x0.abs() <= band && y.abs() <= band => {
                    acc.add(&h.hinted.unwrap_or(h.c));
                }
                _ => acc.add(&h.c),
            }
        }
        FrictionSums {
            contact,
            force: m.to_inertial(acc.f[0], acc.f[1], acc.f[2]),
            moment1: m.to_inertial(acc.m1[0], acc.m1[1], acc.m1[2]),
            moment2: m.to_inertial(acc.m2[0], acc.m2[1], acc.m2[2]),
            w: acc.w,
            arm1: m.to_inertial(a1[0], a1[1], a1[2]),
            arm2: m.to_inertial(a2[0], a2[1], a2[2]),
            mu_len,
            stuck,
        }
    }
}
