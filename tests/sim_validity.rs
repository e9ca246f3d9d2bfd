//! Leaving the model's validity right at a communication point (`sim::validity`): an input
//! set there that makes Fn negative at once (a negative T_load drives gear 2) is an episode
//! starting at that instant (here -1000 N m, so that Fn < 0 also in the transient). With `on_lift_off = discard` the doStep stops there without
//! stepping past it, so the FMU state taken after the Discard is one the FMU reads back
//! (found by the FMI 3.0 fuzzer: it was refused with "FMU time outside the solver's last
//! step", the stepper having taken a step beyond the instant).

use geared_rotor::bytes::{Reader, Writer};
use geared_rotor::rotor::Params;
use geared_rotor::sim::{Input, OnViolation, SimError, SimState, Simulation, SolverSettings};

#[test]
fn a_discard_at_the_start_of_a_step_leaves_a_state_that_reads_back() {
    let settings = SolverSettings {
        rtol: 1e-6,
        h_max: 1e-4,
    };
    for t0 in [0.0, 1e-3] {
        let mut sim = Simulation::new(Params::default(), settings, 0.0, 314.159, 0.0).unwrap();
        sim.set_on_violation(OnViolation::Discard);
        if t0 > 0.0 {
            sim.do_step(0.0, t0).unwrap();
        }
        sim.set_input(Input::TLoad, -1000.0).unwrap();
        let e = sim.do_step(t0, 1e-4).unwrap_err();
        assert!(matches!(e, SimError::Validity(_)), "{e}");
        assert_eq!(sim.last_successful_time(), t0);
        assert_eq!(sim.time(), t0);
        assert_eq!(sim.stepper_time(), t0, "the stepper stays at the instant");
        assert!(sim.outputs().fn_ < 0.0);
        let mut w = Writer::default();
        sim.state().write(&mut w);
        let st = SimState::read(&mut Reader::new(&w.buf)).unwrap();
        st.validate().unwrap();
        let back = Simulation::from_state(&st).unwrap();
        assert_eq!(back.time(), t0);
    }
}
