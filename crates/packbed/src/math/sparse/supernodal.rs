//! The numeric supernodal Cholesky factorisation `P A Pᵀ = L Lᵀ`, written
//! into faer's supernodal storage (so faer's triangular solves and
//! [`super::factor::Factor::sparse_forward`] read it unchanged), with the
//! independent subtrees of the elimination tree factored on separate threads.
//!
//! Why not faer's own (0.23): it walks the supernodes one after another and
//! parallelises only inside each dense block, so the many small supernodes
//! below the top separators run on one core. Nested dissection makes the two
//! halves under every separator independent; factoring them side by side
//! keeps both cores busy in the lower tree, and the large separators at the
//! top still use both cores inside their dense blocks. The arithmetic per
//! supernode is faer's left-looking one: gather the updates of the
//! descendants whose rows meet it, factor the diagonal block, solve the rows
//! below it; every sum is taken in the same order whatever the thread count.

use crate::math::Real;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{
    cholesky_in_place, cholesky_in_place_scratch, LltRegularization,
};
use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::SparseColMatRef;
use faer::{Accum, MatMut, MatRef, Par};

/// A dense operation smaller than this many multiply-adds runs on one core.
const PARALLEL_WORK: usize = 1 << 21;

/// A subtree lighter than this share of the whole factorisation is not worth
/// a thread of its own.
const SPLIT_SHARE: f64 = 1.0 / 64.0;

/// The supernodal elimination tree and the work under each supernode.
pub struct Tree {
    children: Vec<Vec<usize>>,
    roots: Vec<usize>,
    /// Supernodes in postorder; the subtree of `s` is `post[first[s]..=pos[s]]`.
    post: Vec<usize>,
    pos: Vec<usize>,
    first: Vec<usize>,
    /// Multiply-adds of the subtree of each supernode.
    weight: Vec<f64>,
    total: f64,
}

impl Tree {
    /// The tree of `symbolic` given each supernode's parent (`usize::MAX`: a root).
    pub fn new(symbolic: &SymbolicSupernodalCholesky<usize>, parent: &[usize]) -> Tree {
        let ns = parent.len();
        let mut children = vec![Vec::new(); ns];
        let mut roots = Vec::new();
        for (s, &p) in parent.iter().enumerate() {
            if p == usize::MAX {
                roots.push(s);
            } else {
                children[p].push(s);
            }
        }
        let mut own = vec![0.0; ns];
        for (s, w) in own.iter_mut().enumerate() {
            let c = (symbolic.supernode_end()[s] - symbolic.supernode_begin()[s]) as f64;
            let p = symbolic.supernode(s).pattern().len() as f64;
            *w = c * c * c / 6.0 + c * c * p / 2.0 + c * p * p / 2.0 + 1.0;
        }
        let (mut post, mut pos, mut first) = (Vec::with_capacity(ns), vec![0; ns], vec![0; ns]);
        let mut weight = own.clone();
        let mut stack: Vec<(usize, usize)> = roots.iter().rev().map(|&r| (r, 0)).collect();
        while let Some((s, next)) = stack.pop() {
            if next == 0 {
                first[s] = post.len();
            }
            if let Some(&k) = children[s].get(next) {
                stack.push((s, next + 1));
                stack.push((k, 0));
            } else {
                pos[s] = post.len();
                post.push(s);
                if parent[s] != usize::MAX {
                    weight[parent[s]] += weight[s];
                }
            }
        }
        let total = roots.iter().map(|&r| weight[r]).sum();
        Tree {
            children,
            roots,
            post,
            pos,
            first,
            weight,
            total,
        }
    }
}

/// The lower triangle of `P A Pᵀ` in compressed columns.
struct Lower {
    ptr: Vec<usize>,
    row: Vec<usize>,
    val: Vec<Real>,
}

impl Lower {
    /// `a`'s lower triangle (entries above the diagonal are ignored, as faer
    /// does for `Side::Lower`) permuted by `inv` (original `j` → permuted `inv[j]`).
    fn permuted(a: SparseColMatRef<'_, usize, Real>, inv: &[usize]) -> Lower {
        let n = a.ncols();
        let mut ptr = vec![0usize; n + 1];
        let each = |f: &mut dyn FnMut(usize, usize, Real)| {
            for j in 0..n {
                for (i, &v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
                    if i >= j {
                        let (pi, pj) = (inv[i], inv[j]);
                        f(pi.max(pj), pi.min(pj), v);
                    }
                }
            }
        };
        each(&mut |_, c, _| ptr[c + 1] += 1);
        for c in 0..n {
            ptr[c + 1] += ptr[c];
        }
        let mut next = ptr.clone();
        let mut row = vec![0; ptr[n]];
        let mut val = vec![0.0; ptr[n]];
        each(&mut |r, c, v| {
            row[next[c]] = r;
            val[next[c]] = v;
            next[c] += 1;
        });
        Lower { ptr, row, val }
    }
}

/// The factor's values, shared by the threads: each supernode's block is
/// written by the one task that factors it and read only by its ancestors,
/// which run after it (a parent waits for the `rayon::join` of its subtrees).
#[derive(Clone, Copy)]
struct Values {
    ptr: *mut Real,
    len: usize,
}

// SAFETY: see the type's comment; no block is written by two tasks or read
// while it is written.
unsafe impl Send for Values {}
unsafe impl Sync for Values {}

impl Values {
    /// # Safety
    /// Only the task factoring the supernode that owns `range` may call this.
    #[allow(clippy::mut_from_ref)]
    unsafe fn block_mut(&self, range: std::ops::Range<usize>) -> &mut [Real] {
        assert!(range.start <= range.end && range.end <= self.len);
        std::slice::from_raw_parts_mut(self.ptr.add(range.start), range.len())
    }

    /// # Safety
    /// `range` must belong to a supernode already factored.
    unsafe fn block(&self, range: std::ops::Range<usize>) -> &[Real] {
        assert!(range.start <= range.end && range.end <= self.len);
        std::slice::from_raw_parts(self.ptr.add(range.start), range.len())
    }
}

/// One task's working memory.
struct Scratch {
    /// Local row of each global row in the supernode being factored.
    local: Vec<usize>,
    update: Vec<Real>,
    stack: MemBuffer,
}

impl Scratch {
    fn new(n: usize, widest: usize, par: Par) -> Scratch {
        Scratch {
            local: vec![usize::MAX; n],
            update: Vec::new(),
            stack: MemBuffer::new(cholesky_in_place_scratch::<Real>(
                widest,
                par,
                Default::default(),
            )),
        }
    }
}

/// The matrix is not positive definite.
#[derive(Debug)]
pub struct NotPositive;

struct Job<'a> {
    symbolic: &'a SymbolicSupernodalCholesky<usize>,
    tree: &'a Tree,
    a: Lower,
    values: Values,
    par: Par,
    widest: usize,
}

/// Factors `a` (original order, lower triangle) permuted by `inv` into
/// `values` (faer's supernodal layout of `symbolic`).
pub fn factorize(
    symbolic: &SymbolicSupernodalCholesky<usize>,
    tree: &Tree,
    a: SparseColMatRef<'_, usize, Real>,
    inv: &[usize],
    values: &mut [Real],
    par: Par,
) -> Result<(), NotPositive> {
    assert_eq!(values.len(), symbolic.len_val());
    let ns = symbolic.n_supernodes();
    let widest = (0..ns)
        .map(|s| symbolic.supernode_end()[s] - symbolic.supernode_begin()[s])
        .max()
        .unwrap_or(0);
    let job = Job {
        symbolic,
        tree,
        a: Lower::permuted(a, inv),
        values: Values {
            ptr: values.as_mut_ptr(),
            len: values.len(),
        },
        par,
        widest,
    };
    let mut scratch = Scratch::new(symbolic.nrows(), widest, par);
    job.descend(&tree.roots, Vec::new(), &mut scratch)
}

impl Job<'_> {
    /// Factors the subtrees of `kids`. Light subtrees run here, in
    /// postorder; a lone heavy one is entered, its supernode put on `chain`
    /// (a path down the tree) and its children taken as the next `kids`; two
    /// or more heavy ones are shared between two tasks. The supernodes on
    /// `chain` are factored last, deepest first, so that every supernode
    /// follows its descendants.
    fn descend(
        &self,
        kids: &[usize],
        mut chain: Vec<usize>,
        scratch: &mut Scratch,
    ) -> Result<(), NotPositive> {
        let tree = self.tree;
        let split = tree.total * SPLIT_SHARE;
        let threads = rayon::current_num_threads();
        let mut kids = kids;
        loop {
            let (heavy, light): (Vec<usize>, Vec<usize>) = kids
                .iter()
                .partition(|&&k| threads > 1 && tree.weight[k] >= split);
            for k in light {
                self.sequential(k, scratch)?;
            }
            match heavy.len() {
                0 => break,
                1 => {
                    chain.push(heavy[0]);
                    kids = &tree.children[heavy[0]];
                }
                _ => {
                    let (left, right) = balance(&heavy, &tree.weight);
                    let (a, b) = rayon::join(
                        || {
                            let mut own =
                                Scratch::new(self.symbolic.nrows(), self.widest, self.par);
                            left.iter()
                                .try_for_each(|&k| self.descend(&[k], Vec::new(), &mut own))
                        },
                        || {
                            right
                                .iter()
                                .try_for_each(|&k| self.descend(&[k], Vec::new(), scratch))
                        },
                    );
                    a?;
                    b?;
                    break;
                }
            }
        }
        for &s in chain.iter().rev() {
            self.node(s, scratch)?;
        }
        Ok(())
    }

    /// Factors the subtree of `s` on this thread.
    fn sequential(&self, s: usize, scratch: &mut Scratch) -> Result<(), NotPositive> {
        let tree = self.tree;
        for &x in &tree.post[tree.first[s]..=tree.pos[s]] {
            self.node(x, scratch)?;
        }
        Ok(())
    }

    /// Factors supernode `s`, whose descendants are factored.
    fn node(&self, s: usize, scratch: &mut Scratch) -> Result<(), NotPositive> {
        let sym = self.symbolic;
        let tree = self.tree;
        let (sb, se) = (sym.supernode_begin()[s], sym.supernode_end()[s]);
        let c = se - sb;
        let pattern = sym.supernode(s).pattern();
        let r = c + pattern.len();
        let vp = sym.col_ptr_for_val();
        // SAFETY: this task owns supernode `s`.
        let ls = unsafe { self.values.block_mut(vp[s]..vp[s + 1]) };
        ls.fill(0.0);
        let local = &mut scratch.local;
        for (i, &row) in pattern.iter().enumerate() {
            local[row] = c + i;
        }
        let at = |row: usize, local: &[usize]| if row < se { row - sb } else { local[row] };
        for j in sb..se {
            let col = &mut ls[(j - sb) * r..(j - sb + 1) * r];
            for k in self.a.ptr[j]..self.a.ptr[j + 1] {
                col[at(self.a.row[k], local)] += self.a.val[k];
            }
        }
        for &d in &tree.post[tree.first[s]..tree.pos[s]] {
            let dp = sym.supernode(d).pattern();
            let k0 = dp.partition_point(|&x| x < sb);
            let k1 = k0 + dp[k0..].partition_point(|&x| x < se);
            if k1 == k0 {
                continue;
            }
            let dc = sym.supernode_end()[d] - sym.supernode_begin()[d];
            let dr = dc + dp.len();
            // SAFETY: `d` is a descendant of `s`, factored before it.
            let ld = MatRef::from_column_major_slice(
                unsafe { self.values.block(vp[d]..vp[d + 1]) },
                dr,
                dc,
            );
            let (m, w) = (dp.len() - k0, k1 - k0);
            let below = ld.subrows(dc + k0, m);
            let within = ld.subrows(dc + k0, w);
            scratch.update.resize(m * w, 0.0);
            let t = MatMut::from_column_major_slice_mut(&mut scratch.update[..m * w], m, w);
            // Only the lower triangle of the square top is needed: the
            // descendants of a top separator lie wholly inside it, where a
            // full product would double the work.
            let par = self.par_for(m * w * dc);
            let (mut t_top, mut t_below) = t.split_at_row_mut(w);
            triangular::matmul(
                t_top.as_mut(),
                BlockStructure::TriangularLower,
                Accum::Replace,
                within,
                BlockStructure::Rectangular,
                within.transpose(),
                BlockStructure::Rectangular,
                1.0,
                par,
            );
            if m > w {
                matmul(
                    t_below.as_mut(),
                    Accum::Replace,
                    below.subrows(w, m - w),
                    within.transpose(),
                    1.0,
                    par,
                );
            }
            let rows = &dp[k0..];
            for (jj, &cj) in rows[..w].iter().enumerate() {
                let tcol = &scratch.update[jj * m..(jj + 1) * m];
                let lcol = &mut ls[(cj - sb) * r..(cj - sb + 1) * r];
                for ii in jj..m {
                    lcol[at(rows[ii], local)] -= tcol[ii];
                }
            }
        }
        let par = self.par_for(c * c * r);
        let (top, bottom) = MatMut::from_column_major_slice_mut(ls, r, c).split_at_row_mut(c);
        let mut top = top;
        cholesky_in_place(
            top.as_mut(),
            LltRegularization::default(),
            par,
            MemStack::new(&mut scratch.stack),
            Default::default(),
        )
        .map_err(|_| NotPositive)?;
        solve_lower_triangular_in_place(top.as_ref(), bottom.transpose_mut(), par);
        for &row in pattern {
            local[row] = usize::MAX;
        }
        Ok(())
    }

    fn par_for(&self, work: usize) -> Par {
        if work >= PARALLEL_WORK {
            self.par
        } else {
            Par::Seq
        }
    }
}

/// `heavy` in two groups of about equal weight (largest first, each to the
/// lighter group).
fn balance(heavy: &[usize], weight: &[f64]) -> (Vec<usize>, Vec<usize>) {
    let mut sorted = heavy.to_vec();
    sorted.sort_by(|&a, &b| weight[b].total_cmp(&weight[a]).then(a.cmp(&b)));
    let (mut left, mut right) = (Vec::new(), Vec::new());
    let (mut wl, mut wr) = (0.0, 0.0);
    for k in sorted {
        if wl <= wr {
            wl += weight[k];
            left.push(k);
        } else {
            wr += weight[k];
            right.push(k);
        }
    }
    (left, right)
}

#[cfg(test)]
pub(super) mod tests {
    use super::super::factor::Factor;
    use super::*;
    use faer::sparse::linalg::cholesky::{
        factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky,
    };
    use faer::sparse::linalg::SupernodalThreshold;
    use faer::sparse::{SparseColMat, Triplet};
    use faer::Side;

    /// The matrix of the lower triangle `t` and its supernodal analysis.
    pub(in crate::math::sparse) fn analysed(
        n: usize,
        t: &[Triplet<usize, usize, Real>],
    ) -> (SparseColMat<usize, Real>, SymbolicCholesky<usize>) {
        let a = SparseColMat::<usize, Real>::try_new_from_triplets(n, n, t).unwrap();
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let symbolic =
            factorize_symbolic_cholesky(a.symbolic(), Side::Lower, Default::default(), params)
                .unwrap();
        (a, symbolic)
    }

    /// Factors the lower triangle `t` (an SPD matrix of order `n`) with faer's
    /// own supernodal factorisation and with ours on one and on two threads.
    fn factors(n: usize, t: &[Triplet<usize, usize, Real>]) -> (Vec<Real>, Vec<Real>, Vec<Real>) {
        let (a, symbolic) = analysed(n, t);
        let mut reference = vec![0.0; symbolic.len_val()];
        let mut mem = MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<Real>(Par::Seq, Default::default()),
        );
        symbolic
            .factorize_numeric_llt(
                &mut reference,
                a.as_ref(),
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .unwrap();
        let mut f = Factor::new(symbolic, Par::rayon(8)).unwrap();
        let mut ours = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| f.factorize(a.as_ref())).unwrap();
            f.values.clone()
        };
        let (one, two) = (ours(1), ours(2));
        (reference, one, two)
    }

    fn assert_same_factor(reference: &[Real], one: &[Real], two: &[Real]) {
        // Bit for bit whatever the thread count.
        assert!(one.iter().zip(two).all(|(a, b)| a.to_bits() == b.to_bits()));
        let scale = reference.iter().fold(0.0 as Real, |m, v| m.max(v.abs()));
        let err = reference
            .iter()
            .zip(one)
            .fold(0.0 as Real, |m, (a, b)| m.max((a - b).abs()));
        assert!(err <= 1e-12 * scale, "error {err} of {scale}");
    }

    /// A 3D grid Laplacian plus a shift: an elimination tree with wide
    /// subtrees, so the two-thread run factors them side by side.
    #[test]
    fn grid_equals_faer_and_is_thread_independent() {
        let side = 11;
        let n = side * side * side;
        let at = |x: usize, y: usize, z: usize| (z * side + y) * side + x;
        let mut t = Vec::new();
        for z in 0..side {
            for y in 0..side {
                for x in 0..side {
                    let i = at(x, y, z);
                    t.push(Triplet::new(i, i, 6.0 + 1e-3 * (i % 5) as Real));
                    for j in [
                        (x + 1 < side).then(|| at(x + 1, y, z)),
                        (y + 1 < side).then(|| at(x, y + 1, z)),
                        (z + 1 < side).then(|| at(x, y, z + 1)),
                    ]
                    .into_iter()
                    .flatten()
                    {
                        t.push(Triplet::new(j, i, -1.0));
                    }
                }
            }
        }
        let (reference, one, two) = factors(n, &t);
        assert_same_factor(&reference, &one, &two);
    }

    /// A matrix that is not positive definite is refused, not factored.
    #[test]
    fn indefinite_is_refused() {
        let t = [
            Triplet::new(0, 0, 1.0),
            Triplet::new(1, 0, 2.0),
            Triplet::new(1, 1, 1.0),
        ];
        let (a, symbolic) = analysed(2, &t);
        let mut f = Factor::new(symbolic, Par::Seq).unwrap();
        assert!(f.factorize(a.as_ref()).is_err());
    }

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config::with_cases(48))]
        /// Random sparse SPD matrices (weighted graph Laplacians over a path
        /// and random edges, a few entries repeated, plus a positive diagonal): our factor equals
        /// faer's, and is the same on one thread and on two.
        #[test]
        fn random_spd_equals_faer(
            n in 2usize..160,
            edges in proptest::collection::vec((0usize..160, 0usize..160, 0.01f64..2.0), 0..600),
            shift in proptest::collection::vec(1e-6f64..1.0, 160),
        ) {
            let mut degree = vec![0.0; n];
            let mut t = Vec::new();
            // A path through all nodes, so the matrix is never diagonal (faer
            // analyses a diagonal matrix as simplicial, which the stiffness
            // matrix, dense within each body's block, never is).
            let path = (1..n).map(|i| (i - 1, i, 0.5));
            for (a, b, w) in path.chain(edges.iter().copied()) {
                let (a, b) = (a % n, b % n);
                if a != b {
                    t.push(Triplet::new(a.max(b), a.min(b), -w));
                    degree[a] += w;
                    degree[b] += w;
                }
            }
            for (i, d) in degree.iter().enumerate() {
                t.push(Triplet::new(i, i, d + shift[i]));
            }
            let (reference, one, two) = factors(n, &t);
            assert_same_factor(&reference, &one, &two);
        }
    }
}
