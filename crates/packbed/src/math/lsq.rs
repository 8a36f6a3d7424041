//! Least squares for force balances: one Lawson–Hanson active-set core for the
//! non-negative problems (is "up" a non-negative combination of the contact
//! normals?), and the small dense solvers its passive fits use.
//!
//! Three solvers share the core and differ in their rules ([`Rules`]) and in how
//! they fit the passive columns: [`nnls`] (a sphere's `D` normals, closed-form
//! normal equations), [`nnls_gen`] (a chain's generalised normals, normal
//! equations by elimination) and [`nnls_qr`] (Householder QR, for the chain's
//! rare path and the independent rest test, which must measure a balance the
//! same way). Their tolerances differ on purpose and are kept as they were: each
//! one sets where its engine's beds come to rest.

use super::{Gen, Real, Vector};

/// Columns the working arrays of [`nnls_gen`] hold at most.
pub const MAX_GEN_COLUMNS: usize = 48;

/// What a passive set with numerically dependent columns does.
#[derive(Clone, Copy, PartialEq)]
enum Dependent {
    /// Stop: the coefficients so far are the answer.
    Stop,
    /// Leave the new column out for good; a column left out in the middle of a
    /// step keeps relaxing towards zero with the others.
    Ban,
    /// Leave the new column out until a fit succeeds; a column left out in the
    /// middle of a step keeps its coefficient.
    BanUntilFit,
}

/// The rules of one active-set solver.
struct Rules {
    /// Gradient a column must exceed to enter the passive set.
    enter: Real,
    /// Coefficient at or below which a passive column leaves.
    leave: Real,
    /// Rounds of each loop beyond three per column.
    extra_rounds: usize,
    /// What a dependent passive set does.
    dependent: Dependent,
}

/// The rest test of a sphere.
const SPHERE: Rules = Rules {
    enter: 1e-13,
    leave: 1e-13,
    extra_rounds: 3,
    dependent: Dependent::Stop,
};
/// The fast path of a chain's settling.
const GEN: Rules = Rules {
    enter: 1e-14,
    leave: 1e-15,
    extra_rounds: 3,
    dependent: Dependent::Ban,
};
/// The QR balance of the chain's rare path and of the independent rest test.
const QR: Rules = Rules {
    enter: 1e-14,
    leave: 1e-15,
    extra_rounds: 10,
    dependent: Dependent::BanUntilFit,
};

/// The columns of one non-negative problem, as the active-set core sees them.
trait Columns {
    /// The residual vector `b − Σ x_i a_i`.
    type Residual;
    /// Number of columns.
    fn len(&self) -> usize;
    /// The residual at coefficients `x`.
    fn residual(&self, x: &[Real]) -> Self::Residual;
    /// The objective's descent rate along column `i`: `a_i · r`.
    fn gradient(&self, i: usize, r: &Self::Residual) -> Real;
    /// Unconstrained least squares over the passive columns, written into the
    /// zeroed `z` at their indices; false when they are numerically dependent.
    fn fit(&self, passive: &[bool], z: &mut [Real]) -> bool;
}

/// Lawson–Hanson active set: minimises `|b − Σ x_i a_i|` over `x ≥ 0`, starting
/// from `x = 0` (the working slices hold at least one entry per column, `passive`
/// and `banned` all false). Returns the residual.
fn active_set<C: Columns>(
    cols: &C,
    rules: &Rules,
    x: &mut [Real],
    passive: &mut [bool],
    banned: &mut [bool],
    z: &mut [Real],
) -> C::Residual {
    let m = cols.len();
    // The QR rules leave a column banned in the middle of a step where it was,
    // as the independent rest test always has.
    let every = rules.dependent != Dependent::BanUntilFit;
    let rounds = 3 * m + rules.extra_rounds;
    for _ in 0..rounds {
        let r = cols.residual(x);
        let mut best = None;
        let mut best_w = rules.enter;
        for i in 0..m {
            if !passive[i] && !banned[i] {
                let w = cols.gradient(i, &r);
                if w > best_w {
                    best_w = w;
                    best = Some(i);
                }
            }
        }
        let Some(j) = best else { break };
        passive[j] = true;
        // Solve on the passive set and step back towards feasibility while a
        // coefficient would turn negative.
        for _ in 0..rounds {
            z[..m].fill(0.0);
            if !cols.fit(&passive[..m], &mut z[..m]) {
                if rules.dependent == Dependent::Stop {
                    return cols.residual(x);
                }
                passive[j] = false;
                banned[j] = true;
                break;
            }
            if (0..m).all(|i| !passive[i] || z[i] > 0.0) {
                for i in (0..m).filter(|&i| every || passive[i]) {
                    x[i] = z[i];
                }
                if rules.dependent == Dependent::BanUntilFit {
                    banned[..m].fill(false);
                }
                break;
            }
            let mut alpha: Real = 1.0;
            for i in 0..m {
                if passive[i] && z[i] <= 0.0 {
                    let d = x[i] - z[i];
                    if d > 0.0 {
                        alpha = alpha.min(x[i] / d);
                    }
                }
            }
            for i in 0..m {
                if !every && !passive[i] {
                    continue;
                }
                x[i] += alpha * (z[i] - x[i]);
                if passive[i] && x[i] <= rules.leave {
                    x[i] = 0.0;
                    passive[i] = false;
                }
            }
        }
    }
    cols.residual(x)
}

/// Columns that are vectors, with their target.
struct VectorColumns<'a, const D: usize> {
    a: &'a [Vector<D>],
    target: Vector<D>,
    /// Pivot tolerance of the elimination, relative to the Gram matrix's largest
    /// diagonal entry; `None` for the closed-form fit of at most three columns.
    pivot: Option<Real>,
}

impl<const D: usize> Columns for VectorColumns<'_, D> {
    type Residual = Vector<D>;

    fn len(&self) -> usize {
        self.a.len()
    }

    fn residual(&self, x: &[Real]) -> Vector<D> {
        let mut r = self.target;
        for (a, &xi) in self.a.iter().zip(x) {
            r -= *a * xi;
        }
        r
    }

    fn gradient(&self, i: usize, r: &Vector<D>) -> Real {
        self.a[i].dot(r)
    }

    fn fit(&self, passive: &[bool], z: &mut [Real]) -> bool {
        let Some(pivot) = self.pivot else {
            return least_squares_subset(self.a, self.target, passive, z);
        };
        let mut idx = [0usize; 6];
        let mut k = 0;
        for (i, _) in passive.iter().enumerate().filter(|(_, &p)| p) {
            if k == 6 {
                return false;
            }
            idx[k] = i;
            k += 1;
        }
        let mut g = [[0.0; 6]; 6];
        let mut b = [0.0; 6];
        let mut scale: Real = 0.0;
        for r in 0..k {
            for c in 0..k {
                g[r][c] = self.a[idx[r]].dot(&self.a[idx[c]]);
            }
            b[r] = self.a[idx[r]].dot(&self.target);
            scale = scale.max(g[r][r]);
        }
        let Some(sol) = solve_pivoted(&mut g, &mut b, k, pivot * scale) else {
            return false;
        };
        for (t, &i) in idx[..k].iter().enumerate() {
            z[i] = sol[t];
        }
        true
    }
}

/// Non-negative least squares for at most a handful of vectors:
/// minimise `|target − Σ λ_i a_i|` over `λ_i ≥ 0` (Lawson–Hanson active set).
///
/// Returns the coefficients (written into `lambda`, same length as `a`) and the
/// residual vector `target − Σ λ_i a_i`. Used for the rest test: a particle rests
/// when "up" is a non-negative combination of its contact normals.
pub fn nnls<const D: usize>(a: &[Vector<D>], target: Vector<D>, lambda: &mut [Real]) -> Vector<D> {
    let m = a.len();
    debug_assert!(lambda.len() >= m);
    const MAX: usize = 16;
    assert!(m <= MAX, "nnls: at most {MAX} vectors");
    for l in lambda.iter_mut().take(m) {
        *l = 0.0;
    }
    // Fast paths for the common cases of the rest test: one contact, or all
    // contacts carrying a compressive force.
    if m == 1 {
        let l = (a[0].dot(&target) / a[0].norm2()).max(0.0);
        lambda[0] = if l.is_finite() { l } else { 0.0 };
        return target - a[0] * lambda[0];
    }
    if m <= D && m <= 3 {
        let mut z = [0.0; MAX];
        let all = [true; MAX];
        if least_squares_subset(a, target, &all[..m], &mut z) && z[..m].iter().all(|&v| v > 0.0) {
            lambda[..m].copy_from_slice(&z[..m]);
            let mut r = target;
            for i in 0..m {
                r -= a[i] * z[i];
            }
            return r;
        }
    }
    let cols = VectorColumns {
        a,
        target,
        pivot: None,
    };
    let (mut passive, mut banned, mut z) = ([false; MAX], [false; MAX], [0.0; MAX]);
    active_set(&cols, &SPHERE, lambda, &mut passive, &mut banned, &mut z)
}

/// Non-negative least squares in the generalised space of a rigid body:
/// minimises `|target − Σ λ_i a_i|` over `λ ≥ 0` (any number of passive columns
/// up to 6, [`nnls`] stops at three; at most [`MAX_GEN_COLUMNS`] columns).
/// Columns that are numerically dependent on the passive set cannot improve the
/// fit and are left out. Returns the residual.
pub fn nnls_gen(a: &[Gen], target: Gen, lambda: &mut [Real]) -> Gen {
    let m = a.len();
    lambda[..m].iter_mut().for_each(|l| *l = 0.0);
    let cols = VectorColumns {
        a,
        target,
        pivot: Some(1e-15),
    };
    // Small working arrays for the common case (clearing them is a
    // noticeable part of a 5-bead chain's cost).
    if m <= 16 {
        let (mut passive, mut banned, mut z) = ([false; 16], [false; 16], [0.0; 16]);
        active_set(&cols, &GEN, lambda, &mut passive, &mut banned, &mut z)
    } else {
        const N: usize = MAX_GEN_COLUMNS;
        let (mut passive, mut banned, mut z) = ([false; N], [false; N], [0.0; N]);
        active_set(&cols, &GEN, lambda, &mut passive, &mut banned, &mut z)
    }
}

/// Columns of `q ≤ 6` coordinates, fitted by Householder QR.
struct QrColumns<'a> {
    a: &'a [[Real; 6]],
    q: usize,
    b: &'a [Real; 6],
}

impl Columns for QrColumns<'_> {
    type Residual = [Real; 6];

    fn len(&self) -> usize {
        self.a.len()
    }

    fn residual(&self, x: &[Real]) -> [Real; 6] {
        let mut r = *self.b;
        for (col, &xk) in self.a.iter().zip(x) {
            for d in 0..self.q {
                r[d] -= xk * col[d];
            }
        }
        r
    }

    fn gradient(&self, i: usize, r: &[Real; 6]) -> Real {
        (0..self.q).map(|d| self.a[i][d] * r[d]).sum::<Real>()
    }

    fn fit(&self, passive: &[bool], z: &mut [Real]) -> bool {
        // More than six passive columns are more than `q`: no fit.
        let mut sub = [[0.0; 6]; 6];
        let mut idx = [0usize; 6];
        let mut k = 0;
        for (i, _) in passive.iter().enumerate().filter(|(_, &p)| p) {
            if k == 6 {
                return false;
            }
            sub[k] = self.a[i];
            idx[k] = i;
            k += 1;
        }
        let Some(sol) = least_squares_qr(&sub[..k], self.q, self.b) else {
            return false;
        };
        for (t, &i) in idx[..k].iter().enumerate() {
            z[i] = sol[t];
        }
        true
    }
}

/// Non-negative least squares `b ≈ Σ x_k a_k`, `x ≥ 0`, in the first `q ≤ 6`
/// coordinates (Lawson–Hanson, each passive fit by Householder QR; a column
/// numerically dependent on the passive ones is banned until the passive set
/// changes). Any number of columns. Returns the residual `b − Σ x_k a_k` and
/// `x`. It allocates: for the chain settling's rare path and the independent
/// rest test (`analysis::validate`), which must measure a balance the same way.
#[cold]
#[inline(never)]
pub fn nnls_qr(a: &[[Real; 6]], q: usize, b: &[Real; 6]) -> ([Real; 6], Vec<Real>) {
    let m = a.len();
    let mut x = vec![0.0; m];
    let (mut passive, mut banned, mut z) = (vec![false; m], vec![false; m], vec![0.0; m]);
    let cols = QrColumns { a, q, b };
    let r = active_set(&cols, &QR, &mut x, &mut passive, &mut banned, &mut z);
    (r, x)
}

/// Least squares `target ≈ Σ z_i a_i` over the vectors marked in `subset`
/// (normal equations, solved in closed form for up to three unknowns).
/// Returns false when the chosen vectors are (nearly) linearly dependent.
fn least_squares_subset<const D: usize>(
    a: &[Vector<D>],
    target: Vector<D>,
    subset: &[bool],
    z: &mut [Real],
) -> bool {
    let mut idx = [0usize; 3];
    let mut k = 0;
    for i in 0..a.len() {
        if subset[i] {
            if k == D || k == 3 {
                return false;
            }
            idx[k] = i;
            k += 1;
        }
    }
    let mut g = [[0.0; 3]; 3];
    let mut b = [0.0; 3];
    for r in 0..k {
        for c in r..k {
            g[r][c] = a[idx[r]].dot(&a[idx[c]]);
            g[c][r] = g[r][c];
        }
        b[r] = a[idx[r]].dot(&target);
    }
    // Scale of the Gram matrix, to judge a determinant as zero.
    let scale = (0..k).map(|r| g[r][r]).fold(0.0, Real::max);
    let sol = match k {
        0 => return true,
        1 => {
            if g[0][0] <= 0.0 {
                return false;
            }
            [b[0] / g[0][0], 0.0, 0.0]
        }
        2 => {
            let det = g[0][0] * g[1][1] - g[0][1] * g[0][1];
            if det.abs() <= 1e-14 * scale * scale {
                return false;
            }
            [
                (b[0] * g[1][1] - b[1] * g[0][1]) / det,
                (g[0][0] * b[1] - g[0][1] * b[0]) / det,
                0.0,
            ]
        }
        _ => {
            // Cramer's rule with cofactors of the symmetric 3 × 3 Gram matrix.
            let c00 = g[1][1] * g[2][2] - g[1][2] * g[1][2];
            let c01 = g[1][2] * g[0][2] - g[0][1] * g[2][2];
            let c02 = g[0][1] * g[1][2] - g[1][1] * g[0][2];
            let c11 = g[0][0] * g[2][2] - g[0][2] * g[0][2];
            let c12 = g[0][1] * g[0][2] - g[0][0] * g[1][2];
            let c22 = g[0][0] * g[1][1] - g[0][1] * g[0][1];
            let det = g[0][0] * c00 + g[0][1] * c01 + g[0][2] * c02;
            if det.abs() <= 1e-14 * scale * scale * scale {
                return false;
            }
            [
                (c00 * b[0] + c01 * b[1] + c02 * b[2]) / det,
                (c01 * b[0] + c11 * b[1] + c12 * b[2]) / det,
                (c02 * b[0] + c12 * b[1] + c22 * b[2]) / det,
            ]
        }
    };
    for r in 0..k {
        z[idx[r]] = sol[r];
    }
    true
}

/// Least squares `b ≈ Σ z_c cols[c]` in the first `q ≤ 6` coordinates, by
/// Householder QR (the normal equations would square the condition number,
/// which nearly parallel contact normals make large); `None` when the columns
/// are numerically dependent or more than `q`.
/// Entries `p..6` of the result are 0. No allocation: it runs inside the chain
/// settling's force balance.
pub fn least_squares_qr(cols: &[[Real; 6]], q: usize, b: &[Real; 6]) -> Option<[Real; 6]> {
    let p = cols.len();
    if p > q || q > 6 {
        return None;
    }
    let mut m = [[0.0; 6]; 6];
    m[..p].copy_from_slice(cols);
    let mut y = *b;
    let scale = m
        .iter()
        .take(p)
        .map(|c| (0..q).map(|d| c[d] * c[d]).sum::<Real>().sqrt())
        .fold(0.0, Real::max);
    for c in 0..p {
        let norm = (c..q).map(|d| m[c][d] * m[c][d]).sum::<Real>().sqrt();
        if norm.is_nan() || norm <= 1e-12 * scale {
            return None;
        }
        // Reflector v = x − α e_c, α of the opposite sign to x_c.
        let alpha = if m[c][c] > 0.0 { -norm } else { norm };
        let mut v = [0.0; 6];
        v[c..q].copy_from_slice(&m[c][c..q]);
        v[c] -= alpha;
        let vv: Real = (c..q).map(|d| v[d] * v[d]).sum();
        if vv > 0.0 {
            for col in m[..p].iter_mut().skip(c) {
                let f = 2.0 * (c..q).map(|d| v[d] * col[d]).sum::<Real>() / vv;
                for d in c..q {
                    col[d] -= f * v[d];
                }
            }
            let f = 2.0 * (c..q).map(|d| v[d] * y[d]).sum::<Real>() / vv;
            for d in c..q {
                y[d] -= f * v[d];
            }
        }
    }
    // Column `c` of R is stored as `m[c]`.
    back_substitute(p, &y, |r, c| m[c][r])
}

/// Solves the `m × m` system `a y = b` (Gaussian elimination with partial
/// pivoting), refusing pivots of size `tiny` or below: `None` for a (nearly)
/// singular system. `tiny = 1e-300` asks only for a non-singular one.
pub fn solve_pivoted(
    a: &mut [[Real; 6]; 6],
    b: &mut [Real; 6],
    m: usize,
    tiny: Real,
) -> Option<[Real; 6]> {
    for col in 0..m {
        let p = (col..m).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[p][col].abs().partial_cmp(&tiny) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        a.swap(col, p);
        b.swap(col, p);
        for i in col + 1..m {
            let f = a[i][col] / a[col][col];
            for j in col..m {
                a[i][j] -= f * a[col][j];
            }
            b[i] -= f * b[col];
        }
    }
    back_substitute(m, b, |i, j| a[i][j])
}

/// Solves the upper triangular `n × n` system `u y = b` (`u(i, j)` its entry in
/// row `i`, column `j`); `None` unless every entry of `y` is finite.
fn back_substitute(n: usize, b: &[Real; 6], u: impl Fn(usize, usize) -> Real) -> Option<[Real; 6]> {
    let mut y = [0.0; 6];
    for i in (0..n).rev() {
        let mut s = b[i];
        for j in i + 1..n {
            s -= u(i, j) * y[j];
        }
        y[i] = s / u(i, i);
    }
    y.iter().all(|v| v.is_finite()).then_some(y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// NNLS by brute force: the best least-squares fit over every subset whose
    /// unconstrained solution is non-negative.
    fn brute_nnls(a: &[Vector<3>], t: Vector<3>) -> Real {
        let m = a.len();
        let mut best = t.norm();
        for mask in 1u32..(1 << m) {
            let subset: Vec<bool> = (0..m).map(|i| mask & (1 << i) != 0).collect();
            let mut z = [0.0; 16];
            if least_squares_subset(a, t, &subset, &mut z)
                && (0..m).all(|i| !subset[i] || z[i] >= 0.0)
            {
                let mut r = t;
                for i in 0..m {
                    if subset[i] {
                        r -= a[i] * z[i];
                    }
                }
                best = best.min(r.norm());
            }
        }
        best
    }

    proptest! {
        #[test]
        fn nnls_matches_brute_force(
            v in prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), 1..6),
        ) {
            let a: Vec<Vector<3>> = v.iter().map(|c| Vector(*c)).collect();
            prop_assume!(a.iter().all(|x| x.norm() > 0.1));
            let mut l = [0.0; 16];
            let r = nnls(&a, Vector::up(), &mut l);
            prop_assert!(l[..a.len()].iter().all(|&x| x >= 0.0));
            let mut check = Vector::up();
            for i in 0..a.len() {
                check -= a[i] * l[i];
            }
            prop_assert!((check - r).norm() < 1e-9);
            prop_assert!((r.norm() - brute_nnls(&a, Vector::up())).abs() < 1e-7,
                "{} vs {}", r.norm(), brute_nnls(&a, Vector::up()));
        }
    }

    #[test]
    fn nnls_two_supports_in_2d() {
        let s = 0.5f64.sqrt();
        let a = [Vector([s, s]), Vector([-s, s])];
        let mut l = [0.0; 2];
        let r = nnls(&a, Vector::up(), &mut l);
        assert!(r.norm() < 1e-14);
        assert!((l[0] - s).abs() < 1e-14 && (l[1] - s).abs() < 1e-14);
    }

    #[test]
    fn nnls_releases_tensile_contact() {
        // One support to the right and below: cannot hold the particle.
        let a = [Vector([0.6, 0.8]), Vector([0.6, -0.8])];
        let mut l = [0.0; 2];
        let r = nnls(&a, Vector::up(), &mut l);
        assert!(l[1] == 0.0);
        assert!((l[0] - 0.8).abs() < 1e-14);
        assert!(r.norm() > 0.1);
    }

    #[test]
    fn nnls_three_supports_in_3d() {
        let mut n = Vec::new();
        for k in 0..3 {
            let a = 2.0 * std::f64::consts::PI * k as f64 / 3.0;
            n.push(Vector([0.5 * a.cos(), 0.5 * a.sin(), 0.75f64.sqrt()]));
        }
        let mut l = [0.0; 3];
        let r = nnls(&n, Vector::up(), &mut l);
        assert!(r.norm() < 1e-14, "{r:?}");
        for v in l {
            assert!((v - 1.0 / (3.0 * 0.75f64.sqrt())).abs() < 1e-12);
        }
    }

    proptest! {
        /// The QR solution satisfies the normal equations `Aᵀ(Az − b) = 0`.
        #[test]
        fn qr_least_squares_is_a_least_squares_solution(
            raw in prop::collection::vec(prop::array::uniform6(-1.0f64..1.0), 1..=6),
            b in prop::array::uniform6(-1.0f64..1.0),
        ) {
            if let Some(z) = least_squares_qr(&raw, 6, &b) {
                let mut r = b;
                for (c, col) in raw.iter().enumerate() {
                    for d in 0..6 {
                        r[d] -= z[c] * col[d];
                    }
                }
                for col in &raw {
                    let g: Real = (0..6).map(|d| col[d] * r[d]).sum();
                    prop_assert!(g.abs() < 1e-8, "gradient {g}");
                }
            }
        }
    }
}
