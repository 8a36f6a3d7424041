//! `packbed render`, the pictures and exports of `packbed run`, and the check of
//! the exports with the real OVITO Python module.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::common::{assert_user_error, ok, png_size, Scratch};

#[test]
fn run_writes_pictures_plots_and_exports_that_render_reads() {
    let s = Scratch::new();
    let d = s.work.as_path();
    ok(
        d,
        &[
            "run",
            "--dim",
            "2",
            "--quiet",
            "--out",
            "r",
            "--export",
            "vtk,dump,xyz",
        ],
    );
    for f in [
        "bed.png",
        "bed.svg",
        "plot_coordination.svg",
        "plot_profile.png",
        "bed.vtu",
        "bed.dump",
        "bed.xyz",
    ] {
        assert!(d.join("r").join(f).is_file(), "{f}");
    }
    assert_eq!(
        png_size(&std::fs::read(d.join("r/bed.png")).unwrap()),
        (1200, 1000)
    );
    let rows = std::fs::read_to_string(d.join("r/particles.csv"))
        .unwrap()
        .lines()
        .count()
        - 1;
    let svg = std::fs::read_to_string(d.join("r/bed.svg")).unwrap();
    assert_eq!(svg.matches("class=\"particle\"").count(), rows);
    // Every format renders to the same SVG picture (same particles, same box).
    let mut pictures = Vec::new();
    for f in ["particles.csv", "bed.vtu", "bed.dump", "bed.xyz"] {
        let out = format!("{f}.svg");
        ok(
            d,
            &[
                "render",
                &format!("r/{f}"),
                "--out",
                &out,
                "--title",
                "same",
            ],
        );
        let svg = std::fs::read_to_string(d.join(out)).unwrap();
        // The discs in bed coordinates (the legend, and so the layout, differs:
        // only particles.csv has species names, from summary.json).
        let bed: Vec<String> = svg
            .lines()
            .filter(|l| l.starts_with("<circle class=\"particle\""))
            .map(String::from)
            .collect();
        assert_eq!(bed.len(), rows, "{f}");
        pictures.push(bed);
    }
    assert!(pictures.iter().all(|p| *p == pictures[0]));
    // Options.
    ok(
        d,
        &[
            "render",
            "r/particles.csv",
            "--out",
            "c.png",
            "--color",
            "contacts",
            "--width",
            "640",
            "--height",
            "480",
        ],
    );
    assert_eq!(
        png_size(&std::fs::read(d.join("c.png")).unwrap()),
        (640, 480)
    );
    ok(
        d,
        &[
            "render",
            "r/particles.csv",
            "--out",
            "k.svg",
            "--color",
            "chains",
        ],
    );
    let k = std::fs::read_to_string(d.join("k.svg")).unwrap();
    assert!(k.contains("wall-to-wall chain"));
    // Contact forces under shear: one disc per particle, a continuous legend.
    ok(
        d,
        &[
            "render",
            "r/particles.csv",
            "--out",
            "f.svg",
            "--color",
            "force",
        ],
    );
    let f = std::fs::read_to_string(d.join("f.svg")).unwrap();
    assert!(f.contains(">largest bond force (shear)<"));
    assert_eq!(f.matches("class=\"particle\"").count(), rows);
    assert!(!f.contains("NaN"));
    ok(d, &["render", "r/bed.xyz"]);
    assert!(d.join("r/bed.png").is_file());
}

#[test]
fn same_seed_gives_identical_pictures() {
    let s = Scratch::new();
    let d = s.work.as_path();
    for out in ["a", "b"] {
        ok(d, &["run", "--quiet", "--seed", "3", "--out", out]);
    }
    for f in ["bed.png", "plot_coordination.png", "plot_profile.svg"] {
        let a = std::fs::read(d.join("a").join(f)).unwrap();
        let b = std::fs::read(d.join("b").join(f)).unwrap();
        assert!(a == b, "{f} differs");
    }
}

#[test]
fn render_3d_views_and_cuts() {
    let s = Scratch::new();
    let d = s.work.as_path();
    ok(d, &["run", "--quiet", "--out", "r", "--no-pictures"]);
    assert!(!d.join("r/bed.png").exists());
    ok(
        d,
        &[
            "render",
            "r/particles.csv",
            "--out",
            "h.png",
            "--cut",
            "half",
            "--view",
            "20,60",
        ],
    );
    ok(
        d,
        &[
            "render",
            "r/particles.csv",
            "--out",
            "s.png",
            "--cut",
            "y:40:80",
            "--color",
            "height",
            "--supersample",
            "1",
        ],
    );
    assert_eq!(
        png_size(&std::fs::read(d.join("s.png")).unwrap()),
        (1200, 1000)
    );
    // Contact forces under shear colour the spheres (no longer refused).
    ok(
        d,
        &[
            "render",
            "r/particles.csv",
            "--out",
            "f.png",
            "--color",
            "force",
        ],
    );
    assert_eq!(
        png_size(&std::fs::read(d.join("f.png")).unwrap()),
        (1200, 1000)
    );
    // Bad views, cuts, colours and formats: the output file first, then options.
    for (tail, needles) in [
        (&["x.svg"][..], &["SVG", "2D"][..]),
        (&["x.png", "--cut", "w:1:2"][..], &["--cut"][..]),
        (&["x.png", "--view", "0,100"][..], &["elevation"][..]),
        (&["x.jpg"][..], &[".png or .svg"][..]),
        (&["x.png", "--width", "5"][..], &["width"][..]),
    ] {
        let mut args = vec!["render", "r/particles.csv", "--out"];
        args.extend_from_slice(tail);
        assert_user_error(&s, &args, needles);
    }
    assert!(!d.join("x.png").exists() && !d.join("x.svg").exists());
}

#[test]
fn bad_bed_files_and_exports_are_refused() {
    let s = Scratch::new();
    let d = s.work.as_path();
    std::fs::write(d.join("p.txt"), "1 2 3 1\n4 5 nan 1\n").unwrap();
    assert_user_error(
        &s,
        &["render", "p.txt", "--box", "10,10,10"],
        &["p.txt:2", "not a finite number"],
    );
    std::fs::write(d.join("q.txt"), "1 2 3 1\n").unwrap();
    assert_user_error(
        &s,
        &["render", "q.txt"],
        &["q.txt:1", "give the box (W,D,H)"],
    );
    ok(
        d,
        &["render", "q.txt", "--box", "10,10,10", "--out", "q.png"],
    );
    assert_user_error(&s, &["run", "--export", "pdb"], &["pdb", "vtk, dump, xyz"]);
    assert!(!d.join("packbed-out").exists());
}

/// OVITO reads the LAMMPS dump and the XYZ export of a 3D bed of equal spheres
/// and finds packbed's count, radii, box, periodic flags and mean coordination.
/// The `ovito` Python module is optional on a developer's machine: without it
/// the test says "skipped: …" on stderr and passes, so `cargo test` goes on to
/// the doc tests. `PACKBED_REQUIRE_OVITO=1` (set by `.ci/run`, which installs
/// the module) makes a missing module or Python a failure, so CI still proves
/// that the exports load in OVITO.
#[test]
fn ovito_reads_the_exports_and_agrees_on_coordination() {
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    let required = std::env::var("PACKBED_REQUIRE_OVITO").as_deref() == Ok("1");
    if let Some(why) = ovito_missing(&python) {
        assert!(
            !required,
            "PACKBED_REQUIRE_OVITO=1 but {why} (pip install ovito)"
        );
        eprintln!("skipped: the OVITO export check ({why}; pip install ovito, or set PACKBED_REQUIRE_OVITO=1 to make this a failure)");
        return;
    }
    let script: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/ovito_check.py");
    let s = Scratch::new();
    let d = s.work.as_path();
    for (out, periodic) in [("walls", false), ("periodic", true)] {
        let mut args = vec![
            "run",
            "--quiet",
            "--radii",
            "10",
            "--ratio",
            "1",
            "--box",
            "diameters=10",
            "--seed",
            "2",
        ];
        if periodic {
            args.push("--periodic");
        }
        args.extend(["--out", out, "--export", "dump,xyz", "--no-pictures"]);
        ok(d, &args);
        let o = Command::new(&python)
            .arg(&script)
            .arg(d.join(out))
            .stdin(Stdio::null())
            .output()
            .unwrap_or_else(|e| panic!("cannot run {python}: {e}"));
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(
            o.status.success(),
            "{out}: {}{stderr}",
            String::from_utf8_lossy(&o.stdout)
        );
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert_eq!(stdout.lines().count(), 2, "{stdout}");
    }
}

/// Why the OVITO check cannot run here, or `None` when `import ovito` works.
fn ovito_missing(python: &str) -> Option<String> {
    match Command::new(python)
        .args(["-c", "import ovito, numpy"])
        .stdin(Stdio::null())
        .output()
    {
        Err(e) => Some(format!("cannot run {python}: {e}")),
        Ok(o) if !o.status.success() => Some(format!(
            "{python} cannot import the ovito module: {}",
            String::from_utf8_lossy(&o.stderr)
                .lines()
                .last()
                .unwrap_or("")
                .trim()
        )),
        Ok(_) => None,
    }
}

#[test]
fn render_help_names_the_options() {
    let s = Scratch::new();
    let o = s.ok(&["render", "--help"]);
    for opt in [
        "--out",
        "--color",
        "--cut",
        "--view",
        "--box",
        "--network",
        "--width",
    ] {
        assert!(o.stdout.contains(opt), "{opt}");
    }
}

/// A 2D picture has no view or cut-away: asking for one is refused, not ignored.
#[test]
fn view_and_cut_on_a_2d_bed_are_refused() {
    let s = Scratch::new();
    let d = s.work.as_path();
    std::fs::write(d.join("discs.txt"), "10 10 5\n20 10 5\n").unwrap();
    let bed = ["render", "discs.txt", "--box", "40,40", "--out", "p.png"];
    for (extra, needles) in [
        (&["--view", "20,60"][..], &["--view", "2D", "discs.txt"][..]),
        (&["--cut", "half"][..], &["--cut", "2D"][..]),
        (
            &["--cut", "x:0:10", "--view", "0,10"][..],
            &["--view and --cut", "2D"][..],
        ),
    ] {
        let args: Vec<&str> = bed.iter().chain(extra).copied().collect();
        assert_user_error(&s, &args, needles);
        assert!(!d.join("p.png").exists(), "{args:?} wrote the picture");
    }
    ok(d, &bed);
}

/// `(radius, fill colour)` of every particle of a bed SVG.
fn disc_fills(svg: &str) -> Vec<(f64, String)> {
    svg.lines()
        .filter(|l| l.starts_with("<circle class=\"particle\""))
        .map(|l| {
            let attr = |name: &str| {
                let start = l.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
                let end = start + l[start..].find('"').unwrap();
                l[start..end].to_string()
            };
            (attr("r").parse().unwrap(), attr("fill"))
        })
        .collect()
}

/// Lightness of a `#rrggbb` colour.
fn lightness(hex: &str) -> f64 {
    let c = |k: usize| u8::from_str_radix(&hex[1 + 2 * k..3 + 2 * k], 16).unwrap() as f64;
    0.299 * c(0) + 0.587 * c(1) + 0.114 * c(2)
}

#[test]
fn size_distributions_are_pictured_by_radius() {
    let s = Scratch::new();
    let config = s.input(
        "psd.toml",
        "dim = 2\nseed = 3\n\n[box]\ndiameters = 10\n\n[fill]\ncount = 80\n\n\
         [[species]]\nname = \"powder\"\nsize = { dist = \"uniform\", min = 4.0, max = 10.0 }\n\n\
         [analysis]\nlength_unit = \"mm\"\n",
    );
    s.ok(&["run", config.to_str().unwrap(), "--quiet", "--out", "psd"]);
    let svg = s.read("psd/bed.svg");
    // Lengths on the plots' axes in the config's unit.
    let profile = s.read("psd/plot_profile.svg");
    assert!(profile.contains("height above the floor (mm)"));
    // And on the picture's scale bar and radius legend.
    assert!(svg.contains(" mm<") && svg.contains(">radius (mm)<"));
    // The run's own picture: a radius scale, not one colour for the species.
    let mut discs = disc_fills(&svg);
    assert_eq!(discs.len(), 80);
    discs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let distinct: std::collections::BTreeSet<&str> = discs.iter().map(|d| d.1.as_str()).collect();
    assert!(distinct.len() > 20, "{} colours", distinct.len());
    // A larger disc never has a darker colour (viridis brightens).
    for w in discs.windows(2) {
        assert!(
            lightness(&w[1].1) >= lightness(&w[0].1) - 1.0,
            "r {} {} vs r {} {}",
            w[0].0,
            w[0].1,
            w[1].0,
            w[1].1
        );
    }
    // Two fixed sizes keep one colour per species; `--color radius` asks.
    s.ok(&["run", "--dim", "2", "--quiet", "--out", "two"]);
    let two = s.read("two/bed.svg");
    assert!(!two.contains(">radius<"));
    s.ok(&[
        "render",
        "two/particles.csv",
        "--color",
        "radius",
        "--out",
        "two-r.svg",
    ]);
    let r = s.read("two-r.svg");
    assert!(r.contains(">radius<"));
    let discs = disc_fills(&r);
    let small = discs.iter().find(|d| d.0 < 15.0).unwrap();
    let large = discs.iter().find(|d| d.0 > 15.0).unwrap();
    assert!(lightness(&large.1) > lightness(&small.1));
}
