//! Sequential deposition: particles settle one at a time under gravity onto the
//! bed already there (the drop-and-roll model of `docs/reference/model.md`).

mod arc_search;
mod base_layer;
mod body;
pub mod chain;
pub mod compaction;
pub(crate) mod obstacle;
pub(crate) mod roll;
pub mod rsa;
mod rule;
mod speculate;
mod trail;

use crate::bed::{AnyBed, Bed, Filtrate};
use crate::config::{AnyPlan, BaseLayerKind, Config, Fill, Mode, Plan, Settling};
use crate::error::{Error, Result};
use crate::grid::{Grid, Levels};
use crate::math::{ball_volume, Real, Vector};
use crate::species::{EntryOrientation, Shape, Species, SpeciesPicker};
use body::{Chain, Dropper, Sphere};
use chain::ChainShape;
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;
use roll::Terrain;
use std::ops::ControlFlow;
use std::time::Instant;

pub use body::{drop_onto, Entry};

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
    /// Moves of every dropped body, re-drops included: straight falls and
    /// rolls along an arc (spheres), steps of the descent (chains). The cost of
    /// a bed is about its moves times the cost of one move.
    pub moves: u64,
    /// Wall time of deposition in seconds.
    pub deposit_seconds: f64,
    /// The bodies that passed the filter medium through the open floor, in
    /// the order they were fed (empty without a medium).
    pub filtrate: Vec<Filtrate>,
    /// How far the medium was lifted above the open floor (0 without one).
    pub medium_lift: Real,
    /// What the compaction after settling did (none without `[compaction]`).
    pub compaction: Option<compaction::CompactionReport>,
}

/// Re-drops of one particle after which the run gives up (never seen in practice).
const MAX_REDROPS_PER_PARTICLE: u32 = 1000;

/// The random generator of a run.
pub type RunRng = Xoshiro256PlusPlus;

/// What a build reports its progress to: called now and then with the number
/// of particles placed so far; [`ControlFlow::Break`] asks the build to stop
/// (Ctrl-C in Python), which then fails with [`Error::Interrupted`].
pub type Progress<'a> = dyn FnMut(u64) -> ControlFlow<()> + 'a;

/// The deposition engine for one bed.
struct Engine<'p, const D: usize> {
    plan: &'p Plan<D>,
    bed: Bed<D>,
    grid: Grid<D>,
    /// The feed being placed: its species (a draw's index into `picks`),
    /// how they settle, and the bed's size when it is done.
    picker: SpeciesPicker,
    picks: Vec<u32>,
    settling: Settling,
    feed_end: u64,
    /// A feed by mass: the solid volume it feeds (infinite for a feed by
    /// count), and the volume fed so far, placed or passed.
    feed_volume_end: Real,
    feed_volume: Real,
    /// Beads fed that passed the medium (they count toward the feeds'
    /// counts but are not in the bed).
    passed_beads: u64,
    /// True once the floor under the medium is open.
    open_floor: bool,
    rng: RunRng,
    report: DepositReport,
}

impl<'p, const D: usize> Engine<'p, D> {
    fn new(plan: &'p Plan<D>) -> Result<Self> {
        let grid = Grid::for_particles(
            &plan.container,
            &grid_levels::<D>(&plan.species),
            plan.estimated_particles() as usize,
        );
        let mut engine = Engine {
            plan,
            bed: Bed::new(plan.container, plan.species.clone()),
            grid,
            picker: SpeciesPicker::new(&plan.species),
            picks: (0..plan.species.len() as u32).collect(),
            settling: plan.settling,
            feed_end: match plan.fill {
                Fill::Count(n) => n,
                Fill::Roof { .. } => u64::MAX,
            },
            feed_volume_end: Real::INFINITY,
            feed_volume: 0.0,
            passed_beads: 0,
            open_floor: false,
            rng: RunRng::seed_from_u64(plan.seed),
            report: DepositReport::default(),
        };
        engine.start_feed(0);
        Ok(engine)
    }

    /// Makes feed `k` of `[[feeds]]` the one being placed (nothing without
    /// the table: one feed of every species, as `new` set it).
    fn start_feed(&mut self, k: usize) {
        let Some(feed) = self.plan.feeds.get(k) else {
            return;
        };
        let species: Vec<Species> = feed
            .species
            .iter()
            .map(|&s| self.plan.species[s as usize].clone())
            .collect();
        self.picker = SpeciesPicker::new(&species);
        self.picks = feed.species.clone();
        self.settling = feed.settling;
        // The feeds before it end where they ended: a feed by count at its
        // count (a chain may pass it by a few beads), a feed by mass where
        // its mass was reached.
        let before = if k == 0 {
            0
        } else {
            self.feed_end.min(self.fed())
        };
        (self.feed_end, self.feed_volume_end) = match feed.volume {
            Some(v) => (u64::MAX, v),
            None => (before + feed.count, Real::INFINITY),
        };
        self.feed_volume = 0.0;
        if !feed.medium && k > 0 && self.plan.feeds[k - 1].medium {
            self.open_the_floor();
        }
    }

    /// Lifts the medium built so far by [`Plan::medium_gap`] and opens the
    /// floor: a later body that reaches the floor has fallen clear of the
    /// medium (the gap holds the longest of them), and leaves as filtrate.
    fn open_the_floor(&mut self) {
        let lift = self.plan.medium_gap();
        for c in &mut self.bed.centres {
            c[D - 1] += lift;
        }
        self.grid = Grid::for_particles(
            &self.plan.container,
            &grid_levels::<D>(&self.plan.species),
            self.plan.estimated_particles() as usize,
        );
        for (id, (c, &r)) in self.bed.centres.iter().zip(&self.bed.radii).enumerate() {
            self.grid.insert(id as u32, c, r);
        }
        self.open_floor = true;
        self.report.medium_lift = lift;
    }

    /// Beads fed so far: those in the bed and those that passed the medium.
    fn fed(&self) -> u64 {
        self.bed.len() as u64 + self.passed_beads
    }

    fn terrain(&self) -> Terrain<'_, D> {
        Terrain::of(&self.plan.container, &self.grid, &self.bed)
    }

    /// Draws the species and radius of the next particle.
    fn draw_particle(&mut self) -> (u32, Real) {
        draw(&self.picker, &self.picks, &self.plan.species, &mut self.rng)
    }

    /// Adds all beads of a body at `pose` as one new body.
    fn place_body<B: Dropper<D>>(&mut self, body: &B, pose: &B::Pose, species: u32) {
        let id = self.bed.bodies.last().map_or(0, |&b| b + 1);
        for k in 0..body.beads() {
            self.place_bead(body.bead(pose, k), body.radius(), species, id);
        }
    }

    /// The chain shape of species `s` with bead radius `r`, if it is a chain.
    fn chain_of(&self, s: u32, r: Real) -> Option<(ChainShape, EntryOrientation)> {
        match self.plan.species[s as usize].shape {
            Shape::Sphere => None,
            Shape::Chain {
                beads,
                spacing,
                orientation,
            } => Some((ChainShape { beads, spacing, r }, orientation)),
        }
    }

    /// Adds a particle to the bed (wrapping periodic coordinates into the box).
    fn place_bead(&mut self, p: Vector<D>, r: Real, species: u32, body: u32) {
        let p = self.plan.container.wrap(p);
        let id = self.bed.len() as u32;
        self.grid.insert(id, &p, r);
        self.bed.push_bead(p, r, species, body);
    }

    /// The bed's size when the feed being placed is done.
    fn target(&self) -> u64 {
        self.feed_end
    }

    /// True while the feed being placed has more to feed: its count or
    /// its mass not yet reached.
    fn feeding(&self) -> bool {
        self.fed() < self.feed_end && self.feed_volume < self.feed_volume_end
    }

    /// Deposits the bed; spheres in speculative batches when `speculate`
    /// (the same bed either way).
    fn run(mut self, progress: &mut Progress, speculate: bool) -> Result<(Bed<D>, DepositReport)> {
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
            self.base_layer(speculate);
        }
        let mut batches = speculate.then(speculate::Batches::new);
        for k in 0..self.plan.feeds.len().max(1) {
            self.start_feed(k);
            if let Some(mesh) = self.plan.feeds.get(k).and_then(|f| f.mesh) {
                self.lay_mesh(&mesh, k);
                continue;
            }
            if self.plan.feeds.get(k).is_some_and(|f| f.file.is_some()) {
                self.lay_file(k)?;
                continue;
            }
            if !self.place_feed(&mut batches, progress)? {
                break;
            }
        }
        let _ = progress(self.bed.len() as u64);
        self.report.deposit_seconds = started.elapsed().as_secs_f64();
        Ok((self.bed, self.report))
    }

    /// Lays the wires of feed `k`, a woven mesh, on the floor: placed where
    /// the mesh says, not dropped (a filter's mesh is held fixed).
    fn lay_mesh(&mut self, mesh: &crate::config::Mesh, k: usize) {
        let c = self.plan.container;
        let wires = mesh
            .wires(&c, "")
            .expect("the plan checked the mesh against its box");
        for (family, &s) in wires.iter().zip(&self.plan.feeds[k].species) {
            for beads in mesh.bodies::<D>(family) {
                let id = self.bed.bodies.last().map_or(0, |&b| b + 1);
                for p in beads {
                    self.place_bead(p, mesh.r, s, id);
                }
            }
        }
    }

    /// Places the particles of feed `k`, a medium read from a bed file, as
    /// the file has them: each body of the file one body of the bed (the
    /// plan checked them against the box and each other when it read them).
    fn lay_file(&mut self, k: usize) -> Result<()> {
        let beads = self.plan.feeds[k]
            .file
            .as_ref()
            .and_then(|f| f.beads.clone())
            .ok_or_else(|| {
                Error::config(format!(
                    "feeds[{k}].file: the medium's bed file was not read: plan the run with `planned` (the front door's), which reads it, not with `Config::plan` alone"
                ))
            })?;
        let first = self.bed.bodies.last().map_or(0, |&b| b + 1);
        for i in 0..beads.radii.len() {
            let mut p = Vector::<D>::zero();
            for a in 0..D {
                p[a] = beads.centres[i][a];
            }
            self.place_bead(p, beads.radii[i], beads.species[i], first + beads.bodies[i]);
        }
        Ok(())
    }

    /// Places the feed being placed, up to [`Engine::target`]; false if the
    /// bed filled up first (its roof overflowed).
    fn place_feed(
        &mut self,
        batches: &mut Option<speculate::Batches<D>>,
        progress: &mut Progress,
    ) -> Result<bool> {
        while self.feeding() {
            if let Some(batches) = batches.as_mut() {
                match self.drop_batch(batches, progress)? {
                    speculate::Ended::Placed { more: true } => continue,
                    speculate::Ended::Placed { more: false } => return Ok(false),
                    speculate::Ended::Chain => {}
                }
            }
            let (s, r) = self.draw_particle();
            let more = match self.chain_of(s, r) {
                Some((shape, orientation)) => {
                    self.drop_body(&Chain { shape, orientation }, s, progress)?
                }
                None => self.drop_body(&Sphere(r), s, progress)?,
            };
            if !more {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Drops one body of species `s` until it rests, and adds it to the bed
    /// unless it sticks out above the roof. Returns false when the roof has
    /// been overflowed more often than the fill allows: the bed is full.
    fn drop_body<B: Dropper<D>>(
        &mut self,
        body: &B,
        s: u32,
        progress: &mut Progress,
    ) -> Result<bool> {
        let pose = self.find_rest(body, None)?;
        self.keep_body(body, &pose, s, progress)
    }

    /// Drops `body` until it rests. `first` is the outcome of a drop already
    /// made, with the generator standing after it.
    fn find_rest<B: Dropper<D>>(
        &mut self,
        body: &B,
        mut first: Option<Option<B::Pose>>,
    ) -> Result<B::Pose> {
        let mut tries = 0;
        loop {
            let settled = match first.take() {
                Some(settled) => settled,
                None => {
                    let start = body.enter(&self.plan.container, &self.plan.feed, &mut self.rng);
                    self.settle_from(body, start)
                }
            };
            if let Some(p) = settled {
                return Ok(p);
            }
            self.report.redrops += 1;
            tries += 1;
            if tries >= MAX_REDROPS_PER_PARTICLE {
                return Err(Error::Impossible(match self.settling.momentum {
                    // Not the geometry: an energy that impacts barely drain
                    // outlasts the move budget on every drop.
                    Some(m) => format!(
                        "{} under the momentum rule (restitution {}, sliding friction {}): its energy outlasts {} moves; lower `restitution` or `drop_height`, or add `sliding_friction`",
                        body.stuck(tries),
                        m.restitution,
                        m.sliding_friction,
                        roll::MAX_MOVES
                    ),
                    None => body.stuck(tries),
                }));
            }
        }
    }

    /// Settles `body` from `start` on the bed as it is, with the run's generator.
    fn settle_from<B: Dropper<D>>(&mut self, body: &B, start: B::Pose) -> Option<B::Pose> {
        let terrain = Terrain::of(&self.plan.container, &self.grid, &self.bed);
        body.settle(
            &terrain,
            start,
            &self.settling,
            &mut self.rng,
            &mut self.report.moves,
        )
    }

    /// Adds a body at rest to the bed unless it sticks out above the roof.
    /// Returns false when the roof has been overflowed more often than the
    /// fill allows: the bed is full.
    fn keep_body<B: Dropper<D>>(
        &mut self,
        body: &B,
        pose: &B::Pose,
        s: u32,
        progress: &mut Progress,
    ) -> Result<bool> {
        self.feed_volume += Real::from(body.beads()) * ball_volume::<D>(body.radius());
        if self.open_floor {
            // Bodies held by the medium stand above half the gap, bodies on
            // the floor below it (`Plan::medium_gap`): no tolerance is needed.
            let half_gap = 0.5 * self.report.medium_lift;
            let lowest = (0..body.beads())
                .map(|k| body.bead(pose, k))
                .min_by(|a, b| a[D - 1].total_cmp(&b[D - 1]))
                .unwrap_or(Vector::zero());
            if lowest[D - 1] - body.radius() < half_gap {
                let at = self.plan.container.wrap(lowest);
                let mut xy = [0.0; 2];
                for (k, x) in xy.iter_mut().enumerate().take(D - 1) {
                    *x = at[k];
                }
                self.report.filtrate.push(Filtrate {
                    species: s,
                    radius: body.radius(),
                    beads: body.beads(),
                    at: xy,
                });
                self.passed_beads += u64::from(body.beads());
                return Ok(true);
            }
        }
        if let Fill::Roof { misses } = self.plan.fill {
            let top = (0..body.beads())
                .map(|k| body.bead(pose, k)[D - 1])
                .fold(Real::NEG_INFINITY, Real::max)
                + body.radius();
            if top > self.plan.container.height() {
                self.report.roof_overflows += 1;
                return Ok(self.report.roof_overflows <= misses);
            }
        }
        let before = self.bed.len();
        self.place_body(body, pose, s);
        self.report.dropped += 1;
        if before / 4096 != self.bed.len() / 4096 && progress(self.bed.len() as u64).is_break() {
            return Err(Error::Interrupted);
        }
        Ok(true)
    }
}

/// Draws the species (one of `picks`, by `picker`) and radius of a particle
/// from `rng`.
fn draw(
    picker: &SpeciesPicker,
    picks: &[u32],
    species: &[Species],
    rng: &mut RunRng,
) -> (u32, Real) {
    let s = picks[picker.pick(rng)];
    let r = species[s as usize].size.sample(rng);
    (s, r)
}

/// The levels of the neighbour grid for the particles `species` produce: fitted
/// to a sample of the mix drawn with a generator of its own (the run's draws are
/// untouched), chains weighted by their beads.
pub(crate) fn grid_levels<const D: usize>(species: &[Species]) -> Levels {
    const SAMPLE: usize = 4096;
    let r_max = species
        .iter()
        .filter(|s| s.ratio > 0.0)
        .map(|s| s.size.bounds().1)
        .fold(0.0, Real::max);
    // The plan has ratios >= 0 summing to more than 0 (SpeciesPicker's terms).
    let picker = SpeciesPicker::new(species);
    let mut rng = RunRng::seed_from_u64(0x9e1d_5a3e);
    let sample: Vec<(Real, Real)> = (0..SAMPLE)
        .map(|_| {
            let s = &species[picker.pick(&mut rng)];
            let r = s.size.sample(&mut rng);
            let beads = Real::from(s.shape.beads());
            (r, beads)
        })
        .collect();
    Levels::for_sizes::<D>(r_max, &sample)
}

/// Builds a bed for a validated plan. `progress` is called now and then with the
/// number of particles placed so far; when it breaks, the build stops with
/// [`Error::Interrupted`].
pub fn deposit<const D: usize>(
    plan: &Plan<D>,
    progress: &mut Progress,
) -> Result<(Bed<D>, DepositReport)> {
    let (mut bed, mut report) = match plan.mode {
        Mode::Deposit if speculate::worth_it() => speculate::on_every_core(plan, progress)?,
        Mode::Deposit => Engine::new(plan)?.run(progress, false)?,
        Mode::Rsa => rsa::rsa(plan, progress)?,
    };
    if let Some(c) = &plan.compaction {
        report.compaction = Some(compaction::compact(&mut bed, c)?);
    }
    Ok((bed, report))
}

/// Builds the bed a configuration describes, in its dimension.
pub fn build(config: &Config, progress: &mut Progress) -> Result<(AnyBed, DepositReport)> {
    build_planned(&config.planned()?, progress)
}

/// [`build`] of a config planned already.
pub fn build_planned(plan: &AnyPlan, progress: &mut Progress) -> Result<(AnyBed, DepositReport)> {
    match plan {
        AnyPlan::D2(p) => deposit(p, progress).map(|(b, r)| (AnyBed::D2(b), r)),
        AnyPlan::D3(p) => deposit(p, progress).map(|(b, r)| (AnyBed::D3(b), r)),
    }
}
