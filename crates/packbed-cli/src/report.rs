//! The short human summary `packbed run` prints on stdout.

use packbed::analysis::Summary;
use packbed::io::{AnalyzeSummary, RunSummary, RUN_FILES};
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
    t.push_str(&measures_text(&s.analysis));
    let tm = &s.timing;
    let _ = writeln!(
        t,
        "  time: {:.3} s (deposition {:.3} s, analysis {:.3} s)",
        tm.total_seconds, tm.deposit_seconds, tm.analysis_seconds
    );
    let _ = writeln!(t, "  files in {}: {}", out.display(), RUN_FILES.join(", "));
    t
}

/// The summary `packbed analyze` prints.
pub fn analyze_text(s: &AnalyzeSummary, out: &Path) -> String {
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
    let _ = writeln!(
        t,
        "packbed: {} ({}D, {} particles, {} bodies, {size} box, {sides})",
        s.source, s.dim, s.counts.particles, s.counts.bodies
    );
    t.push_str(&measures_text(&s.analysis));
    let _ = writeln!(
        t,
        "  time: read {:.3} s, analysis {:.3} s",
        s.timing.read_seconds, s.timing.analysis_seconds
    );
    let _ = writeln!(t, "  {}", crate::analyze::files(out));
    t
}

fn opt(v: Option<f64>) -> String {
    v.map_or("-".into(), |x| format!("{x:.4}"))
}

/// One line per measure, shared by `run` and `analyze`.
pub fn measures_text(a: &Summary) -> String {
    let mut t = String::new();
    let p = &a.packing;
    let r = &p.regions;
    let _ = writeln!(
        t,
        "  packing fraction: global {:.4}, bulk {:.4}; floor {}, roof {}, wall {}, centre {}",
        p.global,
        p.bulk,
        opt(r.floor),
        opt(r.roof),
        opt(r.wall),
        opt(r.centre)
    );
    let k = &a.coordination;
    let _ = writeln!(
        t,
        "  coordination: bulk {:.3} ({} particles in the bulk), overall {:.3}; {} floor and {} wall contacts",
        k.mean_bulk, k.bulk_particles, k.mean, k.floor_contacts, k.wall_contacts
    );
    if k.by_species.len() > 1 {
        let per: Vec<String> = k
            .by_species
            .iter()
            .map(|s| {
                let name = if s.name.is_empty() {
                    format!("species {}", s.species)
                } else {
                    s.name.clone()
                };
                format!("{name} {:.3} (bulk {:.3})", s.mean, s.mean_bulk)
            })
            .collect();
        let _ = writeln!(t, "    by species: {}", per.join(", "));
    }
    let c = &a.percolation;
    let chain = if c.spans {
        let lengths = c
            .chain_length
            .map(|l| format!(", lengths {}–{} (mean {:.1})", l.min, l.max, l.mean))
            .unwrap_or_default();
        format!(
            "spans ({} spanning clusters); shortest chain {} particles, {} disjoint chains, {}{} unique chains{lengths}",
            c.spanning_clusters,
            c.shortest_chain.unwrap_or(0),
            c.disjoint_chains,
            c.unique_chains,
            if c.cap_hit { "+ (cap hit)" } else { "" }
        )
    } else {
        "no spanning chain".into()
    };
    let _ = writeln!(
        t,
        "  percolation (r >= {}: {} large bodies, {} clusters): {chain}",
        c.large_radius, c.large_bodies, c.clusters
    );
    if let Some(v) = &a.voids {
        let _ = writeln!(
            t,
            "  voids: {}, area min {:.4} / mean {:.4} / max {:.4} (mean = {:.4} × largest disc), {:.2} sides on average",
            v.count, v.min_area, v.mean_area, v.max_area, v.mean_area_scaled, v.mean_sides
        );
    }
    if let Some(o) = &a.orientation {
        let _ = writeln!(
            t,
            "  orientation: {} chains, order parameter S = {:.3}, mean angle from {} {:.1}°",
            o.bodies,
            o.order_parameter,
            o.angle_from.name(),
            o.mean_angle
        );
    }
    let g = &a.segregation;
    if g.bottom_fraction.len() > 1 {
        let per: Vec<String> = g
            .bottom_fraction
            .iter()
            .enumerate()
            .map(|(i, f)| format!("species {i} {:.1}%", 100.0 * f))
            .collect();
        let _ = writeln!(
            t,
            "  segregation: in the bottom 10% of the bed: {} (all {:.1}%)",
            per.join(", "),
            100.0 * g.bottom_fraction_all
        );
    }
    t
}
