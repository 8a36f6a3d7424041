//! Plots of an ensemble and of a sweep, drawn from the statistics alone (the
//! [`Aggregate`]s), so that merged shards give the same files as one run.
//!
//! Per ensemble (or sweep value): packing fractions and mean coordination
//! numbers as bars with ± sd, the coordination-number histograms summed over
//! the beds (overall and per species, side by side), the mean packing profile
//! with ± sd, and for chains the summed orientation histogram. Per sweep: each
//! headline measure's mean ± sd against the parameter, and the percentage of
//! beds with a percolation chain.

use super::plot::{format_number, BarGroup, Plot, PlotData, Series};
use super::run_plots::{chain_angle_plot, length_label};
use crate::analysis::orientation::AngleFrom;
use crate::analysis::stats::{Aggregate, ArrayStats, Histogram, Stats};
use crate::config::{LengthUnit, SweepConfig, SweepValue};

/// Plots of one ensemble, as `(file stem, plot)`; only those whose measures
/// the beds have.
/// `dim` and `angle_from` say how the chain-angle histogram is to be read;
/// `unit` names the lengths' unit where the config gives one.
pub fn ensemble_plots(
    a: &Aggregate,
    dim: usize,
    angle_from: AngleFrom,
    unit: Option<LengthUnit>,
) -> Vec<(String, Plot)> {
    let beds = a.replicates;
    let mut out = Vec::new();
    if let Some(p) = packing_bars(a, beds) {
        out.push(("plot_packing".to_string(), p));
    }
    if let Some(p) = coordination_means(a, beds) {
        out.push(("plot_coordination_means".to_string(), p));
    }
    if let Some(p) = coordination_histograms(a, beds) {
        out.push(("plot_coordination".to_string(), p));
    }
    if let Some(p) = packing_profile(a, beds, unit) {
        out.push(("plot_profile".to_string(), p));
    }
    if let Some(p) = chain_angles(a, beds, dim, angle_from) {
        out.push(("plot_chain_angles".to_string(), p));
    }
    if let Some(p) = drainage_curve(a, beds) {
        out.push(("plot_drainage".to_string(), p));
    }
    out
}

/// The drainage curves of the beds at the fixed reduced pressures
/// (`drainage.curve`): the mean saturation, shaded between the lowest and
/// the highest bed's (a band, not error bars: 41 points of bars would hide
/// the curve; the sd per point is in `ensemble.csv`).
fn drainage_curve(a: &Aggregate, beds: u64) -> Option<Plot> {
    let pc = series(a, "drainage.curve.pc_reduced")?;
    let s = series(a, "drainage.curve.saturation")?;
    let rows: Vec<(&Stats, &Stats)> = pc
        .entries
        .iter()
        .zip(&s.entries)
        .filter(|(p, s)| p.n > 0 && s.n > 0 && p.mean > 0.0)
        .collect();
    if rows.is_empty() {
        return None;
    }
    Some(Plot {
        title: format!(
            "Primary drainage: mean over {}, shaded from the lowest to the highest bed",
            beds_text(beds)
        ),
        x_label: "capillary pressure P_c·d32/γ".into(),
        y_label: "wetting saturation".into(),
        data: PlotData::LogLines {
            series: vec![Series {
                name: "mean".into(),
                points: rows.iter().map(|(p, s)| (p.mean, s.mean)).collect(),
                errors: None,
                markers: false,
                band: Some(rows.iter().map(|(_, s)| (s.min, s.max)).collect()),
            }],
        },
        y_range: Some((0.0, 1.0)),
        x_range: None,
    })
}

fn measure<'a>(a: &'a Aggregate, name: &str) -> Option<&'a Stats> {
    a.measures
        .iter()
        .find(|m| m.name == name)
        .map(|m| &m.stats)
        .filter(|s| s.n > 0)
}

fn histogram<'a>(a: &'a Aggregate, name: &str) -> Option<&'a Histogram> {
    a.histograms
        .iter()
        .find(|h| h.name == name)
        .filter(|h| h.counts.iter().any(|&c| c > 0.0))
}

fn series<'a>(a: &'a Aggregate, name: &str) -> Option<&'a ArrayStats> {
    a.series.iter().find(|s| s.name == name)
}

/// Species names in the order their coordination measures appear.
fn species_names(a: &Aggregate) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for m in &a.measures {
        if let Some(rest) = m.name.strip_prefix("coordination.by_species.") {
            if let Some(name) = rest.strip_suffix(".mean") {
                if !names.iter().any(|n| n == name) {
                    names.push(name.to_string());
                }
            }
        }
    }
    names
}

fn beds_text(beds: u64) -> String {
    if beds == 1 {
        "1 bed".into()
    } else {
        format!("{beds} beds")
    }
}

/// Global, bulk and regional packing fractions.
fn packing_bars(a: &Aggregate, beds: u64) -> Option<Plot> {
    let rows: Vec<(&str, &Stats)> = [
        ("global", "packing.global"),
        ("bulk", "packing.bulk"),
        ("floor", "packing.regions.floor"),
        ("roof", "packing.regions.roof"),
        ("wall", "packing.regions.wall"),
        ("centre", "packing.regions.centre"),
    ]
    .into_iter()
    .filter_map(|(label, key)| measure(a, key).map(|s| (label, s)))
    .collect();
    if rows.is_empty() {
        return None;
    }
    Some(Plot {
        title: format!("Packing fraction: mean ± sd over {}", beds_text(beds)),
        x_label: "region of the bed".into(),
        y_label: "packing fraction".into(),
        // Dots on an axis that spans the data: regions differ by a few
        // hundredths, which bars on 0–1 drew as equal.
        data: PlotData::Dots {
            categories: rows.iter().map(|r| r.0.to_string()).collect(),
            groups: vec![BarGroup {
                name: "mean ± sd".into(),
                values: rows.iter().map(|r| r.1.mean).collect(),
                errors: Some(rows.iter().map(|r| r.1.sd).collect()),
            }],
        },
        y_range: None,
        x_range: None,
    })
}

/// Mean coordination number, whole bed and bulk, overall and per species.
fn coordination_means(a: &Aggregate, beds: u64) -> Option<Plot> {
    let names = species_names(a);
    let mut categories = vec!["all".to_string()];
    let mut keys = vec!["coordination".to_string()];
    // One species is the same as "all": no second bar.
    if names.len() > 1 {
        for n in &names {
            categories.push(n.clone());
            keys.push(format!("coordination.by_species.{n}"));
        }
    }
    let group = |suffix: &str, name: &str| -> Option<BarGroup> {
        let stats: Vec<Option<&Stats>> = keys
            .iter()
            .map(|k| measure(a, &format!("{k}.{suffix}")))
            .collect();
        stats.iter().any(Option::is_some).then(|| BarGroup {
            name: name.into(),
            values: stats.iter().map(|s| s.map_or(0.0, |s| s.mean)).collect(),
            errors: Some(stats.iter().map(|s| s.map_or(0.0, |s| s.sd)).collect()),
        })
    };
    let groups: Vec<BarGroup> = [group("mean", "whole bed"), group("mean_bulk", "bulk")]
        .into_iter()
        .flatten()
        .collect();
    if groups.is_empty() {
        return None;
    }
    Some(Plot {
        title: format!(
            "Mean coordination number: mean ± sd over {}",
            beds_text(beds)
        ),
        x_label: "particles".into(),
        y_label: "contacts per particle".into(),
        data: PlotData::Bars { categories, groups },
        y_range: None,
        x_range: None,
    })
}

/// Coordination-number histograms summed over the beds, as % of particles.
fn coordination_histograms(a: &Aggregate, beds: u64) -> Option<Plot> {
    let names = species_names(a);
    let mut hists: Vec<(String, &Histogram)> = Vec::new();
    if let Some(h) = histogram(a, "coordination.histogram") {
        hists.push(("all particles".into(), h));
    }
    if names.len() > 1 {
        for n in &names {
            if let Some(h) = histogram(a, &format!("coordination.by_species.{n}.histogram")) {
                hists.push((n.clone(), h));
            }
        }
    }
    if hists.is_empty() {
        return None;
    }
    // Up to the highest bin that any histogram uses.
    let bins = hists
        .iter()
        .filter_map(|(_, h)| h.counts.iter().rposition(|&c| c > 0.0))
        .max()
        .map_or(1, |k| k + 1);
    Some(Plot {
        title: format!("Coordination numbers, summed over {}", beds_text(beds)),
        x_label: "coordination number (contacts with other particles)".into(),
        y_label: "particles (%)".into(),
        data: PlotData::Bars {
            categories: (0..bins).map(|k| k.to_string()).collect(),
            groups: hists
                .into_iter()
                .map(|(name, h)| BarGroup {
                    name,
                    values: (0..bins)
                        .map(|k| 100.0 * h.fraction.get(k).copied().unwrap_or(0.0))
                        .collect(),
                    errors: None,
                })
                .collect(),
        },
        y_range: None,
        x_range: None,
    })
}

/// Mean packing fraction per slab against the slab's mid-height, ± sd.
fn packing_profile(a: &Aggregate, beds: u64, unit: Option<LengthUnit>) -> Option<Plot> {
    let z = series(a, "packing.profile.z")?;
    let phi = series(a, "packing.profile.fraction")?;
    let points: Vec<(f64, f64, f64)> = z
        .entries
        .iter()
        .zip(&phi.entries)
        .filter(|(z, p)| z.n > 0 && p.n > 0)
        .map(|(z, p)| (z.mean, p.mean, p.sd))
        .collect();
    if points.is_empty() {
        return None;
    }
    let slab = measure(a, "packing.profile.slab").map_or(0.0, |s| s.mean);
    let top = points.last().map_or(0.0, |p| p.0 + 0.5 * slab);
    Some(Plot {
        title: format!(
            "Packing fraction profile: mean ± sd over {} (slabs {} {} thick)",
            beds_text(beds),
            format_number(slab),
            length_label(unit)
        ),
        x_label: format!("height above the floor ({})", length_label(unit)),
        y_label: "packing fraction".into(),
        data: PlotData::Lines {
            series: vec![Series {
                name: "mean ± sd".into(),
                points: points.iter().map(|p| (p.0, p.1)).collect(),
                errors: Some(points.iter().map(|p| p.2).collect()),
                markers: false,
                band: None,
            }],
        },
        y_range: Some((0.0, 1.0)),
        x_range: Some((0.0, top.max(slab))),
    })
}

/// The chain-axis angle histogram summed over the beds.
fn chain_angles(a: &Aggregate, beds: u64, dim: usize, from: AngleFrom) -> Option<Plot> {
    let h = histogram(a, "orientation.histogram.counts")?;
    let lo = measure(a, "orientation.histogram.lo")?.mean;
    let width = measure(a, "orientation.histogram.bin_width")?.mean;
    let chains = h.counts.iter().sum::<f64>();
    let s = measure(a, "orientation.order_parameter");
    let order = s.map_or(String::new(), |s| {
        format!("; S = {} ± {}", format_number(s.mean), format_number(s.sd))
    });
    let points: Vec<(f64, f64)> = h
        .fraction
        .iter()
        .enumerate()
        .map(|(k, &f)| (lo + width * (k as f64 + 0.5), 100.0 * f))
        .collect();
    Some(chain_angle_plot(
        format!(
            "Chain orientation: {} chains in {}{order}",
            format_number(chains),
            beds_text(beds)
        ),
        points,
        lo,
        width,
        dim,
        from,
    ))
}

/// Measures drawn against the sweep parameter, with their plot file stems.
const SWEEP_MEASURES: [(&str, &str, &str); 14] = [
    ("cake.porosity", "plot_sweep_porosity", "porosity (bulk)"),
    (
        "permeability.k_z",
        "plot_sweep_permeability",
        "network permeability k along z",
    ),
    (
        "packing.global",
        "plot_sweep_packing_global",
        "packing fraction (global)",
    ),
    (
        "packing.bulk",
        "plot_sweep_packing_bulk",
        "packing fraction (bulk)",
    ),
    (
        "coordination.mean",
        "plot_sweep_coordination",
        "mean coordination number",
    ),
    (
        "coordination.mean_bulk",
        "plot_sweep_coordination_bulk",
        "mean coordination number (bulk)",
    ),
    (
        "drainage.residual_saturation",
        "plot_sweep_residual_saturation",
        "residual saturation after deliquoring",
    ),
    (
        "agglomeration.bonds_per_particle",
        "plot_sweep_bonds",
        "solid-bridge bonds per particle",
    ),
    (
        "agglomeration.agglomerates",
        "plot_sweep_agglomerates",
        "agglomerates",
    ),
    (
        "agglomeration.fraction_in_agglomerates",
        "plot_sweep_fraction_agglomerated",
        "volume fraction of particles in agglomerates",
    ),
    (
        "agglomeration.d50_product",
        "plot_sweep_d50_product",
        "median size of the dried product (length units)",
    ),
    (
        "filtration.alpha_fit_m_per_kg",
        "plot_sweep_alpha",
        "specific cake resistance α fitted to Ruth's line (m/kg)",
    ),
    (
        "filtration.r_medium_fit_per_m",
        "plot_sweep_medium_resistance",
        "medium resistance R_m fitted to Ruth's line (1/m)",
    ),
    (
        "filtration.final.time_s",
        "plot_sweep_filtration_time",
        "filtration time to the end of the curve (s)",
    ),
];

/// Plots of a sweep: each headline measure's mean ± sd against the parameter,
/// and the percentage of beds with a percolation chain (overall and per
/// direction). `points` are the sweep values' labels and statistics, in the
/// order of `sweep.values`.
pub fn sweep_plots(sweep: &SweepConfig, points: &[(&str, &Aggregate)]) -> Vec<(String, Plot)> {
    let Some(first) = points.first() else {
        return Vec::new();
    };
    // A line against the value when every value is one number; bars per label
    // otherwise (e.g. ratios `1:2`).
    let xs: Option<Vec<f64>> = sweep
        .values
        .iter()
        .map(|v| match v {
            SweepValue::Number(x) => Some(*x),
            SweepValue::List(_) | SweepValue::Text(_) | SweepValue::Flag(_) => None,
        })
        .collect::<Option<Vec<f64>>>()
        .filter(|xs| xs.len() == points.len());
    let labels: Vec<String> = points.iter().map(|p| p.0.to_string()).collect();
    let parameter = sweep.parameter.as_str();
    let mut out = Vec::new();
    for (key, stem, what) in SWEEP_MEASURES {
        if measure(first.1, key).is_none() {
            continue;
        }
        let stats: Vec<Option<&Stats>> = points.iter().map(|p| measure(p.1, key)).collect();
        let curve = Curve {
            name: "mean ± sd".into(),
            values: stats.iter().map(|s| s.map(|s| s.mean)).collect(),
            errors: Some(stats.iter().map(|s| s.map_or(0.0, |s| s.sd)).collect()),
        };
        out.push((
            stem.to_string(),
            against(
                format!("{}: mean ± sd per {parameter}", capitalised(what)),
                parameter,
                what,
                xs.as_deref(),
                &labels,
                vec![curve],
                None,
            ),
        ));
    }
    if measure(first.1, "percolation.spans").is_some() {
        let mut keys = vec![("any direction".to_string(), "percolation.spans".to_string())];
        let axes = ["x", "y"];
        let directions = (0..2)
            .filter(|k| measure(first.1, &format!("percolation.directions[{k}].spans")).is_some())
            .count();
        if directions > 1 {
            for (k, axis) in axes.iter().enumerate().take(directions) {
                keys.push((
                    format!("along {axis}"),
                    format!("percolation.directions[{k}].spans"),
                ));
            }
        }
        let curves = keys
            .iter()
            .map(|(name, key)| Curve {
                name: name.clone(),
                values: points
                    .iter()
                    .map(|p| measure(p.1, key).map(|s| s.mean))
                    .collect(),
                errors: None,
            })
            .collect();
        out.push((
            "plot_sweep_percolation".to_string(),
            against(
                format!("Beds with a percolation chain, per {parameter}"),
                parameter,
                "beds with a chain (%)",
                xs.as_deref(),
                &labels,
                curves,
                Some((0.0, 100.0)),
            ),
        ));
    }
    out
}

fn capitalised(text: &str) -> String {
    let mut c = text.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// The x-axis label of a swept parameter, with its unit.
fn parameter_label(parameter: &str) -> String {
    let what = match parameter {
        "ratio" => "number ratio of the species",
        "radii" => "radii of the species (length units)",
        "box.diameters" => "box width (largest particle diameters)",
        "box.size" => "box size (length units)",
        "fill.count" => "particles placed",
        "fill.roof_misses" => "overflows allowed at the roof",
        "analysis.large_radius" => "radius of a large particle (length units)",
        "analysis.drying.concentration" => "dissolved solid (kg/m³)",
        "analysis.drying.solubility" => "solubility (kg/m³)",
        "analysis.drying.min_neck" => "smallest bond neck (harmonic mean radius)",
        "analysis.drying.tensile_strength" => "tensile strength of the solid (Pa)",
        "analysis.drying.agitation.stress" => "agitation stress (Pa)",
        "analysis.drainage.pressure" => "deliquoring capillary pressure (Pa)",
        "analysis.drainage.reduced_pressure" => "deliquoring pressure P_c·d32/γ",
        p if p.ends_with(".radius") => "radius (length units)",
        p if p.ends_with(".ratio") => "number ratio",
        _ => return parameter.to_string(),
    };
    format!("{parameter}: {what}")
}

/// One quantity per sweep value (`None`: not measured there).
struct Curve {
    name: String,
    values: Vec<Option<f64>>,
    errors: Option<Vec<f64>>,
}

/// Lines over a logarithmic axis or a linear one.
fn lines(log: bool, series: Vec<Series>) -> PlotData {
    if log {
        PlotData::LogLines { series }
    } else {
        PlotData::Lines { series }
    }
}

/// Curves against the sweep values: lines over numeric values, grouped bars
/// over labels.
fn against(
    title: String,
    parameter: &str,
    y_label: &str,
    xs: Option<&[f64]>,
    labels: &[String],
    curves: Vec<Curve>,
    y_range: Option<(f64, f64)>,
) -> Plot {
    // Values spanning two decades or more (a washing's dilutions) are
    // spread on a logarithmic axis.
    let decades = xs.is_some_and(|xs| {
        let (lo, hi) = xs
            .iter()
            .fold((f64::INFINITY, 0f64), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        lo > 0.0 && hi >= 100.0 * lo
    });
    let data = match xs {
        Some(xs) => lines(
            decades,
            curves
                .into_iter()
                .map(|c| {
                    let kept: Vec<usize> =
                        (0..xs.len()).filter(|&i| c.values[i].is_some()).collect();
                    Series {
                        name: c.name,
                        points: kept
                            .iter()
                            .map(|&i| (xs[i], c.values[i].unwrap_or(0.0)))
                            .collect(),
                        errors: c.errors.map(|e| kept.iter().map(|&i| e[i]).collect()),
                        markers: true,
                        band: None,
                    }
                })
                .collect(),
        ),
        None => PlotData::Bars {
            categories: labels.to_vec(),
            groups: curves
                .into_iter()
                .map(|c| BarGroup {
                    name: c.name,
                    values: c.values.iter().map(|v| v.unwrap_or(0.0)).collect(),
                    errors: c.errors,
                })
                .collect(),
        },
    };
    Plot {
        title,
        x_label: parameter_label(parameter),
        y_label: y_label.into(),
        data,
        y_range,
        x_range: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::stats::{Kind, MeasureStats};
    use crate::render::run_plots::isotropic_angles;

    fn stats(mean: f64, sd: f64) -> Stats {
        Stats {
            n: 4,
            mean,
            sd,
            min: mean - sd,
            max: mean + sd,
        }
    }

    fn aggregate(measures: &[(&str, f64, f64)]) -> Aggregate {
        Aggregate {
            replicates: 4,
            measures: measures
                .iter()
                .map(|&(name, mean, sd)| MeasureStats {
                    name: name.into(),
                    kind: Kind::Value,
                    stats: stats(mean, sd),
                })
                .collect(),
            ..Aggregate::default()
        }
    }

    #[test]
    fn the_drainage_curve_is_the_mean_with_a_band_from_the_lowest_to_the_highest_bed() {
        let entry = |mean: f64, min: f64, max: f64| Stats {
            n: 3,
            mean,
            sd: 0.1,
            min,
            max,
        };
        let mut a = aggregate(&[]);
        a.replicates = 3;
        a.series = vec![
            ArrayStats {
                name: "drainage.curve.pc_reduced".into(),
                entries: vec![entry(1.0, 1.0, 1.0), entry(10.0, 10.0, 10.0)],
            },
            ArrayStats {
                name: "drainage.curve.saturation".into(),
                entries: vec![entry(1.0, 1.0, 1.0), entry(0.3, 0.2, 0.45)],
            },
        ];
        let plots = ensemble_plots(&a, 3, AngleFrom::Horizontal, None);
        let (_, p) = plots
            .iter()
            .find(|(stem, _)| stem == "plot_drainage")
            .expect("a drainage plot");
        let PlotData::LogLines { series } = &p.data else {
            panic!("{:?}", p.data)
        };
        assert_eq!(series[0].points, vec![(1.0, 1.0), (10.0, 0.3)]);
        assert_eq!(series[0].band, Some(vec![(1.0, 1.0), (0.2, 0.45)]));
        assert!(p.to_svg(800, 500).unwrap().contains("<polygon"));
        // Without the curve, no plot.
        a.series.clear();
        let plots = ensemble_plots(&a, 3, AngleFrom::Horizontal, None);
        assert!(plots.iter().all(|(stem, _)| stem != "plot_drainage"));
    }

    #[test]
    fn packing_bars_follow_the_measures_present() {
        let a = aggregate(&[
            ("packing.global", 0.55, 0.01),
            ("packing.regions.wall", 0.5, 0.02),
        ]);
        let plots = ensemble_plots(&a, 3, AngleFrom::Vertical, None);
        let (_, p) = plots.iter().find(|p| p.0 == "plot_packing").unwrap();
        let PlotData::Dots { categories, groups } = &p.data else {
            panic!("dots expected");
        };
        assert_eq!(categories, &["global", "wall"]);
        assert_eq!(groups[0].values, vec![0.55, 0.5]);
        assert_eq!(groups[0].errors, Some(vec![0.01, 0.02]));
        assert!(p.title.contains("4 beds"));
    }

    #[test]
    fn packing_axis_spans_the_differences_not_zero_to_one() {
        // Regions 0.55 ± 0.01 and 0.60 ± 0.02: the axis must show them apart.
        let a = aggregate(&[
            ("packing.global", 0.55, 0.01),
            ("packing.regions.centre", 0.6, 0.02),
        ]);
        let plots = ensemble_plots(&a, 3, AngleFrom::Vertical, None);
        let (_, p) = plots.iter().find(|p| p.0 == "plot_packing").unwrap();
        let (_, (lo, hi)) = p.ranges();
        assert!(lo <= 0.54 && hi >= 0.62, "{lo}–{hi} hides data");
        // The data fill at least half the axis (0.54–0.62 of at most 0.16).
        assert!(hi - lo <= 0.16, "{lo}–{hi}");
        assert!(lo > 0.3 && hi < 0.8, "{lo}–{hi}");
    }

    #[test]
    fn profile_axis_names_the_length_unit() {
        let mut a = aggregate(&[("packing.profile.slab", 10.0, 0.0)]);
        let entry = |mean| Stats {
            n: 4,
            mean,
            sd: 0.0,
            min: mean,
            max: mean,
        };
        a.series = vec![
            ArrayStats {
                name: "packing.profile.z".into(),
                entries: vec![entry(5.0), entry(15.0)],
            },
            ArrayStats {
                name: "packing.profile.fraction".into(),
                entries: vec![entry(0.5), entry(0.6)],
            },
        ];
        let plots = ensemble_plots(&a, 3, AngleFrom::Vertical, Some(LengthUnit::Micrometre));
        let (_, p) = plots.iter().find(|p| p.0 == "plot_profile").unwrap();
        assert_eq!(p.x_label, "height above the floor (µm)");
        assert!(p.title.contains("slabs 10 µm thick"), "{}", p.title);
        let plots = ensemble_plots(&a, 3, AngleFrom::Vertical, None);
        let (_, p) = plots.iter().find(|p| p.0 == "plot_profile").unwrap();
        assert_eq!(p.x_label, "height above the floor (length units)");
    }

    #[test]
    fn coordination_means_per_species_side_by_side() {
        let a = aggregate(&[
            ("coordination.mean", 4.0, 0.1),
            ("coordination.mean_bulk", 4.5, 0.2),
            ("coordination.by_species.large.mean", 6.0, 0.3),
            ("coordination.by_species.small.mean", 3.0, 0.4),
        ]);
        let plots = ensemble_plots(&a, 3, AngleFrom::Vertical, None);
        let (_, p) = plots
            .iter()
            .find(|p| p.0 == "plot_coordination_means")
            .unwrap();
        let PlotData::Bars { categories, groups } = &p.data else {
            panic!("bars expected");
        };
        assert_eq!(categories, &["all", "large", "small"]);
        assert_eq!(groups[0].values, vec![4.0, 6.0, 3.0]);
        // Bulk is known for "all" only; species bars are 0 there.
        assert_eq!(groups[1].values, vec![4.5, 0.0, 0.0]);
    }

    #[test]
    fn random_orientation_reference_sums_to_all_chains() {
        for (lo, bins, dim, from) in [
            (0.0, 18, 3, AngleFrom::Vertical),
            (-90.0, 36, 2, AngleFrom::Vertical),
            (0.0, 18, 3, AngleFrom::Horizontal),
            (0.0, 36, 2, AngleFrom::Horizontal),
        ] {
            let r = isotropic_angles(lo, 5.0, bins, dim, from);
            let total: f64 = r.points.iter().map(|p| p.1).sum();
            assert!((total - 100.0).abs() < 1e-9, "{lo}: {total}");
        }
        // In space, near-horizontal axes are the likeliest by far.
        let r = isotropic_angles(0.0, 5.0, 18, 3, AngleFrom::Vertical);
        assert!(r.points[17].1 > 10.0 * r.points[0].1);
        let h = isotropic_angles(0.0, 5.0, 18, 3, AngleFrom::Horizontal);
        assert!((h.points[0].1 - r.points[17].1).abs() < 1e-12);
    }

    #[test]
    fn numeric_sweeps_are_lines_and_ratios_are_bars() {
        let a = aggregate(&[("packing.global", 0.6, 0.01)]);
        let b = aggregate(&[("packing.global", 0.62, 0.02)]);
        let mut sw = SweepConfig {
            parameter: "box.diameters".into(),
            values: vec![SweepValue::Number(6.0), SweepValue::Number(24.0)],
            labels: None,
        };
        let plots = sweep_plots(&sw, &[("6", &a), ("24", &b)]);
        let (_, p) = plots
            .iter()
            .find(|p| p.0 == "plot_sweep_packing_global")
            .unwrap();
        let PlotData::Lines { series } = &p.data else {
            panic!("lines expected");
        };
        assert_eq!(series[0].points, vec![(6.0, 0.6), (24.0, 0.62)]);
        assert_eq!(series[0].errors, Some(vec![0.01, 0.02]));
        sw.values = vec![
            SweepValue::List(vec![1.0, 1.0]),
            SweepValue::List(vec![1.0, 2.0]),
        ];
        let plots = sweep_plots(&sw, &[("1:1", &a), ("1:2", &b)]);
        let PlotData::Bars { categories, .. } = &plots[0].1.data else {
            panic!("bars expected");
        };
        assert_eq!(categories, &["1:1", "1:2"]);
    }

    #[test]
    fn a_drying_sweep_plots_the_agglomeration_against_the_concentration() {
        let keys = [
            "agglomeration.bonds_per_particle",
            "agglomeration.agglomerates",
            "agglomeration.fraction_in_agglomerates",
            "agglomeration.d50_product",
            "drainage.residual_saturation",
        ];
        let a = aggregate(&keys.map(|k| (k, 1.0, 0.1)));
        let b = aggregate(&keys.map(|k| (k, 0.5, 0.1)));
        let sw = SweepConfig {
            parameter: "analysis.drying.concentration".into(),
            values: vec![SweepValue::Number(50.0), SweepValue::Number(5.0)],
            labels: None,
        };
        let plots = sweep_plots(&sw, &[("50", &a), ("5", &b)]);
        let stems: Vec<&str> = plots.iter().map(|p| p.0.as_str()).collect();
        assert_eq!(
            stems,
            [
                "plot_sweep_residual_saturation",
                "plot_sweep_bonds",
                "plot_sweep_agglomerates",
                "plot_sweep_fraction_agglomerated",
                "plot_sweep_d50_product",
            ]
        );
        let p = &plots[2].1;
        assert_eq!(
            p.x_label,
            "analysis.drying.concentration: dissolved solid (kg/m³)"
        );
        let PlotData::Lines { series } = &p.data else {
            panic!("lines expected");
        };
        assert_eq!(series[0].points, vec![(50.0, 1.0), (5.0, 0.5)]);
        // Dilutions over decades: a logarithmic axis.
        let sw = SweepConfig {
            values: vec![SweepValue::Number(50.0), SweepValue::Number(0.5)],
            ..sw
        };
        let plots = sweep_plots(&sw, &[("50", &a), ("0.5", &b)]);
        assert!(matches!(plots[2].1.data, PlotData::LogLines { .. }));
    }
}
