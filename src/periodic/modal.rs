//! Modal damping of the periodic orbit (`docs/damping.md`): from the Floquet multipliers
//! `rho = exp(s T_m)` of the orbit each mode's characteristic exponent `s`, its frequency
//! `Im(s) / (2 pi)` in Hz and its damping ratio `zeta = -Re(s) / |s|`, and the part of that
//! damping the tooth friction adds, `zeta - zeta(mu = 0)`.
//!
//! The logarithm fixes `Im(s)` only up to multiples of `2 pi / T_m`. It is resolved by the
//! friction-free linearisation about the mean state: the same pair, speed and load with
//! `mu = 0` (law 1) has the static equilibrium as its periodic orbit, and its linearisation
//! there ([`linearised_matrix`]: the rotors on their bearings with the rigid mesh
//! constraint, the constraint's geometric stiffness included) is an autonomous linear
//! system whose eigenvalues `s0` are unambiguous. Each multiplier is paired with one `s0`
//! (one to one, nearest exponent and mode shape first) and given the branch `k` that
//! brings `s = (ln rho + 2 pi i k) / T_m` nearest to it. This is the continuation in mu
//! from 0 done in one step: it is unambiguous as long as the friction moves every exponent
//! by less than half the band, `pi / T_m`; [`ModalResult::shift`] reports the largest
//! move in units of that half band (default pair: 0.03 at 3000 rpm and mu = 0.05, at most
//! 0.11 over the damping studies, at 1500 rpm and mu = 0.1; far inside).
//!
//! The multipliers come from a central-difference monodromy with a small step
//! ([`ModalOptions::fd_step`]): with Coulomb friction the damping a perturbation sees depends
//! on its amplitude once its velocities approach the orbit's own small vibration velocities
//! (the sliding direction near the pitch line saturates), and the modal damping is the
//! small-amplitude limit.
//!
//! Each mode is named by the states that dominate its eigenvector: the kinetic-energy share
//! `m_i |x_i|^2` of each centre axis and `J_2 |dphi_2|^2` of the rotation of gear 2 (from the
//! constraint `G dq = 0`), for the eigenvector of the monodromy matrix at the start of the
//! period.

use super::{PeriodicError, PeriodicSystem, Reduced, NZ};
use crate::gear::FrictionLaw;
use crate::radau5::Statistics;
use crate::rotor::{idx, Params};
use nalgebra::{Complex, SMatrix, SVector, Vector3};
use std::f64::consts::PI;

/// A complex 12 x 12 matrix (monodromy or linearisation in complex arithmetic).
type CMat = SMatrix<Complex<f64>, NZ, NZ>;
/// A complex reduced vector (an eigenvector).
pub type CVec = SVector<Complex<f64>, NZ>;

/// Names of the seven kinetic-energy shares of a mode shape.
pub const STATE_NAMES: [&str; 7] = [
    "centre 1 x",
    "centre 1 y",
    "centre 1 z",
    "centre 2 x",
    "centre 2 y",
    "centre 2 z",
    "gear 2 torsion",
];

/// Settings of [`modal_analysis`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalOptions {
    /// RADAU5 relative tolerance of the period integrations of the monodromy matrix.
    pub rtol: f64,
    /// Difference step of the central-difference monodromy with friction, relative to
    /// [`PeriodicSystem::scales`]. Coulomb friction makes the period map's derivative an
    /// amplitude limit: near the pitch line, where the sliding speed is smaller than the
    /// perturbation's, the direction `v / |v|` saturates, and the differenced multipliers
    /// move in proportion to the step (default pair, largest |rho|: 0.89985, 0.89375,
    /// 0.89058, 0.89061, 0.89062 at 1e-2 .. 1e-6). 1e-5 (~1e-10 m) is inside that limit to
    /// ~3e-5 and still above the integration noise.
    pub fd_step: f64,
    /// The step without friction (law 1 or 2 with mu = 0): the period map is smooth, and
    /// 1e-3 (~1e-8 m) puts the integration noise at ~1e-9 of the multipliers (1e-5 leaves
    /// ~1e-6).
    pub fd_step_frictionless: f64,
    /// Shooting's Newton tolerance (scaled residual) for the orbit.
    pub shooting_tol: f64,
}

impl Default for ModalOptions {
    fn default() -> Self {
        ModalOptions {
            rtol: 1e-13,
            fd_step: 1e-5,
            fd_step_frictionless: 1e-3,
            shooting_tol: 1e-9,
        }
    }
}

/// One mode of the periodic orbit.
#[derive(Debug, Clone, PartialEq)]
pub struct Mode {
    /// The states that dominate the mode shape, e.g. "centre 1 x + gear 2 torsion".
    pub name: String,
    /// Characteristic exponent s in 1/s (branch resolved).
    pub s: Complex<f64>,
    /// Floquet multiplier rho = exp(s T_m).
    pub multiplier: Complex<f64>,
    /// The branch k of `s = (ln rho + 2 pi i k) / T_m`.
    pub branch: i64,
    /// Frequency Im(s) / (2 pi) in Hz.
    pub freq_hz: f64,
    /// Damping ratio -Re(s) / |s|.
    pub zeta: f64,
    /// The friction-free mode it continues: exponent s0 of the linearisation at mu = 0.
    pub s0: Complex<f64>,
    /// Its frequency in Hz.
    pub freq0_hz: f64,
    /// Its damping ratio; `zeta - zeta0` is what the friction adds.
    pub zeta0: f64,
    /// Kinetic-energy shares (sum 1) in the order of [`STATE_NAMES`].
    pub shares: [f64; 7],
    /// Eigenvector of the monodromy matrix (reduced coordinates at the start of the
    /// period), largest displacement component 1.
    pub eigvec: CVec,
}

impl Mode {
    /// `zeta - zeta(mu = 0)`: the damping ratio the tooth friction adds.
    pub fn dzeta(&self) -> f64 {
        self.zeta - self.zeta0
    }
}

/// Modes of a periodic orbit, by increasing friction-free frequency.
#[derive(Debug, Clone)]
pub struct ModalResult {
    /// Mesh period T_m in s.
    pub period: f64,
    /// The modes with Im(s0) >= 0 (one per complex pair, each real exponent on its own).
    pub modes: Vec<Mode>,
    /// Largest |s - s0| over all exponents in units of pi / T_m (the resolution is
    /// unambiguous below 1).
    pub shift: f64,
    /// The reduced state of the orbit at the start of the period.
    pub z: Reduced,
    /// The central-difference monodromy matrix.
    pub monodromy: SMatrix<f64, NZ, NZ>,
    /// Statistics of one period integration on the orbit.
    pub stats: Statistics,
}

/// Jacobian of the reduced vector field `z' = F(z)` (centre displacements and velocities,
/// xi, omega2 and lambda from the constraints, `PeriodicSystem::lift`) at `z`, phase 0, by
/// central differences with steps `rel * scales`. At mu = 0 and the static equilibrium this
/// is the linearisation of the rotors on their bearings with the rigid mesh constraint.
///
/// # Errors
/// Lift or model errors.
pub fn linearised_matrix(
    sys: &PeriodicSystem,
    z: &Reduced,
    rel: f64,
) -> Result<SMatrix<f64, NZ, NZ>, PeriodicError> {
    let mut model = sys.model().clone();
    let mass = model.mass();
    let s = sys.scales();
    let mut field = |z: &Reduced| -> Result<Reduced, PeriodicError> {
        let y = sys.lift(z)?;
        let mut f = SVector::<f64, { crate::rotor::NY }>::zeros();
        model.rhs(0.0, &y, &mut f)?;
        Ok(Reduced::from_fn(|i, _| {
            if i < 6 {
                f[idx::Q + i]
            } else {
                f[idx::V + i - 6] / mass[(idx::V + i - 6, idx::V + i - 6)]
            }
        }))
    };
    let mut a = SMatrix::<f64, NZ, NZ>::zeros();
    for j in 0..NZ {
        let h = rel * s[j];
        let (mut zp, mut zm) = (*z, *z);
        zp[j] += h;
        zm[j] -= h;
        a.set_column(j, &((field(&zp)? - field(&zm)?) / (2.0 * h)));
    }
    Ok(a)
}

/// Central-difference monodromy matrix of the reduced period map around the orbit `z`.
///
/// # Errors
/// Solver or model errors.
pub fn central_monodromy(
    sys: &mut PeriodicSystem,
    z: &Reduced,
    rel: f64,
    rtol: f64,
) -> Result<SMatrix<f64, NZ, NZ>, PeriodicError> {
    let steps = sys.fd_steps(rel, rtol);
    let mut m = SMatrix::<f64, NZ, NZ>::zeros();
    for j in 0..NZ {
        let (mut zp, mut zm) = (*z, *z);
        zp[j] += steps[j];
        zm[j] -= steps[j];
        let (pp, _) = sys.integrate(&zp, 1, rtol, None)?;
        let (pm, _) = sys.integrate(&zm, 1, rtol, None)?;
        m.set_column(j, &((pp - pm) / (2.0 * steps[j])));
    }
    Ok(m)
}

/// Eigenvalues of `a` and their right eigenvectors (inverse iteration on the shifted
/// matrix in complex arithmetic), each eigenvector scaled so that its largest
/// displacement component (the first six) is 1.
pub fn eigen(a: &SMatrix<f64, NZ, NZ>) -> Vec<(Complex<f64>, CVec)> {
    let ac: CMat = a.map(|x| Complex::new(x, 0.0));
    let norm = a.abs().max().max(f64::MIN_POSITIVE);
    a.complex_eigenvalues()
        .iter()
        .map(|&lam| {
            // A shift just off the eigenvalue keeps the LU regular; two steps suffice
            // (the error falls by |shift error| / |gap to the next eigenvalue| per step).
            let mu = lam + Complex::new(1e-10 * norm, 1e-10 * norm);
            let lu = (ac - CMat::identity() * mu).lu();
            let mut x = CVec::from_fn(|i, _| Complex::new(1.0 + 0.1 * i as f64, 0.3));
            for _ in 0..3 {
                if let Some(y) = lu.solve(&x) {
                    let n = y.norm();
                    if n > 0.0 && n.is_finite() {
                        x = y / Complex::new(n, 0.0);
                    }
                }
            }
            (lam, normalise(x))
        })
        .collect()
}

fn normalise(x: CVec) -> CVec {
    let mut best = Complex::new(1.0, 0.0);
    let mut bn = 0.0;
    for i in 0..6 {
        if x[i].norm() > bn {
            bn = x[i].norm();
            best = x[i];
        }
    }
    if bn > 0.0 {
        x / best
    } else {
        x
    }
}

/// |a^H b|^2 / (|a|^2 |b|^2) over the displacement components: 1 for the same shape.
fn mac(a: &CVec, b: &CVec) -> f64 {
    let (mut ab, mut aa, mut bb) = (Complex::new(0.0, 0.0), 0.0, 0.0);
    for i in 0..6 {
        ab += a[i].conj() * b[i];
        aa += a[i].norm_sqr();
        bb += b[i].norm_sqr();
    }
    if aa > 0.0 && bb > 0.0 {
        ab.norm_sqr() / (aa * bb)
    } else {
        0.0
    }
}

/// Kinetic-energy shares of a mode shape (sum 1), order of [`STATE_NAMES`]: `m_i |x_i|^2`
/// per centre axis, `J_2 |dphi_2|^2` with `dphi_2 = -G_u x / G_phi2` from the constraint row
/// at the orbit's start `z`.
pub fn shares(sys: &PeriodicSystem, z: &Reduced, v: &CVec) -> Result<[f64; 7], PeriodicError> {
    let model = sys.model();
    let mass = model.mass();
    let u1 = Vector3::new(z[0], z[1], z[2]);
    let u2 = Vector3::new(z[3], z[4], z[5]);
    let mesh = model
        .geometry()
        .mesh(&u1, &u2)
        .map_err(|_| PeriodicError::Singular { method: "modal" })?;
    let g = model.geometry().constraint_row(&mesh);
    let mut dphi = Complex::new(0.0, 0.0);
    for i in 0..6 {
        dphi -= v[i] * g[i];
    }
    dphi /= g[6];
    let mut e = [0.0; 7];
    for (i, ei) in e.iter_mut().enumerate() {
        let x = if i < 6 { v[i] } else { dphi };
        *ei = mass[(idx::V + i, idx::V + i)] * x.norm_sqr();
    }
    let sum: f64 = e.iter().sum();
    if sum > 0.0 {
        for ei in &mut e {
            *ei /= sum;
        }
    }
    Ok(e)
}

/// The name of a mode from its shares: the largest, and the second when it has at least
/// 0.2 of the energy ("centre 1 x + gear 2 torsion").
pub fn mode_name(shares: &[f64; 7]) -> String {
    let mut order: Vec<usize> = (0..7).collect();
    order.sort_by(|&a, &b| shares[b].total_cmp(&shares[a]));
    let mut name = STATE_NAMES[order[0]].to_string();
    if shares[order[1]] >= 0.2 {
        name.push_str(" + ");
        name.push_str(STATE_NAMES[order[1]]);
    }
    name
}

fn zeta_of(s: Complex<f64>) -> f64 {
    if s.norm() > 0.0 {
        -s.re / s.norm()
    } else {
        0.0
    }
}

/// The friction-free reference of `params`: the same pair, speed and load with law 1 and
/// mu = 0, its static equilibrium and the eigenvalues and eigenvectors of its linearisation
/// there ([`linearised_matrix`]).
///
/// # Errors
/// Parameter, model or lift errors.
pub fn reference(
    params: Params,
    omega1: f64,
    t_load: f64,
) -> Result<Vec<(Complex<f64>, CVec)>, PeriodicError> {
    let p0 = Params {
        mu: 0.0,
        friction_law: FrictionLaw::Coulomb,
        ..params
    };
    let sys0 = PeriodicSystem::new(p0, omega1, t_load)?;
    let (z0, _) = sys0.static_equilibrium()?;
    let a = linearised_matrix(&sys0, &z0, 1e-4)?;
    Ok(eigen(&a))
}

/// Modal damping of the periodic orbit of `params` at the constant drive speed `omega1`
/// [rad/s] and load torque `t_load` [N m]: the orbit by shooting, the central-difference
/// monodromy, its eigenvalues and eigenvectors, the branch of each exponent from the
/// friction-free reference ([`reference()`], see the module docs).
///
/// # Errors
/// Parameter, model or solver errors; shooting that does not converge.
pub fn modal_analysis(
    params: Params,
    omega1: f64,
    t_load: f64,
    opts: &ModalOptions,
) -> Result<ModalResult, PeriodicError> {
    if params.tooth_contact != crate::rotor::ToothContact::Rigid {
        return Err(PeriodicError::Param(crate::parameter::ParamError {
            name: "tooth_contact",
            value: f64::from(params.tooth_contact.code()),
            requirement: "tooth_contact = rigid for the modal damping (periodic --damping): its \
                          friction-free reference is the rigid linearisation; with elastic teeth \
                          the periodic program without --damping gives the Floquet multipliers \
                          and the mesh mode's frequency and damping ratio (periodic::elastic)"
                .into(),
        }));
    }
    let refs = reference(params, omega1, t_load)?;
    let mut sys = PeriodicSystem::new(params, omega1, t_load)?;
    let (z0, _) = sys.static_equilibrium()?;
    let sopts = super::shooting::ShootingOptions {
        tol: opts.shooting_tol,
        samples: 2,
        ..Default::default()
    };
    let sh = match super::shooting::shoot(&mut sys, &z0, &sopts) {
        Ok(sh) => sh,
        // Where Newton stalls slightly above the tolerance (the period map's noise), a
        // tenfold looser tolerance from the stalled state.
        Err(PeriodicError::NoConvergence { .. }) => super::shooting::shoot(
            &mut sys,
            &z0,
            &super::shooting::ShootingOptions {
                tol: 10.0 * opts.shooting_tol,
                ..sopts
            },
        )?,
        Err(e) => return Err(e),
    };
    let z = sh.z;
    let (_, stats) = sys.integrate(&z, 1, opts.rtol, None)?;
    let step = if sys.model().coulomb_mu() == Some(0.0) {
        opts.fd_step_frictionless
    } else {
        opts.fd_step
    };
    let m = central_monodromy(&mut sys, &z, step, opts.rtol)?;
    let floq = eigen(&m);
    let t = sys.period();
    let band = PI / t;

    // Candidate exponent of multiplier j on the branch nearest to reference i.
    let candidate = |rho: Complex<f64>, s0: Complex<f64>| -> (Complex<f64>, i64) {
        let ln = rho.ln();
        let k = ((s0.im * t - ln.im) / (2.0 * PI)).round();
        (
            Complex::new(ln.re / t, (ln.im + 2.0 * PI * k) / t),
            k as i64,
        )
    };
    // One-to-one pairing, cheapest first: exponent distance in half bands plus the shape
    // mismatch.
    let mut pairs = Vec::new();
    for (i, (s0, v0)) in refs.iter().enumerate() {
        for (j, (rho, w)) in floq.iter().enumerate() {
            let (s, _) = candidate(*rho, *s0);
            pairs.push(((s - s0).norm() / band + (1.0 - mac(v0, w)), i, j));
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut used_i, mut used_j) = ([false; NZ], [false; NZ]);
    let mut matched = Vec::new();
    for (_, i, j) in pairs {
        if !used_i[i] && !used_j[j] {
            used_i[i] = true;
            used_j[j] = true;
            matched.push((i, j));
        }
    }
    let mut shift: f64 = 0.0;
    let mut modes = Vec::new();
    // Near a parametric resonance (a mode's frequency near k f_mesh / 2) the conjugate pair
    // of multipliers can meet on the real axis and part there: two real multipliers of
    // different modulus for one mode, and the pairing between the mode's two exponents s0,
    // conj(s0) and them is a tie. Report the less damped one (the larger modulus), so that
    // an instability is never dropped with the conjugate.
    let real = |rho: Complex<f64>| rho.im.abs() <= 1e-9 * rho.norm();
    let partner = |i: usize| -> Option<usize> {
        let (s0, _) = refs[i];
        (0..refs.len()).filter(|&q| q != i).min_by(|&a, &b| {
            (refs[a].0 - s0.conj())
                .norm()
                .total_cmp(&(refs[b].0 - s0.conj()).norm())
        })
    };
    let matched_of = |i: usize| matched.iter().find(|m| m.0 == i).map(|m| m.1);
    for &(i, j) in &matched {
        let (s0, _) = refs[i];
        let (mut rho, mut w) = floq[j];
        if s0.im >= 0.0 && real(rho) {
            if let Some(j2) = partner(i).and_then(matched_of) {
                if real(floq[j2].0) && floq[j2].0.norm() > rho.norm() {
                    (rho, w) = floq[j2];
                }
            }
        }
        let (s, k) = candidate(rho, s0);
        shift = shift.max((s - s0).norm() / band);
        if s0.im < 0.0 {
            continue;
        }
        let sh = shares(&sys, &z, &w)?;
        modes.push(Mode {
            name: mode_name(&sh),
            s,
            multiplier: rho,
            branch: k,
            freq_hz: s.im / (2.0 * PI),
            zeta: zeta_of(s),
            s0,
            freq0_hz: s0.im / (2.0 * PI),
            zeta0: zeta_of(s0),
            shares: sh,
            eigvec: w,
        });
    }
    modes.sort_by(|a, b| {
        a.freq0_hz
            .total_cmp(&b.freq0_hz)
            .then(b.s0.re.total_cmp(&a.s0.re))
    });
    Ok(ModalResult {
        period: t,
        modes,
        shift,
        z,
        monodromy: m,
        stats,
    })
}
