//! Mean mesh stiffness per unit face width `c_gamma` after ISO 6336-1, method B, for
//! solid steel gears (`model.md` §2.1). Used by the elastic tooth contact of issue 27;
//! the rigid model does not use it (the FMU reports it as `c_gamma_used`).
//!
//! Source: ISO 6336-1 (Calculation of load capacity of spur and helical gears, part 1),
//! clause 9 "tooth stiffness parameters", method B. We know the formulas and the nine
//! coefficients from the standard's method B as it has long been published and from
//! their reproduction of calculation example 1 of ISO/TR 6336-30:2017 (printed digits
//! of z_n, c'_th and c', tests/gear_stiffness.rs); we could not check the text of the
//! 2019 edition itself, so the standard's equation numbers are not quoted, only the
//! clause.
//!
//! Units: the standard states the stiffnesses in N/(mm um) and the flexibility q' in
//! mm um/N. [`flexibility_mm_um_per_n`] keeps the standard's unit; every stiffness this
//! module returns is SI, N/m^2 per unit face width: 1 N/(mm um) = 1e9 N/m^2
//! ([`N_PER_MM_UM`]).
//!
//! Left out here (method B has them or allows them): the load dependence of c' below a
//! line load F_t K_A / b of 100 N/mm (as far as we know the standard scales c' by
//! `(F_t K_A / b / 100)^0.25` there; the elastic contact wants a load-independent
//! stiffness), gear blanks that are not solid (C_R < 1), pinion and wheel cut with
//! different basic racks (the standard averages C_B of both; here both gears share one
//! rack) and materials other than steel on steel.

use super::geometry::PairGeometry;

/// 1 N/(mm um) in N/m^2 (the standard's unit of c' and c_gamma).
pub const N_PER_MM_UM: f64 = 1e9;

/// Coefficients C1..C9 of the theoretical single-tooth flexibility q' (ISO 6336-1,
/// clause 9, method B; the standard's table of the polynomial's constants), in
/// mm um/N, for solid external spur and helical gears of steel. Index k holds C(k+1).
pub const Q_COEFFICIENTS: [f64; 9] = [
    0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182,
];

/// Correction factor C_M = 0.8 (ISO 6336-1, clause 9, method B): brings the theoretical
/// single stiffness of the polynomial to measured values of solid disc gears.
pub const C_M: f64 = 0.8;

/// Gear blank factor C_R = 1 (ISO 6336-1, clause 9, method B) for solid gear blanks.
pub const C_R: f64 = 1.0;

/// Virtual number of teeth of a helical gear, `z_n = z / (cos^2 beta_b cos beta)`
/// (ISO 6336-1 and ISO 21771; dimensionless). `beta` and `beta_b` in rad, any sign.
pub fn virtual_teeth(z: f64, beta: f64, beta_b: f64) -> f64 {
    let cb = beta_b.cos();
    z / (cb * cb * beta.cos())
}

/// Minimum flexibility of a tooth pair, the polynomial of ISO 6336-1 (clause 9, method
/// B) in N^-1 mm um:
///
/// `q' = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2 + C8 x1^2 + C9 x2^2`
///
/// The standard states it for `x1 >= x2` and `-0.5 <= x1 + x2 <= 2.0`
/// ([`polynomial_in_range`]); outside it is extrapolated.
pub fn flexibility_mm_um_per_n(zn1: f64, zn2: f64, x1: f64, x2: f64) -> f64 {
    let c = &Q_COEFFICIENTS;
    c[0] + c[1] / zn1
        + c[2] / zn2
        + c[3] * x1
        + c[4] * x1 / zn1
        + c[5] * x2
        + c[6] * x2 / zn2
        + c[7] * x1 * x1
        + c[8] * x2 * x2
}

/// Whether the shifts lie where ISO 6336-1 states the polynomial of q': `x1 >= x2` and
/// `-0.5 <= x1 + x2 <= 2.0`.
pub fn polynomial_in_range(x1: f64, x2: f64) -> bool {
    x1 >= x2 && (-0.5..=2.0).contains(&(x1 + x2))
}

/// Basic rack factor `C_B = [1 + 0.5 (1.2 - h_fP*)] [1 - 0.02 (20 deg - alpha_n)]`
/// (ISO 6336-1, clause 9, method B; dimensionless), with the dedendum coefficient
/// `h_fP* = h_fP / m_n` of the basic rack and its pressure angle `alpha_n` (rad; the
/// bracket takes it in degrees). 1 for the rack h_fP* = 1.2, alpha_n = 20 deg; 0.975
/// for h_fP* = 1.25. The standard averages the factors of pinion and wheel when they
/// are cut with different racks; here both share one rack. Whether the 2019 edition
/// bounds h_fP* for this formula we could not verify; it is applied as written.
pub fn basic_rack_factor(h_fp: f64, alpha_n: f64) -> f64 {
    (1.0 + 0.5 * (1.2 - h_fp)) * (1.0 - 0.02 * (20.0 - alpha_n.to_degrees()))
}

/// Mean mesh stiffness per unit face width from the single stiffness,
/// `c_gamma_alpha = c' (0.75 eps_alpha + 0.25)` (ISO 6336-1, clause 9, method B; same
/// unit as `c_prime`). As far as we know the standard adds that spur gears with
/// `eps_alpha < 1.2` may have a mesh stiffness up to 10 % lower; we could not verify
/// that note in the 2019 text, and the formula is applied as written for every
/// eps_alpha.
pub fn mesh_from_single(c_prime: f64, eps_alpha: f64) -> f64 {
    c_prime * (0.75 * eps_alpha + 0.25)
}

/// The stiffness quantities of ISO 6336-1, method B, for one pair (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshStiffness {
    /// Virtual number of teeth of gear 1, z_n1.
    pub zn1: f64,
    /// Virtual number of teeth of gear 2, z_n2.
    pub zn2: f64,
    /// Theoretical single stiffness c'_th = 1/q', N/m^2.
    pub c_th: f64,
    /// Basic rack factor C_B.
    pub c_b: f64,
    /// Single stiffness c' = c'_th C_M C_R C_B cos(beta), N/m^2.
    pub c_prime: f64,
    /// Mean mesh stiffness per unit face width c_gamma_alpha = c' (0.75 eps_alpha +
    /// 0.25), N/m^2.
    pub c_gamma_alpha: f64,
    /// Whether x1, x2 lie in the stated range of the polynomial of q'
    /// ([`polynomial_in_range`]).
    pub in_range: bool,
}

impl MeshStiffness {
    /// ISO 6336-1, method B, solid steel gears, for the pair `g` at its nominal centre
    /// distance (eps_alpha of `model.md` (2.12)), with the basic rack's dedendum
    /// coefficient `g.data.h_fp` and pressure angle `g.data.alpha_n`.
    pub fn iso_6336(g: &PairGeometry) -> Self {
        let d = &g.data;
        let zn1 = virtual_teeth(f64::from(d.z1), d.beta, g.beta_b);
        let zn2 = virtual_teeth(f64::from(d.z2), d.beta, g.beta_b);
        let q = flexibility_mm_um_per_n(zn1, zn2, d.x1, d.x2);
        let c_th = N_PER_MM_UM / q;
        let c_b = basic_rack_factor(d.h_fp, d.alpha_n);
        // c' = c'_th C_M C_R C_B cos(beta) (ISO 6336-1, clause 9, method B).
        let c_prime = c_th * C_M * C_R * c_b * d.beta.cos();
        Self {
            zn1,
            zn2,
            c_th,
            c_b,
            c_prime,
            c_gamma_alpha: mesh_from_single(c_prime, g.eps_alpha),
            in_range: polynomial_in_range(d.x1, d.x2),
        }
    }
}

/// The mean mesh stiffness per unit face width the model uses, N/m^2: the parameter
/// `c_gamma` when it is positive, else c_gamma_alpha of ISO 6336-1 ([`MeshStiffness`]).
/// The FMU reports it as the calculated parameter `c_gamma_used`.
pub fn c_gamma_used(g: &PairGeometry) -> f64 {
    if g.data.c_gamma > 0.0 {
        g.data.c_gamma
    } else {
        MeshStiffness::iso_6336(g).c_gamma_alpha
    }
}
