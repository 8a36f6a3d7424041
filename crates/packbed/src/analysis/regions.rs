//! Regional packing fractions, as in the edge-effect studies: `floor`
//! (`z < 2 d_max`), `roof` (`z > H − 2 d_max`), `wall` (within `2 d_max` of a side
//! wall) and `centre` (at least `2 d_max` from every wall, the floor and the roof).
//!
//! Each region is a union of disjoint axis-aligned boxes, and particles cut by a
//! box face are cut exactly ([`super::ball_box_volume`]), so the wall frame is
//! never counted twice where two walls meet. `H` is the height the global packing
//! fraction uses: the roof, or the highest particle top if that is higher.

use super::packing::{particle_volumes, Region};
use crate::bed::Bed;
use crate::math::{Real, Vector};
use serde::Serialize;

/// `packing.regions.*`: solid fraction of each region (`None` when the region is
/// empty: no side walls with periodic sides, no centre in a box under 4 `d_max`).
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct RegionalPacking {
    /// `z < 2 d_max`.
    pub floor: Option<Real>,
    /// `z > H − 2 d_max`.
    pub roof: Option<Real>,
    /// Within `2 d_max` of a side wall (`None` with periodic sides).
    pub wall: Option<Real>,
    /// At least `2 d_max` from every wall, the floor and the roof.
    pub centre: Option<Real>,
}

/// The height of the box the regional and global fractions refer to.
pub fn analysis_height<const D: usize>(bed: &Bed<D>) -> Real {
    let roof = bed.container.height();
    let top = bed.top();
    if roof.is_finite() && roof >= top {
        roof
    } else {
        top
    }
}

/// The four regions of `bed` as unions of disjoint boxes, in the order floor,
/// roof, wall, centre; a region with no volume is an empty list.
pub fn region_boxes<const D: usize>(bed: &Bed<D>) -> [Vec<Region<D>>; 4] {
    let d2 = 4.0 * bed.r_max(); // 2 d_max
    let h = analysis_height(bed);
    let size = bed.container.size;
    let periodic = bed.container.periodic;
    // The whole box, wrapped along periodic axes.
    let mut whole = Region {
        lo: Vector::zero(),
        hi: size,
        wrap: [false; D],
    };
    whole.hi[D - 1] = h;
    for k in 0..D - 1 {
        whole.wrap[k] = periodic;
    }
    let keep = |r: Region<D>| -> Vec<Region<D>> {
        if r.volume() > 0.0 && r.volume().is_finite() {
            vec![r]
        } else {
            Vec::new()
        }
    };
    let mut floor = whole;
    floor.hi[D - 1] = d2.min(h);
    let mut roof = whole;
    roof.lo[D - 1] = (h - d2).max(0.0);
    // The wall frame: along each horizontal axis in turn, the two strips next to its
    // walls, restricted on the axes already done to their interior so that the
    // strips are disjoint. Strips are at most half the width each.
    let mut wall = Vec::new();
    if !periodic {
        let mut inner = whole;
        for k in 0..D - 1 {
            let a = d2.min(0.5 * size[k]);
            let mut low = inner;
            low.hi[k] = a;
            let mut high = inner;
            high.lo[k] = size[k] - a;
            wall.extend(keep(low));
            wall.extend(keep(high));
            inner.lo[k] = a;
            inner.hi[k] = size[k] - a;
        }
    }
    let mut centre = whole;
    for k in 0..D - 1 {
        if !periodic {
            centre.lo[k] = d2;
            centre.hi[k] = size[k] - d2;
        }
    }
    centre.lo[D - 1] = d2;
    centre.hi[D - 1] = h - d2;
    let centre_ok = (0..D).all(|k| centre.hi[k] > centre.lo[k]);
    [
        keep(floor),
        keep(roof),
        wall,
        if centre_ok { keep(centre) } else { Vec::new() },
    ]
}

/// Solid fraction of a union of disjoint boxes (`None` for no volume).
pub fn union_fraction<const D: usize>(
    bed: &Bed<D>,
    boxes: &[Region<D>],
    volumes: &[Real],
) -> Option<Real> {
    let v: Real = boxes.iter().map(Region::volume).sum();
    if !(v > 0.0 && v.is_finite()) {
        return None;
    }
    let solid: Real = boxes.iter().map(|b| b.solid_volume_of(bed, volumes)).sum();
    let f = solid / v;
    f.is_finite().then_some(f)
}

/// The regional packing fractions of `bed`.
pub fn regional_packing<const D: usize>(bed: &Bed<D>) -> RegionalPacking {
    regional_packing_of(bed, &particle_volumes(bed))
}

/// Regional packing given each particle's volume share.
pub(crate) fn regional_packing_of<const D: usize>(
    bed: &Bed<D>,
    volumes: &[Real],
) -> RegionalPacking {
    if bed.is_empty() {
        return RegionalPacking::default();
    }
    let [floor, roof, wall, centre] = region_boxes(bed);
    RegionalPacking {
        floor: union_fraction(bed, &floor, volumes),
        roof: union_fraction(bed, &roof, volumes),
        wall: union_fraction(bed, &wall, volumes),
        centre: union_fraction(bed, &centre, volumes),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::container::Container;
    use std::f64::consts::PI;

    /// Discs of radius 1/2 on the unit square lattice filling `n × n` (d_max = 1).
    fn lattice2(n: usize, periodic: bool) -> Bed<2> {
        let mut bed = Bed::new(
            Container {
                size: Vector([n as Real, n as Real]),
                periodic,
            },
            Vec::new(),
        );
        for j in 0..n {
            for i in 0..n {
                bed.push(Vector([i as Real + 0.5, j as Real + 0.5]), 0.5, 0);
            }
        }
        bed
    }

    #[test]
    fn square_lattice_is_pi_over_four_everywhere() {
        // Region edges at 2 and n − 2 fall between lattice cells: every region
        // holds whole cells, so its fraction is exactly π/4.
        let r = regional_packing(&lattice2(10, false));
        for f in [r.floor, r.roof, r.wall, r.centre] {
            assert!((f.unwrap() - PI / 4.0).abs() < 1e-13, "{r:?}");
        }
        let p = regional_packing(&lattice2(10, true));
        assert_eq!(p.wall, None);
        assert!((p.centre.unwrap() - PI / 4.0).abs() < 1e-13);
    }

    #[test]
    fn region_boundaries_through_particles_are_cut_exactly() {
        // One disc of radius 1 (d_max = 2, so 2 d_max = 4) centred on the corner of
        // the centre region at (4, 4): a quarter of it lies in the centre region.
        let mut bed = Bed::new(
            Container {
                size: Vector([20.0, 20.0]),
                periodic: false,
            },
            Vec::new(),
        );
        bed.push(Vector([4.0, 4.0]), 1.0, 0);
        let [floor, roof, wall, centre] = region_boxes(&bed);
        let v = particle_volumes(&bed);
        let solid = |b: &[Region<2>]| b.iter().map(|r| r.solid_volume_of(&bed, &v)).sum::<Real>();
        assert!((solid(&centre) - PI / 4.0).abs() < 1e-14);
        // The frame: the left strip holds half the disc; the bottom part of the
        // inner column is floor, not wall. Floor holds half.
        assert!((solid(&wall) - PI / 2.0).abs() < 1e-14);
        assert!((solid(&floor) - PI / 2.0).abs() < 1e-14);
        assert_eq!(solid(&roof), 0.0);
        // Frame area: two strips 4 × 20.
        assert_eq!(wall.iter().map(Region::volume).sum::<Real>(), 160.0);
    }

    #[test]
    fn cube_frame_is_disjoint_and_fills_the_border() {
        let mut bed = Bed::new(
            Container {
                size: Vector([10.0, 12.0, 14.0]),
                periodic: false,
            },
            Vec::new(),
        );
        bed.push(Vector([5.0, 6.0, 0.5]), 0.5, 0); // d_max = 1, 2 d_max = 2
        let [_, _, wall, centre] = region_boxes(&bed);
        let frame: Real = wall.iter().map(Region::volume).sum();
        assert!((frame - (10.0 * 12.0 - 6.0 * 8.0) * 14.0).abs() < 1e-9);
        assert!((centre[0].volume() - 6.0 * 8.0 * 10.0).abs() < 1e-9);
        // A box narrower than 4 d_max is all wall, still counted once.
        bed.container.size = Vector([3.0, 3.0, 14.0]);
        bed.centres[0] = Vector([1.5, 1.5, 0.5]);
        let [_, _, wall, centre] = region_boxes(&bed);
        let frame: Real = wall.iter().map(Region::volume).sum();
        assert!((frame - 9.0 * 14.0).abs() < 1e-9);
        assert!(centre.is_empty());
        let r = regional_packing(&bed);
        let ball = 4.0 / 3.0 * PI * 0.125;
        assert!((r.wall.unwrap() - ball / (9.0 * 14.0)).abs() < 1e-15);
        assert_eq!(r.centre, None);
    }

    #[test]
    fn simple_cubic_lattice_in_3d() {
        // Spheres of radius 1/2 on the unit cubic lattice, 8 per side: every region
        // is a union of whole cells, fraction π/6.
        let mut bed = Bed::new(
            Container {
                size: Vector([8.0, 8.0, 8.0]),
                periodic: false,
            },
            Vec::new(),
        );
        for i in 0..8 {
            for j in 0..8 {
                for k in 0..8 {
                    bed.push(
                        Vector([i as Real + 0.5, j as Real + 0.5, k as Real + 0.5]),
                        0.5,
                        0,
                    );
                }
            }
        }
        let r = regional_packing(&bed);
        for f in [r.floor, r.roof, r.wall, r.centre] {
            assert!((f.unwrap() - PI / 6.0).abs() < 1e-12, "{r:?}");
        }
    }
}
