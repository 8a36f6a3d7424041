//! Orientation of chains (any body of several beads): the axis is the principal
//! direction of its bead centres (the eigenvector of their scatter matrix with the
//! largest eigenvalue), pointed upwards. Its angle from vertical is signed in 2D
//! (−90° lying to the left, 0° upright, +90° to the right); in 3D the polar angle
//! (0°–90°) and the azimuth (−180°–180°, from x towards y; 0 for an upright body).
//! The orientational order parameter is `S = <(3 cos² θ − 1) / 2>` (1: all
//! upright, −1/2: all flat).
//!
//! The source study measured angles from the horizontal instead; with
//! [`AngleFrom::Horizontal`] every angle (histogram, mean) is `90° − ` the angle
//! from vertical: in 2D 0°–180° (0° lying to the right, 90° upright, 180° lying
//! to the left), in 3D the elevation 0°–90° above the horizontal. The order
//! parameter and the azimuth do not depend on the convention.
//!
//! A body lying flat (tilt below [`FLAT_TILT`]) has no upper end, so its axis
//! points from its first bead to its last. A chain enters upright with its first
//! bead at the bottom, so one that fell flat is counted on the side it fell to;
//! chains laid down in random directions split evenly. (Pointing every flat body
//! to +90° put all chains lying on the floor into the last bin of the 2D
//! histogram, about twice the first; and which way the rounding of a nearly flat
//! axis went was chance.)

use super::histogram::BinnedHistogram;
use super::profile::species_count;
use crate::bed::Bed;
use crate::math::{Real, Vector};
use serde::Serialize;

/// Width of the angle bins, degrees.
pub const BIN_DEGREES: Real = 5.0;

/// Vertical component of the unit axis below which a body counts as lying flat:
/// a tilt of about 6·10⁻⁸ degrees, far above the rounding of bead positions
/// (~10⁻¹² of a radius) and far below any tilt a bed can resolve.
pub const FLAT_TILT: Real = 1e-9;

// The convention is a setting of the config schema, where it is defined.
pub use crate::config::AngleFrom;

/// One body's axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyAxis {
    /// Body id.
    pub body: u32,
    /// Species of its first bead.
    pub species: u32,
    /// Unit axis with a non-negative vertical component.
    pub axis: [Real; 3],
    /// Angle from vertical, degrees: signed in 2D, polar (0–90) in 3D.
    pub angle: Real,
    /// Azimuth in degrees (3D; 0 in 2D).
    pub azimuth: Real,
}

/// Orientation statistics of one group of bodies.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct OrientationStats {
    /// Number of bodies.
    pub bodies: u64,
    /// `S = <(3 cos² θ − 1) / 2>`.
    pub order_parameter: Real,
    /// Mean angle in the bed's convention (see [`Orientation::angle_from`]), degrees.
    pub mean_angle: Real,
    /// Angle in the bed's convention, 5° bins: from vertical `[-90, 90]` in 2D
    /// and `[0, 90]` in 3D; from horizontal `[0, 180]` in 2D and `[0, 90]` in 3D.
    pub histogram: BinnedHistogram,
    /// Azimuth `[-180, 180]` in 5° bins (3D only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub azimuth_histogram: Option<BinnedHistogram>,
}

/// `orientation.*` of `summary.json` (beds with bodies of several beads).
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Orientation {
    /// Bodies of several beads.
    pub bodies: u64,
    /// The direction the angles are measured from.
    pub angle_from: AngleFrom,
    /// Over all such bodies (with respect to the vertical in either convention).
    pub order_parameter: Real,
    /// Mean angle, degrees.
    pub mean_angle: Real,
    /// Angle over all such bodies.
    pub histogram: BinnedHistogram,
    /// Azimuth over all such bodies (3D only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub azimuth_histogram: Option<BinnedHistogram>,
    /// Per species index (species without chains have `bodies = 0`).
    pub by_species: Vec<OrientationStats>,
}

/// The axis of every body of at least two beads, in body order of appearance.
pub fn body_axes<const D: usize>(bed: &Bed<D>) -> Vec<BodyAxis> {
    let mut out = Vec::new();
    let n = bed.len();
    // Beads of one body are consecutive rows (as deposition writes them); a body
    // split over non-adjacent rows is gathered by sorting.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| (bed.bodies[i], i));
    let mut k = 0;
    while k < n {
        let b = bed.bodies[order[k]];
        let mut e = k + 1;
        while e < n && bed.bodies[order[e]] == b {
            e += 1;
        }
        if e - k >= 2 {
            if let Some(axis) = principal_axis(bed, &order[k..e]) {
                out.push(describe(b, bed.species[order[k]], axis, D));
            }
        }
        k = e;
    }
    out
}

/// Principal direction of the bead centres (unwrapped around the first bead).
fn principal_axis<const D: usize>(bed: &Bed<D>, beads: &[usize]) -> Option<[Real; 3]> {
    let first = bed.centres[beads[0]];
    let pts: Vec<Vector<D>> = beads
        .iter()
        .map(|&i| first + bed.container.displacement(&first, &bed.centres[i]))
        .collect();
    let m = pts.len() as Real;
    let mut mean = [0.0; 3];
    for p in &pts {
        for a in 0..D {
            mean[a] += p[a] / m;
        }
    }
    let mut s = [[0.0; 3]; 3];
    for p in &pts {
        for a in 0..D {
            for b in 0..D {
                s[a][b] += (p[a] - mean[a]) * (p[b] - mean[b]);
            }
        }
    }
    let v = largest_eigenvector(s)?;
    // In 2D the vertical axis is index 1: move it to index 2 for one convention.
    let mut axis = if D == 2 { [v[0], 0.0, v[1]] } else { v };
    if axis[2].abs() <= FLAT_TILT {
        // Lying flat: from the first bead towards the last.
        let run = pts[pts.len() - 1] - pts[0];
        let h = axis[0].hypot(axis[1]);
        axis = [axis[0] / h, axis[1] / h, 0.0];
        let along = axis[0] * run[0] + if D == 3 { axis[1] * run[1] } else { 0.0 };
        if along < 0.0 {
            axis = [-axis[0], -axis[1], 0.0];
        }
    } else if axis[2] < 0.0 {
        axis = [-axis[0], -axis[1], -axis[2]];
    }
    Some(axis)
}

/// Unit eigenvector of the largest eigenvalue of a symmetric 3×3 matrix (cyclic
/// Jacobi rotations); `None` for a zero matrix (coincident beads).
fn largest_eigenvector(mut a: [[Real; 3]; 3]) -> Option<[Real; 3]> {
    let scale: Real = a.iter().flatten().map(|x| x.abs()).sum();
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off <= 1e-15 * scale {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() <= 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← Jᵀ A J, V ← V J with the rotation in the (p, q) plane.
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for k in 0..3 {
                let (vkp, vkq) = (v[k][p], v[k][q]);
                v[k][p] = c * vkp - s * vkq;
                v[k][q] = s * vkp + c * vkq;
            }
        }
    }
    let best = (0..3).max_by(|&i, &j| a[i][i].total_cmp(&a[j][j]))?;
    let e = [v[0][best], v[1][best], v[2][best]];
    let norm = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
    (norm > 0.0).then(|| [e[0] / norm, e[1] / norm, e[2] / norm])
}

fn describe(body: u32, species: u32, axis: [Real; 3], d: usize) -> BodyAxis {
    let polar = axis[2].clamp(-1.0, 1.0).acos().to_degrees();
    let (angle, azimuth) = if d == 2 {
        (if axis[0] < 0.0 { -polar } else { polar }, 0.0)
    } else if axis[0] == 0.0 && axis[1] == 0.0 {
        (polar, 0.0)
    } else {
        (polar, axis[1].atan2(axis[0]).to_degrees())
    };
    BodyAxis {
        body,
        species,
        axis,
        angle,
        azimuth,
    }
}

fn stats(axes: &[&BodyAxis], d: usize, from: AngleFrom) -> OrientationStats {
    let (lo, hi) = from.range(d);
    let mut histogram = BinnedHistogram::new(lo, hi, BIN_DEGREES);
    let mut azimuth = (d == 3).then(|| BinnedHistogram::new(-180.0, 180.0, BIN_DEGREES));
    let mut s = 0.0;
    let mut mean = 0.0;
    for a in axes {
        let angle = from.convert(a.angle);
        histogram.add(angle);
        if let Some(h) = azimuth.as_mut() {
            h.add(a.azimuth);
        }
        let c = a.axis[2];
        s += 0.5 * (3.0 * c * c - 1.0);
        mean += angle;
    }
    let n = axes.len();
    OrientationStats {
        bodies: n as u64,
        order_parameter: if n > 0 { s / n as Real } else { 0.0 },
        mean_angle: if n > 0 { mean / n as Real } else { 0.0 },
        histogram,
        azimuth_histogram: azimuth,
    }
}

/// Orientation statistics of `bed` with angles measured from `from`, `None`
/// when no body has several beads.
pub fn orientation<const D: usize>(bed: &Bed<D>, from: AngleFrom) -> Option<Orientation> {
    let axes = body_axes(bed);
    if axes.is_empty() {
        return None;
    }
    let all: Vec<&BodyAxis> = axes.iter().collect();
    let total = stats(&all, D, from);
    let by_species = (0..species_count(bed) as u32)
        .map(|s| {
            let group: Vec<&BodyAxis> = axes.iter().filter(|a| a.species == s).collect();
            stats(&group, D, from)
        })
        .collect();
    Some(Orientation {
        bodies: total.bodies,
        angle_from: from,
        order_parameter: total.order_parameter,
        mean_angle: total.mean_angle,
        histogram: total.histogram,
        azimuth_histogram: total.azimuth_histogram,
        by_species,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::container::Container;

    /// A straight chain of `beads` unit beads, spacing 1, from `start` along `dir`.
    fn chain<const D: usize>(
        bed: &mut Bed<D>,
        start: Vector<D>,
        dir: Vector<D>,
        beads: usize,
        species: u32,
    ) {
        let body = bed.bodies.last().map_or(0, |&b| b + 1);
        let u = dir.normalized().unwrap();
        for k in 0..beads {
            bed.push_bead(start + u * k as Real, 1.0, species, body);
        }
    }

    #[test]
    fn signed_angles_in_2d() {
        let mut bed = Bed::new(
            Container {
                size: Vector([100.0, 100.0]),
                periodic: false,
            },
            Vec::new(),
        );
        let t = 30f64.to_radians();
        chain(&mut bed, Vector([10.0, 10.0]), Vector([0.0, 1.0]), 5, 0);
        chain(
            &mut bed,
            Vector([20.0, 10.0]),
            Vector([t.sin(), t.cos()]),
            5,
            0,
        );
        chain(
            &mut bed,
            Vector([30.0, 10.0]),
            Vector([t.sin(), -t.cos()]),
            4,
            1,
        ); // pointing down-right: axis up-left
        chain(&mut bed, Vector([40.0, 10.0]), Vector([1.0, 0.0]), 3, 1);
        bed.push(Vector([50.0, 10.0]), 1.0, 2); // a sphere: no axis
        let axes = body_axes(&bed);
        let angles: Vec<Real> = axes.iter().map(|a| a.angle).collect();
        let want = [0.0, 30.0, -30.0, 90.0];
        for (g, w) in angles.iter().zip(want) {
            assert!((g - w).abs() < 1e-9, "{angles:?}");
        }
        let o = orientation(&bed, AngleFrom::Vertical).unwrap();
        assert_eq!(o.bodies, 4);
        let c30 = t.cos() * t.cos();
        let s = (1.0 + 2.0 * 0.5 * (3.0 * c30 - 1.0) - 0.5) / 4.0;
        assert!((o.order_parameter - s).abs() < 1e-12);
        assert_eq!(o.histogram.counts.len(), 36);
        assert_eq!(o.histogram.counts[18], 1); // [0, 5)
                                               // ±30 sit on bin edges: one of the two bins next to the edge, by rounding.
        assert_eq!(o.histogram.counts[23] + o.histogram.counts[24], 1);
        assert_eq!(o.histogram.counts[11] + o.histogram.counts[12], 1);
        assert_eq!(o.histogram.counts[35], 1); // 90
        assert_eq!(o.by_species.len(), 3);
        assert_eq!(o.by_species[0].bodies, 2);
        assert_eq!(o.by_species[2].bodies, 0);
        assert!(o.azimuth_histogram.is_none());
    }

    /// Flat bodies point from their first bead to their last, whatever the
    /// rounding of a nearly flat axis: the side a chain that entered upright fell
    /// to.
    #[test]
    fn flat_bodies_lie_on_the_side_of_their_last_bead() {
        let mut bed = Bed::new(
            Container {
                size: Vector([100.0, 100.0]),
                periodic: true,
            },
            Vec::new(),
        );
        for (x, dir, z) in [
            (10.0, 1.0, 0.0),
            (20.0, -1.0, 0.0),
            (30.0, 1.0, -1e-13),
            (40.0, -1.0, 1e-13),
            (99.0, 1.0, 0.0), // across the seam
        ] {
            chain(&mut bed, Vector([x, 10.0]), Vector([dir, z]), 4, 0);
        }
        for c in bed.centres.iter_mut() {
            c[0] = c[0].rem_euclid(100.0);
        }
        let angles: Vec<Real> = body_axes(&bed).iter().map(|a| a.angle).collect();
        assert_eq!(angles, [90.0, -90.0, 90.0, -90.0, 90.0]);
        let o = orientation(&bed, AngleFrom::Vertical).unwrap();
        assert_eq!((o.histogram.counts[0], o.histogram.counts[35]), (2, 3));
        // A real tilt keeps the upper end's side whatever the bead order.
        let mut tilted = Bed::new(bed.container, Vec::new());
        chain(
            &mut tilted,
            Vector([50.0, 10.0]),
            Vector([-1.0, -1e-3]),
            4,
            0,
        );
        assert!(body_axes(&tilted)[0].angle > 89.9);

        let mut bed3 = Bed::new(
            Container {
                size: Vector([100.0, 100.0, 100.0]),
                periodic: false,
            },
            Vec::new(),
        );
        chain(
            &mut bed3,
            Vector([50.0, 50.0, 1.0]),
            Vector([0.0, -1.0, 0.0]),
            3,
            0,
        );
        chain(
            &mut bed3,
            Vector([50.0, 50.0, 5.0]),
            Vector([-1.0, 0.0, 1e-14]),
            3,
            0,
        );
        let axes = body_axes(&bed3);
        assert_eq!((axes[0].angle, axes[0].azimuth), (90.0, -90.0));
        assert_eq!((axes[1].angle, axes[1].azimuth.abs()), (90.0, 180.0));
    }

    #[test]
    fn polar_and_azimuth_in_3d() {
        let mut bed = Bed::new(
            Container {
                size: Vector([100.0, 100.0, 100.0]),
                periodic: true,
            },
            Vec::new(),
        );
        chain(
            &mut bed,
            Vector([10.0, 10.0, 10.0]),
            Vector([1.0, 1.0, 1.0]),
            6,
            0,
        );
        // Stored across the periodic seam: beads at x = 99.5, 0.5, 1.5.
        chain(
            &mut bed,
            Vector([99.5, 10.0, 10.0]),
            Vector([1.0, 0.0, 0.0]),
            3,
            0,
        );
        for b in bed.centres.iter_mut() {
            b[0] = b[0].rem_euclid(100.0);
        }
        let axes = body_axes(&bed);
        assert!((axes[0].angle - (1.0f64 / 3f64.sqrt()).acos().to_degrees()).abs() < 1e-9);
        assert!((axes[0].azimuth - 45.0).abs() < 1e-9);
        assert!((axes[1].angle - 90.0).abs() < 1e-9);
        assert!(axes[1].azimuth.abs() < 1e-9);
        let o = orientation(&bed, AngleFrom::Vertical).unwrap();
        // cos²θ = 1/3 gives 0; lying flat gives −1/2.
        assert!((o.order_parameter - (-0.25)).abs() < 1e-12);
        assert_eq!(o.histogram.counts.len(), 18);
        assert_eq!(o.azimuth_histogram.as_ref().unwrap().counts.len(), 72);
    }

    #[test]
    fn eigenvector_of_a_known_matrix_and_spheres_only() {
        let v = largest_eigenvector([[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 1.0]]).unwrap();
        let s = 0.5f64.sqrt();
        assert!(
            (v[0].abs() - s).abs() < 1e-12 && (v[1].abs() - s).abs() < 1e-12 && v[2].abs() < 1e-12
        );
        assert!(largest_eigenvector([[0.0; 3]; 3]).is_none());
        let mut bed = Bed::new(
            Container {
                size: Vector([10.0, 10.0]),
                periodic: false,
            },
            Vec::new(),
        );
        bed.push(Vector([1.0, 1.0]), 1.0, 0);
        assert!(orientation(&bed, AngleFrom::Vertical).is_none());
    }
}
