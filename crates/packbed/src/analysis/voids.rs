//! Voids of a 2D bed: the faces of the contact network.
//!
//! The network is a plane graph: a vertex at each disc centre, an edge between
//! touching discs (the segment between their centres, which the two discs cover),
//! and a vertex where a disc touches a wall, joined to the disc's centre and to its
//! neighbours along the wall; the box corners and the roof line close the box.
//! Beads of one chain are joined in bead order. Around each vertex the edges are
//! sorted by angle, and walking every half-edge to the next one clockwise around
//! its end traces each face once, counter-clockwise.
//!
//! A void is a bounded face inside the bed: every face except the one outside the
//! box and the open space above the bed (the faces that hold a piece of the roof
//! line), and, with periodic sides, except faces that wind around the box (the
//! space above the bed and below the floor line). Its area is the area of the
//! polygon of its walk minus the sector of each disc at the corners of the walk
//! (a disc met twice, at the end of a dead-end edge, loses its whole area). Its
//! number of sides is the number of discs around it plus the wall segments it
//! touches. A cluster of discs not connected to the walls (only in imported beds)
//! is a hole in the face that holds it: its outline is subtracted from that face.
//! The area is exact when discs do not overlap; overlaps (DEM data, overlapping
//! beads of a chain) count the lens twice.

use super::contacts::Contacts;
use super::histogram::count_histogram;
use super::regions::analysis_height;
use crate::bed::Bed;
use crate::container::Wall;
use crate::math::Real;
use serde::Serialize;
use std::f64::consts::{PI, TAU};

/// One void.
#[derive(Clone, Debug, PartialEq)]
pub struct Void {
    /// Area of the void (polygon minus the disc sectors in it).
    pub area: Real,
    /// Discs around it plus wall segments.
    pub sides: u32,
    /// The discs around it, ascending.
    pub discs: Vec<u32>,
}

/// `voids.*` of `summary.json` (2D beds only).
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct VoidSummary {
    /// Number of voids.
    pub count: u64,
    /// Smallest void area (0 with no void).
    pub min_area: Real,
    /// Mean void area.
    pub mean_area: Real,
    /// Largest void area.
    pub max_area: Real,
    /// Mean void area ÷ the area of the largest disc.
    pub mean_area_scaled: Real,
    /// Sum of the void areas.
    pub total_area: Real,
    /// Mean number of sides.
    pub mean_sides: Real,
    /// Number of voids with 0, 1, 2, … sides.
    pub sides_histogram: Vec<u64>,
    /// Every void's area, in the order of `sides`.
    pub areas: Vec<Real>,
    /// Every void's number of sides.
    pub sides: Vec<u32>,
}

/// What an edge of the network is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// Between discs, or a disc and its wall contact point.
    Link,
    /// A piece of a wall or the floor.
    Wall,
    /// The roof line.
    Roof,
}

/// The half-edge structure of the network.
struct PlanarGraph {
    /// Position of each vertex (discs first, `0..n`).
    pos: Vec<[Real; 2]>,
    /// Per half-edge: start vertex, end vertex, displacement, kind.
    from: Vec<u32>,
    to: Vec<u32>,
    disp: Vec<[Real; 2]>,
    kind: Vec<Kind>,
    /// Next half-edge of the same face.
    next: Vec<u32>,
    /// Number of discs.
    discs: usize,
}

impl PlanarGraph {
    fn build(bed: &Bed<2>, contacts: &Contacts) -> PlanarGraph {
        let n = bed.len();
        let w = bed.container.size[0];
        let h = analysis_height(bed);
        let periodic = bed.container.periodic;
        let mut pos: Vec<[Real; 2]> = bed.centres.iter().map(|c| [c[0], c[1]]).collect();
        let mut edges: Vec<(u32, u32, [Real; 2], Kind)> = Vec::new();
        let link = |a: usize, b: usize| -> [Real; 2] {
            let d = bed.container.displacement(&bed.centres[a], &bed.centres[b]);
            [d[0], d[1]]
        };
        for c in &contacts.pairs {
            let (i, j) = (c.i as usize, c.j as usize);
            if i < n && j < n {
                edges.push((c.i, c.j, link(i, j), Kind::Link));
            }
        }
        for i in 1..n {
            if bed.bodies[i] == bed.bodies[i - 1] {
                edges.push(((i - 1) as u32, i as u32, link(i - 1, i), Kind::Link));
            }
        }
        // Points along each wall: (coordinate along the wall, vertex).
        let mut floor: Vec<(Real, u32)> = Vec::new();
        let mut left: Vec<(Real, u32)> = Vec::new();
        let mut right: Vec<(Real, u32)> = Vec::new();
        for wc in &contacts.walls {
            let i = wc.i as usize;
            if i >= n {
                continue;
            }
            let c = bed.centres[i];
            let (p, list) = match wc.wall {
                Wall::Floor => ([c[0], 0.0], &mut floor),
                Wall::Low(_) => ([0.0, c[1]], &mut left),
                Wall::High(_) => ([w, c[1]], &mut right),
            };
            let v = pos.len() as u32;
            pos.push(p);
            list.push((if wc.wall == Wall::Floor { p[0] } else { p[1] }, v));
            edges.push((wc.i, v, [p[0] - c[0], p[1] - c[1]], Kind::Link));
        }
        let by_coord = |a: &(Real, u32), b: &(Real, u32)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
        floor.sort_by(by_coord);
        left.sort_by(by_coord);
        right.sort_by(by_coord);
        let chain = |pts: &[u32], pos: &[[Real; 2]], edges: &mut Vec<_>| {
            for p in pts.windows(2) {
                let (a, b) = (pos[p[0] as usize], pos[p[1] as usize]);
                edges.push((p[0], p[1], [b[0] - a[0], b[1] - a[1]], Kind::Wall));
            }
        };
        if periodic {
            let pts: Vec<u32> = floor.iter().map(|e| e.1).collect();
            chain(&pts, &pos, &mut edges);
            if let (Some(&a), Some(&b)) = (pts.last(), pts.first()) {
                let (pa, pb) = (pos[a as usize], pos[b as usize]);
                edges.push((a, b, [pb[0] + w - pa[0], 0.0], Kind::Wall));
            }
        } else {
            let corner = |p: [Real; 2], pos: &mut Vec<[Real; 2]>| {
                pos.push(p);
                (pos.len() - 1) as u32
            };
            let c00 = corner([0.0, 0.0], &mut pos);
            let c10 = corner([w, 0.0], &mut pos);
            let c11 = corner([w, h], &mut pos);
            let c01 = corner([0.0, h], &mut pos);
            let mut pts = vec![c00];
            pts.extend(floor.iter().map(|e| e.1));
            pts.push(c10);
            pts.extend(right.iter().map(|e| e.1));
            pts.push(c11);
            chain(&pts, &pos, &mut edges);
            let mut pts = vec![c00];
            pts.extend(left.iter().map(|e| e.1));
            pts.push(c01);
            chain(&pts, &pos, &mut edges);
            edges.push((c01, c11, [w, 0.0], Kind::Roof));
        }
        let m = 2 * edges.len();
        let mut net = PlanarGraph {
            pos,
            from: Vec::with_capacity(m),
            to: Vec::with_capacity(m),
            disp: Vec::with_capacity(m),
            kind: Vec::with_capacity(m),
            next: vec![0; m],
            discs: n,
        };
        for &(a, b, d, k) in &edges {
            // Half-edge 2e goes a → b, 2e + 1 is its twin.
            net.from.extend([a, b]);
            net.to.extend([b, a]);
            net.disp.extend([d, [-d[0], -d[1]]]);
            net.kind.extend([k, k]);
        }
        // Half-edges around each vertex, sorted by angle (counter-clockwise).
        let nv = net.pos.len();
        let (start, mut around) = crate::math::sparse::group_by_key(&net.from, nv);
        let angle: Vec<Real> = net.disp.iter().map(|d| d[1].atan2(d[0])).collect();
        let mut slot = vec![0usize; m];
        for v in 0..nv {
            let s = &mut around[start[v]..start[v + 1]];
            s.sort_by(|&a, &b| {
                angle[a as usize]
                    .total_cmp(&angle[b as usize])
                    .then(a.cmp(&b))
            });
            for (k, &e) in s.iter().enumerate() {
                slot[e as usize] = start[v] + k;
            }
        }
        // next(u → v) = the half-edge before (v → u) counter-clockwise around v:
        // the face on the left is walked counter-clockwise.
        for e in 0..m {
            let twin = e ^ 1;
            let v = net.from[twin] as usize;
            let k = slot[twin];
            let prev = if k == start[v] {
                start[v + 1] - 1
            } else {
                k - 1
            };
            net.next[e] = around[prev];
        }
        net
    }
}

/// A traced face.
struct Face {
    /// Signed polygon area (positive: counter-clockwise).
    polygon: Real,
    /// Sum of the disc sectors at its corners.
    sectors: Real,
    /// Displacement after one walk round (non-zero: it winds round a periodic box).
    winding: [Real; 2],
    /// Holds a piece of the roof.
    roof: bool,
    /// Discs on the walk, ascending, distinct.
    discs: Vec<u32>,
    /// Wall half-edges on the walk.
    walls: u32,
    /// The polygon, unwrapped.
    ring: Vec<[Real; 2]>,
    /// A vertex on the walk (to find its component).
    vertex: u32,
}

fn trace(net: &PlanarGraph, radii: &[Real]) -> Vec<Face> {
    let m = net.from.len();
    let mut done = vec![false; m];
    let mut faces = Vec::new();
    for e0 in 0..m {
        if done[e0] {
            continue;
        }
        let mut p = net.pos[net.from[e0] as usize];
        let mut face = Face {
            polygon: 0.0,
            sectors: 0.0,
            winding: [0.0; 2],
            roof: false,
            discs: Vec::new(),
            walls: 0,
            ring: Vec::new(),
            vertex: net.from[e0],
        };
        let mut e = e0;
        loop {
            done[e] = true;
            let d = net.disp[e];
            let q = [p[0] + d[0], p[1] + d[1]];
            face.polygon += 0.5 * (p[0] * q[1] - p[1] * q[0]);
            face.ring.push(p);
            face.winding[0] += d[0];
            face.winding[1] += d[1];
            match net.kind[e] {
                Kind::Roof => face.roof = true,
                Kind::Wall => face.walls += 1,
                Kind::Link => {}
            }
            let f = net.next[e] as usize;
            let v = net.to[e] as usize;
            if v < net.discs {
                // The corner angle from the outgoing edge round to the incoming one.
                let din = net.disp[e ^ 1];
                let dout = net.disp[f];
                let mut a = din[1].atan2(din[0]) - dout[1].atan2(dout[0]);
                if f == (e ^ 1) {
                    a = TAU;
                } else {
                    a = a.rem_euclid(TAU);
                }
                face.sectors += 0.5 * a * radii[v] * radii[v];
                face.discs.push(v as u32);
            }
            p = q;
            e = f;
            if e == e0 {
                break;
            }
        }
        face.discs.sort_unstable();
        face.discs.dedup();
        faces.push(face);
    }
    faces
}

/// True when `p` lies inside the closed polygon `ring` (even–odd rule).
fn inside(ring: &[[Real; 2]], p: [Real; 2]) -> bool {
    let mut c = false;
    let m = ring.len();
    for k in 0..m {
        let (a, b) = (ring[k], ring[(k + 1) % m]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                c = !c;
            }
        }
    }
    c
}

/// Every void of a 2D bed.
pub fn voids(bed: &Bed<2>, contacts: &Contacts) -> Vec<Void> {
    if bed.is_empty() {
        return Vec::new();
    }
    let net = PlanarGraph::build(bed, contacts);
    let faces = trace(&net, &bed.radii);
    let nv = net.pos.len();
    // Components of the network, and which touch a wall vertex.
    let mut comp = vec![u32::MAX; nv];
    let mut wall_comp = Vec::new();
    let mut adj_start = vec![0usize; nv + 1];
    for &f in &net.from {
        adj_start[f as usize + 1] += 1;
    }
    for v in 0..nv {
        adj_start[v + 1] += adj_start[v];
    }
    let mut adj = vec![0u32; net.to.len()];
    let mut fill = adj_start.clone();
    for e in 0..net.from.len() {
        let f = net.from[e] as usize;
        adj[fill[f]] = net.to[e];
        fill[f] += 1;
    }
    for s in 0..nv {
        if comp[s] != u32::MAX {
            continue;
        }
        let id = wall_comp.len() as u32;
        let mut touches_wall = false;
        let mut stack = vec![s];
        comp[s] = id;
        while let Some(u) = stack.pop() {
            touches_wall |= u >= net.discs;
            for &v in &adj[adj_start[u]..adj_start[u + 1]] {
                if comp[v as usize] == u32::MAX {
                    comp[v as usize] = id;
                    stack.push(v as usize);
                }
            }
        }
        wall_comp.push(touches_wall);
    }
    let ncomp = wall_comp.len();
    // The outline of each floating component: its face of least signed area (an
    // isolated disc has no face: it is its own outline).
    let mut outline: Vec<Option<usize>> = vec![None; ncomp];
    for (k, f) in faces.iter().enumerate() {
        let c = comp[f.vertex as usize] as usize;
        if wall_comp[c] {
            continue;
        }
        if outline[c].is_none_or(|o| f.polygon < faces[o].polygon) {
            outline[c] = Some(k);
        }
    }
    let tiny = 1e-9 * bed.container.size[0].abs().max(1.0);
    let is_void: Vec<bool> = faces
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let c = comp[f.vertex as usize] as usize;
            let winds = f.winding[0].abs() > tiny;
            !f.roof && !winds && f.polygon > 0.0 && outline[c] != Some(k)
        })
        .collect();
    let mut area: Vec<Real> = faces.iter().map(|f| f.polygon - f.sectors).collect();
    let mut holes_in: Vec<Vec<u32>> = vec![Vec::new(); faces.len()];
    // Place each floating component in the smallest void face around it.
    let w = bed.container.size[0];
    let shifts: &[Real] = if bed.container.periodic {
        &[0.0, -1.0, 1.0]
    } else {
        &[0.0]
    };
    for c in 0..ncomp {
        if wall_comp[c] {
            continue;
        }
        let (rep, hole_area, discs): (usize, Real, Vec<u32>) = match outline[c] {
            Some(o) => (
                faces[o].vertex as usize,
                faces[o].polygon - faces[o].sectors,
                faces[o].discs.clone(),
            ),
            None => {
                let v = comp.iter().position(|&x| x as usize == c).unwrap_or(0);
                let r = bed.radii.get(v).copied().unwrap_or(0.0);
                (v, -PI * r * r, vec![v as u32])
            }
        };
        let p = net.pos[rep];
        let mut best: Option<usize> = None;
        for (k, f) in faces.iter().enumerate() {
            if comp[f.vertex as usize] as usize == c
                || f.polygon.is_nan()
                || f.polygon <= 0.0
                || f.winding[0].abs() > tiny
            {
                continue;
            }
            if best.is_some_and(|b| faces[b].polygon <= f.polygon) {
                continue;
            }
            if shifts
                .iter()
                .any(|&s| inside(&f.ring, [p[0] + s * w, p[1]]))
            {
                best = Some(k);
            }
        }
        if let Some(b) = best {
            area[b] += hole_area;
            holes_in[b].extend(discs);
        }
    }
    let mut out = Vec::new();
    for (k, f) in faces.iter().enumerate() {
        if !is_void[k] {
            continue;
        }
        let mut discs = f.discs.clone();
        discs.extend(&holes_in[k]);
        discs.sort_unstable();
        discs.dedup();
        out.push(Void {
            area: area[k].max(0.0),
            sides: f.discs.len() as u32 + f.walls,
            discs,
        });
    }
    out
}

/// The summary of the voids of a 2D bed.
pub fn void_summary(bed: &Bed<2>, voids: &[Void]) -> VoidSummary {
    let count = voids.len();
    let areas: Vec<Real> = voids.iter().map(|v| v.area).collect();
    let sides: Vec<u32> = voids.iter().map(|v| v.sides).collect();
    let total: Real = areas.iter().sum();
    let mean = if count > 0 {
        total / count as Real
    } else {
        0.0
    };
    let r = bed.r_max();
    let largest = PI * r * r;
    VoidSummary {
        count: count as u64,
        min_area: areas.iter().copied().reduce(Real::min).unwrap_or(0.0),
        mean_area: mean,
        max_area: areas.iter().copied().reduce(Real::max).unwrap_or(0.0),
        mean_area_scaled: if largest > 0.0 { mean / largest } else { 0.0 },
        total_area: total,
        mean_sides: if count > 0 {
            sides.iter().map(|&s| Real::from(s)).sum::<Real>() / count as Real
        } else {
            0.0
        },
        sides_histogram: count_histogram(sides.iter().copied()),
        areas,
        sides,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::find_contacts;

    fn found(bed: &Bed<2>) -> Vec<Void> {
        voids(bed, &find_contacts(bed, 1e-9))
    }

    /// `k` unit discs touching in a ring around `(cx, cy)`.
    fn ring(k: usize, cx: Real, cy: Real) -> Vec<(Real, Real, Real)> {
        let rho = 1.0 / (PI / k as Real).sin();
        (0..k)
            .map(|i| {
                let a = TAU * i as Real / k as Real;
                (cx + rho * a.cos(), cy + rho * a.sin(), 1.0)
            })
            .collect()
    }

    #[test]
    fn rings_of_touching_discs_enclose_the_known_void() {
        for k in [3usize, 4, 5, 6, 9] {
            // Polygon of k sides of length 2 minus k sectors of the interior angle.
            let polygon = k as Real / (PI / k as Real).tan();
            let want = polygon - 0.5 * (k as Real - 2.0) * PI;
            // Floating in a walled box: the ring is a hole in the open space.
            let v = found(&Bed::of_discs([20.0, 20.0], false, &ring(k, 10.0, 10.0)));
            assert_eq!(v.len(), 1, "k = {k}");
            assert!(
                (v[0].area - want).abs() < 1e-12,
                "k = {k}: {} vs {want}",
                v[0].area
            );
            assert_eq!(v[0].sides, k as u32);
            // Across the seam of a periodic box: the same void.
            let v = found(&Bed::of_discs([20.0, 20.0], true, &ring(k, 0.3, 10.0)));
            let v: Vec<&Void> = v.iter().collect();
            assert_eq!(v.len(), 1, "periodic k = {k}");
            assert!((v[0].area - want).abs() < 1e-12);
        }
    }

    #[test]
    fn floor_row_between_walls_closes_voids_with_the_walls() {
        // Three unit discs on the floor of a box 6 wide: two corner voids
        // (1 − π/4, a disc and two walls) and two floor voids (2 − π/2).
        let v = found(&Bed::of_discs(
            [6.0, 10.0],
            false,
            &[(1.0, 1.0, 1.0), (3.0, 1.0, 1.0), (5.0, 1.0, 1.0)],
        ));
        let mut areas: Vec<(Real, u32)> = v.iter().map(|v| (v.area, v.sides)).collect();
        areas.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert_eq!(areas.len(), 4);
        for (a, s) in &areas[..2] {
            assert!((a - (1.0 - PI / 4.0)).abs() < 1e-14);
            assert_eq!(*s, 3);
        }
        for (a, s) in &areas[2..] {
            assert!((a - (2.0 - PI / 2.0)).abs() < 1e-14);
            assert_eq!(*s, 3);
        }
        let s = void_summary(&Bed::of_discs([6.0, 10.0], false, &[(1.0, 1.0, 1.0)]), &v);
        assert_eq!(s.count, 4);
        assert!((s.total_area - (6.0 - 1.5 * PI)).abs() < 1e-13);
        assert!((s.mean_area_scaled - (6.0 - 1.5 * PI) / 4.0 / PI).abs() < 1e-13);
        assert_eq!(s.sides_histogram, vec![0, 0, 0, 4]);
    }

    #[test]
    fn periodic_floor_row_wraps_into_floor_voids() {
        // Three unit discs on the floor of a periodic box 6 wide: three floor voids.
        let v = found(&Bed::of_discs(
            [6.0, 10.0],
            true,
            &[(1.0, 1.0, 1.0), (3.0, 1.0, 1.0), (5.0, 1.0, 1.0)],
        ));
        assert_eq!(v.len(), 3);
        for v in &v {
            assert!((v.area - (2.0 - PI / 2.0)).abs() < 1e-14);
        }
    }

    #[test]
    fn dead_ends_and_rattlers_are_taken_out_of_their_void() {
        // A ring of 9 (a big void) with one disc hanging inside from a contact and
        // one free disc (a rattler) inside.
        let mut discs = ring(9, 10.0, 10.0);
        let rho = 1.0 / (PI / 9.0).sin();
        discs.push((10.0 + rho - 2.0, 10.0, 1.0)); // touches ring disc 0 only
        discs.push((10.0 - 0.5, 10.0, 0.5)); // touches nothing
        let v = found(&Bed::of_discs([20.0, 20.0], false, &discs));
        let polygon = 9.0 / (PI / 9.0).tan();
        let want = polygon - 3.5 * PI - PI - PI * 0.25;
        assert_eq!(v.len(), 1);
        assert!((v[0].area - want).abs() < 1e-12, "{} vs {want}", v[0].area);
        assert_eq!(v[0].discs.len(), 11);
    }
}
