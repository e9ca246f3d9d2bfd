//! Test 4 (issue 2): virtual power of the friction resultants (model.md §4, §9.4):
//! `Q_f^T q' + M1_z omega1 = -P_loss`, at random displaced states, velocities, phases and
//! both signs of lambda, for several gear sets.

use geared_rotor::gear::{FrictionLaw, GearData, Kinematics, PairGeometry};
use nalgebra::Vector3;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
    fn sym(&mut self, a: f64) -> f64 {
        a * (2.0 * self.next() - 1.0)
    }
}

#[test]
fn friction_virtual_power_equals_minus_loss() {
    let d0 = GearData::default();
    let sets = [
        d0,
        GearData {
            beta: (-20f64).to_radians(),
            ..d0
        },
        GearData { beta: 0.0, ..d0 },
        GearData {
            z1: 17,
            z2: 60,
            beta: 0.0,
            x1: 0.5,
            x2: -0.5,
            ..d0
        },
        GearData {
            z1: 19,
            z2: 53,
            m_n: 3e-3,
            beta: 30f64.to_radians(),
            x1: 0.3,
            x2: 0.1,
            b: 30e-3,
            ..d0
        },
    ];
    let mut rng = Rng(4);
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for d in sets {
        let g = PairGeometry::new(&d).unwrap();
        for i in 0..2000 {
            let u1 = Vector3::new(rng.sym(5e-5), rng.sym(5e-5), rng.sym(5e-5));
            let u2 = Vector3::new(rng.sym(5e-5), rng.sym(5e-5), rng.sym(5e-5));
            let m = g.mesh(&u1, &u2).unwrap();
            let omega1 = rng.sym(400.0);
            // near the rigid ratio most of the time, arbitrary otherwise
            let omega2 = if i % 2 == 0 {
                omega1 * g.rb1 / g.rb2 * (1.0 + rng.sym(1e-3))
            } else {
                rng.sym(400.0)
            };
            let vs = if i % 3 == 0 { 1e-6 } else { 0.5 };
            let k = Kinematics {
                v1: Vector3::new(rng.sym(vs), rng.sym(vs), rng.sym(vs)),
                v2: Vector3::new(rng.sym(vs), rng.sym(vs), rng.sym(vs)),
                omega1,
                omega2,
            };
            let phi1 = rng.sym(1e4);
            let sums = g.friction_sums(&m, phi1, rng.sym(1.0), &k, FrictionLaw::Coulomb);
            if sums.contact.length == 0.0 {
                continue;
            }
            let lambda = rng.sym(5000.0);
            let mu = 0.02 + 0.1 * rng.next();
            let fr = sums.resultants(mu, lambda);
            // Q_f = [F1, F2, -M2_z] (phi2 about -e_z)
            let terms = [
                fr.f1.dot(&k.v1),
                fr.f2.dot(&k.v2),
                -fr.m2.z * k.omega2,
                fr.m1.z * k.omega1,
            ];
            let sum: f64 = terms.iter().sum();
            let scale = terms.iter().fold(fr.p_loss, |a, t| a.max(t.abs()));
            let e = (sum + fr.p_loss).abs() / scale;
            worst = worst.max(e);
            assert!(fr.p_loss >= 0.0);
            assert!(
                e < 1e-12,
                "{d:?}: Q_f.q' + M1z w1 = {sum}, P_loss = {}",
                fr.p_loss
            );
            // F1 = -F2 exactly
            assert_eq!(fr.f1, -fr.f2);
            n += 1;
        }
    }
    println!("test 4: {n} states, max |Q_f^T q' + M1_z omega1 + P_loss| / max|term| = {worst:.2e}");
}
