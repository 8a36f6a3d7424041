//! `packing.pair_correlation`: the pair correlation function g(r) of the
//! particle centres in the bulk region, the measure that tells a random
//! loose bed from a dense one beside its packing fraction (the split second
//! peak of dense equal spheres at √3 d and 2 d; the contact peak at d).
//!
//! The reference centres are those in the bulk region; their neighbours are
//! every centre of the bed (periodic sides by the minimum image). The bulk
//! region lies at least two largest diameters from the floor and side walls
//! and three below the surface, and the reach is at most two largest
//! diameters (and half a period), so every shell about a reference centre
//! lies inside the bed and the ideal-gas normalisation holds:
//! `g(r) = N(r, r + Δr) / (N_ref n V_shell)`, with `n = N_ref / V_bulk` and
//! `V_shell` the exact shell volume (area in 2D).

use super::packing::Region;
use crate::bed::Bed;
use crate::math::{ball_volume, Real, Vector};
use rayon::prelude::*;
use serde::Serialize;

/// Bins per mean diameter.
const BINS_PER_DIAMETER: Real = 50.0;

/// g(r) of the bulk's centres.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct PairCorrelation {
    /// Bin width: a fiftieth of the number-mean diameter.
    pub bin: Real,
    /// The middle of each bin.
    pub r: Vec<Real>,
    /// g at each bin (1 for an ideal gas).
    pub g: Vec<Real>,
    /// Reference centres (in the bulk region).
    pub centres: u64,
}

/// g(r) of `bed`'s centres in `region` (its bulk region), out to three
/// number-mean diameters (at most two largest diameters and half a period).
/// `None` for an empty region or bed.
pub fn pair_correlation<const D: usize>(
    bed: &Bed<D>,
    region: &Region<D>,
) -> Option<PairCorrelation> {
    let n = bed.len();
    if n < 2 {
        return None;
    }
    let d_mean = 2.0 * bed.radii.iter().sum::<Real>() / n as Real;
    let mut reach = (3.0 * d_mean).min(4.0 * bed.r_max());
    if bed.container.periodic {
        for k in 0..D - 1 {
            reach = reach.min(0.5 * bed.container.size[k]);
        }
    }
    let bin = d_mean / BINS_PER_DIAMETER;
    if !(reach > 0.0 && bin > 0.0 && reach.is_finite()) {
        return None;
    }
    let bins = ((reach / bin).floor() as usize).max(1);
    let reach = bins as Real * bin;
    let refs: Vec<usize> = (0..n)
        .filter(|&i| region.contains(&bed.centres[i]))
        .collect();
    if refs.is_empty() {
        return None;
    }
    let grid = Cells::new(bed, reach);
    let counts = refs
        .par_chunks(1024)
        .map(|chunk| {
            let mut h = vec![0u64; bins];
            for &i in chunk {
                grid.for_each_near(&bed.centres[i], |j| {
                    if j != i {
                        let d = bed
                            .container
                            .displacement(&bed.centres[i], &bed.centres[j])
                            .norm();
                        let k = (d / bin).floor();
                        if k >= 0.0 && (k as usize) < bins {
                            h[k as usize] += 1;
                        }
                    }
                });
            }
            h
        })
        .reduce(
            || vec![0u64; bins],
            |mut a, b| {
                a.iter_mut().zip(&b).for_each(|(x, y)| *x += y);
                a
            },
        );
    let centres = refs.len() as Real;
    let density = centres / region.volume();
    let shell =
        |k: usize| ball_volume::<D>((k + 1) as Real * bin) - ball_volume::<D>(k as Real * bin);
    Some(PairCorrelation {
        bin,
        r: (0..bins).map(|k| (k as Real + 0.5) * bin).collect(),
        g: counts
            .iter()
            .enumerate()
            .map(|(k, &c)| c as Real / (centres * density * shell(k)))
            .collect(),
        centres: refs.len() as u64,
    })
}

/// Centres sorted into cubes of side at least `reach`: the centres within
/// `reach` of a point lie in its cube and the neighbouring ones. Not the
/// contacts' [`super::cells::CellList`]: that one finds pairs within a
/// multiple of their radii and gathers them all (at a reach of three
/// diameters, about 60 pairs per particle), where g(r) needs a fixed reach
/// and only counts them.
struct Cells<const D: usize> {
    lo: Vector<D>,
    side: [Real; D],
    n: [usize; D],
    wrap: [bool; D],
    start: Vec<u32>,
    ids: Vec<u32>,
}

impl<const D: usize> Cells<D> {
    fn new(bed: &Bed<D>, reach: Real) -> Self {
        let mut lo = Vector::<D>::zero();
        let mut hi = Vector::<D>::zero();
        let mut wrap = [false; D];
        for k in 0..D {
            wrap[k] = k < D - 1 && bed.container.periodic;
            if wrap[k] {
                hi[k] = bed.container.size[k];
            } else {
                lo[k] = bed
                    .centres
                    .iter()
                    .map(|c| c[k])
                    .fold(Real::INFINITY, Real::min);
                hi[k] = bed
                    .centres
                    .iter()
                    .map(|c| c[k])
                    .fold(Real::NEG_INFINITY, Real::max);
            }
        }
        // No more cells than four per centre: a sparse bed (imported, or a
        // hit-and-stick one) gets larger cubes, never more memory.
        let most = 4.0 * bed.len() as Real + 1.0;
        let mut side_len = reach;
        let count = |s: Real| {
            (0..D)
                .map(|k| ((hi[k] - lo[k]) / s).floor().max(1.0))
                .product::<Real>()
        };
        while count(side_len) > most {
            side_len *= 2.0;
        }
        let mut n = [1usize; D];
        let mut side = [0.0; D];
        for k in 0..D {
            n[k] = ((hi[k] - lo[k]) / side_len).floor().max(1.0) as usize;
            side[k] = ((hi[k] - lo[k]) / n[k] as Real).max(side_len);
        }
        let mut cells = Cells {
            lo,
            side,
            n,
            wrap,
            start: Vec::new(),
            ids: Vec::new(),
        };
        let total: usize = n.iter().product();
        let index: Vec<usize> = bed.centres.iter().map(|c| cells.cell_of(c)).collect();
        let mut start = vec![0u32; total + 1];
        for &c in &index {
            start[c + 1] += 1;
        }
        for c in 0..total {
            start[c + 1] += start[c];
        }
        let mut next = start.clone();
        let mut ids = vec![0u32; bed.len()];
        for (i, &c) in index.iter().enumerate() {
            ids[next[c] as usize] = i as u32;
            next[c] += 1;
        }
        cells.start = start;
        cells.ids = ids;
        cells
    }

    fn coordinate(&self, p: &Vector<D>, k: usize) -> usize {
        let x = if self.wrap[k] {
            p[k].rem_euclid(self.side[k] * self.n[k] as Real)
        } else {
            p[k] - self.lo[k]
        };
        let i = (x / self.side[k]).floor();
        if i.is_finite() && i > 0.0 {
            (i as usize).min(self.n[k] - 1)
        } else {
            0
        }
    }

    fn cell_of(&self, p: &Vector<D>) -> usize {
        (0..D).fold(0, |index, k| index * self.n[k] + self.coordinate(p, k))
    }

    /// Calls `f(j)` for every centre in the cube of `p` and its neighbours,
    /// each once.
    fn for_each_near(&self, p: &Vector<D>, mut f: impl FnMut(usize)) {
        // Per axis, the distinct neighbouring cells (a period of one or two
        // cells would name a cell twice).
        let mut axes = [[0usize; 3]; D];
        let mut counts = [0usize; D];
        for k in 0..D {
            let c = self.coordinate(p, k) as isize;
            let n = self.n[k] as isize;
            for step in -1..=1 {
                let mut x = c + step;
                if self.wrap[k] {
                    x = x.rem_euclid(n);
                } else if x < 0 || x >= n {
                    continue;
                }
                let x = x as usize;
                if !axes[k][..counts[k]].contains(&x) {
                    axes[k][counts[k]] = x;
                    counts[k] += 1;
                }
            }
        }
        let mut pick = [0usize; D];
        loop {
            let cell = (0..D).fold(0, |index, k| index * self.n[k] + axes[k][pick[k]]);
            for &j in &self.ids[self.start[cell] as usize..self.start[cell + 1] as usize] {
                f(j as usize);
            }
            let mut k = 0;
            loop {
                if k == D {
                    return;
                }
                pick[k] += 1;
                if pick[k] < counts[k] {
                    break;
                }
                pick[k] = 0;
                k += 1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::packing::bulk_region;

    /// g(r) by brute force over every pair, each image counted (the reach
    /// is at most half a period, so one image at most is within it).
    fn brute<const D: usize>(bed: &Bed<D>, region: &Region<D>, g: &PairCorrelation) -> Vec<u64> {
        let mut h = vec![0u64; g.r.len()];
        for i in 0..bed.len() {
            if !region.contains(&bed.centres[i]) {
                continue;
            }
            for j in 0..bed.len() {
                if i == j {
                    continue;
                }
                let d = bed
                    .container
                    .displacement(&bed.centres[i], &bed.centres[j])
                    .norm();
                let k = (d / g.bin).floor() as usize;
                if k < h.len() {
                    h[k] += 1;
                }
            }
        }
        h
    }

    fn counts<const D: usize>(g: &PairCorrelation, region: &Region<D>) -> Vec<u64> {
        let n = g.centres as Real;
        let density = n / region.volume();
        (0..g.r.len())
            .map(|k| {
                let shell =
                    ball_volume::<D>((k + 1) as Real * g.bin) - ball_volume::<D>(k as Real * g.bin);
                (g.g[k] * n * density * shell).round() as u64
            })
            .collect()
    }

    fn random_bed<const D: usize>(periodic: bool, seed: u64) -> Bed<D> {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let mut size = [12.0; D];
        size[D - 1] = 30.0;
        let spheres: Vec<([Real; D], Real, u32)> = (0..900)
            .map(|_| {
                let mut c = [0.0; D];
                for k in 0..D {
                    c[k] = rng.random_range(0.0..size[k]);
                }
                (c, rng.random_range(0.3..0.7), 0)
            })
            .collect();
        Bed::of_spheres(size, periodic, spheres)
    }

    #[test]
    fn the_cells_count_what_every_pair_counts() {
        for periodic in [false, true] {
            for seed in 1..4 {
                let b3 = random_bed::<3>(periodic, seed);
                let region = bulk_region(&b3).expect("a bulk");
                let g = pair_correlation(&b3, &region).unwrap();
                assert_eq!(counts(&g, &region), brute(&b3, &region, &g));
                let b2 = random_bed::<2>(periodic, seed);
                let region = bulk_region(&b2).expect("a bulk");
                let g = pair_correlation(&b2, &region).unwrap();
                assert_eq!(counts(&g, &region), brute(&b2, &region, &g));
            }
        }
    }

    #[test]
    fn a_square_lattice_peaks_at_its_spacings() {
        // Discs of diameter 1 on a unit square lattice, periodic: neighbours
        // at 1 (4) and √2 (4), nothing between.
        let spheres: Vec<([Real; 2], Real, u32)> = (0..20)
            .flat_map(|i| (0..40).map(move |j| ([i as Real + 0.5, j as Real + 0.5], 0.5, 0)))
            .collect();
        let bed = Bed::of_spheres([20.0, 40.0], true, spheres);
        let region = bulk_region(&bed).unwrap();
        let g = pair_correlation(&bed, &region).unwrap();
        let per_centre = |r: Real| {
            let k = (r / g.bin).floor() as usize;
            counts(&g, &region)[k] as Real / g.centres as Real
        };
        // The reach is two largest diameters, 2: the next shell, at 2, is
        // just out of it.
        assert_eq!(g.r.len() as Real * g.bin, 2.0);
        assert_eq!(per_centre(1.0), 4.0);
        assert_eq!(per_centre(2.0_f64.sqrt()), 4.0);
        let total: u64 = counts(&g, &region).iter().sum();
        assert_eq!(total, 8 * g.centres);
        // Between the shells nothing: g is 0 there.
        assert_eq!(g.g[(1.2 / g.bin) as usize], 0.0);
    }
}
