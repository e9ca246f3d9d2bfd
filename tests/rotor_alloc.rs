//! Test 7 (issue 2): f(t, y) (and the Jacobian) allocate nothing. A counting global
//! allocator counts the allocations of this thread while enabled.

use geared_rotor::rotor::{idx, GearedRotor, Inputs, Params, NY};
use nalgebra::{SMatrix, SVector};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ENABLED: Cell<bool> = const { Cell::new(false) };
    static COUNT: Cell<u64> = const { Cell::new(0) };
}

fn bump() {
    let _ = ENABLED.try_with(|e| {
        if e.get() {
            let _ = COUNT.try_with(|c| c.set(c.get() + 1));
        }
    });
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        bump();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        bump();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        bump();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn count<F: FnOnce()>(f: F) -> u64 {
    COUNT.with(|c| c.set(0));
    ENABLED.with(|e| e.set(true));
    f();
    ENABLED.with(|e| e.set(false));
    COUNT.with(|c| c.get())
}

#[test]
fn rhs_and_jacobian_do_not_allocate() {
    // the counter itself works
    assert!(count(|| drop(std::hint::black_box(vec![1u8; 16]))) >= 1);
    for beta in [20f64.to_radians(), 0.0] {
        let mut p = Params::default();
        p.gear.beta = beta;
        let mut model = GearedRotor::new(p).unwrap();
        model.set_inputs(Inputs {
            omega1: 314.159,
            t_load: 50.0,
            ..Inputs::default()
        });
        let (ic, _) = model.static_equilibrium(0.0, 0.0).unwrap();
        let y0 = model.initialize_with(0.0, &ic).unwrap();
        let mut f = SVector::<f64, NY>::zeros();
        let mut jac = SMatrix::<f64, NY, NY>::zeros();
        let n = count(|| {
            for i in 0..5000 {
                let mut y = y0;
                y[idx::PHI1] = i as f64 * 1e-3;
                y[idx::V] = 1e-3 * (i as f64).sin();
                model.rhs(1e-4 * i as f64, &y, &mut f).unwrap();
                std::hint::black_box(&f);
            }
        });
        assert_eq!(n, 0, "rhs allocated {n} times in 5000 calls");
        let n = count(|| {
            for i in 0..200 {
                let mut y = y0;
                y[idx::PHI1] = i as f64 * 1e-3;
                assert!(model.jacobian(0.0, &y, &mut jac));
                std::hint::black_box(&jac);
            }
        });
        assert_eq!(n, 0, "jacobian allocated {n} times");
        let n = count(|| {
            std::hint::black_box(model.outputs(0.0, &y0));
        });
        assert_eq!(n, 0, "outputs allocated {n} times");
    }
}
