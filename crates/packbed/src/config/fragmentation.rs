//! `[fragmentation]`: the load, the breaks and the springs of a bed's
//! breakage (`docs/reference/fragmentation.md`), shared by run configs and
//! `packbed fragment`.

use crate::error::{Error, Result};
use crate::math::Real;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

fn one() -> Real {
    1.0
}

/// Which load the bed carries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Load {
    /// `+F x̂` on the top bodies, `−F x̂` on the bottom bodies (the study's).
    #[default]
    Shear,
    /// `−F ẑ` on the top bodies; the floor reacts.
    Compression,
    /// Each body's weight, by solid volume, summing to F.
    Gravity,
}

impl Load {
    /// The name used in configs, options and `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            Load::Shear => "shear",
            Load::Compression => "compression",
            Load::Gravity => "gravity",
        }
    }
}

impl std::str::FromStr for Load {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "shear" => Ok(Load::Shear),
            "compression" => Ok(Load::Compression),
            "gravity" => Ok(Load::Gravity),
            _ => Err(Error::config(format!(
                "unknown load {s:?}: give shear, compression or gravity"
            ))),
        }
    }
}

/// How many bonds to break.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Breaks {
    /// Exactly this many (fewer if the bonds run out).
    Count(u64),
    /// Until the bed fails.
    #[default]
    Failure,
}

impl std::str::FromStr for Breaks {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        if s == "failure" {
            return Ok(Breaks::Failure);
        }
        match s.parse::<u64>() {
            Ok(0) => Err(Error::config(
                "fragmentation.breaks must be at least 1 (or \"failure\")",
            )),
            Ok(n) => Ok(Breaks::Count(n)),
            Err(_) => Err(Error::config(format!(
                "breaks must be a whole number of at least 1 or \"failure\", got {s:?}"
            ))),
        }
    }
}

impl std::fmt::Display for Breaks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Breaks::Count(n) => write!(f, "{n}"),
            Breaks::Failure => f.write_str("failure"),
        }
    }
}

/// `[fragmentation]`: the settings of a fragmentation (`packbed fragment`'s
/// options; in a run config, every run and replicate also breaks its bed).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FragmentationConfig {
    /// The load.
    #[serde(default)]
    pub load: Load,
    /// How many bonds to break: a number or `"failure"`.
    #[serde(default)]
    pub breaks: Breaks,
    /// `k_t / k_n` (`k_n = 1`).
    #[serde(default = "one")]
    pub kt_over_kn: Real,
}

impl Default for FragmentationConfig {
    fn default() -> Self {
        FragmentationConfig {
            load: Load::Shear,
            breaks: Breaks::Failure,
            kt_over_kn: 1.0,
        }
    }
}

impl FragmentationConfig {
    /// Refuses settings no bed can be broken with, naming them as a config
    /// file does (`fragmentation.breaks`).
    pub(crate) fn check(&self) -> Result<()> {
        self.check_naming(&|key| format!("fragmentation.{key}"))
    }

    /// `FragmentationConfig::check`, with the settings named by `name`
    /// (the command: `--kt-kn`).
    pub fn check_naming(&self, name: &dyn Fn(&str) -> String) -> Result<()> {
        if let Breaks::Count(0) = self.breaks {
            return Err(Error::config(format!(
                "{} must be at least 1 (or \"failure\")",
                name("breaks")
            )));
        }
        if !(self.kt_over_kn.is_finite() && self.kt_over_kn >= 0.0) {
            return Err(Error::config(format!(
                "{} must be a number >= 0, got {}",
                name("kt_over_kn"),
                self.kt_over_kn
            )));
        }
        Ok(())
    }
}

impl Serialize for Breaks {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            Breaks::Count(n) => s.serialize_u64(*n),
            Breaks::Failure => s.serialize_str("failure"),
        }
    }
}

impl<'de> Deserialize<'de> for Breaks {
    fn deserialize<De: Deserializer<'de>>(d: De) -> std::result::Result<Self, De::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            Count(i64),
            Word(String),
        }
        match Raw::deserialize(d)? {
            Raw::Count(n) if n >= 1 => Ok(Breaks::Count(n as u64)),
            Raw::Count(n) => Err(serde::de::Error::custom(format!(
                "breaks must be at least 1 (or \"failure\"), got {n}"
            ))),
            Raw::Word(w) => w
                .parse()
                .map_err(|e: Error| serde::de::Error::custom(e.message())),
        }
    }
}
