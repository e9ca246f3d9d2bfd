//! Periodic steady state (issue 5, `model.md` §9.9, §9.10, §11): shooting against a long
//! time integration, Floquet stability, convergence of the harmonic approach to the
//! shooting orbit, and the frictionless case where both must return the static
//! equilibrium.

use geared_rotor::periodic::harmonic::{harmonic_balance, HarmonicOptions};
use geared_rotor::periodic::shooting::{shoot, ShootingOptions};
use geared_rotor::periodic::{max_rel_deviation, OrbitPoint, PeriodicSystem, NZ};
use geared_rotor::rotor::Params;

const OMEGA1: f64 = 314.159;

fn scaled_max(a: &[f64], b: &[f64], s: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .zip(s)
        .fold(0.0f64, |m, ((x, y), s)| m.max(((x - y) / s).abs()))
}

#[test]
fn shooting_orbit_is_the_limit_of_a_long_integration_and_stable() {
    let mut sys = PeriodicSystem::new(Params::default(), OMEGA1, 0.0).unwrap();
    let (z0, _) = sys.static_equilibrium().unwrap();
    let opts = ShootingOptions::default();
    let sh = shoot(&mut sys, &z0, &opts).unwrap();
    assert!(sh.residual <= 1e-10, "shooting residual {:e}", sh.residual);

    // Independent: plain time integration from the static equilibrium. The slowest
    // transient decays by the largest Floquet multiplier (~0.89) per period, so 220
    // periods bring it from O(1) below 1e-10 of the scale.
    let (z_long, _) = sys.integrate(&z0, 220, opts.rtol, None).unwrap();
    let s = sys.scales();
    let dev = scaled_max(z_long.as_slice(), sh.z.as_slice(), s.as_slice());
    assert!(
        dev <= 1e-8,
        "long integration vs shooting: {dev:e} (scaled)"
    );

    // Floquet multipliers: 12 of the reduced map, all inside the unit circle, and none
    // above the bound of the least damped bearing axis (`damping_bracket`): friction only
    // adds damping here (Coulomb friction against the fast sliding acts like a viscous
    // damper on the small transverse velocities, so some modes decay faster than any
    // bearing damper alone allows; the frictionless test checks the full bracket).
    assert_eq!(sh.floquet.len(), NZ);
    let max = sh.floquet_max_abs();
    let (_, hi) = damping_bracket(&Params::default(), sys.period());
    assert!(
        max < 1.0 && max <= hi,
        "largest multiplier {max} (bound {hi})"
    );
}

/// For light damping the decay rate of a mode is its Rayleigh quotient
/// `phi^T D phi / (2 phi^T M phi)`; with diagonal D and M (the constrained rotation of gear 2
/// included: d_phi over J2) it lies between the smallest and largest `d_i / (2 m_i)`, so
/// without friction every Floquet multiplier lies in `[exp(-max rate T), exp(-min rate T)]`.
fn damping_bracket(p: &Params, t: f64) -> (f64, f64) {
    let mut rates: Vec<f64> = (0..3)
        .flat_map(|a| {
            [
                p.rotor1.d[a] / (2.0 * p.rotor1.m),
                p.rotor2.d[a] / (2.0 * p.rotor2.m),
            ]
        })
        .collect();
    rates.push(p.d_phi / (2.0 * p.rotor2.j));
    let lo = (-rates.iter().cloned().fold(0.0, f64::max) * t).exp();
    let hi = (-rates.iter().cloned().fold(f64::INFINITY, f64::min) * t).exp();
    (lo, hi)
}

#[test]
fn harmonic_approach_converges_to_the_shooting_orbit() {
    let mut sys = PeriodicSystem::new(Params::default(), OMEGA1, 0.0).unwrap();
    let (z0, _) = sys.static_equilibrium().unwrap();
    let sh = shoot(&mut sys, &z0, &ShootingOptions::default()).unwrap();
    let opts = HarmonicOptions::default();
    let mut prev = None;
    let mut devs = Vec::new();
    for n in 1..=12 {
        let hb = harmonic_balance(&sys, n, prev.as_ref(), &opts).unwrap();
        assert!(
            hb.residual <= opts.tol,
            "n = {n}: residual {:e}",
            hb.residual
        );
        let pts: Vec<OrbitPoint> = sh.orbit.iter().map(|p| hb.point(p.t)).collect();
        devs.push((n, max_rel_deviation(&pts, &sh.orbit)));
        prev = Some(hb);
    }
    println!("{devs:?}");
    // Falls with n along a coarse ladder, and n = 4 matches well (the paper's statement).
    for w in [1usize, 2, 3, 4, 6, 8, 12].windows(2) {
        let (a, b) = (devs[w[0] - 1].1, devs[w[1] - 1].1);
        assert!(
            b < a,
            "deviation rose from n = {} ({a:e}) to n = {} ({b:e})",
            w[0],
            w[1]
        );
    }
    assert!(devs[3].1 < 1e-2, "n = 4 deviation {:e}", devs[3].1);
    assert!(
        devs[11].1 < devs[0].1 / 20.0,
        "n = 12 not much better than n = 1: {devs:?}"
    );
}

#[test]
fn frictionless_periodic_solution_is_the_static_equilibrium() {
    let params = Params {
        mu: 0.0,
        ..Params::default()
    };
    let mut sys = PeriodicSystem::new(params, OMEGA1, 0.0).unwrap();
    let (z_static, lambda_static) = sys.static_equilibrium().unwrap();
    let s = sys.scales();
    // Start the shooting away from the equilibrium, so that it has to find it.
    let mut start = z_static;
    start[0] += 0.5 * s[0];
    start[10] -= 0.3 * s[10];
    let opts = ShootingOptions {
        transient_periods: 0,
        ..ShootingOptions::default()
    };
    let sh = shoot(&mut sys, &start, &opts).unwrap();
    let dev = scaled_max(sh.z.as_slice(), z_static.as_slice(), s.as_slice());
    assert!(dev <= 1e-8, "shooting vs static equilibrium: {dev:e}");
    let (lo, hi) = damping_bracket(&params, sys.period());
    // 1e-4 relative: the accuracy of the forward-difference monodromy (an uncoupled
    // under-damped axis decays at exactly d / (2 m), so the edges are reached).
    for m in &sh.floquet {
        assert!(
            m.norm() >= lo * (1.0 - 1e-4) && m.norm() <= hi * (1.0 + 1e-4),
            "multiplier |{m}| = {} outside [{lo}, {hi}]",
            m.norm()
        );
    }
    for p in &sh.orbit {
        assert!(
            (p.lambda - lambda_static).abs() <= 1e-8 * lambda_static,
            "lambda {} vs {}",
            p.lambda,
            lambda_static
        );
    }

    let hb = harmonic_balance(&sys, 4, None, &HarmonicOptions::default()).unwrap();
    for sig in 0..8 {
        let scale = if sig == 7 { lambda_static } else { s[0] };
        for k in 1..=4 {
            assert!(
                hb.amplitude(sig, k) <= 1e-9 * scale,
                "signal {sig} harmonic {k}: {:e}",
                hb.amplitude(sig, k)
            );
        }
    }
    for i in 0..6 {
        assert!(
            (hb.coeffs[(i, 0)] - z_static[i]).abs() <= 1e-9 * s[i],
            "mean u[{i}]"
        );
    }
    assert!((hb.coeffs[(7, 0)] - lambda_static).abs() <= 1e-9 * lambda_static);
}

/// Without the rotational damper the load torque alone sets the nominal normal force. The
/// periodic module's scales used to take it from the damper alone (`d_phi omega2`), so at
/// d_phi = 0 the monodromy's difference steps (1e-13 m) sat in the integration noise and a
/// stable orbit was called unstable (|mu| = 4.45 at T_load = 100 N m, 10.4 at 20 N m).
/// Independent check of the multipliers: the decay of a small perturbation of the orbit in
/// a plain time integration, fitted as an exponential envelope over many periods: its
/// rate per period must be the largest Floquet multiplier.
#[test]
fn floquet_multipliers_without_damper_match_the_decay_of_a_perturbation() {
    for t_load in [100.0, 20.0] {
        let params = Params {
            d_phi: 0.0,
            ..Params::default()
        };
        let mut sys = PeriodicSystem::new(params, OMEGA1, t_load).unwrap();
        // The FMU's start (chord shooting at its tolerance, as initialization = periodic).
        let (z, report) = geared_rotor::sim::init::periodic_orbit(&mut sys, 1e-9).unwrap();
        assert!(report.floquet_max_abs < 1.0, "{report:?}");
        // Full Newton shooting with its own monodromy (rtol 1e-13; at 20 N m the scaled
        // residual stalls at ~2e-9, so 1e-8 is asked).
        let opts = ShootingOptions {
            tol: 1e-8,
            ..ShootingOptions::default()
        };
        let sh = shoot(&mut sys, &z, &opts).unwrap();
        let rho = sh.floquet_max_abs();
        // Perturb +-delta in u1x and u2y and difference the two runs (the orbit's own
        // small error cancels to second order); fit ln|d_k| = a + k ln(rho) for k in
        // [10, 60] where the perturbation is far above the noise and the faster modes
        // have died out.
        let delta = 2e-9;
        let mut zp = sh.z;
        let mut zm = sh.z;
        zp[0] += delta;
        zp[4] += delta;
        zm[0] -= delta;
        zm[4] -= delta;
        let (mut ks, mut ls) = (Vec::new(), Vec::new());
        for k in 1..=60 {
            zp = sys.integrate(&zp, 1, 1e-12, None).unwrap().0;
            zm = sys.integrate(&zm, 1, 1e-12, None).unwrap().0;
            let d = (0..6).map(|i| (zp[i] - zm[i]).powi(2)).sum::<f64>().sqrt() / 2.0;
            if k >= 10 {
                ks.push(k as f64);
                ls.push(d.ln());
            }
        }
        let n = ks.len() as f64;
        let (mk, ml) = (ks.iter().sum::<f64>() / n, ls.iter().sum::<f64>() / n);
        let slope = ks
            .iter()
            .zip(&ls)
            .map(|(k, l)| (k - mk) * (l - ml))
            .sum::<f64>()
            / ks.iter().map(|k| (k - mk).powi(2)).sum::<f64>();
        let decay = slope.exp();
        println!(
            "T_load {t_load}: |mu| chord {:.4}, shooting {rho:.4}, time-run decay per period {decay:.4}",
            report.floquet_max_abs
        );
        assert!(
            (decay - rho).abs() <= 0.02 * rho,
            "decay {decay} vs |mu| {rho}"
        );
        assert!(
            (report.floquet_max_abs - rho).abs() <= 0.02 * rho,
            "chord {} vs {rho}",
            report.floquet_max_abs
        );
    }
}
