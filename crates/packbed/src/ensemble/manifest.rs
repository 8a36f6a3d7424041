//! `manifest.json`, which makes a directory an ensemble: the config, the
//! replicate count and the shard; and the checks that let a rerun resume it or
//! a merge join its shards.

use crate::config::Config;
use crate::error::{Error, Result};
use crate::io::Staging;
use serde_json::{json, Value};
use std::fs;
use std::path::Path;

/// Name of the file that identifies an ensemble directory.
pub const MANIFEST: &str = "manifest.json";

/// One shard of an ensemble: the replicates `i` with `i mod count == index`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// `K`, from 0.
    pub index: u64,
    /// `M`, at least 1.
    pub count: u64,
}

impl Shard {
    /// The whole ensemble.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `K/M` with `0 <= K < M`.
    pub fn parse(text: &str) -> Result<Shard> {
        let bad = || {
            Error::setting(
                "shard",
                format!(
                    "`{text}` is not K/M with 0 <= K < M (e.g. 0/4 for the first of four shards)"
                ),
            )
        };
        let (k, m) = text.split_once('/').ok_or_else(bad)?;
        let k: u64 = k.trim().parse().map_err(|_| bad())?;
        let m: u64 = m.trim().parse().map_err(|_| bad())?;
        if m == 0 || k >= m {
            return Err(bad());
        }
        Ok(Shard { index: k, count: m })
    }

    /// True if replicate `i` belongs to this shard.
    pub(crate) fn has(&self, i: u64) -> bool {
        i % self.count == self.index
    }

    /// `(K, M)` of a real shard, `None` for the whole ensemble.
    pub(super) fn as_pair(&self) -> Option<(u64, u64)> {
        (self.count > 1).then_some((self.index, self.count))
    }
}

/// An [`Error::Io`] on `path`.
pub(super) fn io_err(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// A JSON file, or an [`Error::Data`] naming its line.
fn read_json(path: &Path) -> Result<Value> {
    let text = fs::read_to_string(path).map_err(|e| io_err(path, e))?;
    serde_json::from_str(&text).map_err(|e| Error::Data {
        path: path.to_path_buf(),
        line: e.line(),
        message: format!("not valid JSON: {e}"),
    })
}

/// The config as stored in the manifest: what makes two ensembles the same.
pub(super) fn config_key(config: &Config) -> Value {
    let mut c = config.clone();
    c.ensemble = None;
    serde_json::to_value(&c).unwrap_or(Value::Null)
}

/// 64-bit FNV-1a of the text: a short fingerprint to show, not a security hash.
pub fn fingerprint(text: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The first key where two JSON documents differ, e.g. `species[1].ratio`.
pub(super) fn first_difference(a: &Value, b: &Value, path: &str) -> Option<String> {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for (k, v) in x {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                match y.get(k) {
                    Some(w) => {
                        if let Some(d) = first_difference(v, w, &p) {
                            return Some(d);
                        }
                    }
                    None => return Some(p),
                }
            }
            y.keys().find(|k| !x.contains_key(*k)).map(|k| {
                if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                }
            })
        }
        (Value::Array(x), Value::Array(y)) => {
            for (i, (v, w)) in x.iter().zip(y).enumerate() {
                if let Some(d) = first_difference(v, w, &format!("{path}[{i}]")) {
                    return Some(d);
                }
            }
            (x.len() != y.len()).then(|| format!("{path} (length)"))
        }
        _ => (a != b).then(|| {
            if path.is_empty() {
                "(top)".into()
            } else {
                path.to_string()
            }
        }),
    }
}

/// The contents of `manifest.json`: what an ensemble directory holds, so that
/// a rerun resumes only the same ensemble and a merge joins only its shards.
#[derive(Clone, Debug)]
pub struct Manifest {
    /// Version of packbed that made the ensemble.
    pub packbed_version: String,
    /// Replicates requested.
    pub runs: u64,
    /// The shard.
    pub shard: Shard,
    /// The config (`ensemble` table left out), as JSON.
    pub config: Value,
}

impl Manifest {
    /// The text of `manifest.json`.
    fn to_json(&self) -> String {
        let text = serde_json::to_string(&self.config).unwrap_or_default();
        let v = json!({
            "format": "packbed-ensemble-manifest",
            "packbed_version": self.packbed_version,
            "fingerprint": fingerprint(&text),
            "runs": self.runs,
            "shard": self.shard.as_pair().map(|(k, m)| json!({"index": k, "count": m})),
            "config": self.config,
        });
        let mut s = serde_json::to_string_pretty(&v).unwrap_or_default();
        s.push('\n');
        s
    }

    /// Reads the manifest of an ensemble directory.
    pub(crate) fn read(dir: &Path) -> Result<Manifest> {
        let path = dir.join(MANIFEST);
        if !path.exists() {
            return Err(Error::Impossible(format!(
                "{}: not a packbed ensemble directory (no {MANIFEST})",
                dir.display()
            )));
        }
        let v = read_json(&path)?;
        let bad = |what: &str| Error::Data {
            path: path.clone(),
            line: 1,
            message: format!("{what} missing or malformed"),
        };
        let runs = v["runs"].as_u64().ok_or_else(|| bad("`runs`"))?;
        let shard = match &v["shard"] {
            Value::Null => Shard::ALL,
            s => Shard {
                index: s["index"].as_u64().ok_or_else(|| bad("`shard.index`"))?,
                count: s["count"].as_u64().ok_or_else(|| bad("`shard.count`"))?,
            },
        };
        if shard.count == 0 || shard.index >= shard.count {
            return Err(bad("`shard`"));
        }
        Ok(Manifest {
            packbed_version: v["packbed_version"].as_str().unwrap_or("?").to_string(),
            runs,
            shard,
            config: v["config"].clone(),
        })
    }

    /// The config stored in the manifest of `dir`.
    pub(super) fn config(&self, dir: &Path) -> Result<Config> {
        serde_json::from_value(self.config.clone()).map_err(|e| Error::Data {
            path: dir.join(MANIFEST),
            line: 1,
            message: format!("`config` is not a packbed config: {e}"),
        })
    }
}

/// Checks that `out` can hold this ensemble: new, empty, or the same ensemble
/// (same config, shard and packbed version) to resume, whose manifest it returns.
pub(super) fn check_out(out: &Path, wanted: &Manifest) -> Result<Option<Manifest>> {
    if !out.exists() {
        return Ok(None);
    }
    if !out.is_dir() {
        return Err(Error::setting(
            "out",
            format!("{}: exists and is not a directory", out.display()),
        ));
    }
    if !out.join(MANIFEST).exists() {
        let empty = fs::read_dir(out)
            .map_err(|e| io_err(out, e))?
            .next()
            .is_none();
        return if empty {
            Ok(None)
        } else {
            Err(Error::setting(
                "out",
                format!(
                    "{}: the directory is not empty and holds no ensemble ({MANIFEST}); choose a new or empty directory",
                    out.display()
                ),
            ))
        };
    }
    let have = Manifest::read(out)?;
    if have.config != wanted.config {
        let key = first_difference(&have.config, &wanted.config, "").unwrap_or_default();
        return Err(Error::setting(
            "out",
            format!(
                "{} holds an ensemble of a different config (fingerprint {} there, {} here; first difference at `{key}`): use another output directory, or delete it to start over",
                out.display(),
                fingerprint(&serde_json::to_string(&have.config).unwrap_or_default()),
                fingerprint(&serde_json::to_string(&wanted.config).unwrap_or_default()),
            ),
        ));
    }
    if have.shard != wanted.shard {
        let show = |s: Shard| match s.as_pair() {
            Some((k, m)) => format!("shard {k}/{m}"),
            None => "the whole ensemble".to_string(),
        };
        return Err(Error::setting(
            "out",
            format!(
                "{} holds {}, but this run is {}: use another output directory",
                out.display(),
                show(have.shard),
                show(wanted.shard)
            ),
        ));
    }
    if have.packbed_version != wanted.packbed_version {
        return Err(Error::setting(
            "out",
            format!(
                "{} was made by packbed {}, this is {}: replicates could differ; use another output directory",
                out.display(),
                have.packbed_version,
                wanted.packbed_version
            ),
        ));
    }
    Ok(Some(have))
}

/// Writes `manifest.json` into `out` atomically.
pub(super) fn write_manifest(out: &Path, m: &Manifest) -> Result<()> {
    let mut s = Staging::new(out)?;
    let text = m.to_json();
    s.stage(MANIFEST, |w| w.write_all(text.as_bytes()))?;
    s.commit().map(drop)
}
