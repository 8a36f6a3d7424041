//! The short summary of an ensemble or a merge for a person, as `packbed
//! ensemble` prints it: what ran, the headline statistics, where the files are.

use super::run::{count, file_names, path};
use crate::analysis::stats::Kind;
use crate::ensemble::{reports, Outcome};
use crate::error::inert;
use std::fmt::Write;
use std::path::Path;

/// Measures printed on screen, when present, in this order: the cake first;
/// yes/no measures follow (those of percolation only when it was asked for).
const ON_SCREEN: [&str; 21] = [
    "cake.porosity",
    "cake.d32",
    "cake.k_kozeny_carman",
    "cake.specific_resistance",
    "packing.global",
    "packing.bulk",
    "coordination.mean",
    "coordination.mean_bulk",
    "pores.d_c35",
    "permeability.k_x",
    "permeability.k_z",
    "drainage.breakthrough.reduced",
    "drainage.saturation_at_breakthrough",
    "drainage.residual_saturation",
    "agglomeration.bonds_per_particle",
    "agglomeration.fraction_in_agglomerates",
    "agglomeration.agitation.fraction_in_agglomerates",
    // A filtration's, each key naming its SI unit (the rest in `ensemble.md`).
    "filtration.alpha_fit_m_per_kg",
    "filtration.r_medium_fit_per_m",
    "filtration.final.time_s",
    "capture.passed_fraction",
];

use reports::SETTINGS;

/// The note of an ensemble rerun with fewer replicates than `out` holds.
pub fn reduced_note(out: &Path, runs: u64, earlier: u64) -> String {
    let range = |lo: u64, hi: u64| {
        if hi == lo + 1 {
            format!("replicate {lo}")
        } else {
            format!("replicates {lo}–{}", hi - 1)
        }
    };
    format!(
        "{} held an ensemble of {earlier} replicates; --runs {runs} reuses those of {} that are \
         finished, and the statistics are over the {runs} requested ({} stay on disk, unused)",
        path(out),
        range(0, runs),
        range(runs, earlier)
    )
}

/// A few lines for a person: what ran (`threads` for a run, `None` for a
/// merge), the headline numbers, where the files are.
pub fn ensemble_text(o: &Outcome, out: &Path, threads: Option<usize>) -> String {
    let mut t = String::new();
    let beds: u64 = o.points.iter().map(|p| p.aggregate.replicates).sum();
    let built: u64 = o.points.iter().map(|p| p.built).sum();
    let resumed: u64 = o.points.iter().map(|p| p.resumed).sum();
    let how = match threads {
        Some(j) => format!(
            "{built} built, {resumed} resumed, {}",
            count(j as u64, "thread", "threads")
        ),
        None => format!(
            "merged from {}",
            count(resumed, "replicate summary", "replicate summaries")
        ),
    };
    let _ = writeln!(
        t,
        "packbed: ensemble of {} ({how}) in {:.2} s",
        count(beds, "bed", "beds"),
        o.wall_seconds
    );
    for p in &o.points {
        if let Some(l) = &p.label {
            let _ = writeln!(t, "  {}  ({})", inert(l), path(&p.dir));
        }
        let a = &p.aggregate;
        // In the order of ON_SCREEN, not of the aggregate: a measure null in
        // the first bed (the bulk of a small bed) comes last there.
        let headline = ON_SCREEN
            .iter()
            .filter_map(|&name| a.measures.iter().find(|m| m.name == name));
        // Ten yes/no flags of percolation (per direction, per cap) buried the
        // cake of a size distribution: unless percolation was asked for, they
        // fold into one line below.
        let flags = a.measures.iter().filter(|m| {
            m.kind == Kind::Percent
                && !m.name.ends_with("_empty")
                && !SETTINGS.contains(&m.name.as_str())
                && (p.percolation_asked || !m.name.starts_with("percolation."))
        });
        for m in headline.chain(flags) {
            let [lo, mid, hi] = reports::cells(&m.stats, m.kind);
            let _ = writeln!(
                t,
                "    {:<40} {mid}  (min {lo}, max {hi})",
                inert(&reports::label(m, a.replicates))
            );
        }
        if !p.percolation_asked {
            if let Some(line) = percolation_line(a) {
                let _ = writeln!(t, "    {line}");
            }
        }
    }
    let names = file_names;
    match o.points.first().filter(|p| p.label.is_some()) {
        // A sweep: its comparison on top, each value's statistics in its directory.
        Some(p) => {
            let _ = writeln!(t, "  files in {}: {}", path(out), names(&o.files));
            let _ = writeln!(
                t,
                "  in each of {} sweep/*/: {}, runs/",
                o.points.len(),
                names(&p.files)
            );
        }
        None => {
            let _ = writeln!(t, "  files in {}: {}, runs/", path(out), names(&o.files));
        }
    }
    t
}

/// A percentage of beds: whole numbers without decimals.
fn percent(x: f64) -> String {
    if x.fract() == 0.0 {
        format!("{x:.0} %")
    } else {
        format!("{x:.1} %")
    }
}

/// Percolation of an ensemble in one line (`None`: not measured): in how many
/// beds a chain spans, per direction in 3D, and how often the enumeration of
/// unique chains was capped; the rest is in `ensemble.md`.
fn percolation_line(a: &crate::analysis::stats::Aggregate) -> Option<String> {
    let mean = |name: &str| {
        a.measures
            .iter()
            .find(|m| m.name == name)
            .map(|m| m.stats.mean)
    };
    let spans = mean("percolation.spans")?;
    let mut line = format!("percolation: a chain spans in {} of beds", percent(spans));
    let per_axis: Vec<String> = (0..)
        .map_while(|k| mean(&format!("percolation.directions[{k}].spans")))
        .zip(["x", "y"])
        .map(|(s, axis)| format!("{axis} {}", percent(s)))
        .collect();
    if per_axis.len() > 1 {
        let _ = write!(line, " ({})", per_axis.join(", "));
    }
    if let Some(capped) = mean("percolation.cap_hit").filter(|&c| c > 0.0) {
        let _ = write!(line, "; chain enumeration capped in {}", percent(capped));
    }
    line.push_str("; the rest in ensemble.md");
    Some(line)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::stats::{Aggregate, MeasureStats, Stats};
    use crate::ensemble::PointResult;
    use std::path::PathBuf;

    fn percent(name: &str, beds_true: u64, beds: u64) -> MeasureStats {
        let values: Vec<f64> = (0..beds)
            .map(|i| if i < beds_true { 100.0 } else { 0.0 })
            .collect();
        MeasureStats {
            name: name.into(),
            kind: Kind::Percent,
            stats: Stats::of(&values),
        }
    }

    fn screen(percolation_asked: bool) -> String {
        // The porosity after the packing, as when the first bed had no bulk.
        let mut measures = vec![
            MeasureStats {
                name: "packing.global".into(),
                kind: Kind::Value,
                stats: Stats::of(&[0.6; 10]),
            },
            MeasureStats {
                name: "cake.porosity".into(),
                kind: Kind::Value,
                stats: Stats::of(&[0.38, 0.39, 0.4, 0.41, 0.37, 0.36, 0.38, 0.39, 0.4]),
            },
        ];
        measures.push(percent("percolation.spans", 9, 10));
        measures.push(percent("percolation.cap_hit", 1, 10));
        for k in 0..2 {
            measures.push(percent(
                &format!("percolation.directions[{k}].spans"),
                8 - k,
                10,
            ));
            for cap in ["chain", "length", "search"] {
                let name = format!("percolation.directions[{k}].{cap}_cap_hit");
                measures.push(percent(&name, 1, 10));
            }
        }
        let o = Outcome {
            points: vec![PointResult {
                label: None,
                dir: PathBuf::from("e"),
                percolation_asked,
                aggregate: Aggregate {
                    replicates: 10,
                    measures,
                    ..Default::default()
                },
                built: 10,
                resumed: 0,
                files: Vec::new(),
            }],
            wall_seconds: 1.0,
            files: Vec::new(),
            reduced_from: None,
            warnings: Vec::new(),
        };
        ensemble_text(&o, Path::new("e"), Some(2))
    }

    #[test]
    fn percolation_folds_into_one_line_unless_asked_for() {
        let t = screen(false);
        let lines: Vec<&str> = t.lines().collect();
        // The header, the cake, the packing, one line of percolation, the files.
        assert_eq!(lines.len(), 5, "{t}");
        assert!(lines[1].contains("cake.porosity (9 of 10 beds)"), "{t}");
        assert!(lines[2].contains("packing.global"), "{t}");
        assert_eq!(
            lines[3],
            "    percolation: a chain spans in 90 % of beds (x 80 %, y 70 %); chain enumeration capped in 10 %; the rest in ensemble.md"
        );
        let asked = screen(true);
        assert_eq!(asked.lines().count(), 4 + 10, "{asked}");
        assert!(asked.contains("percolation.directions[1].search_cap_hit (% of beds)"));
        assert!(!asked.contains("the rest in ensemble.md"), "{asked}");
    }
}
