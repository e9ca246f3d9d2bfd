//! Test 6 (issue 2): consistent initialisation (model.md §7). lambda(0) satisfies the hidden
//! constraint `d/dt (G(q) v - r_b1 cos(beta_b) omega1) = 0` to round-off, for both signs
//! of lambda. dG/dt v is computed here by central differences of G(q + h v) (Richardson),
//! v' from f of the crate divided by the masses.

mod common;

use common::rng::Rng;
use common::rotor::{driven, hidden_constraint};
use geared_rotor::rotor::{idx, GearedRotor, InitialConditions, Inputs, Params, NY};
use nalgebra::SVector;

#[test]
fn lambda_satisfies_hidden_constraint_for_both_signs() {
    let mut rng = Rng(6);
    let mut worst: f64 = 0.0;
    let (mut npos, mut nneg) = (0, 0);
    for i in 0..400 {
        let mut p = Params::default();
        if i % 4 == 1 {
            p.gear.beta = -p.gear.beta;
        }
        if i % 4 == 2 {
            p.gear.beta = 0.0;
        }
        p.mu = 0.2 * rng.next();
        let mut model = GearedRotor::new(p).unwrap();
        // large load torques of either sign: negative T_load drives gear 2 -> lambda < 0
        model.set_inputs(Inputs {
            omega1: rng.sym(400.0),
            omega1_der: rng.sym(1e4),
            t_load: rng.sym(400.0),
            t_load_der: rng.sym(100.0),
            t_ref: 0.0,
        });
        let t0 = rng.sym(1.0);
        let mut ic = InitialConditions::default();
        for j in 0..6 {
            ic.u[j] = rng.sym(3e-5);
            ic.u_dot[j] = rng.sym(0.05);
        }
        ic.phi1 = rng.sym(1e3);
        let y = model.initialize_with(t0, &ic).unwrap();
        let lam = y[idx::LAMBDA];
        if lam > 0.0 {
            npos += 1
        } else {
            nneg += 1
        }
        // the velocity constraint holds and the gap is zero
        let mut f = SVector::<f64, NY>::zeros();
        model.rhs(t0, &y, &mut f).unwrap();
        let g = *model.geometry();
        assert!(f[idx::LAMBDA].abs() <= 1e-14 * g.rb1 * y[idx::OMEGA1].abs().max(1.0));
        assert!(model.outputs(t0, &y).gap.abs() < 1e-17);
        let (res, scale) = hidden_constraint(&mut model, t0, &y);
        let e = res.abs() / scale;
        worst = worst.max(e);
        assert!(
            e < 1e-11,
            "i={i}: lambda {lam}, residual {res}, scale {scale}"
        );
        // and the value is off for any other lambda: 1 % more lambda breaks it
        let mut y2 = y;
        y2[idx::LAMBDA] *= 1.01;
        let (res2, _) = hidden_constraint(&mut model, t0, &y2);
        assert!(res2.abs() / scale > 1e-4 || lam.abs() < 1.0);
    }
    println!("test 6: {npos} states with lambda > 0, {nneg} with lambda < 0; max |hidden-constraint residual| / scale = {worst:.2e}");
    assert!(npos > 50 && nneg > 50);
}

#[test]
fn default_initialisation_and_static_equilibrium() {
    let mut model = driven(Params::default(), 314.159);
    let y = model.initialize(0.0).unwrap();
    let g = *model.geometry();
    let o = model.outputs(0.0, &y);
    assert!((o.omega2 - 314.159 * 27.0 / 41.0).abs() < 1e-12);
    // frictionless static equilibrium: lambda = d_phi omega2 / (r_b2 cos beta_b), K u = lambda G^T
    let p = Params {
        mu: 0.0,
        ..Params::default()
    };
    let mut m0 = driven(p, 314.159);
    let (ic, lam) = m0.static_equilibrium(0.0, 0.0).unwrap();
    let y0 = m0.initialize_with(0.0, &ic).unwrap();
    let lam_ref = 0.5 * 314.159 * 27.0 / 41.0 / (g.rb2 * g.cos_beta_b);
    assert!(((lam - lam_ref) / lam_ref).abs() < 1e-14);
    // at the equilibrium the consistent lambda is the static one and v' = 0
    assert!(
        ((y0[idx::LAMBDA] - lam_ref) / lam_ref).abs() < 1e-9,
        "{} vs {lam_ref}",
        y0[idx::LAMBDA]
    );
    let mut f = SVector::<f64, NY>::zeros();
    m0.rhs(0.0, &y0, &mut f).unwrap();
    for i in 0..7 {
        assert!(
            f[idx::V + i].abs() < 1e-9 * lam_ref,
            "component {i}: {}",
            f[idx::V + i]
        );
    }
    let o = m0.outputs(0.0, &y0);
    // T1 omega1 = d_phi omega2^2 (model.md §9.5)
    assert!((o.t1 * o.omega1 - 0.5 * o.omega2 * o.omega2).abs() < 1e-9 * o.t1 * o.omega1);
    println!(
        "lambda(0) default = {:.6} N, static frictionless = {lam_ref:.6} N",
        y[idx::LAMBDA]
    );
}
