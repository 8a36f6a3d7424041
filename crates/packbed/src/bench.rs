//! The throughput benchmark of `packbed bench` (and of the Python package): a
//! bed of equal spheres (discs in 2D) or rigid chains dropped onto a bare floor,
//! and, on request, the time of every analysis stage on a bed.
//!
//! The bed: `n` bodies of radius 10 (`base_layer = "none"`, so that only drop
//! and roll is timed, unless asked for), `fill.count = n`, in a box whose side
//! is about n^(1/3) diameters of radius 10 in 3D (n^(1/2) in 2D), so that a bed
//! of equal spheres ends up roughly as high as it is wide. Instead of equal
//! spheres: lognormal radii of median 10 (default truncation), or given radii
//! in equal numbers; the box stays the same, and broad beds grow taller.

use crate::analysis::{analyze_timed, AnalysisOptions, StageTimes};
use crate::bed::{AnyBed, Bed};
use crate::config::{BaseLayerKind, Config, SettlingConfig, SizeConfig};
use crate::error::Result;
use serde::Serialize;
use std::ops::ControlFlow;
use std::time::Instant;

/// Radius of every bench particle.
pub(crate) const RADIUS: f64 = 10.0;

/// The radii of the bench particles.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum BenchSizes {
    /// Every particle of radius `RADIUS`.
    #[default]
    Equal,
    /// Lognormal radii of median `RADIUS` and this geometric standard
    /// deviation, truncated as a config's are by default.
    Lognormal(f64),
    /// One species per radius, in equal numbers.
    Radii(Vec<f64>),
}

impl BenchSizes {
    /// Refuses a geometric standard deviation below 1 and radii that are not
    /// positive, naming the setting (`gsd`, `radii`).
    pub(crate) fn check(&self) -> Result<()> {
        let (setting, bad, what) = match self {
            BenchSizes::Equal => return Ok(()),
            BenchSizes::Lognormal(g) => (
                "gsd",
                (!(*g >= 1.0 && g.is_finite())).then_some(*g),
                "a geometric standard deviation (a number >= 1)",
            ),
            BenchSizes::Radii(r) => (
                "radii",
                r.iter().copied().find(|r| !(*r > 0.0 && r.is_finite())),
                "a radius (a positive number)",
            ),
        };
        match bad {
            Some(x) => Err(crate::error::Error::setting(
                setting,
                format!("`{x}` is not {what}"),
            )),
            None => Ok(()),
        }
    }
}

/// What to deposit. With the `cli` feature these are options of `packbed
/// bench` (the sizes aside), their documentation its help.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct BenchBed {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 3, value_parser = clap::value_parser!(u8).range(2..=3)))]
    pub dim: u8,
    /// Number of particles to deposit (of chains, with `--chains`).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 100_000, allow_negative_numbers = true, value_parser = clap::value_parser!(u64).range(1..)))]
    pub n: u64,
    /// Deposit rigid chains of this many beads (radius 10, spacing 1.0,
    /// entering upright) instead of spheres; `--n` counts chains.
    #[cfg_attr(feature = "cli", arg(long, value_name = "BEADS", value_parser = clap::value_parser!(u32).range(1..=1000)))]
    pub chains: Option<u32>,
    /// Periodic side boundaries (no side walls).
    #[cfg_attr(feature = "cli", arg(long))]
    pub periodic: bool,
    /// The radii.
    #[cfg_attr(feature = "cli", arg(skip))]
    pub sizes: BenchSizes,
    /// Seed the floor with the random base layer first (timed with the rest).
    #[cfg_attr(feature = "cli", arg(long))]
    pub base_layer: bool,
    /// Settle by a rule of `[settling]` (docs/settling.md): stop at the K-th
    /// contact.
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "K", allow_negative_numbers = true)
    )]
    pub contacts: Option<u8>,
    /// Settle by a rule: stick at each new contact with probability P.
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "P", allow_negative_numbers = true)
    )]
    pub sticking: Option<f64>,
    /// Settle by a rule: stop where the path is less steep than this angle.
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "DEGREES", allow_negative_numbers = true)
    )]
    pub friction_angle: Option<f64>,
    /// Settle by a rule: momentum, with this restitution at each impact.
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "E", allow_negative_numbers = true)
    )]
    pub restitution: Option<f64>,
    /// With `--restitution`: the fall before the first impact, in the
    /// bench's length units (its spheres' radius is 10).
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "H", allow_negative_numbers = true)
    )]
    pub drop_height: Option<f64>,
    /// With `--restitution`: the sliding friction coefficient.
    #[cfg_attr(
        feature = "cli",
        arg(long, value_name = "MU", allow_negative_numbers = true)
    )]
    pub sliding_friction: Option<f64>,
    /// With `--restitution`: a climb that meets a particle rolls on over it.
    #[cfg_attr(feature = "cli", arg(long))]
    pub climb_over: bool,
}

impl BenchBed {
    /// The bench bed as a config (seed 1).
    pub fn config(&self) -> Config {
        let mut c = Config {
            dim: self.dim,
            seed: 1,
            ..Config::default()
        };
        // One lateral side in diameters: a cube (square) of n particles at
        // random close packing is about this wide; never narrower than 4
        // diameters. A chain counts as its beads, and the box is at least two
        // chains wide.
        let beads = self.chains.unwrap_or(1);
        let particles = self.n.saturating_mul(u64::from(beads));
        let chain_length = (f64::from(beads) + 1.0) * RADIUS;
        let side = ((particles as f64).powf(1.0 / self.dim as f64).max(4.0) * 2.0 * RADIUS)
            .max(2.0 * chain_length);
        // Never narrower than four of the largest diameters.
        let r_max = match &self.sizes {
            BenchSizes::Equal => RADIUS,
            BenchSizes::Lognormal(gsd) => RADIUS * gsd.powf(crate::species::TRUNCATION_SIGMAS),
            BenchSizes::Radii(r) => r.iter().copied().fold(RADIUS, f64::max),
        };
        let side = side.max(8.0 * r_max);
        c.container.width = Some(side);
        c.container.depth = (self.dim == 3).then_some(side);
        c.container.height = Some(side);
        c.container.periodic = self.periodic;
        c.fill.count = Some(particles);
        c.fill.base_layer = if self.base_layer {
            BaseLayerKind::Random
        } else {
            BaseLayerKind::None
        };
        c.settling = SettlingConfig {
            contacts: self.contacts,
            sticking: self.sticking,
            friction_angle: self.friction_angle,
            cohesion_diameter: None,
            cohesion_exponent: None,
            restitution: self.restitution,
            drop_height: self.drop_height,
            sliding_friction: self.sliding_friction,
            climb_over: self.climb_over.then_some(true),
        };
        c.species.truncate(1);
        c.species[0].radius = Some(RADIUS);
        c.species[0].ratio = 1.0;
        match &self.sizes {
            BenchSizes::Equal => {}
            BenchSizes::Lognormal(gsd) => {
                c.species[0].radius = None;
                c.species[0].size = Some(SizeConfig {
                    dist: Some("lognormal".into()),
                    median: Some(RADIUS),
                    gsd: Some(*gsd),
                    ..SizeConfig::default()
                });
            }
            BenchSizes::Radii(radii) => {
                let template = c.species[0].clone();
                c.species = radii
                    .iter()
                    .map(|&r| crate::config::SpeciesConfig {
                        radius: Some(r),
                        ..template.clone()
                    })
                    .collect();
            }
        }
        if let Some(b) = self.chains {
            for s in &mut c.species {
                s.shape = "chain".into();
                s.beads = Some(b);
            }
        }
        c
    }
}

/// What `packbed bench --json` prints.
#[derive(Clone, Debug, Serialize)]
pub struct BenchResult {
    /// 2 or 3.
    pub dim: u8,
    /// Particles in the bed.
    pub n: u64,
    /// Periodic side boundaries.
    pub periodic: bool,
    /// Wall time of the deposition (0 for a bed read from a file).
    pub seconds: f64,
    /// Particles deposited per second.
    pub particles_per_second: f64,
    /// Bodies (chains, or particles) deposited.
    pub bodies: u64,
    /// Bodies deposited per second.
    pub bodies_per_second: f64,
    /// Particles re-dropped because they found no rest.
    pub redrops: u64,
    /// Moves of every body, re-drops included (falls and rolls along an arc
    /// for spheres, descent steps for chains): `seconds / moves` is the cost
    /// of a move, `moves / bodies` the moves per body.
    pub moves: u64,
    /// Particles placed by the base layer (included in `n`).
    pub base_layer: u64,
    /// Peak resident memory of the process, where the system reports it (else 0).
    pub peak_rss_bytes: u64,
    /// Threads a bed's spheres could settle on (`RAYON_NUM_THREADS`; the
    /// same bed on any number): `seconds / moves` is wall time per move,
    /// the cost of one move only when this is 1.
    pub threads: usize,
    /// Seconds per analysis stage, stages of the same name summed.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub analysis: Vec<(String, f64)>,
}

/// The stages the analysis speed target counts: contacts, packing and
/// percolation without the capped chain enumeration, within 1 s on 10^6
/// spheres (BENCHMARKS.md, "Analysis").
pub(crate) const TARGET_STAGES: [&str; 6] = [
    "contacts",
    "packing/",
    "percolation/graph",
    "percolation/clusters",
    "percolation/shortest",
    "percolation/disjoint",
];

/// Deposits the bench bed, timing it; `progress` is called with the particles
/// placed so far.
pub fn deposit(bench: &BenchBed, progress: &mut dyn FnMut(u64)) -> Result<(AnyBed, BenchResult)> {
    bench.sizes.check()?;
    let start = Instant::now();
    let (bed, report) = crate::deposit::build(&bench.config(), &mut |n| {
        progress(n);
        ControlFlow::Continue(())
    })?;
    let seconds = start.elapsed().as_secs_f64();
    let mut result = measured(&bed, Some(seconds));
    result.redrops = report.redrops;
    result.moves = report.moves;
    result.base_layer = report.base_layer;
    Ok((bed, result))
}

/// The counts of `bed`, with the deposition rates when it took `seconds`.
pub fn measured(bed: &AnyBed, seconds: Option<f64>) -> BenchResult {
    let (n, bodies) = (bed.len(), bed.body_count());
    BenchResult {
        dim: bed.dim(),
        n: n as u64,
        periodic: bed.periodic(),
        seconds: seconds.unwrap_or(0.0),
        // A clock too coarse to see the run must not produce infinity.
        particles_per_second: seconds.map_or(0.0, |s| n as f64 / s.max(1e-9)),
        bodies: bodies as u64,
        bodies_per_second: seconds.map_or(0.0, |s| bodies as f64 / s.max(1e-9)),
        redrops: 0,
        moves: 0,
        base_layer: 0,
        peak_rss_bytes: peak_rss_bytes().unwrap_or(0),
        threads: rayon::current_num_threads(),
        analysis: Vec::new(),
    }
}

/// Seconds per analysis stage on `bed` with default settings, stages of the
/// same name summed, in the order they first ran.
pub fn time_analysis(bed: &AnyBed) -> Vec<(String, f64)> {
    time_measures(bed, &AnalysisOptions::default())
}

/// Seconds to triangulate the bed's centres alone (first), then per stage of
/// the pore measures (triangulation, network, flow; with `drainage` the
/// drainage, the drying and the transport) on `bed`, after the contacts and packing they
/// need.
pub fn time_pores(bed: &AnyBed, drainage: bool) -> Vec<(String, f64)> {
    use crate::config::{Measure, Measures};
    let mut measures = vec![Measure::Packing, Measure::Pores, Measure::Permeability];
    if drainage {
        measures.push(Measure::Drainage);
        measures.push(Measure::Agglomeration);
    }
    let options = AnalysisOptions {
        measures: Measures::of(&measures),
        ..AnalysisOptions::default()
    };
    let alone = (
        "triangulation of the centres alone".to_string(),
        time_triangulation(bed),
    );
    std::iter::once(alone)
        .chain(time_measures(bed, &options))
        .collect()
}

/// Seconds to triangulate the bed's own centres weighted by r² (no images,
/// no network), the least of three runs: the same work as CGAL's `Regular_triangulation_3` on the same
/// points, for `scripts/bench-cgal.sh` beside it.
fn time_triangulation(bed: &AnyBed) -> f64 {
    fn timed<const D: usize>(bed: &Bed<D>) -> f64 {
        let points: Vec<[f64; D]> = bed.centres.iter().map(|c| c.0).collect();
        let weights: Vec<f64> = bed.radii.iter().map(|r| r * r).collect();
        // The least of three: a shared machine's noise only ever adds time.
        (0..3)
            .map(|_| {
                let t = std::time::Instant::now();
                let tri =
                    crate::analysis::pores::triangulation::Triangulation::new(&points, &weights);
                let seconds = t.elapsed().as_secs_f64();
                std::hint::black_box(tri.slots());
                seconds
            })
            .fold(f64::INFINITY, f64::min)
    }
    crate::bed::each_dim!(bed, b => timed(b))
}

fn time_measures(bed: &AnyBed, options: &AnalysisOptions) -> Vec<(String, f64)> {
    fn timed<const D: usize>(bed: &Bed<D>, options: &AnalysisOptions) -> StageTimes {
        let mut times = StageTimes::default();
        let _ = analyze_timed(bed, options, &mut times);
        times
    }
    let times = crate::bed::each_dim!(bed, b => timed(b, options));
    let mut out: Vec<(String, f64)> = Vec::new();
    for (name, t) in times.0 {
        match out.iter_mut().find(|e| e.0 == name) {
            Some(e) => e.1 += t,
            None => out.push((name.to_string(), t)),
        }
    }
    out
}

/// Seconds of the stages the speed target counts ([`TARGET_STAGES`]).
pub(crate) fn target_seconds(stages: &[(String, f64)]) -> f64 {
    stages
        .iter()
        .filter(|(name, _)| TARGET_STAGES.iter().any(|p| name.starts_with(p)))
        .map(|e| e.1)
        .sum()
}

/// Peak resident memory of this process (`VmHWM`), where Linux reports it.
pub(crate) fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// What `packbed bench` prints: the bed and its rates, the moves, and the time
/// of each analysis stage; `spec` is the deposited bed (`None`: read from a file).
pub fn text(r: &BenchResult, spec: Option<&BenchBed>) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let walls = if r.periodic { "periodic" } else { "walls" };
    let rss = r.peak_rss_bytes as f64 / (1 << 20) as f64;
    match spec {
        None => {
            let _ = writeln!(
                s,
                "packbed bench: {}D, {} particles, {walls}, read from file",
                r.dim, r.n
            );
        }
        Some(BenchBed {
            chains: Some(beads),
            ..
        }) => {
            let _ = writeln!(
                s,
                "packbed bench: {}D, {} chains of {beads} beads, {walls}: {:.3} s, {:.0} chains/s, {} re-drops, peak RSS {rss:.1} MiB",
                r.dim, r.bodies, r.seconds, r.bodies_per_second, r.redrops
            );
        }
        Some(b) => {
            let sizes = match &b.sizes {
                BenchSizes::Lognormal(g) => format!(" (lognormal radii, median 10, gsd {g})"),
                BenchSizes::Radii(r) => {
                    let list: Vec<String> = r.iter().map(|x| x.to_string()).collect();
                    format!(" (radii {}, equal numbers)", list.join(", "))
                }
                BenchSizes::Equal => String::new(),
            };
            let mut rule = Vec::new();
            if let Some(k) = b.contacts {
                rule.push(format!("contacts {k}"));
            }
            if let Some(p) = b.sticking {
                rule.push(format!("sticking {p}"));
            }
            if let Some(a) = b.friction_angle {
                rule.push(format!("friction angle {a}°"));
            }
            if let Some(e) = b.restitution {
                rule.push(format!("momentum (restitution {e})"));
            }
            if let Some(h) = b.drop_height {
                rule.push(format!("drop height {h}"));
            }
            if let Some(mu) = b.sliding_friction {
                rule.push(format!("sliding friction {mu}"));
            }
            if b.climb_over {
                rule.push("climbing over".to_string());
            }
            let sizes = if rule.is_empty() {
                sizes
            } else {
                format!("{sizes}, settling by {}", rule.join(", "))
            };
            let _ = writeln!(
                s,
                "packbed bench: {}D, {} particles{sizes}, {walls}: {:.3} s, {:.0} particles/s, peak RSS {rss:.1} MiB",
                r.dim, r.n, r.seconds, r.particles_per_second
            );
        }
    }
    if spec.is_some() {
        let dropped = r.bodies.saturating_sub(r.base_layer).max(1);
        let _ = writeln!(
            s,
            "  {} moves ({:.1} per dropped body), {:.3} µs per move on {} thread{}; {} re-drops; {} base-layer particles",
            r.moves,
            r.moves as f64 / dropped as f64,
            1e6 * r.seconds / r.moves.max(1) as f64,
            r.threads,
            if r.threads == 1 { "" } else { "s" },
            r.redrops,
            r.base_layer
        );
    }
    if !r.analysis.is_empty() {
        for (name, t) in &r.analysis {
            let _ = writeln!(s, "  {name:<28} {t:>9.3} s");
        }
        let all: f64 = r.analysis.iter().map(|e| e.1).sum();
        let _ = writeln!(
            s,
            "  contacts + packing + percolation (no enumeration): {:.3} s; all stages {all:.3} s",
            target_seconds(&r.analysis)
        );
    }
    s
}
