//! The coast flanks' gap from first principles (docs/model.md §3.6): in the transverse
//! section Z = 0, each flank is an involute in polar form (ISO 21771: a tooth of base
//! thickness `s_b` is bounded at radius r by `psi = psi_b -+ inv(acos(r_b / r))`), gear 2
//! is turned numerically until its flank touches gear 1's, and that rotation times r_b2
//! is the gap along the line of action. No line-of-action formula of the model is used;
//! the test only takes the model's convention for where gear 1's drive flank is (3.10)
//! and calibrates gear 2's tooth angles where the drive flanks touch undeflected.
//! Checked for displaced centres (in-plane and axial), other angles, spur, helical and
//! shifted pairs with a set centre distance: the model's drive and coast approaches.

use geared_rotor::gear::{inv, GearData, PairGeometry};
use geared_rotor::rotor::{idx, GearedRotor, Inputs, Params, ToothContact, NY};
use nalgebra::{SVector, Vector2};
use std::f64::consts::{FRAC_PI_2, PI};

fn polar(p: Vector2<f64>, c: Vector2<f64>) -> (f64, f64) {
    let d = p - c;
    (d.norm(), d.y.atan2(d.x))
}

/// Angle difference wrapped to (-pi, pi].
fn wrap(x: f64) -> f64 {
    let y = x.rem_euclid(2.0 * PI);
    if y > PI {
        y - 2.0 * PI
    } else {
        y
    }
}

/// Base tooth thickness (arc) of a gear from its shift, ISO 21771, m.
fn s_b(d: &GearData, z: i32, x: f64) -> f64 {
    let cb = d.beta.cos();
    let alpha_t = (d.alpha_n.tan() / cb).atan();
    let r = f64::from(z) * d.m_n / (2.0 * cb);
    let s_t = d.m_n / cb * (FRAC_PI_2 + 2.0 * x * d.alpha_n.tan());
    r * alpha_t.cos() * (s_t / r + 2.0 * inv(alpha_t))
}

/// One gear's flank in the section: centre, base radius, tip radius, base angle of the
/// flank and its side (+1: the tooth's CCW side, angle = psi_b - inv; -1: CW side).
#[derive(Clone, Copy)]
struct Flank {
    c: Vector2<f64>,
    rb: f64,
    ra: f64,
    psi_b: f64,
    side: f64,
}

impl Flank {
    fn angle(&self, r: f64) -> f64 {
        self.psi_b - self.side * inv((self.rb / r).acos())
    }
    fn point(&self, r: f64) -> Vector2<f64> {
        let a = self.angle(r);
        self.c + r * Vector2::new(a.cos(), a.sin())
    }
}

/// Penetration of flank `q` (sampled) into the tooth of gear 1 bounded by flank `f`:
/// the largest `r (psi - psi_f(r))`, signed so that > 0 is inside the tooth (for f's
/// CCW side inside is clockwise of it).
fn penetration(f: &Flank, q: &Flank) -> f64 {
    let n = 4000;
    let mut best = f64::NEG_INFINITY;
    for i in 1..n {
        let r2 = q.rb + (q.ra - q.rb) * i as f64 / n as f64;
        let p = q.point(r2);
        let (r, psi) = polar(p, f.c);
        if r <= f.rb || r >= f.ra {
            continue;
        }
        let m = r * wrap(f.side * (f.angle(r) - psi));
        best = best.max(m);
    }
    best
}

/// Rotation (about its centre, CCW positive) that brings flank q into contact with f:
/// the root of the penetration, by the secant method from a bracket.
fn contact_rotation(f: &Flank, q: &Flank, dir: f64) -> Option<f64> {
    let pen = |d: f64| {
        let mut qq = *q;
        qq.psi_b += d;
        penetration(f, &qq)
    };
    // The gaps are below 0.3 mm against r_b2 of 4 cm: a bracket of +-1.2e-2 rad (pairs
    // of teeth that do not meet there have none).
    let (mut a, mut b) = (-1.2e-2 * dir, 1.2e-2 * dir);
    let (mut fa, mut fb) = (pen(a), pen(b));
    if fa.signum() == fb.signum() || !fa.is_finite() || !fb.is_finite() {
        return None;
    }
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        let fm = pen(m);
        if fm.signum() == fa.signum() {
            (a, fa) = (m, fm);
        } else {
            (b, fb) = (m, fm);
        }
        if (b - a).abs() < 1e-14 {
            break;
        }
    }
    let _ = fb;
    Some(0.5 * (a + b))
}

fn model(gear: GearData) -> GearedRotor {
    let p = Params {
        gear,
        tooth_contact: ToothContact::Elastic,
        d_phi: 0.0,
        ..Params::default()
    };
    let mut m = GearedRotor::new(p).unwrap();
    m.set_inputs(Inputs {
        omega1: 100.0,
        t_load: 0.0,
        ..Inputs::default()
    });
    m
}

/// The state of `base` with displacements u, gear 1 turned by dphi1 and gear 2 by dphi2
/// (its body angle, -e_z sense).
fn moved(
    base: &SVector<f64, NY>,
    g: &PairGeometry,
    u: [f64; 6],
    dphi1: f64,
    dphi2: f64,
) -> SVector<f64, NY> {
    let mut y = *base;
    for i in 0..6 {
        y[i] = u[i];
    }
    y[idx::PHI1] += dphi1;
    // xi = r_b2 phi2 - r_b1 phi1.
    y[6] += g.rb2 * dphi2 - g.rb1 * dphi1;
    y
}

/// A pair with everything the first-principles evaluation needs.
struct Pair {
    m: GearedRotor,
    g: PairGeometry,
    gear: GearData,
    y0: SVector<f64, NY>,
    /// Base thicknesses of gears 1 and 2 less half the thinning each.
    sb: [f64; 2],
    /// Base angle of gear 2's calibrated tooth (CCW-side flank) at the start.
    psi2_0: f64,
}

/// First-principles rotations of gear 2 that close the drive gap (CCW) and the coast gap
/// (CW) in the section Z = 0, and every coast rotation found (one per touching pair).
struct Gaps {
    drive: f64,
    coast: f64,
    coast_all: Vec<f64>,
}

impl Pair {
    fn new(gear: GearData) -> Self {
        let mut m = model(gear);
        let y0 = m.initialize(0.0).unwrap();
        let g = *m.geometry();
        // Gear 1's coast flank lies the base thickness less half the thinning (the play
        // j_t at a_w less what a_w opens for unthinned teeth) clockwise of its drive flank.
        let (z1, z2) = (f64::from(gear.z1), f64::from(gear.z2));
        let alpha_t = (gear.alpha_n.tan() / gear.beta.cos()).atan();
        let inv_w0 = inv(alpha_t) + 2.0 * gear.alpha_n.tan() * (gear.x1 + gear.x2) / (z1 + z2);
        let j_t = gear.j_bn / g.cos_beta_b;
        let thinning = j_t - 2.0 * g.r_sum * (inv(g.alpha_wt) - inv_w0);
        let sb = [
            s_b(&gear, gear.z1, gear.x1) - 0.5 * thinning,
            s_b(&gear, gear.z2, gear.x2) - 0.5 * thinning,
        ];
        let mut pair = Pair {
            m,
            g,
            gear,
            y0,
            sb,
            psi2_0: 0.0,
        };
        // Calibrate gear 2 at the start (drive flanks touch, undeflected: no load): its
        // CCW-side flank passes through the drive contact point of tooth 0 at Z = 0.
        let mesh0 = g
            .mesh(&nalgebra::Vector3::zeros(), &nalgebra::Vector3::zeros())
            .unwrap();
        let f1 = pair.drive1(&y0, 0.0);
        let sigma = g.rb1 * (f1.psi_b - mesh0.theta + mesh0.alpha);
        let p = mesh0.t1 + sigma * mesh0.t;
        let (r, ang) = polar(Vector2::new(p.x, p.y), Vector2::new(g.a_w, 0.0));
        pair.psi2_0 = ang + inv((g.rb2 / r).acos());
        pair
    }

    /// Gear 1's drive flank of tooth k in the section Z = 0 (3.10): base point at
    /// phi1 + inv alpha_wt + ((k + psi0) p_bt + u1z tan beta_b) / r_b1.
    fn drive1(&self, y: &SVector<f64, NY>, k: f64) -> Flank {
        let g = &self.g;
        let psi0 = self.m.params().psi0;
        let c = Vector2::new(y[0], y[1]);
        let base =
            y[idx::PHI1] + g.inv_alpha_wt + ((k + psi0) * g.p_bt + y[2] * g.tan_beta_b) / g.rb1;
        Flank {
            c,
            rb: g.rb1,
            ra: g.ra1,
            psi_b: base,
            side: 1.0,
        }
    }

    /// The first-principles gaps of the state `moved(y0, u, dphi1, dphi2)`.
    fn gaps(&self, u: [f64; 6], dphi1: f64, dphi2: f64) -> Gaps {
        let g = &self.g;
        let y = moved(&self.y0, g, u, dphi1, dphi2);
        // Gear 2 in the state: centre moved, turned by dphi2 clockwise, its section at
        // Z = 0 at the local axial coordinate -u2z (its teeth turn by +tan(beta_b)/r_b2
        // per unit of axial coordinate, the mate of gear 1's -tan(beta_b)/r_b1).
        let c2 = Vector2::new(g.a_w + u[3], u[4]);
        let psi2 = self.psi2_0 - dphi2 - u[5] * g.tan_beta_b / g.rb2;
        let pitch2 = 2.0 * PI / f64::from(self.gear.z2);
        let mut out = Gaps {
            drive: f64::INFINITY,
            coast: f64::INFINITY,
            coast_all: Vec::new(),
        };
        // The coast zone lies ~2 alpha from the drive zone: some 3 pitches of gear 1 and
        // 5 of gear 2 away from the calibrated teeth.
        for k in -6..=6 {
            let f1 = self.drive1(&y, f64::from(k));
            let f1c = Flank {
                psi_b: f1.psi_b - self.sb[0] / g.rb1,
                side: -1.0,
                ..f1
            };
            for j in -9..=9 {
                let base = psi2 + f64::from(j) * pitch2;
                let d2 = Flank {
                    c: c2,
                    rb: g.rb2,
                    ra: g.ra2,
                    psi_b: base,
                    side: 1.0,
                };
                let c2f = Flank {
                    psi_b: base - self.sb[1] / g.rb2,
                    side: -1.0,
                    ..d2
                };
                // Only pairs of teeth that nearly touch now (the gaps are < 0.3 mm).
                // Drive: gear 2 turned CCW closes the drive gap; coast: clockwise.
                if penetration(&f1, &d2).abs() < 3e-4 {
                    if let Some(rot) = contact_rotation(&f1, &d2, 1.0) {
                        if rot.abs() < out.drive.abs() {
                            out.drive = rot;
                        }
                    }
                }
                if penetration(&f1c, &c2f).abs() < 3e-4 {
                    if let Some(rot) = contact_rotation(&f1c, &c2f, -1.0) {
                        out.coast_all.push(rot);
                        if rot.abs() < out.coast.abs() {
                            out.coast = rot;
                        }
                    }
                }
            }
        }
        out
    }
}

fn check_pair(name: &str, gear: GearData) -> (f64, f64) {
    let pair = Pair::new(gear);
    let (m, g) = (&pair.m, &pair.g);
    let z12 = f64::from(gear.z1) / f64::from(gear.z2);
    let mut worst = (0.0f64, 0.0f64);
    let states = [
        ([0.0; 6], 0.0, 0.0),
        ([2e-5, -3e-5, 0.0, -1e-5, 4e-5, 0.0], 0.01, 0.01 * z12),
        (
            [5e-5, 1e-5, 3e-5, -4e-5, -2e-5, -6e-5],
            0.07,
            0.07 * z12 + 2.5e-3,
        ),
        (
            [-3e-5, 0.0, -1e-5, 6e-5, 1e-5, 2e-5],
            0.123,
            0.123 * z12 - 1e-4,
        ),
    ];
    for (u, dphi1, dphi2) in states {
        let y = moved(&pair.y0, g, u, dphi1, dphi2);
        let delta = m.elastic_contact_at(0.0, &y).unwrap().delta;
        let delta_c = m.coast_contact_at(0.0, &y).unwrap().delta;
        // The event functions (no velocities here: phi = delta) from the drive mesh alone.
        let phi = m.flank_event_functions(0.0, &y).unwrap();
        assert!((phi[0] - delta).abs() < 1e-15 && (phi[1] - delta_c).abs() < 1e-15);
        let gaps = pair.gaps(u, dphi1, dphi2);
        // Gaps along the line of action: drive g = r_b2 (CCW turn needed), coast
        // g_c = r_b2 (CW turn needed); the model's approaches are -cos(beta_b) g.
        let g_d = g.rb2 * gaps.drive;
        let g_c = -g.rb2 * gaps.coast;
        let (gd_m, gc_m) = (-delta / g.cos_beta_b, -delta_c / g.cos_beta_b);
        println!(
            "{name} u {u:?} dphi1 {dphi1}: drive gap {g_d:.6e} (model {gd_m:.6e}), coast gap \
             {g_c:.6e} (model {gc_m:.6e})"
        );
        worst.0 = worst.0.max((g_d - gd_m).abs());
        worst.1 = worst.1.max((g_c - gc_m).abs());
    }
    worst
}

#[test]
fn coast_gap_agrees_with_the_involute_flanks() {
    let d = GearData::default();
    let cases = [
        ("default helical", d),
        ("spur", GearData { beta: 0.0, ..d }),
        (
            "shifted, a_w set, j_bn 0.2 mm",
            GearData {
                x1: 0.3,
                x2: -0.1,
                a_w: 70.7e-3,
                j_bn: 2e-4,
                beta: 0.25,
                ..d
            },
        ),
    ];
    for (name, gear) in cases {
        let (wd, wc) = check_pair(name, gear);
        let g = PairGeometry::new(&gear).unwrap();
        println!(
            "{name}: eps_alpha {:.3}; worst drive {wd:.2e} m, coast {wc:.2e} m",
            g.eps_alpha
        );
        // The sampled flanks resolve the touching rotation to ~1e-10 m.
        assert!(wd < 1e-9 && wc < 1e-9, "{name}: {wd:e} {wc:e}");
    }
}

/// Spur pair, one mesh period in 24 phases (and a shifted spur pair): every pair of teeth
/// whose coast involutes touch in the active zone needs the same rotation; their number
/// is the coast contact length over b, which tests where the model puts the coast contact
/// lines (the coast phase (3.27), from the tooth thicknesses).
#[test]
fn spur_coast_lines_sit_where_the_coast_flanks_touch() {
    let d = GearData {
        beta: 0.0,
        ..GearData::default()
    };
    for gear in [
        d,
        GearData {
            x1: 0.35,
            x2: -0.2,
            j_bn: 1.5e-4,
            ..d
        },
    ] {
        let pair = Pair::new(gear);
        let z12 = f64::from(gear.z1) / f64::from(gear.z2);
        let (mut ones, mut twos) = (0, 0);
        for i in 0..24 {
            let dphi1 = 2.0 * PI / f64::from(gear.z1) * (i as f64 + 0.37) / 24.0;
            let dphi2 = dphi1 * z12 - 2e-3;
            let y = moved(&pair.y0, &pair.g, [0.0; 6], dphi1, dphi2);
            let gaps = pair.gaps([0.0; 6], dphi1, dphi2);
            let n = gaps
                .coast_all
                .iter()
                .filter(|r| (*r - gaps.coast).abs() < 1e-8)
                .count();
            let l = pair.m.coast_contact_at(0.0, &y).unwrap().length / gear.b;
            assert_eq!(
                n as f64, l,
                "x1 {}, phase {i}: {n} pairs touch, l_c / b = {l}",
                gear.x1
            );
            if n == 1 {
                ones += 1;
            } else {
                twos += 1;
            }
        }
        println!(
            "spur x1 {}: coast pairs over a mesh period: {ones} x 1, {twos} x 2",
            gear.x1
        );
        assert!(ones > 0 && twos > 0);
    }
}
