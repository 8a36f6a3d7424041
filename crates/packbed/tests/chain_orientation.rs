//! Left and right in 2D chain orientation: chains lying flat are counted on the
//! side of their last bead, so the signed-angle histogram of a bed whose physics
//! is mirror-symmetric must be mirror-symmetric too (before, every chain of the
//! base layer pointed to +90° and the last bin held about twice the first).

use packbed::analysis::orientation::{body_axes, orientation};
use packbed::bed::Bed;
use packbed::config::Config;
use packbed::deposit::deposit;

fn bed_2d(seed: u64) -> Bed<2> {
    let text = format!(
        "dim = 2\nseed = {seed}\n[box]\nwidth = 3000\nheight = 400\nperiodic = true\n\
         [fill]\ncount = 4000\nbase_layer = \"random\"\n\
         [[species]]\nradius = 10\nshape = \"chain\"\nbeads = 5\n"
    );
    let plan = Config::from_toml(&text, "test")
        .unwrap()
        .plan::<2>()
        .unwrap();
    deposit::<2>(&plan, &mut |_| {}).unwrap().0
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
        let o = orientation(&bed_2d(seed)).unwrap();
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
