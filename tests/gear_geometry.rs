//! Test 1 (issue 2): default-pair values of model.md §2 and the validation rules.

mod common;

use common::gear::reference_circles;
use geared_rotor::gear::{GearData, PairGeometry};
use geared_rotor::rotor::Params;

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

#[test]
fn default_pair_matches_model_md_reference_values() {
    let g = PairGeometry::new(&GearData::default()).unwrap();
    // model.md §2 reference values (lengths in mm, angles in deg there).
    let checks = [
        ("r_b1", g.rb1 * 1e3, 26.793197),
        ("r_b2", g.rb2 * 1e3, 40.685966),
        ("beta_b", g.beta_b.to_degrees(), 18.747237),
        ("alpha_wt", g.alpha_wt.to_degrees(), 21.172832),
        ("a_w", g.a_w * 1e3, 72.364089),
        ("p_bt", g.p_bt * 1e3, 6.235060),
        ("eps_alpha", g.eps_alpha, 1.536206),
        ("eps_beta", g.eps_beta, 0.979816),
        ("eps_1", g.eps_1, 0.786183),
        ("eps_2", g.eps_2, 0.750023),
    ];
    let mut worst: f64 = 0.0;
    for (name, got, want) in checks {
        let e = rel(got, want);
        worst = worst.max(e);
        assert!(e <= 1e-6, "{name}: got {got}, want {want}, rel err {e:e}");
    }
    println!("test 1: max relative deviation from model.md §2 values = {worst:.2e}");
    // Internal consistency: p_bt from gear 2, eps_1 + eps_2 = eps_alpha.
    assert!(rel(2.0 * std::f64::consts::PI * g.rb2 / 41.0, g.p_bt) < 1e-14);
    assert!(rel(g.eps_1 + g.eps_2, g.eps_alpha) < 1e-14);
    // Given a_w equal to the derived one reproduces alpha_wt.
    let d = GearData {
        a_w: g.a_w,
        ..GearData::default()
    };
    let g2 = PairGeometry::new(&d).unwrap();
    assert!(rel(g2.alpha_wt, g.alpha_wt) < 1e-12);
}

/// a (centre distance) such that the transverse contact ratio of a pair equals `eps`,
/// computed from the §2 formulas independently of the crate (bisection).
fn a_w_for_eps_alpha(d: &GearData, eps: f64) -> f64 {
    let (_, r1, r2, rb1, rb2) = reference_circles(d);
    let (ra1, ra2) = (
        r1 + d.m_n * (d.ha_coef + d.x1),
        r2 + d.m_n * (d.ha_coef + d.x2),
    );
    let p = 2.0 * std::f64::consts::PI * rb1 / d.z1 as f64;
    let e = |a: f64| {
        let al = ((rb1 + rb2) / a).acos();
        ((ra1 * ra1 - rb1 * rb1).sqrt() + (ra2 * ra2 - rb2 * rb2).sqrt() - a * al.sin()) / p
    };
    let (mut lo, mut hi) = (rb1 + rb2 + 1e-9, ra1 + ra2);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if e(mid) > eps {
            lo = mid
        } else {
            hi = mid
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn each_validation_rule_rejects_and_names_the_parameter() {
    let d0 = GearData::default();
    let deg = |x: f64| x.to_radians();
    let spur = GearData { beta: 0.0, ..d0 };
    let cases: Vec<(&str, GearData)> = vec![
        ("z1", GearData { z1: 4, ..d0 }),
        ("z2", GearData { z2: 3, ..d0 }),
        ("m_n", GearData { m_n: 0.0, ..d0 }),
        ("m_n", GearData { m_n: -1e-3, ..d0 }),
        (
            "m_n",
            GearData {
                m_n: f64::NAN,
                ..d0
            },
        ),
        ("alpha_n", GearData { alpha_n: 0.0, ..d0 }),
        (
            "alpha_n",
            GearData {
                alpha_n: deg(45.0),
                ..d0
            },
        ),
        (
            "beta",
            GearData {
                beta: deg(45.0),
                ..d0
            },
        ),
        (
            "beta",
            GearData {
                beta: deg(-46.0),
                ..d0
            },
        ),
        ("b", GearData { b: 0.0, ..d0 }),
        ("h_aP", GearData { ha_coef: 0.0, ..d0 }),
        (
            "x1",
            GearData {
                x1: f64::INFINITY,
                ..d0
            },
        ),
        ("a_w", GearData { a_w: -1.0, ..d0 }),
        // r_a1 > r_b1 and r_a2 > r_b2
        ("x1", GearData { x1: -2.5, ..d0 }),
        ("x2", GearData { x2: -3.0, ..d0 }),
        // inv alpha_wt > 0
        (
            "x1+x2",
            GearData {
                x1: -1.2,
                x2: -1.2,
                ..d0
            },
        ),
        // a_w > r_b1 + r_b2
        ("a_w", GearData { a_w: 0.060, ..d0 }),
        // sigma_A >= 0 (tip of gear 2 beyond T1)
        (
            "x2",
            GearData {
                x2: 2.0,
                a_w: 72.364089e-3,
                ..d0
            },
        ),
        // sigma_E <= a_w sin alpha_wt (tip of gear 1 beyond T2)
        (
            "x1",
            GearData {
                x1: 4.0,
                a_w: 72.364089e-3,
                ..d0
            },
        ),
        // sigma_A < sigma_E (tips do not overlap on the line of action)
        (
            "h_aP",
            GearData {
                a_w: a_w_for_eps_alpha(&d0, -0.2),
                ..d0
            },
        ),
        // eps_alpha + eps_beta > 1: spur with eps_alpha = 0.9
        (
            "h_aP",
            GearData {
                a_w: a_w_for_eps_alpha(&spur, 0.9),
                ..spur
            },
        ),
    ];
    let mut cases = cases;
    // helical: eps_alpha = 0.5, eps_beta = 0.3 (b from beta_b, model.md §2)
    let bb = (d0.beta.sin() * d0.alpha_n.cos()).asin();
    let at = (d0.alpha_n.tan() / d0.beta.cos()).atan();
    let p = 2.0 * std::f64::consts::PI * (27.0 * d0.m_n / (2.0 * d0.beta.cos())) * at.cos() / 27.0;
    cases.push((
        "b",
        GearData {
            a_w: a_w_for_eps_alpha(&d0, 0.5),
            b: 0.3 * p / bb.tan(),
            ..d0
        },
    ));
    for (want, d) in &cases {
        match PairGeometry::new(d) {
            Ok(g) => panic!(
                "{want}: accepted {d:?} (eps_alpha {}, sigma_A {})",
                g.eps_alpha, g.sigma_a
            ),
            Err(e) => {
                let msg = e.to_string();
                assert_eq!(e.name, *want, "{msg}");
                assert!(msg.contains(want), "{msg}");
                assert!(msg.contains("violates"), "{msg}");
                println!("rejected: {msg}");
            }
        }
    }
    // The borderline sets just inside the rules are accepted.
    for d in [
        GearData {
            z1: 5,
            z2: 5,
            x1: 0.5,
            x2: 0.5,
            ..spur
        },
        GearData {
            beta: deg(-20.0),
            ..d0
        },
        GearData {
            a_w: a_w_for_eps_alpha(&spur, 1.05),
            ..spur
        },
    ] {
        assert!(
            PairGeometry::new(&d).is_ok(),
            "{d:?}: {:?}",
            PairGeometry::new(&d).err()
        );
    }
}

#[test]
fn rotor_parameter_rules_name_the_parameter() {
    let p0 = Params::default();
    assert!(p0.validate().is_ok());
    let mut cases: Vec<(&str, Params)> = Vec::new();
    let mut p = p0;
    p.rotor1.m = 0.0;
    cases.push(("m1", p));
    let mut p = p0;
    p.rotor2.j = -1.0;
    cases.push(("J2", p));
    let mut p = p0;
    p.rotor2.k[2] = -1.0;
    cases.push(("k2.z", p));
    let mut p = p0;
    p.rotor1.d[1] = f64::NAN;
    cases.push(("d1.y", p));
    let mut p = p0;
    p.d_phi = -0.1;
    cases.push(("d_phi", p));
    let mut p = p0;
    p.mu = -0.01;
    cases.push(("mu", p));
    let mut p = p0;
    p.omega1_filter_hz = 0.0;
    cases.push(("omega1_filter_frequency", p));
    let mut p = p0;
    p.psi0 = f64::NAN;
    cases.push(("psi0", p));
    let mut p = p0;
    p.gear.z1 = 2;
    cases.push(("z1", p));
    for (want, p) in cases {
        let e = p.validate().unwrap_err();
        assert_eq!(e.name, want);
        assert!(e.to_string().contains(want));
    }
}
