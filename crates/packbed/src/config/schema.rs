//! The TOML schema (`docs/reference/formats.md`, "The config file"): every table and key a config
//! file may hold (strict: unknown keys are errors), their defaults, and reading
//! a file.

use super::feed::FeedConfig;
use super::fragmentation::FragmentationConfig;
use super::settling::SettlingConfig;
use super::AnalysisConfig;
use crate::error::{Error, Result};
use crate::math::Real;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Deposition under gravity, or random sequential addition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Sequential drop-and-roll deposition.
    #[default]
    Deposit,
    /// Random sequential addition (no gravity).
    Rsa,
}

/// How the floor is prepared before deposition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BaseLayerKind {
    /// Random saturated layer on the floor, then a gap-filling sweep.
    #[default]
    Random,
    /// Bare floor.
    None,
}

/// The whole configuration file, as written by the user (defaults filled in).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// 2 or 3.
    #[serde(default = "default_dim")]
    pub dim: u8,
    /// Seed of the run's random generator.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// `deposit` or `rsa`.
    #[serde(default)]
    pub mode: Mode,
    /// The container.
    #[serde(default, rename = "box")]
    pub container: BoxConfig,
    /// When to stop, and the base layer.
    #[serde(default)]
    pub fill: FillConfig,
    /// The species, at least one.
    #[serde(default = "default_species")]
    pub species: Vec<SpeciesConfig>,
    /// How a dropped particle comes to rest (default: it rolls until held).
    #[serde(default, skip_serializing_if = "SettlingConfig::is_default")]
    pub settling: SettlingConfig,
    /// Where particles enter (default: uniformly over the box).
    #[serde(default, skip_serializing_if = "FeedConfig::is_default")]
    pub feed: FeedConfig,
    /// Compact the settled bed (`[compaction]`; default: not).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compaction: Option<super::CompactionConfig>,
    /// Several feeds, one after another (`[[feeds]]`); empty: one feed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub feeds: Vec<super::FeedStageConfig>,
    /// Analysis settings.
    #[serde(default)]
    pub analysis: AnalysisConfig,
    /// The filtration of the slurry through the medium (`filtration.*` in
    /// the summary, `filtration.csv`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filtration: Option<super::FiltrationConfig>,
    /// Load and break every bed (`fragmentation.*` in its summary).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fragmentation: Option<FragmentationConfig>,
    /// Defaults of `packbed ensemble` (the replicate count); ignored by `run`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ensemble: Option<EnsembleConfig>,
    /// Values of one parameter to run as separate ensembles (`packbed ensemble`
    /// only: `run` refuses a config with a sweep, since it builds one bed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SweepConfig>,
}

/// `[box]`: a preset, a cube of `diameters` large diameters, or explicit sizes.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxConfig {
    /// `"thesis"` (the default when nothing else is given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// A cube (square in 2D) of side `diameters × 2 r_max`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diameters: Option<Real>,
    /// Explicit width (x).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<Real>,
    /// Explicit depth (y, 3D only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<Real>,
    /// Explicit height (roof).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<Real>,
    /// Periodic side boundaries.
    #[serde(default)]
    pub periodic: bool,
}

/// `[fill]`: stop at the roof or after a count; base layer.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FillConfig {
    /// `"roof"` (default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until: Option<String>,
    /// Place exactly this many particles (the roof is ignored).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub count: Option<u64>,
    /// Roof misses (particles that would stick out above the roof, discarded)
    /// tolerated in total before stopping; the next one stops the fill.
    #[serde(default = "default_roof_misses")]
    pub roof_misses: u64,
    /// `random` or `none`.
    #[serde(default)]
    pub base_layer: BaseLayerKind,
}

/// The source study kept dropping after a particle stuck out above the roof
/// and stopped only after many such misses; 100 in total reproduces its
/// published packing fractions in 2D and 3D (`docs/reference/model.md`, "Filling").
pub const DEFAULT_ROOF_MISSES: u64 = 100;

fn default_roof_misses() -> u64 {
    DEFAULT_ROOF_MISSES
}

impl Default for FillConfig {
    fn default() -> Self {
        FillConfig {
            until: None,
            count: None,
            roof_misses: DEFAULT_ROOF_MISSES,
            base_layer: BaseLayerKind::Random,
        }
    }
}

/// `[[species]]`: one species.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeciesConfig {
    /// Optional name used in reports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Fixed radius (or give `size`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<Real>,
    /// A size distribution instead of a fixed radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<SizeConfig>,
    /// Number ratio.
    #[serde(default = "default_ratio")]
    pub ratio: Real,
    /// `sphere` (default) or `chain`.
    #[serde(default = "default_shape")]
    pub shape: String,
    /// Beads per chain.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beads: Option<u32>,
    /// Bead centre distance in radii.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<Real>,
    /// Chain orientation on entry.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<String>,
}

/// `size = { dist = "...", ... }` or `size = { table = "psd.csv" }`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SizeConfig {
    /// `normal`, `lognormal` or `uniform`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dist: Option<String>,
    /// Normal: mean radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean: Option<Real>,
    /// Normal: standard deviation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sd: Option<Real>,
    /// Lognormal: median radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub median: Option<Real>,
    /// Lognormal: geometric standard deviation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gsd: Option<Real>,
    /// Uniform: smallest radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<Real>,
    /// Uniform: largest radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<Real>,
    /// A PSD table (relative to the config file): discrete sizes, sieve
    /// classes or a cumulative curve, as its header says ([`SizeTable`]).
    ///
    /// [`SizeTable`]: crate::species::SizeTable
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<PathBuf>,
    /// How sizes spread within a class of a table: `log-uniform` (default) or
    /// `uniform`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub within: Option<String>,
    /// A sieve table's smallest size in the pan, in the table's size unit
    /// (default: half the finest aperture).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pan_min: Option<Real>,
}

/// `[sweep]`: the parameter to vary and its values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepConfig {
    /// One of [`crate::ensemble::sweep::PARAMETERS`].
    pub parameter: String,
    /// The values, in the order the sweep runs and reports them.
    pub values: Vec<SweepValue>,
    /// Names of the values in tables and directory names (default: from the values).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub labels: Option<Vec<String>>,
}

/// One value of a swept parameter: a number, a list of numbers, a text
/// (a PSD table's file), or a switch.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SweepValue {
    /// A single number.
    Number(f64),
    /// A list of numbers.
    List(Vec<f64>),
    /// A text: a file name.
    Text(String),
    /// A switch: `true` or `false`.
    Flag(bool),
}

/// `[ensemble]`: defaults of `packbed ensemble` stored with the config.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnsembleConfig {
    /// Number of replicate beds (per sweep value) when `--runs` is not given.
    pub runs: u64,
}

fn default_dim() -> u8 {
    3
}
fn default_seed() -> u64 {
    1
}
fn default_ratio() -> Real {
    1.0
}
fn default_shape() -> String {
    "sphere".into()
}
fn default_species() -> Vec<SpeciesConfig> {
    [20.0, 10.0]
        .iter()
        .map(|&r| SpeciesConfig {
            name: None,
            radius: Some(r),
            size: None,
            ratio: 1.0,
            shape: default_shape(),
            beads: None,
            spacing: None,
            orientation: None,
        })
        .collect()
}

impl Default for Config {
    fn default() -> Self {
        Config {
            dim: default_dim(),
            seed: default_seed(),
            mode: Mode::default(),
            container: BoxConfig::default(),
            fill: FillConfig::default(),
            species: default_species(),
            settling: SettlingConfig::default(),
            feed: FeedConfig::default(),
            compaction: None,
            feeds: Vec::new(),
            analysis: AnalysisConfig::default(),
            filtration: None,
            fragmentation: None,
            ensemble: None,
            sweep: None,
        }
    }
}

impl Config {
    /// Parses a TOML configuration; `origin` names the file in error messages.
    pub fn from_toml(text: &str, origin: &str) -> Result<Config> {
        // `FILE:LINE: what`, the shape of every error with a place in a file.
        toml::from_str(text).map_err(|e| {
            let message = e.message().trim().to_string();
            match e.span() {
                Some(s) => Error::Data {
                    path: origin.into(),
                    line: text[..s.start.min(text.len())].matches('\n').count() + 1,
                    message,
                },
                None => Error::config(format!("{origin}: {message}")),
            }
        })
    }

    /// Reads and parses a TOML configuration file.
    pub fn from_file(path: &Path) -> Result<Config> {
        let text = crate::input::read_text(path)?;
        let mut c = Config::from_toml(&text, &path.display().to_string())?;
        // PSD tables are relative to the config file, and so are the tables
        // a sweep goes through.
        if let Some(dir) = path.parent() {
            for s in &mut c.species {
                if let Some(SizeConfig { table: Some(t), .. }) = &mut s.size {
                    if t.is_relative() {
                        *t = dir.join(&*t);
                    }
                }
            }
            // So is a medium's bed file.
            for f in &mut c.feeds {
                if let Some(t) = &mut f.file {
                    if t.is_relative() {
                        *t = dir.join(&*t);
                    }
                }
            }
            if let Some(sweep) = &mut c.sweep {
                if sweep.parameter.ends_with(".size.table") {
                    for v in &mut sweep.values {
                        if let SweepValue::Text(t) = v {
                            if Path::new(t.as_str()).is_relative() {
                                *t = dir.join(&*t).display().to_string();
                            }
                        }
                    }
                }
            }
        }
        Ok(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_file_is_the_default_bed() {
        let c = Config::from_toml("", "empty.toml").unwrap();
        let d = Config::default();
        assert_eq!((c.dim, c.seed, c.mode), (d.dim, d.seed, d.mode));
        let radii: Vec<_> = c.species.iter().map(|s| s.radius).collect();
        assert_eq!(radii, [Some(20.0), Some(10.0)]);
        assert_eq!(c.fill.roof_misses, DEFAULT_ROOF_MISSES);
    }

    #[test]
    fn an_unknown_key_is_refused_at_its_line() {
        let e = Config::from_toml("dim = 3\n\n[box]\nwidht = 200\n", "c.toml").unwrap_err();
        let Error::Data {
            path,
            line,
            message,
        } = &e
        else {
            panic!("expected a FILE:LINE error, got {e:?}");
        };
        assert_eq!((path.to_str(), *line), (Some("c.toml"), 4));
        assert!(message.contains("widht"), "{message}");
    }

    #[test]
    fn tables_are_read_relative_to_the_config_file() {
        let dir = std::env::temp_dir().join(format!("packbed-schema-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("c.toml");
        std::fs::write(
            &path,
            "[[species]]\nsize = { table = \"psd.csv\" }\n\
             [sweep]\nparameter = \"species.0.size.table\"\nvalues = [\"a.csv\", \"/abs/b.csv\"]\n",
        )
        .unwrap();
        let c = Config::from_file(&path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let table = c.species[0].size.as_ref().unwrap().table.as_ref().unwrap();
        assert_eq!(table, &dir.join("psd.csv"));
        let values = &c.sweep.unwrap().values;
        assert_eq!(
            values[0],
            SweepValue::Text(dir.join("a.csv").display().to_string())
        );
        assert_eq!(values[1], SweepValue::Text("/abs/b.csv".into()));
    }
}
