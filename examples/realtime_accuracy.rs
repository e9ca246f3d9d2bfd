//! Accuracy of the real-time mode (`h_fixed`) against the adaptive mode (issue 11): the
//! default pair driven by omega1 = 314.159 (1 + 0.01 sin(2 pi 50 t)) held at every
//! communication point, 0..0.2 s, every run compared at every point with an adaptive run at
//! rtol 1e-8 driven by the same input. Printed: max |dT1| / mean T1_ref, max |dFn| / mean
//! Fn_ref, max |dTE| / max |TE_ref|, max energy-balance residual / E_in, and the work.
//!
//! Run: `cargo run --release --example realtime_accuracy`.

use geared_rotor::rotor::{Outputs, Params};
use geared_rotor::sim::{Input, Simulation, SolverSettings};
use std::f64::consts::PI;

const W0: f64 = 314.159;
const T_END: f64 = 0.2;

fn sim(rtol: f64, h_fixed: f64) -> Simulation {
    let mut s = Simulation::new(
        Params::default(),
        SolverSettings { rtol, h_max: 1e-4 },
        0.0,
        W0,
        0.0,
    )
    .expect("default case");
    s.set_h_fixed(h_fixed).expect("h_fixed");
    s
}

fn trajectory(rtol: f64, h_fixed: f64, h: f64) -> Result<(Vec<Outputs>, f64, u64), String> {
    let mut s = sim(rtol, h_fixed);
    let o0 = s.outputs();
    let e0 = o0.e_kin + o0.e_pot;
    let mut out = Vec::new();
    let mut energy = 0.0f64;
    for k in 0..(T_END / h).round() as usize {
        let t = k as f64 * h;
        s.set_input(
            Input::Omega1,
            W0 * (1.0 + 0.01 * (2.0 * PI * 50.0 * t).sin()),
        )
        .map_err(|e| e.to_string())?;
        s.do_step(t, h).map_err(|e| e.to_string())?;
        let o = s.outputs();
        energy = energy.max(
            ((o.e_in - o.e_loss - o.e_damp - o.e_load - (o.e_kin + o.e_pot - e0)) / o.e_in).abs(),
        );
        out.push(o);
    }
    Ok((out, energy, s.stats().nfcn))
}

fn main() {
    println!("default pair, omega1 changing at every point, 0..{T_END} s, reference: adaptive rtol 1e-8 with the same input");
    println!(
        "{:>7} {:>22} {:>11} {:>11} {:>11} {:>11} {:>9}",
        "H [s]", "mode", "dT1/T1", "dFn/Fn", "dTE/TE", "energy", "nfcn"
    );
    for h in [1e-4, 1e-5] {
        let (r, _, _) = trajectory(1e-8, 0.0, h).expect("reference");
        let n = r.len() as f64;
        let mean_t1 = r.iter().map(|o| o.t1).sum::<f64>() / n;
        let mean_fn = r.iter().map(|o| o.fn_).sum::<f64>() / n;
        let max_te = r.iter().map(|o| o.te.abs()).fold(0.0, f64::max);
        let mut modes = vec![("adaptive rtol 1e-6".to_string(), 1e-6, 0.0)];
        for hf in [1e-5, 2.5e-5, 5e-5, 1e-4] {
            if hf <= h * (1.0 + 1e-12) || hf < 2.0 * h {
                modes.push((format!("h_fixed {hf:e}"), 1e-6, hf));
            }
        }
        for (name, rtol, hf) in modes {
            match trajectory(rtol, hf, h) {
                Ok((a, energy, nfcn)) => {
                    let d = |f: fn(&Outputs) -> f64| {
                        a.iter()
                            .zip(&r)
                            .map(|(x, y)| (f(x) - f(y)).abs())
                            .fold(0.0, f64::max)
                    };
                    println!(
                        "{h:>7.0e} {name:>22} {:>11.2e} {:>11.2e} {:>11.2e} {:>11.2e} {:>9}",
                        d(|o| o.t1) / mean_t1,
                        d(|o| o.fn_) / mean_fn,
                        d(|o| o.te) / max_te,
                        energy,
                        nfcn
                    );
                }
                Err(e) => println!("{h:>7.0e} {name:>22} failed: {e}"),
            }
        }
    }
}
