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
    #[command(flatten)]
    pub spec: BenchBed,
    /// Lognormal radii of median 10 and this geometric standard deviation
    /// (truncated as a config's are by default) instead of equal spheres.
    #[arg(
        long,
        value_name = "G",
        conflicts_with = "radii",
        allow_negative_numbers = true
    )]
    pub gsd: Option<f64>,
    /// One species per radius, in equal numbers (e.g. `10,50`), instead of
    /// equal spheres of radius 10.
    #[arg(long, value_name = "R,R,...", value_parser = packbed::parse_numbers)]
    pub radii: Option<packbed::Numbers>,
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
    /// With `--pores`: also the drainage (water on glass, its curve, the
    /// pendular bridges and the relative permeabilities), the drying of the
    /// drained cake (solid bridges, agglomerates) and the transport
    /// (formation factor, tortuosity), each its own stage.
    #[arg(long, requires = "pores")]
    pub drainage: bool,
    /// Analyse this bed file (anything `packbed analyze` reads) instead of
    /// depositing one; implies `--analysis`.
    #[arg(long, value_name = "PATH")]
    pub bed: Option<std::path::PathBuf>,
}

/// Runs `packbed bench`.
pub fn bench(args: BenchArgs) -> Result<()> {
    let spec = BenchBed {
        sizes: match (args.gsd, &args.radii) {
            (Some(g), _) => BenchSizes::Lognormal(g),
            (None, Some(r)) => BenchSizes::Radii(r.clone()),
            (None, None) => BenchSizes::Equal,
        },
        ..args.spec
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
        r.analysis = bench::time_pores(&bed, args.drainage);
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
