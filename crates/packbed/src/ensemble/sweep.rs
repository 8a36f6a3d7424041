//! Sweeps: one config, several values of one parameter. The `[sweep]` table of a
//! config names the parameter and lists its values; `packbed ensemble` runs an
//! ensemble for every value (same master seed, so the values are compared on
//! the same replicate seeds) and tabulates them side by side.
//!
//! ```toml
//! [sweep]
//! parameter = "ratio"                       # see PARAMETERS
//! values = [[1, 1], [1, 1.5], [1, 2]]
//! labels = ["1:1", "1:1.5", "1:2"]          # optional
//! ```

// The `[sweep]` and `[ensemble]` tables are part of the config schema.
use crate::config::{feed_parameter, species_parameter, Config, Edit};
pub use crate::config::{SweepConfig, SweepValue};
use crate::error::{Error, Result};

/// The parameters a sweep can vary, with the form of their values.
pub use crate::config::SWEEP_PARAMETERS as PARAMETERS;

/// One value of a sweep, resolved: the config to run and how to name it.
#[derive(Clone, Debug)]
pub struct SweepPoint {
    /// Position in the sweep (0-based).
    pub index: usize,
    /// Human label, e.g. `1:1.5`.
    pub label: String,
    /// Directory name under `sweep/`, e.g. `01-ratio-1-1.5`.
    pub dir: String,
    /// The value as given.
    pub value: SweepValue,
    /// The config with the value applied and no `[sweep]` left.
    pub config: Config,
}

fn fmt_num(x: f64) -> String {
    format!("{x}")
}

impl SweepValue {
    fn numbers(&self) -> Vec<f64> {
        match self {
            SweepValue::Number(x) => vec![*x],
            SweepValue::List(v) => v.clone(),
            SweepValue::Text(_) | SweepValue::Flag(_) => Vec::new(),
        }
    }
}

/// Text → `a-b-c` safe for a directory name.
fn slug(text: &str) -> String {
    let mut s = String::new();
    for c in text.chars() {
        if c.is_ascii_alphanumeric() || c == '.' {
            s.push(c.to_ascii_lowercase());
        } else if !s.ends_with('-') {
            s.push('-');
        }
    }
    s.trim_matches(|c| c == '-' || c == '.').to_string()
}

impl SweepConfig {
    /// Resolves every value into a config to run (validated), for a base config
    /// whose `sweep` is this one.
    pub fn points(&self, base: &Config) -> Result<Vec<SweepPoint>> {
        let known = PARAMETERS
            .iter()
            .map(|(p, _)| *p)
            .collect::<Vec<_>>()
            .join(", ");
        let p = self.parameter.as_str();
        if !PARAMETERS.iter().any(|(q, _)| *q == p)
            && species_parameter(p).is_none()
            && feed_parameter(p).is_none()
        {
            return Err(Error::config(format!(
                "sweep.parameter: unknown parameter `{p}` (expected one of {known})"
            )));
        }
        if self.values.is_empty() {
            return Err(Error::config("sweep.values: give at least one value"));
        }
        if let Some(l) = &self.labels {
            if l.len() != self.values.len() {
                return Err(Error::config(format!(
                    "sweep.labels has {} labels for {} values",
                    l.len(),
                    self.values.len()
                )));
            }
        }
        let mut points = Vec::with_capacity(self.values.len());
        let mut dirs = std::collections::HashSet::new();
        let short = p.rsplit('.').next().unwrap_or(p);
        for (i, value) in self.values.iter().enumerate() {
            let mut config = base.clone();
            config.sweep = None;
            let edit = Edit::from_sweep(p, value)
                .map_err(|e| Error::config(format!("sweep.values[{i}]: {e}")))?;
            let place = format!("sweep.values[{i}]");
            config
                .apply(&edit)
                .map_err(|e| e.within(p).within(&place))?;
            crate::pipeline::planned(&config).map_err(|e| e.within(&place))?;
            let nums = value.numbers();
            let text: Vec<String> = match value {
                // A table is named by its file's stem.
                SweepValue::Text(t) => vec![std::path::Path::new(t)
                    .file_stem()
                    .map_or_else(|| t.clone(), |s| s.to_string_lossy().into_owned())],
                SweepValue::Flag(b) => vec![b.to_string()],
                _ => nums.iter().map(|&x| fmt_num(x)).collect(),
            };
            let label = match &self.labels {
                Some(l) => l[i].clone(),
                None if p == "ratio" => text.join(":"),
                None => text.join(", "),
            };
            let name = match &self.labels {
                Some(l) => slug(&l[i]),
                None => slug(&format!("{short}-{}", text.join("-"))),
            };
            let dir = format!("{i:02}-{name}");
            if !dirs.insert(name.clone()) {
                return Err(Error::config(format!(
                    "sweep: two values would share the directory name `{name}`; give distinct `labels`"
                )));
            }
            points.push(SweepPoint {
                index: i,
                label,
                dir,
                value: value.clone(),
                config,
            });
        }
        Ok(points)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(text: &str) -> Config {
        Config::from_toml(text, "test").unwrap()
    }

    #[test]
    fn ratio_sweep() {
        let c = config("dim = 2\n[sweep]\nparameter = \"ratio\"\nvalues = [[1, 1], [1, 1.5]]\n");
        let pts = c.sweep.as_ref().unwrap().points(&c).unwrap();
        assert_eq!(pts.len(), 2);
        assert_eq!(pts[1].label, "1:1.5");
        assert_eq!(pts[1].dir, "01-ratio-1-1.5");
        assert_eq!(pts[1].config.species[1].ratio, 1.5);
        assert!(pts[1].config.sweep.is_none());
    }

    #[test]
    fn radii_sweep_changes_species_count() {
        let c = config("[sweep]\nparameter = \"radii\"\nvalues = [[10], [10, 20], [10, 50]]\n");
        let pts = c.sweep.as_ref().unwrap().points(&c).unwrap();
        assert_eq!(pts[0].config.species.len(), 1);
        assert_eq!(pts[2].config.species[1].radius, Some(50.0));
        assert_eq!(pts[0].dir, "00-radii-10");
    }

    #[test]
    fn size_distributions_are_swept() {
        let base = "[fill]\ncount = 100\n[[species]]\nsize = { dist = \"lognormal\", median = 10, gsd = 1.2 }\n";
        let c = config(&format!(
            "{base}[sweep]\nparameter = \"species[0].size.gsd\"\nvalues = [1.2, 1.6, 2.0]\n"
        ));
        let pts = c.sweep.as_ref().unwrap().points(&c).unwrap();
        let gsd: Vec<Option<f64>> = pts
            .iter()
            .map(|p| p.config.species[0].size.as_ref().unwrap().gsd)
            .collect();
        assert_eq!(gsd, [Some(1.2), Some(1.6), Some(2.0)]);
        assert_eq!(pts[2].dir, "02-gsd-2");
        let c = config(&format!(
            "{base}[sweep]\nparameter = \"species[0].size.median\"\nvalues = [5, 20]\n"
        ));
        let pts = c.sweep.as_ref().unwrap().points(&c).unwrap();
        assert_eq!(
            pts[1].config.species[0].size.as_ref().unwrap().median,
            Some(20.0)
        );
        // A sweep over measured tables: each value is a file, named by its stem.
        let dir = tempfile::tempdir().unwrap();
        for name in ["batch-a", "batch-b"] {
            std::fs::write(
                dir.path().join(format!("{name}.csv")),
                "radius_min,radius_max,mass\n5,10,1\n10,20,1\n",
            )
            .unwrap();
        }
        let path = dir.path().join("sweep.toml");
        std::fs::write(
            &path,
            "[[species]]\nradius = 10\n[sweep]\nparameter = \"species[0].size.table\"\nvalues = [\"batch-a.csv\", \"batch-b.csv\"]\n",
        )
        .unwrap();
        let c = Config::from_file(&path).unwrap();
        let pts = c.sweep.as_ref().unwrap().points(&c).unwrap();
        assert_eq!(pts[1].label, "batch-b");
        assert_eq!(pts[1].dir, "01-table-batch-b");
        let size = pts[1].config.species[0].size.as_ref().unwrap();
        assert_eq!(
            size.table.as_deref(),
            Some(dir.path().join("batch-b.csv").as_path())
        );
        assert_eq!(pts[1].config.species[0].radius, None);
    }

    #[test]
    fn the_drying_and_the_drainage_are_swept() {
        let base = "[analysis]\nlength_unit = \"um\"\nmeasures = [\"agglomeration\"]\n\
                    [analysis.drying]\nsolubility = 50\n";
        let swept = |parameter: &str, values: &str| {
            let c = config(&format!(
                "{base}[sweep]\nparameter = \"{parameter}\"\nvalues = {values}\n"
            ));
            c.sweep.as_ref().unwrap().points(&c).unwrap()
        };
        let pts = swept("analysis.drying.concentration", "[50, 6.77, 0.92]");
        let c: Vec<f64> = pts
            .iter()
            .map(|p| p.config.analysis.drying.concentration)
            .collect();
        assert_eq!(c, [50.0, 6.77, 0.92]);
        assert_eq!(pts[1].dir, "01-concentration-6.77");
        assert!(pts
            .iter()
            .all(|p| p.config.analysis.drying.solubility == Some(50.0)));
        let pts = swept("analysis.drying.solubility", "[50, 100]");
        assert_eq!(pts[1].config.analysis.drying.solubility, Some(100.0));
        let pts = swept("analysis.drying.min_neck", "[0.02, 0.1]");
        assert_eq!(pts[1].config.analysis.drying.min_neck, 0.1);
        let pts = swept("analysis.drying.tensile_strength", "[1e6, 4e6]");
        assert_eq!(pts[0].config.analysis.drying.tensile_strength, 1e6);
        let pts = swept("analysis.drainage.reduced_pressure", "[15, 80]");
        assert_eq!(pts[1].config.analysis.drainage.reduced_pressure, Some(80.0));
        assert_eq!(pts[1].dir, "01-reduced-pressure-80");
        let pts = swept("analysis.drainage.pressure", "[2e5, 4e5]");
        let d = &pts[1].config.analysis.drainage;
        assert_eq!((d.pressure, d.reduced_pressure), (Some(4e5), None));
    }

    #[test]
    fn a_switch_is_swept() {
        let base = "[settling]\nrestitution = 0.9\n";
        let c = config(&format!(
            "{base}[sweep]\nparameter = \"settling.climb_over\"\nvalues = [false, true]\n"
        ));
        let pts = c.sweep.as_ref().unwrap().points(&c).unwrap();
        let on: Vec<Option<bool>> = pts.iter().map(|p| p.config.settling.climb_over).collect();
        assert_eq!(on, [Some(false), Some(true)]);
        assert_eq!(pts[1].label, "true");
        assert_eq!(pts[0].dir, "00-climb-over-false");
        // The rule refuses it without momentum, as the config does.
        let c = config("[sweep]\nparameter = \"settling.climb_over\"\nvalues = [true]\n");
        let e = c
            .sweep
            .as_ref()
            .unwrap()
            .points(&c)
            .unwrap_err()
            .to_string();
        assert!(e.contains("values[0]") && e.contains("restitution"), "{e}");
    }

    #[test]
    fn bad_sweeps_are_explained() {
        let bad = [
            (
                "parameter = \"colour\"\nvalues = [1]",
                "unknown parameter `colour`",
            ),
            ("parameter = \"ratio\"\nvalues = []", "at least one value"),
            (
                "parameter = \"ratio\"\nvalues = [[1, 2, 3]]",
                "values[0]: ratio: 3 values",
            ),
            ("parameter = \"box.diameters\"\nvalues = [0.5]", "values[0]"),
            ("parameter = \"fill.count\"\nvalues = [2.5]", "whole number"),
            (
                "parameter = \"ratio\"\nvalues = [[1, 1]]\nlabels = []",
                "labels",
            ),
            (
                "parameter = \"species[5].radius\"\nvalues = [3]",
                "only 2 species",
            ),
            (
                "parameter = \"species[0].size.gsd\"\nvalues = [1.5]",
                "no size distribution",
            ),
            (
                "parameter = \"species[0].size.table\"\nvalues = [3]",
                "file name",
            ),
            (
                "parameter = \"ratio\"\nvalues = [\"a.csv\"]",
                "expected a number",
            ),
            (
                "parameter = \"fill.count\"\nvalues = [true]",
                "values[0]: expected a number, got true",
            ),
            (
                "parameter = \"settling.climb_over\"\nvalues = [1]",
                "values[0]: expected true or false",
            ),
            (
                "parameter = \"analysis.drying.concentration\"\nvalues = [-1]",
                "values[0]: analysis.drying: concentration (kg/m³) must be finite and at least 0",
            ),
            (
                "parameter = \"analysis.drying.concentration\"\nvalues = [[1, 2]]",
                "values[0]: expected one number",
            ),
            (
                "parameter = \"analysis.drying.solubility\"\nvalues = [10]",
                "values[0]: analysis.drying: the concentration 50 kg/m³ is above the solubility 10",
            ),
            (
                "parameter = \"analysis.drying.min_neck\"\nvalues = [5, -0.1]",
                "values[1]: analysis.drying: min_neck",
            ),
            (
                "parameter = \"analysis.drying.tensile_strength\"\nvalues = [\"strong\"]",
                "expected a number",
            ),
            (
                "parameter = \"analysis.drainage.reduced_pressure\"\nvalues = [0]",
                "values[0]: analysis.drainage.reduced_pressure",
            ),
            (
                "parameter = \"analysis.drainage.pressure\"\nvalues = [1e5]",
                "needs analysis.length_unit",
            ),
        ];
        for (body, needle) in bad {
            let c = config(&format!("[sweep]\n{body}\n"));
            let e = c
                .sweep
                .as_ref()
                .unwrap()
                .points(&c)
                .unwrap_err()
                .to_string();
            assert!(e.contains(needle), "{body}: {e}");
        }
        let e = Config::from_toml("[sweep]\nparameter = \"ratio\"\nvalue = [1]\n", "t")
            .unwrap_err()
            .to_string();
        assert!(e.contains("value"), "{e}");
    }
}
