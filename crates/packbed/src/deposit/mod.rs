//! Sequential deposition: particles settle one at a time under gravity onto the
//! bed already there (the drop-and-roll model of `spec/model.md`).

mod base_layer;
pub mod chain;
pub(crate) mod obstacle;
pub(crate) mod roll;
pub mod rsa;

use crate::bed::{AnyBed, Bed};
use crate::config::{BaseLayerKind, Config, Fill, Mode, Plan};
use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::math::{Real, Vector};
use crate::species::{Orientation, Shape, SpeciesPicker};
use chain::{ChainShape, Pose};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use roll::Terrain;
use std::time::Instant;

/// What happened during deposition, for the run summary.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DepositReport {
    /// Particles placed by the base layer (random phase and gap-filling sweep).
    pub base_layer: u64,
    /// Of those, particles placed by the gap-filling sweep.
    pub base_layer_sweep: u64,
    /// Particles placed by drop and roll.
    pub dropped: u64,
    /// Particles that found no rest within the move budget and were dropped again.
    pub redrops: u64,
    /// Particles discarded because they would stick out above the roof.
    pub roof_overflows: u64,
    /// Wall time of deposition in seconds.
    pub deposit_seconds: f64,
}

/// Consecutive failed random placements after which the floor counts as saturated
/// (per particle that fits on the floor); the sweep then fills what is left.
const BASE_LAYER_PATIENCE: u64 = 10;
/// Re-drops of one particle after which the run gives up (never seen in practice).
const MAX_REDROPS_PER_PARTICLE: u32 = 1000;

/// The random generator of a run.
pub type RunRng = Xoshiro256PlusPlus;

/// The deposition engine for one bed.
struct Engine<'p, const D: usize> {
    plan: &'p Plan<D>,
    bed: Bed<D>,
    grid: Grid<D>,
    r_max: Real,
    picker: SpeciesPicker,
    rng: RunRng,
    report: DepositReport,
}

impl<'p, const D: usize> Engine<'p, D> {
    fn new(plan: &'p Plan<D>) -> Result<Self> {
        let r_max = plan
            .species
            .iter()
            .map(|s| s.size.bounds().1)
            .fold(0.0, Real::max);
        let grid = Grid::new(&plan.container, 2.0 * r_max);
        Ok(Engine {
            plan,
            bed: Bed::new(plan.container, plan.species.clone()),
            grid,
            r_max,
            picker: SpeciesPicker::new(&plan.species),
            rng: RunRng::seed_from_u64(plan.seed),
            report: DepositReport::default(),
        })
    }

    fn terrain(&self) -> Terrain<'_, D> {
        Terrain {
            container: &self.plan.container,
            grid: &self.grid,
            centres: &self.bed.centres,
            radii: &self.bed.radii,
            r_fixed_max: self.r_max,
        }
    }

    /// Draws the species and radius of the next particle.
    fn draw_particle(&mut self) -> (u32, Real) {
        let s = self.picker.pick(&mut self.rng);
        let r = self.plan.species[s].size.sample(&mut self.rng);
        (s as u32, r)
    }

    /// A uniformly random horizontal position where a sphere of radius `r` fits
    /// between the walls (anywhere in the period when periodic).
    fn drop_point(&mut self, r: Real) -> Vector<D> {
        let c = &self.plan.container;
        let mut p = Vector::<D>::zero();
        for k in 0..D - 1 {
            p[k] = if c.periodic {
                self.rng.random_range(0.0..c.size[k])
            } else if c.size[k] - r > r {
                self.rng.random_range(r..c.size[k] - r)
            } else {
                0.5 * c.size[k]
            };
        }
        p
    }

    /// Adds a particle that is a body of its own.
    fn place(&mut self, p: Vector<D>, r: Real, species: u32) {
        let body = self.bed.bodies.last().map_or(0, |&b| b + 1);
        self.place_bead(p, r, species, body);
    }

    /// Adds all beads of a chain as one new body.
    fn place_chain(&mut self, shape: ChainShape, pose: &Pose<D>, species: u32) {
        let body = self.bed.bodies.last().map_or(0, |&b| b + 1);
        for k in 0..shape.beads {
            let p = pose.com + pose.axis * shape.offset(k);
            self.place_bead(p, shape.r, species, body);
        }
    }

    /// The chain shape of species `s` with bead radius `r`, if it is a chain.
    fn chain_of(&self, s: u32, r: Real) -> Option<(ChainShape, Orientation)> {
        match self.plan.species[s as usize].shape {
            Shape::Sphere => None,
            Shape::Chain {
                beads,
                spacing,
                orientation,
            } => Some((ChainShape { beads, spacing, r }, orientation)),
        }
    }

    /// A random entry pose for a chain: its axis as `orientation` asks, its
    /// centre of mass uniformly over the horizontal positions where its
    /// footprint fits between the walls (anywhere in the period when periodic).
    /// An orientation that cannot fit (a horizontal chain longer than a walled
    /// box) is redrawn, and after 64 tries the chain enters upright.
    fn chain_entry(&mut self, shape: ChainShape, orientation: Orientation) -> Pose<D> {
        let c = self.plan.container;
        for attempt in 0..=64 {
            let orientation = if attempt == 64 {
                Orientation::Vertical
            } else {
                orientation
            };
            let axis = match orientation {
                Orientation::Vertical => Vector::up(),
                Orientation::Random => random_axis::<D>(&mut self.rng, false),
                Orientation::Horizontal => random_axis::<D>(&mut self.rng, true),
            };
            let mut com = Vector::<D>::zero();
            let mut fits = true;
            for k in 0..D - 1 {
                let e = axis[k].abs() * shape.half_length() + shape.r;
                com[k] = if c.periodic {
                    self.rng.random_range(0.0..c.size[k])
                } else if c.size[k] - e > e {
                    self.rng.random_range(e..c.size[k] - e)
                } else if c.size[k] - e >= e - 1e-12 * shape.r {
                    0.5 * c.size[k]
                } else {
                    fits = false;
                    0.5 * c.size[k]
                };
            }
            if fits {
                return Pose { com, axis };
            }
        }
        unreachable!("an upright chain fits wherever its bead does")
    }

    /// Adds a particle to the bed (wrapping periodic coordinates into the box).
    fn place_bead(&mut self, mut p: Vector<D>, r: Real, species: u32, body: u32) {
        let c = &self.plan.container;
        if c.periodic {
            for k in 0..D - 1 {
                let w = c.size[k];
                p[k] -= w * (p[k] / w).floor();
                if p[k] >= w {
                    p[k] = 0.0;
                }
            }
        }
        let id = self.bed.len() as u32;
        self.grid.insert(id, &p, r);
        self.bed.push_bead(p, r, species, body);
    }

    fn target(&self) -> u64 {
        match self.plan.fill {
            Fill::Count(n) => n,
            Fill::Roof { .. } => u64::MAX,
        }
    }

    /// Random particles resting on the floor until saturated, then the sweep.
    fn base_layer(&mut self) {
        let target = self.target();
        let c = self.plan.container;
        // How many of the smallest particles would tile the floor: a scale for
        // how long to keep trying at random.
        let r_min = self
            .plan
            .species
            .iter()
            .filter(|s| s.ratio > 0.0)
            .map(|s| s.size.bounds().0)
            .fold(Real::INFINITY, Real::min);
        let floor_area: Real = (0..D - 1).map(|k| c.size[k]).product();
        let footprint = (2.0 * r_min).powi(D as i32 - 1);
        let patience = BASE_LAYER_PATIENCE * ((floor_area / footprint).ceil() as u64).max(1);
        let mut failures = 0;
        while failures < patience && (self.bed.len() as u64) < target {
            let (s, r) = self.draw_particle();
            if let Some((shape, _)) = self.chain_of(s, r) {
                // A chain lies flat on the floor, at a random azimuth.
                let mut pose = self.chain_entry(shape, Orientation::Horizontal);
                pose.com[D - 1] = r;
                let terrain = self.terrain();
                // The entry falls back to upright when no azimuth tried fits
                // between the walls; upright on the floor would stand through it.
                let flat = pose.axis[D - 1].abs() < 0.5;
                let fits = flat
                    && (0..shape.beads).all(|k| {
                        base_layer::fits(
                            &terrain,
                            &(pose.com + pose.axis * shape.offset(k)),
                            r,
                            0.0,
                        )
                    });
                if fits {
                    self.place_chain(shape, &pose, s);
                    failures = 0;
                } else {
                    failures += 1;
                }
                continue;
            }
            let mut p = self.drop_point(r);
            p[D - 1] = r;
            if base_layer::fits(&self.terrain(), &p, r, 0.0) {
                self.place(p, r, s);
                failures = 0;
            } else {
                failures += 1;
            }
        }
        // The sweep: along the floor in order of position, fill every gap where
        // the smallest particle still fits, touching its neighbours. When the
        // smallest particle is a chain the random phase alone saturates the floor
        // (the sweep's vertices are for single spheres).
        let (s_min, r_fill) = self
            .plan
            .species
            .iter()
            .enumerate()
            // A species of ratio 0 is never drawn, so it has no place in the layer.
            .filter(|(_, s)| s.ratio > 0.0)
            .map(|(i, s)| (i as u32, s.size.bounds().0))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("the ratios sum to more than zero");
        if self.chain_of(s_min, r_fill).is_some() {
            self.report.base_layer = self.bed.len() as u64;
            return;
        }
        let slack = 1e-9 * r_fill;
        let mut candidates = Vec::new();
        let before = self.bed.len();
        loop {
            let mut order: Vec<u32> = (0..self.bed.len() as u32).collect();
            order.sort_by(|&a, &b| {
                let (pa, pb) = (self.bed.centres[a as usize], self.bed.centres[b as usize]);
                pa.0.iter()
                    .zip(pb.0.iter())
                    .map(|(x, y)| x.total_cmp(y))
                    .find(|o| o.is_ne())
                    .unwrap_or(std::cmp::Ordering::Equal)
            });
            let placed_before = self.bed.len();
            for j in std::iter::once(None).chain(order.into_iter().map(Some)) {
                if (self.bed.len() as u64) >= target {
                    break;
                }
                base_layer::floor_vertices(&self.terrain(), j, r_fill, &mut candidates);
                for &p in &candidates {
                    if !p.is_finite() || (p[D - 1] - r_fill).abs() > slack {
                        continue;
                    }
                    let mut q = p;
                    for k in 0..D - 1 {
                        if c.periodic {
                            let w = c.size[k];
                            q[k] -= w * (q[k] / w).floor();
                        }
                    }
                    if (self.bed.len() as u64) < target
                        && base_layer::fits(&self.terrain(), &q, r_fill, slack)
                    {
                        self.place(q, r_fill, s_min);
                    }
                }
            }
            if self.bed.len() == placed_before {
                break;
            }
        }
        self.report.base_layer_sweep = (self.bed.len() - before) as u64;
        self.report.base_layer = self.bed.len() as u64;
    }

    fn run(mut self, progress: &mut dyn FnMut(u64)) -> Result<(Bed<D>, DepositReport)> {
        let started = Instant::now();
        if let Fill::Count(n) = self.plan.fill {
            let n = n as usize;
            self.bed.centres.reserve_exact(n);
            self.bed.radii.reserve_exact(n);
            self.bed.species.reserve_exact(n);
            self.bed.bodies.reserve_exact(n);
            self.grid.reserve(n);
        }
        if self.plan.base_layer == BaseLayerKind::Random {
            self.base_layer();
        }
        let target = self.target();
        let misses = match self.plan.fill {
            Fill::Roof { misses } => Some(misses),
            Fill::Count(_) => None,
        };
        let roof = self.plan.container.height();
        while (self.bed.len() as u64) < target {
            let (s, r) = self.draw_particle();
            if let Some((shape, orientation)) = self.chain_of(s, r) {
                let mut tries = 0;
                let pose = loop {
                    let start = self.chain_entry(shape, orientation);
                    let terrain = Terrain {
                        container: &self.plan.container,
                        grid: &self.grid,
                        centres: &self.bed.centres,
                        radii: &self.bed.radii,
                        r_fixed_max: self.r_max,
                    };
                    if let Some(p) = chain::settle_chain(&terrain, shape, start, &mut self.rng) {
                        break p;
                    }
                    self.report.redrops += 1;
                    tries += 1;
                    if tries >= MAX_REDROPS_PER_PARTICLE {
                        return Err(Error::Impossible(format!(
                            "a chain of {} beads of radius {r} found no resting place after {tries} drops",
                            shape.beads
                        )));
                    }
                };
                if let Some(misses) = misses {
                    let top = (0..shape.beads)
                        .map(|k| (pose.com + pose.axis * shape.offset(k))[D - 1])
                        .fold(Real::NEG_INFINITY, Real::max)
                        + r;
                    if top > roof {
                        self.report.roof_overflows += 1;
                        if self.report.roof_overflows > misses {
                            break;
                        }
                        continue;
                    }
                }
                let before = self.bed.len();
                self.place_chain(shape, &pose, s);
                self.report.dropped += 1;
                if before / 4096 != self.bed.len() / 4096 {
                    progress(self.bed.len() as u64);
                }
                continue;
            }
            let mut tries = 0;
            let p = loop {
                let start = self.drop_point(r);
                let terrain = Terrain {
                    container: &self.plan.container,
                    grid: &self.grid,
                    centres: &self.bed.centres,
                    radii: &self.bed.radii,
                    r_fixed_max: self.r_max,
                };
                if let Some(p) = roll::settle(&terrain, r, start, &mut self.rng) {
                    break p;
                }
                self.report.redrops += 1;
                tries += 1;
                if tries >= MAX_REDROPS_PER_PARTICLE {
                    return Err(Error::Impossible(format!(
                        "a particle of radius {r} found no resting place after {tries} drops"
                    )));
                }
            };
            if let Some(misses) = misses {
                if p[D - 1] + r > roof {
                    self.report.roof_overflows += 1;
                    if self.report.roof_overflows > misses {
                        break;
                    }
                    continue;
                }
            }
            self.place(p, r, s);
            self.report.dropped += 1;
            if self.bed.len().is_multiple_of(4096) {
                progress(self.bed.len() as u64);
            }
        }
        progress(self.bed.len() as u64);
        self.report.deposit_seconds = started.elapsed().as_secs_f64();
        Ok((self.bed, self.report))
    }
}

/// Builds a bed for a validated plan. `progress` is called now and then with the
/// number of particles placed so far.
pub fn deposit<const D: usize>(
    plan: &Plan<D>,
    progress: &mut dyn FnMut(u64),
) -> Result<(Bed<D>, DepositReport)> {
    match plan.mode {
        Mode::Deposit => Engine::new(plan)?.run(progress),
        Mode::Rsa => rsa::rsa(plan, progress),
    }
}

/// Builds the bed a configuration describes, in its dimension.
pub fn build(config: &Config, progress: &mut dyn FnMut(u64)) -> Result<(AnyBed, DepositReport)> {
    match config.dim {
        2 => deposit(&config.plan::<2>()?, progress).map(|(b, r)| (AnyBed::D2(b), r)),
        3 => deposit(&config.plan::<3>()?, progress).map(|(b, r)| (AnyBed::D3(b), r)),
        d => Err(crate::Error::config(format!("dim must be 2 or 3, got {d}"))),
    }
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

/// Drops one chain onto a fixed bed, entering with the horizontal position and
/// axis of `start` (lowered to just above the bed), and returns its bead centres
/// at rest (wrapped into a periodic box), or `None` if it finds no rest. For
/// hand-checked cases and tools, like [`drop_one`].
pub fn drop_chain<const D: usize>(
    bed: &Bed<D>,
    shape: ChainShape,
    start: Pose<D>,
    seed: u64,
) -> Option<Vec<Vector<D>>> {
    let r_max = bed.r_max().max(shape.r);
    let mut grid = Grid::new(&bed.container, 2.0 * r_max);
    for (i, (c, &ri)) in bed.centres.iter().zip(&bed.radii).enumerate() {
        grid.insert(i as u32, c, ri);
    }
    let terrain = Terrain {
        container: &bed.container,
        grid: &grid,
        centres: &bed.centres,
        radii: &bed.radii,
        r_fixed_max: r_max,
    };
    let mut rng = RunRng::seed_from_u64(seed);
    let pose = chain::settle_chain(&terrain, shape, start, &mut rng)?;
    let mut beads = shape.beads(pose.com, pose.axis);
    if bed.container.periodic {
        for p in &mut beads {
            for k in 0..D - 1 {
                let w = bed.container.size[k];
                p[k] -= w * (p[k] / w).floor();
            }
        }
    }
    Some(beads)
}

/// Drops one sphere of radius `r` at the horizontal position of `start` onto a
/// fixed bed and returns where it comes to rest (wrapped into a periodic box), or
/// `None` if it finds no rest. For hand-checked cases and tools; runs build their
/// beds with [`deposit`].
pub fn drop_one<const D: usize>(
    bed: &Bed<D>,
    r: Real,
    start: Vector<D>,
    seed: u64,
) -> Option<Vector<D>> {
    let r_max = bed.r_max().max(r);
    let mut grid = Grid::new(&bed.container, 2.0 * r_max);
    for (i, (c, &ri)) in bed.centres.iter().zip(&bed.radii).enumerate() {
        grid.insert(i as u32, c, ri);
    }
    let terrain = Terrain {
        container: &bed.container,
        grid: &grid,
        centres: &bed.centres,
        radii: &bed.radii,
        r_fixed_max: r_max,
    };
    let mut rng = RunRng::seed_from_u64(seed);
    let mut p = roll::settle(&terrain, r, start, &mut rng)?;
    if bed.container.periodic {
        for k in 0..D - 1 {
            let w = bed.container.size[k];
            p[k] -= w * (p[k] / w).floor();
        }
    }
    Some(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::container::Container;

    fn bed<const D: usize>(
        size: [Real; D],
        periodic: bool,
        spheres: &[([Real; D], Real)],
    ) -> Bed<D> {
        let mut b = Bed::new(
            Container {
                size: Vector(size),
                periodic,
            },
            Vec::new(),
        );
        for (c, r) in spheres {
            b.push(Vector(*c), *r, 0);
        }
        b
    }

    fn close<const D: usize>(p: Vector<D>, q: [Real; D]) {
        assert!((p - Vector(q)).norm() < 1e-10, "{p:?} != {q:?}");
    }

    #[test]
    fn disc_onto_two_touching_discs() {
        let b = bed([20.0, 20.0], false, &[([5.0, 1.0], 1.0), ([7.0, 1.0], 1.0)]);
        let p = drop_one(&b, 1.0, Vector([6.3, 0.0]), 1).unwrap();
        close(p, [6.0, 1.0 + 3f64.sqrt()]);
    }

    #[test]
    fn sphere_onto_three_touching_spheres() {
        let s3 = 3f64.sqrt();
        let b = bed(
            [20.0, 20.0, 20.0],
            false,
            &[
                ([5.0, 5.0, 1.0], 1.0),
                ([7.0, 5.0, 1.0], 1.0),
                ([6.0, 5.0 + s3, 1.0], 1.0),
            ],
        );
        let centroid = [6.0, 5.0 + s3 / 3.0];
        let p = drop_one(&b, 1.0, Vector([6.2, 5.4, 0.0]), 1).unwrap();
        close(p, [centroid[0], centroid[1], 1.0 + (8.0f64 / 3.0).sqrt()]);
    }

    #[test]
    fn disc_against_wall_on_one_support() {
        let b = bed([20.0, 20.0], false, &[([2.5, 1.0], 1.0)]);
        let p = drop_one(&b, 1.0, Vector([1.6, 0.0]), 1).unwrap();
        close(p, [1.0, 1.0 + 1.75f64.sqrt()]);
    }

    #[test]
    fn sphere_rolls_off_an_edge_to_the_floor() {
        let b = bed([20.0, 20.0, 20.0], false, &[([5.0, 5.0, 2.0], 2.0)]);
        let p = drop_one(&b, 1.0, Vector([5.5, 5.0, 0.0]), 1).unwrap();
        close(p, [8.0, 5.0, 1.0]);
    }

    #[test]
    fn sphere_rolls_along_a_groove_then_onto_the_floor() {
        // Two touching spheres of radius 2 on the floor; a small sphere lands in
        // the groove between them, off-centre, and rolls along the groove circle
        // (centre (10, 10, 2), radius √5 in the plane x = 10). With a horizontal
        // axis both contact forces vanish at the circle's equator, z = 2, where it
        // leaves the groove and falls straight to the floor.
        let b = bed(
            [20.0, 20.0, 20.0],
            false,
            &[([8.0, 10.0, 2.0], 2.0), ([12.0, 10.0, 2.0], 2.0)],
        );
        let p = drop_one(&b, 1.0, Vector([10.0, 10.3, 0.0]), 1).unwrap();
        close(p, [10.0, 10.0 + 5f64.sqrt(), 1.0]);
    }

    #[test]
    fn periodic_neighbour_across_the_boundary() {
        // Two discs touching across x = 0 in a periodic box of width 10.
        let b = bed([10.0, 20.0], true, &[([0.5, 1.0], 1.0), ([8.5, 1.0], 1.0)]);
        // Their gap centre is at x = 9.5 (≡ −0.5), distance between them 2.
        let p = drop_one(&b, 1.0, Vector([9.6, 0.0]), 1).unwrap();
        close(p, [9.5, 1.0 + 3f64.sqrt()]);
    }
}
