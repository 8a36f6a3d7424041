//! The proof a replicate's `summary.json` carries that it belongs to its
//! ensemble (`proof` in the file): a fingerprint of the config as used, seed
//! and `[ensemble]` table left out, and the measures the summary holds; with
//! the file's `packbed_version`. Resume and `packbed merge` check it before a
//! summary enters the statistics, and refuse by path one that does not match.

use crate::analysis::Summary;
use crate::config::Config;
use crate::error::echo;
pub use crate::io::summary::ReplicateProof;
use serde_json::Value;

/// The key of the proof in a replicate's `summary.json`.
pub const PROOF_KEY: &str = "proof";

impl ReplicateProof {
    /// The proof of a replicate built from `config` with the measures of `analysis`.
    pub fn of(config: &Config, analysis: &Summary) -> ReplicateProof {
        let a = analysis;
        let held = [
            ("cake", a.cake.is_some()),
            ("packing", a.packing.is_some()),
            ("coordination", a.coordination.is_some()),
            ("percolation", a.percolation.is_some()),
            ("voids", a.voids.is_some()),
            ("orientation", a.orientation.is_some()),
            ("segregation", a.segregation.is_some()),
            ("pores", a.pores.is_some()),
            ("permeability", a.permeability.is_some()),
        ];
        ReplicateProof {
            config_hash: config_hash(config),
            measures: held.iter().filter(|h| h.1).map(|h| h.0).collect(),
        }
    }
}

/// A fingerprint ([`super::fingerprint`]) of `config` as a run uses it
/// (defaults filled in), its seed and `[ensemble]` table left out: the same
/// for every replicate of one ensemble (or sweep value), different for
/// another config. A check against mistakes, not against forgery.
pub fn config_hash(config: &Config) -> String {
    let used = crate::io::summary::config_as_used(config);
    let mut v = serde_json::to_value(&used).unwrap_or(Value::Null);
    if let Some(o) = v.as_object_mut() {
        o.remove("seed");
        o.remove("ensemble");
    }
    super::fingerprint(&v.to_string())
}

/// Why the replicate summary `v` does not belong to an ensemble of the config
/// whose [`config_hash`] is `hash`, made by packbed `version`; `None` when it
/// does: same version, a proof of the same config, and every measure the
/// proof names present.
pub fn not_belonging(v: &Value, hash: &str, version: &str) -> Option<String> {
    let made_by = v.get("packbed_version").and_then(Value::as_str);
    if made_by != Some(version) {
        return Some(format!(
            "it was made by packbed {}, the ensemble by packbed {version}",
            made_by.map_or_else(|| "(unknown)".to_string(), echo)
        ));
    }
    let Some(proof) = v.get(PROOF_KEY) else {
        return Some(format!(
            "it carries no `{PROOF_KEY}` of the config it was made from"
        ));
    };
    let found = proof.get("config_hash").and_then(Value::as_str);
    if found != Some(hash) {
        return Some(format!(
            "it was made from another config (config hash {}, the ensemble's {hash})",
            found.map_or_else(|| "(none)".to_string(), echo)
        ));
    }
    let Some(measures) = proof.get("measures").and_then(Value::as_array) else {
        return Some(format!("its `{PROOF_KEY}` names no measures"));
    };
    for m in measures {
        let name = m.as_str().unwrap_or("");
        if name.is_empty() || v.get(name).is_none() {
            return Some(format!(
                "it lacks the measure `{}` it was written with",
                echo(&m.as_str().map_or_else(|| m.to_string(), str::to_string))
            ));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn summary(config: &Config) -> Value {
        let done = crate::run_bed(config, &mut |_| {}).unwrap();
        let mut s = done.summary;
        s.proof = Some(ReplicateProof::of(config, &s.analysis));
        serde_json::from_str(&s.to_json().unwrap()).unwrap()
    }

    #[test]
    fn a_replicate_proves_it_belongs_and_a_stranger_is_named() {
        let mut c = Config::default();
        c.fill.count = Some(40);
        let v = summary(&c);
        let hash = config_hash(&c);
        let version = env!("CARGO_PKG_VERSION");
        assert_eq!(not_belonging(&v, &hash, version), None);
        // The seed is not part of the config's identity: every replicate has its own.
        let mut seeded = c.clone();
        seeded.seed += 7;
        assert_eq!(config_hash(&seeded), hash);
        // Another config.
        let mut other = c.clone();
        other.species[0].radius = Some(15.0);
        let why = not_belonging(&v, &config_hash(&other), version).unwrap();
        assert!(why.contains("another config"), "{why}");
        // Another version.
        let why = not_belonging(&v, &hash, "0.0.1").unwrap();
        assert!(why.contains("made by packbed"), "{why}");
        // A measure removed.
        let mut cut = v.clone();
        cut.as_object_mut().unwrap().remove("coordination");
        let why = not_belonging(&cut, &hash, version).unwrap();
        assert!(why.contains("lacks the measure `coordination`"), "{why}");
        // No proof at all.
        let mut bare = v.clone();
        bare.as_object_mut().unwrap().remove(PROOF_KEY);
        assert!(not_belonging(&bare, &hash, version).is_some());
    }
}
