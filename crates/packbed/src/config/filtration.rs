//! `[filtration]`: the filtration of the slurry feeds through the medium,
//! read as a laboratory reads it (Ruth's t/V against V):
//!
//! ```toml
//! [filtration]
//! pressure = 1e5        # Pa, constant pressure drop; or flow_rate (m/s)
//! viscosity = 1e-3      # Pa s, the filtrate's
//! concentration = 50    # kg of solids deposited per m³ of filtrate (Ruth's c)
//! checkpoints = 20      # cake levels the flow is solved at
//! stop = { pressure = 5e5, time = 600, mass = 2.0 }  # any of them: Pa, s, kg/m²
//! ```
//!
//! It needs a medium (`[[feeds]]` with `medium = true`) and the SI scale of
//! the bed: `[analysis] length_unit` and `solid_density`.

use crate::error::{Error, Result};
use crate::math::Real;
use serde::{Deserialize, Serialize};

/// The most checkpoints of a filtration.
pub const MAX_CHECKPOINTS: u32 = 1000;

/// `[filtration]` as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FiltrationConfig {
    /// Constant pressure drop across medium and cake, Pa.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pressure: Option<Real>,
    /// Constant filtrate flux (volume per area per time), m/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flow_rate: Option<Real>,
    /// The filtrate's viscosity, Pa s.
    #[serde(default = "default_viscosity")]
    pub viscosity: Real,
    /// Mass of solids deposited per volume of filtrate, kg/m³.
    pub concentration: Real,
    /// Cake levels the flow is solved at.
    #[serde(default = "default_checkpoints")]
    pub checkpoints: u32,
    /// Where the filtration stops, if before the last checkpoint.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop: Option<FiltrationStop>,
}

/// `[filtration] stop`: the first reached ends the curve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FiltrationStop {
    /// Pressure drop, Pa (at constant flow rate).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pressure: Option<Real>,
    /// Time, s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<Real>,
    /// Cake mass per area, kg/m².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<Real>,
}

fn default_viscosity() -> Real {
    1e-3
}

fn default_checkpoints() -> u32 {
    20
}

/// How the filtration is driven.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Drive {
    /// Constant pressure drop, Pa.
    Pressure(Real),
    /// Constant flux, m/s.
    FlowRate(Real),
}

impl FiltrationConfig {
    /// The drive, checked with every other setting: one line on bad input.
    pub fn drive(&self) -> Result<Drive> {
        let positive = |name: &str, v: Real| {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(Error::config(format!(
                    "filtration.{name} must be a positive number, got {v}"
                )))
            }
        };
        positive("viscosity", self.viscosity)?;
        positive("concentration", self.concentration)?;
        if !(2..=MAX_CHECKPOINTS).contains(&self.checkpoints) {
            return Err(Error::config(format!(
                "filtration.checkpoints must be from 2 to {MAX_CHECKPOINTS}, got {}",
                self.checkpoints
            )));
        }
        if let Some(s) = &self.stop {
            for (name, v) in [("pressure", s.pressure), ("time", s.time), ("mass", s.mass)] {
                if let Some(v) = v {
                    positive(&format!("stop.{name}"), v)?;
                }
            }
        }
        match (self.pressure, self.flow_rate) {
            (Some(p), None) => Ok(Drive::Pressure(positive("pressure", p)?)),
            (None, Some(q)) => Ok(Drive::FlowRate(positive("flow_rate", q)?)),
            _ => Err(Error::config(
                "filtration: give either `pressure` (Pa, constant pressure) or `flow_rate` (m/s, constant rate), one of them",
            )),
        }
    }
}
