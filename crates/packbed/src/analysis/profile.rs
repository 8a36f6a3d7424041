//! Packing-fraction profile: solid fraction in horizontal slabs, bottom to top
//! (spec: slabs of thickness `d_max / 4`). Each particle's share of a slab is the
//! exact volume of the ball between the slab's two planes.

use super::packing::ball_box_volume;
use crate::bed::Bed;
use crate::math::{Real, Vector};

/// One slab of the profile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slab {
    /// Bottom of the slab.
    pub z_lo: Real,
    /// Top of the slab.
    pub z_hi: Real,
    /// Solid volume (area in 2D) in the slab ÷ slab volume.
    pub fraction: Real,
}

/// Most slabs a profile will have (a thinner slab is widened to stay under it).
pub const MAX_SLABS: usize = 100_000;

/// The spec's slab thickness: a quarter of the largest diameter.
pub fn default_thickness<const D: usize>(bed: &Bed<D>) -> Real {
    bed.r_max() / 2.0
}

/// Solid fraction in slabs of `thickness` from the floor up to the roof (or the
/// bed's top, if higher). Empty for an empty bed or a thickness that is not > 0.
pub fn packing_profile<const D: usize>(bed: &Bed<D>, thickness: Real) -> Vec<Slab> {
    let top = bed.container.height().max(bed.top());
    if bed.is_empty() || !(thickness > 0.0 && thickness.is_finite()) || !(top > 0.0) {
        return Vec::new();
    }
    let mut n = (top / thickness).ceil() as usize;
    let t = if n > MAX_SLABS {
        n = MAX_SLABS;
        top / n as Real
    } else {
        thickness
    };
    let mut solid = vec![0.0; n];
    // Horizontally unbounded: particles lie within the side walls, and with
    // periodic sides the part of a particle beyond one side is inside the box
    // through the other, so the whole cross-section counts.
    let mut lo = Vector::<D>([Real::NEG_INFINITY; D]);
    let mut hi = Vector::<D>([Real::INFINITY; D]);
    for (c, &r) in bed.centres.iter().zip(&bed.radii) {
        let z = c.height();
        let first = (((z - r) / t).floor().max(0.0) as usize).min(n - 1);
        let last = (((z + r) / t).floor().max(0.0) as usize).min(n - 1);
        for (k, s) in solid.iter_mut().enumerate().take(last + 1).skip(first) {
            lo[D - 1] = k as Real * t;
            hi[D - 1] = (k + 1) as Real * t;
            *s += ball_box_volume(c, r, &lo, &hi);
        }
    }
    let area: Real = (0..D - 1).map(|k| bed.container.size[k]).product();
    solid
        .iter()
        .enumerate()
        .map(|(k, &v)| Slab {
            z_lo: k as Real * t,
            z_hi: (k + 1) as Real * t,
            fraction: v / (area * t),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::packing::cap_volume;
    use crate::container::Container;
    use std::f64::consts::PI;

    #[test]
    fn square_lattice_profile_is_exact() {
        // Discs of radius 0.5 on the unit lattice in a 10 × 10 box.
        let mut bed = Bed::new(
            Container {
                size: Vector([10.0, 10.0]),
                periodic: false,
            },
            Vec::new(),
        );
        for j in 0..10 {
            for i in 0..10 {
                bed.push(Vector([i as Real + 0.5, j as Real + 0.5]), 0.5, 0);
            }
        }
        let p = packing_profile(&bed, default_thickness(&bed));
        assert_eq!(p.len(), 40);
        // Outer quarter of a row: a circular segment of height 0.25 per disc.
        let outer = cap_volume::<2>(0.5, 0.25) * 10.0 / (10.0 * 0.25);
        let inner = (PI * 0.25 / 2.0 - cap_volume::<2>(0.5, 0.25)) * 10.0 / (10.0 * 0.25);
        for (k, s) in p.iter().enumerate() {
            let want = if k % 4 == 0 || k % 4 == 3 { outer } else { inner };
            assert!((s.fraction - want).abs() < 1e-12, "slab {k}: {} vs {want}", s.fraction);
            assert!((s.z_lo - 0.25 * k as Real).abs() < 1e-15);
        }
        // The mean over the slabs is the global packing fraction.
        let mean: Real = p.iter().map(|s| s.fraction).sum::<Real>() / p.len() as Real;
        assert!((mean - PI / 4.0).abs() < 1e-12);
    }

    #[test]
    fn profile_integrates_to_the_solid_volume_in_3d() {
        let mut bed = Bed::new(
            Container {
                size: Vector([6.0, 6.0, 5.0]),
                periodic: true,
            },
            Vec::new(),
        );
        // Spheres crossing the periodic sides and slab boundaries at odd heights.
        bed.push(Vector([0.2, 3.0, 1.0]), 1.0, 0);
        bed.push(Vector([3.0, 5.9, 2.37]), 0.8, 1);
        bed.push(Vector([4.0, 1.0, 3.1]), 0.6, 1);
        let t = 0.3;
        let p = packing_profile(&bed, t);
        assert_eq!(p.len(), (5.0f64 / t).ceil() as usize);
        let integral: Real = p.iter().map(|s| s.fraction * 36.0 * t).sum();
        assert!((integral - bed.solid_volume()).abs() < 1e-10 * bed.solid_volume());
        assert!(p.iter().all(|s| (0.0..=1.0).contains(&s.fraction)));
    }

    #[test]
    fn degenerate_inputs_give_no_slabs() {
        let bed: Bed<2> = Bed::new(
            Container {
                size: Vector([1.0, 1.0]),
                periodic: false,
            },
            Vec::new(),
        );
        assert!(packing_profile(&bed, 0.1).is_empty());
        let mut b2 = bed.clone();
        b2.push(Vector([0.5, 0.5]), 0.5, 0);
        assert!(packing_profile(&b2, 0.0).is_empty());
        assert!(packing_profile(&b2, Real::NAN).is_empty());
        assert_eq!(packing_profile(&b2, 1e-9).len(), MAX_SLABS);
    }
}
