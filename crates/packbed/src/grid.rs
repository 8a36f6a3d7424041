//! Multilevel cell grid for neighbour queries, growing upwards as the bed grows.
//!
//! Particles are sorted by radius into levels (Ogarko & Luding 2012, "A fast
//! multilevel algorithm for contact detection of arbitrarily polydisperse
//! objects"): each level is a uniform grid whose cells suit its own particles,
//! so a fine particle's query never scans cells sized for the coarsest one.
//! A query names the box the querying body's centre may sweep and its own reach
//! (`margin`); each level widens the box by `margin` plus the largest radius it
//! holds, so the cost of a query follows the sizes near it, not the size range
//! of the bed. One level of cells `2 r_max` wide is the uniform grid of equal
//! spheres, visited in the same order.
//!
//! Each cell keeps a singly linked list of particle ids (`head` per cell, `next`
//! per particle): 4 bytes per particle and per cell, no allocation per particle.
//! A height map per level keeps the highest particle top of each column of
//! cells, so a falling particle can start just above the bed.

use crate::container::Container;
use crate::math::{ball_volume, Real, Vector};

const EMPTY: u32 = u32::MAX;

/// Most levels a grid has: a size range of 2^16 between the coarsest and the
/// finest class; finer particles share the last level (still exact, slower).
const MAX_LEVELS: usize = 16;

/// How particles are sorted into levels, and the cell size of each.
#[derive(Clone, Debug, PartialEq)]
pub struct Levels {
    /// Level `l` holds radii `>= lower[l]` not held by a coarser level; the last
    /// bound is 0 (every radius has a level).
    lower: Vec<Real>,
    /// Smallest cell width of each level.
    cell: Vec<Real>,
}

impl Levels {
    /// One level of cells at least `cell` wide: a uniform grid.
    pub fn uniform(cell: Real) -> Self {
        Levels {
            lower: vec![0.0],
            cell: vec![cell],
        }
    }

    /// Levels for particles whose radii are at most `r_max` and distributed as
    /// `sample` (radius, weight) in a bed of dimension `D`.
    ///
    /// Size classes halve from `r_max` down (class 0 holds `[r_max/2, r_max]`);
    /// empty classes are skipped. A class's cells are as wide as its largest
    /// diameter, or wider when it is sparse: at least the side of the volume its
    /// share of the particles would fill alone if the bed were solid, so that no
    /// level has more cells than particles (memory linear in the bed). A class so
    /// sparse that its cells come out as wide as the coarser level's joins it:
    /// a level of its own would only cost an extra pass per query.
    pub fn for_sizes<const D: usize>(r_max: Real, sample: &[(Real, Real)]) -> Self {
        if !(r_max.is_finite() && r_max > 0.0) {
            return Levels::uniform(1.0);
        }
        let class_of = |r: Real| -> usize {
            let mut bound = 0.5 * r_max;
            for k in 0..MAX_LEVELS - 1 {
                if r >= bound {
                    return k;
                }
                bound *= 0.5;
            }
            MAX_LEVELS - 1
        };
        let mut weight = [0.0; MAX_LEVELS];
        let mut largest = [0.0 as Real; MAX_LEVELS];
        let (mut total, mut volume) = (0.0, 0.0);
        for &(r, w) in sample {
            if !(w > 0.0 && r.is_finite() && r >= 0.0) {
                continue;
            }
            let r = r.min(r_max);
            let k = class_of(r);
            weight[k] += w;
            largest[k] = largest[k].max(r);
            total += w;
            volume += w * ball_volume::<D>(r);
        }
        if !(total > 0.0 && volume > 0.0) {
            return Levels::uniform(2.0 * r_max);
        }
        // Mean particle volume: a class holding share `f` of the particles has
        // one particle per `mean / f` of a solid bed.
        let mean = volume / total;
        let mut levels = Levels {
            lower: Vec::new(),
            cell: Vec::new(),
        };
        let mut bound = 0.5 * r_max;
        for k in 0..MAX_LEVELS {
            let lower = if k + 1 == MAX_LEVELS { 0.0 } else { bound };
            bound *= 0.5;
            if k > 0 && weight[k] == 0.0 {
                continue;
            }
            let diameter = 2.0 * if k == 0 { r_max } else { largest[k] };
            let sparse = (mean * total / weight[k].max(Real::MIN_POSITIVE)).powf(1.0 / D as Real);
            let cell = diameter.max(if sparse.is_finite() { sparse } else { diameter });
            match levels.cell.last() {
                Some(&coarser) if cell >= coarser => {
                    *levels.lower.last_mut().expect("one level") = lower;
                }
                _ => {
                    levels.lower.push(lower);
                    levels.cell.push(cell);
                }
            }
        }
        // Radii below the smallest sampled class still need a level.
        *levels.lower.last_mut().expect("class 0 is always a level") = 0.0;
        levels
    }

    /// The level of a particle of radius `r`.
    #[inline]
    fn of(&self, r: Real) -> usize {
        let last = self.lower.len() - 1;
        for (l, &b) in self.lower[..last].iter().enumerate() {
            if r >= b {
                return l;
            }
        }
        last
    }
}

/// One level: a uniform grid, layers added upwards as particles arrive.
#[derive(Clone, Debug)]
struct Level<const D: usize> {
    cell: [Real; D],
    inv_cell: [Real; D],
    counts: [usize; D],
    head: Vec<u32>,
    column_top: Vec<Real>,
    columns: usize,
    /// Largest radius inserted (0 while empty).
    r_max: Real,
    population: usize,
}

impl<const D: usize> Level<D> {
    fn new(container: &Container<D>, reach: Real, max_columns: usize) -> Self {
        let mut cell = [0.0; D];
        let mut counts = [1usize; D];
        let mut wanted = [1.0; D];
        let mut all: Real = 1.0;
        for k in 0..D - 1 {
            // Cap the cell count so that tiny particles in a huge box cannot
            // exhaust memory with empty cells; cells only get wider (still valid).
            wanted[k] = (container.extent(k) / reach)
                .floor()
                .clamp(1.0, (1 << 14) as Real);
            all *= wanted[k];
        }
        // Columns beyond `max_columns` would mostly stay empty: every side
        // shrinks by the same factor, so the cells stay about square.
        let shrink = (max_columns.max(1) as Real / all)
            .min(1.0)
            .powf(1.0 / (D - 1) as Real);
        let mut columns = 1;
        for k in 0..D - 1 {
            let n = ((wanted[k] * shrink).floor() as usize).max(1);
            counts[k] = n;
            cell[k] = container.extent(k) / n as Real;
            columns *= n;
        }
        // Layers likewise: a few particles spread through a tall box (RSA)
        // need a few tall cells, not one layer per diameter of the height.
        let most_layers = (max_columns.saturating_mul(4) / columns).max(1) as Real;
        cell[D - 1] = reach.max(container.extent(D - 1) / most_layers);
        counts[D - 1] = 0;
        let mut inv_cell = [0.0; D];
        for k in 0..D {
            inv_cell[k] = 1.0 / cell[k];
        }
        Level {
            cell,
            inv_cell,
            counts,
            head: Vec::new(),
            column_top: vec![0.0; columns],
            columns,
            r_max: 0.0,
            population: 0,
        }
    }

    #[inline]
    fn layer_of(&self, z: Real) -> usize {
        floor_index(z * self.inv_cell[D - 1]).max(0) as usize
    }

    #[inline]
    fn column_of(&self, p: &Vector<D>) -> usize {
        let mut idx = 0;
        for k in (0..D - 1).rev() {
            let n = self.counts[k];
            let i = floor_index(p[k] * self.inv_cell[k]).clamp(0, n as isize - 1);
            idx = idx * n + i as usize;
        }
        idx
    }

    /// The layers holding centres in `[z_lo, z_hi]`, if any.
    #[inline]
    fn layers(&self, z_lo: Real, z_hi: Real) -> Option<(usize, usize)> {
        let layers = self.counts[D - 1];
        if layers == 0 || z_hi < 0.0 {
            return None;
        }
        let z0 = self.layer_of(z_lo);
        let z1 = self.layer_of(z_hi).min(layers - 1);
        (z0 <= z1).then_some((z0, z1))
    }
}

/// The neighbour grid over a container.
#[derive(Clone, Debug)]
pub struct Grid<const D: usize> {
    levels: Vec<Level<D>>,
    plan: Levels,
    extent: [Real; D],
    periodic: bool,
    next: Vec<u32>,
}

impl<const D: usize> Grid<D> {
    /// A grid over `container` with the given levels, for about `particles`
    /// particles: at most four columns of cells per particle on each level
    /// and four cells per column, so that memory follows the bed and not the
    /// box (10 particles in a 100000 × 100000 box need a few wide cells, not
    /// 2^28 of a diameter each).
    pub fn for_particles(container: &Container<D>, plan: &Levels, particles: usize) -> Self {
        let max_columns = particles.saturating_mul(4).max(64);
        let mut extent = [0.0; D];
        for k in 0..D - 1 {
            extent[k] = container.extent(k);
        }
        Grid {
            levels: plan
                .cell
                .iter()
                .map(|&c| Level::new(container, c, max_columns))
                .collect(),
            plan: plan.clone(),
            extent,
            periodic: container.periodic,
            next: Vec::new(),
        }
    }

    /// A grid holding the particles `centres` with `radii` (ids in order), its
    /// levels fitted to them and to a further radius `r_extra` that will query it.
    pub fn of_particles(
        container: &Container<D>,
        centres: &[Vector<D>],
        radii: &[Real],
        r_extra: Real,
    ) -> Self {
        let r_max = radii.iter().copied().fold(r_extra, Real::max);
        let sample: Vec<(Real, Real)> = radii.iter().map(|&r| (r, 1.0)).collect();
        let levels = Levels::for_sizes::<D>(r_max, &sample);
        let mut grid = Grid::for_particles(container, &levels, centres.len());
        grid.reserve(centres.len());
        for (i, (c, &r)) in centres.iter().zip(radii).enumerate() {
            grid.insert(i as u32, c, r);
        }
        grid
    }

    /// The cell width along the first axis of the level holding radius `r`.
    #[cfg(test)]
    pub(crate) fn cell_width_for(&self, r: Real) -> Real {
        self.levels[self.plan.of(r)].cell[0]
    }

    /// Reserves room for `n` particles.
    pub fn reserve(&mut self, n: usize) {
        self.next.reserve(n);
    }

    /// Adds particle `id` (ids must be added in order 0, 1, 2, …) with centre `p`
    /// (inside the box laterally) and radius `r`.
    pub fn insert(&mut self, id: u32, p: &Vector<D>, r: Real) {
        debug_assert_eq!(id as usize, self.next.len());
        let level = &mut self.levels[self.plan.of(r)];
        let layer = level.layer_of(p[D - 1]);
        if layer >= level.counts[D - 1] {
            let layers = layer + 1;
            level.head.resize(layers * level.columns, EMPTY);
            level.counts[D - 1] = layers;
        }
        let col = level.column_of(p);
        let cell = layer * level.columns + col;
        self.next.push(level.head[cell]);
        level.head[cell] = id;
        let top = p[D - 1] + r;
        if top > level.column_top[col] {
            level.column_top[col] = top;
        }
        if r > level.r_max {
            level.r_max = r;
        }
        level.population += 1;
    }

    /// True if a particle of radius `r` would be the largest of its level so
    /// far: inserting it widens that level's queries.
    pub fn widens(&self, r: Real) -> bool {
        r > self.levels[self.plan.of(r)].r_max
    }

    /// How far beyond a query's box, widened by its margin, the centre of a
    /// particle it visits can lie: the largest radius of a level plus its
    /// widest horizontal cell. (A visited cell overlaps the box widened by the
    /// margin and its level's largest radius, and holds the centre.)
    pub fn reach_beyond_margin(&self) -> Real {
        self.levels
            .iter()
            .map(|l| l.r_max + l.cell[..D - 1].iter().copied().fold(0.0, Real::max))
            .fold(0.0, Real::max)
    }

    /// Highest particle top over the columns of particles that could overlap the
    /// horizontal box `[lo, hi]` widened by `margin` (vertical components
    /// ignored); 0 when they are empty.
    pub fn max_top(&self, lo: &Vector<D>, hi: &Vector<D>, margin: Real) -> Real {
        let mut best: Real = 0.0;
        for level in self.occupied() {
            let (lo, hi) = widen(lo, hi, margin + level.r_max, D - 1);
            self.for_each_column(level, &lo, &hi, |col, _, _| {
                best = best.max(level.column_top[col]);
                true
            });
        }
        best
    }

    /// Calls `f(id, shift, image)` for every particle in the cells that could
    /// hold a particle overlapping the box `[lo, hi]` widened by `margin`;
    /// `shift` is the periodic image offset to add to its centre and `image` a
    /// code naming that image (0 for the particle itself).
    #[inline]
    pub fn for_each_in_box(
        &self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        margin: Real,
        mut f: impl FnMut(u32, Vector<D>, u16),
    ) {
        self.search(lo, hi, margin, self.levels.iter(), |id, shift, image| {
            f(id, shift, image);
            false
        });
    }

    /// True if `f` holds for some particle visited by
    /// [`Grid::for_each_in_box`] with the same box; stops at the first.
    /// Overlap tests, where most queries of a saturating floor end at their
    /// first neighbour. The coarse levels come first: they are the cheapest to
    /// search for a large body (few, wide cells), and no dearer for a small
    /// one (measured: a broad lognormal base layer 5 % faster than finest
    /// first; the answer is the same either way).
    pub fn any_in_box(
        &self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        margin: Real,
        f: impl FnMut(u32, Vector<D>, u16) -> bool,
    ) -> bool {
        self.search(lo, hi, margin, self.levels.iter(), f)
    }

    /// [`Grid::any_in_box`] over `levels` in the order given.
    #[inline]
    fn search<'g>(
        &'g self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        margin: Real,
        levels: impl Iterator<Item = &'g Level<D>>,
        mut f: impl FnMut(u32, Vector<D>, u16) -> bool,
    ) -> bool {
        for level in levels.filter(|l| l.population > 0) {
            let (lo, hi) = widen(lo, hi, margin + level.r_max, D);
            let Some((z0, z1)) = level.layers(lo[D - 1], hi[D - 1]) else {
                continue;
            };
            let stopped = !self.for_each_column(level, &lo, &hi, |col, shift, image| {
                for layer in z0..z1 + 1 {
                    let mut id = level.head[layer * level.columns + col];
                    while id != EMPTY {
                        if f(id, shift, image) {
                            return false;
                        }
                        id = self.next[id as usize];
                    }
                }
                true
            });
            if stopped {
                return true;
            }
        }
        false
    }

    /// The particles a body falling from above could meet: centres at heights in
    /// `[lo, hi]` (vertical components, not widened) whose balls reach the
    /// horizontal box `[lo, hi]` widened by `margin`, one layer at a time from the
    /// top down across the levels, for as long as it matters. `f` returns the
    /// lowest height the querying body's centre can still reach; layers whose
    /// particles all lie more than `margin` plus their radius below it are
    /// skipped.
    pub fn scan_down(
        &self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        margin: Real,
        mut f: impl FnMut(u32, Vector<D>, u16) -> Real,
    ) {
        // Per level: the horizontal box, the reach, the lowest layer and the
        // next layer to scan (a merge of the levels by the top of their layers).
        let mut boxes = [(
            Vector::<D>::zero(),
            Vector::<D>::zero(),
            0.0,
            0usize,
            0usize,
        ); MAX_LEVELS];
        let mut live = 0usize;
        for (l, level) in self.levels.iter().enumerate() {
            if level.population == 0 {
                continue;
            }
            let reach = margin + level.r_max;
            let (wlo, whi) = widen(lo, hi, reach, D - 1);
            if let Some((z0, z1)) = level.layers(lo[D - 1], hi[D - 1]) {
                boxes[l] = (wlo, whi, reach, z0, z1 + 1);
                live |= 1 << l;
            }
        }
        let mut floor_height: Real = Real::NEG_INFINITY;
        while live != 0 {
            // The level whose next layer reaches highest.
            let mut pick = usize::MAX;
            let mut pick_top = Real::NEG_INFINITY;
            let mut rest = live;
            while rest != 0 {
                let l = rest.trailing_zeros() as usize;
                rest &= rest - 1;
                let (_, _, reach, _, next) = boxes[l];
                let top = next as Real * self.levels[l].cell[D - 1] + reach;
                if top > pick_top {
                    pick_top = top;
                    pick = l;
                }
            }
            let (wlo, whi, reach, z0, next) = boxes[pick];
            let level = &self.levels[pick];
            let layer = next - 1;
            // The old single-level test, `layer_top < lowest - reach`, kept in
            // that form so equal spheres scan exactly as before.
            if (next as Real * level.cell[D - 1]) < floor_height - reach {
                live &= !(1 << pick);
                continue;
            }
            self.for_each_column(level, &wlo, &whi, |col, shift, image| {
                let mut id = level.head[layer * level.columns + col];
                while id != EMPTY {
                    floor_height = floor_height.max(f(id, shift, image));
                    id = self.next[id as usize];
                }
                true
            });
            if layer == z0 {
                live &= !(1 << pick);
            } else {
                boxes[pick].4 = layer;
            }
        }
    }

    fn occupied(&self) -> impl Iterator<Item = &Level<D>> {
        self.levels.iter().filter(|l| l.population > 0)
    }

    /// Calls `f(column, shift, image)` for every column (as an image with its
    /// periodic shift) of `level` overlapping the horizontal box `[lo, hi]`,
    /// until `f` returns false; returns false if it stopped early. A box wider
    /// than the period visits a column once per image it covers.
    #[inline]
    fn for_each_column(
        &self,
        level: &Level<D>,
        lo: &Vector<D>,
        hi: &Vector<D>,
        mut f: impl FnMut(usize, Vector<D>, u16) -> bool,
    ) -> bool {
        let mut first = [0isize; 2];
        let mut last = [0isize; 2];
        for k in 0..D - 1 {
            let n = level.counts[k] as isize;
            let mut a = floor_index(lo[k] * level.inv_cell[k]);
            let mut b = floor_index(hi[k] * level.inv_cell[k]);
            if !self.periodic {
                a = a.max(0);
                b = b.min(n - 1);
            }
            if a > b {
                return true;
            }
            first[k] = a;
            last[k] = b;
        }
        let mut offset = Vector::<D>::zero();
        let nx = level.counts[0] as isize;
        let row_of = |k: usize, a: isize| {
            let n = level.counts[k] as isize;
            (a.rem_euclid(n), a.div_euclid(n))
        };
        // Shifts and image codes change only where a row wraps round the
        // period: they are worked out there, not per column.
        if D == 2 {
            let (mut i, mut period) = row_of(0, first[0]);
            offset[0] = period as Real * self.extent[0];
            let mut image = image_code(period, 0);
            for _ in first[0]..last[0] + 1 {
                if !f(i as usize, offset, image) {
                    return false;
                }
                i += 1;
                if i == nx {
                    i = 0;
                    period += 1;
                    offset[0] = period as Real * self.extent[0];
                    image = image_code(period, 0);
                }
            }
        } else {
            let ny = level.counts[1] as isize;
            let (mut iy, mut py) = row_of(1, first[1]);
            let (ix0, px0) = row_of(0, first[0]);
            for _ in first[1]..last[1] + 1 {
                offset[1] = py as Real * self.extent[1];
                let row = iy as usize * nx as usize;
                let image_y = image_code(py, 1);
                let (mut ix, mut px) = (ix0, px0);
                offset[0] = px as Real * self.extent[0];
                let mut image = image_code(px, 0) | image_y;
                for _ in first[0]..last[0] + 1 {
                    if !f(row + ix as usize, offset, image) {
                        return false;
                    }
                    ix += 1;
                    if ix == nx {
                        ix = 0;
                        px += 1;
                        offset[0] = px as Real * self.extent[0];
                        image = image_code(px, 0) | image_y;
                    }
                }
                iy += 1;
                if iy == ny {
                    iy = 0;
                    py += 1;
                }
            }
        }
        true
    }
}

/// The box `[lo, hi]` widened by `by` along the first `axes` axes.
#[inline]
fn widen<const D: usize>(
    lo: &Vector<D>,
    hi: &Vector<D>,
    by: Real,
    axes: usize,
) -> (Vector<D>, Vector<D>) {
    let (mut lo, mut hi) = (*lo, *hi);
    for k in 0..axes {
        lo[k] -= by;
        hi[k] += by;
    }
    (lo, hi)
}

/// Code of the periodic image `period` along horizontal axis `k` (8 bits per axis,
/// 0 for the home cell), so that images of one particle can be told apart.
#[inline]
fn image_code(period: isize, k: usize) -> u16 {
    ((period as i16 as u16) & 0xff) << (8 * k)
}

/// `x.floor() as isize` without a libm call (the baseline x86-64 target has no
/// rounding instruction, and this runs for every cell lookup).
#[inline]
fn floor_index(x: Real) -> isize {
    let i = x as isize;
    if (i as Real) > x {
        i - 1
    } else {
        i
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::collections::HashSet;

    /// The particles whose balls meet the box `[lo, hi]` widened by `margin`,
    /// as (id, shift) over every periodic image near the box: the set a query
    /// must visit, found by brute force.
    fn required<const D: usize>(
        c: &Container<D>,
        parts: &[(Vector<D>, Real)],
        lo: &Vector<D>,
        hi: &Vector<D>,
        margin: Real,
        axes: usize,
    ) -> HashSet<(u32, [i64; 2])> {
        let mut out = HashSet::new();
        let range = if c.periodic { -3..=3 } else { 0..=0 };
        for (i, (p, r)) in parts.iter().enumerate() {
            for a in range.clone() {
                for b in if D == 3 { range.clone() } else { 0..=0 } {
                    let mut q = *p;
                    q[0] += a as Real * c.size[0];
                    if D == 3 {
                        q[1] += b as Real * c.size[1];
                    }
                    // Distance from the centre to the widened box.
                    let mut d2 = 0.0;
                    for k in 0..axes {
                        let (l, h) = (lo[k] - margin, hi[k] + margin);
                        let e = if q[k] < l {
                            l - q[k]
                        } else if q[k] > h {
                            q[k] - h
                        } else {
                            0.0
                        };
                        d2 += e * e;
                    }
                    if d2 < r * r * (1.0 - 1e-12) {
                        out.insert((i as u32, [a, b]));
                    }
                }
            }
        }
        out
    }

    fn shift_of<const D: usize>(c: &Container<D>, shift: &Vector<D>) -> [i64; 2] {
        let mut s = [0i64; 2];
        for k in 0..D - 1 {
            s[k] = (shift[k] / c.size[k]).round() as i64;
        }
        s
    }

    /// Random beds of radii spread over three decades, in levels planned from
    /// the radii themselves.
    fn check_queries<const D: usize>(
        periodic: bool,
        parts: Vec<([Real; 3], Real)>,
        query: ([Real; 3], [Real; 3], Real),
    ) -> Result<(), TestCaseError> {
        let mut size = Vector::<D>::zero();
        for k in 0..D - 1 {
            size[k] = 400.0;
        }
        size[D - 1] = 1000.0;
        let c = Container { size, periodic };
        let parts: Vec<(Vector<D>, Real)> = parts
            .into_iter()
            .map(|(x, r)| {
                let mut p = Vector::<D>::zero();
                for k in 0..D {
                    p[k] = x[3 - D + k] * size[k];
                }
                (p, r)
            })
            .collect();
        let centres: Vec<Vector<D>> = parts.iter().map(|p| p.0).collect();
        let radii: Vec<Real> = parts.iter().map(|p| p.1).collect();
        let grid = Grid::of_particles(&c, &centres, &radii, 0.0);
        let (mut lo, mut hi) = (Vector::<D>::zero(), Vector::<D>::zero());
        for k in 0..D {
            let (a, b) = (query.0[3 - D + k] * size[k], query.1[3 - D + k] * 200.0);
            lo[k] = a;
            hi[k] = a + b;
        }
        let margin = query.2;
        let need = required(&c, &parts, &lo, &hi, margin, D);
        let mut seen = HashSet::new();
        grid.for_each_in_box(&lo, &hi, margin, |id, shift, image| {
            let s = shift_of(&c, &shift);
            assert_eq!(image, {
                let mut code = 0;
                for k in 0..D - 1 {
                    code |= image_code(s[k] as isize, k);
                }
                code
            });
            assert!(seen.insert((id, s)), "{id} {s:?} visited twice");
        });
        for n in &need {
            prop_assert!(seen.contains(n), "missed {n:?}");
        }
        // The stopping variant agrees, and stops at the first hit.
        let mut after_hit = 0;
        let mut hit = false;
        let any = grid.any_in_box(&lo, &hi, margin, |id, shift, _| {
            after_hit += usize::from(hit);
            hit = need.contains(&(id, shift_of(&c, &shift)));
            hit
        });
        prop_assert_eq!(any, !need.is_empty());
        prop_assert_eq!(after_hit, 0);
        // The scan from the top visits every centre below the box's top, each
        // image once, when nothing is pruned.
        let mut down = HashSet::new();
        grid.scan_down(&lo, &hi, margin, |id, shift, _| {
            assert!(down.insert((id, shift_of(&c, &shift))));
            Real::NEG_INFINITY
        });
        let below: HashSet<_> = required(&c, &parts, &lo, &hi, margin, D - 1)
            .into_iter()
            .filter(|(id, _)| {
                let z = parts[*id as usize].0[D - 1];
                z >= lo[D - 1] && z <= hi[D - 1]
            })
            .collect();
        for n in &below {
            prop_assert!(down.contains(n), "scan_down missed {n:?}");
        }
        // The height map: no ball reaching the footprint is higher.
        let top = grid.max_top(&lo, &hi, margin);
        let highest = required(&c, &parts, &lo, &hi, margin, D - 1)
            .iter()
            .map(|(id, _)| parts[*id as usize].0[D - 1] + parts[*id as usize].1)
            .fold(0.0, Real::max);
        prop_assert!(top >= highest, "max_top {top} below {highest}");
        Ok(())
    }

    fn particle() -> impl Strategy<Value = ([Real; 3], Real)> {
        ([0.0..1.0, 0.0..1.0, 0.0..1.0], -1.0..2.0 as Real)
            .prop_map(|(x, e): ([Real; 3], Real)| (x, 10.0 as Real * (10.0 as Real).powf(e)))
    }

    fn query() -> impl Strategy<Value = ([Real; 3], [Real; 3], Real)> {
        (
            [-0.2..1.2, -0.2..1.2, -0.1..1.1],
            [0.0..1.0, 0.0..1.0, 0.0..1.0],
            0.0..60.0,
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn queries_find_every_particle_in_reach_2d(
            periodic in any::<bool>(),
            parts in prop::collection::vec(particle(), 1..300),
            q in query(),
        ) {
            check_queries::<2>(periodic, parts, q)?;
        }

        #[test]
        fn queries_find_every_particle_in_reach_3d(
            periodic in any::<bool>(),
            parts in prop::collection::vec(particle(), 1..300),
            q in query(),
        ) {
            check_queries::<3>(periodic, parts, q)?;
        }
    }

    #[test]
    fn equal_and_narrow_sizes_keep_one_level_of_largest_diameter() {
        let equal = Levels::for_sizes::<3>(10.0, &[(10.0, 1.0)]);
        assert_eq!(equal, Levels::uniform(20.0));
        let pair = Levels::for_sizes::<3>(20.0, &[(10.0, 1.0), (20.0, 1.0)]);
        assert_eq!(pair, Levels::uniform(40.0));
        let pair_2d = Levels::for_sizes::<2>(20.0, &[(10.0, 1.0), (20.0, 2.0)]);
        assert_eq!(pair_2d, Levels::uniform(40.0));
    }

    #[test]
    fn wide_pairs_get_a_level_each() {
        // One fine per coarse sphere: the coarse ones hold most of the volume,
        // and the fines' cells are the side of the solid volume per fine,
        // (4/3 π (10³ + 50³))^⅓ ≈ 80.9, wider than their diameter.
        let l = Levels::for_sizes::<3>(50.0, &[(10.0, 1.0), (50.0, 1.0)]);
        assert_eq!(l.lower, vec![25.0, 0.0]);
        assert_eq!(l.cell[0], 100.0);
        let per_fine = (4.0 / 3.0 * std::f64::consts::PI * (1e3 + 125e3)).powf(1.0 / 3.0);
        assert!((l.cell[1] - per_fine).abs() < 1e-9, "{l:?}");
        assert_eq!(l.of(50.0), 0);
        assert_eq!(l.of(10.0), 1);
        assert_eq!(l.of(0.0), 1);
        // A hundred fines per coarse sphere: cells near the fines' diameter,
        // (4/3 π (100 · 10³ + 50³) / 100)^⅓ ≈ 21.1.
        let dense = Levels::for_sizes::<3>(50.0, &[(10.0, 100.0), (50.0, 1.0)]);
        let per_fine = (4.0 / 3.0 * std::f64::consts::PI * (1e5 + 125e3) / 100.0).powf(1.0 / 3.0);
        assert_eq!(dense.cell[0], 100.0);
        assert!((dense.cell[1] - per_fine).abs() < 1e-9, "{dense:?}");
        // Fines so rare that their cells would be wider than the coarse
        // level's join it.
        let rare = Levels::for_sizes::<3>(50.0, &[(10.0, 1.0), (50.0, 1000.0)]);
        assert_eq!(rare, Levels::uniform(100.0));
    }

    #[test]
    fn broad_lognormal_levels_keep_cells_fewer_than_particles() {
        // Lognormal quantiles, median 10, gsd 2, within ±3 sd.
        let n = 20_000;
        let radii: Vec<Real> = (0..n)
            .map(|i| {
                10.0 * (2.0 as Real)
                    .powf(crate::math::normal::quantile((i as Real + 0.5) / n as Real))
            })
            .filter(|&r| (1.25..=80.0).contains(&r))
            .collect();
        let sample: Vec<(Real, Real)> = radii.iter().map(|&r| (r, 1.0)).collect();
        let levels = Levels::for_sizes::<3>(80.0, &sample);
        assert!(levels.cell.len() >= 3, "{levels:?}");
        // Finer levels have narrower cells, and every cell is at least as wide
        // as the diameters of its level.
        for w in levels.cell.windows(2) {
            assert!(w[1] < w[0], "{levels:?}");
        }
        for (r, _) in &sample {
            let l = levels.of(*r);
            assert!(levels.cell[l] >= 2.0 * r, "{r} in {levels:?}");
        }
        // A bed of these spheres at random close packing: the cells of all
        // levels together number at most the particles over the packing
        // fraction (each level's cells hold a solid volume per particle).
        let volume: Real = radii
            .iter()
            .map(|&r| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3))
            .sum::<Real>()
            / 0.64;
        let cells: Real = levels.cell.iter().map(|c| volume / c.powi(3)).sum();
        assert!(
            cells < radii.len() as Real / 0.64,
            "{cells} cells for {}",
            radii.len()
        );
    }
}
