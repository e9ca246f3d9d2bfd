//! Parameters and held inputs of the geared rotor (`model.md` §5, §10).

use crate::gear::{FrictionLaw, FrictionParams, GearData, PairGeometry, ParamError};

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
    /// `model.md` §10; omega1_filter_hz = 1000 Hz (`model.md` §8).
    fn default() -> Self {
        Self {
            gear: GearData::default(),
            rotor1: RotorData {
                m: 2.0,
                j: 1.0e-3,
                k: [2e8, 2e8, 1e8],
                d: [1200.0, 1200.0, 850.0],
            },
            rotor2: RotorData {
                m: 4.0,
                j: 5.0e-3,
                k: [2e8, 2e8, 1e8],
                d: [1700.0, 1700.0, 1200.0],
            },
            d_phi: 0.5,
            mu: 0.05,
            psi0: 0.0,
            friction_law: FrictionLaw::Coulomb,
            omega1_filter_hz: 1000.0,
            friction: FrictionParams::default(),
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

fn check_rotor(r: &RotorData, names: [&'static str; 8]) -> Result<(), ParamError> {
    check(r.m > 0.0 && r.m.is_finite(), names[0], r.m, "0 < m < inf")?;
    check(r.j > 0.0 && r.j.is_finite(), names[1], r.j, "0 < J < inf")?;
    for i in 0..3 {
        check(
            r.k[i] >= 0.0 && r.k[i].is_finite(),
            names[2 + i],
            r.k[i],
            "0 <= k < inf",
        )?;
        check(
            r.d[i] >= 0.0 && r.d[i].is_finite(),
            names[5 + i],
            r.d[i],
            "0 <= d < inf",
        )?;
    }
    Ok(())
}

impl Params {
    /// Checks every bound and derives the pair geometry.
    ///
    /// # Errors
    /// The first violated bound, named as in the FMI model description.
    pub fn validate(&self) -> Result<PairGeometry, ParamError> {
        let g = PairGeometry::new(&self.gear)?;
        check_rotor(
            &self.rotor1,
            ["m1", "J1", "k1.x", "k1.y", "k1.z", "d1.x", "d1.y", "d1.z"],
        )?;
        check_rotor(
            &self.rotor2,
            ["m2", "J2", "k2.x", "k2.y", "k2.z", "d2.x", "d2.y", "d2.z"],
        )?;
        check_d_phi(self.d_phi)?;
        check_mu(self.mu)?;
        check(self.psi0.is_finite(), "psi0", self.psi0, "psi0 finite")?;
        check(
            self.omega1_filter_hz > 0.0 && self.omega1_filter_hz.is_finite(),
            "omega1_filter_frequency",
            self.omega1_filter_hz,
            "0 < omega1_filter_frequency < inf",
        )?;
        self.friction.validate()?;
        Ok(g)
    }
}

pub(crate) fn check_mu(mu: f64) -> Result<(), ParamError> {
    check(mu >= 0.0 && mu.is_finite(), "mu", mu, "0 <= mu < inf")
}

pub(crate) fn check_d_phi(d: f64) -> Result<(), ParamError> {
    check(d >= 0.0 && d.is_finite(), "d_phi", d, "0 <= d_phi < inf")
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
