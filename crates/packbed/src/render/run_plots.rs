//! The plots of one bed and of ensembles, built from plain data: coordination
//! histograms (overall and per species), the packing profile, regional packing
//! bars, chain-angle histograms, and ensemble/sweep summaries. Each function
//! returns a `Plot`; callers choose file names and formats.

use super::plot::{BarGroup, Plot, PlotData, Series};
use crate::analysis::orientation::AngleFrom;
use crate::analysis::psd::PsdSummary;
use crate::bed::Bed;
use crate::config::LengthUnit;
use crate::math::Real;

/// The unit of lengths for an axis label: the run's `[analysis] length_unit`
/// when it gave one, else "length units" (the bed's own numbers).
pub fn length_label(unit: Option<LengthUnit>) -> &'static str {
    unit.map_or("length units", LengthUnit::symbol)
}

/// Coordination-number histograms side by side: all particles, then each species,
/// as percentages of their particles (so that groups of different sizes compare).
/// `z` is the coordination number of each particle.
pub fn coordination_histogram<const D: usize>(bed: &Bed<D>, z: &[u32]) -> Plot {
    let zmax = z.iter().copied().max().unwrap_or(0) as usize;
    let cats: Vec<String> = (0..=zmax).map(|k| k.to_string()).collect();
    let hist = |pick: &dyn Fn(usize) -> bool| -> Vec<f64> {
        let mut h = vec![0.0; zmax + 1];
        let mut n = 0usize;
        for (i, &k) in z.iter().enumerate() {
            if pick(i) {
                h[k as usize] += 1.0;
                n += 1;
            }
        }
        if n > 0 {
            h.iter_mut().for_each(|v| *v *= 100.0 / n as f64);
        }
        h
    };
    let mut groups = vec![BarGroup {
        name: "all particles".into(),
        values: hist(&|_| true),
        errors: None,
    }];
    let mut present: Vec<u32> = bed.species.clone();
    present.sort_unstable();
    present.dedup();
    if present.len() > 1 {
        for s in present {
            let name = bed
                .species_info
                .get(s as usize)
                .map(|i| i.name.clone())
                .unwrap_or_else(|| format!("species {s}"));
            groups.push(BarGroup {
                name,
                values: hist(&|i| bed.species[i] == s),
                errors: None,
            });
        }
    }
    Plot {
        title: format!("Coordination number ({} particles)", z.len()),
        x_label: "coordination number (touching bodies)".into(),
        y_label: "particles (%)".into(),
        data: PlotData::Bars {
            categories: cats,
            groups,
        },
        y_range: None,
        x_range: None,
    }
}

/// Packing fraction against height, one point per slab at its mid-height
/// (`profile` as from `analysis::profile::profile`: `(z_mid, fraction)` for
/// slabs `slab` thick). `bulk` (optional) is drawn as a horizontal reference line.
/// `unit` names the lengths' unit where the run knows it.
pub fn packing_profile(
    profile: &[(Real, Real)],
    slab: Real,
    bulk: Option<Real>,
    unit: Option<LengthUnit>,
) -> Plot {
    let points: Vec<(f64, f64)> = profile.to_vec();
    let thickness = slab;
    let bottom = profile.first().map(|p| p.0 - 0.5 * slab);
    let top = profile.last().map(|p| p.0 + 0.5 * slab);
    let mut series = vec![Series {
        name: "slabs".into(),
        points,
        errors: None,
        markers: false,
        band: None,
    }];
    if let (Some(b), Some(lo), Some(hi)) = (bulk, bottom, top) {
        series.push(Series {
            name: format!("bulk {}", super::plot::format_number(b)),
            points: vec![(lo, b), (hi, b)],
            errors: None,
            markers: false,
            band: None,
        });
    }
    Plot {
        title: format!(
            "Packing fraction profile (slabs {} {} thick)",
            super::plot::format_number(thickness),
            length_label(unit)
        ),
        x_label: format!("height above the floor ({})", length_label(unit)),
        y_label: "packing fraction".into(),
        data: PlotData::Lines { series },
        y_range: Some((0.0, 1.0)),
        x_range: top.map(|t| (0.0, t)),
    }
}

/// The pore body and constriction size distributions of the slab, cumulative
/// by number (% smaller than a radius), one line each: the curves granular
/// filter design reads `d_c35` from. `body` and `constriction` are radii, in
/// `unit` where the run knows it.
pub fn pore_sizes(body: &[Real], constriction: &[Real], unit: Option<LengthUnit>) -> Plot {
    let cumulative = |name: &str, values: &[Real]| {
        let mut v: Vec<Real> = values.iter().copied().filter(|x| x.is_finite()).collect();
        v.sort_by(Real::total_cmp);
        let n = v.len().max(1) as Real;
        // At most 400 points: a curve, not a scatter of 10^6 steps.
        let step = v.len().div_ceil(400).max(1);
        let mut points: Vec<(Real, Real)> = v
            .iter()
            .enumerate()
            .step_by(step)
            .map(|(i, &x)| (x, 100.0 * (i + 1) as Real / n))
            .collect();
        if let Some(&last) = v.last() {
            points.push((last, 100.0));
        }
        Series {
            name: format!("{name} ({} in the slab)", v.len()),
            points,
            errors: None,
            markers: false,
            band: None,
        }
    };
    // The axis ends at the 99.5th percentile: a few slivers' tangent spheres
    // would otherwise squeeze the curves into the left tenth.
    let mut all: Vec<Real> = body
        .iter()
        .chain(constriction)
        .copied()
        .filter(|x| x.is_finite())
        .collect();
    all.sort_by(Real::total_cmp);
    let x_range = all
        .get((all.len() as Real * 0.995) as usize)
        .filter(|&&x| x > 0.0)
        .map(|&x| (0.0, x));
    let mut series = vec![
        cumulative("pore bodies", body),
        cumulative("constrictions", constriction),
    ];
    // The plot does not clip: the points past the axis are left out.
    if let Some((_, hi)) = x_range {
        for s in &mut series {
            s.points.retain(|p| p.0 <= hi);
        }
    }
    Plot {
        title: "Pore and constriction sizes".into(),
        x_label: format!("radius ({})", length_label(unit)),
        y_label: "smaller than the radius (% by number)".into(),
        data: PlotData::Lines { series },
        y_range: Some((0.0, 100.0)),
        x_range,
    }
}

/// The capillary pressure–saturation curve of the drainage as a lab draws
/// it: `P_c·d32/γ` up against the wetting saturation, the whole liquid and
/// the part left when the trapped and pendular liquid is set aside, with
/// the breakthrough marked.
pub fn drainage_curve(d: &crate::analysis::pores::drainage::Drainage) -> Plot {
    let points = |f: &dyn Fn(&crate::analysis::pores::drainage::CurvePoint) -> Real| {
        d.curve
            .iter()
            .map(|p| (f(p), p.pc_reduced))
            .collect::<Vec<_>>()
    };
    let mut series = vec![
        Series {
            name: "wetting saturation".into(),
            points: points(&|p| p.saturation),
            errors: None,
            markers: false,
            band: None,
        },
        Series {
            name: "of it joined to the outlet".into(),
            points: points(&|p| p.connected),
            errors: None,
            markers: false,
            band: None,
        },
    ];
    if let (Some(b), Some(s)) = (
        &d.summary.breakthrough,
        d.summary.saturation_at_breakthrough,
    ) {
        series.push(Series {
            name: format!("breakthrough, P_c·d32/γ = {:.2}", b.reduced),
            points: vec![(s, b.reduced)],
            errors: None,
            markers: true,
            band: None,
        });
    }
    Plot {
        title: "Primary drainage".into(),
        x_label: "wetting saturation".into(),
        y_label: "capillary pressure P_c·d32/γ".into(),
        data: PlotData::Lines { series },
        y_range: None,
        x_range: Some((0.0, 1.0)),
    }
}

/// The size distribution as sieve analyses draw it: mass % passing against
/// diameter on a log axis, requested and placed (the roof cuts the coarse
/// tail; fines that percolate down stay). `unit` names the length unit.
pub fn size_distribution(psd: &PsdSummary, unit: Option<&str>) -> Plot {
    let curve = |name: &str, pick: &dyn Fn(&crate::analysis::psd::PsdRow) -> Real| Series {
        name: name.to_string(),
        points: psd.table.iter().map(|r| (r.diameter, pick(r))).collect(),
        errors: None,
        markers: psd.table.len() <= 30,
        band: None,
    };
    let d50 = |d: Real| match unit {
        Some(u) => format!("d50 {} {u}", crate::math::display_length(d)),
        None => format!("d50 {}", crate::math::display_length(d)),
    };
    Plot {
        title: "Size distribution by mass".into(),
        x_label: format!("diameter ({})", unit.unwrap_or("length units")),
        y_label: "finer than the diameter (% by mass)".into(),
        data: PlotData::LogLines {
            series: vec![
                curve(&format!("requested ({})", d50(psd.requested.d50)), &|r| {
                    r.requested_mass_percent_passing
                }),
                curve(&format!("placed ({})", d50(psd.placed.d50)), &|r| {
                    r.placed_mass_percent_passing
                }),
            ],
        },
        y_range: Some((0.0, 100.0)),
        x_range: None,
    }
}

/// Regional packing bars: `(region name, value, standard deviation if any)`.
pub fn regional_packing(regions: &[(String, Real, Option<Real>)]) -> Plot {
    let errors = regions
        .iter()
        .all(|r| r.2.is_some())
        .then(|| regions.iter().map(|r| r.2.unwrap_or(0.0)).collect());
    Plot {
        title: "Packing fraction by region".into(),
        x_label: "region".into(),
        y_label: "packing fraction".into(),
        data: PlotData::Bars {
            categories: regions.iter().map(|r| r.0.clone()).collect(),
            groups: vec![BarGroup {
                name: "packing fraction".into(),
                values: regions.iter().map(|r| r.1).collect(),
                errors,
            }],
        },
        y_range: Some((0.0, 1.0)),
        x_range: None,
    }
}

/// Angle of each chain's axis from vertical, in degrees: signed in 2D (−90 lying
/// to the left, +90 to the right), polar 0–90 in 3D. Bodies of one bead have no
/// axis and are skipped. The axis runs from the body's first bead to its last.
pub fn chain_angles<const D: usize>(bed: &Bed<D>) -> Vec<Real> {
    let mut out = Vec::new();
    let mut k = 0;
    while k < bed.len() {
        let mut end = k + 1;
        while end < bed.len() && bed.bodies[end] == bed.bodies[k] {
            end += 1;
        }
        if end - k > 1 {
            let a = bed
                .container
                .displacement(&bed.centres[k], &bed.centres[end - 1]);
            // Orient upwards so that the sign means lean, not bead order.
            let a = if a.height() < 0.0 { -a } else { a };
            let vert = a.height();
            let horiz = if D == 2 {
                a[0]
            } else {
                (0..D - 1).map(|i| a[i] * a[i]).sum::<Real>().sqrt()
            };
            out.push(horiz.atan2(vert).to_degrees());
        }
        k = end;
    }
    out
}

/// Histogram of chain angles (from vertical, as `chain_angles` gives them)
/// in 5° bins of the `from` convention, as percentages of the chains.
pub fn chain_angle_histogram(angles: &[Real], dim: usize, from: AngleFrom) -> Plot {
    let (lo, hi) = from.range(dim);
    let bins = ((hi - lo) / 5.0) as usize;
    let mut h = vec![0.0; bins];
    for &a in angles {
        let a = from.convert(a);
        let k = (((a - lo) / 5.0).floor().max(0.0) as usize).min(bins - 1);
        h[k] += 100.0 / angles.len().max(1) as f64;
    }
    let points: Vec<(f64, f64)> = h
        .iter()
        .enumerate()
        .map(|(k, &v)| (lo + 5.0 * k as f64 + 2.5, v))
        .collect();
    chain_angle_plot(
        format!("Chain orientation ({} chains, 5° bins)", angles.len()),
        points,
        lo,
        5.0,
        dim,
        from,
    )
}

/// A chain-angle histogram (`points`: bin centre, % of chains; bins `width`
/// wide from `lo`, in the `from` convention for dimension `dim`) against the
/// shares random orientations would give.
pub fn chain_angle_plot(
    title: String,
    points: Vec<(Real, Real)>,
    lo: Real,
    width: Real,
    dim: usize,
    from: AngleFrom,
) -> Plot {
    let reference = isotropic_angles(lo, width, points.len(), dim, from);
    Plot {
        title,
        x_label: match (from, dim) {
            (AngleFrom::Vertical, 2) => {
                "angle from vertical (degrees, negative: leaning left)".into()
            }
            (AngleFrom::Vertical, _) => "polar angle from vertical (degrees)".into(),
            (AngleFrom::Horizontal, 2) => {
                "angle from horizontal (degrees, 0: lying right, 180: lying left)".into()
            }
            (AngleFrom::Horizontal, _) => "elevation angle from horizontal (degrees)".into(),
        },
        y_label: "chains (%)".into(),
        y_range: Some(angle_share_range(&points, &reference)),
        x_range: Some((lo, lo + width * points.len() as Real)),
        data: PlotData::Lines {
            series: vec![
                Series {
                    name: "chains".into(),
                    points,
                    errors: None,
                    markers: true,
                    band: None,
                },
                reference,
            ],
        },
    }
}

/// The share of chains per angle bin (%) if their axes pointed at random:
/// uniform in the plane (2D), `∝ sin θ` of the polar angle θ in space (3D;
/// `∝ cos` of the elevation from the horizontal), so that a 3D histogram
/// rising towards flat is read against the rise that isotropy alone gives.
pub fn isotropic_angles(lo: Real, width: Real, bins: usize, dim: usize, from: AngleFrom) -> Series {
    let (range_lo, range_hi) = from.range(dim);
    let points = (0..bins)
        .map(|k| {
            let a = lo + width * k as Real;
            let share = match (dim, from) {
                (2, _) => width / (range_hi - range_lo),
                (_, AngleFrom::Vertical) => a.to_radians().cos() - (a + width).to_radians().cos(),
                (_, AngleFrom::Horizontal) => (a + width).to_radians().sin() - a.to_radians().sin(),
            };
            (a + 0.5 * width, 100.0 * share)
        })
        .collect();
    Series {
        name: "random orientations".into(),
        points,
        errors: None,
        markers: false,
        band: None,
    }
}

/// A y range from 0 (a share is never negative) to a little above the data.
fn angle_share_range(points: &[(Real, Real)], reference: &Series) -> (Real, Real) {
    let top = points
        .iter()
        .chain(&reference.points)
        .fold(0.0, |m: Real, p| m.max(p.1));
    (0.0, if top > 0.0 { 1.1 * top } else { 1.0 })
}

/// The filtration curve as a laboratory plots it: t/V against V at constant
/// pressure (Δp against V at constant rate), the checkpoints and Ruth's
/// fitted line through them.
pub fn filtration_curve(f: &crate::analysis::filtration::FiltrationSummary) -> Plot {
    let pressure = f.drive == "pressure";
    let y = |c: &crate::analysis::filtration::Checkpoint| {
        if pressure {
            c.time_s / c.volume_m3_per_m2
        } else {
            c.pressure_pa
        }
    };
    let point = |c: &crate::analysis::filtration::Checkpoint| (c.volume_m3_per_m2, y(c));
    let drawn = |skip: usize| -> Vec<(Real, Real)> {
        f.checkpoints
            .iter()
            .skip(skip)
            .filter(|c| c.volume_m3_per_m2 > 0.0)
            .map(point)
            .collect()
    };
    let points = drawn(0);
    // Ruth's line through the points it was fitted to (past the medium's
    // surface: `filtration::filtration`).
    let fitted = drawn(1);
    let mut series = vec![Series {
        name: "the network's checkpoints".into(),
        points,
        errors: None,
        markers: true,
        band: None,
    }];
    if let (Some(first), Some(last), Some((slope, icpt)), Some(a), Some(r)) = (
        fitted.first(),
        fitted.last(),
        crate::analysis::filtration::line(&fitted),
        f.alpha_fit_m_per_kg,
        f.r_medium_fit_per_m,
    ) {
        series.push(Series {
            name: format!("Ruth's line: α {a:.3e} m/kg, R_m {r:.3e} 1/m"),
            points: vec![
                (first.0, slope * first.0 + icpt),
                (last.0, slope * last.0 + icpt),
            ],
            errors: None,
            markers: false,
            band: None,
        });
    }
    Plot {
        title: "Filtration curve".into(),
        x_label: "filtrate volume per area V (m³/m²)".into(),
        y_label: if pressure {
            "t / V (s/m)".into()
        } else {
            "pressure drop (Pa)".into()
        },
        data: PlotData::Lines { series },
        y_range: None,
        x_range: None,
    }
}

/// The grade-efficiency curve: the fraction captured (lodged or in the
/// cake) against size, on a log axis, with the cut size x50.
pub fn grade_efficiency(c: &crate::analysis::capture::CaptureSummary, unit: Option<&str>) -> Plot {
    let points: Vec<(Real, Real)> = c
        .classes
        .iter()
        .filter_map(|k| Some(((k.d_lo * k.d_hi).sqrt(), k.grade_efficiency?)))
        .collect();
    let name = match c.x50 {
        Some(x) => format!(
            "x50 {} {}",
            crate::math::display_length(x),
            unit.unwrap_or("")
        ),
        None => "no x50 within the sizes fed".into(),
    };
    let mut series = vec![Series {
        name: format!("captured: {}", name.trim()),
        points,
        errors: None,
        markers: true,
        band: None,
    }];
    // Beside it, what the particles meet: the fraction of the medium's
    // throats narrower than d, and of the slurry finer than d.
    let finer =
        |name: &str, f: &dyn Fn(&crate::analysis::capture::ConstrictionClass) -> Real| Series {
            name: name.into(),
            points: c.constrictions.iter().map(|k| (k.d_hi, f(k))).collect(),
            errors: None,
            markers: false,
            band: None,
        };
    if !c.constrictions.is_empty() {
        series.push(finer("medium's constrictions finer", &|k| {
            k.constrictions_finer
        }));
        series.push(finer("slurry finer (by number)", &|k| k.slurry_finer));
    }
    Plot {
        title: "Grade efficiency of the medium".into(),
        x_label: format!("diameter ({})", unit.unwrap_or("length units")),
        y_label: "captured (lodged or cake); fraction finer".into(),
        data: PlotData::LogLines { series },
        y_range: Some((0.0, 1.0)),
        x_range: None,
    }
}
