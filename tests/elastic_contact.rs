//! The elastic drive-flank contact (`tooth_contact = elastic`, docs/model.md §3.5):
//! the stiff limit against the rigid model, the quasi-static deflection of a spur pair
//! through single and double tooth contact, the energy balance with the mesh terms, and a
//! rattle run that separates the flanks.

use geared_rotor::gear::{c_gamma_used, GearData};
use geared_rotor::rotor::{FrictionLaw, Outputs, Params, ToothContact};
use geared_rotor::sim::{Initialization, Input, OnViolation, Simulation, SolverSettings};
use std::f64::consts::PI;

const OMEGA1: f64 = 314.159;

fn elastic(p: Params) -> Params {
    Params {
        tooth_contact: ToothContact::Elastic,
        ..p
    }
}

fn spur(p: Params) -> Params {
    Params {
        gear: GearData {
            beta: 0.0,
            ..p.gear
        },
        ..p
    }
}

fn sim(p: Params, s: SolverSettings, omega1: f64, t_load: f64) -> Simulation {
    Simulation::with_initialization(p, s, 0.0, omega1, t_load, Initialization::StaticEquilibrium)
        .unwrap()
}

/// c_gamma_used of the pair of `p`.
fn c_used(p: &Params) -> f64 {
    c_gamma_used(&p.validate().unwrap())
}

/// Largest deviations of the elastic run from the rigid one at the samples: T1 and Fn
/// relative to the rigid Fn's size, TE and the centre positions in metres.
fn deviations(a: &[Outputs], b: &[Outputs]) -> [f64; 4] {
    let mut d = [0.0f64; 4];
    for (x, y) in a.iter().zip(b) {
        d[0] = d[0].max((x.t1 - y.t1).abs() / y.t1.abs());
        d[1] = d[1].max((x.fn_ - y.fn_).abs() / y.fn_.abs());
        d[2] = d[2].max((x.te - y.te).abs());
        for i in 0..3 {
            d[3] = d[3].max((x.u1[i] - y.u1[i]).abs());
            d[3] = d[3].max((x.u2[i] - y.u2[i]).abs());
        }
    }
    d
}

fn samples(mut s: Simulation, h: f64, n: usize, skip: usize) -> Vec<Outputs> {
    let mut out = Vec::new();
    for k in 0..n {
        s.do_step(k as f64 * h, h).unwrap();
        if k >= skip {
            out.push(s.outputs());
        }
    }
    out
}

/// c_gamma x 10^k, k = 0..4: every deviation from the rigid solution falls with the
/// compliance 1/c (rate ~ 1 per decade) and is tiny at k = 4.
#[test]
fn stiff_limit_converges_to_the_rigid_solution() {
    let settings = SolverSettings {
        rtol: 1e-8,
        h_max: 1e-4,
    };
    let base = Params::default();
    let t_load = 50.0;
    let (h, n, skip) = (2.5e-4, 40, 8);
    let rigid = samples(sim(base, settings, OMEGA1, t_load), h, n, skip);
    let c0 = c_used(&base);
    println!("stiff limit (default pair, T_load = {t_load} N m, 3000 rpm, samples 2-10 ms):");
    println!("   k  c_gamma [N/(mm um)]  |dT1|/T1    |dFn|/Fn    |dTE| [m]   |du| [m]");
    let mut rows = Vec::new();
    for k in 0..=4 {
        let c = c0 * 10f64.powi(k);
        let p = elastic(Params {
            gear: GearData {
                c_gamma: c,
                ..base.gear
            },
            ..base
        });
        let e = samples(sim(p, settings, OMEGA1, t_load), h, n, skip);
        let d = deviations(&e, &rigid);
        println!(
            "   {k}  {:>18.1}  {:.3e}   {:.3e}   {:.3e}   {:.3e}",
            c * 1e-9,
            d[0],
            d[1],
            d[2],
            d[3]
        );
        rows.push(d);
    }
    // Rates from k = 1 to 4. Positions and TE: the deflection delta ~ Fn / c, rate 1.
    // Forces: the mesh damping force d_l l delta' with d_l ~ sqrt(c) (zeta_mesh fixed) and
    // delta' ~ 1/c falls as c^-1/2, so T1 and Fn approach the rigid values at rate 1/2.
    let names = ["T1", "Fn", "TE", "u"];
    for j in 0..4 {
        let rate = (rows[1][j] / rows[4][j]).log10() / 3.0;
        println!(
            "   {}: mean rate {rate:.2} decades per decade of c_gamma (k = 1..4)",
            names[j]
        );
        let expected = if j < 2 { 0.5 } else { 1.0 };
        assert!(rate > 0.8 * expected, "{}: rate {rate}", names[j]);
    }
    assert!(rows[4][0] < 1e-3 && rows[4][1] < 1e-3, "{:?}", rows[4]);
    assert!(rows[4][2] < 1e-8 && rows[4][3] < 1e-9, "{:?}", rows[4]);
}

/// Spur pair at 10 rpm, bearings 100 times stiffer, constant load, no friction (without
/// the stick mode, which the elastic contact does not have yet, Coulomb friction chatters
/// at the pitch line of a spur pair at this speed): between the zone changes the
/// deflection is the static one, delta = Fn / (c_l l(t)), to 1e-6, in single (l = b) and
/// double (l = 2 b) tooth contact.
#[test]
fn quasi_static_spur_deflection_follows_the_contact_length() {
    let mut p = elastic(spur(Params {
        mu: 0.0,
        ..Params::default()
    }));
    // Bearings 100 times stiffer and 100 times more damped (damping ratio of their modes
    // ~0.3 instead of 0.003), so that the ringing after a zone change dies out.
    for r in [&mut p.rotor1, &mut p.rotor2] {
        for x in r.k.iter_mut().chain(r.d.iter_mut()) {
            *x *= 100.0;
        }
    }
    let settings = SolverSettings {
        rtol: 1e-8,
        h_max: 1e-2,
    };
    let omega1 = 2.0 * PI * 10.0 / 60.0;
    let mut s = sim(p, settings, omega1, 100.0);
    let geom = p.validate().unwrap();
    let c_l = c_used(&p) * geom.cos_beta_b / geom.eps_alpha;
    let period = 2.0 * PI / (27.0 * omega1);
    let h = period / 400.0;
    let mut zone_start = 0usize;
    let mut pairs = s.outputs().pairs_in_contact;
    let mut last: Option<Outputs> = None;
    let mut worst = [0.0f64; 3];
    let mut seen = [0usize; 3];
    // The outputs at the ends of the zones (quasi-static: a zone change's transient has
    // died out to ~1e-15 there).
    let mut ends: Vec<Outputs> = Vec::new();
    for k in 0..1200 {
        s.do_step(k as f64 * h, h).unwrap();
        let o = s.outputs();
        let np = o.pairs_in_contact as usize;
        assert!(np == 1 || np == 2, "{np} pairs");
        assert!((o.contact_length - np as f64 * p.gear.b).abs() < 1e-12);
        assert!((o.mesh_stiffness - c_l * o.contact_length).abs() <= 1e-12 * o.mesh_stiffness);
        if o.pairs_in_contact != pairs {
            // The zone that ended: its last sample, if the zone lasted 60 samples (35 ms).
            if let Some(e) = last.filter(|_| k - zone_start >= 60) {
                let n = e.pairs_in_contact as usize;
                let stat = e.fn_ / (c_l * e.contact_length);
                worst[n] = worst[n].max((e.mesh_deflection - stat).abs() / stat);
                seen[n] += 1;
                ends.push(e);
            }
            pairs = o.pairs_in_contact;
            zone_start = k;
        }
        last = Some(o);
    }
    // TE step between a single-contact end and the next double-contact end: at the same
    // Fn the bearings are where they were, so TE moves by the deflection difference,
    // +(Fn / (c_l b) - Fn / (2 c_l b)) / cos(beta_b) (gap (3.7): dg/dxi = 1; the
    // smaller deflection lets gear 2 lag less).
    let mut step_err = 0.0f64;
    let mut steps = 0;
    for w in ends.windows(2) {
        if w[0].pairs_in_contact == 1 && w[1].pairs_in_contact == 2 {
            let fn_ = w[0].fn_;
            let closed = (fn_ / (c_l * p.gear.b) - fn_ / (2.0 * c_l * p.gear.b)) / geom.cos_beta_b;
            let step = w[1].te - w[0].te;
            step_err = step_err.max((step - closed).abs() / closed);
            steps += 1;
            println!(
                "TE step single -> double: {step:.6e} m, closed form {closed:.6e} m, Fn {:.6} / {:.6} N",
                w[0].fn_, w[1].fn_
            );
        }
    }
    println!(
        "quasi-static spur (10 rpm, T_load 100 N m), zone ends: max |delta - Fn/(c_l l)| / \
         delta = {:.2e} in single contact ({} zones), {:.2e} in double contact ({} zones); \
         TE step against the closed form {step_err:.2e} ({steps} steps)",
        worst[1], seen[1], worst[2], seen[2]
    );
    assert!(seen[1] >= 2 && seen[2] >= 2, "{seen:?}");
    assert!(worst[1] < 1e-6 && worst[2] < 1e-6, "{worst:?}");
    assert!(steps >= 1 && step_err < 1e-6, "{step_err:e}");
}

/// The energy balance with the mesh terms: E_in + W_k = E_load + E_kin + E_pot + E_loss +
/// E_damp, each from the start, to 1e-8 of E_in (laws 1 and 4, loaded, default pair).
#[test]
fn energy_balance_closes_with_the_mesh_terms() {
    let settings = SolverSettings {
        rtol: 1e-8,
        h_max: 1e-4,
    };
    for law in [FrictionLaw::Coulomb, FrictionLaw::LocalEhl] {
        let p = elastic(Params {
            friction_law: law,
            ..Params::default()
        });
        let mut s = sim(p, settings, OMEGA1, 80.0);
        let o0 = s.outputs();
        let h = 1e-4;
        let mut worst = 0.0f64;
        let mut w_max = 0.0f64;
        for k in 0..200 {
            s.do_step(k as f64 * h, h).unwrap();
            let o = s.outputs();
            let supplied = o.e_in + (o.w_mesh_stiffness - o0.w_mesh_stiffness);
            let used = o.e_load + (o.e_kin - o0.e_kin) + (o.e_pot - o0.e_pot) + o.e_loss + o.e_damp;
            worst = worst.max((supplied - used).abs() / o.e_in.abs());
            w_max = w_max.max(o.w_mesh_stiffness.abs());
        }
        let o = s.outputs();
        println!(
            "{law:?}: 20 ms, E_in {:.4} J, E_loss {:.4} J, E_damp {:.4} J, W_k {:.3e} J \
             (max {:.3e}), mesh spring {:.3e} J: worst |balance| / E_in = {worst:.2e}",
            o.e_in, o.e_loss, o.e_damp, o.w_mesh_stiffness, w_max, o.e_mesh_spring
        );
        assert!(worst < 1e-8, "{law:?}: {worst:e}");
    }
}

/// Rattle: small load (d_phi 0.01, no load torque), omega1 +-5 % at 30 Hz: the flanks
/// separate and touch again; the run completes without a validity stop (`discard`
/// policy), Fn >= 0 throughout and the energy balance holds.
#[test]
fn rattle_separates_without_discard_and_keeps_fn_non_negative() {
    let settings = SolverSettings {
        rtol: 1e-6,
        h_max: 1e-4,
    };
    let p = elastic(Params {
        d_phi: 0.01,
        ..Params::default()
    });
    let mut s = sim(p, settings, OMEGA1, 0.0);
    s.set_on_violation(OnViolation::Discard);
    let o0 = s.outputs();
    let h = 1e-4;
    let (mut free, mut onsets, mut prev) = (0usize, 0usize, 1);
    let mut fn_min = f64::INFINITY;
    let mut worst = 0.0f64;
    for k in 0..1000 {
        let t = k as f64 * h;
        s.set_input(
            Input::Omega1,
            OMEGA1 * (1.0 + 0.05 * (2.0 * PI * 30.0 * t).sin()),
        )
        .unwrap();
        s.do_step(t, h).unwrap();
        let o = s.outputs();
        fn_min = fn_min.min(o.fn_);
        if o.mesh_state == 0 {
            free += 1;
            assert_eq!(o.fn_, 0.0);
            assert!(o.mesh_deflection <= 0.0);
        } else if prev == 0 {
            onsets += 1;
        }
        prev = o.mesh_state;
        let supplied = o.e_in + (o.w_mesh_stiffness - o0.w_mesh_stiffness);
        let used = o.e_load + (o.e_kin - o0.e_kin) + (o.e_pot - o0.e_pot) + o.e_loss + o.e_damp;
        // Over the larger of |E_in| and E_kin (~170 J; the net E_in of a rattle is small).
        worst = worst.max((supplied - used).abs() / o.e_in.abs().max(o.e_kin));
    }
    println!(
        "rattle (0.1 s): {free} of 1000 samples in free flight, {onsets} contact onsets seen \
         at the samples, min Fn {fn_min:.3e} N, worst |balance| / max(|E_in|, E_kin) \
         {worst:.2e}; {}",
        s.stats()
    );
    assert!(
        free > 10 && onsets > 1,
        "no rattle: {free} free, {onsets} onsets"
    );
    assert!(fn_min >= 0.0);
    // rtol 1e-6 here: the balance holds to that order.
    assert!(worst < 1e-5, "{worst:e}");
}

/// The constants of (3.17)-(3.20) against an independent evaluation for the default
/// pair: c_l from c_gamma_used, m_eq from the masses (gear 1's speed prescribed), the
/// mean of c_l l over a mesh period equal to c_gamma b.
#[test]
fn elastic_mesh_constants() {
    let p = elastic(Params::default());
    let g = p.validate().unwrap();
    let model = geared_rotor::rotor::GearedRotor::new(p).unwrap();
    let e = *model.elastic_mesh().unwrap();
    let c = c_used(&p);
    let c_l = c * g.cos_beta_b / g.eps_alpha;
    assert!((e.c_l - c_l).abs() <= 1e-12 * c_l);
    // |n| = 1; gear 2's inertia seen on the line of action at r_b2 cos(beta_b).
    let (m1, m2, j2) = (p.rotor1.m, p.rotor2.m, p.rotor2.j);
    let rb2c = g.rb2 * g.cos_beta_b;
    let m_eq = 1.0 / (1.0 / m1 + 1.0 / m2 + rb2c * rb2c / j2);
    assert!((e.m_eq - m_eq).abs() <= 1e-12 * m_eq, "{} {m_eq}", e.m_eq);
    let k = c * p.gear.b;
    let d_l = 2.0 * p.zeta_mesh * (k * m_eq).sqrt() * g.cos_beta_b / (p.gear.b * g.eps_alpha);
    assert!((e.d_l - d_l).abs() <= 1e-12 * d_l);
    // Mean of k(t) = c_l l over one mesh period, undeflected, by the trapezoidal rule on
    // 4000 phases (l is piecewise linear in the phase).
    let m = g
        .mesh(&nalgebra::Vector3::zeros(), &nalgebra::Vector3::zeros())
        .unwrap();
    let n = 4000;
    let mean: f64 = (0..n)
        .map(|i| {
            let phi1 = g.phi1_period * i as f64 / n as f64;
            e.c_l * g.contact_summary(&m, phi1, 0.0).length
        })
        .sum::<f64>()
        / n as f64;
    println!(
        "c_gamma_used {:.4} N/(mm um), c_l {:.4e} N/m2, d_l {:.4e} N s/m2, m_eq {:.4} kg, \
         mesh frequency {:.1} Hz, mean k {:.6e} N/m = c_gamma b {:.6e} N/m",
        c * 1e-9,
        e.c_l,
        e.d_l,
        e.m_eq,
        (k / m_eq).sqrt() / (2.0 * PI),
        mean,
        k
    );
    assert!((mean - k).abs() < 1e-3 * k, "{mean} {k}");
}

/// The real-time mode (`h_fixed`, fixed steps, no event location) runs the elastic
/// contact: 10 ms of the loaded default pair at h = 1e-5 s stay within 1e-3 of the
/// adaptive solution in Fn and within 1e-9 m in TE (measured 3.1e-5 and 1.5e-10 m).
#[test]
fn real_time_mode_runs_the_elastic_contact() {
    let settings = SolverSettings {
        rtol: 1e-6,
        h_max: 1e-4,
    };
    let p = elastic(Params::default());
    let mut a = sim(p, settings, OMEGA1, 50.0);
    let mut r = sim(p, settings, OMEGA1, 50.0);
    r.set_h_fixed(1e-5).unwrap();
    let h = 1e-4;
    let (mut dfn, mut dte) = (0.0f64, 0.0f64);
    for k in 0..100 {
        a.do_step(k as f64 * h, h).unwrap();
        r.do_step(k as f64 * h, h).unwrap();
        let (oa, or) = (a.outputs(), r.outputs());
        dfn = dfn.max((oa.fn_ - or.fn_).abs() / oa.fn_);
        dte = dte.max((oa.te - or.te).abs());
    }
    println!(
        "real-time mode h = 1e-5 s against adaptive: max |dFn|/Fn {dfn:.2e}, |dTE| {dte:.2e} m"
    );
    assert!(dfn < 1e-3 && dte < 1e-9, "{dfn:e} {dte:e}");
}

/// The output derivatives of the elastic contact keep the last slot of y, the work stored
/// in the mesh spring (no multiplier to project): the derivative of `w_mesh_stiffness`
/// agrees with its difference quotient over a short doStep, and the outputs either side
/// of the central difference are those of the current state (the projection that the
/// rigid multiplier gets once wrote Fn into the slot: w = e_mesh_spring - Fn there).
#[test]
fn output_derivatives_keep_the_stored_spring_work() {
    let settings = SolverSettings {
        rtol: 1e-8,
        h_max: 1e-4,
    };
    let mut s = sim(elastic(Params::default()), settings, OMEGA1, 100.0);
    let h = 1e-4;
    for k in 0..20 {
        s.do_step(k as f64 * h, h).unwrap();
    }
    let t = s.time();
    let w0 = s.outputs().w_mesh_stiffness;
    let (om, op, delta) = s.outputs_for_derivative();
    let d = (op.w_mesh_stiffness - om.w_mesh_stiffness) / (2.0 * delta);
    assert!(
        (om.w_mesh_stiffness - w0).abs() < 1e-6 && (op.w_mesh_stiffness - w0).abs() < 1e-6,
        "{} {} {w0}",
        om.w_mesh_stiffness,
        op.w_mesh_stiffness
    );
    let dt = 1e-7;
    s.do_step(t, dt).unwrap();
    let fd = (s.outputs().w_mesh_stiffness - w0) / dt;
    println!("d w_mesh_stiffness / dt: {d:.6e} W, difference quotient {fd:.6e} W");
    assert!(
        (d - fd).abs() <= 1e-2 * fd.abs().max(1e-3),
        "{d:e} vs {fd:e}"
    );
}
