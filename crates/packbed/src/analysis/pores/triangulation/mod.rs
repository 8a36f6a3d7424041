//! The regular (power, weighted Delaunay) triangulation of weighted points in
//! 2D and 3D: one Bowyer–Watson engine for both dimensions.
//!
//! Points are inserted along a Hilbert curve; each is located by a stochastic
//! visibility walk from the last cell made (a straight walk can cycle in a
//! regular triangulation, a randomised one cannot), the cells whose orthogonal
//! sphere it conflicts with are removed and the cavity is closed with cells on
//! its boundary facets. The predicates are exact (`math::predicates`) and the
//! power test is symbolically perturbed by point index, so lattices and other
//! degenerate inputs give a valid triangulation: every cell positively
//! oriented, every facet locally regular.
//!
//! The engine starts from a simplex of far points of weight 0 that holds every
//! input point; cells with one of those corners are not part of the result.
//! Near the convex hull of the input this can differ from the triangulation of
//! the input alone; the pore space is only ever read well inside it (periodic
//! images, mirror images and the bulk slab keep the hull away).

mod split;

use crate::math::predicates::{
    orient2d, orient3d, power_test_2d_oriented_lazy, power_test_3d_oriented_lazy,
};

/// For two distinct vertex positions of a tetrahedron, the other two.
const OTHER_TWO: [[(usize, usize); 4]; 4] = [
    [(0, 0), (2, 3), (1, 3), (1, 2)],
    [(2, 3), (0, 0), (0, 3), (0, 2)],
    [(1, 3), (0, 3), (0, 0), (0, 1)],
    [(1, 2), (0, 2), (0, 1), (0, 0)],
];

/// Slots of the ridge table (12 bytes each) beyond which a cavity's ridges
/// are paired by sorting instead. In the tests, small cavities (up to three
/// cells) take the table and larger ones sort, so that both ways are checked
/// on every triangulation the tests build.
const fn ridge_table_max(dim: usize) -> usize {
    match (cfg!(test), dim) {
        (false, _) => 1 << 20,
        (true, 2) => 5,
        (true, _) => 36,
    }
}

/// No neighbour (only across the facets of the far simplex).
pub const NONE: u32 = u32::MAX;

/// A regular triangulation of weighted points in `D` dimensions.
#[derive(Clone, Debug)]
pub struct Triangulation<const D: usize> {
    /// The points with their weights (radius squared for a sphere): the
    /// input, then the `D + 1` far corners. Together, because a power test
    /// reads both: one cache line per vertex instead of two.
    sites: Vec<([f64; D], f64)>,
    /// Priority of each point in the symbolic perturbation (distinct); read
    /// only when a power test is exactly zero.
    ranks: Vec<u64>,
    /// Number of input points.
    input: usize,
    /// The cells with their neighbours; a freed slot has vertex 0 `NONE`.
    cells: Vec<Cell>,
    free: Vec<u32>,
    /// Input points that have no cell (their sphere lies within the power
    /// cells of others: only possible where spheres overlap).
    hidden: Vec<u32>,
}

/// A cell: its vertices, positively oriented (only the first `D + 1` used),
/// and the neighbour across the facet opposite each. One 32-byte record, so
/// that the conflict search reads one cache line per cell.
#[derive(Clone, Copy, Debug)]
#[repr(align(32))]
struct Cell {
    v: [u32; 4],
    n: [u32; 4],
}

/// Work space of one insertion, kept between insertions to avoid allocation.
#[derive(Default)]
struct Scratch {
    /// Per cell: twice the insertion that last visited it, plus 1 if it
    /// conflicted (one word: half the cache lines of a pair).
    visit: Vec<u32>,
    /// Per point: the insertion that last marked it as a vertex of the
    /// cavity's boundary, and its number among those vertices.
    mark: Vec<(u32, u32)>,
    stack: Vec<u32>,
    conflict: Vec<u32>,
    /// Boundary facets: (removed cell, index of the vertex q replaces, outer cell).
    boundary: Vec<(u32, usize, u32)>,
    /// Ridges of the new cells waiting for their partner: (insertion stamp,
    /// cell, facet), at the ridge's pair of boundary-vertex numbers, a table
    /// small enough to stay in the first-level cache. A hash table over vertex
    /// ids spent a tenth of the insertion waiting for its slots, a linear list
    /// a quarter.
    ridges: Vec<(u32, u32, u32)>,
    /// The same for a cavity too large for that table: (ridge, cell, facet),
    /// paired by sorting.
    sorted: Vec<(usize, u32, u32)>,
    created: Vec<u32>,
}

impl<const D: usize> Triangulation<D> {
    /// Vertices per cell.
    pub const V: usize = D + 1;

    /// The regular triangulation of `points` with `weights` (radius squared).
    /// Every coordinate and weight must be finite.
    pub fn new(points: &[[f64; D]], weights: &[f64]) -> Self {
        let ranks: Vec<u64> = (0..points.len() as u64).collect();
        Self::with_ranks(points, weights, &ranks)
    }

    /// The same with the priorities of the perturbation given: distinct, and
    /// below `u64::MAX − 4`. Periodic images rank by (particle, image), an
    /// order that a translation keeps, so that the translates of a degenerate
    /// configuration (a lattice) are split into cells the same way.
    ///
    /// Large inputs are triangulated in two pieces on two threads
    /// (`split`): the same input cells, each once, with their links, and
    /// no far cells (their links read `NONE`). Small ones, and any input
    /// whose pieces cannot be certified, in one piece.
    pub(crate) fn with_ranks(points: &[[f64; D]], weights: &[f64], ranks: &[u64]) -> Self {
        assert!(
            D == 2 || D == 3,
            "packbed triangulates in 2 or 3 dimensions"
        );
        assert_eq!(points.len(), weights.len());
        assert_eq!(points.len(), ranks.len());
        // Insertions are stamped in 31 bits (`Scratch::visit`); a bed that
        // large would not fit in memory anyway.
        assert!(points.len() < 1 << 30, "too many points to triangulate");
        let corners = far_corners(points, weights);
        if points.len() >= split::MIN_POINTS {
            if let Some(t) = split::triangulate(points, weights, ranks, &corners) {
                return t;
            }
        }
        Self::build(points, weights, ranks, &corners)
    }

    /// The triangulation in one piece, in the far simplex with these corners.
    fn build(points: &[[f64; D]], weights: &[f64], ranks: &[u64], corners: &[[f64; D]; 4]) -> Self {
        let input = points.len();
        // The points are stored in the order of insertion, along the Hilbert
        // curve, while the triangulation is built: a cavity's vertices then
        // lie together in memory, as they do in space (the input, in order of
        // deposition, scatters them). Every predicate sees the same values and
        // ranks, so the cells are the same; their vertices are renumbered to
        // the input's at the end.
        let order = crate::math::hilbert::order(points);
        let mut t = Triangulation {
            sites: order
                .iter()
                .map(|&i| (points[i as usize], weights[i as usize]))
                .collect(),
            ranks: order.iter().map(|&i| ranks[i as usize]).collect(),
            input,
            cells: Vec::new(),
            free: Vec::new(),
            hidden: Vec::new(),
        };
        // About 6.4 cells a point in a packed bed (2 in 2D): sized once, so
        // that the cells are not copied as they grow.
        let expected = if D == 2 { 2 * input } else { 13 * input / 2 } + 64;
        t.cells.reserve(expected);
        t.add_far_simplex(corners);
        let mut scratch = Scratch {
            mark: vec![(0, 0); t.sites.len()],
            visit: Vec::with_capacity(expected),
            ..Scratch::default()
        };
        let mut rng = 0x9E37_79B9_7F4A_7C15u64;
        let mut last = 0u32;
        for k in 0..input as u32 {
            last = t.insert(k, last, k + 1, &mut scratch, &mut rng);
        }
        drop(scratch);
        t.renumber_to_input(&order);
        t
    }

    /// Gives the vertices their input numbers back, `order[k]` being the input
    /// number of the `k`-th point inserted.
    fn renumber_to_input(&mut self, order: &[u32]) {
        let input = self.input;
        let mut on_cell = vec![false; input];
        for cell in &self.cells {
            if cell.v[0] != NONE {
                for &x in &cell.v[..Self::V] {
                    if (x as usize) < input {
                        on_cell[x as usize] = true;
                    }
                }
            }
        }
        self.hidden = (0..input as u32)
            .filter(|&k| !on_cell[k as usize])
            .collect();
        drop(on_cell);
        let to_input = |x: &mut u32| {
            if (*x as usize) < input {
                *x = order[*x as usize];
            }
        };
        for cell in &mut self.cells {
            if cell.v[0] != NONE {
                cell.v[..Self::V].iter_mut().for_each(to_input);
            }
        }
        self.hidden.iter_mut().for_each(to_input);
        self.hidden.sort_unstable();
        let mut sites = self.sites.clone();
        let mut ranks = self.ranks.clone();
        for (k, &i) in order.iter().enumerate() {
            sites[i as usize] = self.sites[k];
            ranks[i as usize] = self.ranks[k];
        }
        self.sites = sites;
        self.ranks = ranks;
    }

    /// Number of input points.
    pub(crate) fn input_len(&self) -> usize {
        self.input
    }

    /// The input points with no cell, in index order.
    pub fn hidden(&self) -> &[u32] {
        &self.hidden
    }

    /// Coordinates of point `i`.
    pub(crate) fn point(&self, i: u32) -> &[f64; D] {
        &self.sites[i as usize].0
    }

    /// Weight of point `i`.
    pub(crate) fn weight(&self, i: u32) -> f64 {
        self.sites[i as usize].1
    }

    /// Number of cell slots (alive or not); cell ids are below it.
    pub fn slots(&self) -> usize {
        self.cells.len()
    }

    /// The vertices of cell `c` (the first `D + 1` entries).
    pub fn vertices(&self, c: u32) -> &[u32] {
        &self.cells[c as usize].v[..Self::V]
    }

    /// The neighbours of cell `c`, opposite each vertex.
    pub fn neighbours(&self, c: u32) -> &[u32] {
        &self.cells[c as usize].n[..Self::V]
    }

    /// True when `c` is a cell of the triangulation of the input: alive and
    /// without a far corner.
    pub fn is_input_cell(&self, c: u32) -> bool {
        // A freed slot's vertex 0 is NONE, beyond the input like a far corner.
        self.vertices(c).iter().all(|&v| (v as usize) < self.input)
    }

    /// The cells of the input points' triangulation.
    pub fn input_cells(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.cells.len() as u32).filter(move |&c| self.is_input_cell(c))
    }

    /// The far simplex (corners from [`far_corners`]), the first cell.
    fn add_far_simplex(&mut self, corner: &[[f64; D]; 4]) {
        let first = self.sites.len() as u32;
        let mut v = [0u32; 4];
        for (k, c) in corner.iter().enumerate().take(D + 1) {
            self.sites.push((*c, 0.0));
            self.ranks.push(u64::MAX - k as u64);
            v[k] = first + k as u32;
        }
        if self.orient_of(&v) < 0 {
            v.swap(0, 1);
        }
        self.cells.push(Cell { v, n: [NONE; 4] });
    }

    /// Orientation of the cell with these vertices.
    fn orient_of(&self, v: &[u32; 4]) -> i8 {
        let p = |k: usize| &self.sites[v[k] as usize].0;
        orient::<D>([p(0), p(1), p(2), p(if D == 3 { 3 } else { 0 })])
    }

    /// True when point `q` conflicts with cell `c` (lies inside its orthogonal
    /// sphere in the power sense, ties broken by the perturbation).
    fn conflicts(&self, c: u32, q: u32) -> bool {
        power_test::<D>(&self.sites, &self.ranks, &self.cells[c as usize].v, q) > 0
    }

    /// The cell that contains point `q`, by a stochastic visibility walk from `start`.
    fn locate(&self, q: u32, start: u32, rng: &mut u64) -> u32 {
        let qp = &self.sites[q as usize].0;
        let mut c = start;
        let mut from = NONE;
        'walk: loop {
            let Cell { v, n: adjacent } = &self.cells[c as usize];
            let offset = (next_random(rng) % Self::V as u64) as usize;
            for k in 0..Self::V {
                let i = (offset + k) % Self::V;
                let n = adjacent[i];
                if n == from || n == NONE {
                    continue;
                }
                let mut p = [qp; 4];
                for (j, pj) in p.iter_mut().enumerate().take(Self::V) {
                    if j != i {
                        *pj = &self.sites[v[j] as usize].0;
                    }
                }
                if D == 2 {
                    p[3] = p[0];
                }
                if orient::<D>(p) < 0 {
                    from = c;
                    c = n;
                    continue 'walk;
                }
            }
            return c;
        }
    }

    /// Inserts point `q`, searching from cell `start`; returns a cell to start
    /// the next search from.
    fn insert(&mut self, q: u32, start: u32, stamp: u32, s: &mut Scratch, rng: &mut u64) -> u32 {
        let c0 = self.locate(q, start, rng);
        if !self.conflicts(c0, q) {
            // q's power cell is empty: it is hidden from the start (found
            // with the others at the end).
            return c0;
        }
        if s.visit.len() < self.cells.len() {
            s.visit.resize(self.cells.len(), 0);
        }
        s.stack.clear();
        s.conflict.clear();
        s.boundary.clear();
        let seen = 2 * stamp;
        s.visit[c0 as usize] = seen + 1;
        s.stack.push(c0);
        while let Some(c) = s.stack.pop() {
            s.conflict.push(c);
            for i in 0..Self::V {
                let n = self.cells[c as usize].n[i];
                let inside = n != NONE && {
                    let visit = s.visit[n as usize];
                    if visit & !1 == seen {
                        visit == seen + 1
                    } else {
                        let hit = self.conflicts(n, q);
                        s.visit[n as usize] = seen + u32::from(hit);
                        if hit {
                            s.stack.push(n);
                        }
                        hit
                    }
                };
                if !inside {
                    s.boundary.push((c, i, n));
                }
            }
        }
        // Number the boundary's vertices. Vertices of the removed cells that
        // are on no boundary facet leave the triangulation (q's sphere covers
        // their power cell); they are found at the end, as the points on no
        // cell, rather than here on every insertion: in a bed of disjoint
        // spheres none ever is, since each centre lies in its own power cell.
        let mut count = 0u32;
        for &(c, i, _) in &s.boundary {
            let v = &self.cells[c as usize].v;
            for step in 1..Self::V {
                // Whether a vertex is met for the first time is a coin toss
                // to the branch predictor: written either way.
                let x = v[(i + step) % Self::V] as usize;
                let met = s.mark[x];
                let first = met.0 != stamp;
                s.mark[x] = if first { (stamp, count) } else { met };
                count += u32::from(first);
            }
        }
        // New cells take slots freed by earlier insertions only, so that an
        // outer cell's link to a removed cell is never mistaken for a new one.
        s.created.clear();
        // A ridge is the boundary facet less q's vertex and one other: one
        // vertex in 2D, two in 3D, numbered below `count`.
        let count = count as usize;
        let wanted = if D == 2 { count } else { count * count };
        // The table grows with the square of the boundary: a cavity of
        // thousands of vertices (points on one sphere) pairs by sorting.
        let by_table = wanted <= ridge_table_max(D);
        if by_table && s.ridges.len() < wanted {
            s.ridges.resize(wanted, (0, 0, 0));
        }
        s.sorted.clear();
        for b in 0..s.boundary.len() {
            let (old, i, outer) = s.boundary[b];
            // Built by selection, not by storing one entry into an array and
            // then copying it whole: that stalled store forwarding on every
            // new cell (5 % of the insertion in a profile).
            let ov = self.cells[old as usize].v;
            let v: [u32; 4] = std::array::from_fn(|j| if j == i { q } else { ov[j] });
            let n: [u32; 4] = std::array::from_fn(|j| if j == i { outer } else { NONE });
            let nc = match self.free.pop() {
                Some(slot) => {
                    self.cells[slot as usize] = Cell { v, n };
                    slot
                }
                None => {
                    self.cells.push(Cell { v, n });
                    s.visit.push(0);
                    (self.cells.len() - 1) as u32
                }
            };
            if outer != NONE {
                // Without a branch per entry: which one links back is a coin
                // toss to the branch predictor.
                let links = &self.cells[outer as usize].n;
                let back = (0..Self::V).fold(0, |b, j| if links[j] == old { j } else { b });
                debug_assert_eq!(links[back], old);
                self.cells[outer as usize].n[back] = nc;
            }
            // The facets through q: across facet k (k ≠ i) lies the ridge made
            // of the facet's other vertices, met by exactly one other new cell.
            let mut number = [0usize; 4];
            for (j, &x) in v.iter().enumerate().take(Self::V) {
                number[j] = s.mark[x as usize].1 as usize;
            }
            for step in 1..Self::V {
                let k = (i + step) % Self::V;
                let slot = if D == 2 {
                    number[3 - i - k]
                } else {
                    let (a, b) = OTHER_TWO[i][k];
                    let (a, b) = (number[a], number[b]);
                    a.min(b) * count + a.max(b)
                };
                if !by_table {
                    s.sorted.push((slot, nc, k as u32));
                    continue;
                }
                // Unconditional writes, values chosen by the coin toss of
                // which of the two cells comes first: the first leaves its
                // own link open (NONE), the second closes both.
                let r = s.ridges[slot];
                let second = r.0 == stamp;
                s.ridges[slot] = (stamp, nc, k as u32);
                let (to, facet, link) = if second {
                    (r.1, r.2 as usize, nc)
                } else {
                    (nc, k, NONE)
                };
                self.cells[nc as usize].n[k] = if second { r.1 } else { NONE };
                self.cells[to as usize].n[facet] = link;
            }
            s.created.push(nc);
        }
        if !by_table {
            s.sorted.sort_unstable();
            for pair in s.sorted.chunks_exact(2) {
                let [(key, a, fa), (same, b, fb)] = [pair[0], pair[1]];
                debug_assert_eq!(key, same, "each ridge joins exactly two new cells");
                self.cells[a as usize].n[fa as usize] = b;
                self.cells[b as usize].n[fb as usize] = a;
            }
        }
        for &c in &s.conflict {
            self.cells[c as usize].v[0] = NONE;
            self.free.push(c);
        }
        s.created[0]
    }
}

/// The far simplex: `D + 1` points of weight 0 whose hull holds the input
/// with room to spare, so that the first cell is valid.
fn far_corners<const D: usize>(points: &[[f64; D]], weights: &[f64]) -> [[f64; D]; 4] {
    let (lo, hi) = if points.is_empty() {
        ([0.0; D], [1.0; D])
    } else {
        crate::math::bounds(points)
    };
    let w_max = weights.iter().fold(0.0f64, |m, &w| m.max(w));
    let extent = (0..D)
        .map(|k| hi[k] - lo[k])
        .fold(w_max.sqrt(), f64::max)
        .max(1.0);
    // Near: the corners enter every hull cell's power test, and at 1e3
    // extents their magnitude defeated the floating-point filter (the
    // exact fallback took 6 % of the time). Cells near the hull may then
    // differ from the input's own triangulation; the pore space is never
    // read there (the margin check sees to the sides, the slab to the top).
    let s = 3.0 * extent;
    let mut corner = [[0.0; D]; 4];
    for (k, c) in corner.iter_mut().enumerate().take(D + 1) {
        for a in 0..D {
            let centre = 0.5 * (lo[a] + hi[a]);
            // Corner k sits at -s on every axis but axis k-1 (corner 0 all -s),
            // where it sits at +D·s: a right simplex around the box.
            c[a] = if k >= 1 && a == k - 1 {
                centre + (D as f64 + 1.0) * s
            } else {
                centre - s
            };
        }
    }
    corner
}

/// Orientation of `D + 1` points (the fourth ignored in 2D).
pub(crate) fn orient<const D: usize>(p: [&[f64; D]; 4]) -> i8 {
    match D {
        2 => orient2d([p[0][0], p[0][1]], [p[1][0], p[1][1]], [p[2][0], p[2][1]]),
        _ => orient3d(
            [p[0][0], p[0][1], p[0][2]],
            [p[1][0], p[1][1], p[1][2]],
            [p[2][0], p[2][1], p[2][2]],
            [p[3][0], p[3][1], p[3][2]],
        ),
    }
}

/// The perturbed power test of point `q` against the cell with vertices `v`:
/// positive when `q` conflicts.
pub(crate) fn power_test<const D: usize>(
    sites: &[([f64; D], f64)],
    ranks: &[u64],
    v: &[u32; 4],
    q: u32,
) -> i8 {
    let p = |i: u32| &sites[i as usize].0;
    let w = |i: u32| sites[i as usize].1;
    let r = |i: u32| ranks[i as usize];
    match D {
        2 => {
            let at = |i: u32| [p(i)[0], p(i)[1]];
            let v = [v[0], v[1], v[2]];
            power_test_2d_oriented_lazy(v.map(at), v.map(w), at(q), w(q), || (v.map(r), r(q)))
        }
        _ => {
            // Gathered by hand: `array::map` was left out of line here, a
            // call per test (5 % of the insertion in a profile).
            let at = |i: u32| [p(i)[0], p(i)[1], p(i)[2]];
            let pts = [at(v[0]), at(v[1]), at(v[2]), at(v[3])];
            let ws = [w(v[0]), w(v[1]), w(v[2]), w(v[3])];
            power_test_3d_oriented_lazy(pts, ws, at(q), w(q), || {
                ([r(v[0]), r(v[1]), r(v[2]), r(v[3])], r(q))
            })
        }
    }
}

/// xorshift64*: the walk's coin, seeded the same for every triangulation so
/// that the result never depends on anything but the input.
fn next_random(state: &mut u64) -> u64 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    state.wrapping_mul(0x2545_F491_4F6C_DD1D)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Brute force: every input cell positively oriented, links symmetric,
    /// every facet locally regular, and no input point (not hidden) inside any
    /// input cell's orthogonal sphere.
    pub(crate) fn check_regular<const D: usize>(t: &Triangulation<D>) -> Result<(), String> {
        let v_n = D + 1;
        let mut is_vertex = vec![false; t.input_len()];
        for c in t.input_cells() {
            let v = t.cells[c as usize].v;
            if t.orient_of(&v) <= 0 {
                return Err(format!("cell {c} {v:?} is not positively oriented"));
            }
            for i in 0..v_n {
                let n = t.cells[c as usize].n[i];
                if n == NONE {
                    continue;
                }
                if t.cells[n as usize].v[0] == NONE {
                    return Err(format!("cell {c} links to a dead cell"));
                }
                let back = t.cells[n as usize].n[..v_n].iter().position(|&x| x == c);
                let Some(j) = back else {
                    return Err(format!("cell {n} does not link back to {c}"));
                };
                let far = t.cells[n as usize].v[j];
                if t.conflicts(c, far) {
                    return Err(format!("facet {i} of cell {c} is not locally regular"));
                }
            }
            for q in 0..t.input_len() as u32 {
                if !v[..v_n].contains(&q) && t.conflicts(c, q) && !t.hidden.contains(&q) {
                    return Err(format!("point {q} lies in the orthosphere of cell {c}"));
                }
            }
        }
        for c in 0..t.slots() {
            if t.cells[c].v[0] != NONE {
                for &x in &t.cells[c].v[..v_n] {
                    if (x as usize) < t.input_len() {
                        is_vertex[x as usize] = true;
                    }
                }
            }
        }
        for (q, &is) in is_vertex.iter().enumerate() {
            if !is && !t.hidden.contains(&(q as u32)) {
                return Err(format!("point {q} is neither a vertex nor hidden"));
            }
        }
        Ok(())
    }

    /// Sum of the input cells' volumes (areas in 2D).
    pub(crate) fn total_volume<const D: usize>(t: &Triangulation<D>) -> f64 {
        t.input_cells()
            .map(|c| {
                let v = t.vertices(c);
                let p = |k: usize| t.point(v[k]);
                let e = |k: usize| -> [f64; 3] {
                    let mut d = [0.0; 3];
                    for a in 0..D {
                        d[a] = p(k)[a] - p(0)[a];
                    }
                    d
                };
                let (a, b) = (e(1), e(2));
                if D == 2 {
                    0.5 * (a[0] * b[1] - a[1] * b[0])
                } else {
                    let c3 = e(3);
                    (a[0] * (b[1] * c3[2] - b[2] * c3[1]) - a[1] * (b[0] * c3[2] - b[2] * c3[0])
                        + a[2] * (b[0] * c3[1] - b[1] * c3[0]))
                        / 6.0
                }
            })
            .sum()
    }

    fn lattice<const D: usize>(n: usize, fcc: bool) -> (Vec<[f64; D]>, Vec<f64>) {
        let mut pts = Vec::new();
        let total = n.pow(D as u32);
        for i in 0..total {
            let mut p = [0.0; D];
            let mut r = i;
            for a in 0..D {
                p[a] = (r % n) as f64;
                r /= n;
            }
            pts.push(p);
            if fcc && D == 3 && p.iter().all(|&x| x < (n - 1) as f64) {
                for shift in [[0.5, 0.5, 0.0], [0.5, 0.0, 0.5], [0.0, 0.5, 0.5]] {
                    let mut q = p;
                    for a in 0..D {
                        q[a] += shift[a];
                    }
                    pts.push(q);
                }
            }
        }
        let w = vec![0.1; pts.len()];
        (pts, w)
    }

    #[test]
    fn lattices_tile_their_hull() {
        for n in [2usize, 3, 5] {
            let (p, w) = lattice::<3>(n, false);
            let t = Triangulation::new(&p, &w);
            check_regular(&t).unwrap();
            let side = (n - 1) as f64;
            assert!((total_volume(&t) - side.powi(3)).abs() < 1e-9, "n = {n}");
            let (p, w) = lattice::<2>(n, false);
            let t = Triangulation::new(&p, &w);
            check_regular(&t).unwrap();
            assert!((total_volume(&t) - side * side).abs() < 1e-9);
        }
        // Face-centred cubic points (inside the cubes of a 4³ lattice).
        let (p, w) = lattice::<3>(4, true);
        let t = Triangulation::new(&p, &w);
        check_regular(&t).unwrap();
        assert!((total_volume(&t) - 27.0).abs() < 1e-9);
        assert!(t.hidden().is_empty());
    }

    #[test]
    fn a_sphere_inside_anothers_power_cell_is_hidden() {
        // A big sphere at the origin and a small one near its centre.
        let mut p = vec![[0.0, 0.0, 0.0], [0.1, 0.0, 0.0]];
        let mut w = vec![4.0, 0.01];
        for k in 0..20 {
            let a = k as f64;
            p.push([
                5.0 * (a * 0.7).cos(),
                5.0 * (a * 1.3).sin(),
                5.0 * (a * 0.3).cos(),
            ]);
            w.push(0.25);
        }
        let t = Triangulation::new(&p, &w);
        check_regular(&t).unwrap();
        assert_eq!(t.hidden(), &[1]);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn random_weighted_points_are_regular_3d(
            pts in prop::collection::vec(([0.0f64..10.0, 0.0f64..10.0, 0.0f64..10.0], 0.0f64..1.0), 5..120)
        ) {
            let p: Vec<[f64; 3]> = pts.iter().map(|(x, _)| *x).collect();
            let w: Vec<f64> = pts.iter().map(|x| x.1).collect();
            let t = Triangulation::new(&p, &w);
            prop_assert_eq!(check_regular(&t), Ok(()));
        }

        #[test]
        fn random_weighted_points_are_regular_2d(
            pts in prop::collection::vec(([0.0f64..10.0, 0.0f64..10.0], 0.0f64..1.0), 4..150)
        ) {
            let p: Vec<[f64; 2]> = pts.iter().map(|(x, _)| *x).collect();
            let w: Vec<f64> = pts.iter().map(|x| x.1).collect();
            let t = Triangulation::new(&p, &w);
            prop_assert_eq!(check_regular(&t), Ok(()));
        }

        #[test]
        fn integer_grids_with_few_weights_are_regular(
            pts in prop::collection::vec(([0u8..4, 0u8..4, 0u8..4], 0u8..3), 5..60)
        ) {
            // Many cospherical and coplanar points, repeated points and equal weights.
            let p: Vec<[f64; 3]> = pts.iter().map(|(x, _)| x.map(f64::from)).collect();
            let w: Vec<f64> = pts.iter().map(|x| x.1 as f64 * 0.05).collect();
            let t = Triangulation::new(&p, &w);
            prop_assert_eq!(check_regular(&t), Ok(()));
        }
    }
}
