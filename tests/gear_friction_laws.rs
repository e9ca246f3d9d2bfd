//! Friction laws 2-4 at the level of one contact line and of the pair (docs/friction.md):
//! - law 2 (regularised Coulomb): closed forms against adaptive quadrature of the
//!   regularised integrands (split where x changes sign), and convergence of the mean loss
//!   to Coulomb's as v_reg -> 0 (rate reported);
//! - law 3 (ISO/TR 14179-2 mean coefficient, Schlenk): the crate's mu_mz against this file's
//!   own evaluation of the published formula at operating points of the default pair;
//! - law 4 (Xu et al. 2007 local EHL coefficient): mu at random points against the
//!   literal published formula, and the five line integrals with mu(s) against adaptive
//!   quadrature of this file's own local law;
//! - virtual power `Q_f^T q' + M1_z omega1 = -P_loss` for every law at random states.

mod common;

/// Log-uniform in [lo, hi) (the shared Rng::log takes decimal exponents).
fn lg(rng: &mut common::rng::Rng, lo: f64, hi: f64) -> f64 {
    rng.log(lo.log10(), hi.log10())
}

use common::gear::{gear_sets, reference_circles};
use common::quad::gauss_legendre;
use common::rng::Rng;
use geared_rotor::gear::friction::ehl::mu_xu;
use geared_rotor::gear::friction::mu_mz;
use geared_rotor::gear::friction::regularised::regularised_integrals;
use geared_rotor::gear::{
    line_integrals, EhlLine, FrictionParams, GearData, IsoMean, Kinematics, LineIntegrals, LineLaw,
    Lubricant, PairGeometry,
};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Adaptive Gauss-Legendre (20 points against two halves of 20) of six integrands given
/// by one closure, over [a, b]: an interval is accepted when every component's change,
/// divided by its `scale`, is below `tol` (scaled by the interval's share of the whole),
/// or when it is shorter than 1e-12 of the whole.
fn adapt5(f: &dyn Fn(f64) -> [f64; 6], a: f64, b: f64, tol: f64, scale: [f64; 6]) -> [f64; 6] {
    let (x, w) = gauss_legendre(20);
    let rule = |a: f64, b: f64| {
        let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
        let mut acc = [0.0; 6];
        for i in 0..x.len() {
            let v = f(c + h * x[i]);
            for k in 0..6 {
                acc[k] += h * w[i] * v[k];
            }
        }
        acc
    };
    let total = b - a;
    let mut stack = vec![(a, b, rule(a, b))];
    let mut sum = [0.0; 6];
    while let Some((a, b, whole)) = stack.pop() {
        let m = 0.5 * (a + b);
        let (l, r) = (rule(a, m), rule(m, b));
        let err = (0..6)
            .map(|k| (l[k] + r[k] - whole[k]).abs() / scale[k])
            .fold(0.0, f64::max);
        if err <= tol * (b - a) / total || (b - a) < 1e-12 * total {
            for k in 0..6 {
                sum[k] += l[k] + r[k];
            }
        } else {
            stack.push((a, m, l));
            stack.push((m, b, r));
        }
    }
    sum
}

/// Reference integrals of the local law `mu(s) v_T/|v_T|`-type integrands, split at the
/// sign change of x: returns (I_x, I_y, K_x, K_y, W, int mu).
fn reference(
    x0: f64,
    y: f64,
    kappa: f64,
    len: f64,
    scale: [f64; 6],
    integrand: &dyn Fn(f64, f64, f64) -> [f64; 6],
) -> [f64; 6] {
    let f = |s: f64| {
        let x = x0 - kappa * s;
        integrand(s, x, y)
    };
    let root = if kappa != 0.0 { x0 / kappa } else { f64::NAN };
    let parts: Vec<(f64, f64)> = if root > 0.0 && root < len {
        vec![(0.0, root), (root, len)]
    } else {
        vec![(0.0, len)]
    };
    let mut acc = [0.0; 6];
    for (a, b) in parts {
        let v = adapt5(&f, a, b, 1e-14, scale);
        for k in 0..6 {
            acc[k] += v[k];
        }
    }
    acc
}

/// Largest error of the five integrals, each relative to its natural scale
/// (L for I, L^2 for K, the magnitude of W).
fn rel_err(li: &LineIntegrals, r: &[f64; 6], len: f64, w_scale: f64) -> f64 {
    let e = [
        (li.ix - r[0]).abs() / len,
        (li.iy - r[1]).abs() / len,
        (li.kx - r[2]).abs() / (len * len),
        (li.ky - r[3]).abs() / (len * len),
        (li.w - r[4]).abs() / w_scale,
    ];
    e.iter().cloned().fold(0.0, f64::max)
}

/// Random line cases over the regimes of the Coulomb integrals: sign change inside, near an end,
/// kappa -> 0, y -> 0, y = 0.
fn line_case(rng: &mut Rng, i: usize) -> (f64, f64, f64, f64) {
    let len = 0.005 + 0.02 * rng.next();
    let kappa = match i % 5 {
        0 => rng.sym(1e-6),
        _ => 100.0 * rng.sign() * (0.2 + rng.next()),
    };
    let root = match i % 4 {
        0 => len * rng.next(),
        1 => len * (1.0 + rng.sym(1e-6)),
        2 => -len * rng.next(),
        _ => len * (1.0 + 3.0 * rng.next()),
    };
    let x0 = if i.is_multiple_of(5) {
        rng.sym(3.0)
    } else {
        kappa * root
    };
    let y = match i % 3 {
        0 => 0.0,
        1 => rng.sym(1e-3),
        _ => rng.sym(0.5),
    };
    (x0, y, kappa, len)
}

#[test]
fn law2_closed_forms_match_adaptive_quadrature() {
    let mut rng = Rng(21);
    let mut worst: f64 = 0.0;
    for i in 0..250 {
        let (x0, y, kappa, len) = line_case(&mut rng, i);
        let v_reg = lg(&mut rng, 1e-4, 1.0);
        let li = regularised_integrals(x0, y, kappa, len, v_reg);
        let v2 = v_reg * v_reg;
        let integrand = |s: f64, x: f64, y: f64| {
            let big_r = (x * x + y * y + v2).sqrt();
            [
                x / big_r,
                y / big_r,
                s * x / big_r,
                s * y / big_r,
                (x * x + y * y) / big_r,
                0.0,
            ]
        };
        let x1 = x0 - kappa * len;
        let w_scale = len * (x0.abs().max(x1.abs()).max(y.abs())).max(1e-300);
        let r = reference(
            x0,
            y,
            kappa,
            len,
            [len, len, len * len, len * len, w_scale, len],
            &integrand,
        );
        let e = rel_err(&li, &r, len, w_scale);
        assert!(
            e < 1e-10,
            "law 2 case {i}: x0 {x0} y {y} kappa {kappa} len {len} v_reg {v_reg}: {li:?} vs {r:?}: {e:e}"
        );
        worst = worst.max(e);
    }
    println!("law 2: worst error of the closed forms against adaptive quadrature {worst:.2e}");
}

/// Default pair in rigid rotation: phase mean of the loss per unit mu |lambda| / l.
fn mean_loss(g: &PairGeometry, law: &LineLaw) -> f64 {
    let m = g.mesh(&Vector3::zeros(), &Vector3::zeros()).unwrap();
    let omega1 = 314.159;
    let k = Kinematics {
        v1: Vector3::zeros(),
        v2: Vector3::zeros(),
        omega1,
        omega2: omega1 * g.rb1 / g.rb2,
    };
    let n = 2000;
    let mut acc = 0.0;
    for i in 0..n {
        let phi1 = (i as f64 + 0.5) / n as f64 * 2.0 * PI / g.data.z1 as f64;
        let s = g.friction_sums_line(&m, phi1, 0.0, &k, law);
        acc += s.resultants(1.0, 1.0).p_loss;
    }
    acc / n as f64
}

#[test]
fn law2_loss_converges_to_coulomb_as_v_reg_vanishes() {
    for (label, d) in [
        ("helical default", GearData::default()),
        (
            "spur",
            GearData {
                beta: 0.0,
                ..GearData::default()
            },
        ),
    ] {
        let g = PairGeometry::new(&d).unwrap();
        let p1 = mean_loss(&g, &LineLaw::Coulomb);
        let mut prev = f64::INFINITY;
        let mut rows = Vec::new();
        for k in 1..=6 {
            let v_reg = 10f64.powi(-k);
            let p2 = mean_loss(
                &g,
                &LineLaw::Regularised {
                    v_reg,
                    with_mean: false,
                },
            );
            let d = (p1 - p2) / p1;
            assert!(
                d > 0.0,
                "{label}: the regularised loss must be below Coulomb's"
            );
            assert!(d < prev, "{label}: no convergence at v_reg {v_reg}: {d:e}");
            rows.push((v_reg, d));
            prev = d;
        }
        let rates: Vec<f64> = rows.windows(2).map(|w| (w[0].1 / w[1].1).log10()).collect();
        println!(
            "{label}: (v_reg, (P1 - P2)/P1) = {rows:?}; observed order per decade {rates:.3?}"
        );
        // Second order in v_reg (with a logarithm for helical lines through the pitch
        // line: v_reg^2 ln(1/v_reg)), so more than 1.5 decades per decade.
        assert!(rates.iter().all(|&r| r > 1.5), "{label}: rates {rates:?}");
        assert!(rows[5].1 < 1e-9, "{label}: {:e}", rows[5].1);
    }
}

/// The published formula of ISO/TR 14179-2 (Schlenk), written here from its definition:
/// F_bt/b [N/mm], v_SigmaC [m/s], rho_redC [mm], eta [mPa s], Ra [um].
fn schlenk(fbt_b: f64, v_sum: f64, rho: f64, eta: f64, ra: f64, x_l: f64) -> f64 {
    // as a product of logarithms, not the crate's sequence of powers
    (0.048f64.ln() + 0.2 * (fbt_b.ln() - v_sum.ln() - rho.ln()) - 0.05 * eta.ln() + 0.25 * ra.ln())
        .exp()
        * x_l
}

#[test]
fn law3_mu_mz_matches_the_published_formula() {
    let mut rng = Rng(33);
    let mut worst: f64 = 0.0;
    // the plain formula at random operating points in its range
    for _ in 0..200 {
        let (f, v, rho, eta, ra, xl) = (
            lg(&mut rng, 50.0, 2000.0),
            lg(&mut rng, 1.0, 60.0),
            lg(&mut rng, 2.0, 30.0),
            lg(&mut rng, 5.0, 500.0),
            lg(&mut rng, 0.1, 2.0),
            0.6 + 0.5 * rng.next(),
        );
        let e = (mu_mz(f, v, rho, eta, ra, xl) / schlenk(f, v, rho, eta, ra, xl) - 1.0).abs();
        worst = worst.max(e);
    }
    assert!(worst < 1e-12, "mu_mz formula: {worst:e}");
    // the pair's operating point: F_bt = lambda cos beta_b, v_SigmaC = 2 v_t sin alpha_wt,
    // rho_redC from the pitch-point radii, from this file's own geometry (x1 = x2 = 0).
    let d = GearData::default();
    let (at, r1, _r2, rb1, rb2) = reference_circles(&d);
    let beta_b = (d.beta.sin() * d.alpha_n.cos()).asin();
    let (rho1, rho2) = (rb1 * at.tan() * 1e3, rb2 * at.tan() * 1e3);
    let rho_red = rho1 * rho2 / ((rho1 + rho2) * beta_b.cos());
    let fp = FrictionParams::default();
    let g = PairGeometry::new(&d).unwrap();
    let iso = IsoMean::new(
        d.b,
        g.rb1,
        g.rb2,
        g.alpha_wt,
        g.cos_beta_b,
        fp.eta_oil,
        fp.ra,
        fp.x_l,
    );
    let mut rows = Vec::new();
    for (rpm, lambda) in [
        (1500.0, 500.0),
        (2000.0, 1500.0),
        (2500.0, 2700.0),
        (3000.0, 2700.0),
        (3000.0, 6000.0),
        (6000.0, 12000.0),
    ] {
        let omega1 = rpm * PI / 30.0;
        let omega2 = omega1 * d.z1 as f64 / d.z2 as f64;
        let v_t = omega1 * r1 * at.cos() / at.cos(); // pitch radius r_w1 = r1 for x = 0
        let v_sum = 2.0 * v_t * at.sin();
        let fbt_b = lambda * beta_b.cos() / (d.b * 1e3);
        let want = schlenk(fbt_b, v_sum, rho_red, fp.eta_oil * 1e3, fp.ra * 1e6, fp.x_l);
        let got = iso.mu(lambda, omega1, omega2);
        let e = (got / want - 1.0).abs();
        rows.push((rpm, lambda, got));
        assert!(
            e < 1e-12,
            "{rpm} rpm, lambda {lambda}: {got} vs {want}: {e:e}"
        );
    }
    println!("law 3: (rpm, lambda [N], mu_mz) = {rows:.5?}; formula worst {worst:.1e}");
}

/// Xu et al. (2007) written here from the paper's definitions (P_h GPa, V_e m/s, nu0 cP,
/// R m, S um), with `powf` for every factor.
fn xu(p_h: f64, sr: f64, v_e: f64, nu0: f64, r: f64, s: f64) -> f64 {
    let b = [
        -8.916465, 1.03303, 1.036077, -0.354068, 2.812084, -0.100601, 0.752755, -0.390958, 0.620305,
    ];
    let z = sr.abs() * p_h * nu0.log10();
    let f = b[0] + b[3] * z + b[4] * (-z).exp() + b[8] * s.exp();
    f.exp() * p_h.powf(b[1]) * sr.abs().powf(b[2]) * v_e.powf(b[5]) * nu0.powf(b[6]) * r.powf(b[7])
}

/// The local law 4 of this file at sigma on the line of action: (mu, R, V_e, P_h).
#[allow(clippy::too_many_arguments)]
fn local_mu(
    sigma: f64,
    r_slide: f64,
    q: f64,
    omega: (f64, f64),
    lt: f64,
    cb: f64,
    lub: &Lubricant,
) -> f64 {
    let (rho1, rho2) = (sigma, lt - sigma);
    let big_r = rho1 * rho2 / (rho1 + rho2) / cb;
    let v_e = 0.5 * (omega.0 * rho1 + omega.1 * rho2);
    let p_h = (q * lub.e_reduced / (2.0 * PI * big_r)).sqrt() / 1e9;
    xu(
        p_h,
        r_slide / v_e,
        v_e,
        lub.eta_oil * 1e3,
        big_r,
        lub.roughness * 1e6,
    )
}

#[test]
fn law4_mu_matches_the_published_formula_at_random_points() {
    let mut rng = Rng(44);
    let mut worst: f64 = 0.0;
    for _ in 0..2000 {
        let (p_h, sr, v_e, nu, r, s) = (
            lg(&mut rng, 0.3, 3.0),
            rng.sym(1.5),
            lg(&mut rng, 0.5, 40.0),
            lg(&mut rng, 2.0, 300.0),
            lg(&mut rng, 1e-3, 0.05),
            lg(&mut rng, 0.05, 1.5),
        );
        let e = (mu_xu(p_h, sr, v_e, nu, r, s) / xu(p_h, sr, v_e, nu, r, s) - 1.0).abs();
        assert!(e.is_finite(), "{p_h} {sr} {v_e} {nu} {r} {s}");
        worst = worst.max(e);
    }
    // the line law at random loads, speeds and positions
    for _ in 0..2000 {
        let lub = Lubricant {
            eta_oil: lg(&mut rng, 0.005, 0.3),
            roughness: lg(&mut rng, 0.05e-6, 1.5e-6),
            e_reduced: Lubricant::reduced_modulus(
                lg(&mut rng, 1e11, 3e11),
                0.25 + 0.1 * rng.next(),
                lg(&mut rng, 1e11, 3e11),
                0.25 + 0.1 * rng.next(),
            ),
        };
        let q = lg(&mut rng, 1e4, 1e6);
        let omega = (lg(&mut rng, 50.0, 1000.0), lg(&mut rng, 50.0, 1000.0));
        let (lt, beta_b) = (0.02 + 0.03 * rng.next(), 0.4 * rng.next());
        let e = EhlLine::new(&lub, q, omega.0, omega.1, lt, beta_b.cos(), beta_b.sin());
        let sigma = lt * (0.05 + 0.9 * rng.next());
        let r_slide = lg(&mut rng, 1e-4, 10.0);
        let want = local_mu(sigma, r_slide, q, omega, lt, beta_b.cos(), &lub);
        let got = e.mu_at(sigma, r_slide);
        let err = (got / want - 1.0).abs();
        assert!(err.is_finite() && want > 0.0, "mu {got} vs {want}");
        worst = worst.max(err);
    }
    println!("law 4: mu against the published formula, worst relative error {worst:.2e}");
    assert!(worst < 1e-12, "{worst:e}");
}

/// One law-4 segment of the line tests: the line load q, the speeds, the line of action
/// (length lt, base helix angle beta_b), the sliding x(s) = x0 - kappa s, the axial
/// sliding y, the segment length and sigma at its start.
#[derive(Debug, Clone, Copy)]
struct Law4Line {
    q: f64,
    omega: (f64, f64),
    lt: f64,
    beta_b: f64,
    x0: f64,
    y: f64,
    kappa: f64,
    len: f64,
    sigma0: f64,
}

impl Law4Line {
    /// Largest error of the crate's six segment integrals against adaptive quadrature of
    /// the published local law, each relative to its natural scale: I, K relative to
    /// mu ~ 0.1 times their Coulomb scale, W to 0.1 L max|v_T|, int mu ds to 0.1 L.
    fn error(&self, lub: &Lubricant) -> f64 {
        let Law4Line {
            q,
            omega,
            lt,
            beta_b,
            x0,
            y,
            kappa,
            len,
            sigma0,
        } = *self;
        let (sb, cb) = beta_b.sin_cos();
        let e = EhlLine::new(lub, q, omega.0, omega.1, lt, cb, sb);
        let (li, mu_int) = e.segment_integrals(x0, y, kappa, len, sigma0);
        let integrand = |s: f64, x: f64, y: f64| {
            let r = (x * x + y * y).sqrt();
            if r == 0.0 {
                return [0.0; 6];
            }
            let mu = local_mu(sigma0 - sb * s, r, q, omega, lt, cb, lub);
            [
                mu * x / r,
                mu * y / r,
                s * mu * x / r,
                s * mu * y / r,
                mu * r,
                mu,
            ]
        };
        let x1 = x0 - kappa * len;
        let w_scale = 0.1 * len * x0.abs().max(x1.abs()).max(y.abs());
        let sc = 0.1 * len;
        let r = reference(
            x0,
            y,
            kappa,
            len,
            [sc, sc, sc * len, sc * len, w_scale, sc],
            &integrand,
        );
        let err = rel_err(&li, &r, len, w_scale / 0.1) / 0.1;
        err.max((mu_int - r[5]).abs() / (0.1 * len))
    }
}

#[test]
fn law4_line_integrals_match_adaptive_quadrature() {
    let mut rng = Rng(45);
    let fp = FrictionParams::default();
    let lub = fp.lubricant();
    let mut worst: f64 = 0.0;
    let mut worst_y: f64 = 0.0;
    // worst over the lines of run-like axial sliding (the cases from 2000 on) and how many
    // of their pieces have 3e-6 <= delta/far <= 1e-2
    let mut worst_run: f64 = 0.0;
    let mut run_pieces = 0;
    for i in 0..3000u32 {
        // a line of the default pair's size: sigma in the active part of the line of action
        let lt = 0.026;
        let beta_b: f64 = if i.is_multiple_of(7) { 0.0 } else { 0.33 };
        let sb = beta_b.sin();
        let omega = (314.159 * (0.3 + rng.next()), 206.9 * (0.3 + rng.next()));
        let q = lg(&mut rng, 1e4, 4e5);
        let len = 0.004 + 0.016 * rng.next();
        let sigma0 = 0.004 + 0.018 * rng.next();
        let len = len.min((sigma0 - 0.002) / sb.max(1e-300));
        let kappa = (omega.0 + omega.1) * sb;
        // x(s) = x_base + (omega1 + omega2) sigma(s): rolling at sigma_p = omega2 lt / sum
        let jitter = if i.is_multiple_of(3) {
            rng.sym(0.3)
        } else {
            0.0
        };
        let x0 = -omega.1 * lt + (omega.0 + omega.1) * sigma0 + jitter;
        // axial sliding from none over tiny (both sides of the quadrature's switch at
        // delta = 3e-6 d_far) to a third of the sliding at the tips
        let root = x0 / kappa;
        // distances of the two ends from the pitch line (the far ends of the pieces)
        let ends = [root.abs(), (len - root).abs()];
        let y = match i % 4 {
            // as in a run: delta = |y / kappa| log-uniform from 1e-6 to 3e-2 of the
            // larger far end (the bearings' and the transmission error's small sliding)
            _ if i >= 2000 => rng.sign() * kappa * ends[0].max(ends[1]) * lg(&mut rng, 1e-6, 3e-2),
            0 => 0.0,
            1 => rng.sym(1.0) * 10f64.powi(-3 - (i % 9) as i32),
            2 => rng.sym(1e-2),
            _ => rng.sym(0.3),
        };
        let line = Law4Line {
            q,
            omega,
            lt,
            beta_b,
            x0,
            y,
            kappa,
            len,
            sigma0,
        };
        let err = line.error(&lub);
        assert!(err.is_finite(), "case {i}: {line:?}");
        if i >= 2000 {
            worst_run = worst_run.max(err);
            let delta = (y / kappa).abs();
            // the pieces' far ends: both ends when the pitch line lies inside the segment
            let fars = if root > 0.0 && root < len {
                ends
            } else {
                [ends[0].max(ends[1]); 2]
            };
            let n_pieces = if root > 0.0 && root < len { 2 } else { 1 };
            run_pieces += fars[..n_pieces]
                .iter()
                .filter(|&&d| (3e-6..=1e-2).contains(&(delta / d)))
                .count();
        } else if y == 0.0 {
            worst = worst.max(err);
        } else {
            worst_y = worst_y.max(err);
        }
        assert!(err < 1e-10, "case {i}: {line:?}: {err:e}");
    }
    println!(
        "law 4: line integrals against adaptive quadrature: worst {worst:.2e} (y = 0), {worst_y:.2e} (axial sliding y != 0), {worst_run:.2e} (run-like axial sliding, {run_pieces} pieces with 3e-6 <= delta/far <= 1e-2)"
    );
    assert!(run_pieces >= 700, "{run_pieces}");
}

/// Pieces that end near the pitch line without reaching it (the root of x just outside
/// the segment, at `near` from its end) with small axial sliding: the expansion in delta
/// on [0, h0] minus [0, near] (near < 0.1 h0), both for near below and above 100 delta,
/// and the pieces starting at the root as a control. Built so that each class is present:
/// at this line's size z stays below 1, so h0 is the far end of the piece.
#[test]
fn law4_pieces_ending_near_the_pitch_line_match_adaptive_quadrature() {
    let mut rng = Rng(47);
    let lub = FrictionParams::default().lubricant();
    let (lt, beta_b) = (0.026, 0.33f64);
    let mut worst = [0.0f64; 3];
    let mut counts = [0usize; 3];
    for i in 0..600u32 {
        let omega = (314.159 * (0.3 + rng.next()), 206.9 * (0.3 + rng.next()));
        let q = lg(&mut rng, 1e4, 4e5);
        let len = 0.004 + 0.012 * rng.next();
        let sigma0 = 0.008 + 0.012 * rng.next();
        let kappa = (omega.0 + omega.1) * beta_b.sin();
        let delta = len * lg(&mut rng, 1e-9, 1e-5);
        // class 0: near < 100 delta; class 1: 100 delta <= near <= 0.05 len; 2: near = 0
        let class = (i % 3) as usize;
        let near = match class {
            0 => delta * lg(&mut rng, 0.1, 99.0),
            1 => (100.0 * delta).max(len * lg(&mut rng, 1e-6, 0.05)),
            _ => 0.0,
        };
        // the root before the start (x0 < 0 side) or after the end of the segment
        let root = if rng.next() < 0.5 { -near } else { len + near };
        let line = Law4Line {
            q,
            omega,
            lt,
            beta_b,
            x0: kappa * root,
            y: rng.sign() * kappa * delta,
            kappa,
            len,
            sigma0,
        };
        let err = line.error(&lub);
        assert!(
            err < 1e-10,
            "case {i} (class {class}, near {near}): {line:?}: {err:e}"
        );
        worst[class] = worst[class].max(err);
        counts[class] += 1;
    }
    println!(
        "law 4, pieces ending near the pitch line: worst {:.2e} (near < 100 delta), {:.2e} (near >= 100 delta), {:.2e} (at the root)",
        worst[0], worst[1], worst[2]
    );
    assert!(counts.iter().all(|&c| c >= 200), "{counts:?}");
}

#[test]
fn virtual_power_equals_minus_loss_for_every_law() {
    let mut rng = Rng(46);
    let lub = FrictionParams::default().lubricant();
    let mut worst = [0.0f64; 3];
    for d in gear_sets() {
        let g = PairGeometry::new(&d).unwrap();
        for i in 0..600u32 {
            let u1 = Vector3::new(rng.sym(5e-5), rng.sym(5e-5), rng.sym(5e-5));
            let u2 = Vector3::new(rng.sym(5e-5), rng.sym(5e-5), rng.sym(5e-5));
            let m = g.mesh(&u1, &u2).unwrap();
            let omega1 = 50.0 + 350.0 * rng.next();
            let omega2 = omega1 * g.rb1 / g.rb2 * (1.0 + rng.sym(1e-3));
            let vs = if i.is_multiple_of(3) { 1e-6 } else { 0.5 };
            let k = Kinematics {
                v1: Vector3::new(rng.sym(vs), rng.sym(vs), rng.sym(vs)),
                v2: Vector3::new(rng.sym(vs), rng.sym(vs), rng.sym(vs)),
                omega1,
                omega2,
            };
            let phi1 = rng.sym(1e4);
            let lambda = rng.sym(5000.0);
            let l = g.contact_summary(&m, phi1, 0.3).length;
            if l == 0.0 {
                continue;
            }
            let laws = [
                LineLaw::Regularised {
                    v_reg: lg(&mut rng, 1e-4, 1.0),
                    with_mean: false,
                },
                LineLaw::Ehl(EhlLine::new(
                    &lub,
                    lambda.abs() / l,
                    omega1,
                    omega2,
                    m.len_t1t2,
                    g.cos_beta_b,
                    g.sin_beta_b,
                )),
                LineLaw::Coulomb,
            ];
            for (j, law) in laws.iter().enumerate() {
                let s = g.friction_sums_line(&m, phi1, 0.3, &k, law);
                let mu = if j == 1 { 1.0 } else { 0.05 };
                let fr = s.resultants(mu, lambda);
                let terms = [
                    fr.f1.dot(&k.v1),
                    fr.f2.dot(&k.v2),
                    -fr.m2.z * k.omega2,
                    fr.m1.z * k.omega1,
                ];
                let sum: f64 = terms.iter().sum();
                let scale = terms.iter().fold(fr.p_loss, |a, t| a.max(t.abs()));
                let e = (sum + fr.p_loss).abs() / scale.max(1e-300);
                assert!(fr.p_loss >= 0.0);
                assert!(e < 1e-12, "law {j}: {sum} vs -{}", fr.p_loss);
                worst[j] = worst[j].max(e);
            }
        }
    }
    println!("virtual power, worst relative residual (law 2, law 4, Coulomb): {worst:?}");
}

#[test]
fn law2_sums_reduce_to_coulomb_shapes() {
    // Independent identity: for y = 0 the regularised I_x equals Coulomb's I_x with y = v_reg.
    let li = regularised_integrals(0.3, 0.0, 50.0, 0.01, 0.02);
    let c = line_integrals(0.3, 0.02, 50.0, 0.01);
    assert_eq!((li.ix, li.kx, li.iy, li.ky), (c.ix, c.kx, 0.0, 0.0));
}

/// Adaptive Gauss-Legendre (20 points against two halves) of N integrands over [a, b],
/// each component's change measured against its own `scale`.
fn adapt_n<const N: usize>(
    f: &dyn Fn(f64) -> [f64; N],
    a: f64,
    b: f64,
    tol: f64,
    scale: &[f64; N],
) -> [f64; N] {
    let (x, w) = gauss_legendre(20);
    let rule = |a: f64, b: f64| {
        let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
        let mut acc = [0.0; N];
        for i in 0..x.len() {
            let v = f(c + h * x[i]);
            for k in 0..N {
                acc[k] += h * w[i] * v[k];
            }
        }
        acc
    };
    let total = b - a;
    let mut stack = vec![(a, b, rule(a, b))];
    let mut sum = [0.0; N];
    while let Some((a, b, whole)) = stack.pop() {
        let m = 0.5 * (a + b);
        let (l, r) = (rule(a, m), rule(m, b));
        let err = (0..N)
            .map(|k| (l[k] + r[k] - whole[k]).abs() / scale[k])
            .fold(0.0, f64::max);
        if err <= tol * (b - a) / total || (b - a) < 1e-13 * total {
            for k in 0..N {
                sum[k] += l[k] + r[k];
            }
        } else {
            stack.push((a, m, l));
            stack.push((m, b, r));
        }
    }
    sum
}

/// Law 4 on whole gear states: the crate's friction resultants (F2, M1, M2 and P_loss from
/// `friction_sums_line`) against this file's own assembly: the force density
/// `-q mu(s) v_T / |v_T|` on gear 2, with v_T the tangential part of the relative velocity
/// at each point of each contact line (written here from the kinematics of rigid gears on
/// moving centres) and mu from this file's local law, integrated adaptively along every
/// line (split where the sliding across the line changes sign). Random states of six gear
/// sets (helical both hands, spur) with bearing velocities up to 0.5 m/s, so that the
/// lines slide along themselves (axial sliding) too.
#[test]
fn law4_resultants_match_adaptive_quadrature_on_random_gear_states() {
    let mut rng = Rng(47);
    let lub = FrictionParams::default().lubricant();
    let mut worst: f64 = 0.0;
    let mut cases = 0;
    for d in gear_sets() {
        let g = PairGeometry::new(&d).unwrap();
        let (sb, cb) = (g.sin_beta_b, g.cos_beta_b);
        for i in 0..40u32 {
            let u1 = Vector3::new(rng.sym(3e-5), rng.sym(3e-5), rng.sym(3e-5));
            let u2 = Vector3::new(rng.sym(3e-5), rng.sym(3e-5), rng.sym(3e-5));
            let m = g.mesh(&u1, &u2).unwrap();
            let omega1 = 100.0 + 300.0 * rng.next();
            let omega2 = omega1 * g.rb1 / g.rb2 * (1.0 + rng.sym(1e-3));
            let vs = [0.0, 1e-6, 1e-3, 0.5][i as usize % 4];
            let k = Kinematics {
                v1: Vector3::new(rng.sym(vs), rng.sym(vs), rng.sym(vs)),
                v2: Vector3::new(rng.sym(vs), rng.sym(vs), rng.sym(vs)),
                omega1,
                omega2,
            };
            let phi1 = rng.sym(1e3);
            let lambda = 200.0 + 5000.0 * rng.next();
            let psi0 = 0.3;
            let mut segs = Vec::new();
            let summary = g.for_each_segment(&m, phi1, psi0, |s| segs.push(*s));
            let l = summary.length;
            if l == 0.0 {
                continue;
            }
            let q = lambda / l;
            let e = EhlLine::new(&lub, q, omega1, omega2, m.len_t1t2, cb, sb);
            let fr = g
                .friction_sums_line(&m, phi1, psi0, &k, &LineLaw::Ehl(e))
                .resultants(1.0, lambda);
            // local frame (e_w, t, e_z): relative velocity of gear 2 against gear 1 at P
            let dv = k.v2 - k.v1;
            let (cp, sp) = (m.cos_psi, m.sin_psi);
            let dvl = [dv.x * cp + dv.y * sp, -dv.x * sp + dv.y * cp, dv.z];
            let lt = m.len_t1t2;
            let c = [0.0, -sb, cb];
            let cross = |a: [f64; 3], b: [f64; 3]| {
                [
                    a[1] * b[2] - a[2] * b[1],
                    a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0],
                ]
            };
            let mut sum = [0.0f64; 10];
            for seg in &segs {
                let point = |s: f64| -> [f64; 10] {
                    let sigma = seg.sigma0 - sb * s;
                    let zz = seg.z0 + cb * s;
                    let v = [
                        dvl[0] + (omega1 + omega2) * sigma - omega2 * lt,
                        dvl[1] + omega2 * g.rb2 - omega1 * g.rb1,
                        dvl[2],
                    ];
                    let (vw, vc) = (v[0], v[1] * c[1] + v[2] * c[2]);
                    let r = (vw * vw + vc * vc).sqrt();
                    if r == 0.0 {
                        return [0.0; 10];
                    }
                    let mu = local_mu(sigma, r, q, (omega1, omega2), lt, cb, &lub);
                    // force density on gear 2 in local components
                    let f2 = [
                        -q * mu * vw / r,
                        -q * mu * vc * c[1] / r,
                        -q * mu * vc * c[2] / r,
                    ];
                    let m2 = cross([-g.rb2, sigma - lt, zz - m.c2.z], f2);
                    let m1 = cross([g.rb1, sigma, zz - m.c1.z], [-f2[0], -f2[1], -f2[2]]);
                    [
                        f2[0],
                        f2[1],
                        f2[2],
                        m1[0],
                        m1[1],
                        m1[2],
                        m2[0],
                        m2[1],
                        m2[2],
                        q * mu * r,
                    ]
                };
                // sliding across the line x(s) is linear: split at its root
                let x_at = |s: f64| point(s);
                let x0 = dvl[0] + (omega1 + omega2) * seg.sigma0 - omega2 * lt;
                let kappa = (omega1 + omega2) * sb;
                let root = if kappa != 0.0 { x0 / kappa } else { f64::NAN };
                let parts: Vec<(f64, f64)> = if root > 0.0 && root < seg.length {
                    vec![(0.0, root), (root, seg.length)]
                } else {
                    vec![(0.0, seg.length)]
                };
                // natural scales: the friction force ~ 0.05 lambda, its moments ~ that
                // times a_w, the loss ~ that times a few m/s
                let mut scale = [0.05 * lambda; 10];
                for sc in scale.iter_mut().skip(3).take(6) {
                    *sc *= g.a_w;
                }
                for (a, b) in parts {
                    let v = adapt_n(&x_at, a, b, 1e-14, &scale);
                    for k in 0..10 {
                        sum[k] += v[k];
                    }
                }
            }
            let f2 = m.to_inertial(sum[0], sum[1], sum[2]);
            let m1 = m.to_inertial(sum[3], sum[4], sum[5]);
            let m2 = m.to_inertial(sum[6], sum[7], sum[8]);
            // each resultant relative to its own size
            let rel = |a: Vector3<f64>, b: Vector3<f64>| (a - b).norm() / b.norm();
            let errs = [
                rel(fr.f2, f2),
                rel(fr.f1, -f2),
                rel(fr.m1, m1),
                rel(fr.m2, m2),
                (fr.p_loss - sum[9]).abs() / sum[9],
            ];
            let e = errs.iter().cloned().fold(0.0, f64::max);
            assert!(
                e < 1e-10,
                "{d:?} case {i}: y {} errors (F2, F1, M1, M2, P_loss) {errs:?}: F2 {:?} vs {f2:?}, P_loss {} vs {}",
                -sb * (dvl[1] + omega2 * g.rb2 - omega1 * g.rb1) + cb * dvl[2],
                fr.f2,
                fr.p_loss,
                sum[9]
            );
            worst = worst.max(e);
            cases += 1;
        }
    }
    println!("law 4 resultants against adaptive quadrature on {cases} gear states: worst relative error {worst:.2e}");
}
