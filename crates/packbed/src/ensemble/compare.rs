//! `packbed compare`: beds side by side. Each directory is a run, an ensemble
//! or a sweep (each of its values a group); the measures the groups share are
//! tabled with mean ± sd, and every group after the first is set against the
//! first by Welch's t-test: is the difference larger than the replicate
//! scatter would make by chance?

use super::stats::{measures_of, Kind, Measure, Stats};
use crate::error::{Error, Result};
use serde::Serialize;
use serde_json::Value;
use statrs::distribution::{ContinuousCDF, StudentsT};
use std::path::{Path, PathBuf};

/// The significance level of the "beyond the scatter" verdict.
pub const ALPHA: f64 = 0.05;

/// The measures a filtration study reads first, in this order when present;
/// the rest follow in the order of `summary.json`.
pub const HEADLINE: [&str; 16] = [
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
    "psd.placed.d50",
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
}

/// Reads the beds of each directory: a run (`summary.json`), an ensemble
/// (`runs/NNNN/summary.json`) or a sweep (`sweep/NN-label/runs/...`, one group
/// per value).
pub fn read_groups(dirs: &[PathBuf]) -> Result<Vec<Group>> {
    let mut groups = Vec::new();
    for dir in dirs {
        let name = dir.file_name().map_or_else(
            || dir.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        let sweep = dir.join("sweep");
        if sweep.is_dir() {
            for point in sorted_dirs(&sweep)? {
                let label = point
                    .file_name()
                    .map_or(String::new(), |n| n.to_string_lossy().into_owned());
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

/// Compares the groups: the measures all share, with the same value in
/// every bed of every group left out (settings and table sizes, not results).
pub fn compare(groups: &[Group]) -> Result<Comparison> {
    let aggregates = groups
        .iter()
        .map(|g| measures_of(&g.summaries))
        .collect::<Result<Vec<_>>>()?;
    let find = |a: &[Measure], name: &str| a.iter().position(|m| m.name == name);
    let mut rows = Vec::new();
    let mut not_shared = Vec::new();
    for m in &aggregates[0].measures {
        let found: Option<Vec<&Measure>> = aggregates
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
        rows.push(Row {
            name: m.name.clone(),
            kind: m.kind,
            stats,
            tests,
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
    /// group after the first `difference`, `t`, `df`, `p`.
    pub fn to_csv(&self) -> Result<String> {
        let mut w = csv::Writer::from_writer(Vec::new());
        let mut header = vec!["measure".to_string(), "kind".to_string()];
        for (g, _) in &self.groups {
            for c in ["mean", "sd", "n"] {
                header.push(format!("{g}.{c}"));
            }
        }
        for (g, _) in &self.groups[1..] {
            for c in ["difference", "t", "df", "p"] {
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
            for t in &r.tests {
                rec.extend([t.difference.to_string(), opt(t.t), opt(t.df), opt(t.p)]);
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
            .map(|r| format!("| {} |", r.join(" | ")))
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
            "  n: beds in which the measure is defined; p: Welch's t-test against {}, \"beyond scatter\" when p < {ALPHA}\n",
            self.groups[0].0
        ));
        t
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
            let mut cells = vec![format!("{}{unit}", r.name)];
            for s in &r.stats {
                cells.push(mean_sd(s));
            }
            for t in &r.tests {
                let rel = t
                    .relative
                    .map_or(String::new(), |x| format!(" ({:+.1} %)", 100.0 * x));
                cells.push(format!("{}{rel}", number(t.difference)));
                cells.push(match (t.p, t.beyond_scatter) {
                    (Some(p), Some(true)) => format!("{} beyond scatter", p_value(p)),
                    (Some(p), _) => format!("{} within scatter", p_value(p)),
                    _ => "n/a (fewer than 2 beds)".to_string(),
                });
            }
            lines.push(cells);
        }
        lines
    }

    /// `compare.md`: the groups, what `n` and `p` mean, and the full table.
    pub fn report(&self) -> String {
        let mut t = String::from("# packbed compare\n\n");
        for (g, n) in &self.groups {
            t.push_str(&format!("- `{g}`: {n} beds\n"));
        }
        t.push_str(&format!(
            "\nmean ± sd over each group's beds (n: beds in which the measure is defined); \
             each group after the first against the first by Welch's t-test, two-sided: \
             \"beyond scatter\" when p < {ALPHA}. Measures with the same value in every bed \
             (settings, table sizes) are left out.\n\n"
        ));
        t.push_str(&self.to_markdown(false));
        if !self.not_shared.is_empty() {
            t.push_str(&format!(
                "\nIn some groups only (not compared): {}\n",
                self.not_shared.join(", ")
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
const PLOTTED: [&str; 6] = [
    "cake.porosity",
    "permeability.k_z",
    "cake.k_kozeny_carman",
    "cake.d32",
    "cake.specific_resistance",
    "pores.d_c35",
];

/// Files of a comparison (plots aside).
pub const COMPARE_FILES: [&str; 2] = ["compare.md", "compare.csv"];

/// Writes `compare.md`, `compare.csv` and, with `pictures`, a bar plot per
/// headline measure (`plot_compare_<measure>`) and the groups' size
/// distributions (`plot_compare_psd`) into `out`, atomically.
pub fn write_comparison(
    out: &Path,
    groups: &[Group],
    c: &Comparison,
    pictures: bool,
) -> Result<Vec<PathBuf>> {
    let mut s = crate::io::Staging::new(out)?;
    let md = c.report();
    let csv = c.to_csv()?;
    s.stage(COMPARE_FILES[0], |w| w.write_all(md.as_bytes()))?;
    s.stage(COMPARE_FILES[1], |w| w.write_all(csv.as_bytes()))?;
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
    let unit = groups
        .first()
        .and_then(|g| g.summaries.first())
        .and_then(|s| s.pointer("/config/analysis/length_unit"))
        .and_then(|u| serde_json::from_value::<crate::config::LengthUnit>(u.clone()).ok())
        .map_or("length units", crate::config::LengthUnit::symbol);
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
                y_range: None,
                x_range: None,
            };
            (stem, plot)
        })
        .collect();

    // Each group's placed curve (mean over its beds) and its request.
    let mut series = Vec::new();
    for g in groups {
        let Some(curves) = psd_curves(&g.summaries) else {
            continue;
        };
        series.push(Series {
            name: format!("{} placed", g.name),
            points: curves.placed,
            errors: None,
            markers: false,
        });
        series.push(Series {
            name: format!("{} requested", g.name),
            points: curves.requested,
            errors: None,
            markers: true,
        });
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
        other => other.into(),
    }
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
                "measure,kind,a.mean,a.sd,a.n,b.mean,b.sd,b.n,b.difference,b.t,b.df,b.p\n"
            ),
            "{csv}"
        );
    }
}
