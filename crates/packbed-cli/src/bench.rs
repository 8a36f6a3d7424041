//! `packbed bench`: deposition throughput on equal spheres (discs in 2D), and
//! with `--analysis` the time of each analysis stage on that bed (or on a bed
//! read from a file).
//!
//! The bed: `n` particles of radius 10 dropped onto a bare floor (`base_layer =
//! "none"`, so that only drop and roll is timed), `fill.count = n`, in a box
//! whose side is about n^(1/3) diameters in 3D (n^(1/2) in 2D), so that the bed
//! ends up roughly as high as it is wide.

use crate::progress::Progress;
use anyhow::{Context, Result};
use clap::Args;
use packbed::analysis::{analyze_timed, AnalysisOptions, StageTimes};
use packbed::bed::{AnyBed, Bed};
use packbed::config::{BaseLayerKind, Config};
use serde::Serialize;
use std::time::Instant;

/// Radius of every bench particle.
const RADIUS: f64 = 10.0;

/// Arguments of `packbed bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u8).range(2..=3))]
    pub dim: u8,
    /// Number of particles to deposit (of chains, with `--chains`).
    #[arg(long, default_value_t = 100_000, allow_negative_numbers = true, value_parser = clap::value_parser!(u64).range(1..))]
    pub n: u64,
    /// Deposit rigid chains of this many beads (radius 10, spacing 1.0,
    /// entering upright) instead of spheres; `--n` counts chains.
    #[arg(long, value_name = "BEADS", value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub chains: Option<u32>,
    /// Periodic side boundaries (no side walls).
    #[arg(long)]
    pub periodic: bool,
    /// Print one JSON object instead of a line of text.
    #[arg(long)]
    pub json: bool,
    /// Also time every analysis stage on the bed (contacts, packing,
    /// percolation, …), the unique-chain enumeration included.
    #[arg(long)]
    pub analysis: bool,
    /// Analyse this bed file (anything `packbed analyze` reads) instead of
    /// depositing one; implies `--analysis`.
    #[arg(long, value_name = "PATH")]
    pub bed: Option<std::path::PathBuf>,
}

/// What `packbed bench --json` prints.
#[derive(Debug, Serialize)]
struct BenchResult {
    dim: u8,
    n: u64,
    periodic: bool,
    seconds: f64,
    particles_per_second: f64,
    /// Bodies (chains, or particles) deposited and per second.
    bodies: u64,
    bodies_per_second: f64,
    /// Particles re-dropped because they found no rest.
    redrops: u64,
    peak_rss_bytes: u64,
    /// Seconds per analysis stage, stages of the same name summed.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    analysis: Vec<(String, f64)>,
}

/// The bench bed as a config.
fn bench_config(args: &BenchArgs) -> Config {
    let mut c = Config {
        dim: args.dim,
        seed: 1,
        ..Config::default()
    };
    // One lateral side in diameters: a cube (square) of n particles at random
    // close packing is about this wide; never narrower than 4 diameters. A
    // chain counts as its beads, and the box is at least two chains wide.
    let beads = args.chains.unwrap_or(1);
    let particles = args.n.saturating_mul(u64::from(beads));
    let chain_length = (f64::from(beads) + 1.0) * RADIUS;
    let side = ((particles as f64).powf(1.0 / args.dim as f64).max(4.0) * 2.0 * RADIUS)
        .max(2.0 * chain_length);
    c.container.width = Some(side);
    c.container.depth = (args.dim == 3).then_some(side);
    c.container.height = Some(side);
    c.container.periodic = args.periodic;
    c.fill.count = Some(particles);
    c.fill.base_layer = BaseLayerKind::None;
    c.species.truncate(1);
    c.species[0].radius = Some(RADIUS);
    if let Some(b) = args.chains {
        c.species[0].shape = "chain".into();
        c.species[0].beads = Some(b);
    }
    c
}

/// Runs `packbed bench`.
pub fn bench(args: BenchArgs) -> Result<()> {
    let (bed, seconds, redrops) = match &args.bed {
        Some(path) => (packbed::io::read::read_bed(path, None)?, None, 0),
        None => {
            let config = bench_config(&args);
            let mut progress = Progress::new(&config, args.json);
            let start = Instant::now();
            let built = packbed::deposit::build(&config, &mut |n| progress.update(n));
            let seconds = start.elapsed().as_secs_f64();
            progress.finish();
            let (bed, report) = built.context("bench")?;
            (bed, Some(seconds), report.redrops)
        }
    };
    let analysis = if args.analysis || args.bed.is_some() {
        match &bed {
            AnyBed::D2(b) => time_analysis(b),
            AnyBed::D3(b) => time_analysis(b),
        }
    } else {
        Vec::new()
    };
    let (dim, n, bodies, periodic) = match &bed {
        AnyBed::D2(b) => (2, b.len(), b.body_count(), b.container.periodic),
        AnyBed::D3(b) => (3, b.len(), b.body_count(), b.container.periodic),
    };
    let r = BenchResult {
        dim,
        n: n as u64,
        periodic,
        seconds: seconds.unwrap_or(0.0),
        // A clock too coarse to see the run must not produce infinity.
        particles_per_second: seconds.map_or(0.0, |s| n as f64 / s.max(1e-9)),
        bodies: bodies as u64,
        bodies_per_second: seconds.map_or(0.0, |s| bodies as f64 / s.max(1e-9)),
        redrops,
        peak_rss_bytes: peak_rss_bytes().unwrap_or(0),
        analysis,
    };
    if args.json {
        println!("{}", serde_json::to_string(&r)?);
        return Ok(());
    }
    let walls = if r.periodic { "periodic" } else { "walls" };
    match seconds {
        Some(s) if args.chains.is_some() => println!(
            "packbed bench: {}D, {} chains of {} beads, {walls}: {s:.3} s, {:.0} chains/s, {} re-drops, peak RSS {:.1} MiB",
            r.dim,
            r.bodies,
            args.chains.unwrap_or(1),
            r.bodies_per_second,
            r.redrops,
            r.peak_rss_bytes as f64 / (1 << 20) as f64
        ),
        Some(s) => println!(
            "packbed bench: {}D, {} particles, {walls}: {s:.3} s, {:.0} particles/s, peak RSS {:.1} MiB",
            r.dim,
            r.n,
            r.particles_per_second,
            r.peak_rss_bytes as f64 / (1 << 20) as f64
        ),
        None => println!("packbed bench: {}D, {} particles, {walls}, read from file", r.dim, r.n),
    }
    if !r.analysis.is_empty() {
        for (name, t) in &r.analysis {
            println!("  {name:<28} {t:>9.3} s");
        }
        let target: f64 = r
            .analysis
            .iter()
            .filter(|(name, _)| TARGET_STAGES.iter().any(|p| name.starts_with(p)))
            .map(|e| e.1)
            .sum();
        let all: f64 = r.analysis.iter().map(|e| e.1).sum();
        println!("  contacts + packing + percolation (no enumeration): {target:.3} s; all stages {all:.3} s");
    }
    Ok(())
}

/// The stages the analysis speed target counts (`spec/performance.md`):
/// contacts, packing and percolation without the capped chain enumeration.
const TARGET_STAGES: [&str; 6] = [
    "contacts",
    "packing/",
    "percolation/graph",
    "percolation/clusters",
    "percolation/shortest",
    "percolation/disjoint",
];

/// Seconds per analysis stage on `bed` with default settings, stages of the same
/// name summed, in the order they first ran.
fn time_analysis<const D: usize>(bed: &Bed<D>) -> Vec<(String, f64)> {
    let mut times = StageTimes::default();
    let _ = analyze_timed(bed, &AnalysisOptions::default(), &mut times);
    let mut out: Vec<(String, f64)> = Vec::new();
    for (name, t) in times.0 {
        match out.iter_mut().find(|e| e.0 == name) {
            Some(e) => e.1 += t,
            None => out.push((name.to_string(), t)),
        }
    }
    out
}

/// Peak resident memory of this process (`VmHWM`), where Linux reports it.
fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
