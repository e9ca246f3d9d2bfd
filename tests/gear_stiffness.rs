//! Mesh stiffness of ISO 6336-1, method B (`gear::stiffness`, `model.md` §2.1), against
//! calculation example 1 of ISO/TR 6336-30:2017 and against values evaluated here by
//! hand, independently of the module: the virtual tooth numbers, the polynomial of q'
//! and the factors are written out again below from the standard's formulas (own
//! trigonometry from the engineering data, not `PairGeometry`'s derived fields).

use geared_rotor::gear::stiffness::{self, MeshStiffness, N_PER_MM_UM};
use geared_rotor::gear::{GearData, PairGeometry};

const DEG: f64 = std::f64::consts::PI / 180.0;

/// Relative difference.
fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// `x` printed with `digits` decimals equals `printed`.
fn prints_as(x: f64, digits: usize, printed: &str) -> bool {
    format!("{x:.digits$}") == printed
}

/// ISO/TR 6336-30:2017, calculation example 1: m_n 8 mm, alpha_n 20 deg, z 17/103,
/// beta 15.8 deg, x 0.145/0, b 100 mm, basic rack D (h_fP* = 1.4), centre distance
/// a = 500 mm.
fn example_1() -> GearData {
    GearData {
        z1: 17,
        z2: 103,
        m_n: 8e-3,
        alpha_n: 20.0 * DEG,
        beta: 15.8 * DEG,
        b: 100e-3,
        x1: 0.145,
        x2: 0.0,
        ha_coef: 1.0,
        a_w: 500e-3,
        h_fp: 1.4,
        c_gamma: 0.0,
        j_bn: 0.0,
    }
}

#[test]
fn iso_tr_6336_30_example_1() {
    let g = PairGeometry::new(&example_1()).expect("example 1 is a valid pair");
    let s = MeshStiffness::iso_6336(&g);
    // The example's printed values: z_n 18.905 / 114.543, c'_th 17.8558, c' 12.3705
    // N/(mm um).
    assert!(prints_as(s.zn1, 3, "18.905"), "z_n1 = {}", s.zn1);
    assert!(prints_as(s.zn2, 3, "114.543"), "z_n2 = {}", s.zn2);
    assert!(
        prints_as(s.c_th / N_PER_MM_UM, 4, "17.8558"),
        "c'_th = {}",
        s.c_th
    );
    assert!(prints_as(s.c_b, 3, "0.900"), "C_B = {}", s.c_b);
    assert!(
        prints_as(s.c_prime / N_PER_MM_UM, 4, "12.3705"),
        "c' = {}",
        s.c_prime
    );
    assert!(s.in_range);

    // c_gamma_alpha: the example prints 17.4648 N/(mm um). With our tip radii
    // r_a = r + m_n (h_aP + x) unrounded at a = 500 mm, eps_alpha = 1.549342 and
    // c_gamma_alpha = 17.4672 (1.4e-4 above). The example's value follows when its
    // tip diameters are taken to 0.01 mm, d_a1 = 159.66 mm and d_a2 = 872.35 mm (our
    // reading of where the difference comes from: these are the diameters the printed
    // 17.4648 implies; we could not check them in the report's text).
    assert!(
        prints_as(g.eps_alpha, 6, "1.549342"),
        "eps_alpha = {}",
        g.eps_alpha
    );
    assert!(
        prints_as(s.c_gamma_alpha / N_PER_MM_UM, 4, "17.4672"),
        "c_gamma_alpha = {}",
        s.c_gamma_alpha
    );
    let (da1, da2) = (159.66e-3, 872.35e-3);
    let rho = |da: f64, rb: f64| ((da / 2.0) * (da / 2.0) - rb * rb).sqrt();
    let eps_rounded = (rho(da1, g.rb1) + rho(da2, g.rb2) - g.a_w * g.alpha_wt.sin()) / g.p_bt;
    let c_gamma_rounded = stiffness::mesh_from_single(s.c_prime, eps_rounded);
    assert!(
        prints_as(c_gamma_rounded / N_PER_MM_UM, 4, "17.4648"),
        "c_gamma_alpha with the example's tip diameters = {c_gamma_rounded}"
    );
    // c_gamma_used is c_gamma_alpha when c_gamma = 0, the parameter otherwise.
    assert_eq!(stiffness::c_gamma_used(&g), s.c_gamma_alpha);
    let set = PairGeometry::new(&GearData {
        c_gamma: 14e9,
        ..example_1()
    })
    .unwrap();
    assert_eq!(stiffness::c_gamma_used(&set), 14e9);
}

/// The ISO 6336-1 evaluation written out again, from the engineering data alone, in
/// the standard's units (N/(mm um)); returns (z_n1, z_n2, c'_th, c', c_gamma_alpha).
fn by_hand(d: &GearData, eps_alpha: f64) -> (f64, f64, f64, f64, f64) {
    let beta_b = (d.beta.sin() * d.alpha_n.cos()).asin();
    let k = beta_b.cos().powi(2) * d.beta.cos();
    let (zn1, zn2) = (f64::from(d.z1) / k, f64::from(d.z2) / k);
    let (x1, x2) = (d.x1, d.x2);
    let q = 0.04723 + 0.15551 / zn1 + 0.25791 / zn2
        - 0.00635 * x1
        - 0.11654 * x1 / zn1
        - 0.00193 * x2
        - 0.24188 * x2 / zn2
        + 0.00529 * x1 * x1
        + 0.00182 * x2 * x2;
    let c_th = 1.0 / q;
    let c_b = (1.0 + 0.5 * (1.2 - d.h_fp)) * (1.0 - 0.02 * (20.0 - d.alpha_n / DEG));
    let c_prime = c_th * 0.8 * 1.0 * c_b * d.beta.cos();
    (zn1, zn2, c_th, c_prime, c_prime * (0.75 * eps_alpha + 0.25))
}

/// Three pairs besides the example: spur, helical, shifted. The module must agree with
/// the hand evaluation above to round-off, and both with the printed numbers (z_n1,
/// z_n2, c'_th, c', c_gamma_alpha in N/(mm um)), which a third evaluation (a few lines
/// of Python with its own eps_alpha from (2.6)-(2.12)) gave when the test was written.
#[test]
fn three_pairs_by_hand() {
    let base = GearData::default();
    let cases = [
        (
            "spur z 20/40, m_n 3 mm",
            GearData {
                z1: 20,
                z2: 40,
                m_n: 3e-3,
                beta: 0.0,
                b: 20e-3,
                ..base
            },
            ["20.000", "40.000", "16.2725", "12.6926", "18.7392"],
        ),
        (
            "helical, the default pair (z 27/41, beta 20 deg)",
            base,
            ["32.043", "48.657", "17.4265", "12.7730", "17.9097"],
        ),
        (
            "shifted spur z 13/60, x 0.5/0.2, alpha_n 25 deg, h_fP 1.4",
            GearData {
                z1: 13,
                z2: 60,
                m_n: 2e-3,
                alpha_n: 25.0 * DEG,
                beta: 0.0,
                b: 15e-3,
                x1: 0.5,
                x2: 0.2,
                h_fp: 1.4,
                ..base
            },
            ["13.000", "60.000", "17.8455", "14.1336", "17.5302"],
        ),
    ];
    for (name, d, printed) in cases {
        let g = PairGeometry::new(&d).unwrap_or_else(|e| panic!("{name}: {e}"));
        let s = MeshStiffness::iso_6336(&g);
        let (zn1, zn2, c_th, c_prime, c_gamma) = by_hand(&d, g.eps_alpha);
        for (what, ours, hand) in [
            ("z_n1", s.zn1, zn1),
            ("z_n2", s.zn2, zn2),
            ("c'_th", s.c_th / N_PER_MM_UM, c_th),
            ("c'", s.c_prime / N_PER_MM_UM, c_prime),
            ("c_gamma_alpha", s.c_gamma_alpha / N_PER_MM_UM, c_gamma),
        ] {
            assert!(
                rel(ours, hand) < 1e-13,
                "{name}: {what} {ours} vs by hand {hand}"
            );
        }
        assert!(prints_as(s.zn1, 3, printed[0]), "{name}: z_n1 {}", s.zn1);
        assert!(prints_as(s.zn2, 3, printed[1]), "{name}: z_n2 {}", s.zn2);
        assert!(prints_as(c_th, 4, printed[2]), "{name}: c'_th {c_th}");
        assert!(prints_as(c_prime, 4, printed[3]), "{name}: c' {c_prime}");
        assert!(
            prints_as(c_gamma, 4, printed[4]),
            "{name}: c_gamma_alpha {c_gamma}"
        );
        assert!(s.in_range, "{name}");
    }
}

#[test]
fn basic_rack_factor_and_range() {
    // C_B = 1 for h_fP* = 1.2 at 20 deg; 0.975 for the ISO 53 rack A (1.25).
    assert!((stiffness::basic_rack_factor(1.2, 20.0 * DEG) - 1.0).abs() < 1e-15);
    assert!((stiffness::basic_rack_factor(1.25, 20.0 * DEG) - 0.975).abs() < 1e-15);
    // 25 deg: the second bracket is 1.1.
    assert!((stiffness::basic_rack_factor(1.2, 25.0 * DEG) - 1.1).abs() < 1e-14);
    assert!(stiffness::polynomial_in_range(0.5, 0.2));
    assert!(!stiffness::polynomial_in_range(0.0, 0.3), "x1 < x2");
    assert!(
        !stiffness::polynomial_in_range(-0.4, -0.4),
        "x1 + x2 < -0.5"
    );
}

#[test]
fn invalid_stiffness_parameters_are_refused_by_name() {
    for (d, name) in [
        (
            GearData {
                h_fp: 0.0,
                ..GearData::default()
            },
            "h_fP",
        ),
        (
            GearData {
                c_gamma: -1.0,
                ..GearData::default()
            },
            "c_gamma",
        ),
    ] {
        let e = PairGeometry::new(&d).expect_err(name);
        assert_eq!(e.name, name);
    }
}
