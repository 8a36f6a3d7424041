//! Random sequential addition (RSA): particles at uniform random points in the
//! box, no gravity, never moving, overlaps rejected, until saturation: no point
//! of the box can take another particle of the smallest size.
//!
//! Two phases, one random process:
//! 1. Blind trials: a centre uniform over the box shrunk by the smallest radius
//!    `r_min`, a species and radius drawn as usual; kept when it fits (inside
//!    the box, no overlap). Cheap while the box is open.
//! 2. Once most trials fail, the exclusion-region phase (Zhang & Torquato 2013,
//!    see `voxels`): the space where the smallest particle still fits is kept
//!    on voxels, trial centres are drawn only there, and voxels are refined
//!    until none is left. Sampling only where something may fit leaves the
//!    process unchanged; its cost stays near linear in the box.
//!
//! Several species or a size distribution: saturation means no room for the
//! smallest radius the species can produce. In phase 2, a trial centre with room
//! for the smallest particle always receives one: the drawn particle if it fits,
//! else a species and radius redrawn among those that fit there. (Without this a
//! distribution whose smallest sizes are rare would need endless trials.) With
//! one size the two phases are exactly the classic RSA process.

mod voxels;

use crate::bed::Bed;
use crate::config::{Fill, Plan};
use crate::container::Container;
use crate::deposit::{DepositReport, Progress, RunRng};
use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::math::{Real, Vector};
use crate::species::{Shape, SizeDist, Species, SpeciesPicker};
use rand::{RngExt, SeedableRng};
use std::time::Instant;
use voxels::{covered, nearest2, Ball, Lattice, Voxels};

/// Blind trials are counted in windows of this many; the exclusion-region phase
/// starts after the first window in which fewer than [`SWITCH_SUCCESS`] of them
/// placed a particle.
const WINDOW: u64 = 4096;
/// Success fraction of blind trials below which the voxels take over.
const SWITCH_SUCCESS: Real = 0.05;
/// Side of the first voxels relative to the smallest radius.
const VOXEL_SIDE: Real = 0.5;
/// Most voxels of the first lattice (one bit each while it is built; indices
/// are `u32`).
const MAX_VOXELS: usize = 1 << 28;
/// On the first lattice, rounds of trials go on while each round leaves fewer
/// than this fraction of the voxels it started with.
const LATTICE_SHRINK: Real = 0.9;
/// Trials per voxel in one round (on the first lattice) or at one level (below).
const TRIALS_PER_VOXEL: Real = 0.25;
/// Voxels are refined down to this side relative to the smallest radius; what
/// is left then is tested at each voxel's centre (any space missed is below
/// `1e-10` of a radius across).
const SMALLEST_VOXEL: Real = 1e-10;

/// The grid is first refitted to the radii placed at this bed size, then at
/// every doubling.
const FIRST_REGRID: usize = 4096;

/// Builds an RSA bed for a validated plan.
pub fn rsa<const D: usize>(
    plan: &Plan<D>,
    progress: &mut Progress,
) -> Result<(Bed<D>, DepositReport)> {
    let started = Instant::now();
    let mut run = Rsa::new(plan)?;
    run.blind(progress);
    run.exclusion_regions(progress);
    if run.stopped {
        return Err(Error::Interrupted);
    }
    let _ = progress(run.bed.len() as u64);
    let report = DepositReport {
        dropped: run.bed.len() as u64,
        deposit_seconds: started.elapsed().as_secs_f64(),
        ..DepositReport::default()
    };
    Ok((run.bed, report))
}

/// The state of one RSA run.
struct Rsa<'p, const D: usize> {
    species: &'p [Species],
    container: Container<D>,
    bed: Bed<D>,
    grid: Grid<D>,
    picker: SpeciesPicker,
    rng: RunRng,
    /// Smallest and largest radius any species can produce.
    r_min: Real,
    r_max: Real,
    /// Centres of the smallest particle lie in `[lo, hi]`.
    lo: Vector<D>,
    hi: Vector<D>,
    /// Particles to place at most.
    target: u64,
    /// Bed size at which the grid is next refitted to the radii placed.
    regrid_at: usize,
    /// The caller asked to stop (its progress broke): the bed counts as full.
    stopped: bool,
}

impl<'p, const D: usize> Rsa<'p, D> {
    fn new(plan: &'p Plan<D>) -> Result<Self> {
        if plan
            .species
            .iter()
            .any(|s| matches!(s.shape, Shape::Chain { .. }))
        {
            return Err(Error::Impossible(
                "random sequential addition of chains is not implemented (spheres and discs only)"
                    .into(),
            ));
        }
        let (r_min, r_max) = plan
            .species
            .iter()
            .map(|s| s.size.bounds())
            .fold((Real::INFINITY, 0.0 as Real), |(a, b), (lo, hi)| {
                (a.min(lo), b.max(hi))
            });
        let container = plan.container;
        let (mut lo, mut hi) = (Vector::zero(), container.size);
        for k in 0..D {
            if !(container.periodic && k < D - 1) {
                lo[k] = r_min;
                hi[k] = container.size[k] - r_min;
            }
        }
        if (0..D).any(|k| hi[k] < lo[k]) {
            return Err(Error::Impossible(format!(
                "the box has no room for a particle of radius {r_min}"
            )));
        }
        let target = match plan.fill {
            Fill::Count(n) => n,
            Fill::Roof { .. } => u64::MAX,
        };
        let mut bed = Bed::new(container, plan.species.clone());
        let mut grid = Grid::for_particles(
            &container,
            &super::grid_levels::<D>(&plan.species),
            plan.estimated_particles() as usize,
        );
        if let Fill::Count(n) = plan.fill {
            let n = n as usize;
            bed.centres.reserve_exact(n);
            bed.radii.reserve_exact(n);
            bed.species.reserve_exact(n);
            bed.bodies.reserve_exact(n);
            grid.reserve(n);
        }
        Ok(Rsa {
            species: &plan.species,
            container,
            bed,
            grid,
            picker: SpeciesPicker::new(&plan.species),
            rng: RunRng::seed_from_u64(plan.seed),
            r_min,
            r_max,
            lo,
            hi,
            target,
            regrid_at: FIRST_REGRID,
            stopped: false,
        })
    }

    fn full(&self) -> bool {
        self.stopped || self.bed.len() as u64 >= self.target
    }

    /// True when a particle of radius `r` centred at `p` lies inside the box and
    /// overlaps no particle (touching is allowed).
    #[inline]
    fn fits(&self, p: &Vector<D>, r: Real) -> bool {
        let c = &self.container;
        for k in 0..D {
            if !(c.periodic && k < D - 1) && (p[k] < r || p[k] > c.size[k] - r) {
                return false;
            }
        }
        !self.grid.any_in_box(p, p, r, |j, shift, _| {
            let d = *p - (self.bed.centres[j as usize] + shift);
            let s = r + self.bed.radii[j as usize];
            d.norm2() < s * s
        })
    }

    /// The largest radius, up to `cap`, of a particle that fits centred at `p`.
    /// Searched outwards from twice the smallest radius: near saturation the
    /// answer is small, and a search as wide as `cap` (70 smallest radii with
    /// radii 70 and 2) visited tens of thousands of particles per trial.
    fn room(&self, p: &Vector<D>, cap: Real) -> Real {
        let c = &self.container;
        let mut cap = cap;
        for k in 0..D {
            if !(c.periodic && k < D - 1) {
                cap = cap.min(p[k]).min(c.size[k] - p[k]);
            }
        }
        let mut reach = cap.min(2.0 * self.r_min);
        loop {
            let mut room = reach;
            self.grid.for_each_in_box(p, p, reach, |j, shift, _| {
                let d = *p - (self.bed.centres[j as usize] + shift);
                room = room.min(d.norm() - self.bed.radii[j as usize]);
            });
            // A particle the search missed is at least `reach` away, so a
            // room below it is the room within `cap`.
            if room < reach || reach >= cap || reach <= 0.0 {
                return room;
            }
            reach = cap.min(4.0 * reach);
        }
    }

    /// Adds a particle (its centre wrapped into the box on periodic axes).
    fn place(&mut self, p: Vector<D>, r: Real, species: u32, progress: &mut Progress) {
        let p = self.container.wrap(p);
        let id = self.bed.len() as u32;
        self.grid.insert(id, &p, r);
        self.bed.push(p, r, species);
        if self.bed.len() >= self.regrid_at {
            self.regrid();
        }
        if self.bed.len().is_multiple_of(4096) && progress(self.bed.len() as u64).is_break() {
            self.stopped = true;
        }
    }

    /// Refits the grid's levels to the radii the bed holds. They were planned
    /// from the radii drawn, but RSA rejects sizes unequally: with radii 70
    /// and 2 in a box 140 wide, half the draws are 70 and almost none of
    /// them fits, and cells planned for that mix were 28 small diameters wide.
    /// Refitting at every doubling of the bed keeps the cost linear; the
    /// searches' answers do not depend on the grid, so neither does the bed.
    fn regrid(&mut self) {
        self.grid = Grid::of_particles(
            &self.container,
            &self.bed.centres,
            &self.bed.radii,
            self.r_max,
        );
        self.regrid_at = self.bed.len().saturating_mul(2);
    }

    /// Draws the species and radius of the next particle.
    fn draw_particle(&mut self) -> (u32, Real) {
        let s = self.picker.pick(&mut self.rng);
        let r = self.species[s].size.sample(&mut self.rng);
        (s as u32, r)
    }

    /// A uniformly random point of the box `[lo, lo + side]`.
    #[inline]
    fn point_in(&mut self, lo: &Vector<D>, side: &Vector<D>) -> Vector<D> {
        let mut p = *lo;
        for k in 0..D {
            let u: Real = self.rng.random();
            p[k] += side[k] * u;
        }
        p
    }

    /// Phase 1: blind trials until most of them fail.
    fn blind(&mut self, progress: &mut Progress) {
        let (lo, side) = (self.lo, self.hi - self.lo);
        let needed = (WINDOW as Real * SWITCH_SUCCESS).ceil() as u64;
        while !self.full() {
            let mut placed = 0;
            for _ in 0..WINDOW {
                let p = self.point_in(&lo, &side);
                let (s, r) = self.draw_particle();
                if self.fits(&p, r) {
                    self.place(p, r, s, progress);
                    placed += 1;
                    if self.full() {
                        return;
                    }
                }
            }
            if placed < needed {
                return;
            }
        }
    }

    /// One trial of phase 2 at `p`: the drawn particle if it fits, else one
    /// redrawn among the species and sizes that fit there, if any does.
    fn trial(&mut self, p: Vector<D>, progress: &mut Progress) {
        let (s, r) = self.draw_particle();
        if self.fits(&p, r) {
            self.place(p, r, s, progress);
            return;
        }
        if r == self.r_min {
            return;
        }
        let room = self.room(&p, self.r_max);
        if room < self.r_min {
            return;
        }
        let (s, r) = self.draw_fitting(room);
        // `room` comes from square roots; keep the exact test the last word.
        if self.fits(&p, r) {
            self.place(p, r, s, progress);
        }
    }

    /// A species (by ratio, among those whose smallest size is at most `room`)
    /// and a radius of it at most `room`.
    fn draw_fitting(&mut self, room: Real) -> (u32, Real) {
        let total: Real = self
            .species
            .iter()
            .filter(|s| s.size.bounds().0 <= room)
            .map(|s| s.ratio)
            .sum();
        let mut u: Real = self.rng.random::<Real>() * total;
        let mut chosen = None;
        for (i, s) in self.species.iter().enumerate() {
            if s.size.bounds().0 <= room && s.ratio > 0.0 {
                chosen = Some(i);
                if u < s.ratio {
                    break;
                }
                u -= s.ratio;
            }
        }
        // A species with a zero ratio is never drawn; if only such species fit,
        // fall back to the smallest size of all.
        let Some(i) = chosen else {
            let (i, _) = self
                .species
                .iter()
                .enumerate()
                .min_by(|a, b| a.1.size.bounds().0.total_cmp(&b.1.size.bounds().0))
                .expect("at least one species");
            return (i as u32, self.r_min);
        };
        (
            i as u32,
            sample_at_most(&self.species[i].size, room, &mut self.rng),
        )
    }

    /// Phase 2: trials only in voxels that may hold available space, refined
    /// level by level until none is left.
    fn exclusion_regions(&mut self, progress: &mut Progress) {
        if self.full() {
            return;
        }
        let mut wrap = [false; D];
        for w in wrap.iter_mut().take(D - 1) {
            *w = self.container.periodic;
        }
        let lattice = Lattice::new(self.lo, self.hi, VOXEL_SIDE * self.r_min, MAX_VOXELS, wrap);
        let mut mask = vec![0u64; lattice.len().div_ceil(64)];
        for (c, &r) in self.bed.centres.iter().zip(&self.bed.radii) {
            lattice.mark_covered(c, r + self.r_min, &mut mask);
        }
        let mut flat = lattice.uncovered(&mask);
        // On the first lattice, new particles are cheap to mark: repeat trials
        // there for as long as they clear voxels fast, then refine.
        loop {
            let n = flat.len();
            if n == 0 {
                return;
            }
            let before = self.bed.len();
            let trials = (TRIALS_PER_VOXEL * n as Real).ceil() as usize;
            for _ in 0..trials {
                let i = self.rng.random_range(0..n);
                let p = self.point_in(&lattice.corner(flat[i] as usize), &lattice.side);
                self.trial(p, progress);
                if self.full() {
                    return;
                }
            }
            for i in before..self.bed.len() {
                lattice.mark_covered(
                    &self.bed.centres[i],
                    self.bed.radii[i] + self.r_min,
                    &mut mask,
                );
            }
            flat.retain(|&f| !Lattice::<D>::is_marked(&mask, f as usize));
            if flat.len() as Real > LATTICE_SHRINK * n as Real {
                break;
            }
        }
        drop(mask);
        let mut voxels = Voxels {
            side: lattice.side,
            corners: flat.iter().map(|&f| lattice.corner(f as usize)).collect(),
        };
        drop(flat);
        let smallest = SMALLEST_VOXEL * self.r_min;
        let mut balls = Vec::new();
        while !voxels.corners.is_empty() && !self.full() {
            let n = voxels.corners.len();
            let trials = (TRIALS_PER_VOXEL * n as Real).ceil() as usize;
            for _ in 0..trials {
                let i = self.rng.random_range(0..n);
                let p = self.point_in(&voxels.corners[i], &voxels.side);
                self.trial(p, progress);
                if self.full() {
                    return;
                }
            }
            if (0..D).all(|k| voxels.side[k] <= smallest) {
                // Below any size that matters: one last look at each centre.
                for i in 0..voxels.corners.len() {
                    let p = voxels.corners[i] + voxels.side * 0.5;
                    self.trial(p, progress);
                    if self.full() {
                        return;
                    }
                }
                return;
            }
            voxels = self.refine(&voxels, &mut balls);
        }
    }

    /// Splits every voxel into `2^D` children and keeps those no single
    /// exclusion ball holds whole.
    fn refine(&self, voxels: &Voxels<D>, balls: &mut Vec<Ball<D>>) -> Voxels<D> {
        let side = voxels.side * 0.5;
        let mut corners = Vec::with_capacity(voxels.corners.len() * 2);
        for corner in &voxels.corners {
            // The balls that meet this voxel: only they can hold a child.
            balls.clear();
            // A ball holding a child holds both ends of the child along every
            // axis, so its centre lies within its radius plus `r_min` of the
            // voxel's middle, where the children meet (the grid widens the
            // point by each level's radius). Searching only within reach of
            // both ends of the whole voxel, as before, missed balls holding a
            // child: harmless while cells were wide, a child kept that a ball
            // holds is only sampled in vain, but it made the trials depend on
            // the grid.
            let middle = *corner + voxels.side * 0.5;
            self.grid
                .for_each_in_box(&middle, &middle, self.r_min, |j, shift, _| {
                    let centre = self.bed.centres[j as usize] + shift;
                    let rr = self.bed.radii[j as usize] + self.r_min;
                    if nearest2(corner, &voxels.side, &centre) < rr * rr {
                        balls.push(Ball {
                            centre,
                            radius2: rr * rr,
                        });
                    }
                });
            if covered(corner, &voxels.side, balls) {
                continue;
            }
            for child in 0..1usize << D {
                let mut c = *corner;
                for k in 0..D {
                    if child >> k & 1 == 1 {
                        c[k] += side[k];
                    }
                }
                if !covered(&c, &side, balls) {
                    corners.push(c);
                }
            }
        }
        Voxels { side, corners }
    }
}

/// A radius from `size` conditioned to be at most `room` (which is at least the
/// distribution's smallest radius). Drawn by rejection; where the distribution
/// has almost no mass below `room`, the radius is taken uniformly between its
/// smallest value and `room` (a table picks among its radii that fit, by weight).
fn sample_at_most(size: &SizeDist, room: Real, rng: &mut RunRng) -> Real {
    for _ in 0..64 {
        let r = size.sample(rng);
        if r <= room {
            return r;
        }
    }
    let (lo, hi) = size.bounds();
    match size {
        SizeDist::Fixed(r) => *r,
        SizeDist::Table(t) => t.sample_at_most(room, rng).unwrap_or(lo),
        _ => {
            let top = room.min(hi);
            let u: Real = rng.random();
            (lo + (top - lo) * u).clamp(lo, top)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;
    use rand::RngExt;

    fn plan(text: &str) -> Plan<3> {
        Config::from_toml(text, "test")
            .unwrap()
            .plan::<3>()
            .unwrap()
    }

    const MIX: &str = "dim = 3\nmode = \"rsa\"\n[box]\nwidth = 140\nheight = 300\n\
        [fill]\ncount = 20000\n\
        [[species]]\nradius = 70\n[[species]]\nradius = 2\n";

    #[test]
    fn the_grid_is_refit_to_the_radii_placed() {
        let plan = plan(MIX);
        let mut run = Rsa::new(&plan).unwrap();
        // Planned from the draws, half of them radius 70, the small spheres'
        // cells are many diameters wide.
        assert!(run.grid.cell_width_for(2.0) > 40.0);
        run.blind(&mut |_| std::ops::ControlFlow::Continue(()));
        assert!(run.bed.len() >= FIRST_REGRID);
        assert!(run.bed.radii.iter().filter(|&&r| r == 2.0).count() > run.bed.len() - 5);
        let cell = run.grid.cell_width_for(2.0);
        assert!((4.0..8.0).contains(&cell), "cell {cell}");
    }

    #[test]
    fn refining_keeps_exactly_the_children_no_ball_holds() {
        for text in [
            MIX,
            "dim = 3\nmode = \"rsa\"\n[box]\nwidth = 50\nheight = 50\n\
                      [fill]\ncount = 3000\n[[species]]\nradius = 3\n",
        ] {
            let plan = plan(text);
            let mut run = Rsa::new(&plan).unwrap();
            run.blind(&mut |_| std::ops::ControlFlow::Continue(()));
            let mut rng = RunRng::seed_from_u64(11);
            let side = Vector([run.r_min * 0.5; 3]);
            let corners: Vec<Vector<3>> = (0..3000)
                .map(|_| {
                    let (lo, hi) = (run.lo, run.hi - side);
                    Vector([0, 1, 2].map(|k| rng.random_range(lo[k]..hi[k])))
                })
                .collect();
            let voxels = Voxels { side, corners };
            let kept = run.refine(&voxels, &mut Vec::new());
            // Every ball meeting the voxel, found without the grid.
            let mut want = Vec::new();
            for corner in &voxels.corners {
                let balls: Vec<Ball<3>> = (0..run.bed.len())
                    .map(|j| (run.bed.centres[j], run.bed.radii[j] + run.r_min))
                    .filter(|(c, rr)| nearest2(corner, &side, c) < rr * rr)
                    .map(|(centre, rr)| Ball {
                        centre,
                        radius2: rr * rr,
                    })
                    .collect();
                if covered(corner, &side, &balls) {
                    continue;
                }
                for child in 0..8usize {
                    let c = Vector([0, 1, 2].map(|k| {
                        corner[k]
                            + if child >> k & 1 == 1 {
                                side[k] * 0.5
                            } else {
                                0.0
                            }
                    }));
                    if !covered(&c, &(side * 0.5), &balls) {
                        want.push(c);
                    }
                }
            }
            assert!(
                want.len() < 8 * voxels.corners.len(),
                "some children are held"
            );
            assert_eq!(kept.corners, want);
        }
    }

    #[test]
    fn room_is_the_gap_to_the_nearest_surface_or_wall() {
        let plan = plan(MIX);
        let mut run = Rsa::new(&plan).unwrap();
        run.blind(&mut |_| std::ops::ControlFlow::Continue(()));
        let mut rng = RunRng::seed_from_u64(7);
        let size = run.container.size;
        for _ in 0..2000 {
            let p = Vector([
                rng.random_range(2.0..138.0),
                rng.random_range(2.0..138.0),
                rng.random_range(2.0..298.0),
            ]);
            let cap = [70.0, 5.0, 0.5][rng.random_range(0..3)];
            let mut want: Real = cap;
            for k in 0..3 {
                want = want.min(p[k]).min(size[k] - p[k]);
            }
            for (c, r) in run.bed.centres.iter().zip(&run.bed.radii) {
                want = want.min((p - *c).norm() - r);
            }
            assert_eq!(run.room(&p, cap), want, "at {p:?}, cap {cap}");
        }
    }
}
