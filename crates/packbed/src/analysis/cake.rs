//! Filter cake properties (`docs/reference/pores.md`, "Cake properties"): porosity,
//! Sauter diameter, specific surface, the Kozeny–Carman permeability and, with a
//! solid density and a length unit, the specific cake resistance in SI units.
//!
//! The bulk values use the bulk region of the packing measure (null with it);
//! the whole-cake values use the cake up to its surface height, because the box
//! up to the roof holds head space that is no part of the cake.

use super::packing::Region;
use crate::bed::Bed;
use crate::math::Real;
use serde::Serialize;
use std::f64::consts::PI;

/// The Kozeny constant of the Carman–Kozeny relation `k = ε³ d² / (180 (1 − ε)²)`
/// for beds of spheres (Carman 1937: 5 × 36).
pub const KOZENY_CARMAN: Real = 180.0;

/// Settings of the cake properties (`[analysis] solid_density`, `length_unit`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CakeOptions {
    /// Density of the solid, kg/m³.
    pub solid_density: Option<Real>,
    /// Metres per length unit of the bed (`length_unit`).
    pub metres_per_unit: Option<Real>,
}

/// `cake.*` keys of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct CakeSummary {
    /// Porosity `ε = 1 − φ` of the bulk region (null as `packing.bulk`).
    pub porosity: Option<Real>,
    /// Sauter mean diameter `Σ V / Σ S × 6` (× 4 in 2D) of the bodies with a
    /// particle centre in the bulk region: `Σ d³ / Σ d²` for spheres.
    pub d32: Option<Real>,
    /// Surface per solid volume, `6 / d32` (`4 / d32` in 2D), 1/length.
    pub specific_surface: Option<Real>,
    /// Solid surface per bed volume, `(1 − ε) × specific_surface`, 1/length.
    pub surface_per_bed_volume: Option<Real>,
    /// Kozeny–Carman permeability `ε³ d32² / (180 (1 − ε)²)`, length² (3D only).
    pub k_kozeny_carman: Option<Real>,
    /// The same in m² (with `length_unit`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k_kozeny_carman_m2: Option<Real>,
    /// Cake height: the surface height of the bed (mean of column tops).
    pub height: Real,
    /// Solid volume per floor area (area per floor length in 2D), a length.
    pub solids_per_area: Real,
    /// Solid mass per floor area, kg/m² (with `solid_density` and `length_unit`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub solids_mass_per_area: Option<Real>,
    /// Specific cake resistance `α = 1 / (k ρ_s (1 − ε))`, m/kg, from the bulk
    /// porosity and `specific_resistance_from`'s `k` (3D, with `solid_density`
    /// and `length_unit`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub specific_resistance: Option<Real>,
    /// Which permeability `α` uses: `kozeny_carman` (or `network` when the
    /// permeability measure is computed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub specific_resistance_from: Option<&'static str>,
    /// The same properties over the whole cake up to `height`.
    pub whole: CakeRegion,
    /// The solid density the resistance was computed with.
    #[serde(skip)]
    pub solid_density_used: Option<Real>,
    /// The bed's length unit (`m`, `mm`, `um`, `nm`) when one was given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub length_unit: Option<&'static str>,
    /// Metres per length unit (`length_unit`).
    #[serde(skip)]
    pub metres_per_unit: Option<Real>,
    /// What the numbers mean where they differ from a filter cake's (2D).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<&'static str>,
}

/// Cake properties of one region.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct CakeRegion {
    /// Porosity `1 − φ`.
    pub porosity: Real,
    /// Sauter mean diameter.
    pub d32: Real,
    /// Surface per solid volume.
    pub specific_surface: Real,
    /// Solid surface per bed volume.
    pub surface_per_bed_volume: Real,
    /// Kozeny–Carman permeability (3D; null in 2D).
    pub k_kozeny_carman: Option<Real>,
}

/// Kozeny–Carman permeability `ε³ d² / (180 (1 − ε)²)`; `None` for a porosity
/// that is not in (0, 1) or a size that is not positive.
pub fn kozeny_carman(porosity: Real, d32: Real) -> Option<Real> {
    let solid = 1.0 - porosity;
    let ok = porosity > 0.0 && solid > 0.0 && d32 > 0.0 && d32.is_finite();
    ok.then(|| porosity.powi(3) * d32 * d32 / (KOZENY_CARMAN * solid * solid))
}

/// Specific cake resistance `1 / (k ρ_s (1 − ε))` for `k` in m² and `ρ_s` in
/// kg/m³: m/kg.
pub fn specific_resistance(k_m2: Real, solid_density: Real, porosity: Real) -> Option<Real> {
    let a = 1.0 / (k_m2 * solid_density * (1.0 - porosity));
    (a.is_finite() && a > 0.0).then_some(a)
}

/// The cake properties of `bed`. `volumes` and `surfaces` are each particle's
/// share of its body's union; `bulk` is the bulk region when its measures are
/// valid, with its packing fraction; `height` the surface height.
pub fn cake<const D: usize>(
    bed: &Bed<D>,
    volumes: &[Real],
    surfaces: &[Real],
    bulk: Option<(&Region<D>, Real)>,
    height: Real,
    options: &CakeOptions,
) -> CakeSummary {
    let solids: Real = volumes.iter().sum();
    let floor: Real = (0..D - 1).map(|k| bed.container.size[k]).product();
    let solids_per_area = finite_or_zero(solids / floor);
    let whole_fraction = finite_or_zero(solids / (floor * height)).min(1.0);
    let everything = vec![true; bed.len()];
    let whole = region_properties::<D>(whole_fraction, sauter(bed, volumes, surfaces, &everything));
    let bulk_props = bulk.map(|(region, fraction)| {
        let inside: Vec<bool> = bed.centres.iter().map(|c| region.contains(c)).collect();
        region_properties::<D>(fraction, sauter(bed, volumes, surfaces, &inside))
    });
    let unit = options.metres_per_unit;
    let k_m2 = bulk_props
        .as_ref()
        .and_then(|p| p.k_kozeny_carman)
        .zip(unit)
        .map(|(k, m)| k * m * m);
    let resistance = k_m2
        .zip(options.solid_density)
        .zip(bulk_props.as_ref())
        .and_then(|((k, rho), p)| specific_resistance(k, rho, p.porosity));
    let mass = options
        .solid_density
        .zip(unit)
        .filter(|_| D == 3)
        .map(|(rho, m)| rho * solids_per_area * m);
    CakeSummary {
        porosity: bulk_props.as_ref().map(|p| p.porosity),
        d32: bulk_props.as_ref().map(|p| p.d32),
        specific_surface: bulk_props.as_ref().map(|p| p.specific_surface),
        surface_per_bed_volume: bulk_props.as_ref().map(|p| p.surface_per_bed_volume),
        k_kozeny_carman: bulk_props.as_ref().and_then(|p| p.k_kozeny_carman),
        k_kozeny_carman_m2: k_m2,
        height,
        solids_per_area,
        solids_mass_per_area: mass,
        specific_resistance: resistance,
        specific_resistance_from: resistance.map(|_| "kozeny_carman"),
        whole,
        solid_density_used: options.solid_density,
        length_unit: unit.and_then(unit_name),
        metres_per_unit: unit,
        note: (D == 2).then_some(
            "2D: areas and perimeters per unit depth; no Kozeny-Carman permeability (a relation for 3D beds)",
        ),
    }
}

impl CakeSummary {
    /// Takes the network's permeability along z (the direction of filtration)
    /// for the specific cake resistance, when one can be given.
    pub fn use_network_k(&mut self, k_z: Real) {
        if self.specific_resistance.is_none() {
            return;
        }
        let m = self
            .k_kozeny_carman_m2
            .zip(self.k_kozeny_carman)
            .map(|(m2, k)| m2 / k);
        let (Some(m2_per_unit), Some(porosity), Some(rho)) =
            (m, self.porosity, self.solid_density_used)
        else {
            return;
        };
        self.specific_resistance = specific_resistance(k_z * m2_per_unit, rho, porosity);
        self.specific_resistance_from = self.specific_resistance.map(|_| "network");
    }
}

/// The physical ranges of a filter cake's figures, outside which a figure is
/// far more likely a wrong unit than a cake (`CakeSummary::implausible`).
///
/// - Sizes: cake filtration handles particles from about 0.1 µm (colloids,
///   which blind a filter cloth) to about 10 mm (coarse sands and gravels);
///   the span the particle-size charts of filtration texts give (e.g. Wakeman
///   & Tarleton, *Solid/Liquid Separation: Principles of Industrial
///   Filtration*, Elsevier 2005; Svarovsky, *Solid-Liquid Separation*, 4th ed.,
///   2000).
/// - Porosity: random packings of equal spheres lie between about 0.36
///   (close; Scott & Kilgour 1969) and 0.45 (loose); wide size distributions
///   go lower, loose or elongated particles higher; outside 0.15–0.95 a bulk
///   is no cake.
/// - Permeability and specific resistance: what Kozeny–Carman gives at the
///   ends of the size range for porosities 0.3–0.6 and solid densities
///   1,000–5,000 kg/m³, rounded outward: k from 3e-18 m² (0.1 µm, ε 0.3) to
///   7.5e-7 m² (10 mm, ε 0.6), α from 3e3 m/kg (10 mm, ε 0.6, 1,000 kg/m³) to
///   1e14 m/kg (0.1 µm, ε 0.3, 5,000 kg/m³), α's top widened to the 1e16 m/kg
///   of compressible colloidal cakes. A coarse sand's α of 3e7 m/kg is
///   within them: a floor of 1e8 would call it implausible.
pub const PLAUSIBLE: Plausible = Plausible {
    diameter_m: (1e-7, 1e-2),
    porosity: (0.15, 0.95),
    k_m2: (1e-18, 1e-6),
    alpha_m_per_kg: (1e3, 1e16),
};

/// Ranges of [`PLAUSIBLE`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plausible {
    /// Particle (Sauter) diameter, m.
    pub diameter_m: (Real, Real),
    /// Bulk porosity.
    pub porosity: (Real, Real),
    /// Permeability, m².
    pub k_m2: (Real, Real),
    /// Specific cake resistance, m/kg.
    pub alpha_m_per_kg: (Real, Real),
}

impl CakeSummary {
    /// A warning for each figure outside [`PLAUSIBLE`], for a bed with a
    /// length unit (3D: a filter cake; without a unit the figures have no
    /// physical scale to check).
    pub fn implausible(&self) -> Vec<String> {
        let Some(m) = self.metres_per_unit.filter(|_| self.note.is_none()) else {
            return Vec::new();
        };
        let unit = self.length_unit.unwrap_or("units");
        let r = PLAUSIBLE;
        let mut out = Vec::new();
        let mut check = |what: String, x: Real, (lo, hi): (Real, Real), si: &str, why: &str| {
            if x.is_finite() && !(lo..=hi).contains(&x) {
                out.push(format!(
                    "cake: {what} {x:.3e}{si} lies outside {lo:e}..{hi:e}{si}, the range of \
                     filter cakes; {why}"
                ));
            }
        };
        let unit_hint = format!(
            "are the bed's lengths really in {unit} (`length_unit`, and the unit of a size \
             table's header)?"
        );
        let d32 = self.d32.unwrap_or(self.whole.d32);
        if d32 > 0.0 {
            check(
                format!("d32 ({} {unit})", crate::math::display_length(d32)),
                d32 * m,
                r.diameter_m,
                " m",
                &unit_hint,
            );
        }
        if let Some(p) = self.porosity {
            check(
                "bulk porosity".into(),
                p,
                r.porosity,
                "",
                "is the bulk region a cake (box, roof)?",
            );
        }
        if let Some(k) = self.k_kozeny_carman_m2 {
            check("k (Kozeny-Carman)".into(), k, r.k_m2, " m²", &unit_hint);
        }
        if let Some(a) = self.specific_resistance {
            check(
                "specific resistance".into(),
                a,
                r.alpha_m_per_kg,
                " m/kg",
                "check length_unit and solid_density (kg/m³)",
            );
        }
        out
    }
}

/// The properties of a region of packing fraction `fraction` whose bodies have
/// this Sauter diameter.
fn region_properties<const D: usize>(fraction: Real, d32: Real) -> CakeRegion {
    let porosity = (1.0 - fraction).clamp(0.0, 1.0);
    // 6 / d for a sphere's surface per volume, 4 / d for a disc's perimeter per area.
    let shape = if D == 3 { 6.0 } else { 4.0 };
    let specific_surface = if d32 > 0.0 { shape / d32 } else { 0.0 };
    CakeRegion {
        porosity,
        d32,
        specific_surface,
        surface_per_bed_volume: (1.0 - porosity) * specific_surface,
        k_kozeny_carman: if D == 3 {
            kozeny_carman(porosity, d32)
        } else {
            None
        },
    }
}

/// Sauter diameter of the bodies with at least one flagged particle: 6 ΣV / ΣS
/// (4 ΣA / ΣP in 2D) over all their particles, 0 for none.
fn sauter<const D: usize>(
    bed: &Bed<D>,
    volumes: &[Real],
    surfaces: &[Real],
    flagged: &[bool],
) -> Real {
    // Body ids of a read bed need not be dense (a file may number them in
    // the billions): a sorted list, not an array indexed by id.
    let mut chosen: Vec<u32> = (0..bed.len())
        .filter(|&i| flagged[i])
        .map(|i| bed.bodies[i])
        .collect();
    chosen.sort_unstable();
    chosen.dedup();
    // Σ d³ / Σ d² (Σ d² / Σ d in 2D), each particle as the sphere of its
    // volume and surface share; a whole sphere adds (2r)³ and (2r)² exactly,
    // so that equal spheres give d32 = 2r to the last bit.
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..bed.len() {
        if chosen.binary_search(&bed.bodies[i]).is_err() {
            continue;
        }
        let d = 2.0 * bed.radii[i];
        let whole = surfaces[i] == super::packing::sphere_surface::<D>(bed.radii[i]);
        let (a, b) = match (D, whole) {
            (3, true) => (d * d * d, d * d),
            (3, false) => (6.0 * volumes[i] / PI, surfaces[i] / PI),
            (_, true) => (d * d, d),
            (_, false) => (4.0 * volumes[i] / PI, surfaces[i] / PI),
        };
        num += a;
        den += b;
    }
    finite_or_zero(num / den)
}

fn finite_or_zero(x: Real) -> Real {
    if x.is_finite() {
        x
    } else {
        0.0
    }
}

/// The name of a unit of this many metres, if it is one of the config's.
fn unit_name(metres: Real) -> Option<&'static str> {
    [(1.0, "m"), (1e-3, "mm"), (1e-6, "um"), (1e-9, "nm")]
        .into_iter()
        .find(|(m, _)| (metres / m - 1.0).abs() < 1e-12)
        .map(|(_, n)| n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::packing::particle_volumes_and_surfaces;
    use crate::container::Container;
    use crate::math::Vector;
    use std::f64::consts::PI;

    /// Spheres of radius 1 and 2 on a simple grid, a periodic 3D bed.
    fn two_sizes() -> Bed<3> {
        let mut bed = Bed::new(
            Container {
                size: Vector([8.0, 8.0, 12.0]),
                periodic: true,
            },
            Vec::new(),
        );
        bed.push(Vector([2.0, 2.0, 2.0]), 2.0, 0);
        bed.push(Vector([6.0, 6.0, 1.0]), 1.0, 1);
        bed.push(Vector([6.0, 2.0, 1.0]), 1.0, 1);
        bed
    }

    #[test]
    fn sauter_diameter_of_spheres_is_sum_d3_over_sum_d2() {
        let bed = two_sizes();
        let (v, s) = particle_volumes_and_surfaces(&bed);
        let d32 = sauter(&bed, &v, &s, &[true; 3]);
        let by_hand = (64.0 + 8.0 + 8.0) / (16.0 + 4.0 + 4.0);
        assert!((d32 - by_hand).abs() < 1e-12 * by_hand, "{d32} {by_hand}");
        // Only the small spheres flagged.
        let d = sauter(&bed, &v, &s, &[false, true, false]);
        assert!((d - 2.0).abs() < 1e-12);
    }

    #[test]
    fn chain_counts_its_union() {
        // Two beads of radius 1 whose centres are 1 apart: the union's volume is
        // two balls less the lens, its surface two spheres less two caps.
        let mut bed = Bed::new(
            Container {
                size: Vector([10.0, 10.0, 10.0]),
                periodic: false,
            },
            Vec::new(),
        );
        bed.push_bead(Vector([5.0, 5.0, 1.0]), 1.0, 0, 0);
        bed.push_bead(Vector([6.0, 5.0, 1.0]), 1.0, 0, 0);
        let (v, s) = particle_volumes_and_surfaces(&bed);
        // Each cap beyond the plane at 0.5: height 0.5.
        let cap_v = PI * 0.25 * (3.0 - 0.5) / 3.0;
        let cap_s = 2.0 * PI * 0.5;
        let union_v = 2.0 * (4.0 / 3.0 * PI - cap_v);
        let union_s = 2.0 * (4.0 * PI - cap_s);
        assert!((v.iter().sum::<Real>() - union_v).abs() < 1e-12);
        assert!((s.iter().sum::<Real>() - union_s).abs() < 1e-12);
        let d32 = sauter(&bed, &v, &s, &[true, false]);
        assert!((d32 - 6.0 * union_v / union_s).abs() < 1e-12);
    }

    #[test]
    fn kozeny_carman_by_hand_and_refuses_nonsense() {
        // ε = 0.4, d = 1: 0.064 / (180 × 0.36).
        let k = kozeny_carman(0.4, 1.0).unwrap();
        assert!((k - 0.064 / 64.8).abs() < 1e-15);
        // Scales with d².
        assert!((kozeny_carman(0.4, 3.0).unwrap() / k - 9.0).abs() < 1e-12);
        assert_eq!(kozeny_carman(0.0, 1.0), None);
        assert_eq!(kozeny_carman(1.0, 1.0), None);
        assert_eq!(kozeny_carman(0.4, 0.0), None);
        assert_eq!(kozeny_carman(Real::NAN, 1.0), None);
    }

    #[test]
    fn properties_of_a_bed_by_hand() {
        let bed = two_sizes();
        let (v, s) = particle_volumes_and_surfaces(&bed);
        let solids = 4.0 / 3.0 * PI * (8.0 + 1.0 + 1.0);
        let region = Region {
            lo: Vector([0.0, 0.0, 0.0]),
            hi: Vector([8.0, 8.0, 4.0]),
            wrap: [true, true, false],
        };
        let options = CakeOptions {
            solid_density: Some(2000.0),
            metres_per_unit: Some(1e-6),
        };
        let c = cake(&bed, &v, &s, Some((&region, 0.3)), 4.0, &options);
        assert!((c.porosity.unwrap() - 0.7).abs() < 1e-15);
        let d32 = 80.0 / 24.0;
        assert!((c.d32.unwrap() - d32).abs() < 1e-12);
        assert!((c.specific_surface.unwrap() - 6.0 / d32).abs() < 1e-12);
        assert!((c.surface_per_bed_volume.unwrap() - 0.3 * 6.0 / d32).abs() < 1e-12);
        let k = 0.343 * d32 * d32 / (180.0 * 0.09);
        assert!((c.k_kozeny_carman.unwrap() - k).abs() < 1e-12 * k);
        assert!((c.k_kozeny_carman_m2.unwrap() - k * 1e-12).abs() < 1e-12 * k * 1e-12);
        let alpha = 1.0 / (k * 1e-12 * 2000.0 * 0.3);
        assert!((c.specific_resistance.unwrap() / alpha - 1.0).abs() < 1e-12);
        assert_eq!(c.specific_resistance_from, Some("kozeny_carman"));
        assert!((c.solids_per_area - solids / 64.0).abs() < 1e-12);
        // kg/m²: ρ × (volume per area in µm) × 1e-6 m/µm.
        let mass = 2000.0 * solids / 64.0 * 1e-6;
        assert!((c.solids_mass_per_area.unwrap() - mass).abs() < 1e-12 * mass);
        // Whole cake: the solids over floor × height.
        assert!((c.whole.porosity - (1.0 - solids / 256.0)).abs() < 1e-12);
        assert_eq!(c.note, None);
        // No bulk region: the bulk keys are null, the whole cake is still there.
        let c = cake(&bed, &v, &s, None, 4.0, &CakeOptions::default());
        assert_eq!((c.porosity, c.d32, c.k_kozeny_carman), (None, None, None));
        assert_eq!(
            (c.specific_resistance, c.solids_mass_per_area),
            (None, None)
        );
        assert!(c.whole.k_kozeny_carman.is_some());
    }

    #[test]
    fn discs_have_no_kozeny_carman_and_say_why() {
        let bed = Bed::of_discs([10.0, 10.0], false, &[(2.0, 2.0, 1.0), (5.0, 2.0, 2.0)]);
        let (v, s) = particle_volumes_and_surfaces(&bed);
        let c = cake(&bed, &v, &s, None, 4.0, &CakeOptions::default());
        // Discs: 4 ΣA / ΣP = Σ d² / Σ d.
        assert!((c.whole.d32 - (4.0 + 16.0) / 6.0).abs() < 1e-12);
        assert_eq!(c.whole.k_kozeny_carman, None);
        assert!(c.note.is_some());
        // An empty bed gives zeros, not NaN.
        let empty: Bed<3> = Bed::new(two_sizes().container, Vec::new());
        let c = cake(&empty, &[], &[], None, 0.0, &CakeOptions::default());
        assert_eq!(c.whole.d32, 0.0);
        assert_eq!(c.whole.porosity, 1.0);
        assert_eq!(c.solids_per_area, 0.0);
    }
}
