//! Histograms shared by the measures: counts of small integers (coordination
//! numbers, void sides) and fixed-width bins of angles.

use crate::math::Real;
use serde::Serialize;

/// Counts of each value `0, 1, 2, …` up to the largest value seen (empty for no
/// values).
pub fn count_histogram(values: impl IntoIterator<Item = u32>) -> Vec<u64> {
    let mut counts: Vec<u64> = Vec::new();
    for v in values {
        let v = v as usize;
        if v >= counts.len() {
            counts.resize(v + 1, 0);
        }
        counts[v] += 1;
    }
    counts
}

/// A histogram of fixed-width bins over `[lo, hi]`; the value `hi` falls in the
/// last bin.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct BinnedHistogram {
    /// Lower edge of the first bin.
    pub lo: Real,
    /// Width of every bin.
    pub bin_width: Real,
    /// Count in each bin, from `lo` upwards.
    pub counts: Vec<u64>,
}

impl BinnedHistogram {
    /// Empty bins of width `bin_width` covering `[lo, hi]`.
    pub fn new(lo: Real, hi: Real, bin_width: Real) -> Self {
        let n = ((hi - lo) / bin_width).round().max(1.0) as usize;
        BinnedHistogram {
            lo,
            bin_width,
            counts: vec![0; n],
        }
    }

    /// Adds one value; values outside the range go to the nearest end bin, NaN is
    /// ignored.
    pub fn add(&mut self, v: Real) {
        if v.is_nan() || self.counts.is_empty() {
            return;
        }
        let k = ((v - self.lo) / self.bin_width).floor();
        let k = k.clamp(0.0, (self.counts.len() - 1) as Real) as usize;
        self.counts[k] += 1;
    }

    /// Upper edge of the last bin.
    pub fn hi(&self) -> Real {
        self.lo + self.bin_width * self.counts.len() as Real
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_of_small_integers() {
        assert_eq!(count_histogram([2, 0, 2, 5]), vec![1, 0, 2, 0, 0, 1]);
        assert!(count_histogram([]).is_empty());
    }

    #[test]
    fn angle_bins_with_closed_upper_end() {
        let mut h = BinnedHistogram::new(-90.0, 90.0, 5.0);
        assert_eq!(h.counts.len(), 36);
        for v in [-90.0, -85.0, -0.1, 0.0, 4.99, 90.0, 120.0, Real::NAN] {
            h.add(v);
        }
        assert_eq!(h.counts[0], 1);
        assert_eq!(h.counts[1], 1);
        assert_eq!(h.counts[17], 1);
        assert_eq!(h.counts[18], 2);
        assert_eq!(h.counts[35], 2);
        assert_eq!(h.counts.iter().sum::<u64>(), 7);
        assert_eq!(h.hi(), 90.0);
    }
}
