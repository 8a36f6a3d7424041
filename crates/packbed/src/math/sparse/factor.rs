//! The kept Cholesky factor `A₀ = Pᵀ L Lᵀ P` (faer, supernodal) and its two
//! triangular halves, one of them sparse.
//!
//! A broken bond's columns `W` have nonzeros at two bodies only, so `L⁻¹ P w`
//! is nonzero only on the rows of the supernodes on the elimination-tree path
//! from those bodies to the root: [`Factor::sparse_forward`] visits those
//! supernodes alone (a few thousand rows of a 3·10⁵-row factor), where a dense
//! triangular solve reads the whole factor (hundreds of MB). That is why the
//! Woodbury update is kept in this half-solved form, `Y = L⁻¹ P W`.

use super::supernodal::{self, NotPositive, Tree};
use crate::math::Real;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::SparseColMatRef;
use faer::{Conj, MatMut, Par};

/// A sparse vector with sorted indices.
#[derive(Clone, Debug, Default)]
pub struct SparseVec {
    /// Row indices, increasing.
    pub idx: Vec<usize>,
    /// Values.
    pub val: Vec<Real>,
}

impl SparseVec {
    /// `self · x` for a dense `x`.
    pub fn dot_dense(&self, x: &[Real]) -> Real {
        self.idx.iter().zip(&self.val).map(|(&i, v)| v * x[i]).sum()
    }

    /// `self · other` (both sparse, indices sorted).
    pub fn dot(&self, other: &SparseVec) -> Real {
        let (mut a, mut b, mut sum) = (0, 0, 0.0);
        while a < self.idx.len() && b < other.idx.len() {
            match self.idx[a].cmp(&other.idx[b]) {
                std::cmp::Ordering::Less => a += 1,
                std::cmp::Ordering::Greater => b += 1,
                std::cmp::Ordering::Equal => {
                    sum += self.val[a] * other.val[b];
                    a += 1;
                    b += 1;
                }
            }
        }
        sum
    }
}

/// The factor and what its sparse solve needs.
pub struct Factor {
    pub(super) symbolic: SymbolicCholesky<usize>,
    pub(super) values: Vec<Real>,
    /// Permuted row `i` is original row `fwd[i]`; original `j` is permuted `inv[j]`.
    fwd: Vec<usize>,
    inv: Vec<usize>,
    /// Supernode of each permuted row, and each supernode's parent (`usize::MAX`: a root).
    supernode_of: Vec<usize>,
    parent: Vec<usize>,
    tree: Tree,
    par: Par,
}

impl Factor {
    /// The factor's structure from a supernodal symbolic analysis (`None` for
    /// a simplicial one, which the caller rules out).
    pub fn new(symbolic: SymbolicCholesky<usize>, par: Par) -> Option<Factor> {
        let n = symbolic.nrows();
        let (fwd, inv) = match symbolic.perm() {
            Some(p) => (p.arrays().0.to_vec(), p.arrays().1.to_vec()),
            None => ((0..n).collect(), (0..n).collect()),
        };
        let SymbolicCholeskyRaw::Supernodal(s) = symbolic.raw() else {
            return None;
        };
        let mut supernode_of = vec![0; n];
        for k in 0..s.n_supernodes() {
            for row in &mut supernode_of[s.supernode_begin()[k]..s.supernode_end()[k]] {
                *row = k;
            }
        }
        let parent: Vec<usize> = (0..s.n_supernodes())
            .map(|k| {
                s.supernode(k)
                    .pattern()
                    .first()
                    .map_or(usize::MAX, |&row| supernode_of[row])
            })
            .collect();
        let tree = Tree::new(s, &parent);
        Some(Factor {
            tree,
            symbolic,
            values: Vec::new(),
            fwd,
            inv,
            supernode_of,
            parent,
            par,
        })
    }

    /// Factors `a` (original order, lower triangle; the pattern analysed)
    /// into the kept values.
    pub fn factorize(&mut self, a: SparseColMatRef<'_, usize, Real>) -> Result<(), NotPositive> {
        self.values.resize(self.symbolic.len_val(), 0.0);
        let SymbolicCholeskyRaw::Supernodal(s) = self.symbolic.raw() else {
            unreachable!("Factor::new accepts supernodal only")
        };
        supernodal::factorize(s, &self.tree, a, &self.inv, &mut self.values, self.par)
    }

    fn supernodal(&self) -> SupernodalLltRef<'_, usize, Real> {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => SupernodalLltRef::new(s, &self.values),
            SymbolicCholeskyRaw::Simplicial(_) => {
                unreachable!("Factor::new accepts supernodal only")
            }
        }
    }

    fn scratch(&self) -> MemBuffer {
        MemBuffer::new(self.symbolic.solve_in_place_scratch::<Real>(1, self.par))
    }

    /// `L⁻¹ P b` (in the permuted order).
    pub fn forward(&self, b: &[Real]) -> Vec<Real> {
        let n = b.len();
        let mut y: Vec<Real> = self.fwd.iter().map(|&i| b[i]).collect();
        let mut mem = self.scratch();
        self.supernodal().l_solve_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut y, n, 1),
            self.par,
            MemStack::new(&mut mem),
        );
        y
    }

    /// `Pᵀ L⁻ᵀ u` (`u` in the permuted order, the result in the original).
    pub fn backward(&self, mut u: Vec<Real>) -> Vec<Real> {
        let n = u.len();
        let mut mem = self.scratch();
        self.supernodal().l_transpose_solve_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut u, n, 1),
            self.par,
            MemStack::new(&mut mem),
        );
        self.inv.iter().map(|&i| u[i]).collect()
    }

    /// `L⁻¹ P w` for a sparse `w` (original indices), visiting only the
    /// supernodes on the paths from `w`'s rows to the root; `work` is a
    /// zeroed scratch of the factor's size, left zeroed.
    pub fn sparse_forward(&self, idx: &[usize], val: &[Real], work: &mut [Real]) -> SparseVec {
        let mut visit: Vec<usize> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for &i in idx {
            let mut s = self.supernode_of[self.inv[i]];
            while s != usize::MAX && seen.insert(s) {
                visit.push(s);
                s = self.parent[s];
            }
        }
        visit.sort_unstable();
        for (&i, &v) in idx.iter().zip(val) {
            work[self.inv[i]] += v;
        }
        let l = self.supernodal();
        let mut out = SparseVec::default();
        for &k in &visit {
            let node = l.supernode(k);
            let m = node.val();
            let start = node.start();
            let size = m.ncols();
            // x_top ← L_top⁻¹ x_top (column by column of the lower triangle).
            for j in 0..size {
                let col = m.col(j);
                let xj = work[start + j] / col[j];
                work[start + j] = xj;
                if xj != 0.0 {
                    for i in j + 1..size {
                        work[start + i] -= col[i] * xj;
                    }
                    for (p, &row) in node.pattern().iter().enumerate() {
                        work[row] -= col[size + p] * xj;
                    }
                }
            }
            for r in start..start + size {
                out.idx.push(r);
                out.val.push(work[r]);
                work[r] = 0.0;
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::super::supernodal::tests::analysed;
    use super::*;
    use faer::sparse::Triplet;

    /// A grid Laplacian plus a diagonal shift (lower triangle), factored.
    fn grid_factor(side: usize) -> Factor {
        let n = side * side;
        let mut t = Vec::new();
        for r in 0..side {
            for c in 0..side {
                let i = r * side + c;
                t.push(Triplet::new(i, i, 4.0 + 0.01 * (i % 7) as Real));
                if c + 1 < side {
                    t.push(Triplet::new(i + 1, i, -1.0));
                }
                if r + 1 < side {
                    t.push(Triplet::new(i + side, i, -1.0));
                }
            }
        }
        let (a, symbolic) = analysed(n, &t);
        let mut f = Factor::new(symbolic, Par::Seq).unwrap();
        f.factorize(a.as_ref()).unwrap();
        f
    }

    /// The sparse forward solve equals the dense one on every row (zeros
    /// off its support), and leaves its scratch zeroed; forward then
    /// backward inverts the matrix.
    #[test]
    fn sparse_forward_equals_dense_forward() {
        let f = grid_factor(23);
        let n = 23 * 23;
        let mut work = vec![0.0; n];
        for (idx, val) in [
            (vec![0], vec![1.0]),
            (vec![5, 300, 301], vec![0.5, -2.0, 1.5]),
            (vec![n - 1, 17], vec![3.0, 1.0]),
        ] {
            let mut dense = vec![0.0; n];
            for (&i, &v) in idx.iter().zip(&val) {
                dense[i] += v;
            }
            let full = f.forward(&dense);
            let sparse = f.sparse_forward(&idx, &val, &mut work);
            assert!(sparse.idx.windows(2).all(|w| w[0] < w[1]));
            let mut scattered = vec![0.0; n];
            for (&i, &v) in sparse.idx.iter().zip(&sparse.val) {
                scattered[i] = v;
            }
            for i in 0..n {
                assert!((scattered[i] - full[i]).abs() <= 1e-13, "row {i}");
            }
            assert!(work.iter().all(|&w| w == 0.0));
            assert!((sparse.dot(&sparse) - full.iter().map(|v| v * v).sum::<Real>()).abs() < 1e-12);
            // A x = b for x = Pᵀ L⁻ᵀ L⁻¹ P b: check against the grid stencil.
            let x = f.backward(full);
            for r in 0..23 {
                for c in 0..23 {
                    let i = r * 23 + c;
                    let mut ax = (4.0 + 0.01 * (i % 7) as Real) * x[i];
                    for (ok, j) in [
                        (c > 0, i.wrapping_sub(1)),
                        (c + 1 < 23, i + 1),
                        (r > 0, i.wrapping_sub(23)),
                        (r + 1 < 23, i + 23),
                    ] {
                        if ok {
                            ax -= x[j];
                        }
                    }
                    assert!((ax - dense[i]).abs() < 1e-12, "row {i}");
                }
            }
        }
    }
}
