//! `packbed compare`: beds side by side. Each directory is a run, an ensemble
//! or a sweep (each of its values a group); the measures the groups share are
//! tabled with mean ± sd, and every group after the first is set against the
//! first by Welch's t-test: is the difference larger than the replicate
//! scatter would make by chance? For a positive measure the groups are also
//! set against the first as a ratio of means with its 95 % confidence
//! interval ([`Ratio`]).
//!
//! Groups whose beds name different length units (`[analysis] length_unit`)
//! are compared in the first group's unit: every measure is converted by the
//! power of the length in it ([`crate::analysis::dimensions::length_power`]);
//! a measure of unknown dimension is left out rather than compared across
//! units. A group that names no unit cannot be set against one that does.

use super::stats::{measures_of, Kind, MeasureStats, Stats};
use crate::analysis::dimensions::{filtration_unit, length_power};
use crate::config::LengthUnit;
use crate::error::markdown_cell;
use crate::error::{echo, Error, Result};
use serde::Serialize;
use serde_json::Value;
use statrs::distribution::{ContinuousCDF, StudentsT};
use std::path::{Path, PathBuf};

/// The significance level of the "beyond the scatter" verdict.
pub const ALPHA: f64 = 0.05;

/// The measures a filtration study reads first, in this order when present;
/// the rest follow in the order of `summary.json`.
pub const HEADLINE: [&str; 38] = [
    "cake.porosity",
    "cake.d32",
    "cake.specific_surface",
    "cake.k_kozeny_carman",
    "cake.k_kozeny_carman_m2",
    "permeability.k_z",
    "permeability.k_x",
    "permeability.k_y",
    "cake.specific_resistance",
    "cake.height",
    "cake.solids_per_area",
    "cake.solids_mass_per_area",
    "packing.bulk",
    "coordination.mean_bulk",
    "pores.d_c35",
    "drainage.breakthrough.reduced",
    "drainage.breakthrough.pa",
    "drainage.residual_saturation",
    "agglomeration.bonds_per_particle",
    "agglomeration.agglomerates",
    "agglomeration.fraction_in_agglomerates",
    "agglomeration.d50_product",
    "agglomeration.agitation.fraction_in_agglomerates",
    "agglomeration.agitation.d50_product",
    "psd.placed.d50",
    // A filtration's (units from `dimensions::filtration_unit`).
    "filtration.alpha_fit_m_per_kg",
    "filtration.alpha_network_m_per_kg",
    "filtration.r_medium_fit_per_m",
    "filtration.r_medium_clogged_per_m",
    "filtration.r_medium_per_m",
    "filtration.ruth_departure",
    "filtration.final.time_s",
    "filtration.final.volume_m3_per_m2",
    "filtration.final.cake_height_m",
    "capture.passed_fraction",
    "capture.lodged_fraction",
    "capture.cake_fraction",
    "capture.x50",
];

/// Beds of one directory (or one value of a sweep).
#[derive(Clone, Debug)]
pub struct Group {
    /// Name in the tables: the directory's name, or the sweep value's.
    pub name: String,
    /// Where its summaries were read.
    pub dir: PathBuf,
    /// Its beds' summaries, in replicate order.
    pub summaries: Vec<Value>,
}

/// Welch's test of one group against the first.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Welch {
    /// Mean of this group minus mean of the first.
    pub difference: f64,
    /// The difference relative to the first group's mean (`null` for a mean of 0).
    pub relative: Option<f64>,
    /// `t` statistic (`null` without scatter or with fewer than 2 beds in a group).
    pub t: Option<f64>,
    /// Welch–Satterthwaite degrees of freedom.
    pub df: Option<f64>,
    /// Two-sided p-value.
    pub p: Option<f64>,
    /// `p < 0.05`: the difference is larger than the replicate scatter explains.
    pub beyond_scatter: Option<bool>,
}

impl Welch {
    /// The test of `b` against `a`.
    pub fn of(a: &Stats, b: &Stats) -> Welch {
        let difference = b.mean - a.mean;
        let relative = (a.mean != 0.0).then(|| difference / a.mean.abs());
        let none = Welch {
            difference,
            relative,
            t: None,
            df: None,
            p: None,
            beyond_scatter: None,
        };
        if a.n < 2 || b.n < 2 {
            return none;
        }
        let (va, vb) = (a.sd * a.sd / a.n as f64, b.sd * b.sd / b.n as f64);
        let se2 = va + vb;
        if se2 <= 0.0 {
            // No scatter in either group: equal means are the same, different
            // ones differ beyond any scatter.
            return Welch {
                p: Some(if difference == 0.0 { 1.0 } else { 0.0 }),
                beyond_scatter: Some(difference != 0.0),
                ..none
            };
        }
        let t = difference / se2.sqrt();
        let df = se2 * se2 / (va * va / (a.n - 1) as f64 + vb * vb / (b.n - 1) as f64);
        let p = StudentsT::new(0.0, 1.0, df)
            .map(|d| 2.0 * d.sf(t.abs()))
            .ok()
            .filter(|p| p.is_finite())
            .map(|p| p.clamp(0.0, 1.0));
        Welch {
            t: Some(t),
            df: Some(df),
            p,
            beyond_scatter: p.map(|p| p < ALPHA),
            ..none
        }
    }
}

/// The confidence level of [`Ratio`]'s interval.
pub const CONFIDENCE: f64 = 0.95;

/// The ratio of a group's mean to the first group's, `b / a`, of a measure
/// that is positive in every bed of both, with its 95 % confidence interval
/// by the delta method on the logarithm of the means: the variance of
/// `ln(mean)` is `(sd / mean)² / n` per group, `ln(b / a)` has their sum
/// `se²` as variance, with Welch–Satterthwaite's degrees of freedom
/// `df = se⁴ / Σ (cv²/n)² / (n − 1)`, and the interval is
/// `b / a × exp(± t(0.975, df) × se)`. Without a second bed in either group
/// there is no interval (`ci` is `None`); with no scatter in either it is
/// the ratio itself.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Ratio {
    /// Mean of this group over the mean of the first.
    pub ratio: f64,
    /// The 95 % confidence interval of the ratio, `[low, high]`.
    pub ci: Option<[f64; 2]>,
    /// The degrees of freedom of the interval.
    pub df: Option<f64>,
}

impl Ratio {
    /// The ratio of `b` to `a`; `None` unless every value of both is positive.
    pub fn of(a: &Stats, b: &Stats) -> Option<Ratio> {
        let positive = |s: &Stats| s.n > 0 && s.min > 0.0 && s.mean > 0.0;
        if !positive(a) || !positive(b) {
            return None;
        }
        let ratio = b.mean / a.mean;
        if !ratio.is_finite() || ratio <= 0.0 {
            return None;
        }
        let none = Ratio {
            ratio,
            ci: None,
            df: None,
        };
        if a.n < 2 || b.n < 2 {
            return Some(none);
        }
        let var = |s: &Stats| (s.sd / s.mean).powi(2) / s.n as f64;
        let (va, vb) = (var(a), var(b));
        let se2 = va + vb;
        if !se2.is_finite() {
            return Some(none);
        }
        if se2 <= 0.0 {
            return Some(Ratio {
                ci: Some([ratio, ratio]),
                ..none
            });
        }
        let df = se2 * se2 / (va * va / (a.n - 1) as f64 + vb * vb / (b.n - 1) as f64);
        let t = StudentsT::new(0.0, 1.0, df)
            .ok()
            .map(|d| d.inverse_cdf(0.5 + CONFIDENCE / 2.0))
            .filter(|t| t.is_finite());
        let Some(t) = t else {
            return Some(none);
        };
        let half = t * se2.sqrt();
        let ci = [ratio * (-half).exp(), ratio * half.exp()];
        Some(Ratio {
            ci: ci.iter().all(|x| x.is_finite()).then_some(ci),
            df: Some(df),
            ..none
        })
    }

    /// "56.2× less (95 % CI 51.0–61.9×)", "2.50× more (…)", "1.00× (…)".
    pub fn text(&self) -> String {
        let (factor, word) = self.factor();
        format!("{factor}{word} ({})", self.interval())
    }

    /// The factor, at least 1, and " less" (ratio below 1), " more" or "".
    fn factor(&self) -> (String, &'static str) {
        let word = match self.ratio {
            r if r < 1.0 => " less",
            r if r > 1.0 => " more",
            _ => "",
        };
        (format!("{}×", times(self.up(self.ratio))), word)
    }

    /// "95 % CI 51.0–61.9×", the bounds of the factor, or why there is none.
    fn interval(&self) -> String {
        match self.ci {
            Some([lo, hi]) => {
                let (a, b) = if self.ratio < 1.0 {
                    (self.up(hi), self.up(lo))
                } else {
                    (lo, hi)
                };
                format!("95 % CI {}–{}×", times(a), times(b))
            }
            None => "no CI: one bed".into(),
        }
    }

    /// A ratio as the factor `text` shows: `1 / r` when the ratio is below 1.
    fn up(&self, r: f64) -> f64 {
        if self.ratio < 1.0 {
            1.0 / r
        } else {
            r
        }
    }
}

/// A factor with three significant digits (four near 1, where a factor of
/// 1.002 would read as none).
fn times(x: f64) -> String {
    if (1e-3..1e5).contains(&x.abs()) {
        let near_one = usize::from((0.9..1.1).contains(&x.abs()));
        let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize + near_one;
        format!("{x:.digits$}")
    } else {
        format!("{x:.2e}")
    }
}

/// One measure across the groups.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Dotted key of `summary.json`.
    pub name: String,
    /// Number or percentage of beds.
    pub kind: Kind,
    /// Statistics per group, in the groups' order.
    pub stats: Vec<Stats>,
    /// Each group after the first against the first.
    pub tests: Vec<Welch>,
    /// Each group after the first over the first, for a positive measure.
    pub ratios: Vec<Option<Ratio>>,
    /// The power of the length unit in the measure (`None`: not known).
    pub length_power: Option<i32>,
}

/// The comparison of groups.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// Group names and their bed counts.
    pub groups: Vec<(String, u64)>,
    /// The shared measures that vary, headline first.
    pub rows: Vec<Row>,
    /// Measures of some groups only, left out of the table.
    pub not_shared: Vec<String>,
    /// Measures of unknown dimension left out because the groups' length
    /// units differ.
    pub not_converted: Vec<String>,
    /// The unit every length is in: the first group's (`None`: no group
    /// names one).
    pub length_unit: Option<LengthUnit>,
    /// Per group, the length of its unit in the common unit (1 for a group
    /// in it): its lengths were multiplied by this.
    pub length_factors: Vec<f64>,
    /// Which groups' lengths were converted to the common unit, and from what.
    pub unit_note: Option<String>,
    /// What a reader must be warned of: 2D beds against 3D ones, beds of
    /// different packbed versions, measures left out for their unit.
    pub warnings: Vec<String>,
}

/// Reads the beds of each directory: a run (`summary.json`), an ensemble
/// (`runs/NNNN/summary.json`) or a sweep (`sweep/NN-label/runs/...`, one group
/// per value).
pub fn read_groups(dirs: &[PathBuf]) -> Result<Vec<Group>> {
    let mut groups = Vec::new();
    for dir in dirs {
        // Names are shown on the terminal, in Markdown and in SVG: control
        // characters of a directory's name are escaped once, here.
        let name = echo(&dir.file_name().map_or_else(
            || dir.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        ));
        let sweep = dir.join("sweep");
        if sweep.is_dir() {
            for point in sorted_dirs(&sweep)? {
                let label = echo(
                    &point
                        .file_name()
                        .map_or(String::new(), |n| n.to_string_lossy().into_owned()),
                );
                groups.push(Group {
                    name: format!("{name}/{label}"),
                    summaries: replicates(&point)?,
                    dir: point,
                });
            }
        } else if dir.join("runs").is_dir() {
            groups.push(Group {
                name,
                summaries: replicates(dir)?,
                dir: dir.clone(),
            });
        } else if dir.join("summary.json").is_file() {
            groups.push(Group {
                name,
                summaries: vec![read_json(&dir.join("summary.json"))?],
                dir: dir.clone(),
            });
        } else {
            return Err(Error::Impossible(format!(
                "{}: not a run (summary.json), an ensemble (runs/) or a sweep (sweep/) of packbed",
                dir.display()
            )));
        }
    }
    if groups.len() < 2 {
        return Err(Error::Impossible(format!(
            "compare needs at least two groups of beds; {} gave {}",
            dirs.iter()
                .map(|d| d.display().to_string())
                .collect::<Vec<_>>()
                .join(", "),
            groups.len()
        )));
    }
    // Equal names would make the table ambiguous: number them.
    for i in 0..groups.len() {
        let n = groups[i].name.clone();
        if groups.iter().filter(|g| g.name == n).count() > 1 {
            groups[i].name = format!("{n} ({})", i + 1);
        }
    }
    Ok(groups)
}

fn sorted_dirs(dir: &Path) -> Result<Vec<PathBuf>> {
    let io = |source| Error::Io {
        path: dir.to_path_buf(),
        source,
    };
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(io)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    v.sort();
    Ok(v)
}

/// The finished replicates of an ensemble directory, in replicate order.
fn replicates(dir: &Path) -> Result<Vec<Value>> {
    let mut out = Vec::new();
    for run in sorted_dirs(&dir.join("runs"))? {
        let s = run.join("summary.json");
        // A replicate still running (or killed) has no summary yet.
        if s.is_file() {
            out.push(read_json(&s)?);
        }
    }
    if out.is_empty() {
        return Err(Error::Impossible(format!(
            "{}: the ensemble has no finished beds (runs/*/summary.json)",
            dir.display()
        )));
    }
    Ok(out)
}

fn read_json(path: &Path) -> Result<Value> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|e| Error::Data {
        path: path.to_path_buf(),
        line: e.line(),
        message: format!("not a packbed summary: {e}"),
    })
}

/// What a group's beds say of themselves: their length unit (the same in
/// every bed, or an error), their dimensions and packbed versions.
struct Identity {
    unit: Option<LengthUnit>,
    dims: Vec<u64>,
    versions: Vec<String>,
}

fn identity(g: &Group) -> Result<Identity> {
    let mut id = Identity {
        unit: None,
        dims: Vec::new(),
        versions: Vec::new(),
    };
    for (k, s) in g.summaries.iter().enumerate() {
        let unit = match s.pointer("/config/analysis/length_unit") {
            None | Some(Value::Null) => None,
            Some(u) => Some(
                serde_json::from_value::<LengthUnit>(u.clone()).map_err(|_| {
                    Error::Impossible(format!(
                        "{}: unknown length_unit `{}` in its summary",
                        g.name,
                        echo(&u.to_string())
                    ))
                })?,
            ),
        };
        if k > 0 && unit != id.unit {
            return Err(Error::Impossible(format!(
                "{}: its beds name different length units ({} and {}); compare beds of one unit per group",
                g.name,
                unit_name(id.unit),
                unit_name(unit)
            )));
        }
        id.unit = unit;
        if let Some(d) = s.get("dim").and_then(Value::as_u64) {
            if !id.dims.contains(&d) {
                id.dims.push(d);
            }
        }
        if let Some(v) = s.get("packbed_version").and_then(Value::as_str) {
            let v = echo(v);
            if !id.versions.contains(&v) {
                id.versions.push(v);
            }
        }
    }
    Ok(id)
}

fn unit_name(u: Option<LengthUnit>) -> &'static str {
    u.map_or("none", LengthUnit::symbol)
}

/// The notes of beds of different dimensions or packbed versions.
fn mixture_notes(groups: &[Group], ids: &[Identity]) -> Vec<String> {
    let mut notes = Vec::new();
    let per_group = |f: &dyn Fn(&Identity) -> String| -> String {
        groups
            .iter()
            .zip(ids)
            .map(|(g, id)| format!("{} {}", g.name, f(id)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut dims: Vec<u64> = ids.iter().flat_map(|i| i.dims.clone()).collect();
    dims.sort_unstable();
    dims.dedup();
    if dims.len() > 1 {
        notes.push(format!(
            "the groups mix 2D and 3D beds ({}): their measures are not of the same kind \
             (2D values are per unit depth)",
            per_group(&|id| {
                id.dims
                    .iter()
                    .map(|d| format!("{d}D"))
                    .collect::<Vec<_>>()
                    .join("+")
            })
        ));
    }
    let mut versions: Vec<&String> = ids.iter().flat_map(|i| &i.versions).collect();
    versions.sort();
    versions.dedup();
    if versions.len() > 1 {
        notes.push(format!(
            "the beds come from different packbed versions ({}): a difference may be the \
             version's, not the beds'",
            per_group(&|id| id.versions.join("+"))
        ));
    }
    notes
}

/// Compares the groups: the measures all share, with the same value in
/// every bed of every group left out (settings and table sizes, not results).
/// Lengths are converted to the first group's unit (see the module).
pub fn compare(groups: &[Group]) -> Result<Comparison> {
    let ids = groups.iter().map(identity).collect::<Result<Vec<_>>>()?;
    let unit = ids.first().and_then(|i| i.unit);
    if let Some(k) = ids.iter().position(|i| i.unit.is_some() != unit.is_some()) {
        let (named, bare) = if unit.is_some() { (0, k) } else { (k, 0) };
        return Err(Error::Impossible(format!(
            "{} names its length unit ({}) and {} does not: their lengths cannot be compared; \
             set [analysis] length_unit for both (`packbed analyze --length-unit` for beds built)",
            groups[named].name,
            unit_name(ids[named].unit),
            groups[bare].name
        )));
    }
    let length_factors: Vec<f64> = ids
        .iter()
        .map(|i| match (i.unit, unit) {
            (Some(u), Some(r)) => u.metres() / r.metres(),
            _ => 1.0,
        })
        .collect();
    let converting = length_factors.iter().any(|&f| f != 1.0);
    let mut unit_note = None;
    if converting {
        let converted: Vec<String> = groups
            .iter()
            .zip(&ids)
            .filter(|(_, i)| i.unit != unit)
            .map(|(g, i)| format!("{} from {}", g.name, unit_name(i.unit)))
            .collect();
        unit_note = Some(format!(
            "lengths in {} (the unit of {}): converted {} (lengths, areas and inverse lengths by \
             the unit's power)",
            unit_name(unit),
            groups[0].name,
            converted.join(", ")
        ));
    }
    let mut warnings = mixture_notes(groups, &ids);
    let mut aggregates = groups
        .iter()
        .map(|g| measures_of(&g.summaries))
        .collect::<Result<Vec<_>>>()?;
    let dims: Vec<u8> = ids
        .iter()
        .map(|i| i.dims.first().map_or(3, |&d| d.min(3) as u8))
        .collect();
    let mut not_converted = Vec::new();
    for ((a, &f), &dim) in aggregates.iter_mut().zip(&length_factors).zip(&dims) {
        if f == 1.0 {
            continue;
        }
        a.measures.retain_mut(|m| match length_power(&m.name, dim) {
            Some(p) => {
                let s = f.powi(p);
                let st = &mut m.stats;
                (st.mean, st.sd, st.min, st.max) = (st.mean * s, st.sd * s, st.min * s, st.max * s);
                true
            }
            None => {
                if !not_converted.contains(&m.name) {
                    not_converted.push(m.name.clone());
                }
                false
            }
        });
    }
    if converting {
        // A measure of unknown dimension is left out of every group.
        for a in &mut aggregates {
            a.measures.retain(|m| !not_converted.contains(&m.name));
        }
    }
    if !not_converted.is_empty() {
        warnings.push(format!(
            "not compared across length units (dimension not known): {}",
            not_converted.join(", ")
        ));
    }
    let find = |a: &[MeasureStats], name: &str| a.iter().position(|m| m.name == name);
    let mut rows = Vec::new();
    let mut not_shared = Vec::new();
    for m in &aggregates[0].measures {
        let found: Option<Vec<&MeasureStats>> = aggregates
            .iter()
            .map(|a| find(&a.measures, &m.name).map(|i| &a.measures[i]))
            .collect();
        let Some(found) = found else {
            not_shared.push(m.name.clone());
            continue;
        };
        let stats: Vec<Stats> = found.iter().map(|x| x.stats).collect();
        let constant = stats
            .iter()
            .all(|s| s.min == stats[0].min && s.max == stats[0].min);
        if constant {
            continue;
        }
        let tests = stats[1..].iter().map(|s| Welch::of(&stats[0], s)).collect();
        let ratios = stats[1..]
            .iter()
            .map(|s| Ratio::of(&stats[0], s).filter(|_| m.kind == Kind::Value))
            .collect();
        rows.push(Row {
            name: m.name.clone(),
            kind: m.kind,
            stats,
            tests,
            ratios,
            length_power: length_power(&m.name, dims[0]),
        });
    }
    for a in &aggregates[1..] {
        for m in &a.measures {
            if find(&aggregates[0].measures, &m.name).is_none() && !not_shared.contains(&m.name) {
                not_shared.push(m.name.clone());
            }
        }
    }
    // Headline measures first, in their order; the rest as in summary.json.
    let rank = |name: &str| {
        HEADLINE
            .iter()
            .position(|h| *h == name)
            .unwrap_or(HEADLINE.len())
    };
    rows.sort_by_key(|r| rank(&r.name));
    Ok(Comparison {
        groups: groups
            .iter()
            .map(|g| (g.name.clone(), g.summaries.len() as u64))
            .collect(),
        rows,
        not_shared,
        not_converted,
        length_unit: unit,
        length_factors,
        unit_note,
        warnings,
    })
}

impl Comparison {
    /// The rows of the headline measures.
    pub fn headline(&self) -> impl Iterator<Item = &Row> {
        self.rows
            .iter()
            .filter(|r| HEADLINE.contains(&r.name.as_str()))
    }

    /// `compare.csv`: one row per measure; per group `mean`, `sd`, `n`; per
    /// group after the first `difference`, `t`, `df`, `p` and, for a positive
    /// measure, `ratio`, `ratio_ci_low`, `ratio_ci_high` (95 %).
    pub fn to_csv(&self) -> Result<String> {
        let mut w = csv::Writer::from_writer(Vec::new());
        let mut header = vec!["measure".to_string(), "kind".to_string()];
        for (g, _) in &self.groups {
            for c in ["mean", "sd", "n"] {
                header.push(format!("{g}.{c}"));
            }
        }
        for (g, _) in &self.groups[1..] {
            for c in [
                "difference",
                "t",
                "df",
                "p",
                "ratio",
                "ratio_ci_low",
                "ratio_ci_high",
            ] {
                header.push(format!("{g}.{c}"));
            }
        }
        let csv_err = |e: csv::Error| Error::Impossible(format!("compare.csv: {e}"));
        w.write_record(&header).map_err(csv_err)?;
        let opt = |x: Option<f64>| x.map_or(String::new(), |v| v.to_string());
        for r in &self.rows {
            let mut rec = vec![r.name.clone(), r.kind.as_str().to_string()];
            for s in &r.stats {
                rec.extend([s.mean.to_string(), s.sd.to_string(), s.n.to_string()]);
            }
            for (t, q) in r.tests.iter().zip(&r.ratios) {
                rec.extend([t.difference.to_string(), opt(t.t), opt(t.df), opt(t.p)]);
                let ci = q.and_then(|q| q.ci);
                rec.extend([
                    opt(q.map(|q| q.ratio)),
                    opt(ci.map(|c| c[0])),
                    opt(ci.map(|c| c[1])),
                ]);
            }
            w.write_record(&rec).map_err(csv_err)?;
        }
        let bytes = w
            .into_inner()
            .map_err(|e| Error::Impossible(format!("compare.csv: {e}")))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// A table for a person (`compare.md`, and on screen with `headline`
    /// only): mean ± sd per group, then each group against the first.
    pub fn to_markdown(&self, headline_only: bool) -> String {
        let rows = self.table(headline_only);
        let mut lines: Vec<String> = rows
            .iter()
            .map(|r| {
                let cells: Vec<String> = r.iter().map(|c| markdown_cell(c)).collect();
                format!("| {} |", cells.join(" | "))
            })
            .collect();
        lines.insert(1, format!("|{}", " --- |".repeat(rows[0].len())));
        lines.join("\n") + "\n"
    }

    /// The screen: the headline table with aligned columns, and where the rest is.
    pub fn to_text(&self, out: &Path) -> String {
        let cells = self.table(true);
        let cols = cells.iter().map(Vec::len).max().unwrap_or(0);
        let width: Vec<usize> = (0..cols)
            .map(|k| {
                cells
                    .iter()
                    .filter_map(|r| r.get(k))
                    .map(|c| c.chars().count())
                    .max()
                    .unwrap_or(0)
            })
            .collect();
        let mut t = String::new();
        for r in &cells {
            let padded: Vec<String> = r
                .iter()
                .enumerate()
                .map(|(k, c)| format!("{c:<w$}", w = width[k]))
                .collect();
            t.push_str("  ");
            t.push_str(padded.join("  ").trim_end());
            t.push('\n');
        }
        if self.rows.len() > self.headline().count() {
            t.push_str(&format!(
                "  {} more measures in {}\n",
                self.rows.len() - self.headline().count(),
                out.join(COMPARE_FILES[0]).display()
            ));
        }
        t.push_str(&format!(
            "  n: beds in which the measure is defined; p: Welch's t-test against {}, \"beyond scatter\" when p < {ALPHA}; \
             ratio: of the means, 95 % CI by the delta method on their logarithms\n",
            self.groups[0].0
        ));
        for line in self.permeability_lines() {
            t.push_str(&format!("  {line}\n"));
        }
        if let Some(u) = &self.unit_note {
            t.push_str(&format!("  {u}\n"));
        }
        t
    }

    /// "fine is 56.2× less permeable than coarse (permeability.k_z, 95 % CI …)",
    /// per group after the first, from the network's `k_z` or else the
    /// Kozeny–Carman `k`.
    pub fn permeability_lines(&self) -> Vec<String> {
        let row = ["permeability.k_z", "cake.k_kozeny_carman"]
            .iter()
            .find_map(|k| self.rows.iter().find(|r| r.name == *k));
        let Some(row) = row else {
            return Vec::new();
        };
        row.ratios
            .iter()
            .zip(&self.groups[1..])
            .filter_map(|(q, (g, _))| {
                let q = q.as_ref()?;
                let (factor, word) = q.factor();
                let how = if word.is_empty() {
                    format!("{factor} as permeable as")
                } else {
                    format!("{factor}{word} permeable than")
                };
                Some(format!(
                    "{g} is {how} {} ({}, {})",
                    self.groups[0].0,
                    row.name,
                    q.interval()
                ))
            })
            .collect()
    }

    /// `compare.json`: the groups, the common length unit and what was
    /// converted, the warnings, and per measure each group's `mean`, `sd`,
    /// `n` and each later group against the first (`difference`, Welch's
    /// `t`, `df`, `p`, and the `ratio` of the means with `ratio_ci_95`).
    /// A number that is not finite is `null`.
    pub fn to_json(&self) -> Result<String> {
        use serde_json::json;
        let num = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
        let opt = |x: Option<f64>| x.map_or(Value::Null, num);
        let groups: Vec<Value> = self
            .groups
            .iter()
            .zip(&self.length_factors)
            .map(|((g, n), f)| json!({"name": g, "beds": n, "length_factor": num(*f)}))
            .collect();
        let rows: Vec<Value> = self
            .rows
            .iter()
            .map(|r| {
                let stats: Vec<Value> = r
                    .stats
                    .iter()
                    .map(|s| {
                        // No scatter is known of one bed.
                        let sd = if s.n < 2 { Value::Null } else { num(s.sd) };
                        json!({"mean": num(s.mean), "sd": sd, "n": s.n})
                    })
                    .collect();
                let against: Vec<Value> = r
                    .tests
                    .iter()
                    .zip(&r.ratios)
                    .zip(&self.groups[1..])
                    .map(|((t, q), (g, _))| {
                        let mut v = json!({
                            "group": g,
                            "difference": num(t.difference),
                            "relative": opt(t.relative),
                            "t": opt(t.t),
                            "df": opt(t.df),
                            "p": opt(t.p),
                            "beyond_scatter": t.beyond_scatter,
                            "ratio": opt(q.map(|q| q.ratio)),
                            "ratio_ci_95": q.and_then(|q| q.ci).map_or(Value::Null, |c| json!([num(c[0]), num(c[1])])),
                        });
                        let note = match q {
                            None => Some("no ratio: the measure is not positive in every bed"),
                            Some(q) if q.ci.is_none() => {
                                Some("no confidence interval: a group has one bed")
                            }
                            _ => None,
                        };
                        if let Some(n) = note {
                            v["ratio_note"] = json!(n);
                        }
                        v
                    })
                    .collect();
                let mut row = json!({
                    "measure": r.name,
                    "kind": r.kind.as_str(),
                    "length_power": r.length_power,
                    "groups": stats,
                    "against_first": against,
                });
                if let Some(u) = self.unit_of(&r.name) {
                    row["unit"] = json!(u);
                }
                row
            })
            .collect();
        let doc = json!({
            "length_unit": self.length_unit.map(LengthUnit::name),
            "unit_note": self.unit_note,
            "warnings": self.warnings,
            "groups": groups,
            "measures": rows,
            "not_shared": self.not_shared,
            "not_converted": self.not_converted,
            "ratio_method": "ratio of the means; 95 % CI by the delta method on the logarithms of the means with Welch's degrees of freedom",
        });
        let mut text = serde_json::to_string_pretty(&doc)
            .map_err(|e| Error::Impossible(format!("compare.json: {e}")))?;
        text.push('\n');
        Ok(text)
    }

    /// The unit of a filtration's or capture's measure in this comparison
    /// (lengths in the common unit), `None` for the others.
    pub fn unit_of(&self, key: &str) -> Option<String> {
        filtration_unit(
            key,
            self.length_unit.map_or("length units", LengthUnit::symbol),
        )
    }

    /// The cells of the table, its header first.
    fn table(&self, headline_only: bool) -> Vec<Vec<String>> {
        let mut head = vec!["measure".to_string()];
        for (g, n) in &self.groups {
            head.push(format!("{g} (n = {n})"));
        }
        for (g, _) in &self.groups[1..] {
            head.push(format!("{g} − {}", self.groups[0].0));
            head.push("p (Welch)".to_string());
            head.push(format!("{g} / {}", self.groups[0].0));
        }
        let mut lines = vec![head];
        let rows: Vec<&Row> = if headline_only {
            self.headline().collect()
        } else {
            self.rows.iter().collect()
        };
        for r in rows {
            let unit = if r.kind == Kind::Percent {
                " % of beds"
            } else {
                ""
            };
            let mut cells = vec![match self.unit_of(&r.name) {
                Some(u) => format!("{} ({u})", r.name),
                None => format!("{}{unit}", r.name),
            }];
            for s in &r.stats {
                cells.push(mean_sd(s));
            }
            for (t, q) in r.tests.iter().zip(&r.ratios) {
                let rel = t
                    .relative
                    .map_or(String::new(), |x| format!(" ({:+.1} %)", 100.0 * x));
                cells.push(format!("{}{rel}", number(t.difference)));
                cells.push(match (t.p, t.beyond_scatter) {
                    (Some(p), Some(true)) => format!("{} beyond scatter", p_value(p)),
                    (Some(p), _) => format!("{} within scatter", p_value(p)),
                    _ => "n/a (fewer than 2 beds)".to_string(),
                });
                cells.push(q.map_or_else(String::new, |q| q.text()));
            }
            lines.push(cells);
        }
        lines
    }

    /// `compare.md`: the groups, what `n` and `p` mean, and the full table.
    pub fn report(&self) -> String {
        let mut t = String::from("# packbed compare\n\n");
        for (g, n) in &self.groups {
            t.push_str(&format!("- {}: {n} beds\n", markdown_cell(g)));
        }
        t.push_str(&format!(
            "\nmean ± sd over each group's beds (n: beds in which the measure is defined); \
             each group after the first against the first by Welch's t-test, two-sided: \
             \"beyond scatter\" when p < {ALPHA}; for a positive measure the ratio of the \
             means with its 95 % confidence interval (delta method on the logarithms of the \
             means, Welch's degrees of freedom; none with one bed in a group). Measures with \
             the same value in every bed (settings, table sizes) are left out.\n\n"
        ));
        match &self.unit_note {
            Some(u) => t.push_str(&format!("Units: {}.\n\n", markdown_cell(u))),
            None => {
                if let Some(u) = self.length_unit {
                    t.push_str(&format!("Units: lengths in {}.\n\n", u.symbol()));
                }
            }
        }
        for w in &self.warnings {
            t.push_str(&format!("Note: {}.\n\n", markdown_cell(w)));
        }
        for line in self.permeability_lines() {
            t.push_str(&format!("{}\n\n", markdown_cell(&line)));
        }
        t.push_str(&self.to_markdown(false));
        if !self.not_shared.is_empty() {
            t.push_str(&format!(
                "\nIn some groups only (not compared): {}\n",
                markdown_cell(&self.not_shared.join(", "))
            ));
        }
        t
    }
}

fn mean_sd(s: &Stats) -> String {
    if s.n < 2 {
        number(s.mean)
    } else {
        format!("{} ± {}", number(s.mean), short(s.sd))
    }
}

/// Four significant digits, as a table wants.
fn number(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-3..1e5).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.3e}")
    }
}

/// Two significant digits: a scatter is known no better.
fn short(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-3..1e5).contains(&a) {
        let digits = (1 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.1e}")
    }
}

fn p_value(p: f64) -> String {
    if p < 1e-4 {
        "p < 0.0001".into()
    } else {
        format!("p = {p:.4}")
    }
}

/// The measures drawn, when present: one plot each.
#[cfg(feature = "render")]
const PLOTTED: [&str; 10] = [
    "filtration.alpha_fit_m_per_kg",
    "filtration.r_medium_fit_per_m",
    "cake.porosity",
    "permeability.k_z",
    "cake.k_kozeny_carman",
    "cake.d32",
    "cake.specific_resistance",
    "pores.d_c35",
    "drainage.breakthrough.reduced",
    "drainage.residual_saturation",
];

/// Files of a comparison (plots aside).
pub const COMPARE_FILES: [&str; 3] = ["compare.md", "compare.csv", "compare.json"];

/// Writes `compare.md`, `compare.csv`, `compare.json` and, with `pictures`, a bar plot per
/// headline measure (`plot_compare_<measure>`), the groups' size
/// distributions (`plot_compare_psd`) and drainage curves
/// (`plot_compare_drainage`) into `out`, atomically.
pub fn write_comparison(
    out: &Path,
    groups: &[Group],
    c: &Comparison,
    pictures: bool,
) -> Result<Vec<PathBuf>> {
    let mut s = crate::io::Staging::new(out)?;
    let md = c.report();
    let csv = c.to_csv()?;
    let json = c.to_json()?;
    s.stage(COMPARE_FILES[0], |w| w.write_all(md.as_bytes()))?;
    s.stage(COMPARE_FILES[1], |w| w.write_all(csv.as_bytes()))?;
    s.stage(COMPARE_FILES[2], |w| w.write_all(json.as_bytes()))?;
    if pictures {
        #[cfg(feature = "render")]
        {
            // A comparison is quick to redo and its plots are much of what
            // it is for: a plot that cannot be drawn stays an error here.
            let mut missing = Vec::new();
            super::write::stage_plots(&mut s, &plots(groups, c), &mut missing)?;
            if let Some(m) = missing.into_iter().next() {
                return Err(crate::error::Error::Impossible(m));
            }
        }
        #[cfg(not(feature = "render"))]
        {
            let _ = groups;
            return Err(crate::output::no_pictures());
        }
    }
    s.commit()
}

/// The bars of the headline measures and the size distributions.
#[cfg(feature = "render")]
fn plots(groups: &[Group], c: &Comparison) -> Vec<(String, crate::render::plot::Plot)> {
    use crate::render::plot::{BarGroup, Plot, PlotData, Series};
    let names: Vec<String> = c.groups.iter().map(|g| g.0.clone()).collect();
    // Every group's lengths are in the common unit (`compare`).
    let unit = c.length_unit.map_or("length units", LengthUnit::symbol);
    let mut out: Vec<(String, Plot)> = c
        .rows
        .iter()
        .filter(|r| PLOTTED.contains(&r.name.as_str()))
        .map(|r| {
            let stem = format!("plot_compare_{}", r.name.replace(['.', '[', ']'], "_"));
            let plot = Plot {
                title: r.name.clone(),
                x_label: String::new(),
                y_label: format!("{} (mean ± sd)", axis_name(&r.name, unit)),
                // Dots on an axis that spans the data: the differences are
                // what the plot is about, not the distance from 0.
                data: PlotData::Dots {
                    categories: names.clone(),
                    groups: vec![BarGroup {
                        name: "mean ± sd".into(),
                        values: r.stats.iter().map(|s| s.mean).collect(),
                        errors: Some(r.stats.iter().map(|s| s.sd).collect()),
                    }],
                },
                y_range: dots_range(&r.stats),
                x_range: None,
            };
            (stem, plot)
        })
        .collect();

    // Each group's placed curve (mean over its beds) and its request.
    let mut series = Vec::new();
    for (g, &f) in groups.iter().zip(&c.length_factors) {
        let Some(mut curves) = psd_curves(&g.summaries) else {
            continue;
        };
        for p in curves.placed.iter_mut().chain(&mut curves.requested) {
            p.0 *= f;
        }
        series.push(Series {
            name: format!("{} placed", g.name),
            points: curves.placed,
            errors: None,
            markers: false,
            band: None,
        });
        series.push(Series {
            name: format!("{} requested", g.name),
            points: curves.requested,
            errors: None,
            markers: true,
            band: None,
        });
    }
    let drainage: Vec<Series> = groups
        .iter()
        .filter_map(|g| {
            let c = drainage_curve(&g.summaries)?;
            let beds = if c.beds == 1 {
                "1 bed".to_string()
            } else {
                format!("{} beds", c.beds)
            };
            Some(Series {
                name: format!("{} ({beds})", g.name),
                points: c.points,
                errors: None,
                markers: false,
                band: Some(c.band),
            })
        })
        .collect();
    if !drainage.is_empty() {
        out.push((
            "plot_compare_drainage".into(),
            Plot {
                title:
                    "Primary drainage: each group's mean, shaded from its lowest to its highest bed"
                        .into(),
                x_label: "capillary pressure P_c·d32/γ".into(),
                y_label: "wetting saturation".into(),
                data: PlotData::LogLines { series: drainage },
                y_range: Some((0.0, 1.0)),
                x_range: None,
            },
        ));
    }
    if !series.is_empty() {
        out.push((
            "plot_compare_psd".into(),
            Plot {
                title: "Size distributions by mass".into(),
                x_label: format!("diameter ({unit})"),
                y_label: "finer than the diameter (% by mass)".into(),
                data: PlotData::LogLines { series },
                y_range: Some((0.0, 100.0)),
                x_range: None,
            },
        ));
    }
    out
}

/// The y axis of a measure's dots: the means ± sd, padded by 5 %, and for a
/// measure that no bed has below 0 never below 0 (its error bars are cut at
/// the axis). `None`: the plot's own range (a measure that may be negative).
#[cfg(feature = "render")]
fn dots_range(stats: &[Stats]) -> Option<(f64, f64)> {
    if stats.iter().any(|s| s.min < 0.0) {
        return None;
    }
    let lo = stats
        .iter()
        .map(|s| s.mean - s.sd)
        .fold(f64::INFINITY, f64::min);
    let hi = stats
        .iter()
        .map(|s| s.mean + s.sd)
        .fold(f64::NEG_INFINITY, f64::max);
    if !lo.is_finite() || !hi.is_finite() {
        return None;
    }
    if hi - lo <= 1e-12 * hi.abs() {
        return Some(if hi > 0.0 {
            (0.9 * hi, 1.1 * hi)
        } else {
            (0.0, 1.0)
        });
    }
    let pad = 0.05 * (hi - lo);
    Some(((lo - pad).max(0.0), hi + pad))
}

/// A plotted measure's name with its unit.
#[cfg(feature = "render")]
fn axis_name(key: &str, unit: &str) -> String {
    match key {
        "cake.porosity" => "porosity".into(),
        "permeability.k_z" => format!("network k along z ({unit}²)"),
        "cake.k_kozeny_carman" => format!("Kozeny–Carman k ({unit}²)"),
        "cake.d32" => format!("d32 ({unit})"),
        "cake.specific_resistance" => "specific cake resistance (m/kg)".into(),
        "pores.d_c35" => format!("constriction d_c35 ({unit})"),
        "drainage.breakthrough.reduced" => "breakthrough pressure P_c·d32/γ".into(),
        "drainage.residual_saturation" => "residual wetting saturation".into(),
        "filtration.alpha_fit_m_per_kg" => "α fitted to Ruth's line (m/kg)".into(),
        "filtration.r_medium_fit_per_m" => "R_m fitted to Ruth's line (1/m)".into(),
        other => other.into(),
    }
}

/// A group's drainage curve at the fixed reduced pressures
/// (`drainage.curve`) over the beds that have one on the grid of the first
/// such bed: the mean saturation per pressure, the lowest and highest bed's,
/// and the number of beds. `None` when no bed has a curve.
#[cfg(feature = "render")]
struct DrainageCurve {
    points: Vec<(f64, f64)>,
    band: Vec<(f64, f64)>,
    beds: usize,
}

#[cfg(feature = "render")]
fn drainage_curve(summaries: &[Value]) -> Option<DrainageCurve> {
    let numbers = |s: &Value, key: &str| -> Option<Vec<f64>> {
        s.pointer(&format!("/drainage/curve/{key}"))?
            .as_array()?
            .iter()
            .map(Value::as_f64)
            .collect()
    };
    let curves: Vec<(Vec<f64>, Vec<f64>)> = summaries
        .iter()
        .filter_map(|s| Some((numbers(s, "pc_reduced")?, numbers(s, "saturation")?)))
        .filter(|(p, s)| p.len() == s.len() && !p.is_empty())
        .collect();
    let pc = curves.first()?.0.clone();
    let same: Vec<&Vec<f64>> = curves.iter().filter(|c| c.0 == pc).map(|c| &c.1).collect();
    let mut sum = vec![0.0; pc.len()];
    let mut band = vec![(f64::INFINITY, f64::NEG_INFINITY); pc.len()];
    for saturation in &same {
        for ((t, b), &x) in sum.iter_mut().zip(&mut band).zip(saturation.iter()) {
            *t += x;
            *b = (b.0.min(x), b.1.max(x));
        }
    }
    let n = same.len() as f64;
    Some(DrainageCurve {
        points: pc.iter().zip(&sum).map(|(&p, &t)| (p, t / n)).collect(),
        band,
        beds: same.len(),
    })
}

/// A group's mass curves: requested (of its first bed) and placed (the mean
/// over beds, row by row).
#[cfg(feature = "render")]
struct Curves {
    requested: Vec<(f64, f64)>,
    placed: Vec<(f64, f64)>,
}

#[cfg(feature = "render")]
fn psd_curves(summaries: &[Value]) -> Option<Curves> {
    let rows = |s: &Value| -> Option<Vec<(f64, f64, f64)>> {
        s.pointer("/psd/table")?
            .as_array()?
            .iter()
            .map(|r| {
                Some((
                    r.get("diameter")?.as_f64()?,
                    r.get("requested_mass_percent_passing")?.as_f64()?,
                    r.get("placed_mass_percent_passing")?.as_f64()?,
                ))
            })
            .collect()
    };
    let first = rows(summaries.first()?)?;
    let mut placed: Vec<f64> = vec![0.0; first.len()];
    let mut n = 0.0;
    for s in summaries {
        let r = rows(s)?;
        if r.len() != first.len() {
            return None;
        }
        for (p, x) in placed.iter_mut().zip(&r) {
            *p += x.2;
        }
        n += 1.0;
    }
    Some(Curves {
        requested: first.iter().map(|r| (r.0, r.1)).collect(),
        placed: first
            .iter()
            .zip(&placed)
            .map(|(r, p)| (r.0, p / n))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stats(values: &[f64]) -> Stats {
        Stats::of(values)
    }

    #[test]
    fn welch_matches_a_hand_solved_case() {
        // a: mean 2, s² = 1 (n 3); b: mean 5, s² = 4 (n 5).
        // se² = 1/3 + 4/5 = 17/15, t = 3/√(17/15) = 2.8180;
        // df = (17/15)² / ((1/3)²/2 + (4/5)²/4) = 1.28444/0.21556 = 5.9588.
        let a = stats(&[1.0, 2.0, 3.0]);
        let b = stats(&[3.0, 3.0, 5.0, 7.0, 7.0]);
        assert!((b.sd * b.sd - 4.0).abs() < 1e-12);
        let w = Welch::of(&a, &b);
        assert!((w.t.unwrap() - 3.0 / (17.0f64 / 15.0).sqrt()).abs() < 1e-12);
        let df = (17.0f64 / 15.0).powi(2) / ((1.0f64 / 3.0).powi(2) / 2.0 + 0.8f64.powi(2) / 4.0);
        assert!((w.df.unwrap() - df).abs() < 1e-12);
        // Student's t with 5.9588 df: two-sided p of t = 2.818 is 0.0307
        // (by quadrature of the t density: 0.03066).
        assert!((w.p.unwrap() - 0.03066).abs() < 1e-4, "{:?}", w.p);
        assert_eq!(w.beyond_scatter, Some(true));
        assert_eq!(w.difference, 3.0);
        assert_eq!(w.relative, Some(1.5));
    }

    #[test]
    fn welch_p_of_a_large_sample_is_the_normal_one() {
        // With many beds t is nearly normal: t = 1.96 gives p ≈ 0.05.
        let a = Stats {
            n: 100_000,
            mean: 0.0,
            sd: 1.0,
            min: 0.0,
            max: 0.0,
        };
        let b = Stats {
            mean: 1.96 * (2.0f64 / 100_000.0).sqrt(),
            ..a
        };
        let p = Welch::of(&a, &b).p.unwrap();
        assert!((p - 0.05).abs() < 1e-3, "{p}");
    }

    #[test]
    fn one_bed_or_no_scatter() {
        let one = stats(&[1.0]);
        let many = stats(&[1.0, 2.0]);
        assert_eq!(Welch::of(&one, &many).p, None);
        let same = stats(&[2.0, 2.0]);
        let other = stats(&[3.0, 3.0]);
        assert_eq!(Welch::of(&same, &other).beyond_scatter, Some(true));
        assert_eq!(Welch::of(&same, &same).beyond_scatter, Some(false));
    }

    fn summary(porosity: f64, height: f64) -> Value {
        serde_json::json!({
            "dim": 3,
            "cake": {"porosity": porosity, "height": height},
            "config": {"seed": 1},
        })
    }

    #[test]
    fn groups_compare_shared_measures_that_vary() {
        let groups = vec![
            Group {
                name: "a".into(),
                dir: "a".into(),
                summaries: vec![
                    summary(0.40, 10.0),
                    summary(0.41, 10.0),
                    summary(0.42, 10.0),
                ],
            },
            Group {
                name: "b".into(),
                dir: "b".into(),
                summaries: vec![
                    summary(0.45, 10.0),
                    summary(0.46, 10.0),
                    summary(0.47, 10.0),
                ],
            },
        ];
        let c = compare(&groups).unwrap();
        // The height is 10 in every bed: no information, left out.
        assert_eq!(c.rows.len(), 1);
        let r = &c.rows[0];
        assert_eq!(r.name, "cake.porosity");
        assert!((r.tests[0].difference - 0.05).abs() < 1e-12);
        assert_eq!(r.tests[0].beyond_scatter, Some(true));
        let md = c.report();
        assert!(
            md.contains("a (n = 3)") && md.contains("beyond scatter"),
            "{md}"
        );
        let csv = c.to_csv().unwrap();
        assert!(
            csv.starts_with(
                "measure,kind,a.mean,a.sd,a.n,b.mean,b.sd,b.n,b.difference,b.t,b.df,b.p,b.ratio,b.ratio_ci_low,b.ratio_ci_high\n"
            ),
            "{csv}"
        );
    }

    #[test]
    fn ratio_ci_matches_a_hand_solved_case() {
        // a: mean 2, sd 1, n 3; b: mean 4, sd 2, n 3: ratio 2, both cv 0.5.
        // Var ln(mean) = cv²/n = 1/12 each, se² = 1/6; df = (1/6)² /
        // (2 (1/12)² / 2) = 4; t(0.975, 4) = 2.776445 (Student's t table).
        // CI = 2 exp(± 2.776445 × √(1/6)) = [0.643823, 6.212890].
        let a = stats(&[1.0, 2.0, 3.0]);
        let b = stats(&[2.0, 4.0, 6.0]);
        let q = Ratio::of(&a, &b).unwrap();
        assert_eq!(q.ratio, 2.0);
        assert!((q.df.unwrap() - 4.0).abs() < 1e-12, "{q:?}");
        let [lo, hi] = q.ci.unwrap();
        assert!((lo - 0.643823).abs() < 2e-6, "{lo}");
        assert!((hi - 6.212890).abs() < 2e-5, "{hi}");
        assert_eq!(q.text(), "2.00× more (95 % CI 0.644–6.21×)");
        // The other way round: b to a is 2× less, the bounds inverted.
        let back = Ratio::of(&b, &a).unwrap();
        assert_eq!(back.text(), "2.00× less (95 % CI 0.644–6.21×)");
        // One bed: the ratio, no interval; a value ≤ 0: no ratio.
        let one = Ratio::of(&stats(&[4.0]), &a).unwrap();
        assert_eq!((one.ratio, one.ci), (0.5, None));
        assert_eq!(one.text(), "2.00× less (no CI: one bed)");
        assert_eq!(Ratio::of(&stats(&[0.0, 1.0]), &a), None);
        assert_eq!(Ratio::of(&a, &stats(&[-1.0, 1.0])), None);
    }

    fn cake(unit: Option<&str>, dim: u8, version: &str, k: f64, d32: f64) -> Value {
        let mut v = serde_json::json!({
            "packbed_version": version,
            "dim": dim,
            "cake": {"porosity": 0.4 + k * 1e-9, "d32": d32, "k_kozeny_carman": k,
                     "specific_resistance": 1e9 / k},
            "fragmentation": {"max_force": k},
            "config": {"seed": 1, "analysis": {}},
        });
        if let Some(u) = unit {
            v["config"]["analysis"]["length_unit"] = u.into();
        }
        v
    }

    fn group(name: &str, beds: Vec<Value>) -> Group {
        Group {
            name: name.into(),
            dir: name.into(),
            summaries: beds,
        }
    }

    #[test]
    fn lengths_are_compared_in_the_first_groups_unit() {
        // Sand in mm (k 2.0e-5 mm², d32 0.2 mm), flour in µm (k 0.36 µm²,
        // d32 20 µm): in mm flour's k is 3.6e-7 mm², 55.6× less.
        let sand = group(
            "sand",
            vec![
                cake(Some("mm"), 3, "1.0.0", 2.0e-5, 0.20),
                cake(Some("mm"), 3, "1.0.0", 2.2e-5, 0.21),
            ],
        );
        let flour = group(
            "flour",
            vec![
                cake(Some("um"), 3, "1.0.0", 0.34, 20.0),
                cake(Some("um"), 3, "1.0.0", 0.38, 21.0),
            ],
        );
        let c = compare(&[sand.clone(), flour.clone()]).unwrap();
        let row = |name: &str| c.rows.iter().find(|r| r.name == name).unwrap();
        let k = row("cake.k_kozeny_carman");
        assert!(
            (k.stats[1].mean - 0.36e-6).abs() < 1e-18,
            "{:?}",
            k.stats[1]
        );
        assert!((k.stats[1].sd - (0.02f64 * 2.0f64.sqrt()) * 1e-6).abs() < 1e-15);
        let q = k.ratios[0].unwrap();
        assert!((q.ratio - 0.36e-6 / 2.1e-5).abs() < 1e-12, "{q:?}");
        assert!(k.tests[0].difference < 0.0);
        let d32 = row("cake.d32");
        assert!((d32.stats[1].mean - 0.0205).abs() < 1e-15);
        // SI values stay as they are.
        let alpha = row("cake.specific_resistance");
        let raw = (1e9 / 0.34 + 1e9 / 0.38) / 2.0;
        assert!((alpha.stats[1].mean / raw - 1.0).abs() < 1e-12);
        // A measure of unknown dimension is not compared across units.
        assert!(c.rows.iter().all(|r| !r.name.starts_with("fragmentation")));
        assert_eq!(c.not_converted, vec!["fragmentation.max_force".to_string()]);
        assert_eq!(c.length_unit, Some(LengthUnit::Millimetre));
        assert_eq!(c.length_factors, vec![1.0, 1e-3]);
        let note = c.unit_note.as_deref().unwrap();
        assert!(
            note.contains("lengths in mm") && note.contains("flour from µm"),
            "{note}"
        );
        assert!(c.permeability_lines()[0].starts_with("flour is 58.3× less permeable than sand"));
        let json: Value = serde_json::from_str(&c.to_json().unwrap()).unwrap();
        assert_eq!(json["length_unit"], "mm");
        assert_eq!(json["groups"][1]["length_factor"], 1e-3);
        // The same units: nothing converted, every measure compared.
        let c = compare(&[sand.clone(), sand.clone()]).unwrap();
        assert!(c.unit_note.is_none() && c.not_converted.is_empty());
        // One group names its unit, the other does not: refused.
        let bare = group("bare", vec![cake(None, 3, "1.0.0", 0.3, 20.0)]);
        let e = compare(&[sand.clone(), bare]).unwrap_err().to_string();
        assert!(
            e.contains("sand names its length unit (mm) and bare does not"),
            "{e}"
        );
    }

    #[test]
    fn beds_of_2d_and_3d_or_of_two_versions_are_noted() {
        let a = group("a", vec![cake(Some("mm"), 3, "1.0.0", 2e-5, 0.2)]);
        let b = group("b", vec![cake(Some("mm"), 2, "1.1.0", 3e-5, 0.3)]);
        let c = compare(&[a, b]).unwrap();
        assert_eq!(c.warnings.len(), 2, "{:?}", c.warnings);
        assert!(c.warnings[0].contains("mix 2D and 3D beds (a 3D, b 2D)"));
        assert!(c.warnings[1].contains("different packbed versions (a 1.0.0, b 1.1.0)"));
        assert!(c.report().contains("Note: the groups mix 2D and 3D beds"));
    }

    #[cfg(feature = "render")]
    #[test]
    fn a_positive_measure_is_plotted_above_zero() {
        // Porosities 0.01–0.9: mean − sd is below 0.
        let beds = |xs: &[f64]| {
            xs.iter()
                .map(|&x| serde_json::json!({"dim": 3, "cake": {"porosity": x}}))
                .collect()
        };
        let groups = vec![
            group("a", beds(&[0.01, 0.02, 0.9])),
            group("b", beds(&[0.02, 0.03, 0.95])),
        ];
        let c = compare(&groups).unwrap();
        let stats = &c.rows[0].stats;
        assert!(stats[0].mean - stats[0].sd < 0.0);
        let p = plots(&groups, &c);
        let (_, y) = p[0].1.ranges();
        assert!(y.0 >= 0.0 && y.1 > stats[1].mean + stats[1].sd, "{y:?}");
    }
}
