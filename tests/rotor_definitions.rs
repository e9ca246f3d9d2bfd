//! The rotor model's definitions in `src/rotor`: the static equilibrium under a load
//! torque, the phi2 output relative to the initial angles, the rigid-rotation start state,
//! the filter and held-input rows of f, and the default parameter set, each against
//! model.md / README definitions evaluated here.

mod common;

use common::rotor::masses;
use geared_rotor::rotor::{idx, GearedRotor, InitialConditions, Inputs, Params, NY};
use nalgebra::{SVector, Vector3};
use std::f64::consts::PI;

/// Base radii and base helix angle of the default pair from model.md §2 (recomputed here).
fn default_radii() -> (f64, f64, f64) {
    let (mn, an, b) = (2e-3, 20f64.to_radians(), 20f64.to_radians());
    let at = (an.tan() / b.cos()).atan();
    let rb1 = 27.0 * mn / (2.0 * b.cos()) * at.cos();
    let rb2 = 41.0 * mn / (2.0 * b.cos()) * at.cos();
    (rb1, rb2, (b.sin() * an.cos()).asin())
}

/// Contact normal n of model.md §3.1/§3.2 for displacements u (6 components).
fn normal(u: &[f64; 6], a_w: f64, rb1: f64, rb2: f64, beta_b: f64) -> Vector3<f64> {
    let d = Vector3::new(a_w + u[3] - u[0], u[4] - u[1], 0.0);
    let psi = d.y.atan2(d.x) - ((rb1 + rb2) / d.x.hypot(d.y)).acos();
    let t = Vector3::new(-psi.sin(), psi.cos(), 0.0);
    beta_b.cos() * t + beta_b.sin() * Vector3::z()
}

/// Frictionless static equilibrium with a load torque (model.md §7, §9.5): the torque
/// balance of gear 2 gives `lambda r_b2 cos(beta_b) = d_phi omega2 + T_load` with
/// `omega2 = omega1 z1/z2`, and every bearing carries the normal force, `K2 u2 = lambda n`,
/// `K1 u1 = -lambda n`, with n from the displaced state. The reference uses the spec
/// formulas and radii recomputed here; the crate's start state must also have v' = 0.
#[test]
fn static_equilibrium_with_load_torque_balances_forces() {
    let (rb1, rb2, bb) = default_radii();
    let mut worst: f64 = 0.0;
    for t_load in [40.0, -15.0, 120.0] {
        let p = Params {
            mu: 0.0,
            ..Params::default()
        };
        let omega1 = 300.0;
        let mut model = GearedRotor::new(p).unwrap();
        model.set_inputs(Inputs {
            omega1,
            t_load,
            ..Inputs::default()
        });
        let (ic, lam) = model.static_equilibrium(0.0, 0.3).unwrap();
        let omega2 = omega1 * 27.0 / 41.0;
        let lam_ref = (p.d_phi * omega2 + t_load) / (rb2 * bb.cos());
        let e = ((lam - lam_ref) / lam_ref).abs();
        worst = worst.max(e);
        assert!(e < 1e-9, "T_load {t_load}: lambda {lam} vs {lam_ref}");
        let a_w = model.geometry().a_w;
        let n = normal(&ic.u, a_w, rb1, rb2, bb);
        for i in 0..3 {
            let k1 = p.rotor1.k[i];
            let k2 = p.rotor2.k[i];
            assert!((k2 * ic.u[3 + i] - lam_ref * n[i]).abs() < 1e-9 * lam_ref.abs());
            assert!((k1 * ic.u[i] + lam_ref * n[i]).abs() < 1e-9 * lam_ref.abs());
        }
        let y = model.initialize_with(0.0, &ic).unwrap();
        let mut f = SVector::<f64, NY>::zeros();
        model.rhs(0.0, &y, &mut f).unwrap();
        for i in 0..7 {
            let e = f[idx::V + i].abs() / lam_ref.abs();
            worst = worst.max(e);
            assert!(e < 1e-9, "T_load {t_load}: v'[{i}] force {}", f[idx::V + i]);
        }
    }
    println!("rotor_definitions: static equilibrium with load, max rel dev {worst:.2e}");
}

/// phi2 is reported relative to the start (model.md §6: TE = r_b2 phi2 - r_b1 phi1
/// "relative to t = 0"; phi2 about -e_z): at a start with phi1(0) != 0 it is 0, and after
/// the gears turn by d_phi1 with transmission error xi it is `(xi + r_b1 d_phi1)/r_b2`,
/// from the definition of xi with r_b1, r_b2 recomputed from model.md §2.
#[test]
fn phi2_output_is_relative_to_the_initial_angles() {
    let (rb1, rb2, _) = default_radii();
    let mut model = GearedRotor::new(Params::default()).unwrap();
    model.set_inputs(Inputs {
        omega1: 314.159,
        ..Inputs::default()
    });
    let ic = InitialConditions {
        phi1: 0.7,
        ..InitialConditions::default()
    };
    let mut y = model.initialize_with(0.0, &ic).unwrap();
    let o = model.outputs(0.0, &y);
    assert!(o.phi2.abs() < 1e-15, "phi2(0) = {}", o.phi2);
    assert!((o.phi1 - 0.7).abs() < 1e-15);
    y[idx::PHI1] += 0.3;
    y[6] = 2e-6;
    let o = model.outputs(0.0, &y);
    let want = (2e-6 + rb1 * 0.3) / rb2;
    let e = ((o.phi2 - want) / want).abs();
    println!("rotor_definitions: phi2 rel dev {e:.2e}");
    assert!(e < 1e-9, "phi2 {} vs {want}", o.phi2);
}

/// The rigid-rotation state (no displacement, omega1 from the input) lies on the velocity
/// constraint (model.md §3.3: G q' = r_b1 cos(beta_b) omega1 with u' = 0 gives
/// `omega2 = omega1 r_b1 / r_b2 = omega1 z1/z2`) and its lambda satisfies the hidden
/// constraint: with u' = 0 and omega1' = 0, G' v = 0, so `G M^-1 (M v') = 0`, with G from
/// the spec normal (recomputed here) and M v' = f of the crate.
#[test]
fn rigid_rotation_state_is_on_the_constraint() {
    let (rb1, rb2, bb) = default_radii();
    for mu in [0.0, 0.05] {
        let p = Params {
            mu,
            ..Params::default()
        };
        let mut model = GearedRotor::new(p).unwrap();
        model.set_inputs(Inputs {
            omega1: 250.0,
            t_load: 30.0,
            ..Inputs::default()
        });
        let y = model.rigid_rotation_state(0.0, 0.4).unwrap();
        assert!((y[idx::V + 6] - 250.0 * 27.0 / 41.0).abs() < 1e-12 * 250.0);
        let mut f = SVector::<f64, NY>::zeros();
        model.rhs(0.0, &y, &mut f).unwrap();
        assert!(f[idx::LAMBDA].abs() < 1e-14 * rb1 * 250.0);
        let n = normal(&[0.0; 6], model.geometry().a_w, rb1, rb2, bb);
        let grow = [-n.x, -n.y, -n.z, n.x, n.y, n.z, rb2 * bb.cos()];
        let ms = masses(&p);
        let mut hidden = 0.0;
        let mut scale: f64 = 0.0;
        for i in 0..7 {
            hidden += grow[i] * f[idx::V + i] / ms[i];
            scale = scale.max((grow[i] * f[idx::V + i] / ms[i]).abs());
        }
        println!(
            "rotor_definitions: rigid rotation mu {mu}: hidden constraint {hidden:.2e} of {scale:.2e}"
        );
        assert!(hidden.abs() < 1e-12 * scale, "{hidden} of {scale}");
    }
}

/// The filter rows of f are the critically damped filter of README "Input smoothing"
/// (model.md §8): `omega1'' = w_c^2 (omega1_ref(t) - omega1) - 2 w_c omega1'`, phi1' = omega1,
/// `w_c = 2 pi omega1_filter_frequency`, with the held input
/// `omega1_ref(t) = omega1 + der (t - t_ref)`; the torque row of gear 2 (mu = 0) is
/// `J2 omega2' = lambda r_b2 cos(beta_b) - d_phi omega2 - T_load(t)` with
/// `T_load(t) = T_load + der (t - t_ref)`, and E_load' = T_load(t) omega2. All evaluated here
/// at a time after t_ref, so a reversed or missing ramp shows.
#[test]
fn filter_and_held_input_rows_follow_their_definitions() {
    let (_, rb2, bb) = default_radii();
    for f_c in [1000.0, 250.0] {
        let p = Params {
            mu: 0.0,
            omega1_filter_hz: f_c,
            ..Params::default()
        };
        let mut model = GearedRotor::new(p).unwrap();
        let inputs = Inputs {
            omega1: 300.0,
            omega1_der: 2000.0,
            t_load: 10.0,
            t_load_der: -300.0,
            t_ref: 0.01,
        };
        model.set_inputs(inputs);
        let mut y = model.initialize(0.01).unwrap();
        y[idx::OMEGA1] = 290.0;
        y[idx::OMEGA1_DOT] = 1500.0;
        let t = 0.013;
        let mut f = SVector::<f64, NY>::zeros();
        model.rhs(t, &y, &mut f).unwrap();
        let wc = 2.0 * PI * f_c;
        let w_ref = 300.0 + 2000.0 * (t - 0.01);
        let want = wc * wc * (w_ref - 290.0) - 2.0 * wc * 1500.0;
        assert!(
            (f[idx::OMEGA1_DOT] - want).abs() < 1e-12 * want.abs(),
            "omega1'' {} vs {want}",
            f[idx::OMEGA1_DOT]
        );
        assert_eq!(f[idx::PHI1], 290.0);
        assert_eq!(f[idx::OMEGA1], 1500.0);
        let tl = 10.0 - 300.0 * (t - 0.01);
        let lam = y[idx::LAMBDA];
        let omega2 = y[idx::V + 6];
        let want = lam * rb2 * bb.cos() - p.d_phi * omega2 - tl;
        assert!(
            (f[idx::V + 6] - want).abs() < 1e-12 * (lam * rb2).abs(),
            "J2 omega2' {} vs {want}",
            f[idx::V + 6]
        );
        assert!((f[idx::E_LOAD] - tl * omega2).abs() < 1e-12 * (tl * omega2).abs());
    }
}

/// The default parameter set is the one of model.md §10 (and README: filter corner
/// 1000 Hz), value by value as written in the spec.
#[test]
fn default_parameters_are_the_model_md_set() {
    let p = Params::default();
    let g = p.gear;
    assert_eq!((g.z1, g.z2), (27, 41));
    assert_eq!(g.m_n, 2.0e-3);
    assert!((g.alpha_n - 20f64.to_radians()).abs() < 1e-15);
    assert!((g.beta - 20f64.to_radians()).abs() < 1e-15);
    assert_eq!(
        (g.b, g.x1, g.x2, g.ha_coef, g.a_w),
        (18e-3, 0.0, 0.0, 1.0, 0.0)
    );
    assert_eq!((p.rotor1.m, p.rotor1.j), (2.0, 1.0e-3));
    assert_eq!(p.rotor1.k, [2e8, 2e8, 1e8]);
    assert_eq!(p.rotor1.d, [1200.0, 1200.0, 850.0]);
    assert_eq!((p.rotor2.m, p.rotor2.j), (4.0, 5.0e-3));
    assert_eq!(p.rotor2.k, [2e8, 2e8, 1e8]);
    assert_eq!(p.rotor2.d, [1700.0, 1700.0, 1200.0]);
    assert_eq!((p.d_phi, p.mu, p.psi0), (0.5, 0.05, 0.0));
    assert_eq!(p.omega1_filter_hz, 1000.0);
}

/// The filter rows of the analytic Jacobian are the exact partial derivatives of the
/// filter of README "Input smoothing" (linear, so no differencing is needed):
/// `d omega1''/d omega1 = -w_c^2`, `d omega1''/d omega1' = -2 w_c`, `d phi1'/d omega1 = 1`,
/// `d omega1'/d omega1' = 1`, and nothing else in those rows. (The generic Jacobian test
/// compares with a row-scaled 1e-3 tolerance, under which the -2 w_c entry, 1.6e-4 of
/// w_c^2, is invisible.)
#[test]
fn jacobian_filter_rows_are_the_filter_derivatives() {
    for f_c in [1000.0, 40.0] {
        let p = Params {
            omega1_filter_hz: f_c,
            ..Params::default()
        };
        let mut model = GearedRotor::new(p).unwrap();
        model.set_inputs(Inputs {
            omega1: 300.0,
            ..Inputs::default()
        });
        let mut y = model.initialize(0.0).unwrap();
        y[idx::OMEGA1_DOT] = 800.0;
        let mut jac = nalgebra::SMatrix::<f64, NY, NY>::zeros();
        assert!(model.jacobian(0.0, &y, &mut jac));
        let wc = 2.0 * PI * f_c;
        for j in 0..NY {
            let want = |row: usize| match (row, j) {
                (r, c) if r == idx::PHI1 && c == idx::OMEGA1 => 1.0,
                (r, c) if r == idx::OMEGA1 && c == idx::OMEGA1_DOT => 1.0,
                (r, c) if r == idx::OMEGA1_DOT && c == idx::OMEGA1 => -wc * wc,
                (r, c) if r == idx::OMEGA1_DOT && c == idx::OMEGA1_DOT => -2.0 * wc,
                _ => 0.0,
            };
            for row in [idx::PHI1, idx::OMEGA1, idx::OMEGA1_DOT] {
                let w = want(row);
                assert!(
                    (jac[(row, j)] - w).abs() <= 1e-12 * w.abs(),
                    "f_c {f_c}: J[{row}, {j}] = {} vs {w}",
                    jac[(row, j)]
                );
            }
        }
    }
}
