//! `packing.heap`: the slope of a heap's flank, fitted to its surface, for
//! beds poured from a point (`[feed] pattern = "point"`): the angle a
//! settling rule's heap stands at.
//!
//! The apex is the highest particle top. Every particle's top is binned by
//! its horizontal distance from the apex's centre (the minimum image on
//! periodic sides), in bins one largest diameter wide; a bin's height is its
//! highest top, the surface there. The flank is the bins whose surface lies
//! between 20 % and 80 % of the way from the lowest bin's surface up to the
//! apex (the apex's rounding and the foot's spread left out); a least-squares
//! line through them gives the slope. A surface with less relief than three
//! largest diameters, or whose flank heights a line explains less than 90 %
//! of (R² < 0.9: a rough flat surface), is no heap: the measure is null.

use crate::bed::Bed;
use crate::math::{Real, Vector};
use serde::Serialize;

/// The flank: from this share of the relief above the foot...
const FLANK_LOW: Real = 0.2;
/// ...up to this one.
const FLANK_HIGH: Real = 0.8;

/// The least share of the flank's height variance the line must explain
/// (its R²).
const MIN_R2: Real = 0.9;

/// A heap's flank, fitted.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Heap {
    /// The flank's slope, degrees from the horizontal.
    pub slope_degrees: Real,
    /// The apex: the highest particle top.
    pub apex_height: Real,
    /// The bins (one largest diameter wide) the line was fitted to.
    pub flank_bins: u64,
}

/// The heap of `bed`, if its surface has one.
pub fn heap<const D: usize>(bed: &Bed<D>) -> Option<Heap> {
    let n = bed.len();
    if n == 0 {
        return None;
    }
    let d_max = 2.0 * bed.r_max();
    let top = |i: usize| bed.centres[i][D - 1] + bed.radii[i];
    let apex = (0..n).max_by(|&a, &b| top(a).total_cmp(&top(b)).then(b.cmp(&a)))?;
    let apex_height = top(apex);
    let axis: Vector<D> = bed.centres[apex];
    let mut surface: Vec<Real> = Vec::new();
    for i in 0..n {
        let mut w = bed.container.displacement(&axis, &bed.centres[i]);
        w[D - 1] = 0.0;
        let k = (w.norm() / d_max).floor();
        if !(k.is_finite() && k >= 0.0) {
            continue;
        }
        let k = k as usize;
        if k >= 1 << 20 {
            continue;
        }
        if surface.len() <= k {
            surface.resize(k + 1, Real::NEG_INFINITY);
        }
        surface[k] = surface[k].max(top(i));
    }
    let foot = surface
        .iter()
        .copied()
        .filter(|h| h.is_finite())
        .fold(Real::INFINITY, Real::min);
    let relief = apex_height - foot;
    if relief.is_nan() || relief < 3.0 * d_max {
        return None;
    }
    let (lo, hi) = (foot + FLANK_LOW * relief, foot + FLANK_HIGH * relief);
    let flank: Vec<(Real, Real)> = surface
        .iter()
        .enumerate()
        .filter(|(_, &h)| h >= lo && h <= hi)
        .map(|(k, &h)| ((k as Real + 0.5) * d_max, h))
        .collect();
    if flank.len() < 3 {
        return None;
    }
    let m = flank.len() as Real;
    let (sx, sy) = flank
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x, b + y));
    let (mx, my) = (sx / m, sy / m);
    let (sxy, sxx, syy) = flank.iter().fold((0.0, 0.0, 0.0), |(a, b, c), &(x, y)| {
        (
            a + (x - mx) * (y - my),
            b + (x - mx) * (x - mx),
            c + (y - my) * (y - my),
        )
    });
    // A rough flat surface (hit-and-stick, a spike) has relief but no
    // flank: its heights do not fall along a line.
    if !(sxx > 0.0 && syy > 0.0) || sxy * sxy < MIN_R2 * sxx * syy {
        return None;
    }
    let slope = -sxy / sxx;
    Some(Heap {
        slope_degrees: slope.atan().to_degrees(),
        apex_height,
        flank_bins: flank.len() as u64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Spheres of radius 0.5 whose tops lie on a cone (3D) or a tent (2D) of
    /// slope `angle` about the box's middle, over a flat layer.
    fn cone<const D: usize>(angle: Real) -> Bed<D> {
        let t = angle.to_radians().tan();
        let width = 200.0;
        let mut spheres = Vec::new();
        let steps = if D == 3 { 200 } else { 1 };
        for i in 0..200 {
            for j in 0..steps {
                let mut c = [0.0; D];
                c[0] = i as Real + 0.5;
                if D == 3 {
                    c[1] = j as Real + 0.5;
                }
                let mut rho2 = 0.0;
                for k in 0..D - 1 {
                    rho2 += (c[k] - 100.0) * (c[k] - 100.0);
                }
                let surface = (60.0 - t * rho2.sqrt()).max(1.0);
                c[D - 1] = surface - 0.5;
                spheres.push((c, 0.5, 0));
            }
        }
        let mut size = [width; D];
        size[D - 1] = 100.0;
        Bed::of_spheres(size, false, spheres)
    }

    #[test]
    fn a_cone_and_a_tent_give_their_slope() {
        for angle in [15.0, 25.0, 35.0] {
            let h3 = heap(&cone::<3>(angle)).expect("a heap");
            assert!((h3.slope_degrees - angle).abs() < 1.0, "3D {angle}: {h3:?}");
            let h2 = heap(&cone::<2>(angle)).expect("a heap");
            assert!((h2.slope_degrees - angle).abs() < 1.0, "2D {angle}: {h2:?}");
            assert!(h2.flank_bins >= 3);
        }
    }

    #[test]
    fn a_flat_bed_is_no_heap() {
        assert_eq!(heap(&cone::<3>(0.0)), None);
        assert_eq!(heap(&cone::<2>(0.5)), None);
    }
}
