//! Outputs of model.md §6 against their definitions, computed here from the state, the
//! §3 formulas and the powers in f.

use geared_rotor::rotor::{idx, GearedRotor, Inputs, Params, NY};
use nalgebra::{SVector, Vector3};

#[test]
fn outputs_follow_their_definitions() {
    let mut model = GearedRotor::new(Params::default()).unwrap();
    model.set_inputs(Inputs {
        omega1: 300.0,
        t_load: 20.0,
        ..Inputs::default()
    });
    let (mut ic, _) = model.static_equilibrium(0.0, 0.0).unwrap();
    ic.u_dot = [0.01, -0.02, 0.005, -0.01, 0.015, -0.004];
    let mut y = model.initialize_with(0.0, &ic).unwrap();
    y[idx::PHI1] = 0.37;
    y[idx::OMEGA1_DOT] = 55.0;
    y[6] = 3e-6; // xi
    y[idx::E_IN] = 1.5;
    let p = *model.params();
    let g = *model.geometry();
    let o = model.outputs(0.0, &y);
    let mut f = SVector::<f64, NY>::zeros();
    model.rhs(0.0, &y, &mut f).unwrap();
    let close = |a: f64, b: f64, what: &str| {
        assert!(
            (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1e-12),
            "{what}: {a} vs {b}"
        );
    };
    close(o.p_in, f[idx::E_IN], "P_in");
    close(o.p_loss, f[idx::E_LOSS], "P_loss");
    close(o.p_damp, f[idx::E_DAMP], "P_damp");
    close(o.p_in, o.t1 * o.omega1, "T1 omega1");
    close(o.e_in, 1.5, "E_in");
    close(o.fn_, y[idx::LAMBDA], "Fn");
    assert_eq!(o.contact_lost, y[idx::LAMBDA] < 0.0);
    // phi2 from xi = r_b2 phi2 - r_b1 phi1 (phi1(0) = phi2(0) = 0)
    close(o.phi2, (3e-6 + g.rb1 * 0.37) / g.rb2, "phi2");
    close(o.te, 3e-6, "TE");
    // bearing forces K u + D u'
    let k1 = p.rotor1.k;
    let d1 = p.rotor1.d;
    for i in 0..3 {
        close(
            o.f_bearing1[i],
            k1[i] * y[i] + d1[i] * y[idx::V + i],
            "F_bearing1",
        );
        close(
            o.f_bearing2[i],
            p.rotor2.k[i] * y[3 + i] + p.rotor2.d[i] * y[idx::V + 3 + i],
            "F_bearing2",
        );
    }
    // energies
    let mut ek = 0.5 * p.rotor1.j * y[idx::OMEGA1].powi(2);
    let masses = [
        p.rotor1.m, p.rotor1.m, p.rotor1.m, p.rotor2.m, p.rotor2.m, p.rotor2.m, p.rotor2.j,
    ];
    let mut ep = 0.0;
    for i in 0..7 {
        ek += 0.5 * masses[i] * y[idx::V + i].powi(2);
    }
    for i in 0..3 {
        ep += 0.5 * (k1[i] * y[i] * y[i] + p.rotor2.k[i] * y[3 + i] * y[3 + i]);
    }
    close(o.e_kin, ek, "E_kin");
    close(o.e_pot, ep, "E_pot");
    // normal force lambda n with n from model.md §3.1/§3.2
    let c1 = Vector3::new(y[0], y[1], y[2]);
    let c2 = Vector3::new(g.a_w + y[3], y[4], y[5]);
    let d = c2 - c1;
    let psi = d.y.atan2(d.x) - ((g.rb1 + g.rb2) / d.x.hypot(d.y)).acos();
    let t = Vector3::new(-psi.sin(), psi.cos(), 0.0);
    let n = g.beta_b.cos() * t + g.beta_b.sin() * Vector3::z();
    let lam = y[idx::LAMBDA];
    for i in 0..3 {
        close(
            o.f_contact2[i] - o.f_friction2[i],
            lam * n[i],
            "normal force on gear 2",
        );
        close(
            o.f_contact1[i] - o.f_friction1[i],
            -lam * n[i],
            "normal force on gear 1",
        );
        close(o.f_friction1[i], -o.f_friction2[i], "F1 = -F2");
    }
    // z-moments of the normal force: -lambda r_b1 cos(beta_b) on gear 1 (opposes omega1),
    // -lambda r_b2 cos(beta_b) about +e_z on gear 2 (drives phi2 about -e_z)
    let cb = g.beta_b.cos();
    assert!((o.m_contact1[2] - o.m_friction1[2] + lam * g.rb1 * cb).abs() < 1e-9 * lam);
    assert!((o.m_contact2[2] - o.m_friction2[2] + lam * g.rb2 * cb).abs() < 1e-9 * lam);
    // T1 = lambda r_b1 cos(beta_b) - M1_z + J1 omega1'
    close(
        o.t1,
        lam * g.rb1 * cb - o.m_friction1[2] + p.rotor1.j * 55.0,
        "T1",
    );
    // tilting moments of the normal load: integrate (lambda/l) (P - c2) x n along the lines
    // with the segments' end points (Simpson is exact for the linear integrand)
    let m = model.mesh(0.0, &y).unwrap();
    let mut mom = Vector3::zeros();
    let mut len = 0.0;
    g.for_each_segment(&m, y[idx::PHI1], p.psi0, |s| {
        let p0 = m.point(s.sigma0, s.z0);
        let p1 = p0 + s.length * m.c;
        let pm = 0.5 * (p0 + p1);
        let avg = ((p0 - c2) + 4.0 * (pm - c2) + (p1 - c2)) / 6.0;
        mom += s.length * avg.cross(&n);
        len += s.length;
    });
    close(len, o.contact_length, "contact length");
    let mn2 = lam / len * mom;
    for i in 0..3 {
        assert!(
            (o.m_contact2[i] - o.m_friction2[i] - mn2[i]).abs() < 1e-9 * lam * g.rb2,
            "normal moment on gear 2, component {i}: {} vs {}",
            o.m_contact2[i] - o.m_friction2[i],
            mn2[i]
        );
    }
    assert!(o.pairs_in_contact >= 1);
    // gap: 0 at the initial state; xi shifts it one to one
    close(o.gap, 3e-6, "gap");
}
