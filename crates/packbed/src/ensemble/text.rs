//! The short summary of an ensemble or a merge for a person, as `packbed
//! ensemble` prints it: what ran, the headline statistics, where the files are.

use super::stats::Kind;
use super::{tables, Outcome};
use crate::output::text::{count, file_names};
use std::fmt::Write;
use std::path::Path;

/// Measures printed on screen, when present (every yes/no measure is added),
/// in the summary's order: the cake first.
const ON_SCREEN: [&str; 11] = [
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
];

/// A few lines for a person: what ran (`threads` for a run, `None` for a
/// merge), the headline numbers, where the files are.
pub fn summary(o: &Outcome, out: &Path, threads: Option<usize>) -> String {
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
            let _ = writeln!(t, "  {l}  ({})", p.dir.display());
        }
        let a = &p.aggregate;
        for m in &a.measures {
            if ON_SCREEN.contains(&m.name.as_str())
                || (m.kind == Kind::Percent && !m.name.ends_with("_empty"))
            {
                let [lo, mid, hi] = tables::cells(&m.stats, m.kind);
                let _ = writeln!(
                    t,
                    "    {:<40} {mid}  (min {lo}, max {hi})",
                    tables::label(m, a.replicates)
                );
            }
        }
    }
    let names = file_names;
    match o.points.first().filter(|p| p.label.is_some()) {
        // A sweep: its comparison on top, each value's statistics in its directory.
        Some(p) => {
            let _ = writeln!(t, "  files in {}: {}", out.display(), names(&o.files));
            let _ = writeln!(
                t,
                "  in each of {} sweep/*/: {}, runs/",
                o.points.len(),
                names(&p.files)
            );
        }
        None => {
            let _ = writeln!(
                t,
                "  files in {}: {}, runs/",
                out.display(),
                names(&o.files)
            );
        }
    }
    t
}
