//! Size distributions with bounds: the window `[min, max]` of a normal or
//! lognormal, its default of ±3 standard deviations, what sets the box by it,
//! and the refusals of bad bounds.

use crate::common::{config, run};
use packbed::Config;
use packbed::Real;
use packbed::SizeDist;
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

fn one_species(dim: u8, size: &str) -> String {
    // A count keeps radii near 0 (a normal cut just above 0) from asking for
    // more particles than memory holds.
    format!("dim = {dim}\n[box]\npreset = \"thesis\"\n[fill]\ncount = 10\n[[species]]\nsize = {{ {size} }}\n")
}

fn size_of(dim: u8, size: &str) -> SizeDist {
    let c = config(&one_species(dim, size));
    c.plan::<3>().unwrap().species[0].size.clone()
}

/// The config's error for `size`, which must be refused.
fn refusal(size: &str) -> String {
    let text = one_species(3, size);
    match Config::from_toml(&text, "bounds.toml").and_then(|c| c.validate()) {
        Ok(()) => panic!("accepted: {size}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bounds_from_the_config_are_the_window() {
    let d = size_of(
        3,
        "dist = \"lognormal\", median = 10, gsd = 2, min = 2, max = 100",
    );
    assert_eq!(d.bounds(), (2.0, 100.0));
    assert_eq!(d.describe(), "r ~ lognormal(median 10, gsd 2) in [2, 100]");
    let d = size_of(3, "dist = \"normal\", mean = 10, sd = 2, min = 9, max = 30");
    assert_eq!(d.bounds(), (9.0, 30.0));
    assert_eq!(d.describe(), "r ~ normal(mean 10, sd 2) in [9, 30]");
    // No spread: the one radius, whatever window holds it.
    let d = size_of(3, "dist = \"normal\", mean = 10, sd = 0, min = 5, max = 20");
    assert_eq!(d.bounds(), (10.0, 10.0));
}

#[test]
fn without_bounds_the_window_is_three_sd() {
    let d = size_of(3, "dist = \"lognormal\", median = 10, gsd = 2");
    assert_eq!(d.bounds(), (1.25, 80.0));
    assert_eq!(
        d.describe(),
        "r ~ lognormal(median 10, gsd 2) in [1.25, 80] (±3 sd)"
    );
    let d = size_of(3, "dist = \"normal\", mean = 10, sd = 2");
    assert_eq!(d.bounds(), (4.0, 16.0));
    // 10 − 3·4 < 0: cut just above 0 (at mean / 1000), as before.
    let d = size_of(3, "dist = \"normal\", mean = 10, sd = 4");
    assert_eq!(d.bounds(), (0.01, 22.0));
}

#[test]
fn a_bound_alone_keeps_the_default_on_the_other_side() {
    let d = size_of(3, "dist = \"lognormal\", median = 10, gsd = 2, max = 40");
    assert_eq!(d.bounds(), (1.25, 40.0));
    assert_eq!(
        d.describe(),
        "r ~ lognormal(median 10, gsd 2) in [1.25, 40] (min at -3 sd)"
    );
    let d = size_of(3, "dist = \"normal\", mean = 10, sd = 2, min = 1");
    assert_eq!(d.bounds(), (1.0, 16.0));
    assert_eq!(
        d.describe(),
        "r ~ normal(mean 10, sd 2) in [1, 16] (max at +3 sd)"
    );
}

#[test]
fn the_thesis_box_scales_with_the_upper_bound() {
    // 6 largest diameters a side in 3D: 12 · 40, not 12 · 80.
    let c = config(&one_species(
        3,
        "dist = \"lognormal\", median = 10, gsd = 2, max = 40",
    ));
    let plan = c.plan::<3>().unwrap();
    assert_eq!(plan.container.size.0, [480.0; 3]);
    // `diameters = N` too: 2 · 5 · 40.
    let c = config(
        "dim = 3\n[box]\ndiameters = 5\n[[species]]\nsize = { dist = \"lognormal\", median = 10, gsd = 2, max = 40 }\n",
    );
    assert_eq!(c.plan::<3>().unwrap().container.size.0, [400.0; 3]);
}

#[test]
fn bad_bounds_are_refused_naming_the_setting() {
    for (size, expected) in [
        (
            "dist = \"lognormal\", median = 10, gsd = 2, min = 0",
            "species[0].size.min must be a positive number, got 0",
        ),
        (
            "dist = \"normal\", mean = 10, sd = 2, max = -5",
            "species[0].size.max must be a positive number, got -5",
        ),
        (
            "dist = \"lognormal\", median = 10, gsd = 2, max = inf",
            "species[0].size.max must be a positive number, got inf",
        ),
        (
            "dist = \"lognormal\", median = 10, gsd = 2, min = nan",
            "species[0].size.min must be a positive number, got NaN",
        ),
        (
            "dist = \"lognormal\", median = 10, gsd = 2, min = 50, max = 20",
            "species[0].size: max (20) is smaller than min (50)",
        ),
        (
            "dist = \"lognormal\", median = 10, gsd = 2, min = 100",
            "species[0].size.min (100) is above the default upper end of the window (80, +3 sd); give `max` too",
        ),
        (
            "dist = \"normal\", mean = 10, sd = 2, max = 3",
            "species[0].size.max (3) is below the default lower end of the window (4); give `min` too",
        ),
        (
            "dist = \"lognormal\", median = 10, gsd = 1.1, min = 50, max = 60",
            "species[0].size: the window [50, 60] holds only 2.8e-64 of lognormal(median 10, gsd 1.1) (at least 1e-6 needed); move `min`/`max` towards the distribution or widen them",
        ),
        (
            "dist = \"normal\", mean = 10, sd = 0, min = 20, max = 30",
            "species[0].size: the window [20, 30] holds nothing of normal(mean 10, sd 0) (at least 1e-6 needed); move `min`/`max` towards the distribution or widen them",
        ),
        (
            "table = \"psd.csv\", max = 30",
            "species[0].size: `min`/`max` do not apply to a table (its rows bound it; leave out the rows you do not want)",
        ),
    ] {
        let e = refusal(size);
        assert!(e.contains(expected), "{size}:\n  got      {e}\n  expected {expected}");
        assert!(!e.contains('\n'), "{size}: not one line: {e}");
    }
}

#[test]
fn a_window_in_the_tail_is_refused_or_drawn_at_once() {
    // Just enough mass (2e-6, 4.6 sd out) is drawn from; nothing loops.
    let d = size_of(
        3,
        "dist = \"normal\", mean = 10, sd = 1, min = 14.6, max = 20",
    );
    assert!(d.window_mass() > 1e-6 && d.window_mass() < 1e-5);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
    for _ in 0..10_000 {
        let r = d.sample(&mut rng);
        assert!((14.6..=20.0).contains(&r), "{r}");
    }
    // One radius: `min = max`.
    let d = size_of(
        3,
        "dist = \"lognormal\", median = 10, gsd = 2, min = 12, max = 12",
    );
    assert_eq!(d.sample(&mut rng), 12.0);
    assert_eq!(d.bounds(), (12.0, 12.0));
}

/// `Φ(x)` by the Taylor series of erf, independent of the crate's `erfc`: exact
/// to about 1e-15 for `|x| <= 4`.
fn phi(x: Real) -> Real {
    let t = x / std::f64::consts::SQRT_2;
    let (mut term, mut sum) = (t, t);
    for n in 1..200 {
        term *= -t * t / n as Real;
        sum += term / (2 * n + 1) as Real;
    }
    0.5 + sum / std::f64::consts::PI.sqrt()
}

/// `z` with `Φ(z) = p`, by bisection.
fn phi_inverse(p: Real) -> Real {
    let (mut lo, mut hi) = (-4.0, 4.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if phi(mid) < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The median of 100 000 draws against that of the truncated distribution:
/// half of the window's mass below it, `Φ(z) = (Φ(a) + Φ(b)) / 2` for the
/// window `[a, b]` in standard units.
fn check_median(
    d: &SizeDist,
    (a, b): (Real, Real),
    to_radius: impl Fn(Real) -> Real,
    expected: Real,
) {
    let z = phi_inverse(0.5 * (phi(a) + phi(b)));
    let m = to_radius(z);
    assert!((m - expected).abs() < 1e-6, "{m} vs hand value {expected}");
    assert!(
        (d.median() - m).abs() < 1e-9 * m,
        "{}: {} vs {m}",
        d.describe(),
        d.median()
    );
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
    let mut r: Vec<Real> = (0..100_000).map(|_| d.sample(&mut rng)).collect();
    r.sort_by(Real::total_cmp);
    let sampled = 0.5 * (r[49_999] + r[50_000]);
    // The sample median's sd is 1 / (2 f(m) √n): 0.027 for the lognormal,
    // 0.0043 for the normal; 5 sd is allowed.
    let sd = 1.0 / (2.0 * density(d, m) * (r.len() as Real).sqrt());
    assert!(
        (sampled - m).abs() < 5.0 * sd,
        "{}: sample median {sampled}, truncated median {m} (sd {sd})",
        d.describe()
    );
}

/// Density of the truncated distribution at `r`, by a central difference of
/// the crate-independent CDF.
fn density(d: &SizeDist, r: Real) -> Real {
    let (cdf, (lo, hi)): (Box<dyn Fn(Real) -> Real>, _) = match *d {
        SizeDist::Normal { mean, sd, lo, hi } => {
            (Box::new(move |x| phi((x - mean) / sd)), (lo, hi))
        }
        SizeDist::Lognormal {
            median,
            gsd,
            lo,
            hi,
        } => (
            Box::new(move |x: Real| phi((x / median).ln() / gsd.ln())),
            (lo, hi),
        ),
        _ => unreachable!(),
    };
    let h = 1e-4 * r;
    (cdf(r + h) - cdf(r - h)) / (2.0 * h) / (cdf(hi) - cdf(lo))
}

#[test]
fn the_median_of_bounded_draws_is_the_truncated_median() {
    // Lognormal median 10, gsd 2 in [8, 100]: a = log2 0.8 = -0.321928,
    // b = log2 10 = 3.321928; Φ(a) = 0.373754, Φ(b) = 0.999553, so the median
    // has Φ(z) = 0.686653, z = 0.486386 and r = 10 · 2^z = 14.00931 (not 10).
    let d = size_of(
        3,
        "dist = \"lognormal\", median = 10, gsd = 2, min = 8, max = 100",
    );
    check_median(
        &d,
        (0.8f64.log2(), 10f64.log2()),
        |z| 10.0 * 2f64.powf(z),
        14.009_312_478_929,
    );
    // Normal mean 10, sd 2 in [9, 12]: a = -0.5, b = 1; Φ(a) = 0.308538,
    // Φ(b) = 0.841345, Φ(z) = 0.574941, z = 0.188968, r = 10.377936.
    let d = size_of(3, "dist = \"normal\", mean = 10, sd = 2, min = 9, max = 12");
    check_median(&d, (-0.5, 1.0), |z| 10.0 + 2.0 * z, 10.377_936_464);
}

#[test]
fn a_bounded_bed_holds_only_radii_in_the_window() {
    let c = config(
        "dim = 2\nseed = 5\n[box]\nwidth = 400\nheight = 300\n[fill]\ncount = 300\n[[species]]\nsize = { dist = \"lognormal\", median = 10, gsd = 1.5, min = 7, max = 12 }\n",
    );
    let (b, _) = run::<2>(&c);
    assert!(b.len() >= 100, "{}", b.len());
    assert!(b.radii.iter().all(|r| (7.0..=12.0).contains(r)));
}

#[test]
fn bounds_round_trip_through_the_config_as_written() {
    let c = config(&one_species(
        3,
        "dist = \"lognormal\", median = 10, gsd = 2, min = 2.5, max = 100",
    ));
    let text = toml::to_string(&c).unwrap();
    let back = config(&text);
    let s = back.species[0].size.as_ref().unwrap();
    assert_eq!((s.min, s.max), (Some(2.5), Some(100.0)), "{text}");
    assert_eq!(
        back.plan::<3>().unwrap().species,
        c.plan::<3>().unwrap().species
    );
    // And through JSON, as in summary.json's `config`.
    let json = serde_json::to_string(&c).unwrap();
    let back: Config = serde_json::from_str(&json).unwrap();
    assert_eq!(
        back.plan::<3>().unwrap().species,
        c.plan::<3>().unwrap().species
    );
}
