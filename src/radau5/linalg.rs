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

    /// Factorises the leading `n x n` block of `self.a` in place like `DEC` with `N = n`
    /// (the rest of the storage is not touched; `n <= N`), except that the diagonal keeps
    /// the reciprocals `1/u_kk`, so that [`RealLu::solve_leading`] multiplies instead of
    /// dividing (divisions are a long latency chain in the back substitution). Rounds
    /// differently from `SOL`, so only for the quadrature path (no Fortran counterpart). Used for the
    /// block-triangular systems of quadrature components (see `stepper.rs`).
    ///
    /// # Errors
    /// [`Singular`] when a zero pivot appears.
    pub fn factor_leading(&mut self, n: usize) -> Result<(), Singular> {
        // Column slices (storage is column-major): no bounds checks in the inner loops,
        // and the column updates vectorise (separate multiply and add, as scalar).
        let n = n.min(N);
        self.perm = std::array::from_fn(|i| i);
        if n == 0 {
            return Ok(());
        }
        let data = self.a.as_mut_slice();
        for k in 0..n - 1 {
            let (left, right) = data.split_at_mut((k + 1) * N);
            let (prev, colk) = left.split_at_mut(k * N);
            let colk = &mut colk[..n];
            let mut m = k;
            for i in k + 1..n {
                if colk[i].abs() > colk[m].abs() {
                    m = i;
                }
            }
            self.ip[k] = m;
            let mut t = colk[m];
            if m != k {
                colk[m] = colk[k];
                colk[k] = t;
                self.perm.swap(m, k);
                for col in prev.chunks_exact_mut(N) {
                    col.swap(m, k);
                }
            }
            if t == 0.0 {
                return Err(Singular(k + 1));
            }
            t = 1.0 / t;
            colk[k] = t;
            for x in &mut colk[k + 1..n] {
                *x = -*x * t;
            }
            let mult = &colk[k + 1..n];
            for col in right.chunks_exact_mut(N).take(n - k - 1) {
                col.swap(m, k);
                let t = col[k];
                if t != 0.0 {
                    for (y, x) in col[k + 1..n].iter_mut().zip(mult) {
                        *y += *x * t;
                    }
                }
            }
        }
        let last = &mut self.a[(n - 1, n - 1)];
        if *last == 0.0 {
            return Err(Singular(n));
        }
        *last = 1.0 / *last;
        Ok(())
    }

    /// Solves with the factors of [`RealLu::factor_leading`]`(n)`; uses `b[..n]`.
    pub fn solve_leading(&self, n: usize, b: &mut SVector<f64, N>) {
        let n = n.min(N);
        if n == 0 {
            return;
        }
        let b = &mut b.as_mut_slice()[..n];
        let data = self.a.as_slice();
        let mut src = [0.0; N];
        src[..n].copy_from_slice(b);
        for (bi, &p) in b.iter_mut().zip(&self.perm[..n]) {
            *bi = src[p];
        }
        for k in 0..n - 1 {
            let col = &data[k * N..k * N + n];
            let (head, tail) = b.split_at_mut(k + 1);
            let t = head[k];
            for (y, x) in tail.iter_mut().zip(&col[k + 1..]) {
                *y += *x * t;
            }
        }
        for k in (1..n).rev() {
            let col = &data[k * N..k * N + n];
            let (head, tail) = b.split_at_mut(k);
            tail[0] *= col[k];
            let t = -tail[0];
            for (y, x) in head.iter_mut().zip(&col[..k]) {
                *y += *x * t;
            }
        }
        b[0] *= data[0];
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

    /// Factorises the leading `n x n` block in place (as [`RealLu::factor_leading`]:
    /// the diagonal keeps `1/u_kk`).
    ///
    /// # Errors
    /// [`Singular`] when a zero pivot appears.
    pub fn factor_leading(&mut self, n: usize) -> Result<(), Singular> {
        let n = n.min(N);
        self.perm = std::array::from_fn(|i| i);
        if n == 0 {
            return Ok(());
        }
        let norm1 = |z: Complex<f64>| z.re.abs() + z.im.abs();
        let data = self.a.as_mut_slice();
        for k in 0..n - 1 {
            let (left, right) = data.split_at_mut((k + 1) * N);
            let (prev, colk) = left.split_at_mut(k * N);
            let colk = &mut colk[..n];
            let mut m = k;
            for i in k + 1..n {
                if norm1(colk[i]) > norm1(colk[m]) {
                    m = i;
                }
            }
            self.ip[k] = m;
            let p = colk[m];
            if m != k {
                colk[m] = colk[k];
                colk[k] = p;
                self.perm.swap(m, k);
                for col in prev.chunks_exact_mut(N) {
                    col.swap(m, k);
                }
            }
            if norm1(p) == 0.0 {
                return Err(Singular(k + 1));
            }
            let den = p.re * p.re + p.im * p.im;
            let tr = p.re / den;
            let ti = -p.im / den;
            colk[k] = Complex::new(tr, ti);
            for x in &mut colk[k + 1..n] {
                let prodr = x.re * tr - x.im * ti;
                let prodi = x.im * tr + x.re * ti;
                *x = Complex::new(-prodr, -prodi);
            }
            let mult = &colk[k + 1..n];
            for col in right.chunks_exact_mut(N).take(n - k - 1) {
                col.swap(m, k);
                let t = col[k];
                let (tr, ti) = (t.re, t.im);
                if tr.abs() + ti.abs() == 0.0 {
                    continue;
                }
                for (y, x) in col[k + 1..n].iter_mut().zip(mult) {
                    let prodr = x.re * tr - x.im * ti;
                    let prodi = x.im * tr + x.re * ti;
                    *y = Complex::new(y.re + prodr, y.im + prodi);
                }
            }
        }
        let last = &mut self.a[(n - 1, n - 1)];
        if norm1(*last) == 0.0 {
            return Err(Singular(n));
        }
        let den = last.re * last.re + last.im * last.im;
        *last = Complex::new(last.re / den, -last.im / den);
        Ok(())
    }

    /// Solves with the factors of [`ComplexLu::factor_leading`]`(n)`; uses `br[..n]`,
    /// `bi[..n]`.
    pub fn solve_leading(&self, n: usize, br: &mut SVector<f64, N>, bi: &mut SVector<f64, N>) {
        let n = n.min(N);
        if n == 0 {
            return;
        }
        let (br, bi) = (&mut br.as_mut_slice()[..n], &mut bi.as_mut_slice()[..n]);
        let data = self.a.as_slice();
        let mut sr = [0.0; N];
        let mut si = [0.0; N];
        sr[..n].copy_from_slice(br);
        si[..n].copy_from_slice(bi);
        for ((r, i), &p) in br.iter_mut().zip(bi.iter_mut()).zip(&self.perm[..n]) {
            *r = sr[p];
            *i = si[p];
        }
        for k in 0..n - 1 {
            let col = &data[k * N + k + 1..k * N + n];
            let (hr, tr_) = br.split_at_mut(k + 1);
            let (hi, ti_) = bi.split_at_mut(k + 1);
            let (tr, ti) = (hr[k], hi[k]);
            for ((yr, yi), x) in tr_.iter_mut().zip(ti_.iter_mut()).zip(col) {
                *yr += x.re * tr - x.im * ti;
                *yi += x.im * tr + x.re * ti;
            }
        }
        for k in (0..n).rev() {
            let col = &data[k * N..k * N + n];
            let d = col[k]; // 1/u_kk
            let (xr, xi) = (br[k], bi[k]);
            br[k] = xr * d.re - xi * d.im;
            bi[k] = xi * d.re + xr * d.im;
            if k == 0 {
                break;
            }
            let (tr, ti) = (-br[k], -bi[k]);
            for ((yr, yi), x) in br[..k].iter_mut().zip(bi[..k].iter_mut()).zip(&col[..k]) {
                *yr += x.re * tr - x.im * ti;
                *yi += x.im * tr + x.re * ti;
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
    fn leading_blocks_solve_and_ignore_the_rest() {
        // 3 x 3 systems in the leading block of 5 x 5 storage filled with junk elsewhere.
        let m = SMatrix::<f64, 3, 3>::new(0.0, 2.0, 1.0, 1.0, 1.0, 1.0, 4.0, -1.0, 3.0);
        let x = SVector::<f64, 3>::new(1.0, -2.0, 0.5);
        let rhs = m * x;
        let mut lu = RealLu::<5> {
            a: SMatrix::from_element(7.0),
            ..RealLu::zeros()
        };
        let mut lc = ComplexLu::<5> {
            a: SMatrix::from_element(Complex::new(7.0, -3.0)),
            ..ComplexLu::zeros()
        };
        let im = [1.0, -0.5, 0.25];
        for i in 0..3 {
            for j in 0..3 {
                lu.a[(i, j)] = m[(i, j)];
                lc.a[(i, j)] = Complex::new(m[(i, j)], if i == j { im[i] } else { 0.0 });
            }
        }
        lu.factor_leading(3).unwrap();
        lc.factor_leading(3).unwrap();
        let mut b = SVector::<f64, 5>::from_element(9.0);
        for i in 0..3 {
            b[i] = rhs[i];
        }
        lu.solve_leading(3, &mut b);
        for i in 0..3 {
            assert!((b[i] - x[i]).abs() < 1e-14);
        }
        assert_eq!((b[3], b[4]), (9.0, 9.0));
        // Complex: A = m + i diag(im), x complex; b = A x computed independently.
        let xr = [1.0, 2.0, -1.0];
        let xi = [0.5, -1.0, 3.0];
        let mut br = SVector::<f64, 5>::zeros();
        let mut bi = SVector::<f64, 5>::zeros();
        for i in 0..3 {
            for j in 0..3 {
                let (ar, ai) = (m[(i, j)], if i == j { im[i] } else { 0.0 });
                br[i] += ar * xr[j] - ai * xi[j];
                bi[i] += ar * xi[j] + ai * xr[j];
            }
        }
        lc.solve_leading(3, &mut br, &mut bi);
        for i in 0..3 {
            assert!((br[i] - xr[i]).abs() < 1e-13 && (bi[i] - xi[i]).abs() < 1e-13);
        }
        let mut s = RealLu::<3>::zeros();
        assert_eq!(s.factor_leading(2), Err(Singular(1)));
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
