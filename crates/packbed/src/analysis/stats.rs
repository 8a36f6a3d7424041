//! Statistics over replicates, computed from the runs' `summary.json` documents:
//! what an ensemble, a merge and a comparison report, and what the ensemble
//! plots draw (so it sits below both `ensemble` and `render`).
//!
//! The summary is walked generically, so every measure added to
//! `analysis::Summary` is included without touching this module:
//! - a number becomes a [`MeasureStats`] (mean ± sample sd, min, max, n);
//! - a boolean becomes the percentage of beds where it is true (a measure of
//!   the 0/100 indicator, so its mean is the percentage);
//! - an array of numbers whose key contains `histogram` is summed over the
//!   replicates and normalised ([`Histogram`]);
//! - any other array of numbers (a profile) gets statistics per entry
//!   ([`ArrayStats`]);
//! - an array of objects that all have distinct `name`s is keyed by name
//!   (`species.large.placed`), other arrays by index (`x[3]`).
//!
//! Replicates are folded in replicate order, never in completion order, so the
//! result is the same bit for bit whatever the threads or shards.

use crate::error::{Error, Result};
use serde_json::{Map, Value};

/// Keys of `summary.json` that are not measures of the bed: identity and
/// settings of the run (the same in every replicate, or the seed), and
/// timings, which are summarised apart ([`TIMING_KEY`]).
const NOT_MEASURES: [&str; 8] = [
    "packbed_version",
    "proof",
    "dim",
    "seed",
    "mode",
    "box",
    "config",
    TIMING_KEY,
];

/// Wall times kept beside a measure rather than under [`TIMING_KEY`] (the
/// filtration's and the compaction's own times): left out of the statistics
/// of the bed, which must be the same bytes whatever machine built the
/// replicates.
const WALL_TIMES: [&str; 2] = ["filtration.seconds", "compaction.seconds"];

/// The key of the wall times in `summary.json`, kept out of the statistics of
/// the bed because they depend on the machine and its load.
pub const TIMING_KEY: &str = "timing";

/// Settings repeated per species (not measured): left out under `species`.
const SPECIES_SETTINGS: [&str; 4] = ["name", "size", "shape", "ratio"];

/// What kind of scalar a measure is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A number measured in each bed.
    Value,
    /// A yes/no property: the statistics are of 100 × the indicator, so the
    /// mean is the percentage of beds where it holds.
    Percent,
}

impl Kind {
    /// Name used in the output files.
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Value => "value",
            Kind::Percent => "percent",
        }
    }
}

/// Mean ± sample standard deviation, extremes and count of some values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stats {
    /// Number of values.
    pub n: u64,
    /// Arithmetic mean (0 for none).
    pub mean: f64,
    /// Sample standard deviation (divisor n − 1; 0 when n < 2).
    pub sd: f64,
    /// Smallest value (0 for none).
    pub min: f64,
    /// Largest value (0 for none).
    pub max: f64,
}

impl Stats {
    /// The statistics of `values`, summed in the order given.
    pub fn of(values: &[f64]) -> Stats {
        let n = values.len();
        if n == 0 {
            return Stats {
                n: 0,
                mean: 0.0,
                sd: 0.0,
                min: 0.0,
                max: 0.0,
            };
        }
        let mean = values.iter().sum::<f64>() / n as f64;
        // Two passes: the textbook one-pass formula loses digits when the spread
        // is small against the mean, as for packing fractions.
        let sd = if n < 2 {
            0.0
        } else {
            let ss: f64 = values.iter().map(|v| (v - mean) * (v - mean)).sum();
            (ss / (n - 1) as f64).sqrt()
        };
        let min = values.iter().copied().fold(f64::INFINITY, f64::min);
        let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Stats {
            n: n as u64,
            mean,
            sd,
            min,
            max,
        }
    }
}

/// A scalar measure over the replicates.
#[derive(Clone, Debug, PartialEq)]
pub struct MeasureStats {
    /// Dotted key, e.g. `packing.global`.
    pub name: String,
    /// Number or percentage of beds.
    pub kind: Kind,
    /// The statistics.
    pub stats: Stats,
}

/// A histogram summed over the replicates.
#[derive(Clone, Debug, PartialEq)]
pub struct Histogram {
    /// Dotted key, e.g. `coordination.histogram`.
    pub name: String,
    /// Replicates that had it.
    pub replicates: u64,
    /// Summed counts per bin (bins beyond a replicate's length count 0 for it).
    pub counts: Vec<f64>,
    /// `counts` divided by their total (all 0 if the total is 0).
    pub fraction: Vec<f64>,
}

/// An array of measures (e.g. a profile), with statistics per entry.
#[derive(Clone, Debug, PartialEq)]
pub struct ArrayStats {
    /// Dotted key, e.g. `packing.profile`.
    pub name: String,
    /// Statistics of entry `k` over the replicates whose array has entry `k`.
    pub entries: Vec<Stats>,
}

/// Everything measured over an ensemble.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Aggregate {
    /// Number of replicates folded in.
    pub replicates: u64,
    /// Scalar measures, in the order of `summary.json`.
    pub measures: Vec<MeasureStats>,
    /// Histograms.
    pub histograms: Vec<Histogram>,
    /// Profiles and other arrays.
    pub series: Vec<ArrayStats>,
}

/// One leaf of a summary.
enum Leaf {
    Number(f64),
    Bool(bool),
    Histogram(Vec<f64>),
    Series(Vec<f64>),
}

/// Values collected per key while folding.
enum Column {
    Scalar(Kind, Vec<f64>),
    Histogram(u64, Vec<f64>),
    Series(Vec<Vec<f64>>),
}

/// Folds the summaries (in replicate order) into statistics. `skip` lists
/// top-level keys left out; [`measures_of`] uses the keys that are not measures.
fn fold(summaries: &[Value], skip: &[&str], only: Option<&str>) -> Result<Aggregate> {
    let mut order: Vec<String> = Vec::new();
    let mut columns: std::collections::HashMap<String, Column> = Default::default();
    for (r, summary) in summaries.iter().enumerate() {
        let mut leaves = Vec::new();
        let Value::Object(top) = summary else {
            return Err(Error::Impossible(format!(
                "replicate summary {r} is not a JSON object"
            )));
        };
        for (key, v) in top {
            let wanted = match only {
                Some(o) => key == o,
                None => !skip.contains(&key.as_str()),
            };
            if wanted {
                flatten(key, v, &mut leaves);
            }
        }
        for (name, leaf) in leaves {
            if only.is_none() && WALL_TIMES.contains(&name.as_str()) {
                continue;
            }
            let col = match columns.get_mut(&name) {
                Some(c) => c,
                None => {
                    order.push(name.clone());
                    let c = match &leaf {
                        Leaf::Number(_) => Column::Scalar(Kind::Value, Vec::new()),
                        Leaf::Bool(_) => Column::Scalar(Kind::Percent, Vec::new()),
                        Leaf::Histogram(_) => Column::Histogram(0, Vec::new()),
                        Leaf::Series(_) => Column::Series(Vec::new()),
                    };
                    columns.entry(name.clone()).or_insert(c)
                }
            };
            match (col, leaf) {
                (Column::Scalar(Kind::Value, v), Leaf::Number(x)) => v.push(x),
                (Column::Scalar(Kind::Percent, v), Leaf::Bool(b)) => {
                    v.push(if b { 100.0 } else { 0.0 })
                }
                (Column::Histogram(n, sum), Leaf::Histogram(h)) => {
                    *n += 1;
                    if sum.len() < h.len() {
                        sum.resize(h.len(), 0.0);
                    }
                    for (s, x) in sum.iter_mut().zip(&h) {
                        *s += x;
                    }
                }
                (Column::Series(per), Leaf::Series(s)) => {
                    if per.len() < s.len() {
                        per.resize(s.len(), Vec::new());
                    }
                    for (p, x) in per.iter_mut().zip(s) {
                        p.push(x);
                    }
                }
                _ => {
                    return Err(Error::Impossible(format!(
                        "summary key `{name}` has a different type in replicate summary {r} than before (summaries of different packbed versions?)"
                    )))
                }
            }
        }
    }
    let mut agg = Aggregate {
        replicates: summaries.len() as u64,
        ..Default::default()
    };
    for name in order {
        match columns.remove(&name) {
            Some(Column::Scalar(kind, v)) => agg.measures.push(MeasureStats {
                name,
                kind,
                stats: Stats::of(&v),
            }),
            Some(Column::Histogram(replicates, counts)) => {
                let total: f64 = counts.iter().sum();
                let fraction = counts
                    .iter()
                    .map(|c| if total > 0.0 { c / total } else { 0.0 })
                    .collect();
                agg.histograms.push(Histogram {
                    name,
                    replicates,
                    counts,
                    fraction,
                })
            }
            Some(Column::Series(per)) => agg.series.push(ArrayStats {
                name,
                entries: per.iter().map(|v| Stats::of(v)).collect(),
            }),
            None => {}
        }
    }
    Ok(agg)
}

/// Statistics of every measure of the bed in the run summaries (timings and
/// run settings left out), in replicate order.
pub fn measures_of(summaries: &[Value]) -> Result<Aggregate> {
    fold(summaries, &NOT_MEASURES, None)
}

/// Statistics of the wall times (`timing.*`) of the run summaries.
pub fn timings_of(summaries: &[Value]) -> Result<Aggregate> {
    fold(summaries, &[], Some(TIMING_KEY))
}

/// The first replicate whose summary holds a measure of another kind than the
/// other replicates do (a number become text, say), as `(replicate, key, its
/// kind, the others' kind)`. Folding would drop such a value and average the
/// rest, losing the replicate without a word.
pub fn odd_replicate(summaries: &[Value]) -> Option<(usize, String, &'static str, &'static str)> {
    let mut kinds: Vec<Vec<(String, &'static str)>> = Vec::with_capacity(summaries.len());
    for summary in summaries {
        let mut out = Vec::new();
        if let Value::Object(top) = summary {
            for (key, v) in top {
                if !NOT_MEASURES.contains(&key.as_str()) {
                    kind_leaves(key, v, &mut out);
                }
            }
        } else {
            kind_leaves("", summary, &mut out);
        }
        kinds.push(out);
    }
    let mut votes: std::collections::HashMap<&str, Vec<(&'static str, usize)>> = Default::default();
    for leaves in &kinds {
        for (key, kind) in leaves {
            let v = votes.entry(key.as_str()).or_default();
            match v.iter_mut().find(|e| e.0 == *kind) {
                Some(e) => e.1 += 1,
                None => v.push((kind, 1)),
            }
        }
    }
    for (r, leaves) in kinds.iter().enumerate() {
        for (key, kind) in leaves {
            let v = &votes[key.as_str()];
            if v.len() < 2 {
                continue;
            }
            let usual = v.iter().max_by_key(|e| e.1).map_or(*kind, |e| e.0);
            if usual != *kind {
                return Some((r, key.clone(), kind, usual));
            }
        }
    }
    None
}

/// Each non-null leaf of `v` under `path` with the kind of its value.
fn kind_leaves(path: &str, v: &Value, out: &mut Vec<(String, &'static str)>) {
    match v {
        Value::Null => {}
        Value::Number(_) => out.push((path.to_string(), "a number")),
        Value::Bool(_) => out.push((path.to_string(), "true or false")),
        Value::String(_) => out.push((path.to_string(), "text")),
        Value::Array(a) => {
            for (i, item) in a.iter().enumerate() {
                kind_leaves(&format!("{path}[{i}]"), item, out);
            }
        }
        Value::Object(m) => {
            for (k, item) in m {
                kind_leaves(&format!("{path}.{k}"), item, out);
            }
        }
    }
}

fn flatten(path: &str, v: &Value, out: &mut Vec<(String, Leaf)>) {
    match v {
        Value::Number(n) => {
            if let Some(x) = n.as_f64() {
                out.push((path.to_string(), Leaf::Number(x)));
            }
        }
        Value::Bool(b) => out.push((path.to_string(), Leaf::Bool(*b))),
        Value::Object(m) => flatten_object(path, m, out),
        Value::Array(a) => {
            if a.iter().all(Value::is_number) {
                let xs: Vec<f64> = a.iter().filter_map(Value::as_f64).collect();
                let leaf = if path.contains("histogram") {
                    Leaf::Histogram(xs)
                } else {
                    Leaf::Series(xs)
                };
                out.push((path.to_string(), leaf));
            } else if let Some(names) = distinct_names(a) {
                for (name, item) in names.iter().zip(a) {
                    let p = format!("{path}.{name}");
                    match item {
                        Value::Object(m) if path == "species" => {
                            let m: Map<String, Value> = m
                                .iter()
                                .filter(|(k, _)| !SPECIES_SETTINGS.contains(&k.as_str()))
                                .map(|(k, v)| (k.clone(), v.clone()))
                                .collect();
                            flatten_object(&p, &m, out)
                        }
                        Value::Object(m) => flatten_object(&p, m, out),
                        other => flatten(&p, other, out),
                    }
                }
            } else {
                for (i, item) in a.iter().enumerate() {
                    flatten(&format!("{path}[{i}]"), item, out);
                }
            }
        }
        Value::Null | Value::String(_) => {}
    }
}

fn flatten_object(path: &str, m: &Map<String, Value>, out: &mut Vec<(String, Leaf)>) {
    for (k, v) in m {
        if k == "name" {
            continue;
        }
        flatten(&format!("{path}.{k}"), v, out);
    }
}

/// The `name`s of an array of objects, if every one has a distinct, non-empty name.
fn distinct_names(a: &[Value]) -> Option<Vec<String>> {
    let names: Vec<String> = a
        .iter()
        .map(|v| v.get("name").and_then(Value::as_str).map(str::to_string))
        .collect::<Option<Vec<_>>>()?;
    let mut sorted = names.clone();
    sorted.sort();
    sorted.dedup();
    (sorted.len() == names.len() && names.iter().all(|n| !n.is_empty())).then_some(names)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn stats_by_hand() {
        let s = Stats::of(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(s.n, 4);
        assert_eq!(s.mean, 2.5);
        // Σ(x − 2.5)² = 5, over n − 1 = 3.
        assert_eq!(s.sd, (5.0f64 / 3.0).sqrt());
        assert_eq!((s.min, s.max), (1.0, 4.0));
        let one = Stats::of(&[7.0]);
        assert_eq!(
            (one.n, one.mean, one.sd, one.min, one.max),
            (1, 7.0, 0.0, 7.0, 7.0)
        );
        assert_eq!(Stats::of(&[]).n, 0);
    }

    #[test]
    fn walk_of_a_summary() {
        let runs = vec![
            json!({"seed": 5, "packing": {"global": 0.5, "flag": true},
                   "coordination": {"histogram": [1, 2, 1]},
                   "packing_profile": [0.1, 0.3],
                   "species": [{"name": "large", "ratio": 1, "placed": 4}],
                   "compaction": {"steps": 3, "seconds": 1.5},
                   "timing": {"deposit_seconds": 0.25}}),
            json!({"seed": 6, "packing": {"global": 0.7, "flag": false},
                   "coordination": {"histogram": [0, 2, 3, 1]},
                   "packing_profile": [0.3],
                   "species": [{"name": "large", "ratio": 1, "placed": 6}],
                   "compaction": {"steps": 5, "seconds": 2.5},
                   "timing": {"deposit_seconds": 0.75}}),
        ];
        let a = measures_of(&runs).unwrap();
        assert_eq!(a.replicates, 2);
        let names: Vec<&str> = a.measures.iter().map(|m| m.name.as_str()).collect();
        // The compaction's wall time is left out: the statistics are the
        // same bytes on any machine.
        assert_eq!(
            names,
            [
                "packing.global",
                "packing.flag",
                "species.large.placed",
                "compaction.steps"
            ]
        );
        let g = a.measures[0].stats;
        assert!((g.mean - 0.6).abs() < 1e-15);
        // sd of {0.5, 0.7}: |0.7 − 0.5| / √2.
        assert!((g.sd - 0.2 / 2f64.sqrt()).abs() < 1e-15);
        assert_eq!(a.measures[1].kind, Kind::Percent);
        assert_eq!(a.measures[1].stats.mean, 50.0);
        assert_eq!(a.measures[2].stats.mean, 5.0);
        assert_eq!(a.measures[3].stats.mean, 4.0);
        let h = &a.histograms[0];
        assert_eq!(h.counts, [1.0, 4.0, 4.0, 1.0]);
        assert_eq!(h.fraction, [0.1, 0.4, 0.4, 0.1]);
        let p = &a.series[0];
        assert_eq!(p.entries[0].n, 2);
        assert_eq!(p.entries[0].mean, 0.2);
        assert_eq!(p.entries[1].n, 1);
        let t = timings_of(&runs).unwrap();
        assert_eq!(t.measures.len(), 1);
        assert_eq!(t.measures[0].stats.mean, 0.5);
    }

    #[test]
    fn the_filtrations_wall_time_is_not_a_measure() {
        let runs = vec![
            json!({"filtration": {"alpha_fit_m_per_kg": 2e9, "seconds": 0.5}}),
            json!({"filtration": {"alpha_fit_m_per_kg": 3e9, "seconds": 0.9}}),
        ];
        let a = measures_of(&runs).unwrap();
        let names: Vec<&str> = a.measures.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["filtration.alpha_fit_m_per_kg"]);
    }

    #[test]
    fn percent_of_booleans() {
        let runs: Vec<Value> = [true, false, true, true]
            .iter()
            .map(|&b| json!({ "percolation": { "spans": b } }))
            .collect();
        let a = measures_of(&runs).unwrap();
        let s = a.measures[0].stats;
        // Indicator 100·{1,0,1,1}: mean 75, Σ(x − 75)² = 3·625 + 5625 = 7500, /3 → sd 50.
        assert_eq!((s.mean, s.sd, s.min, s.max), (75.0, 50.0, 0.0, 100.0));
    }

    #[test]
    fn a_number_become_text_is_the_odd_replicate() {
        let good = json!({"seed": 1, "packing": {"global": 0.5}, "source": "x"});
        let bad = json!({"seed": 2, "packing": {"global": "0.5"}, "source": "y"});
        let all = [good.clone(), bad, good.clone()];
        assert_eq!(
            odd_replicate(&all),
            Some((1, "packing.global".into(), "text", "a number"))
        );
        assert_eq!(odd_replicate(&[good.clone(), good]), None);
    }

    #[test]
    fn type_change_is_an_error() {
        let runs = vec![json!({"a": 1}), json!({"a": true})];
        assert!(measures_of(&runs).is_err());
    }
}
