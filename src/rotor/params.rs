//! Parameters and held inputs of the geared rotor (`model.md` §5, §10).

use super::param_table::{self, ROTOR_PARAMETERS};
use crate::gear::{FrictionLaw, FrictionParams, GearData, PairGeometry};
use crate::parameter::ParamError;

/// Mass data of one rotor (`model.md` §5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotorData {
    /// Mass (translational DoFs).
    pub m: f64,
    /// Polar moment of inertia about the gear axis.
    pub j: f64,
    /// Bearing stiffness per axis x, y, z.
    pub k: [f64; 3],
    /// Bearing damping per axis x, y, z.
    pub d: [f64; 3],
}

/// All parameters of the model (`model.md` §10).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    /// Gear pair data.
    pub gear: GearData,
    /// Rotor 1 (driving, prescribed speed).
    pub rotor1: RotorData,
    /// Rotor 2 (driven).
    pub rotor2: RotorData,
    /// Rotational damper on gear 2.
    pub d_phi: f64,
    /// Coefficient of friction.
    pub mu: f64,
    /// Initial mesh phase in base pitches (§3.4).
    pub psi0: f64,
    /// Friction law (seam).
    pub friction_law: FrictionLaw,
    /// Corner frequency of the drive-speed filter (`model.md` §8), Hz.
    pub omega1_filter_hz: f64,
    /// Parameters of friction laws 2-4 (v_reg, lubricant, roughness, materials).
    pub friction: FrictionParams,
    /// Damping ratio of the elastic mesh (`model.md` §3.5); unused by the rigid contact.
    pub zeta_mesh: f64,
    /// The tooth contact model (FMU Enumeration `tooth_contact`, fixed; not in the
    /// parameter table, like the binding's settings, but part of the model).
    pub tooth_contact: ToothContact,
}

/// The tooth contact model (`model.md` §3.3, §3.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ToothContact {
    /// 1: rigid teeth, the no-penetration constraint and its Lagrange multiplier (index 2).
    #[default]
    Rigid,
    /// 2: elastic teeth on the drive flank: the normal force from the approach delta and
    /// its rate, an algebraic (index-1) component in place of the multiplier.
    Elastic,
}

impl ToothContact {
    /// From the FMI code (1 rigid, 2 elastic).
    pub fn from_code(code: i32) -> Option<Self> {
        match code {
            1 => Some(ToothContact::Rigid),
            2 => Some(ToothContact::Elastic),
            _ => None,
        }
    }

    /// The FMI code.
    pub fn code(self) -> i32 {
        match self {
            ToothContact::Rigid => 1,
            ToothContact::Elastic => 2,
        }
    }
}

impl Default for Params {
    /// The defaults of the parameter table (`param_table`; `model.md` §10,
    /// omega1_filter_hz = 1000 Hz, `model.md` §8).
    fn default() -> Self {
        let mut p = Params {
            gear: GearData::default(),
            rotor1: RotorData {
                m: 0.0,
                j: 0.0,
                k: [0.0; 3],
                d: [0.0; 3],
            },
            rotor2: RotorData {
                m: 0.0,
                j: 0.0,
                k: [0.0; 3],
                d: [0.0; 3],
            },
            d_phi: 0.0,
            mu: 0.0,
            psi0: 0.0,
            friction_law: FrictionLaw::Coulomb,
            omega1_filter_hz: 0.0,
            friction: FrictionParams::default(),
            zeta_mesh: 0.0,
            tooth_contact: ToothContact::Rigid,
        };
        for q in &ROTOR_PARAMETERS {
            (q.put)(&mut p, q.default);
        }
        p
    }
}

impl Params {
    /// Checks every parameter's rule (`param_table`) and the pair's rules, and derives the
    /// pair geometry.
    ///
    /// # Errors
    /// The first violated rule, named as in the FMI model description.
    pub fn validate(&self) -> Result<PairGeometry, ParamError> {
        let g = PairGeometry::new(&self.gear)?;
        for p in &ROTOR_PARAMETERS {
            p.check(self)?;
        }
        // 0 means "the solid body of the geometry"; a path that builds a model must
        // resolve it first (`with_solid_bodies`), the FMU does.
        for (name, x) in [
            ("m1", self.rotor1.m),
            ("J1", self.rotor1.j),
            ("m2", self.rotor2.m),
            ("J2", self.rotor2.j),
        ] {
            if !(x > 0.0) {
                return Err(ParamError {
                    name,
                    value: x,
                    requirement: format!(
                        "{name} > 0 here (0 = the solid steel body from the geometry is \
                         resolved by the FMU; give a positive value)"
                    ),
                });
            }
        }
        self.friction.validate()?;
        let ra_max = crate::gear::friction::benedict_kelley::RA_MAX;
        if self.friction_law == FrictionLaw::BenedictKelley && !(self.friction.ra < ra_max) {
            return Err(ParamError {
                name: "Ra",
                value: self.friction.ra,
                requirement: format!(
                    "Ra < {ra_max:e} m with friction_law = 5 (Benedict & Kelley's roughness \
                     factor 50/(50 - S) needs S < 50 micro-inch)"
                ),
            });
        }
        Ok(g)
    }

    /// The masses and inertias with every 0 replaced by the solid steel body of the
    /// geometry (`SolidBodies`); a pair whose geometry is invalid is returned unchanged
    /// (`validate` then names the rule).
    pub fn with_solid_bodies(mut self) -> Self {
        if let Ok(g) = PairGeometry::new(&self.gear) {
            let s = SolidBodies::of(&g);
            for (x, solid) in [
                (&mut self.rotor1.m, s.m[0]),
                (&mut self.rotor1.j, s.j[0]),
                (&mut self.rotor2.m, s.m[1]),
                (&mut self.rotor2.j, s.j[1]),
            ] {
                if *x == 0.0 {
                    *x = solid;
                }
            }
        }
        self
    }

    /// Warnings for masses or inertias that do not fit the geometry: outside
    /// `PLAUSIBLE_SOLID_RATIO` times the solid steel body (`SolidBodies`). One
    /// message per value, naming it, the solid body's value and the rule.
    pub fn implausible_bodies(&self, g: &PairGeometry) -> Vec<String> {
        let s = SolidBodies::of(g);
        let (lo, hi) = PLAUSIBLE_SOLID_RATIO;
        let mut out = Vec::new();
        for (name, unit, x, solid) in [
            ("m1", "kg", self.rotor1.m, s.m[0]),
            ("J1", "kg m^2", self.rotor1.j, s.j[0]),
            ("m2", "kg", self.rotor2.m, s.m[1]),
            ("J2", "kg m^2", self.rotor2.j, s.j[1]),
        ] {
            let ratio = x / solid;
            if !(lo..=hi).contains(&ratio) {
                let ratio = if (1e-3..1e4).contains(&ratio) {
                    format!("{ratio:.3}")
                } else {
                    format!("{ratio:.3e}")
                };
                out.push(format!(
                    "{name} = {x:.4e} {unit} is {ratio} times the solid steel gear body of \
                     this geometry ({name}_solid = {solid:.4e} {unit}); plausible is {lo} to \
                     {hi} times (a thin rim keeps at least ~0.34 of the solid inertia, a shaft \
                     and hub rarely add more than ten times the gear); check the value and its \
                     unit, or set {name} = 0 to use the solid body"
                ));
            }
        }
        out
    }
}

/// Density of steel used for the solid gear bodies, kg/m^3.
pub const STEEL_DENSITY: f64 = 7850.0;

/// The range of (given value) / (solid body's value) of a mass or inertia that passes
/// without a warning. Lower end: a gear with a web keeps at least its rim; a rim from
/// 0.9 r to r already has 1 - 0.9^4 = 0.34 of the solid inertia. Upper end: a gear on a
/// shaft with a hub or a coupling rarely carries more than ten times its own body.
pub const PLAUSIBLE_SOLID_RATIO: (f64, f64) = (0.3, 10.0);

/// The solid steel gear bodies of a pair (`model.md` §5): each gear a solid cylinder of
/// its reference diameter `d_j = 2 r_j = z_j m_n / cos beta` and the face width `b`, of
/// steel ([`STEEL_DENSITY`]):
///
/// `m_j = rho pi r_j^2 b` [kg],  `J_j = m_j r_j^2 / 2` [kg m^2]
/// (the polar moment of inertia of a solid cylinder about its axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidBodies {
    /// Masses of gear 1, 2, kg.
    pub m: [f64; 2],
    /// Polar moments of inertia of gear 1, 2, kg m^2.
    pub j: [f64; 2],
}

impl SolidBodies {
    /// From the pair geometry (reference radii r1, r2 and the face width b, in m).
    pub fn of(g: &PairGeometry) -> Self {
        let body = |r: f64| {
            let m = STEEL_DENSITY * std::f64::consts::PI * r * r * g.data.b;
            (m, 0.5 * m * r * r)
        };
        let (m1, j1) = body(g.r1);
        let (m2, j2) = body(g.r2);
        SolidBodies {
            m: [m1, m2],
            j: [j1, j2],
        }
    }
}

/// The rule of the tunable mu (`param_table`), for a new value.
pub(crate) fn check_mu(mu: f64) -> Result<(), ParamError> {
    ROTOR_PARAMETERS[param_table::MU].check_value(mu)
}

/// The rule of the tunable d_phi (`param_table`), for a new value.
pub(crate) fn check_d_phi(d: f64) -> Result<(), ParamError> {
    ROTOR_PARAMETERS[param_table::D_PHI].check_value(d)
}

/// Held inputs: `value(t) = value + der (t - t_ref)` (der from
/// fmi2SetRealInputDerivatives, else 0).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Inputs {
    /// Reference drive speed omega1 (before the filter of `model.md` §8).
    pub omega1: f64,
    /// Its time derivative.
    pub omega1_der: f64,
    /// Load torque on gear 2.
    pub t_load: f64,
    /// Its time derivative.
    pub t_load_der: f64,
    /// Time at which `omega1` and `t_load` hold.
    pub t_ref: f64,
}

impl Inputs {
    /// omega1_ref(t).
    #[inline]
    pub fn omega1_at(&self, t: f64) -> f64 {
        self.omega1 + self.omega1_der * (t - self.t_ref)
    }

    /// T_load(t).
    #[inline]
    pub fn t_load_at(&self, t: f64) -> f64 {
        self.t_load + self.t_load_der * (t - self.t_ref)
    }
}
