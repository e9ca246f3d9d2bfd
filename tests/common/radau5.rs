//! Set-up shared by the RADAU5 tests.

use super::radau5_problems::Pendulum2;
use geared_rotor::radau5::{Options, Problem, Radau5, Snapshot, Tolerance};
use nalgebra::SVector;

/// Default options with rtol = atol = tol.
pub fn opts<const N: usize>(tol: f64) -> Options<N> {
    Options {
        rtol: Tolerance::Scalar(tol),
        atol: Tolerance::Scalar(tol),
        ..Options::default()
    }
}

/// The index-2 pendulum (g = 9.81) and a consistent start: angle 1 rad from the downward
/// vertical, at rest, lambda = g cos(1) (unit mass and length).
pub fn pendulum2() -> (Pendulum2, SVector<f64, 5>) {
    let g = 9.81;
    let y0 = SVector::<f64, 5>::new(1.0f64.sin(), -(1.0f64.cos()), 0.0, 0.0, g * 1.0f64.cos());
    (Pendulum2 { g }, y0)
}

/// `opts(tol)` for the pendulum: 4 index-1 components (positions, velocities), 1 index-2
/// component (lambda).
pub fn pendulum2_opts(tol: f64) -> Options<5> {
    Options {
        n1: 4,
        n2: 1,
        ..opts(tol)
    }
}

/// Takes `steps` steps of `s` towards `t_end` (every seventh one to a stop time `ahead`
/// of t instead, so that clipped steps are covered too), with a snapshot in bytes before
/// each; then continues from every snapshot in a fresh stepper (built with other options,
/// which the restore replaces) and checks that t, y and the counters repeat bit for bit.
#[allow(dead_code)]
pub fn check_snapshots_continue<P: Problem<N>, const N: usize>(
    p: &mut P,
    s: &mut Radau5<N>,
    steps: usize,
    t_end: f64,
    ahead: f64,
) {
    let mut snaps = Vec::new();
    let mut traj = Vec::new();
    for k in 0..steps {
        snaps.push(s.snapshot().to_bytes());
        let t_stop = if k % 7 == 3 { s.t() + ahead } else { t_end };
        s.step(p, t_stop).unwrap();
        traj.push((t_stop, s.t().to_bits(), s.y().map(f64::to_bits), *s.stats()));
    }
    for (k, bytes) in snaps.iter().enumerate() {
        let snap = Snapshot::<N>::from_bytes(bytes).unwrap();
        let mut r = Radau5::new(p, opts(1e-2), 1.0, SVector::zeros()).unwrap();
        r.restore(&snap);
        for (t_stop, t, y, st) in &traj[k..] {
            r.step(p, *t_stop).unwrap();
            assert_eq!(r.t().to_bits(), *t, "from snapshot {k}");
            assert_eq!(r.y().map(f64::to_bits), *y, "from snapshot {k}");
            assert_eq!(r.stats(), st, "from snapshot {k}");
        }
    }
}
