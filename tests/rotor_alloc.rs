//! Test 7 (issue 2): f(t, y) (and the Jacobian) allocate nothing. A counting global
//! allocator counts the allocations of this thread while a closure runs.

mod common;

use common::alloc::count;
use geared_rotor::rotor::{idx, GearedRotor, Inputs, Params, NY};
use nalgebra::{SMatrix, SVector};

#[global_allocator]
static GLOBAL: common::alloc::Counting = common::alloc::Counting;

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

/// The same for the elastic contact (docs/model.md §3.5): f, its chain-rule Jacobian, the
/// fast part of its split and the outputs allocate nothing, in contact and in free flight.
#[test]
fn elastic_rhs_does_not_allocate() {
    for beta in [20f64.to_radians(), 0.0] {
        let mut p = Params::default();
        p.gear.beta = beta;
        p.tooth_contact = geared_rotor::rotor::ToothContact::Elastic;
        let mut model = GearedRotor::new(p).unwrap();
        model.set_inputs(Inputs {
            omega1: 314.159,
            t_load: 50.0,
            ..Inputs::default()
        });
        let (ic, _) = model.static_equilibrium(0.0, 0.0).unwrap();
        let y0 = model.initialize_with(0.0, &ic).unwrap();
        let mut f = SVector::<f64, NY>::zeros();
        let n = count(|| {
            for i in 0..5000 {
                let mut y = y0;
                y[idx::PHI1] = i as f64 * 1e-3;
                y[idx::V] = 1e-3 * (i as f64).sin();
                // Every other call in free flight (gear 2 ahead by 0.1 mm).
                if i % 2 == 1 {
                    y[idx::Q + 6] += 1e-4;
                }
                model.rhs(1e-4 * i as f64, &y, &mut f).unwrap();
                std::hint::black_box(&f);
            }
        });
        assert_eq!(n, 0, "elastic rhs allocated {n} times in 5000 calls");
        let mut jac = SMatrix::<f64, NY, NY>::zeros();
        let n = count(|| {
            for i in 0..200 {
                let mut y = y0;
                y[idx::PHI1] = i as f64 * 1e-3;
                y[idx::V] = 1e-3 * (i as f64).sin();
                if i % 2 == 1 {
                    y[idx::Q + 6] += 1e-4;
                }
                assert!(model.jacobian(0.0, &y, &mut jac));
                std::hint::black_box(&jac);
                // The fast part of the split Jacobian (radau5.md §8).
                assert!(model.jacobian_fast(0.0, &y, &mut jac));
                std::hint::black_box(&jac);
            }
        });
        assert_eq!(
            n, 0,
            "elastic jacobian (or its fast part) allocated {n} times"
        );
        let n = count(|| {
            std::hint::black_box(model.outputs(0.0, &y0));
        });
        assert_eq!(n, 0, "elastic outputs allocated {n} times");
    }
}
