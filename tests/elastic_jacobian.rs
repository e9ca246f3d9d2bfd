//! The analytic Jacobian of the elastic contact (docs/model.md §3.5, chain rule through
//! Fn(y), src/rotor/dae/elastic_jacobian.rs): against central differences of f computed
//! here, for helical and spur pairs, every friction law, in contact with the damping
//! pushing and pulling, with the damping clipped (it would pull the flanks together) and in
//! free flight; and a loaded run with it against the same run with forward differences of
//! f (RADAU5's own), to the integration tolerance, with the work of both.

mod common;

use common::rng::Rng;
use common::rotor::LAWS;
use geared_rotor::gear::FrictionLaw;
use geared_rotor::radau5::Statistics;
use geared_rotor::rotor::{idx, GearedRotor, Inputs, Params, ToothContact, NY, SCALES};
use geared_rotor::sim::{Initialization, Simulation, SolverSettings};
use nalgebra::{SMatrix, SVector};

const OMEGA1: f64 = 314.159;

/// Where the state sits on the contact law (3.15).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Regime {
    /// delta > 0, the damping term at +-30 % of the spring term: Fn > 0.
    Damped(f64),
    /// delta > 0, the damping term -3 times the spring term: clipped, Fn = 0.
    Clipped,
    /// delta < 0: free flight.
    Free,
}

fn elastic(beta_deg: f64, law: FrictionLaw) -> GearedRotor {
    let mut p = Params {
        tooth_contact: ToothContact::Elastic,
        friction_law: law,
        ..Params::default()
    };
    p.gear.beta = beta_deg.to_radians();
    GearedRotor::new(p).unwrap()
}

/// A state near the static equilibrium (random displacements, velocities, phase, filter
/// rate) moved into `regime` through xi (the approach) and omega2 (its rate).
fn state(model: &mut GearedRotor, rng: &mut Rng, regime: Regime) -> SVector<f64, NY> {
    model.set_inputs(Inputs {
        omega1: OMEGA1 + rng.sym(30.0),
        t_load: 50.0 + rng.sym(20.0),
        ..Inputs::default()
    });
    let (mut ic, _) = model.static_equilibrium(0.0, 0.0).unwrap();
    for j in 0..6 {
        ic.u[j] += rng.sym(2e-6);
        ic.u_dot[j] = rng.sym(0.02);
    }
    ic.phi1 = rng.sym(10.0);
    let mut y = model.initialize_with(0.0, &ic).unwrap();
    y[idx::OMEGA1_DOT] = rng.sym(100.0);
    let g = *model.geometry();
    let e = *model.elastic_mesh().unwrap();
    let c = model.elastic_contact_at(0.0, &y).unwrap();
    assert!(c.delta > 0.0);
    if regime == Regime::Free {
        // gear 2 ahead: the approach becomes -delta.
        y[idx::Q + 6] += 2.0 * c.delta / g.cos_beta_b;
    }
    let ratio = match regime {
        Regime::Damped(r) => r,
        Regime::Clipped => -3.0,
        Regime::Free => rng.sym(1.0),
    };
    // delta' = -(G v - r_b1 cos(beta_b) omega1): omega2 + dw moves it by -r_b2 cos(beta_b) dw.
    let target = ratio * e.c_l * c.delta / e.d_l;
    y[idx::V + 6] += -(target - c.delta_dot) / (g.rb2 * g.cos_beta_b);
    let c = model.elastic_contact_at(0.0, &y).unwrap();
    match regime {
        Regime::Damped(_) => assert!(c.delta > 0.0 && c.fn_ > 0.0, "{c:?}"),
        Regime::Clipped => assert!(c.delta > 0.0 && c.fn_ == 0.0, "{c:?}"),
        Regime::Free => assert!(c.delta < 0.0 && c.fn_ == 0.0, "{c:?}"),
    }
    y
}

/// Central differences of f, column by column, with the step `1e-5` of the state scale.
fn central_differences(model: &mut GearedRotor, y: &SVector<f64, NY>) -> SMatrix<f64, NY, NY> {
    let mut fd = SMatrix::<f64, NY, NY>::zeros();
    let (mut fp, mut fm) = (SVector::<f64, NY>::zeros(), SVector::<f64, NY>::zeros());
    for j in 0..NY {
        let h = 1e-5 * SCALES[j];
        let (mut yp, mut ym) = (*y, *y);
        yp[j] += h;
        ym[j] -= h;
        model.rhs(0.0, &yp, &mut fp).unwrap();
        model.rhs(0.0, &ym, &mut fm).unwrap();
        for i in 0..NY {
            fd[(i, j)] = (fp[i] - fm[i]) / (yp[j] - ym[j]);
        }
    }
    fd
}

/// Largest deviation of `jac` from `fd`, each entry in units of its row's size (the
/// largest |fd_ik s_k|, s the state scales: every row and column in physical units), and
/// where.
fn deviation(jac: &SMatrix<f64, NY, NY>, fd: &SMatrix<f64, NY, NY>) -> (f64, usize, usize) {
    let mut worst = (0.0, 0, 0);
    for i in 0..NY {
        let row = (0..NY)
            .map(|k| (fd[(i, k)] * SCALES[k]).abs())
            .fold(0.0, f64::max);
        for j in 0..NY {
            let d = (jac[(i, j)] - fd[(i, j)]).abs() * SCALES[j];
            let e = if row > 0.0 {
                d / row
            } else if d > 0.0 {
                f64::INFINITY
            } else {
                0.0
            };
            if e > worst.0 {
                worst = (e, i, j);
            }
        }
    }
    worst
}

/// Helical and spur pair, laws 1-5, three states in each regime: every entry within 1e-5
/// of its row's size (measured: at most 3e-7, the one-sided friction columns). Seen
/// failing with dl/dy dropped (2.9e-2, E_damp row) and with dG/dq v dropped from
/// d delta'/dq (5.1e-5: small at these vibration speeds, still 5 times the bound).
#[test]
fn analytic_jacobian_matches_central_differences() {
    let mut rng = Rng(27);
    let regimes = [
        Regime::Damped(0.3),
        Regime::Damped(-0.3),
        Regime::Clipped,
        Regime::Free,
    ];
    let mut jac = SMatrix::<f64, NY, NY>::zeros();
    let mut worst_all = 0.0f64;
    for beta in [20.0, 0.0] {
        for law in LAWS {
            let mut model = elastic(beta, law);
            for regime in regimes {
                let mut worst = (0.0f64, 0, 0);
                for _ in 0..3 {
                    let y = state(&mut model, &mut rng, regime);
                    assert!(model.jacobian(0.0, &y, &mut jac), "no analytic Jacobian");
                    let fd = central_differences(&mut model, &y);
                    let d = deviation(&jac, &fd);
                    assert!(
                        d.0 < 1e-5,
                        "beta {beta}, {law:?}, {regime:?}: d f{}/d y{}: jac {:e}, fd {:e} \
                         (deviation {:.2e} of the row)",
                        d.1,
                        d.2,
                        jac[(d.1, d.2)],
                        fd[(d.1, d.2)],
                        d.0
                    );
                    if d.0 > worst.0 {
                        worst = d;
                    }
                }
                println!(
                    "beta {beta:>4}, {law:?}, {regime:?}: max |J - FD| / row {:.2e} (f{} y{})",
                    worst.0, worst.1, worst.2
                );
                worst_all = worst_all.max(worst.0);
            }
        }
    }
    println!("elastic Jacobian: max |J - FD| / row over all cases {worst_all:.2e}");
}

/// The loaded default pair (T_load = 50 N m, 3000 rpm) from the static equilibrium over
/// 0.1 s, one doStep per 0.1 ms (docs/model.md §3.5 "Cost"), with the Jacobian analytic or
/// by RADAU5's forward differences of f (`difference`): the state at every communication
/// point and the solver's work.
/// How the stepper gets its Jacobians in [`loaded_run`].
#[derive(Debug, Clone, Copy, PartialEq)]
enum Jac {
    /// Forward differences of f (RADAU5's own).
    Difference,
    /// The analytic J at every renewal.
    Whole,
    /// The analytic J split into its fast and slow parts (the default): renewals of the
    /// fast part alone while the Newton contraction allows.
    Split,
}

fn loaded_run(contact: ToothContact, jac: Jac, rtol: f64) -> (Vec<SVector<f64, NY>>, Statistics) {
    let (ys, s) = loaded_simulation(contact, jac, rtol);
    (ys, *s.stats())
}

/// [`loaded_run`] with the simulation at its end.
fn loaded_simulation(
    contact: ToothContact,
    jac: Jac,
    rtol: f64,
) -> (Vec<SVector<f64, NY>>, Simulation) {
    let settings = SolverSettings { rtol, h_max: 1e-4 };
    let p = Params {
        tooth_contact: contact,
        ..Params::default()
    };
    let mut s = Simulation::with_initialization(
        p,
        settings,
        0.0,
        OMEGA1,
        50.0,
        Initialization::StaticEquilibrium,
    )
    .unwrap();
    s.set_difference_jacobian(jac == Jac::Difference);
    s.set_whole_jacobian(jac == Jac::Whole);
    let h = 1e-4;
    let mut ys = Vec::new();
    for k in 0..1000 {
        s.do_step(k as f64 * h, h).unwrap();
        ys.push(*s.y());
    }
    (ys, s)
}

/// Largest difference of two runs' states in units of the state scales (the last slot, the
/// spring's work, in the energies' scale), and its component.
fn run_difference(a: &[SVector<f64, NY>], b: &[SVector<f64, NY>]) -> (f64, usize) {
    let mut worst = (0.0f64, 0);
    for (ya, yb) in a.iter().zip(b) {
        for i in 0..NY {
            let scale = if i == idx::LAMBDA {
                SCALES[idx::E_IN]
            } else {
                SCALES[i]
            };
            let e = (ya[i] - yb[i]).abs() / scale.max(1e-6 * yb[i].abs());
            if e > worst.0 {
                worst = (e, i);
            }
        }
    }
    worst
}

/// f evaluations including those of the difference Jacobians (RADAU5's nfcn does not count
/// them, as in Hairer's code): NY per Jacobian.
fn f_evaluations(s: &Statistics, difference: bool) -> u64 {
    s.nfcn + if difference { NY as u64 * s.njac } else { 0 }
}

/// The loaded run with the analytic Jacobian (whole at every renewal) and with forward
/// differences of f: the states agree within a few rtol of their scales, well inside the integration error (the
/// difference to the same run at rtol / 10), and the analytic run takes fewer f evaluations.
/// Prints the work of both and of the rigid model (deterministic counts, no timing).
#[test]
fn analytic_and_difference_jacobians_give_the_same_run() {
    let rtol = 1e-6;
    let (a, sa) = loaded_run(ToothContact::Elastic, Jac::Whole, rtol);
    let (d, sd) = loaded_run(ToothContact::Elastic, Jac::Difference, rtol);
    let (fine, _) = loaded_run(ToothContact::Elastic, Jac::Difference, rtol / 10.0);
    let (_, sr) = loaded_run(ToothContact::Rigid, Jac::Whole, rtol);
    let (fa, fd) = (f_evaluations(&sa, false), f_evaluations(&sd, true));
    println!("loaded run, 0.1 s, rtol {rtol:e}:");
    println!("  elastic, analytic Jacobian:    {sa}, f evaluations {fa}");
    println!("  elastic, forward differences:  {sd}, f evaluations {fd}");
    println!("  rigid (analytic Jacobian):     {sr}");
    let dev = run_difference(&a, &d);
    let err = run_difference(&fine, &d);
    println!(
        "  analytic vs differences: largest difference {:.2e} of the scale (component {}); \
         the differences run vs rtol / 10: {:.2e} (component {})",
        dev.0, dev.1, err.0, err.1
    );
    assert!(dev.0 < 5.0 * rtol, "{dev:?}");
    assert!(fa < fd, "{fa} >= {fd}");
}

/// The split Jacobian (`GearedRotor::jacobian_fast`, radau5.md §8) changes the step
/// sequence but not the accuracy: the loaded run with it stays within the integration
/// error of the run with whole renewals (their difference below twice the whole run's
/// difference to the run at rtol / 10), and it renews the whole J at most half as often.
#[test]
fn split_jacobian_keeps_the_accuracy_with_fewer_whole_renewals() {
    let rtol = 1e-6;
    let (w, sw) = loaded_run(ToothContact::Elastic, Jac::Whole, rtol);
    let (p, sp) = loaded_run(ToothContact::Elastic, Jac::Split, rtol);
    let (fine, _) = loaded_run(ToothContact::Elastic, Jac::Whole, rtol / 10.0);
    let dev = run_difference(&p, &w);
    let err = run_difference(&fine, &w);
    println!("loaded run, 0.1 s, rtol {rtol:e}:");
    println!("  whole renewals: {sw}");
    println!("  split:          {sp}");
    println!(
        "  split vs whole: {:.2e} of the scale (component {}); whole vs rtol / 10: {:.2e} \
         (component {})",
        dev.0, dev.1, err.0, err.1
    );
    assert!(dev.0 < 2.0 * err.0, "{dev:?} vs {err:?}");
    assert_eq!(sw.njac_fast, 0);
    assert!(sp.njac_fast > 0);
    assert!(2 * sp.njac <= sw.njac, "{} vs {}", sp.njac, sw.njac);
}

/// What the split rests on: along a loaded run, the Newton iteration with the old slow
/// part and the new fast part, `S(y0) + F(y1)`, keeps contracting fast where the old J(y0)
/// has aged, for states 0.1 to 0.4 ms apart (a mesh period is about 0.74 ms). The predicted
/// contraction of the simplified Newton iteration with an approximate J is the norm of
/// `(gamma/h M - J1)^-1 (J1 - J_approx)` (scaled by the state scales, h = 25 us, the
/// loaded run's typical step). Measured: J0 up to 5.6e-2 (across a kink of the contact
/// length), S0 + F1 at most 7.6e-3 (where the friction columns, in S, change at a kink);
/// with `F` = 0 the two would be equal.
#[test]
fn fast_part_carries_what_changes_along_the_mesh() {
    let (ys, sim) = loaded_simulation(ToothContact::Elastic, Jac::Split, 1e-8);
    let mut model = sim.model().clone();
    let mass = model.mass();
    // RADAU5's real eigenvalue gamma of the inverse Radau IIA matrix.
    let fac1 = 3.637_834_252_744_496 / 25e-6;
    let scale = |i: usize| {
        if i == idx::LAMBDA {
            SCALES[idx::E_IN]
        } else {
            SCALES[i]
        }
    };
    let contraction = |j1: &SMatrix<f64, NY, NY>, approx: &SMatrix<f64, NY, NY>| {
        let e = (mass * fac1 - j1).lu();
        let x = e.solve(&(j1 - approx)).expect("regular Newton matrix");
        // Infinity norm of D^-1 X D.
        (0..NY)
            .map(|i| {
                (0..NY)
                    .map(|j| (x[(i, j)] * scale(j) / scale(i)).abs())
                    .sum::<f64>()
            })
            .fold(0.0, f64::max)
    };
    let (mut worst, mut old_max) = (0.0f64, 0.0f64);
    for k0 in (200..1000).step_by(37) {
        for gap in 1..=4 {
            let (y0, y1) = (ys[k0 - gap], ys[k0]);
            let (t0, t1) = ((k0 - gap + 1) as f64 * 1e-4, (k0 + 1) as f64 * 1e-4);
            let mut j0 = SMatrix::<f64, NY, NY>::zeros();
            let mut f0 = j0;
            let mut j1 = j0;
            let mut f1 = j0;
            assert!(model.jacobian(t0, &y0, &mut j0) && model.jacobian_fast(t0, &y0, &mut f0));
            assert!(model.jacobian(t1, &y1, &mut j1) && model.jacobian_fast(t1, &y1, &mut f1));
            let split = contraction(&j1, &(j0 - f0 + f1));
            let old = contraction(&j1, &j0);
            worst = worst.max(split);
            old_max = old_max.max(old);
        }
    }
    println!(
        "predicted Newton contraction: with S0 + F1 at most {worst:.3e}, with J0 up to \
         {old_max:.3e}"
    );
    assert!(old_max > 3e-2, "{old_max}: no aged J in the sample");
    assert!(worst < 1e-2, "{worst}");
}
