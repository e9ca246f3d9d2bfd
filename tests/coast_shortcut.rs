//! The shortcut of the elastic f (docs/model.md §3.6, issue 27 "Cost"): while the drive
//! flanks overlap at a working angle alpha >= alpha_wt the coast flanks are apart by more
//! than the play j_t (g_c = play(alpha) - g, (3.24), (3.28)), so f does not evaluate their
//! approach there. Held against the coast approach itself on random states that overlap
//! the drive flanks, for helical, spur and shifted pairs down to a 1 um backlash.

use geared_rotor::gear::GearData;
use geared_rotor::rotor::{idx, GearedRotor, InitialConditions, Inputs, Params, ToothContact};

struct Rng(u64);

impl Rng {
    fn sym(&mut self, a: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        a * (2.0 * (self.0 >> 11) as f64 / (1u64 << 53) as f64 - 1.0)
    }
}

#[test]
fn overlapping_drive_flanks_at_alpha_wt_or_more_leave_the_coast_apart() {
    let d = Params::default().gear;
    let pairs = [
        ("helical", d),
        ("spur", GearData { beta: 0.0, ..d }),
        (
            "shifted, j_bn 1 um",
            GearData {
                x1: 0.3,
                x2: -0.1,
                j_bn: 1e-6,
                ..d
            },
        ),
    ];
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for (name, gear) in pairs {
        let p = Params {
            gear,
            tooth_contact: ToothContact::Elastic,
            ..Params::default()
        };
        let mut model = GearedRotor::new(p).unwrap();
        model.set_inputs(Inputs {
            omega1: 314.159,
            t_load: 50.0,
            ..Inputs::default()
        });
        let g = *model.geometry();
        let j_t = gear.j_bn / g.cos_beta_b;
        let y0 = model
            .initialize_with(0.0, &InitialConditions::default())
            .unwrap();
        let (mut taken, mut closest) = (0, f64::INFINITY);
        for _ in 0..20_000 {
            let mut y = y0;
            // Centre displacements up to the backlash's size, any mesh phase, TE from
            // just touching to deep overlap.
            for j in 0..6 {
                y[idx::Q + j] = rng.sym(1e-4);
            }
            y[idx::PHI1] = rng.sym(10.0);
            y[idx::Q + 6] = rng.sym(3e-5);
            let (Some(drive), Some(coast), Ok(m)) = (
                model.elastic_contact_at(0.0, &y),
                model.coast_contact_at(0.0, &y),
                model.mesh(0.0, &y),
            ) else {
                continue;
            };
            if drive.delta > 0.0 && m.alpha >= g.alpha_wt {
                taken += 1;
                // delta_c = -cos(beta_b) g_c with g_c > j_t.
                let gc = -coast.delta / g.cos_beta_b;
                closest = closest.min(gc / j_t);
                assert!(gc > j_t * (1.0 - 1e-9), "{name}: g_c {gc:e} <= j_t {j_t:e}");
            }
        }
        println!("{name}: {taken} states with the shortcut, smallest g_c / j_t {closest:.6}");
        assert!(taken > 1000, "{name}: {taken}");
    }
}
