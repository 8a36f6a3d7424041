//! Pore-network geometry of a regular (power) triangulation of spheres (3D) or
//! discs (2D).
//!
//! A pore is a cell of the triangulation (tetrahedron / triangle) whose node is
//! the power centre of its weighted vertices; a throat is a facet shared by two
//! cells (triangle / edge). This module computes, per cell and per throat, the
//! quantities needed by the flow model of Chareyre et al. (2012), as used in
//! Yade's flow engine.
//!
//! Conventions shared by every function:
//! * Inputs are plain `f64` arrays; radii are expected to be `>= 0`.
//! * Every computation is done in a local frame (origin at the first vertex,
//!   lengths divided by the largest offset component) so results do not
//!   depend on the absolute position or scale of the cell beyond rounding,
//!   and tiny or huge cells neither underflow nor overflow in intermediate
//!   products.
//! * No function returns NaN. Degenerate or non-finite inputs give the finite
//!   fallback documented on each function; a true result that exceeds the `f64`
//!   range saturates at `±f64::MAX`.
//! * Sphere/disc "sectors": the part of a vertex sphere inside a tetrahedron is
//!   taken to be the sector `r³ Ω / 3` (Ω = solid angle at that vertex), and in
//!   2D the part of a disc inside a triangle is `½ r² θ`. This is exact when
//!   the sphere does not reach the face opposite its centre (the *sector
//!   condition*); a sphere reaching past it (a sliver, or a large sphere
//!   beside small ones) makes the void an approximation, clamped at zero.
//! * Overlapping spheres (DEM pours, scans) are inclusion–exclusion over the
//!   vertex spheres. Two overlapping vertex spheres `i, j` share a lens that
//!   the sectors subtract twice. The lens is axisymmetric about the line
//!   `c_i c_j`, an edge of the cell, so while it stays within the cell's two
//!   other faces (checked with a ball holding it: centred on the circle where
//!   the spheres meet, of that circle's radius) the part inside the cell is
//!   exactly `V_lens · φ_ij / 2π` (φ_ij the cell's dihedral angle at that
//!   edge), added back. In 2D, and for a throat's facet (the great circles in
//!   its plane), the lens is symmetric about the edge and half of it lies in
//!   the triangle while it stays off the other two edges. The same holds for
//!   a throat region's tetrahedra `(p, c_i, c_j, c_k)`: the lens part
//!   `V_lens · φ / 2π` is added back to its void, and the caps of each sphere
//!   inside the other (`2π r h` each, not a solid–fluid surface) times
//!   `φ / 2π` are taken off its solid surface, so the hydraulic radius sees
//!   the wetted surface only.
//! * Not exact, flagged (`overlap_inexact`) and counted in the summary: three
//!   spheres sharing a point (a triple overlap, about 13 % overlap for equal
//!   spheres), whose common part is left out of the inclusion–exclusion,
//!   and a lens reaching another face (slivers, thin throat regions), whose
//!   wedge share exceeds its part in the cell. Both make the value the
//!   pairwise one, an upper bound on the void when the sectors are exact
//!   (Bonferroni's inequality), clamped to the cell's volume. A centre
//!   inside the other sphere (overlap of a radius or more) has no small lens
//!   on the edge: the sectors alone stand there (a lower bound on the void).
//!   Detection of a triple overlap: the common part of three balls is
//!   symmetric about the plane of their centres, so it is non-empty exactly
//!   when their great discs in that plane share a point, i.e. when a
//!   crossing point of two of the circles lies in the third disc or one disc
//!   lies inside the other two.
//! * The pore body radius and the constriction radius are the tangent
//!   sphere (circle) of the gap the spheres leave, whether or not those
//!   overlap (checked against Newton at 0.1–5 % overlap); circles sharing a
//!   point leave no gap, and the constriction (2D: the pore body) is 0 there
//!   rather than a circle outside them.

use crate::math::v3::{
    add as add3, cross as cross3, dot as dot3, norm as norm3, scale as scale3, sub as sub3,
};

/// Volume (area in 2D) of a cell and its void part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellVolume {
    /// Volume of the tetrahedron (area of the triangle in 2D).
    pub volume: f64,
    /// `volume` minus the vertex sphere sectors (disc sectors in 2D), `>= 0`.
    pub void_volume: f64,
    /// True when the sectors exceeded the cell volume and `void_volume` was
    /// clamped to zero, or when the cell was too degenerate to measure.
    pub clamped: bool,
    /// True when vertex spheres overlap and the void is not exact: three of
    /// them share a point, a lens reaches another face, or a centre lies
    /// inside another sphere (module docs, which give the bound used).
    pub overlap_inexact: bool,
}

/// Geometry of the throat between two pores.
///
/// In 2D every quantity is per unit depth: `fluid_area` is a length,
/// `void_volume` an area and `solid_surface` a length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThroatGeometry {
    /// Distance between the two power centres (the flow merges pores closer
    /// than `flow::LENGTH_FLOOR` of their spheres' mean radius).
    pub length: f64,
    /// Facet area not covered by the vertex spheres' great-circle sectors.
    pub fluid_area: f64,
    /// Void volume of the region spanned by the facet and the two power centres.
    pub void_volume: f64,
    /// Sphere surface inside that region.
    pub solid_surface: f64,
    /// `void_volume / solid_surface`, or 0 when there is no solid surface.
    pub hydraulic_radius: f64,
    /// True when the facet's spheres overlap and a figure above is not exact
    /// (as [`CellVolume::overlap_inexact`], for the facet or either of the
    /// region's tetrahedra).
    pub overlap_inexact: bool,
}

/// Relative tolerance under which a cell (tetrahedron or triangle) is treated
/// as flat: the power centre then lies ~1/FLAT_TOL cell sizes away and
/// carries no useful information.
const FLAT_TOL: f64 = 1e-10;

type V3 = [f64; 3];
type V2 = [f64; 2];

fn sub2(a: V2, b: V2) -> V2 {
    [a[0] - b[0], a[1] - b[1]]
}
fn dot2(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn cross2(a: V2, b: V2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
fn norm2(a: V2) -> f64 {
    dot2(a, a).sqrt()
}

/// Maps NaN to 0 and infinities to `±f64::MAX`, the last line of defence for
/// the "never NaN, always finite" contract.
fn fin(x: f64) -> f64 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(-f64::MAX, f64::MAX)
    }
}

fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Offsets of `pts[1..]` from `pts[0]`, divided by the largest offset
/// component, plus that scale, and the radii `r` in that frame. `None` when an
/// input is not finite or all points coincide, since no frame exists then.
fn framed<const D: usize, const N: usize, const M: usize>(
    pts: &[[f64; D]; N],
    r: &[f64; M],
) -> Option<(f64, [[f64; D]; N], [f64; M])> {
    if !pts.iter().flatten().chain(r).all(|x| x.is_finite()) {
        return None;
    }
    let mut d = [[0.0; D]; N];
    let mut l: f64 = 0.0;
    for (di, p) in d.iter_mut().zip(pts) {
        for (x, (a, o)) in di.iter_mut().zip(p.iter().zip(&pts[0])) {
            *x = a - o;
        }
        // Max-norm: a Euclidean norm would square, and underflow or overflow
        // at the very scales this frame exists to handle.
        l = di.iter().fold(l, |m, x| m.max(x.abs()));
    }
    if !(l.is_finite() && l > 0.0) {
        return None;
    }
    // 3D scales by the reciprocal and 2D divides, as each did before the two
    // shared this code: the pore files stay byte-identical across versions.
    let inv = 1.0 / l;
    for x in d.iter_mut().flatten() {
        *x = if D == 3 { *x * inv } else { *x / l };
    }
    Some((l, d, r.map(|x| x / l)))
}

/// For a cell with vertex offsets `d` (vertex 0 at the origin) and radii `r`,
/// returns `(q, w)` with `2 d_i·q = |d_i|² − r_i² + r_0²` (q = power centre)
/// and `d_i·w = r_0 − r_i`. Any point `y` with `|y − d_i| − r_i` equal for all
/// i and equal to `|y| − r_0 = ρ` satisfies `y = q + ρ w`: subtracting the
/// squared tangency equations cancels the quadratic terms.
fn power_and_slope_3d(d: &[V3; 3], r: &[f64; 4]) -> Option<(V3, V3)> {
    let det = dot3(d[0], cross3(d[1], d[2]));
    let size = norm3(d[0]) * norm3(d[1]) * norm3(d[2]);
    if det.abs() <= FLAT_TOL * size {
        return None;
    }
    // Cramer's rule through the cofactor rows of the matrix with rows d_i.
    let cof = [cross3(d[1], d[2]), cross3(d[2], d[0]), cross3(d[0], d[1])];
    let solve = |rhs: [f64; 3]| -> V3 {
        let mut x = [0.0; 3];
        for (ci, bi) in cof.iter().zip(rhs) {
            x = add3(x, scale3(*ci, bi));
        }
        scale3(x, 1.0 / det)
    };
    let mut rq = [0.0; 3];
    let mut rw = [0.0; 3];
    for i in 0..3 {
        rq[i] = 0.5 * (dot3(d[i], d[i]) - (r[i + 1] - r[0]) * (r[i + 1] + r[0]));
        rw[i] = r[0] - r[i + 1];
    }
    Some((solve(rq), solve(rw)))
}

fn power_and_slope_2d(d: &[V2; 2], r: &[f64; 3]) -> Option<(V2, V2)> {
    let det = cross2(d[0], d[1]);
    let size = norm2(d[0]) * norm2(d[1]);
    if det.abs() <= FLAT_TOL * size {
        return None;
    }
    let solve = |b: [f64; 2]| -> V2 {
        [
            (b[0] * d[1][1] - b[1] * d[0][1]) / det,
            (d[0][0] * b[1] - d[1][0] * b[0]) / det,
        ]
    };
    let rq = [
        0.5 * (dot2(d[0], d[0]) - (r[1] - r[0]) * (r[1] + r[0])),
        0.5 * (dot2(d[1], d[1]) - (r[2] - r[0]) * (r[2] + r[0])),
    ];
    let rw = [r[0] - r[1], r[0] - r[2]];
    Some((solve(rq), solve(rw)))
}

/// Smallest strictly positive real root of `a x² + b x + c`, using the
/// cancellation-free form of the quadratic formula. A slightly negative
/// discriminant is rounding noise around a double root and is treated as zero.
fn smallest_positive_root(a: f64, b: f64, c: f64) -> Option<f64> {
    let mut disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        if disc >= -1e-12 * (b * b + (4.0 * a * c).abs()) {
            disc = 0.0;
        } else {
            return None;
        }
    }
    let qq = -0.5 * (b + disc.sqrt().copysign(b));
    let r1 = (qq != 0.0).then(|| c / qq);
    let r2 = (a != 0.0).then(|| qq / a);
    [r1, r2]
        .into_iter()
        .flatten()
        .filter(|x| x.is_finite() && *x > 0.0)
        .fold(None, |best: Option<f64>, x| {
            Some(best.map_or(x, |b| b.min(x)))
        })
}

/// `(|q| − r0)(|q| + r0)`: the power of the power centre, factored so that it
/// stays accurate when the orthogonal sphere is tiny.
fn power_value(qn: f64, r0: f64) -> f64 {
    (qn - r0) * (qn + r0)
}

/// Radius of the circle tangent externally to the circles `(0, r0)`,
/// `(d0, r1)`, `(d1, r2)` in frame units; 0 when there is none.
fn apollonius_2d_scaled(d: &[V2; 2], r: &[f64; 3]) -> f64 {
    let Some((q, w)) = power_and_slope_2d(d, r) else {
        return 0.0;
    };
    let a = dot2(w, w) - 1.0;
    let b = 2.0 * (dot2(q, w) - r[0]);
    let c = power_value(norm2(q), r[0]);
    smallest_positive_root(a, b, c).unwrap_or(0.0)
}

/// Solid angle subtended at the origin by the triangle `(a, b, c)`
/// (Van Oosterom & Strackee 1983), in `[0, 2π]`. The atan2 form keeps the
/// correct branch for angles above π, where the plain atan form would wrap.
fn solid_angle(a: V3, b: V3, c: V3) -> f64 {
    let (la, lb, lc) = (norm3(a), norm3(b), norm3(c));
    let num = dot3(a, cross3(b, c)).abs();
    let den = la * lb * lc + dot3(a, b) * lc + dot3(a, c) * lb + dot3(b, c) * la;
    2.0 * num.atan2(den)
}

/// Angle between two 2D vectors in `[0, π]`; atan2 rather than acos because
/// acos loses all precision near 0 and π.
fn angle2(u: V2, v: V2) -> f64 {
    cross2(u, v).abs().atan2(dot2(u, v))
}

fn angle3(u: V3, v: V3) -> f64 {
    norm3(cross3(u, v)).atan2(dot3(u, v))
}

/// Heights of the caps that two overlapping balls (radii `a`, `b`, centres
/// `d` apart) cut from each other: `(h_a, h_b)`, `h_a` the depth of ball `a`
/// inside ball `b`. `None` when they do not overlap (or a radius is 0). A ball
/// inside the other is all cap (`h = 2r`, the other's 0). The heights are
/// `ov (b + d − a) / 2d` with `ov = a + b − d` taken first, so that a tiny
/// overlap loses no digits to cancellation.
fn cap_heights(a: f64, b: f64, d: f64) -> Option<(f64, f64)> {
    let ov = a + b - d;
    if !(a > 0.0 && b > 0.0 && ov > 0.0 && d.is_finite()) {
        return None;
    }
    if d + a <= b {
        return Some((2.0 * a, 0.0));
    }
    if d + b <= a {
        return Some((0.0, 2.0 * b));
    }
    Some((ov * (b + d - a) / (2.0 * d), ov * (a + d - b) / (2.0 * d)))
}

/// Lens of two overlapping balls from [`cap_heights`]: its volume and the
/// areas of the two spherical caps bounding it (`2π r h` each: the surface
/// of each sphere inside the other).
fn lens_3d(a: f64, b: f64, (ha, hb): (f64, f64)) -> (f64, f64, f64) {
    let cap = |r: f64, h: f64| std::f64::consts::PI * h * h * (3.0 * r - h) / 3.0;
    let tau = 2.0 * std::f64::consts::PI;
    (cap(a, ha) + cap(b, hb), tau * a * ha, tau * b * hb)
}

/// `α − sin α cos α`: a circular segment of half-angle α over `r²`. Its
/// series below 0.05 (error under 2e-15 relative), where the difference
/// would lose `1/α²` of its digits.
fn segment(alpha: f64) -> f64 {
    if alpha < 0.05 {
        let a2 = alpha * alpha;
        alpha * a2 * (2.0 / 3.0 - a2 * (2.0 / 15.0 - a2 * (4.0 / 315.0 - a2 * 2.0 / 2835.0)))
    } else {
        alpha - 0.5 * (2.0 * alpha).sin()
    }
}

/// Lens of two overlapping discs from [`cap_heights`]: its area and the
/// lengths of the two arcs bounding it (`2 r α` each: the circle of each
/// disc inside the other).
fn lens_2d(a: f64, b: f64, (ha, hb): (f64, f64)) -> (f64, f64, f64) {
    // Half-angle of the chord seen from the centre; π for a disc inside.
    let half = |r: f64, h: f64| (h * (2.0 * r - h)).max(0.0).sqrt().atan2(r - h);
    let (alpha, beta) = (half(a, ha), half(b, hb));
    (
        a * a * segment(alpha) + b * b * segment(beta),
        2.0 * a * alpha,
        2.0 * b * beta,
    )
}

/// True when the three discs `(c_i, r_i)` share a point (closed discs, but
/// a single touching point does not count): a crossing point of two circles
/// lies inside the third disc, or one disc lies inside the other two (see
/// the module docs).
fn discs_share_a_point(c: &[V2; 3], r: &[f64; 3]) -> bool {
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let inside = |a: usize, b: usize| norm2(sub2(c[a], c[b])) + r[a] <= r[b];
        if r[i] > 0.0 && inside(i, j) && inside(i, k) {
            return true;
        }
        let e = sub2(c[j], c[i]);
        let d = norm2(e);
        let Some((hi, _)) = cap_heights(r[i], r[j], d) else {
            continue;
        };
        if d == 0.0 {
            continue;
        }
        let u = [e[0] / d, e[1] / d];
        let x = r[i] - hi;
        let y = (hi * (2.0 * r[i] - hi)).max(0.0).sqrt();
        for s in [-1.0, 1.0] {
            let p = [
                c[i][0] + x * u[0] - s * y * u[1],
                c[i][1] + x * u[1] + s * y * u[0],
            ];
            if norm2(sub2(p, c[k])) < r[k] {
                return true;
            }
        }
    }
    false
}

/// The three points in a frame of their own plane (`a` at the origin, `b`
/// on the first axis); `None` when `a` and `b` coincide.
fn in_plane(a: V3, b: V3, c: V3) -> Option<[V2; 3]> {
    let ab = sub3(b, a);
    let n1 = norm3(ab);
    // A norm: 0 or NaN is all that can fail here.
    if n1 == 0.0 || !n1.is_finite() {
        return None;
    }
    let e1 = scale3(ab, 1.0 / n1);
    let ac = sub3(c, a);
    let x = dot3(ac, e1);
    let y = norm3(sub3(ac, scale3(e1, x)));
    Some([[0.0, 0.0], [n1, 0.0], [x, y]])
}

/// True when the balls at `a, b, c` share a point: their common part is
/// symmetric about the plane of the centres, so it meets that plane, where
/// the balls are their great discs. Coincident centres count as sharing.
fn balls_share_a_point(a: V3, b: V3, c: V3, r: [f64; 3]) -> bool {
    let ordered = in_plane(a, b, c)
        .or_else(|| in_plane(b, c, a).map(|p| [p[2], p[0], p[1]]))
        .or_else(|| in_plane(c, a, b).map(|p| [p[1], p[2], p[0]]));
    match ordered {
        Some(p) => discs_share_a_point(&p, &r),
        None => r.iter().all(|&x| x > 0.0),
    }
}

/// Dihedral angle at the edge `a → b` between the half-planes through `u`
/// and through `v`.
pub fn dihedral(a: V3, b: V3, u: V3, v: V3) -> f64 {
    let e = sub3(b, a);
    angle3(cross3(e, sub3(u, a)), cross3(e, sub3(v, a)))
}

/// Power centre of four weighted points (weights `r²`): the point `p` with
/// `|p − c_i|² − r_i²` equal for all i, and that common value (the squared
/// radius of the orthogonal sphere, negative when `p` lies inside all spheres).
///
/// `None` when the centres are (nearly) coplanar (relative volume below
/// `1e-10`), when two or more of them coincide so that they span no volume,
/// or when an input is not finite.
pub fn power_centre_3d(c: &[[f64; 3]; 4], r: &[f64; 4]) -> Option<([f64; 3], f64)> {
    let (l, d, rs) = framed(c, r)?;
    let (q, _) = power_and_slope_3d(&[d[1], d[2], d[3]], &rs)?;
    let p = add3(c[0], scale3(q, l)).map(fin);
    Some((p, fin(power_value(norm3(q), rs[0]) * l * l)))
}

/// 2D analogue of [`power_centre_3d`] for three weighted points; `None` when
/// the centres are (nearly) collinear or an input is not finite.
pub fn power_centre_2d(c: &[[f64; 2]; 3], r: &[f64; 3]) -> Option<([f64; 2], f64)> {
    let (l, d, rs) = framed(c, r)?;
    let (q, _) = power_and_slope_2d(&[d[1], d[2]], &rs)?;
    let p = [fin(c[0][0] + q[0] * l), fin(c[0][1] + q[1] * l)];
    Some((p, fin(power_value(norm2(q), rs[0]) * l * l)))
}

/// Pore body radius: radius ρ of the sphere externally tangent to the four
/// vertex spheres (`|x − c_i| = ρ + r_i`, Apollonius' problem).
///
/// The centre is `x = p + ρ w` (see [`power_centre_3d`]), leaving a quadratic
/// in ρ. Of its roots the smallest strictly positive one is returned: in a
/// well-shaped cell that is the sphere filling the gap between the four
/// spheres, while a second positive root is a larger sphere touching them
/// from outside the cell. Returns 0.0 when no root is positive (the spheres
/// overlap enough to close the pore), when the cell is flat (see
/// [`power_centre_3d`]), or when an input is not finite.
pub fn pore_body_radius_3d(c: &[[f64; 3]; 4], r: &[f64; 4]) -> f64 {
    let Some((l, d, rs)) = framed(c, r) else {
        return 0.0;
    };
    let Some((q, w)) = power_and_slope_3d(&[d[1], d[2], d[3]], &rs) else {
        return 0.0;
    };
    let a = dot3(w, w) - 1.0;
    let b = 2.0 * (dot3(q, w) - rs[0]);
    let cc = power_value(norm3(q), rs[0]);
    fin(smallest_positive_root(a, b, cc).unwrap_or(0.0) * l)
}

/// 2D pore body radius: the circle externally tangent to the three discs, with
/// the same root rule and fallbacks as [`pore_body_radius_3d`] (0.0 for
/// collinear centres or no positive root).
pub fn pore_body_radius_2d(c: &[[f64; 2]; 3], r: &[f64; 3]) -> f64 {
    let Some((l, d, rs)) = framed(c, r) else {
        return 0.0;
    };
    // Discs sharing a point leave no gap between them (see
    // [`constriction_radius_3d`]).
    if discs_share_a_point(&d, &rs) {
        return 0.0;
    }
    fin(apollonius_2d_scaled(&[d[1], d[2]], &rs) * l)
}

/// Volume of the tetrahedron and its void volume,
/// `volume − Σ r_i³ Ω_i / 3 + Σ V_lens,ij φ_ij / 2π` (the sectors and, for each pair of overlapping
/// vertex spheres, the part of their lens inside the cell, counted twice by
/// the sectors; module docs), clamped to `[0, volume]` with `clamped = true`
/// when it fell below 0.
///
/// A flat cell has zero volume and its void is clamped (unless all radii are
/// zero). Coincident centres or non-finite inputs give
/// `{ volume: 0, void_volume: 0, clamped: true }`.
pub fn cell_volumes_3d(c: &[[f64; 3]; 4], r: &[f64; 4]) -> CellVolume {
    const DEGENERATE: CellVolume = CellVolume {
        volume: 0.0,
        void_volume: 0.0,
        clamped: true,
        overlap_inexact: false,
    };
    let Some((l, d, rs)) = framed(c, r) else {
        return DEGENERATE;
    };
    let det = dot3(d[1], cross3(d[2], d[3])).abs();
    let volume = det / 6.0;
    let mut sectors = 0.0;
    for (i, [j, k, m]) in [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]]
        .into_iter()
        .enumerate()
    {
        let om = solid_angle(sub3(d[j], d[i]), sub3(d[k], d[i]), sub3(d[m], d[i]));
        sectors += rs[i].powi(3) * om / 3.0;
    }
    let (lenses, inexact) = cell_lenses_3d(&d, &rs);
    let void = volume - sectors + lenses;
    let l3 = l * l * l;
    CellVolume {
        volume: fin(volume * l3),
        void_volume: fin(void.clamp(0.0, volume) * l3),
        clamped: void < 0.0,
        overlap_inexact: inexact,
    }
}

/// The lens parts inside the tetrahedron `d` (frame units, `det` six times
/// its volume) of its overlapping vertex spheres, and whether they are
/// inexact (module docs: a lens reaching another face, three spheres sharing
/// a point, or a centre inside another sphere). `(0, false)` when no two
/// spheres overlap.
fn cell_lenses_3d(d: &[V3; 4], rs: &[f64; 4]) -> (f64, bool) {
    const EDGES: [[usize; 4]; 6] = [
        [0, 1, 2, 3],
        [0, 2, 1, 3],
        [0, 3, 1, 2],
        [1, 2, 0, 3],
        [1, 3, 0, 2],
        [2, 3, 0, 1],
    ];
    let mut lenses = 0.0;
    let mut overlaps = [[false; 4]; 4];
    let mut any = false;
    let mut inexact = false;
    for [i, j, k, m] in EDGES {
        let Some(h) = cap_heights(rs[i], rs[j], norm3(sub3(d[j], d[i]))) else {
            continue;
        };
        any = true;
        overlaps[i][j] = true;
        overlaps[j][i] = true;
        match lens_ball(d[i], rs[i], d[j], rs[j], h) {
            Some(ball) => {
                // The faces opposite i and j: (j, k, m) and (i, k, m).
                inexact |=
                    crosses_plane(ball, d[j], d[k], d[m]) || crosses_plane(ball, d[i], d[k], d[m]);
            }
            None => return (0.0, true),
        }
        let phi = dihedral(d[i], d[j], d[k], d[m]);
        lenses += lens_3d(rs[i], rs[j], h).0 * phi / (2.0 * std::f64::consts::PI);
    }
    if !any {
        return (0.0, false);
    }
    // A face whose three spheres share a point (needs all its pairs).
    let triple = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]]
        .into_iter()
        .any(|[j, k, m]| {
            overlaps[j][k]
                && overlaps[k][m]
                && overlaps[j][m]
                && balls_share_a_point(d[j], d[k], d[m], [rs[j], rs[k], rs[m]])
        });
    (lenses, inexact || triple)
}

/// A ball holding the lens of two overlapping spheres: centred on the
/// circle where their surfaces meet, with that circle's radius (each cap is
/// at most a hemisphere, so its points lie within the rim's distance).
/// `None` when a centre lies inside the other sphere: the lens is then no
/// small blob on the edge, and the sectors alone stand.
fn lens_ball<const D: usize>(
    ci: [f64; D],
    ri: f64,
    cj: [f64; D],
    rj: f64,
    (hi, hj): (f64, f64),
) -> Option<([f64; D], f64)> {
    let mut dist = 0.0;
    for a in 0..D {
        dist += (cj[a] - ci[a]) * (cj[a] - ci[a]);
    }
    let dist = dist.sqrt();
    if !(dist > ri.max(rj) && hi <= ri && hj <= rj) {
        return None;
    }
    let t = (ri - hi) / dist;
    let m = std::array::from_fn(|a| ci[a] + t * (cj[a] - ci[a]));
    Some((m, (hi * (2.0 * ri - hi)).max(0.0).sqrt()))
}

/// True when the ball reaches across the plane through `a, b, c`.
fn crosses_plane((m, rho): (V3, f64), a: V3, b: V3, c: V3) -> bool {
    let n = cross3(sub3(b, a), sub3(c, a));
    dot3(n, sub3(m, a)).abs() < rho * norm3(n)
}

/// True when the disc reaches across the line through `a, b`.
fn crosses_line((m, rho): (V2, f64), a: V2, b: V2) -> bool {
    let e = sub2(b, a);
    cross2(e, sub2(m, a)).abs() < rho * norm2(e)
}

/// Area of the triangle and its void area, `area − Σ ½ r_i² θ_i` with θ_i
/// the triangle's angle at vertex i, clamped at 0 with `clamped = true`.
/// Fallbacks as in [`cell_volumes_3d`].
pub fn cell_volumes_2d(c: &[[f64; 2]; 3], r: &[f64; 3]) -> CellVolume {
    const DEGENERATE: CellVolume = CellVolume {
        volume: 0.0,
        void_volume: 0.0,
        clamped: true,
        overlap_inexact: false,
    };
    let Some((l, d, rs)) = framed(c, r) else {
        return DEGENERATE;
    };
    let twice = cross2(d[1], d[2]).abs();
    let area = twice / 2.0;
    let mut sectors = 0.0;
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        sectors += 0.5 * rs[i] * rs[i] * angle2(sub2(d[j], d[i]), sub2(d[k], d[i]));
    }
    let (lenses, inexact) = triangle_lenses(&d, &rs);
    let void = area - sectors + lenses;
    let l2 = l * l;
    CellVolume {
        volume: fin(area * l2),
        void_volume: fin(void.clamp(0.0, area) * l2),
        clamped: void < 0.0,
        overlap_inexact: inexact,
    }
}

/// The lens halves inside the triangle `d` of its overlapping discs, and
/// whether they are inexact (module docs: a lens reaching another edge,
/// three discs sharing a point, or a centre inside another disc). `(0,
/// false)` when no two discs overlap.
fn triangle_lenses(d: &[V2; 3], rs: &[f64; 3]) -> (f64, bool) {
    let mut lenses = 0.0;
    let mut any = false;
    let mut inexact = false;
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let Some(h) = cap_heights(rs[i], rs[j], norm2(sub2(d[j], d[i]))) else {
            continue;
        };
        any = true;
        match lens_ball(d[i], rs[i], d[j], rs[j], h) {
            // The edges opposite i and j.
            Some(disc) => {
                inexact |= crosses_line(disc, d[j], d[k]) || crosses_line(disc, d[i], d[k]);
            }
            None => return (0.0, true),
        }
        lenses += 0.5 * lens_2d(rs[i], rs[j], h).0;
    }
    if !any {
        return (0.0, false);
    }
    (lenses, inexact || discs_share_a_point(d, rs))
}

/// Constriction radius of a throat facet with vertex spheres `(c_i, r_i)`:
/// the circle in the facet plane externally tangent to the three great
/// circles, i.e. the 2D Apollonius problem in that plane, with the
/// smallest-positive-root rule of [`pore_body_radius_3d`].
///
/// Returns 0.0 when no root is positive or the three circles share a point
/// (the spheres close the throat), when
/// the centres are (nearly) collinear, or when an input is not finite.
pub fn constriction_radius_3d(c: &[[f64; 3]; 3], r: &[f64; 3]) -> f64 {
    let Some((l, d, rs)) = framed(c, r) else {
        return 0.0;
    };
    // In-plane orthonormal basis (e1 along d1); the 2D solver rejects
    // near-collinear triangles, so only exact degeneracy needs a guard here.
    let n1 = norm3(d[1]);
    if n1 == 0.0 {
        return 0.0;
    }
    let e1 = scale3(d[1], 1.0 / n1);
    let x2 = dot3(d[2], e1);
    let y2 = norm3(sub3(d[2], scale3(e1, x2)));
    if y2 == 0.0 {
        return 0.0;
    }
    let plane = [[0.0, 0.0], [n1, 0.0], [x2, y2]];
    // Circles sharing a point close the throat: a positive root there is a
    // circle outside them, not a constriction.
    if discs_share_a_point(&plane, &rs) {
        return 0.0;
    }
    fin(apollonius_2d_scaled(&[plane[1], plane[2]], &rs) * l)
}

/// 2D constriction: half the gap between the two discs,
/// `(|c_0 − c_1| − r_0 − r_1) / 2`, clamped at 0 when they touch or overlap
/// (and 0.0 for non-finite inputs).
pub fn constriction_radius_2d(c: &[[f64; 2]; 2], r: &[f64; 2]) -> f64 {
    let Some((l, d, rs)) = framed(c, r) else {
        // Coincident centres: the discs overlap unless both radii are 0,
        // and then the gap is 0 as well.
        return 0.0;
    };
    fin((0.5 * (norm2(d[1]) - rs[0] - rs[1])).max(0.0) * l)
}

/// Totals of one tetrahedron (triangle in 2D) of the throat region, in frame
/// units, already multiplied by its side sign.
#[derive(Clone, Copy)]
struct RegionTotals {
    volume: f64,
    /// The sectors less the overlaps' lens parts: the solid volume.
    sectors: f64,
    /// The sphere surface less the caps inside other spheres.
    surface: f64,
    /// An overlap term is not exact (module docs).
    inexact: bool,
}

impl RegionTotals {
    const ZERO: RegionTotals = RegionTotals {
        volume: 0.0,
        sectors: 0.0,
        surface: 0.0,
        inexact: false,
    };

    /// `self − other`, taken as one subtraction per field so that swapping the
    /// two power centres negates the totals exactly and the throat is
    /// bit-for-bit symmetric.
    fn minus(self, other: RegionTotals) -> RegionTotals {
        RegionTotals {
            volume: self.volume - other.volume,
            sectors: self.sectors - other.sectors,
            surface: self.surface - other.surface,
            inexact: self.inexact || other.inexact,
        }
    }
}

/// Combines the per-side totals and applies the module's sign rule; see
/// [`throat_3d`].
fn finish_throat(
    t: RegionTotals,
    length: f64,
    fluid_area: f64,
    l: f64,
    dim: i32,
) -> ThroatGeometry {
    // Orient the region so its volume is non-negative; then the void and the
    // solid surface are the oriented totals, clamped at 0. A region whose
    // signed volume cancels exactly is oriented by its surface instead, so the
    // result stays symmetric in p1, p2.
    let key = if t.volume != 0.0 { t.volume } else { t.surface };
    let orient = if key >= 0.0 { 1.0 } else { -1.0 };
    let void = (orient * (t.volume - t.sectors)).max(0.0);
    let surface = (orient * t.surface).max(0.0);
    let rh = if surface > 0.0 { void / surface } else { 0.0 };
    let rh = if rh.is_finite() { rh } else { 0.0 };
    ThroatGeometry {
        length: fin(length * l),
        fluid_area: fin(fluid_area * l.powi(dim - 1)),
        void_volume: fin(void * l.powi(dim)),
        solid_surface: fin(surface * l.powi(dim - 1)),
        hydraulic_radius: fin(rh * l),
        overlap_inexact: t.inexact,
    }
}

const DEGENERATE_THROAT: ThroatGeometry = ThroatGeometry {
    length: 0.0,
    fluid_area: 0.0,
    void_volume: 0.0,
    solid_surface: 0.0,
    hydraulic_radius: 0.0,
    overlap_inexact: false,
};

/// ThroatGeometry between pores with power centres `p1`, `p2` through the facet with
/// vertex spheres `(c_v, r_v)`, v = 0, 1, 2 (Chareyre et al. 2012).
///
/// * `length = |p1 − p2|`.
/// * `fluid_area` = facet triangle area − Σ ½ r_v² θ_v (θ_v the triangle's
///   angle at c_v), clamped at 0.
/// * The region is made of the tetrahedra `T1 = (p1, c_0, c_1, c_2)` and
///   `T2 = (p2, c_0, c_1, c_2)`. Each contributes its volume `V_t`, its sphere
///   sectors `Σ r_v³ Ω_v / 3` and its solid surface `Σ r_v² Ω_v`.
///
/// Sign rule: with `n = (c_1 − c_0) × (c_2 − c_0)` and `s_t = sign(n·(p_t − c_0))`
/// the side of the facet each power centre is on, every quantity is totalled
/// as `X = s_1 X(T1) − s_2 X(T2)`. When `p1` and `p2` are on opposite sides this
/// is `±(X(T1) + X(T2))`, the union; on the same side it is `±(X(T1) − X(T2))`,
/// the difference (the region between two power centres of which one lies
/// outside its own cell). The overall sign is then fixed so that the region
/// volume is non-negative (by the surface if the volume cancels exactly), and
/// `void_volume = max(±(V − sectors), 0)`,
/// `solid_surface = max(±surface, 0)`. This equals the absolute values of the
/// totals whenever the oriented void and surface are non-negative, which holds
/// for opposite sides and for nested same-side tetrahedra as long as the
/// sector assumption holds; a negative oriented void means the sectors
/// over-cover the region, and 0 is a better answer there than its magnitude. The result is symmetric in `p1`, `p2`. A power centre exactly in the
/// facet plane (`s_t = 0`) spans a flat tetrahedron and contributes nothing.
///
/// `hydraulic_radius = void_volume / solid_surface`, or 0.0 when there is no
/// solid surface (zero radii or a flat region). A collinear facet gives zero
/// area and no side, hence zero volume/surface. Non-finite inputs or all
/// points coincident give an all-zero throat.
pub fn throat_3d(p1: [f64; 3], p2: [f64; 3], c: &[[f64; 3]; 3], r: &[f64; 3]) -> ThroatGeometry {
    let Some((l, d, rs)) = framed(&[c[0], c[1], c[2], p1, p2], r) else {
        return DEGENERATE_THROAT;
    };
    let f = [d[0], d[1], d[2]];
    let n = cross3(f[1], f[2]);
    let collinear = norm3(n) <= FLAT_TOL * norm3(f[1]) * norm3(f[2]);

    let twice = norm3(n);
    let mut fluid = 0.5 * twice;
    for v in 0..3 {
        let (j, k) = ((v + 1) % 3, (v + 2) % 3);
        fluid -= 0.5 * rs[v] * rs[v] * angle3(sub3(f[j], f[v]), sub3(f[k], f[v]));
    }
    // Overlapping spheres: each pair's lens (volume, its two caps) with the
    // third vertex of the facet, and the facet's own lens halves.
    type Lens = (usize, usize, usize, (f64, f64, f64), (f64, f64));
    let mut lenses: [Option<Lens>; 3] = [None; 3];
    for (slot, (v, w, u)) in [(0, 1, 2), (1, 2, 0), (0, 2, 1)].into_iter().enumerate() {
        if let Some(h) = cap_heights(rs[v], rs[w], norm3(sub3(f[w], f[v]))) {
            lenses[slot] = Some((v, w, u, lens_3d(rs[v], rs[w], h), h));
        }
    }
    let overlaps = lenses.iter().any(Option::is_some);
    let mut facet_inexact = false;
    if overlaps && !collinear {
        if let Some(plane) = in_plane(f[0], f[1], f[2]) {
            let (halves, inexact) = triangle_lenses(&plane, &[rs[0], rs[1], rs[2]]);
            fluid += halves;
            facet_inexact = inexact;
        }
    }
    let fluid = if collinear {
        0.0
    } else {
        fluid.clamp(0.0, 0.5 * twice)
    };

    let side = |p: V3| -> RegionTotals {
        let h = dot3(n, p);
        let s = if collinear { 0.0 } else { sign(h) };
        let mut t = RegionTotals::ZERO;
        if s == 0.0 {
            return t;
        }
        t.volume = s * h.abs() / 6.0;
        for v in 0..3 {
            let (j, k) = ((v + 1) % 3, (v + 2) % 3);
            let om = solid_angle(sub3(p, f[v]), sub3(f[j], f[v]), sub3(f[k], f[v]));
            t.sectors += s * rs[v].powi(3) * om / 3.0;
            t.surface += s * rs[v] * rs[v] * om;
        }
        if !overlaps {
            return t;
        }
        // The lens of c_v, c_w is axisymmetric about their edge: the part in
        // (p, c_0, c_1, c_2) is its share φ / 2π of the dihedral angle there,
        // exact while it stays off the faces opposite c_v and c_w.
        t.inexact = facet_inexact;
        for &(v, w, u, (vol, cap_v, cap_w), h) in lenses.iter().flatten() {
            let Some(ball) = lens_ball(f[v], rs[v], f[w], rs[w], h) else {
                t.inexact = true;
                continue;
            };
            t.inexact |= crosses_plane(ball, p, f[w], f[u]) || crosses_plane(ball, p, f[v], f[u]);
            let share = dihedral(f[v], f[w], f[u], p) / (2.0 * std::f64::consts::PI);
            t.sectors -= s * vol * share;
            t.surface -= s * (cap_v + cap_w) * share;
        }
        t
    };
    let t = side(d[3]).minus(side(d[4]));
    finish_throat(t, norm3(sub3(d[3], d[4])), fluid, l, 3)
}

/// 2D analogue of [`throat_3d`] (per unit depth) for the edge `(c_0, c_1)`:
/// `fluid_area` is the gap length `|c_0 − c_1| − r_0 − r_1` clamped at 0; the
/// region is the triangles `(p_t, c_0, c_1)` with disc sectors `½ r² θ` and
/// solid perimeter `Σ r θ`; same sign rule (side of the line through the
/// edge), same fallbacks.
pub fn throat_2d(p1: [f64; 2], p2: [f64; 2], c: &[[f64; 2]; 2], r: &[f64; 2]) -> ThroatGeometry {
    let Some((l, d, rs)) = framed(&[c[0], c[1], p1, p2], r) else {
        return DEGENERATE_THROAT;
    };
    let e = d[1];
    let fluid = (norm2(e) - rs[0] - rs[1]).max(0.0);
    let lens = cap_heights(rs[0], rs[1], norm2(e)).map(|h| (h, lens_2d(rs[0], rs[1], h)));
    let side = |p: V2| -> RegionTotals {
        let h = cross2(e, p);
        let s = sign(h);
        let mut t = RegionTotals::ZERO;
        if s == 0.0 {
            return t;
        }
        t.volume = s * h.abs() / 2.0;
        let th0 = angle2(p, e);
        let th1 = angle2(sub2(p, e), [-e[0], -e[1]]);
        t.sectors = s * 0.5 * (rs[0] * rs[0] * th0 + rs[1] * rs[1] * th1);
        t.surface = s * (rs[0] * th0 + rs[1] * th1);
        if let Some((hh, (area, arc0, arc1))) = lens {
            // Overlapping discs: half their lens, symmetric about the edge,
            // lies on this side, exactly while it stays off the triangle's
            // other two edges.
            match lens_ball([0.0, 0.0], rs[0], e, rs[1], hh) {
                Some(disc) => {
                    t.inexact = crosses_line(disc, p, e) || crosses_line(disc, p, [0.0, 0.0]);
                    t.sectors -= s * 0.5 * area;
                    t.surface -= s * 0.5 * (arc0 + arc1);
                }
                None => t.inexact = true,
            }
        }
        t
    };
    let t = side(d[2]).minus(side(d[3]));
    finish_throat(t, norm2(sub2(d[2], d[3])), fluid, l, 2)
}

/// Hydraulic conductance of a throat, `g = A ℓ² / (2 μ L)` with `ℓ` the
/// throat's hydraulic radius (Chareyre et al. 2012) or its constriction
/// radius (`config::Conductance`); per unit depth in 2D.
///
/// The caller is expected to floor `length`; a non-positive or non-finite
/// `length` or `viscosity` is treated as an invalid throat and gives 0.0.
pub fn conductance(fluid_area: f64, radius: f64, length: f64, viscosity: f64) -> f64 {
    if !(length > 0.0 && length.is_finite() && viscosity > 0.0 && viscosity.is_finite()) {
        return 0.0;
    }
    fin(fluid_area * radius * radius / (2.0 * viscosity * length))
}

#[cfg(test)]
mod tests;
