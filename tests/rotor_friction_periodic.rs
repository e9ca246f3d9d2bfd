//! The periodic module with friction laws 2-4 (`src/periodic`): shooting finds the
//! periodic orbit (residual <= 1e-10, multipliers inside the unit circle) and the harmonic
//! approach of order 6 agrees with it, as for law 1 in tests/periodic.rs.

use geared_rotor::gear::FrictionLaw;
use geared_rotor::periodic::harmonic::{harmonic_balance, HarmonicOptions};
use geared_rotor::periodic::shooting::{shoot, ShootingOptions};
use geared_rotor::periodic::{max_rel_deviation, OrbitPoint, PeriodicSystem};
use geared_rotor::rotor::Params;

#[test]
fn shooting_and_harmonic_approach_work_for_every_law() {
    for law in [
        FrictionLaw::RegularisedCoulomb,
        FrictionLaw::IsoMean,
        FrictionLaw::LocalEhl,
    ] {
        let p = Params {
            friction_law: law,
            ..Params::default()
        };
        let mut sys = PeriodicSystem::new(p, 314.159, 50.0).unwrap();
        let (z0, _) = sys.static_equilibrium().unwrap();
        let sh = shoot(&mut sys, &z0, &ShootingOptions::default()).unwrap();
        let max = sh.floquet_max_abs();
        let opts = HarmonicOptions::default();
        let mut prev = None;
        let mut dev = f64::NAN;
        for n in [2usize, 4, 6] {
            let hb = harmonic_balance(&sys, n, prev.as_ref(), &opts).unwrap();
            assert!(
                hb.residual <= opts.tol,
                "law {law:?}, n = {n}: {:e}",
                hb.residual
            );
            let pts: Vec<OrbitPoint> = sh.orbit.iter().map(|q| hb.point(q.t)).collect();
            dev = max_rel_deviation(&pts, &sh.orbit);
            prev = Some(hb);
        }
        println!(
            "law {}: shooting residual {:.1e}, largest Floquet multiplier {max:.4}, harmonic n = 6 vs shooting {dev:.2e}",
            law.code(),
            sh.residual
        );
        assert!(sh.residual <= 1e-10, "law {law:?}: {:e}", sh.residual);
        assert!(max < 1.0, "law {law:?}: multiplier {max}");
        assert!(dev < 1e-2, "law {law:?}: harmonic vs shooting {dev:e}");
    }
}
