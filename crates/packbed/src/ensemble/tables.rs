//! The files of an ensemble: `ensemble.json`, `ensemble.csv`, `histograms.csv`,
//! the human table `ensemble.md` (the source study's layout: one row per
//! measure, columns min, mean ± sd, max), and for sweeps `sweep.csv` and
//! `sweep.md` (one row per value). Every function here is pure: the same
//! aggregate gives the same bytes.

use super::stats::{Aggregate, Kind, Measure, Stats};
use crate::config::Config;
use crate::io::tables::Num;
use serde_json::{json, Map, Value};
use std::fmt::Write;

/// What an ensemble's files say about where its numbers come from.
#[derive(Clone, Debug)]
pub struct Header<'a> {
    /// The config every replicate ran (seed: the master seed).
    pub config: &'a Config,
    /// Replicates requested (`--runs`).
    pub runs: u64,
    /// This shard, if the ensemble is one (`K/M`).
    pub shard: Option<(u64, u64)>,
    /// The sweep value, if the ensemble is one: (parameter, label, value).
    pub sweep: Option<(&'a str, &'a str, Value)>,
}

/// `ensemble.json`.
pub fn ensemble_json(h: &Header, a: &Aggregate) -> String {
    let mut top = Map::new();
    top.insert("format".into(), json!("packbed-ensemble"));
    top.insert("packbed_version".into(), json!(env!("CARGO_PKG_VERSION")));
    top.insert("runs".into(), json!(h.runs));
    top.insert("replicates".into(), json!(a.replicates));
    if let Some((k, m)) = h.shard {
        top.insert("shard".into(), json!({ "index": k, "count": m }));
    }
    top.insert("master_seed".into(), json!(h.config.seed));
    top.insert("seed_rule".into(), json!(super::seeds::SEED_RULE));
    if let Some((p, label, value)) = &h.sweep {
        top.insert(
            "sweep".into(),
            json!({ "parameter": p, "label": label, "value": value }),
        );
    }
    top.insert(
        "config".into(),
        serde_json::to_value(h.config).unwrap_or(Value::Null),
    );
    let mut measures = Map::new();
    for m in &a.measures {
        let mut e = stats_json(&m.stats);
        e.insert(0, ("kind", json!(m.kind.as_str())));
        measures.insert(
            m.name.clone(),
            Value::Object(e.into_iter().map(|(k, v)| (k.to_string(), v)).collect()),
        );
    }
    top.insert("measures".into(), Value::Object(measures));
    let mut hist = Map::new();
    for h in &a.histograms {
        hist.insert(
            h.name.clone(),
            json!({ "replicates": h.replicates, "counts": h.counts, "fraction": h.fraction }),
        );
    }
    top.insert("histograms".into(), Value::Object(hist));
    let mut series = Map::new();
    for s in &a.series {
        let col = |f: fn(&Stats) -> Value| Value::Array(s.entries.iter().map(f).collect());
        series.insert(
            s.name.clone(),
            json!({
                "n": col(|e| json!(e.n)),
                "mean": col(|e| json!(e.mean)),
                "sd": col(|e| json!(e.sd)),
                "min": col(|e| json!(e.min)),
                "max": col(|e| json!(e.max)),
            }),
        );
    }
    top.insert("series".into(), Value::Object(series));
    let mut text = serde_json::to_string_pretty(&Value::Object(top)).unwrap_or_default();
    text.push('\n');
    text
}

fn stats_json(s: &Stats) -> Vec<(&'static str, Value)> {
    vec![
        ("n", json!(s.n)),
        ("mean", json!(s.mean)),
        ("sd", json!(s.sd)),
        ("min", json!(s.min)),
        ("max", json!(s.max)),
    ]
}

/// Header of `ensemble.csv`.
pub const CSV_HEADER: &str = "name,n,mean,sd,min,max,kind";

/// CSV text written through the `csv` crate, so that a name holding a comma,
/// a quote or a line break (measures are named after species, and species
/// names are the user's) is quoted instead of breaking the columns.
fn csv_text(rows: impl FnOnce(&mut csv::Writer<Vec<u8>>) -> csv::Result<()>) -> String {
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    // Writing into memory does not fail; an error here would be a bug in the
    // rows (a record of the wrong length), and leaves the rows written so far.
    let _ = rows(&mut w);
    let bytes = w.into_inner().unwrap_or_default();
    String::from_utf8(bytes).unwrap_or_default()
}

fn csv_row(w: &mut csv::Writer<Vec<u8>>, name: &str, s: &Stats, kind: &str) -> csv::Result<()> {
    w.write_record([
        name,
        &s.n.to_string(),
        &Num(s.mean).to_string(),
        &Num(s.sd).to_string(),
        &Num(s.min).to_string(),
        &Num(s.max).to_string(),
        kind,
    ])
}

/// `ensemble.csv`: one row per scalar measure, then one per profile entry
/// (`packing.profile[3]`); booleans have kind `percent` (their mean is the
/// percentage of beds where they hold).
pub fn ensemble_csv(a: &Aggregate) -> String {
    csv_text(|w| {
        w.write_record(CSV_HEADER.split(','))?;
        for m in &a.measures {
            csv_row(w, &m.name, &m.stats, m.kind.as_str())?;
        }
        for s in &a.series {
            for (k, e) in s.entries.iter().enumerate() {
                csv_row(w, &format!("{}[{k}]", s.name), e, Kind::Value.as_str())?;
            }
        }
        Ok(())
    })
}

/// `histograms.csv`: `name,bin,count,fraction`, counts summed over the beds.
pub fn histograms_csv(a: &Aggregate) -> String {
    csv_text(|w| {
        w.write_record(["name", "bin", "count", "fraction"])?;
        for h in &a.histograms {
            for (k, (c, f)) in h.counts.iter().zip(&h.fraction).enumerate() {
                w.write_record([
                    h.name.as_str(),
                    &k.to_string(),
                    &Num(*c).to_string(),
                    &Num(*f).to_string(),
                ])?;
            }
        }
        Ok(())
    })
}

/// Decimals that show `x` to about `sig` significant digits.
fn decimals(x: f64, sig: i32) -> usize {
    if x == 0.0 || !x.is_finite() {
        return 0;
    }
    let e = x.abs().log10().floor() as i32;
    (sig - 1 - e).clamp(0, 9) as usize
}

/// A number with `d` decimals, trailing zeros kept (a column of a table).
fn fixed(x: f64, d: usize) -> String {
    let s = format!("{x:.d$}");
    // "-0.000" reads as a sign error.
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}

/// Decimals for one row: the mean to 4 significant digits, the sd to 2.
fn row_decimals(s: &Stats, kind: Kind) -> usize {
    let integers = [s.mean, s.min, s.max].iter().all(|v| v.fract() == 0.0) && s.sd == 0.0;
    if integers {
        return 0;
    }
    if kind == Kind::Percent {
        return 1;
    }
    let scale = s.mean.abs().max(s.min.abs()).max(s.max.abs());
    decimals(scale, 4).max(if s.sd > 0.0 { decimals(s.sd, 2) } else { 0 })
}

/// The cells `min`, `mean ± sd`, `max` of a measure.
pub fn cells(s: &Stats, kind: Kind) -> [String; 3] {
    let d = row_decimals(s, kind);
    // Extremes are values of single beds: whole numbers (counts) stay whole.
    let extreme = |x: f64| fixed(x, if x.fract() == 0.0 { 0 } else { d });
    [
        extreme(s.min),
        format!("{} ± {}", fixed(s.mean, d), fixed(s.sd, d)),
        extreme(s.max),
    ]
}

/// The row name of a measure: its key, with the unit of booleans.
pub fn label(m: &Measure, beds: u64) -> String {
    let mut l = m.name.clone();
    if m.kind == Kind::Percent {
        l.push_str(" (% of beds)");
    }
    if m.stats.n != beds {
        let _ = write!(l, " (n = {})", m.stats.n);
    }
    l
}

/// One line describing the system of a config.
pub fn describe(c: &Config) -> String {
    let b = &c.container;
    let boxed = if let Some(n) = b.diameters {
        format!("cube of {n} largest diameters")
    } else if let (Some(w), Some(h)) = (b.width, b.height) {
        match (c.dim, b.depth) {
            (3, d) => format!("{w} × {} × {h}", d.unwrap_or(w)),
            _ => format!("{w} × {h}"),
        }
    } else {
        format!("{} box", b.preset.as_deref().unwrap_or("thesis"))
    };
    let sides = if b.periodic {
        "periodic sides"
    } else {
        "walls"
    };
    let species: Vec<String> = c
        .species
        .iter()
        .map(|s| {
            let size = match s.radius {
                Some(r) => format!("r = {r}"),
                None => "size distribution".into(),
            };
            format!("{size} (ratio {})", s.ratio)
        })
        .collect();
    let fill = match c.fill.count {
        Some(n) => format!("{n} particles"),
        None => "filled to the roof".into(),
    };
    format!(
        "{}D, {boxed} ({sides}), {fill}; species: {}",
        c.dim,
        species.join(", ")
    )
}

/// `1 bed`, `2 beds`.
fn beds(n: u64) -> String {
    if n == 1 {
        "1 bed".into()
    } else {
        format!("{n} beds")
    }
}

/// `ensemble.md`: the human table.
pub fn ensemble_md(h: &Header, a: &Aggregate) -> String {
    let mut t = String::new();
    let title = match &h.sweep {
        Some((p, label, _)) => format!("Ensemble of {}: {p} = {label}", beds(a.replicates)),
        None => format!("Ensemble of {}", beds(a.replicates)),
    };
    let _ = writeln!(t, "# {title}\n");
    let _ = writeln!(t, "{}.", describe(h.config));
    let _ = write!(t, "Master seed {}", h.config.seed);
    if let Some((k, m)) = h.shard {
        let _ = write!(
            t,
            "; shard {k}/{m} (replicates i with i mod {m} = {k}; `packbed merge` joins the shards)"
        );
    }
    let _ = writeln!(t, ".\n");
    let _ = writeln!(t, "| measure | min | mean ± sd | max |");
    let _ = writeln!(t, "| --- | ---: | ---: | ---: |");
    for m in &a.measures {
        let [lo, mid, hi] = cells(&m.stats, m.kind);
        let _ = writeln!(t, "| {} | {lo} | {mid} | {hi} |", label(m, a.replicates));
    }
    let _ = writeln!(
        t,
        "\nsd is the sample standard deviation (n − 1); \"% of beds\" rows are yes/no measures."
    );
    for hist in &a.histograms {
        let _ = writeln!(
            t,
            "\n## {} (summed over {}, fraction of all entries)\n",
            hist.name,
            beds(hist.replicates)
        );
        let bins: Vec<String> = (0..hist.counts.len()).map(|k| k.to_string()).collect();
        let _ = writeln!(t, "| bin | {} |", bins.join(" | "));
        let _ = writeln!(t, "| --- |{}", " ---: |".repeat(bins.len()));
        let f: Vec<String> = hist.fraction.iter().map(|v| fixed(*v, 4)).collect();
        let _ = writeln!(t, "| fraction | {} |", f.join(" | "));
    }
    if !a.series.is_empty() {
        let names: Vec<&str> = a.series.iter().map(|s| s.name.as_str()).collect();
        let _ = writeln!(
            t,
            "\nProfiles ({}) are in `ensemble.csv` and `ensemble.json`, entry by entry.",
            names.join(", ")
        );
    }
    t
}

/// One value of a sweep with its statistics, for the sweep tables.
#[derive(Clone, Debug)]
pub struct SweepRow<'a> {
    /// Label of the value.
    pub label: &'a str,
    /// Its ensemble.
    pub aggregate: &'a Aggregate,
}

/// `sweep.csv`: `index,label,name,n,mean,sd,min,max,kind`, one row per value and
/// scalar measure.
pub fn sweep_csv(rows: &[SweepRow]) -> String {
    csv_text(|w| {
        w.write_record([
            "index", "label", "name", "n", "mean", "sd", "min", "max", "kind",
        ])?;
        for (i, r) in rows.iter().enumerate() {
            for m in &r.aggregate.measures {
                let s = &m.stats;
                w.write_record([
                    i.to_string(),
                    r.label.to_string(),
                    m.name.clone(),
                    s.n.to_string(),
                    Num(s.mean).to_string(),
                    Num(s.sd).to_string(),
                    Num(s.min).to_string(),
                    Num(s.max).to_string(),
                    m.kind.as_str().to_string(),
                ])?;
            }
        }
        Ok(())
    })
}

/// Measures shown side by side in the first table of `sweep.md`, if present.
const HEADLINE: [&str; 4] = [
    "packing.global",
    "packing.bulk",
    "coordination.mean",
    "coordination.mean_bulk",
];

/// `sweep.md`: a headline table (one row per value; packing, coordination and
/// every yes/no measure such as percolation as % of beds), then one table per
/// measure in the source study's layout with one row per value.
pub fn sweep_md(parameter: &str, base: &Config, rows: &[SweepRow]) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "# Sweep over {parameter}\n");
    let _ = writeln!(t, "{}.", describe(base));
    let _ = writeln!(
        t,
        "Every value ran the same replicate seeds (master seed {}).\n",
        base.seed
    );
    let Some(first) = rows.first() else {
        return t;
    };
    let mut headline: Vec<&str> = HEADLINE
        .iter()
        .copied()
        .filter(|h| first.aggregate.measures.iter().any(|m| m.name == *h))
        .collect();
    for m in &first.aggregate.measures {
        if m.kind == Kind::Percent && !m.name.ends_with("_empty") {
            headline.push(&m.name);
        }
    }
    let find = |a: &'_ Aggregate, name: &str| a.measures.iter().find(|m| m.name == name).cloned();
    let _ = writeln!(
        t,
        "| {parameter} | beds | {} |",
        headline
            .iter()
            .map(|h| match find(first.aggregate, h) {
                Some(m) if m.kind == Kind::Percent => format!("{h} (% of beds)"),
                _ => h.to_string(),
            })
            .collect::<Vec<_>>()
            .join(" | ")
    );
    let _ = writeln!(t, "| --- | ---: |{}", " ---: |".repeat(headline.len()));
    for r in rows {
        let cells: Vec<String> = headline
            .iter()
            .map(|h| match find(r.aggregate, h) {
                Some(m) => cells(&m.stats, m.kind)[1].clone(),
                None => "–".into(),
            })
            .collect();
        let _ = writeln!(
            t,
            "| {} | {} | {} |",
            r.label,
            r.aggregate.replicates,
            cells.join(" | ")
        );
    }
    // Every measure, in the order of the first value's ensemble, then any that
    // only later values have.
    let mut names: Vec<String> = Vec::new();
    for r in rows {
        for m in &r.aggregate.measures {
            if !names.contains(&m.name) {
                names.push(m.name.clone());
            }
        }
    }
    for name in &names {
        let _ = writeln!(t, "\n## {name}\n");
        let _ = writeln!(t, "| {parameter} | min | mean ± sd | max |");
        let _ = writeln!(t, "| --- | ---: | ---: | ---: |");
        for r in rows {
            match find(r.aggregate, name) {
                Some(m) => {
                    let [lo, mid, hi] = cells(&m.stats, m.kind);
                    let unit = if m.kind == Kind::Percent { " %" } else { "" };
                    let _ = writeln!(t, "| {} | {lo}{unit} | {mid}{unit} | {hi}{unit} |", r.label);
                }
                None => {
                    let _ = writeln!(t, "| {} | – | – | – |", r.label);
                }
            }
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn st(n: u64, mean: f64, sd: f64, min: f64, max: f64) -> Stats {
        Stats {
            n,
            mean,
            sd,
            min,
            max,
        }
    }

    #[test]
    fn table_cells() {
        assert_eq!(
            cells(&st(500, 0.58321, 0.01234, 0.5512, 0.6102), Kind::Value),
            ["0.5512", "0.5832 ± 0.0123", "0.6102"]
        );
        assert_eq!(
            cells(&st(3, 4.393, 0.2, 4.0, 4.7), Kind::Value),
            ["4", "4.393 ± 0.200", "4.700"]
        );
        assert_eq!(
            cells(&st(4, 75.0, 50.0, 0.0, 100.0), Kind::Percent)[1],
            "75.0 ± 50.0"
        );
        assert_eq!(
            cells(&st(4, 120.0, 0.0, 120.0, 120.0), Kind::Value)[1],
            "120 ± 0"
        );
        assert_eq!(fixed(-0.00001, 3), "0.000");
    }

    #[test]
    fn csv_rows() {
        let a = Aggregate {
            replicates: 2,
            measures: vec![Measure {
                name: "packing.global".into(),
                kind: Kind::Value,
                stats: st(2, 0.5, 0.25, 0.25, 0.75),
            }],
            ..Default::default()
        };
        assert_eq!(
            ensemble_csv(&a),
            "name,n,mean,sd,min,max,kind\npacking.global,2,0.5,0.25,0.25,0.75,value\n"
        );
    }
}
