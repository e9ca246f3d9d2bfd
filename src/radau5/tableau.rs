//! Radau IIA (3 stages, order 5) coefficients exactly as `radau5.f` (2002) sets them up
//! in `RADCOR` (radau5.md §1).
//!
//! The transformation matrices `T`, `T^-1` are the Fortran's 20-digit literals; `gamma`,
//! `alpha`, `beta` (eigenvalues of `A^-1`) are computed at run time from the same closed
//! formulas as the Fortran, so that every rounding is the same.

/// Constants of the method (radau5.md §1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tableau {
    /// Nodes `c1 = (4 - sqrt 6)/10`, `c2 = (4 + sqrt 6)/10` (`c3 = 1`).
    pub c1: f64,
    pub c2: f64,
    /// `c1 - 1`, `c2 - 1`, `c1 - c2` (dense output, radau5.md §6).
    pub c1m1: f64,
    pub c2m1: f64,
    pub c1mc2: f64,
    /// Error weights `d1 = -(13 + 7 sqrt 6)/3`, `d2 = (-13 + 7 sqrt 6)/3`, `d3 = -1/3` (§1, §5).
    pub dd1: f64,
    pub dd2: f64,
    pub dd3: f64,
    /// Real eigenvalue `gamma` of `A^-1` (Fortran `U1` after inversion).
    pub gamma: f64,
    /// Complex pair `alpha +- i beta` of `A^-1` (Fortran `ALPH`, `BETA`).
    pub alpha: f64,
    pub beta: f64,
}

/// `T` (row-major), with `T^-1 A^-1 T = [[gamma,0,0],[0,alpha,-beta],[0,beta,alpha]]`.
/// `T32 = 1`, `T33 = 0` are exploited in the Newton update like in the Fortran.
/// (The 20-digit literals are kept as the Fortran writes them; both round to the same f64.)
#[allow(clippy::excessive_precision)]
pub const T: [[f64; 3]; 3] = [
    [
        9.123_239_487_089_294_279_2e-2,
        -0.141_255_295_020_954_208_43,
        -3.002_919_410_514_742_449_2e-2,
    ],
    [
        0.241_717_932_707_107_018_96,
        0.204_129_352_293_799_931_99,
        0.382_942_112_757_261_937_79,
    ],
    [0.966_048_182_615_092_936_19, 1.0, 0.0],
];

/// `T^-1` (row-major), the Fortran's `TI11 .. TI33`.
#[allow(clippy::excessive_precision)]
pub const TI: [[f64; 3]; 3] = [
    [
        4.325_579_890_063_155_351_0,
        0.339_199_251_815_809_869_54,
        0.541_770_539_935_874_871_19,
    ],
    [
        -4.178_718_591_551_904_727_3,
        -0.327_682_820_761_062_387_08,
        0.476_623_554_500_550_451_96,
    ],
    [
        -0.502_872_634_945_786_875_95,
        2.571_926_949_855_605_429_2,
        -0.596_039_204_828_224_924_97,
    ],
];

impl Tableau {
    /// The constants, evaluated with the same expressions as `RADCOR`.
    pub fn new() -> Self {
        let sq6 = 6.0f64.sqrt();
        let c1 = (4.0 - sq6) / 10.0;
        let c2 = (4.0 + sq6) / 10.0;
        let cbrt81 = 81.0f64.powf(1.0 / 3.0);
        let cbrt9 = 9.0f64.powf(1.0 / 3.0);
        let u1 = (6.0 + cbrt81 - cbrt9) / 30.0;
        let alph = (12.0 - cbrt81 + cbrt9) / 60.0;
        let beta = (cbrt81 + cbrt9) * 3.0f64.sqrt() / 60.0;
        let cno = alph * alph + beta * beta;
        Tableau {
            c1,
            c2,
            c1m1: c1 - 1.0,
            c2m1: c2 - 1.0,
            c1mc2: c1 - c2,
            dd1: -(13.0 + 7.0 * sq6) / 3.0,
            dd2: (-13.0 + 7.0 * sq6) / 3.0,
            dd3: -1.0 / 3.0,
            gamma: 1.0 / u1,
            alpha: alph / cno,
            beta: beta / cno,
        }
    }

    /// The Butcher matrix `A` of Radau IIA (radau5.md §1), for checks.
    pub fn butcher_a() -> [[f64; 3]; 3] {
        let s6 = 6.0f64.sqrt();
        [
            [
                (88.0 - 7.0 * s6) / 360.0,
                (296.0 - 169.0 * s6) / 1800.0,
                (-2.0 + 3.0 * s6) / 225.0,
            ],
            [
                (296.0 + 169.0 * s6) / 1800.0,
                (88.0 + 7.0 * s6) / 360.0,
                (-2.0 - 3.0 * s6) / 225.0,
            ],
            [(16.0 - s6) / 36.0, (16.0 + s6) / 36.0, 1.0 / 9.0],
        ]
    }
}

impl Default for Tableau {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop, clippy::excessive_precision)]
mod tests {
    use super::*;

    fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                for (k, bk) in b.iter().enumerate() {
                    c[i][j] += a[i][k] * bk[j];
                }
            }
        }
        c
    }

    /// 3x3 inverse by the adjugate (independent of the method's own constants).
    fn inv(a: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        let mut r = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                let (r0, r1) = ((j + 1) % 3, (j + 2) % 3);
                let (c0, c1) = ((i + 1) % 3, (i + 2) % 3);
                r[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
            }
        }
        r
    }

    /// radau5.md §1: `T^-1 A^-1 T = [[gamma,0,0],[0,alpha,-beta],[0,beta,alpha]]` to 1e-14.
    #[test]
    fn transformed_inverse_has_block_form() {
        let tab = Tableau::new();
        let ainv = inv(&Tableau::butcher_a());
        let m = mul(&TI, &mul(&ainv, &T));
        let want = [
            [tab.gamma, 0.0, 0.0],
            [0.0, tab.alpha, -tab.beta],
            [0.0, tab.beta, tab.alpha],
        ];
        for i in 0..3 {
            for j in 0..3 {
                let d = (m[i][j] - want[i][j]).abs();
                assert!(d <= 1e-14, "entry ({i},{j}): {} vs {}", m[i][j], want[i][j]);
            }
        }
        // Published values (radau5.md §1).
        assert!((tab.gamma - 3.637_834_252_744_495_7).abs() < 1e-14);
        assert!((tab.alpha - 2.681_082_873_627_752_1).abs() < 1e-14);
        assert!((tab.beta - 3.050_430_199_247_410_6).abs() < 1e-14);
        // T T^-1 = I
        let id = mul(&T, &TI);
        for (i, row) in id.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 1e-14);
            }
        }
    }
}
