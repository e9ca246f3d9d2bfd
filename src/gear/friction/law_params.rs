//! Parameters of friction laws 2-5, described once, and their validation
//! (`docs/friction.md`).

use super::ehl::Lubricant;
use crate::parameter::{Kind, ParamError, Parameter, Rule};

/// Parameters of the friction laws beyond Coulomb's mu (SI units; FMI names in brackets).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionParams {
    /// Regularising speed of law 2 (m/s) (`v_reg`); law 5: the sliding speed below which
    /// its force falls off linearly.
    pub v_reg: f64,
    /// Dynamic viscosity of the oil at its temperature (Pa s) (`eta_oil`), laws 3, 4 and 5.
    pub eta_oil: f64,
    /// Mean arithmetic flank roughness Ra = (Ra1 + Ra2)/2 (m) (`Ra`); law 3, law 4 as Xu's
    /// composite roughness S, law 5 as Benedict & Kelley's average roughness S.
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

/// The friction-law parameters, each described once (FMI name, unit, default, declared
/// bounds, rule). Defaults: v_reg = 0.01 m/s, an ISO VG 100 mineral oil near 70 °C
/// (eta = 0.03 Pa s, X_L = 1), ground flanks (Ra = 0.5 um), steel (E = 206 GPa,
/// nu = 0.3). Every law's parameters are checked whichever law is selected, so that a
/// later switch of the law cannot meet an unchecked value.
pub static FRICTION_PARAMETERS: [Parameter<FrictionParams>; 8] = [
    positive("v_reg", "m/s", 0.01, |f| f.v_reg, |f, x| f.v_reg = x),
    positive("eta_oil", "Pa.s", 0.03, |f| f.eta_oil, |f, x| f.eta_oil = x),
    positive("Ra", "m", 0.5e-6, |f| f.ra, |f, x| f.ra = x),
    positive("X_L", "1", 1.0, |f| f.x_l, |f, x| f.x_l = x),
    positive("E1", "Pa", 206e9, |f| f.e1, |f, x| f.e1 = x),
    poisson("nu1", |f| f.nu1, |f, x| f.nu1 = x),
    positive("E2", "Pa", 206e9, |f| f.e2, |f, x| f.e2 = x),
    poisson("nu2", |f| f.nu2, |f, x| f.nu2 = x),
];

/// A parameter that must be > 0 (declared min 1e-300: FMI bounds are inclusive).
const fn positive(
    name: &'static str,
    unit: &'static str,
    default: f64,
    get: fn(&FrictionParams) -> f64,
    put: fn(&mut FrictionParams, f64),
) -> Parameter<FrictionParams> {
    Parameter {
        name,
        unit,
        kind: Kind::Real,
        default,
        min: Some(1e-300),
        max: None,
        rule: Rule::Positive,
        get,
        put,
    }
}

/// A Poisson's ratio: -1 < nu < 0.5 (declared -0.999999 ..= 0.499999), default 0.3.
const fn poisson(
    name: &'static str,
    get: fn(&FrictionParams) -> f64,
    put: fn(&mut FrictionParams, f64),
) -> Parameter<FrictionParams> {
    Parameter {
        name,
        unit: "1",
        kind: Kind::Real,
        default: 0.3,
        min: Some(-0.999999),
        max: Some(0.499999),
        rule: Rule::Open(-1.0, 0.5),
        get,
        put,
    }
}

impl Default for FrictionParams {
    /// The defaults of [`FRICTION_PARAMETERS`].
    fn default() -> Self {
        let mut f = FrictionParams {
            v_reg: 0.0,
            eta_oil: 0.0,
            ra: 0.0,
            x_l: 0.0,
            e1: 0.0,
            nu1: 0.0,
            e2: 0.0,
            nu2: 0.0,
        };
        for p in &FRICTION_PARAMETERS {
            (p.put)(&mut f, p.default);
        }
        f
    }
}

impl FrictionParams {
    /// Checks the rule of every parameter of [`FRICTION_PARAMETERS`].
    ///
    /// # Errors
    /// The first violated rule, named as in the FMI model description.
    pub fn validate(&self) -> Result<(), ParamError> {
        FRICTION_PARAMETERS.iter().try_for_each(|p| p.check(self))
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
