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
        self.friction.validate()?;
        Ok(g)
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
