//! Real type, fixed-size vectors and the dimension of space.
//!
//! Every geometric routine in packbed is generic over `const D: usize` (2 or 3) and
//! works on [`Vector<D>`]. This module is the only place that names a concrete
//! dimension; the last axis is always vertical ("up").

use std::ops::{Add, AddAssign, Div, Index, IndexMut, Mul, Neg, Sub, SubAssign};

/// The real number type of all geometry.
pub type Real = f64;

/// A point or direction in `D`-dimensional space; the last component is height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vector<const D: usize>(pub [Real; D]);

/// A 2D vector `(x, y)`, `y` up.
pub type Vector2 = Vector<2>;
/// A 3D vector `(x, y, z)`, `z` up.
pub type Vector3 = Vector<3>;

impl<const D: usize> Default for Vector<D> {
    fn default() -> Self {
        Self::zero()
    }
}

impl<const D: usize> Vector<D> {
    /// Index of the vertical axis.
    pub const UP: usize = D - 1;

    /// The zero vector.
    #[inline]
    pub const fn zero() -> Self {
        Vector([0.0; D])
    }

    /// The unit vector pointing up (against gravity).
    #[inline]
    pub fn up() -> Self {
        Self::axis(D - 1)
    }

    /// The unit vector along axis `k`.
    #[inline]
    pub fn axis(k: usize) -> Self {
        let mut v = Self::zero();
        v.0[k] = 1.0;
        v
    }

    /// Height (the vertical component).
    #[inline]
    pub fn height(&self) -> Real {
        self.0[D - 1]
    }

    /// Scalar product.
    #[inline]
    pub fn dot(&self, o: &Self) -> Real {
        let mut s = 0.0;
        for k in 0..D {
            s += self.0[k] * o.0[k];
        }
        s
    }

    /// Squared Euclidean length.
    #[inline]
    pub fn norm2(&self) -> Real {
        self.dot(self)
    }

    /// Euclidean length.
    #[inline]
    pub fn norm(&self) -> Real {
        self.norm2().sqrt()
    }

    /// This vector scaled to unit length, or `None` for a (near) zero vector.
    #[inline]
    pub fn normalized(&self) -> Option<Self> {
        let n = self.norm();
        if n > 0.0 && n.is_finite() {
            Some(*self / n)
        } else {
            None
        }
    }

    /// The horizontal part (vertical component set to zero).
    #[inline]
    pub fn horizontal(&self) -> Self {
        let mut v = *self;
        v.0[D - 1] = 0.0;
        v
    }

    /// True when every component is finite.
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|c| c.is_finite())
    }
}

impl<const D: usize> Index<usize> for Vector<D> {
    type Output = Real;
    #[inline]
    fn index(&self, k: usize) -> &Real {
        &self.0[k]
    }
}

impl<const D: usize> IndexMut<usize> for Vector<D> {
    #[inline]
    fn index_mut(&mut self, k: usize) -> &mut Real {
        &mut self.0[k]
    }
}

impl<const D: usize> Add for Vector<D> {
    type Output = Self;
    #[inline]
    fn add(mut self, o: Self) -> Self {
        for k in 0..D {
            self.0[k] += o.0[k];
        }
        self
    }
}

impl<const D: usize> AddAssign for Vector<D> {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        for k in 0..D {
            self.0[k] += o.0[k];
        }
    }
}

impl<const D: usize> Sub for Vector<D> {
    type Output = Self;
    #[inline]
    fn sub(mut self, o: Self) -> Self {
        for k in 0..D {
            self.0[k] -= o.0[k];
        }
        self
    }
}

impl<const D: usize> SubAssign for Vector<D> {
    #[inline]
    fn sub_assign(&mut self, o: Self) {
        for k in 0..D {
            self.0[k] -= o.0[k];
        }
    }
}

impl<const D: usize> Mul<Real> for Vector<D> {
    type Output = Self;
    #[inline]
    fn mul(mut self, s: Real) -> Self {
        for k in 0..D {
            self.0[k] *= s;
        }
        self
    }
}

impl<const D: usize> Div<Real> for Vector<D> {
    type Output = Self;
    #[inline]
    fn div(self, s: Real) -> Self {
        self * (1.0 / s)
    }
}

impl<const D: usize> Neg for Vector<D> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self * -1.0
    }
}

/// Volume of a `D`-ball of radius `r` (area of a disc in 2D).
pub fn ball_volume<const D: usize>(r: Real) -> Real {
    match D {
        1 => 2.0 * r,
        2 => std::f64::consts::PI * r * r,
        3 => 4.0 / 3.0 * std::f64::consts::PI * r * r * r,
        _ => unreachable!("packbed works in 2 or 3 dimensions"),
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
    let mut passive = [false; MAX];
    let residual = |lam: &[Real]| {
        let mut r = target;
        for i in 0..m {
            r -= a[i] * lam[i];
        }
        r
    };
    let tol = 1e-13;
    for _outer in 0..(3 * m + 3) {
        let r = residual(lambda);
        // Gradient of the objective: w_i = a_i · r.
        let mut best = None;
        let mut best_w = tol;
        for i in 0..m {
            if !passive[i] {
                let w = a[i].dot(&r);
                if w > best_w {
                    best_w = w;
                    best = Some(i);
                }
            }
        }
        let Some(j) = best else { break };
        passive[j] = true;
        // Inner loop: solve the unconstrained problem on the passive set and step
        // back towards feasibility while a coefficient would turn negative.
        for _inner in 0..(3 * m + 3) {
            let mut z = [0.0; MAX];
            if !least_squares_subset(a, target, &passive[..m], &mut z) {
                return residual(lambda);
            }
            let mut alpha = 1.0;
            let mut any_neg = false;
            for i in 0..m {
                if passive[i] && z[i] <= 0.0 {
                    any_neg = true;
                    let denom = lambda[i] - z[i];
                    if denom > 0.0 {
                        alpha = Real::min(alpha, lambda[i] / denom);
                    }
                }
            }
            if !any_neg {
                lambda[..m].copy_from_slice(&z[..m]);
                break;
            }
            for i in 0..m {
                lambda[i] += alpha * (z[i] - lambda[i]);
                if passive[i] && lambda[i] <= tol {
                    lambda[i] = 0.0;
                    passive[i] = false;
                }
            }
        }
    }
    residual(lambda)
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
    let mut z = [0.0; 6];
    for r in (0..p).rev() {
        let mut t = y[r];
        for c in r + 1..p {
            t -= m[c][r] * z[c];
        }
        z[r] = t / m[r][r];
    }
    z.iter().all(|v| v.is_finite()).then_some(z)
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
    let mut passive = vec![false; m];
    let mut banned = vec![false; m];
    let residual = |x: &[Real]| {
        let mut r = *b;
        for (col, &xk) in a.iter().zip(x) {
            for d in 0..q {
                r[d] -= xk * col[d];
            }
        }
        r
    };
    let dot = |u: &[Real; 6], v: &[Real; 6]| (0..q).map(|d| u[d] * v[d]).sum::<Real>();
    let mut idx: Vec<usize> = Vec::with_capacity(6);
    let mut sub: Vec<[Real; 6]> = Vec::with_capacity(6);
    for _ in 0..3 * m + 10 {
        let r = residual(&x);
        let mut best = None;
        let mut best_w = 1e-14;
        for k in 0..m {
            if !passive[k] && !banned[k] {
                let w = dot(&a[k], &r);
                if w > best_w {
                    best_w = w;
                    best = Some(k);
                }
            }
        }
        let Some(j) = best else { break };
        passive[j] = true;
        for _ in 0..3 * m + 10 {
            idx.clear();
            idx.extend((0..m).filter(|&k| passive[k]));
            sub.clear();
            sub.extend(idx.iter().map(|&k| a[k]));
            let Some(z) = crate::math::least_squares_qr(&sub, q, b) else {
                passive[j] = false;
                banned[j] = true;
                break;
            };
            let z = &z[..idx.len()];
            if z.iter().all(|&v| v > 0.0) {
                for (&k, &v) in idx.iter().zip(z) {
                    x[k] = v;
                }
                banned.fill(false);
                break;
            }
            let mut alpha: Real = 1.0;
            for (&k, &v) in idx.iter().zip(z) {
                if v <= 0.0 {
                    alpha = alpha.min(x[k] / (x[k] - v));
                }
            }
            for (&k, &v) in idx.iter().zip(z) {
                x[k] += alpha * (v - x[k]);
                if x[k] <= 1e-15 {
                    x[k] = 0.0;
                    passive[k] = false;
                }
            }
        }
    }
    (residual(&x), x)
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
