//! Benchmark (not a test): median time of one f(t, y) and one Jacobian evaluation for the
//! default pair, per friction law (1 Coulomb, 2 regularised, 3 ISO/TR 14179-2 mean, 4 local
//! EHL, 5 Benedict & Kelley), and of one consistent lambda (a closed form for laws 1-2, a
//! scalar solve for 3-5). `GEAR_BENCH_LAWS=1,5` times a subset.
//! Three sets of states over one mesh period: the static equilibrium at 64 phases (`rhs`),
//! the same with an imposed axial vibration (`rhs_moving`), and 64 states of a simulated
//! run (`rhs_run`, see [`run_states`]), whose small axial sliding from the bearings and the
//! transmission error is what law 4's quadrature meets in practice.
//! Run: `cargo run --release --example gear_bench`.

use geared_rotor::gear::FrictionLaw;
use geared_rotor::rotor::{GearedRotor, Inputs, Params, NY};
use geared_rotor::sim::{Simulation, SolverSettings};
use nalgebra::{SMatrix, SVector};
use std::hint::black_box;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Median seconds per call of `f(r)` (r = 0, 1, ...) over `rounds` rounds of `reps` calls.
fn time_per_call(rounds: usize, reps: usize, mut f: impl FnMut(usize)) -> f64 {
    let mut samples = Vec::with_capacity(rounds);
    for _ in 0..rounds {
        let t0 = Instant::now();
        for r in 0..reps {
            f(r);
        }
        samples.push(t0.elapsed().as_secs_f64() / reps as f64);
    }
    median(samples)
}

fn main() {
    // `gear_bench count LAW WHAT N`: exactly N evaluations (WHAT = rhs, rhs_moving,
    // rhs_run, jacobian or lambda, the consistent lambda) for instruction counting
    // (valgrind --tool=callgrind), no timing. rhs_run simulates its states first: count
    // with N and 0 and take the difference.
    let args: Vec<String> = std::env::args().collect();
    if args.len() == 5 && args[1] == "count" {
        let law = FrictionLaw::from_code(args[2].parse().expect("law code")).expect("law 1-5");
        let n: usize = args[4].parse().expect("N");
        count(
            Params {
                friction_law: law,
                ..Params::default()
            },
            &args[3],
            n,
        );
        return;
    }
    // `GEAR_BENCH_LAWS=1,5`: only these law codes; default all five.
    let codes: Vec<i32> = std::env::var("GEAR_BENCH_LAWS")
        .ok()
        .map(|v| v.split(',').filter_map(|c| c.trim().parse().ok()).collect())
        .unwrap_or_else(|| (1..=5).collect());
    for law in codes.into_iter().filter_map(FrictionLaw::from_code) {
        println!("friction law {} ({law:?})", law.code());
        bench(Params {
            friction_law: law,
            ..Params::default()
        });
    }
}

fn bench(params: Params) {
    let mut model = GearedRotor::new(params).expect("default parameters are valid");
    // States spread over one mesh period so that every contact configuration is timed.
    let still = states(&mut model, false);
    let o = model.outputs(0.0, &still[0]);
    println!(
        "initial: lambda = {:.3} N, T1 = {:.4} N m, omega2 = {:.4}, l = {:.6} m, pairs = {}, u1 = {:?}",
        o.fn_, o.t1, o.omega2, o.contact_length, o.pairs_in_contact, o.u1
    );
    // The same states with axial vibration: sliding along the lines, y != 0, which law 4
    // integrates with its axial-sliding rule.
    let moving = states(&mut model, true);
    let run = run_states(params);
    let mut f = SVector::<f64, NY>::zeros();
    let reps = 2000;
    for (label, ys) in [
        ("rhs", &still),
        ("rhs with axial sliding", &moving),
        ("rhs on run states", &run),
    ] {
        let per_call = time_per_call(200, reps, |r| {
            let y = &ys[r % ys.len()];
            model.rhs(0.0, black_box(y), &mut f).expect("rhs");
            black_box(&f);
        });
        println!(
            "{label}: median {:.1} ns per evaluation (200 x {reps} reps)",
            per_call * 1e9
        );
    }
    let mut jac = SMatrix::<f64, NY, NY>::zeros();
    let reps = 200;
    let per_call = time_per_call(100, reps, |r| {
        let y = &still[r % still.len()];
        assert!(model.jacobian(0.0, black_box(y), &mut jac));
        black_box(&jac);
    });
    println!(
        "jacobian: median {:.2} us per evaluation (100 x {reps} reps)",
        per_call * 1e6
    );
    let reps = 2000;
    let per_call = time_per_call(50, reps, |r| {
        let y = &still[r % still.len()];
        black_box(model.consistent_lambda(0.0, black_box(y)).expect("lambda"));
    });
    println!(
        "consistent lambda: median {:.1} ns per evaluation (50 x {reps} reps)",
        per_call * 1e9
    );
}

/// The default state over one mesh period (64 phases), optionally with axial vibration.
fn states(model: &mut GearedRotor, moving: bool) -> Vec<SVector<f64, NY>> {
    model.set_inputs(Inputs {
        omega1: OMEGA1,
        ..Inputs::default()
    });
    let (ic, _) = model
        .static_equilibrium(0.0, 0.0)
        .expect("static equilibrium");
    let y0 = model.initialize_with(0.0, &ic).expect("initial state");
    (0..64)
        .map(|i| {
            let mut y = y0;
            y[geared_rotor::rotor::idx::PHI1] = i as f64 * 2.0 * std::f64::consts::PI / 27.0 / 64.0;
            if moving {
                y[geared_rotor::rotor::idx::V + 2] = 0.05;
                y[geared_rotor::rotor::idx::V + 5] = -0.05;
            }
            y
        })
        .collect()
}

/// Operating speed of the runs (rad/s).
const OMEGA1: f64 = 314.159;

/// 64 states over one mesh period of a simulated run of the pair (from rest at OMEGA1,
/// T_load = 0, RADAU5 at the FMU's default rtol 1e-6 and h_max 1e-4 s), after 0.2 s: the
/// bearings and the transmission error then move the gears a little, so the lines carry a
/// small axial sliding (y != 0, far below the sliding at the tips), as in every real run.
fn run_states(params: Params) -> Vec<SVector<f64, NY>> {
    let settings = SolverSettings {
        rtol: 1e-6,
        h_max: 1e-4,
    };
    let mut sim = Simulation::new(params, settings, 0.0, OMEGA1, 0.0).expect("start");
    let t_settle = 0.2;
    sim.do_step(0.0, t_settle).expect("settle");
    // one mesh period: the pitch angle of gear 1 at OMEGA1
    let period = sim.model().geometry().phi1_period / OMEGA1;
    let mut t = t_settle;
    (0..64)
        .map(|_| {
            sim.do_step(t, period / 64.0).expect("step");
            t = sim.time();
            *sim.y()
        })
        .collect()
}

fn count(params: Params, what: &str, n: usize) {
    let mut model = GearedRotor::new(params).expect("default parameters are valid");
    let ys = if what == "rhs_run" {
        model.set_inputs(Inputs {
            omega1: OMEGA1,
            ..Inputs::default()
        });
        run_states(params)
    } else {
        states(&mut model, what == "rhs_moving")
    };
    let mut f = SVector::<f64, NY>::zeros();
    let mut jac = SMatrix::<f64, NY, NY>::zeros();
    for r in 0..n {
        let y = &ys[r % ys.len()];
        if what == "jacobian" {
            assert!(model.jacobian(0.0, black_box(y), &mut jac));
            black_box(&jac);
        } else if what == "lambda" {
            black_box(model.consistent_lambda(0.0, black_box(y)).expect("lambda"));
        } else {
            model.rhs(0.0, black_box(y), &mut f).expect("rhs");
            black_box(&f);
        }
    }
}
