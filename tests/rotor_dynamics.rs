//! Whole-model sanity runs without the RADAU5 of the crate: the DAE reduced to an ODE by
//! taking lambda from its closed form (model.md §7) at every stage, integrated with classical
//! RK4 at a step far below the fastest time scale. Checks model.md §9.5 (frictionless
//! static equilibrium), §9.6 (energy balance from the accumulator states), §9.7 (dynamic mean
//! loss vs H_V: at the defaults about 0.7 % below) and §9.9 (mean omega2 = omega1 z1/z2).

use geared_rotor::rotor::{idx, GearedRotor, Inputs, Params, NY};
use nalgebra::SVector;

fn deriv(
    model: &mut GearedRotor,
    masses: &[f64; 7],
    t: f64,
    y: &SVector<f64, NY>,
) -> SVector<f64, NY> {
    let mut y = *y;
    y[idx::LAMBDA] = model.consistent_lambda(t, &y).unwrap();
    let mut f = SVector::<f64, NY>::zeros();
    model.rhs(t, &y, &mut f).unwrap();
    for i in 0..7 {
        f[idx::V + i] /= masses[i];
    }
    f[idx::LAMBDA] = 0.0;
    f
}

fn rk4(
    model: &mut GearedRotor,
    masses: &[f64; 7],
    t: f64,
    y: &SVector<f64, NY>,
    h: f64,
) -> SVector<f64, NY> {
    let k1 = deriv(model, masses, t, y);
    let k2 = deriv(model, masses, t + 0.5 * h, &(y + 0.5 * h * k1));
    let k3 = deriv(model, masses, t + 0.5 * h, &(y + 0.5 * h * k2));
    let k4 = deriv(model, masses, t + h, &(y + h * k3));
    let mut yn = y + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    yn[idx::LAMBDA] = model.consistent_lambda(t + h, &yn).unwrap();
    yn
}

fn masses(p: &Params) -> [f64; 7] {
    [
        p.rotor1.m, p.rotor1.m, p.rotor1.m, p.rotor2.m, p.rotor2.m, p.rotor2.m, p.rotor2.j,
    ]
}

#[test]
fn frictionless_run_settles_at_static_equilibrium_and_balances_energy() {
    let p = Params {
        mu: 0.0,
        ..Params::default()
    };
    let mut model = GearedRotor::new(p).unwrap();
    let omega1 = 314.159;
    model.set_inputs(Inputs {
        omega1,
        ..Inputs::default()
    });
    let mut y = model.initialize(0.0).unwrap(); // from rest position: transient
    let ms = masses(&p);
    let y0 = y;
    let e0 = model.outputs(0.0, &y0);
    let h = 2.0 * std::f64::consts::PI / (27.0 * omega1) / 100.0;
    let mut t = 0.0;
    for _ in 0..20_000 {
        y = rk4(&mut model, &ms, t, &y, h);
        t += h;
    }
    let g = *model.geometry();
    let o = model.outputs(t, &y);
    let omega2 = omega1 * 27.0 / 41.0;
    let lam = p.d_phi * omega2 / (g.rb2 * g.cos_beta_b);
    println!(
        "mu = 0, t = {t:.4}: lambda {} vs {lam}, omega2 {} vs {omega2}, T1 w1 {} vs {}",
        o.fn_,
        o.omega2,
        o.t1 * o.omega1,
        p.d_phi * omega2 * omega2
    );
    assert!(((o.fn_ - lam) / lam).abs() < 1e-6);
    assert!(((o.omega2 - omega2) / omega2).abs() < 1e-9);
    assert!(
        ((o.t1 * o.omega1 - p.d_phi * omega2 * omega2) / (p.d_phi * omega2 * omega2)).abs() < 1e-6
    );
    let bal = o.e_in - o.e_loss - o.e_damp - o.e_load - (o.e_kin - e0.e_kin) - (o.e_pot - e0.e_pot);
    println!(
        "energy balance residual {bal:e} J of E_in {} J; gap drift {:e} m",
        o.e_in, o.gap
    );
    assert!(bal.abs() < 1e-8 * o.e_in);
    assert!(o.gap.abs() < 1e-9);
}

#[test]
fn default_run_mean_loss_is_just_below_h_v() {
    let p = Params::default();
    let mut model = GearedRotor::new(p).unwrap();
    let omega1 = 314.159;
    model.set_inputs(Inputs {
        omega1,
        ..Inputs::default()
    });
    let (ic, _) = model.static_equilibrium(0.0, 0.0).unwrap();
    let mut y = model.initialize_with(0.0, &ic).unwrap();
    let ms = masses(&p);
    let e0 = model.outputs(0.0, &y);
    let tm = 2.0 * std::f64::consts::PI / (27.0 * omega1);
    let n = 100;
    let h = tm / n as f64;
    let mut t = 0.0;
    // settle for 60 mesh periods
    for _ in 0..60 * n {
        y = rk4(&mut model, &ms, t, &y, h);
        t += h;
    }
    let (ein0, eloss0, phi_a, xi_a) = (y[idx::E_IN], y[idx::E_LOSS], y[idx::PHI1], y[6]);
    let periods = 20;
    for _ in 0..periods * n {
        y = rk4(&mut model, &ms, t, &y, h);
        t += h;
    }
    let g = *model.geometry();
    let ratio = (y[idx::E_LOSS] - eloss0) / (p.mu * (y[idx::E_IN] - ein0));
    let rel = (ratio - g.h_v) / g.h_v;
    // mean omega2 over whole periods from xi: Delta phi2 = (Delta xi + r_b1 Delta phi1) / r_b2
    let dphi1 = y[idx::PHI1] - phi_a;
    let dphi2 = (y[6] - xi_a + g.rb1 * dphi1) / g.rb2;
    let w2_rel = (dphi2 / dphi1 - 27.0 / 41.0) / (27.0 / 41.0);
    let o = model.outputs(t, &y);
    let bal = o.e_in - o.e_loss - o.e_damp - o.e_load - (o.e_kin - e0.e_kin) - (o.e_pot - e0.e_pot);
    println!(
        "defaults: <P_loss>/(mu <P_in>) = {ratio:.6}, H_V = {:.6}, rel {rel:.4e}; mean omega2 rel err {w2_rel:.2e}; energy residual {:.2e} of E_in; gap {:.2e} m",
        g.h_v,
        bal / o.e_in,
        o.gap
    );
    assert!(
        rel < 0.0 && rel > -0.015,
        "model.md §9.7: about 0.7 % below H_V, got {rel:e}"
    );
    assert!(w2_rel.abs() < 1e-5);
    assert!(bal.abs() < 1e-8 * o.e_in);
}

#[test]
fn stiff_bearings_small_mu_mean_loss_matches_h_v() {
    // model.md §9.7: bearings 1e10 N/m, mu = 1e-3: mean over whole mesh periods within
    // 2e-4 relative of H_V.
    let mut p = Params {
        mu: 1e-3,
        ..Params::default()
    };
    p.rotor1.k = [1e10; 3];
    p.rotor2.k = [1e10; 3];
    let mut model = GearedRotor::new(p).unwrap();
    let omega1 = 314.159;
    model.set_inputs(Inputs {
        omega1,
        ..Inputs::default()
    });
    let (ic, _) = model.static_equilibrium(0.0, 0.0).unwrap();
    let mut y = model.initialize_with(0.0, &ic).unwrap();
    let ms = masses(&p);
    let tm = 2.0 * std::f64::consts::PI / (27.0 * omega1);
    let n = 100;
    let h = tm / n as f64;
    let mut t = 0.0;
    for _ in 0..60 * n {
        y = rk4(&mut model, &ms, t, &y, h);
        t += h;
    }
    let (ein0, eloss0) = (y[idx::E_IN], y[idx::E_LOSS]);
    for _ in 0..20 * n {
        y = rk4(&mut model, &ms, t, &y, h);
        t += h;
    }
    let g = *model.geometry();
    let ratio = (y[idx::E_LOSS] - eloss0) / (p.mu * (y[idx::E_IN] - ein0));
    let rel = (ratio - g.h_v) / g.h_v;
    println!(
        "k = 1e10, mu = 1e-3: <P_loss>/(mu <P_in>) = {ratio:.8}, H_V = {:.8}, rel {rel:.3e}",
        g.h_v
    );
    assert!(rel.abs() < 2e-4);
}
