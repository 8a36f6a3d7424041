//! The pore network's figures that once came out wrong without a word
//! (issue 57): a slab too thin for its permeability, its side axes' flux
//! balance, the anisotropy of a slab too thin for it.

use crate::common::Scratch;
use serde_json::Value;

/// A periodic bed of equal spheres (radius 1: d32 = 2) whose flow runs
/// through the slab `[lo, hi]`.
fn bed(s: &Scratch, name: &str, slab: (f64, f64)) -> String {
    let p = s.input(
        &format!("{name}.toml"),
        &format!(
            "dim = 3\nseed = 1\n[box]\nwidth = 12\ndepth = 12\nheight = 40\nperiodic = true\n\
             [fill]\ncount = 700\n[[species]]\nradius = 1\n\
             [analysis]\nmeasures = [\"packing\", \"pores\", \"permeability\"]\n\
             [analysis.flow]\nslab = [{}, {}]\n",
            slab.0, slab.1
        ),
    );
    p.to_str().unwrap().to_string()
}

#[test]
fn a_slab_too_thin_for_its_permeability_is_warned_of_and_its_zeros_are_null() {
    // Half a d32 thick: along x no pore path crosses it, and its flux does
    // not balance. Its k_x was 0 with an imbalance of 0.45, k_y 4 % of the
    // bed's, k_z 40 % high and the anisotropy 53, without a word.
    let s = Scratch::new();
    let cfg = bed(&s, "thin", (9.5, 10.5));
    let o = s.ok(&["run", &cfg, "--out", "thin", "--no-pictures"]);
    let warning = o
        .stderr
        .lines()
        .find(|l| l.starts_with("packbed: warning: permeability: the flow slab is 0.50 d32"))
        .unwrap_or_else(|| panic!("{}", o.stderr));
    assert!(warning.contains("would do"), "{warning}");
    let summary = s.summary("thin");
    let warnings = summary["warnings"].as_array().unwrap();
    assert!(
        warnings.iter().any(|w| w
            .as_str()
            .unwrap()
            .starts_with("permeability: the flow slab")),
        "{warnings:?}"
    );
    let k = &summary["permeability"];
    for key in [
        "k_x",
        "anisotropy",
        "k_over_d32_squared",
        "k_over_kozeny_carman",
    ] {
        assert_eq!(k[key], Value::Null, "{key}: {k}");
    }
    assert!(k["k_z"].as_f64().unwrap() > 0.0, "{k}");
    let note = k["note"].as_str().unwrap();
    assert!(
        note.contains("does not balance along x") && note.contains("0.50 d32 thick"),
        "{note}"
    );
    // Every k given rests on a balanced flux (the spec's 1e-9).
    for axis in k["axes"].as_array().unwrap() {
        let balanced = axis["imbalance"].as_f64().unwrap() <= 1e-9;
        assert!(balanced || axis["k"].is_null(), "{axis}");
    }
    // The screen says so too.
    assert!(o.stdout.contains("k_x null"), "{}", o.stdout);
}

#[test]
fn a_slab_thick_enough_has_no_warning_and_an_anisotropy_with_its_uncertainty() {
    // 11 d32 thick in a box 6 d32 wide: above every threshold.
    let s = Scratch::new();
    let cfg = bed(&s, "thick", (4.0, 26.0));
    let o = s.ok(&["run", &cfg, "--out", "thick", "--no-pictures"]);
    assert!(!o.stderr.contains("warning"), "{}", o.stderr);
    let summary = s.summary("thick");
    let k = &summary["permeability"];
    assert_eq!(k["note"], Value::Null, "{k}");
    let a = k["anisotropy"].as_f64().unwrap();
    let u = k["anisotropy_uncertainty"].as_f64().unwrap();
    // At least the slab's bias on the side axes, 0.5 d32 / 11 d32.
    assert!(u >= a * 0.5 / 11.0 && u < 0.5 * a, "{a} ± {u}");
}
