//! The Jacobian of the crate against central differences of f (model.md §5; its friction
//! columns are one-sided differences, so agreement is ~1e-4 of the row scale, while a wrong
//! sign or a missing term shows up at O(1)), and the energy
//! bookkeeping of f (E_in' - E_loss' - E_damp' - E_load' = d/dt (E_kin + E_pot), model.md §9.6)
//! at consistent states.

use geared_rotor::rotor::{idx, GearedRotor, Inputs, Params, NY};
use nalgebra::{SMatrix, SVector};

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

fn state(model: &mut GearedRotor, rng: &mut Rng) -> SVector<f64, NY> {
    model.set_inputs(Inputs {
        omega1: 314.159 + rng.sym(50.0),
        t_load: rng.sym(50.0),
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
    y
}

#[test]
fn jacobian_matches_central_differences() {
    let mut rng = Rng(7);
    let mut worst: f64 = 0.0;
    for beta in [20f64.to_radians(), -20f64.to_radians(), 0.0] {
        let mut p = Params::default();
        p.gear.beta = beta;
        let mut model = GearedRotor::new(p).unwrap();
        for _ in 0..20 {
            let y = state(&mut model, &mut rng);
            let mut jac = SMatrix::<f64, NY, NY>::zeros();
            assert!(model.jacobian(0.0, &y, &mut jac));
            let mut fp = SVector::<f64, NY>::zeros();
            let mut fm = SVector::<f64, NY>::zeros();
            for j in 0..NY {
                let h = if j < 7 {
                    1e-8
                } else {
                    1e-7 * y[j].abs().max(1e-2)
                };
                let (mut yp, mut ym) = (y, y);
                yp[j] += h;
                ym[j] -= h;
                // skip columns where a contact line enters/leaves between the points
                let (ok1, ok2) = (model.rhs(0.0, &yp, &mut fp), model.rhs(0.0, &ym, &mut fm));
                ok1.unwrap();
                ok2.unwrap();
                for i in 0..NY {
                    let fd = (fp[i] - fm[i]) / (yp[j] - ym[j]);
                    // row scale: largest entry of the analytic row times a typical state size
                    let row_scale = (0..NY)
                        .map(|k| jac[(i, k)].abs())
                        .fold(0.0, f64::max)
                        .max(1e-300);
                    let e = (fd - jac[(i, j)]).abs() / row_scale;
                    worst = worst.max(e);
                    assert!(
                        e < 1e-3,
                        "beta {beta}: d f{i}/d y{j}: jac {} fd {fd} (row scale {row_scale})",
                        jac[(i, j)]
                    );
                }
            }
        }
    }
    println!("jacobian: max |J - FD| / max|row| = {worst:.2e}");
}

#[test]
fn energy_rates_balance() {
    let mut rng = Rng(8);
    let mut model = GearedRotor::new(Params::default()).unwrap();
    let p = *model.params();
    let stiff = [
        p.rotor1.k[0],
        p.rotor1.k[1],
        p.rotor1.k[2],
        p.rotor2.k[0],
        p.rotor2.k[1],
        p.rotor2.k[2],
        0.0,
    ];
    let mut worst: f64 = 0.0;
    for _ in 0..200 {
        let y = state(&mut model, &mut rng);
        let mut f = SVector::<f64, NY>::zeros();
        model.rhs(0.0, &y, &mut f).unwrap();
        // d/dt E_kin = v^T M v' + J1 omega1 omega1',  d/dt E_pot = q^T K v
        let mut de = p.rotor1.j * y[idx::OMEGA1] * y[idx::OMEGA1_DOT];
        for i in 0..7 {
            de += y[idx::V + i] * f[idx::V + i] + stiff[i] * y[i] * y[idx::V + i];
        }
        let bal = f[idx::E_IN] - f[idx::E_LOSS] - f[idx::E_DAMP] - f[idx::E_LOAD];
        let e = (bal - de).abs() / f[idx::E_IN].abs().max(f[idx::E_LOSS]);
        worst = worst.max(e);
        assert!(e < 1e-9, "{bal} vs {de}");
    }
    println!("energy rate balance: max rel err {worst:.2e}");
}
