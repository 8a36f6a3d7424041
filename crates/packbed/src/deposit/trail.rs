//! The way a settling sphere's centre went, leg by leg: what its settling
//! depended on, for [`super::speculate`].
//!
//! Every grid query of a settling asks about the particles its centre could
//! touch along one leg: the fall (a vertical segment), a roll (an arc of a
//! circle, from its start to where it stopped), or the contacts at one point
//! (the snap to the exact resting point, the check of a balanced sphere). A
//! particle whose inflated ball stays clear of every leg, by a margin far
//! above the engine's tolerances, changes none of the answers: along a leg
//! the distance to its centre changes no faster than the arc length, so the
//! leg would meet it, if at all, well after it stopped, beyond every tie
//! window of the ranking.

use crate::container::Container;
use crate::geometry::{Arc, Crossing};
use crate::math::{Real, Vector};

/// What is added to the reach at which a particle counts as near a leg: far
/// above the engine's tolerances (`1e-12` of a radius for gaps and of the
/// angle for ties) and the rounding of `c`'s coordinates.
pub(crate) fn margin<const D: usize>(reach: Real, c: &Vector<D>) -> Real {
    1e-6 * reach + 1e-12 * c.norm()
}

/// One leg of a settling.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Leg<const D: usize> {
    /// The fall from `from` straight down to height `to`.
    Fall { from: Vector<D>, to: Real },
    /// The roll along `arc` from its start to `stop`.
    Roll { arc: Arc<D>, stop: Crossing },
    /// The contacts at one point.
    Point(Vector<D>),
}

impl<const D: usize> Leg<D> {
    /// An axis-aligned box holding the leg.
    fn bounds(&self) -> (Vector<D>, Vector<D>) {
        match self {
            Leg::Fall { from, to } => {
                let mut lo = *from;
                lo[D - 1] = *to;
                (lo, *from)
            }
            Leg::Roll { arc, stop } => arc.bounds_to(stop),
            Leg::Point(p) => (*p, *p),
        }
    }

    /// True if the leg comes within `reach` of `c` (this image only). Exact up
    /// to rounding: callers add a margin.
    fn comes_within(&self, c: &Vector<D>, reach: Real) -> bool {
        let r2 = reach * reach;
        match self {
            Leg::Fall { from, to } => {
                let mut w = *c - *from;
                let h = c[D - 1];
                w[D - 1] = if h > from[D - 1] {
                    h - from[D - 1]
                } else if h < *to {
                    *to - h
                } else {
                    0.0
                };
                w.norm2() <= r2
            }
            Leg::Roll { arc, stop } => {
                // |p(t) − c|² − reach² = a cos t + b sin t + k over [0, stop].
                let f = arc.ball_trig(c, reach);
                let at_stop = f.a * stop.cos + f.b * stop.sin + f.c;
                if f.a + f.c <= 0.0 || at_stop <= 0.0 {
                    return true;
                }
                let amplitude = f.a.hypot(f.b);
                if amplitude == 0.0 || f.c - amplitude > 0.0 {
                    return false;
                }
                // The circle's nearest point to `c`, if the leg reaches it.
                let nearest = Crossing {
                    cos: -f.a / amplitude,
                    sin: -f.b / amplitude,
                };
                nearest.diamond() <= stop.diamond()
            }
            Leg::Point(p) => (*c - *p).norm2() <= r2,
        }
    }

    /// True if the leg comes within `reach` of any periodic image of `c`.
    pub(crate) fn near(&self, container: &Container<D>, c: &Vector<D>, reach: Real) -> bool {
        let (lo, hi) = self.bounds();
        let mut ranges = [(0i64, 0i64); 2];
        for k in 0..D - 1 {
            if container.periodic {
                let period = container.extent(k);
                let first = ((lo[k] - reach - c[k]) / period).ceil();
                let last = ((hi[k] + reach - c[k]) / period).floor();
                // A leg many periods long meets an image anyway (and a
                // coordinate that is no number counts as near).
                if last - first > 8.0 || (last - first).is_nan() {
                    return true;
                }
                if first > last {
                    return false;
                }
                ranges[k] = (first as i64, last as i64);
            }
        }
        let (b0, b1) = if D == 3 { ranges[1] } else { (0, 0) };
        for j in b0..b1 + 1 {
            for i in ranges[0].0..ranges[0].1 + 1 {
                let mut image = *c;
                if container.periodic {
                    image[0] += i as Real * container.extent(0);
                    if D == 3 {
                        image[1] += j as Real * container.extent(1);
                    }
                }
                if self.comes_within(&image, reach) {
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

    /// Nearest approach of the leg to `c`, by sampling it finely.
    fn sampled<const D: usize>(leg: &Leg<D>, c: &Vector<D>) -> Real {
        let n = 20_000;
        (0..=n)
            .map(|s| {
                let f = s as Real / n as Real;
                let p = match leg {
                    Leg::Fall { from, to } => {
                        let mut p = *from;
                        p[D - 1] = from[D - 1] + f * (to - from[D - 1]);
                        p
                    }
                    Leg::Roll { arc, stop } => {
                        let t = f * stop.sin.atan2(stop.cos).rem_euclid(std::f64::consts::TAU);
                        arc.point_at(&Crossing {
                            cos: t.cos(),
                            sin: t.sin(),
                        })
                    }
                    Leg::Point(p) => *p,
                };
                (p - *c).norm()
            })
            .fold(Real::INFINITY, Real::min)
    }

    fn unit(v: [Real; 3]) -> Option<Vector<3>> {
        Vector(v).normalized()
    }

    proptest! {
        #[test]
        fn a_roll_is_near_exactly_where_its_samples_are(
            m in prop::array::uniform3(-5.0f64..5.0),
            rho in 0.5f64..3.0,
            u in prop::array::uniform3(-1.0f64..1.0),
            w in prop::array::uniform3(-1.0f64..1.0),
            turn in 0.01f64..std::f64::consts::PI,
            c in prop::array::uniform3(-8.0f64..8.0),
            reach in 0.1f64..4.0,
        ) {
            let (Some(u), Some(w)) = (unit(u), unit(w)) else { return Ok(()) };
            let Some(v) = (w - u * w.dot(&u)).normalized() else { return Ok(()) };
            let arc = Arc { m: Vector(m), rho, u, v };
            let leg = Leg::Roll { arc, stop: Crossing { cos: turn.cos(), sin: turn.sin() } };
            let c = Vector(c);
            let d = sampled(&leg, &c);
            // The sampling misses the nearest approach by at most rho * step.
            let slack = rho * 3.2 / 20_000.0 + 1e-9;
            if d < reach - slack {
                prop_assert!(leg.comes_within(&c, reach), "{d} {reach}");
            }
            if d > reach + 1e-9 {
                prop_assert!(!leg.comes_within(&c, reach), "{d} {reach}");
            }
        }

        #[test]
        fn a_fall_is_near_exactly_where_its_samples_are(
            from in prop::array::uniform3(-5.0f64..5.0),
            drop in 0.0f64..6.0,
            c in prop::array::uniform3(-8.0f64..8.0),
            reach in 0.1f64..4.0,
        ) {
            let leg = Leg::Fall { from: Vector(from), to: from[2] - drop };
            let c = Vector(c);
            let d = sampled(&leg, &c);
            if d < reach - drop / 20_000.0 - 1e-9 {
                prop_assert!(leg.comes_within(&c, reach));
            }
            if d > reach + 1e-9 {
                prop_assert!(!leg.comes_within(&c, reach));
            }
        }
    }

    #[test]
    fn a_leg_meets_the_images_of_a_periodic_box() {
        let plan = crate::config::Config::from_toml(
            "dim = 3\n[box]\nwidth = 100\ndepth = 50\nheight = 100\nperiodic = true\n\
             [[species]]\nradius = 1\n",
            "test",
        )
        .unwrap()
        .plan::<3>()
        .unwrap();
        let c = &plan.container;
        let leg = Leg::Fall {
            from: Vector([0.5, 49.5, 30.0]),
            to: 10.0,
        };
        // Across both periodic axes at once.
        assert!(leg.near(c, &Vector([99.0, 0.5, 20.0]), 2.0));
        assert!(!leg.near(c, &Vector([99.0, 0.5, 20.0]), 1.0));
        // Below the leg's end.
        assert!(!leg.near(c, &Vector([0.5, 49.5, 7.0]), 2.0));
        assert!(leg.near(c, &Vector([0.5, 49.5, 8.5]), 2.0));
        let point = Leg::Point(Vector([50.0, 25.0, 5.0]));
        assert!(point.near(c, &Vector([51.0, 25.0, 5.0]), 1.5));
        assert!(!point.near(c, &Vector([52.0, 25.0, 5.0]), 1.5));
    }
}
