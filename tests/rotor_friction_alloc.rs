//! f(t, y), the Jacobian, the consistent lambda (a scalar solve for laws 3 and 4) and the
//! outputs allocate nothing, for every friction law (counting global allocator).

mod common;

use common::alloc::count;
use geared_rotor::rotor::{idx, GearedRotor, Inputs, Params, NY};
use nalgebra::{SMatrix, SVector};

#[global_allocator]
static GLOBAL: common::alloc::Counting = common::alloc::Counting;

#[test]
fn every_law_evaluates_without_allocation() {
    assert!(count(|| drop(std::hint::black_box(vec![1u8; 16]))) >= 1);
    for law in common::rotor::LAWS {
        for beta in [20f64.to_radians(), 0.0] {
            let mut p = Params {
                friction_law: law,
                ..Params::default()
            };
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
                for i in 0..500 {
                    let mut y = y0;
                    y[idx::PHI1] = i as f64 * 1e-3;
                    y[idx::V + 2] = 1e-3 * (i as f64).sin();
                    model.rhs(0.0, &y, &mut f).unwrap();
                    std::hint::black_box(model.consistent_lambda(0.0, &y).unwrap());
                    std::hint::black_box(model.outputs_consistent(0.0, &y));
                }
                for i in 0..20 {
                    let mut y = y0;
                    y[idx::PHI1] = i as f64 * 1e-3;
                    assert!(model.jacobian(0.0, &y, &mut jac));
                }
            });
            assert_eq!(n, 0, "law {law:?}, beta {beta}: {n} allocations");
        }
    }
}
