//! Options: defaults of `radau5.f` (radau5.md §2), per-component tolerances, the
//! finite-difference Jacobian, zero Newton start.

mod common;

use common::radau5_problems::{Robertson, VanDerPol};
use geared_rotor::radau5::{
    Controller, Error, JacobianMode, NewtonStart, Options, Radau5, Tolerance,
};
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
    assert_eq!(o.resume_after_stop, 1.0);
}

/// `resume_after_stop` (not in the Fortran) outside [0, 1] or NaN is refused by name.
#[test]
fn resume_after_stop_out_of_range_is_refused() {
    for bad in [-0.1, 1.5, f64::NAN] {
        let o = Options::<2> {
            resume_after_stop: bad,
            ..Options::default()
        };
        let mut p = VanDerPol { eps: 1e-6 };
        match Radau5::new(&mut p, o, 0.0, SVector::<f64, 2>::new(2.0, 0.0)) {
            Err(Error::InvalidOption { name, .. }) => assert_eq!(name, "resume_after_stop"),
            other => panic!("{bad}: {:?}", other.map(|_| ())),
        }
    }
}

/// After a step shortened to land on a stop time, the next step starts at
/// max(h_new, resume_after_stop * h_planned): from the same state, a stop a tenth of the
/// planned step ahead gives h_new (resume 0, the shortened step's own proposal, at most
/// 8 times that step) and the documented maximum for 0.5 and 1; the solution at the stop is
/// the same in all three (the option only concerns the following step).
#[test]
fn resume_after_stop_sets_the_step_after_a_shortened_one() {
    let mut p = VanDerPol { eps: 1e-3 };
    let y0 = SVector::<f64, 2>::new(2.0, 0.0);
    let run = |resume: f64, p: &mut VanDerPol| {
        let o = Options::<2> {
            rtol: Tolerance::Scalar(1e-6),
            atol: Tolerance::Scalar(1e-6),
            resume_after_stop: resume,
            ..Options::default()
        };
        let mut s = Radau5::new(p, o, 0.0, y0).unwrap();
        for _ in 0..30 {
            s.step(p, 1.0).unwrap();
        }
        let h_planned = s.h();
        let t_stop = s.t() + 0.1 * h_planned;
        assert_eq!(s.step(p, t_stop).unwrap(), t_stop);
        (h_planned, s.h(), *s.y())
    };
    let (hp, h0, y_a) = run(0.0, &mut p);
    let (hp5, h5, y_b) = run(0.5, &mut p);
    let (hp1, h1, y_c) = run(1.0, &mut p);
    assert_eq!((hp, hp), (hp5, hp1));
    assert_eq!((y_a, y_a), (y_b, y_c));
    assert!(
        h0 <= 8.0 * 0.1 * hp * (1.0 + 1e-12) && h0 < 0.5 * hp,
        "h_new {h0:e}, planned {hp:e}"
    );
    assert_eq!(h5, h0.max(0.5 * hp));
    assert_eq!(h1, h0.max(hp));
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
