//! Law 2: Coulomb friction with a regularised sliding direction.
//!
//! The unit sliding direction `v_T / |v_T|` of the Coulomb law is replaced by
//! `v_T / sqrt(|v_T|^2 + v_reg^2)` (v_reg (m/s) > 0): the force per unit length on gear 2 is
//! `-mu q v_T / sqrt(|v_T|^2 + v_reg^2)`, a smooth function of the velocities that tends to
//! Coulomb's law as v_reg -> 0 (the usual regularisation for start-up from standstill; it
//! removes the jump of f where the sliding on a spur line reverses at the pitch line).
//!
//! Closed forms: with `R = sqrt(x^2 + y_e^2)`, `y_e = sqrt(y^2 + v_reg^2)`, the five
//! integrals are the Coulomb ones of [`super::line_integrals`] with y replaced by y_e,
//! except for the y-direction and the loss:
//! `I_x = int x/R`, `K_x = int s x/R` (Coulomb's with y_e), `I_y = (y/y_e) I_y(y_e)`,
//! `K_y = (y/y_e) K_y(y_e)`, `W = int r^2/R ds = int R ds - v_reg^2 int ds/R`
//! `= W(y_e) - v_reg^2 I_y(y_e)/y_e`. Where the integrand is smooth (the regime in which
//! [`super::line_integrals`] uses Gauss-Legendre) the loss is integrated directly as
//! `int (x^2 + y^2)/R ds`, which does not cancel when v_reg dominates.

use super::{line_integrals, LineIntegrals, GL_RATIO, GL_W, GL_X};

/// The five integrals of the regularised law for one segment (`x(s) = x0 - kappa s`,
/// constant `y`, `0 <= s <= len`), per unit `mu |lambda| / l`. `v_reg > 0`.
pub fn regularised_integrals(x0: f64, y: f64, kappa: f64, len: f64, v_reg: f64) -> LineIntegrals {
    if !(len > 0.0) {
        return LineIntegrals::default();
    }
    let ye = y.hypot(v_reg);
    let half = 0.5 * kappa.abs() * len;
    let xm = x0 - 0.5 * kappa * len;
    let rm = xm.hypot(ye);
    if half == 0.0 || rm > GL_RATIO * half {
        return gauss_legendre(x0, y, ye, kappa, len);
    }
    let c = line_integrals(x0, ye, kappa, len);
    let ratio = y / ye;
    LineIntegrals {
        ix: c.ix,
        iy: ratio * c.iy,
        kx: c.kx,
        ky: ratio * c.ky,
        w: c.w - v_reg * v_reg * (c.iy / ye),
    }
}

/// 10-point Gauss-Legendre for the smooth regime (R >= y_e > 0 everywhere).
fn gauss_legendre(x0: f64, y: f64, ye: f64, kappa: f64, len: f64) -> LineIntegrals {
    let h = 0.5 * len;
    let (y2, ye2) = (y * y, ye * ye);
    let (mut ix, mut iy, mut kx, mut ky, mut w) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 0..5 {
        for sgn in [-1.0, 1.0] {
            let s = h * (1.0 + sgn * GL_X[i]);
            let x = x0 - kappa * s;
            let x2 = x * x;
            let wi = GL_W[i] / (x2 + ye2).sqrt();
            ix += wi * x;
            iy += wi;
            kx += wi * x * s;
            ky += wi * s;
            w += wi * (x2 + y2);
        }
    }
    LineIntegrals {
        ix: h * ix,
        iy: h * y * iy,
        kx: h * kx,
        ky: h * y * ky,
        w: h * w,
    }
}

/// `int_0^len |v_T| / sqrt(|v_T|^2 + v_reg^2) ds`: the length-weighted local coefficient
/// of the regularised law per unit mu (for the output `mu_eff` only, not in f). 2 x 10
/// Gauss-Legendre points split where x changes sign; relative accuracy ~1e-6 or better
/// where the sliding passes close to zero, which is ample for an output.
pub fn mean_factor(x0: f64, y: f64, kappa: f64, len: f64, v_reg: f64) -> f64 {
    if !(len > 0.0) {
        return 0.0;
    }
    let y2 = y * y;
    let v2 = v_reg * v_reg;
    let piece = |a: f64, b: f64| -> f64 {
        let h = 0.5 * (b - a);
        let mut acc = 0.0;
        for i in 0..5 {
            for sgn in [-1.0, 1.0] {
                let s = a + h * (1.0 + sgn * GL_X[i]);
                let x = x0 - kappa * s;
                let r2 = x * x + y2;
                acc += GL_W[i] * (r2 / (r2 + v2)).sqrt();
            }
        }
        h * acc
    };
    let root = if kappa != 0.0 { x0 / kappa } else { f64::NAN };
    if root > 0.0 && root < len {
        piece(0.0, root) + piece(root, len)
    } else {
        piece(0.0, len)
    }
}
