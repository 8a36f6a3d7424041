//! Size segregation: the composition of each species in horizontal slabs, and the
//! fraction of each species found in the bottom 10% of the bed (fines that fell
//! through the coarse skeleton).

use super::profile::{slab_solids, species_count};
use crate::bed::Bed;
use crate::math::Real;
use serde::Serialize;

/// The share of the bed's height that counts as its bottom.
pub const BOTTOM_SHARE: Real = 0.1;

/// `segregation.*`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Segregation {
    /// Slab thickness of the composition profile (`d_max`).
    pub slab: Real,
    /// Height of each slab's middle.
    pub z: Vec<Real>,
    /// `composition[s][k]`: share of species `s` in the solid volume of slab `k`
    /// (0 in a slab with no solid).
    pub composition: Vec<Vec<Real>>,
    /// Bed height: the highest particle top.
    pub bed_height: Real,
    /// Per species: the fraction of its particles whose centre lies below
    /// `0.1 × bed_height` (0 for a species with no particle).
    pub bottom_fraction: Vec<Real>,
    /// The same for all particles together, the reference to compare with.
    pub bottom_fraction_all: Real,
}

/// Composition in slabs of thickness `slab` and bottom fractions of `bed`.
pub fn segregation<const D: usize>(bed: &Bed<D>, slab: Real, volumes: &[Real]) -> Segregation {
    let s = slab_solids(bed, slab, volumes);
    let m = s.edges.len().saturating_sub(1);
    let ns = species_count(bed);
    let mut composition = vec![vec![0.0; m]; ns];
    for k in 0..m {
        let total: Real = s.solid.iter().map(|row| row[k]).sum();
        if total > 0.0 {
            for sp in 0..ns {
                composition[sp][k] = s.solid[sp][k] / total;
            }
        }
    }
    let height = bed.top();
    let cut = BOTTOM_SHARE * height;
    let mut below = vec![0u64; ns];
    let mut all = vec![0u64; ns];
    for (c, &sp) in bed.centres.iter().zip(&bed.species) {
        all[sp as usize] += 1;
        if c.height() < cut {
            below[sp as usize] += 1;
        }
    }
    let frac = |b: u64, a: u64| if a > 0 { b as Real / a as Real } else { 0.0 };
    Segregation {
        slab,
        z: (0..m)
            .map(|k| 0.5 * (s.edges[k] + s.edges[k + 1]))
            .collect(),
        composition,
        bed_height: height,
        bottom_fraction: below.iter().zip(&all).map(|(&b, &a)| frac(b, a)).collect(),
        bottom_fraction_all: frac(below.iter().sum(), all.iter().sum()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::packing::particle_volumes;
    use crate::container::Container;
    use crate::math::Vector;

    #[test]
    fn fines_under_a_coarse_layer() {
        // A floor row of 8 small discs (r = 1/2, species 1) under a row of 2 large
        // discs (r = 2, species 0) resting on it: slab d_max = 4.
        let mut bed = Bed::new(
            Container {
                size: Vector([8.0, 8.0]),
                periodic: false,
            },
            Vec::new(),
        );
        for i in 0..8 {
            bed.push(Vector([i as Real + 0.5, 0.5]), 0.5, 1);
        }
        bed.push(Vector([2.0, 3.0]), 2.0, 0);
        bed.push(Vector([6.0, 3.0]), 2.0, 0);
        let v = particle_volumes(&bed);
        let s = segregation(&bed, 4.0, &v);
        assert_eq!(s.bed_height, 5.0);
        // Bottom 10%: z < 0.5: no centre (the small centres sit at exactly 0.5).
        assert_eq!(s.bottom_fraction, vec![0.0, 0.0]);
        let mut low = bed.clone();
        for c in low.centres.iter_mut().take(8) {
            c[1] = 0.49;
        }
        let s2 = segregation(&low, 4.0, &v);
        assert_eq!(s2.bottom_fraction, vec![0.0, 1.0]);
        assert!((s2.bottom_fraction_all - 0.8).abs() < 1e-15);
        // Slab [4, 8]: only large-disc caps: composition 1 large, 0 small.
        assert_eq!(s.z, vec![2.0, 6.0]);
        assert_eq!(s.composition[0][1], 1.0);
        assert_eq!(s.composition[1][1], 0.0);
        let small = 8.0 * std::f64::consts::PI * 0.25;
        let large_low = v[8] + v[9] - 2.0 * crate::analysis::packing::cap_volume::<2>(2.0, 1.0);
        assert!((s.composition[1][0] - small / (small + large_low)).abs() < 1e-14);
        for k in 0..2 {
            assert!((s.composition[0][k] + s.composition[1][k] - 1.0).abs() < 1e-14);
        }
    }
}
