//! Test 2 (issue 2): G = cos(beta_b) dg/dq by central differences, and n . v_rel is the
//! same at every point of the plane of action and equals G q' - r_b1 cos(beta_b) omega1
//! (model.md §3.3, §9.2).

use geared_rotor::gear::{GearData, Kinematics, PairGeometry};
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

fn gear_sets() -> Vec<GearData> {
    let d0 = GearData::default();
    let deg = |x: f64| x.to_radians();
    vec![
        d0,
        GearData {
            beta: deg(-20.0),
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
            beta: deg(30.0),
            x1: 0.3,
            x2: 0.1,
            b: 30e-3,
            ..d0
        },
        GearData {
            z1: 23,
            z2: 31,
            beta: deg(-12.0),
            a_w: 56.0e-3,
            ..d0
        },
    ]
}

#[test]
fn constraint_row_is_cos_beta_b_times_gradient_of_gap() {
    let mut rng = Rng(1);
    let mut worst: f64 = 0.0;
    for d in gear_sets() {
        let g = PairGeometry::new(&d).unwrap();
        for _ in 0..200 {
            let mut q = [0.0; 7];
            for qi in q.iter_mut().take(6) {
                *qi = rng.sym(1e-4);
            }
            q[6] = rng.sym(0.1);
            let phi1 = rng.sym(0.1);
            let gap = |q: &[f64; 7]| {
                let m = g
                    .mesh(
                        &Vector3::new(q[0], q[1], q[2]),
                        &Vector3::new(q[3], q[4], q[5]),
                    )
                    .unwrap();
                g.gap_raw(&m, g.rb2 * q[6] - g.rb1 * phi1)
            };
            let m = g
                .mesh(
                    &Vector3::new(q[0], q[1], q[2]),
                    &Vector3::new(q[3], q[4], q[5]),
                )
                .unwrap();
            let row = g.constraint_row(&m);
            let norm = row.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            for j in 0..7 {
                // the gap is affine in phi2 and u_z; for u_x, u_y: h^2 truncation ~ (h/a)^2
                let h = if j == 6 { 1e-3 } else { 1e-7 };
                let mut qp = q;
                let mut qm = q;
                qp[j] += h;
                qm[j] -= h;
                let fd = g.cos_beta_b * (gap(&qp) - gap(&qm)) / (qp[j] - qm[j]);
                let e = (fd - row[j]).abs() / norm;
                worst = worst.max(e);
                assert!(e <= 1e-7, "{d:?} j={j}: G={} fd={fd} rel {e:e}", row[j]);
            }
        }
    }
    println!("test 2a: max |G - cos(beta_b) dg/dq| / |G|_max = {worst:.2e}");
}

#[test]
fn normal_relative_velocity_is_uniform_over_the_plane_of_action() {
    let mut rng = Rng(2);
    let mut worst: f64 = 0.0;
    let mut worst_n: f64 = 0.0;
    for d in gear_sets() {
        let g = PairGeometry::new(&d).unwrap();
        for _ in 0..200 {
            let u1 = Vector3::new(rng.sym(1e-4), rng.sym(1e-4), rng.sym(1e-4));
            let u2 = Vector3::new(rng.sym(1e-4), rng.sym(1e-4), rng.sym(1e-4));
            let m = g.mesh(&u1, &u2).unwrap();
            // n from the model.md §3.1/§3.2 formulas, independently of the crate.
            let c1 = u1;
            let c2 = Vector3::new(g.a_w, 0.0, 0.0) + u2;
            let dd = c2 - c1;
            let a = dd.x.hypot(dd.y);
            let theta = dd.y.atan2(dd.x);
            let alpha = ((g.rb1 + g.rb2) / a).acos();
            let t = Vector3::new(-(theta - alpha).sin(), (theta - alpha).cos(), 0.0);
            let bb = g.beta_b;
            let n = bb.cos() * t + bb.sin() * Vector3::z();
            worst_n = worst_n.max((n - m.n).norm());
            let k = Kinematics {
                v1: Vector3::new(rng.sym(1.0), rng.sym(1.0), rng.sym(1.0)),
                v2: Vector3::new(rng.sym(1.0), rng.sym(1.0), rng.sym(1.0)),
                omega1: rng.sym(400.0),
                omega2: rng.sym(400.0),
            };
            let q_dot = [k.v1.x, k.v1.y, k.v1.z, k.v2.x, k.v2.y, k.v2.z, k.omega2];
            let row = g.constraint_row(&m);
            let gq: f64 = row
                .iter()
                .zip(q_dot.iter())
                .map(|(a, b)| a * b)
                .sum::<f64>()
                - g.rb1 * g.cos_beta_b * k.omega1;
            let scale = (k.omega1.abs() + k.omega2.abs()) * (g.rb2 + g.a_w) + 3.0;
            for _ in 0..20 {
                // random point of the plane of action P = T1 + sigma t + Z e_z
                let sigma = rng.sym(0.1);
                let z = rng.sym(0.05);
                let t1 =
                    c1 + g.rb1 * Vector3::new((theta - alpha).cos(), (theta - alpha).sin(), 0.0);
                let p = Vector3::new(t1.x, t1.y, 0.0) + sigma * t + z * Vector3::z();
                let ez = Vector3::z();
                let v1 = k.v1 + k.omega1 * ez.cross(&(p - c1));
                let v2 = k.v2 - k.omega2 * ez.cross(&(p - c2));
                let nv = n.dot(&(v2 - v1));
                let e = (nv - gq).abs() / scale;
                worst = worst.max(e);
                assert!(e < 1e-13, "n.v_rel {nv} vs G q' - .. {gq}");
                // the crate's own relative velocity agrees
                let vr = g.relative_velocity(&m, &k, &m.point(sigma, z));
                assert!((vr - (v2 - v1)).norm() / scale < 1e-13);
            }
            assert!((g.normal_velocity(&m, &k) - gq).abs() / scale < 1e-13);
        }
    }
    assert!(worst_n < 1e-14, "n differs from model.md §3.2: {worst_n:e}");
    println!("test 2b: max |n.v_rel - (G q' - r_b1 cos(beta_b) omega1)| / scale = {worst:.2e}; |n - n_spec| = {worst_n:.1e}");
}
