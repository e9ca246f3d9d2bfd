//! The friction resultants of `src/gear` and what they rest on: the contact lines, the
//! resultants (all three components of forces and moments, including the tilting moments),
//! the normal-load lever arms and the spur loss factor, each against a computation from first
//! principles that does not use the crate's segments, frames or line integrals.

mod common;

use common::gear::{gear_sets, reference_circles};
use common::quad::gauss_legendre;
use common::rng::Rng;
use geared_rotor::gear::{FrictionLaw, GearData, Kinematics, PairGeometry};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// The quantities of model.md §2 recomputed from the engineering data alone.
struct Spec {
    rb1: f64,
    rb2: f64,
    ra1: f64,
    ra2: f64,
    beta_b: f64,
    p_bt: f64,
    a_w: f64,
    inv_alpha_wt: f64,
}

fn involute(x: f64) -> f64 {
    x.tan() - x
}

impl Spec {
    fn new(d: &GearData) -> Spec {
        let (at, r1, r2, rb1, rb2) = reference_circles(d);
        let alpha_wt = if d.a_w == 0.0 {
            // inv alpha_wt = inv alpha_t + 2 tan alpha_n (x1 + x2)/(z1 + z2), by bisection
            let v = involute(at) + 2.0 * d.alpha_n.tan() * (d.x1 + d.x2) / (d.z1 + d.z2) as f64;
            let (mut lo, mut hi) = (1e-6, 1.5);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if involute(mid) < v {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            0.5 * (lo + hi)
        } else {
            ((rb1 + rb2) / d.a_w).acos()
        };
        Spec {
            rb1,
            rb2,
            ra1: r1 + d.m_n * (d.ha_coef + d.x1),
            ra2: r2 + d.m_n * (d.ha_coef + d.x2),
            beta_b: (d.beta.sin() * d.alpha_n.cos()).asin(),
            p_bt: 2.0 * PI * rb1 / d.z1 as f64,
            a_w: (rb1 + rb2) / alpha_wt.cos(),
            inv_alpha_wt: involute(alpha_wt),
        }
    }
}

/// The plane of action of a displaced state (model.md §3.1, §3.2) and the contact lines
/// clipped to the active rectangle (§3.4), each as (start point, length) along `c`.
struct Plane {
    c1: Vector3<f64>,
    c2: Vector3<f64>,
    n: Vector3<f64>,
    c: Vector3<f64>,
    lines: Vec<(Vector3<f64>, f64)>,
}

fn plane(
    s: &Spec,
    d: &GearData,
    u1: Vector3<f64>,
    u2: Vector3<f64>,
    phi1: f64,
    psi0: f64,
) -> Plane {
    let c1 = u1;
    let c2 = Vector3::new(s.a_w, 0.0, 0.0) + u2;
    let dd = c2 - c1;
    let a = dd.x.hypot(dd.y);
    let theta = dd.y.atan2(dd.x);
    let alpha = ((s.rb1 + s.rb2) / a).acos();
    let psi = theta - alpha;
    let e_w = Vector3::new(psi.cos(), psi.sin(), 0.0);
    let t = Vector3::z().cross(&e_w);
    let (sb, cb) = s.beta_b.sin_cos();
    let n = cb * t + sb * Vector3::z();
    let c = -sb * t + cb * Vector3::z();
    // tips of gear 2 and gear 1 on the line of action of the displaced state
    let sigma_a = a * alpha.sin() - (s.ra2 * s.ra2 - s.rb2 * s.rb2).sqrt();
    let sigma_e = (s.ra1 * s.ra1 - s.rb1 * s.rb1).sqrt();
    let (z_lo, z_hi) = (u1.z.max(u2.z) - 0.5 * d.b, u1.z.min(u2.z) + 0.5 * d.b);
    let mut t1 = c1 + s.rb1 * e_w;
    t1.z = 0.0;
    let tau = s.beta_b.tan();
    let base = s.rb1 * (phi1 - theta + alpha + s.inv_alpha_wt) + psi0 * s.p_bt;
    let k0 = ((sigma_a - base) / s.p_bt).floor() as i64;
    let mut lines = Vec::new();
    for k in (k0 - 80)..=(k0 + 80) {
        let sk = base + k as f64 * s.p_bt;
        // sigma_k(Z) = sk - (Z - u1z) tau; Z range where sigma_A <= sigma <= sigma_E
        let (zmin, zmax) = if tau == 0.0 {
            if sk >= sigma_a && sk < sigma_e {
                (z_lo, z_hi)
            } else {
                continue;
            }
        } else {
            let za = u1.z + (sk - sigma_a) / tau;
            let ze = u1.z + (sk - sigma_e) / tau;
            (za.min(ze).max(z_lo), za.max(ze).min(z_hi))
        };
        if zmax > zmin {
            let sig = sk - (zmin - u1.z) * tau;
            lines.push((t1 + sig * t + zmin * Vector3::z(), (zmax - zmin) / cb));
        }
    }
    Plane {
        c1,
        c2,
        n,
        c,
        lines,
    }
}

/// Adaptive 10-point Gauss-Legendre of a vector integrand on [a, b].
struct Quad {
    x: Vec<f64>,
    w: Vec<f64>,
}

impl Quad {
    fn rule<const K: usize>(&self, f: &dyn Fn(f64) -> [f64; K], a: f64, b: f64) -> [f64; K] {
        let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
        let mut s = [0.0; K];
        for (xi, wi) in self.x.iter().zip(&self.w) {
            let v = f(m + h * xi);
            for k in 0..K {
                s[k] += wi * h * v[k];
            }
        }
        s
    }
    fn adapt<const K: usize>(
        &self,
        f: &dyn Fn(f64) -> [f64; K],
        (a, b): (f64, f64),
        whole: [f64; K],
        tol: &[f64; K],
        min_width: f64,
    ) -> [f64; K] {
        let m = 0.5 * (a + b);
        let (l, r) = (self.rule(f, a, m), self.rule(f, m, b));
        let mut s = [0.0; K];
        let mut ok = true;
        for k in 0..K {
            s[k] = l[k] + r[k];
            ok &= (s[k] - whole[k]).abs() <= tol[k];
        }
        if ok || b - a <= min_width {
            return s;
        }
        let (sl, sr) = (
            self.adapt(f, (a, m), l, tol, min_width),
            self.adapt(f, (m, b), r, tol, min_width),
        );
        let mut s = [0.0; K];
        for k in 0..K {
            s[k] = sl[k] + sr[k];
        }
        s
    }
    /// Integral over s in [0, len], split at `cut` if it lies inside; per-component
    /// tolerance 1e-14 of the integral of |f_k| (from a coarse rule).
    fn integrate<const K: usize>(
        &self,
        f: &dyn Fn(f64) -> [f64; K],
        len: f64,
        cut: Option<f64>,
    ) -> [f64; K] {
        let mut pts = vec![0.0, len];
        if let Some(c) = cut {
            if c > 0.0 && c < len {
                pts.insert(1, c);
            }
        }
        let fabs = |s_: f64| f(s_).map(f64::abs);
        let mut tol = [1e-300; K];
        for w in pts.windows(2) {
            let a = self.rule(&fabs, w[0], w[1]);
            for k in 0..K {
                tol[k] += 1e-14 * a[k];
            }
        }
        let mut s = [0.0; K];
        for w in pts.windows(2) {
            let whole = self.rule(f, w[0], w[1]);
            let v = self.adapt(f, (w[0], w[1]), whole, &tol, 1e-12 * len);
            for k in 0..K {
                s[k] += v[k];
            }
        }
        s
    }
}

fn quad() -> Quad {
    let (x, w) = gauss_legendre(10);
    Quad { x, w }
}

/// Friction resultants (model.md §4) by direct quadrature of the Coulomb force density
/// `-p v_T/|v_T|` on gear 2 (`+p v_T/|v_T|` on gear 1) along every contact line of the
/// independently built plane of action, with `v_T` the tangential part of
/// `v2(P) - v1(P)` from the rigid-body velocity field of each gear. No line integral, frame
/// or segment of the crate enters the reference. Compared: all components of F1, F2, M1,
/// M2, the loss P_loss, the contact length and the number of pairs, over the randomised gear
/// sets with displaced centres (so sigma_A, Z_lo, Z_hi and the frame differ from nominal),
/// random centre velocities and speeds. The quadrature is split where the sliding
/// direction changes sign (x = e_w . v_rel = 0, affine in s) and refined adaptively.
#[test]
fn friction_resultants_match_quadrature_of_the_sliding_direction() {
    let q = quad();
    let mut rng = Rng(901);
    let (mut worst_f, mut worst_m, mut worst_w, mut worst_l) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut nseg = 0;
    for d in gear_sets() {
        let g = PairGeometry::new(&d).unwrap();
        let s = Spec::new(&d);
        for i in 0..60 {
            let u1 = Vector3::new(rng.sym(1e-4), rng.sym(1e-4), rng.sym(3e-4));
            let u2 = Vector3::new(rng.sym(1e-4), rng.sym(1e-4), rng.sym(3e-4));
            let omega1 = rng.sym(400.0);
            let omega2 = if i % 2 == 0 {
                omega1 * s.rb1 / s.rb2 * (1.0 + rng.sym(1e-3))
            } else {
                rng.sym(400.0)
            };
            let k = Kinematics {
                v1: Vector3::new(rng.sym(0.3), rng.sym(0.3), rng.sym(0.3)),
                v2: Vector3::new(rng.sym(0.3), rng.sym(0.3), rng.sym(0.3)),
                omega1,
                omega2,
            };
            let phi1 = rng.sym(5.0);
            let psi0 = rng.sym(1.0);
            let (mu, lambda) = (0.02 + 0.1 * rng.next(), rng.sym(5000.0));
            let m = g.mesh(&u1, &u2).unwrap();
            let fr_sums = g.friction_sums(&m, phi1, psi0, &k, FrictionLaw::Coulomb);
            let fr = fr_sums.resultants(mu, lambda);
            // reference
            let pl = plane(&s, &d, u1, u2, phi1, psi0);
            let ell: f64 = pl.lines.iter().map(|l| l.1).sum();
            let el = (fr_sums.contact.length - ell).abs() / ell;
            worst_l = worst_l.max(el);
            assert!(
                el < 1e-12,
                "{d:?}: contact length {} vs {ell}",
                fr_sums.contact.length
            );
            assert_eq!(fr_sums.contact.pairs as usize, pl.lines.len());
            let p = mu * lambda.abs() / ell;
            let ez = Vector3::z();
            let (mut f2, mut m1, mut m2, mut w) =
                (Vector3::zeros(), Vector3::zeros(), Vector3::zeros(), 0.0);
            let mut scale_m: f64 = 0.0;
            for &(p0, len) in &pl.lines {
                nseg += 1;
                let vt = |s_: f64| {
                    let pt = p0 + s_ * pl.c;
                    let v1 = k.v1 + k.omega1 * ez.cross(&(pt - pl.c1));
                    let v2 = k.v2 - k.omega2 * ez.cross(&(pt - pl.c2));
                    let vr = v2 - v1;
                    (pt, vr - pl.n.dot(&vr) * pl.n)
                };
                let f = |s_: f64| {
                    let (pt, v) = vt(s_);
                    let r = v.norm();
                    let u = if r > 0.0 { v / r } else { Vector3::zeros() };
                    let a1 = (pt - pl.c1).cross(&u);
                    let a2 = (pt - pl.c2).cross(&u);
                    [u.x, u.y, u.z, a1.x, a1.y, a1.z, a2.x, a2.y, a2.z, r]
                };
                // sign change of x = (tangential velocity) . (e_w-like direction): x is affine
                // in s, so its zero follows from the two ends (e_w = c x n).
                let ew = pl.c.cross(&pl.n);
                let (x0, x1) = (vt(0.0).1.dot(&ew), vt(len).1.dot(&ew));
                let cut = if x0 * x1 < 0.0 {
                    Some(len * x0 / (x0 - x1))
                } else {
                    None
                };
                let v = q.integrate(&f, len, cut);
                f2 -= p * Vector3::new(v[0], v[1], v[2]);
                m1 += p * Vector3::new(v[3], v[4], v[5]);
                m2 -= p * Vector3::new(v[6], v[7], v[8]);
                w += p * v[9];
                scale_m = scale_m.max((p0 - pl.c2).norm() + len);
            }
            let sf = p * ell;
            let e_f = (fr.f2 - f2).norm().max((fr.f1 + f2).norm()) / sf;
            let e_m = (fr.m1 - m1).norm().max((fr.m2 - m2).norm()) / (sf * scale_m);
            let e_w = (fr.p_loss - w).abs() / w.max(1e-300);
            worst_f = worst_f.max(e_f);
            worst_m = worst_m.max(e_m);
            worst_w = worst_w.max(e_w);
            assert!(e_f < 1e-9, "{d:?} i={i}: F2 {:?} vs {f2:?}", fr.f2);
            assert!(
                e_m < 1e-9,
                "{d:?} i={i}: M1 {:?} vs {m1:?}, M2 {:?} vs {m2:?}",
                fr.m1,
                fr.m2
            );
            assert!(e_w < 1e-9, "{d:?} i={i}: P_loss {} vs {w}", fr.p_loss);
        }
    }
    println!(
        "gear_friction_resultants: {nseg} segments; max rel dev: contact length {worst_l:.2e}, forces {worst_f:.2e}, moments {worst_m:.2e}, P_loss {worst_w:.2e}"
    );
}

/// The lever-arm sums of the normal load (`FrictionSums::arm1/arm2` = sum over the contact
/// lines of `int (P - c_j) ds`, model.md §6 contact moments) against the same integrals
/// computed in closed form from the independently built contact lines:
/// `int_0^L (P0 + s c - c_j) ds = L (P0 - c_j) + L^2/2 c`. All three components, so the
/// tilting (x, y) parts that no other test looks at are covered for both gears.
#[test]
fn normal_load_lever_arms_match_the_contact_lines() {
    let mut rng = Rng(902);
    let mut worst: f64 = 0.0;
    for d in gear_sets() {
        let g = PairGeometry::new(&d).unwrap();
        let s = Spec::new(&d);
        for _ in 0..200 {
            let u1 = Vector3::new(rng.sym(1e-4), rng.sym(1e-4), rng.sym(3e-4));
            let u2 = Vector3::new(rng.sym(1e-4), rng.sym(1e-4), rng.sym(3e-4));
            let phi1 = rng.sym(5.0);
            let psi0 = rng.sym(1.0);
            let k = Kinematics {
                omega1: 300.0,
                omega2: 200.0,
                ..Kinematics::default()
            };
            let m = g.mesh(&u1, &u2).unwrap();
            let sums = g.friction_sums(&m, phi1, psi0, &k, FrictionLaw::Coulomb);
            let pl = plane(&s, &d, u1, u2, phi1, psi0);
            let (mut a1, mut a2, mut ell) = (Vector3::zeros(), Vector3::zeros(), 0.0);
            for &(p0, len) in &pl.lines {
                a1 += len * (p0 - pl.c1) + 0.5 * len * len * pl.c;
                a2 += len * (p0 - pl.c2) + 0.5 * len * len * pl.c;
                ell += len;
            }
            let scale = ell * s.a_w;
            let e = (sums.arm1 - a1).norm().max((sums.arm2 - a2).norm()) / scale;
            worst = worst.max(e);
            assert!(
                e < 1e-12,
                "{d:?}: arm1 {:?} vs {a1:?}, arm2 {:?} vs {a2:?}",
                sums.arm1,
                sums.arm2
            );
        }
    }
    println!("gear_friction_resultants: lever arms max rel dev {worst:.2e}");
}

/// Spur loss factor with the pitch point outside the single-contact zone on the approach
/// side (eps_1 > 1; the existing spur case has eps_2 > 1). Reference: the phase average
/// over one base pitch of the rigid-rotation loss ratio computed from kinematics alone:
/// sliding speed `(omega1 + omega2)|sigma - sigma_C|` on each of the N lines in contact
/// (`sigma_A <= sigma_k < sigma_E`), line load `lambda/(N b)`, input power
/// `lambda r_b1 omega1`, `omega2 = omega1 r_b1/r_b2`, so
/// `P_loss/(mu P_in) = (1/r_b1 + 1/r_b2) (1/N) sum_k |sigma_k - sigma_C|`, averaged exactly
/// (piecewise linear between the phases where a line passes sigma_A, sigma_C, sigma_E;
/// 2-point Gauss per piece). All radii are recomputed from model.md §2.
#[test]
fn spur_loss_factor_with_approach_beyond_single_contact() {
    let d = GearData {
        z1: 60,
        z2: 17,
        beta: 0.0,
        x1: -0.5,
        x2: 0.5,
        ..GearData::default()
    };
    let g = PairGeometry::new(&d).unwrap();
    let s = Spec::new(&d);
    let alpha_wt = ((s.rb1 + s.rb2) / s.a_w).acos();
    let sigma_c = s.rb1 * alpha_wt.tan();
    let sigma_a = s.a_w * alpha_wt.sin() - (s.ra2 * s.ra2 - s.rb2 * s.rb2).sqrt();
    let sigma_e = (s.ra1 * s.ra1 - s.rb1 * s.rb1).sqrt();
    let p = s.p_bt;
    let eps_1 = (sigma_c - sigma_a) / p;
    assert!(eps_1 > 1.0, "test needs eps_1 > 1, got {eps_1}");
    let ratio = |sh: f64| {
        let (mut n, mut sum) = (0, 0.0);
        for k in -100..100 {
            let sk = sh + k as f64 * p;
            if sk >= sigma_a && sk < sigma_e {
                n += 1;
                sum += (sk - sigma_c).abs();
            }
        }
        (1.0 / s.rb1 + 1.0 / s.rb2) * sum / n as f64
    };
    let mut cuts = vec![0.0, p];
    for sig in [sigma_a, sigma_c, sigma_e] {
        cuts.push(sig.rem_euclid(p));
    }
    cuts.sort_by(|a, b| a.total_cmp(b));
    let mut mean = 0.0;
    let gx = 0.5 / 3f64.sqrt();
    for w in cuts.windows(2) {
        let (m, h) = (0.5 * (w[0] + w[1]), w[1] - w[0]);
        mean += 0.5 * h * (ratio(m - gx * h) + ratio(m + gx * h));
    }
    mean /= p;
    let e = ((g.h_v - mean) / mean).abs();
    println!(
        "gear_friction_resultants: spur eps_1 = {eps_1:.4}: H_V {} vs kinematic mean {mean}, rel dev {e:.2e}",
        g.h_v
    );
    assert!(e < 1e-12, "H_V {} vs {mean}", g.h_v);
}
