//! The size distribution a bed holds against the one its species asked for,
//! by mass (volume at equal density) as sieve analyses report it and by
//! number. They differ: a roof keeps out the coarse particles that would stick
//! out of it, and fines that percolate down stay in a bed that a short run
//! would end early.

use crate::bed::Bed;
use crate::math::Real;
use crate::species::{passing_quantile, SizeDist, Species};
use serde::Serialize;

/// Points of the curve over the window of a continuous distribution.
const CURVE_POINTS: usize = 25;

/// `psd.*`: the placed size distribution next to the requested one.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PsdSummary {
    /// Mass-median diameters and spans, requested and placed.
    pub requested: PsdStats,
    /// The same of the bed.
    pub placed: PsdStats,
    /// The curves, row by row (also `psd.csv`).
    pub table: Vec<PsdRow>,
}

/// Diameters below which 10, 50 and 90 % of the solid's mass lies.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PsdStats {
    /// `d10` by mass.
    pub d10: Real,
    /// `d50` by mass (the mass median diameter).
    pub d50: Real,
    /// `d90` by mass.
    pub d90: Real,
    /// `(d90 − d10) / d50`.
    pub span: Real,
}

/// One size of the curves.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PsdRow {
    /// The radius.
    pub radius: Real,
    /// The diameter.
    pub diameter: Real,
    /// Requested: % of the mass in particles at most this size.
    pub requested_mass_percent_passing: Real,
    /// Placed: the same in the bed.
    pub placed_mass_percent_passing: Real,
    /// Requested: % of the bodies at most this size.
    pub requested_number_percent_passing: Real,
    /// Placed: the same in the bed.
    pub placed_number_percent_passing: Real,
}

/// The requested mixture: each species' number share and its beads per body.
struct Mixture<'a> {
    parts: Vec<(Real, Real, &'a SizeDist)>,
    mean_mass: Real,
}

impl<'a> Mixture<'a> {
    fn new(species: &'a [Species]) -> Option<Self> {
        let total: Real = species.iter().map(|s| s.ratio).sum();
        if total <= 0.0 {
            return None;
        }
        let parts: Vec<(Real, Real, &SizeDist)> = species
            .iter()
            .filter(|s| s.ratio > 0.0)
            .map(|s| {
                let beads = Real::from(s.shape.beads());
                (s.ratio / total, beads, &s.size)
            })
            .collect();
        let mean_mass = parts.iter().map(|(p, b, d)| p * b * d.mean_cube()).sum();
        Some(Mixture { parts, mean_mass })
    }

    fn number_passing(&self, x: Real) -> Real {
        self.parts
            .iter()
            .map(|(p, _, d)| p * d.number_passing(x))
            .sum()
    }

    fn mass_passing(&self, x: Real) -> Real {
        let part: Real = self
            .parts
            .iter()
            .map(|(p, b, d)| p * b * d.mean_cube() * d.volume_passing(x))
            .sum();
        (part / self.mean_mass).clamp(0.0, 1.0)
    }

    /// The radius below which the share `q` of the mass lies, by bisection
    /// over the species' windows.
    fn mass_quantile(&self, q: Real) -> Real {
        let start: (Real, Real) = (Real::INFINITY, 0.0);
        let (lo, hi) = self
            .parts
            .iter()
            .map(|(_, _, d)| d.bounds())
            .fold(start, |(a, b), (l, h)| (a.min(l), b.max(h)));
        passing_quantile(lo, hi, q, |x| self.mass_passing(x))
    }
}

/// Whether the species draw their sizes from a distribution (not only fixed
/// radii): the runs whose placed sizes are worth comparing.
pub fn has_distribution(species: &[Species]) -> bool {
    species
        .iter()
        .any(|s| s.ratio > 0.0 && !matches!(s.size, SizeDist::Fixed(_)))
}

/// The placed size distribution of `bed` against its species' request;
/// `None` when no species draws from a distribution or the bed is empty.
pub fn size_distribution<const D: usize>(bed: &Bed<D>) -> Option<PsdSummary> {
    if bed.is_empty() || !has_distribution(&bed.species_info) {
        return None;
    }
    let mixture = Mixture::new(&bed.species_info)?;
    // Bodies by number (one radius per body: the beads of a chain are equal),
    // particles by volume.
    let mut bodies: Vec<Real> = Vec::new();
    let mut last = None;
    for (&b, &r) in bed.bodies.iter().zip(&bed.radii) {
        if last != Some(b) {
            bodies.push(r);
            last = Some(b);
        }
    }
    bodies.sort_by(Real::total_cmp);
    let mut by_volume: Vec<(Real, Real)> = bed.radii.iter().map(|&r| (r, r * r * r)).collect();
    by_volume.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total_volume: Real = by_volume.iter().map(|x| x.1).sum();
    let mut cumulative = Vec::with_capacity(by_volume.len());
    let mut acc = 0.0;
    for &(_, v) in &by_volume {
        acc += v;
        cumulative.push(acc / total_volume);
    }
    let placed_mass = |x: Real| {
        let i = by_volume.partition_point(|p| p.0 <= x);
        if i == 0 {
            0.0
        } else {
            cumulative[i - 1]
        }
    };
    let placed_number =
        |x: Real| bodies.partition_point(|&r| r <= x) as Real / bodies.len() as Real;
    let placed_quantile = |q: Real| {
        let i = cumulative
            .partition_point(|&c| c < q)
            .min(by_volume.len() - 1);
        by_volume[i].0
    };
    let stats = |quantile: &dyn Fn(Real) -> Real| {
        let (d10, d50, d90) = (
            2.0 * quantile(0.1),
            2.0 * quantile(0.5),
            2.0 * quantile(0.9),
        );
        PsdStats {
            d10,
            d50,
            d90,
            span: (d90 - d10) / d50,
        }
    };
    let table = sizes(&bed.species_info)
        .into_iter()
        .map(|r| PsdRow {
            radius: r,
            diameter: 2.0 * r,
            requested_mass_percent_passing: 100.0 * mixture.mass_passing(r),
            placed_mass_percent_passing: 100.0 * placed_mass(r),
            requested_number_percent_passing: 100.0 * mixture.number_passing(r),
            placed_number_percent_passing: 100.0 * placed_number(r),
        })
        .collect();
    Some(PsdSummary {
        requested: stats(&|q| mixture.mass_quantile(q)),
        placed: stats(&placed_quantile),
        table,
    })
}

/// The radii of the table's rows: a table's own sizes and class edges, fixed
/// radii, and a geometric grid over a continuous window (every placed radius
/// lies within them).
fn sizes(species: &[Species]) -> Vec<Real> {
    let mut v = Vec::new();
    for s in species.iter().filter(|s| s.ratio > 0.0) {
        match &s.size {
            SizeDist::Fixed(r) => v.push(*r),
            SizeDist::Table(t) => v.extend(t.sizes()),
            d => {
                let (lo, hi) = d.bounds();
                let step = (hi / lo).powf(1.0 / (CURVE_POINTS - 1) as Real);
                v.extend((0..CURVE_POINTS).map(|i| lo * step.powi(i as i32)));
                v.push(hi);
            }
        }
    }
    v.retain(|r| r.is_finite() && *r > 0.0);
    v.sort_by(Real::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs());
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bed::Bed;
    use crate::container::Container;
    use crate::math::Vector;
    use crate::species::Shape;

    fn species(size: SizeDist) -> Species {
        Species {
            name: "s".into(),
            shape: Shape::Sphere,
            size,
            ratio: 1.0,
        }
    }

    fn bed_of(radii: &[Real], size: SizeDist) -> Bed<3> {
        let mut bed = Bed::new(
            Container {
                size: Vector([1e3, 1e3, 1e3]),
                periodic: false,
            },
            vec![species(size)],
        );
        for (i, &r) in radii.iter().enumerate() {
            bed.push(Vector([10.0 * i as Real, 0.0, r]), r, 0);
        }
        bed
    }

    #[test]
    fn a_bed_of_fixed_sizes_has_no_comparison() {
        let bed = bed_of(&[1.0, 1.0], SizeDist::Fixed(1.0));
        assert_eq!(size_distribution(&bed), None);
    }

    #[test]
    fn placed_curves_count_by_hand() {
        // Radii 1, 1, 2: bodies 2/3 at r <= 1; mass 2/(2 + 8) = 20 %.
        let bed = bed_of(&[1.0, 2.0, 1.0], SizeDist::Uniform { min: 1.0, max: 2.0 });
        let p = size_distribution(&bed).unwrap();
        let row = p.table.iter().find(|r| r.radius == 1.0).unwrap();
        assert!((row.placed_number_percent_passing - 200.0 / 3.0).abs() < 1e-12);
        assert!((row.placed_mass_percent_passing - 20.0).abs() < 1e-12);
        // The requested uniform on [1, 2] has nothing below 1 and all below 2.
        assert_eq!(row.requested_mass_percent_passing, 0.0);
        let top = p.table.last().unwrap();
        assert_eq!(top.radius, 2.0);
        assert_eq!(top.requested_mass_percent_passing, 100.0);
        assert_eq!(top.placed_mass_percent_passing, 100.0);
        // The mass median of the bed is in the radius-2 particle.
        assert_eq!(p.placed.d50, 4.0);
        assert_eq!(p.placed.d10, 2.0);
        // Requested: volume below x is (x⁴ − 1)/15; half at x = 8.5^¼.
        assert!((p.requested.d50 - 2.0 * 8.5f64.powf(0.25)).abs() < 1e-9);
    }

    #[test]
    fn curves_never_fall() {
        let (lo, hi) = SizeDist::lognormal_window(5.0, 1.5);
        let d = SizeDist::Lognormal {
            median: 5.0,
            gsd: 1.5,
            lo,
            hi,
        };
        let radii: Vec<Real> = (0..50).map(|i| lo + (hi - lo) * i as Real / 49.0).collect();
        let p = size_distribution(&bed_of(&radii, d)).unwrap();
        assert!(p.table.len() >= CURVE_POINTS);
        for w in p.table.windows(2) {
            assert!(w[0].radius < w[1].radius);
            assert!(w[0].requested_mass_percent_passing <= w[1].requested_mass_percent_passing);
            assert!(w[0].placed_mass_percent_passing <= w[1].placed_mass_percent_passing);
        }
    }
}
