//! Options: defaults of `radau5.f` (radau5.md §2), per-component tolerances, the
//! finite-difference Jacobian, zero Newton start.

use geared_rotor::radau5::test_problems::{Robertson, VanDerPol};
use geared_rotor::radau5::{Controller, JacobianMode, NewtonStart, Options, Radau5, Tolerance};
use nalgebra::SVector;

#[test]
fn defaults_are_those_of_radau5_f() {
    let o = Options::<4>::default();
    assert_eq!(o.uround, 1e-16);
    assert_eq!(o.safety, 0.9);
    assert_eq!(o.theta_jac, 0.001);
    assert_eq!(o.max_newton, 7);
    assert_eq!((o.fac_min, o.fac_max), (0.2, 8.0));
    assert_eq!((o.keep_h_lo, o.keep_h_hi), (1.0, 1.2));
    assert_eq!(o.max_steps, 100_000);
    assert_eq!(o.h_init, 1e-6);
    assert_eq!((o.n1, o.n2, o.n3), (4, 0, 0));
    assert_eq!(o.controller, Controller::Gustafsson);
    assert_eq!(o.newton_start, NewtonStart::Extrapolate);
    assert_eq!(o.jacobian, JacobianMode::Analytic);
    assert!(o.h_max.is_infinite());
}

fn rob(o: Options<3>) -> Radau5<3> {
    let mut p = Robertson;
    let mut s = Radau5::new(&mut p, o, 0.0, SVector::<f64, 3>::new(1.0, 0.0, 0.0)).unwrap();
    s.integrate_to(&mut p, 40.0).unwrap();
    s
}

/// ITOL = 1 with equal entries must take exactly the decisions of ITOL = 0.
#[test]
fn per_component_tolerances_equal_to_scalar_give_identical_runs() {
    let scalar = Options {
        rtol: Tolerance::Scalar(1e-6),
        atol: Tolerance::Scalar(1e-12),
        ..Options::default()
    };
    let per = Options {
        rtol: Tolerance::PerComponent(SVector::repeat(1e-6)),
        atol: Tolerance::PerComponent(SVector::repeat(1e-12)),
        ..Options::default()
    };
    let (a, b) = (rob(scalar), rob(per));
    assert_eq!(a.stats(), b.stats());
    assert_eq!(a.y(), b.y());
    // a looser atol on y2 alone changes the run (the per-component path is used)
    let mut atol = SVector::repeat(1e-12);
    atol[1] = 1e-6;
    let c = rob(Options {
        atol: Tolerance::PerComponent(atol),
        ..per
    });
    assert_ne!(c.stats(), a.stats());
}

/// Forward differences instead of the analytic Jacobian: same accuracy.
#[test]
fn finite_difference_jacobian_and_zero_newton_start() {
    let y_ref = [1.706167732170483, -0.8928097010247975];
    let run = |jacobian, newton_start| {
        let mut p = VanDerPol { eps: 1e-6 };
        let o = Options {
            rtol: Tolerance::Scalar(1e-6),
            atol: Tolerance::Scalar(1e-6),
            jacobian,
            newton_start,
            ..Options::default()
        };
        let mut s = Radau5::new(&mut p, o, 0.0, SVector::<f64, 2>::new(2.0, 0.0)).unwrap();
        s.integrate_to(&mut p, 2.0).unwrap();
        let err = (s.y()[0] - y_ref[0]).abs().max((s.y()[1] - y_ref[1]).abs());
        (err, *s.stats())
    };
    let (e_an, s_an) = run(JacobianMode::Analytic, NewtonStart::Extrapolate);
    let (e_fd, s_fd) = run(JacobianMode::FiniteDifference, NewtonStart::Extrapolate);
    let (e_z, s_z) = run(JacobianMode::Analytic, NewtonStart::Zero);
    println!("analytic {e_an:e} {s_an}\nfd       {e_fd:e} {s_fd}\nzero     {e_z:e} {s_z}");
    assert!(e_fd < 3.0 * e_an + 1e-7);
    assert!(e_z < 3.0 * e_an + 1e-7);
    // the zero start needs more Newton iterations per step
    assert!(s_z.nsol as f64 / s_z.nstep as f64 > s_an.nsol as f64 / s_an.nstep as f64);
    // h_max is respected
    let mut p = VanDerPol { eps: 1e-6 };
    let o = Options {
        h_max: 1e-3,
        ..Options::default()
    };
    let mut s = Radau5::new(&mut p, o, 0.0, SVector::<f64, 2>::new(2.0, 0.0)).unwrap();
    let mut t = 0.0;
    while t < 0.5 {
        let t_new = s.step(&mut p, 0.5).unwrap();
        assert!(t_new - t <= 1e-3 * (1.0 + 1e-12));
        t = t_new;
    }
}
