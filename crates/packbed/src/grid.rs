//! Uniform cell grid for neighbour queries, growing upwards as the bed grows.
//!
//! Cells are at least as wide as the largest interaction distance, so a query box
//! touches only a few cells. Each cell keeps a singly linked list of particle ids
//! (`head` per cell, `next` per particle): 4 bytes per particle and per cell, no
//! allocation per particle. A height map keeps the highest particle top of each
//! column of cells, so a falling particle can start just above the bed.

use crate::container::Container;
use crate::math::{Real, Vector};

const EMPTY: u32 = u32::MAX;

/// The neighbour grid over a container.
#[derive(Clone, Debug)]
pub struct Grid<const D: usize> {
    cell: [Real; D],
    inv_cell: [Real; D],
    counts: [usize; D],
    extent: [Real; D],
    periodic: bool,
    head: Vec<u32>,
    next: Vec<u32>,
    column_top: Vec<Real>,
    columns: usize,
}

impl<const D: usize> Grid<D> {
    /// A grid whose cells are at least `reach` wide on every axis.
    pub fn new(container: &Container<D>, reach: Real) -> Self {
        let mut cell = [0.0; D];
        let mut counts = [1usize; D];
        let mut extent = [0.0; D];
        let mut columns = 1;
        for k in 0..D - 1 {
            let w = container.extent(k);
            // Cap the cell count so that tiny particles in a huge box cannot
            // exhaust memory with empty cells; cells only get wider (still valid).
            let n = ((w / reach).floor() as usize).clamp(1, 1 << 14);
            counts[k] = n;
            cell[k] = w / n as Real;
            extent[k] = w;
            columns *= n;
        }
        cell[D - 1] = reach;
        counts[D - 1] = 0;
        let mut inv_cell = [0.0; D];
        for k in 0..D {
            inv_cell[k] = 1.0 / cell[k];
        }
        Grid {
            cell,
            inv_cell,
            counts,
            extent,
            periodic: container.periodic,
            head: Vec::new(),
            next: Vec::new(),
            column_top: vec![0.0; columns],
            columns,
        }
    }

    /// Reserves room for `n` particles.
    pub fn reserve(&mut self, n: usize) {
        self.next.reserve(n);
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

    /// Adds particle `id` (ids must be added in order 0, 1, 2, …) with centre `p`
    /// (inside the box laterally) and radius `r`.
    pub fn insert(&mut self, id: u32, p: &Vector<D>, r: Real) {
        debug_assert_eq!(id as usize, self.next.len());
        let layer = self.layer_of(p[D - 1]);
        if layer >= self.counts[D - 1] {
            let layers = layer + 1;
            self.head.resize(layers * self.columns, EMPTY);
            self.counts[D - 1] = layers;
        }
        let col = self.column_of(p);
        let cell = layer * self.columns + col;
        self.next.push(self.head[cell]);
        self.head[cell] = id;
        let top = p[D - 1] + r;
        if top > self.column_top[col] {
            self.column_top[col] = top;
        }
    }

    /// Highest particle top over the columns that overlap the horizontal box
    /// `[lo, hi]` (vertical components ignored); 0 when they are empty.
    pub fn max_top(&self, lo: &Vector<D>, hi: &Vector<D>) -> Real {
        let mut best: Real = 0.0;
        self.for_each_column(lo, hi, |col, _, _| {
            best = best.max(self.column_top[col]);
            true
        });
        best
    }

    /// Calls `f(column, shift)` for every column (as an image with its periodic
    /// shift) overlapping the horizontal box `[lo, hi]`, until `f` returns false;
    /// returns false if it stopped early.
    #[inline]
    fn for_each_column(
        &self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        mut f: impl FnMut(usize, Vector<D>, u16) -> bool,
    ) -> bool {
        // Per axis, the wrapped cell indices and image shifts of the range, worked
        // out once per query (no division in the loop below).
        const MAX_SPAN: usize = 16;
        let mut index = [[0usize; MAX_SPAN]; 2];
        let mut shift = [[0.0; MAX_SPAN]; 2];
        let mut image = [[0u16; MAX_SPAN]; 2];
        let mut span = [1usize; 2];
        for k in 0..D - 1 {
            let n = self.counts[k] as isize;
            let mut a = floor_index(lo[k] * self.inv_cell[k]);
            let mut b = floor_index(hi[k] * self.inv_cell[k]);
            if !self.periodic {
                a = a.max(0);
                b = b.min(n - 1);
            }
            if a > b {
                return true;
            }
            // A query wider than the table cannot occur with cells at least as wide
            // as the reach; clamp defensively.
            b = b.min(a + MAX_SPAN as isize - 1);
            let mut i = a.rem_euclid(n);
            let mut period = a.div_euclid(n);
            for j in 0..=(b - a) as usize {
                index[k][j] = i as usize;
                shift[k][j] = period as Real * self.extent[k];
                image[k][j] = image_code(period, k);
                i += 1;
                if i == n {
                    i = 0;
                    period += 1;
                }
            }
            span[k] = (b - a + 1) as usize;
        }
        let mut offset = Vector::<D>::zero();
        if D == 2 {
            for j in 0..span[0] {
                offset[0] = shift[0][j];
                if !f(index[0][j], offset, image[0][j]) {
                    return false;
                }
            }
        } else {
            let nx = self.counts[0];
            for jy in 0..span[1] {
                offset[1] = shift[1][jy];
                let row = index[1][jy] * nx;
                for jx in 0..span[0] {
                    offset[0] = shift[0][jx];
                    if !f(row + index[0][jx], offset, image[0][jx] | image[1][jy]) {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// Calls `f(id, shift, image)` for every particle in the cells overlapping the
    /// box `[lo, hi]`; `shift` is the periodic image offset to add to its centre
    /// and `image` a code naming that image (0 for the particle itself).
    #[inline]
    pub fn for_each_in_box(
        &self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        mut f: impl FnMut(u32, Vector<D>, u16),
    ) {
        self.any_in_box(lo, hi, |id, shift, image| {
            f(id, shift, image);
            false
        });
    }

    /// True if `f` holds for some particle in the cells overlapping the box `[lo,
    /// hi]` (arguments as for [`Grid::for_each_in_box`]); stops at the first.
    /// Overlap tests, where most queries of a saturating floor end at their
    /// first neighbour.
    pub fn any_in_box(
        &self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        mut f: impl FnMut(u32, Vector<D>, u16) -> bool,
    ) -> bool {
        let layers = self.counts[D - 1];
        if layers == 0 || hi[D - 1] < 0.0 {
            return false;
        }
        let z0 = self.layer_of(lo[D - 1]);
        let z1 = self.layer_of(hi[D - 1]).min(layers - 1);
        if z0 > z1 {
            return false;
        }
        !self.for_each_column(lo, hi, |col, shift, image| {
            for layer in z0..=z1 {
                let mut id = self.head[layer * self.columns + col];
                while id != EMPTY {
                    if f(id, shift, image) {
                        return false;
                    }
                    id = self.next[id as usize];
                }
            }
            true
        })
    }

    /// Like [`Grid::for_each_in_box`], one layer at a time from the top down, for
    /// as long as `f` returns the lowest height still worth scanning: layers whose
    /// top lies below it are skipped.
    pub fn scan_down(
        &self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        mut f: impl FnMut(u32, Vector<D>, u16) -> Real,
    ) {
        let layers = self.counts[D - 1];
        if layers == 0 || hi[D - 1] < 0.0 {
            return;
        }
        let z0 = self.layer_of(lo[D - 1]);
        let z1 = self.layer_of(hi[D - 1]).min(layers - 1);
        let mut floor_height: Real = Real::NEG_INFINITY;
        for layer in (z0..=z1).rev() {
            let layer_top = (layer + 1) as Real * self.cell[D - 1];
            if layer_top < floor_height {
                break;
            }
            self.for_each_column(lo, hi, |col, shift, image| {
                let mut id = self.head[layer * self.columns + col];
                while id != EMPTY {
                    floor_height = floor_height.max(f(id, shift, image));
                    id = self.next[id as usize];
                }
                true
            });
        }
    }
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
