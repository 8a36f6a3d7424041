//! Left and right in 2D chain orientation: chains lying flat are counted on the
//! side of their last bead, so the signed-angle histogram of a bed whose physics
//! is mirror-symmetric must be mirror-symmetric too (before, every chain of the
//! base layer pointed to +90° and the last bin held about twice the first).

use packbed::Bed;
use packbed::{body_axes, orientation, AngleFrom};

fn bed_2d(seed: u64) -> Bed<2> {
    let text = format!(
        "dim = 2\nseed = {seed}\n[box]\nwidth = 3000\nheight = 400\nperiodic = true\n\
         [fill]\ncount = 4000\nbase_layer = \"random\"\n\
         [[species]]\nradius = 10\nshape = \"chain\"\nbeads = 5\n"
    );
    crate::common::run::<2>(&crate::common::config(&text)).0
}

/// `|a − b|` within four standard deviations of a fair split of `a + b`.
fn balanced(a: u64, b: u64) -> bool {
    let (a, b) = (a as f64, b as f64);
    (a - b).abs() <= 4.0 * (a + b).sqrt()
}

#[test]
fn flat_chains_of_the_base_layer_lie_both_ways() {
    let bed = bed_2d(3);
    let axes = body_axes(&bed);
    let left = axes.iter().filter(|a| a.angle == -90.0).count() as u64;
    let right = axes.iter().filter(|a| a.angle == 90.0).count() as u64;
    assert!(left + right >= 50, "{left} + {right} flat chains");
    assert!(
        left > 0 && right > 0 && balanced(left, right),
        "{left} vs {right}"
    );
}

#[test]
fn signed_angle_histogram_is_mirror_symmetric() {
    let (mut lo, mut hi, mut ends) = (0u64, 0u64, [0u64; 2]);
    for seed in 1..=3 {
        let o = orientation(&bed_2d(seed), AngleFrom::Vertical).unwrap();
        let c = &o.histogram.counts;
        assert_eq!(c.len(), 36);
        lo += c[..18].iter().sum::<u64>();
        hi += c[18..].iter().sum::<u64>();
        ends[0] += c[0];
        ends[1] += c[35];
    }
    assert!(balanced(lo, hi), "left {lo}, right {hi}");
    assert!(balanced(ends[0], ends[1]), "end bins {ends:?}");
}

/// Hand-made beds measured in both conventions: the source study's angles are
/// from the horizontal, packbed's default from the vertical.
#[test]
fn angles_from_vertical_and_from_horizontal() {
    use packbed::Container;
    use packbed::Vector;
    use packbed::{analyze_with, AnalysisOptions};
    let with = |from: AngleFrom| AnalysisOptions {
        angle_from: from,
        ..AnalysisOptions::default()
    };

    // 3D: one rod lying along x, one standing upright, far apart.
    let mut bed = Bed::new(
        Container {
            size: Vector([100.0, 100.0, 100.0]),
            periodic: false,
        },
        Vec::new(),
    );
    for k in 0..4 {
        bed.push_bead(Vector([10.0 + k as f64, 50.0, 1.0]), 1.0, 0, 0);
    }
    for k in 0..4 {
        bed.push_bead(Vector([80.0, 50.0, 1.0 + k as f64]), 1.0, 0, 1);
    }
    let (_, v) = analyze_with(&bed, &with(AngleFrom::Vertical));
    let (_, h) = analyze_with(&bed, &with(AngleFrom::Horizontal));
    let (v, h) = (v.orientation.unwrap(), h.orientation.unwrap());
    assert_eq!(v.angle_from, AngleFrom::Vertical);
    assert_eq!(h.angle_from, AngleFrom::Horizontal);
    // The horizontal rod: 90° from vertical (last bin), 0° from horizontal (first).
    assert_eq!((v.histogram.lo, v.histogram.counts.len()), (0.0, 18));
    assert_eq!((h.histogram.lo, h.histogram.counts.len()), (0.0, 18));
    assert_eq!((v.histogram.counts[17], v.histogram.counts[0]), (1, 1));
    assert_eq!((h.histogram.counts[0], h.histogram.counts[17]), (1, 1));
    assert!((v.mean_angle - 45.0).abs() < 1e-9 && (h.mean_angle - 45.0).abs() < 1e-9);
    // The order parameter is about the vertical in either convention.
    assert_eq!(v.order_parameter, h.order_parameter);
    let json = serde_json::to_value(&h).unwrap();
    assert_eq!(json["angle_from"], "horizontal");

    // The horizontal rod alone.
    let mut flat = Bed::new(bed.container, Vec::new());
    for k in 0..4 {
        flat.push_bead(Vector([10.0 + k as f64, 50.0, 1.0]), 1.0, 0, 0);
    }
    let v = orientation(&flat, AngleFrom::Vertical).unwrap();
    let h = orientation(&flat, AngleFrom::Horizontal).unwrap();
    assert!((v.mean_angle - 90.0).abs() < 1e-9, "{}", v.mean_angle);
    assert!(h.mean_angle.abs() < 1e-9, "{}", h.mean_angle);

    // 2D: lying right, lying left, upright, and leaning 30° to the right.
    let mut bed = Bed::new(
        Container {
            size: Vector([200.0, 100.0]),
            periodic: false,
        },
        Vec::new(),
    );
    let t = 30f64.to_radians();
    for (body, (start, dir)) in [
        ([10.0, 1.0], [1.0, 0.0]),
        ([60.0, 1.0], [-1.0, 0.0]),
        ([100.0, 1.0], [0.0, 1.0]),
        ([150.0, 1.0], [t.sin(), t.cos()]),
    ]
    .into_iter()
    .enumerate()
    {
        for k in 0..4 {
            let p = Vector([start[0] + dir[0] * k as f64, start[1] + dir[1] * k as f64]);
            bed.push_bead(p, 1.0, 0, body as u32);
        }
    }
    let v: Vec<f64> = body_axes(&bed)
        .iter()
        .map(|a| AngleFrom::Vertical.convert(a.angle))
        .collect();
    let h: Vec<f64> = body_axes(&bed)
        .iter()
        .map(|a| AngleFrom::Horizontal.convert(a.angle))
        .collect();
    let near = |a: &[f64], b: [f64; 4]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9);
    assert!(near(&v, [90.0, -90.0, 0.0, 30.0]), "{v:?}");
    assert!(near(&h, [0.0, 180.0, 90.0, 60.0]), "{h:?}");
    let o = orientation(&bed, AngleFrom::Horizontal).unwrap();
    assert_eq!((o.histogram.lo, o.histogram.hi()), (0.0, 180.0));
    let c = &o.histogram.counts;
    assert_eq!((c[0], c[35], c[18]), (1, 1, 1), "{c:?}");
}
