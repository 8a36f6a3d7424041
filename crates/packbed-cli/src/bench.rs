//! `packbed bench`: deposition throughput on equal spheres (discs in 2D) or
//! chains, and with `--analysis` the time of each analysis stage on that bed
//! (or on a bed read from a file). The bed and the timing are the library's
//! ([`packbed::bench`]); this file parses and prints.

use crate::progress::Progress;
use anyhow::{Context, Result};
use clap::Args;
use packbed::bench::{self, BenchBed};

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

/// Runs `packbed bench`.
pub fn bench(args: BenchArgs) -> Result<()> {
    let (bed, mut r) = match &args.bed {
        Some(path) => {
            let bed = packbed::io::read::read_bed(path, None)?;
            let r = bench::measured(&bed, None);
            (bed, r)
        }
        None => {
            let spec = BenchBed {
                dim: args.dim,
                n: args.n,
                chains: args.chains,
                periodic: args.periodic,
            };
            let mut progress = Progress::new(&spec.config(), args.json);
            let built = bench::deposit(&spec, &mut |n| progress.update(n));
            progress.finish();
            built.context("bench")?
        }
    };
    if args.analysis || args.bed.is_some() {
        r.analysis = bench::time_analysis(&bed);
    }
    if args.json {
        println!("{}", serde_json::to_string(&r)?);
        return Ok(());
    }
    let walls = if r.periodic { "periodic" } else { "walls" };
    let rss = r.peak_rss_bytes as f64 / (1 << 20) as f64;
    match (args.bed.is_some(), args.chains) {
        (true, _) => println!("packbed bench: {}D, {} particles, {walls}, read from file", r.dim, r.n),
        (false, Some(beads)) => println!(
            "packbed bench: {}D, {} chains of {beads} beads, {walls}: {:.3} s, {:.0} chains/s, {} re-drops, peak RSS {rss:.1} MiB",
            r.dim, r.bodies, r.seconds, r.bodies_per_second, r.redrops
        ),
        (false, None) => println!(
            "packbed bench: {}D, {} particles, {walls}: {:.3} s, {:.0} particles/s, peak RSS {rss:.1} MiB",
            r.dim, r.n, r.seconds, r.particles_per_second
        ),
    }
    if !r.analysis.is_empty() {
        for (name, t) in &r.analysis {
            println!("  {name:<28} {t:>9.3} s");
        }
        let all: f64 = r.analysis.iter().map(|e| e.1).sum();
        println!(
            "  contacts + packing + percolation (no enumeration): {:.3} s; all stages {all:.3} s",
            bench::target_seconds(&r.analysis)
        );
    }
    Ok(())
}
