//! `packbed bench`: deposition throughput on equal spheres (discs in 2D).
//!
//! The bed: `n` particles of radius 10 dropped onto a bare floor (`base_layer =
//! "none"`, so that only drop and roll is timed), `fill.count = n`, in a box
//! whose side is about n^(1/3) diameters in 3D (n^(1/2) in 2D), so that the bed
//! ends up roughly as high as it is wide.

use crate::progress::Progress;
use anyhow::{Context, Result};
use clap::Args;
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
    /// Number of particles to deposit.
    #[arg(long, default_value_t = 100_000, allow_negative_numbers = true, value_parser = clap::value_parser!(u64).range(1..))]
    pub n: u64,
    /// Periodic side boundaries (no side walls).
    #[arg(long)]
    pub periodic: bool,
    /// Print one JSON object instead of a line of text.
    #[arg(long)]
    pub json: bool,
}

/// What `packbed bench --json` prints.
#[derive(Debug, Serialize)]
struct BenchResult {
    dim: u8,
    n: u64,
    periodic: bool,
    seconds: f64,
    particles_per_second: f64,
    peak_rss_bytes: u64,
}

/// The bench bed as a config.
fn bench_config(args: &BenchArgs) -> Config {
    let mut c = Config {
        dim: args.dim,
        seed: 1,
        ..Config::default()
    };
    // One lateral side in diameters: a cube (square) of n particles at random
    // close packing is about this wide; never narrower than 4 diameters.
    let side = (args.n as f64).powf(1.0 / args.dim as f64).max(4.0) * 2.0 * RADIUS;
    c.container.width = Some(side);
    c.container.depth = (args.dim == 3).then_some(side);
    c.container.height = Some(side);
    c.container.periodic = args.periodic;
    c.fill.count = Some(args.n);
    c.fill.base_layer = BaseLayerKind::None;
    c.species.truncate(1);
    c.species[0].radius = Some(RADIUS);
    c
}

/// Runs `packbed bench`.
pub fn bench(args: BenchArgs) -> Result<()> {
    let config = bench_config(&args);
    let mut progress = Progress::new(&config, args.json);
    let start = Instant::now();
    let built = packbed::deposit::build(&config, &mut |n| progress.update(n));
    let seconds = start.elapsed().as_secs_f64();
    progress.finish();
    let (bed, _) = built.context("bench")?;
    let n = match &bed {
        packbed::bed::AnyBed::D2(b) => b.len(),
        packbed::bed::AnyBed::D3(b) => b.len(),
    } as u64;
    let r = BenchResult {
        dim: args.dim,
        n,
        periodic: args.periodic,
        seconds,
        // A clock too coarse to see the run must not produce infinity.
        particles_per_second: n as f64 / seconds.max(1e-9),
        peak_rss_bytes: peak_rss_bytes().unwrap_or(0),
    };
    if args.json {
        println!("{}", serde_json::to_string(&r)?);
    } else {
        println!(
            "packbed bench: {}D, {} particles, {}: {:.3} s, {:.0} particles/s, peak RSS {:.1} MiB",
            r.dim,
            r.n,
            if r.periodic { "periodic" } else { "walls" },
            r.seconds,
            r.particles_per_second,
            r.peak_rss_bytes as f64 / (1 << 20) as f64
        );
    }
    Ok(())
}

/// Peak resident memory of this process (`VmHWM`), where Linux reports it.
fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
