//! Units: a bed is valid at either end of the lengths packbed accepts
//! (`config::LENGTH_RANGE`), and lengths beyond it are refused with exit-code-2
//! errors rather than giving overlapping particles (radii of 1e-100) or a run
//! that never ends (1e160), as they did before the range was checked.

use packbed::check_bed;
use packbed::Error;
use packbed::{Config, LENGTH_RANGE};

fn config(dim: u8, small: f64, large: f64) -> Config {
    let text = format!(
        "dim = {dim}\nseed = 3\n[[species]]\nradius = {small:e}\n[[species]]\nradius = {large:e}\n"
    );
    crate::common::config(&text)
}

/// Deposits the bed of `c` and checks it from positions alone.
fn deposit_and_check<const D: usize>(c: &Config, what: &str) {
    let bed = crate::common::run::<D>(c).0;
    let report = check_bed(&bed, 1e-9);
    assert!(report.is_ok() && bed.len() > 100, "{what}: {report}");
}

#[test]
fn beds_at_both_ends_of_the_range_are_valid() {
    let (lo, hi) = LENGTH_RANGE;
    // Radii 10 and 20 scaled so that the smallest radius, or the 2D thesis box
    // (30 largest radii; 12 in 3D), sits at an end of the range.
    for scale in [lo / 10.0, hi / 600.0] {
        deposit_and_check::<3>(
            &config(3, 10.0 * scale, 20.0 * scale),
            &format!("3D {scale:e}"),
        );
        deposit_and_check::<2>(
            &config(2, 10.0 * scale, 20.0 * scale),
            &format!("2D {scale:e}"),
        );
    }
}

#[test]
fn lengths_beyond_the_range_are_refused() {
    let (lo, hi) = LENGTH_RANGE;
    for (small, large) in [
        (lo / 2.0, lo),
        (1e-100, 2e-100),
        (hi / 5.0, hi / 4.0),
        (1e160, 1e161),
    ] {
        match config(3, small, large).plan::<3>() {
            Err(e @ Error::Config(_)) => {
                assert!(e.to_string().contains("choose other units"), "{e}")
            }
            other => panic!("{small:e}, {large:e}: {:?}", other.map(|p| p.species.len())),
        }
    }
}
