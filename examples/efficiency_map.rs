//! Efficiency map of the default pair per friction law (not a test): speed x load torque,
//! efficiency `1 - <P_loss>/<P_in>` over whole mesh periods in the steady state, from the
//! energy accumulators E_loss, E_in of a `Simulation` (RADAU5, rtol 1e-8).
//! Run: `cargo run --release --example efficiency_map [settle_periods] [avg_periods]`
//! (`EFFICIENCY_LAWS=1,5` for a subset of the laws 1-5, `EFFICIENCY_V_REG=0.001` for
//! another v_reg).

use geared_rotor::gear::FrictionLaw;
use geared_rotor::rotor::{idx, Params};
use geared_rotor::sim::{Simulation, SolverSettings};
use std::f64::consts::PI;
use std::time::Instant;

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let settle = *args.first().unwrap_or(&60);
    let avg = *args.get(1).unwrap_or(&20);
    let settings = SolverSettings {
        rtol: 1e-8,
        h_max: 1e-4,
    };
    let rpms = [1500.0, 2000.0, 2500.0, 3000.0];
    let loads = [0.0, 25.0, 50.0, 100.0];
    println!("settle {settle} mesh periods, average over {avg}; rows: speed [rpm], columns: T_load [N m]");
    // `EFFICIENCY_LAWS=5` (or e.g. `1,5`): only these law codes; default all five.
    let codes: Vec<i32> = std::env::var("EFFICIENCY_LAWS")
        .ok()
        .map(|v| v.split(',').filter_map(|c| c.trim().parse().ok()).collect())
        .unwrap_or_else(|| (1..=5).collect());
    for law in codes.into_iter().filter_map(FrictionLaw::from_code) {
        let mut p = Params {
            friction_law: law,
            ..Params::default()
        };
        // `EFFICIENCY_V_REG=0.001`: law 2's regularising speed and law 5's bound (m/s).
        if let Some(v) = std::env::var("EFFICIENCY_V_REG")
            .ok()
            .and_then(|v| v.parse().ok())
        {
            p.friction.v_reg = v;
        }
        let t0 = Instant::now();
        println!(
            "\nlaw {} ({law:?}): efficiency [%] / mean mu_eff",
            law.code()
        );
        print!("{:>6}", "rpm");
        for l in loads {
            print!(" | {:>9.0} N m          ", l);
        }
        println!();
        for rpm in rpms {
            let omega1 = rpm * PI / 30.0;
            let tm = 2.0 * PI / (27.0 * omega1);
            print!("{rpm:>6.0}");
            for t_load in loads {
                let mut s = Simulation::new(p, settings, 0.0, omega1, t_load).expect("start");
                let mut t = 0.0;
                for k in 1..=settle {
                    let te = k as f64 * tm;
                    s.do_step(t, te - t).expect("settle");
                    t = te;
                }
                let a = *s.y();
                let mut mu_sum = 0.0;
                let n_sub = 8;
                for k in 1..=(avg * n_sub) {
                    let te = (settle as f64 + k as f64 / n_sub as f64) * tm;
                    s.do_step(t, te - t).expect("average");
                    t = te;
                    mu_sum += s.outputs().mu_eff;
                }
                let b = *s.y();
                let e_in = b[idx::E_IN] - a[idx::E_IN];
                let e_loss = b[idx::E_LOSS] - a[idx::E_LOSS];
                let eta = 1.0 - e_loss / e_in;
                print!(
                    " | {:>9.5} % {:>8.5}",
                    100.0 * eta,
                    mu_sum / (avg * n_sub) as f64
                );
            }
            println!();
        }
        println!("({:.1} s CPU for this law)", t0.elapsed().as_secs_f64());
    }
}
