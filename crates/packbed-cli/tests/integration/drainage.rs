//! `--measures drainage` through the command: its files, its summary and
//! its refusals.

use crate::common::{assert_config_refused, Scratch};

fn config(extra: &str) -> String {
    format!(
        "dim = 3\nseed = 1\n[box]\nwidth = 12\ndepth = 12\nheight = 60\nperiodic = true\n\
         [fill]\ncount = 1200\n[[species]]\nradius = 1\n\
         [analysis]\nmeasures = [\"packing\", \"drainage\"]\n{extra}"
    )
}

#[test]
fn drainage_writes_its_curve_bridges_and_pore_states() {
    let s = Scratch::new();
    let c = s.input("wet.toml", &config("length_unit = \"um\"\n"));
    let o = s.ok(&["run", c.to_str().unwrap(), "--out", "wet", "--no-pictures"]);
    // On screen after the cake: the breakthrough in Pa and the liquid left.
    let screen = format!("{}{}", o.stdout, o.stderr);
    assert!(
        screen.contains("drainage: breakthrough P_c·d32/γ"),
        "{screen}"
    );
    assert!(screen.contains(" Pa), saturation then "), "{screen}");
    let summary = s.summary("wet");
    let d = &summary["drainage"];
    let bt = d["breakthrough"]["reduced"].as_f64().unwrap();
    // Random packs of equal spheres break through at P_c R/γ of about 3.3
    // (Yade, MS-P) to 6 (Haines): reduced by d32 = 2R, 6.6 to 12.
    assert!((6.0..13.0).contains(&bt), "{bt}");
    // With the length unit, Pa: γ/R = 0.0728 / 1e-6 Pa per unit of P_c R/γ.
    let pa = d["breakthrough"]["pa"].as_f64().unwrap();
    assert!((pa - bt / 2.0 * 0.0728 / 1e-6).abs() < 1e-6 * pa, "{pa}");
    let curve = s.read("wet/drainage.csv");
    let header = curve.lines().next().unwrap();
    assert_eq!(
        header,
        "pc_reduced,pc_pa,saturation,connected,trapped,pendular,k_rw,k_rg"
    );
    assert!(curve.lines().count() > 50);
    let liquid = s.read("wet/liquid.csv");
    assert!(liquid.starts_with("particle_a,particle_b,sx,sy,gap,volume"));
    assert_eq!(
        liquid.lines().count() as u64 - 1,
        d["bridges"].as_u64().unwrap()
    );
    let pores = s.read("wet/pores.csv");
    assert!(pores
        .lines()
        .next()
        .unwrap()
        .ends_with(",filled,liquid_state,cluster,liquid"));
}

#[test]
fn drainage_bad_input() {
    let s = Scratch::new();
    let bad = [
        (
            "[analysis.drainage]\ncontact_angle = 95\n",
            "not a drainage",
        ),
        (
            "[analysis.drainage]\nsurface_tension = -0.07\n",
            "surface_tension",
        ),
        ("[analysis.drainage]\npressure = 5000\n", "length_unit"),
    ];
    for (k, (extra, needle)) in bad.iter().enumerate() {
        assert_config_refused(&s, &format!("bad{k}.toml"), &config(extra), &[needle]);
    }
    // A slab from the floor has no outlet below it: refused before the bed
    // is built.
    assert_config_refused(
        &s,
        "floor.toml",
        &config("[analysis.flow]\nslab = [0, 20]\n"),
        &["no outlet"],
    );
}

#[test]
fn ensembles_average_the_drainage_curve_and_compare_draws_each_groups() {
    let s = Scratch::new();
    let narrow = s.input("narrow.toml", &config(""));
    let wide = s.input(
        "wide.toml",
        &config("").replace(
            "radius = 1\n",
            "size = { dist = \"lognormal\", median = 1.0, gsd = 1.3 }\n",
        ),
    );
    s.ok(&[
        "ensemble",
        narrow.to_str().unwrap(),
        "--runs",
        "3",
        "--out",
        "narrow",
    ]);
    s.ok(&[
        "ensemble",
        wide.to_str().unwrap(),
        "--runs",
        "2",
        "--out",
        "wide",
    ]);
    // Every replicate's curve sits on the same reduced pressures, so the
    // ensemble's statistics are per pressure: the mean lies between the
    // lowest and the highest bed's, and falls with the pressure.
    let csv = s.read("narrow/ensemble.csv");
    let row = |name: &str| -> Vec<f64> {
        let line = csv
            .lines()
            .find(|l| l.starts_with(&format!("{name},")))
            .unwrap_or_else(|| panic!("no {name} in ensemble.csv"));
        line.split(',')
            .skip(1)
            .take(5)
            .map(|x| x.parse().unwrap())
            .collect()
    };
    let mut last = f64::INFINITY;
    for k in 0..41 {
        let p = row(&format!("drainage.curve.pc_reduced[{k}]"));
        assert_eq!(p[0], 3.0);
        assert!((p[1] - 10f64.powf(k as f64 / 20.0)).abs() < 1e-9, "{p:?}");
        let sat = row(&format!("drainage.curve.saturation[{k}]"));
        let (mean, min, max) = (sat[1], sat[3], sat[4]);
        assert!(
            min <= mean && mean <= max && (0.0..=1.0).contains(&min),
            "{sat:?}"
        );
        assert!(mean <= last + 1e-12, "the mean curve rises at point {k}");
        last = mean;
    }
    // Below the first entry (P_c·d32/γ = 1) the beds are full; at 100 the
    // liquid left is the residual, well below a half.
    assert_eq!(row("drainage.curve.saturation[0]")[1], 1.0);
    assert!(row("drainage.curve.saturation[40]")[1] < 0.5);
    let plot = s.read("narrow/plot_drainage.svg");
    assert!(plot.contains("<polygon"), "the band is drawn");
    // compare: both groups' mean curves with their bands, and the
    // breakthrough among the measures.
    let o = s.ok(&["compare", "narrow", "wide", "--out", "cmp"]);
    assert!(
        o.stdout.contains("drainage.breakthrough.reduced"),
        "{}",
        o.stdout
    );
    let svg = s.read("cmp/plot_compare_drainage.svg");
    assert_eq!(svg.matches("<polygon").count(), 2, "{svg}");
    let texts = crate::common::svg_texts(&svg);
    assert!(texts.iter().any(|t| t == "narrow (3 beds)"), "{texts:?}");
    assert!(texts.iter().any(|t| t == "wide (2 beds)"), "{texts:?}");
}
