//! Gear pairs for the randomised gear tests: the default helical pair, its other hand, the
//! same pair as spur gears, a profile-shifted spur pair, a strongly helical pair, and the
//! default pair at a prescribed centre distance.

use geared_rotor::gear::GearData;

/// Spur pair 17/60 with x = +-0.5: its pitch point lies outside the single-contact zone
/// (model.md, loss factor), a case plain Ohlendorf gets wrong.
pub fn spur_17_60() -> GearData {
    GearData {
        z1: 17,
        z2: 60,
        beta: 0.0,
        x1: 0.5,
        x2: -0.5,
        ..GearData::default()
    }
}

/// The gear sets the randomised gear tests loop over.
pub fn gear_sets() -> Vec<GearData> {
    let d0 = GearData::default();
    let deg = |x: f64| x.to_radians();
    vec![
        d0,
        GearData {
            beta: deg(-20.0),
            ..d0
        },
        GearData { beta: 0.0, ..d0 },
        spur_17_60(),
        GearData {
            z1: 19,
            z2: 53,
            m_n: 3e-3,
            beta: deg(30.0),
            x1: 0.3,
            x2: 0.1,
            b: 30e-3,
            ..d0
        },
        GearData {
            z1: 23,
            z2: 31,
            beta: deg(-12.0),
            a_w: 56.0e-3,
            ..d0
        },
    ]
}

/// Transverse pressure angle alpha_t and the pitch and base radii (r1, r2, rb1, rb2) of
/// model.md §2, computed here independently of the crate (for the tests' own references).
pub fn reference_circles(d: &GearData) -> (f64, f64, f64, f64, f64) {
    let cb = d.beta.cos();
    let at = (d.alpha_n.tan() / cb).atan();
    let (r1, r2) = (
        d.z1 as f64 * d.m_n / (2.0 * cb),
        d.z2 as f64 * d.m_n / (2.0 * cb),
    );
    (at, r1, r2, r1 * at.cos(), r2 * at.cos())
}
