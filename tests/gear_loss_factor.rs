//! Test 5 (issue 2): kinematic gear loss factor (model.md §9.7, §9.8). Rigid rotation, no
//! displacement: `P_loss / (mu lambda r_b1 cos(beta_b) omega1)` averaged exactly over one
//! mesh period (piecewise between the kinks, adaptive Gauss-Legendre per piece) equals
//! H_V; the mean contact length is `eps_alpha b / cos(beta_b)`, constant for integer eps_beta.

use geared_rotor::gear::{FrictionLaw, GearData, Kinematics, PairGeometry};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// 20-point Gauss-Legendre nodes/weights by Newton on the Legendre recurrence.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let leg = |z: f64| {
                let (mut p0, mut p1) = (1.0, z);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                (p1, n as f64 * (z * p1 - p0) / (z * z - 1.0))
            };
            let mut z = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (p, dp) = leg(z);
                let dz = p / dp;
                z -= dz;
                if dz.abs() < 1e-16 {
                    break;
                }
            }
            let (_, dp) = leg(z);
            (z, 2.0 / ((1.0 - z * z) * dp * dp))
        })
        .collect()
}

fn rule(gl: &[(f64, f64)], f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
    h * gl.iter().map(|(x, w)| w * f(c + h * x)).sum::<f64>()
}

fn adapt(
    gl: &[(f64, f64)],
    f: &dyn Fn(f64) -> f64,
    a: f64,
    b: f64,
    whole: f64,
    tol: f64,
    depth: u32,
) -> f64 {
    let m = 0.5 * (a + b);
    let (l, r) = (rule(gl, f, a, m), rule(gl, f, m, b));
    if (l + r - whole).abs() <= tol || depth == 0 {
        return l + r;
    }
    adapt(gl, f, a, m, l, tol, depth - 1) + adapt(gl, f, m, b, r, tol, depth - 1)
}

/// Period average of f over phi1 in [0, 2 pi / z1), split at every kink: the phases where a
/// contact line passes a corner (sigma_A, sigma_C, sigma_E) x (Z = -b/2, b/2) of the active
/// rectangle. At zero displacement the line k is sigma = r_b1 phi1 + sigma_C + k p_bt - Z tan(beta_b)
/// (model.md §3.4 with theta = 0, alpha = alpha_wt, psi0 = 0).
fn period_mean(g: &PairGeometry, f: &dyn Fn(f64) -> f64) -> f64 {
    let per = 2.0 * PI / g.data.z1 as f64;
    let mut cuts = vec![0.0, per];
    let tau = g.beta_b.tan();
    for sig in [g.sigma_a, g.sigma_c, g.sigma_e] {
        for z in [-0.5 * g.data.b, 0.5 * g.data.b] {
            let s = sig + z * tau - g.sigma_c;
            let phi = (s / g.rb1).rem_euclid(per);
            cuts.push(phi);
        }
    }
    cuts.sort_by(|a, b| a.total_cmp(b));
    cuts.dedup();
    let gl = gauss_legendre(20);
    let mut total = 0.0;
    for w in cuts.windows(2) {
        if w[1] - w[0] <= 0.0 {
            continue;
        }
        let whole = rule(&gl, f, w[0], w[1]);
        total += adapt(
            &gl,
            f,
            w[0],
            w[1],
            whole,
            1e-15 * whole.abs().max(1e-300),
            30,
        );
    }
    total / per
}

fn check(label: &str, d: GearData, integer_eps_beta: bool) -> (f64, f64, f64) {
    let g = PairGeometry::new(&d).unwrap();
    let m = g.mesh(&Vector3::zeros(), &Vector3::zeros()).unwrap();
    let omega1 = 314.159;
    let k = Kinematics {
        v1: Vector3::zeros(),
        v2: Vector3::zeros(),
        omega1,
        omega2: omega1 * g.rb1 / g.rb2,
    };
    let (mu, lambda) = (0.05, 2700.0);
    let ratio = |phi1: f64| {
        let s = g.friction_sums(&m, phi1, 0.0, &k, FrictionLaw::Coulomb);
        let fr = s.resultants(mu, lambda);
        fr.p_loss / (mu * lambda * g.rb1 * g.cos_beta_b * omega1)
    };
    let length = |phi1: f64| g.contact_summary(&m, phi1, 0.0).length;
    let mean_ratio = period_mean(&g, &ratio);
    let mean_len = period_mean(&g, &length);
    // H_V from the model.md §9.7 formulas, evaluated here from the §2 quantities
    let u = d.z2 as f64 / d.z1 as f64;
    let z1 = d.z1 as f64;
    let (e1, e2) = (g.eps_1, g.eps_2);
    let hv = if d.beta == 0.0 {
        PI * (u + 1.0) / (2.0 * z1 * u)
            * (e1 * e1 + e2 * e2 + (1.0 - e1) * (1.0 - e1).abs() + (1.0 - e2) * (1.0 - e2).abs())
    } else {
        PI * (u + 1.0) / (z1 * u * g.beta_b.cos()) * (e1 * e1 + e2 * e2) / g.eps_alpha
    };
    assert!(
        ((g.h_v - hv) / hv).abs() < 1e-14,
        "{label}: crate H_V {} vs {hv}",
        g.h_v
    );
    let err_hv = ((mean_ratio - hv) / hv).abs();
    let len_ref = g.eps_alpha * d.b / g.beta_b.cos();
    let err_len = ((mean_len - len_ref) / len_ref).abs();
    let mut spread: f64 = 0.0;
    if integer_eps_beta {
        for i in 0..1000 {
            let phi = i as f64 * 2.0 * PI / z1 / 1000.0 + 1e-7;
            spread = spread.max(((length(phi) - len_ref) / len_ref).abs());
        }
    }
    println!(
        "test 5 {label}: eps_alpha {:.6} eps_beta {:.6} eps_1 {:.6} eps_2 {:.6}: <ratio> = {mean_ratio:.12}, H_V = {hv:.12}, rel err {err_hv:.2e}; <l> rel err {err_len:.2e}; l spread {spread:.2e}",
        g.eps_alpha, g.eps_beta, e1, e2
    );
    assert!(
        err_hv <= 1e-9,
        "{label}: <P_loss>/(..) = {mean_ratio} vs H_V = {hv}"
    );
    assert!(err_len <= 1e-9, "{label}: mean l {mean_len} vs {len_ref}");
    if integer_eps_beta {
        assert!(spread <= 1e-12, "{label}: l not constant: {spread:e}");
    }
    (err_hv, err_len, spread)
}

#[test]
fn kinematic_loss_factor_matches_h_v() {
    let d0 = GearData::default();
    let g0 = PairGeometry::new(&d0).unwrap();
    let b1 = g0.p_bt / g0.beta_b.tan();
    check("helical eps_beta = 1", GearData { b: b1, ..d0 }, true);
    check("helical eps_beta = 2", GearData { b: 2.0 * b1, ..d0 }, true);
    check(
        "helical eps_beta = 1, left hand",
        GearData {
            b: b1,
            beta: -d0.beta,
            ..d0
        },
        true,
    );
    check("default as spur", GearData { beta: 0.0, ..d0 }, false);
    let d = GearData {
        z1: 17,
        z2: 60,
        beta: 0.0,
        x1: 0.5,
        x2: -0.5,
        ..d0
    };
    let (_, _, _) = check("spur 17/60, x = +-0.5", d, false);
    // model.md: plain Ohlendorf is off by 0.35 % for this pair (pitch point outside the
    // single-contact zone): make sure the case really exercises that branch.
    let g = PairGeometry::new(&d).unwrap();
    let u = 60.0 / 17.0;
    let ohl =
        PI * (u + 1.0) / (17.0 * u) * (1.0 - g.eps_alpha + g.eps_1 * g.eps_1 + g.eps_2 * g.eps_2);
    let off = ((ohl - g.h_v) / g.h_v).abs();
    println!("  Ohlendorf vs H_V for 17/60: {off:.4e}");
    assert!(off > 3e-3);
}

#[test]
fn default_pair_non_integer_overlap_is_close_to_h_v() {
    // eps_beta = 0.98: l varies, so the helical formula is an approximation (printed, and
    // held to a loose bound only).
    let d = GearData::default();
    let g = PairGeometry::new(&d).unwrap();
    let m = g.mesh(&Vector3::zeros(), &Vector3::zeros()).unwrap();
    let k = Kinematics {
        v1: Vector3::zeros(),
        v2: Vector3::zeros(),
        omega1: 1.0,
        omega2: g.rb1 / g.rb2,
    };
    let ratio = |phi1: f64| {
        let s = g.friction_sums(&m, phi1, 0.0, &k, FrictionLaw::Coulomb);
        s.resultants(1.0, 1.0).p_loss / (g.rb1 * g.cos_beta_b)
    };
    let mean = period_mean(&g, &ratio);
    let e = (mean - g.h_v) / g.h_v;
    println!(
        "default pair (eps_beta = {:.6}): kinematic <ratio> = {mean:.9}, H_V = {:.9}, rel {e:.3e}",
        g.eps_beta, g.h_v
    );
    assert!(e.abs() < 0.02);
}
