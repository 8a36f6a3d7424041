//! `packbed bench`: deposition throughput on equal spheres (discs in 2D),
//! lognormal radii (`--gsd`), given radii (`--radii`) or chains, and with `--analysis` the time of each analysis stage on that bed
//! (or on a bed read from a file). The bed and the timing are the library's
//! ([`packbed::bench`]); this file parses and prints.

use crate::progress::Progress;
use anyhow::{Context, Result};
use clap::Args;
use packbed::bench::{self, BenchBed, BenchSizes};

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
    /// Lognormal radii of median 10 and this geometric standard deviation
    /// (truncated as a config's are by default) instead of equal spheres.
    #[arg(long, value_name = "G", conflicts_with = "radii")]
    pub gsd: Option<f64>,
    /// One species per radius, in equal numbers (e.g. `10,50`), instead of
    /// equal spheres of radius 10.
    #[arg(long, value_name = "R,R,...", value_parser = crate::overrides::numbers)]
    pub radii: Option<crate::overrides::Numbers>,
    /// Seed the floor with the random base layer first (timed with the rest).
    #[arg(long)]
    pub base_layer: bool,
    /// Print one JSON object instead of a line of text.
    #[arg(long)]
    pub json: bool,
    /// Also time every analysis stage on the bed (contacts, packing,
    /// percolation, …), the unique-chain enumeration included.
    #[arg(long)]
    pub analysis: bool,
    /// Time the pore space instead (triangulation, network, flow along every
    /// axis), after the contacts and packing it needs.
    #[arg(long)]
    pub pores: bool,
    /// Analyse this bed file (anything `packbed analyze` reads) instead of
    /// depositing one; implies `--analysis`.
    #[arg(long, value_name = "PATH")]
    pub bed: Option<std::path::PathBuf>,
}

/// Runs `packbed bench`.
pub fn bench(args: BenchArgs) -> Result<()> {
    let spec = BenchBed {
        dim: args.dim,
        n: args.n,
        chains: args.chains,
        periodic: args.periodic,
        sizes: match (args.gsd, &args.radii) {
            (Some(g), _) => BenchSizes::Lognormal(g),
            (None, Some(r)) => BenchSizes::Radii(r.clone()),
            (None, None) => BenchSizes::Equal,
        },
        base_layer: args.base_layer,
    };
    let (bed, mut r) = match &args.bed {
        Some(path) => {
            let bed = packbed::read_bed(path, None)?;
            let r = bench::measured(&bed, None);
            (bed, r)
        }
        None => {
            let mut progress = Progress::new(spec.config().estimated_particles(), args.json);
            let built = bench::deposit(&spec, &mut |n| progress.update(n));
            progress.finish();
            built.context("bench")?
        }
    };
    if args.pores {
        r.analysis = bench::time_pores(&bed);
    } else if args.analysis || args.bed.is_some() {
        r.analysis = bench::time_analysis(&bed);
    }
    if args.json {
        println!("{}", serde_json::to_string(&r)?);
    } else {
        print!("{}", bench::text(&r, args.bed.is_none().then_some(&spec)));
    }
    Ok(())
}
