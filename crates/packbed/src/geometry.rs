//! Exact geometry of the moving centre: inflated obstacles (balls and planes), the
//! circles it rolls along, first events on a circle, and points where `D` surfaces
//! meet. All closed form: no stepping.

use crate::math::{Real, Vector};
#[cfg(test)]
use std::f64::consts::TAU;

/// A surface the moving centre must stay outside of: a fixed sphere inflated by
/// the moving radius (`|p − c| ≥ R`), or a plane (`n · p ≥ h`: floor, side wall).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface<const D: usize> {
    /// An inflated sphere.
    Ball {
        /// Centre (periodic image already applied).
        centre: Vector<D>,
        /// Inflated radius `r_fixed + r_moving`.
        radius: Real,
    },
    /// A plane with unit normal pointing into the free side.
    Plane {
        /// Unit normal.
        normal: Vector<D>,
        /// Offset: the plane is `normal · p = offset`.
        offset: Real,
    },
}

impl<const D: usize> Surface<D> {
    /// Signed distance of `p` from the surface (positive on the free side).
    #[inline]
    pub fn gap(&self, p: &Vector<D>) -> Real {
        match self {
            Surface::Ball { centre, radius } => (*p - *centre).norm() - radius,
            Surface::Plane { normal, offset } => normal.dot(p) - offset,
        }
    }

    /// Unit normal of the surface at (or nearest to) `p`, pointing to the free side.
    #[inline]
    pub fn normal_at(&self, p: &Vector<D>) -> Vector<D> {
        match self {
            Surface::Ball { centre, .. } => (*p - *centre).normalized().unwrap_or_else(Vector::up),
            Surface::Plane { normal, .. } => *normal,
        }
    }

    /// True for a sphere.
    #[inline]
    pub fn is_ball(&self) -> bool {
        matches!(self, Surface::Ball { .. })
    }
}

/// A circle `p(t) = m + ρ (u cos t + v sin t)` travelled from `t = 0`.
#[derive(Clone, Copy, Debug)]
pub struct Arc<const D: usize> {
    /// Centre of the circle.
    pub m: Vector<D>,
    /// Radius of the circle.
    pub rho: Real,
    /// Unit vector from `m` to the start point.
    pub u: Vector<D>,
    /// Unit tangent at the start, the direction of travel.
    pub v: Vector<D>,
}

/// A trigonometric function `a cos t + b sin t + c` of the arc parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trig {
    /// Coefficient of `cos t`.
    pub a: Real,
    /// Coefficient of `sin t`.
    pub b: Real,
    /// Constant term.
    pub c: Real,
}

impl<const D: usize> Arc<D> {
    /// `|p(t) − c|² − R²`: negative inside the ball.
    #[inline]
    pub fn ball_trig(&self, centre: &Vector<D>, radius: Real) -> Trig {
        let w = self.m - *centre;
        Trig {
            a: 2.0 * self.rho * self.u.dot(&w),
            b: 2.0 * self.rho * self.v.dot(&w),
            c: w.norm2() + self.rho * self.rho - radius * radius,
        }
    }

    /// `n · p(t) − h`: negative behind the plane.
    #[inline]
    pub fn plane_trig(&self, normal: &Vector<D>, offset: Real) -> Trig {
        Trig {
            a: self.rho * normal.dot(&self.u),
            b: self.rho * normal.dot(&self.v),
            c: normal.dot(&self.m) - offset,
        }
    }

    /// Height of `p(t)` above the circle's centre, divided by ρ.
    #[inline]
    pub fn height_trig(&self) -> Trig {
        Trig {
            a: self.u.height(),
            b: self.v.height(),
            c: 0.0,
        }
    }

    /// The point at the angle given as a point of the unit circle.
    #[inline]
    pub fn point_at(&self, x: &Crossing) -> Vector<D> {
        self.m + (self.u * x.cos + self.v * x.sin) * self.rho
    }

    /// The unit tangent (direction of travel) at `x`: `−u sin t + v cos t`.
    #[inline]
    pub fn tangent_at(&self, x: &Crossing) -> Vector<D> {
        self.v * x.cos - self.u * x.sin
    }

    /// The lowest point of the circle ahead (at most half a turn away), as a point
    /// of the unit circle: no trigonometric function needed.
    #[inline]
    pub fn lowest_crossing(&self) -> Crossing {
        let (uz, vz) = (self.u.height(), self.v.height());
        let h = (uz * uz + vz * vz).sqrt();
        if h == 0.0 || vz > 0.0 {
            return Crossing {
                cos: -1.0,
                sin: 0.0,
            };
        }
        Crossing {
            cos: -uz / h,
            sin: -vz / h,
        }
    }

    /// An axis-aligned box holding the arc from the start to `end` (at most half a
    /// turn): the box of its end points widened by the sagitta.
    #[inline]
    pub fn bounds_to(&self, end: &Crossing) -> (Vector<D>, Vector<D>) {
        let p0 = self.m + self.u * self.rho;
        let p1 = self.point_at(end);
        let cos_half = (0.5 * (1.0 + end.cos)).max(0.0).sqrt();
        let sagitta = self.rho * (1.0 - cos_half);
        chord_box(&p0, &p1, sagitta)
    }

    /// Parameter of the lowest point of the circle, in `(0, 2π)`.
    #[cfg(test)]
    pub fn lowest(&self) -> Real {
        let phi = self.v.height().atan2(self.u.height());
        let t = (phi + std::f64::consts::PI).rem_euclid(TAU);
        if t <= 0.0 {
            TAU
        } else {
            t
        }
    }
}

/// The box of a chord's end points widened by `sagitta` on every side: it holds
/// the arc over the chord.
#[inline]
fn chord_box<const D: usize>(
    p0: &Vector<D>,
    p1: &Vector<D>,
    sagitta: Real,
) -> (Vector<D>, Vector<D>) {
    let mut lo = *p0;
    let mut hi = *p0;
    for k in 0..D {
        lo[k] = lo[k].min(p1[k]) - sagitta;
        hi[k] = hi[k].max(p1[k]) + sagitta;
    }
    (lo, hi)
}

impl Trig {
    /// Value at `t`.
    #[inline]
    #[cfg(test)]
    pub fn at(&self, t: Real) -> Real {
        let (s, c) = t.sin_cos();
        self.a * c + self.b * s + self.c
    }

    /// The first `t ∈ [0, t_max]` where the function goes from non-negative to
    /// negative (the moving centre enters an obstacle, or a contact force turns
    /// tensile). `tol` is the size of a value that counts as zero.
    #[cfg(test)]
    pub fn first_downcrossing(&self, t_max: Real, tol: Real) -> Option<Real> {
        let limit = Crossing::at(t_max.min(TAU));
        self.downcrossing(tol)
            .filter(|x| t_max >= TAU || x.diamond() <= limit.diamond())
            .map(|x| x.angle())
    }

    /// False only if [`Trig::downcrossing`] with the same `tol` finds no
    /// crossing by its first, cheap test: the same comparisons, without
    /// branches, so that a batch of candidates can be sifted in one loop.
    #[inline]
    pub fn may_cross(&self, tol: Real) -> bool {
        let f0 = self.a + self.c;
        let inside = f0 < -tol;
        let level = if f0 > tol { 0.0 } else { f0.min(0.0) - tol };
        let c = self.c - level;
        let k2 = self.a * self.a + self.b * self.b;
        let misses = (c >= 0.0) & (c * c >= k2);
        (inside & (self.b < 0.0)) | (!inside & !misses)
    }

    /// True if the function stays above zero, by a wide margin, on the whole
    /// arc from the start to `end` (at most half a turn): then its first
    /// downcrossing, if any, lies more than `1e-8` of a turn beyond `end`
    /// (the margin, `1e-8 (|a| + |b| + |c|)`, over the largest slope). The
    /// minimum of `a cos t + b sin t + c` lies in the direction `(−a, −b)`;
    /// outside the arc, the function's least value on it is at an end. No
    /// square root, no division, no branch: a sift can ask it of every
    /// candidate.
    #[inline]
    pub fn clear_until(&self, end: &Crossing) -> bool {
        let ab = self.a.abs() + self.b.abs();
        let margin = 1e-8 * (ab + self.c.abs());
        let f0 = self.a + self.c;
        let f1 = self.a * end.cos + self.b * end.sin + self.c;
        let (mx, my) = (-self.a, -self.b);
        let slack = 1e-9 * ab;
        let min_on_arc = (my >= -slack) & (mx * end.sin - my * end.cos >= -slack);
        (end.sin >= 0.0) & (f0 > margin) & (f1 > margin) & !min_on_arc
    }

    /// Where the function first goes from non-negative to negative along the whole
    /// turn `t ∈ [0, 2π)`, as a point on the unit circle: no inverse trigonometric
    /// function is needed until the caller knows the crossing matters.
    ///
    /// Starting within `tol` of zero, the event is crossing `−tol` below the start:
    /// a surface touched tangentially (a contact just released, a wall the path
    /// runs along) is met again only if the path really goes into it, and then
    /// after a step of positive length, so no zero-length cycle can arise.
    /// Starting inside by more than `tol`, the event is immediate if heading in.
    #[inline]
    pub fn downcrossing(&self, tol: Real) -> Option<Crossing> {
        let f0 = self.a + self.c;
        if f0 < -tol {
            return (self.b < 0.0).then_some(Crossing { cos: 1.0, sin: 0.0 });
        }
        let level = if f0 > tol { 0.0 } else { f0.min(0.0) - tol };
        let c = self.c - level;
        let k2 = self.a * self.a + self.b * self.b;
        // Cheap rejection (most candidates): the function never reaches the level.
        if c >= 0.0 && c * c >= k2 {
            return None;
        }
        let k = k2.sqrt();
        // A graze (dipping below the level by less than the tolerance) is no event.
        if c - k > -tol || c <= -k {
            return None;
        }
        // Entry angle φ + α with cos φ = a/k, sin φ = b/k, cos α = −c/k.
        let sin_alpha = ((k - c) * (k + c)).max(0.0).sqrt();
        let cos = (-self.a * c - self.b * sin_alpha) / k2;
        let sin = (-self.b * c + self.a * sin_alpha) / k2;
        Some(Crossing { cos, sin })
    }
}

/// A point `(cos t, sin t)` of the unit circle, ordered by its angle in `[0, 2π)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// `cos t`.
    pub cos: Real,
    /// `sin t`.
    pub sin: Real,
}

impl Crossing {
    /// The point at angle `t`.
    #[inline]
    #[cfg(test)]
    pub fn at(t: Real) -> Self {
        let (sin, cos) = t.sin_cos();
        Crossing { cos, sin }
    }

    /// A number in `[0, 4)` that grows with the angle in `[0, 2π)` ("diamond
    /// angle"): ordering without `atan2`, and as fine as the angle near zero.
    #[inline]
    pub fn diamond(&self) -> Real {
        let (x, y) = (self.cos, self.sin);
        if y >= 0.0 {
            if x >= 0.0 {
                y / (x + y)
            } else {
                1.0 - x / (y - x)
            }
        } else if x < 0.0 {
            2.0 - y / (-x - y)
        } else {
            3.0 + x / (x - y)
        }
    }

    /// The angle in `[0, 2π)`.
    #[inline]
    #[cfg(test)]
    pub fn angle(&self) -> Real {
        let t = self.sin.atan2(self.cos);
        if t < 0.0 {
            t + TAU
        } else {
            t
        }
    }
}

/// The points where `D` surfaces (at least one of them a ball) meet: zero, one or
/// two points. Planes and differences of spheres give `D − 1` linear equations (a
/// line); the line meets the first ball in up to two points.
pub fn intersection_points<const D: usize>(surfaces: &[Surface<D>]) -> ([Vector<D>; 2], usize) {
    debug_assert_eq!(surfaces.len(), D);
    let none = ([Vector::zero(); 2], 0);
    let Some(first) = surfaces.iter().position(|s| s.is_ball()) else {
        return none;
    };
    let Surface::Ball {
        centre: c0,
        radius: r0,
    } = surfaces[first]
    else {
        return none;
    };
    // Rows of the linear system `rows[i] · p = rhs[i]`, made relative to c0 for
    // accuracy: unknown q = p − c0.
    let mut rows = [Vector::<D>::zero(); 3];
    let mut rhs = [0.0; 3];
    let mut k = 0;
    for (i, s) in surfaces.iter().enumerate() {
        if i == first {
            continue;
        }
        match s {
            Surface::Ball { centre, radius } => {
                // |q|² = r0², |q − e|² = r² ⇒ 2 e·q = r0² − r² + |e|².
                let e = *centre - c0;
                rows[k] = e * 2.0;
                rhs[k] = r0 * r0 - radius * radius + e.norm2();
            }
            Surface::Plane { normal, offset } => {
                rows[k] = *normal;
                rhs[k] = offset - normal.dot(&c0);
            }
        }
        k += 1;
    }
    // Orthonormalise the rows (Gram–Schmidt), carrying the right-hand sides, to
    // get the minimum-norm particular solution and the line's direction.
    let mut basis = [Vector::<D>::zero(); 3];
    let mut q0 = Vector::<D>::zero();
    for i in 0..k {
        let mut row = rows[i];
        let mut b = rhs[i];
        for j in 0..i {
            let f = row.dot(&basis[j]);
            row -= basis[j] * f;
            b -= f * q0_component(&q0, &basis[j]);
        }
        let n = row.norm();
        if n < 1e-12 * rows[i].norm().max(1e-300) {
            return none; // dependent equations: degenerate
        }
        basis[i] = row / n;
        q0 += basis[i] * (b / n);
    }
    // Direction of the line: the axis least aligned with the rows, orthogonalised.
    let mut dir = Vector::<D>::zero();
    let mut best = -1.0;
    for ax in 0..D {
        let mut w = Vector::<D>::axis(ax);
        for j in 0..k {
            w -= basis[j] * w.dot(&basis[j]);
        }
        let n = w.norm2();
        if n > best {
            best = n;
            dir = w;
        }
    }
    let Some(dir) = dir.normalized() else {
        return none;
    };
    // |q0 + s dir|² = r0² with q0 ⟂ dir.
    let disc = r0 * r0 - q0.norm2();
    if disc < 0.0 {
        if disc > -1e-12 * r0 * r0 {
            return ([c0 + q0, Vector::zero()], 1);
        }
        return none;
    }
    let s = disc.sqrt();
    ([c0 + q0 - dir * s, c0 + q0 + dir * s], 2)
}

#[inline]
fn q0_component<const D: usize>(q0: &Vector<D>, b: &Vector<D>) -> Real {
    q0.dot(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The unit circle in the plane, starting at (1, 0) going up.
    fn unit_circle() -> Arc<2> {
        Arc {
            m: Vector([0.0, 0.0]),
            rho: 1.0,
            u: Vector([1.0, 0.0]),
            v: Vector([0.0, 1.0]),
        }
    }

    #[test]
    fn downcrossing_of_a_ball_ahead() {
        // Unit circle in the plane, start at (1, 0) going up (v = (0, 1));
        // ball of radius 0.5 at (0, 1): entered at an angle found by hand.
        let arc = unit_circle();
        let f = arc.ball_trig(&Vector([0.0, 1.0]), 0.5);
        let t = f.first_downcrossing(TAU, 1e-12).unwrap();
        // |p(t) − (0,1)|² = 2 − 2 sin t = 0.25 ⇒ sin t = 7/8.
        assert!((t - (7.0f64 / 8.0).asin()).abs() < 1e-12, "{t}");
        assert!(f.at(t).abs() < 1e-12);
    }

    #[test]
    fn leaving_contact_is_not_an_event() {
        // Start exactly on the surface of a ball behind us, moving away.
        let arc = unit_circle();
        // Ball centred at (1, -1) with radius 1 touches the start (1, 0).
        let f = arc.ball_trig(&Vector([1.0, -1.0]), 1.0);
        assert!(f.at(0.0).abs() < 1e-15);
        let t = f.first_downcrossing(TAU, 1e-12);
        // It is re-entered only after coming round the circle.
        assert!(t.is_none_or(|t| t > 1.0), "{t:?}");
    }

    #[test]
    fn lowest_point() {
        let arc = Arc {
            m: Vector([0.0, 0.0, 0.0]),
            rho: 1.0,
            u: Vector([0.0, 0.0, 1.0]),
            v: Vector([1.0, 0.0, 0.0]),
        };
        assert!((arc.lowest() - std::f64::consts::PI).abs() < 1e-15);
    }

    #[test]
    fn three_spheres_meet_in_two_points() {
        // Three unit-radius inflated balls at the corners of an equilateral
        // triangle of side 1 in the plane z = 0: the points are at height
        // sqrt(1 − 1/3) above and below the centroid.
        let s3 = 3f64.sqrt();
        let c = [
            Vector([0.0, 0.0, 0.0]),
            Vector([1.0, 0.0, 0.0]),
            Vector([0.5, s3 / 2.0, 0.0]),
        ];
        let surfaces = c.map(|c| Surface::Ball {
            centre: c,
            radius: 1.0,
        });
        let (pts, n) = intersection_points(&surfaces);
        assert_eq!(n, 2);
        let h = (1.0f64 - 1.0 / 3.0).sqrt();
        for p in &pts[..2] {
            assert!((p[0] - 0.5).abs() < 1e-14 && (p[1] - s3 / 6.0).abs() < 1e-14);
            assert!((p[2].abs() - h).abs() < 1e-14);
        }
    }

    proptest! {
        #[test]
        fn intersection_points_lie_on_every_surface(
            c in prop::array::uniform3(prop::array::uniform3(-5.0f64..5.0)),
            r in prop::array::uniform3(0.5f64..6.0),
            plane in any::<bool>(),
            h in -2.0f64..2.0,
        ) {
            let mut s: Vec<Surface<3>> = (0..3).map(|i| Surface::Ball {
                centre: Vector(c[i]), radius: r[i] }).collect();
            if plane {
                s[2] = Surface::Plane { normal: Vector([0.0, 0.0, 1.0]), offset: h };
            }
            let (pts, n) = intersection_points(&s);
            for p in &pts[..n] {
                for surf in &s {
                    prop_assert!(surf.gap(p).abs() < 1e-8, "{:?} {:?}", surf, p);
                }
            }
        }

        #[test]
        fn diamond_angle_grows_with_the_angle(t1 in 0.0f64..TAU, t2 in 0.0f64..TAU) {
            let (d1, d2) = (Crossing::at(t1).diamond(), Crossing::at(t2).diamond());
            prop_assert!((0.0..4.0).contains(&d1));
            if t1 < t2 - 1e-12 {
                prop_assert!(d1 <= d2, "{t1} {t2} {d1} {d2}");
            }
        }

        #[test]
        fn may_cross_keeps_every_crossing(
            a in -3.0f64..3.0, b in -3.0f64..3.0, c in -3.0f64..3.0,
            // Values near the tolerance and near tangency, where the branches part.
            near in any::<bool>(), tol in prop::sample::select(vec![0.0, 1e-12, 1e-3, 0.5]),
        ) {
            let f = if near { Trig { a, b, c: -a + tol * c.signum() } } else { Trig { a, b, c } };
            if f.downcrossing(tol).is_some() {
                prop_assert!(f.may_cross(tol), "{f:?} {tol}");
            }
            // Tangent circles: c*c == a*a + b*b exactly.
            let g = Trig { a: 3.0, b: 4.0, c: 5.0 + tol * (c % 1.0) };
            if g.downcrossing(tol).is_some() {
                prop_assert!(g.may_cross(tol), "{g:?} {tol}");
            }
        }

        #[test]
        fn clear_until_means_no_crossing_until_well_past_the_end(
            a in -3.0f64..3.0, b in -3.0f64..3.0, c in -3.0f64..3.0,
            end in 0.0f64..std::f64::consts::PI,
            tol in prop::sample::select(vec![0.0, 1e-12, 1e-6]),
        ) {
            let f = Trig { a, b, c };
            let e = Crossing::at(end);
            if f.clear_until(&e) {
                for i in 0..=400 {
                    prop_assert!(f.at(end * i as f64 / 400.0) > 0.0);
                }
                if let Some(x) = f.downcrossing(tol) {
                    prop_assert!(x.diamond() > e.diamond() + 1e-9, "{f:?} {end} {x:?}");
                }
            }
        }

        #[test]
        fn downcrossing_is_a_root_with_no_earlier_negative(
            a in -3.0f64..3.0, b in -3.0f64..3.0, c in -3.0f64..3.0,
        ) {
            let f = Trig { a, b, c };
            prop_assume!(f.at(0.0) > 1e-6);
            if let Some(t) = f.first_downcrossing(TAU, 1e-12) {
                prop_assert!(f.at(t).abs() < 1e-9);
                for i in 0..200 {
                    let s = t * i as f64 / 200.0;
                    prop_assert!(f.at(s) > -1e-9);
                }
            } else {
                for i in 0..400 {
                    prop_assert!(f.at(TAU * i as f64 / 400.0) > -1e-6);
                }
            }
        }
    }
}
