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
use crate::config::{Config, SpeciesConfig};
pub use crate::config::{EnsembleConfig, SweepConfig, SweepValue};
use crate::error::{Error, Result};

/// The parameters a sweep can vary, with the form of their values.
pub const PARAMETERS: [(&str, &str); 9] = [
    ("ratio", "a list with one number ratio per species, e.g. [1, 2]"),
    (
        "radii",
        "a list of radii, e.g. [10, 20] (one sphere species each unless the count matches the config's species)",
    ),
    ("box.diameters", "a number: a cube (square) of that many largest diameters"),
    ("box.size", "a list [W, H] (2D) or [W, D, H] (3D)"),
    ("fill.count", "a whole number of particles"),
    ("fill.roof_misses", "a whole number"),
    ("analysis.large_radius", "a radius"),
    ("species[K].radius", "a radius for species K (0-based)"),
    ("species[K].ratio", "a number ratio for species K (0-based)"),
];

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

/// `species[K].key` → (K, key).
fn species_parameter(p: &str) -> Option<(usize, &str)> {
    let rest = p.strip_prefix("species[")?;
    let (k, key) = rest.split_once("].")?;
    Some((k.parse().ok()?, key))
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
        if !PARAMETERS.iter().any(|(q, _)| *q == p) && species_parameter(p).is_none() {
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
            apply(p, value, &mut config)
                .map_err(|e| Error::config(format!("sweep.values[{i}]: {e}")))?;
            config.validate().map_err(|e| match e {
                Error::Config(m) => Error::config(format!("sweep.values[{i}]: {m}")),
                other => other,
            })?;
            let nums = value.numbers();
            let text: Vec<String> = nums.iter().map(|&x| fmt_num(x)).collect();
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

fn one(value: &SweepValue) -> std::result::Result<f64, String> {
    match value {
        SweepValue::Number(x) => Ok(*x),
        SweepValue::List(v) if v.len() == 1 => Ok(v[0]),
        SweepValue::List(v) => Err(format!("expected one number, got a list of {}", v.len())),
    }
}

fn list(value: &SweepValue) -> Vec<f64> {
    value.numbers()
}

fn whole(x: f64) -> std::result::Result<u64, String> {
    if x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x < 2f64.powi(63) {
        Ok(x as u64)
    } else {
        Err(format!("expected a whole number, got {x}"))
    }
}

fn sphere_like(template: &SpeciesConfig, radius: f64) -> SpeciesConfig {
    SpeciesConfig {
        name: None,
        radius: Some(radius),
        size: None,
        ratio: 1.0,
        shape: template.shape.clone(),
        beads: template.beads,
        spacing: template.spacing,
        orientation: template.orientation.clone(),
    }
}

/// Sets parameter `p` of `c` to `value`.
fn apply(p: &str, value: &SweepValue, c: &mut Config) -> std::result::Result<(), String> {
    match p {
        "ratio" => {
            let v = list(value);
            if v.len() != c.species.len() {
                return Err(format!(
                    "ratio has {} numbers but the config has {} species",
                    v.len(),
                    c.species.len()
                ));
            }
            for (s, r) in c.species.iter_mut().zip(v) {
                s.ratio = r;
            }
        }
        "radii" => {
            let v = list(value);
            if v.is_empty() {
                return Err("radii: give at least one radius".into());
            }
            if v.len() == c.species.len() {
                for (s, r) in c.species.iter_mut().zip(v) {
                    s.radius = Some(r);
                    s.size = None;
                }
            } else {
                let template = c.species[0].clone();
                c.species = v.iter().map(|&r| sphere_like(&template, r)).collect();
            }
        }
        "box.diameters" => {
            let periodic = c.container.periodic;
            c.container = Default::default();
            c.container.periodic = periodic;
            c.container.diameters = Some(one(value)?);
        }
        "box.size" => {
            let v = list(value);
            let periodic = c.container.periodic;
            c.container = Default::default();
            c.container.periodic = periodic;
            match (v.as_slice(), c.dim) {
                ([w, h], _) => {
                    c.container.width = Some(*w);
                    c.container.height = Some(*h);
                }
                ([w, d, h], 3) => {
                    c.container.width = Some(*w);
                    c.container.depth = Some(*d);
                    c.container.height = Some(*h);
                }
                _ => {
                    return Err(format!(
                        "box.size: give [W, H] or, in 3D, [W, D, H]; got {v:?}"
                    ))
                }
            }
        }
        "fill.count" => {
            c.fill.count = Some(whole(one(value)?)?);
            c.fill.until = None;
        }
        "fill.roof_misses" => c.fill.roof_misses = whole(one(value)?)?,
        "analysis.large_radius" => c.analysis.large_radius = Some(one(value)?),
        _ => {
            let (k, key) =
                species_parameter(p).ok_or_else(|| format!("unknown parameter `{p}`"))?;
            let n = c.species.len();
            let s = c
                .species
                .get_mut(k)
                .ok_or_else(|| format!("{p}: the config has only {n} species"))?;
            match key {
                "radius" => {
                    s.radius = Some(one(value)?);
                    s.size = None;
                }
                "ratio" => s.ratio = one(value)?,
                _ => {
                    return Err(format!(
                        "{p}: only species[K].radius and species[K].ratio can be swept"
                    ))
                }
            }
        }
    }
    Ok(())
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
    fn bad_sweeps_are_explained() {
        let bad = [
            (
                "parameter = \"colour\"\nvalues = [1]",
                "unknown parameter `colour`",
            ),
            ("parameter = \"ratio\"\nvalues = []", "at least one value"),
            (
                "parameter = \"ratio\"\nvalues = [[1, 2, 3]]",
                "values[0]: ratio has 3",
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
