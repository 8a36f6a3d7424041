//! Exact geometric predicates for regular (power / weighted Delaunay) triangulations in 2D and 3D.
//!
//! Every predicate first evaluates its determinant in plain `f64` arithmetic together with a
//! rigorous forward error bound (a dynamic filter: constant × "permanent", the same polynomial
//! evaluated on absolute values). When the filter cannot certify the sign of a power test:
//! 1. if every difference `p_i − q` is a double (no rounding: neighbouring points away from the
//!    origin), the same translated determinant is evaluated in double-word arithmetic with its
//!    own rigorous bound (about 1e-30 of the permanent), then, if still undecided, exactly;
//! 2. otherwise the determinant is recomputed exactly on the *untranslated* input values, so
//!    no rounded coordinate difference ever enters it.
//!
//! The exact evaluations use Shewchuk-style floating-point expansions (error-free `two_sum` /
//! `two_product` transformations).
//!
//! # Conventions
//!
//! * `orient2d(a, b, c)` = sign of `det[b - a, c - a]`, `+1` when `a, b, c` turn counter-clockwise.
//! * `orient3d(a, b, c, d)` = sign of `((b - a) × (c - a)) · (d - a)`, `+1` when `d` lies on the
//!   side of the plane `abc` that `(b - a) × (c - a)` points to.
//! * A weighted point is `(centre, w)` with `w = radius²`. The power distance of a weighted point
//!   `(x, w)` to a sphere `(c, R)` (R = radius²) is `|x - c|² - w - R`. The orthosphere of the
//!   4 (3D) / 3 (2D) points `p` is the sphere whose power distance to every `p_i` is zero.
//!   `power_test_*` returns `+1` when the power distance of `(q, wq)` to that orthosphere is
//!   negative ("q conflicts with the cell"), `-1` when positive and `0` when zero. The result does
//!   not depend on the order or orientation of `p`. If `p` is degenerate (coplanar in 3D,
//!   collinear in 2D) there is no orthosphere and the predicates return `0`.
//!
//! # Lifted determinant
//!
//! With `h_i = |x_i|² - w_i` the lifted determinant of the points `p_0 .. p_{n-1}, q` is
//! (3D) `D = det[x_i, y_i, z_i, h_i, 1]` (5 × 5, rows `p_0, p_1, p_2, p_3, q`), and
//! (2D) `D = det[x_i, y_i, h_i, 1]` (4 × 4, rows `p_0, p_1, p_2, q`). Expanding along the `h`
//! column gives `D = Σ_i (-1)^i · h_i · O_i`, where `O_i` is the orientation (`orient3d` /
//! `orient2d` as defined above) of the other points taken in their row order. Then
//!
//! * 3D: `power_test_3d = -sign(D) · orient3d(p_0, p_1, p_2, p_3)`,
//! * 2D: `power_test_2d = +sign(D) · orient2d(p_0, p_1, p_2)`.
//!
//! # Symbolic perturbation (`*_perturbed`)
//!
//! Every weight is perturbed as `w_i → w_i + ε_i` with infinitesimals `ε_i > 0` such that
//! `ε_i / ε_j → 0` whenever `rank_i < rank_j`: the point of **higher rank receives the larger
//! perturbation**. Concretely, with the `n` points (p and q) sorted by increasing rank at
//! positions `pos_i = 0 .. n-1`, one may take `ε_i = ε^(n - pos_i)`, i.e. the highest-ranked point
//! gets `ε¹`, the next `ε²`, …, for `ε → 0⁺`. Since the weights enter `D` only through the `h`
//! column, `D(ε) = D - Σ_i ε_i (-1)^i O_i` exactly; so when `D = 0` the sign is decided by the
//! highest-ranked point `i` whose minor `O_i` is non-zero, giving
//! `power_test_3d_perturbed = (-1)^i · sign(O_i) · orient3d(p)` and
//! `power_test_2d_perturbed = -(-1)^i · sign(O_i) · orient2d(p)`. The minor of `q` is the
//! orientation of `p` itself, so the sequence always terminates, and when `q` is the
//! highest-ranked point of the degenerate configuration the answer is `+1` (a larger weight
//! of `q` means conflict). Ranks must be distinct (e.g. global point indices); equal ranks are
//! broken by argument position (`p[0]` first, `q` last), which is then order dependent. This is
//! a genuine perturbation of the weights, hence consistent across all calls that use the same
//! rank for the same point, and independent of the order of `p`.
//!
//! # Exactness range
//!
//! The results are exact (no rounding can change them) provided that every **non-zero**
//! coordinate `x` satisfies `2^-140 ≤ |x| ≤ 2^140` (≈ 7.2e-43 … 1.4e42) and every non-zero weight
//! `2^-280 ≤ |w| ≤ 2^280` for the power tests, and `2^-250 ≤ |x| ≤ 2^250` (≈ 5.5e-76 … 1.8e75)
//! for `orient2d` / `orient3d`. These bounds guarantee that no intermediate value of either the
//! filter or the exact expansion arithmetic overflows or underflows (the power determinant has
//! degree 5: coordinates beyond ≈ 1e61 overflow `f64` whatever the method). Inputs must be finite.

/// Sign of a determinant: -1, 0 or +1.
pub type Sign = i8;

/// Unit roundoff of `f64` (round to nearest): 2^-53.
const UNIT: f64 = f64::EPSILON * 0.5;
// Relative error bounds of the filters (see the comments in each predicate): an evaluation in
// which every monomial suffers at most k roundings has error ≤ ((1+u)^k - 1)·P(exact); the
// computed permanent satisfies P(exact) ≤ P_computed·(1-u)^-m. The constants below exceed
// ((1+u)^k - 1)(1-u)^-m (1+u) for the respective k, m.
const ORIENT2D_BOUND: f64 = 5.0 * UNIT; // k = 4, m = 4
const ORIENT3D_BOUND: f64 = 9.0 * UNIT; // k = 8, m = 8
const POWER2D_BOUND: f64 = 13.0 * UNIT; // k = 12, m = 12
const POWER3D_BOUND: f64 = 18.0 * UNIT; // k = 17, m = 17

#[inline(always)]
fn sign_of(x: f64) -> Sign {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Sign of `det[b - a, c - a]`; `+1` when `a, b, c` are counter-clockwise.
#[inline]
pub fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
    // Each monomial: 2 rounded differences, 1 product, 1 subtraction → k = 4.
    let ux = b[0] - a[0];
    let uy = b[1] - a[1];
    let vx = c[0] - a[0];
    let vy = c[1] - a[1];
    let l = ux * vy;
    let r = uy * vx;
    let det = l - r;
    let perm = l.abs() + r.abs();
    let bound = ORIENT2D_BOUND * perm;
    if det > bound || -det > bound {
        return sign_of(det);
    }
    // Every product has an exactly zero factor (a difference of equal
    // numbers): the determinant is exactly 0, as for collinear points on an
    // axis-parallel line, common in beds (a floor layer).
    if perm == 0.0 {
        return 0;
    }
    exp_sign(&orient2d_exact(a, b, c))
}

/// Sign of `((b - a) × (c - a)) · (d - a)`.
#[inline]
pub fn orient3d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Sign {
    // det = u · (v × w); each monomial: 3 differences + 1 product + 1 subtraction
    // + 1 product + 2 additions → k = 8.
    let (ux, uy, uz) = (b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    let (vx, vy, vz) = (c[0] - a[0], c[1] - a[1], c[2] - a[2]);
    let (wx, wy, wz) = (d[0] - a[0], d[1] - a[1], d[2] - a[2]);
    let vywz = vy * wz;
    let vzwy = vz * wy;
    let vzwx = vz * wx;
    let vxwz = vx * wz;
    let vxwy = vx * wy;
    let vywx = vy * wx;
    let det = ux * (vywz - vzwy) + uy * (vzwx - vxwz) + uz * (vxwy - vywx);
    let perm = ux.abs() * (vywz.abs() + vzwy.abs())
        + uy.abs() * (vzwx.abs() + vxwz.abs())
        + uz.abs() * (vxwy.abs() + vywx.abs());
    let bound = ORIENT3D_BOUND * perm;
    if det > bound || -det > bound {
        return sign_of(det);
    }
    // Every monomial has an exactly zero factor: 0 exactly, as for four
    // centres in one horizontal plane (the spheres on the floor), which
    // otherwise took the exact path a third of the triangulation's time.
    if perm == 0.0 {
        return 0;
    }
    exp_sign(&orient3d_exact(a, b, c, d))
}

/// Power test in 3D. `p`: four weighted points (centre, weight = radius²) in any orientation
/// (non-coplanar), `q`: the query. `+1` if `q` lies strictly inside the orthogonal sphere of the
/// four in the power sense (power distance of `q` to the orthosphere `< 0`, i.e. `q` conflicts
/// with the cell), `-1` if outside, `0` if on it (and `0` if `p` is coplanar).
#[inline]
#[cfg(test)]
pub fn power_test_3d(p: [[f64; 3]; 4], w: [f64; 4], q: [f64; 3], wq: f64) -> Sign {
    let s = power_det_sign_3d(&p, &w, q, wq);
    if s == 0 {
        return 0;
    }
    -s * orient3d(p[0], p[1], p[2], p[3])
}

/// Same as [`power_test_3d`] in 2D with three weighted points (non-collinear) and a query.
#[inline]
#[cfg(test)]
pub fn power_test_2d(p: [[f64; 2]; 3], w: [f64; 3], q: [f64; 2], wq: f64) -> Sign {
    let s = power_det_sign_2d(&p, &w, q, wq);
    if s == 0 {
        return 0;
    }
    s * orient2d(p[0], p[1], p[2])
}

/// Symbolically perturbed [`power_test_3d`]: never `0` for non-coplanar `p`.
///
/// Weights are perturbed as `w_i → w_i + ε_i`, where a point of higher rank gets an infinitely
/// larger perturbation (see the module documentation for the exact convention). Ranks must be
/// distinct. Returns `0` only if `p` is coplanar.
#[cfg(test)]
pub fn power_test_3d_perturbed(
    p: [[f64; 3]; 4],
    w: [f64; 4],
    rank: [u64; 4],
    q: [f64; 3],
    wq: f64,
    rank_q: u64,
) -> Sign {
    let o4 = orient3d(p[0], p[1], p[2], p[3]);
    perturbed_3d(p, w, q, wq, o4, || (rank, rank_q))
}

/// [`power_test_3d_perturbed`] for `p` known to be positively oriented (the
/// cells of a triangulation), which spares the orientation test.
#[inline]
#[cfg(test)]
pub fn power_test_3d_oriented(
    p: [[f64; 3]; 4],
    w: [f64; 4],
    rank: [u64; 4],
    q: [f64; 3],
    wq: f64,
    rank_q: u64,
) -> Sign {
    perturbed_3d(p, w, q, wq, 1, || (rank, rank_q))
}

/// [`power_test_3d_oriented`] with the ranks asked for only when the
/// determinant is exactly zero (they are rarely needed, and a triangulation
/// keeps them apart from the points).
#[inline]
pub fn power_test_3d_oriented_lazy(
    p: [[f64; 3]; 4],
    w: [f64; 4],
    q: [f64; 3],
    wq: f64,
    ranks: impl FnOnce() -> ([u64; 4], u64),
) -> Sign {
    perturbed_3d(p, w, q, wq, 1, ranks)
}

/// [`power_test_2d_oriented`] with the ranks asked for only on a tie.
#[inline]
pub fn power_test_2d_oriented_lazy(
    p: [[f64; 2]; 3],
    w: [f64; 3],
    q: [f64; 2],
    wq: f64,
    ranks: impl FnOnce() -> ([u64; 3], u64),
) -> Sign {
    perturbed_2d(p, w, q, wq, 1, ranks)
}

/// The perturbed 3D power test given `p`'s orientation `o4`; the ranks are
/// asked for only when the determinant is exactly zero.
#[inline]
fn perturbed_3d(
    p: [[f64; 3]; 4],
    w: [f64; 4],
    q: [f64; 3],
    wq: f64,
    o4: Sign,
    ranks: impl FnOnce() -> ([u64; 4], u64),
) -> Sign {
    let s = power_det_sign_3d(&p, &w, q, wq);
    if s != 0 || o4 == 0 {
        return -s * o4;
    }
    let (rank, rank_q) = ranks();
    // D = 0: D(ε) = -Σ ε_i (-1)^i O_i, result = -sign(D(ε)) · O_4.
    let o4_q = |o: &[[f64; 3]]| orient3d(o[0], o[1], o[2], o[3]);
    tie_break(
        &[p[0], p[1], p[2], p[3], q],
        &[rank[0], rank[1], rank[2], rank[3], rank_q],
        o4_q,
        o4,
    )
}

/// The sign of a power test whose determinant is zero, from the perturbation
/// of the highest-ranked point whose minor (`orient` of the other points) is
/// not zero; the minor of `q` (last of `pts`) is the cell's own orientation
/// `o`, never zero here. In 3D the even minors count `+`, in 2D `-`: the sign
/// of `(-1)^i` flips with the lifted determinant's size.
fn tie_break<const D: usize>(
    pts: &[[f64; D]],
    ranks: &[u64],
    orient: impl Fn(&[[f64; D]]) -> Sign,
    o: Sign,
) -> Sign {
    let q = pts.len() - 1;
    let even: Sign = if D == 3 { 1 } else { -1 };
    let mut order = [0usize, 1, 2, 3, 4];
    let order = &mut order[..pts.len()];
    order.sort_unstable_by(|&a, &b| ranks[b].cmp(&ranks[a]).then(a.cmp(&b)));
    for &i in order.iter() {
        if i == q {
            return 1; // the minor of q is o itself: ± o · o, the sign making it positive.
        }
        let mut minor = [[0.0; D]; 4];
        let mut k = 0;
        for (j, pt) in pts.iter().enumerate() {
            if j != i {
                minor[k] = *pt;
                k += 1;
            }
        }
        let oi = orient(&minor[..q]);
        if oi != 0 {
            return if i % 2 == 0 {
                even * oi * o
            } else {
                -even * oi * o
            };
        }
    }
    unreachable!("the minor of q is the cell's orientation, not 0")
}

/// Symbolically perturbed [`power_test_2d`]: never `0` for non-collinear `p`.
///
/// Same convention as [`power_test_3d_perturbed`]. Returns `0` only if `p` is collinear.
#[cfg(test)]
pub fn power_test_2d_perturbed(
    p: [[f64; 2]; 3],
    w: [f64; 3],
    rank: [u64; 3],
    q: [f64; 2],
    wq: f64,
    rank_q: u64,
) -> Sign {
    let o3 = orient2d(p[0], p[1], p[2]);
    perturbed_2d(p, w, q, wq, o3, || (rank, rank_q))
}

/// [`power_test_2d_perturbed`] for `p` known to be counter-clockwise.
#[inline]
#[cfg(test)]
pub fn power_test_2d_oriented(
    p: [[f64; 2]; 3],
    w: [f64; 3],
    rank: [u64; 3],
    q: [f64; 2],
    wq: f64,
    rank_q: u64,
) -> Sign {
    perturbed_2d(p, w, q, wq, 1, || (rank, rank_q))
}

/// The perturbed 2D power test given `p`'s orientation `o3`; the ranks are
/// asked for only on a tie.
#[inline]
fn perturbed_2d(
    p: [[f64; 2]; 3],
    w: [f64; 3],
    q: [f64; 2],
    wq: f64,
    o3: Sign,
    ranks: impl FnOnce() -> ([u64; 3], u64),
) -> Sign {
    let s = power_det_sign_2d(&p, &w, q, wq);
    if s != 0 || o3 == 0 {
        return s * o3;
    }
    let (rank, rank_q) = ranks();
    // D = 0: D(ε) = -Σ ε_i (-1)^i O_i, result = sign(D(ε)) · O_3.
    let o3_q = |o: &[[f64; 2]]| orient2d(o[0], o[1], o[2]);
    tie_break(
        &[p[0], p[1], p[2], q],
        &[rank[0], rank[1], rank[2], rank_q],
        o3_q,
        o3,
    )
}

/// Sign of the 5×5 lifted determinant D (rows p0..p3, q), filtered.
///
/// Evaluated translated to q: D = det[d_i, h_i] (4×4) with d_i = p_i - q and
/// h_i = |d_i|² - (w_i - wq), by the Laplace expansion over complementary 2×2 minors of the
/// column pairs (x, y) and (z, h). Rounding count per monomial: h carries ≤ 6 (2 for d², 1
/// product, 2 additions, 1 subtraction), n = dz·h - dz·h ≤ 9, m = dx·dy - dx·dy ≤ 4, m·n ≤ 14,
/// the 6-term sum tree of depth 3 → k = 17. The permanent has ≤ 12 roundings and degree 5 in the
/// rounded differences → m = 17.
#[inline]
#[allow(clippy::needless_range_loop)]
fn power_det_sign_3d(p: &[[f64; 3]; 4], w: &[f64; 4], q: [f64; 3], wq: f64) -> Sign {
    let mut dx = [0.0; 4];
    let mut dy = [0.0; 4];
    let mut dz = [0.0; 4];
    let mut h = [0.0; 4];
    let mut ha = [0.0; 4];
    for i in 0..4 {
        let x = p[i][0] - q[0];
        let y = p[i][1] - q[1];
        let z = p[i][2] - q[2];
        let s = x * x + y * y + z * z;
        let dw = w[i] - wq;
        dx[i] = x;
        dy[i] = y;
        dz[i] = z;
        h[i] = s - dw;
        ha[i] = s + dw.abs();
    }
    let m = |i: usize, j: usize| dx[i] * dy[j] - dx[j] * dy[i];
    let n = |i: usize, j: usize| dz[i] * h[j] - dz[j] * h[i];
    let (m01, m02, m03, m12, m13, m23) = (m(0, 1), m(0, 2), m(0, 3), m(1, 2), m(1, 3), m(2, 3));
    let (n01, n02, n03, n12, n13, n23) = (n(0, 1), n(0, 2), n(0, 3), n(1, 2), n(1, 3), n(2, 3));
    let det = ((m01 * n23 - m02 * n13) + (m03 * n12 + m12 * n03)) + (m23 * n01 - m13 * n02);
    // First a semi-static bound: each of the 24 monomials takes one entry
    // from each column, so the permanent is at most 24 times the product of
    // the columns' largest magnitudes (the 1e-4 covers this product's own
    // four roundings). It decides nearly every test for the cost of a few
    // maxima; the permanent is the second, tighter bound.
    let max = |a: &[f64; 4]| a[0].abs().max(a[1].abs()).max(a[2].abs().max(a[3].abs()));
    let semi =
        (24.0 * (1.0 + 1e-4) * POWER3D_BOUND) * ((max(&dx) * max(&dy)) * (max(&dz) * max(&ha)));
    if det > semi || -det > semi {
        return sign_of(det);
    }
    let pm = |i: usize, j: usize| (dx[i] * dy[j]).abs() + (dx[j] * dy[i]).abs();
    let pn = |i: usize, j: usize| dz[i].abs() * ha[j] + dz[j].abs() * ha[i];
    let perm = ((pm(0, 1) * pn(2, 3) + pm(0, 2) * pn(1, 3))
        + (pm(0, 3) * pn(1, 2) + pm(1, 2) * pn(0, 3)))
        + (pm(2, 3) * pn(0, 1) + pm(1, 3) * pn(0, 2));
    let bound = POWER3D_BOUND * perm;
    if det > bound || -det > bound {
        return sign_of(det);
    }
    translated_det_sign_3d(p, w, q, wq)
        .unwrap_or_else(|| exp_sign(&power_det_3d_exact(p, w, q, wq)))
}

/// Sign of the 4×4 lifted determinant D (rows p0..p2, q), filtered.
///
/// Evaluated translated to q: D = det[d_i, h_i] (3×3) = Σ ±h_i · m_jk. Rounding count:
/// h ≤ 5, m ≤ 4, h·m ≤ 10, 3-term sum → k = 12; permanent ≤ 8 roundings, degree 4 → m = 12.
#[inline]
#[allow(clippy::needless_range_loop)]
fn power_det_sign_2d(p: &[[f64; 2]; 3], w: &[f64; 3], q: [f64; 2], wq: f64) -> Sign {
    let mut dx = [0.0; 3];
    let mut dy = [0.0; 3];
    let mut h = [0.0; 3];
    let mut ha = [0.0; 3];
    for i in 0..3 {
        let x = p[i][0] - q[0];
        let y = p[i][1] - q[1];
        let s = x * x + y * y;
        let dw = w[i] - wq;
        dx[i] = x;
        dy[i] = y;
        h[i] = s - dw;
        ha[i] = s + dw.abs();
    }
    let m = |i: usize, j: usize| {
        let a = dx[i] * dy[j];
        let b = dx[j] * dy[i];
        (a - b, a.abs() + b.abs())
    };
    let (m12, pm12) = m(1, 2);
    let (m02, pm02) = m(0, 2);
    let (m01, pm01) = m(0, 1);
    let det = (h[0] * m12 - h[1] * m02) + h[2] * m01;
    let perm = (ha[0] * pm12 + ha[1] * pm02) + ha[2] * pm01;
    let bound = POWER2D_BOUND * perm;
    if det > bound || -det > bound {
        return sign_of(det);
    }
    translated_det_sign_2d(p, w, q, wq)
        .unwrap_or_else(|| exp_sign(&power_det_2d_exact(p, w, q, wq)))
}

// ---------------------------------------------------------------------------------------------
// Exact arithmetic: nonoverlapping floating-point expansions (Shewchuk 1997). An expansion is a
// Vec<f64> of components sorted by increasing magnitude whose exact sum is the value; zero
// components are eliminated. Only the fallback path uses these.
// ---------------------------------------------------------------------------------------------

/// Error-free sum: a + b = x + y exactly, x = fl(a + b).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let bv = x - a;
    let av = x - bv;
    let br = b - bv;
    let ar = a - av;
    (x, ar + br)
}

/// Error-free product: a · b = x + y exactly, x = fl(a · b) (needs no underflow).
#[inline]
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let x = a * b;
    (x, a.mul_add(b, -x))
}

/// Sum of two expansions (Shewchuk's LINEAR-EXPANSION-SUM, Theorem 11, with zero elimination;
/// TWO-SUM is used in place of FAST-TWO-SUM, which yields identical results).
fn exp_sum(e: &[f64], f: &[f64]) -> Vec<f64> {
    let mut g = Vec::with_capacity(e.len() + f.len());
    let (mut i, mut j) = (0, 0);
    while i < e.len() && j < f.len() {
        if e[i].abs() <= f[j].abs() {
            g.push(e[i]);
            i += 1;
        } else {
            g.push(f[j]);
            j += 1;
        }
    }
    g.extend_from_slice(&e[i..]);
    g.extend_from_slice(&f[j..]);
    g.retain(|&x| x != 0.0);
    if g.len() < 2 {
        return g;
    }
    let mut h = Vec::with_capacity(g.len());
    let (mut big, mut small) = two_sum(g[1], g[0]);
    for &gi in &g[2..] {
        let (r, hh) = two_sum(gi, small);
        if hh != 0.0 {
            h.push(hh);
        }
        let (nb, ns) = two_sum(big, r);
        big = nb;
        small = ns;
    }
    if small != 0.0 {
        h.push(small);
    }
    if big != 0.0 {
        h.push(big);
    }
    h
}

/// Expansion times a double (Shewchuk's SCALE-EXPANSION with zero elimination).
fn exp_scale(e: &[f64], b: f64) -> Vec<f64> {
    let mut h = Vec::with_capacity(2 * e.len());
    if e.is_empty() || b == 0.0 {
        return h;
    }
    let (mut q, hh) = two_product(e[0], b);
    if hh != 0.0 {
        h.push(hh);
    }
    for &ei in &e[1..] {
        let (p1, p0) = two_product(ei, b);
        let (s, hh) = two_sum(q, p0);
        if hh != 0.0 {
            h.push(hh);
        }
        let (nq, hh) = two_sum(p1, s);
        if hh != 0.0 {
            h.push(hh);
        }
        q = nq;
    }
    if q != 0.0 {
        h.push(q);
    }
    h
}

/// Product of two expansions: sum of the first scaled by each component of the second.
fn exp_mul(e: &[f64], f: &[f64]) -> Vec<f64> {
    let (e, f) = if e.len() >= f.len() { (e, f) } else { (f, e) };
    let mut acc = Vec::new();
    for &fj in f {
        acc = exp_sum(&acc, &exp_scale(e, fj));
    }
    acc
}

/// Shewchuk's COMPRESS: same value, usually far fewer components.
fn exp_compress(e: &[f64]) -> Vec<f64> {
    let Some((&top, rest)) = e.split_last() else {
        return Vec::new();
    };
    let mut upper = Vec::with_capacity(e.len());
    let mut q = top;
    for &c in rest.iter().rev() {
        let (qn, small) = two_sum(q, c);
        if small != 0.0 {
            upper.push(qn);
            q = small;
        } else {
            q = qn;
        }
    }
    let mut out = Vec::with_capacity(upper.len() + 1);
    for &c in upper.iter().rev() {
        let (qn, small) = two_sum(c, q);
        if small != 0.0 {
            out.push(small);
        }
        q = qn;
    }
    if q != 0.0 {
        out.push(q);
    }
    out
}

fn exp_neg(e: &[f64]) -> Vec<f64> {
    e.iter().map(|&x| -x).collect()
}

/// Sign of an expansion: the sign of its largest-magnitude (last non-zero) component.
fn exp_sign(e: &[f64]) -> Sign {
    e.iter()
        .rev()
        .find(|&&x| x != 0.0)
        .map_or(0, |&x| sign_of(x))
}

/// a·b - c·d exactly.
fn diff_prod(a: f64, b: f64, c: f64, d: f64) -> Vec<f64> {
    let (x1, y1) = two_product(a, b);
    let (x2, y2) = two_product(c, d);
    exp_sum(&[y1, x1], &[-y2, -x2])
}

/// det of the 2×2 matrix with rows u, v: ux·vy - uy·vx.
fn det2_exact(u: [f64; 2], v: [f64; 2]) -> Vec<f64> {
    diff_prod(u[0], v[1], u[1], v[0])
}

/// det of the 3×3 matrix with rows r0, r1, r2 (expansion along the first column).
fn det3_exact(r0: [f64; 3], r1: [f64; 3], r2: [f64; 3]) -> Vec<f64> {
    let m0 = diff_prod(r1[1], r2[2], r1[2], r2[1]);
    let m1 = diff_prod(r2[1], r0[2], r2[2], r0[1]);
    let m2 = diff_prod(r0[1], r1[2], r0[2], r1[1]);
    let t = exp_sum(&exp_scale(&m0, r0[0]), &exp_scale(&m1, r1[0]));
    exp_sum(&t, &exp_scale(&m2, r2[0]))
}

/// orient2d(a, b, c) = det2(a, b) + det2(b, c) + det2(c, a), exactly.
fn orient2d_exact(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Vec<f64> {
    let t = exp_sum(&det2_exact(a, b), &det2_exact(b, c));
    exp_sum(&t, &det2_exact(c, a))
}

/// orient3d(a, b, c, d) = -det[(a,1), (b,1), (c,1), (d,1)]
/// = det3(b,c,d) - det3(a,c,d) + det3(a,b,d) - det3(a,b,c), exactly.
fn orient3d_exact(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Vec<f64> {
    let t0 = exp_sum(&det3_exact(b, c, d), &exp_neg(&det3_exact(a, c, d)));
    let t1 = exp_sum(&det3_exact(a, b, d), &exp_neg(&det3_exact(a, b, c)));
    exp_sum(&t0, &t1)
}

/// h = |x|² - w exactly.
fn lift_exact(x: &[f64], w: f64) -> Vec<f64> {
    let mut acc = vec![-w];
    for &c in x {
        let (hi, lo) = two_product(c, c);
        acc = exp_sum(&acc, &[lo, hi]);
    }
    acc
}

/// The differences `p_i − q` when every one is a double (no rounding: true
/// of neighbouring points, by Sterbenz's lemma, away from the origin).
fn exact_differences<const D: usize, const N: usize>(
    p: &[[f64; D]; N],
    q: [f64; D],
) -> Option<[[f64; D]; N]> {
    let mut d = [[0.0; D]; N];
    for (di, pi) in d.iter_mut().zip(p) {
        for k in 0..D {
            let (x, tail) = two_sum(pi[k], -q[k]);
            if tail != 0.0 {
                return None;
            }
            di[k] = x;
        }
    }
    Some(d)
}

// ---------------------------------------------------------------------------------------------
// The second filter: the translated determinant in double-word arithmetic (a value is an
// unevaluated sum hi + lo, about 106 bits). Joldes, Muller & Popescu (2017, ACM TOMS 44:15)
// prove relative errors of at most 3u²/(1 − 4u) for their AccurateDWPlusDW and 5u² for
// DWTimesDW3 (below, with 2Sum in place of Fast2Sum, which is exact wherever Fast2Sum is and
// everywhere else too); we count 8u² for either. A monomial of the determinant passes through
// at most k such operations, so the error is at most ((1 + 8u²)^k − 1)·P with P the permanent,
// as in the first filter. Near-cospherical sets, which a deposited bed is full of (spheres at
// contact distance to the last bit), have |det| around 1e-16 of P: the first filter cannot
// decide them, this one decides them at about a twentieth of the exact path's cost.
// ---------------------------------------------------------------------------------------------

/// A double-word number hi + lo.
#[derive(Clone, Copy)]
struct Dw(f64, f64);

/// Exact product of two doubles as a double word.
#[inline(always)]
fn dw_prod(a: f64, b: f64) -> Dw {
    let (x, y) = two_product(a, b);
    Dw(x, y)
}

/// AccurateDWPlusDW (Joldes et al. 2017, Algorithm 6): relative error ≤ 3u²/(1 − 4u).
#[inline(always)]
fn dw_add(x: Dw, y: Dw) -> Dw {
    let (sh, sl) = two_sum(x.0, y.0);
    let (th, tl) = two_sum(x.1, y.1);
    let c = sl + th;
    let (vh, vl) = two_sum(sh, c);
    let w = tl + vl;
    let (zh, zl) = two_sum(vh, w);
    Dw(zh, zl)
}

#[inline(always)]
fn dw_sub(x: Dw, y: Dw) -> Dw {
    dw_add(x, Dw(-y.0, -y.1))
}

/// DWTimesDW3 (Joldes et al. 2017, Algorithm 12): relative error ≤ 5u².
#[inline(always)]
fn dw_mul(x: Dw, y: Dw) -> Dw {
    let (ch, cl1) = two_product(x.0, y.0);
    let tl0 = x.1 * y.1;
    let tl1 = x.0.mul_add(y.1, tl0);
    let cl2 = x.1.mul_add(y.0, tl1);
    let cl3 = cl1 + cl2;
    let (zh, zl) = two_sum(ch, cl3);
    Dw(zh, zl)
}

/// u² = 2^-106.
const UNIT2: f64 = UNIT * UNIT;
/// 3D: a monomial passes through at most 9 double-word operations (h: 3, n: 5, m·n: 6, the
/// 6-term sum: 9): ((1 + 8u²)^9 − 1) < 73u², and the computed permanent is within (1 ± 13u)
/// of the exact one. 128 leaves room.
const DW_POWER3D_BOUND: f64 = 128.0 * UNIT2;
/// 2D: at most 5 (h: 2, h·m: 3, the 3-term sum: 5): < 41u².
const DW_POWER2D_BOUND: f64 = 64.0 * UNIT2;

/// True when the double-word filter's error analysis holds for these differences and weight
/// differences: every value stays a multiple of 2^-800 or so (no underflow) and below 2^600
/// (no overflow), because every non-zero difference lies in [2^-100, 2^100] and every non-zero
/// weight difference in [2^-200, 2^200].
fn dw_in_range<const D: usize>(d: &[[f64; D]], dw: &[Dw]) -> bool {
    let ok = |x: f64, lo: f64, hi: f64| x == 0.0 || (x.abs() >= lo && x.abs() <= hi);
    let (lo1, hi1) = (2f64.powi(-100), 2f64.powi(100));
    let (lo2, hi2) = (2f64.powi(-200), 2f64.powi(200));
    d.iter().flatten().all(|&x| ok(x, lo1, hi1))
        && dw.iter().all(|w| ok(w.0, lo2, hi2) && ok(w.1, lo2, hi2))
}

/// h_i = |d_i|² − dw_i in double words (3 operations deep).
#[inline(always)]
fn dw_lift<const D: usize>(d: &[f64; D], dw: Dw) -> Dw {
    let mut acc = dw_prod(d[0], d[0]);
    for &c in &d[1..] {
        acc = dw_add(acc, dw_prod(c, c));
    }
    dw_sub(acc, dw)
}

/// Sign of the translated 3D lifted determinant from the double-word filter, when it decides.
fn dw_det_sign_3d(d: &[[f64; 3]; 4], w: &[f64; 4], wq: f64) -> Option<Sign> {
    let dw: [Dw; 4] = std::array::from_fn(|i| {
        let (x, y) = two_sum(w[i], -wq);
        Dw(x, y)
    });
    if !dw_in_range(d, &dw) {
        return None;
    }
    let h: [Dw; 4] = std::array::from_fn(|i| dw_lift(&d[i], dw[i]));
    let ha: [f64; 4] = std::array::from_fn(|i| {
        d[i][0] * d[i][0] + d[i][1] * d[i][1] + d[i][2] * d[i][2] + dw[i].0.abs() + dw[i].1.abs()
    });
    let m = |i: usize, j: usize| dw_sub(dw_prod(d[i][0], d[j][1]), dw_prod(d[j][0], d[i][1]));
    let pm = |i: usize, j: usize| (d[i][0] * d[j][1]).abs() + (d[j][0] * d[i][1]).abs();
    let n = |i: usize, j: usize| {
        dw_sub(
            dw_mul(Dw(d[i][2], 0.0), h[j]),
            dw_mul(Dw(d[j][2], 0.0), h[i]),
        )
    };
    let pn = |i: usize, j: usize| d[i][2].abs() * ha[j] + d[j][2].abs() * ha[i];
    let t = |a: (usize, usize), b: (usize, usize)| dw_mul(m(a.0, a.1), n(b.0, b.1));
    let det = dw_add(
        dw_add(
            dw_sub(t((0, 1), (2, 3)), t((0, 2), (1, 3))),
            dw_add(t((0, 3), (1, 2)), t((1, 2), (0, 3))),
        ),
        dw_sub(t((2, 3), (0, 1)), t((1, 3), (0, 2))),
    );
    let perm = ((pm(0, 1) * pn(2, 3) + pm(0, 2) * pn(1, 3))
        + (pm(0, 3) * pn(1, 2) + pm(1, 2) * pn(0, 3)))
        + (pm(2, 3) * pn(0, 1) + pm(1, 3) * pn(0, 2));
    // |hi + lo| ≥ |hi|(1 − u): compare hi against the bound with that slack.
    let bound = DW_POWER3D_BOUND * perm * (1.0 + 4.0 * UNIT);
    (det.0.abs() > bound).then(|| sign_of(det.0))
}

/// Sign of the translated 2D lifted determinant from the double-word filter, when it decides.
fn dw_det_sign_2d(d: &[[f64; 2]; 3], w: &[f64; 3], wq: f64) -> Option<Sign> {
    let dw: [Dw; 3] = std::array::from_fn(|i| {
        let (x, y) = two_sum(w[i], -wq);
        Dw(x, y)
    });
    if !dw_in_range(d, &dw) {
        return None;
    }
    let h: [Dw; 3] = std::array::from_fn(|i| dw_lift(&d[i], dw[i]));
    let ha: [f64; 3] = std::array::from_fn(|i| {
        d[i][0] * d[i][0] + d[i][1] * d[i][1] + dw[i].0.abs() + dw[i].1.abs()
    });
    let m = |i: usize, j: usize| dw_sub(dw_prod(d[i][0], d[j][1]), dw_prod(d[j][0], d[i][1]));
    let pm = |i: usize, j: usize| (d[i][0] * d[j][1]).abs() + (d[j][0] * d[i][1]).abs();
    let det = dw_add(
        dw_sub(dw_mul(h[0], m(1, 2)), dw_mul(h[1], m(0, 2))),
        dw_mul(h[2], m(0, 1)),
    );
    let perm = (ha[0] * pm(1, 2) + ha[1] * pm(0, 2)) + ha[2] * pm(0, 1);
    let bound = DW_POWER2D_BOUND * perm * (1.0 + 4.0 * UNIT);
    (det.0.abs() > bound).then(|| sign_of(det.0))
}

/// h = |d|² − (w − wq) exactly.
fn lift_translated(d: &[f64], w: f64, wq: f64) -> Vec<f64> {
    let mut acc = exp_sum(&[-w], &[wq]);
    for &c in d {
        let (hi, lo) = two_product(c, c);
        acc = exp_sum(&acc, &[lo, hi]);
    }
    exp_compress(&acc)
}

/// Sign of the lifted determinant, exactly, from the differences to `q` when
/// they are doubles: the 4×4 det[d_i, h_i] expanded along the lift column.
/// The filter's own quantity, with far smaller numbers than the untranslated
/// 5×5 (whose raw coordinates and lifts cancel over many components), so a
/// deposited bed's near-cospherical sets, about one power test in 160, cost
/// a fraction of the full expansion. `None` when a difference is not a double.
fn translated_det_sign_3d(p: &[[f64; 3]; 4], w: &[f64; 4], q: [f64; 3], wq: f64) -> Option<Sign> {
    let d = exact_differences(p, q)?;
    if let Some(s) = dw_det_sign_3d(&d, w, wq) {
        return Some(s);
    }
    let mut acc = Vec::new();
    for i in 0..4 {
        let mut rows = [[0.0; 3]; 3];
        for (n, j) in (0..4).filter(|&j| j != i).enumerate() {
            rows[n] = d[j];
        }
        let minor = exp_compress(&det3_exact(rows[0], rows[1], rows[2]));
        let term = exp_mul(&lift_translated(&d[i], w[i], wq), &minor);
        // Cofactor sign (−1)^(i + 3).
        acc = if i % 2 == 0 {
            exp_sum(&acc, &exp_neg(&term))
        } else {
            exp_sum(&acc, &term)
        };
    }
    Some(exp_sign(&acc))
}

/// [`translated_det_sign_3d`] in 2D: det[d_i, h_i] (3×3) along the lift column.
fn translated_det_sign_2d(p: &[[f64; 2]; 3], w: &[f64; 3], q: [f64; 2], wq: f64) -> Option<Sign> {
    let d = exact_differences(p, q)?;
    if let Some(s) = dw_det_sign_2d(&d, w, wq) {
        return Some(s);
    }
    let mut acc = Vec::new();
    for i in 0..3 {
        let mut rows = [[0.0; 2]; 2];
        for (n, j) in (0..3).filter(|&j| j != i).enumerate() {
            rows[n] = d[j];
        }
        let minor = det2_exact(rows[0], rows[1]);
        let term = exp_mul(&lift_translated(&d[i], w[i], wq), &minor);
        // Cofactor sign (−1)^(i + 2).
        acc = if i % 2 == 0 {
            exp_sum(&acc, &term)
        } else {
            exp_sum(&acc, &exp_neg(&term))
        };
    }
    Some(exp_sign(&acc))
}

/// Exact 5×5 lifted determinant D = Σ_i (-1)^i h_i O_i (rows p0..p3, q), untranslated.
fn power_det_3d_exact(p: &[[f64; 3]; 4], w: &[f64; 4], q: [f64; 3], wq: f64) -> Vec<f64> {
    let pts = [p[0], p[1], p[2], p[3], q];
    let ws = [w[0], w[1], w[2], w[3], wq];
    // det3 of every increasing triple, shared by two minors each.
    let mut tri: Vec<Vec<f64>> = vec![Vec::new(); 125];
    for i in 0..5 {
        for j in i + 1..5 {
            for k in j + 1..5 {
                tri[i * 25 + j * 5 + k] = det3_exact(pts[i], pts[j], pts[k]);
            }
        }
    }
    let t = |i: usize, j: usize, k: usize| &tri[i * 25 + j * 5 + k];
    let mut acc = Vec::new();
    for i in 0..5 {
        let mut o = [0usize; 4];
        for (n, j) in (0..5).filter(|&j| j != i).enumerate() {
            o[n] = j;
        }
        let [a, b, c, d] = o;
        let plus = exp_sum(t(b, c, d), t(a, b, d));
        let minus = exp_sum(t(a, c, d), t(a, b, c));
        let oi = exp_compress(&exp_sum(&plus, &exp_neg(&minus)));
        let hi = exp_compress(&lift_exact(&pts[i], ws[i]));
        let term = exp_mul(&hi, &oi);
        let term = if i % 2 == 0 { term } else { exp_neg(&term) };
        acc = exp_sum(&acc, &term);
    }
    acc
}

/// Exact 4×4 lifted determinant D = Σ_i (-1)^i h_i O_i (rows p0..p2, q), untranslated.
fn power_det_2d_exact(p: &[[f64; 2]; 3], w: &[f64; 3], q: [f64; 2], wq: f64) -> Vec<f64> {
    let pts = [p[0], p[1], p[2], q];
    let ws = [w[0], w[1], w[2], wq];
    let mut acc = Vec::new();
    for i in 0..4 {
        let mut o = [[0.0; 2]; 3];
        let mut n = 0;
        for (j, pt) in pts.iter().enumerate() {
            if j != i {
                o[n] = *pt;
                n += 1;
            }
        }
        let oi = exp_compress(&orient2d_exact(o[0], o[1], o[2]));
        let hi = exp_compress(&lift_exact(&pts[i], ws[i]));
        let term = exp_mul(&hi, &oi);
        let term = if i % 2 == 0 { term } else { exp_neg(&term) };
        acc = exp_sum(&acc, &term);
    }
    acc
}

#[cfg(test)]
mod tests;
