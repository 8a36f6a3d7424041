//! Packing fraction: solid volume (area in 2D) over box or region volume, with the
//! parts of particles cut by a region boundary computed exactly.
//!
//! 2D cuts are closed form. 3D cuts integrate the closed-form 2D slice area over
//! height, written as the polar angle θ (`z = c + r sin θ`, so the slice radius
//! `r cos θ` has no square-root singularity at the poles), with Gauss–Legendre on
//! pieces split wherever the slice circle starts or stops touching an edge or
//! corner of the box. On each piece the substitution `θ = a + (b − a)(1 − cos φ)/2`
//! turns the `(θ − θ_b)^{3/2}` behaviour at a tangency into a smooth function of
//! `φ`. The result agrees with exact cap formulas to ~1e-13 of the ball's volume.

// `!(a > b)` is meant: NaN inputs must take the safe branch (nothing, or a
// reported violation), which `a <= b` would not.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::cells::CellList;
use crate::bed::Bed;
use crate::math::{ball_volume, Real, Vector};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::sync::OnceLock;

/// An axis-aligned box of space where solid fractions are measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region<const D: usize> {
    /// Low corner.
    pub lo: Vector<D>,
    /// High corner.
    pub hi: Vector<D>,
    /// Axes along which the region is a whole period of a periodic box: not cut
    /// there, so a particle crossing `x = 0` counts fully (its other half is its own
    /// image entering at `x = W`).
    pub wrap: [bool; D],
}

impl<const D: usize> Region<D> {
    /// Area (2D) or volume (3D) of the region.
    pub fn volume(&self) -> Real {
        (0..D).map(|k| (self.hi[k] - self.lo[k]).max(0.0)).product()
    }

    /// True when `p` lies in the region (always true along wrapped axes).
    pub fn contains(&self, p: &Vector<D>) -> bool {
        (0..D).all(|k| self.wrap[k] || (p[k] >= self.lo[k] && p[k] <= self.hi[k]))
    }

    /// Solid volume of `bed` inside the region.
    pub fn solid_volume(&self, bed: &Bed<D>) -> Real {
        self.solid_volume_of(bed, &particle_volumes(bed))
    }

    /// Solid volume inside the region, given each particle's own volume share.
    pub(crate) fn solid_volume_of(&self, bed: &Bed<D>, volumes: &[Real]) -> Real {
        let (lo, hi) = self.cut_bounds();
        let share = |i: usize| -> Real {
            let (c, r) = (&bed.centres[i], bed.radii[i]);
            let whole = ball_volume::<D>(r);
            if !(whole > 0.0) || (0..D).any(|k| c[k] + r <= lo[k] || c[k] - r >= hi[k]) {
                return 0.0;
            }
            let inside = (0..D).all(|k| c[k] - r >= lo[k] && c[k] + r <= hi[k]);
            let part = if inside {
                whole
            } else {
                ball_box_volume(c, r, &lo, &hi)
            };
            // Overlapping beads of a chain: scale the cut by the bead's share of the
            // chain's union. Exact for beads wholly inside; an approximation only for
            // beads that straddle the region boundary (see `particle_volumes`).
            part * (volumes[i] / whole)
        };
        // Partial sums over fixed chunks, added in order: the same bits whatever
        // the thread count.
        const CHUNK: usize = 8192;
        let parts: Vec<Real> = (0..bed.len().div_ceil(CHUNK))
            .into_par_iter()
            .map(|k| {
                (k * CHUNK..((k + 1) * CHUNK).min(bed.len()))
                    .map(share)
                    .sum()
            })
            .collect();
        parts.iter().sum()
    }

    /// Packing fraction in the region (0 for a region of no volume).
    pub fn fraction(&self, bed: &Bed<D>) -> Real {
        self.fraction_of(bed, &particle_volumes(bed))
    }

    /// Packing fraction given each particle's volume share.
    pub(crate) fn fraction_of(&self, bed: &Bed<D>, volumes: &[Real]) -> Real {
        let v = self.volume();
        if !(v > 0.0 && v.is_finite()) {
            return 0.0;
        }
        let f = self.solid_volume_of(bed, volumes) / v;
        if f.is_finite() {
            f
        } else {
            0.0
        }
    }

    /// The bounds used to cut particles: infinite along wrapped axes.
    fn cut_bounds(&self) -> (Vector<D>, Vector<D>) {
        let (mut lo, mut hi) = (self.lo, self.hi);
        for k in 0..D {
            if self.wrap[k] {
                lo[k] = Real::NEG_INFINITY;
                hi[k] = Real::INFINITY;
            }
        }
        (lo, hi)
    }
}

/// The bulk region: at least `2 d_max` from the side walls (no cut on periodic
/// axes) and the floor, and `3 d_max` below the bed's [`surface_height`]; `None`
/// when the bed is too small to have one.
pub fn bulk_region<const D: usize>(bed: &Bed<D>) -> Option<Region<D>> {
    if bed.is_empty() {
        return None;
    }
    let d_max = 2.0 * bed.r_max();
    let mut lo = Vector::zero();
    let mut hi = Vector::zero();
    let mut wrap = [false; D];
    for k in 0..D - 1 {
        if bed.container.periodic {
            wrap[k] = true;
            hi[k] = bed.container.size[k];
        } else {
            lo[k] = 2.0 * d_max;
            hi[k] = bed.container.size[k] - 2.0 * d_max;
        }
    }
    lo[D - 1] = 2.0 * d_max;
    hi[D - 1] = surface_height(bed) - 3.0 * d_max;
    let ok = (0..D).all(|k| lo[k].is_finite() && hi[k].is_finite() && hi[k] > lo[k]);
    ok.then_some(Region { lo, hi, wrap })
}

/// The smallest cube, of side `N` largest diameters (a run's `--box
/// diameters=N`), whose [`bulk_region`] would hold `min_bodies` bodies, as
/// this bed's packing predicts: its bodies per volume below its surface, a
/// cube filled to within the gap this bed leaves below its roof (at most a
/// diameter), and the bulk region's margins (two diameters from the floor
/// and each wall, three below the surface). `None` for an empty bed.
pub fn cube_for_bulk<const D: usize>(bed: &Bed<D>, min_bodies: u64) -> Option<u64> {
    let d = 2.0 * bed.r_max();
    let surface = surface_height(bed);
    let mut volume = surface;
    for k in 0..D - 1 {
        volume *= bed.container.size[k];
    }
    let per_volume = bed.body_count() as Real / volume;
    if !(d > 0.0 && per_volume > 0.0 && per_volume.is_finite()) {
        return None;
    }
    let gap = ((bed.container.size[D - 1] - surface) / d).clamp(0.0, 1.0);
    let wall_margin = if bed.container.periodic { 0.0 } else { 4.0 };
    let per_cell = per_volume * d.powi(D as i32);
    let holds = |n: Real| {
        let across = (n - wall_margin).max(0.0);
        let up = (n - gap - 5.0).max(0.0);
        per_cell * across.powi(D as i32 - 1) * up
    };
    // A fifth more than the minimum: another seed packs a little differently,
    // and the box named should have a bulk for it too.
    let want = 1.2 * min_bodies as Real;
    (1..=100_000u64).find(|&n| holds(n as Real) >= want)
}

/// Height of the bed's surface: the mean, over columns of the floor about one
/// largest diameter wide, of the highest particle top whose centre lies in the
/// column (0 for a column with none). One particle sticking up (a spike) moves
/// it by a column's share only; the highest top alone biased the bulk of wide
/// walled beds 0.003 low.
pub fn surface_height<const D: usize>(bed: &Bed<D>) -> Real {
    if bed.is_empty() {
        return 0.0;
    }
    let d_max = 2.0 * bed.r_max();
    let mut n = [1usize; D];
    let mut width = [0.0; D];
    let mut columns = 1usize;
    for k in 0..D - 1 {
        let w = bed.container.size[k];
        // At least a diameter wide, so that a filled bed has a particle in each.
        n[k] = ((w / d_max).floor() as usize).clamp(1, 1 << 16);
        width[k] = w / n[k] as Real;
        columns *= n[k];
    }
    // Only occupied columns are stored: a wide, shallow box has billions of
    // columns and a few particles (the mean over the empty ones counts 0).
    let mut tops: Vec<(usize, Real)> = Vec::with_capacity(bed.len());
    for (c, &r) in bed.centres.iter().zip(&bed.radii) {
        let mut index = 0;
        for k in 0..D - 1 {
            let i = (c[k] / width[k]).floor();
            let i = if i.is_finite() && i > 0.0 {
                (i as usize).min(n[k] - 1)
            } else {
                0
            };
            index = index * n[k] + i;
        }
        tops.push((index, (c[D - 1] + r).max(0.0)));
    }
    tops.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)));
    tops.dedup_by_key(|t| t.0);
    tops.iter().map(|t| t.1).sum::<Real>() / columns as Real
}

/// Global packing fraction: solid volume ÷ box volume up to the roof. When particles
/// stick out above the roof (fill by count) the box is taken up to the highest
/// particle top instead, so that the fraction stays a fraction of a box that holds
/// the whole bed.
pub fn global_fraction<const D: usize>(bed: &Bed<D>) -> Real {
    global_fraction_of(bed, &particle_volumes(bed))
}

/// Global packing fraction given each particle's volume share.
pub(crate) fn global_fraction_of<const D: usize>(bed: &Bed<D>, volumes: &[Real]) -> Real {
    let roof = bed.container.height();
    let top = bed.top();
    let height = if roof.is_finite() && roof >= top {
        roof
    } else {
        top
    };
    let base: Real = (0..D - 1).map(|k| bed.container.size[k]).product();
    let v = base * height;
    let f = volumes.iter().sum::<Real>() / v;
    if v > 0.0 && f.is_finite() {
        f
    } else {
        0.0
    }
}

/// Packing fraction of the bulk region, `None` when the bed has no bulk region.
pub fn bulk_fraction<const D: usize>(bed: &Bed<D>) -> Option<Real> {
    bulk_region(bed).map(|reg| reg.fraction(bed))
}

/// Each particle's share of solid volume: its whole volume, except for overlapping
/// beads of one body, whose union must be counted once. The union is split along
/// power planes (the radical planes of overlapping bead pairs, which cut the union
/// into one piece per bead): a bead keeps its ball minus the caps beyond those
/// planes. Exact for straight chains of any spacing and for any body whose caps do
/// not overlap each other; otherwise (three beads of a bent body sharing a point)
/// the doubly cut part is subtracted twice, a tiny error that is documented here
/// rather than hidden.
pub fn particle_volumes<const D: usize>(bed: &Bed<D>) -> Vec<Real> {
    union_shares(bed, false).0
}

/// Each particle's share of the solid volume and of the solid surface (area in
/// 2D, perimeter): the surface of a bead of a chain is its sphere less the caps
/// cut off by the same power planes as [`particle_volumes`], so that a body's
/// shares add up to its union's volume and surface.
pub fn particle_volumes_and_surfaces<const D: usize>(bed: &Bed<D>) -> (Vec<Real>, Vec<Real>) {
    let (volumes, surfaces) = union_shares(bed, true);
    (volumes, surfaces.unwrap_or_default())
}

/// Volumes and, when asked, surfaces of the beads' shares of their unions.
fn union_shares<const D: usize>(bed: &Bed<D>, surfaces: bool) -> (Vec<Real>, Option<Vec<Real>>) {
    let positive = |r: Real, f: fn(Real) -> Real| if r > 0.0 { f(r) } else { 0.0 };
    let mut volumes: Vec<Real> = bed
        .radii
        .iter()
        .map(|&r| positive(r, ball_volume::<D>))
        .collect();
    let mut areas: Option<Vec<Real>> = surfaces.then(|| {
        bed.radii
            .iter()
            .map(|&r| positive(r, sphere_surface::<D>))
            .collect()
    });
    if !has_shared_body(bed) {
        return (volumes, areas);
    }
    // Planes (unit normal, signed distance from the bead's centre) cutting each bead.
    let mut planes: Vec<Vec<(Vector<D>, Real)>> = vec![Vec::new(); bed.len()];
    let mut swallowed = vec![false; bed.len()];
    let cells = CellList::new(bed, 0.0);
    cells.for_each_pair_where(
        |i, j| bed.bodies[i] == bed.bodies[j],
        |i, j| {
            let (ri, rj) = (bed.radii[i], bed.radii[j]);
            let dv = bed.container.displacement(&bed.centres[i], &bed.centres[j]);
            let d = dv.norm();
            if !(d < ri + rj) {
                return;
            }
            // One bead inside another adds nothing to the union; for identical
            // coincident beads keep the first.
            if d <= (ri - rj).abs() {
                if ri < rj || (ri == rj && i > j) {
                    swallowed[i] = true;
                } else {
                    swallowed[j] = true;
                }
                return;
            }
            let u = dv / d;
            let ti = (d * d + ri * ri - rj * rj) / (2.0 * d);
            add_plane(&mut planes[i], u, ti);
            add_plane(&mut planes[j], -u, d - ti);
        },
    );
    for i in 0..bed.len() {
        if swallowed[i] {
            volumes[i] = 0.0;
            if let Some(a) = areas.as_mut() {
                a[i] = 0.0;
            }
            continue;
        }
        let r = bed.radii[i];
        let cut: Real = planes[i].iter().map(|&(_, t)| cap_volume::<D>(r, t)).sum();
        volumes[i] = (volumes[i] - cut).max(0.0);
        if let Some(a) = areas.as_mut() {
            let cut: Real = planes[i].iter().map(|&(_, t)| cap_surface::<D>(r, t)).sum();
            a[i] = (a[i] - cut).max(0.0);
        }
    }
    (volumes, areas)
}

/// Surface of a ball of radius `r` (perimeter of a disc in 2D).
pub fn sphere_surface<const D: usize>(r: Real) -> Real {
    match D {
        2 => 2.0 * PI * r,
        3 => 4.0 * PI * r * r,
        _ => unreachable!("packbed works in 2 or 3 dimensions"),
    }
}

/// Surface (arc length in 2D) of the part of a sphere of radius `r` beyond a
/// plane at signed distance `t` from its centre.
pub fn cap_surface<const D: usize>(r: Real, t: Real) -> Real {
    if !(r > 0.0) || t >= r {
        return 0.0;
    }
    if t <= -r {
        return sphere_surface::<D>(r);
    }
    match D {
        2 => 2.0 * r * (t / r).clamp(-1.0, 1.0).acos(),
        3 => 2.0 * PI * r * (r - t),
        _ => unreachable!("packbed works in 2 or 3 dimensions"),
    }
}

/// True when two particles share a body id (only then can beads overlap).
fn has_shared_body<const D: usize>(bed: &Bed<D>) -> bool {
    let mut b = bed.bodies.clone();
    b.sort_unstable();
    b.windows(2).any(|w| w[0] == w[1])
}

/// Adds a cutting plane, keeping only the nearest plane per direction: along a
/// straight chain the plane of the next-but-one bead lies beyond the next one's.
fn add_plane<const D: usize>(planes: &mut Vec<(Vector<D>, Real)>, u: Vector<D>, t: Real) {
    for p in planes.iter_mut() {
        if p.0.dot(&u) > 1.0 - 1e-12 {
            p.1 = p.1.min(t);
            return;
        }
    }
    planes.push((u, t));
}

/// Volume (area in 2D) of the part of a ball of radius `r` beyond a plane at signed
/// distance `t` from its centre.
pub fn cap_volume<const D: usize>(r: Real, t: Real) -> Real {
    if !(r > 0.0) || t >= r {
        return 0.0;
    }
    if t <= -r {
        return ball_volume::<D>(r);
    }
    match D {
        2 => r * r * (t / r).clamp(-1.0, 1.0).acos() - t * half_chord(r, t),
        3 => PI * (r - t) * (r - t) * (2.0 * r + t) / 3.0,
        _ => unreachable!("packbed works in 2 or 3 dimensions"),
    }
}

/// Exact volume (area in 2D) of the ball of centre `c` and radius `r` inside the
/// axis-aligned box `[lo, hi]`; bounds may be infinite.
pub fn ball_box_volume<const D: usize>(
    c: &Vector<D>,
    r: Real,
    lo: &Vector<D>,
    hi: &Vector<D>,
) -> Real {
    if !(r > 0.0 && r.is_finite()) {
        return 0.0;
    }
    // Work relative to the centre, clamped to the ball: infinite bounds become ±r.
    let mut a = [0.0; D];
    let mut b = [0.0; D];
    for k in 0..D {
        a[k] = (lo[k] - c[k]).max(-r);
        b[k] = (hi[k] - c[k]).min(r);
        if !(b[k] > a[k]) {
            return 0.0;
        }
    }
    let clipped = |k: usize| a[k] > -r || b[k] < r;
    let mut axes = (0..D).filter(|&k| clipped(k));
    match (axes.next(), axes.next()) {
        (None, _) => return ball_volume::<D>(r),
        // Cut along one axis only (most particles a region boundary meets): a
        // slab of the ball, in closed form from caps. Written so that nothing
        // small is the difference of two large volumes: a slab on one side of
        // the centre is a difference of two caps on that side.
        (Some(k), None) => {
            let v = if a[k] >= 0.0 {
                cap_volume::<D>(r, a[k]) - cap_volume::<D>(r, b[k])
            } else if b[k] <= 0.0 {
                cap_volume::<D>(r, -b[k]) - cap_volume::<D>(r, -a[k])
            } else {
                ball_volume::<D>(r) - cap_volume::<D>(r, b[k]) - cap_volume::<D>(r, -a[k])
            };
            return v.max(0.0);
        }
        _ => {}
    }
    match D {
        1 => b[0] - a[0],
        2 => disc_rect_area(r, a[0], b[0], a[1], b[1]),
        3 => ball_box_3(r, [a[0], b[0]], [a[1], b[1]], [a[2], b[2]]),
        _ => unreachable!("packbed works in 2 or 3 dimensions"),
    }
}

/// Half the chord of a circle of radius `r` at distance `y` from its centre,
/// `sqrt(r² − y²)` written to keep precision near `|y| = r`.
#[inline]
fn half_chord(r: Real, y: Real) -> Real {
    ((r - y) * (r + y)).max(0.0).sqrt()
}

/// `∫₀ˣ sqrt(r² − t²) dt`.
#[inline]
fn chord_integral(r: Real, x: Real) -> Real {
    let x = x.clamp(-r, r);
    0.5 * (x * half_chord(r, x) + r * r * (x / r).clamp(-1.0, 1.0).asin())
}

/// Exact area of the disc of radius `r` centred at the origin inside
/// `[x0, x1] × [y0, y1]` (bounds relative to the centre).
pub(crate) fn disc_rect_area(r: Real, x0: Real, x1: Real, y0: Real, y1: Real) -> Real {
    if !(r > 0.0) {
        return 0.0;
    }
    let (x0, x1) = (x0.max(-r), x1.min(r));
    let (y0, y1) = (y0.max(-r), y1.min(r));
    if !(x1 > x0 && y1 > y0) {
        return 0.0;
    }
    // Integrate the length of each vertical chord inside [y0, y1] over x. Between
    // the x where the circle crosses y = y0 or y = y1 the chord's ends are each
    // either on the circle (±sqrt(r² − x²)) or on a box edge (constant), so each
    // piece integrates in closed form.
    let mut cuts = [x0, x1, 0.0, 0.0, 0.0, 0.0];
    let (h0, h1) = (half_chord(r, y0), half_chord(r, y1));
    let mut m = 2;
    for x in [-h0, h0, -h1, h1] {
        if x > x0 && x < x1 {
            cuts[m] = x;
            m += 1;
        }
    }
    let cuts = &mut cuts[..m];
    cuts.sort_unstable_by(|p, q| p.total_cmp(q));
    let mut area = 0.0;
    for w in cuts.windows(2) {
        let (a, b) = (w[0], w[1]);
        if !(b > a) {
            continue;
        }
        let s = half_chord(r, 0.5 * (a + b));
        if s.min(y1) - (-s).max(y0) <= 0.0 {
            continue;
        }
        let mut circle_ends = 0.0;
        let mut constant = 0.0;
        if s < y1 {
            circle_ends += 1.0;
        } else {
            constant += y1;
        }
        if -s > y0 {
            circle_ends += 1.0;
        } else {
            constant -= y0;
        }
        area += circle_ends * (chord_integral(r, b) - chord_integral(r, a)) + constant * (b - a);
    }
    area.max(0.0)
}

/// Gauss–Legendre nodes and weights on `[-1, 1]`.
fn gauss_legendre() -> &'static [(Real, Real)] {
    const N: usize = 24;
    static NODES: OnceLock<Vec<(Real, Real)>> = OnceLock::new();
    NODES.get_or_init(|| {
        let mut out = Vec::with_capacity(N);
        for i in 0..N {
            let mut x = (PI * (i as Real + 0.75) / (N as Real + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                // Legendre recurrence for P_N(x) and its derivative.
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=N {
                    let k = k as Real;
                    let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = N as Real * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            out.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
        }
        out
    })
}

/// Volume of the ball of radius `r` at the origin inside the box `x × y × z`
/// (bounds relative to the centre, already clamped to `[-r, r]`).
fn ball_box_3(r: Real, x: [Real; 2], y: [Real; 2], z: [Real; 2]) -> Real {
    // Slice radii at which the slice circle touches an edge line or passes a
    // corner: there the slice area is not smooth in height.
    let mut radii = [0.0; 8];
    let mut m = 0;
    for e in [x[0], x[1], y[0], y[1]] {
        if e.abs() < r {
            radii[m] = e.abs();
            m += 1;
        }
    }
    for ex in x {
        for ey in y {
            let d = ex.hypot(ey);
            if d < r {
                radii[m] = d;
                m += 1;
            }
        }
    }
    // Integrate in the polar angle θ (z = r sin θ): the slice radius r cos θ is
    // then smooth in θ, and only the tangencies remain as break points.
    let angle = |z: Real| z.atan2(half_chord(r, z));
    let mut cuts = [0.0; 18];
    cuts[0] = angle(z[0]);
    cuts[1] = angle(z[1]);
    let mut n = 2;
    for &rho in &radii[..m] {
        let h = half_chord(r, rho);
        for zc in [-h, h] {
            if zc > z[0] && zc < z[1] {
                cuts[n] = zc.atan2(rho);
                n += 1;
            }
        }
    }
    let cuts = &mut cuts[..n];
    cuts.sort_unstable_by(|p, q| p.total_cmp(q));
    let nodes = gauss_legendre();
    let mut vol = 0.0;
    for w in cuts.windows(2) {
        let (a, b) = (w[0], w[1]);
        if !(b > a) {
            continue;
        }
        // θ = a + (b − a)(1 − cos φ)/2, φ ∈ [0, π]: dθ = (b − a)/2 · sin φ dφ, and
        // dz = r cos θ dθ.
        let mut piece = 0.0;
        for &(s, wgt) in nodes {
            let phi = 0.5 * PI * (s + 1.0);
            let theta = a + 0.5 * (b - a) * (1.0 - phi.cos());
            let rho = r * theta.cos();
            piece += wgt * phi.sin() * rho * disc_rect_area(rho, x[0], x[1], y[0], y[1]);
        }
        vol += piece * 0.5 * PI * 0.5 * (b - a);
    }
    vol.max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::container::Container;
    use proptest::prelude::*;

    const INF: Real = Real::INFINITY;

    fn v2(x: Real, y: Real) -> Vector<2> {
        Vector([x, y])
    }

    fn v3(x: Real, y: Real, z: Real) -> Vector<3> {
        Vector([x, y, z])
    }

    fn close(a: Real, b: Real, rel: Real) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-300)
    }

    #[test]
    fn disc_cut_by_an_edge_a_corner_and_a_chord() {
        let c = v2(1.0, 2.0);
        let r = 1.5;
        let full = PI * r * r;
        let half = ball_box_volume(&c, r, &v2(1.0, -INF), &v2(INF, INF));
        assert!(close(half, full / 2.0, 1e-15), "{half}");
        let quarter = ball_box_volume(&c, r, &v2(-10.0, 2.0), &v2(1.0, 10.0));
        assert!(close(quarter, full / 4.0, 1e-15), "{quarter}");
        assert_eq!(ball_box_volume(&c, r, &v2(-9.0, -9.0), &v2(9.0, 9.0)), full);
        assert_eq!(ball_box_volume(&c, r, &v2(3.0, -9.0), &v2(9.0, 9.0)), 0.0);
        // Segment beyond a chord at distance t: r² acos(t/r) − t sqrt(r² − t²).
        let t = 0.6;
        let seg = r * r * (t / r).acos() - t * (r * r - t * t).sqrt();
        let got = ball_box_volume(&c, r, &v2(-INF, 2.0 + t), &v2(INF, INF));
        assert!(close(got, seg, 1e-14), "{got} {seg}");
        assert!(close(cap_volume::<2>(r, t), seg, 1e-15));
        // A square inscribed in the disc lies wholly inside it: area 2r².
        let s = r / 2f64.sqrt();
        let sq = ball_box_volume(&c, r, &v2(1.0 - s, 2.0 - s), &v2(1.0 + s, 2.0 + s));
        assert!(close(sq, 2.0 * r * r, 1e-14), "{sq}");
    }

    #[test]
    fn sphere_cut_by_planes() {
        let c = v3(0.3, -0.2, 5.0);
        let r = 2.0;
        let full = 4.0 / 3.0 * PI * r * r * r;
        for t in [-1.9, -1.0, 0.0, 0.5, 1.2, 1.99] {
            // Cap beyond z = c + t: π (r − t)² (2r + t) / 3.
            let cap = PI * (r - t) * (r - t) * (2.0 * r + t) / 3.0;
            let got = ball_box_volume(&c, r, &v3(-INF, -INF, 5.0 + t), &v3(INF, INF, INF));
            assert!(close(got, cap, 1e-13), "t = {t}: {got} vs {cap}");
            assert!(close(cap_volume::<3>(r, t), cap, 1e-15));
            // The same cap cut by a side plane.
            let side = ball_box_volume(&c, r, &v3(-INF, -INF, -INF), &v3(0.3 - t, INF, INF));
            // Tiny caps lose relative digits to cancellation in the slice areas, but
            // stay within 1e-16 of the ball's volume.
            assert!(close(side, cap, 1e-11), "side t = {t}: {side} vs {cap}");
            assert!((side - cap).abs() < 1e-15 * full);
        }
        let two = ball_box_volume(&c, r, &v3(0.3, -0.2, -INF), &v3(INF, INF, INF));
        assert!(close(two, full / 4.0, 1e-13), "{two}");
        let three = ball_box_volume(&c, r, &v3(-INF, -0.2, 5.0), &v3(0.3, INF, INF));
        assert!(close(three, full / 8.0, 1e-13), "{three}");
        assert_eq!(
            ball_box_volume(&c, r, &v3(-9.0, -9.0, 0.0), &v3(9.0, 9.0, 9.0)),
            full
        );
        assert_eq!(
            ball_box_volume(&c, r, &v3(-9.0, -9.0, 7.5), &v3(9.0, 9.0, 9.0)),
            0.0
        );
        // A slab through the centre, |z| ≤ h: full minus two caps.
        let h = 0.7;
        let slab = ball_box_volume(&c, r, &v3(-INF, -INF, 5.0 - h), &v3(INF, INF, 5.0 + h));
        let want = full - 2.0 * PI * (r - h) * (r - h) * (2.0 * r + h) / 3.0;
        assert!(close(slab, want, 1e-13), "{slab} vs {want}");
    }

    #[test]
    fn degenerate_inputs_give_zero_not_nan() {
        let c = v3(0.0, 0.0, 0.0);
        assert_eq!(
            ball_box_volume(&c, 0.0, &v3(-1.0, -1.0, -1.0), &v3(1.0, 1.0, 1.0)),
            0.0
        );
        assert_eq!(
            ball_box_volume(&c, -1.0, &v3(-1.0, -1.0, -1.0), &v3(1.0, 1.0, 1.0)),
            0.0
        );
        assert_eq!(
            ball_box_volume(&c, 1.0, &v3(Real::NAN, -1.0, -1.0), &v3(1.0, 1.0, 1.0)),
            ball_box_volume(&c, 1.0, &v3(-1.0, -1.0, -1.0), &v3(1.0, 1.0, 1.0))
        );
        assert_eq!(
            ball_box_volume(&c, 1.0, &v3(0.5, -1.0, -1.0), &v3(0.5, 1.0, 1.0)),
            0.0
        );
        assert_eq!(
            ball_box_volume(&v2(0.0, 0.0), 1.0, &v2(1.0, 0.0), &v2(-1.0, 1.0)),
            0.0
        );
    }

    /// Chord-length integral by the midpoint rule: an independent estimate of the
    /// disc ∩ rectangle area.
    fn disc_rect_brute(c: Vector<2>, r: Real, lo: Vector<2>, hi: Vector<2>) -> Real {
        let n = 200_000;
        let (a, b) = (lo[0].max(c[0] - r), hi[0].min(c[0] + r));
        if b <= a {
            return 0.0;
        }
        let h = (b - a) / n as Real;
        let mut s = 0.0;
        for k in 0..n {
            let x = a + (k as Real + 0.5) * h - c[0];
            let w = (r * r - x * x).max(0.0).sqrt();
            s += ((c[1] + w).min(hi[1]) - (c[1] - w).max(lo[1])).max(0.0);
        }
        s * h
    }

    /// Slice areas integrated over the whole height with a fine composite rule after
    /// z = r sin θ, ignoring the breakpoints: an independent estimate of the 3D cut.
    fn ball_box_brute(c: Vector<3>, r: Real, lo: Vector<3>, hi: Vector<3>) -> Real {
        let n = 40_000;
        let t0 = ((lo[2] - c[2]) / r).clamp(-1.0, 1.0).asin();
        let t1 = ((hi[2] - c[2]) / r).clamp(-1.0, 1.0).asin();
        let h = (t1 - t0) / n as Real;
        let mut s = 0.0;
        for k in 0..n {
            let th = t0 + (k as Real + 0.5) * h;
            let rho = r * th.cos();
            let area = ball_box_volume(&v2(c[0], c[1]), rho, &v2(lo[0], lo[1]), &v2(hi[0], hi[1]));
            s += area * r * th.cos();
        }
        s * h
    }

    fn sorted(a: Real, b: Real) -> (Real, Real) {
        (a.min(b), a.max(b))
    }

    proptest! {
        #[test]
        fn disc_rectangle_matches_brute_force_and_splits_additively(
            cx in -2.0f64..2.0, cy in -2.0f64..2.0, r in 0.1f64..3.0,
            x0 in -4.0f64..4.0, x1 in -4.0f64..4.0, y0 in -4.0f64..4.0, y1 in -4.0f64..4.0,
            s in 0.0f64..1.0,
        ) {
            let (x0, x1) = sorted(x0, x1);
            let (y0, y1) = sorted(y0, y1);
            let c = v2(cx, cy);
            let whole = ball_box_volume(&c, r, &v2(x0, y0), &v2(x1, y1));
            let full = PI * r * r;
            let brute = disc_rect_brute(c, r, v2(x0, y0), v2(x1, y1));
            prop_assert!((whole - brute).abs() < 1e-6 * full, "{} vs {}", whole, brute);
            let xm = x0 + s * (x1 - x0);
            let left = ball_box_volume(&c, r, &v2(x0, y0), &v2(xm, y1));
            let right = ball_box_volume(&c, r, &v2(xm, y0), &v2(x1, y1));
            prop_assert!((left + right - whole).abs() < 1e-13 * full);
            let bigger = ball_box_volume(&c, r, &v2(x0 - s, y0), &v2(x1, y1 + s));
            prop_assert!(bigger >= whole - 1e-14 * full);
            prop_assert!(whole >= 0.0 && whole <= full * (1.0 + 1e-15));
        }

        #[test]
        fn ball_box_matches_brute_force_and_splits_additively(
            cx in -2.0f64..2.0, cy in -2.0f64..2.0, cz in -2.0f64..2.0, r in 0.1f64..3.0,
            x0 in -4.0f64..4.0, x1 in -4.0f64..4.0, y0 in -4.0f64..4.0, y1 in -4.0f64..4.0,
            z0 in -4.0f64..4.0, z1 in -4.0f64..4.0, s in 0.0f64..1.0,
        ) {
            let (x0, x1) = sorted(x0, x1);
            let (y0, y1) = sorted(y0, y1);
            let (z0, z1) = sorted(z0, z1);
            let c = v3(cx, cy, cz);
            let full = 4.0 / 3.0 * PI * r * r * r;
            let (lo, hi) = (v3(x0, y0, z0), v3(x1, y1, z1));
            let whole = ball_box_volume(&c, r, &lo, &hi);
            let brute = ball_box_brute(c, r, lo, hi);
            prop_assert!((whole - brute).abs() < 1e-6 * full, "{} vs {}", whole, brute);
            // Splitting moves the quadrature breakpoints: agreement tests accuracy.
            for axis in 0..3 {
                let mut mid_hi = hi;
                let mut mid_lo = lo;
                mid_hi[axis] = lo[axis] + s * (hi[axis] - lo[axis]);
                mid_lo[axis] = mid_hi[axis];
                let a = ball_box_volume(&c, r, &lo, &mid_hi);
                let b = ball_box_volume(&c, r, &mid_lo, &hi);
                prop_assert!((a + b - whole).abs() < 1e-11 * full,
                    "axis {}: {} + {} vs {}", axis, a, b, whole);
            }
            prop_assert!(whole >= 0.0 && whole <= full * (1.0 + 1e-14));
        }

        #[test]
        fn cubic_lattice_fills_pi_over_six_of_any_whole_cell_box(
            ox in 0.0f64..3.0, oy in 0.0f64..3.0, oz in 0.0f64..3.0,
            nx in 1usize..4, ny in 1usize..4, nz in 1usize..4,
        ) {
            // Spheres of diameter 1 on the unit lattice: any box whose sides are whole
            // numbers of cells holds π/6 of solid, however it cuts the spheres.
            let bed = lattice3(8);
            let lo = v3(ox, oy, oz);
            let hi = v3(ox + nx as Real, oy + ny as Real, oz + nz as Real);
            let reg = Region { lo, hi, wrap: [false; 3] };
            prop_assert!(close(reg.fraction(&bed), PI / 6.0, 1e-11), "{}", reg.fraction(&bed));
        }
    }

    /// Spheres of radius 1/2 on the unit cubic lattice filling an `n`-cube box.
    fn lattice3(n: usize) -> Bed<3> {
        let mut bed = Bed::new(
            Container {
                size: v3(n as Real, n as Real, n as Real),
                periodic: false,
            },
            Vec::new(),
        );
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    bed.push(
                        v3(i as Real + 0.5, j as Real + 0.5, k as Real + 0.5),
                        0.5,
                        0,
                    );
                }
            }
        }
        bed
    }

    #[test]
    fn cubic_lattice_global_and_bulk_fractions() {
        let bed = lattice3(10);
        assert!(close(global_fraction(&bed), PI / 6.0, 1e-13));
        // d_max = 1: [2, 8] laterally, [2, top − 3] = [2, 7] vertically.
        let reg = bulk_region(&bed).unwrap();
        assert_eq!((reg.lo, reg.hi), (v3(2.0, 2.0, 2.0), v3(8.0, 8.0, 7.0)));
        assert_eq!(reg.volume(), 180.0);
        assert!(close(bulk_fraction(&bed).unwrap(), PI / 6.0, 1e-13));
        // Half-cell offset: the region boundary passes through sphere centres.
        let cut = Region {
            lo: v3(2.5, 2.5, 2.5),
            hi: v3(7.5, 7.5, 6.5),
            wrap: [false; 3],
        };
        assert!(close(cut.fraction(&bed), PI / 6.0, 1e-13));
    }

    #[test]
    fn global_uses_the_top_when_particles_stick_out_of_the_roof() {
        let mut bed = lattice3(2);
        bed.container.size = v3(2.0, 2.0, 1.0);
        // 8 spheres of volume π/6 in a 2×2×2 box (the top, not the roof at 1).
        assert!(close(global_fraction(&bed), 8.0 * PI / 6.0 / 8.0, 1e-14));
        bed.container.size = v3(2.0, 2.0, 4.0);
        assert!(close(global_fraction(&bed), 8.0 * PI / 6.0 / 16.0, 1e-14));
    }

    #[test]
    fn periodic_square_lattice_counts_discs_crossing_the_side_fully() {
        // Discs of diameter 1 centred on x = 0..9, so the first crosses x = 0.
        let mut bed = Bed::new(
            Container {
                size: v2(10.0, 10.0),
                periodic: true,
            },
            Vec::new(),
        );
        for i in 0..10 {
            for j in 0..10 {
                bed.push(v2(i as Real, j as Real + 0.5), 0.5, 0);
            }
        }
        let reg = bulk_region(&bed).unwrap();
        assert_eq!(reg.wrap, [true, false]);
        assert_eq!((reg.lo, reg.hi), (v2(0.0, 2.0), v2(10.0, 7.0)));
        assert!(close(reg.fraction(&bed), PI / 4.0, 1e-14));
        assert!(close(global_fraction(&bed), PI / 4.0, 1e-14));
    }

    #[test]
    fn surface_of_a_wide_shallow_box_needs_no_grid_of_its_columns() {
        // 50000 × 50000 columns: a dense grid of them would take 20 GB.
        let mut bed = Bed::new(
            Container {
                size: v3(100_000.0, 100_000.0, 100.0),
                periodic: false,
            },
            Vec::new(),
        );
        bed.push(v3(1.0, 1.0, 1.0), 1.0, 0);
        bed.push(v3(1.5, 1.0, 3.0), 1.0, 0);
        bed.push(v3(50_000.0, 50_000.0, 1.0), 1.0, 0);
        let columns = 50_000.0 * 50_000.0;
        assert!(close(surface_height(&bed), (4.0 + 2.0) / columns, 1e-14));
    }

    #[test]
    fn small_or_empty_beds_have_no_bulk_region() {
        let empty: Bed<3> = Bed::new(
            Container {
                size: v3(10.0, 10.0, 10.0),
                periodic: false,
            },
            Vec::new(),
        );
        assert!(bulk_region(&empty).is_none());
        assert_eq!(global_fraction(&empty), 0.0);
        // Five diameters tall: 2 d_max above the floor meets 3 d_max below the top.
        let mut bed = lattice3(5);
        assert!(bulk_region(&bed).is_none());
        bed.container.size = v3(0.0, 5.0, 5.0);
        assert_eq!(global_fraction(&bed), 0.0);
    }

    #[test]
    fn overlapping_beads_of_a_chain_count_once() {
        let container = Container {
            size: v2(20.0, 20.0),
            periodic: false,
        };
        // Two beads of radius 1, centres 1 apart: union = 2πr² − lens, with the lens
        // 2 r² acos(d / 2r) − (d/2) sqrt(4r² − d²).
        let mut bed = Bed::new(container, Vec::new());
        bed.push_bead(v2(5.0, 5.0), 1.0, 0, 0);
        bed.push_bead(v2(6.0, 5.0), 1.0, 0, 0);
        let lens = 2.0 * (0.5f64).acos() - 0.5 * 3f64.sqrt();
        let got: Real = particle_volumes(&bed).iter().sum();
        assert!(close(got, 2.0 * PI - lens, 1e-14), "{got}");
        // In 3D the lens is π (2r − d)² (d + 4r) / 12.
        let mut bed3 = Bed::new(
            Container {
                size: v3(20.0, 20.0, 20.0),
                periodic: false,
            },
            Vec::new(),
        );
        bed3.push_bead(v3(5.0, 5.0, 5.0), 1.0, 0, 0);
        bed3.push_bead(v3(5.0, 5.6, 5.8), 1.0, 0, 0);
        let lens3 = PI * 1.0 * 1.0 * 5.0 / 12.0;
        let got3: Real = particle_volumes(&bed3).iter().sum();
        assert!(close(got3, 8.0 / 3.0 * PI - lens3, 1e-14), "{got3}");
        // Different bodies that overlap are not merged (an overlap is the checker's
        // business, not the packing fraction's).
        bed.bodies[1] = 1;
        let sep: Real = particle_volumes(&bed).iter().sum();
        assert!(close(sep, 2.0 * PI, 1e-15));
    }

    #[test]
    fn dense_straight_chain_union_matches_a_grid_count() {
        // Spacing 0.5 r: every point near the axis lies in three beads, where a
        // pairwise lens correction would be wrong.
        let mut bed = Bed::new(
            Container {
                size: v2(20.0, 20.0),
                periodic: false,
            },
            Vec::new(),
        );
        for k in 0..4 {
            bed.push_bead(
                v2(5.0 + 0.5 * k as Real * 0.6, 5.0 + 0.5 * k as Real * 0.8),
                1.0,
                0,
                0,
            );
        }
        let got: Real = particle_volumes(&bed).iter().sum();
        let n = 2000;
        let h = 5.0 / n as Real;
        let mut count = 0usize;
        for a in 0..n {
            for b in 0..n {
                let p = v2(3.5 + (a as Real + 0.5) * h, 3.5 + (b as Real + 0.5) * h);
                if bed.centres.iter().any(|c| (p - *c).norm2() <= 1.0) {
                    count += 1;
                }
            }
        }
        let grid = count as Real * h * h;
        assert!((got - grid).abs() < 2e-4 * got, "{got} vs {grid}");
    }
}
