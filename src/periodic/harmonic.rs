//! The n-th order harmonic approach (`model.md` §11): the six centre displacements u, the
//! transmission-error coordinate xi and lambda as truncated Fourier series in the mesh
//! frequency `Omega = 2 pi / T_m`,
//!
//! `x_s(t) = a_s0 + sum_{k=1..n} (a_sk cos(k Omega t) + b_sk sin(k Omega t))`,  s = 1..8.
//!
//! Residuals (alternating frequency/time): at N >= 2n+1 equidistant instants t_j of the
//! period the seven equations of motion `M q'' - f_v(q, q', phi1(t_j), lambda) = 0`
//! (`model.md` §5; `f_v` the force part of the rotor's right-hand side, friction included)
//! and the position-level constraint `g(q, phi1) = 0` (§3.3) are evaluated in the time
//! domain and projected onto the 2n+1 harmonics (for N = 2n+1 this is trigonometric
//! collocation). Newton on the 8 (2n+1) coefficients with a forward-difference Jacobian
//! and step halving. The position-level constraint (rather than its time derivative) fixes
//! the mean of xi, which the velocity-level constraint would leave free.
//!
//! With the elastic contact (`tooth_contact = elastic`, `model.md` §3.5) there is no
//! constraint: the eighth signal is the normal force Fn and its residual `Fn(q, q', phi1) -
//! Fn`, Fn of (3.16) being a function of the state (gear 2's equation of motion then fixes
//! the mean of xi through the mesh spring). The `max(0, ..)` of (3.15) is a kink and contact
//! loss makes the orbit non-smooth: the series converge slowly there, and shooting
//! (`periodic::elastic`) is the method of record.

use super::{OrbitPoint, PeriodicError, PeriodicSystem};
use crate::rotor::{idx, NY};
use nalgebra::{DMatrix, DVector, SVector};
use std::f64::consts::PI;

/// Number of Fourier-expanded signals: u1x u1y u1z u2x u2y u2z, xi, lambda.
pub const NS: usize = 8;

/// Settings of [`harmonic_balance`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HarmonicOptions {
    /// Time samples per period = `oversampling (2n + 1)`; 1 is plain collocation. The
    /// friction terms have kinks where contact lines enter and leave, and their aliasing
    /// spoils the projection: measured on the default pair against the shooting orbit,
    /// plain collocation stalls at ~2 % deviation for n = 7..12, oversampling 4 falls to
    /// 0.05..0.4 % but not monotonically, oversampling 16 falls monotonically from 9 %
    /// (n = 1) to 0.05 % (n = 12).
    pub oversampling: usize,
    /// Newton stops when the scaled max-norm of the projected residual is at most this.
    pub tol: f64,
    /// Newton iterations at most.
    pub max_newton: usize,
    /// Forward-difference step relative to the scale of each signal.
    pub fd_step: f64,
}

impl Default for HarmonicOptions {
    fn default() -> Self {
        HarmonicOptions {
            oversampling: 16,
            tol: 1e-10,
            max_newton: 30,
            fd_step: 1e-7,
        }
    }
}

/// A converged harmonic-balance solution of order n.
#[derive(Debug, Clone)]
pub struct HarmonicSolution {
    /// Order n (highest harmonic).
    pub n: usize,
    /// Mesh period in s.
    pub period: f64,
    /// Coefficients, row s = signal, columns `[a0, a1, b1, a2, b2, ..., an, bn]`.
    pub coeffs: DMatrix<f64>,
    /// Scaled max-norm of the projected residual.
    pub residual: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

impl HarmonicSolution {
    /// All signals at time t: `(value, first derivative, second derivative)`.
    fn eval_all(&self, t: f64) -> ([f64; NS], [f64; NS], [f64; NS]) {
        eval_series(&self.coeffs, self.n, 2.0 * PI / self.period, t)
    }

    /// The orbit at time t (within the period).
    pub fn point(&self, t: f64) -> OrbitPoint {
        let (x, _, _) = self.eval_all(t);
        OrbitPoint {
            t,
            u: [x[0], x[1], x[2], x[3], x[4], x[5]],
            xi: x[6],
            lambda: x[7],
        }
    }

    /// `samples` equidistant points over one period, starting at t = 0.
    pub fn orbit(&self, samples: usize) -> Vec<OrbitPoint> {
        (0..samples)
            .map(|j| self.point(self.period * j as f64 / samples as f64))
            .collect()
    }

    /// Amplitude `sqrt(a_k^2 + b_k^2)` of harmonic k >= 1 of signal s.
    pub fn amplitude(&self, s: usize, k: usize) -> f64 {
        self.coeffs[(s, 2 * k - 1)].hypot(self.coeffs[(s, 2 * k)])
    }
}

fn eval_series(c: &DMatrix<f64>, n: usize, w: f64, t: f64) -> ([f64; NS], [f64; NS], [f64; NS]) {
    let mut x = [0.0; NS];
    let mut dx = [0.0; NS];
    let mut ddx = [0.0; NS];
    for s in 0..NS {
        x[s] = c[(s, 0)];
    }
    for k in 1..=n {
        let kw = k as f64 * w;
        let (sn, cs) = (kw * t).sin_cos();
        for s in 0..NS {
            let (a, b) = (c[(s, 2 * k - 1)], c[(s, 2 * k)]);
            x[s] += a * cs + b * sn;
            dx[s] += kw * (-a * sn + b * cs);
            ddx[s] -= kw * kw * (a * cs + b * sn);
        }
    }
    (x, dx, ddx)
}

/// Problem data shared by the residual evaluations.
struct Balance<'a> {
    sys: &'a PeriodicSystem,
    n: usize,
    nodes: usize,
    /// Scale of each signal (unknowns) and of each residual row.
    signal_scale: [f64; NS],
    force_scale: f64,
    mass: [f64; 7],
    /// `cos`/`sin` of `k Omega t_j`, rows j, columns `[1, cos 1, sin 1, ...]`.
    basis: DMatrix<f64>,
}

impl Balance<'_> {
    fn unknowns(&self) -> usize {
        NS * (2 * self.n + 1)
    }

    fn coeffs_from(&self, x: &DVector<f64>) -> DMatrix<f64> {
        let m = 2 * self.n + 1;
        DMatrix::from_fn(NS, m, |s, k| x[s * m + k] * self.signal_scale[s])
    }

    /// Projected, scaled residual of the coefficient vector x (scaled by `signal_scale`).
    fn residual(&self, x: &DVector<f64>) -> Result<DVector<f64>, PeriodicError> {
        let c = self.coeffs_from(x);
        let model = self.sys.model();
        let g = model.geometry();
        let omega1 = self.sys.omega1();
        let w = 2.0 * PI / self.sys.period();
        let m = 2 * self.n + 1;
        let mut time = DMatrix::<f64>::zeros(self.nodes, NS);
        let mut y = SVector::<f64, NY>::zeros();
        let mut f = SVector::<f64, NY>::zeros();
        let mut model = model.clone();
        // The eighth equation: the constraint g = 0 where the force is its multiplier,
        // else the force's own law.
        let multiplier = model.contact().has_multiplier();
        for j in 0..self.nodes {
            let t = self.sys.period() * j as f64 / self.nodes as f64;
            let (v, dv, ddv) = eval_series(&c, self.n, w, t);
            y.fill(0.0);
            for i in 0..6 {
                y[idx::Q + i] = v[i];
                y[idx::V + i] = dv[i];
            }
            y[idx::Q + 6] = v[6];
            // xi = r_b2 phi2 - r_b1 phi1 with phi1' = omega1 constant (rotor::idx::Q).
            y[idx::V + 6] = (dv[6] + g.rb1 * omega1) / g.rb2;
            y[idx::PHI1] = omega1 * t;
            y[idx::OMEGA1] = omega1;
            y[idx::LAMBDA] = v[7];
            model.rhs(t, &y, &mut f)?;
            for i in 0..7 {
                let acc = if i < 6 { ddv[i] } else { ddv[6] / g.rb2 };
                let scale = if i < 6 {
                    self.force_scale
                } else {
                    self.force_scale * g.rb2
                };
                time[(j, i)] = (self.mass[i] * acc - f[idx::V + i]) / scale;
            }
            let mesh = model.mesh(t, &y)?;
            time[(j, 7)] = if multiplier {
                (g.gap_raw(&mesh, v[6]) + model.gap_offset()) / self.signal_scale[6]
            } else {
                // Elastic contact (§3.5): the eighth signal is the normal force Fn (3.16),
                // a function of the state; its residual is Fn(state) - signal.
                let fn_ = model
                    .elastic_contact_at(t, &y)
                    .ok_or(PeriodicError::Singular {
                        method: "harmonic balance",
                    })?
                    .fn_;
                (fn_ - v[7]) / self.signal_scale[7]
            };
        }
        // Projection onto 1, 2 cos, 2 sin (the DFT; exact collocation for N = 2n + 1).
        let proj = self.basis.transpose() * time / self.nodes as f64;
        let mut r = DVector::<f64>::zeros(NS * m);
        for s in 0..NS {
            for k in 0..m {
                let wk = if k == 0 { 1.0 } else { 2.0 };
                r[s * m + k] = wk * proj[(k, s)];
            }
        }
        Ok(r)
    }
}

/// Harmonic approach of order `n` at the operating point of `sys`, started from `guess`
/// (coefficients of any order; missing harmonics start at zero) or, without one, from the
/// frictionless static equilibrium.
///
/// # Errors
/// Model errors at a sample point, a singular Newton matrix, or no convergence.
pub fn harmonic_balance(
    sys: &PeriodicSystem,
    n: usize,
    guess: Option<&HarmonicSolution>,
    opts: &HarmonicOptions,
) -> Result<HarmonicSolution, PeriodicError> {
    let n = n.max(1);
    let m = 2 * n + 1;
    let nodes = opts.oversampling.max(1) * m;
    let zs = sys.scales();
    let (z_static, lambda_static) = sys.static_equilibrium()?;
    let u_scale = (0..6).fold(f64::INFINITY, |a, i| a.min(zs[i]));
    let mut signal_scale = [0.0; NS];
    for (s, sc) in signal_scale.iter_mut().enumerate().take(6) {
        *sc = zs[s];
    }
    signal_scale[6] = u_scale;
    signal_scale[7] = lambda_static.abs().max(1.0);
    let mass_ext = sys.model().mass();
    let mut mass = [0.0; 7];
    for (i, mi) in mass.iter_mut().enumerate() {
        *mi = mass_ext[(idx::V + i, idx::V + i)];
    }
    let w = 2.0 * PI / sys.period();
    let basis = DMatrix::from_fn(nodes, m, |j, k| {
        let t = sys.period() * j as f64 / nodes as f64;
        if k == 0 {
            1.0
        } else {
            let h = k.div_ceil(2) as f64;
            if k % 2 == 1 {
                (h * w * t).cos()
            } else {
                (h * w * t).sin()
            }
        }
    });
    let bal = Balance {
        sys,
        n,
        nodes,
        signal_scale,
        force_scale: signal_scale[7],
        mass,
        basis,
    };
    // Start: the guess (truncated or zero-padded) or the static equilibrium.
    let mut x = DVector::<f64>::zeros(bal.unknowns());
    match guess {
        Some(gs) => {
            for s in 0..NS {
                for k in 0..m.min(gs.coeffs.ncols()) {
                    x[s * m + k] = gs.coeffs[(s, k)] / signal_scale[s];
                }
            }
        }
        None => {
            let y = if sys.is_elastic() {
                sys.lift_elastic(&sys.elastic_start()?)?
            } else {
                sys.lift(&z_static)?
            };
            for s in 0..6 {
                x[s * m] = z_static[s] / signal_scale[s];
            }
            x[6 * m] = y[idx::Q + 6] / signal_scale[6];
            x[7 * m] = lambda_static / signal_scale[7];
        }
    }
    let norm = |r: &DVector<f64>| r.amax();
    let mut r = bal.residual(&x)?;
    let mut iterations = 0;
    loop {
        let res = norm(&r);
        if res <= opts.tol {
            return Ok(HarmonicSolution {
                n,
                period: sys.period(),
                coeffs: bal.coeffs_from(&x),
                residual: res,
                iterations,
            });
        }
        if iterations >= opts.max_newton {
            return Err(PeriodicError::NoConvergence {
                method: "harmonic balance",
                iterations,
                residual: res,
            });
        }
        let nu = bal.unknowns();
        let mut jac = DMatrix::<f64>::zeros(nu, nu);
        for i in 0..nu {
            let mut xi = x.clone();
            xi[i] += opts.fd_step;
            let ri = bal.residual(&xi)?;
            jac.set_column(i, &((ri - &r) / opts.fd_step));
        }
        let dx = jac.lu().solve(&(-&r)).ok_or(PeriodicError::Singular {
            method: "harmonic balance",
        })?;
        // Step halving on the residual norm (friction makes the residual only piecewise
        // smooth in the coefficients).
        let mut alpha = 1.0;
        loop {
            let xt = &x + &dx * alpha;
            let rt = bal.residual(&xt)?;
            if norm(&rt) < res || alpha < 1e-3 {
                x = xt;
                r = rt;
                break;
            }
            alpha *= 0.5;
        }
        iterations += 1;
        if dx.amax() * alpha <= 1e-14 && norm(&r) > opts.tol {
            // Stagnation above the tolerance: report it rather than return a poor solution.
            return Err(PeriodicError::NoConvergence {
                method: "harmonic balance",
                iterations,
                residual: norm(&r),
            });
        }
    }
}
