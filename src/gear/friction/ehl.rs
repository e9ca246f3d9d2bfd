//! Law 4: a local EHL coefficient of friction mu(s) along every contact line.
//!
//! The regression formula of Xu, Kahraman, Anderson & Maddock (2007), "Prediction of
//! mechanical efficiency of parallel-axis gear pairs", ASME J. Mech. Des. 129(1) 58-68:
//! the friction formula of that paper (its eqs. 4-5 as far as could be checked here; the
//! nine coefficients, fitted to thermal non-Newtonian EHL predictions for a 75W90 gear
//! oil, were checked against a second text that reproduces them; they also appear in
//! Xu's 2005 Ohio State dissertation):
//!
//! `mu = exp(f) P_h^b2 |SR|^b3 V_e^b6 nu0^b7 R^b8`,
//! `f = b1 + b4 |SR| P_h log10(nu0) + b5 exp(-|SR| P_h log10(nu0)) + b9 exp(S)`,
//!
//! in the paper's units: P_h (GPa) the maximum Hertzian pressure, SR = u_s / V_e (1) the
//! slide-to-roll ratio, V_e (m/s) the entraining (mean rolling) speed, nu0 [mPa s = cP] the
//! dynamic viscosity at the inlet temperature and ambient pressure, R (m) the equivalent
//! radius of curvature in the normal section, S (um) the composite roughness.
//!
//! Along a line at `sigma(s) = sigma0 - sin beta_b s` from T1 on the line
//! of action (length L_t = a sin alpha): rho1 = sigma, rho2 = L_t - sigma,
//! `R = rho1 rho2 / (L_t cos beta_b)`, `V_e = (omega1 rho1 + omega2 rho2)/2`, the sliding
//! speed `u_s = |v_T| = r(s)` (as in the Coulomb line integrals), and
//! `P_h = sqrt(q E' / (2 pi R))` for the line load q = |lambda| / l (N/m),
//! `E' = 2 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)`.
//!
//! The friction force per unit length is `mu(s) q v_T / |v_T|`; since mu ~ |SR|^1.036,
//! the force goes to zero continuously at the pitch line (no sign jump). Range of the fit
//! (Xu 2005): P_h 0.5..2.5 GPa, SR up to ~1, V_e a few to ~30 m/s, typical automotive
//! gear oils; elsewhere it is an extrapolation (V_e is floored at [`V_E_MIN`]).
//!
//! Quadrature: each segment is split where x(s) changes sign. Near that root the
//! integrand is `d^b3 g(d)` in the distance d from it, with g smooth (for y = 0), so each
//! side is integrated by a 10-point Gauss-Jacobi rule for the weight d^b3 on
//! [0, d_far/2] (minus [0, d_near] when the root lies just outside the segment) and
//! 10-point Gauss-Legendre on [d_far/2, d_far]; with axial sliding
//! (y != 0) by Gauss-Legendre in t with d = d_far t^3; a side whose root lies farther away
//! than a quarter of its length gets 10-point Gauss-Legendre. Spur lines (sigma constant along the
//! line) need one evaluation of mu. No allocation.

use super::{LineIntegrals, GL_W, GL_X};

/// Xu et al. (2007) coefficients b1..b9 for the 75W90 oil.
pub const XU_B: [f64; 9] = [
    -8.916465, 1.03303, 1.036077, -0.354068, 2.812084, -0.100601, 0.752755, -0.390958, 0.620305,
];

/// Nodes of the 10-point Gauss-Jacobi rule for `int_0^1 u^b3 g(u) du` (b3 = 1.036077 of
/// [`XU_B`]), by Golub-Welsch in 40-digit arithmetic (exact for g of degree <= 19).
#[allow(clippy::excessive_precision)]
const GJ_X: [f64; 10] = [
    0.030688807066477196945,
    0.099387846150663433585,
    0.20035837284406491832,
    0.32543840655260438154,
    0.46452608923152146914,
    0.60638959860929487547,
    0.73957338606247751589,
    0.85332332740648847286,
    0.93845662125485954481,
    0.98811947854616804332,
];
/// Weights matching [`GJ_X`] (they sum to 1/(1 + b3)).
#[allow(clippy::excessive_precision)]
const GJ_W: [f64; 10] = [
    0.001365642086831812379,
    0.0078641079999687145576,
    0.021661915834414182589,
    0.041843787718258343456,
    0.064342586476047226498,
    0.083021786306639125953,
    0.091559848538750126175,
    0.085525141077227033331,
    0.063961333900589901045,
    0.029994411051845108667,
];

/// Floor of the entraining speed V_e (m/s) (guard at standstill, outside the fit).
pub const V_E_MIN: f64 = 1e-3;

/// Xu et al. (2007) friction formula (eqs. 4-5) in the paper's units (P_h GPa, SR 1, V_e m/s, nu0 mPa s,
/// R m, S um), evaluated literally (the reference for tests; the line integration uses
/// an equivalent logarithmic form).
pub fn mu_xu(p_h: f64, sr: f64, v_e: f64, nu0: f64, r: f64, s: f64) -> f64 {
    let b = XU_B;
    let z = sr.abs() * p_h * nu0.log10();
    let f = b[0] + b[3] * z + b[4] * (-z).exp() + b[8] * s.exp();
    f.exp() * p_h.powf(b[1]) * sr.abs().powf(b[2]) * v_e.powf(b[5]) * nu0.powf(b[6]) * r.powf(b[7])
}

/// The lubricant and the flank materials of law 4 (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lubricant {
    /// Dynamic viscosity of the oil at the inlet temperature (Pa s).
    pub eta_oil: f64,
    /// Composite roughness (m) (Xu's S).
    pub roughness: f64,
    /// Reduced modulus E' = 2 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2) (Pa).
    pub e_reduced: f64,
}

impl Lubricant {
    /// E' from Young's moduli (Pa) and Poisson's ratios of both gears.
    pub fn reduced_modulus(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
        2.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
    }
}

/// Law 4 for one evaluation: the line load and the speeds fixed, constants folded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EhlLine {
    /// Constant part of ln mu: b1 + b9 e^S + b7 ln nu0 + b2 ln(P_h sqrt(R)).
    ln_k: f64,
    /// P_h sqrt(R) (GPa m^0.5) = sqrt(q E' / (2 pi)) 1e-9.
    ph_c: f64,
    /// log10(nu0 (mPa s)).
    log10_nu: f64,
    omega1: f64,
    omega2: f64,
    /// L_t = a sin alpha (m).
    lt: f64,
    /// 1 / (L_t cos beta_b).
    inv_lt_cb: f64,
    sin_beta_b: f64,
}

impl EhlLine {
    /// Law 4 at line load `q = |lambda| / l` (N/m), speeds omega1, omega2 (rad/s), on the
    /// line of action of length `lt` (m) with base helix angle beta_b.
    pub fn new(
        lub: &Lubricant,
        q: f64,
        omega1: f64,
        omega2: f64,
        lt: f64,
        cos_beta_b: f64,
        sin_beta_b: f64,
    ) -> Self {
        let b = XU_B;
        let nu = lub.eta_oil * 1e3;
        let ph_c = (q.abs() * lub.e_reduced / (2.0 * std::f64::consts::PI)).sqrt() * 1e-9;
        let ln_k = b[0] + b[8] * (lub.roughness * 1e6).exp() + b[6] * nu.ln() + b[1] * ph_c.ln();
        EhlLine {
            ln_k,
            ph_c,
            log10_nu: nu.log10(),
            omega1,
            omega2,
            lt,
            inv_lt_cb: 1.0 / (lt * cos_beta_b),
            sin_beta_b,
        }
    }

    /// Local mu at sigma on the line of action for the sliding speed r = |v_T| > 0, with
    /// everything that varies along a line: R(sigma), V_e(sigma), SR = r / V_e.
    #[inline]
    pub fn mu_at(&self, sigma: f64, r: f64) -> f64 {
        self.mu_over_power(sigma, r, 1.0)
    }

    /// `mu / d^b3` for a distance d > 0 (m) (the quadrature's weight d^b3 divided out
    /// analytically: `b3 ln(r / d)` in place of `b3 ln r`); `d = 1` gives mu.
    #[inline]
    fn mu_over_power(&self, sigma: f64, r: f64, d: f64) -> f64 {
        let b = XU_B;
        let (rho1, rho2) = (sigma, self.lt - sigma);
        if !(rho1 > 0.0 && rho2 > 0.0 && r > 0.0) {
            return 0.0;
        }
        let rr = rho1 * rho2 * self.inv_lt_cb;
        let ve = (0.5 * (self.omega1 * rho1 + self.omega2 * rho2))
            .abs()
            .max(V_E_MIN);
        let z = r / ve * (self.ph_c / rr.sqrt()) * self.log10_nu;
        let ln_mu = self.ln_k
            + b[3] * z
            + b[4] * (-z).exp()
            + (b[7] - 0.5 * b[1]) * rr.ln()
            + (b[5] - b[2]) * ve.ln()
            + b[2] * (r / d).ln();
        ln_mu.exp()
    }

    /// The five integrals of `mu(s) v_T / |v_T|` (and `int mu r ds` as W) for one segment
    /// starting at sigma0, per unit line load q, and `int mu ds`.
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
        if self.sin_beta_b == 0.0 && kappa == 0.0 {
            // Spur line: sigma, v_T and so mu are constant along it.
            let r = x0.hypot(y);
            let mu = self.mu_at(sigma0, r);
            if r > 0.0 {
                let k = 0.5 * len * len;
                let (ux, uy) = (mu * x0 / r, mu * y / r);
                return (
                    LineIntegrals {
                        ix: len * ux,
                        iy: len * uy,
                        kx: k * ux,
                        ky: k * uy,
                        w: len * mu * r,
                    },
                    len * mu,
                );
            }
            return (LineIntegrals::default(), len * mu);
        }
        let ctx = Ctx {
            x0,
            y,
            kappa,
            sigma0,
        };
        let mut acc = Acc::default();
        let root = if kappa != 0.0 { x0 / kappa } else { f64::NAN };
        if root > 0.0 && root < len {
            acc.piece(self, &ctx, 0.0, root, root);
            acc.piece(self, &ctx, root, len, root);
        } else {
            acc.piece(self, &ctx, 0.0, len, root);
        }
        (
            LineIntegrals {
                ix: acc.ix,
                iy: y * acc.iy,
                kx: acc.kx,
                ky: y * acc.ky,
                w: acc.w,
            },
            acc.mu,
        )
    }
}

/// Segment data for the quadrature.
struct Ctx {
    x0: f64,
    y: f64,
    kappa: f64,
    sigma0: f64,
}

#[derive(Default)]
struct Acc {
    ix: f64,
    iy: f64,
    kx: f64,
    ky: f64,
    w: f64,
    mu: f64,
}

impl Acc {
    /// Integrates over [a, b] (b > a) on one side of the sign change at `root` (NaN or
    /// outside [a, b] when there is none in the segment).
    fn piece(&mut self, e: &EhlLine, c: &Ctx, a: f64, b: f64, root: f64) {
        let len = b - a;
        if !(len > 0.0) {
            return;
        }
        let (da, db) = ((a - root).abs(), (b - root).abs());
        let (near, far) = if da <= db { (da, db) } else { (db, da) };
        if !(near < 0.25 * len) {
            // Root far away (or none): the integrand is smooth on [a, b] (its branch point
            // at least a quarter length from it: Bernstein ellipse rho >= 2.6; the branch
            // point is weak, |x|^1.036).
            let h = 0.5 * len;
            for i in 0..5 {
                for sgn in [-1.0, 1.0] {
                    let s = a + h * (1.0 + sgn * GL_X[i]);
                    self.node(e, c, s, h * GL_W[i], 0.0);
                }
            }
            return;
        }
        let dir = if a + b > 2.0 * root { 1.0 } else { -1.0 };
        if c.y == 0.0 {
            // In the distance d from the root the integrand is d^b3 times a smooth
            // function: Gauss-Jacobi with that weight on [0, far/2] (minus [0, near] when
            // the root lies outside), Gauss-Legendre on [far/2, far] (rho = 5.8).
            let mid = 0.5 * far;
            self.jacobi(e, c, root, dir, mid, 1.0);
            if near > 0.0 {
                self.jacobi(e, c, root, dir, near, -1.0);
            }
            let h = 0.25 * far;
            for i in 0..5 {
                for sgn in [-1.0, 1.0] {
                    let s = root + dir * (mid + h * (1.0 + sgn * GL_X[i]));
                    self.node(e, c, s, h * GL_W[i], 0.0);
                }
            }
            return;
        }
        // y != 0 (axial sliding): r^b3 does not vanish at the root; d = far t^3 with t in
        // [t0, 1] clusters the nodes there (relative accuracy ~1e-6 when |y| is small
        // against the sliding along the segment, docs/friction.md).
        let t0 = (near / far).cbrt();
        let (tm, th) = (0.5 * (1.0 + t0), 0.5 * (1.0 - t0));
        for i in 0..5 {
            for sgn in [-1.0, 1.0] {
                let t = tm + sgn * th * GL_X[i];
                let t2 = t * t;
                let s = root + dir * far * t2 * t;
                self.node(e, c, s, th * GL_W[i] * 3.0 * far * t2, 0.0);
            }
        }
    }

    /// `sign * int_0^dmax` over the distance d from the root along `dir`, by the
    /// 10-point Gauss-Jacobi rule for the weight d^b3.
    fn jacobi(&mut self, e: &EhlLine, c: &Ctx, root: f64, dir: f64, dmax: f64, sign: f64) {
        let scale = sign * dmax.powf(1.0 + XU_B[2]);
        for i in 0..10 {
            let d = dmax * GJ_X[i];
            self.node(e, c, root + dir * d, scale * GJ_W[i], d);
        }
    }

    /// Adds the node s with weight wq; `d > 0`: the weight includes d^b3 (Gauss-Jacobi),
    /// so mu / d^b3 is used; `d = 0`: plain weight, mu itself.
    #[inline]
    fn node(&mut self, e: &EhlLine, c: &Ctx, s: f64, wq: f64, d: f64) {
        let x = c.x0 - c.kappa * s;
        let r = (x * x + c.y * c.y).sqrt();
        if !(r > 0.0) {
            return;
        }
        let mu = e.mu_over_power(
            c.sigma0 - e.sin_beta_b * s,
            r,
            if d > 0.0 { d } else { 1.0 },
        );
        let wm = wq * mu;
        let f = wm / r;
        self.ix += f * x;
        self.iy += f;
        self.kx += f * x * s;
        self.ky += f * s;
        self.w += wm * r;
        self.mu += wm;
    }
}
