//! The short human summary `packbed run` prints on stdout.

use packbed::analysis::percolation::DirectionPercolation;
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
    let from = match b.source {
        Some("options") => " from --box".to_string(),
        Some(f) => format!(" from the {f}"),
        None => String::new(),
    };
    let _ = writeln!(
        t,
        "packbed: {} ({}D, {} particles, {} bodies, {size} box{from}, {sides})",
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

/// The warning about overlapping particles in an analysed bed, if any.
pub fn overlap_warning(s: &AnalyzeSummary) -> Option<String> {
    let c = &s.checks;
    (c.overlapping_pairs > 0).then(|| {
        format!(
            "packbed: warning: overlap: {} pair{} of particles overlap, the worst by {} of the \
             smaller radius (analysed all the same; checks.* in summary.json)",
            c.overlapping_pairs,
            if c.overlapping_pairs == 1 { "" } else { "s" },
            if c.max_overlap >= 1e-3 {
                format!("{:.3}", c.max_overlap)
            } else {
                format!("{:.1e}", c.max_overlap)
            }
        )
    })
}

fn opt(v: Option<f64>) -> String {
    v.map_or("-".into(), |x| format!("{x:.4}"))
}

fn opt3(v: Option<f64>) -> String {
    v.map_or("-".into(), |x| format!("{x:.3}"))
}

/// One line per measure, shared by `run` and `analyze`.
pub fn measures_text(a: &Summary) -> String {
    let mut t = String::new();
    let p = &a.packing;
    let r = &p.regions;
    let _ = writeln!(
        t,
        "  packing fraction: global {:.4}, bulk {} ({} bodies); floor {}, roof {}, wall {}, centre {}",
        p.global,
        opt(p.bulk),
        p.bulk_bodies,
        opt(r.floor),
        opt(r.roof),
        opt(r.wall),
        opt(r.centre)
    );
    let k = &a.coordination;
    let _ = writeln!(
        t,
        "  coordination: bulk {} ({} particles in the bulk), overall {:.3}; {} floor and {} wall contacts",
        opt3(k.mean_bulk), k.bulk_particles, k.mean, k.floor_contacts, k.wall_contacts
    );
    if let Some(why) = &p.bulk_note {
        let _ = writeln!(t, "  bulk measures: none ({why})");
    }
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
                format!("{name} {:.3} (bulk {})", s.mean, opt3(s.mean_bulk))
            })
            .collect();
        let _ = writeln!(t, "    by species: {}", per.join(", "));
    }
    let c = &a.percolation;
    let chain = if c.spans {
        let lengths = c
            .chain_length
            .map(|l| format!(" of {}–{} particles (mean {:.1})", l.min, l.max, l.mean))
            .unwrap_or_default();
        // 3D: per direction and summed (the source study counted "x or y" together).
        let per_axis = |count: fn(&DirectionPercolation) -> u64, sum: u64| {
            if c.directions.len() > 1 {
                let each: Vec<String> = c
                    .directions
                    .iter()
                    .map(|d| format!("{} {}", d.axis, count(d)))
                    .collect();
                format!("{} (sum {sum})", each.join(", "))
            } else {
                sum.to_string()
            }
        };
        let capped = if c.cap_hit {
            let mut why = Vec::new();
            if c.directions.iter().any(|d| d.chain_cap_hit) {
                why.push("chain count");
            }
            if c.directions.iter().any(|d| d.length_cap_hit) {
                why.push("chain length");
            }
            if c.directions.iter().any(|d| d.search_cap_hit) {
                why.push("search steps");
            }
            format!(" (enumeration capped by {})", why.join(" and "))
        } else {
            String::new()
        };
        format!(
            "spans ({} spanning clusters); shortest chain {} particles; vertex-disjoint chains {}; unique chains {}{lengths}{capped}",
            c.spanning_clusters,
            c.shortest_chain.unwrap_or(0),
            per_axis(|d| d.disjoint_chains, c.disjoint_chains_sum),
            per_axis(|d| d.unique_chains, c.unique_chains),
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
            "  orientation: {} chains, order parameter S = {:.3}, mean angle from vertical {:.1}°",
            o.bodies, o.order_parameter, o.mean_angle
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
