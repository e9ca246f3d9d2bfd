//! Quadrature of law 4 along one contact segment (`docs/friction.md`, law 4).
//!
//! Along a segment `x(s) = x0 - kappa s` and `r(s) = sqrt(x^2 + y^2)`; mu(s) behaves like
//! `r^b3` (b3 = 1.036) times a smooth factor. The segment is split at the root of x
//! (`s = x0 / kappa`, the pitch line) and every piece lies on one side of it, at the
//! distances `near <= d <= far` from the root.
//!
//! With delta = |y / kappa| (the axial sliding y in units of the distance along the line):
//!
//! - Root panel, for y = 0 or delta < 3e-6 d_far: 8-point Gauss-Jacobi for the weight
//!   d^(b3 - 1) on [0, h0] (minus the same on [0, near] when the root lies outside the
//!   piece), h0 such that z = SR P_h log10(nu0) <= 0.2 on it: the law's double exponential
//!   exp(b5 e^-z) grows fast for Re z < 0, where a panel's ellipse of analyticity reaches
//!   when it starts at z = 0. With this weight every integrand is smooth times d^(b3-1)
//!   (`mu = d^(b3-1) d g`, `mu / r = d^(b3-1) g / |kappa|`); for y = 0 `r / d = |kappa|`
//!   is constant, so a node costs two logarithms and two exponentials.
//! - Root panel with axial sliding (delta >= 3e-6 d_far): r has branch points at
//!   d = +-i delta; on [near, min(far, delta)] d = delta sinh u makes the integrands
//!   analytic in the strip |Im u| < pi/2, 8-point Gauss-Legendre in u.
//! - The rest [h0 or delta, far]: Gauss-Legendre panels [a, 2a] from the far end down
//!   (the branch points at 0 and +-i delta <= a stay outside the ellipse rho = 5.8),
//!   no longer than their distance from the ends of the line of action (R = 0 there);
//!   below far/64 and far/1024 the ratio grows to 4 and 8 (those panels carry less than
//!   1e-4 and 1e-6 of the integrals); 8 nodes, 6 between far/64 and far/8.
//!
//! Accuracy against adaptive quadrature of the local law (`tests/gear_friction_laws.rs`,
//! 2000 random lines, 3/4 of them with axial sliding from 1e-11 to 0.3 m/s): worst
//! 6e-12 (y = 0) and 1.8e-11 (y != 0) of the natural scale of each integral.
//! No allocation.

use super::{EhlLine, XU_B};
use crate::gear::friction::LineIntegrals;

/// 8-point Gauss-Legendre nodes (positive half) on [-1, 1].
#[allow(clippy::excessive_precision)]
const GL8_X: [f64; 4] = [
    0.183_434_642_495_649_804_939_5,
    0.525_532_409_916_328_985_817_7,
    0.796_666_477_413_626_739_591_6,
    0.960_289_856_497_536_231_683_6,
];
/// Weights matching [`GL8_X`].
#[allow(clippy::excessive_precision)]
const GL8_W: [f64; 4] = [
    0.362_683_783_378_361_982_965_2,
    0.313_706_645_877_887_287_338_0,
    0.222_381_034_453_374_470_544_4,
    0.101_228_536_290_376_259_152_5,
];

/// 6-point Gauss-Legendre nodes (positive half) and weights.
#[allow(clippy::excessive_precision)]
const GL6_X: [f64; 3] = [
    0.238_619_186_083_196_908_630_5,
    0.661_209_386_466_264_513_661_4,
    0.932_469_514_203_152_027_812_3,
];
#[allow(clippy::excessive_precision)]
const GL6_W: [f64; 3] = [
    0.467_913_934_572_691_047_389_9,
    0.360_761_573_048_138_607_569_8,
    0.171_324_492_379_170_345_040_3,
];
/// Nodes of the 8-point Gauss-Jacobi rule for `int_0^1 u^(b3 - 1) g(u) du` (b3 = 1.036077
/// of [`XU_B`]), by Golub-Welsch in 50-digit arithmetic (exact for g of degree <= 15).
/// With the weight d^(b3 - 1) every integrand near the root is smooth times the weight:
/// `mu = d^(b3-1) (d g)`, `mu x/r = d^(b3-1) (+-d g)`, `mu / r = d^(b3-1) g / |kappa|`.
#[allow(clippy::excessive_precision)]
const GJ8_X: [f64; 8] = [
    0.020_687_445_822_119_240_141_99,
    0.103_254_982_426_856_946_188_6,
    0.239_141_156_678_428_782_029_4,
    0.410_104_150_135_896_039_320_1,
    0.593_155_870_866_866_140_329_6,
    0.763_679_882_850_852_315_668_1,
    0.898_747_280_412_280_425_280_6,
    0.980_228_189_841_381_723_009_5,
];
/// Weights matching [`GJ8_X`] (they sum to 1/b3).
#[allow(clippy::excessive_precision)]
const GJ8_W: [f64; 8] = [
    0.044_839_568_320_316_305_354_7,
    0.102_942_847_525_243_169_72,
    0.149_061_551_475_483_256_833_4,
    0.175_353_963_781_179_989_463_1,
    0.177_483_888_904_162_532_651_4,
    0.154_800_995_748_332_969_575_3,
    0.110_329_259_500_848_699_182_5,
    0.050_367_153_701_354_232_693_59,
];

/// Axial sliding slower than this fraction of the sliding at a piece's far end
/// (delta < DELTA_SMALL far) changes its integrals by less than ~(DELTA_SMALL)^2: the
/// Gauss-Jacobi rule of y = 0 is used with the true r (mu / r stays ~ d^(b3 - 1)).
const DELTA_SMALL: f64 = 3e-6;

/// Largest z = SR P_h log10(nu0) on the Gauss-Jacobi panel at the root: the law's
/// double exponential exp(b5 e^-z) grows fast for Re z < 0, where the ellipse of
/// analyticity of a panel starting at z = 0 reaches.
const Z_ROOT: f64 = 0.2;

/// Segment data for the quadrature.
struct Line<'a> {
    e: &'a EhlLine,
    x0: f64,
    y: f64,
    kappa: f64,
    sigma0: f64,
}

#[derive(Default)]
struct Acc {
    ix: f64,
    iy: f64,
    kx: f64,
    ky: f64,
    w: f64,
    mu: f64,
}

impl Acc {
    /// Adds the node s with the quadrature weight `wm = weight * mu(s)`, x = x(s), r = r(s).
    #[inline]
    fn add(&mut self, s: f64, x: f64, r: f64, wm: f64) {
        let f = wm / r;
        self.ix += f * x;
        self.iy += f;
        self.kx += f * x * s;
        self.ky += f * s;
        self.w += wm * r;
        self.mu += wm;
    }
}

/// The five integrals of `mu(s) v_T / |v_T|` (W = `int mu r ds`) and `int mu ds` for one
/// segment of a helical line (kappa != 0 or sin beta_b != 0).
pub(super) fn segment(
    e: &EhlLine,
    x0: f64,
    y: f64,
    kappa: f64,
    len: f64,
    sigma0: f64,
) -> (LineIntegrals, f64) {
    let line = Line {
        e,
        x0,
        y,
        kappa,
        sigma0,
    };
    let mut acc = Acc::default();
    let root = if kappa != 0.0 { x0 / kappa } else { f64::NAN };
    if root > 0.0 && root < len {
        line.piece(&mut acc, 0.0, root, root);
        line.piece(&mut acc, root, len, root);
    } else {
        line.piece(&mut acc, 0.0, len, root);
    }
    (
        LineIntegrals {
            ix: acc.ix,
            iy: y * acc.iy,
            kx: acc.kx,
            ky: y * acc.ky,
            w: acc.w,
        },
        acc.mu,
    )
}

impl Line<'_> {
    /// Integrates over [a, b] (b > a), on one side of the root of x (NaN when kappa = 0).
    fn piece(&self, acc: &mut Acc, a: f64, b: f64, root: f64) {
        let len = b - a;
        if !(len > 0.0) {
            return;
        }
        let (da, db) = ((a - root).abs(), (b - root).abs());
        let (near, far) = if da <= db { (da, db) } else { (db, da) };
        if !far.is_finite() {
            // kappa = 0: x constant along the piece.
            self.legendre(acc, a, len, 8);
            return;
        }
        let dir = if a + b > 2.0 * root { 1.0 } else { -1.0 };
        let delta = (self.y / self.kappa).abs();
        let inner = if delta < DELTA_SMALL * far {
            // Gauss-Jacobi panel [0, h0] with z <= Z_ROOT on it (z ~ d).
            let s_far = root + dir * far;
            let z_far = self.e.z_at(
                self.sigma0 - self.e.sin_beta_b * s_far,
                self.kappa.abs() * far,
            );
            let h0 = if z_far > Z_ROOT {
                far * Z_ROOT / z_far
            } else {
                far
            };
            let h0 = h0.min(self.room(root, root + dir * h0).max(1e-3 * far));
            if near < h0 {
                self.jacobi(acc, root, dir, h0, 1.0);
                if near > 0.0 {
                    self.jacobi(acc, root, dir, near, -1.0);
                }
                h0
            } else {
                near
            }
        } else {
            // Axial sliding: r = sqrt(kappa^2 d^2 + y^2) has branch points at d = +-i delta.
            let hi = far.min(delta);
            if near < hi {
                self.sinh_panel(acc, root, dir, near, hi, delta);
                hi
            } else {
                near
            }
        };
        self.graded(acc, root, dir, inner, far);
    }

    /// `int_lo^far` over the distance d from the root by Gauss-Legendre panels [a, 2a]
    /// from the far end down (the branch points at d = 0 and d = +-i delta <= a are then
    /// outside the ellipse rho = 3 + sqrt(8)); panels far below the far end carry little
    /// of the integrals (~ (a / far)^(1 + b3)) and get fewer nodes.
    fn graded(&self, acc: &mut Acc, root: f64, dir: f64, lo: f64, far: f64) {
        let mut hi = far;
        while hi > lo {
            // ratio 2 (rho = 5.8) near the far end, 4 (rho = 3) below far/64, 8 (rho = 2.1)
            // below far/1024, where the panels carry < 1e-4 and < 1e-6 of the integrals
            let ratio = if hi > far / 64.0 {
                0.5
            } else if hi > far / 1024.0 {
                0.25
            } else {
                0.125
            };
            let mut a = (ratio * hi).max(lo);
            // and no longer than their distance from the ends of the line of action (R = 0)
            let room = self.room(root + dir * a, root + dir * hi);
            if hi - a > room {
                a = hi - room.max(1e-3 * far);
            }
            let n = if a >= 0.125 * far || hi <= far / 64.0 {
                8
            } else {
                6
            };
            let s0 = if dir > 0.0 { root + a } else { root - hi };
            self.legendre(acc, s0, hi - a, n);
            hi = a;
        }
    }

    /// The node s with plain quadrature weight wq.
    #[inline]
    fn node(&self, acc: &mut Acc, s: f64, wq: f64) {
        let x = self.x0 - self.kappa * s;
        let r = (x * x + self.y * self.y).sqrt();
        if !(r > 0.0) {
            return;
        }
        let sigma = self.sigma0 - self.e.sin_beta_b * s;
        let mu = (self.e.ln_mu_over_slide(sigma, r) + XU_B[2] * r.ln()).exp();
        acc.add(s, x, r, wq * mu);
    }

    /// Distance in s of the stretch between s1 and s2 from the ends of the line of action
    /// (sigma = 0 or L_t, where R = 0 and the law is singular).
    fn room(&self, s1: f64, s2: f64) -> f64 {
        let sb = self.e.sin_beta_b;
        if sb == 0.0 {
            return f64::INFINITY;
        }
        let (g1, g2) = (self.sigma0 - sb * s1, self.sigma0 - sb * s2);
        g1.min(g2).min(self.e.lt - g1.max(g2)).max(0.0) / sb.abs()
    }

    /// n-point Gauss-Legendre (n = 6 or 8) on [a, a + len].
    fn legendre(&self, acc: &mut Acc, a: f64, len: f64, n: usize) {
        let (x, w): (&[f64], &[f64]) = match n {
            6 => (&GL6_X, &GL6_W),
            _ => (&GL8_X, &GL8_W),
        };
        let h = 0.5 * len;
        for i in 0..x.len() {
            for sgn in [-1.0, 1.0] {
                self.node(acc, a + h * (1.0 + sgn * x[i]), h * w[i]);
            }
        }
    }

    /// `sign * int_0^dmax` over the distance d from the root along `dir`, by the 8-point
    /// Gauss-Jacobi rule for the weight d^(b3 - 1):
    /// `mu / d^(b3 - 1) = d exp(ln_mu_over_slide + b3 ln(r / d))`, and for y = 0
    /// `r / d = |kappa|` is constant (one logarithm per call instead of per node).
    fn jacobi(&self, acc: &mut Acc, root: f64, dir: f64, dmax: f64, sign: f64) {
        let ak = self.kappa.abs();
        let scale = sign * dmax.powf(XU_B[2]);
        let c0 = XU_B[2] * ak.ln();
        let sb = self.e.sin_beta_b;
        let y2 = self.y * self.y;
        for i in 0..8 {
            let d = dmax * GJ8_X[i];
            let s = root + dir * d;
            // x(s) = kappa (root - s), formed without the cancellation of x0 - kappa s
            let x = -self.kappa * dir * d;
            let (r, c) = if y2 == 0.0 {
                (ak * d, c0)
            } else {
                let r = (x * x + y2).sqrt();
                (r, XU_B[2] * (r / d).ln())
            };
            let g = (self.e.ln_mu_over_slide(self.sigma0 - sb * s, r) + c).exp();
            acc.add(s, x, r, scale * GJ8_W[i] * d * g);
        }
    }

    /// y != 0: `int_lo^hi` (hi <= delta) in d = delta sinh u by 8-point Gauss-Legendre in
    /// u (u <= asinh 1 = 0.88, inside the strip |Im u| < pi/2 of analyticity).
    fn sinh_panel(&self, acc: &mut Acc, root: f64, dir: f64, lo: f64, hi: f64, delta: f64) {
        let (u0, u1) = ((lo / delta).asinh(), (hi / delta).asinh());
        let (um, hu) = (0.5 * (u0 + u1), 0.5 * (u1 - u0));
        let ry = self.kappa.abs() * delta;
        let sb = self.e.sin_beta_b;
        for i in 0..4 {
            for sgn in [-1.0, 1.0] {
                let u = um + sgn * hu * GL8_X[i];
                let (sh, ch) = (u.sinh(), u.cosh());
                let d = delta * sh;
                let s = root + dir * d;
                let x = -self.kappa * dir * d;
                let r = ry * ch;
                let mu =
                    (self.e.ln_mu_over_slide(self.sigma0 - sb * s, r) + XU_B[2] * r.ln()).exp();
                acc.add(s, x, r, hu * GL8_W[i] * delta * ch * mu);
            }
        }
    }
}
