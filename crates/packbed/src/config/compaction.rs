//! `[compaction]`: after settling, lower the bed's potential energy by small
//! collective moves until no move lowers it (`deposit::compaction`). It moves
//! a settled bed toward the density of a frictionless DEM pour.
//!
//! - `steps` (default 1000): most steps;
//! - `step` (default 0.05): how far a free sphere falls in one step, in mean
//!   diameters (no sphere moves more than 1.5 steps);
//! - `until` (default 0.01): when a step lowers the centre of mass by less
//!   than this share of the step, the step is quartered, down to 10⁻³ of
//!   `step`, where the compaction stops once nothing moves.
//! - `friction` (default 0): the Coulomb coefficient of every contact, as
//!   the cone of Anitescu's convex relaxation (a contact slides only where
//!   the slope of the slide exceeds it).
//!
//! Spheres and discs only, on a bare floor (no chains, no laid medium), in
//! `mode = "deposit"`.

use crate::error::{Error, Result};
use crate::math::Real;
use serde::{Deserialize, Serialize};

/// `[compaction]` as written.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CompactionConfig {
    /// Most steps.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<u32>,
    /// How far a free sphere falls in one step, in mean diameters.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<Real>,
    /// Refine the step when a step lowers the centre of mass by less than
    /// this share of it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until: Option<Real>,
    /// The friction coefficient of the contacts (0: frictionless).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<Real>,
}

/// How a settled bed is compacted: `[compaction]`, resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Compaction {
    /// Most steps.
    pub steps: u32,
    /// How far a free sphere falls in one step, in mean diameters.
    pub step: Real,
    /// Refine the step when a step lowers the centre of mass by less than
    /// this share of it.
    pub until: Real,
    /// The friction coefficient of the contacts (0: frictionless).
    pub friction: Real,
}

/// Default most steps.
pub const DEFAULT_STEPS: u32 = 1000;
/// Default step, in mean diameters.
pub const DEFAULT_STEP: Real = 0.05;
/// Default convergence: a descent of 1 % of the step.
pub const DEFAULT_UNTIL: Real = 0.01;

impl CompactionConfig {
    /// The compaction, checked.
    pub fn resolve(&self) -> Result<Compaction> {
        let steps = self.steps.unwrap_or(DEFAULT_STEPS);
        let step = self.step.unwrap_or(DEFAULT_STEP);
        // A step beyond a quarter diameter lets the linearised contacts
        // hold pairs the step carries past one another's sides.
        let in_range = step > 0.0 && step <= 0.25;
        if !in_range {
            return Err(Error::config(format!(
                "compaction.step must be in (0, 0.25] mean diameters, got {}",
                crate::math::display_length(step)
            )));
        }
        let until = self.until.unwrap_or(DEFAULT_UNTIL);
        let in_range = until >= 0.0 && until.is_finite();
        if !in_range {
            return Err(Error::config(format!(
                "compaction.until must be a share of the step, 0 or more, got {}",
                crate::math::display_length(until)
            )));
        }
        let friction = self.friction.unwrap_or(0.0);
        // Beyond 10 a cone is all but a stop (a slide opens its contact ten
        // times as far), and the solver's scaling suffers.
        let in_range = (0.0..=10.0).contains(&friction);
        if !in_range {
            return Err(Error::config(format!(
                "compaction.friction must be a coefficient from 0 to 10, got {}",
                crate::math::display_length(friction)
            )));
        }
        Ok(Compaction {
            steps,
            step,
            until,
            friction,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_steps_and_convergence_are_refused_with_the_key() {
        let c = |step, until| CompactionConfig {
            steps: None,
            step,
            until,
            friction: None,
        };
        assert!(c(None, None).resolve().is_ok());
        for bad in [0.0, -0.1, 0.3, Real::NAN, Real::INFINITY] {
            let e = c(Some(bad), None).resolve().unwrap_err().to_string();
            assert!(e.contains("compaction.step must be"), "{e}");
        }
        for bad in [-1.0, Real::NAN, Real::INFINITY] {
            let e = c(None, Some(bad)).resolve().unwrap_err().to_string();
            assert!(e.contains("compaction.until must be"), "{e}");
        }
        for bad in [-0.1, 10.5, Real::NAN, Real::INFINITY] {
            let f = CompactionConfig {
                friction: Some(bad),
                ..Default::default()
            };
            let e = f.resolve().unwrap_err().to_string();
            assert!(e.contains("compaction.friction must be"), "{e}");
        }
    }
}
