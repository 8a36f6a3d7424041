//! The files of an ensemble: `ensemble.json`, `ensemble.csv`, `histograms.csv`,
//! the human table `ensemble.md` (the source study's layout: one row per
//! measure, columns min, mean ± sd, max), and for sweeps `sweep.csv` and
//! `sweep.md` (one row per value). Every function here is pure: the same
//! aggregate gives the same bytes.

use super::stats::{Aggregate, Kind, MeasureStats, Stats};
use crate::analysis::dimensions::filtration_unit;
use crate::config::Config;
use crate::error::markdown_cell;
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
    let length = length_symbol(h.config);
    for m in &a.measures {
        let mut e = stats_json(&m.stats);
        e.insert(0, ("kind", json!(m.kind.as_str())));
        if let Some(u) = filtration_unit(&m.name, length) {
            e.insert(1, ("unit", json!(u)));
        }
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
    if let Some(c) = scientific_cells(s, kind) {
        return c;
    }
    let d = row_decimals(s, kind);
    // Extremes are values of single beds: whole numbers (counts) stay whole.
    let extreme = |x: f64| fixed(x, if x.fract() == 0.0 { 0 } else { d });
    [
        extreme(s.min),
        format!("{} ± {}", fixed(s.mean, d), fixed(s.sd, d)),
        extreme(s.max),
    ]
}

/// The cells of a measure far from 1 in scientific notation (mean to 4
/// significant digits, sd to 2), or `None`: in fixed notation a cake
/// resistance of 1.5e9 m/kg reads as ten digits, and a permeability of
/// 7.5e-13 m² as zero. Whole numbers (counts) stay in fixed notation.
fn scientific_cells(s: &Stats, kind: Kind) -> Option<[String; 3]> {
    let scale = s.mean.abs().max(s.min.abs()).max(s.max.abs());
    // Counts are whole in every bed; a continuous measure never is, except
    // beyond 2^53 where every float is.
    let whole = s.min.fract() == 0.0 && s.max.fract() == 0.0 && scale < 1e15;
    let far = scale >= 1e6 || (scale > 0.0 && scale < 1e-3);
    (kind == Kind::Value && far && !whole && scale.is_finite()).then(|| {
        [
            format!("{:.3e}", s.min),
            format!("{:.3e} ± {:.1e}", s.mean, s.sd),
            format!("{:.3e}", s.max),
        ]
    })
}

/// The row name of a measure: its key, with the unit of booleans and, when
/// it is not defined in every bed (a bulk measure of a bed without a bulk), in
/// how many of the `beds` it is.
pub fn label(m: &MeasureStats, beds: u64) -> String {
    let mut l = m.name.clone();
    if m.kind == Kind::Percent {
        l.push_str(" (% of beds)");
    }
    if m.stats.n != beds {
        let _ = write!(l, " ({} of {beds} beds)", m.stats.n);
    }
    l
}

/// The cake properties that lead `ensemble.md`, when present, with what they
/// are: the numbers a filtration engineer looks for first.
pub const CAKE: [(&str, &str); 13] = [
    ("cake.porosity", "porosity (bulk)"),
    ("cake.d32", "Sauter diameter d32 (bulk)"),
    ("cake.specific_surface", "specific surface, 1/length (bulk)"),
    (
        "cake.k_kozeny_carman",
        "Kozeny–Carman permeability k (bulk)",
    ),
    (
        "cake.k_kozeny_carman_m2",
        "Kozeny–Carman permeability k, m²",
    ),
    ("permeability.k_z", "network permeability k along z"),
    ("permeability.k_x", "network permeability k along x"),
    ("permeability.k_y", "network permeability k along y"),
    ("cake.height", "cake height"),
    ("cake.solids_per_area", "solid volume per floor area"),
    (
        "cake.solids_mass_per_area",
        "solid mass per floor area, kg/m²",
    ),
    (
        "cake.specific_resistance",
        "specific cake resistance α, m/kg",
    ),
    ("cake.whole.porosity", "porosity (whole cake)"),
];

/// The figures of a filtration that follow the cake in `ensemble.md` (and
/// lead `sweep.md`'s per-measure tables), when present, with what they are;
/// their units come from [`filtration_unit`].
pub const FILTRATION: [(&str, &str); 17] = [
    ("filtration.alpha_fit_m_per_kg", "α fitted to Ruth's line"),
    (
        "filtration.alpha_network_m_per_kg",
        "α of the network (rise of R over rise of mass)",
    ),
    (
        "filtration.r_medium_fit_per_m",
        "R_m fitted to Ruth's line (intercept)",
    ),
    (
        "filtration.r_medium_clogged_per_m",
        "R_m in place (with what lodged in it)",
    ),
    ("filtration.r_medium_per_m", "R_m of the clean medium"),
    (
        "filtration.ruth_departure",
        "Ruth's line: rms departure over mean",
    ),
    ("filtration.final.time_s", "time at the end"),
    (
        "filtration.final.volume_m3_per_m2",
        "filtrate volume per area at the end",
    ),
    ("filtration.final.pressure_pa", "pressure drop at the end"),
    ("filtration.final.cake_height_m", "cake height at the end"),
    (
        "filtration.final.mass_kg_per_m2",
        "solids per area at the end",
    ),
    (
        "capture.passed_fraction",
        "passed the medium, fraction of fed",
    ),
    (
        "capture.lodged_fraction",
        "lodged in the medium, fraction of fed",
    ),
    ("capture.cake_fraction", "in the cake, fraction of fed"),
    ("capture.x50", "cut size x50 (grade efficiency 1/2)"),
    ("capture.passed", "passed the medium"),
    ("capture.lodged", "lodged in the medium"),
];

/// The bed's length unit as the tables print it.
fn length_symbol(c: &Config) -> &'static str {
    c.analysis
        .length_unit
        .map_or("length units", crate::config::LengthUnit::symbol)
}

/// Whether a row of `ensemble.md` says nothing about the beds, so that the
/// table is left with results (`ensemble.csv` keeps every row). By name
/// first, so that a result that happens to agree in every bed (a lattice's
/// packing fraction, a chain in every bed) is never dropped:
/// - settings and indices, whatever their values: slab widths (`*.slab`, set
///   from the largest diameter drawn), species indices (`*.species`), the
///   fluid's viscosity and the conductance factor;
/// - bookkeeping counts (`counts.*`, `species.*`, `*.bodies`, `*.particles`)
///   that are the same whole number in every bed: they restate the config
///   (`fill.count`, a single species, no redrops);
/// - the size distribution the config asked for (`*.requested.*`,
///   `*.requested_*`), which the beds' placed one is held against;
/// - flags that only explain a null (`*_empty`) when no bed raised one.
pub fn is_uninformative(m: &MeasureStats, beds: u64) -> bool {
    let last = m.name.rsplit('.').next().unwrap_or("");
    if matches!(
        last,
        "slab" | "species" | "viscosity" | "conductance" | "conductance_factor"
    ) {
        return true;
    }
    if m.name
        .split('.')
        .any(|seg| seg == "requested" || seg.starts_with("requested_"))
    {
        return true;
    }
    let s = &m.stats;
    let same_whole = s.n == beds && s.min == s.max && s.min.fract() == 0.0;
    let bookkeeping = m.name.starts_with("counts.")
        || m.name.starts_with("species.")
        || matches!(last, "bodies" | "particles");
    if bookkeeping && m.kind == Kind::Value && same_whole {
        return true;
    }
    m.kind == Kind::Percent && last.ends_with("_empty") && s.max == 0.0
}

/// Arrays of records that are curves (one record per point, e.g. the size
/// distribution's 25 points of `psd.table`): a row per field and point would
/// bury the table, so they go with the profiles, to `ensemble.csv`.
const CURVES: [&str; 4] = [
    "psd.table",
    "filtration.checkpoints",
    "capture.classes",
    "capture.depth_profile",
];

/// The curves of a filtration: in `sweep.md` too they are left to
/// `sweep.csv` (a table per checkpoint and field would bury the figures).
const FILTRATION_CURVES: [&str; 3] = [
    "filtration.checkpoints",
    "capture.classes",
    "capture.depth_profile",
];

/// The curve a measure is a point of, if any.
fn curve_of(name: &str) -> Option<&'static str> {
    CURVES.iter().copied().find(|c| {
        name.strip_prefix(c)
            .is_some_and(|rest| rest.starts_with('['))
    })
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
        Some((p, label, _)) => format!(
            "Ensemble of {}: {} = {}",
            beds(a.replicates),
            markdown_cell(p),
            markdown_cell(label)
        ),
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
    let _ = writeln!(
        t,
        "Each row: min, mean ± sample standard deviation (n − 1), max over the beds; \
         \"(k of N beds)\" marks a quantity defined in k beds only (e.g. a bulk \
         measure of a bed without a bulk region); \"% of beds\" rows are yes/no measures.\n"
    );
    let find = |name: &str| a.measures.iter().find(|m| m.name == name);
    let cake: Vec<(&MeasureStats, &str)> = CAKE
        .iter()
        .filter_map(|&(key, what)| find(key).map(|m| (m, what)))
        .collect();
    if !cake.is_empty() {
        let _ = writeln!(t, "## Cake\n");
        let _ = writeln!(t, "| property | key | min | mean ± sd | max |");
        let _ = writeln!(t, "| --- | --- | ---: | ---: | ---: |");
        for (m, what) in &cake {
            let [lo, mid, hi] = cells(&m.stats, m.kind);
            let key = markdown_cell(&label(m, a.replicates));
            let _ = writeln!(t, "| {what} | {key} | {lo} | {mid} | {hi} |");
        }
    }
    let filtration: Vec<(&MeasureStats, &str)> = FILTRATION
        .iter()
        .filter_map(|&(key, what)| find(key).map(|m| (m, what)))
        .collect();
    if !filtration.is_empty() {
        let length = length_symbol(h.config);
        let gap = if cake.is_empty() { "" } else { "\n" };
        let _ = writeln!(t, "{gap}## Filtration\n");
        let _ = writeln!(t, "| figure | unit | key | min | mean ± sd | max |");
        let _ = writeln!(t, "| --- | --- | --- | ---: | ---: | ---: |");
        for (m, what) in &filtration {
            let [lo, mid, hi] = cells(&m.stats, m.kind);
            let key = markdown_cell(&label(m, a.replicates));
            let unit = markdown_cell(&filtration_unit(&m.name, length).unwrap_or_default());
            let _ = writeln!(t, "| {what} | {unit} | {key} | {lo} | {mid} | {hi} |");
        }
        let _ = writeln!(
            t,
            "\nThe filtration in SI; the capture's sizes in {length}. Per checkpoint and per size class in `ensemble.csv`."
        );
    }
    if !cake.is_empty() || !filtration.is_empty() {
        let _ = writeln!(t, "\n## All measures\n");
    }
    let _ = writeln!(t, "| measure | min | mean ± sd | max |");
    let _ = writeln!(t, "| --- | ---: | ---: | ---: |");
    let mut left_out = Vec::new();
    let mut curves: Vec<&str> = Vec::new();
    for m in &a.measures {
        if CAKE.iter().any(|&(key, _)| key == m.name)
            || FILTRATION.iter().any(|&(key, _)| key == m.name)
        {
            continue;
        }
        if let Some(c) = curve_of(&m.name) {
            if !curves.contains(&c) {
                curves.push(c);
            }
            continue;
        }
        if is_uninformative(m, a.replicates) {
            let unit = if m.kind == Kind::Percent { " %" } else { "" };
            left_out.push(match m.stats.min == m.stats.max {
                true => format!(
                    "{} = {}{unit}",
                    markdown_cell(&m.name),
                    cells(&m.stats, m.kind)[0]
                ),
                false => markdown_cell(&m.name),
            });
            continue;
        }
        let [lo, mid, hi] = cells(&m.stats, m.kind);
        let _ = writeln!(
            t,
            "| {} | {lo} | {mid} | {hi} |",
            markdown_cell(&label(m, a.replicates))
        );
    }
    if !left_out.is_empty() {
        let _ = writeln!(
            t,
            "\nLeft out, as settings or as bookkeeping the same in every bed (in `ensemble.csv`): {}.",
            left_out.join(", ")
        );
    }
    for hist in &a.histograms {
        let _ = writeln!(
            t,
            "\n## {} (summed over {}, fraction of all entries)\n",
            markdown_cell(&hist.name),
            beds(hist.replicates)
        );
        let bins: Vec<String> = (0..hist.counts.len()).map(|k| k.to_string()).collect();
        let _ = writeln!(t, "| bin | {} |", bins.join(" | "));
        let _ = writeln!(t, "| --- |{}", " ---: |".repeat(bins.len()));
        let f: Vec<String> = hist.fraction.iter().map(|v| fixed(*v, 4)).collect();
        let _ = writeln!(t, "| fraction | {} |", f.join(" | "));
    }
    if !a.series.is_empty() || !curves.is_empty() {
        let names: Vec<String> = a
            .series
            .iter()
            .map(|s| s.name.as_str())
            .chain(curves)
            .map(markdown_cell)
            .collect();
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

/// Yes/no keys that are settings echoed in the summary, not measures: the
/// same in every bed, they say nothing on screen or in a headline table.
pub const SETTINGS: [&str; 1] = ["drainage.trapping"];

/// Measures shown side by side in the first table of `sweep.md`, if present.
const HEADLINE: [&str; 13] = [
    "cake.porosity",
    "cake.d32",
    "cake.k_kozeny_carman",
    "permeability.k_z",
    "cake.specific_resistance",
    "packing.global",
    "packing.bulk",
    "coordination.mean",
    "coordination.mean_bulk",
    "drainage.residual_saturation",
    "agglomeration.bonds_per_particle",
    "agglomeration.agglomerates",
    "agglomeration.fraction_in_agglomerates",
];

/// Filtration figures shown in the first table of `sweep.md`, after
/// [`HEADLINE`]'s, if present.
const SWEEP_FILTRATION: [&str; 5] = [
    "filtration.alpha_fit_m_per_kg",
    "filtration.r_medium_fit_per_m",
    "filtration.final.time_s",
    "capture.passed_fraction",
    "capture.x50",
];

/// `sweep.md`: a headline table (one row per value; the cake, packing,
/// coordination and every yes/no result such as percolation as % of beds,
/// the search caps left to the tables below), then one table per
/// measure in the source study's layout with one row per value.
pub fn sweep_md(parameter: &str, base: &Config, rows: &[SweepRow]) -> String {
    let mut t = String::new();
    let parameter = markdown_cell(parameter);
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
        .chain(&SWEEP_FILTRATION)
        .copied()
        .filter(|h| first.aggregate.measures.iter().any(|m| m.name == *h))
        .collect();
    let length = length_symbol(base);
    // A filtration figure's key with its unit.
    let with_unit = |name: &str| match filtration_unit(name, length) {
        Some(u) => format!("{name} ({u})"),
        None => name.to_string(),
    };
    for m in &first.aggregate.measures {
        // The caps of the chain search are bookkeeping, not results: they
        // stay in the per-measure tables below.
        if m.kind == Kind::Percent
            && !m.name.ends_with("_empty")
            && !m.name.ends_with("cap_hit")
            && !SETTINGS.contains(&m.name.as_str())
        {
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
                Some(m) if m.kind == Kind::Percent => format!("{} (% of beds)", markdown_cell(h)),
                _ => markdown_cell(&with_unit(h)),
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
            markdown_cell(r.label),
            r.aggregate.replicates,
            cells.join(" | ")
        );
    }
    // Every measure, in the order of the first value's ensemble, then any that
    // only later values have.
    let mut names: Vec<String> = Vec::new();
    let mut curves: Vec<&str> = Vec::new();
    for r in rows {
        for m in &r.aggregate.measures {
            if let Some(c) = curve_of(&m.name).filter(|c| FILTRATION_CURVES.contains(c)) {
                if !curves.contains(&c) {
                    curves.push(c);
                }
                continue;
            }
            if !names.contains(&m.name) {
                names.push(m.name.clone());
            }
        }
    }
    for name in &names {
        let _ = writeln!(t, "\n## {}\n", markdown_cell(&with_unit(name)));
        let _ = writeln!(t, "| {parameter} | min | mean ± sd | max |");
        let _ = writeln!(t, "| --- | ---: | ---: | ---: |");
        for r in rows {
            match find(r.aggregate, name) {
                Some(m) => {
                    let [lo, mid, hi] = cells(&m.stats, m.kind);
                    let unit = if m.kind == Kind::Percent { " %" } else { "" };
                    let _ = writeln!(
                        t,
                        "| {} | {lo}{unit} | {mid}{unit} | {hi}{unit} |",
                        markdown_cell(r.label)
                    );
                }
                None => {
                    let _ = writeln!(t, "| {} | – | – | – |", markdown_cell(r.label));
                }
            }
        }
    }
    if !curves.is_empty() {
        let _ = writeln!(
            t,
            "\nPer checkpoint and per size class ({}): in `sweep.csv`, entry by entry.",
            curves.join(", ")
        );
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

    /// The min, mean ± sd and max cells of each `(stats, kind)` are `want`.
    fn assert_cells(cases: &[(Stats, Kind, [&str; 3])]) {
        for (s, kind, want) in cases {
            assert_eq!(cells(s, *kind), *want, "{s:?}");
        }
    }

    /// The mean ± sd cell of each `(stats, kind)` is `want`.
    fn assert_mean_cells(cases: &[(Stats, Kind, &str)]) {
        for (s, kind, want) in cases {
            assert_eq!(cells(s, *kind)[1], *want, "{s:?}");
        }
    }

    #[test]
    fn table_cells() {
        assert_cells(&[
            (
                st(500, 0.58321, 0.01234, 0.5512, 0.6102),
                Kind::Value,
                ["0.5512", "0.5832 ± 0.0123", "0.6102"],
            ),
            (
                st(3, 4.393, 0.2, 4.0, 4.7),
                Kind::Value,
                ["4", "4.393 ± 0.200", "4.700"],
            ),
        ]);
        assert_mean_cells(&[
            (st(4, 75.0, 50.0, 0.0, 100.0), Kind::Percent, "75.0 ± 50.0"),
            (st(4, 120.0, 0.0, 120.0, 120.0), Kind::Value, "120 ± 0"),
        ]);
        assert_eq!(fixed(-0.00001, 3), "0.000");
    }

    fn measure(name: &str, kind: Kind, stats: Stats) -> MeasureStats {
        MeasureStats {
            name: name.into(),
            kind,
            stats,
        }
    }

    /// An aggregate of `replicates` beds holding `measures`.
    fn aggregate(replicates: u64, measures: &[(&str, Kind, Stats)]) -> Aggregate {
        Aggregate {
            replicates,
            measures: measures
                .iter()
                .map(|&(name, kind, s)| measure(name, kind, s))
                .collect(),
            ..Default::default()
        }
    }

    #[test]
    fn far_from_one_in_scientific_notation() {
        // A cake resistance and a permeability in m², as a PSD ensemble gave.
        assert_cells(&[(
            st(
                10,
                1.4830690125e9,
                2.232717205e8,
                1.1412879505e9,
                1.8547281565e9,
            ),
            Kind::Value,
            ["1.141e9", "1.483e9 ± 2.2e8", "1.855e9"],
        )]);
        assert_mean_cells(&[
            (
                st(10, 7.494e-13, 1.272e-13, 5.741e-13, 9.802e-13),
                Kind::Value,
                "7.494e-13 ± 1.3e-13",
            ),
            // Counts stay whole however large.
            (
                st(2, 2500000.0, 0.0, 2500000.0, 2500000.0),
                Kind::Value,
                "2500000 ± 0",
            ),
            (
                st(2, 2500000.5, 0.75, 2500000.0, 2500001.0),
                Kind::Value,
                "2500000.50 ± 0.75",
            ),
        ]);
    }

    #[test]
    fn rows_say_in_how_many_beds_they_are_defined() {
        let m = measure("packing.bulk", Kind::Value, st(9, 0.6, 0.01, 0.59, 0.61));
        assert_eq!(label(&m, 10), "packing.bulk (9 of 10 beds)");
        assert_eq!(label(&m, 9), "packing.bulk");
    }

    #[test]
    fn settings_and_constant_bookkeeping_are_uninformative() {
        use std::f64::consts::FRAC_PI_6;
        let same = |x: f64| st(10, x, 0.0, x, x);
        let (v, p) = (Kind::Value, Kind::Percent);
        let dropped = [
            // Settings and indices, whatever their values.
            ("packing.profile.slab", v, st(10, 15.8, 0.5, 14.6, 16.4)),
            ("coordination.by_species.powder.species", v, same(0.0)),
            // Bookkeeping that restates the config.
            ("counts.particles", v, same(1500.0)),
            ("species.powder.placed", v, same(1500.0)),
            ("coordination.by_species.powder.bodies", v, same(1500.0)),
            // The size distribution asked for.
            ("psd.requested.d50", v, same(20.0)),
            ("psd.table[3].requested_mass_percent_passing", v, same(12.5)),
            // A flag that explains a null, when no bed raised it.
            ("packing.bulk_region_empty", p, same(0.0)),
        ];
        let kept = [
            // Bookkeeping that varies.
            ("counts.particles", v, st(10, 1490.5, 3.0, 1486.0, 1495.0)),
            // A bed missing the count: the row says so.
            ("counts.particles", v, st(9, 1500.0, 0.0, 1500.0, 1500.0)),
            // Results that agree in every bed stay (a simple cubic lattice: π/6).
            ("packing.global", v, same(FRAC_PI_6)),
            ("percolation.large_bodies", v, same(750.0)),
            ("percolation.spanning_clusters", v, same(1.0)),
            ("percolation.spans", p, same(100.0)),
            // The size distribution placed.
            ("psd.placed.d50", v, st(10, 19.5, 0.3, 19.1, 20.0)),
            // A flag raised by a bed.
            (
                "packing.bulk_region_empty",
                p,
                st(10, 10.0, 31.6, 0.0, 100.0),
            ),
        ];
        for (cases, drop) in [(dropped, true), (kept, false)] {
            for (name, kind, s) in cases {
                let m = measure(name, kind, s);
                assert_eq!(is_uninformative(&m, 10), drop, "{m:?}");
            }
        }
    }

    #[test]
    fn sweep_md_leads_with_the_cake_and_leaves_the_caps_below() {
        let a = aggregate(
            4,
            &[
                ("packing.global", Kind::Value, st(4, 0.6, 0.01, 0.59, 0.61)),
                ("cake.porosity", Kind::Value, st(4, 0.38, 0.01, 0.37, 0.39)),
                (
                    "percolation.spans",
                    Kind::Percent,
                    st(4, 75.0, 50.0, 0.0, 100.0),
                ),
                (
                    "percolation.cap_hit",
                    Kind::Percent,
                    st(4, 100.0, 0.0, 100.0, 100.0),
                ),
                (
                    "drainage.trapping",
                    Kind::Percent,
                    st(4, 100.0, 0.0, 100.0, 100.0),
                ),
                (
                    "agglomeration.agglomerates",
                    Kind::Value,
                    st(4, 20.0, 3.0, 17.0, 24.0),
                ),
            ],
        );
        let rows = [SweepRow {
            label: "batch A",
            aggregate: &a,
        }];
        let md = sweep_md("species[0].size.table", &Config::default(), &rows);
        let head = md
            .lines()
            .find(|l| l.starts_with("| species[0].size.table |"))
            .unwrap();
        assert_eq!(
            head,
            "| species[0].size.table | beds | cake.porosity | packing.global | agglomeration.agglomerates | percolation.spans (% of beds) |"
        );
        // The cap is still reported, in its own table further down.
        assert!(md.contains("percolation.cap_hit"));
    }

    #[test]
    fn ensemble_md_leads_with_the_cake() {
        let config = Config::default();
        let h = Header {
            config: &config,
            runs: 10,
            shard: None,
            sweep: None,
        };
        let v = Kind::Value;
        let mut a = aggregate(
            10,
            &[
                ("counts.particles", v, st(10, 1500.0, 0.0, 1500.0, 1500.0)),
                ("cake.porosity", v, st(10, 0.3861, 0.011, 0.3712, 0.4041)),
                ("cake.d32", v, st(9, 29.57, 1.34, 27.81, 31.39)),
                ("packing.global", v, st(10, 0.3626, 0.0197, 0.3352, 0.3964)),
                ("permeability.k_z", v, st(10, 0.81, 0.1, 0.7, 0.95)),
            ],
        );
        for k in 0..25 {
            let name = format!("psd.table[{k}].placed_mass_percent_passing");
            let stats = st(
                10,
                4.0 * k as f64,
                0.5,
                4.0 * k as f64 - 1.0,
                4.0 * k as f64 + 1.0,
            );
            a.measures.push(measure(&name, Kind::Value, stats));
        }
        let md = ensemble_md(&h, &a);
        // A curve goes with the profiles, not a row per point.
        assert!(!md.contains("| psd.table[3]"), "{md}");
        assert!(
            md.contains("Profiles (psd.table) are in `ensemble.csv`"),
            "{md}"
        );
        let at = |s: &str| md.find(s).unwrap_or_else(|| panic!("{s} not in\n{md}"));
        assert!(at("## Cake") < at("| packing.global |"), "{md}");
        assert!(
            at("| porosity (bulk) | cake.porosity | 0.3712 | 0.3861 ± 0.0110 | 0.4041 |")
                < at("| Sauter diameter d32 (bulk) | cake.d32 (9 of 10 beds) |")
        );
        assert!(at("| cake.d32 (9") < at("| network permeability k along z | permeability.k_z |"));
        // Each row once: the cake is not repeated under all measures.
        assert_eq!(md.matches("cake.porosity").count(), 1, "{md}");
        assert!(!md.contains("| counts.particles |"), "{md}");
        assert!(
            md.contains("(in `ensemble.csv`): counts.particles = 1500."),
            "{md}"
        );
        assert!(md.contains("defined in k beds only"), "{md}");
    }

    #[test]
    fn the_filtration_figures_follow_the_cake_with_their_units() {
        let mut config = Config::default();
        config.analysis.length_unit = Some(crate::config::LengthUnit::Micrometre);
        let v = Kind::Value;
        let a = aggregate(
            3,
            &[
                ("cake.porosity", v, st(3, 0.38, 0.01, 0.37, 0.39)),
                ("capture.x50", v, st(2, 9.5, 0.5, 9.0, 10.0)),
                (
                    "filtration.alpha_fit_m_per_kg",
                    v,
                    st(3, 1.8e9, 5e7, 1.75e9, 1.85e9),
                ),
                (
                    "filtration.final.time_s",
                    v,
                    st(3, 0.026, 0.001, 0.025, 0.027),
                ),
                (
                    "filtration.checkpoints[2].time_s",
                    v,
                    st(3, 0.005, 0.0003, 0.0047, 0.0053),
                ),
            ],
        );
        let h = Header {
            config: &config,
            runs: 3,
            shard: None,
            sweep: None,
        };
        let md = ensemble_md(&h, &a);
        let at = |s: &str| md.find(s).unwrap_or_else(|| panic!("{s} not in\n{md}"));
        assert!(
            at("## Cake") < at("\n## Filtration\n") && at("## Filtration") < at("## All measures")
        );
        at("| α fitted to Ruth's line | m/kg | filtration.alpha_fit_m_per_kg |");
        at("| cut size x50 (grade efficiency 1/2) | µm | capture.x50 (2 of 3 beds) |");
        at("| time at the end | s | filtration.final.time_s |");
        assert!(!md.contains("| filtration.checkpoints[2]"), "{md}");
        let json: Value = serde_json::from_str(&ensemble_json(&h, &a)).unwrap();
        assert_eq!(json["measures"]["capture.x50"]["unit"], "µm");
        assert!(json["measures"]["cake.porosity"].get("unit").is_none());
        let rows = [SweepRow {
            label: "1 bar",
            aggregate: &a,
        }];
        let sweep = sweep_md("filtration.pressure", &config, &rows);
        let head = sweep
            .lines()
            .find(|l| l.starts_with("| filtration.pressure |"))
            .unwrap();
        assert!(head.contains("| capture.x50 (µm) |"), "{head}");
        assert!(
            sweep.contains("\n## filtration.alpha_fit_m_per_kg (m/kg)\n"),
            "{sweep}"
        );
        assert!(!sweep.contains("## filtration.checkpoints"), "{sweep}");
    }

    #[test]
    fn csv_rows() {
        let a = aggregate(
            2,
            &[("packing.global", Kind::Value, st(2, 0.5, 0.25, 0.25, 0.75))],
        );
        assert_eq!(
            ensemble_csv(&a),
            "name,n,mean,sd,min,max,kind\npacking.global,2,0.5,0.25,0.25,0.75,value\n"
        );
    }
}
