//! Contact lines (model.md §3.4): segments lie on the tooth lines and inside the active
//! rectangle, end on its boundary, have the stated direction and length; the mean number of
//! pairs in contact is eps_alpha + eps_beta (helical) resp. eps_alpha (spur); both hands give
//! the same contact length at zero displacement (mirror symmetry in Z).

mod common;

use geared_rotor::gear::{GearData, PairGeometry};
use nalgebra::Vector3;

#[test]
fn segments_are_clipped_tooth_lines() {
    let d0 = GearData::default();
    for d in [
        d0,
        GearData {
            beta: -d0.beta,
            ..d0
        },
        GearData { beta: 0.0, ..d0 },
    ] {
        let g = PairGeometry::new(&d).unwrap();
        let tau = g.beta_b.tan();
        for i in 0..500 {
            let s = i as f64;
            let u1 = Vector3::new(
                1e-5 * (0.3 * s).sin(),
                1e-5 * (0.7 * s).cos(),
                2e-4 * (0.11 * s).sin(),
            );
            let u2 = Vector3::new(
                1e-5 * (0.5 * s).cos(),
                1e-5 * (0.2 * s).sin(),
                2e-4 * (0.13 * s).cos(),
            );
            let m = g.mesh(&u1, &u2).unwrap();
            let phi1 = 0.0137 * s - 3.0;
            let psi0 = 0.25;
            // model.md §3.4: sigma_k(Z) = r_b1 (phi1 - theta + alpha + inv alpha_wt) - (Z - u1z) tan beta_b + (k + psi0) p_bt
            let base = g.rb1 * (phi1 - m.theta + m.alpha + g.inv_alpha_wt) + psi0 * g.p_bt;
            let (zlo, zhi) = (u1.z.max(u2.z) - d.b / 2.0, u1.z.min(u2.z) + d.b / 2.0);
            let tol = 1e-12;
            let summary = g.for_each_segment(&m, phi1, psi0, |seg| {
                let z1 = seg.z0 + seg.length * g.beta_b.cos();
                let sig1 = seg.sigma0 - seg.length * g.beta_b.sin();
                for (sg, z) in [(seg.sigma0, seg.z0), (sig1, z1)] {
                    assert!(
                        sg >= m.sigma_a - tol && sg <= m.sigma_e + tol,
                        "sigma {sg} outside"
                    );
                    assert!(z >= zlo - tol && z <= zhi + tol, "Z {z} outside");
                    // on some tooth line: (sigma + (Z - u1z) tau - base) / p_bt is an integer
                    let kk = (sg + (z - u1.z) * tau - base) / g.p_bt;
                    assert!((kk - kk.round()).abs() < 1e-9, "not on a tooth line: {kk}");
                }
                // each end lies on the boundary of the rectangle
                let on_bnd = |sg: f64, z: f64| {
                    (sg - m.sigma_a).abs() < tol
                        || (sg - m.sigma_e).abs() < tol
                        || (z - zlo).abs() < tol
                        || (z - zhi).abs() < tol
                };
                assert!(on_bnd(seg.sigma0, seg.z0) && on_bnd(sig1, z1));
                // P_k0 + L c is the other end
                let p1 = m.point(seg.sigma0, seg.z0) + seg.length * m.c;
                assert!((p1 - m.point(sig1, z1)).norm() < 1e-14);
            });
            assert!(summary.pairs >= 1 && summary.length > 0.0);
        }
    }
}

#[test]
fn mean_pairs_and_both_hands() {
    let d0 = GearData::default();
    for d in [d0, GearData { beta: 0.0, ..d0 }] {
        let g = PairGeometry::new(&d).unwrap();
        let gm = PairGeometry::new(&GearData { beta: -d.beta, ..d }).unwrap();
        let m = g.mesh(&Vector3::zeros(), &Vector3::zeros()).unwrap();
        let mm = gm.mesh(&Vector3::zeros(), &Vector3::zeros()).unwrap();
        let n = 200_000;
        let mut pairs = 0i64;
        for i in 0..n {
            let phi1 = (i as f64 + 0.5) / n as f64 * 2.0 * std::f64::consts::PI / d.z1 as f64;
            let s = g.contact_summary(&m, phi1, 0.0);
            let sm = gm.contact_summary(&mm, phi1, 0.0);
            assert!((s.length - sm.length).abs() < 1e-15, "hands differ");
            assert_eq!(s.pairs, sm.pairs);
            pairs += s.pairs as i64;
        }
        let mean = pairs as f64 / n as f64;
        let want = g.eps_alpha + g.eps_beta;
        println!(
            "beta {:.1} deg: mean pairs {mean:.5} vs eps_alpha + eps_beta {want:.5}",
            d.beta.to_degrees()
        );
        assert!((mean - want).abs() < 1e-4);
    }
}

/// The mesh-phase reduction `reduce(x, p)` (fused multiply-add instead of the exact `fmod`
/// of `rem_euclid`) lands in [0, p) and differs from the exact remainder by no more than a
/// few roundings of x, circularly (a remainder just below p and one just above 0 are the
/// same phase), for x over 20 decades, both signs, and exact multiples of p.
#[test]
fn phase_reduction_matches_the_exact_remainder() {
    use geared_rotor::gear::contact_lines::reduce;
    let g = PairGeometry::new(&GearData::default()).unwrap();
    let mut rng = common::rng::Rng(7);
    let mut worst: f64 = 0.0;
    for p in [g.p_bt, g.phi1_period, 1.0] {
        for i in 0..20_000 {
            let x = match i % 4 {
                0 => rng.sign() * rng.log(-12.0, 8.0),
                1 => (i as f64 - 10_000.0) * p,
                2 => (i as f64) * p * (1.0 + f64::EPSILON * rng.sym(4.0)),
                _ => -rng.log(-300.0, -12.0),
            };
            let r = reduce(x, p);
            assert!((0.0..p).contains(&r), "reduce({x:e}, {p:e}) = {r:e}");
            let exact = x.rem_euclid(p);
            let d = (r - exact).abs();
            let d = d.min(p - d);
            let bound = 4.0 * f64::EPSILON * x.abs().max(p);
            assert!(d <= bound, "x = {x:e}, p = {p:e}: {r:e} vs {exact:e}");
            worst = worst.max(d / (f64::EPSILON * x.abs().max(p)));
        }
    }
    println!("largest difference: {worst:e} roundings of max(|x|, p)");
}
