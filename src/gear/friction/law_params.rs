//! Parameters of friction laws 2-4 and their validation (`docs/friction.md`).

use super::ehl::Lubricant;
use crate::gear::ParamError;

/// Parameters of the friction laws beyond Coulomb's mu (SI units; FMI names in brackets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionParams {
    /// Regularising speed of law 2 (m/s) (`v_reg`).
    pub v_reg: f64,
    /// Dynamic viscosity of the oil at its temperature (Pa s) (`eta_oil`), laws 3 and 4.
    pub eta_oil: f64,
    /// Mean arithmetic flank roughness Ra = (Ra1 + Ra2)/2 (m) (`Ra`); law 3, and law 4
    /// as Xu's composite roughness S.
    pub ra: f64,
    /// Lubricant factor X_L of ISO/TR 14179-2 (1) (`X_L`), law 3.
    pub x_l: f64,
    /// Young's modulus of gear 1 (Pa) (`E1`), law 4.
    pub e1: f64,
    /// Poisson's ratio of gear 1 (`nu1`), law 4.
    pub nu1: f64,
    /// Young's modulus of gear 2 (Pa) (`E2`), law 4.
    pub e2: f64,
    /// Poisson's ratio of gear 2 (`nu2`), law 4.
    pub nu2: f64,
}

impl Default for FrictionParams {
    /// v_reg = 0.01 m/s, an ISO VG 100 mineral oil near 70 °C (eta = 0.03 Pa s, X_L = 1),
    /// ground flanks (Ra = 0.5 um), steel (E = 206 GPa, nu = 0.3).
    fn default() -> Self {
        FrictionParams {
            v_reg: 0.01,
            eta_oil: 0.03,
            ra: 0.5e-6,
            x_l: 1.0,
            e1: 206e9,
            nu1: 0.3,
            e2: 206e9,
            nu2: 0.3,
        }
    }
}

fn check(ok: bool, name: &'static str, value: f64, req: &str) -> Result<(), ParamError> {
    if ok {
        Ok(())
    } else {
        Err(ParamError {
            name,
            value,
            requirement: req.to_string(),
        })
    }
}

impl FrictionParams {
    /// Checks every bound (all laws' parameters, whichever law is selected, so that a
    /// later switch of the law cannot meet an unchecked value).
    ///
    /// # Errors
    /// The first violated bound, named as in the FMI model description.
    pub fn validate(&self) -> Result<(), ParamError> {
        let pos = |x: f64| x > 0.0 && x.is_finite();
        check(
            pos(self.v_reg),
            "v_reg",
            self.v_reg,
            "0 < v_reg < inf (m/s)",
        )?;
        check(
            pos(self.eta_oil),
            "eta_oil",
            self.eta_oil,
            "0 < eta_oil < inf (Pa s, e.g. 0.03)",
        )?;
        check(pos(self.ra), "Ra", self.ra, "0 < Ra < inf (m, e.g. 0.5e-6)")?;
        check(
            pos(self.x_l),
            "X_L",
            self.x_l,
            "0 < X_L < inf (1.0 for mineral oil)",
        )?;
        check(pos(self.e1), "E1", self.e1, "0 < E1 < inf (Pa)")?;
        check(
            self.nu1 > -1.0 && self.nu1 < 0.5,
            "nu1",
            self.nu1,
            "-1 < nu1 < 0.5",
        )?;
        check(pos(self.e2), "E2", self.e2, "0 < E2 < inf (Pa)")?;
        check(
            self.nu2 > -1.0 && self.nu2 < 0.5,
            "nu2",
            self.nu2,
            "-1 < nu2 < 0.5",
        )?;
        Ok(())
    }

    /// The lubricant/material data of law 4.
    pub fn lubricant(&self) -> Lubricant {
        Lubricant {
            eta_oil: self.eta_oil,
            roughness: self.ra,
            e_reduced: Lubricant::reduced_modulus(self.e1, self.nu1, self.e2, self.nu2),
        }
    }
}
