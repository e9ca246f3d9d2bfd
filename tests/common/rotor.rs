//! Set-up shared by the geared-rotor model tests.

use geared_rotor::gear::FrictionLaw;
use geared_rotor::rotor::{idx, GearedRotor, Inputs, Params, NY};
use nalgebra::{SVector, Vector3};

/// Every friction law (docs/friction.md), in code order.
pub const LAWS: [FrictionLaw; 5] = [
    FrictionLaw::Coulomb,
    FrictionLaw::RegularisedCoulomb,
    FrictionLaw::IsoMean,
    FrictionLaw::LocalEhl,
    FrictionLaw::BenedictKelley,
];

/// Diagonal of the mass matrix of the velocity block v = (u1', u2', phi2') (model.md §5):
/// m1 three times, m2 three times, J2.
pub fn masses(p: &Params) -> [f64; 7] {
    [
        p.rotor1.m, p.rotor1.m, p.rotor1.m, p.rotor2.m, p.rotor2.m, p.rotor2.m, p.rotor2.j,
    ]
}

/// The model with parameters `p`, driven at constant omega1 with all other inputs at their
/// defaults (no load).
pub fn driven(p: Params, omega1: f64) -> GearedRotor {
    let mut model = GearedRotor::new(p).unwrap();
    model.set_inputs(Inputs {
        omega1,
        ..Inputs::default()
    });
    model
}

/// Largest deviation of `a` from `b` in units of the physical scales of the simulation
/// (`rotor::SCALES`, the atol of each component divided by rtol; 1e-3 of |b| where that is
/// larger), lambda excluded (an algebraic component; the outputs re-project it). Returns
/// the deviation and the component.
pub fn scaled_dev(
    a: &nalgebra::SVector<f64, { geared_rotor::rotor::NY }>,
    b: &nalgebra::SVector<f64, { geared_rotor::rotor::NY }>,
) -> (f64, usize) {
    use geared_rotor::rotor::SCALES;
    use geared_rotor::rotor::{idx, NY};
    let mut worst = (0.0, 0);
    for i in 0..NY {
        if i == idx::LAMBDA {
            continue;
        }
        let d = (a[i] - b[i]).abs() / SCALES[i].max(1e-3 * b[i].abs());
        if d > worst.0 {
            worst = (d, i);
        }
    }
    worst
}

/// Returns (residual of the hidden constraint, scale = |lambda| G M^-1 G^T + |G M^-1 F| ...):
/// `d/dt (G v) - r_b1 cos(beta_b) omega1'` with dG/dt v by central differences (Richardson)
/// and v' from the crate's f, an oracle independent of the crate's consistent lambda.
pub fn hidden_constraint(model: &mut GearedRotor, t: f64, y: &SVector<f64, NY>) -> (f64, f64) {
    let p = *model.params();
    let g = *model.geometry();
    let masses = masses(&p);
    let mut f = SVector::<f64, NY>::zeros();
    model.rhs(t, y, &mut f).unwrap();
    let row = |q: &[f64; 6]| {
        let m = g
            .mesh(
                &Vector3::new(q[0], q[1], q[2]),
                &Vector3::new(q[3], q[4], q[5]),
            )
            .unwrap();
        g.constraint_row(&m)
    };
    let v: Vec<f64> = (0..7).map(|i| y[idx::V + i]).collect();
    // d/dt G(q(t)) v at fixed v: central differences along q + h v, Richardson h, h/2
    let gdot_v = |h: f64| {
        let mut qp = [0.0; 6];
        let mut qm = [0.0; 6];
        for i in 0..6 {
            qp[i] = y[i] + h * v[i];
            qm[i] = y[i] - h * v[i];
        }
        let (rp, rm) = (row(&qp), row(&qm));
        (0..7)
            .map(|i| (rp[i] - rm[i]) / (2.0 * h) * v[i])
            .sum::<f64>()
    };
    let h = 1e-5;
    let gdv = (4.0 * gdot_v(h / 2.0) - gdot_v(h)) / 3.0;
    let r0 = row(&[y[0], y[1], y[2], y[3], y[4], y[5]]);
    let mut gvdot = 0.0;
    let mut scale: f64 = 0.0;
    for i in 0..7 {
        let vdot = f[idx::V + i] / masses[i];
        gvdot += r0[i] * vdot;
        scale = scale
            .max((r0[i] * vdot).abs())
            .max((r0[i] * r0[i] * y[idx::LAMBDA] / masses[i]).abs());
    }
    let res = gdv + gvdot - g.rb1 * g.cos_beta_b * y[idx::OMEGA1_DOT];
    (res, scale)
}
