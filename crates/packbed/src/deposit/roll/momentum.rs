//! The momentum rule (`[settling] restitution`): a settling sphere carries
//! kinetic energy along its quasi-static path and spends it at impacts and on
//! the rims of the pockets it could otherwise not leave.
//!
//! Energies are heights: `E = v² / 2g`, the kinetic energy over the weight,
//! so mass and gravity drop out. The sphere lands with the energy of a free
//! fall from `drop_height`; along its path it gains what it descends (the
//! path is frictionless and it slides: no rotational energy); at each impact
//! (a new contact) it keeps the tangential part of its energy and `e²` of the
//! normal part, `E' = E (1 − (1 − e²) cos² θ)`, with θ between its direction
//! of travel and the contact normal; sliding on its supports it loses µ times
//! its horizontal travel (Coulomb friction on a plane: `µ N ds = µ m g dx`). Where the quasi-static rule would hold it
//! (`D` supports), it leaves over the lowest rim of the pocket that its energy
//! clears: it rolls on all supports but one, up the circle that keeps them,
//! to the circle's highest point, and on down the other side with the energy
//! it has left. A rim whose way up meets another particle or a wall is no way
//! out. What the energy does not clear, the pocket absorbs: it stays.
//!
//! The path stays the quasi-static one (a fast particle would fly off a
//! convex support; here it follows it), so the rule changes only where
//! particles come to rest, not how they get there, and the geometry stays
//! exact: every rest is still a contact of `D` supports, or the floor.

use super::{blocked_on_arc, circle, first_contact_on_arc, ContactSet, Terrain};
use crate::config::Momentum;
use crate::deposit::arc_search::Batch;
use crate::deposit::obstacle::is_floor;
use crate::deposit::trail::Leg;
use crate::geometry::{Arc, Crossing};
use crate::math::{Real, Vector};

/// The kinetic energy of one settling sphere, as a height.
pub(crate) struct Motion {
    /// `1 − e²`: the share of the normal energy an impact takes.
    lost: Real,
    /// The free fall before the first impact.
    drop: Real,
    /// Sliding friction: the energy lost per unit of horizontal travel.
    mu: Real,
    /// Whether a climb that meets a particle rolls on over it.
    climb_over: bool,
    /// Zero until the first impact.
    energy: Real,
    landed: bool,
}

impl Motion {
    /// The motion of a sphere of radius `r`.
    pub(crate) fn new(m: &Momentum, r: Real) -> Self {
        Motion {
            lost: 1.0 - m.restitution * m.restitution,
            drop: m.drop_height.unwrap_or(2.0 * r),
            mu: m.sliding_friction,
            climb_over: m.climb_over,
            energy: 0.0,
            landed: false,
        }
    }

    /// The energy left.
    pub(crate) fn energy(&self) -> Real {
        self.energy
    }

    /// The sliding friction coefficient.
    pub(crate) fn mu(&self) -> Real {
        self.mu
    }

    /// Whether a climb that meets a particle rolls on over it.
    pub(crate) fn climb_over(&self) -> bool {
        self.climb_over
    }

    /// Sets the energy left (a chain's climb out of a pocket is accounted
    /// step by step where it climbs, and handed back at its end).
    pub(crate) fn set_energy(&mut self, energy: Real) {
        self.energy = energy.max(0.0);
    }

    /// A free fall of `dz`: the first lands with the energy of `drop_height`
    /// (the particle fell from the feed, not from just above the bed, where
    /// the engine starts it); later ones add their height.
    pub(crate) fn fell(&mut self, dz: Real) {
        if self.landed {
            self.descended(dz);
        } else {
            self.energy = self.drop;
            self.landed = true;
        }
    }

    /// A move that lost `dz` of height (negative: climbed).
    pub(crate) fn descended(&mut self, dz: Real) {
        self.energy = (self.energy + dz).max(0.0);
    }

    /// A move on supports from `a` to `b`: it gains its descent and loses
    /// to friction µ times its horizontal travel (the chord's: exact on a
    /// plane, and on a circle short against its radius).
    pub(crate) fn slid<const D: usize>(&mut self, a: &Vector<D>, b: &Vector<D>) {
        self.energy = left_after(self.energy, self.mu, a, b).max(0.0);
    }

    /// An impact where `cos2` is the largest `cos² θ` between the direction
    /// of travel and a new contact's normal.
    pub(crate) fn impact(&mut self, cos2: Real) {
        self.energy *= self.kept_at_impact(cos2);
    }

    /// The share of the energy an impact of [`Motion::impact`] keeps.
    pub(crate) fn kept_at_impact(&self, cos2: Real) -> Real {
        1.0 - self.lost * cos2.clamp(0.0, 1.0)
    }
}

/// The energy left at `b` of a sphere that had `energy` at `a` and slid
/// there under friction `mu`: its descent gained, µ times its horizontal
/// travel lost (negative where it ran out on the way). The one account of
/// [`Motion::slid`], the stop along an arc and the climbs over blockers.
fn left_after<const D: usize>(energy: Real, mu: Real, a: &Vector<D>, b: &Vector<D>) -> Real {
    energy + a.height() - b.height() - mu * (*b - *a).horizontal().norm()
}

/// The largest `cos²` between the unit direction `t` and the normals of the
/// contacts `hits` at `p`.
pub(super) fn head_on<const D: usize>(hits: &ContactSet<D>, p: &Vector<D>, t: &Vector<D>) -> Real {
    (0..hits.len)
        .map(|i| {
            let c = hits.get(i).surface.normal_at(p).dot(t);
            c * c
        })
        .fold(0.0, Real::max)
}

/// Where a sphere moving along `arc` from `p` with `energy`, losing `mu`
/// per unit of horizontal travel, has first spent its energy at a point less
/// steep than the friction angle's sine `s`, before `end`: static friction
/// holds it there (with `mu = tan α`, a block on a plane less steep than α
/// slows down and stays, on a steeper one it speeds up). The energy is the
/// one [`Motion::slid`] books, sampled at [`SPENT_SAMPLES`] points of the arc
/// and the first sign change bisected to 1e-13 of a radian: an energy that dips below
/// zero and rises again between two samples is missed, which on the short
/// arcs between contacts changes where a particle stops by less than a
/// sample's length, never whether it overlaps.
pub(super) fn spent_on_arc<const D: usize>(
    arc: &Arc<D>,
    p: &Vector<D>,
    energy: Real,
    mu: Real,
    s: Real,
    end: &Crossing,
) -> Option<Crossing> {
    let left = |x: &Crossing| left_after(energy, mu, p, &arc.point_at(x));
    let mut t_end = end.sin.atan2(end.cos);
    if t_end < 0.0 {
        t_end += std::f64::consts::TAU;
    }
    // Most moves keep their energy: the climb is at most to the circle's
    // top and the horizontal travel at most the arc's length.
    let (uz, vz) = (arc.u.height(), arc.v.height());
    let climb = arc.rho * ((uz * uz + vz * vz).sqrt() - uz);
    if energy > climb + mu * arc.rho * t_end.min(2.0) {
        return None;
    }
    if keeps_energy(arc, p, energy, mu, end, t_end) {
        return None;
    }
    // Samples by rotation and bisection by half-angles: one `sin_cos` an arc.
    let (sin, cos) = (t_end / SPENT_SAMPLES as Real).sin_cos();
    let mut lo = Crossing { cos: 1.0, sin: 0.0 };
    for _ in 0..SPENT_SAMPLES {
        let x = unit(lo.cos * cos - lo.sin * sin, lo.sin * cos + lo.cos * sin);
        if left(&x) > 0.0 {
            lo = x;
            continue;
        }
        let mut hi = x;
        // Until the bracket is 1e-13 of a radian (at most ~40 halvings).
        while (hi.cos - lo.cos).powi(2) + (hi.sin - lo.sin).powi(2) > 1e-26 {
            let mid = unit(lo.cos + hi.cos, lo.sin + hi.sin);
            if left(&mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        // Static friction holds it only where the way on is less steep than
        // the angle; elsewhere it slides on from rest.
        return (-arc.tangent_at(&hi).height() < s).then_some(hi);
    }
    None
}

/// True where a sphere moving along `arc` from `p` with `energy` has energy
/// left everywhere before `end` (at angle `t_end`), by a margin, by a bound
/// from below. The horizontal travel is at most the arc's length `ρt`, so
/// what is left is at least `E + g(t)`, `g(t) = Δh(t) − µρt`, and
/// `g′ = ρ (s − µ)` with `s(t) = A sin θ` the descent rate, θ the angle past
/// the circle's top. Where θ stays within [−π/2, 3π/2] (a rolling arc ends
/// at or before the lowest point), `s` rises and then falls, so `g` falls
/// while `s < µ`, rises, and falls again: its least value is at the start,
/// at the end, or at the first point as steep as µ. The rolling arcs go
/// down, where the circle's climb bound is of no help. The margin keeps
/// this to cases the samples would also find with energy left everywhere,
/// so the answer is the samples' own.
fn keeps_energy<const D: usize>(
    arc: &Arc<D>,
    p: &Vector<D>,
    energy: Real,
    mu: Real,
    end: &Crossing,
    t_end: Real,
) -> bool {
    use std::f64::consts::FRAC_PI_2;
    let (uz, vz) = (arc.u.height(), arc.v.height());
    let theta0 = (-vz).atan2(uz);
    if theta0 < -FRAC_PI_2 || theta0 + t_end > 3.0 * FRAC_PI_2 {
        return false;
    }
    let g = |x: &Crossing, t: Real| p.height() - arc.point_at(x).height() - mu * arc.rho * t;
    let mut least = g(end, t_end).min(0.0);
    let a = uz.hypot(vz);
    if mu < a {
        // s = µ where θ = asin(µ / A), on the rising side.
        let t1 = (mu / a).asin() - theta0;
        if t1 > 0.0 && t1 < t_end {
            let (sin, cos) = t1.sin_cos();
            least = least.min(g(&Crossing { cos, sin }, t1));
        }
    }
    energy + least > 1e-9 * (energy + arc.rho + p.height().abs())
}

/// The point of the unit circle in the direction `(c, s)` (not zero).
fn unit(c: Real, s: Real) -> Crossing {
    let n = (c * c + s * s).sqrt();
    Crossing {
        cos: c / n,
        sin: s / n,
    }
}

/// Points of an arc [`spent_on_arc`] samples before it bisects.
const SPENT_SAMPLES: usize = 16;

/// A way out of a pocket.
pub(super) struct Exit<const D: usize> {
    /// The rim: the highest point of the circle the sphere climbs.
    pub top: Vector<D>,
    /// The supports it keeps on the way.
    pub kept: ContactSet<D>,
    /// The direction of travel at the rim (horizontal).
    pub onward: Vector<D>,
    /// The rim's height above the pocket.
    pub barrier: Real,
}

/// A rim within reach: the support let go, the circle climbed, its top.
#[derive(Clone, Copy)]
struct Rim<const D: usize> {
    barrier: Real,
    gone: usize,
    arc: Arc<D>,
    top: Crossing,
}

impl<const D: usize> Rim<D> {
    fn none() -> Self {
        Rim {
            barrier: Real::INFINITY,
            gone: 0,
            arc: Arc {
                m: Vector::zero(),
                rho: 0.0,
                u: Vector::zero(),
                v: Vector::zero(),
            },
            top: Crossing { cos: 1.0, sin: 0.0 },
        }
    }
}

/// The supports of `held` but its `gone`-th, in the order the pocket's
/// circle is built from (its bits depend on it).
fn kept<const D: usize>(held: &ContactSet<D>, gone: usize) -> ContactSet<D> {
    let mut kept = *held;
    kept.remove_key(held.get(gone).key);
    kept
}

/// The lowest open rim of the pocket `held` (the supports at `p`) below the
/// energy of `motion`, if any; with `climb_over`, else the first blocked
/// climb, lowest first, that goes on over its blockers to a rim (see
/// [`over_the_blockers`]). A sphere on the floor has no way out.
pub(super) fn way_out<const D: usize>(
    terrain: &Terrain<'_, D>,
    held: &ContactSet<D>,
    p: &Vector<D>,
    r: Real,
    tol: Real,
    motion: &Motion,
    batch: &mut Batch<D>,
) -> Option<Exit<D>> {
    let (energy, mu) = (motion.energy, motion.mu);
    if energy <= 0.0 || (0..held.len).any(|i| is_floor(held.get(i).key)) {
        return None;
    }
    // Each rim: let one support go and climb on the others, away from it.
    let mut rims = [Rim::<D>::none(); super::MAX_ACTIVE];
    let mut n = 0;
    for gone in 0..held.len {
        let away = held.get(gone).surface.normal_at(p);
        let Some(arc) = circle(&kept(held, gone), p, &away) else {
            continue;
        };
        let (uz, vz) = (arc.u.height(), arc.v.height());
        if vz <= 0.0 {
            // Not a climb (a support that carried no load).
            continue;
        }
        // Most rims are out of reach: a bound from below on the climb, with
        // no `hypot` (a few ulps under it, scaled down by far more) and no
        // friction (never negative), rules them out. Rounding is monotonic,
        // so the bound never exceeds the barrier below, bit for bit.
        let h_below = (uz * uz + vz * vz).sqrt() * (1.0 - 1e-12);
        if arc.m.height() + arc.rho * h_below - p.height() >= energy {
            continue;
        }
        let Some(top) = highest(&arc) else {
            continue;
        };
        // The climb to the rim, and the friction on the way (its chord).
        let barrier = arc.m.height() + arc.rho * uz.hypot(vz) - p.height()
            + mu * (arc.point_at(&top) - *p).horizontal().norm();
        if barrier < energy {
            rims[n] = Rim {
                barrier,
                gone,
                arc,
                top,
            };
            n += 1;
        }
    }
    rims[..n].sort_by(|a, b| a.barrier.total_cmp(&b.barrier).then(a.gone.cmp(&b.gone)));
    for &Rim {
        barrier,
        gone,
        arc,
        top,
    } in &rims[..n]
    {
        let kept = kept(held, gone);
        let blocked = blocked_on_arc(terrain, &arc, &kept, r, &top, top.diamond(), tol, batch);
        // What the search asked depends on the arc up to the rim: noted
        // whether the way is open or not (a speculative settling is judged by
        // every arc it looked along).
        terrain.went(Leg::Roll { arc, stop: top });
        if blocked {
            continue;
        }
        return Some(Exit {
            top: arc.point_at(&top),
            kept,
            onward: arc.tangent_at(&top),
            barrier,
        });
    }
    if motion.climb_over {
        for &Rim { gone, arc, top, .. } in &rims[..n] {
            let climb = Climb {
                kept: kept(held, gone),
                arc,
                top,
            };
            if let Some(exit) = over_the_blockers(terrain, climb, p, r, tol, motion, batch) {
                return Some(exit);
            }
        }
    }
    None
}

/// The highest point of `arc`'s circle, as a crossing (none for a level one).
fn highest<const D: usize>(arc: &Arc<D>) -> Option<Crossing> {
    let (uz, vz) = (arc.u.height(), arc.v.height());
    let h = uz.hypot(vz);
    (h != 0.0).then(|| Crossing {
        cos: uz / h,
        sin: vz / h,
    })
}

/// One arc of a climb: the supports kept, the circle, its highest point.
struct Climb<const D: usize> {
    kept: ContactSet<D>,
    arc: Arc<D>,
    top: Crossing,
}

/// Blocked climbs a particle may roll on over, one after another, before
/// its way out counts as closed.
const MOST_BLOCKERS: usize = 6;

/// A climb from `p` that meets a particle, carried on over it: at the
/// blocker the sphere keeps its energy less the climb, the friction and the
/// impact, and rolls on along the groove of the blocker and the supports the
/// way on keeps (of the circles that leave one support, the one whose
/// direction is nearest its own), up to that circle's highest point, and
/// so on over at most [`MOST_BLOCKERS`] blockers. It is out where a circle
/// reaches its top unblocked, or where the way on already goes down (over
/// the crest at the blocker). Where the energy runs out first, or two
/// particles are met at once, the way is closed.
fn over_the_blockers<const D: usize>(
    terrain: &Terrain<'_, D>,
    mut climb: Climb<D>,
    p: &Vector<D>,
    r: Real,
    tol: Real,
    motion: &Motion,
    batch: &mut Batch<D>,
) -> Option<Exit<D>> {
    let mut at = *p;
    let mut energy = motion.energy;
    let mut hits = ContactSet::<D>::new();
    for _ in 0..MOST_BLOCKERS {
        let Climb {
            kept: supports,
            arc,
            top,
        } = climb;
        let (hit, rank) = first_contact_on_arc(
            terrain,
            &arc,
            &supports,
            r,
            &top,
            top.diamond(),
            tol,
            &mut hits,
            batch,
        );
        let stop = if rank.is_finite() { hit } else { top };
        terrain.went(Leg::Roll { arc, stop });
        let q = arc.point_at(&stop);
        energy = left_after(energy, motion.mu, &at, &q);
        if energy <= 0.0 {
            return None;
        }
        if !rank.is_finite() {
            return Some(Exit {
                top: q,
                kept: supports,
                onward: arc.tangent_at(&top),
                barrier: motion.energy - energy,
            });
        }
        if hits.len != 1 {
            return None;
        }
        let heading = arc.tangent_at(&hit);
        energy *= motion.kept_at_impact(head_on(&hits, &q, &heading));
        // On with the blocker and all supports but one: the one the way on
        // leaves, along the circle nearest the heading.
        let mut next: Option<(Real, ContactSet<D>, Arc<D>)> = None;
        for j in 0..supports.len {
            let mut on = kept(&supports, j);
            on.push(hits.get(0));
            let Some(a) = circle(&on, &q, &heading) else {
                continue;
            };
            if a.v.dot(&supports.get(j).surface.normal_at(&q)) < 0.0 {
                // Into the support it would leave.
                continue;
            }
            let along = a.v.dot(&heading);
            if next.as_ref().is_none_or(|(best, ..)| along > *best) {
                next = Some((along, on, a));
            }
        }
        let (_, on, a) = next?;
        if a.v.height() <= 0.0 {
            // Over the crest at the blocker: on from here, downhill.
            return Some(Exit {
                top: q,
                onward: a.v,
                kept: on,
                barrier: motion.energy - energy,
            });
        }
        // Going up, so the circle has a highest point.
        let top = highest(&a)?;
        climb = Climb {
            kept: on,
            arc: a,
            top,
        };
        at = q;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::super::tests::tilted_arc;
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Where the bound says the energy lasts, it lasts at every one of
        /// 2,000 points of the arc, by the energy [`Motion::slid`] books.
        #[test]
        fn the_energy_bound_never_claims_energy_that_runs_out(
            theta in 0.0 as Real..6.2,
            phi in 0.0 as Real..6.2,
            tilt in -1.5 as Real..1.5,
            t_end in 0.01 as Real..4.7,
            energy in 0.0 as Real..3.0,
            mu in 0.0 as Real..1.2,
        ) {
            let arc = tilted_arc(theta, phi, tilt);
            let p = arc.point_at(&Crossing { cos: 1.0, sin: 0.0 });
            let end = Crossing { cos: t_end.cos(), sin: t_end.sin() };
            if keeps_energy(&arc, &p, energy, mu, &end, t_end) {
                for k in 0..=2000 {
                    let t = t_end * k as Real / 2000.0;
                    let q = arc.point_at(&Crossing { cos: t.cos(), sin: t.sin() });
                    let left = energy + p.height() - q.height() - mu * (q - p).horizontal().norm();
                    prop_assert!(left > 0.0, "energy {left} at {t} of {t_end}");
                }
            }
        }
    }

    #[test]
    fn the_energy_bound_sees_a_steep_descent_keep_it_and_a_level_one_lose_it() {
        // A vertical circle started at its top heading along x: it goes
        // down, at first level. With µ = 0.5 and the arc to a quarter turn,
        // the least energy is where the descent rate reaches µ (30° past the
        // top): E + 2 (1 − cos 30°) − 0.5 · 2 · π/6 = E − 0.2557.
        let arc = Arc::<3> {
            m: Vector([0.0, 0.0, 5.0]),
            rho: 2.0,
            u: Vector([0.0, 0.0, 1.0]),
            v: Vector([1.0, 0.0, 0.0]),
        };
        let p = Vector([0.0, 0.0, 7.0]);
        let quarter = Crossing { cos: 0.0, sin: 1.0 };
        let t = std::f64::consts::FRAC_PI_2;
        let least = 2.0 * (1.0 - (std::f64::consts::PI / 6.0).cos()) - std::f64::consts::PI / 6.0;
        assert!(keeps_energy(&arc, &p, -least + 1e-6, 0.5, &quarter, t));
        assert!(!keeps_energy(&arc, &p, -least - 1e-6, 0.5, &quarter, t));
        // Without friction any energy lasts on the way down.
        assert!(keeps_energy(&arc, &p, 1e-3, 0.0, &quarter, t));
    }
}
