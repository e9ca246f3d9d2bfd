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

/// The gear loss factor of ISO/TR 14179-2 (Ohlendorf's formula, H. Ohlendorf,
/// dissertation TU Munich 1958, as given by Niemann & Winter, Maschinenelemente vol. II,
/// and used by ISO/TR 14179-2:2001 in `P_VZP = mu_mz H_V P_in`):
///
/// `H_V = pi (u + 1) / (z1 u cos beta_b) (1 - eps_alpha + eps_1^2 + eps_2^2)`  (dimensionless)
///
/// with u = z2/z1, eps_1 and eps_2 the approach and recess parts of the transverse contact
/// ratio (eps_alpha = eps_1 + eps_2). It assumes the load of a spur pair (shared equally in
/// double contact, whole in single contact); for helical pairs it is the standard's value,
/// not the model's. The model spreads the load uniformly over the contact lines and has
/// its own loss factor `H_V` (`PairGeometry::loss_factor`, `model.md` §9.7): equal to this
/// one for spur pairs with eps_1, eps_2 <= 1, 16-19 % above it for common helical pairs.
pub fn ohlendorf_h_v(z1: f64, z2: f64, cos_beta_b: f64, eps_1: f64, eps_2: f64) -> f64 {
    let u = z2 / z1;
    std::f64::consts::PI * (u + 1.0) / (z1 * u * cos_beta_b)
        * (1.0 - (eps_1 + eps_2) + eps_1 * eps_1 + eps_2 * eps_2)
}

/// Why [`ohlendorf_h_v`] does not hold for a pair, if it does not: the formula places one
/// double-contact zone on each side of the pitch point (approach and recess parts eps_1,
/// eps_2 at most 1; then eps_alpha <= 2 and no triple contact). The model's own `H_V` is
/// not affected.
pub fn ohlendorf_outside(eps_1: f64, eps_2: f64) -> Option<String> {
    (eps_1 > 1.0 || eps_2 > 1.0).then(|| {
        format!(
            "H_V_iso (Ohlendorf's loss factor of ISO/TR 14179-2) assumes approach and recess \
             contact ratios eps_1, eps_2 <= 1; this pair has eps_1 = {eps_1:.4}, eps_2 = \
             {eps_2:.4} (eps_alpha = {:.4}), so H_V_iso is outside its derivation; the \
             model's H_V holds (docs/friction.md, two loss factors)",
            eps_1 + eps_2
        )
    })
}

/// The operating range of Schlenk's fit as the secondary literature quotes it (the primary
/// text could not be checked here): pitch-line speed v_t at least 1 m/s and transverse
/// load per face width F_bt/b at least 150 N/mm (FZG efficiency tests of case-carburised,
/// ground gears, Schlenk 1994). Below these the formula extrapolates.
pub const FITTED_V_T_MIN: f64 = 1.0;
/// See [`FITTED_V_T_MIN`]; N/mm.
pub const FITTED_LOAD_MIN: f64 = 150.0;

/// Where an operating point (pitch-line speed v_t in m/s, F_bt/b in N/mm) lies outside
/// Schlenk's fitted range ([`FITTED_V_T_MIN`], [`FITTED_LOAD_MIN`]): one phrase per
/// violated bound, empty inside.
pub fn outside_fitted_range(v_t: f64, f_bt_per_b: f64) -> Vec<String> {
    // fixed decimals for ordinary values, an exponent beyond (no 300-digit numbers)
    let num = |x: f64, decimals: usize| {
        if x.abs() < 1e6 {
            format!("{x:.decimals$}")
        } else {
            format!("{x:.3e}")
        }
    };
    let mut out = Vec::new();
    if !(v_t >= FITTED_V_T_MIN) {
        out.push(format!(
            "pitch-line speed v_t = {} m/s < {FITTED_V_T_MIN} m/s",
            num(v_t, 3)
        ));
    }
    if !(f_bt_per_b >= FITTED_LOAD_MIN) {
        out.push(format!(
            "load per face width F_bt/b = {} N/mm < {FITTED_LOAD_MIN} N/mm",
            num(f_bt_per_b, 1)
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ohlendorf's H_V of three pairs against a hand calculation (involute geometry by
    /// hand: eps_1 = (sigma_C - sigma_A)/p_bt, eps_2 = (sigma_E - sigma_C)/p_bt, then the
    /// formula; docs/friction.md "Two loss factors" lists the steps) and, for the spur FZG
    /// C40 gear, the 0.1986 its GEARpie report prints.
    #[test]
    fn ohlendorf_h_v_matches_hand_values() {
        // (z1, z2, eps_1, eps_2, cos beta_b, H_V by hand)
        #[rustfmt::skip]
        let cases = [
            // FZG C40, spur, x = 0.1817/0.1715, a_w = 91.5 mm
            (16.0, 24.0, 0.728_340_3, 0.734_106_1, 1.0, 0.198_622_3),
            // default pair: 27/41, m_n 2 mm, beta 20 deg
            (27.0, 41.0, 0.786_182_7, 0.750_023_0, 0.946_945_6, 0.131_325_7),
            // the user's pair of issue 25: 31/67, m_n 3 mm, beta 15 deg
            (31.0, 67.0, 0.854_412_4, 0.792_108_6, 0.969_973_6, 0.108_645_0),
        ];
        for (z1, z2, e1, e2, cbb, hand) in cases {
            let h = ohlendorf_h_v(z1, z2, cbb, e1, e2);
            assert!((h - hand).abs() < 2e-7, "z {z1}/{z2}: {h} vs {hand}");
        }
        let c40 = ohlendorf_h_v(16.0, 24.0, 1.0, 0.728_340_3, 0.734_106_1);
        assert!((c40 - 0.1986).abs() < 0.5e-4);
    }

    #[test]
    fn fitted_range() {
        assert!(outside_fitted_range(5.0, 300.0).is_empty());
        assert_eq!(outside_fitted_range(0.5, 300.0).len(), 1);
        assert_eq!(outside_fitted_range(0.5, 100.0).len(), 2);
    }
}
