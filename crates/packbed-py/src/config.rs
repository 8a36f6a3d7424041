//! Configs from Python: a TOML file, a dict (as JSON text) of the same schema,
//! and the keywords of `packbed.deposit` (the command's overrides), resolved
//! into one canonical JSON text that every later call (and every Dask task)
//! builds from.

use crate::errors::{config as config_error, to_py};
use packbed::{BoxSpec, Config, Edit, Measure, Mode, Overrides};
use pyo3::prelude::*;
use std::path::Path;

/// The keywords of `packbed.deposit`, as JSON; `deny_unknown_fields` and
/// serde's types give the checks (a string for `dim` is refused).
#[derive(serde::Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct Keywords {
    dim: Option<u8>,
    radii: Option<Vec<f64>>,
    ratio: Option<Vec<f64>>,
    beads: Option<u32>,
    #[serde(rename = "box")]
    container: Option<BoxKeyword>,
    periodic: Option<bool>,
    count: Option<u64>,
    seed: Option<u64>,
    mode: Option<Mode>,
    large: Option<f64>,
    measures: Option<Vec<String>>,
}

/// `box`: the command's text (`thesis`, `W,H`, `W,D,H`, `diameters=N`) or the
/// sizes as numbers.
#[derive(serde::Deserialize)]
#[serde(untagged)]
enum BoxKeyword {
    Text(String),
    Sizes(Vec<f64>),
}

impl Keywords {
    fn overrides(&self) -> PyResult<Overrides> {
        let container = match &self.container {
            None => None,
            Some(b) => {
                let text = match b {
                    BoxKeyword::Text(t) => t.clone(),
                    BoxKeyword::Sizes(s) => {
                        s.iter().map(f64::to_string).collect::<Vec<_>>().join(",")
                    }
                };
                Some(
                    text.parse::<BoxSpec>()
                        .map_err(|e| config_error(format!("box: {e}")))?,
                )
            }
        };
        let measures = match &self.measures {
            None => None,
            Some(list) => Some(
                Measure::parse_list(&list.join(","))
                    .map_err(|e| config_error(format!("measures: {e}")))?,
            ),
        };
        Ok(Overrides {
            dim: self.dim,
            radii: self.radii.clone(),
            ratio: self.ratio.clone(),
            beads: self.beads,
            container,
            periodic: self.periodic == Some(true),
            count: self.count,
            seed: self.seed,
            mode: self.mode,
            large: self.large,
            measures,
        })
    }
}

/// A config from the JSON text of a dict of the TOML schema: written as TOML
/// text and parsed as a config file is, so the checks are the same; an error
/// points at the key and value (the line of text the user never saw would not).
pub fn from_json(text: &str, what: &str) -> PyResult<Config> {
    let value: toml::Value = serde_json::from_str(text)
        .map_err(|e| config_error(format!("{what}: {}", json_message(&e))))?;
    let toml_text = toml::to_string(&value).map_err(|e| config_error(format!("{what}: {e}")))?;
    Config::from_toml(&toml_text, what).map_err(|e| match e {
        packbed::Error::Data { line, message, .. } => {
            let lines: Vec<&str> = toml_text.lines().collect();
            let at = lines.get(line.saturating_sub(1)).map_or("", |l| l.trim());
            let table = lines[..line.saturating_sub(1).min(lines.len())]
                .iter()
                .rev()
                .find(|l| l.starts_with('['))
                .map(|l| format!(" in {}", l.trim()))
                .unwrap_or_default();
            config_error(format!("{what}: {message} (at `{at}`{table})"))
        }
        e => to_py(e),
    })
}

/// serde_json's message without the position in text the user never wrote.
fn json_message(e: &serde_json::Error) -> String {
    let text = e.to_string();
    match text.rfind(" at line ") {
        Some(at) => text[..at].to_string(),
        None => text,
    }
}

/// The keywords from their JSON object, each checked alone so that an error
/// names the keyword (`dim: invalid type: string "3", expected u8`).
fn keywords(text: &str) -> PyResult<Keywords> {
    let object: serde_json::Map<String, serde_json::Value> =
        serde_json::from_str(text).map_err(|e| config_error(json_message(&e)))?;
    for (key, value) in &object {
        let one = serde_json::Value::Object([(key.clone(), value.clone())].into_iter().collect());
        serde_json::from_value::<Keywords>(one).map_err(|e| match e.to_string() {
            m if m.starts_with("unknown field") => config_error(m),
            m => config_error(format!("{key}: {m}")),
        })?;
    }
    serde_json::from_value(serde_json::Value::Object(object))
        .map_err(|e| config_error(json_message(&e)))
}

/// The config a call builds: the TOML file at `path` or the dict `config_json`
/// (or the default), with the keywords `keywords_json` applied, validated.
/// Returns its canonical JSON text.
#[pyfunction]
#[pyo3(signature = (path=None, config_json=None, keywords_json=None))]
pub fn resolve_config(
    path: Option<String>,
    config_json: Option<String>,
    keywords_json: Option<String>,
) -> PyResult<String> {
    let mut config = match (&path, &config_json) {
        (Some(p), _) => Config::from_file(Path::new(p)).map_err(to_py)?,
        (None, Some(j)) => from_json(j, "config")?,
        (None, None) => Config::default(),
    };
    let keywords = match &keywords_json {
        None => Keywords::default(),
        Some(k) => keywords(k)?,
    };
    keywords.overrides()?.apply(&mut config).map_err(to_py)?;
    if keywords.periodic == Some(false) {
        config
            .apply(&Edit::Periodic(false))
            .map_err(|e| to_py(e.within("periodic")))?;
    }
    packbed::validate_ensemble(&config).map_err(to_py)?;
    canonical(&config)
}

/// The canonical JSON text of a config.
pub fn canonical(config: &Config) -> PyResult<String> {
    serde_json::to_string(config).map_err(|e| config_error(e.to_string()))
}

/// A config from its canonical JSON text (made by [`resolve_config`]).
pub fn load(text: &str) -> PyResult<Config> {
    let config = from_json(text, "config")?;
    Ok(config)
}
