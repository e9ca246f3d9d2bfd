//! Dense LU with partial pivoting, operation for operation like `DEC`/`SOL` and
//! `DECC`/`SOLC` of Hairer's `decsol.f` (Moler's Algorithm 423), so that the rounding and
//! hence the step-size decisions match the Fortran (radau5.md §4).
//!
//! Fixed-size storage (no heap). The complex factor holds `nalgebra::Complex` entries, but
//! the arithmetic is written out in real and imaginary parts in the Fortran's order.
//!
//! One deliberate difference in bookkeeping, not in arithmetic: when rows are swapped at
//! stage k, the multipliers of the earlier stages are swapped too (LAPACK's layout), and the
//! composed permutation `perm` is kept. The solve then permutes b once and eliminates with
//! static indices (values stay in registers for small N). Every entry of b receives the
//! same additions, with the same multipliers, in the same order as in `SOL`/`SOLC`, so the
//! results are bit-identical.

use nalgebra::{Complex, SMatrix, SVector};

/// LU factors of a real N x N matrix: `U` on and above the diagonal, the negated
/// multipliers below it; `ip[k]` = pivot row of stage k.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RealLu<const N: usize> {
    pub a: SMatrix<f64, N, N>,
    pub ip: [usize; N],
    /// Composition of the row swaps: row i of the factors is row `perm[i]` of the matrix.
    pub perm: [usize; N],
}

/// LU factors of a complex N x N matrix (layout as [`RealLu`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComplexLu<const N: usize> {
    pub a: SMatrix<Complex<f64>, N, N>,
    pub ip: [usize; N],
    /// As [`RealLu::perm`].
    pub perm: [usize; N],
}

/// The matrix is singular at elimination stage `k` (1-based like the Fortran's IER).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Singular(pub usize);

impl<const N: usize> RealLu<N> {
    pub fn zeros() -> Self {
        RealLu {
            a: SMatrix::zeros(),
            ip: [0; N],
            perm: std::array::from_fn(|i| i),
        }
    }

    /// Factorises `self.a` in place (`DEC`).
    ///
    /// # Errors
    /// [`Singular`] when a zero pivot appears.
    pub fn factor(&mut self) -> Result<(), Singular> {
        let a = &mut self.a;
        if N == 0 {
            return Ok(());
        }
        self.perm = std::array::from_fn(|i| i);
        for k in 0..N.saturating_sub(1) {
            let mut m = k;
            for i in k + 1..N {
                if a[(i, k)].abs() > a[(m, k)].abs() {
                    m = i;
                }
            }
            self.ip[k] = m;
            let mut t = a[(m, k)];
            if m != k {
                a[(m, k)] = a[(k, k)];
                a[(k, k)] = t;
                self.perm.swap(m, k);
                for j in 0..k {
                    a.swap((m, j), (k, j));
                }
            }
            if t == 0.0 {
                return Err(Singular(k + 1));
            }
            t = 1.0 / t;
            for i in k + 1..N {
                a[(i, k)] = -a[(i, k)] * t;
            }
            for j in k + 1..N {
                let t = a[(m, j)];
                a[(m, j)] = a[(k, j)];
                a[(k, j)] = t;
                if t != 0.0 {
                    for i in k + 1..N {
                        a[(i, j)] += a[(i, k)] * t;
                    }
                }
            }
        }
        if a[(N - 1, N - 1)] == 0.0 {
            return Err(Singular(N));
        }
        Ok(())
    }

    /// Solves `A x = b` in place (`SOL`).
    pub fn solve(&self, b: &mut SVector<f64, N>) {
        let a = &self.a;
        if N == 0 {
            return;
        }
        let src = *b;
        for i in 0..N {
            b[i] = src[self.perm[i]];
        }
        for k in 0..N - 1 {
            let t = b[k];
            for i in k + 1..N {
                b[i] += a[(i, k)] * t;
            }
        }
        for k in (1..N).rev() {
            b[k] /= a[(k, k)];
            let t = -b[k];
            for i in 0..k {
                b[i] += a[(i, k)] * t;
            }
        }
        b[0] /= a[(0, 0)];
    }
}

impl<const N: usize> ComplexLu<N> {
    pub fn zeros() -> Self {
        ComplexLu {
            a: SMatrix::from_element(Complex::new(0.0, 0.0)),
            ip: [0; N],
            perm: std::array::from_fn(|i| i),
        }
    }

    /// Factorises `self.a` in place (`DECC`: pivot by `|re| + |im|`).
    ///
    /// # Errors
    /// [`Singular`] when a zero pivot appears.
    pub fn factor(&mut self) -> Result<(), Singular> {
        let a = &mut self.a;
        if N == 0 {
            return Ok(());
        }
        let norm1 = |z: Complex<f64>| z.re.abs() + z.im.abs();
        self.perm = std::array::from_fn(|i| i);
        for k in 0..N.saturating_sub(1) {
            let mut m = k;
            for i in k + 1..N {
                if norm1(a[(i, k)]) > norm1(a[(m, k)]) {
                    m = i;
                }
            }
            self.ip[k] = m;
            let p = a[(m, k)];
            if m != k {
                a[(m, k)] = a[(k, k)];
                a[(k, k)] = p;
                self.perm.swap(m, k);
                for j in 0..k {
                    a.swap((m, j), (k, j));
                }
            }
            if norm1(p) == 0.0 {
                return Err(Singular(k + 1));
            }
            let den = p.re * p.re + p.im * p.im;
            let tr = p.re / den;
            let ti = -p.im / den;
            for i in k + 1..N {
                let x = a[(i, k)];
                let prodr = x.re * tr - x.im * ti;
                let prodi = x.im * tr + x.re * ti;
                a[(i, k)] = Complex::new(-prodr, -prodi);
            }
            for j in k + 1..N {
                let t = a[(m, j)];
                a[(m, j)] = a[(k, j)];
                a[(k, j)] = t;
                let (tr, ti) = (t.re, t.im);
                if tr.abs() + ti.abs() == 0.0 {
                    continue;
                }
                if ti == 0.0 {
                    for i in k + 1..N {
                        let x = a[(i, k)];
                        let prodr = x.re * tr;
                        let prodi = x.im * tr;
                        let y = &mut a[(i, j)];
                        *y = Complex::new(y.re + prodr, y.im + prodi);
                    }
                    continue;
                }
                if tr == 0.0 {
                    for i in k + 1..N {
                        let x = a[(i, k)];
                        let prodr = -x.im * ti;
                        let prodi = x.re * ti;
                        let y = &mut a[(i, j)];
                        *y = Complex::new(y.re + prodr, y.im + prodi);
                    }
                    continue;
                }
                for i in k + 1..N {
                    let x = a[(i, k)];
                    let prodr = x.re * tr - x.im * ti;
                    let prodi = x.im * tr + x.re * ti;
                    let y = &mut a[(i, j)];
                    *y = Complex::new(y.re + prodr, y.im + prodi);
                }
            }
        }
        if norm1(a[(N - 1, N - 1)]) == 0.0 {
            return Err(Singular(N));
        }
        Ok(())
    }

    /// Solves `A x = b` in place with `b = br + i bi` (`SOLC`).
    pub fn solve(&self, br: &mut SVector<f64, N>, bi: &mut SVector<f64, N>) {
        let a = &self.a;
        if N == 0 {
            return;
        }
        let (sr, si) = (*br, *bi);
        for i in 0..N {
            br[i] = sr[self.perm[i]];
            bi[i] = si[self.perm[i]];
        }
        for k in 0..N - 1 {
            let tr = br[k];
            let ti = bi[k];
            for i in k + 1..N {
                let x = a[(i, k)];
                let prodr = x.re * tr - x.im * ti;
                let prodi = x.im * tr + x.re * ti;
                br[i] += prodr;
                bi[i] += prodi;
            }
        }
        for k in (0..N).rev() {
            let d = a[(k, k)];
            let den = d.re * d.re + d.im * d.im;
            let prodr = br[k] * d.re + bi[k] * d.im;
            let prodi = bi[k] * d.re - br[k] * d.im;
            br[k] = prodr / den;
            bi[k] = prodi / den;
            if k == 0 {
                break;
            }
            let tr = -br[k];
            let ti = -bi[k];
            for i in 0..k {
                let x = a[(i, k)];
                let prodr = x.re * tr - x.im * ti;
                let prodi = x.im * tr + x.re * ti;
                br[i] += prodr;
                bi[i] += prodi;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn real_lu_solves_with_pivoting() {
        // Needs a row swap at stage 1 (a11 = 0).
        let m = SMatrix::<f64, 3, 3>::new(0.0, 2.0, 1.0, 1.0, 1.0, 1.0, 4.0, -1.0, 3.0);
        let x = SVector::<f64, 3>::new(1.0, -2.0, 0.5);
        let mut b = m * x;
        let mut lu = RealLu {
            a: m,
            ..RealLu::zeros()
        };
        lu.factor().unwrap();
        lu.solve(&mut b);
        assert!((b - x).norm() < 1e-14);
    }

    #[test]
    fn complex_lu_solves() {
        let re = SMatrix::<f64, 3, 3>::new(0.0, 2.0, 1.0, 1.0, 1.0, 1.0, 4.0, -1.0, 3.0);
        let im = SMatrix::<f64, 3, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
        let a = SMatrix::<Complex<f64>, 3, 3>::from_fn(|i, j| Complex::new(re[(i, j)], im[(i, j)]));
        let x = SVector::<Complex<f64>, 3>::new(
            Complex::new(1.0, 2.0),
            Complex::new(-1.0, 0.5),
            Complex::new(0.0, -3.0),
        );
        let b = a * x;
        let mut br = b.map(|z| z.re);
        let mut bi = b.map(|z| z.im);
        let mut lu = ComplexLu {
            a,
            ..ComplexLu::zeros()
        };
        lu.factor().unwrap();
        lu.solve(&mut br, &mut bi);
        for i in 0..3 {
            assert!((br[i] - x[i].re).abs() < 1e-14 && (bi[i] - x[i].im).abs() < 1e-14);
        }
    }

    #[test]
    fn singular_is_reported() {
        let mut lu = RealLu::<2> {
            a: SMatrix::<f64, 2, 2>::new(1.0, 2.0, 2.0, 4.0),
            ..RealLu::zeros()
        };
        assert_eq!(lu.factor(), Err(Singular(2)));
        let mut c = ComplexLu::<2>::zeros();
        assert_eq!(c.factor(), Err(Singular(1)));
    }
}
