//! The packing-fraction profile: solid fraction in horizontal slabs from the floor
//! up, and the solid volume of each species per slab (shared with
//! [`super::segregation`]).
//!
//! A horizontal slab spans the whole box, so a particle inside the box laterally
//! is cut only by two horizontal planes: its share is the difference of two
//! closed-form caps. A particle sticking out of the box sideways (imported data)
//! is cut exactly by [`super::ball_box_volume`] instead.

use super::packing::{ball_box_volume, cap_volume, particle_volumes};
use super::regions::analysis_height;
use crate::bed::Bed;
use crate::math::{ball_volume, Real, Vector};
use serde::Serialize;

/// At most this many slabs: a guard against a slab width that is tiny compared
/// with the bed (imported data with an outlier), not a limit met in practice.
pub const MAX_SLABS: usize = 1 << 22;

/// At most this many (slab, species) cells, 32 MB of them: 80 species in 4
/// million slabs once asked for 5 GB (found by the config fuzz target).
pub const MAX_SLAB_CELLS: usize = 1 << 22;

/// `packing.profile`: solid fraction in slabs of thickness `slab`, bottom to top.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Profile {
    /// Slab thickness (`d_max / 4` in the summary).
    pub slab: Real,
    /// Height of each slab's middle.
    pub z: Vec<Real>,
    /// Solid fraction of each slab.
    pub fraction: Vec<Real>,
}

/// Solid volume per species in horizontal slabs `[k s, (k + 1) s]` up to the
/// analysis height (the last slab may be thinner).
pub(crate) struct SlabSolids {
    /// Slab bottoms, plus the top of the last slab.
    pub edges: Vec<Real>,
    /// `solid[s][k]`: solid volume of species `s` in slab `k`.
    pub solid: Vec<Vec<Real>>,
    /// Horizontal cross-section of the box.
    pub base: Real,
}

impl SlabSolids {
    /// Volume of slab `k`.
    pub fn slab_volume(&self, k: usize) -> Real {
        self.base * (self.edges[k + 1] - self.edges[k])
    }
}

/// Number of species indices used by `bed` (at least its species list).
pub(crate) fn species_count<const D: usize>(bed: &Bed<D>) -> usize {
    let used = bed.species.iter().max().map_or(0, |&s| s as usize + 1);
    used.max(bed.species_info.len())
}

/// Solid volume of each species in each slab of thickness `slab`.
pub(crate) fn slab_solids<const D: usize>(
    bed: &Bed<D>,
    slab: Real,
    volumes: &[Real],
) -> SlabSolids {
    let h = analysis_height(bed);
    let base: Real = (0..D - 1).map(|k| bed.container.size[k]).product();
    let ns = species_count(bed);
    let empty = SlabSolids {
        edges: Vec::new(),
        solid: vec![Vec::new(); ns],
        base,
    };
    if !(slab > 0.0 && h > 0.0 && h.is_finite() && base > 0.0 && base.is_finite()) {
        return empty;
    }
    let n = (h / slab).ceil();
    let cells = n * ns.max(1) as Real;
    if !(n >= 1.0 && n <= MAX_SLABS as Real && cells <= MAX_SLAB_CELLS as Real) {
        return empty;
    }
    let n = n as usize;
    let mut edges: Vec<Real> = (0..n).map(|k| k as Real * slab).collect();
    edges.push(h);
    let mut solid = vec![vec![0.0; n]; ns];
    let size = bed.container.size;
    for i in 0..bed.len() {
        let (c, r) = (bed.centres[i], bed.radii[i]);
        let whole = ball_volume::<D>(r);
        if !(whole > 0.0 && c.is_finite()) {
            continue;
        }
        let share = volumes[i] / whole;
        let inside_sideways =
            bed.container.periodic || (0..D - 1).all(|k| c[k] - r >= 0.0 && c[k] + r <= size[k]);
        let z = c[D - 1];
        let first = ((z - r) / slab).floor().max(0.0) as usize;
        let last = (((z + r) / slab).floor().max(0.0) as usize).min(n - 1);
        let row = &mut solid[bed.species[i] as usize];
        for k in first..=last {
            let (a, b) = (edges[k], edges[k + 1]);
            let part = if inside_sideways {
                cap_volume::<D>(r, a - z) - cap_volume::<D>(r, b - z)
            } else {
                let mut lo = Vector::zero();
                let mut hi = size;
                lo[D - 1] = a;
                hi[D - 1] = b;
                ball_box_volume(&c, r, &lo, &hi)
            };
            row[k] += part.max(0.0) * share;
        }
    }
    SlabSolids { edges, solid, base }
}

/// Solid fraction in horizontal slabs of thickness `slab` from the floor to the
/// analysis height (roof, or the highest particle top if higher): one
/// `(slab middle, fraction)` per slab, bottom to top. The last slab may be thinner.
pub fn profile<const D: usize>(bed: &Bed<D>, slab: Real) -> Vec<(Real, Real)> {
    let p = profile_of(bed, slab, &particle_volumes(bed));
    p.z.into_iter().zip(p.fraction).collect()
}

/// The profile given each particle's volume share.
pub(crate) fn profile_of<const D: usize>(bed: &Bed<D>, slab: Real, volumes: &[Real]) -> Profile {
    let s = slab_solids(bed, slab, volumes);
    let m = s.edges.len().saturating_sub(1);
    let mut out = Profile {
        slab,
        z: Vec::with_capacity(m),
        fraction: Vec::with_capacity(m),
    };
    for k in 0..m {
        let total: Real = s.solid.iter().map(|row| row[k]).sum();
        let v = s.slab_volume(k);
        out.z.push(0.5 * (s.edges[k] + s.edges[k + 1]));
        out.fraction.push(if v > 0.0 { total / v } else { 0.0 });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::Region;
    use crate::container::Container;
    use proptest::prelude::*;
    use std::f64::consts::PI;

    #[test]
    fn square_lattice_profile_has_the_exact_slab_shape() {
        // One row of 10 discs of radius 1/2 touching the floor, box 10 × 2, slab
        // 1/4: slab [0, 1/4] holds 10 circular segments of height 1/4.
        let mut bed = Bed::new(
            Container {
                size: Vector([10.0, 2.0]),
                periodic: false,
            },
            Vec::new(),
        );
        for i in 0..10 {
            bed.push(Vector([i as Real + 0.5, 0.5]), 0.5, 0);
        }
        let p = profile(&bed, 0.25);
        assert_eq!(p.len(), 8);
        // Circular segment of height 1/4 of a disc of radius 1/2: r² acos(t/r) − t √(r² − t²).
        let (r, t): (Real, Real) = (0.5, 0.25);
        let seg = r * r * (t / r).acos() - t * (r * r - t * t).sqrt();
        assert!((p[0].1 - 10.0 * seg / 2.5).abs() < 1e-14);
        assert!((p[0].0 - 0.125).abs() < 1e-15);
        assert!((p[1].1 - 10.0 * (PI / 8.0 - seg) / 2.5).abs() < 1e-14);
        assert_eq!(p[5].1, 0.0);
        // Slabs sum to the global fraction.
        let mean: Real = p.iter().map(|e| e.1).sum::<Real>() / 8.0;
        assert!((mean - 10.0 * PI / 4.0 / 20.0).abs() < 1e-14);
    }

    #[test]
    fn slabs_times_species_are_bounded_not_slabs_alone() {
        // Two discs of species 0 and 79, 4e6 slabs high: 80 species × 4e6
        // slabs would be 2.6 GB a table; no profile instead.
        let mut bed = Bed::new(
            Container {
                size: Vector([10.0, 4e6 + 1.0]),
                periodic: false,
            },
            Vec::new(),
        );
        bed.push(Vector([2.0, 0.5]), 0.5, 0);
        bed.push(Vector([5.0, 4e6]), 0.5, 79);
        let s = slab_solids(
            &bed,
            1.0,
            &bed.radii.iter().map(|r| PI * r * r).collect::<Vec<_>>(),
        );
        assert!(s.edges.is_empty());
        // One species in the same slabs: within both bounds, a profile.
        bed.species[1] = 0;
        let s = slab_solids(
            &bed,
            1.0,
            &bed.radii.iter().map(|r| PI * r * r).collect::<Vec<_>>(),
        );
        assert!(s.edges.len() > 4_000_000);
    }

    proptest! {
        #[test]
        fn slabs_agree_with_exact_box_cuts(
            periodic in any::<bool>(),
            pts in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0, 0.3f64..1.5), 1..12),
            slab in 0.2f64..3.0,
        ) {
            // Spheres that may stick out of the walls: both code paths are used.
            let mut bed = Bed::new(
                Container { size: Vector([6.0, 5.0, 8.0]), periodic },
                Vec::new(),
            );
            for &(x, y, z, r) in &pts {
                bed.push(Vector([x * 6.0, y * 5.0, r + z * 4.0]), r, 0);
            }
            let v = particle_volumes(&bed);
            let s = slab_solids(&bed, slab, &v);
            for k in 0..s.edges.len() - 1 {
                let mut reg = Region { lo: Vector::zero(), hi: bed.container.size, wrap: [periodic, periodic, false] };
                reg.lo[2] = s.edges[k];
                reg.hi[2] = s.edges[k + 1];
                let want = reg.solid_volume(&bed);
                prop_assert!((s.solid[0][k] - want).abs() < 1e-9 * (1.0 + want), "slab {}: {} vs {}", k, s.solid[0][k], want);
            }
        }
    }
}
