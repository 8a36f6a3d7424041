//! Sequential deposition: particles settle one at a time under gravity.

use crate::bed::{AnyBed, Bed};
use crate::config::{Config, Plan};
use crate::error::Result;

/// What happened during deposition, for the run summary.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DepositReport {
    /// Particles placed by the base layer (random phase and gap-filling sweep).
    pub base_layer: u64,
    /// Particles placed by drop and roll.
    pub dropped: u64,
    /// Particles that found no rest within the move budget and were dropped again.
    pub redrops: u64,
    /// Particles discarded because they would stick out above the roof.
    pub roof_overflows: u64,
    /// Wall time of deposition in seconds.
    pub deposit_seconds: f64,
}

/// Builds a bed for a validated plan. `progress` is called now and then with the
/// number of particles placed so far.
pub fn deposit<const D: usize>(
    plan: &Plan<D>,
    progress: &mut dyn FnMut(u64),
) -> Result<(Bed<D>, DepositReport)> {
    let _ = (plan, progress);
    todo!("engine")
}

/// Builds the bed a configuration describes, in its dimension.
pub fn build(config: &Config, progress: &mut dyn FnMut(u64)) -> Result<(AnyBed, DepositReport)> {
    match config.dim {
        2 => deposit(&config.plan::<2>()?, progress).map(|(b, r)| (AnyBed::D2(b), r)),
        3 => deposit(&config.plan::<3>()?, progress).map(|(b, r)| (AnyBed::D3(b), r)),
        d => Err(crate::Error::config(format!("dim must be 2 or 3, got {d}"))),
    }
}
