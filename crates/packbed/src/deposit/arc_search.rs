//! The candidates of one arc, sifted a batch at a time.
//!
//! A rolling move asks every particle in the cells around its arc whether the
//! arc enters it; about one in three even reaches the arc's box, and fewer
//! still are entered before the arc ends. Asked one at a time, each question
//! is a chain of unpredictable branches and, for many, two square roots and
//! three divisions. Here the grid walk only gathers candidates into a small
//! structure-of-arrays batch; a branch-free loop over the batch keeps those
//! that reach the arc's box, pass the first cheap test of the exact crossing,
//! and are not clear of the arc up to its end; only those few go on to the
//! exact crossing, in the order they were visited and with the same
//! operations as before. The ones dropped are those the ranking would have
//! dropped, so the result is the one the one-at-a-time search gave, bit for
//! bit.

use crate::geometry::{Arc, Crossing, Trig};
use crate::math::{Real, Vector};

/// An arc up to its end (at most half a turn), the box that holds it, and
/// the contact tolerance: what a candidate is asked about.
pub(crate) struct Sweep<const D: usize> {
    pub arc: Arc<D>,
    pub lo: Vector<D>,
    pub hi: Vector<D>,
    pub end: Crossing,
    pub tol: Real,
}

/// Candidate centres (image shift added), inflated radii and identities, in
/// the order the grid visits them.
pub(crate) struct Candidates<const D: usize, const N: usize> {
    centre: [[Real; N]; D],
    big_r: [Real; N],
    key: [(u32, u16); N],
    pub len: usize,
}

/// The batch of the arc search (32 measured best against 16 and 64).
pub(crate) type Batch<const D: usize> = Candidates<D, 32>;

/// [`Candidates::sift`] compiled for one more instruction set: the same
/// operations in the same order (no fused multiply-add), so the same bits,
/// four or eight candidates to an instruction instead of two.
macro_rules! sift_compiled_for {
    ($name:ident, $feature:literal) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feature)]
        unsafe fn $name(&self, sweep: &Sweep<D>) -> u64 {
            self.sift_any(sweep)
        }
    };
}

impl<const D: usize, const N: usize> Candidates<D, N> {
    pub(crate) fn new() -> Self {
        Candidates {
            centre: [[0.0; N]; D],
            big_r: [0.0; N],
            key: [(0, 0); N],
            len: 0,
        }
    }

    /// Adds a candidate unless full; true when the candidates fill it.
    #[inline]
    pub(crate) fn push(&mut self, centre: &Vector<D>, big_r: Real, id: u32, image: u16) -> bool {
        let i = self.len;
        if i == N {
            return true;
        }
        for k in 0..D {
            self.centre[k][i] = centre[k];
        }
        self.big_r[i] = big_r;
        self.key[i] = (id, image);
        self.len = i + 1;
        self.len == N
    }

    /// Candidate `i`: its centre, inflated radius, id and image code.
    #[inline]
    pub(crate) fn get(&self, i: usize) -> (Vector<D>, Real, u32, u16) {
        let mut c = Vector::<D>::zero();
        for k in 0..D {
            c[k] = self.centre[k][i];
        }
        (c, self.big_r[i], self.key[i].0, self.key[i].1)
    }

    /// Bit `i` set for each candidate `i` that may be entered by `arc`
    /// before `end` within the box `[lo, hi]`: its ball reaches the box,
    /// [`Trig::downcrossing`] of its ball function at tolerance `2 R tol`
    /// would not stop at its first cheap rejection, and the function is not
    /// clear of zero up to `end` ([`Trig::clear_until`]). A candidate left
    /// out is one the scalar test rejects, or one entered so far beyond `end`
    /// that the ranking would drop it; one kept may still be rejected there.
    /// Every slot is computed (those past `len` hold old candidates or
    /// zeros, and are masked off): a loop of fixed length, which the
    /// compiler turns into vector instructions.
    #[inline]
    pub(crate) fn sift(&self, sweep: &Sweep<D>) -> u64 {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the processor has just said it has AVX-512F.
            return unsafe { self.sift_avx512(sweep) };
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has just said it has AVX2.
            return unsafe { self.sift_avx2(sweep) };
        }
        self.sift_any(sweep)
    }

    sift_compiled_for!(sift_avx512, "avx512f");
    sift_compiled_for!(sift_avx2, "avx2");

    #[inline(always)]
    fn sift_any(&self, sweep: &Sweep<D>) -> u64 {
        const { assert!(N <= 64) };
        let Sweep {
            arc,
            lo,
            hi,
            end,
            tol,
        } = sweep;
        let two_rho = 2.0 * arc.rho;
        let rho2 = arc.rho * arc.rho;
        let mut keep = [false; N];
        for (i, kept) in keep.iter_mut().enumerate() {
            let big_r = self.big_r[i];
            let mut in_box = true;
            let mut ua = 0.0;
            let mut vb = 0.0;
            let mut w2 = 0.0;
            for k in 0..D {
                let c = self.centre[k][i];
                in_box &= (c >= lo[k] - big_r) & (c <= hi[k] + big_r);
                let w = arc.m[k] - c;
                ua += arc.u[k] * w;
                vb += arc.v[k] * w;
                w2 += w * w;
            }
            let t = Trig {
                a: two_rho * ua,
                b: two_rho * vb,
                c: w2 + rho2 - big_r * big_r,
            };
            *kept = in_box & t.may_cross(2.0 * big_r * tol) & !t.clear_until(end);
        }
        let mut bits = 0u64;
        for (i, &kept) in keep.iter().enumerate().take(self.len) {
            bits |= u64::from(kept) << i;
        }
        bits
    }
}

impl<const D: usize, const N: usize> Candidates<D, N> {
    /// Calls `f(crossing, centre, inflated radius, id, image)`, in order, for
    /// each candidate whose ball `arc` enters within the box `[lo, hi]`
    /// (widened by the ball's radius), at tolerance `2 R tol`, leaving out
    /// balls entered only more than `1e-8` of a turn beyond `end`.
    #[inline]
    pub(crate) fn for_each_crossing(
        &self,
        sweep: &Sweep<D>,
        mut f: impl FnMut(Crossing, Vector<D>, Real, u32, u16),
    ) {
        let mut kept = self.sift(sweep);
        let Sweep { arc, tol, .. } = sweep;
        while kept != 0 {
            let i = kept.trailing_zeros() as usize;
            kept &= kept - 1;
            let (centre, big_r, id, image) = self.get(i);
            if let Some(x) = arc
                .ball_trig(&centre, big_r)
                .downcrossing(2.0 * big_r * tol)
            {
                f(x, centre, big_r, id, image);
            }
        }
    }
}

impl<const D: usize, const N: usize> Candidates<D, N> {
    /// True if `f` holds for one of the crossings
    /// [`Candidates::for_each_crossing`] would pass it; stops at the first.
    #[inline]
    pub(crate) fn any_crossing(
        &self,
        sweep: &Sweep<D>,
        mut f: impl FnMut(Crossing, Vector<D>, Real, u32, u16) -> bool,
    ) -> bool {
        let mut kept = self.sift(sweep);
        let Sweep { arc, tol, .. } = sweep;
        while kept != 0 {
            let i = kept.trailing_zeros() as usize;
            kept &= kept - 1;
            let (centre, big_r, id, image) = self.get(i);
            if let Some(x) = arc
                .ball_trig(&centre, big_r)
                .downcrossing(2.0 * big_r * tol)
            {
                if f(x, centre, big_r, id, image) {
                    return true;
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A circle of radius `rho` about `m`, starting along `u`, heading along
    /// `v` (made orthonormal here).
    fn arc(m: [Real; 3], rho: Real, u: [Real; 3], v: [Real; 3]) -> Option<Arc<3>> {
        let u = Vector(u).normalized()?;
        let v = Vector(v) - u * Vector(v).dot(&u);
        let v = v.normalized()?;
        Some(Arc {
            m: Vector(m),
            rho,
            u,
            v,
        })
    }

    proptest! {
        /// The sifted search meets the same balls at the same crossings, in
        /// the same order, as asking every candidate one at a time, except
        /// balls entered well beyond the arc's end (which the ranking drops).
        #[test]
        fn sifted_crossings_are_the_one_at_a_time_crossings(
            m in prop::array::uniform3(-5.0f64..5.0),
            rho in 0.5f64..4.0,
            u in prop::array::uniform3(-1.0f64..1.0),
            v in prop::array::uniform3(-1.0f64..1.0),
            end in 0.0f64..std::f64::consts::PI,
            balls in prop::collection::vec((prop::array::uniform3(-9.0f64..9.0), 0.5f64..4.0), 0..80),
            tol in prop::sample::select(vec![0.0, 1e-12, 1e-6]),
        ) {
            let Some(arc) = arc(m, rho, u, v) else { return Ok(()); };
            let end = Crossing { cos: end.cos(), sin: end.sin() };
            let (lo, hi) = arc.bounds_to(&end);
            let end_rank = end.diamond();
            let sweep = Sweep { arc, lo, hi, end, tol };
            let mut expected = Vec::new();
            for (i, (c, big_r)) in balls.iter().enumerate() {
                let c = Vector(*c);
                let outside = (0..3).any(|k| c[k] < lo[k] - big_r || c[k] > hi[k] + big_r);
                if outside {
                    continue;
                }
                if let Some(x) = arc.ball_trig(&c, *big_r).downcrossing(2.0 * big_r * tol) {
                    expected.push((i as u32, x.cos.to_bits(), x.sin.to_bits(), x.diamond()));
                }
            }
            let mut got = Vec::new();
            let mut batch = Batch::<3>::new();
            let mut met = |x: Crossing, _: Vector<3>, _: Real, id: u32, _: u16| {
                got.push((id, x.cos.to_bits(), x.sin.to_bits(), x.diamond()));
            };
            for (i, (c, big_r)) in balls.iter().enumerate() {
                if batch.push(&Vector(*c), *big_r, i as u32, 0) {
                    batch.for_each_crossing(&sweep, &mut met);
                    batch.len = 0;
                }
            }
            batch.for_each_crossing(&sweep, &mut met);
            // Those left out are entered well beyond the end; the rest come
            // in order, bit for bit.
            let kept: Vec<_> = expected
                .iter()
                .filter(|e| got.contains(e))
                .copied()
                .collect();
            prop_assert_eq!(&got, &kept);
            // Whatever instructions the processor offers, the sift keeps the
            // same candidates as the portable loop.
            batch.len = 0;
            for (i, (c, big_r)) in balls.iter().enumerate().take(32) {
                batch.push(&Vector(*c), *big_r, i as u32, 0);
            }
            prop_assert_eq!(
                batch.sift(&sweep),
                batch.sift_any(&sweep)
            );
            for e in expected.iter().filter(|e| !got.contains(e)) {
                prop_assert!(e.3 > end_rank + 1e-9, "{e:?} dropped, end {end_rank}");
            }
        }
    }
}
