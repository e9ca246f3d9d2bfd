//! Modal damping of the periodic orbit (issue 24 item 1, `docs/damping.md`):
//! - mu = 0: the frequencies and damping ratios from the Floquet multipliers equal the
//!   eigenvalues of the linear system (the rotors on their bearings with the rigid mesh
//!   constraint, linearised at the static equilibrium), written here from the equations of
//!   `model.md` §3, §5 without the model's code, to 1e-6 relative;
//! - time domain: a small perturbation of the orbit along a mode's eigenvector decays with
//!   the predicted damping ratio and frequency (fitted over 50 mesh periods) to 1e-3.

use geared_rotor::periodic::modal::{modal_analysis, ModalOptions, ModalResult};
use geared_rotor::periodic::{PeriodicSystem, Reduced};
use geared_rotor::rotor::Params;
use nalgebra::{Complex, SMatrix, SVector};
use std::f64::consts::PI;

const OMEGA1: f64 = 314.159;

/// Unit normal n of gear 1's flank (`model.md` (3.1)-(3.5)) for the centre displacements
/// u1, u2 (x, y): `t = (-sin(theta - alpha), cos(theta - alpha), 0)`, `n = cos(beta_b) t +
/// sin(beta_b) e_z`.
fn normal(u: &[f64], a_w: f64, r: f64, beta_b: f64) -> [f64; 3] {
    let (dx, dy) = (a_w + u[3] - u[0], u[4] - u[1]);
    let a = dx.hypot(dy);
    let alpha = (r / a).acos();
    let theta = dy.atan2(dx);
    let (s, c) = (theta - alpha).sin_cos();
    [-s * beta_b.cos(), c * beta_b.cos(), beta_b.sin()]
}

/// The eigenvalues (Im >= 0, by increasing imaginary part) of the frictionless rotor
/// linearised at its static equilibrium: `M q'' + D q' + (K - K_g) q = G^T dlambda`,
/// `G q = 0`, q = (u1, u2, phi2), `G = (-n, n, r_b2 cos beta_b)` (3.9), K_g the geometric
/// stiffness `lambda0 dG^T/dq` of the constraint force (the line of action turns with the
/// centres), eliminated on the null space of G: q = N u, N = [I; -G_u / G_phi].
fn linear_eigenvalues(p: &Params, omega1: f64, t_load: f64) -> Vec<Complex<f64>> {
    let g = p.validate().unwrap();
    let (rb1, rb2, bb) = (g.rb1, g.rb2, g.beta_b);
    let r = rb1 + rb2;
    let omega2 = omega1 * rb1 / rb2;
    let lambda0 = (p.d_phi * omega2 + t_load) / (rb2 * bb.cos());
    let k = [
        p.rotor1.k[0],
        p.rotor1.k[1],
        p.rotor1.k[2],
        p.rotor2.k[0],
        p.rotor2.k[1],
        p.rotor2.k[2],
    ];
    let grow = |u: &[f64]| -> [f64; 6] {
        let n = normal(u, g.a_w, r, bb);
        [-n[0], -n[1], -n[2], n[0], n[1], n[2]]
    };
    // Static equilibrium K u = lambda0 G_u(u)^T by fixed-point iteration.
    let mut u = [0.0; 6];
    for _ in 0..100 {
        let gr = grow(&u);
        for i in 0..6 {
            u[i] = lambda0 * gr[i] / k[i];
        }
    }
    // Geometric stiffness by central differences of the analytic normal.
    let mut kg = SMatrix::<f64, 6, 6>::zeros();
    let h = 1e-7;
    for j in 0..6 {
        let (mut up, mut um) = (u, u);
        up[j] += h;
        um[j] -= h;
        let (gp, gm) = (grow(&up), grow(&um));
        for i in 0..6 {
            kg[(i, j)] = lambda0 * (gp[i] - gm[i]) / (2.0 * h);
        }
    }
    let gu = grow(&u);
    let gphi = rb2 * bb.cos();
    let m = [
        p.rotor1.m, p.rotor1.m, p.rotor1.m, p.rotor2.m, p.rotor2.m, p.rotor2.m,
    ];
    let d = [
        p.rotor1.d[0],
        p.rotor1.d[1],
        p.rotor1.d[2],
        p.rotor2.d[0],
        p.rotor2.d[1],
        p.rotor2.d[2],
    ];
    // Reduced matrices N^T X N with N = [I6; c^T], c_i = -G_i / G_phi.
    let c: Vec<f64> = gu.iter().map(|gi| -gi / gphi).collect();
    let mr = SMatrix::<f64, 6, 6>::from_fn(|i, j| {
        (if i == j { m[i] } else { 0.0 }) + p.rotor2.j * c[i] * c[j]
    });
    let dr = SMatrix::<f64, 6, 6>::from_fn(|i, j| {
        (if i == j { d[i] } else { 0.0 }) + p.d_phi * c[i] * c[j]
    });
    let kr = SMatrix::<f64, 6, 6>::from_fn(|i, j| (if i == j { k[i] } else { 0.0 }) - kg[(i, j)]);
    let mi = mr.try_inverse().unwrap();
    let mut a = SMatrix::<f64, 12, 12>::zeros();
    for i in 0..6 {
        a[(i, 6 + i)] = 1.0;
    }
    a.fixed_view_mut::<6, 6>(6, 0).copy_from(&(-mi * kr));
    a.fixed_view_mut::<6, 6>(6, 6).copy_from(&(-mi * dr));
    let mut ev: Vec<Complex<f64>> = a
        .complex_eigenvalues()
        .iter()
        .copied()
        .filter(|s| s.im >= 0.0)
        .collect();
    ev.sort_by(|x, y| x.im.total_cmp(&y.im));
    ev
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn frictionless_modes_are_the_eigenvalues_of_the_linear_system() {
    for (omega1, t_load) in [(OMEGA1, 0.0), (2.0 * OMEGA1, 50.0)] {
        let p = Params {
            mu: 0.0,
            ..Params::default()
        };
        let r = modal_analysis(p, omega1, t_load, &ModalOptions::default()).unwrap();
        let lin = linear_eigenvalues(&p, omega1, t_load);
        assert_eq!(r.modes.len(), 6);
        assert_eq!(lin.len(), 6);
        let mut modes = r.modes.clone();
        modes.sort_by(|x, y| x.freq_hz.total_cmp(&y.freq_hz));
        let mut worst: (f64, f64) = (0.0, 0.0);
        for (m, s) in modes.iter().zip(&lin) {
            let f = s.im / (2.0 * PI);
            let zeta = -s.re / s.norm();
            println!(
                "omega1 {omega1}: {:<32} f {:.6} Hz (linear {f:.6}), zeta {:.8} (linear {zeta:.8}), zeta0 {:.8}, dzeta {:.2e}",
                m.name, m.freq_hz, m.zeta, m.zeta0, m.dzeta()
            );
            worst.0 = worst.0.max(rel(m.freq_hz, f));
            worst.1 = worst.1.max(rel(m.zeta, zeta));
            assert!(
                rel(m.freq_hz, f) <= 1e-6,
                "{}: f {} vs {f}",
                m.name,
                m.freq_hz
            );
            assert!(
                rel(m.zeta, zeta) <= 1e-6,
                "{}: zeta {} vs {zeta}",
                m.name,
                m.zeta
            );
            // The model's own linearisation (the reference of the branches) agrees too,
            // so the friction adds nothing at mu = 0.
            assert!(
                m.dzeta().abs() <= 1e-6 * zeta,
                "{}: dzeta {}",
                m.name,
                m.dzeta()
            );
        }
        println!(
            "omega1 {omega1}: worst relative deviation f {:.2e}, zeta {:.2e}",
            worst.0, worst.1
        );
    }
}

/// The displacement part of the difference of the runs from z + delta v and z - delta v,
/// sampled `n` times per period over `periods` periods, halved (second-order terms cancel).
fn perturbed_response(
    sys: &mut PeriodicSystem,
    z: &Reduced,
    v: &Reduced,
    periods: usize,
    n: usize,
) -> Vec<[f64; 6]> {
    let rtol = 1e-13;
    let (mut zp, mut zm) = (z + v, z - v);
    let mut out = Vec::with_capacity(periods * n);
    let (mut sp, mut sm) = (Vec::new(), Vec::new());
    for _ in 0..periods {
        zp = sys.integrate(&zp, 1, rtol, Some((n, &mut sp))).unwrap().0;
        zm = sys.integrate(&zm, 1, rtol, Some((n, &mut sm))).unwrap().0;
        for (a, b) in sp.iter().zip(&sm) {
            out.push(std::array::from_fn(|i| (a.u[i] - b.u[i]) / 2.0));
        }
    }
    out
}

/// Time-domain check of two modes of the default pair (mu = 0.05): perturb the orbit along
/// the real and the imaginary part of the mode's eigenvector (both signs, so the runs'
/// difference is linear in the perturbation), combine the two responses to the complex
/// response `x(t) = Phi(t) w = exp(s t) p(t)` (p periodic), project it on w and fit
/// `ln|c|` and the unwrapped `arg c` over periods 5..55 with one offset per sampling phase
/// (the periodic factor p). The slopes are Re(s) and Im(s).
#[test]
fn a_perturbation_along_a_mode_decays_with_its_damping_and_frequency() {
    let p = Params::default();
    let r: ModalResult = modal_analysis(p, OMEGA1, 0.0, &ModalOptions::default()).unwrap();
    let mut sys = PeriodicSystem::new(p, OMEGA1, 0.0).unwrap();
    let t = sys.period();
    let n = 64;
    let (k0, k1) = (5usize, 55usize);
    // The torsion mode (lowest, k = 0) and the second (centre 2 z, k = 1: its frequency
    // lies above half the mesh frequency, so the branch matters).
    for idx in [0usize, 1] {
        let m = &r.modes[idx];
        let w = &m.eigvec;
        let scale = 1e-10 / (0..6).map(|i| w[i].norm()).fold(0.0, f64::max);
        let vre = SVector::<f64, 12>::from_fn(|i, _| scale * w[i].re);
        let vim = SVector::<f64, 12>::from_fn(|i, _| scale * w[i].im);
        let dre = perturbed_response(&mut sys, &r.z, &vre, k1, n);
        let dim = perturbed_response(&mut sys, &r.z, &vim, k1, n);
        let ww: f64 = (0..6).map(|i| w[i].norm_sqr()).sum();
        let c: Vec<Complex<f64>> = dre
            .iter()
            .zip(&dim)
            .map(|(a, b)| {
                (0..6).fold(Complex::new(0.0, 0.0), |acc, i| {
                    acc + w[i].conj() * Complex::new(a[i], b[i])
                }) / (ww * scale)
            })
            .collect();
        // Unwrap the phase along the dense samples.
        let mut phase = Vec::with_capacity(c.len());
        let mut prev = c[0].arg();
        let mut acc = prev;
        for ci in &c {
            let a = ci.arg();
            let mut d = a - prev;
            d -= 2.0 * PI * (d / (2.0 * PI)).round();
            acc += d;
            phase.push(acc);
            prev = a;
        }
        // Slope with one intercept per phase j: pooled regression of the per-phase
        // deviations over the periods k0..k1.
        let fit = |y: &dyn Fn(usize) -> f64| -> f64 {
            let mut num = 0.0;
            let mut den = 0.0;
            let kk: Vec<usize> = (k0..k1).collect();
            let kmean = kk.iter().sum::<usize>() as f64 / kk.len() as f64;
            for j in 0..n {
                let ymean = kk.iter().map(|&k| y(k * n + j)).sum::<f64>() / kk.len() as f64;
                for &k in &kk {
                    let dt = (k as f64 - kmean) * t;
                    num += dt * (y(k * n + j) - ymean);
                    den += dt * dt;
                }
            }
            num / den
        };
        let re = fit(&|i| c[i].norm().ln());
        let im = fit(&|i| phase[i]);
        let s = Complex::new(re, im);
        let zeta = -s.re / s.norm();
        let f = s.im / (2.0 * PI);
        println!(
            "mode {} ({}): time run f {f:.4} Hz, zeta {zeta:.6}; Floquet f {:.4} Hz, zeta {:.6}; rel. dev f {:.2e}, zeta {:.2e}",
            idx + 1,
            m.name,
            m.freq_hz,
            m.zeta,
            rel(f, m.freq_hz),
            rel(zeta, m.zeta)
        );
        assert!(rel(f, m.freq_hz) <= 1e-3, "f {f} vs {}", m.freq_hz);
        assert!(rel(zeta, m.zeta) <= 1e-3, "zeta {zeta} vs {}", m.zeta);
    }
}
