//! Set-up shared by the stick tests (tests/sim_stick.rs, rigid teeth; tests/sim_stick_elastic.rs,
//! elastic teeth): the spur pair, speeds, stick phases and FMU-state round trips.

use geared_rotor::gear::{FrictionLaw, GearData};
use geared_rotor::rotor::Params;
use geared_rotor::sim::{Simulation, SolverSettings};
use std::f64::consts::PI;

/// The default pair made spur (beta = 0), with the friction coefficient and law given.
pub fn spur(mu: f64, law: FrictionLaw) -> Params {
    let d = Params::default();
    Params {
        gear: GearData {
            beta: 0.0,
            ..d.gear
        },
        mu,
        friction_law: law,
        ..d
    }
}

/// rpm in rad/s.
pub fn rpm(n: f64) -> f64 {
    n * PI / 30.0
}

/// Stick phases as (start, end) pairs; changes alternate, starting with a stick.
pub fn phases(changes: &[(f64, bool)]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut start = None;
    for &(t, stick) in changes {
        match (stick, start) {
            (true, None) => start = Some(t),
            (false, Some(s)) => {
                out.push((s, t));
                start = None;
            }
            _ => panic!("changes do not alternate: {changes:?}"),
        }
    }
    out
}

/// Serialises the simulation's state, reads it back, validates it and rebuilds from it.
pub fn round_trip(sim: &Simulation) -> Simulation {
    use geared_rotor::bytes::{Reader, Writer};
    use geared_rotor::sim::SimState;
    let mut w = Writer::default();
    sim.state().write(&mut w);
    let mut r = Reader::new(&w.buf);
    let st = SimState::read(&mut r).unwrap_or_else(|e| panic!("t = {}: {e}", sim.time()));
    st.validate()
        .unwrap_or_else(|e| panic!("t = {}: {e}", sim.time()));
    Simulation::from_state(&st).unwrap()
}

/// The end states' deviation of the regularised law 2 (v / sqrt(v^2 + v_reg^2), no stick
/// mode) from the Filippov solution of law 1, for v_reg = 1e-3, 1e-4, 1e-5, 1e-6 m/s: the
/// largest deviation of the centre positions and TE, relative to the largest displacement
/// of the law-1 run. `pair(law)` is the pair with that law; `run` integrates it and returns
/// the simulation and its stick changes (the law-1 run must have at least three phases).
pub fn regularised_law_deviations(
    pair: impl Fn(FrictionLaw) -> Params,
    run: impl Fn(Params) -> (Simulation, Vec<(f64, bool)>),
) -> Vec<f64> {
    let (stick, changes) = run(pair(FrictionLaw::Coulomb));
    assert!(phases(&changes).len() >= 3, "{changes:?}");
    let ys = *stick.y();
    let scale = (0..6).map(|i| ys[i].abs()).fold(0.0, f64::max);
    let mut devs = Vec::new();
    for v_reg in [1e-3, 1e-4, 1e-5, 1e-6] {
        let mut p = pair(FrictionLaw::RegularisedCoulomb);
        p.friction.v_reg = v_reg;
        let (reg, _) = run(p);
        let yr = *reg.y();
        let dev = (0..7).map(|i| (yr[i] - ys[i]).abs()).fold(0.0, f64::max) / scale;
        println!(
            "v_reg = {v_reg:e} m/s: largest deviation of u, TE {dev:.3e} of the largest \
             displacement; {}",
            reg.stats()
        );
        devs.push(dev);
    }
    devs
}

/// Asserts that runs with different communication steps report the same stick changes,
/// their instants within 1e-9 s.
pub fn assert_same_instants(all: &[Vec<(f64, bool)>]) {
    println!("{:?}", all[0]);
    for other in &all[1..] {
        assert_eq!(other.len(), all[0].len(), "{all:?}");
        for (a, b) in all[0].iter().zip(other) {
            assert_eq!(a.1, b.1);
            assert!((a.0 - b.0).abs() <= 1e-9, "{a:?} vs {b:?}");
        }
    }
}

/// While a line sticks at the simulation's point: its sliding as a fraction of the rolling
/// speed across a base pitch, after checking that its force lies within the bound (4.15)
/// to 1e-6 of |F_w|; None while no line sticks.
#[allow(dead_code)]
pub fn stuck_line_sliding(sim: &Simulation) -> Option<f64> {
    let (t, y) = (sim.time(), *sim.y());
    let m = sim.model();
    if !m.stick() {
        return None;
    }
    let rolling = (y[15] + y[13]).abs() * m.geometry().p_bt;
    let x0 = m.pitch_line_sliding(t, &y).unwrap();
    let (margin, f_w) = m.stick_state(t, &y).unwrap();
    assert!(
        margin >= -1e-6 * f_w.abs(),
        "t = {t}: margin {margin} N, F_w {f_w} N"
    );
    Some(x0.abs() / rolling)
}

/// The stuck-line check of both contacts: `p` at 100 rpm with 50 N m (long stick phases,
/// ~0.2 ms), rtol 1e-8, sampled in 2000 doSteps of 5 us. While a line sticks: its sliding
/// (as a fraction of the rolling speed across a base pitch) is recorded and its force must
/// lie within the bound (4.15) to 1e-6 of |F_w|; `each_stuck` runs there too, and
/// `each_exit` after every doStep that reported an exit. Returns the samples in stick, the
/// exits and the largest sliding.
#[allow(dead_code)]
pub fn sample_stuck_lines(
    p: Params,
    mut each_stuck: impl FnMut(&Simulation),
    mut each_exit: impl FnMut(&Simulation),
) -> (usize, usize, f64) {
    let settings = SolverSettings {
        rtol: 1e-8,
        h_max: 1e-4,
    };
    let mut sim = Simulation::new(p, settings, 0.0, rpm(100.0), 50.0).unwrap();
    let h = 5e-6;
    let (mut samples, mut exits) = (0, 0);
    let mut worst_sliding = 0.0f64;
    for k in 0..2000 {
        let r = sim.do_step(k as f64 * h, h).unwrap();
        if let Some(sliding) = stuck_line_sliding(&sim) {
            worst_sliding = worst_sliding.max(sliding);
            each_stuck(&sim);
            samples += 1;
        }
        for _ in r.stick_changes.iter().flatten().filter(|c| !c.stick) {
            exits += 1;
            each_exit(&sim);
        }
    }
    println!(
        "{samples} samples in stick, {exits} exits, largest sliding {worst_sliding:.2e} of \
         the rolling speed across a pitch"
    );
    (samples, exits, worst_sliding)
}
