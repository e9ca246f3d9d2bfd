//! Bad states give typed errors, never panics (docs/development.md "Standards": no panics on bad input).

mod common;

use common::rotor::driven;
use geared_rotor::rotor::{idx, ModelError, Params, NY};
use nalgebra::{SMatrix, SVector};

#[test]
fn bad_states_are_errors_not_panics() {
    let mut model = driven(Params::default(), 314.159);
    let y0 = model.initialize(0.0).unwrap();
    let mut f = SVector::<f64, NY>::zeros();
    let mut jac = SMatrix::<f64, NY, NY>::zeros();
    let bad = [
        f64::NAN,
        f64::INFINITY,
        -f64::INFINITY,
        1e300,
        -1e300,
        1e-300,
    ];
    for j in 0..NY {
        for &b in &bad {
            let mut y = y0;
            y[j] = b;
            let r = model.rhs(0.0, &y, &mut f);
            if let Err(e) = &r {
                assert!(!e.to_string().is_empty());
            }
            let _ = model.jacobian(0.0, &y, &mut jac);
            let _ = model.outputs(0.0, &y);
            let _ = model.consistent_lambda(0.0, &y);
        }
    }
    // centres pushed together: a typed error naming the distance
    let mut y = y0;
    y[3] = -0.01;
    match model.rhs(0.0, &y, &mut f) {
        Err(ModelError::CentreDistanceTooSmall { a, r_sum, .. }) => assert!(a <= r_sum),
        other => panic!("{other:?}"),
    }
    // axial separation beyond the face width: no contact
    let mut y = y0;
    y[2] = 0.02;
    assert!(matches!(
        model.rhs(0.0, &y, &mut f),
        Err(ModelError::NoContact { .. })
    ));
    let mut y = y0;
    y[idx::LAMBDA] = f64::NAN;
    assert!(matches!(
        model.rhs(0.0, &y, &mut f),
        Err(ModelError::NonFinite { .. })
    ));
}
