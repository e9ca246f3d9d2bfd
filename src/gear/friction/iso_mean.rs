//! Law 3: the mean coefficient of friction of the tooth mesh after ISO/TR 14179-2.
//!
//! Schlenk's formula (L. Schlenk, dissertation TU Munich / FZG 1994), as given in
//! Niemann & Winter, Maschinenelemente vol. II (Springer), and adopted by
//! ISO/TR 14179-2:2001 for the load-dependent mesh loss (the equation numbers of these
//! primary texts could not be checked here; the formula and its units are quoted the same
//! way in the secondary literature on gear efficiency):
//!
//! `mu_mz = 0.048 (F_bt/b / (v_SigmaC rho_redC))^0.2 eta_oil^-0.05 Ra^0.25 X_L`
//!
//! in the standard's own units: F_bt/b (N/mm) the transverse tangential load at the base
//! circle per face width, v_SigmaC (m/s) the sum of the rolling speeds at the pitch point
//! (`2 v_t sin alpha_wt`), rho_redC (mm) the equivalent radius of curvature at the pitch
//! point in the normal section, eta_oil (mPa s) the dynamic viscosity of the oil at its
//! temperature, Ra (um) the mean arithmetic roughness `(Ra1 + Ra2)/2`, X_L (1) the
//! lubricant factor (1.0 mineral oil; smaller for synthetic oils). The load-dependent mesh
//! loss of the standard is then `P_VZP = mu_mz H_V P_in`.
//!
//! Fitted to FZG efficiency tests of case-carburised, ground gears in the mixed/EHL
//! regime. It has no limit at standstill (mu_mz grows as v^-0.2 when v_SigmaC -> 0): the
//! model floors the sum speed at [`V_SUM_MIN`] and reports the coefficient it uses
//! (`mu_mz` output).

/// Floor of the sum speed v_SigmaC (m/s) below which the formula is not evaluated
/// (a guard at start-up, far outside the formula's range).
pub const V_SUM_MIN: f64 = 0.1;

/// Schlenk's formula in the units of ISO/TR 14179-2 (see the module docs): F_bt/b in
/// N/mm, v_SigmaC in m/s, rho_redC in mm, eta_oil in mPa s, Ra in um, X_L dimensionless.
pub fn mu_mz(f_bt_per_b: f64, v_sum: f64, rho_red: f64, eta_oil: f64, ra: f64, x_l: f64) -> f64 {
    0.048 * (f_bt_per_b / (v_sum * rho_red)).powf(0.2) * eta_oil.powf(-0.05) * ra.powf(0.25) * x_l
}

/// The pair's constant part of law 3: everything but the normal force and the speeds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IsoMean {
    /// cos beta_b (F_bt = lambda cos beta_b, the transverse part of the normal force).
    pub cos_beta_b: f64,
    /// Face width b (mm).
    pub b_mm: f64,
    /// rho_redC (mm) = rho_1C rho_2C / ((rho_1C + rho_2C) cos beta_b), rho_jC = r_bj tan alpha_wt.
    pub rho_red_mm: f64,
    /// tan alpha_wt: v_SigmaC = tan alpha_wt (omega1 r_b1 + omega2 r_b2).
    pub tan_alpha_wt: f64,
    /// r_b1, r_b2 (m).
    pub rb: [f64; 2],
    /// eta_oil (mPa s).
    pub eta_mpas: f64,
    /// Ra (um).
    pub ra_um: f64,
    /// X_L.
    pub x_l: f64,
}

impl IsoMean {
    /// From SI inputs: face width b (m), base radii (m), working pressure angle
    /// alpha_wt, cos beta_b, eta_oil (Pa s), Ra (m), X_L.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        b: f64,
        rb1: f64,
        rb2: f64,
        alpha_wt: f64,
        cos_beta_b: f64,
        eta_oil: f64,
        ra: f64,
        x_l: f64,
    ) -> Self {
        let t = alpha_wt.tan();
        let (r1, r2) = (rb1 * t * 1e3, rb2 * t * 1e3);
        IsoMean {
            cos_beta_b,
            b_mm: b * 1e3,
            rho_red_mm: r1 * r2 / ((r1 + r2) * cos_beta_b),
            tan_alpha_wt: t,
            rb: [rb1, rb2],
            eta_mpas: eta_oil * 1e3,
            ra_um: ra * 1e6,
            x_l,
        }
    }

    /// Sum of the rolling speeds at the pitch point (m/s) for the speeds omega1, omega2.
    pub fn v_sum(&self, omega1: f64, omega2: f64) -> f64 {
        self.tan_alpha_wt * (omega1 * self.rb[0] + omega2 * self.rb[1])
    }

    /// mu_mz at the normal force |lambda| (N) and the speeds (v_SigmaC floored at
    /// [`V_SUM_MIN`]; mu_mz = 0 at zero load).
    pub fn mu(&self, lambda: f64, omega1: f64, omega2: f64) -> f64 {
        let f = lambda.abs() * self.cos_beta_b / self.b_mm;
        let v = self.v_sum(omega1, omega2).abs().max(V_SUM_MIN);
        mu_mz(f, v, self.rho_red_mm, self.eta_mpas, self.ra_um, self.x_l)
    }
}
