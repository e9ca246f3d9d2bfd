//! A refused gear pair names the parameter that repairs it and its limit value
//! (`model.md` §2), one test per derived rule. Each limit in a message is parsed and
//! checked: at the limit the set is accepted, a little on the wrong side refused; for
//! interference, the contact ratio and the working angle the limit is also checked
//! against this file's own formulas of `model.md` §2 (not the crate's).

mod common;

use common::gear::reference_circles;
use geared_rotor::gear::{GearData, PairGeometry};

fn inv(x: f64) -> f64 {
    x.tan() - x
}

/// alpha_wt from inv alpha_wt by bisection (independent of the crate's Newton).
fn inv_inverse(v: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.5f64);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if inv(m) < v {
            lo = m
        } else {
            hi = m
        }
    }
    0.5 * (lo + hi)
}

/// (sigma_A, sigma_E, length of the line of action T1T2) at the nominal position, model.md
/// (2.6)-(2.10), for a derived centre distance.
fn sigmas(d: &GearData) -> (f64, f64, f64) {
    let (at, r1, r2, rb1, rb2) = reference_circles(d);
    let awt = inv_inverse(inv(at) + 2.0 * d.alpha_n.tan() * (d.x1 + d.x2) / (d.z1 + d.z2) as f64);
    let loa = (rb1 + rb2) * awt.tan();
    let ra1 = r1 + d.m_n * (d.ha_coef + d.x1);
    let ra2 = r2 + d.m_n * (d.ha_coef + d.x2);
    let se = (ra1 * ra1 - rb1 * rb1).sqrt();
    let sa = loa - (ra2 * ra2 - rb2 * rb2).sqrt();
    (sa, se, loa)
}

/// The message of a refused set (panics if accepted).
fn refused(d: &GearData) -> (String, String) {
    match PairGeometry::new(d) {
        Ok(_) => panic!("accepted {d:?}"),
        Err(e) => {
            let msg = e.to_string();
            println!("{msg}");
            (e.name.to_string(), msg)
        }
    }
}

/// The limit `name >= v` or `name <= v` stated in a message.
fn stated_limit(msg: &str, name: &str) -> Option<(bool, f64)> {
    for op in [">=", "<="] {
        let key = format!(" {name} {op} ");
        if let Some(i) = msg.find(&key) {
            let rest = &msg[i + key.len()..];
            let num: String = rest
                .chars()
                .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | 'e'))
                .collect();
            return Some((op == ">=", num.parse().unwrap()));
        }
    }
    None
}

fn with(d: &GearData, name: &str, v: f64) -> GearData {
    let mut e = *d;
    match name {
        "z1" => e.z1 = v as i32,
        "z2" => e.z2 = v as i32,
        "x1" => e.x1 = v,
        "x2" => e.x2 = v,
        "h_aP" => e.ha_coef = v,
        "b" => e.b = v,
        _ => panic!("{name}"),
    }
    e
}

/// Every limit stated for these parameters works, and a value slightly on the wrong side
/// does not. Returns the limits found.
fn check_limits(d: &GearData, msg: &str, names: &[&str]) -> Vec<(String, bool, f64)> {
    let mut found = vec![];
    for &n in names {
        if let Some((up, v)) = stated_limit(msg, n) {
            let ok = with(d, n, v);
            assert!(
                PairGeometry::new(&ok).is_ok(),
                "{n} = {v} stated in '{msg}' is refused: {:?}",
                PairGeometry::new(&ok).err()
            );
            let integer = n.starts_with('z');
            let step = if integer {
                1.0
            } else {
                2e-3 * v.abs().max(1e-3)
            };
            let wrong = with(d, n, if up { v - step } else { v + step });
            assert!(
                PairGeometry::new(&wrong).is_err(),
                "{n}: a value just beyond the stated limit {v} is accepted ({msg})"
            );
            found.push((n.to_string(), up, v));
        }
    }
    found
}

#[test]
fn small_pinion_interference_names_z1_with_its_limit() {
    // the case: z1 = 10 with the defaults blamed x2, which cannot repair it
    let d = GearData {
        z1: 10,
        ..GearData::default()
    };
    let (name, msg) = refused(&d);
    assert_eq!(name, "z1", "{msg}");
    assert!(msg.contains("z1 >= 13"), "{msg}");
    assert!(msg.contains("interference"), "{msg}");
    // independent: gear 2's tip passes T1 for z1 = 12, not for z1 = 13
    assert!(sigmas(&with(&d, "z1", 12.0)).0 < 0.0);
    assert!(sigmas(&with(&d, "z1", 13.0)).0 >= 0.0);
    let limits = check_limits(&d, &msg, &["z1", "x1", "x2", "h_aP", "z2"]);
    // x1 and h_aP limits are where sigma_A crosses zero (this file's formulas)
    for (n, _, v) in &limits {
        if n == "x1" || n == "h_aP" {
            let sa = sigmas(&with(&d, n, *v)).0;
            assert!((0.0..2e-6).contains(&sa), "{n} = {v}: sigma_A = {sa}");
        }
    }
    assert!(limits.iter().any(|(n, up, _)| n == "x1" && *up), "{msg}");
    assert!(limits.iter().any(|(n, up, _)| n == "h_aP" && !*up), "{msg}");
    // x2 cannot repair it (the issue: x2 = +-0.5 still fails) and the message says so
    for x2 in [-0.5, 0.5] {
        assert!(PairGeometry::new(&with(&d, "x2", x2)).is_err());
    }
}

#[test]
fn small_wheel_interference_names_z2_with_its_limit() {
    // mirror case: the tip of gear 1 passes T2
    let d = GearData {
        z1: 41,
        z2: 10,
        ..GearData::default()
    };
    let (name, msg) = refused(&d);
    assert!(msg.contains("T2"), "{msg}");
    assert_eq!(name, "z2", "{msg}");
    let limits = check_limits(&d, &msg, &["z2", "x2", "x1", "h_aP", "z1"]);
    let z2 = limits.iter().find(|(n, _, _)| n == "z2").unwrap().2;
    let (_, se, loa) = sigmas(&with(&d, "z2", z2));
    assert!(se <= loa);
    let (_, se, loa) = sigmas(&with(&d, "z2", z2 - 1.0));
    assert!(se > loa, "z2 - 1 should still interfere");
}

#[test]
fn fixed_centre_distance_interference_names_the_shift() {
    // a_w given: z1 and x1 cannot move the tip of gear 2 away from T1, x2 and h_aP can
    let d = GearData {
        x2: 2.0,
        a_w: 72.364089e-3,
        ..GearData::default()
    };
    let (name, msg) = refused(&d);
    assert_eq!(name, "x2", "{msg}");
    let limits = check_limits(&d, &msg, &["x2", "h_aP", "z1", "x1"]);
    assert!(limits.iter().any(|(n, up, _)| n == "x2" && !*up), "{msg}");
    assert!(msg.contains("alone cannot"), "{msg}");
}

#[test]
fn tips_apart_names_the_addendum() {
    // centre distance so large that the tips do not overlap on the line of action
    let d = GearData {
        a_w: 80e-3,
        ..GearData::default()
    };
    let (name, msg) = refused(&d);
    assert_eq!(name, "h_aP", "{msg}");
    assert!(!check_limits(&d, &msg, &["h_aP", "x1", "x2"]).is_empty());
}

#[test]
fn contact_ratio_names_face_width_with_its_limit() {
    // helical pair with too narrow a face: eps_alpha + eps_beta <= 1 needs more b
    let d = GearData {
        a_w: 74.5e-3,
        b: 1e-3,
        ..GearData::default()
    };
    let (name, msg) = refused(&d);
    assert_eq!(name, "b", "{msg}");
    let limits = check_limits(&d, &msg, &["b", "h_aP"]);
    let b = limits.iter().find(|(n, _, _)| n == "b").unwrap().2;
    // independent: eps_alpha + eps_beta = 1 at that width (model.md (2.12), (2.13))
    let g = PairGeometry::new(&with(&d, "b", b)).unwrap();
    let (_, _, _, rb1, _) = reference_circles(&d);
    let p_bt = 2.0 * std::f64::consts::PI * rb1 / d.z1 as f64;
    let bb = (d.beta.sin() * d.alpha_n.cos()).asin();
    let total = g.eps_alpha + b * bb.tan() / p_bt;
    assert!(total > 1.0 && total < 1.0 + 1e-3, "{total}");
}

#[test]
fn spur_contact_ratio_names_the_addendum() {
    let d = GearData {
        beta: 0.0,
        a_w: 71.2e-3,
        ..GearData::default()
    };
    let (name, msg) = refused(&d);
    assert_eq!(name, "h_aP", "{msg}");
    assert!(msg.contains("h_aP >="), "{msg}");
    check_limits(&d, &msg, &["h_aP"]);
}

#[test]
fn negative_shift_sum_gives_the_shift_limits() {
    let d = GearData {
        x1: -1.2,
        x2: -1.2,
        ..GearData::default()
    };
    let (name, msg) = refused(&d);
    assert_eq!(name, "x1+x2", "{msg}");
    let limits = check_limits(&d, &msg, &["x1", "x2"]);
    assert!(!limits.is_empty(), "{msg}");
}

#[test]
fn tip_below_base_circle_names_the_shift() {
    let d = GearData {
        x1: -2.5,
        ..GearData::default()
    };
    let (name, msg) = refused(&d);
    assert_eq!(name, "x1", "{msg}");
    assert!(msg.contains("x1 >="), "{msg}");
    check_limits(&d, &msg, &["x1", "h_aP"]);
}

/// Absurd tooth counts (a fuzzed state blob: z2 = 1 174 405 161 with m_n = 4.8e279 m) are
/// refused with advice as fast as ordinary ones: the tooth-count search stays inside its
/// range (5..=400) instead of trying every count down from the given one (that took 441 s).
/// The advice then names a value in that range, or none.
#[test]
fn an_absurd_tooth_count_is_refused_without_searching_a_billion_counts() {
    for (z1, z2, m_n) in [(27, 1_174_405_161, 4.8e279), (1_000_000, 41, 0.002)] {
        let d = GearData {
            z1,
            z2,
            m_n,
            ..GearData::default()
        };
        // Before the fix this call did not return for minutes (the test then hangs).
        if let Err(e) = PairGeometry::new(&d) {
            let msg = e.to_string();
            assert!(!msg.is_empty());
        }
    }
}
