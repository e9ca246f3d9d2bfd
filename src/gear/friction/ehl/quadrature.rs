//! Quadrature of law 4 along one contact segment (`docs/friction.md`, law 4).
//!
//! Along a segment `x(s) = x0 - kappa s` and `r(s) = sqrt(x^2 + y^2)`; mu(s) behaves like
//! `r^b3` (b3 = 1.036) times a smooth factor. The segment is split at the root of x
//! (`s = x0 / kappa`, the pitch line) and every piece lies on one side of it, at the
//! distances `near <= d <= far` from the root.
//!
//! With delta = |y / kappa| (the axial sliding y in units of the distance along the line):
//!
//! - Root panel, for y = 0 or axial sliding delta < 1e-4 h0 (below), when the piece starts
//!   at the root or closer to it than a tenth of the panel: Gauss-Jacobi for the weight
//!   d^(b3 - 1) on [0, h0] (minus the same on [0, near] when the root lies outside the
//!   piece), h0 such that z = SR P_h log10(nu0) <= 1 on it: the law's double exponential
//!   exp(b5 e^-z) grows fast for Re z < 0, where a panel's ellipse of analyticity reaches
//!   when it starts at z = 0. 8 points where z <= 0.2 on the panel, 10 to z = 0.7, 12 to
//!   z = 1 (12 points reach 1e-12 at z = 1, which covers the whole side of the pitch line
//!   at the default pair; 10 points fail the line test at z = 1, 12 at z = 1.5). With
//!   this weight every integrand is smooth times d^(b3-1) (`mu = d^(b3-1) d g`,
//!   `mu / r = d^(b3-1) g / |kappa|`); for y = 0 `r / d = |kappa|` is constant, so a node
//!   costs two logarithms and two exponentials.
//! - Small axial sliding on the root panel (0 < delta < 1e-4 h0; with near = 0 or
//!   near >= 100 delta): an expansion in delta. Each integrand F(d, r) at
//!   r = |kappa| sqrt(d^2 + delta^2) is integrated as
//!   `int F(d, |kappa| d) + delta^2 int dF/d(delta^2) + inner constants`: the first term
//!   at the y = 0 nodes above; the first-order term (~d^(b3-2), integrable) by the
//!   interpolatory rule for the weight d^(b3-2) at the same nodes, from z and e^-z there
//!   (`d ln mu / d ln r = b3 + (b4 - b5 e^-z) z`); the inner region d ~ delta, where
//!   F ~ K r^p d^m (K = mu / r^b3 at the pitch line), adds `K |kappa|^p delta^(1+p+m)
//!   C(p, m)` with C(p, m) = Gamma((m+1)/2) Gamma(-(p+m+1)/2) / (2 Gamma(-p/2)) (the
//!   Mellin integral of `t^m (1+t^2)^(p/2)` with its expansion at infinity subtracted).
//!   mu/r ~ r^(b3-1) needs more: its first-order term is integrable only without its
//!   part at the pitch line, whose share C(b3-1, 0) carries, less its part beyond h0; and
//!   the y-integral's next inner terms (from the slope of mu along sigma and from z) are
//!   (delta/h0)^2 of it. What is left is ~(delta/h0)^3 (1e-12 at 1e-4, 1e-9 at 1e-3 in a
//!   sweep of one line against adaptive quadrature; the other integrands at round-off
//!   below 3e-5). A node costs what it costs at y = 0, plus a few multiplications.
//!   This covers most pieces of a run, where the bearings and the transmission error give
//!   every line a small axial sliding (delta ~ 3e-6..1e-4 of the far end).
//! - Root panel with larger axial sliding: r has branch points at
//!   d = +-i delta; on [near, min(far, 8 delta)] d = delta sinh u makes the integrands
//!   analytic in the strip |Im u| < pi/2, 16-point Gauss-Legendre in u, 10 points when
//!   the panel spans at most 1 in u (16 points over 2 in u fail: a panel to 16 delta or
//!   beyond; 12 points to 8 delta fail too), fewer where 8 delta is a small fraction of
//!   far (below).
//! - The rest [h0 or 8 delta, far]: Gauss-Legendre panels [a, 4a] from the far end down
//!   (the branch points at 0 and +-i delta <= a stay outside the ellipse rho = 3),
//!   no longer than their distance from the ends of the line of action (R = 0 there);
//!   10 points, 8 where a panel spans at most [a, 2a] (rho >= 5.8). 8 points on [a, 4a]
//!   fail the line test; ratio 5 leaves the pair test at 2.5e-11.
//! - Nodes by share: a panel whose upper end lies at q times the piece's far end holds
//!   a share ~q^2 of the piece's integrals (mu ~ d^b3), so its relative error may be
//!   ~1/q^2 larger. The panels near the far end keep the counts above; deeper ones get
//!   8, 6, 4, 2 (graded) or 10, 8, 6, 4 (sinh panel) nodes (`GRADED_NODES`,
//!   `SINH_NODES`: thresholds from the Gauss error rho^-2n, with a margin): at
//!   delta = 1e-3 far a piece takes 46 nodes instead of 56.
//!
//! Each panel evaluates its nodes together (`EhlLine::exp_ln_mu_batch`): one loop per
//! elementary function, with the vectorised `ln` and `exp` of `batch_math`.
//!
//! Accuracy against adaptive quadrature of the local law (`tests/gear_friction_laws.rs`,
//! 3000 random lines, 3/4 of the first 2000 with axial sliding from 1e-11 to 0.3 m/s and
//! 1000 with run-like axial sliding, delta log-uniform from 1e-6 to 3e-2 of the far end):
//! worst 9.8e-13 (y = 0), 4.7e-12 (y != 0) and 7.1e-12 (run-like) of the natural scale of
//! each integral. No allocation.

use super::{batch_math, EhlLine, XU_B};
use crate::gear::friction::LineIntegrals;

use super::rules::*;

/// Rule of the Gauss-Jacobi panel at the root (10 points need z <= 0.7 and then more
/// graded panels: no fewer nodes).
const ROOT_RULE: Rule<12> = Rule::new(GJ12_X, GJ12_W);
/// Rule of the Gauss-Jacobi panel at the root where z <= Z_ROOT_SHORT on it.
const ROOT_RULE_SHORT: Rule<10> = Rule::new(GJ10_X, GJ10_W);
/// Largest z on a root panel that gets [`ROOT_RULE_SHORT`] (10 points with z up to 1
/// fail the line test).
const Z_ROOT_SHORT: f64 = 0.7;
/// Rule of the Gauss-Jacobi panel at the root where z <= Z_ROOT_TINY on it.
const ROOT_RULE_TINY: Rule<8> = Rule::new(GJ8_X, GJ8_W);
/// Largest z on a root panel that gets [`ROOT_RULE_TINY`] (the limit of the earlier
/// 8-point design).
const Z_ROOT_TINY: f64 = 0.2;
/// Rule of the graded panels.
const PANEL_RULE: Rule<10> = Rule::new(GL10_X, GL10_W);
/// Rule of the graded panels no longer than [a, 2a] (the branch points at 0 and
/// +-i delta <= a outside the ellipse rho = 5.8).
const PANEL_RULE_SHORT: Rule<8> = Rule::new(GL8_X, GL8_W);
/// Rule of the sinh panel (axial sliding).
const SINH_RULE: Rule<16> = Rule::new(GL16_X, GL16_W);
/// Rule of a sinh panel no longer than SINH_U_SHORT in u.
const SINH_RULE_SHORT: Rule<10> = Rule::new(GL10_X, GL10_W);
/// Longest sinh panel (in u) that gets [`SINH_RULE_SHORT`]: the strip |Im u| < pi/2
/// gives rho = 6.4 for it (u = 2 fails the line test, 1.5 passes; 1 keeps a margin).
const SINH_U_SHORT: f64 = 1.0;
/// The Gauss-Legendre rules of the panels near the root, where a panel holds a small
/// share of the piece (see [`share_nodes`]).
const GL6_RULE: Rule<6> = Rule::new(GL6_X, GL6_W);
const GL4_RULE: Rule<4> = Rule::new(GL4_X, GL4_W);
const GL2_RULE: Rule<2> = Rule::new(GL2_X, GL2_W);
/// Nodes of a graded panel [a, 4a] by q = 4a / far, its upper end as a fraction of the
/// piece's far end: the first entry whose q_min < q. Over [0, q far] the integrands hold a
/// share ~q^2 of the piece (mu ~ d^b3 and the x-integrals ~ d^(1+b3); the y-integral
/// ~ delta d with delta < d), so the relative error of such a panel may be ~1/q^2 larger
/// than at the far end. Two nodes fewer multiply a panel's error by rho^4 = 81 (rho = 3),
/// so q_min steps by 9; the first step lies one further factor 9 down, for the smooth
/// factor of mu, which can be larger near the root than at the far end (exp(b5 e^-z) up
/// to e^b5 = 17 where z -> 0). Without that margin the line test fails.
const GRADED_NODES: [(f64, usize); 4] = [
    (1.0 / 9.0, 10),
    (1.0 / 81.0, 8),
    (1.0 / 729.0, 6),
    (1.0 / 6561.0, 4),
];
/// Nodes of the sinh panel [near, 8 delta] by q = 8 delta / far (the same share argument
/// as [`GRADED_NODES`]): its span of asinh 8 = 2.8 in u has rho = 2.64 in the strip
/// |Im u| < pi/2 (two nodes fewer: error x 49); the thresholds keep a factor 10 in q
/// beyond the estimate.
const SINH_NODES: [(f64, usize); 4] = [(1e-2, 16), (1e-3, 10), (1e-4, 8), (1e-5, 6)];

/// The node count of a panel whose upper end lies at q times the piece's far end: that
/// of the first entry of `table` with q_min < q, else `fewest`.
fn share_nodes(table: &[(f64, usize); 4], q: f64, fewest: usize) -> usize {
    for &(q_min, n) in table {
        if q > q_min {
            return n;
        }
    }
    fewest
}

/// Pieces that start closer to the root than this fraction of the root panel get the
/// Gauss-Jacobi panel; farther ones only graded panels (a piece away from the pitch line
/// then needs one panel instead of two Gauss-Jacobi panels).
const NEAR_JACOBI: f64 = 0.1;
/// The sinh panel reaches SINH_SPAN delta.
const SINH_SPAN: f64 = 8.0;
/// Ratio of the graded panels [a, RATIO a].
const RATIO: f64 = 4.0;

/// Axial sliding up to this fraction of the Gauss-Jacobi panel [0, h0] (delta <
/// DELTA_EXPANSION h0) is integrated by the expansion in delta on that panel: the terms
/// it leaves out are ~(delta / h0)^3 of the integrals.
const DELTA_EXPANSION: f64 = 1e-4;
/// Axial sliding below this fraction of the Gauss-Jacobi panel changes its integrals by
/// less than ~30 (delta / dmax)^2 = 3e-15 of their natural scale (the largest term of the
/// expansion, the first-order term of mu): the y = 0 integrals are taken as they are.
/// (The integral of mu / r alone, which enters the forces multiplied by y, is then off by
/// up to ~7e-10 of itself: ~2e-13 in the natural scale.)
const DELTA_NEGLIGIBLE: f64 = 1e-8;
/// A piece that does not start at the root takes the expansion only when it starts at
/// least this many delta from it (the expansion of [0, near] needs delta << near; 1
/// still passes the line tests, 100 keeps a margin).
const NEAR_EXPANSION: f64 = 100.0;
/// `C(p, m) = int_0^inf [t^m (1 + t^2)^(p/2) - t^(p+m) - (p/2) t^(p+m-2)] dt`
/// `= Gamma((m+1)/2) Gamma(-(p+m+1)/2) / (2 Gamma(-p/2))` (the Mellin transform continued
/// analytically; the two subtracted terms are the y = 0 integrand and the first-order
/// term), for mu ~ r^b3: p = b3, m = 0 (checked against a quadrature of the integral).
const C_MU: f64 = -13.748914120037686;
/// C(p, m) for mu x / r ~ d r^(b3 - 1): p = b3 - 1, m = 1.
const C_X: f64 = -0.49114056099057474;
/// `int_0^inf [(1 + t^2)^(p/2) - t^p] dt = Gamma(1/2) Gamma(-(p+1)/2) / (2 Gamma(-p/2))`
/// for mu / r ~ r^(b3 - 1), p = b3 - 1 (only the y = 0 integrand subtracted: the
/// first-order term of mu / r is not integrable at the root).
const C_Y: f64 = 0.05611219783674559;

/// Largest z = SR P_h log10(nu0) on the Gauss-Jacobi panel at the root: the law's
/// double exponential exp(b5 e^-z) grows fast for Re z < 0, where the ellipse of
/// analyticity of a panel starting at z = 0 reaches (1.0 with 12 points; 1.5 fails the
/// line test).
const Z_ROOT: f64 = 1.0;

/// A Gauss-Jacobi panel at the root of x: `sign * int_0^dmax` over the distance d from
/// the root (at s = `root`) along `dir`, with the axial sliding delta = |y / kappa|.
#[derive(Clone, Copy)]
struct RootPanel {
    root: f64,
    dir: f64,
    dmax: f64,
    sign: f64,
    delta: f64,
}

/// Segment data for the quadrature.
struct Line<'a> {
    e: &'a EhlLine,
    x0: f64,
    y: f64,
    kappa: f64,
    sigma0: f64,
}

/// Running sums of one segment's integrals (`iy`, `ky` still without the factor y), shared
/// by the quadratures of laws 4 and 5 (`benedict_kelley`).
#[derive(Default)]
pub(in crate::gear::friction) struct Acc {
    pub ix: f64,
    pub iy: f64,
    pub kx: f64,
    pub ky: f64,
    pub w: f64,
    pub mu: f64,
}

impl Acc {
    /// The integrals of the segment with the factor y applied, and `int mu ds`.
    pub fn finish(&self, y: f64) -> (LineIntegrals, f64) {
        (
            LineIntegrals {
                ix: self.ix,
                iy: y * self.iy,
                kx: self.kx,
                ky: y * self.ky,
                w: self.w,
            },
            self.mu,
        )
    }

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
    acc.finish(y)
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
            self.legendre(acc, a, len, &PANEL_RULE);
            return;
        }
        let dir = if a + b > 2.0 * root { 1.0 } else { -1.0 };
        let delta = (self.y / self.kappa).abs();
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
        // Axial sliding small against h0 (and against near, when the piece does not start
        // at the root): the expansion in delta of the Gauss-Jacobi panel holds.
        let expansion =
            delta < DELTA_EXPANSION * h0 && (near == 0.0 || near >= NEAR_EXPANSION * delta);
        let inner = if expansion {
            if near < NEAR_JACOBI * h0 {
                // z grows about linearly with d
                let z_of = |d: f64| z_far * d / far;
                self.jacobi(acc, root, dir, h0, 1.0, z_of(h0), delta);
                if near > 0.0 {
                    self.jacobi(acc, root, dir, near, -1.0, z_of(near), delta);
                }
                h0
            } else {
                near
            }
        } else {
            // Axial sliding: r = sqrt(kappa^2 d^2 + y^2) has branch points at d = +-i delta.
            let hi = far.min(SINH_SPAN * delta);
            if near < hi {
                self.sinh_panel(acc, root, dir, near, hi, delta, hi / far);
                hi
            } else {
                near
            }
        };
        self.graded(acc, root, dir, inner, far);
    }

    /// `int_lo^far` over the distance d from the root by Gauss-Legendre panels
    /// [a, RATIO a] from the far end down, no longer than their distance from the ends of
    /// the line of action (R = 0).
    fn graded(&self, acc: &mut Acc, root: f64, dir: f64, lo: f64, far: f64) {
        let mut hi = far;
        while hi > lo {
            let mut a = (hi / RATIO).max(lo);
            let room = self.room(root + dir * a, root + dir * hi);
            if hi - a > room {
                a = hi - room.max(1e-3 * far);
            }
            let s0 = if dir > 0.0 { root + a } else { root - hi };
            let mut nodes = share_nodes(&GRADED_NODES, hi / far, 2);
            if hi <= 2.0 * a {
                nodes = nodes.min(8);
            }
            match nodes {
                10 => self.legendre(acc, s0, hi - a, &PANEL_RULE),
                8 => self.legendre(acc, s0, hi - a, &PANEL_RULE_SHORT),
                6 => self.legendre(acc, s0, hi - a, &GL6_RULE),
                4 => self.legendre(acc, s0, hi - a, &GL4_RULE),
                _ => self.legendre(acc, s0, hi - a, &GL2_RULE),
            }
            hi = a;
        }
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

    /// Gauss-Legendre on [a, a + len] (all nodes evaluated together).
    fn legendre<const N: usize>(&self, acc: &mut Acc, a: f64, len: f64, rule: &Rule<N>) {
        let sb = self.e.sin_beta_b;
        let y2 = self.y * self.y;
        let (mut s, mut x, mut r, mut sigma, mut extra) =
            ([0.0; N], [0.0; N], [0.0; N], [0.0; N], [0.0; N]);
        for i in 0..N {
            s[i] = a + len * rule.x[i];
            x[i] = self.x0 - self.kappa * s[i];
            r[i] = (x[i] * x[i] + y2).sqrt();
            sigma[i] = self.sigma0 - sb * s[i];
        }
        for i in 0..N {
            extra[i] = XU_B[2] * batch_math::ln(r[i].max(f64::MIN_POSITIVE));
        }
        let mu = self.e.exp_ln_mu_batch(&sigma, &r, &extra);
        for i in 0..N {
            if r[i] > 0.0 {
                acc.add(s[i], x[i], r[i], len * rule.w[i] * mu[i]);
            }
        }
    }

    /// `sign * int_0^dmax` over the distance d from the root along `dir`, by the
    /// Gauss-Jacobi rule for the weight d^(b3 - 1):
    /// `mu / d^(b3 - 1) = d exp(ln_mu_over_slide + b3 ln(r / d))`, and for y = 0
    /// `r / d = |kappa|` is constant (one logarithm per call instead of per node).
    #[allow(clippy::too_many_arguments)]
    fn jacobi(
        &self,
        acc: &mut Acc,
        root: f64,
        dir: f64,
        dmax: f64,
        sign: f64,
        z_max: f64,
        delta: f64,
    ) {
        let panel = RootPanel {
            root,
            dir,
            dmax,
            sign,
            delta,
        };
        if z_max <= Z_ROOT_TINY {
            self.jacobi_rule(acc, panel, &ROOT_RULE_TINY, &GJ8_W2);
        } else if z_max <= Z_ROOT_SHORT {
            self.jacobi_rule(acc, panel, &ROOT_RULE_SHORT, &GJ10_W2);
        } else {
            self.jacobi_rule(acc, panel, &ROOT_RULE, &GJ12_W2);
        }
    }

    /// [`Line::jacobi`] with the rule given (and `w2`, the weights of the interpolatory
    /// rule for u^(b3 - 2) at its nodes).
    fn jacobi_rule<const N: usize>(
        &self,
        acc: &mut Acc,
        panel: RootPanel,
        rule: &Rule<N>,
        w2: &[f64; N],
    ) {
        let RootPanel {
            root,
            dir,
            dmax,
            sign,
            delta,
        } = panel;
        let b = XU_B;
        let ak = self.kappa.abs();
        let scale = sign * dmax.powf(b[2]);
        let sb = self.e.sin_beta_b;
        let (mut d, mut s, mut x, mut r, mut sigma) =
            ([0.0; N], [0.0; N], [0.0; N], [0.0; N], [0.0; N]);
        for i in 0..N {
            d[i] = dmax * rule.x[i];
            s[i] = root + dir * d[i];
            // x(s) = kappa (root - s), formed without the cancellation of x0 - kappa s
            x[i] = -self.kappa * dir * d[i];
            // r at y = 0: r / d = |kappa| (the axial sliding enters below)
            r[i] = ak * d[i];
            sigma[i] = self.sigma0 - sb * s[i];
        }
        let extra = [b[2] * ak.ln(); N];
        if delta > DELTA_NEGLIGIBLE * dmax {
            let (g, z, ez) = self.e.exp_ln_mu_batch_z(&sigma, &r, &extra);
            for i in 0..N {
                acc.add(s[i], x[i], r[i], scale * rule.w[i] * d[i] * g[i]);
            }
            self.axial_sliding_terms(acc, panel, &d, &s, (&g, &z, &ez), w2);
        } else {
            let g = self.e.exp_ln_mu_batch(&sigma, &r, &extra);
            for i in 0..N {
                acc.add(s[i], x[i], r[i], scale * rule.w[i] * d[i] * g[i]);
            }
        }
    }

    /// The terms of the expansion in delta that the y = 0 integrals at the nodes of a
    /// Gauss-Jacobi panel [0, dmax] leave out (see the module documentation): the
    /// first-order term `delta^2 int d F / d(delta^2)` by the interpolatory rule `w2` for
    /// the weight d^(b3 - 2), and the constants of the inner region d ~ delta,
    /// `K kappa^p delta^(1+p+m) C(p, m)` for the integrands `K r^p d^m` near the root
    /// (those with 1 + p + m >= 3 are below (delta/dmax)^3 of their integral and left out).
    /// `node` = (g = mu / d^b3, z, e^-z) at the nodes d, s.
    #[allow(clippy::type_complexity)]
    fn axial_sliding_terms<const N: usize>(
        &self,
        acc: &mut Acc,
        panel: RootPanel,
        d: &[f64; N],
        s: &[f64; N],
        node: (&[f64; N], &[f64; N], &[f64; N]),
        w2: &[f64; N],
    ) {
        let RootPanel {
            root,
            dir,
            dmax,
            sign,
            delta,
        } = panel;
        let (g, z, ez) = node;
        let b = XU_B;
        let ak = self.kappa.abs();
        // d/d(delta^2) at delta = 0, with dr/d(delta^2) = |kappa| / (2 d) and
        // d ln mu / d ln r = beta = b3 + (b4 - b5 e^-z) z, times d^(2 - b3):
        // mu -> g beta / 2, mu x / r -> -kappa dir g (beta - 1) / (2 |kappa|),
        // d mu / r -> dir g (beta - 1) / (2 |kappa|), mu r -> |kappa| d g (beta + 1) / 2.
        // K = mu / r^b3 at the root (z = 0), g(0) = K |kappa|^b3
        let sigma_root = self.sigma0 - self.e.sin_beta_b * root;
        let (ln_k, slope, z_per_r) = self.e.pitch_expansion(sigma_root);
        let k = ln_k.exp();
        let g0 = k * ak.powf(b[2]);
        let (mut t_mu, mut t_x, mut t_kx, mut t_y, mut t_w) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for i in 0..N {
            let beta = b[2] + (b[3] - b[4] * ez[i]) * z[i];
            let wg = w2[i] * g[i];
            t_mu += wg * beta;
            let c = wg * (beta - 1.0) / ak;
            t_x += c;
            t_kx += c * s[i];
            // mu / r: the first-order term of its part g(0) d^(b3-1) is not integrable
            // (that part is in C_Y); the rest, ~d^(b3-2), is
            t_y += w2[i] * (g[i] * (beta - 1.0) - g0 * (b[2] - 1.0)) / (d[i] * ak);
            t_w += wg * ak * d[i] * (beta + 1.0);
        }
        let first = sign * 0.5 * delta * delta * dmax.powf(b[2] - 1.0);
        let kx_dir = -self.kappa * dir;
        acc.mu += first * t_mu;
        acc.ix += first * kx_dir * t_x;
        acc.kx += first * kx_dir * t_kx;
        acc.iy += first * t_y;
        acc.ky += first * (root * t_y + dir * t_x);
        acc.w += first * t_w;
        // inner region: the integrands K r^p d^m near the root
        let dm = sign * k * (ak * delta).powf(b[2] - 1.0) * delta;
        acc.mu += dm * ak * delta * C_MU;
        acc.ix += dm * delta * kx_dir * C_X;
        acc.kx += root * dm * delta * kx_dir * C_X;
        // mu / r = r^(b3-1) Phi(d, r): the next terms of Phi at the root, d dPhi/dd and
        // r dPhi/dr = Phi (b4 - b5) z, are integrands ~r^(b3-1) d and ~r^b3 with inner
        // constants ~delta^(1+b3) (relative (delta/h)^2: the y-integral needs them)
        let iy_next = -self.e.sin_beta_b * dir * slope * C_X + (b[3] - b[4]) * z_per_r * ak * C_MU;
        // and the part of the non-integrable first-order term beyond dmax, which C_Y
        // (an integral to infinity) includes: (p/2) delta^2 dmax^(p-1) / (1 - p), p = b3 - 1
        let p = b[2] - 1.0;
        let tail = 0.5 * p / (1.0 - p) * (delta / dmax).powf(1.0 - p);
        let iy_inner = C_Y + delta * iy_next - tail;
        acc.iy += dm * iy_inner;
        acc.ky += (root * iy_inner + dir * delta * C_X) * dm;
    }

    /// y != 0: `int_lo^hi` (hi <= SINH_SPAN delta) in d = delta sinh u by Gauss-Legendre in
    /// u (inside the strip |Im u| < pi/2 of analyticity).
    #[allow(clippy::too_many_arguments)]
    fn sinh_panel(&self, acc: &mut Acc, root: f64, dir: f64, lo: f64, hi: f64, delta: f64, q: f64) {
        let (u0, u1) = ((lo / delta).asinh(), (hi / delta).asinh());
        let hu = u1 - u0;
        let mut nodes = share_nodes(&SINH_NODES, q, 4);
        if hu <= SINH_U_SHORT {
            nodes = nodes.min(10);
        }
        match nodes {
            16 => self.sinh_rule(acc, root, dir, u0, hu, delta, &SINH_RULE),
            10 => self.sinh_rule(acc, root, dir, u0, hu, delta, &SINH_RULE_SHORT),
            8 => self.sinh_rule(acc, root, dir, u0, hu, delta, &PANEL_RULE_SHORT),
            6 => self.sinh_rule(acc, root, dir, u0, hu, delta, &GL6_RULE),
            _ => self.sinh_rule(acc, root, dir, u0, hu, delta, &GL4_RULE),
        }
    }

    /// [`Line::sinh_panel`] on [u0, u0 + hu] with the rule given.
    #[allow(clippy::too_many_arguments)]
    fn sinh_rule<const N: usize>(
        &self,
        acc: &mut Acc,
        root: f64,
        dir: f64,
        u0: f64,
        hu: f64,
        delta: f64,
        rule: &Rule<N>,
    ) {
        let ry = self.kappa.abs() * delta;
        let sb = self.e.sin_beta_b;
        let (mut s, mut x, mut r, mut sigma, mut extra, mut jac) =
            ([0.0; N], [0.0; N], [0.0; N], [0.0; N], [0.0; N], [0.0; N]);
        for i in 0..N {
            let eu = batch_math::exp(u0 + hu * rule.x[i]);
            // sinh and cosh from one exponential; sinh's cancellation at small u costs an
            // absolute 1e-16 delta in the node position only.
            let (sh, ch) = (0.5 * (eu - 1.0 / eu), 0.5 * (eu + 1.0 / eu));
            let d = delta * sh;
            s[i] = root + dir * d;
            x[i] = -self.kappa * dir * d;
            r[i] = ry * ch;
            sigma[i] = self.sigma0 - sb * s[i];
            extra[i] = XU_B[2] * batch_math::ln(r[i]);
            jac[i] = hu * rule.w[i] * delta * ch;
        }
        let mu = self.e.exp_ln_mu_batch(&sigma, &r, &extra);
        for i in 0..N {
            acc.add(s[i], x[i], r[i], jac[i] * mu[i]);
        }
    }
}
