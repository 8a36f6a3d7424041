//! The short human summary `packbed run` prints on stdout.

use packbed::io::{RunSummary, RUN_FILES};
use std::fmt::Write;
use std::path::Path;

/// A few lines for a person: what was built, what it measures, where the files are.
pub fn run_text(s: &RunSummary, out: &Path) -> String {
    let mut t = String::new();
    let b = &s.container;
    let size = match b.depth {
        Some(d) => format!("{} × {} × {}", b.width, d, b.height),
        None => format!("{} × {}", b.width, b.height),
    };
    let sides = if b.periodic {
        "periodic sides"
    } else {
        "walls"
    };
    let kind = if s.dim == 2 { "discs" } else { "spheres" };
    let _ = writeln!(
        t,
        "packbed: {}D bed of {kind} in a {size} box ({sides}), seed {}",
        s.dim, s.seed
    );
    for sp in &s.species {
        let shape = if sp.shape == "sphere" {
            String::new()
        } else {
            format!(", {}", sp.shape)
        };
        let _ = writeln!(
            t,
            "  species {}: {}{shape}, ratio {}: {} placed",
            sp.name, sp.size, sp.ratio, sp.placed
        );
    }
    let c = &s.counts;
    if s.mode == packbed::config::Mode::Rsa {
        let _ = writeln!(
            t,
            "  particles: {} (random sequential addition{})",
            c.particles,
            match s.config.fill.count {
                Some(n) if c.particles < n => ", saturated before the count",
                Some(_) => "",
                None => ", saturated",
            }
        );
    } else {
        let _ = writeln!(
            t,
            "  particles: {} ({} base layer, {} dropped; {} re-drops, {} roof overflows)",
            c.particles, c.base_layer, c.dropped, c.redrops, c.roof_overflows
        );
    }
    let p = &s.analysis.packing;
    let _ = writeln!(
        t,
        "  packing fraction: global {:.4}, bulk {:.4}",
        p.global, p.bulk
    );
    let k = &s.analysis.coordination;
    let _ = writeln!(
        t,
        "  coordination: bulk {:.3} ({} particles in the bulk), overall {:.3}",
        k.mean_bulk, k.bulk_particles, k.mean
    );
    let tm = &s.timing;
    let _ = writeln!(
        t,
        "  time: {:.3} s (deposition {:.3} s, analysis {:.3} s)",
        tm.total_seconds, tm.deposit_seconds, tm.analysis_seconds
    );
    let _ = writeln!(t, "  files in {}: {}", out.display(), RUN_FILES.join(", "));
    t
}
