//! Set-up shared by the stick tests (tests/sim_stick.rs, rigid teeth; tests/sim_stick_elastic.rs,
//! elastic teeth): the spur pair, speeds, stick phases and FMU-state round trips.

use geared_rotor::gear::{FrictionLaw, GearData};
use geared_rotor::rotor::Params;
use geared_rotor::sim::Simulation;
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
