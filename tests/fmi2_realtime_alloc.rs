//! No heap allocation per doStep in the real-time mode (`h_fixed` > 0): a counting global
//! allocator around SetReal of new inputs + fmi2DoStep + fmi2GetReal after warm-up.

mod common;

use common::alloc::allocations;
use common::fmi2::Fmu;
use geared_rotor::c_abi::*;
use geared_rotor::fmi2::types::Fmi2Status;
use geared_rotor::fmi2::variables::{by_name, Causality, VarType, VARIABLES};

#[global_allocator]
static GLOBAL: common::alloc::Counting = common::alloc::Counting;

#[test]
fn real_time_do_step_does_not_allocate() {
    let f = Fmu::new("alloc_rt", false);
    unsafe {
        assert_eq!(
            fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::OK
        );
        assert_eq!(fmi2EnterInitializationMode(f.c), Fmi2Status::OK);
    }
    assert_eq!(f.set_real("h_fixed", 2.5e-5), Fmi2Status::OK);
    assert_eq!(unsafe { fmi2ExitInitializationMode(f.c) }, Fmi2Status::OK);
    let outs: Vec<u32> = VARIABLES
        .iter()
        .filter(|v| v.causality == Causality::Output && v.ty == VarType::Real)
        .map(|v| v.vr)
        .collect();
    let mut vals = vec![0.0; outs.len()];
    let vrs = [by_name("omega1").unwrap().vr, by_name("T_load").unwrap().vr];
    let h = 1e-4;
    let mut step = |k: usize| {
        let t = k as f64 * h;
        let u = [
            314.159 * (1.0 + 0.01 * (314.0 * t).sin()),
            (314.0 * t).cos(),
        ];
        unsafe {
            assert_eq!(
                fmi2SetReal(f.c, vrs.as_ptr(), 2, u.as_ptr()),
                Fmi2Status::OK
            );
            assert_eq!(fmi2DoStep(f.c, t, h, 1), Fmi2Status::OK);
            assert_eq!(
                fmi2GetReal(f.c, outs.as_ptr(), outs.len(), vals.as_mut_ptr()),
                Fmi2Status::OK
            );
        }
    };
    for k in 0..20 {
        step(k);
    }
    let before = allocations();
    for k in 20..520 {
        step(k);
    }
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} heap allocations in 500 real-time doSteps");
}
