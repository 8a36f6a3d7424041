//! The share of a size distribution finer than a size, by number and by volume
//! (mass at equal density): the requested curve that a run's placed sizes are
//! compared with (sieve analyses and laser diffraction report mass passing).

use super::SizeDist;
use crate::math::{normal, Real};

/// Panels of the quadrature over a truncated normal's window (even, Simpson).
const PANELS: usize = 2048;

/// The smallest radius in `[lo, hi]` (radii, `lo > 0`) at which the
/// non-decreasing `passing` reaches `q`: bisection in the logarithm, as
/// sizes spread over decades.
pub fn passing_quantile(
    mut lo: Real,
    mut hi: Real,
    q: Real,
    passing: impl Fn(Real) -> Real,
) -> Real {
    if lo >= hi || passing(lo) >= q {
        return lo;
    }
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if mid <= lo || mid >= hi {
            break;
        }
        if passing(mid) < q {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

impl SizeDist {
    /// The share of particles (by number) of radius `<= x`.
    pub fn number_passing(&self, x: Real) -> Real {
        self.passing(x, 0)
    }

    /// The share of the solid volume (mass) in particles of radius `<= x`.
    pub fn volume_passing(&self, x: Real) -> Real {
        self.passing(x, 3)
    }

    /// The mean of `r³` by number.
    pub fn mean_cube(&self) -> Real {
        match self {
            SizeDist::Uniform { min, max } if max > min => {
                (max.powi(4) - min.powi(4)) / (4.0 * (max - min))
            }
            SizeDist::Table(t) => t.mean_cube(),
            _ => match self.lognormal_moment(3) {
                Some(m) => m,
                None => match self.normal_integral(Real::INFINITY) {
                    Some((n, v)) => v / n,
                    None => self.median().powi(3),
                },
            },
        }
    }

    /// The radius below which the share `q` (in `[0, 1]`) of the solid volume
    /// lies (the `d50` of a mass curve, as a radius).
    pub fn volume_quantile(&self, q: Real) -> Real {
        let (lo, hi) = self.bounds();
        passing_quantile(lo, hi, q, |x| self.volume_passing(x))
    }

    /// The share by `r^power` (0: number, 3: volume) of radii `<= x`.
    fn passing(&self, x: Real, power: i32) -> Real {
        let (lo, hi) = self.bounds();
        if x < lo {
            return 0.0;
        }
        if x >= hi {
            return 1.0;
        }
        match self {
            SizeDist::Fixed(_) => 1.0,
            SizeDist::Uniform { min, max } => {
                let p = power + 1;
                (x.powi(p) - min.powi(p)) / (max.powi(p) - min.powi(p))
            }
            SizeDist::Table(t) if power == 0 => t.number_passing(x),
            SizeDist::Table(t) => t.volume_passing(x),
            SizeDist::Lognormal {
                median,
                gsd,
                lo,
                hi,
                ..
            } => {
                let s = gsd.ln();
                // r³ times the lognormal density is the lognormal density
                // shifted by 3σ in ln r.
                let shift = Real::from(power) * s;
                let z = |r: Real| (r / median).ln() / s - shift;
                let whole = normal::mass(z(*lo), z(*hi));
                if s > 0.0 && whole > 0.0 {
                    (normal::mass(z(*lo), z(x)) / whole).clamp(0.0, 1.0)
                } else {
                    Real::from(u8::from(x >= self.median()))
                }
            }
            SizeDist::Normal { .. } => {
                match (
                    self.normal_integral(x),
                    self.normal_integral(Real::INFINITY),
                ) {
                    (Some((n, v)), Some((n_all, v_all))) => {
                        let share = if power == 0 { n / n_all } else { v / v_all };
                        share.clamp(0.0, 1.0)
                    }
                    _ => Real::from(u8::from(x >= self.median())),
                }
            }
        }
    }

    /// `E[r³]` of a truncated lognormal (`None` for other kinds, or where the
    /// window holds no representable probability).
    fn lognormal_moment(&self, power: i32) -> Option<Real> {
        let SizeDist::Lognormal {
            median,
            gsd,
            lo,
            hi,
        } = *self
        else {
            return None;
        };
        let s = gsd.ln();
        if s <= 0.0 {
            return None;
        }
        let k = Real::from(power);
        let z = |r: Real, shift: Real| (r / median).ln() / s - shift;
        let whole = normal::mass(z(lo, 0.0), z(hi, 0.0));
        let shifted = normal::mass(z(lo, k * s), z(hi, k * s));
        let m = median.powi(power) * (0.5 * k * k * s * s).exp() * shifted / whole;
        (whole > 0.0 && m.is_finite()).then_some(m)
    }

    /// `(∫ f, ∫ r³ f)` over the window of a truncated normal up to `x`, `f`
    /// its unnormalised density (`None` for other kinds, a spread of 0, or a
    /// density that underflows in the window).
    fn normal_integral(&self, x: Real) -> Option<(Real, Real)> {
        let SizeDist::Normal { mean, sd, lo, hi } = *self else {
            return None;
        };
        if sd <= 0.0 || hi <= lo {
            return None;
        }
        // Relative to the density at the window's most likely radius, so that a
        // window far in a tail does not underflow.
        let peak = mean.clamp(lo, hi);
        let f = |r: Real| (-0.5 * (((r - mean) / sd).powi(2) - ((peak - mean) / sd).powi(2))).exp();
        let h = (hi - lo) / PANELS as Real;
        let (mut n, mut v) = (0.0, 0.0);
        for i in 0..=PANELS {
            let r = lo + h * i as Real;
            let w = if i == 0 || i == PANELS {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            // The panel holding `x` is cut at `x` by a linear share: the curve
            // is a comparison, and 2048 panels make the error invisible.
            let share = ((x - r) / h + 0.5).clamp(0.0, 1.0);
            let d = w * f(r) * share;
            n += d;
            v += d * r * r * r;
        }
        (n > 0.0 && v.is_finite()).then_some((n, v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// The share of `d`'s draws, by number and by volume, at or below `x`.
    fn sampled(d: &SizeDist, x: Real) -> (Real, Real) {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        let draws: Vec<Real> = (0..200_000).map(|_| d.sample(&mut rng)).collect();
        let n = draws.iter().filter(|&&r| r <= x).count() as Real / draws.len() as Real;
        let all: Real = draws.iter().map(|r| r * r * r).sum();
        let v: Real = draws.iter().filter(|&&r| r <= x).map(|r| r * r * r).sum();
        (n, v / all)
    }

    #[test]
    fn curves_match_the_draws() {
        let (lo, hi) = SizeDist::lognormal_window(10.0, 1.6);
        let dists = [
            SizeDist::Lognormal {
                median: 10.0,
                gsd: 1.6,
                lo,
                hi,
            },
            SizeDist::Normal {
                mean: 10.0,
                sd: 2.0,
                lo: 4.0,
                hi: 16.0,
            },
            SizeDist::Uniform {
                min: 5.0,
                max: 15.0,
            },
        ];
        for d in &dists {
            for x in [6.0, 9.0, 10.0, 12.0, 15.0] {
                let (n, v) = sampled(d, x);
                // 200,000 draws: a binomial sd of at most 0.0011.
                assert!((d.number_passing(x) - n).abs() < 0.005, "{d:?} at {x}: {n}");
                assert!((d.volume_passing(x) - v).abs() < 0.006, "{d:?} at {x}: {v}");
            }
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(9);
            let m: Real = (0..200_000)
                .map(|_| d.sample(&mut rng).powi(3))
                .sum::<Real>()
                / 200_000.0;
            assert!((d.mean_cube() / m - 1.0).abs() < 0.02, "{d:?}: {m}");
            let q = d.volume_quantile(0.5);
            assert!((d.volume_passing(q) - 0.5).abs() < 1e-9, "{d:?}");
        }
    }

    #[test]
    fn an_untruncated_lognormal_has_the_hatch_choate_mass_median() {
        // Hatch–Choate: the mass median is median · exp(3 σ²).
        let d = SizeDist::Lognormal {
            median: 10.0,
            gsd: 1.5,
            lo: 1e-6,
            hi: 1e6,
        };
        let s = 1.5f64.ln();
        let expected = 10.0 * (3.0 * s * s).exp();
        assert!((d.volume_quantile(0.5) / expected - 1.0).abs() < 1e-9);
        let m3 = 1000.0 * (4.5 * s * s).exp();
        assert!((d.mean_cube() / m3 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_fixed_size_is_a_step() {
        let d = SizeDist::Fixed(3.0);
        assert_eq!(d.volume_passing(2.999), 0.0);
        assert_eq!(d.volume_passing(3.0), 1.0);
        assert_eq!(d.mean_cube(), 27.0);
    }
}
