//! No heap allocation after construction (issue 3; practices: "no heap allocation per
//! step"): a counting global allocator around stepping, stop times, dense output,
//! snapshot/restore and restart.

mod common;

use common::alloc::allocations;
use common::radau5::{opts, pendulum2, pendulum2_opts};
use common::radau5_problems::{Amplifier1t, VanDerPol};
use geared_rotor::radau5::Radau5;
use nalgebra::SVector;

#[global_allocator]
static GLOBAL: common::alloc::Counting = common::alloc::Counting;

#[test]
fn stepping_allocates_nothing() {
    // the counter does count
    let c0 = allocations();
    let v = std::hint::black_box(vec![1u8; 16]);
    assert!(allocations() > c0 && v.len() == 16);
    // ODE, identity mass
    let mut p = VanDerPol { eps: 1e-6 };
    let mut s = Radau5::new(&mut p, opts(1e-6), 0.0, SVector::<f64, 2>::new(2.0, 0.0)).unwrap();
    let snap = s.snapshot();
    let before = allocations();
    let mut u = SVector::zeros();
    for k in 1..=200 {
        s.integrate_to(&mut p, 0.01 * f64::from(k)).unwrap();
        s.dense_output(s.t_prev(), &mut u);
        s.dense_derivative(s.t(), &mut u);
    }
    s.restore(&snap);
    s.integrate_to(&mut p, 0.5).unwrap();
    let y = *s.y();
    s.restart(&mut p, y, Some(1e-4)).unwrap();
    s.integrate_to(&mut p, 1.0).unwrap();
    assert_eq!(
        allocations() - before,
        0,
        "allocations while stepping (vdp)"
    );

    // index-1 DAE with a full mass matrix
    let mut p = Amplifier1t;
    let y0 = SVector::<f64, 5>::new(0.0, 3.0, 3.0, 6.0, 0.0);
    let mut s = Radau5::new(&mut p, opts(1e-6), 0.0, y0).unwrap();
    let before = allocations();
    s.integrate_to(&mut p, 0.05).unwrap();
    assert_eq!(
        allocations() - before,
        0,
        "allocations while stepping (amp1t)"
    );

    // index-2 DAE
    let (mut p, y0) = pendulum2();
    let mut s = Radau5::new(&mut p, pendulum2_opts(1e-6), 0.0, y0).unwrap();
    let before = allocations();
    s.integrate_to(&mut p, 3.0).unwrap();
    assert_eq!(
        allocations() - before,
        0,
        "allocations while stepping (pend2)"
    );
}
