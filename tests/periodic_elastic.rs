//! Periodic solutions with the elastic drive-flank contact (`tooth_contact = elastic`,
//! docs/model.md §3.5, §11; issue 27 item 6): the orbit found by shooting is periodic when a
//! plain simulation starts on it (the FMU's `initialization = periodic`), it is where a long
//! simulation from the static start settles, the mesh-mode Floquet multiplier of a
//! constant-stiffness pair is the closed-form one of (3.19), and the harmonic approach agrees
//! with shooting.

use geared_rotor::gear::GearData;
use geared_rotor::periodic::elastic::{self, shoot_elastic, ElasticShootingResult};
use geared_rotor::periodic::harmonic::{harmonic_balance, HarmonicOptions};
use geared_rotor::periodic::modal::{modal_analysis, ModalOptions};
use geared_rotor::periodic::shooting::{shoot, ShootingOptions};
use geared_rotor::periodic::{max_rel_deviation, PeriodicSystem};
use geared_rotor::rotor::{FrictionLaw, Outputs, Params, RotorData, ToothContact};
use geared_rotor::sim::{Initialization, Simulation, SolverSettings};
use nalgebra::Complex;
use std::f64::consts::PI;

const OMEGA1: f64 = 314.159;
const T_LOAD: f64 = 50.0;

fn elastic(p: Params) -> Params {
    Params {
        tooth_contact: ToothContact::Elastic,
        ..p
    }
}

/// The default pair with elastic teeth at 3000 rpm and 50 N m, its orbit by shooting.
fn default_orbit() -> (PeriodicSystem, ElasticShootingResult) {
    let mut sys = PeriodicSystem::new(elastic(Params::default()), OMEGA1, T_LOAD).unwrap();
    let z0 = sys.elastic_start().unwrap();
    let sh = shoot_elastic(&mut sys, &z0, &elastic::default_options()).unwrap();
    (sys, sh)
}

/// Peak-to-peak of the orbit's centre positions (x, y of both gears) and of xi.
fn orbit_sizes(sh: &ElasticShootingResult) -> (f64, f64) {
    let range = |f: &dyn Fn(&geared_rotor::periodic::OrbitPoint) -> f64| {
        let (lo, hi) = sh
            .orbit
            .iter()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
        hi - lo
    };
    let mut pp: f64 = 0.0;
    for k in [0, 1, 3, 4] {
        pp = pp.max(range(&|p| p.u[k]));
    }
    (pp, range(&|p| p.xi))
}

/// Largest deviation of a simulation's centre positions and TE from the orbit's start
/// state: (centres / their orbit peak to peak, TE / the xi peak to peak).
fn deviation_from_start(o: &Outputs, sh: &ElasticShootingResult, pp: (f64, f64)) -> (f64, f64) {
    let mut du: f64 = 0.0;
    for i in 0..3 {
        du = du.max((o.u1[i] - sh.z[i]).abs());
        du = du.max((o.u2[i] - sh.z[3 + i]).abs());
    }
    (du / pp.0, (o.te - sh.z[6]).abs() / pp.1)
}

#[test]
fn elastic_orbit_is_periodic_and_is_where_a_long_run_settles() {
    let (sys, sh) = default_orbit();
    let t_m = sys.period();
    let pp = orbit_sizes(&sh);
    println!(
        "elastic orbit (default pair, 3000 rpm, 50 N m): residual {:.2e} after {} Newton \
         iterations, {} steps per period, |mu|max {:.4}, Fn {:?} N, pp centres {:.3e} m, pp xi {:.3e} m",
        sh.residual,
        sh.iterations,
        sh.steps_per_period,
        sh.floquet_max_abs(),
        sh.fn_range(),
        pp.0,
        pp.1
    );
    assert!(sh.residual <= 1e-8, "{}", sh.residual);
    assert!(sh.floquet_max_abs() < 1.0);
    // A real vibration: the orbit moves (not a fixed point of the period map).
    assert!(pp.0 > 1e-9 && pp.1 > 1e-9, "{pp:?}");

    // 1. A plain simulation started on the orbit by the FMU's own initialization = periodic
    //    (chord shooting at the simulation's tolerance) returns to it after 1 and 5 periods.
    let settings = SolverSettings {
        rtol: 1e-9,
        h_max: 1e-4,
    };
    let mut s = Simulation::with_initialization(
        elastic(Params::default()),
        settings,
        0.0,
        OMEGA1,
        T_LOAD,
        Initialization::Periodic,
    )
    .unwrap();
    let d0 = deviation_from_start(&s.outputs(), &sh, pp);
    let mut dev = d0;
    for k in 0..5 {
        s.do_step(k as f64 * t_m, t_m).unwrap();
        let d = deviation_from_start(&s.outputs(), &sh, pp);
        println!("periodic start, after {} period(s): centres {:.2e}, TE {:.2e} of the orbit's peak to peak", k + 1, d.0, d.1);
        dev = (dev.0.max(d.0), dev.1.max(d.1));
    }
    println!(
        "periodic start at t = 0: centres {:.2e}, TE {:.2e}",
        d0.0, d0.1
    );
    assert!(dev.0 < 1e-5 && dev.1 < 1e-5, "{dev:?}");

    // 2. Independent: a long run from the elastic static start (no shooting) settles on the
    //    same state at the period starts (the slowest multiplier |mu| ~ 0.9 per period: after
    //    300 periods the transient is ~1e-14 of its start).
    let mut s = Simulation::with_initialization(
        elastic(Params::default()),
        settings,
        0.0,
        OMEGA1,
        T_LOAD,
        Initialization::StaticEquilibrium,
    )
    .unwrap();
    let d_start = deviation_from_start(&s.outputs(), &sh, pp);
    let n = 300;
    for k in 0..n {
        s.do_step(k as f64 * t_m, t_m).unwrap();
    }
    let d = deviation_from_start(&s.outputs(), &sh, pp);
    println!(
        "long run from the static start: at t = 0 centres {:.2e}, TE {:.2e}; after {n} periods \
         centres {:.2e}, TE {:.2e} of the orbit's peak to peak",
        d_start.0, d_start.1, d.0, d.1
    );
    assert!(
        d_start.0 > 0.1 || d_start.1 > 0.1,
        "the static start is not on the orbit"
    );
    assert!(d.0 < 1e-5 && d.1 < 1e-5, "{d:?}");
}

/// A helical pair with integer overlap eps_beta = 1 (b = pi m_n / sin beta): the contact
/// length, and so the mesh stiffness, is constant, and with soft bearings (k = 1e6 N/m, 1e-3
/// of the mesh stiffness) the mesh mode is the free-centre mode of (3.18)-(3.19).
fn constant_stiffness_pair() -> Params {
    let d = Params::default();
    let gear = GearData {
        b: PI * d.gear.m_n / d.gear.beta.sin(),
        c_gamma: 2.0e10,
        ..d.gear
    };
    let soft = |r: RotorData| RotorData {
        k: [1e6; 3],
        d: [1.0; 3],
        ..r
    };
    elastic(Params {
        gear,
        rotor1: soft(d.rotor1),
        rotor2: soft(d.rotor2),
        d_phi: 0.0,
        mu: 0.0,
        friction_law: FrictionLaw::Coulomb,
        ..d
    })
}

#[test]
fn mesh_mode_multiplier_is_the_closed_form_one() {
    let p = constant_stiffness_pair();
    let g = p.gear;
    // Closed form, independently of the crate (ISO 21771 base helix and base radius).
    let alpha_t = (g.alpha_n.tan() / g.beta.cos()).atan();
    let beta_b = (g.beta.sin() * g.alpha_n.cos()).asin();
    let rb2 = f64::from(g.z2) * g.m_n * alpha_t.cos() / (2.0 * g.beta.cos());
    let inv_m_eq = 1.0 / p.rotor1.m + 1.0 / p.rotor2.m + (rb2 * beta_b.cos()).powi(2) / p.rotor2.j;
    let omega_m = (g.c_gamma * g.b * inv_m_eq).sqrt();
    let zeta = p.zeta_mesh;
    // Drive speed with the mesh frequency at 0.7 f_m: the mode turns by ~1.4 cycles a period.
    let omega1 = 0.7 * omega_m / f64::from(g.z1);
    // A light load (13 N normal force): the centres move 13 um on the soft bearings, which
    // widens the working centre distance and lowers the contact ratio and the mean mesh
    // stiffness by 0.3 % (omega_m by 0.15 %, the decay rate d_l l / 2 m_eq by 0.3 %); the
    // bearings at 1e-3 of the mesh stiffness raise omega_m^2 by ~1e-4. Hence the bands
    // below: frequency 0.3 %, decay per period 0.5 %.
    let t_load = 0.5;
    let mut sys = PeriodicSystem::new(p, omega1, t_load).unwrap();
    let t = sys.period();
    let z0 = sys.elastic_start().unwrap();
    // The light load makes the scales small (xi: 37 nm, its rate 5e-4 m/s): omega2's absolute
    // integration error (rtol |omega2|, omega2 = 336 rad/s) is ~1e-6 of them at rtol 1e-12;
    // the orbit (here the static state, the stiffness being constant) is needed only to 1e-5
    // of them for the monodromy. Period maps at rtol 1e-13 and difference steps 1e-3 of the
    // scales: well above the integration noise (the mesh mode's |mu| moves by 2e-4 between
    // steps 1e-3 and 1e-4 at rtol 1e-12 and 1e-13, by 1e-2 at rtol 1e-10), well below the
    // static mesh deflection (the force's kink at delta = 0).
    let opts = ShootingOptions {
        rtol: 1e-13,
        tol: 1e-5,
        fd_step: 1e-3,
        ..elastic::default_options()
    };
    let sh = shoot_elastic(&mut sys, &z0, &opts).unwrap();
    let mm = elastic::mesh_mode(&sys, &sh.z, &sh.monodromy)
        .unwrap()
        .unwrap();
    let s_cf = Complex::new(-zeta * omega_m, omega_m * (1.0 - zeta * zeta).sqrt());
    let mu_cf = (s_cf * t).exp();
    println!(
        "constant-stiffness pair: f_m = {:.2} Hz (closed form), T_m = {:.4e} s; mesh mode \
         multiplier {:.6} (closed form {:.6}): |mu| {:.6} vs {:.6}, angle {:.6} vs {:.6} rad; \
         f {:.2} Hz, zeta {:.5}; mesh share {:.4}; residual {:.1e}; all |mu| {:?}",
        omega_m / (2.0 * PI),
        t,
        mm.multiplier,
        mu_cf,
        mm.multiplier.norm(),
        mu_cf.norm(),
        mm.multiplier.arg(),
        mu_cf.arg(),
        mm.freq_hz,
        mm.zeta,
        mm.mesh_share,
        sh.residual,
        sh.floquet.iter().map(|c| c.norm()).collect::<Vec<_>>()
    );
    let decay = mm.multiplier.norm().ln() / mu_cf.norm().ln() - 1.0;
    let angle = (mm.multiplier / mu_cf).arg();
    let freq = mm.freq_hz * 2.0 * PI / (omega_m * (1.0 - zeta * zeta).sqrt()) - 1.0;
    println!("relative: decay per period {decay:.2e}, frequency {freq:.2e}; angle {angle:.2e} rad; zeta {:.2e}", mm.zeta / zeta - 1.0);
    assert!(decay.abs() < 5e-3, "{decay}");
    assert!(freq.abs() < 3e-3, "{freq}");
    assert!(angle.abs() < 0.03, "{angle}");
    assert!((mm.zeta / zeta - 1.0).abs() < 0.02);
    assert!(mm.mesh_share > 0.9);
}

#[test]
fn harmonic_approach_agrees_with_shooting_in_elastic_mode() {
    let (sys, sh) = default_orbit();
    let mut prev = None;
    let mut devs = Vec::new();
    for n in [2, 4, 8] {
        let hb = harmonic_balance(&sys, n, prev.as_ref(), &HarmonicOptions::default()).unwrap();
        let dots = hb.orbit(sh.orbit.len());
        let dev = max_rel_deviation(&dots, &sh.orbit);
        // Fn: the eighth signal against the shooting orbit's Fn.
        let fn_dev = dots
            .iter()
            .zip(&sh.orbit)
            .map(|(a, b)| (a.lambda - b.lambda).abs())
            .fold(0.0f64, f64::max);
        let (hi, lo) = sh.fn_range();
        println!(
            "harmonic approach n = {n}: residual {:.1e}, centre deviation {:.2e} of the orbit, \
             Fn deviation {:.2e} of its peak to peak",
            hb.residual,
            dev,
            fn_dev / (hi - lo)
        );
        devs.push(dev);
        prev = Some(hb);
    }
    assert!(devs[2] < 0.01, "{devs:?}");
    assert!(devs[2] < devs[0], "{devs:?}");
}

#[test]
fn rigid_only_parts_refuse_the_elastic_system_by_name() {
    let mut sys = PeriodicSystem::new(elastic(Params::default()), OMEGA1, 0.0).unwrap();
    let (z, _) = sys.static_equilibrium().unwrap();
    let e = shoot(&mut sys, &z, &ShootingOptions::default()).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("tooth_contact") && msg.contains("periodic::elastic"),
        "{msg}"
    );
    let e = modal_analysis(
        elastic(Params::default()),
        OMEGA1,
        0.0,
        &ModalOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("tooth_contact = rigid") && e.contains("--damping"),
        "{e}"
    );
    let rigid = PeriodicSystem::new(Params::default(), OMEGA1, 0.0).unwrap();
    let e = rigid.elastic_start().unwrap_err().to_string();
    assert!(e.contains("tooth_contact = elastic"), "{e}");
}
