//! Friction law 5, Benedict & Kelley (1961) (docs/friction.md): the coefficient against
//! an independent evaluation of the formula in its original imperial units at six
//! operating points, the unit conversions by hand numbers, the bound below v_reg, the
//! segment integrals against a fine reference quadrature, the energy balance of a spur
//! run through the simulation, and the roughness bound of the parameters. The helical
//! energy balance, the Jacobian and the allocation count run for every law, law 5
//! included, in tests/rotor_friction_laws.rs and tests/rotor_friction_alloc.rs.

mod common;

use common::quad::gauss_legendre;
use geared_rotor::gear::friction::benedict_kelley::{
    mu_benedict_kelley, roughness_factor, BkLine, K_SI,
};
use geared_rotor::gear::FrictionLaw;
use geared_rotor::rotor::{GearedRotor, Params};
use geared_rotor::sim::{Simulation, SolverSettings};
use std::f64::consts::PI;

/// The formula as published, in its own units: W lbf/in, nu0 cP, V_s and V_r in/s,
/// S micro-inch (Benedict & Kelley 1961, as restated by He, Cho & Singh 2008).
fn bk_imperial(w_lbf_in: f64, nu0_cp: f64, vs_in_s: f64, vr_in_s: f64, s_uin: f64) -> f64 {
    0.0127
        * (50.0 / (50.0 - s_uin))
        * (3.17e8 * w_lbf_in / (nu0_cp * vs_in_s * vr_in_s * vr_in_s)).log10()
}

/// SI -> the original's units, with the conversion factors written out here (not taken
/// from the crate): 1 lbf = 4.4482216152605 N, 1 in = 0.0254 m, 1 cP = 1e-3 Pa s.
fn bk_from_si(q: f64, eta: f64, vs: f64, vr: f64, ra: f64) -> f64 {
    let lbf_per_in_in_n_per_m = 4.448_221_615_260_5 / 0.0254;
    bk_imperial(
        q / lbf_per_in_in_n_per_m,
        eta / 1e-3,
        vs / 0.0254,
        vr / 0.0254,
        ra / 0.0254e-6,
    )
}

#[test]
fn unit_conversions_by_hand_numbers() {
    // 1 lbf/in = 4.4482216 N / 0.0254 m = 175.1268 N/m; the SI constant
    // 3.17e8 x 0.0254^3 / 175.1268 = 3.17e8 x 1.6387064e-5 / 175.1268 = 29.6625.
    assert!((K_SI - 29.6625).abs() < 5e-5, "K_SI = {K_SI}");
    // Ra = 0.5 um = 19.685 micro-inch: C_R = 50 / 30.315 = 1.64935.
    let c_r = roughness_factor(0.5e-6).unwrap();
    assert!((c_r - 1.649_35).abs() < 5e-6, "C_R = {c_r}");
    assert!(roughness_factor(1.27e-6).is_none());
    // By hand in the original units: W = 1000 lbf/in, nu0 = 30 cP, V_s = 100 in/s,
    // V_r = 1000 in/s, S = 20 micro-inch: C_R = 50/30 = 1.66667, argument
    // 3.17e8 x 1000 / (30 x 100 x 1e6) = 105.667, log10 = 2.023938,
    // mu = 0.0127 x 1.66667 x 2.023938 = 0.0428400.
    assert!((bk_imperial(1000.0, 30.0, 100.0, 1000.0, 20.0) - 0.042_840_0).abs() < 5e-8);
    // The same point in SI through the crate: W = 175126.835 N/m, 0.03 Pa s,
    // V_s = 2.54 m/s, V_r = 25.4 m/s, Ra = 0.508 um.
    let mu = mu_benedict_kelley(175_126.835_246_5, 0.03, 2.54, 25.4, 0.508e-6);
    assert!((mu - 0.042_840_0).abs() < 5e-8, "mu = {mu}");
    // With the entraining speed V_r/2 in place of the sum speed the argument is 4 times
    // larger: mu + 0.0127 C_R log10 4 = 0.04284 + 0.01274 (the convention matters).
    let mu_e = mu_benedict_kelley(175_126.835_246_5, 0.03, 2.54, 12.7, 0.508e-6);
    assert!((mu_e - mu - 0.0127 * (5.0 / 3.0) * 4f64.log10()).abs() < 1e-12);
}

#[test]
fn coefficient_matches_the_published_formula_at_six_operating_points() {
    // Default pair (a = 2 mm x 34 / cos 20 deg ..., L_t from the model's geometry) at
    // 1500 and 3000 rpm, light and heavy load, three positions along the line of action;
    // (q N/m, eta Pa s, Ra m, omega1 rad/s, sigma / L_t, V_s m/s).
    let model = GearedRotor::new(Params::default()).unwrap();
    let g = model.geometry();
    let lt = g.a_w * g.alpha_wt.sin();
    let ratio = g.rb1 / g.rb2;
    let points = [
        (2.0e4, 0.03, 0.5e-6, 157.08, 0.30, 0.8),
        (2.0e5, 0.03, 0.5e-6, 314.16, 0.45, 0.05),
        (5.0e5, 0.01, 0.3e-6, 314.16, 0.60, 2.5),
        (1.0e5, 0.1, 0.8e-6, 157.08, 0.52, 0.2),
        (3.0e5, 0.05, 0.2e-6, 500.0, 0.38, 1.5),
        (8.0e4, 0.02, 1.0e-6, 100.0, 0.70, 0.011),
    ];
    for (i, &(q, eta, ra, omega1, frac, vs)) in points.iter().enumerate() {
        let omega2 = omega1 * ratio;
        let sigma = frac * lt;
        let vr = omega1 * sigma + omega2 * (lt - sigma);
        let e = BkLine::new(q, eta, ra, 0.01, omega1, omega2, lt, 0.3);
        let got = e.mu_at(sigma, vs);
        let want = bk_from_si(q, eta, vs, vr, ra);
        let rel = (got - want).abs() / want;
        println!(
            "point {i}: mu = {got:.12} (independent {want:.12}), V_r = {vr:.4} m/s, rel {rel:.1e}"
        );
        assert!(want > 0.0 && rel < 1e-12, "point {i}: {got} vs {want}");
        assert!((mu_benedict_kelley(q, eta, vs, vr, ra) - want).abs() < 1e-12 * want);
    }
}

#[test]
fn below_v_reg_the_force_falls_off_linearly() {
    let (q, eta, ra, v_reg) = (2e5, 0.03, 0.5e-6, 0.01);
    let e = BkLine::new(q, eta, ra, v_reg, 314.16, 206.9, 0.0264, 0.34);
    let sigma = 0.013;
    let vr = 314.16 * sigma + 206.9 * (0.0264 - sigma);
    let cap = mu_benedict_kelley(q, eta, v_reg, vr, ra);
    for f in [0.0, 0.1, 0.5, 0.999] {
        let mu = e.mu_at(sigma, f * v_reg);
        assert!((mu - f * cap).abs() < 1e-14, "{f}: {mu} vs {}", f * cap);
    }
    // continuous at v_reg, the published formula above it
    assert!((e.mu_at(sigma, v_reg) - cap).abs() < 1e-15);
    let above = e.mu_at(sigma, 3.0 * v_reg);
    assert!((above - mu_benedict_kelley(q, eta, 3.0 * v_reg, vr, ra)).abs() < 1e-15);
    assert!(above < cap);
    // floored at 0 where the argument drops below 1 (light load, fast sliding)
    let light = BkLine::new(1.0, eta, ra, v_reg, 314.16, 206.9, 0.0264, 0.34);
    assert_eq!(light.mu_at(sigma, 5.0), 0.0);
}

/// The six segment integrals (I_x, I_y, K_x, K_y, W, int mu ds) by a composite 20-point
/// Gauss-Legendre rule on 4000 panels, split where |v_T| = v_reg and at x = 0, from the
/// literal formula.
#[allow(clippy::too_many_arguments)]
fn reference(
    q: f64,
    eta: f64,
    ra: f64,
    v_reg: f64,
    om: (f64, f64),
    lt: f64,
    sb: f64,
    x0: f64,
    y: f64,
    kappa: f64,
    len: f64,
    sigma0: f64,
) -> [f64; 6] {
    let (xs, ws) = gauss_legendre(20);
    let mu_loc = |s: f64, r: f64| {
        let sigma = sigma0 - sb * s;
        let vr = (om.0 * sigma + om.1 * (lt - sigma)).abs().max(1e-3);
        let re = r.max(v_reg);
        mu_benedict_kelley(q, eta, re, vr, ra).max(0.0) * r / re
    };
    let mut cuts = vec![0.0, len];
    if kappa != 0.0 {
        let sp = x0 / kappa;
        cuts.push(sp);
        if y.abs() < v_reg {
            let dk = (v_reg * v_reg - y * y).sqrt() / kappa.abs();
            cuts.push(sp - dk);
            cuts.push(sp + dk);
        }
    }
    cuts.retain(|c| (0.0..=len).contains(c));
    cuts.sort_by(f64::total_cmp);
    let mut out = [0.0; 6];
    for w in cuts.windows(2) {
        let n = 4000;
        let h = (w[1] - w[0]) / n as f64;
        for k in 0..n {
            let a = w[0] + k as f64 * h;
            for (xi, wi) in xs.iter().zip(&ws) {
                let s = a + 0.5 * h * (1.0 + xi);
                let x = x0 - kappa * s;
                let r = x.hypot(y);
                if r == 0.0 {
                    continue;
                }
                let mu = mu_loc(s, r);
                let c = 0.5 * h * wi;
                out[0] += c * mu * x / r;
                out[1] += c * mu * y / r;
                out[2] += c * s * mu * x / r;
                out[3] += c * s * mu * y / r;
                out[4] += c * mu * r;
                out[5] += c * mu;
            }
        }
    }
    out
}

#[test]
fn segment_integrals_match_a_fine_reference_quadrature() {
    let (q, eta, ra, v_reg) = (2e5, 0.03, 0.5e-6, 0.01);
    let (om, lt, beta_b) = ((314.16, 206.88), 0.0264, 20f64.to_radians());
    let sb = beta_b.sin();
    let kappa = (om.0 + om.1) * sb;
    let e = BkLine::new(q, eta, ra, v_reg, om.0, om.1, lt, sb);
    let mut worst: f64 = 0.0;
    // (x0, y, len, sigma0): across the pitch point, ending near it, far from it, with
    // axial sliding below and above v_reg.
    let cases = [
        (2.0, 0.0, 0.012, 0.02),
        (2.0, 0.004, 0.012, 0.02),
        (2.0, 0.03, 0.012, 0.02),
        (1.0, 1e-5, 0.0056, 0.016),
        (3.0, 0.0, 0.01, 0.024),
        (-0.5, 0.002, 0.008, 0.01),
        (0.6, 0.2, 0.012, 0.02),
    ];
    for (i, &(x0, y, len, sigma0)) in cases.iter().enumerate() {
        let (li, mu_int) = e.segment_integrals(x0, y, kappa, len, sigma0);
        let r = reference(q, eta, ra, v_reg, om, lt, sb, x0, y, kappa, len, sigma0);
        let got = [li.ix, li.iy, li.kx, li.ky, li.w, mu_int];
        // natural scales: mu ~ 0.1 times len (I), len^2 (K), len max|v_T| (W)
        let vmax = x0.abs().max((x0 - kappa * len).abs()).max(y.abs());
        let sc = [len, len, len * len, len * len, len * vmax, len].map(|s| 0.1 * s);
        for k in 0..6 {
            let err = (got[k] - r[k]).abs() / sc[k];
            worst = worst.max(err);
            assert!(
                err < 1e-7,
                "case {i}, integral {k}: {} vs {} ({err:.1e})",
                got[k],
                r[k]
            );
        }
    }
    println!("law 5 segment integrals: worst error {worst:.2e} of the natural scale");
}

#[test]
fn law5_is_continuous_at_the_reversal_and_rejects_rough_flanks() {
    assert!(!FrictionLaw::BenedictKelley.sharp_reversal());
    assert!(FrictionLaw::BenedictKelley.load_dependent());
    assert_eq!(FrictionLaw::from_code(5), Some(FrictionLaw::BenedictKelley));
    let mut p = Params {
        friction_law: FrictionLaw::BenedictKelley,
        ..Params::default()
    };
    p.friction.ra = 1.3e-6;
    let err = GearedRotor::new(p).unwrap_err().to_string();
    assert!(err.contains("Ra"), "{err}");
    p.friction_law = FrictionLaw::LocalEhl;
    assert!(GearedRotor::new(p).is_ok());
}

/// The spur pair (beta = 0) in the simulation (RADAU5, rtol 1e-8, events at line entry and
/// exit; law 5 is not sharp, so no stick mode and no reversal event) at 100 and 3000 rpm,
/// 50 N m, 20 ms from the start state in doSteps of 1 ms: the energy balance closes to
/// 1e-8 of E_in.
#[test]
fn spur_pair_energy_balance_closes_in_the_simulation() {
    for rpm in [100.0, 3000.0] {
        let d = Params::default();
        let mut p = Params {
            friction_law: FrictionLaw::BenedictKelley,
            ..d
        };
        p.gear.beta = 0.0;
        let omega1 = rpm * PI / 30.0;
        let settings = SolverSettings {
            rtol: 1e-8,
            h_max: 1e-4,
        };
        let mut sim = Simulation::new(p, settings, 0.0, omega1, 50.0).unwrap();
        let o0 = sim.outputs();
        let e0 = o0.e_kin + o0.e_pot;
        let h = 1e-3;
        let mut mu = (f64::INFINITY, 0.0f64);
        for k in 0..20 {
            let r = sim.do_step(k as f64 * h, h).unwrap();
            assert_eq!(r.stick_changes_dropped, 0);
            let m = sim.outputs().mu_eff;
            mu = (mu.0.min(m), mu.1.max(m));
        }
        let o = sim.outputs();
        let res = (o.e_in - o.e_loss - o.e_damp - o.e_load - (o.e_kin + o.e_pot - e0)) / o.e_in;
        println!(
            "law 5 spur, {rpm} rpm: energy residual {res:.2e} of E_in = {:.4} J, E_loss {:.5} J, \
             mu_eff {:.4}..{:.4}",
            o.e_in, o.e_loss, mu.0, mu.1
        );
        assert!(res.abs() <= 1e-8, "{rpm} rpm: {res:e}");
        assert!(o.e_loss > 0.0);
        assert!(mu.0 > 0.01 && mu.1 < 0.2, "{rpm} rpm: mu_eff {mu:?}");
    }
}

/// Near standstill kappa is tiny and the point x = 0 lies far outside the segment
/// (|x0 / kappa| >> len): the integrals still match the reference (no cancellation in
/// the panel ends), and tend to those of kappa = 0.
#[test]
fn segment_integrals_near_standstill() {
    let (q, eta, ra, v_reg) = (2e5, 0.03, 0.5e-6, 0.01);
    let (om, lt, sb) = ((1e-9, 0.66e-9), 0.0264, 20f64.to_radians().sin());
    let e = BkLine::new(q, eta, ra, v_reg, om.0, om.1, lt, sb);
    for (x0, y) in [(0.3, 0.0), (0.003, 0.02), (-0.5, 0.001)] {
        let kappa = (om.0 + om.1) * sb;
        let (li, mu_int) = e.segment_integrals(x0, y, kappa, 0.012, 0.02);
        let r = reference(q, eta, ra, v_reg, om, lt, sb, x0, y, kappa, 0.012, 0.02);
        let (l0, m0) = e.segment_integrals(x0, y, 0.0, 0.012, 0.02);
        let got = [li.ix, li.iy, li.kx, li.ky, li.w, mu_int];
        let flat = [l0.ix, l0.iy, l0.kx, l0.ky, l0.w, m0];
        for k in 0..6 {
            let sc = r[k].abs().max(1e-30);
            assert!(
                (got[k] - r[k]).abs() <= 1e-9 * sc,
                "{x0}, {k}: {} vs {}",
                got[k],
                r[k]
            );
            assert!(
                (flat[k] - r[k]).abs() <= 1e-6 * sc,
                "{x0}, {k}: {} vs {}",
                flat[k],
                r[k]
            );
        }
    }
}
