//! Stick of a spur contact line at the pitch line with elastic teeth (model.md §3.5, §4.1;
//! `sim::stick`, `rotor::dae::stick`): the same Filippov sliding mode as with rigid teeth,
//! the stick force (4.13) now explicit (Fn is a function of the state).
//!
//! Before, the elastic contact had no stick mode and these runs stalled like the rigid
//! ones once did: 100 rpm (mu 0.05, law 1) stopped after 50 000 internal steps at t =
//! 0.0223 s, 1000 rpm with mu 0.3 at 2.19 ms, law 3 at 100 rpm at 0.0223 s.
//!
//! Checked against physics and independent computations:
//! - the cases run to their end with stick phases, the energy balance (3.21) closed to
//!   1e-8 of E_in;
//! - during a stick phase the line does not slide and its force stays within mu times its
//!   share of Fn;
//! - the stick solution is the limit of the regularised law 2 as its regularising speed
//!   goes to zero (law 2 has no stick mode);
//! - the located instants do not depend on the communication step.

mod common;

use common::stick::{
    assert_same_instants, phases, regularised_law_deviations, round_trip, rpm, sample_stuck_lines,
    stuck_line_sliding,
};
use geared_rotor::gear::FrictionLaw;
use geared_rotor::rotor::{idx, Params, ToothContact, NY, RELEASE_BAND};
use nalgebra::SVector;

/// The outputs' input power and friction loss against the energy rates of f at the same
/// state: the stick force enters both the same way (f and the outputs compute it apart).
fn outputs_match_f(sim: &Simulation, what: &str) {
    let (t, y) = (sim.time(), *sim.y());
    let o = sim.outputs();
    let mut f = SVector::<f64, NY>::zeros();
    sim.model().clone().rhs(t, &y, &mut f).unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0);
    assert!(
        close(o.p_in, f[idx::E_IN]),
        "{what}: P_in {} vs {}",
        o.p_in,
        f[idx::E_IN]
    );
    assert!(
        close(o.p_loss, f[idx::E_LOSS]),
        "{what}: P_loss {} vs {}",
        o.p_loss,
        f[idx::E_LOSS]
    );
}
use geared_rotor::sim::{Simulation, SolverSettings};

/// The spur pair of the rigid stick tests with elastic teeth.
fn spur(mu: f64, law: FrictionLaw) -> Params {
    Params {
        tooth_contact: ToothContact::Elastic,
        ..common::stick::spur(mu, law)
    }
}

/// A run with constant inputs in doSteps of `h`: the simulation, the stick changes
/// (instant, stick) it reported and the largest energy residual (3.21) relative to E_in.
fn run(
    p: Params,
    rtol: f64,
    omega1: f64,
    t_load: f64,
    t_end: f64,
    h: f64,
) -> (Simulation, Vec<(f64, bool)>, f64) {
    let settings = SolverSettings { rtol, h_max: 1e-4 };
    let mut sim = Simulation::new(p, settings, 0.0, omega1, t_load).unwrap();
    let o0 = sim.outputs();
    let mut changes = Vec::new();
    let mut worst = 0.0f64;
    let n = (t_end / h).round() as usize;
    for k in 0..n {
        let r = sim
            .do_step(k as f64 * h, h)
            .unwrap_or_else(|e| panic!("t = {}: {e}", k as f64 * h));
        assert_eq!(r.stick_changes_dropped, 0);
        changes.extend(r.stick_changes.iter().flatten().map(|c| (c.t, c.stick)));
        let o = sim.outputs();
        // Supplied (E_in and the stiffness variation's work) against used.
        let supplied = o.e_in + (o.w_mesh_stiffness - o0.w_mesh_stiffness);
        let used = o.e_load + (o.e_kin - o0.e_kin) + (o.e_pot - o0.e_pot) + o.e_loss + o.e_damp;
        worst = worst.max((supplied - used).abs() / o.e_in.abs());
    }
    (sim, changes, worst)
}

#[test]
fn spur_cases_with_stick_run_to_their_end_with_closed_energy_balance() {
    // (case, law, mu, rpm, T_load, t_end)
    let cases = [
        ("100 rpm", FrictionLaw::Coulomb, 0.05, 100.0, 0.0, 0.05),
        (
            "100 rpm, 50 N m",
            FrictionLaw::Coulomb,
            0.05,
            100.0,
            50.0,
            0.02,
        ),
        (
            "1000 rpm, mu 0.3",
            FrictionLaw::Coulomb,
            0.3,
            1000.0,
            0.0,
            0.01,
        ),
        (
            "law 3, 100 rpm",
            FrictionLaw::IsoMean,
            0.05,
            100.0,
            0.0,
            0.05,
        ),
    ];
    for (name, law, mu, n, t_load, t_end) in cases {
        let (sim, changes, res) = run(spur(mu, law), 1e-9, rpm(n), t_load, t_end, 1e-3);
        let ph = phases(&changes);
        let stuck: f64 = ph.iter().map(|(a, b)| b - a).sum();
        println!(
            "{name}: to {t_end} s, {} stick phases ({stuck:.3e} s in all), energy residual \
             {res:.2e} of E_in; {}",
            ph.len(),
            sim.stats()
        );
        assert!(res <= 1e-8, "{name}: energy residual {res:e}");
        assert!(!ph.is_empty(), "{name}: no stick phase");
        for w in ph.windows(2) {
            assert!(w[0].1 < w[1].0, "{name}: {ph:?}");
        }
    }
}

#[test]
fn a_stuck_elastic_line_does_not_slide_and_its_force_stays_within_the_bound() {
    let (samples, exits, worst_sliding) = sample_stuck_lines(
        spur(0.05, FrictionLaw::Coulomb),
        |sim| outputs_match_f(sim, "drive stick"),
        |_| {},
    );
    assert!(
        samples > 20 && exits >= 2,
        "{samples} samples, {exits} exits"
    );
    // Entry tolerance 1e-6 of the rolling speed plus the integration error (measured 2.9e-7).
    assert!(worst_sliding <= 2e-6, "{worst_sliding:e}");
    assert!(worst_sliding <= 0.1 * RELEASE_BAND);
}

#[test]
fn elastic_stick_is_the_limit_of_the_regularised_law() {
    // Law 2 (v / sqrt(v^2 + v_reg^2)) has no stick mode; as v_reg -> 0 its solution must
    // approach the Filippov solution of law 1. Compared: centre positions and TE at the end
    // of 20 ms at 100 rpm and 50 N m, relative to the largest displacement.
    let devs = regularised_law_deviations(
        |law| spur(0.05, law),
        |p| {
            let (sim, changes, _) = run(p, 1e-9, rpm(100.0), 50.0, 0.02, 1e-3);
            (sim, changes)
        },
    );
    assert!(devs.windows(2).all(|w| w[1] < w[0]), "{devs:?}");
    assert!(devs[3] < 0.05 * devs[0] && devs[3] < 1e-5, "{devs:?}");
}

#[test]
fn elastic_stick_instants_do_not_depend_on_the_communication_step() {
    let p = spur(0.3, FrictionLaw::Coulomb);
    let all: Vec<_> = [1e-3, 1e-4, 1e-5]
        .into_iter()
        .map(|h| run(p, 1e-9, rpm(1000.0), 0.0, 0.01, h).1)
        .collect();
    assert!(!all[0].is_empty());
    assert_same_instants(&all);
}

/// A reversed load: the coast flanks carry it, and their lines stick at the coast pitch
/// line (the mirrored pair's, model.md §3.6). Before, the coast lines had no stick mode:
/// 100 rpm with -50 N m stopped after 50 000 internal steps at 9.7 ms. The last case tunes
/// the damper d_phi at 10 ms (the mirrored pair must follow: with its old d_phi the stuck
/// line slid 7e-4 of the rolling speed and the run stalled at 11.3 ms).
#[test]
fn coast_lines_stick_under_a_reversed_load() {
    for (name, law, t_load, tuned_d_phi) in [
        ("law 1, -50 N m", FrictionLaw::Coulomb, -50.0, None),
        ("law 1, -100 N m", FrictionLaw::Coulomb, -100.0, None),
        ("law 3, -50 N m", FrictionLaw::IsoMean, -50.0, None),
        (
            "law 1, -50 N m, d_phi 0 -> 0.5",
            FrictionLaw::Coulomb,
            -50.0,
            Some(0.5),
        ),
    ] {
        let mut p = spur(0.05, law);
        // No damper: its torque would load the drive flanks.
        p.d_phi = 0.0;
        let settings = SolverSettings {
            rtol: 1e-9,
            h_max: 1e-4,
        };
        let init = geared_rotor::sim::Initialization::StaticEquilibrium;
        let mut sim =
            Simulation::with_initialization(p, settings, 0.0, rpm(100.0), t_load, init).unwrap();
        let o0 = sim.outputs();
        let h = 1e-4;
        let (mut changes, mut coast_samples, mut worst_sliding) = (Vec::new(), 0, 0.0f64);
        let mut worst = 0.0f64;
        for k in 0..500 {
            if let (100, Some(d)) = (k, tuned_d_phi) {
                sim.set_d_phi(d).unwrap();
            }
            let r = sim
                .do_step(k as f64 * h, h)
                .unwrap_or_else(|e| panic!("{name}, t = {}: {e}", k as f64 * h));
            changes.extend(r.stick_changes.iter().flatten().map(|c| (c.t, c.stick)));
            let t = sim.time();
            let m = sim.model();
            let o = sim.outputs();
            assert_eq!(o.mesh_state, -1, "{name}: t = {t}");
            if let Some(sliding) = stuck_line_sliding(&sim) {
                assert!(m.stick_flank_is_coast(), "{name}: t = {t}");
                worst_sliding = worst_sliding.max(sliding);
                outputs_match_f(&sim, name);
                coast_samples += 1;
            }
            let supplied = o.e_in + (o.w_mesh_stiffness - o0.w_mesh_stiffness);
            let used = o.e_load + (o.e_kin - o0.e_kin) + (o.e_pot - o0.e_pot) + o.e_loss + o.e_damp;
            worst = worst.max((supplied - used).abs() / o.e_in.abs().max(o.e_load.abs()));
        }
        let ph = phases(&changes);
        println!(
            "{name}: {} coast stick phases, {coast_samples} samples in stick, largest sliding \
             {worst_sliding:.2e} of the rolling speed across a pitch, energy balance {worst:.2e}; {}",
            ph.len(),
            sim.stats()
        );
        assert!(!ph.is_empty() && coast_samples > 5, "{name}: {changes:?}");
        // A stick phase starts with |x0| up to 1e-6 of the rolling speed (the entry
        // tolerance, `sim::stick`) and the relaxation pulls it to zero: 2e-6 bounds that
        // with the integration error (measured <= 9.7e-7).
        assert!(worst_sliding <= 2e-6, "{name}: {worst_sliding:e}");
        assert!(worst <= 1e-8, "{name}: {worst:e}");
    }
}

/// An FMU state taken while a coast line sticks keeps the flank: the copy continues bit
/// for bit like the original (without the flank in the state, the copy would take the
/// stuck line for a drive line).
#[test]
fn a_state_taken_in_a_coast_stick_continues_identically() {
    let mut p = spur(0.05, FrictionLaw::Coulomb);
    p.d_phi = 0.0;
    let settings = SolverSettings {
        rtol: 1e-8,
        h_max: 1e-4,
    };
    let init = geared_rotor::sim::Initialization::StaticEquilibrium;
    let mut sim =
        Simulation::with_initialization(p, settings, 0.0, rpm(100.0), -50.0, init).unwrap();
    let h = 2e-5;
    let mut k = 0;
    while !(sim.model().stick() && sim.model().stick_flank_is_coast()) {
        sim.do_step(k as f64 * h, h).unwrap();
        k += 1;
        assert!(k < 5000, "no coast stick");
    }
    let mut copy = round_trip(&sim);
    assert!(copy.model().stick() && copy.model().stick_flank_is_coast());
    for _ in 0..200 {
        let t = k as f64 * h;
        sim.do_step(t, h).unwrap();
        copy.do_step(t, h).unwrap();
        k += 1;
    }
    let (a, b) = (sim.y(), copy.y());
    for i in 0..a.len() {
        assert_eq!(a[i].to_bits(), b[i].to_bits(), "y[{i}]");
    }
}
