//! Every parameter of the geared rotor, described once: the rotor's own here
//! ([`ROTOR_PARAMETERS`]), the pair's in `gear::GEAR_PARAMETERS`, the friction laws' in
//! `gear::FRICTION_PARAMETERS`; [`all`] lists the 40 in one order (the order of the
//! serialized state). Used by the FMU binding (value store -> [`Params`]), the `periodic`
//! binary (parameter files), the FMU-state codec, the defaults and the validation; the
//! model description declares the same names, units, start values and bounds, and a test
//! (tests/rotor_parameter_table.rs) checks that both agree.

use super::params::Params;
use crate::gear::{FrictionLaw, FrictionParams, GearData, FRICTION_PARAMETERS, GEAR_PARAMETERS};
use crate::parameter::{Kind, ParamError, Parameter, Rule};

const FRICTION_LAWS: &str =
    "1 Coulomb, 2 regularised, 3 ISO/TR 14179-2, 4 local EHL, 5 Benedict-Kelley";

/// The rotor parameters (`model.md` §5, §8, §10), one row each (name, unit, default,
/// declared min, max, the model's rule, the field): masses, inertias, bearings, the
/// damper, friction coefficient and law, initial mesh phase, the drive filter. A mass or
/// inertia of 0 stands for the solid steel gear body of the geometry
/// ([`Params::with_solid_bodies`](super::Params::with_solid_bodies)).
#[rustfmt::skip]
pub static ROTOR_PARAMETERS: [Parameter<Params>; 22] = [
    real("m1", "kg", 2.0, Some(0.0), None, Rule::NonNegative, |p| p.rotor1.m, |p, x| p.rotor1.m = x),
    real("J1", "kg.m2", 1.0e-3, Some(0.0), None, Rule::NonNegative, |p| p.rotor1.j, |p, x| p.rotor1.j = x),
    real("k1.x", "N/m", 2e8, Some(0.0), None, Rule::NonNegative, |p| p.rotor1.k[0], |p, x| p.rotor1.k[0] = x),
    real("k1.y", "N/m", 2e8, Some(0.0), None, Rule::NonNegative, |p| p.rotor1.k[1], |p, x| p.rotor1.k[1] = x),
    real("k1.z", "N/m", 1e8, Some(0.0), None, Rule::NonNegative, |p| p.rotor1.k[2], |p, x| p.rotor1.k[2] = x),
    real("d1.x", "N.s/m", 1200.0, Some(0.0), None, Rule::NonNegative, |p| p.rotor1.d[0], |p, x| p.rotor1.d[0] = x),
    real("d1.y", "N.s/m", 1200.0, Some(0.0), None, Rule::NonNegative, |p| p.rotor1.d[1], |p, x| p.rotor1.d[1] = x),
    real("d1.z", "N.s/m", 850.0, Some(0.0), None, Rule::NonNegative, |p| p.rotor1.d[2], |p, x| p.rotor1.d[2] = x),
    real("m2", "kg", 4.0, Some(0.0), None, Rule::NonNegative, |p| p.rotor2.m, |p, x| p.rotor2.m = x),
    real("J2", "kg.m2", 5.0e-3, Some(0.0), None, Rule::NonNegative, |p| p.rotor2.j, |p, x| p.rotor2.j = x),
    real("k2.x", "N/m", 2e8, Some(0.0), None, Rule::NonNegative, |p| p.rotor2.k[0], |p, x| p.rotor2.k[0] = x),
    real("k2.y", "N/m", 2e8, Some(0.0), None, Rule::NonNegative, |p| p.rotor2.k[1], |p, x| p.rotor2.k[1] = x),
    real("k2.z", "N/m", 1e8, Some(0.0), None, Rule::NonNegative, |p| p.rotor2.k[2], |p, x| p.rotor2.k[2] = x),
    real("d2.x", "N.s/m", 1700.0, Some(0.0), None, Rule::NonNegative, |p| p.rotor2.d[0], |p, x| p.rotor2.d[0] = x),
    real("d2.y", "N.s/m", 1700.0, Some(0.0), None, Rule::NonNegative, |p| p.rotor2.d[1], |p, x| p.rotor2.d[1] = x),
    real("d2.z", "N.s/m", 1200.0, Some(0.0), None, Rule::NonNegative, |p| p.rotor2.d[2], |p, x| p.rotor2.d[2] = x),
    real("d_phi", "N.m.s/rad", 0.5, Some(0.0), Some(1e6), Rule::NonNegative, |p| p.d_phi, |p, x| p.d_phi = x),
    real("mu", "1", 0.05, Some(0.0), Some(1.0), Rule::NonNegative, |p| p.mu, |p, x| p.mu = x),
    real("psi0", "1", 0.0, None, None, Rule::Finite, |p| p.psi0, |p, x| p.psi0 = x),
    Parameter {
        name: "friction_law",
        unit: "",
        kind: Kind::Integer,
        default: 1.0,
        min: Some(1.0),
        max: Some(5.0),
        rule: Rule::Code(5, FRICTION_LAWS),
        get: |p| f64::from(p.friction_law.code()),
        put: |p, x| p.friction_law = FrictionLaw::from_code(x as i32).unwrap_or_default(),
    },
    real("omega1_filter_frequency", "Hz", 1000.0, Some(1e-3), Some(1e6), Rule::Positive, |p| p.omega1_filter_hz, |p, x| p.omega1_filter_hz = x),
    real("zeta_mesh", "1", 0.05, Some(0.0), Some(10.0), Rule::NonNegative, |p| p.zeta_mesh, |p, x| p.zeta_mesh = x),
];

/// Position of d_phi in [`ROTOR_PARAMETERS`] (tunable: checked alone when set).
pub const D_PHI: usize = 16;
/// Position of mu in [`ROTOR_PARAMETERS`] (tunable).
pub const MU: usize = 17;

#[cfg(test)]
mod tests {
    #[test]
    fn tunable_positions() {
        assert_eq!(super::ROTOR_PARAMETERS[super::D_PHI].name, "d_phi");
        assert_eq!(super::ROTOR_PARAMETERS[super::MU].name, "mu");
    }
}

#[allow(clippy::too_many_arguments)]
const fn real(
    name: &'static str,
    unit: &'static str,
    default: f64,
    min: Option<f64>,
    max: Option<f64>,
    rule: Rule,
    get: fn(&Params) -> f64,
    put: fn(&mut Params, f64),
) -> Parameter<Params> {
    Parameter {
        name,
        unit,
        kind: Kind::Real,
        default,
        min,
        max,
        rule,
        get,
        put,
    }
}

/// One parameter of [`Params`], whichever part of it the parameter belongs to.
#[derive(Clone, Copy)]
pub enum ParamRef {
    /// Of the gear pair (`Params::gear`).
    Gear(&'static Parameter<GearData>),
    /// Of the rotor (`Params` itself).
    Rotor(&'static Parameter<Params>),
    /// Of the friction laws (`Params::friction`).
    Friction(&'static Parameter<FrictionParams>),
}

macro_rules! each {
    ($self:expr, $p:ident => $e:expr) => {
        match $self {
            ParamRef::Gear($p) => $e,
            ParamRef::Rotor($p) => $e,
            ParamRef::Friction($p) => $e,
        }
    };
}

impl ParamRef {
    /// FMI name.
    pub fn name(self) -> &'static str {
        each!(self, p => p.name)
    }
    /// SI unit ("1" dimensionless, "" for integers).
    pub fn unit(self) -> &'static str {
        each!(self, p => p.unit)
    }
    /// Real or integer.
    pub fn kind(self) -> Kind {
        each!(self, p => p.kind)
    }
    /// Default value.
    pub fn default_value(self) -> f64 {
        each!(self, p => p.default)
    }
    /// Declared (min, max).
    pub fn declared(self) -> (Option<f64>, Option<f64>) {
        each!(self, p => (p.min, p.max))
    }
    /// The model's rule.
    pub fn rule(self) -> Rule {
        each!(self, p => p.rule)
    }
    /// The value in `params`.
    pub fn get(self, params: &Params) -> f64 {
        match self {
            ParamRef::Gear(p) => (p.get)(&params.gear),
            ParamRef::Rotor(p) => (p.get)(params),
            ParamRef::Friction(p) => (p.get)(&params.friction),
        }
    }
    /// Sets the value in `params` (integers and codes checked).
    ///
    /// # Errors
    /// A non-integer for an integer parameter, an unknown code.
    pub fn set(self, params: &mut Params, x: f64) -> Result<(), ParamError> {
        match self {
            ParamRef::Gear(p) => p.set(&mut params.gear, x),
            ParamRef::Rotor(p) => p.set(params, x),
            ParamRef::Friction(p) => p.set(&mut params.friction, x),
        }
    }
    /// Checks the model's rule of this parameter on `params` (the pair's rules, which
    /// involve several parameters, are `PairGeometry::new`'s).
    ///
    /// # Errors
    /// The violated rule.
    pub fn check(self, params: &Params) -> Result<(), ParamError> {
        match self {
            ParamRef::Gear(p) => p.check(&params.gear),
            ParamRef::Rotor(p) => p.check(params),
            ParamRef::Friction(p) => p.check(&params.friction),
        }
    }
}

/// All parameters of [`Params`]: the pair's, the rotor's, the friction laws'.
pub fn all() -> impl Iterator<Item = ParamRef> {
    GEAR_PARAMETERS
        .iter()
        .map(ParamRef::Gear)
        .chain(ROTOR_PARAMETERS.iter().map(ParamRef::Rotor))
        .chain(FRICTION_PARAMETERS.iter().map(ParamRef::Friction))
}

/// The parameter called `name` (the FMI name).
pub fn by_name(name: &str) -> Option<ParamRef> {
    all().find(|p| p.name() == name)
}
