//! The linear systems of the simplified Newton iteration (radau5.md §4): the real and the
//! complex matrix `E = c M - J`, split into second-order, factorised and quadrature
//! blocks so that only the factorised block is decomposed ([`Blocks`]), and the row
//! pattern of the mass matrix for the products `M x` ([`MassPattern`]).

use nalgebra::{Complex, SMatrix, SVector};

use super::linalg::{ComplexLu, RealLu};
use super::state::State;
use super::Error;

/// Components split by [`Options::quadrature`] and [`Options::second_order`]:
/// `dyn_idx[..nd]` are factorised; `kin_idx[..nk]` obey `y_i' = y_{p(i)}`,
/// `p(i) = i + m2` (second-order structure); `quad_idx[..nq]` are pure quadratures.
/// Writing `E = c M - J` (c = gamma/h, or (alpha + i beta)/h for E2) in the order
/// (K, D, Q) gives, with `P` the 0/1 matrix picking the partners p(i),
///
/// ```text
/// [ c I     -P     0  ] [x_k]   [b_k]
/// [ -J_dk   E_dd   0  ] [x_d] = [b_d]
/// [ -J_qk   -J_qd  c I] [x_q]   [b_q]
/// ```
///
/// because row i of J is `e_p(i)` for K (and M has identity rows/columns there), and the
/// columns of J are zero for Q. Eliminating `x_k = (b_k + P x_d)/c`:
/// `(E_dd - J_dk P^T / c) x_d = b_d + J_dk b_k / c`, then x_k, then
/// `x_q = (b_q + J_qk x_k + J_qd x_d)/c`. The LUs shrink from N to nd (cost ~nd^3), which
/// is what the Fortran's `IWORK(9..10)` option does for second-order systems.
#[derive(Debug, Clone)]
pub(crate) struct Blocks<const N: usize> {
    pub(super) nd: usize,
    pub(super) dyn_idx: [usize; N],
    pub(super) nq: usize,
    pub(super) quad_idx: [usize; N],
    pub(super) nk: usize,
    pub(super) kin_idx: [usize; N],
    /// Position in `dyn_idx` of the partner of each K component.
    pub(super) kin_partner: [usize; N],
    /// For each position r in `dyn_idx`: the K component whose partner it is (or N).
    pub(super) kin_of_dyn: [usize; N],
}

impl<const N: usize> Blocks<N> {
    /// Checks the declared structure against M and the index counts.
    pub(super) fn new(
        quad: &[bool; N],
        second_order: Option<(usize, usize)>,
        mass: Option<&SMatrix<f64, N, N>>,
        n1: usize,
    ) -> Result<Self, Error> {
        let mut b = Self::none();
        b.nd = 0;
        let (m1, m2) = second_order.unwrap_or((0, 0));
        if m1 > 0 && (m2 < m1 || m1 + m2 > N || m1 + m2 > n1) {
            return Err(Error::InvalidOption {
                name: "second_order",
                value: m1 as f64,
                requirement: "m1 <= m2, m1 + m2 <= n1 (the partners are index-1 components)",
            });
        }
        let identity_row_col = |i: usize| {
            mass.is_none_or(|m| {
                (0..N).all(|j| {
                    let e = if i == j { 1.0 } else { 0.0 };
                    m[(i, j)] == e && m[(j, i)] == e
                })
            })
        };
        let mut pos = [N; N];
        for i in 0..N {
            if i < m1 {
                if !identity_row_col(i) || quad[i] || quad[i + m2] {
                    return Err(Error::InvalidOption {
                        name: "second_order",
                        value: i as f64,
                        requirement:
                            "y_i' = y_(i+m2) with identity row and column of M, no quadrature",
                    });
                }
                b.kin_idx[b.nk] = i;
                b.nk += 1;
            } else if quad[i] {
                if i >= n1 || !identity_row_col(i) {
                    return Err(Error::InvalidOption {
                        name: "quadrature",
                        value: i as f64,
                        requirement: "an index-1 component with an identity row and column of M",
                    });
                }
                b.quad_idx[b.nq] = i;
                b.nq += 1;
            } else {
                pos[i] = b.nd;
                b.dyn_idx[b.nd] = i;
                b.nd += 1;
            }
        }
        b.kin_of_dyn = [N; N];
        for k in 0..b.nk {
            let r = pos[b.kin_idx[k] + m2];
            b.kin_partner[k] = r;
            b.kin_of_dyn[r] = b.kin_idx[k];
        }
        Ok(b)
    }

    /// No structure declared (the Fortran's full LUs).
    pub(crate) fn none() -> Self {
        Blocks {
            nd: N,
            dyn_idx: std::array::from_fn(|i| i),
            nq: 0,
            quad_idx: [0; N],
            nk: 0,
            kin_idx: [0; N],
            kin_partner: [0; N],
            kin_of_dyn: [N; N],
        }
    }

    pub(super) fn full(&self) -> bool {
        self.nd == N
    }

    /// Builds the reduced `E1 = fac1 M_dd - J_dd + J_dk P^T / fac1` and
    /// `E2 = c2 M_dd - J_dd + J_dk P^T / c2` (c2 = alphn + i betan) and factorises them.
    #[inline(never)]
    pub(super) fn decompose(
        &self,
        s: &mut State<N>,
        fac1: f64,
        (alphn, betan): (f64, f64),
    ) -> Result<(), ()> {
        let di = &self.dyn_idx[..self.nd];
        let den = alphn * alphn + betan * betan;
        // 1/c2 = (alphn - i betan)/den.
        let (ir, ii) = (alphn / den, -betan / den);
        let inv1 = 1.0 / fac1;
        for (c, &j) in di.iter().enumerate() {
            let kj = self.kin_of_dyn[c];
            for (r, &i) in di.iter().enumerate() {
                let bb = if s.has_mass {
                    s.mass[(i, j)]
                } else if i == j {
                    1.0
                } else {
                    0.0
                };
                let mut e1 = bb * fac1 - s.jac[(i, j)];
                let mut e2 = Complex::new(bb * alphn - s.jac[(i, j)], bb * betan);
                if kj < N {
                    let jk = s.jac[(i, kj)];
                    e1 -= jk * inv1;
                    e2 = Complex::new(e2.re - jk * ir, e2.im - jk * ii);
                }
                s.lu1.a[(r, c)] = e1;
                s.lu2.a[(r, c)] = e2;
            }
        }
        if s.lu1.factor_leading(self.nd).is_ok() && s.lu2.factor_leading(self.nd).is_ok() {
            Ok(())
        } else {
            Err(())
        }
    }

    /// Copies the blocks of J that the reduced solves read into `el` (with every
    /// decomposition: J and the LU pair change together).
    pub(super) fn pack(&self, jac: &SMatrix<f64, N, N>, el: &mut Elimination<N>) {
        let (nd, nk) = (self.nd, self.nk);
        for (n, &k) in self.kin_idx[..nk].iter().enumerate() {
            for (r, &i) in self.dyn_idx[..nd].iter().enumerate() {
                el.jdk[(r, n)] = jac[(i, k)];
            }
        }
        let cols = self.dyn_idx[..nd].iter().chain(&self.kin_idx[..nk]);
        for (c, &j) in cols.enumerate() {
            for (m, &i) in self.quad_idx[..self.nq].iter().enumerate() {
                el.jq[(m, c)] = jac[(i, j)];
            }
        }
    }

    /// Solves `E1 x = b` in place (`E1 = fac1 M - J` factorised by [`Radau5::decompose`]).
    /// Inlined so that the default (full) path is the plain `SOL` call it always was.
    #[inline(always)]
    pub(super) fn solve1(
        &self,
        lu: &RealLu<N>,
        el: &Elimination<N>,
        fac1: f64,
        b: &mut SVector<f64, N>,
    ) {
        if self.full() {
            lu.solve(b);
        } else {
            self.solve1_reduced(lu, el, fac1, b);
        }
    }

    /// [`Blocks::solve1`] with eliminated components. Every sum runs over the same terms
    /// in the same order as the element-wise formulas of [`Blocks`]; the loops read
    /// the packed blocks column by column (contiguous, so they vectorise).
    #[inline(never)]
    pub(super) fn solve1_reduced(
        &self,
        lu: &RealLu<N>,
        el: &Elimination<N>,
        fac1: f64,
        b: &mut SVector<f64, N>,
    ) {
        let (nd, nk, nq) = (self.nd, self.nk, self.nq);
        let (di, ki) = (&self.dyn_idx[..nd], &self.kin_idx[..nk]);
        // c = b_d + J_dk (b_k / fac1) (divisions once per K component: they are slow)
        let mut c = SVector::<f64, N>::zeros();
        let cs = &mut c.as_mut_slice()[..nd];
        for r in 0..nd {
            cs[r] = b[di[r]];
        }
        for n in 0..nk {
            let q = b[ki[n]] / fac1;
            axpy(cs, el.jdk_col(n, nd), q);
        }
        lu.solve_leading(nd, &mut c);
        for r in 0..nd {
            b[di[r]] = c[r];
        }
        for n in 0..nk {
            let k = ki[n];
            b[k] = (b[k] + c[self.kin_partner[n]]) / fac1;
        }
        // x_q = (b_q + J_qd x_d + J_qk x_k) / fac1
        if nq > 0 {
            let qi = &self.quad_idx[..nq];
            let mut acc = [0.0; N];
            let sq = &mut acc[..nq];
            for m in 0..nq {
                sq[m] = b[qi[m]];
            }
            for r in 0..nd {
                axpy(sq, el.jq_col(r, nq), c[r]);
            }
            for n in 0..nk {
                axpy(sq, el.jq_col(nd + n, nq), b[ki[n]]);
            }
            for m in 0..nq {
                b[qi[m]] = sq[m] / fac1;
            }
        }
    }

    /// Solves `E2 (xr + i xi) = br + i bi` in place (`E2 = (alphn + i betan) M - J`).
    #[inline(always)]
    pub(super) fn solve2(
        &self,
        lu: &ComplexLu<N>,
        el: &Elimination<N>,
        ab: (f64, f64),
        br: &mut SVector<f64, N>,
        bi: &mut SVector<f64, N>,
    ) {
        if self.full() {
            lu.solve(br, bi);
        } else {
            self.solve2_reduced(lu, el, ab, br, bi);
        }
    }

    /// [`Blocks::solve2`] with eliminated components (same order of operations as the
    /// element-wise formulas, packed blocks read column by column).
    #[inline(never)]
    pub(super) fn solve2_reduced(
        &self,
        lu: &ComplexLu<N>,
        el: &Elimination<N>,
        (alphn, betan): (f64, f64),
        br: &mut SVector<f64, N>,
        bi: &mut SVector<f64, N>,
    ) {
        let (nd, nk, nq) = (self.nd, self.nk, self.nq);
        let (di, ki) = (&self.dyn_idx[..nd], &self.kin_idx[..nk]);
        let den = alphn * alphn + betan * betan;
        // 1/c2 = (ir + i ii).
        let (ir, ii) = (alphn / den, -betan / den);
        // b_k / c2 for the K components.
        let mut qr = [0.0; N];
        let mut qi = [0.0; N];
        for (n, &k) in ki.iter().enumerate() {
            qr[n] = br[k] * ir - bi[k] * ii;
            qi[n] = bi[k] * ir + br[k] * ii;
        }
        let mut cr = SVector::<f64, N>::zeros();
        let mut ci = SVector::<f64, N>::zeros();
        {
            let (sr, si) = (&mut cr.as_mut_slice()[..nd], &mut ci.as_mut_slice()[..nd]);
            for r in 0..nd {
                sr[r] = br[di[r]];
                si[r] = bi[di[r]];
            }
            for n in 0..nk {
                axpy2(sr, si, el.jdk_col(n, nd), qr[n], qi[n]);
            }
        }
        lu.solve_leading(nd, &mut cr, &mut ci);
        for r in 0..nd {
            br[di[r]] = cr[r];
            bi[di[r]] = ci[r];
        }
        for (n, &k) in ki.iter().enumerate() {
            // x_k = (b_k + x_p)/c2 = b_k/c2 + x_p/c2
            let (xr, xi) = (cr[self.kin_partner[n]], ci[self.kin_partner[n]]);
            br[k] = qr[n] + (xr * ir - xi * ii);
            bi[k] = qi[n] + (xi * ir + xr * ii);
        }
        if nq > 0 {
            let qidx = &self.quad_idx[..nq];
            let (mut ar, mut ai) = ([0.0; N], [0.0; N]);
            let (sr, si) = (&mut ar[..nq], &mut ai[..nq]);
            for m in 0..nq {
                sr[m] = br[qidx[m]];
                si[m] = bi[qidx[m]];
            }
            for r in 0..nd {
                axpy2(sr, si, el.jq_col(r, nq), cr[r], ci[r]);
            }
            for (n, &k) in ki.iter().enumerate() {
                axpy2(sr, si, el.jq_col(nd + n, nq), br[k], bi[k]);
            }
            for m in 0..nq {
                let q = qidx[m];
                br[q] = (sr[m] * alphn + si[m] * betan) / den;
                bi[q] = (si[m] * alphn - sr[m] * betan) / den;
            }
        }
    }
}

/// `acc += col x` (equal lengths; a plain loop the compiler vectorises).
#[inline(always)]
fn axpy(acc: &mut [f64], col: &[f64], x: f64) {
    let col = &col[..acc.len()];
    for m in 0..acc.len() {
        acc[m] += col[m] * x;
    }
}

/// `(ar, ai) += col (xr, xi)` for a real column and a complex factor.
#[inline(always)]
fn axpy2(ar: &mut [f64], ai: &mut [f64], col: &[f64], xr: f64, xi: f64) {
    let n = ar.len();
    let (ai, col) = (&mut ai[..n], &col[..n]);
    for m in 0..n {
        ar[m] += col[m] * xr;
        ai[m] += col[m] * xi;
    }
}

/// The blocks of J that the reduced solves of [`Blocks`] read, packed by
/// [`Blocks::pack`] at every decomposition (so they always belong to the LU pair):
/// `jdk` column n holds `J[dyn_idx[r], kin_idx[n]]` in rows r < nd; `jq` column c holds
/// `J[quad_idx[m], j_c]` in rows m < nq for the columns `j_c` = dyn_idx, then kin_idx.
/// Column-major storage makes every column a contiguous slice.
#[derive(Debug, Clone)]
pub(crate) struct Elimination<const N: usize> {
    jdk: SMatrix<f64, N, N>,
    jq: SMatrix<f64, N, N>,
}

impl<const N: usize> Elimination<N> {
    pub(crate) fn zeros() -> Self {
        Elimination {
            jdk: SMatrix::zeros(),
            jq: SMatrix::zeros(),
        }
    }

    #[inline(always)]
    fn jdk_col(&self, n: usize, nd: usize) -> &[f64] {
        &self.jdk.as_slice()[n * N..n * N + nd]
    }

    #[inline(always)]
    fn jq_col(&self, c: usize, nq: usize) -> &[f64] {
        &self.jq.as_slice()[c * N..c * N + nq]
    }
}

/// Row-wise nonzero pattern of the mass matrix. Products `M x` skip the structural
/// zeros; this changes no bit of the result (the Fortran's sums start at +0 and adding
/// `0 * x_j = +-0` to a sum that is never -0 leaves it unchanged), but saves most of the
/// N^2 work for the (block-)diagonal masses of mechanical DAEs.
#[derive(Debug, Clone)]
pub(crate) struct MassPattern<const N: usize> {
    cols: [[usize; N]; N],
    len: [usize; N],
}

impl<const N: usize> MassPattern<N> {
    pub(crate) fn new(m: &SMatrix<f64, N, N>) -> Self {
        let mut cols = [[0usize; N]; N];
        let mut len = [0usize; N];
        for i in 0..N {
            for j in 0..N {
                if m[(i, j)] != 0.0 {
                    cols[i][len[i]] = j;
                    len[i] += 1;
                }
            }
        }
        MassPattern { cols, len }
    }

    #[inline]
    pub(super) fn row(&self, i: usize) -> &[usize] {
        &self.cols[i][..self.len[i]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::radau5::{Options, Problem, Radau5, RhsError};

    /// N = 6: y0' = y3 (second-order, m1 = 1, m2 = 3), y5 a quadrature, y4 with a zero mass
    /// (index-1 algebraic), the rest dense. Only the structure matters here.
    struct Structured;

    impl Problem<6> for Structured {
        fn rhs(
            &mut self,
            _t: f64,
            y: &SVector<f64, 6>,
            f: &mut SVector<f64, 6>,
        ) -> Result<(), RhsError> {
            f.copy_from(y);
            Ok(())
        }
        fn mass(&self) -> Option<SMatrix<f64, 6, 6>> {
            let mut m = SMatrix::<f64, 6, 6>::identity();
            m[(1, 2)] = 0.3;
            m[(2, 1)] = -0.2;
            m[(4, 4)] = 0.0;
            Some(m)
        }
    }

    /// The block elimination solves `E1 x = b` and `E2 x = b` exactly (to rounding) for
    /// a Jacobian with the declared structure: residuals computed with the full matrices.
    #[test]
    fn block_elimination_solves_the_full_systems() {
        let o = Options {
            quadrature: [false, false, false, false, false, true],
            second_order: Some((1, 3)),
            ..Options::default()
        };
        let mut p = Structured;
        let mut r = Radau5::new(&mut p, o, 0.0, SVector::zeros()).expect("valid");
        assert_eq!((r.blocks.nd, r.blocks.nk, r.blocks.nq), (4, 1, 1));
        let mut jac = SMatrix::<f64, 6, 6>::from_fn(|i, j| {
            (((i * 5 + j * 3) % 7) as f64 - 3.0) * if i == j { 10.0 } else { 1.0 }
        });
        jac.row_mut(0).fill(0.0);
        jac[(0, 3)] = 1.0;
        jac.column_mut(5).fill(0.0);
        r.st.jac = jac;
        let h = 0.01;
        let tab = r.tab;
        let (fac1, alphn, betan) = (tab.gamma / h, tab.alpha / h, tab.beta / h);
        r.blocks
            .decompose(&mut r.st, fac1, (alphn, betan))
            .expect("regular");
        r.blocks.pack(&r.st.jac, &mut r.elim);
        let m = r.st.mass;
        let b = SVector::<f64, 6>::from_fn(|i, _| 1.0 + i as f64 * 0.7);
        let bi = SVector::<f64, 6>::from_fn(|i, _| (i as f64 - 2.0) * 0.3);
        let mut x = b;
        r.blocks.solve1(&r.st.lu1, &r.elim, fac1, &mut x);
        let res = (m * fac1 - jac) * x - b;
        assert!(res.amax() < 1e-13 * b.amax(), "real residual {res}");
        let (mut xr, mut xi) = (b, bi);
        r.blocks
            .solve2(&r.st.lu2, &r.elim, (alphn, betan), &mut xr, &mut xi);
        // (alphn + i betan) M - J applied to xr + i xi.
        let er = m * alphn - jac;
        let ei = m * betan;
        let rr = er * xr - ei * xi - b;
        let ri = er * xi + ei * xr - bi;
        assert!(
            rr.amax().max(ri.amax()) < 1e-13 * b.amax(),
            "complex residual {rr} {ri}"
        );
    }
}
