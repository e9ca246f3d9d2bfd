//! The parity problems of `data/radau5/reference.md`, their reference solutions
//! and the Fortran's counters, shared by the tests and the `radau5_parity` example
//! (which includes this file with `#[path]`). Test support, not part of the FMU library.

use nalgebra::{SMatrix, SVector};

use geared_rotor::radau5::{
    Controller, Error, Options, Problem, Radau5, RhsError, Statistics, Tolerance,
};

/// Van der Pol, `y1' = y2`, `y2' = ((1 - y1^2) y2 - y1)/eps`, eps = 1e-6 (written like
/// Hairer's driver `dr1_radau5.f`).
#[derive(Debug, Clone, Copy)]
pub struct VanDerPol {
    pub eps: f64,
}

impl Problem<2> for VanDerPol {
    fn rhs(
        &mut self,
        _t: f64,
        y: &SVector<f64, 2>,
        f: &mut SVector<f64, 2>,
    ) -> Result<(), RhsError> {
        f[0] = y[1];
        f[1] = ((1.0 - y[0] * y[0]) * y[1] - y[0]) / self.eps;
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        y: &SVector<f64, 2>,
        j: &mut SMatrix<f64, 2, 2>,
    ) -> Result<bool, RhsError> {
        j[(0, 0)] = 0.0;
        j[(0, 1)] = 1.0;
        j[(1, 0)] = (-2.0 * y[0] * y[1] - 1.0) / self.eps;
        j[(1, 1)] = (1.0 - y[0] * y[0]) / self.eps;
        Ok(true)
    }
}

/// Robertson's chemical kinetics.
#[derive(Debug, Clone, Copy)]
pub struct Robertson;

impl Problem<3> for Robertson {
    fn rhs(
        &mut self,
        _t: f64,
        y: &SVector<f64, 3>,
        f: &mut SVector<f64, 3>,
    ) -> Result<(), RhsError> {
        f[0] = -0.04 * y[0] + 1.0e4 * y[1] * y[2];
        f[2] = 3.0e7 * y[1] * y[1];
        f[1] = -f[0] - f[2];
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        y: &SVector<f64, 3>,
        j: &mut SMatrix<f64, 3, 3>,
    ) -> Result<bool, RhsError> {
        j[(0, 0)] = -0.04;
        j[(0, 1)] = 1.0e4 * y[2];
        j[(0, 2)] = 1.0e4 * y[1];
        j[(1, 0)] = 0.04;
        j[(1, 1)] = -1.0e4 * y[2] - 6.0e7 * y[1];
        j[(1, 2)] = -1.0e4 * y[1];
        j[(2, 0)] = 0.0;
        j[(2, 1)] = 6.0e7 * y[1];
        j[(2, 2)] = 0.0;
        Ok(true)
    }
}

/// One-transistor amplifier (Hairer & Wanner II, p. 377): index-1 DAE, singular M.
#[derive(Debug, Clone, Copy)]
pub struct Amplifier1t;

impl Amplifier1t {
    const UB: f64 = 6.0;
    const UF: f64 = 0.026;
    const ALPHA: f64 = 0.99;
    const BETA: f64 = 1.0e-6;
    const R0: f64 = 1000.0;
    const R: f64 = 9000.0;
}

impl Problem<5> for Amplifier1t {
    fn rhs(
        &mut self,
        t: f64,
        y: &SVector<f64, 5>,
        f: &mut SVector<f64, 5>,
    ) -> Result<(), RhsError> {
        let ue = 0.4 * (200.0 * std::f64::consts::PI * t).sin();
        let g = Self::BETA * (((y[1] - y[2]) / Self::UF).exp() - 1.0);
        f[0] = (y[0] - ue) / Self::R0;
        f[1] = (2.0 * y[1] - Self::UB) / Self::R + 0.01 * g;
        f[2] = y[2] / Self::R - g;
        f[3] = (y[3] - Self::UB) / Self::R + Self::ALPHA * g;
        f[4] = y[4] / Self::R;
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        y: &SVector<f64, 5>,
        j: &mut SMatrix<f64, 5, 5>,
    ) -> Result<bool, RhsError> {
        let dg = Self::BETA * ((y[1] - y[2]) / Self::UF).exp() / Self::UF;
        j.fill(0.0);
        j[(0, 0)] = 1.0 / Self::R0;
        j[(1, 1)] = 2.0 / Self::R + 0.01 * dg;
        j[(1, 2)] = -0.01 * dg;
        j[(2, 1)] = -dg;
        j[(2, 2)] = 1.0 / Self::R + dg;
        j[(3, 1)] = Self::ALPHA * dg;
        j[(3, 2)] = -Self::ALPHA * dg;
        j[(3, 3)] = 1.0 / Self::R;
        j[(4, 4)] = 1.0 / Self::R;
        Ok(true)
    }
    fn mass(&self) -> Option<SMatrix<f64, 5, 5>> {
        let mut m = SMatrix::<f64, 5, 5>::zeros();
        m[(0, 0)] = -1.0e-6;
        m[(0, 1)] = 1.0e-6;
        m[(1, 0)] = 1.0e-6;
        m[(1, 1)] = -1.0e-6;
        m[(2, 2)] = -2.0e-6;
        m[(3, 3)] = -3.0e-6;
        m[(3, 4)] = 3.0e-6;
        m[(4, 3)] = 3.0e-6;
        m[(4, 4)] = -3.0e-6;
        Some(m)
    }
}

/// Pendulum in index-2 form: `q' = v`, `v' = -lambda q - (0, g)`, `0 = q . v`.
#[derive(Debug, Clone, Copy)]
pub struct Pendulum2 {
    pub g: f64,
}

impl Problem<5> for Pendulum2 {
    fn rhs(
        &mut self,
        _t: f64,
        y: &SVector<f64, 5>,
        f: &mut SVector<f64, 5>,
    ) -> Result<(), RhsError> {
        f[0] = y[2];
        f[1] = y[3];
        f[2] = -y[4] * y[0];
        f[3] = -y[4] * y[1] - self.g;
        f[4] = y[0] * y[2] + y[1] * y[3];
        Ok(())
    }
    fn jacobian(
        &mut self,
        _t: f64,
        y: &SVector<f64, 5>,
        j: &mut SMatrix<f64, 5, 5>,
    ) -> Result<bool, RhsError> {
        j.fill(0.0);
        j[(0, 2)] = 1.0;
        j[(1, 3)] = 1.0;
        j[(2, 0)] = -y[4];
        j[(2, 4)] = -y[0];
        j[(3, 1)] = -y[4];
        j[(3, 4)] = -y[1];
        j[(4, 0)] = y[2];
        j[(4, 1)] = y[3];
        j[(4, 2)] = y[0];
        j[(4, 3)] = y[1];
        Ok(true)
    }
    fn mass(&self) -> Option<SMatrix<f64, 5, 5>> {
        Some(SMatrix::<f64, 5, 5>::from_diagonal(
            &SVector::<f64, 5>::new(1.0, 1.0, 1.0, 1.0, 0.0),
        ))
    }
}

/// One row of the reference table: the Fortran's counters, time and error.
#[derive(Debug, Clone, Copy)]
pub struct ReferenceRow {
    pub problem: &'static str,
    pub rtol: f64,
    pub atol: f64,
    pub t_end: f64,
    pub controller: Controller,
    pub fortran: Statistics,
    /// Median wall time per solve of the Fortran, in seconds.
    pub fortran_seconds: f64,
    /// Max abs error of the Fortran (for pend2: over q and v).
    pub fortran_err: f64,
    /// pend2 only: error in lambda.
    pub fortran_err_lambda: Option<f64>,
}

const fn st(
    nfcn: u64,
    njac: u64,
    nstep: u64,
    naccpt: u64,
    nrejct: u64,
    ndec: u64,
    nsol: u64,
) -> Statistics {
    Statistics {
        nfcn,
        njac,
        // No Fortran counterpart: these problems give no split Jacobian.
        njac_fast: 0,
        nstep,
        naccpt,
        nrejct,
        ndec,
        nsol,
    }
}

#[allow(clippy::too_many_arguments)]
const fn row(
    problem: &'static str,
    rtol: f64,
    atol: f64,
    t_end: f64,
    controller: Controller,
    fortran: Statistics,
    us: f64,
    err: f64,
) -> ReferenceRow {
    ReferenceRow {
        problem,
        rtol,
        atol,
        t_end,
        controller,
        fortran,
        fortran_seconds: us * 1e-6,
        fortran_err: err,
        fortran_err_lambda: None,
    }
}

use Controller::{Classical as C, Gustafsson as G};

/// Every row of `reference.md` (transcribed from the tables there).
pub const REFERENCE: [ReferenceRow; 26] = [
    row(
        "vdp0",
        1e-4,
        1e-4,
        2.0,
        G,
        st(2253, 162, 281, 245, 7, 252, 669),
        91.0,
        9.89e-6,
    ),
    row(
        "vdp0",
        1e-6,
        1e-6,
        2.0,
        G,
        st(3965, 308, 501, 489, 8, 410, 1158),
        165.0,
        3.91e-7,
    ),
    row(
        "vdp0",
        1e-8,
        1e-8,
        2.0,
        G,
        st(8247, 480, 1054, 1045, 7, 844, 2400),
        331.0,
        2.38e-9,
    ),
    row(
        "vdp0",
        1e-10,
        1e-10,
        2.0,
        G,
        st(17516, 616, 2272, 2268, 2, 1710, 5082),
        686.0,
        5.29e-11,
    ),
    row(
        "vdp0",
        1e-4,
        1e-4,
        2.0,
        C,
        st(2446, 160, 304, 243, 25, 272, 734),
        98.0,
        2.95e-6,
    ),
    row(
        "vdp0",
        1e-6,
        1e-6,
        2.0,
        C,
        st(3972, 298, 491, 481, 8, 409, 1163),
        153.0,
        1.62e-7,
    ),
    row(
        "vdp06",
        1e-4,
        1e-4,
        2.0,
        G,
        st(2247, 162, 280, 242, 8, 252, 668),
        91.0,
        1.29e-5,
    ),
    row(
        "vdp06",
        1e-6,
        1e-6,
        2.0,
        G,
        st(3935, 305, 488, 478, 8, 408, 1152),
        161.0,
        1.75e-7,
    ),
    row(
        "vdp06",
        1e-8,
        1e-8,
        2.0,
        G,
        st(8177, 478, 1039, 1029, 8, 841, 2382),
        329.0,
        2.40e-9,
    ),
    row(
        "vdp06",
        1e-10,
        1e-10,
        2.0,
        G,
        st(17221, 615, 2235, 2231, 2, 1701, 4996),
        719.0,
        5.42e-11,
    ),
    row(
        "rob",
        1e-2,
        1e-8,
        0.3,
        G,
        st(87, 8, 17, 15, 1, 15, 24),
        9.0,
        7.45e-8,
    ),
    row(
        "rob",
        1e-4,
        1e-10,
        40.0,
        G,
        st(247, 26, 36, 34, 2, 36, 71),
        20.0,
        1.50e-8,
    ),
    row(
        "rob",
        1e-6,
        1e-12,
        40.0,
        G,
        st(459, 50, 61, 60, 1, 60, 133),
        26.0,
        8.31e-10,
    ),
    row(
        "rob",
        1e-8,
        1e-14,
        40.0,
        G,
        st(931, 73, 120, 118, 2, 93, 271),
        50.0,
        2.39e-11,
    ),
    row(
        "rob",
        1e-4,
        1e-10,
        1e11,
        G,
        st(994, 128, 138, 136, 2, 138, 286),
        56.0,
        7.96e-12,
    ),
    row(
        "rob",
        1e-6,
        1e-12,
        1e11,
        G,
        st(1953, 251, 262, 261, 1, 261, 564),
        110.0,
        6.77e-14,
    ),
    row(
        "rob",
        1e-8,
        1e-14,
        1e11,
        G,
        st(4033, 395, 537, 535, 2, 415, 1166),
        211.0,
        9.33e-15,
    ),
    row(
        "rob",
        1e-10,
        1e-16,
        1e11,
        G,
        st(8608, 481, 1143, 1141, 2, 525, 2489),
        410.0,
        1.14e-14,
    ),
    row(
        "amp1t",
        1e-4,
        1e-4,
        0.05,
        G,
        st(1510, 126, 166, 127, 6, 166, 461),
        175.0,
        8.35e-6,
    ),
    row(
        "amp1t",
        1e-6,
        1e-6,
        0.05,
        G,
        st(3067, 263, 326, 264, 25, 326, 933),
        351.0,
        4.15e-7,
    ),
    row(
        "amp1t",
        1e-8,
        1e-8,
        0.05,
        G,
        st(5560, 527, 582, 531, 24, 581, 1676),
        643.0,
        1.29e-8,
    ),
    row(
        "amp1t",
        1e-10,
        1e-10,
        0.05,
        G,
        st(10992, 1076, 1150, 1113, 21, 1136, 3293),
        1226.0,
        3.50e-10,
    ),
    pend(
        1e-4,
        st(495, 39, 49, 44, 3, 48, 150),
        48.0,
        1.59e-4,
        1.42e-2,
    ),
    pend(
        1e-6,
        st(784, 74, 80, 79, 1, 80, 235),
        75.0,
        3.16e-6,
        8.70e-4,
    ),
    pend(
        1e-8,
        st(1566, 158, 163, 162, 1, 163, 468),
        148.0,
        2.72e-8,
        1.97e-5,
    ),
    pend(
        1e-10,
        st(3355, 338, 343, 343, 0, 343, 1004),
        309.0,
        4.47e-10,
        5.05e-6,
    ),
];

const fn pend(tol: f64, s: Statistics, us: f64, err: f64, err_l: f64) -> ReferenceRow {
    ReferenceRow {
        problem: "pend2",
        rtol: tol,
        atol: tol,
        t_end: 3.0,
        controller: G,
        fortran: s,
        fortran_seconds: us * 1e-6,
        fortran_err: err,
        fortran_err_lambda: Some(err_l),
    }
}

/// All rows of the reference file.
pub fn all_rows() -> impl Iterator<Item = ReferenceRow> {
    REFERENCE.into_iter()
}

/// Result of one solve of a reference row.
#[derive(Debug, Clone, Copy)]
pub struct Outcome {
    pub stats: Statistics,
    /// Max abs error against the reference solution (pend2: over q and v).
    pub max_abs_err: f64,
    /// pend2 only: abs error in lambda.
    pub err_lambda: Option<f64>,
}

fn options<const N: usize>(r: &ReferenceRow) -> Options<N> {
    Options {
        rtol: Tolerance::Scalar(r.rtol),
        atol: Tolerance::Scalar(r.atol),
        h_init: 1e-6,
        controller: r.controller,
        ..Options::default()
    }
}

fn max_err<const N: usize>(y: &SVector<f64, N>, yref: &[f64]) -> f64 {
    y.iter()
        .zip(yref)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}

/// Reference solution of a row at its end time (values from `reference.md`, digits as
/// published).
#[allow(clippy::excessive_precision)]
pub fn reference_solution(r: &ReferenceRow) -> &'static [f64] {
    match (r.problem, r.t_end) {
        ("vdp0", _) => &[1.706167732170483, -0.8928097010247975],
        ("vdp06", _) => &[1.7061674643275067, -0.89280998786686605],
        ("rob", t) if t < 1.0 => &[
            9.8867393938192560e-01,
            3.4477157436894951e-05,
            1.1291583460638101e-02,
        ],
        ("rob", t) if t < 100.0 => &[
            7.1582706871940527e-01,
            9.1855347645585944e-06,
            2.8416374574583059e-01,
        ],
        ("rob", _) => &[
            0.2083340149701255e-7,
            0.8333360770334713e-13,
            0.9999999791665050,
        ],
        ("amp1t", _) => &[
            -2.2265136830168675e-02,
            3.0686999957782981,
            2.8983404619982003,
            2.0335337199927217,
            -2.2691714715707305,
        ],
        _ => &[
            -0.73375597672468177138,
            -0.67941310454009367936,
            -1.1224418291568238809,
            1.2122203636727194187,
            9.3943964254820557281,
        ],
    }
}

/// Generic driver: construct, integrate `[0, t_end]` in one call.
pub fn solve<P: Problem<N>, const N: usize>(
    p: &mut P,
    opts: Options<N>,
    y0: SVector<f64, N>,
    t_end: f64,
) -> Result<Radau5<N>, Error> {
    let mut s = Radau5::new(p, opts, 0.0, y0)?;
    s.integrate_to(p, t_end)?;
    Ok(s)
}

/// Solves one reference row exactly as the Fortran run was set up.
///
/// # Errors
/// Whatever the solver reports.
pub fn run_row(r: &ReferenceRow) -> Result<Outcome, Error> {
    let yref = reference_solution(r);
    match r.problem {
        "vdp0" | "vdp06" => {
            let y2 = if r.problem == "vdp0" { 0.0 } else { -0.6 };
            let s = solve(
                &mut VanDerPol { eps: 1e-6 },
                options(r),
                SVector::<f64, 2>::new(2.0, y2),
                r.t_end,
            )?;
            Ok(Outcome {
                stats: *s.stats(),
                max_abs_err: max_err(s.y(), yref),
                err_lambda: None,
            })
        }
        "rob" => {
            let s = solve(
                &mut Robertson,
                options(r),
                SVector::<f64, 3>::new(1.0, 0.0, 0.0),
                r.t_end,
            )?;
            Ok(Outcome {
                stats: *s.stats(),
                max_abs_err: max_err(s.y(), yref),
                err_lambda: None,
            })
        }
        "amp1t" => {
            let y0 = SVector::<f64, 5>::new(0.0, 3.0, 3.0, 6.0, 0.0);
            let s = solve(&mut Amplifier1t, options(r), y0, r.t_end)?;
            Ok(Outcome {
                stats: *s.stats(),
                max_abs_err: max_err(s.y(), yref),
                err_lambda: None,
            })
        }
        _ => {
            let g = 9.81;
            let y0 =
                SVector::<f64, 5>::new(1.0f64.sin(), -(1.0f64.cos()), 0.0, 0.0, g * 1.0f64.cos());
            let opts = Options {
                n1: 4,
                n2: 1,
                ..options(r)
            };
            let s = solve(&mut Pendulum2 { g }, opts, y0, r.t_end)?;
            let y = s.y();
            let qv = SVector::<f64, 4>::new(y[0], y[1], y[2], y[3]);
            Ok(Outcome {
                stats: *s.stats(),
                max_abs_err: max_err(&qv, &yref[..4]),
                err_lambda: Some((y[4] - yref[4]).abs()),
            })
        }
    }
}
