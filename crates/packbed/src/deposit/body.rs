//! The kinds of body the engine drops (a sphere, a rigid chain): where each
//! enters, how it settles, which beads it adds. The drop loop is written once
//! over them ([`Dropper`]).

use super::chain::{self, ChainShape, Pose};
use super::roll::{self, Terrain};
use super::RunRng;
use crate::bed::Bed;
use crate::config::{Feed, Settling};
use crate::container::Container;
use crate::grid::Grid;
use crate::math::{Real, Vector};
use crate::species::EntryOrientation;
use rand::{RngExt, SeedableRng};

/// A kind of body the engine drops.
pub(crate) trait Dropper<const D: usize> {
    /// Where the body is: a sphere's centre, a chain's pose.
    type Pose: Copy;

    /// A random entry position above the bed (the height is the settling's
    /// business).
    fn enter(&self, container: &Container<D>, feed: &Feed, rng: &mut RunRng) -> Self::Pose;

    /// Settles the body from `start` onto the fixed terrain; `None` when it
    /// found no rest.
    fn settle(
        &self,
        terrain: &Terrain<'_, D>,
        start: Self::Pose,
        rule: &Settling,
        rng: &mut RunRng,
        moves: &mut u64,
    ) -> Option<Self::Pose>;

    /// Number of beads.
    fn beads(&self) -> u32;

    /// Centre of bead `k` at `pose` (not wrapped into a periodic box).
    fn bead(&self, pose: &Self::Pose, k: u32) -> Vector<D>;

    /// Bead radius.
    fn radius(&self) -> Real;

    /// The error of a body that found no rest after `tries` drops.
    fn stuck(&self, tries: u32) -> String;
}

/// A sphere of the given radius.
#[derive(Clone, Copy)]
pub(crate) struct Sphere(pub Real);

impl<const D: usize> Dropper<D> for Sphere {
    type Pose = Vector<D>;

    fn enter(&self, container: &Container<D>, feed: &Feed, rng: &mut RunRng) -> Vector<D> {
        entry_position(container, feed, rng, |_| self.0, 0.0).0
    }

    fn settle(
        &self,
        terrain: &Terrain<'_, D>,
        start: Vector<D>,
        rule: &Settling,
        rng: &mut RunRng,
        moves: &mut u64,
    ) -> Option<Vector<D>> {
        roll::settle(terrain, self.0, start, rule, rng, moves)
    }

    fn beads(&self) -> u32 {
        1
    }

    fn bead(&self, pose: &Vector<D>, _: u32) -> Vector<D> {
        *pose
    }

    fn radius(&self) -> Real {
        self.0
    }

    fn stuck(&self, tries: u32) -> String {
        format!(
            "a particle of radius {} found no resting place after {tries} drops",
            self.0
        )
    }
}

/// A rigid chain entering with its axis as `orientation` asks.
#[derive(Clone, Copy)]
pub(crate) struct Chain {
    pub shape: ChainShape,
    pub orientation: EntryOrientation,
}

impl<const D: usize> Dropper<D> for Chain {
    type Pose = Pose<D>;

    /// Its centre of mass uniformly over the horizontal positions where its
    /// footprint fits between the walls (anywhere in the period when periodic).
    /// An orientation that cannot fit (a horizontal chain longer than a walled
    /// box) is redrawn, and after 64 tries the chain enters upright.
    fn enter(&self, container: &Container<D>, feed: &Feed, rng: &mut RunRng) -> Pose<D> {
        let shape = self.shape;
        for attempt in 0..=64 {
            let orientation = if attempt == 64 {
                EntryOrientation::Vertical
            } else {
                self.orientation
            };
            let axis = match orientation {
                EntryOrientation::Vertical => Vector::up(),
                EntryOrientation::Random => random_axis::<D>(rng, false),
                EntryOrientation::Horizontal => random_axis::<D>(rng, true),
            };
            let extent = |k: usize| axis[k].abs() * shape.half_length() + shape.r;
            let (com, fits) = entry_position(container, feed, rng, extent, 1e-12 * shape.r);
            if fits {
                return Pose { com, axis };
            }
        }
        unreachable!("an upright chain fits wherever its bead does")
    }

    fn settle(
        &self,
        terrain: &Terrain<'_, D>,
        start: Pose<D>,
        rule: &Settling,
        rng: &mut RunRng,
        moves: &mut u64,
    ) -> Option<Pose<D>> {
        chain::settle_chain(terrain, self.shape, start, rule, rng, moves)
    }

    fn beads(&self) -> u32 {
        self.shape.beads
    }

    fn bead(&self, pose: &Pose<D>, k: u32) -> Vector<D> {
        pose.com + pose.axis * self.shape.offset(k)
    }

    fn radius(&self) -> Real {
        self.shape.r
    }

    fn stuck(&self, tries: u32) -> String {
        format!(
            "a chain of {} beads of radius {} found no resting place after {tries} drops",
            self.shape.beads, self.shape.r
        )
    }
}

/// A random horizontal position for a body reaching `extent(k)` from its
/// centre along horizontal axis `k`: uniformly where it fits between the
/// walls, or anywhere in the period when periodic; along the axes a point or
/// line feed centres, a Gaussian about the feed's position, drawn again
/// while it falls outside where the body fits (after 64 draws, the nearest
/// place that fits), wrapped into the period when periodic. Where it cannot
/// fit, the middle of the box, and `false` unless the misfit is within `tol`.
fn entry_position<const D: usize>(
    container: &Container<D>,
    feed: &Feed,
    rng: &mut RunRng,
    extent: impl Fn(usize) -> Real,
    tol: Real,
) -> (Vector<D>, bool) {
    let mut p = Vector::<D>::zero();
    let mut fits = true;
    for k in 0..D - 1 {
        let (w, e) = (container.size[k], extent(k));
        p[k] = if feed.centred(k) {
            let (lo, hi) = if container.periodic {
                (Real::NEG_INFINITY, Real::INFINITY)
            } else {
                fits &= w - e >= e - tol;
                (e.min(0.5 * w), (w - e).max(0.5 * w))
            };
            let mut x = feed.at[k];
            for _ in 0..64 {
                x = feed.at[k] + feed.spread * gaussian(rng);
                if (lo..=hi).contains(&x) {
                    break;
                }
            }
            let x = x.clamp(lo, hi);
            if container.periodic {
                x.rem_euclid(w)
            } else {
                x
            }
        } else if container.periodic {
            rng.random_range(0.0..w)
        } else if w - e > e {
            rng.random_range(e..w - e)
        } else {
            fits &= w - e >= e - tol;
            0.5 * w
        };
    }
    (p, fits)
}

/// A standard normal draw (Box–Muller, two uniform draws).
fn gaussian(rng: &mut RunRng) -> Real {
    let u: Real = 1.0 - rng.random::<Real>();
    let v: Real = rng.random();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// A random unit axis: uniform over directions with a non-negative vertical
/// component (the sign of a chain's axis means nothing), or uniform over
/// horizontal directions.
fn random_axis<const D: usize>(rng: &mut RunRng, horizontal: bool) -> Vector<D> {
    let mut a = Vector::<D>::zero();
    if D == 2 {
        // Either way along the floor: the axis points from the first bead to the
        // last, and a flat chain is counted on the side its last bead lies.
        let t = if horizontal {
            if rng.random_bool(0.5) {
                0.5 * std::f64::consts::PI
            } else {
                -0.5 * std::f64::consts::PI
            }
        } else {
            rng.random_range(-0.5 * std::f64::consts::PI..0.5 * std::f64::consts::PI)
        };
        a[0] = t.sin();
        a[1] = t.cos();
    } else {
        let z: Real = if horizontal {
            0.0
        } else {
            rng.random_range(0.0..1.0)
        };
        let phi = rng.random_range(0.0..2.0 * std::f64::consts::PI);
        let s = (1.0 - z * z).sqrt();
        a[0] = s * phi.cos();
        a[1] = s * phi.sin();
        a[2] = z;
    }
    a
}

/// A body dropped by hand onto a fixed bed with [`drop_onto`], and where it
/// enters (its horizontal position; it is lowered to just above the bed).
#[derive(Clone, Copy, Debug)]
pub enum Entry<const D: usize> {
    /// A sphere of radius `r` entering at `start`.
    Sphere {
        /// Radius.
        r: Real,
        /// Entry point.
        start: Vector<D>,
    },
    /// A rigid chain entering with the horizontal position and axis of `start`.
    Chain {
        /// Its shape.
        shape: ChainShape,
        /// Entry pose.
        start: Pose<D>,
    },
}

/// Drops one body onto a fixed bed, settling by `rule`, and returns its bead
/// centres at rest (wrapped into a periodic box), or `None` if it finds no
/// rest. For hand-checked cases and tools; runs build their beds with
/// [`deposit`](super::deposit).
pub fn drop_onto<const D: usize>(
    bed: &Bed<D>,
    entry: Entry<D>,
    rule: &Settling,
    seed: u64,
) -> Option<Vec<Vector<D>>> {
    match entry {
        Entry::Sphere { r, start } => drop_alone(bed, &Sphere(r), start, rule, seed),
        Entry::Chain { shape, start } => {
            // The orientation only draws entries, and the entry is given.
            let chain = Chain {
                shape,
                orientation: EntryOrientation::Vertical,
            };
            drop_alone(bed, &chain, start, rule, seed)
        }
    }
}

/// [`drop_onto`] for one kind of body.
fn drop_alone<const D: usize, B: Dropper<D>>(
    bed: &Bed<D>,
    body: &B,
    start: B::Pose,
    rule: &Settling,
    seed: u64,
) -> Option<Vec<Vector<D>>> {
    let grid = Grid::of_particles(&bed.container, &bed.centres, &bed.radii, body.radius());
    let terrain = Terrain::of(&bed.container, &grid, bed);
    let mut rng = RunRng::seed_from_u64(seed);
    let pose = body.settle(&terrain, start, rule, &mut rng, &mut 0)?;
    let beads = (0..body.beads()).map(|k| bed.container.wrap(body.bead(&pose, k)));
    Some(beads.collect())
}
