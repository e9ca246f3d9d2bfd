//! No heap allocation per step: a counting global allocator (per thread) around
//! fmi2DoStep + fmi2GetReal after warm-up, with logging off, for small communication steps
//! (about one internal step each), a long step (many internal steps) and held input changes.

mod common;

use common::alloc::allocations;
use common::fmi2::Fmu;
use geared_rotor::fmi2::types::Fmi2Status;

#[global_allocator]
static GLOBAL: common::alloc::Counting = common::alloc::Counting;

#[test]
fn do_step_and_get_real_do_not_allocate() {
    let f = Fmu::new("alloc", false);
    f.init();
    let h = 1e-5;
    let mut t = 0.0;
    for _ in 0..20 {
        assert_eq!(f.step(t, h), Fmi2Status::OK);
        t += h;
    }
    let outs: Vec<u32> = geared_rotor::fmi2::variables::VARIABLES
        .iter()
        .filter(|v| {
            v.causality == geared_rotor::fmi2::variables::Causality::Output
                && v.ty == geared_rotor::fmi2::variables::VarType::Real
        })
        .map(|v| v.vr)
        .collect();
    let mut vals = vec![0.0; outs.len()];
    let omega1 = geared_rotor::fmi2::variables::by_name("omega1").unwrap().vr;
    let before = allocations();
    for k in 0..500 {
        assert_eq!(f.step(t, h), Fmi2Status::OK);
        t += h;
        let st = unsafe {
            geared_rotor::c_abi::fmi2GetReal(f.c, outs.as_ptr(), outs.len(), vals.as_mut_ptr())
        };
        assert_eq!(st, Fmi2Status::OK);
        // A master re-setting an unchanged input, and a held input step every 100 steps.
        // (316, not 320 rad/s: the step down from 320 during the start transient lifts the
        // teeth off at 4.45 ms, Fn down to -128 N, which the FMU now reports with
        // fmi2Warning and a message.)
        let w = if (k / 100) % 2 == 0 { 314.159 } else { 316.0 };
        let st = unsafe { geared_rotor::c_abi::fmi2SetReal(f.c, &omega1, 1, &w) };
        assert_eq!(st, Fmi2Status::OK);
    }
    // One long communication step (many internal steps).
    assert_eq!(f.step(t, 2e-3), Fmi2Status::OK);
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} heap allocations in 501 doSteps");
    assert!(f.messages().is_empty());
}
