//! The base layer: particles resting on the floor at random places until the floor
//! is saturated, then a sweep that fills every gap still wide enough for the
//! smallest particle (as the source study seeded its beds).

use super::body::{Chain, Dropper, Sphere};
use super::roll::Terrain;
use super::{Engine, RunRng};
use crate::config::{Feed, Fill};
use crate::container::Wall;
use crate::geometry::{intersection_points, Surface};
use crate::math::{Real, Vector};
use crate::species::EntryOrientation;
use rayon::prelude::*;

/// Consecutive failed random placements after which the floor counts as saturated
/// (per particle that fits on the floor); the sweep then fills what is left.
const BASE_LAYER_PATIENCE: u64 = 10;

/// The bed size a roof-filled bed's patience assumes at least: its estimate
/// (by the mean particle) is rough, and no floor of an ordinary bed holds
/// more than this many of its smallest particles.
const ROOF_BED_AT_LEAST: u64 = 1_000_000;

/// Most tries of the random phase drawn ahead and tested on every core at once.
const MOST_AHEAD: usize = 4096;

/// A sphere's try of the random phase, drawn ahead.
struct Try<const D: usize> {
    species: u32,
    r: Real,
    p: Vector<D>,
    /// The generator before this try was drawn.
    rng: RunRng,
}

impl<const D: usize> Engine<'_, D> {
    /// Random particles resting on the floor until saturated, then the sweep
    /// ([`Self::sweep`]). With `in_parallel`, the tries of spheres are tested
    /// on every core ([`Self::tries_ahead`]; the same layer).
    pub(super) fn base_layer(&mut self, in_parallel: bool) {
        let target = self.target();
        let c = self.plan.container;
        let floor_area: Real = (0..D - 1).map(|k| c.size[k]).product();
        // Never more failures in a row than ten per particle the bed will
        // hold: a floor of 1e31 footprints of a species drawn once in 1e17
        // tries (radii 2e16 and 20) set a patience of 1e32 for a bed of 54.
        let bed_size = match self.plan.fill {
            Fill::Count(n) => n,
            Fill::Roof { .. } => self.plan.estimated_particles().max(ROOF_BED_AT_LEAST),
        };
        let patience = random_phase_patience::<D>(&self.plan.species, floor_area)
            .min(BASE_LAYER_PATIENCE.saturating_mul(bed_size.max(1)));
        let mut failures = 0;
        let mut ahead = Ahead::default();
        while failures < patience && (self.bed.len() as u64) < target {
            if in_parallel && self.tries_ahead(&mut ahead, &mut failures, patience) {
                continue;
            }
            let (s, r) = self.draw_particle();
            if let Some((shape, _)) = self.chain_of(s, r) {
                // A chain lies flat on the floor, at a random azimuth.
                let chain = Chain {
                    shape,
                    orientation: EntryOrientation::Horizontal,
                };
                let mut pose = chain.enter(&c, &Feed::default(), &mut self.rng);
                pose.com[D - 1] = r;
                let terrain = self.terrain();
                // The entry falls back to upright when no azimuth tried fits
                // between the walls; upright on the floor would stand through it.
                let flat = pose.axis[D - 1].abs() < 0.5;
                let lies =
                    flat && (0..shape.beads).all(|k| fits(&terrain, &chain.bead(&pose, k), r, 0.0));
                if lies {
                    self.place_body(&chain, &pose, s);
                    failures = 0;
                } else {
                    failures += 1;
                }
                continue;
            }
            let mut p = Sphere(r).enter(&c, &Feed::default(), &mut self.rng);
            p[D - 1] = r;
            if fits(&self.terrain(), &p, r, 0.0) {
                self.place_body(&Sphere(r), &p, s);
                failures = 0;
            } else {
                failures += 1;
            }
        }
        self.sweep();
    }

    /// Tries of spheres drawn ahead from the generator, tested against the
    /// floor as it is on every core, then taken in order as the one-at-a-time
    /// loop above takes them: a try that overlapped a particle before still
    /// does; one that did not is tested again only if a sphere was placed
    /// since. Stops before a chain is drawn (the loop above places it), when
    /// the failures reach `patience` or when the bed is full, with the
    /// generator where the one-at-a-time loop leaves it. False if it drew
    /// nothing (the next draw is a chain).
    fn tries_ahead(&mut self, ahead: &mut Ahead<D>, failures: &mut u64, patience: u64) -> bool {
        let target = self.target();
        let c = self.plan.container;
        ahead.tries.clear();
        while ahead.tries.len() < ahead.size {
            let before = self.rng.clone();
            let (species, r) = self.draw_particle();
            if self.chain_of(species, r).is_some() {
                self.rng = before;
                break;
            }
            let mut p = Sphere(r).enter(&c, &Feed::default(), &mut self.rng);
            p[D - 1] = r;
            ahead.tries.push(Try {
                species,
                r,
                p,
                rng: before,
            });
        }
        if ahead.tries.is_empty() {
            return false;
        }
        let (grid, bed) = (&self.grid, &self.bed);
        ahead
            .tries
            .par_iter()
            .map_init(
                || Terrain::of(&c, grid, bed),
                |terrain, t| fits(terrain, &t.p, t.r, 0.0),
            )
            .collect_into_vec(&mut ahead.fit);
        let placed_before = self.bed.len();
        for (i, t) in ahead.tries.iter().enumerate() {
            if *failures >= patience || (self.bed.len() as u64) >= target {
                self.rng = t.rng.clone();
                break;
            }
            let fit = ahead.fit[i]
                && (self.bed.len() == placed_before || fits(&self.terrain(), &t.p, t.r, 0.0));
            if fit {
                self.place_body(&Sphere(t.r), &t.p, t.species);
                *failures = 0;
            } else {
                *failures += 1;
            }
        }
        // Few tries ahead while the floor still takes many spheres (each
        // placed one makes the tries after it be tested again), more as it
        // saturates.
        ahead.size = if self.bed.len() > placed_before {
            (ahead.size / 2).max(16)
        } else {
            (ahead.size * 2).min(MOST_AHEAD)
        };
        true
    }

    /// The sweep: along the floor in order of position, fill every gap where
    /// the smallest particle still fits, touching its neighbours. When the
    /// smallest particle is a chain the random phase alone saturates the floor
    /// (the sweep's vertices are for single spheres).
    fn sweep(&mut self) {
        let target = self.target();
        let c = self.plan.container;
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
                floor_vertices(&self.terrain(), j, r_fill, &mut candidates);
                for &p in &candidates {
                    if !p.is_finite() || (p[D - 1] - r_fill).abs() > slack {
                        continue;
                    }
                    let q = c.wrap(p);
                    if (self.bed.len() as u64) < target && fits(&self.terrain(), &q, r_fill, slack)
                    {
                        self.place_body(&Sphere(r_fill), &q, s_min);
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
}

/// The tries of [`Engine::tries_ahead`], kept between calls.
struct Ahead<const D: usize> {
    tries: Vec<Try<D>>,
    fit: Vec<bool>,
    size: usize,
}

impl<const D: usize> Default for Ahead<D> {
    fn default() -> Self {
        Ahead {
            tries: Vec::new(),
            fit: Vec::new(),
            size: 16,
        }
    }
}

/// How many failed placements in a row end the random phase: ten times the
/// number of the smallest particles that would tile the floor, a scale for how
/// long the floor takes to saturate. A species so rare that it would not be
/// drawn once in that many tries (a number share of 1e-99 beside one of the
/// bulk) sets no scale: waiting for it would never end, and the sweep puts it
/// into the gaps anyway.
fn random_phase_patience<const D: usize>(
    species: &[crate::species::Species],
    floor_area: Real,
) -> u64 {
    let total: Real = species.iter().map(|s| s.ratio).sum();
    // Saturating: a floor of 1e20 footprints (a box of 1e10 diameters) would
    // overflow the product.
    let patience_for = |r: Real| {
        let footprint = (2.0 * r).powi(D as i32 - 1);
        BASE_LAYER_PATIENCE.saturating_mul(((floor_area / footprint).ceil() as u64).max(1))
    };
    let drawn: Vec<(Real, Real)> = species
        .iter()
        .filter(|s| s.ratio > 0.0)
        .map(|s| (s.size.bounds().0, s.ratio / total))
        .collect();
    let seen = drawn
        .iter()
        .filter(|&&(r, share)| share * patience_for(r) as Real >= 1.0)
        .map(|&(r, _)| r)
        .fold(Real::INFINITY, Real::min);
    let r = if seen.is_finite() {
        seen
    } else {
        drawn.iter().map(|&(r, _)| r).fold(0.0, Real::max)
    };
    patience_for(r)
}

/// True if a sphere of radius `r` centred at `p` overlaps nothing by more than
/// `slack` (walls and fixed particles; the floor is the caller's business).
pub(crate) fn fits<const D: usize>(
    terrain: &Terrain<'_, D>,
    p: &Vector<D>,
    r: Real,
    slack: Real,
) -> bool {
    let c = terrain.container;
    if !c.periodic {
        for k in 0..D - 1 {
            if p[k] < r - slack || p[k] > c.size[k] - r + slack {
                return false;
            }
        }
    }
    // On a nearly saturated floor almost every trial fails on a close
    // neighbour; each level of the grid is searched only as far as its own
    // particles reach.
    !terrain.grid.any_in_box(p, p, r, |id, shift, _| {
        let q = terrain.centres[id as usize] + shift;
        let need = r + terrain.radii[id as usize] - slack;
        (*p - q).norm2() < need * need
    })
}

/// Candidate resting places on the floor for a particle of radius `r` that
/// touch the floor particle `j` (or, with `j = None`, only walls): the points where
/// the floor plane meets `D − 1` other surfaces, one of which is particle `j`.
pub(crate) fn floor_vertices<const D: usize>(
    terrain: &Terrain<'_, D>,
    j: Option<u32>,
    r: Real,
    out: &mut Vec<Vector<D>>,
) {
    out.clear();
    let c = terrain.container;
    let floor = Surface::Plane {
        normal: Vector::up(),
        offset: r,
    };
    let mut walls: Vec<Surface<D>> = Vec::new();
    if !c.periodic {
        for k in 0..D - 1 {
            walls.push(plane(c.wall_normal(Wall::Low(k)), r));
            walls.push(plane(c.wall_normal(Wall::High(k)), r - c.size[k]));
        }
    }
    let push_points = |s: &[Surface<D>], out: &mut Vec<Vector<D>>| {
        let (pts, n) = intersection_points(s);
        out.extend_from_slice(&pts[..n]);
    };
    let Some(j) = j else {
        // Corners: the floor with D − 1 walls of different axes (2D: one wall).
        if D == 2 {
            for w in &walls {
                let mut s = [floor; D];
                s[1] = *w;
                corner_point(&s, out);
            }
        } else if walls.len() == 4 {
            for a in 0..2 {
                for b in 2..4 {
                    let mut s = [floor; D];
                    s[1] = walls[a];
                    s[D - 1] = walls[b];
                    corner_point(&s, out);
                }
            }
        }
        return;
    };
    let cj = terrain.centres[j as usize];
    let ball_j = Surface::Ball {
        centre: cj,
        radius: r + terrain.radii[j as usize],
    };
    if D == 2 {
        let mut s = [floor; D];
        s[1] = ball_j;
        push_points(&s, out);
        return;
    }
    // 3D: particle j with a wall, or with a neighbour (periodic images included).
    for w in &walls {
        let mut s = [floor; D];
        s[1] = ball_j;
        s[D - 1] = *w;
        push_points(&s, out);
    }
    // Neighbours on the floor that a particle of radius `r` touching `j` could
    // also touch: centres within `2 r + r_j` of `j`'s, widened by their own radius.
    let (mut lo, mut hi) = (cj, cj);
    lo[D - 1] = 0.0;
    hi[D - 1] = 0.0;
    let mut others = Vec::new();
    terrain.grid.for_each_in_box(
        &lo,
        &hi,
        2.0 * r + terrain.radii[j as usize],
        |id, shift, _| {
            if id != j || shift != Vector::zero() {
                let q = terrain.centres[id as usize] + shift;
                others.push(Surface::Ball {
                    centre: q,
                    radius: r + terrain.radii[id as usize],
                });
            }
        },
    );
    for o in others {
        let mut s = [floor; D];
        s[1] = ball_j;
        s[D - 1] = o;
        push_points(&s, out);
    }
}

fn plane<const D: usize>(normal: Vector<D>, offset: Real) -> Surface<D> {
    Surface::Plane { normal, offset }
}

/// The point where `D` axis-aligned planes meet.
fn corner_point<const D: usize>(s: &[Surface<D>; D], out: &mut Vec<Vector<D>>) {
    let mut p = Vector::<D>::zero();
    for surf in s {
        if let Surface::Plane { normal, offset } = surf {
            // Axis-aligned unit normal: the coordinate is ±offset on its axis.
            for k in 0..D {
                if normal[k] != 0.0 {
                    p[k] = offset / normal[k];
                }
            }
        }
    }
    out.push(p);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::species::{Shape, SizeDist, Species};

    fn species(radius: Real, ratio: Real) -> Species {
        Species {
            name: format!("r{radius}"),
            shape: Shape::Sphere,
            size: SizeDist::Fixed(radius),
            ratio,
            feed: None,
        }
    }

    #[test]
    fn patience_is_ten_footprints_of_the_smallest_radius_drawn() {
        // Floor 400 x 400: 400 footprints of radius 10 (20 x 20), 16 of radius 50.
        let floor = 400.0 * 400.0;
        let mix = [species(50.0, 1.0), species(10.0, 6.0)];
        assert_eq!(random_phase_patience::<3>(&mix, floor), 4000);
        // In 2D the floor is a length: 400 / 20 = 20 footprints.
        assert_eq!(random_phase_patience::<2>(&mix, 400.0), 200);
        // A ratio of 0 is never drawn; a share of 1e-3 still is, often enough.
        let few = [species(50.0, 1.0), species(10.0, 1e-3), species(1.0, 0.0)];
        assert_eq!(random_phase_patience::<3>(&few, floor), 4000);
    }

    #[test]
    fn a_species_not_drawn_once_in_the_patience_sets_no_scale() {
        let floor = 400.0 * 400.0;
        // Share 1e-99 of radius 10: 4000 tries would draw it 4e-96 times.
        let rare = [species(50.0, 1e100), species(10.0, 1.0)];
        assert_eq!(random_phase_patience::<3>(&rare, floor), 160);
        // Nothing qualifies (a floor smaller than any footprint, many species):
        // the largest radius, the shortest wait.
        let tiny: Vec<Species> = (1..=20).map(|k| species(100.0 * k as Real, 1.0)).collect();
        assert_eq!(random_phase_patience::<3>(&tiny, 1.0), 10);
    }
}
