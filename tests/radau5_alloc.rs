//! No heap allocation after construction (issue 3; practices: "no heap allocation per
//! step"): a counting global allocator around stepping, stop times, dense output,
//! snapshot/restore and restart.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use geared_rotor::radau5::test_problems::{Amplifier1t, Pendulum2, VanDerPol};
use geared_rotor::radau5::{Options, Radau5, Tolerance};
use nalgebra::SVector;

struct Counting;

thread_local! {
    static ALLOCS: Cell<u64> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.with(|c| c.set(c.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCS.with(|c| c.set(c.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> u64 {
    ALLOCS.with(Cell::get)
}

fn o<const N: usize>(tol: f64) -> Options<N> {
    Options {
        rtol: Tolerance::Scalar(tol),
        atol: Tolerance::Scalar(tol),
        ..Options::default()
    }
}

#[test]
fn stepping_allocates_nothing() {
    // the counter does count
    let c0 = allocations();
    let v = std::hint::black_box(vec![1u8; 16]);
    assert!(allocations() > c0 && v.len() == 16);
    // ODE, identity mass
    let mut p = VanDerPol { eps: 1e-6 };
    let mut s = Radau5::new(&mut p, o(1e-6), 0.0, SVector::<f64, 2>::new(2.0, 0.0)).unwrap();
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
    let mut s = Radau5::new(&mut p, o(1e-6), 0.0, y0).unwrap();
    let before = allocations();
    s.integrate_to(&mut p, 0.05).unwrap();
    assert_eq!(
        allocations() - before,
        0,
        "allocations while stepping (amp1t)"
    );

    // index-2 DAE
    let g = 9.81;
    let mut p = Pendulum2 { g };
    let y0 = SVector::<f64, 5>::new(1.0f64.sin(), -(1.0f64.cos()), 0.0, 0.0, g * 1.0f64.cos());
    let mut s = Radau5::new(
        &mut p,
        Options {
            n1: 4,
            n2: 1,
            ..o(1e-6)
        },
        0.0,
        y0,
    )
    .unwrap();
    let before = allocations();
    s.integrate_to(&mut p, 3.0).unwrap();
    assert_eq!(
        allocations() - before,
        0,
        "allocations while stepping (pend2)"
    );
}
