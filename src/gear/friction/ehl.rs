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
//! Quadrature: see [`quadrature`] (split at the pitch line, an 8- to 12-point
//! Gauss-Jacobi panel for the weight d^(b3-1) there, with an expansion in the axial
//! sliding where it is small (as in a run), a sinh map across the branch points of larger
//! axial sliding, graded Gauss-Legendre panels beyond, with fewer nodes where a panel's
//! share of the integrals is small; the nodes of a panel evaluated together with
//! vectorised `ln`/`exp`; 1e-11 against adaptive quadrature). Spur lines (sigma constant
//! along the line) need one evaluation of mu.
//! No allocation.

use super::LineIntegrals;

pub(crate) mod batch_math;
pub mod quadrature;
pub(super) mod rules;

/// Xu et al. (2007) coefficients b1..b9 for the 75W90 oil.
pub const XU_B: [f64; 9] = [
    -8.916465, 1.03303, 1.036077, -0.354068, 2.812084, -0.100601, 0.752755, -0.390958, 0.620305,
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
    /// P_h sqrt(R) log10(nu0): z = SR P_h log10(nu0) = r z_coef / (V_e sqrt(R)).
    z_coef: f64,
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
            z_coef: ph_c * nu.log10(),
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
        if !(r > 0.0) {
            return 0.0;
        }
        (self.ln_mu_over_slide(sigma, r) + XU_B[2] * r.ln()).exp()
    }

    /// `ln mu - b3 ln r` at sigma for the sliding speed r >= 0: the part of ln mu that is
    /// smooth where the sliding vanishes (-inf outside the line of action, so that its
    /// exponential is 0). Two logarithms and one exponential:
    /// `ln_k + b4 z + b5 e^-z + (b8 - b2/2) ln R + (b6 - b3) ln V_e` with
    /// `z = SR P_h log10(nu0) = r (P_h sqrt(R)) log10(nu0) / (V_e sqrt(R))`.
    #[inline]
    pub(crate) fn ln_mu_over_slide(&self, sigma: f64, r: f64) -> f64 {
        let b = XU_B;
        let (rho1, rho2) = (sigma, self.lt - sigma);
        if !(rho1 > 0.0 && rho2 > 0.0) {
            return f64::NEG_INFINITY;
        }
        let rr = rho1 * rho2 * self.inv_lt_cb;
        let ve = (0.5 * (self.omega1 * rho1 + self.omega2 * rho2))
            .abs()
            .max(V_E_MIN);
        let z = r * self.z_coef / (ve * rr.sqrt());
        self.ln_k
            + b[3] * z
            + b[4] * (-z).exp()
            + (b[7] - 0.5 * b[1]) * rr.ln()
            + (b[5] - b[2]) * ve.ln()
    }

    /// `exp(ln_mu_over_slide(sigma_i, r_i) + extra_i)` for the N nodes of a panel (r_i > 0;
    /// 0 outside the line of action): the same formula as [`EhlLine::ln_mu_over_slide`],
    /// written as one loop over the nodes with the branch-free `ln` and `exp` of
    /// [`batch_math`], which the compiler vectorises (two nodes per SSE2 instruction).
    #[inline(always)]
    pub(crate) fn exp_ln_mu_batch<const N: usize>(
        &self,
        sigma: &[f64; N],
        r: &[f64; N],
        extra: &[f64; N],
    ) -> [f64; N] {
        self.exp_ln_mu_batch_z(sigma, r, extra).0
    }

    /// [`EhlLine::exp_ln_mu_batch`] and, per node, z = SR P_h log10(nu0) and e^-z (for
    /// `d ln mu / d ln r = b3 + (b4 - b5 e^-z) z` at fixed sigma).
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    pub(crate) fn exp_ln_mu_batch_z<const N: usize>(
        &self,
        sigma: &[f64; N],
        r: &[f64; N],
        extra: &[f64; N],
    ) -> ([f64; N], [f64; N], [f64; N]) {
        let b = XU_B;
        let (c_r, c_v) = (b[7] - 0.5 * b[1], b[5] - b[2]);
        // One loop per elementary function: each loop's iterations are independent, so
        // the long dependency chains of the series overlap (one fused loop runs at the
        // latency of a chain).
        let (mut rr, mut ve, mut z) = ([0.0; N], [0.0; N], [0.0; N]);
        for i in 0..N {
            let (rho1, rho2) = (sigma[i], self.lt - sigma[i]);
            rr[i] = (rho1 * rho2 * self.inv_lt_cb).max(f64::MIN_POSITIVE);
            ve[i] = (0.5 * (self.omega1 * rho1 + self.omega2 * rho2))
                .abs()
                .max(V_E_MIN);
            z[i] = r[i] * self.z_coef / (ve[i] * rr[i].sqrt());
        }
        let mut ln_mu = [0.0; N];
        for i in 0..N {
            ln_mu[i] = self.ln_k + b[3] * z[i] + extra[i];
        }
        for i in 0..N {
            ln_mu[i] += c_r * batch_math::ln(rr[i]);
        }
        for i in 0..N {
            ln_mu[i] += c_v * batch_math::ln(ve[i]);
        }
        let mut ez = [0.0; N];
        for i in 0..N {
            ez[i] = batch_math::exp(-z[i]);
            ln_mu[i] += b[4] * ez[i];
        }
        let mut out = [0.0; N];
        for i in 0..N {
            let inside = (sigma[i] > 0.0) & (sigma[i] < self.lt);
            let mu = batch_math::exp(ln_mu[i]);
            out[i] = if inside { mu } else { 0.0 };
        }
        (out, z, ez)
    }

    /// At the pitch line (r = 0) at sigma: `ln mu - b3 ln r` (as [`EhlLine::ln_mu_over_slide`]),
    /// its derivative along sigma at fixed r = 0, and z / r (z grows like r at fixed sigma):
    /// the local expansion of mu the quadrature's axial-sliding terms use.
    pub(crate) fn pitch_expansion(&self, sigma: f64) -> (f64, f64, f64) {
        let b = XU_B;
        let (rho1, rho2) = (sigma, self.lt - sigma);
        if !(rho1 > 0.0 && rho2 > 0.0) {
            return (f64::NEG_INFINITY, 0.0, 0.0);
        }
        let rr = rho1 * rho2 * self.inv_lt_cb;
        let v = 0.5 * (self.omega1 * rho1 + self.omega2 * rho2);
        let ve = v.abs().max(V_E_MIN);
        // d ln V_e / d sigma = V_e' / V_e (0 where V_e is floored)
        let dln_ve = if v.abs() > V_E_MIN {
            0.5 * (self.omega1 - self.omega2) / v
        } else {
            0.0
        };
        let slope = (b[7] - 0.5 * b[1]) * (1.0 / rho1 - 1.0 / rho2) + (b[5] - b[2]) * dln_ve;
        (
            self.ln_mu_over_slide(sigma, 0.0),
            slope,
            self.z_coef / (ve * rr.sqrt()),
        )
    }

    /// `z = SR P_h log10(nu0)` at sigma for the sliding speed r (the argument of the
    /// exponentials of the law; the quadrature bounds its range per panel).
    #[inline]
    pub(crate) fn z_at(&self, sigma: f64, r: f64) -> f64 {
        let (rho1, rho2) = (sigma, self.lt - sigma);
        let rr = (rho1 * rho2 * self.inv_lt_cb).abs();
        let ve = (0.5 * (self.omega1 * rho1 + self.omega2 * rho2))
            .abs()
            .max(V_E_MIN);
        (r * self.z_coef / (ve * rr.sqrt())).abs()
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
        quadrature::segment(self, x0, y, kappa, len, sigma0)
    }
}
