//! Spur pairs: f jumps at the mesh events (a whole contact line enters, leaves or reverses
//! its sliding at once). `Simulation` locates the jumps on the collocation polynomial, lands
//! on them from before and continues with f from after them (docs/fmu.md "Mesh events").
//! Checked against RADAU5 driven directly at a 1000 times tighter tolerance without any
//! event handling (its step-size control alone crosses the jumps), and by the energy
//! balance (model.md §9).

mod common;

use common::rotor::{driven, scaled_dev};
use geared_rotor::gear::GearData;
use geared_rotor::radau5::Radau5;
use geared_rotor::rotor::Params;
use geared_rotor::rotor::RotorProblem;
use geared_rotor::sim::{Simulation, SolverSettings};

const OMEGA1: f64 = 314.159;
const SETTINGS: SolverSettings = SolverSettings {
    rtol: 1e-6,
    h_max: 1e-4,
};

fn spur() -> Params {
    let d = Params::default();
    Params {
        gear: GearData {
            beta: 0.0,
            ..d.gear
        },
        ..d
    }
}

#[test]
fn located_jumps_agree_with_plain_radau5_and_conserve_energy() {
    let (t_end, every): (f64, f64) = (0.02, 1e-3);
    // Reference: plain RADAU5, rtol 1e-9, stop times every 1 ms only.
    let mut model = driven(spur(), OMEGA1);
    let y0 = model.initialize(0.0).unwrap();
    let mut p = RotorProblem { model };
    let tight = SolverSettings {
        rtol: 1e-9,
        ..SETTINGS
    };
    let mut r = Radau5::new(&mut p, tight.options(&geared_rotor::rotor::SCALES), 0.0, y0).unwrap();
    let n = (t_end / every).round() as usize;
    let mut refs = Vec::new();
    for k in 1..=n {
        r.integrate_to(&mut p, k as f64 * every).unwrap();
        refs.push(*r.y());
    }
    // One doStep per 1 ms, and 1e-5 s communication steps.
    for h in [every, 1e-5f64] {
        let mut s = Simulation::new(spur(), SETTINGS, 0.0, OMEGA1, 0.0).unwrap();
        let per = (every / h).round() as usize;
        let mut worst = (0.0f64, 0, 0.0);
        let mut k = 0usize;
        for (j, yr) in refs.iter().enumerate() {
            for _ in 0..per {
                s.do_step(k as f64 * h, h).unwrap();
                k += 1;
            }
            let (d, i) = scaled_dev(s.y(), yr);
            if d > worst.0 {
                worst = (d, i, (j + 1) as f64 * every);
            }
        }
        let st = s.stats();
        println!(
            "H = {h:e}: largest deviation {:.2e} of a scale (component {} at {} s); {st}",
            worst.0, worst.1, worst.2
        );
        // Tolerance 1e-6 over 27 mesh periods with 81 jumps: the helical default reaches
        // 1.6e-4 of a scale against RADAU5 at its own tolerance (tests/sim_lookahead.rs).
        assert!(worst.0 < 1e-3, "H = {h:e}: {worst:?}");
        // Energy balance (model.md §9): what the drive put in is dissipated or stored.
        let o = s.outputs();
        let stored = o.e_kin + o.e_pot;
        let o0 = Simulation::new(spur(), SETTINGS, 0.0, OMEGA1, 0.0)
            .unwrap()
            .outputs();
        let balance = o.e_in - o.e_loss - o.e_damp - o.e_load - (stored - o0.e_kin - o0.e_pot);
        println!(
            "energy balance residual {:.2e} of E_in = {:.4e} J",
            balance / o.e_in,
            o.e_in
        );
        assert!(balance.abs() <= 1e-6 * o.e_in, "residual {balance:e} J");
    }
}
