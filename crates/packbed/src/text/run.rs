//! The short summaries for a person that `packbed run` and `packbed analyze`
//! print (and a notebook may show): the headline numbers of `summary.json`,
//! rounded for reading, and where the files are.

use crate::analysis::percolation::DirectionPercolation;
use crate::analysis::{Percolation, Summary};
use crate::error::{echo, inert};
use crate::io::summary::BoxSummary;
use crate::io::{AnalyzeSummary, RunSummary};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// `1 cluster`, `2 clusters`.
pub fn count(n: u64, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// A path for the screen (see [`crate::error::inert_path`]).
pub use crate::error::inert_path as path;

/// A length for the screen (see [`crate::math::display_length`]).
pub use crate::math::display_length as length;

/// What bounds the box at its sides.
fn sides(b: &BoxSummary) -> &'static str {
    if b.periodic {
        "periodic sides"
    } else {
        "walls"
    }
}

/// `W × H` or `W × D × H`.
fn box_size(b: &BoxSummary) -> String {
    match b.depth {
        Some(d) => format!("{} × {} × {}", length(b.width), length(d), length(b.height)),
        None => format!("{} × {}", length(b.width), length(b.height)),
    }
}

/// The names of the files written, for the last line of a summary.
pub fn file_names(files: &[PathBuf]) -> String {
    files
        .iter()
        .filter_map(|f| f.file_name().map(|n| inert(&n.to_string_lossy())))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A few lines for a person: what was built, what it measures, where the files are.
pub fn run_text(s: &RunSummary, out: &Path, files: &[PathBuf]) -> String {
    let mut t = String::new();
    let b = &s.container;
    let size = box_size(b);
    let sides = sides(b);
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
            echo(&sp.name),
            sp.size,
            sp.ratio,
            sp.placed
        );
    }
    // Lengths of the run's lines in the bed's unit where it has one.
    let unit = s
        .config
        .analysis
        .length_unit
        .map_or(String::new(), |u| format!(" {}", u.name()));
    if let Some(p) = &s.psd {
        let d = |x: &crate::analysis::psd::PsdStats| {
            format!("{} / {} / {}", length(x.d10), length(x.d50), length(x.d90))
        };
        let _ = writeln!(
            t,
            "  sizes by mass, d10 / d50 / d90: requested {}, placed {}{unit} (psd.csv)",
            d(&p.requested),
            d(&p.placed)
        );
    }
    let c = &s.counts;
    if s.mode == crate::config::Mode::Rsa {
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
        // `dropped` counts bodies; with chains the base layer must too (its
        // count in summary.json is in beads, the rows of particles.csv).
        let what = if c.bodies == c.particles {
            count(c.particles, "particle", "particles")
        } else {
            format!(
                "{} in {}",
                count(c.particles, "particle", "particles"),
                count(c.bodies, "body", "bodies")
            )
        };
        let base = if c.bodies == c.particles {
            c.base_layer
        } else {
            c.bodies.saturating_sub(c.dropped)
        };
        let _ = writeln!(
            t,
            "  particles: {what} ({base} base layer, {} dropped; {}, {})",
            c.dropped,
            count(c.redrops, "re-drop", "re-drops"),
            count(c.roof_overflows, "roof overflow", "roof overflows")
        );
    }
    let names: Vec<String> = s.species.iter().map(|sp| sp.name.clone()).collect();
    t.push_str(&measures_text_with(
        &s.analysis,
        &names,
        bulk_hint(s).as_deref(),
    ));
    if let Some(c) = &s.compaction {
        let why = c.stopped_by.says();
        let _ = writeln!(
            t,
            "  compaction: {} steps ({why}), centre of mass down {:.4}{unit}, {:.1} s",
            c.steps, c.descent, c.seconds
        );
    }
    if let Some(c) = &s.capture {
        let x50 = c.x50.map_or("none within the sizes fed".to_string(), |x| {
            format!("{x:.4}")
        });
        let _ = writeln!(
            t,
            "  capture: {} fed after the medium: {} passed (filtrate.csv), {} lodged in it, {} in the cake; x50 {x50} (capture.csv)",
            c.fed, c.passed, c.lodged, c.cake
        );
    }
    if let Some(f) = &s.filtration {
        let e = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3e}"));
        let stop = f
            .stopped_by
            .map_or(String::new(), |b| format!(", stopped by {b}"));
        let _ = writeln!(
            t,
            "  filtration: α {} m/kg fitted (network {}), R_m {} 1/m fitted (medium {:.3e} clean, {:.3e} in place); {} checkpoints{stop} (filtration.csv)",
            e(f.alpha_fit_m_per_kg),
            e(f.alpha_network_m_per_kg),
            e(f.r_medium_fit_per_m),
            f.r_medium_per_m,
            f.r_medium_clogged_per_m,
            f.checkpoints.len()
        );
        if let Some(note) = &f.note {
            let _ = writeln!(t, "  filtration note: {note}");
        }
    }
    let tm = &s.timing;
    let _ = writeln!(
        t,
        "  time: {:.3} s (deposition {:.3} s, analysis {:.3} s)",
        tm.total_seconds, tm.deposit_seconds, tm.analysis_seconds
    );
    let _ = writeln!(t, "  files in {}: {}", path(out), file_names(files));
    t
}

/// The summary `packbed analyze` prints.
pub fn analyze_text(s: &AnalyzeSummary, out: &Path, files: &[PathBuf]) -> String {
    let mut t = String::new();
    let b = &s.container;
    let size = box_size(b);
    let sides = sides(b);
    let from = match b.source {
        Some("options") => " from the options".to_string(),
        Some(f) => format!(" from the {f}"),
        None => String::new(),
    };
    let _ = writeln!(
        t,
        "packbed: {} ({}D, {}, {}, {size} box{from}, {sides})",
        inert(&s.source),
        s.dim,
        count(s.counts.particles, "particle", "particles"),
        count(s.counts.bodies, "body", "bodies")
    );
    t.push_str(&measures_text(&s.analysis, &[]));
    let _ = writeln!(
        t,
        "  time: read {:.3} s, analysis {:.3} s",
        s.timing.read_seconds, s.timing.analysis_seconds
    );
    let _ = writeln!(t, "  files in {}: {}", path(out), file_names(files));
    t
}

/// The lines `packbed: warning: …` for stderr, each clean and short
/// whatever input it echoes.
pub fn warning_lines<S: AsRef<str>>(warnings: impl IntoIterator<Item = S>) -> String {
    warnings
        .into_iter()
        .map(|w| {
            format!(
                "packbed: warning: {}\n",
                crate::error::clean_line(w.as_ref())
            )
        })
        .collect()
}

/// The warning about overlapping particles in an analysed bed, if any (the
/// caller adds its own prefix, e.g. "packbed: warning: ").
pub fn overlap_warning(s: &AnalyzeSummary) -> Option<String> {
    let c = &s.checks;
    (c.overlapping_pairs > 0).then(|| {
        format!(
            "overlap: {} pair{} of particles overlap, the worst by {} of the \
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

/// Three significant digits in scientific notation, `-` for none.
fn sci(v: Option<f64>) -> String {
    v.map_or("-".into(), |x| format!("{x:.3e}"))
}

/// The cake properties: the bulk values (the whole cake's when the bed has no
/// bulk region), then the cake resistance when a solid density was given.
fn cake_text(c: &crate::analysis::CakeSummary) -> String {
    let mut t = String::new();
    let (where_, porosity, d32, surface, k) = match (c.porosity, c.d32) {
        (Some(e), Some(d)) => ("bulk", e, d, c.specific_surface, c.k_kozeny_carman),
        _ => (
            "whole cake",
            c.whole.porosity,
            c.whole.d32,
            Some(c.whole.specific_surface),
            c.whole.k_kozeny_carman,
        ),
    };
    // Lengths in the bed's unit where it has one.
    let (u, per, area) = match c.length_unit {
        Some(u) => (format!(" {u}"), format!("per {u}"), format!(" {u}²")),
        None => (String::new(), "per length".to_string(), String::new()),
    };
    let _ = write!(
        t,
        "  cake ({where_}): porosity {porosity:.4}, d32 {}{u}, specific surface {} {per}",
        length(d32),
        sci(surface)
    );
    if k.is_some() {
        let _ = write!(t, ", Kozeny-Carman k {}{area}", sci(k));
    }
    let solids = match c.length_unit {
        Some(u) => format!("{} {u}³ per {u}² of floor", length(c.solids_per_area)),
        None => format!("{} per floor area", length(c.solids_per_area)),
    };
    let _ = writeln!(t, "; height {}{u}, solids {solids}", length(c.height));
    if let (Some(a), Some(m)) = (c.specific_resistance, c.solids_mass_per_area) {
        let from = match c.specific_resistance_from {
            Some("network") => "network k",
            _ => "Kozeny-Carman k",
        };
        let _ = writeln!(
            t,
            "  cake resistance: {a:.3e} m/kg (from the {from}), solids {m:.4e} kg/m²"
        );
    }
    if let Some(note) = c.note {
        let _ = writeln!(t, "    ({note})");
    }
    t
}

/// What a run without a bulk can do about it: the box that gives one (a
/// run's own option; `analyze` reads a bed it cannot rebuild).
fn bulk_hint(s: &RunSummary) -> Option<String> {
    let p = s.analysis.packing.as_ref()?;
    p.bulk_note.as_ref()?;
    let n = p.bulk_cube_diameters?;
    let b = &s.config.container;
    let preset = b.diameters.is_none()
        && b.width.is_none()
        && b.depth.is_none()
        && b.height.is_none()
        && b.preset.as_deref().is_none_or(|p| p == "thesis");
    let whose = if preset {
        "the source study's box"
    } else {
        "this box"
    };
    let shape = if s.dim == 2 { "square" } else { "cube" };
    Some(format!(
        "{whose} is too small for a bulk; a {shape} of {n} largest diameters should give one: --box diameters={n}"
    ))
}

/// One line per measure, shared by `run` and `analyze`; `names` are the
/// species names by index where known.
pub fn measures_text(a: &Summary, names: &[String]) -> String {
    measures_text_with(a, names, None)
}

/// [`measures_text`], with `bulk_hint` said after the reason a bed has no
/// bulk measures.
fn measures_text_with(a: &Summary, names: &[String], bulk_hint: Option<&str>) -> String {
    // Species by name: the run's, else the analysis's own, else the index.
    let species_name = |i: usize| -> String {
        names
            .get(i)
            .filter(|n| !n.is_empty())
            .map(String::as_str)
            .or_else(|| {
                a.coordination
                    .iter()
                    .flat_map(|k| &k.by_species)
                    .find(|s| s.species as usize == i && !s.name.is_empty())
                    .map(|s| s.name.as_str())
            })
            .map_or_else(|| format!("species {i}"), echo)
    };
    let mut t = String::new();
    if let Some(c) = &a.cake {
        t.push_str(&cake_text(c));
    }
    if let Some(p) = &a.packing {
        let r = &p.regions;
        let _ = writeln!(
            t,
            "  packing fraction: global {:.4}, bulk {} ({}); floor {}, roof {}, wall {}, centre {}",
            p.global,
            opt(p.bulk),
            count(p.bulk_bodies, "body", "bodies"),
            opt(r.floor),
            opt(r.roof),
            opt(r.wall),
            opt(r.centre)
        );
    }
    if let Some(k) = &a.coordination {
        let _ = writeln!(
            t,
            "  coordination: bulk {} ({} in the bulk), overall {:.3}; {} and {}",
            opt3(k.mean_bulk),
            count(k.bulk_particles, "particle", "particles"),
            k.mean,
            count(k.floor_contacts, "floor contact", "floor contacts"),
            count(k.wall_contacts, "wall contact", "wall contacts")
        );
    }
    if let Some(k) = a.coordination.as_ref().filter(|k| k.by_species.len() > 1) {
        let per: Vec<String> = k
            .by_species
            .iter()
            .map(|s| {
                format!(
                    "{} {:.3} (bulk {})",
                    species_name(s.species as usize),
                    s.mean,
                    opt3(s.mean_bulk)
                )
            })
            .collect();
        let _ = writeln!(t, "    by species: {}", per.join(", "));
    }
    if let Some(why) = a.packing.as_ref().and_then(|p| p.bulk_note.as_ref()) {
        let _ = writeln!(t, "  bulk measures: none ({why})");
        if let Some(hint) = bulk_hint {
            let _ = writeln!(t, "    {hint}");
        }
    }
    if let Some(p) = &a.pores {
        let _ = writeln!(
            t,
            "  pores (slab z {}–{}): {} pores, body radius median {} (by void volume {}); {} constrictions, radius median {}, d_c35 {}; network porosity {}",
            length(p.slab[0]),
            length(p.slab[1]),
            p.body_radius.count,
            length(p.body_radius.p50),
            length(p.body_radius.by_void_volume.p50),
            p.constriction_radius.count,
            length(p.constriction_radius.p50),
            p.d_c35.map_or("null".into(), length),
            p.network_porosity
                .map_or("null".into(), |v| format!("{v:.4}"))
        );
        if let Some(why) = &p.note {
            let _ = writeln!(t, "    {why}");
        }
    }
    if let Some(k) = &a.permeability {
        let axes: Vec<String> = k
            .axes
            .iter()
            .map(|f| match f.k {
                Some(k) => format!("k_{} {k:.4e}", f.axis),
                None => format!("k_{} null", f.axis),
            })
            .collect();
        let mut line = format!("  permeability: {}", axes.join(", "));
        if let Some(r) = k.k_over_kozeny_carman {
            let _ = write!(line, "; {r:.3} × Kozeny-Carman");
        }
        if let Some(r) = k.k_over_d32_squared {
            let _ = write!(line, ", k/d32² {r:.4e}");
        }
        if let Some(r) = k.anisotropy {
            let _ = write!(line, ", anisotropy k_z/k_side {r:.3}");
        }
        let _ = writeln!(t, "{line}");
        if let Some(why) = &k.note {
            let _ = writeln!(t, "    {why}");
        }
    }
    if let Some(why) = &a.pores_note {
        let _ = writeln!(t, "  pores: none ({why})");
    }
    if let Some(x) = &a.transport {
        let num = |v: Option<f64>| v.map_or("null".into(), |v| format!("{v:.3}"));
        let _ = writeln!(
            t,
            "  transport: formation factor {} (an upper bound: pore bodies left out), Archie m {}, tortuosity hydraulic {} / electrical {}",
            num(x.formation_factor),
            num(x.archie_exponent),
            num(x.hydraulic_tortuosity),
            num(x.electrical_tortuosity)
        );
    }
    if let Some(d) = &a.drainage {
        let pressure = |p: &crate::analysis::pores::drainage::Pressure| match p.pa {
            Some(pa) => format!("P_c·d32/γ {:.3} ({pa:.4e} Pa)", p.reduced),
            None => format!("P_c·d32/γ {:.3}", p.reduced),
        };
        let mut line = match &d.breakthrough {
            Some(b) => format!(
                "  drainage: breakthrough {}, saturation then {:.3}",
                pressure(b),
                d.saturation_at_breakthrough.unwrap_or(0.0)
            ),
            None => "  drainage: no breakthrough".to_string(),
        };
        if let (Some(s), Some(r)) = (&d.state, d.residual_saturation) {
            let _ = write!(
                line,
                "; at {}: liquid {r:.3} (trapped {:.3}, pendular {:.4}), {} bridges",
                pressure(s),
                d.residual_trapped.unwrap_or(0.0),
                d.residual_pendular.unwrap_or(0.0),
                d.bridges
            );
        }
        let _ = writeln!(t, "{line}");
        if let Some(why) = &d.note {
            let _ = writeln!(t, "    {why}");
        }
    }
    if let Some(why) = &a.drainage_note {
        let _ = writeln!(t, "  drainage: none ({why})");
    }
    if let Some(g) = &a.agglomeration {
        let strength = g
            .mean_bond_strength
            .map_or(String::new(), |f| format!(", mean bond {f:.3e} N"));
        let _ = writeln!(
            t,
            "  agglomeration: dried at {} kg/m³ (solubility {}): {} solid bridges, {} bonds ({:.2} per particle{strength}); {} agglomerates hold {:.1}% of the slab's particles, largest {} particles; d50 {:.4} against the particles' {:.4}",
            g.concentration,
            g.solubility.map_or("none".into(), |s| format!("{s}")),
            g.solid_bridges,
            g.bonds,
            g.bonds_per_particle,
            g.agglomerates,
            100.0 * g.fraction_in_agglomerates,
            g.largest_particles,
            g.d50_product,
            g.d50_particles
        );
        if let Some(s) = &g.agitation {
            let first = s
                .first_break_stress
                .map_or("none".into(), |f| format!("{f:.4e} Pa"));
            let _ = writeln!(
                t,
                "    agitated ({}, {:.4e} Pa; first break at {first}): {} of {} bonds broke{}; {} agglomerates hold {:.1}%, largest {} particles; d50 {:.4}",
                s.load,
                s.stress,
                s.broken,
                s.bonds,
                match (s.failure_stress, s.complete) {
                    (Some(f), _) => format!(" and the cake failed at {f:.4e} Pa"),
                    (None, false) => " (stopped at max_breaks)".into(),
                    (None, true) => String::new(),
                },
                s.agglomerates,
                100.0 * s.fraction_in_agglomerates,
                s.largest_particles,
                s.d50_product
            );
        }
        if let Some(why) = &g.note {
            let _ = writeln!(t, "    {why}");
        }
    }
    if let Some(why) = &a.agglomeration_note {
        let _ = writeln!(t, "  agglomeration: none ({why})");
    }
    if let Some(c) = &a.percolation {
        t.push_str(&percolation_text(c));
    }
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
            "  orientation: {}, order parameter S = {:.3}, mean angle from {} {:.1}°",
            count(o.bodies, "chain", "chains"),
            o.order_parameter,
            o.angle_from.name(),
            o.mean_angle
        );
    }
    if let Some(g) = a
        .segregation
        .as_ref()
        .filter(|g| g.bottom_fraction.len() > 1)
    {
        let per: Vec<String> = g
            .bottom_fraction
            .iter()
            .enumerate()
            .map(|(i, f)| format!("{} {:.1}%", species_name(i), 100.0 * f))
            .collect();
        let _ = writeln!(
            t,
            "  segregation: in the bottom 10% of the bed: {} (all {:.1}%)",
            per.join(", "),
            100.0 * g.bottom_fraction_all
        );
    }
    if !a.measures_left_out.is_empty() {
        let _ = writeln!(t, "  left out: {}", a.measures_left_out.join(", "));
    }
    t
}

/// The percolation line.
fn percolation_text(c: &Percolation) -> String {
    let mut t = String::new();
    let chain = if c.spans {
        let lengths = c
            .chain_length
            .map(|l| format!(" of {}–{} particles (mean {:.1})", l.min, l.max, l.mean))
            .unwrap_or_default();
        // 3D: per direction and summed (the source study counted "x or y" together).
        let per_axis = |of: fn(&DirectionPercolation) -> u64, sum: u64, one: &str, many: &str| {
            if c.directions.len() > 1 {
                let each: Vec<String> = c
                    .directions
                    .iter()
                    .map(|d| format!("{} {}", d.axis, of(d)))
                    .collect();
                format!("{many} {} (sum {sum})", each.join(", "))
            } else {
                count(sum, one, many)
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
            "spans ({}); shortest chain {}; {}; {}{lengths}{capped}",
            count(c.spanning_clusters, "spanning cluster", "spanning clusters"),
            count(c.shortest_chain.unwrap_or(0), "particle", "particles"),
            per_axis(
                |d| d.disjoint_chains,
                c.disjoint_chains_sum,
                "vertex-disjoint chain",
                "vertex-disjoint chains"
            ),
            per_axis(
                |d| d.unique_chains,
                c.unique_chains,
                "unique chain",
                "unique chains"
            ),
        )
    } else {
        "no spanning chain".into()
    };
    // The default threshold is not obvious for a size distribution, so the
    // line says which rule set it.
    use crate::analysis::percolation::LargeSource;
    let why = match c.large_rule {
        LargeSource::VolumeMedian => "volume-median radius of the coarsest species",
        LargeSource::LargestSize => "radius of the coarsest species",
        LargeSource::Given => "as given",
    };
    let _ = writeln!(
        t,
        "  percolation (r >= {}, {why}: {}, {}): {chain}",
        length(c.large_radius),
        count(c.large_bodies, "large body", "large bodies"),
        count(c.clusters, "cluster", "clusters")
    );
    t
}

/// The short report of `packbed fragment`.
pub fn fragment_text(
    s: &crate::io::summary::FragmentRunSummary,
    out: &Path,
    files: &[PathBuf],
) -> String {
    let mut t = String::new();
    let b = &s.container;
    let f = &s.fragmentation;
    let _ = writeln!(
        t,
        "packbed: {} ({}D, {}, {} box, {}) under {} (k_t/k_n {})",
        inert(&s.source),
        s.dim,
        count(s.counts.bodies, "body", "bodies"),
        box_size(b),
        sides(b),
        f.load.name(),
        s.settings.kt_over_kn
    );
    let _ = writeln!(
        t,
        "  bonds: {}, force max {:.4} mean {:.4} cv {:.3} (total load 1); unstable bodies {}",
        f.bonds, f.max_force, f.mean_force, f.force_cv, f.unstable_bodies
    );
    let _ = writeln!(t, "  note: {}", s.force_note);
    let failure = match f.breaks_to_failure {
        Some(n) => format!("failed after {}", count(n, "break", "breaks")),
        None => "not failed".to_string(),
    };
    let _ = writeln!(
        t,
        "  breakage: {} ({failure}); {} at the end, the largest of {}",
        count(f.breaks, "bond broken", "bonds broken"),
        count(f.fragments, "fragment", "fragments"),
        count(f.largest_fragment, "body", "bodies")
    );
    let _ = writeln!(
        t,
        "  time: read {:.3} s, first solve {:.3} s, breaks {:.3} s",
        s.timing.read_seconds, s.timing.first_solve_seconds, s.timing.breakage_seconds
    );
    let _ = writeln!(t, "  files in {}: {}", path(out), file_names(files));
    t
}

#[cfg(test)]
mod tests {
    use super::length;

    #[test]
    fn the_default_bed_names_a_box_that_has_a_bulk() {
        use crate::config::Config;
        let config = Config::default();
        let done = crate::run_bed(&config, &mut |_| {}).unwrap();
        let text = super::run_text(&done.summary, std::path::Path::new("out"), &[]);
        let line = text
            .lines()
            .find(|l| l.contains("--box diameters="))
            .unwrap_or_else(|| panic!("no box named:\n{text}"));
        assert!(
            line.contains("the source study's box is too small for a bulk"),
            "{line}"
        );
        let n: f64 = line.rsplit('=').next().unwrap().trim().parse().unwrap();
        // The box it names does have a bulk, of at least the minimum.
        let mut bigger = config.clone();
        bigger.container.diameters = Some(n);
        let done = crate::run_bed(&bigger, &mut |_| {}).unwrap();
        let p = done.summary.analysis.packing.as_ref().unwrap();
        assert!(p.bulk.is_some(), "--box diameters={n}: {:?}", p.bulk_note);
        assert!(p.bulk_bodies >= config.analysis.bulk_min_bodies);
        // And it is not far larger than needed: one diameter less has none.
        let mut smaller = config.clone();
        smaller.container.diameters = Some(n - 2.0);
        let done = crate::run_bed(&smaller, &mut |_| {}).unwrap();
        let p = done.summary.analysis.packing.as_ref().unwrap();
        assert!(
            p.bulk.is_none(),
            "--box diameters={}: a bulk already",
            n - 2.0
        );
    }

    #[test]
    fn species_coordination_follows_the_coordination_line() {
        let done = crate::run_bed(&crate::config::Config::default(), &mut |_| {}).unwrap();
        let text = super::run_text(&done.summary, std::path::Path::new("out"), &[]);
        let lines: Vec<&str> = text.lines().collect();
        let k = lines
            .iter()
            .position(|l| l.trim_start().starts_with("by species:"))
            .unwrap();
        assert!(lines[k - 1].starts_with("  coordination:"), "{text}");
        assert!(lines[k].starts_with("    by species:"), "{text}");
    }

    #[test]
    fn lengths_have_at_most_six_significant_digits() {
        for (x, want) in [
            (1485.1720000000003, "1485.17"),
            (600.0, "600"),
            (66.666666, "66.6667"),
            (0.1 + 0.2, "0.3"),
            (123456789.0, "123456789"),
            (2.5e-7, "2.5e-7"),
            (1.0e20 / 3.0, "3.33333e19"),
            (-12.5, "-12.5"),
            (0.0, "0"),
        ] {
            assert_eq!(length(x), want, "{x}");
        }
    }
}
