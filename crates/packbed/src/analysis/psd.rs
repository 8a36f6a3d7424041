//! The size distribution a bed holds against the one its species asked for,
//! by mass (volume at equal density) as sieve analyses report it and by
//! number. They differ: a roof keeps out the coarse particles that would stick
//! out of it, and fines that percolate down stay in a bed that a short run
//! would end early.

use crate::bed::Bed;
use crate::math::{display_length as length, normal, Real};
use crate::species::{passing_quantile, SizeDist, Species};
use serde::Serialize;

/// Points of the curve over the window of a continuous distribution.
const CURVE_POINTS: usize = 25;

/// How closely, in points of mass percent passing, the placed mass curve must
/// follow the requested one, and how closely the bodies placed must be able to
/// sample it: a run warns when either the gap or the sampling error exceeds
/// it. A point is what a sieve analysis itself reports.
pub const DEPARTURE_TOLERANCE_PERCENT: Real = 1.0;

/// `psd.*`: the placed size distribution next to the requested one.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PsdSummary {
    /// Mass-median diameters and spans, requested and placed.
    pub requested: PsdStats,
    /// The same of the bed.
    pub placed: PsdStats,
    /// How far the placed mass curve lies from the requested one, against
    /// the sampling error of the bodies drawn.
    pub departure: PsdDeparture,
    /// The curves, row by row (also `psd.csv`).
    pub table: Vec<PsdRow>,
}

/// `psd.departure`: the largest gap between the placed and the requested mass
/// curve, and what a draw of this many bodies can resolve.
///
/// The sampling error is that of a mass share of `N` bodies drawn
/// independently from the requested distribution. With the rows of the table
/// as bins of number share `p_j` and mass share `m_j`, the placed mass passing
/// row `k` is a ratio of sums, `F = Σ_{j<=k} n_j v_j / Σ_j n_j v_j`, of
/// multinomial counts `n_j`; its variance to first order (the delta method) is
/// `Var F_k = (1/N) Σ_j (m_j² / p_j) (1{j <= k} − F_k)²`, each body's volume
/// taken as its bin's mean (the spread within a bin, left out, only adds to
/// it). A bin holding much mass in few bodies (small `p_j`, large `m_j`)
/// dominates it: a coarse class expected to draw one body has a sampling error
/// as large as its whole mass share. The error quoted is `z · sd` with `z` the
/// two-sided 95 % normal quantile Bonferroni-corrected over the rows
/// (`Φ⁻¹(1 − 0.025 / rows)`), so that it holds for the whole curve at once.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PsdDeparture {
    /// Largest `|placed − requested|` mass percent passing over the rows.
    pub max_percent: Real,
    /// The diameter of the row where it lies.
    pub at_diameter: Real,
    /// The sampling error (95 %, whole curve) of the placed mass percent
    /// passing for the bodies placed: the largest over the rows.
    pub sampling_error_percent: Real,
    /// Bodies drawn (the `N` of the sampling error).
    pub bodies: u64,
    /// Bodies for which the sampling error is at most
    /// [`DEPARTURE_TOLERANCE_PERCENT`] at every row: what a box must hold.
    pub bodies_needed: Real,
    /// The size range (diameters) of the bin that adds most to the sampling
    /// error, and the bodies the requested distribution expects in it.
    pub sparsest_class: [Real; 2],
    /// Bodies expected in `sparsest_class` for the bodies placed.
    pub sparsest_class_expected_bodies: Real,
    /// Whether the gap or the sampling error exceeds
    /// [`DEPARTURE_TOLERANCE_PERCENT`] (the run warns).
    pub exceeds_tolerance: bool,
}

impl PsdDeparture {
    /// The warning for `summary.json` and the screen, when the departure
    /// exceeds the tolerance.
    pub fn warning(&self) -> Option<String> {
        if !self.exceeds_tolerance {
            return None;
        }
        let n = self.bodies as Real;
        let tol = DEPARTURE_TOLERANCE_PERCENT;
        let cause = if self.max_percent > tol && self.max_percent > self.sampling_error_percent {
            "beyond it: the deposition placed other sizes than it drew (a roof or a narrow \
             box keeps large ones out)"
                .to_string()
        } else {
            format!(
                "the box holds too few bodies for this size distribution (the class {}–{} \
                 expects {} bodies); about {} bodies (a box of {}× this volume) hold the curve \
                 to {tol} point",
                length(self.sparsest_class[0]),
                length(self.sparsest_class[1]),
                length(self.sparsest_class_expected_bodies),
                length(self.bodies_needed.ceil()),
                length((self.bodies_needed / n).ceil()),
            )
        };
        Some(format!(
            "psd: the placed mass curve departs from the requested by {} points at d = {}; \
             {} bodies sample it to ±{} points (95 %): {cause} (psd.departure)",
            length(self.max_percent),
            length(self.at_diameter),
            self.bodies,
            length(self.sampling_error_percent),
        ))
    }
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
    let table: Vec<PsdRow> = sizes(&bed.species_info)
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
        departure: departure(&table, bodies.len() as u64),
        table,
    })
}

/// The departure of the placed curve from the requested and its sampling
/// error for `bodies` bodies ([`PsdDeparture`] says how).
pub fn departure(table: &[PsdRow], bodies: u64) -> PsdDeparture {
    let n = bodies.max(1) as Real;
    // Bins ending at each row: number and mass shares (fractions).
    let mut bins: Vec<(Real, Real)> = Vec::with_capacity(table.len());
    let (mut p0, mut m0) = (0.0, 0.0);
    for row in table {
        let (p, m) = (
            row.requested_number_percent_passing / 100.0,
            row.requested_mass_percent_passing / 100.0,
        );
        bins.push(((p - p0).max(0.0), (m - m0).max(0.0)));
        (p0, m0) = (p, m);
    }
    // Σ_j (m_j² / p_j) (1{j <= k} − F_k)², the variance of row k times N.
    let spread = |k: usize| -> Real {
        let f = table[k].requested_mass_percent_passing / 100.0;
        bins.iter()
            .enumerate()
            .filter(|(_, (p, _))| *p > 0.0)
            .map(|(j, (p, m))| {
                let below = if j <= k { 1.0 } else { 0.0 };
                m * m / p * (below - f).powi(2)
            })
            .sum()
    };
    let spreads: Vec<Real> = (0..table.len()).map(spread).collect();
    let z = normal::quantile(1.0 - 0.025 / table.len().max(1) as Real);
    let worst = (0..table.len())
        .max_by(|&a, &b| {
            let gap = |k: usize| {
                (table[k].placed_mass_percent_passing - table[k].requested_mass_percent_passing)
                    .abs()
            };
            gap(a).total_cmp(&gap(b))
        })
        .unwrap_or(0);
    let gap = table.get(worst).map_or(0.0, |r| {
        (r.placed_mass_percent_passing - r.requested_mass_percent_passing).abs()
    });
    let tol = DEPARTURE_TOLERANCE_PERCENT / 100.0;
    let largest = spreads.iter().copied().fold(0.0, Real::max);
    // The bin adding most to the variance at the row where it is largest.
    let row = (0..spreads.len())
        .max_by(|&a, &b| spreads[a].total_cmp(&spreads[b]))
        .unwrap_or(0);
    let f = table
        .get(row)
        .map_or(0.0, |r| r.requested_mass_percent_passing / 100.0);
    let sparsest = (0..bins.len())
        .filter(|&j| bins[j].0 > 0.0)
        .max_by(|&a, &b| {
            let w = |j: usize| {
                let below = if j <= row { 1.0 } else { 0.0 };
                bins[j].1 * bins[j].1 / bins[j].0 * (below - f).powi(2)
            };
            w(a).total_cmp(&w(b))
        })
        .unwrap_or(0);
    let lower = if sparsest == 0 {
        table.first().map_or(0.0, |r| r.diameter)
    } else {
        table[sparsest - 1].diameter
    };
    PsdDeparture {
        max_percent: gap,
        at_diameter: table.get(worst).map_or(0.0, |r| r.diameter),
        sampling_error_percent: 100.0 * z * (largest / n).sqrt(),
        bodies,
        bodies_needed: (z / tol).powi(2) * largest,
        sparsest_class: [lower, table.get(sparsest).map_or(0.0, |r| r.diameter)],
        sparsest_class_expected_bodies: n * bins.get(sparsest).map_or(0.0, |b| b.0),
        exceeds_tolerance: gap > DEPARTURE_TOLERANCE_PERCENT
            || 100.0 * z * (largest / n).sqrt() > DEPARTURE_TOLERANCE_PERCENT,
    }
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
            feed: None,
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

    fn row(d: Real, n: Real, m: Real) -> PsdRow {
        PsdRow {
            radius: d / 2.0,
            diameter: d,
            requested_mass_percent_passing: m,
            placed_mass_percent_passing: m,
            requested_number_percent_passing: n,
            placed_number_percent_passing: n,
        }
    }

    #[test]
    fn the_sampling_error_is_the_delta_method_variance() {
        // Two sizes of equal number, the larger four times the volume: mass
        // shares 0.2 and 0.8. The placed share of the small ones from N draws
        // is F = x / (4 − 3x), x the share by number (binomial, variance
        // 1/(4N)); dF/dx = 4 / (4 − 3x)² = 0.64 at x = ½, so
        // Var F = 0.64² / (4N) = 0.1024 / N.
        let table = [row(1.0, 50.0, 20.0), row(4f64.cbrt(), 100.0, 100.0)];
        let d = departure(&table, 100);
        let z = normal::quantile(1.0 - 0.025 / 2.0);
        assert!((d.sampling_error_percent - 100.0 * z * (0.1024f64 / 100.0).sqrt()).abs() < 1e-12);
        assert!((d.bodies_needed - (z / 0.01).powi(2) * 0.1024).abs() < 1e-6);
        assert!(d.exceeds_tolerance && d.max_percent == 0.0);
        assert_eq!(d.sparsest_class_expected_bodies, 50.0);
    }

    #[test]
    fn the_sampling_error_matches_repeated_draws() {
        use rand::SeedableRng;
        // A uniform radius on [1, 2], its curve at the grid rows; 4000 beds of
        // 200 draws each: the spread of the placed mass curve at its worst row.
        let dist = SizeDist::Uniform { min: 1.0, max: 2.0 };
        let rows: Vec<PsdRow> = sizes(&[species(dist.clone())])
            .into_iter()
            .map(|r| {
                row(
                    2.0 * r,
                    100.0 * dist.number_passing(r),
                    100.0 * dist.volume_passing(r),
                )
            })
            .collect();
        let (beds, n) = (4000, 200);
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
        let mut sums = vec![(0.0, 0.0); rows.len()];
        for _ in 0..beds {
            let draws: Vec<Real> = (0..n).map(|_| dist.sample(&mut rng)).collect();
            let total: Real = draws.iter().map(|r| r.powi(3)).sum();
            for (k, row) in rows.iter().enumerate() {
                let f: Real = draws
                    .iter()
                    .filter(|&&r| r <= row.radius)
                    .map(|r| r.powi(3))
                    .sum::<Real>()
                    / total;
                sums[k].0 += f;
                sums[k].1 += f * f;
            }
        }
        let sd = sums
            .iter()
            .map(|(s, s2)| {
                (s2 / beds as Real - (s / beds as Real).powi(2))
                    .max(0.0)
                    .sqrt()
            })
            .fold(0.0, Real::max);
        let z = normal::quantile(1.0 - 0.025 / rows.len() as Real);
        let d = departure(&rows, n);
        let predicted = d.sampling_error_percent / (100.0 * z);
        assert!(
            (predicted / sd - 1.0).abs() < 0.06,
            "{predicted} against {sd}"
        );
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
