//! One bed from start to finish: config → deposition → analysis → run summary.
//! `packbed run` and every replicate of an ensemble go through [`run_bed`], so a
//! replicate's `summary.json` is exactly what `run` would write for its seed.

use crate::analysis::Contacts;
use crate::bed::{AnyBed, Bed};
use crate::config::Config;
use crate::deposit::DepositReport;
use crate::error::Result;
use crate::io::{RunSummary, Timing};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A built and analysed bed with its summary.
#[derive(Clone, Debug)]
pub struct FinishedBed {
    /// The bed.
    pub bed: AnyBed,
    /// Particle and wall contacts found by the analysis.
    pub contacts: Contacts,
    /// Everything `summary.json` holds.
    pub summary: RunSummary,
}

/// Builds the bed of `config` (validated here), analyses it and gathers its
/// summary; `progress` is called with the number of particles placed so far.
pub fn run_bed(config: &Config, progress: &mut dyn FnMut(u64)) -> Result<FinishedBed> {
    let start = Instant::now();
    let (bed, deposit) = crate::deposit::build(config, progress)?;
    let (contacts, summary) = match &bed {
        AnyBed::D2(b) => analyse(config, b, &deposit, start),
        AnyBed::D3(b) => analyse(config, b, &deposit, start),
    };
    Ok(FinishedBed {
        bed,
        contacts,
        summary,
    })
}

fn analyse<const D: usize>(
    config: &Config,
    bed: &Bed<D>,
    deposit: &DepositReport,
    start: Instant,
) -> (Contacts, RunSummary) {
    let t = Instant::now();
    let options = crate::analysis::AnalysisOptions {
        bulk_min_bodies: config.analysis.bulk_min_bodies,
        angle_from: config.analysis.chain_angle_from,
        ..crate::analysis::AnalysisOptions::new(
            config.analysis.contact_tol,
            config.analysis.large_radius,
        )
    };
    let (contacts, analysis) = crate::analysis::analyze_with(bed, &options);
    let timing = Timing {
        deposit_seconds: deposit.deposit_seconds,
        analysis_seconds: t.elapsed().as_secs_f64(),
        total_seconds: start.elapsed().as_secs_f64(),
    };
    let summary = RunSummary::new(config, bed, deposit, &analysis, timing);
    (contacts, summary)
}

impl FinishedBed {
    /// Writes the run's files (`output::RUN_FILES`) into `dir`, atomically.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        match &self.bed {
            AnyBed::D2(b) => crate::output::write_run(dir, b, &self.contacts, &self.summary),
            AnyBed::D3(b) => crate::output::write_run(dir, b, &self.contacts, &self.summary),
        }
    }

    /// Writes the run's files plus pictures, plots and exports, atomically.
    pub fn write_with(
        &self,
        dir: &Path,
        extras: &crate::output::RunExtras,
    ) -> Result<Vec<PathBuf>> {
        match &self.bed {
            AnyBed::D2(b) => {
                crate::output::write_run_with(dir, b, &self.contacts, &self.summary, extras)
            }
            AnyBed::D3(b) => {
                crate::output::write_run_with(dir, b, &self.contacts, &self.summary, extras)
            }
        }
    }
}
