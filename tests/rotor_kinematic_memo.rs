//! The model memoises the mesh and the friction sums of the last kinematic state
//! (`src/rotor/dae/memo.rs`). Whatever was evaluated before, f, the consistent lambda and
//! the outputs of a state must be bit for bit those of a model that never saw another
//! state: checked for every friction law on random states, in every order of the three
//! evaluations, and for states that differ from the previous one in a single component.

mod common;

use common::rng::Rng;
use common::rotor::LAWS;
use geared_rotor::gear::FrictionLaw;
use geared_rotor::rotor::{idx, GearedRotor, InitialConditions, Inputs, Outputs, Params, NY};
use nalgebra::SVector;

fn model(law: FrictionLaw) -> GearedRotor {
    let mut m = GearedRotor::new(Params {
        friction_law: law,
        ..Params::default()
    })
    .unwrap();
    m.set_inputs(Inputs {
        omega1: 314.159,
        t_load: 20.0,
        ..Inputs::default()
    });
    m
}

fn random_start(rng: &mut Rng) -> (InitialConditions, f64, f64) {
    let mut ic = InitialConditions::default();
    for k in 0..6 {
        ic.u[k] = rng.sym(2e-5);
        ic.u_dot[k] = rng.sym(0.05);
    }
    ic.phi1 = rng.sym(10.0);
    (ic, rng.sym(2e4), 2500.0 + rng.sym(500.0))
}

/// The state of the start (initialising also sets the model's references of the gap and
/// the transmission error, so every model compared is initialised the same way).
fn state(
    m: &mut GearedRotor,
    (ic, omega1_dot, lambda): &(InitialConditions, f64, f64),
) -> SVector<f64, NY> {
    let mut y = m.initialize_with(0.0, ic).unwrap();
    y[idx::OMEGA1_DOT] = *omega1_dot;
    y[idx::LAMBDA] = *lambda;
    y
}

/// (f, consistent lambda, outputs, consistent outputs) of y.
type Evals = (SVector<f64, NY>, f64, Outputs, Outputs);

fn eval(m: &mut GearedRotor, y: &SVector<f64, NY>, order: [usize; 4]) -> Evals {
    let mut r: Evals = (
        SVector::zeros(),
        0.0,
        Outputs::default(),
        Outputs::default(),
    );
    for what in order {
        match what {
            0 => m.rhs(0.0, y, &mut r.0).unwrap(),
            1 => r.1 = m.consistent_lambda(0.0, y).unwrap(),
            2 => r.2 = m.outputs(0.0, y),
            _ => r.3 = m.outputs_consistent(0.0, y),
        }
    }
    r
}

fn same_bits(a: &Evals, b: &Evals) -> bool {
    let o = |o: &Outputs| format!("{o:?}");
    a.0.iter()
        .zip(b.0.iter())
        .all(|(x, y)| x.to_bits() == y.to_bits())
        && a.1.to_bits() == b.1.to_bits()
        && o(&a.2) == o(&b.2)
        && o(&a.3) == o(&b.3)
}

const ORDERS: [[usize; 4]; 4] = [[0, 1, 2, 3], [3, 2, 1, 0], [2, 0, 3, 1], [1, 3, 0, 2]];

#[test]
fn memoised_evaluations_equal_those_of_a_fresh_model() {
    let mut rng = Rng(907);
    for law in LAWS {
        let mut warm = model(law);
        for case in 0..40 {
            let start = random_start(&mut rng);
            let y = state(&mut warm, &start);
            let order = ORDERS[case % ORDERS.len()];
            let fresh = || {
                let mut m = model(law);
                state(&mut m, &start);
                m
            };
            let reference = eval(&mut fresh(), &y, [0, 1, 2, 3]);
            // the same state twice in a row (the second time from the memo), any order
            for _ in 0..2 {
                let got = eval(&mut warm, &y, order);
                assert!(
                    same_bits(&got, &reference),
                    "law {law:?} case {case}: {order:?}"
                );
            }
            // a state that differs in one component the sums or the mesh depend on
            let j = [
                0,
                4,
                idx::PHI1,
                idx::V + 2,
                idx::V + 6,
                idx::OMEGA1,
                idx::LAMBDA,
            ][case % 7];
            let mut z = y;
            z[j] *= 1.0 + 1e-9;
            z[j] += 1e-300;
            let reference = eval(&mut fresh(), &z, [0, 1, 2, 3]);
            let got = eval(&mut warm, &z, order);
            assert!(
                same_bits(&got, &reference),
                "law {law:?} case {case}: y[{j}] changed"
            );
        }
    }
}
