//! A filter medium read from a bed file (`[[feeds]]` with `file = ...`):
//! its particles are placed as the file has them, bodies kept, lifted above
//! the open floor as every medium is; a file that is no medium for this box
//! is refused with one line.

use crate::common::{assert_checked, config, TOL};
use packbed::{planned, read_bed, run_bed, AnyBed, Bed, CaptureSummary, Config, InvariantChecks};
use std::path::{Path, PathBuf};

/// A periodic box 24 × 24 × `height`, no base layer, the packing measured.
fn boxed(height: f64) -> String {
    format!(
        "dim = 3\nseed = 5\n[box]\nwidth = 24\ndepth = 24\nheight = {height}\nperiodic = true\n\
         [fill]\nbase_layer = \"none\"\n[analysis]\nmeasures = [\"packing\"]\n"
    )
}

const MEDIUM: &str = "[[species]]\nname = \"medium\"\nradius = 1.5\n";
const SLURRY: &str =
    "[[species]]\nname = \"slurry\"\nsize = { dist = \"lognormal\", median = 0.25, gsd = 1.6 }\n";

/// A fresh directory of its own for test `name`.
fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("packbed-medium-file-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The 3D bed of a finished run.
fn bed3(b: AnyBed) -> Bed<3> {
    match b {
        AnyBed::D3(b) => b,
        AnyBed::D2(_) => panic!("a 2D bed"),
    }
}

/// Builds a precoat of 400 spheres of radius 1.5 (one plain feed, seed 5)
/// and writes its run into `dir/precoat`; the path of its `particles.csv`.
fn precoat(dir: &Path) -> PathBuf {
    let c = config(&format!(
        "{}{MEDIUM}",
        boxed(3000.0).replace("[fill]\n", "[fill]\ncount = 400\n")
    ));
    let done = run_bed(&c, &mut |_| {}).unwrap();
    let out = dir.join("precoat");
    done.write(&out).unwrap();
    out.join("particles.csv")
}

/// The config of a slurry of 3000 bodies filtered through the medium of
/// `file` (as written in the config, relative to `dir`), written to
/// `dir/filter.toml` and read back from there.
fn through_file(dir: &Path, file: &str) -> Config {
    let text = format!(
        "{}{SLURRY}[[feeds]]\nfile = \"{file}\"\n[[feeds]]\nspecies = [\"slurry\"]\ncount = 3000\n",
        boxed(3000.0)
    );
    let path = dir.join("filter.toml");
    std::fs::write(&path, text).unwrap();
    Config::from_file(&path).unwrap()
}

/// The bed and capture of a run of `c`.
fn filtered(c: &Config) -> (Bed<3>, CaptureSummary) {
    let done = run_bed(c, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    let capture = done.summary.capture.clone().expect("a capture");
    (bed3(done.bed), capture)
}

/// Every slurry body fed is in one place: passed, lodged or in the cake.
fn assert_counted(cap: &CaptureSummary, fed: u64, medium_bodies: u64) {
    assert_eq!(cap.fed, fed);
    assert_eq!(cap.passed + cap.lodged + cap.cake, cap.fed);
    assert_eq!(cap.passed as usize, cap.filtrate.len());
    assert_eq!(cap.medium_bodies, medium_bodies);
    assert_eq!(cap.classes.iter().map(|c| c.fed).sum::<u64>(), cap.fed);
}

#[test]
fn a_precoat_read_back_is_the_medium_as_the_file_has_it() {
    let dir = scratch("read-back");
    let file = precoat(&dir);
    let read = bed3(read_bed(&file, None).unwrap());
    assert_eq!(read.len(), 400);
    // The path is relative to the config file.
    let c = through_file(&dir, "precoat/particles.csv");
    assert_eq!(c.feeds[0].file.as_deref(), Some(file.as_path()));
    let (b, cap) = filtered(&c);
    assert_counted(&cap, 3000, 400);
    assert!(cap.passed > 0 && cap.lodged + cap.cake > 0, "{cap:?}");
    // The medium comes first in the bed: the file's particles, each at its
    // place lifted by the gap (the largest slurry diameter), radius and
    // body kept, of the species made for the file.
    let lift = cap.medium_lift;
    let d_max = 2.0 * c.plan::<3>().unwrap().species[0].size.bounds().1;
    assert_eq!(lift, d_max);
    for i in 0..read.len() {
        let (p, q) = (b.centres[i], read.centres[i]);
        assert_eq!(
            (p[0], p[1], p[2]),
            (q[0], q[1], q[2] + lift),
            "particle {i}"
        );
        assert_eq!(b.radii[i], read.radii[i]);
        assert_eq!(b.bodies[i], read.bodies[i]);
        assert_eq!(b.species_info[b.species[i] as usize].name, "medium file 0");
    }
    let medium = b
        .species
        .iter()
        .filter(|&&s| b.species_info[s as usize].name == "medium file 0")
        .count();
    assert_eq!(medium, 400);
    // The slurry in the bed is what was lodged or caked.
    assert_eq!((b.len() - 400) as u64, cap.lodged + cap.cake);
    let checks = InvariantChecks {
        rest: false,
        ..InvariantChecks::new(TOL)
    };
    assert_checked(&b, &checks, "medium from a file and its slurry");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_precoat_from_a_file_is_the_granular_precoat_of_the_same_seed() {
    let dir = scratch("same-precoat");
    precoat(&dir);
    let (from_file, cap_file) = filtered(&through_file(&dir, "precoat/particles.csv"));
    let granular = config(&format!(
        "{}{MEDIUM}{SLURRY}[[feeds]]\nspecies = [\"medium\"]\ncount = 400\nmedium = true\n\
         [[feeds]]\nspecies = [\"slurry\"]\ncount = 3000\n",
        boxed(3000.0)
    ));
    let (settled, cap_settled) = filtered(&granular);
    // The same 400 spheres, lifted by the same gap.
    assert_eq!(cap_file.medium_lift, cap_settled.medium_lift);
    for i in 0..400 {
        assert_eq!(from_file.centres[i], settled.centres[i], "particle {i}");
        assert_eq!(from_file.radii[i], settled.radii[i]);
    }
    assert_eq!(cap_file.medium_surface, cap_settled.medium_surface);
    assert_counted(&cap_file, 3000, 400);
    assert_counted(&cap_settled, 3000, 400);
    // The slurries differ: the granular run draws them from its generator
    // after the precoat's draws, the run from the file from a fresh one
    // (the precoat was drawn by another run). Same medium, same slurry
    // distribution, so the capture agrees within its sampling noise.
    let counts = |c: &CaptureSummary| [c.passed, c.lodged, c.cake];
    for (a, b) in counts(&cap_file).into_iter().zip(counts(&cap_settled)) {
        let noise = 5.0 * ((a + b) as f64 / 2.0).sqrt() + 10.0;
        assert!(
            (a as f64 - b as f64).abs() < noise,
            "{:?} against {:?}",
            counts(&cap_file),
            counts(&cap_settled)
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The one-line refusal of a config whose first feed is the medium of
/// `csv` (written as `dir/medium.csv`), `feed` the lines of that feed.
fn refusal(dir: &Path, csv: &str, boxed: &str, feed: &str, later: &str) -> String {
    std::fs::write(dir.join("medium.csv"), csv).unwrap();
    // The medium's species only where a feed names it.
    let medium = if format!("{feed}{later}").contains("\"medium\"") {
        MEDIUM
    } else {
        ""
    };
    let text = format!(
        "{boxed}{medium}{SLURRY}{later}[[feeds]]\nfile = \"medium.csv\"\n{feed}\
         [[feeds]]\nspecies = [\"slurry\"]\ncount = 10\n"
    );
    let path = dir.join("c.toml");
    std::fs::write(&path, &text).unwrap();
    let c = Config::from_file(&path).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let e = planned(&c).map(drop).unwrap_err().to_string();
    assert!(!e.contains('\n'), "{e}");
    e
}

/// A 3D `particles.csv` of spheres `(x, y, z, r)`, each its own body.
fn csv(spheres: &[(f64, f64, f64, f64)]) -> String {
    let mut t = String::from("id,species,body,x,y,z,r\n");
    for (i, (x, y, z, r)) in spheres.iter().enumerate() {
        t.push_str(&format!("{i},0,{i},{x},{y},{z},{r}\n"));
    }
    t
}

#[test]
fn bad_medium_files_are_refused_with_one_line() {
    let dir = scratch("refused");
    let periodic = boxed(3000.0);
    let walled = periodic.replace("periodic = true", "periodic = false");
    let two = csv(&[(5.0, 5.0, 1.5, 1.5), (10.0, 5.0, 1.5, 1.5)]);
    // The medium feed's own lines, and those of a feed before it.
    let mut cases: Vec<(String, String, String, String, Vec<&str>)> = vec![
        // Not a bed, or another dimension.
        (
            "hello world\n".into(),
            periodic.clone(),
            String::new(),
            String::new(),
            vec!["feeds[0].file", "medium.csv:1"],
        ),
        (
            "id,species,body,x,y,r\n0,0,0,5,1.5,1.5\n".into(),
            periodic.clone(),
            String::new(),
            String::new(),
            vec!["feeds[0].file", "is a 2D bed, but the config's dim is 3"],
        ),
        // Outside the box: a wall, the periodic cell, the floor (far and by a hair).
        (
            csv(&[(23.0, 5.0, 1.5, 1.5)]),
            walled.clone(),
            String::new(),
            String::new(),
            vec!["feeds[0].file", "wall x1"],
        ),
        (
            csv(&[(25.0, 5.0, 1.5, 1.5)]),
            periodic.clone(),
            String::new(),
            String::new(),
            vec!["feeds[0].file", "outside the periodic cell"],
        ),
        (
            csv(&[(5.0, 5.0, 1.0, 1.5)]),
            periodic.clone(),
            String::new(),
            String::new(),
            vec!["feeds[0].file", "floor"],
        ),
        (
            csv(&[(5.0, 5.0, 1.499999, 1.5)]),
            periodic.clone(),
            String::new(),
            String::new(),
            vec!["feeds[0].file", "1 particle sticks out of the box", "floor"],
        ),
        // Overlapping particles.
        (
            csv(&[(5.0, 5.0, 1.5, 1.5), (7.99, 5.0, 1.5, 1.5)]),
            periodic.clone(),
            String::new(),
            String::new(),
            vec![
                "feeds[0].file",
                "1 pair of particles",
                "overlap",
                "ids 0 and 1",
            ],
        ),
        // Into the feed region: the medium (3 high, lifted by the slurry's
        // largest diameter) reaches the roof of a box 4 high.
        (
            two.clone(),
            boxed(4.0),
            String::new(),
            String::new(),
            vec![
                "feeds[0].file",
                "stands",
                "reaching the roof (box.height = 4)",
                "feed region",
            ],
        ),
    ];
    for key in [
        "species = [\"medium\"]\n",
        "count = 4\n",
        "mass_per_area = 0.1\n",
        "settling = { restitution = 0.5 }\n",
        "mesh = { wire_diameter = 2, aperture = 3 }\n",
    ] {
        let word = key.split(' ').next().unwrap();
        cases.push((
            two.clone(),
            periodic.clone(),
            key.into(),
            String::new(),
            vec!["feeds[0].", word, "placed as the file has it, not fed"],
        ));
    }
    cases.push((
        two.clone(),
        periodic.clone(),
        String::new(),
        "[[feeds]]\nspecies = [\"medium\"]\ncount = 5\nmedium = true\n".into(),
        vec!["feeds[1].file", "first feed"],
    ));
    for (csv, boxed, feed, later, needles) in &cases {
        let e = refusal(&dir, csv, boxed, feed, later);
        for n in needles {
            assert!(e.contains(n), "`{n}` not in: {e}");
        }
    }
    // A missing file: the reader's error, naming the feed and the file.
    std::fs::remove_file(dir.join("medium.csv")).unwrap();
    let text = format!(
        "{periodic}{SLURRY}[[feeds]]\nfile = \"gone.csv\"\n[[feeds]]\nspecies = [\"slurry\"]\ncount = 10\n"
    );
    let path = dir.join("gone.toml");
    std::fs::write(&path, text).unwrap();
    let e = planned(&Config::from_file(&path).unwrap())
        .map(drop)
        .unwrap_err()
        .to_string();
    assert!(e.contains("feeds[0].file") && e.contains("gone.csv"), "{e}");
    assert!(!e.contains('\n'), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A plate over the whole periodic floor of [`boxed`]: two layers (z = 1
/// and 3) of beads of radius 1 at `spacing` on a square grid, all one body
/// (`one_body`) or each its own. (A single layer has no pore between its
/// layer and its mirror images whose flow the network solves: see the
/// guide's limits.)
fn plate(spacing: f64, one_body: bool) -> String {
    let n = (24.0 / spacing).round() as usize;
    let mut t = String::from("id,species,body,x,y,z,r\n");
    for k in 0..2 {
        for i in 0..n {
            for j in 0..n {
                let id = n * n * k + n * i + j;
                let body = if one_body { 0 } else { id };
                let (x, y, z) = (spacing * i as f64, spacing * j as f64, 1 + 2 * k);
                t.push_str(&format!("{id},0,{body},{x},{y},{z},1\n"));
            }
        }
    }
    t
}

/// A filtration needs a medium that fluid passes: a plate of one body's
/// beads overlapping deeply is a wall to the pore network, and is refused
/// when `[filtration]` asks for the curve; the same plate without it, and a
/// grid of touching spheres with it, are media.
#[test]
fn a_medium_file_with_no_opening_is_refused_for_a_filtration() {
    let dir = scratch("closed");
    let filtration = "[analysis]\nlength_unit = \"um\"\nsolid_density = 2650\n\
                      [filtration]\npressure = 1e5\nconcentration = 100\n";
    let plan = |csv: &str, tail: &str| {
        std::fs::write(dir.join("plate.csv"), csv).unwrap();
        let text = format!(
            "{}{SLURRY}[[feeds]]\nfile = \"plate.csv\"\n\
             [[feeds]]\nspecies = [\"slurry\"]\ncount = 10\n{tail}",
            boxed(400.0).replace("[analysis]\nmeasures = [\"packing\"]\n", "")
        );
        let path = dir.join("c.toml");
        std::fs::write(&path, &text).unwrap();
        planned(&Config::from_file(&path).unwrap_or_else(|e| panic!("{e}\n{text}")))
            .map(drop)
            .map_err(|e| e.to_string())
    };
    let e = plan(&plate(0.5, true), filtration).unwrap_err();
    assert!(!e.contains('\n'), "{e}");
    for needle in ["feeds[0].file", "plate.csv", "no opening", "[filtration]"] {
        assert!(e.contains(needle), "`{needle}` not in: {e}");
    }
    plan(&plate(0.5, true), "").unwrap();
    plan(&plate(2.0, false), filtration).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_files_bodies_stay_whole_and_its_species_keep_their_radii() {
    // Two rigid bodies of two beads each, their rows interleaved and
    // numbered sparsely (a scan's export), of two species and three radii.
    let dir = scratch("bodies");
    std::fs::write(
        dir.join("medium.csv"),
        "id,species,body,x,y,z,r\n\
         0,4,7,4,4,1,1\n1,2,3,12,4,2,2\n2,4,7,5.5,4,1,1\n3,2,3,12,7,1.5,1.5\n",
    )
    .unwrap();
    let path = dir.join("c.toml");
    std::fs::write(
        &path,
        format!(
            "{}{SLURRY}[[feeds]]\nfile = \"medium.csv\"\n[[feeds]]\nspecies = [\"slurry\"]\ncount = 200\n",
            boxed(3000.0)
        ),
    )
    .unwrap();
    let c = Config::from_file(&path).unwrap();
    let (b, cap) = filtered(&c);
    assert_counted(&cap, 200, 2);
    let lift = cap.medium_lift;
    // Body 7 first (its first row comes first), then body 3, each whole.
    assert_eq!(&b.bodies[..4], &[0, 0, 1, 1]);
    let at: Vec<[f64; 4]> = (0..4)
        .map(|i| {
            let p = b.centres[i];
            [p[0], p[1], p[2], b.radii[i]]
        })
        .collect();
    assert_eq!(
        at,
        [
            [4.0, 4.0, 1.0 + lift, 1.0],
            [5.5, 4.0, 1.0 + lift, 1.0],
            [12.0, 4.0, 2.0 + lift, 2.0],
            [12.0, 7.0, 1.5 + lift, 1.5]
        ]
    );
    // One species per species index of the file, in increasing order: 2
    // (radii 2 and 1.5, a table of both) and 4 (radius 1).
    let names: Vec<&str> = (0..4)
        .map(|i| b.species_info[b.species[i] as usize].name.as_str())
        .collect();
    assert_eq!(
        names,
        [
            "medium file 4",
            "medium file 4",
            "medium file 2",
            "medium file 2"
        ]
    );
    let bounds: Vec<(f64, f64)> = ["medium file 2", "medium file 4"]
        .iter()
        .map(|name| {
            let s = b.species_info.iter().find(|s| s.name == *name).unwrap();
            s.size.bounds()
        })
        .collect();
    assert_eq!(bounds, [(1.5, 2.0), (1.0, 1.0)]);
    std::fs::remove_dir_all(&dir).unwrap();
}
