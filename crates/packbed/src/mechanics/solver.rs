//! The linear algebra of the bond network: the stiffness matrix assembled in
//! sparse form, its sparse Cholesky factorisation (faer), and the solves after
//! bonds break.
//!
//! A broken bond removes `W Wᵀ` from the matrix, with `W = Gᵀ C` of rank `D`
//! (`C`: the root of the bond's spring, `G`: the bodies' motion at the contact).
//! Instead of a new factorisation, the solver keeps the factor `L` of the last
//! matrix `A₀` it factored and the bonds removed since, and applies the
//! Sherman–Morrison–Woodbury inverse
//! `(A₀ − W Wᵀ)⁻¹ = A₀⁻¹ + Z S⁻¹ Zᵀ` with `Z = A₀⁻¹ W`, `S = I − Wᵀ Z`,
//! kept half-solved: with `A₀ = Pᵀ L Lᵀ P` and `Y = L⁻¹ P W` (sparse, see
//! `math::sparse::factor`), `S = I − Yᵀ Y` and
//! `A⁻¹ b = Pᵀ L⁻ᵀ (y + Y S⁻¹ Yᵀ y)` with `y = L⁻¹ P b`. A break costs a
//! sparse forward solve per column of `W` and a small dense factorisation; a
//! solve for loads seen before costs one backward half-solve.
//! Because the ground springs make `S` nearly singular when a body loses its
//! last support, that inverse is used as the preconditioner of a conjugate
//! gradient on the exact current matrix (applied bond by bond), which restores
//! full accuracy in one or two steps; when the removed rank grows past a
//! limit, or the iteration does not settle, the matrix is factored again with
//! the symbolic analysis of the first factorisation (the pattern never
//! changes: a broken bond keeps its entries, as zeros).

use super::network::BondGeometry;
use super::spring::{self, body_dofs};
use crate::error::{Error, Result};
use crate::math::sparse::factor::{Factor, SparseVec};
use crate::math::{Real, Vector};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Par, Side};

/// Ground spring stiffness relative to `k_n` (`docs/reference/fragmentation.md`, "Equilibrium").
pub const GROUND: Real = 1e-9;

/// Columns of `W` kept before the matrix is factored again (128 bonds in 3D,
/// 192 in 2D). A column is sparse (`Y = L⁻¹ P W`: the rows of its
/// elimination-tree path) and `S` is small, so carrying them is cheap; a
/// numeric factorisation is not (15 s for 2·10⁴ spheres). Measured on that 3D
/// bed, 100 breaks: 89 s with 96 columns (three factorisations), 49 s with 384
/// (none), the same bonds broken.
const MAX_RANK: usize = 384;

/// How many parts faer splits a large dense block into: fixed, not the
/// number of threads, because the split decides the order of its sums and
/// the results must not depend on the machine (rayon runs the parts on
/// however many threads there are).
const DENSE_DEGREE: usize = 8;

/// Relative residual at which the conjugate gradient stops.
const TOLERANCE: Real = 1e-10;

/// Conjugate-gradient steps before the solver gives up on the kept factor and
/// factors the current matrix.
const MAX_STEPS: usize = 25;

/// The spring constants of every bond.
#[derive(Clone, Copy, Debug)]
pub struct Springs {
    /// Normal stiffness.
    pub kn: Real,
    /// Tangential stiffness.
    pub kt: Real,
}

/// The stiffness matrix of a bond network and its solver.
pub struct Solver<'a, const D: usize> {
    bonds: &'a [BondGeometry<D>],
    springs: Springs,
    /// Ground stiffness of every unknown.
    ground: Vec<Real>,
    /// Bonds present in the current matrix.
    alive: Vec<bool>,
    pattern: SymbolicSparseColMat<usize>,
    /// Where each of [`values`]' values goes in `pattern`.
    slot: Vec<usize>,
    factor: Factor,
    /// `Y = L⁻¹ P W` of the bonds removed since the last factorisation.
    y: Vec<SparseVec>,
    /// Dense `S = I − Yᵀ Y` and its Cholesky factor (lower, row-major).
    s: Vec<Vec<Real>>,
    s_factor: Option<Vec<Vec<Real>>>,
    /// The last right-hand side and `L⁻¹ P` of it: loads change rarely.
    base: Option<(Vec<Real>, Vec<Real>)>,
    /// Zeroed scratch of the sparse forward solve.
    work: Vec<Real>,
    /// Numeric factorisations so far (the first included).
    pub factorisations: usize,
}

/// One column of `W`: a sparse vector over the unknowns.
#[derive(Clone, Debug)]
struct WColumn {
    idx: Vec<usize>,
    val: Vec<Real>,
}

/// Bytes the stiffness solve holds at its peak: the factor's `factor_len`
/// values, the matrix of `matrix_len` lower entries assembled and permuted
/// (an index and a value each, twice), and 1 KB per unknown for the rest
/// (the order, the supernodes' scratch, the broken bonds' columns). Fitted to
/// the peak resident memory of `packbed fragment --breaks 1` (`/usr/bin/time
/// -v`) on 3D beds of 5000 and 20000 spheres: 148 and 545 MB, estimated 124
/// and 514 MB (the bed and its analysis hold the rest).
fn solve_bytes(factor_len: usize, matrix_len: usize, n: usize) -> f64 {
    8.0 * factor_len as f64 + 32.0 * matrix_len as f64 + 1024.0 * n as f64
}

/// Address space the dense kernels reserve: faer's x86 matrix product keeps
/// two buffers of the L3 cache's size per thread (600 MiB a thread on a
/// machine reporting 300 MiB of L3), allocated on first use and mostly never
/// touched. Under `ulimit -v` that reservation alone aborted a 300-sphere
/// bed's factorisation at 1 GiB. The L3 size is read from sysfs; 0 where
/// it is not known.
fn dense_reserve() -> f64 {
    let l3 = std::fs::read_to_string("/sys/devices/system/cpu/cpu0/cache/index3/size")
        .ok()
        .and_then(|s| cache_bytes(s.trim()))
        .unwrap_or(0);
    2.0 * l3 as f64 * rayon::current_num_threads() as f64
}

/// A sysfs cache size (`307200K`, `32M`, `1024`) in bytes.
fn cache_bytes(size: &str) -> Option<u64> {
    let (digits, unit) = match size.strip_suffix('K') {
        Some(d) => (d, 1 << 10),
        None => match size.strip_suffix('M') {
            Some(d) => (d, 1 << 20),
            None => (size, 1),
        },
    };
    digits.parse::<u64>().ok().map(|n| n * unit)
}

fn internal(what: &str) -> Error {
    Error::Impossible(format!("the stiffness matrix could not be {what}"))
}

impl<'a, const D: usize> Solver<'a, D> {
    /// Assembles the matrix of `bonds` over `bodies` bodies with ground
    /// springs (`reach`: each body's `ρ_b`) and factors it.
    pub fn new(
        bonds: &'a [BondGeometry<D>],
        reference: &[Vector<D>],
        reach: &[Real],
        springs: Springs,
    ) -> Result<Self> {
        let m = body_dofs(D);
        let n = reach.len() * m;
        let mut ground = vec![0.0; n];
        for (b, rho) in reach.iter().enumerate() {
            for c in 0..m {
                let lever = if c < D { 1.0 } else { rho * rho };
                ground[b * m + c] = GROUND * springs.kn * lever;
            }
        }
        // Nested dissection of the bodies (ordering.rs), not the minimum
        // degree order of the whole matrix: measured on periodic beds of equal
        // spheres it gives a smaller factor in 2D (31 against 35 million
        // entries at 10⁵ discs) and a faster one in 3D. The order (METIS in
        // 3D, a few tenths of a second) and the pattern do not need each
        // other, so one is built beside the other.
        let ((pattern, slot), (fwd, inv)) = rayon::join(
            || layout::<D>(bonds, reach.len()),
            || dof_order::<D>(bonds, reference),
        );
        let alive = vec![true; bonds.len()];
        let ordering = SymmetricOrdering::Custom(PermRef::new_checked(&fwd, &inv, n));
        // Supernodal always: the sparse forward solve walks its supernodes.
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_cholesky(pattern.as_ref(), Side::Lower, ordering, params)
            .map_err(|_| internal("ordered"))?;
        // The symbolic analysis gives the factor's exact size: refuse here,
        // before the numeric factorisation, what would abort the process.
        let what = format!(
            "the stiffness solve of {} bodies ({n} unknowns, {:.3e} factor entries)",
            reach.len(),
            symbolic.len_val() as f64
        );
        let bytes = solve_bytes(symbolic.len_val(), pattern.row_idx().len(), n);
        crate::input::check_memory(bytes, &what)?;
        crate::input::check_address_space(bytes + dense_reserve(), &what)?;
        let par = Par::rayon(DENSE_DEGREE);
        let factor = Factor::new(symbolic, par).ok_or_else(|| internal("ordered (supernodes)"))?;
        let mut solver = Solver {
            bonds,
            springs,
            ground,
            alive,
            pattern,
            slot,
            factor,
            y: Vec::new(),
            s: Vec::new(),
            s_factor: None,
            base: None,
            work: vec![0.0; n],
            factorisations: 0,
        };
        solver.refactor()?;
        Ok(solver)
    }

    /// Number of unknowns.
    pub fn len(&self) -> usize {
        self.ground.len()
    }

    /// True for a network without bodies.
    pub fn is_empty(&self) -> bool {
        self.ground.is_empty()
    }

    /// Ground stiffness of each unknown.
    pub(crate) fn ground(&self) -> &[Real] {
        &self.ground
    }

    /// Factors the current matrix, forgetting the removed bonds' columns.
    fn refactor(&mut self) -> Result<()> {
        let values = values::<D>(self.bonds, &self.alive, &self.ground, self.springs);
        let matrix = assemble(&self.pattern, &self.slot, &values);
        self.factor
            .factorize(matrix.as_ref())
            .map_err(|_| internal("factored (not positive definite)"))?;
        self.y.clear();
        self.s.clear();
        self.s_factor = None;
        self.base = None;
        self.factorisations += 1;
        Ok(())
    }

    /// Removes bond `k` from the matrix.
    pub(crate) fn remove(&mut self, k: usize) -> Result<()> {
        if !self.alive[k] {
            return Ok(());
        }
        self.alive[k] = false;
        if self.y.len() + D > MAX_RANK {
            return self.refactor();
        }
        for col in w_columns::<D>(&self.bonds[k], self.springs) {
            let y = self
                .factor
                .sparse_forward(&col.idx, &col.val, &mut self.work);
            self.y.push(y);
        }
        // S = I − Yᵀ Y, grown by the new rows and columns.
        let r = self.y.len();
        for row in self.s.iter_mut() {
            row.resize(r, 0.0);
        }
        self.s.resize(r, vec![0.0; r]);
        for p in 0..r {
            for q in r - D..r {
                let v = f64::from(u8::from(p == q)) - self.y[p].dot(&self.y[q]);
                self.s[p][q] = v;
                self.s[q][p] = v;
            }
        }
        self.s_factor = dense_cholesky(&self.s);
        if self.s_factor.is_none() {
            return self.refactor();
        }
        Ok(())
    }

    /// The preconditioner: the Woodbury inverse of the current matrix.
    fn precondition(&self, b: &[Real]) -> Vec<Real> {
        self.finish(self.factor.forward(b))
    }

    /// `Pᵀ L⁻ᵀ (y + Y S⁻¹ Yᵀ y)` for `y = L⁻¹ P b`: the current matrix's
    /// inverse applied to `b`.
    fn finish(&self, mut y: Vec<Real>) -> Vec<Real> {
        if let Some(l) = &self.s_factor {
            let c: Vec<Real> = self.y.iter().map(|w| w.dot_dense(&y)).collect();
            let c = dense_solve(l, c);
            for (w, ck) in self.y.iter().zip(c) {
                for (&i, v) in w.idx.iter().zip(&w.val) {
                    y[i] += ck * v;
                }
            }
        }
        self.factor.backward(y)
    }

    /// `A x` for the current matrix, bond by bond (independent of the
    /// assembled one, so that the residual checks the factor).
    pub fn apply(&self, x: &[Real]) -> Vec<Real> {
        let m = body_dofs(D);
        let mut y: Vec<Real> = x.iter().zip(&self.ground).map(|(a, g)| a * g).collect();
        for (g, _) in self.bonds.iter().zip(&self.alive).filter(|(_, a)| **a) {
            let k = spring::stiffness::<D>(&g.normal, self.springs.kn, self.springs.kt);
            let i = g.i as usize * m;
            let uj = g.j.map(|j| &x[j as usize * m..j as usize * m + m]);
            let f = spring::bond_force::<D>(g, &k, &x[i..i + m], uj);
            let gi = spring::generalized::<D>(&g.arm_i, &f);
            for c in 0..m {
                y[i + c] -= gi[c];
            }
            if let Some(j) = g.j {
                let j = j as usize * m;
                let gj = spring::generalized::<D>(&g.arm_j, &f);
                for c in 0..m {
                    y[j + c] += gj[c];
                }
            }
        }
        y
    }

    /// Solves the current matrix for `b`: the kept factor with the removed
    /// bonds' correction, refined by conjugate gradients on the exact matrix.
    pub(crate) fn solve(&mut self, b: &[Real]) -> Result<Vec<Real>> {
        if self
            .base
            .as_ref()
            .is_none_or(|(old, _)| old.as_slice() != b)
        {
            self.base = Some((b.to_vec(), self.factor.forward(b)));
        }
        if let Some(x) = self.iterate(b) {
            return Ok(x);
        }
        self.refactor()?;
        Ok(self.iterate(b).unwrap_or_else(|| self.precondition(b)))
    }

    /// Preconditioned conjugate gradients from the preconditioned guess;
    /// `None` when they do not reach the tolerance in [`MAX_STEPS`].
    fn iterate(&self, b: &[Real]) -> Option<Vec<Real>> {
        let scale = dot(b, b).sqrt();
        if scale == 0.0 {
            return Some(vec![0.0; b.len()]);
        }
        let mut x = match &self.base {
            Some((old, y0)) if old.as_slice() == b => self.finish(y0.clone()),
            _ => self.precondition(b),
        };
        let ax = self.apply(&x);
        let mut r: Vec<Real> = b.iter().zip(&ax).map(|(b, a)| b - a).collect();
        let mut best = (dot(&r, &r).sqrt(), x.clone());
        if best.0 <= TOLERANCE * scale {
            return Some(x);
        }
        let mut z = self.precondition(&r);
        let mut p = z.clone();
        let mut rz = dot(&r, &z);
        for _ in 0..MAX_STEPS {
            let ap = self.apply(&p);
            let pap = dot(&p, &ap);
            if !(pap > 0.0 && rz.is_finite()) {
                break;
            }
            let alpha = rz / pap;
            for i in 0..x.len() {
                x[i] += alpha * p[i];
                r[i] -= alpha * ap[i];
            }
            let norm = dot(&r, &r).sqrt();
            if norm < best.0 {
                best = (norm, x.clone());
            }
            if norm <= TOLERANCE * scale {
                return Some(x);
            }
            z = self.precondition(&r);
            let rz_new = dot(&r, &z);
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..p.len() {
                p[i] = z[i] + beta * p[i];
            }
        }
        // Round-off bounds the residual near ε·cond; accept a solution whose
        // residual is far below what the measures resolve (1e-6 of the load).
        (best.0 <= 1e-9 * scale).then_some(best.1)
    }
}

fn dot(a: &[Real], b: &[Real]) -> Real {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The `D` columns of `W = Gᵀ C` of a bond.
fn w_columns<const D: usize>(g: &BondGeometry<D>, springs: Springs) -> Vec<WColumn> {
    let m = body_dofs(D);
    let c = spring::stiffness_root::<D>(&g.normal, springs.kn, springs.kt);
    (0..D)
        .map(|col| {
            let mut cv = Vector::<D>::zero();
            for r in 0..D {
                cv.0[r] = c[r][col];
            }
            let mut idx = Vec::with_capacity(2 * m);
            let mut val = Vec::with_capacity(2 * m);
            let gi = spring::generalized::<D>(&g.arm_i, &cv);
            for k in 0..m {
                idx.push(g.i as usize * m + k);
                val.push(-gi[k]);
            }
            if let Some(j) = g.j {
                let gj = spring::generalized::<D>(&g.arm_j, &cv);
                for k in 0..m {
                    idx.push(j as usize * m + k);
                    val.push(gj[k]);
                }
            }
            WColumn { idx, val }
        })
        .collect()
}

/// Lower-triangle positions of the matrix, in the order [`values`] fills them:
/// each body's diagonal block, then each bond's blocks.
fn entries<const D: usize>(bonds: &[BondGeometry<D>], bodies: usize) -> Vec<Pair<usize, usize>> {
    let m = body_dofs(D);
    let mut out = Vec::with_capacity(bodies * m * (m + 1) / 2 + bonds.len() * 3 * m * m);
    for b in 0..bodies {
        lower_block(&mut out, b, b, m, |_| {});
    }
    for g in bonds {
        let i = g.i as usize;
        lower_block(&mut out, i, i, m, |_| {});
        if let Some(j) = g.j.map(|j| j as usize) {
            lower_block(&mut out, j, j, m, |_| {});
            lower_block(&mut out, i, j, m, |_| {});
        }
    }
    out
}

/// The matrix's lower triangle as a pattern, and the slot in it of each
/// entry [`entries`] lists (and [`values`] fills) in turn. Built block by
/// block from each body's bonded bodies, where faer's sort of the entries
/// (ten million for a 3D bed of 2·10⁴ spheres) took half a second.
fn layout<const D: usize>(
    bonds: &[BondGeometry<D>],
    bodies: usize,
) -> (SymbolicSparseColMat<usize>, Vec<usize>) {
    let m = body_dofs(D);
    // Column body `b` holds `b` itself, then the higher bodies bonded to it.
    let mut lists: Vec<Vec<usize>> = (0..bodies).map(|b| vec![b]).collect();
    for g in bonds {
        if let Some(j) = g.j {
            let (i, j) = (g.i as usize, j as usize);
            if i != j {
                lists[i.min(j)].push(i.max(j));
            }
        }
    }
    for l in &mut lists {
        l[1..].sort_unstable();
        l.dedup();
    }
    let mut col_ptr = Vec::with_capacity(bodies * m + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::new();
    for (bj, l) in lists.iter().enumerate() {
        for c in 0..m {
            for &bi in l {
                let first = if bi == bj { c } else { 0 };
                row_idx.extend((first..m).map(|a| bi * m + a));
            }
            col_ptr.push(row_idx.len());
        }
    }
    let slot = entries::<D>(bonds, bodies)
        .iter()
        .map(|&Pair { row, col }| {
            let (bi, a, bj, c) = (row / m, row % m, col / m, col % m);
            let offset = if bi == bj {
                a - c
            } else {
                let p = lists[bj][1..]
                    .binary_search(&bi)
                    .expect("every bonded pair is listed");
                (m - c) + p * m + a
            };
            col_ptr[col] + offset
        })
        .collect();
    let n = bodies * m;
    (
        SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx),
        slot,
    )
}

/// The matrix of `values` laid out by [`layout`] (repeated entries summed in
/// their order).
fn assemble(
    pattern: &SymbolicSparseColMat<usize>,
    slot: &[usize],
    values: &[Real],
) -> SparseColMat<usize, Real> {
    let mut v = vec![0.0; pattern.row_idx().len()];
    for (&k, x) in slot.iter().zip(values) {
        v[k] += x;
    }
    SparseColMat::new(pattern.clone(), v)
}

/// Visits the lower-triangle entries of block `(bi, bj)` (or of its
/// transpose when `bi < bj`) in a fixed order, pushing their positions.
fn lower_block(
    out: &mut Vec<Pair<usize, usize>>,
    bi: usize,
    bj: usize,
    m: usize,
    mut each: impl FnMut((usize, usize)),
) {
    for a in 0..m {
        for c in 0..m {
            if bi == bj && c > a {
                continue;
            }
            // Entry (a, c) of block (bi, bj) sits at row bi·m + a, column bj·m + c.
            let (row, col) = (bi * m + a, bj * m + c);
            let (row, col) = if row >= col { (row, col) } else { (col, row) };
            out.push(Pair { row, col });
            each((a, c));
        }
    }
}

/// Values of the matrix in the order of [`entries`]; a dead bond adds zeros.
fn values<const D: usize>(
    bonds: &[BondGeometry<D>],
    alive: &[bool],
    ground: &[Real],
    springs: Springs,
) -> Vec<Real> {
    let m = body_dofs(D);
    let bodies = ground.len() / m;
    let mut out = Vec::with_capacity(bodies * m * (m + 1) / 2 + bonds.len() * 3 * m * m);
    for b in 0..bodies {
        for a in 0..m {
            for c in 0..=a {
                out.push(if a == c { ground[b * m + a] } else { 0.0 });
            }
        }
    }
    let mut sink = Vec::new();
    for (g, &on) in bonds.iter().zip(alive) {
        let k = spring::stiffness::<D>(&g.normal, springs.kn, springs.kt);
        let blocks = spring::blocks::<D>(g, &k);
        let scale = if on { 1.0 } else { 0.0 };
        let i = g.i as usize;
        sink.clear();
        lower_block(&mut sink, i, i, m, |(a, c)| {
            out.push(scale * blocks[0][a][c])
        });
        if let Some(j) = g.j.map(|j| j as usize) {
            lower_block(&mut sink, j, j, m, |(a, c)| {
                out.push(scale * blocks[2][a][c])
            });
            lower_block(&mut sink, i, j, m, |(a, c)| {
                out.push(scale * blocks[1][a][c])
            });
        }
    }
    out
}

/// Cholesky factor (lower, rows) of a small dense symmetric matrix; `None`
/// when it is not numerically positive definite.
fn dense_cholesky(s: &[Vec<Real>]) -> Option<Vec<Vec<Real>>> {
    let r = s.len();
    let mut l = vec![vec![0.0; r]; r];
    for i in 0..r {
        for j in 0..=i {
            let mut v = s[i][j];
            for k in 0..j {
                v -= l[i][k] * l[j][k];
            }
            if i == j {
                if v.is_nan() || v <= 0.0 {
                    return None;
                }
                l[i][i] = v.sqrt();
            } else {
                l[i][j] = v / l[j][j];
            }
        }
    }
    Some(l)
}

/// Solves `L Lᵀ y = b`.
fn dense_solve(l: &[Vec<Real>], mut b: Vec<Real>) -> Vec<Real> {
    let r = l.len();
    for i in 0..r {
        for k in 0..i {
            b[i] -= l[i][k] * b[k];
        }
        b[i] /= l[i][i];
    }
    for i in (0..r).rev() {
        for k in i + 1..r {
            b[i] -= l[k][i] * b[k];
        }
        b[i] /= l[i][i];
    }
    b
}

/// The elimination order of the unknowns (`fwd[new] = old`, `inv[old] = new`):
/// the bodies by nested dissection, each body's unknowns together.
fn dof_order<const D: usize>(
    bonds: &[BondGeometry<D>],
    reference: &[Vector<D>],
) -> (Vec<usize>, Vec<usize>) {
    let nb = reference.len();
    let mut degree = vec![0usize; nb + 1];
    for g in bonds {
        if let Some(j) = g.j {
            degree[g.i as usize + 1] += 1;
            degree[j as usize + 1] += 1;
        }
    }
    for b in 0..nb {
        degree[b + 1] += degree[b];
    }
    let offsets = degree;
    let mut fill = offsets.clone();
    let mut neighbours = vec![0u32; offsets[nb]];
    for g in bonds {
        if let Some(j) = g.j {
            neighbours[fill[g.i as usize]] = j;
            fill[g.i as usize] += 1;
            neighbours[fill[j as usize]] = g.i;
            fill[j as usize] += 1;
        }
    }
    let order = crate::math::sparse::ordering::elimination_order(reference, &offsets, &neighbours);
    let m = body_dofs(D);
    let mut fwd = Vec::with_capacity(nb * m);
    for &b in &order {
        fwd.extend((0..m).map(|c| b as usize * m + c));
    }
    let mut inv = vec![0; fwd.len()];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    (fwd, inv)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sysfs_cache_sizes_are_read_in_bytes() {
        assert_eq!(cache_bytes("307200K"), Some(300 << 20));
        assert_eq!(cache_bytes("32M"), Some(32 << 20));
        assert_eq!(cache_bytes("1024"), Some(1024));
        assert_eq!(cache_bytes("big"), None);
    }
}
