//! Random sequential addition: particles at uniform random points, no gravity,
//! until saturation.

use crate::bed::Bed;
use crate::config::Plan;
use crate::deposit::DepositReport;
use crate::error::{Error, Result};

/// Builds an RSA bed for a validated plan.
pub fn rsa<const D: usize>(
    plan: &Plan<D>,
    progress: &mut dyn FnMut(u64),
) -> Result<(Bed<D>, DepositReport)> {
    let _ = (plan, progress);
    Err(Error::Impossible(
        "mode = \"rsa\" (random sequential addition) is not implemented yet".into(),
    ))
}
