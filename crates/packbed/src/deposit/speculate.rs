//! Spheres dropped side by side on every core, each result kept only where the
//! one-at-a-time engine would have found the same.
//!
//! A batch of spheres is drawn (species, radius, entry point) from a copy of
//! the run's generator, and every sphere settles on the bed as it was before
//! the batch, in parallel, noting the horizontal box of everything it asked
//! the grid; a thread done with its share while another still settles a
//! sphere of the batch takes the next draws meanwhile (up to the batch's size
//! again), which join the batch. The results are then taken in draw order.
//! Sphere `k`'s result is the one-at-a-time result when nothing placed earlier
//! in the batch lies where its queries could have used it ([`could_have_met`],
//! then, within that box, near one of the legs its centre went: see
//! [`super::trail`]) and the highest top under its entry point is unchanged;
//! otherwise it
//! settles again, alone, on the bed as it now is. A sphere whose settling
//! drew from the generator (a random tip), found no rest (a re-drop draws
//! again) or widened the grid's queries (the largest radius of its level) ends
//! the batch: the draws after it assumed otherwise. Beds, moves and draws are
//! those of the one-at-a-time engine, bit for bit, whatever the number of
//! threads (tests below, and `scripts/same-outputs.sh`). A replicate of an
//! ensemble, already one task of a parallel loop, drops one sphere at a time.

use super::body::{Dropper, Sphere};
use super::roll::{self, Terrain};
use super::trail::Leg;
use super::{DepositReport, Engine, Progress, RunRng};
use crate::bed::Bed;
use crate::config::Plan;
use crate::container::Container;
use crate::error::Result;
use crate::math::{ball_volume, Real, Vector};
use rayon::prelude::*;
use std::cell::RefCell;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Mutex};

/// A sphere drawn for a batch.
pub(super) struct Draw<const D: usize> {
    species: u32,
    r: Real,
    start: Vector<D>,
    /// The generator just after the entry point was drawn.
    rng: RunRng,
}

/// What a sphere of a batch found on the bed before the batch.
pub(super) struct Found<const D: usize> {
    rest: Option<Vector<D>>,
    /// The highest top under the entry point (where the fall starts).
    top: Real,
    /// The generator after settling (moved on only by a random tip).
    rng: RunRng,
    moves: u64,
    /// Horizontal box of every grid query (heights meaningless).
    lo: Vector<D>,
    hi: Vector<D>,
}

/// What a sphere of a batch found, and where it went (see `trail`).
#[derive(Default)]
struct Slot<const D: usize> {
    found: Option<Found<D>>,
    trail: Vec<Leg<D>>,
}

/// Batch sizes: halved while more than a quarter of a batch meets spheres
/// placed before it in the batch (a narrow box), doubled otherwise. At most
/// 16 on two cores: a larger batch keeps the helper thread asleep while it
/// is taken, and meets more of its own spheres (of 8, 12, 16, 24, 32 and 48,
/// 16 settled 10^6 spheres of radii 10 and 50 fastest).
const FIRST_BATCH: usize = 8;
const LARGEST_BATCH: usize = 16;
/// Spheres drawn for a batch, as a multiple of its size (see `drop_batch`).
const EXTRA: usize = 2;

/// The batches of one run, their buffers kept between batches.
pub(super) struct Batches<const D: usize> {
    size: usize,
    draws: Vec<Draw<D>>,
    /// One slot a draw, kept between batches (the trails' buffers with
    /// them), only ever locked by the thread settling that draw: a lock
    /// nobody waits for costs less than a `OnceLock` (2 % of a run in `perf`).
    slots: Vec<Mutex<Slot<D>>>,
    /// The spheres placed in this batch so far.
    placed: Placed<D>,
}

/// How a batch ended.
pub(super) enum Ended {
    /// The next body is a chain: it drops alone.
    Chain,
    /// Spheres were placed; `more` is false once the bed is full.
    Placed { more: bool },
}

impl<const D: usize> Batches<D> {
    pub(super) fn new() -> Self {
        Batches {
            size: FIRST_BATCH,
            draws: Vec::new(),
            slots: Vec::new(),
            placed: Placed::new(),
        }
    }
}

/// Deposits with the engine on a worker of the thread pool, so that each
/// batch's parallel part starts and ends among the pool's threads (from
/// outside the pool every batch would wake a worker and wait for it; measured
/// at 10^6 spheres: 1.78 s against 1.58 s). `progress` stays on the calling
/// thread: the engine sends it each report and waits for its answer, so a
/// stop takes effect where it would on one thread (a report every 4096
/// spheres; one round trip each).
pub(super) fn on_every_core<const D: usize>(
    plan: &Plan<D>,
    progress: &mut Progress,
) -> Result<(Bed<D>, DepositReport)> {
    on_the_cores_of(None, plan, progress)
}

/// [`on_every_core`] on the threads of `pool` (the global pool if `None`),
/// called from outside it.
fn on_the_cores_of<const D: usize>(
    pool: Option<&rayon::ThreadPool>,
    plan: &Plan<D>,
    progress: &mut Progress,
) -> Result<(Bed<D>, DepositReport)> {
    let engine = Engine::new(plan)?;
    let mut out = None;
    match pool {
        Some(pool) => pool.in_place_scope(|s| drive(s, engine, &mut out, progress)),
        None => rayon::in_place_scope(|s| drive(s, engine, &mut out, progress)),
    }
    out.expect("the engine ran to its end")
}

/// Spawns the engine into scope `s` and answers its progress reports with
/// `progress` until it is done; its result lands in `out`.
fn drive<'scope, const D: usize>(
    s: &rayon::Scope<'scope>,
    engine: Engine<'scope, D>,
    out: &'scope mut Option<Result<(Bed<D>, DepositReport)>>,
    progress: &mut Progress,
) {
    let (placed, counts) = mpsc::channel::<u64>();
    let (answer, answers) = mpsc::channel::<ControlFlow<()>>();
    s.spawn(move |_| {
        let mut report = |n| {
            let _ = placed.send(n);
            answers.recv().unwrap_or(ControlFlow::Continue(()))
        };
        *out = Some(engine.run(&mut report, true));
    });
    // Ends when the engine, done, drops its end of the channel.
    for n in counts {
        let _ = answer.send(progress(n));
    }
}

/// True if a batch's speculation pays: more than one thread to run on, and
/// not already one task of a parallel loop (an ensemble's replicates keep the
/// cores busy; a nested batch would only wait for them).
pub(super) fn worth_it() -> bool {
    rayon::current_num_threads() > 1 && rayon::current_thread_index().is_none()
}

impl<const D: usize> Engine<'_, D> {
    /// Drops one batch of spheres (see the module's doc).
    pub(super) fn drop_batch(
        &mut self,
        batches: &mut Batches<D>,
        progress: &mut Progress,
    ) -> Result<Ended> {
        let Batches {
            size,
            draws,
            slots,
            placed,
        } = batches;
        draws.clear();
        let left = self.target().saturating_sub(self.fed());
        let mut rng = self.rng.clone();
        // Up to `EXTRA` times the batch's size is drawn: a thread done with
        // its share while another still settles a slow sphere of the batch
        // (a fine percolating deep) settles the next ones meanwhile.
        // A feed by mass: the spheres drawn until its volume is reached, as
        // the serial engine would feed them.
        let mut volume = self.feed_volume;
        while (draws.len() as u64) < left.min((EXTRA * *size) as u64)
            && volume < self.feed_volume_end
        {
            let (species, r) = super::draw(&self.picker, &self.picks, &self.plan.species, &mut rng);
            if self.chain_of(species, r).is_some() {
                break;
            }
            volume += ball_volume::<D>(r);
            let start =
                Dropper::<D>::enter(&Sphere(r), &self.plan.container, &self.plan.feed, &mut rng);
            draws.push(Draw {
                species,
                r,
                start,
                rng: rng.clone(),
            });
        }
        if draws.is_empty() {
            return Ok(Ended::Chain);
        }
        let (container, grid, bed) = (&self.plan.container, &self.grid, &self.bed);
        let rule = &self.settling;
        let first = (*size).min(draws.len());
        if slots.len() < draws.len() {
            slots.resize_with(draws.len(), Default::default);
        }
        for slot in slots.iter_mut() {
            slot.get_mut().unwrap_or_else(|e| e.into_inner()).found = None;
        }
        let next = AtomicUsize::new(0);
        let first_done = AtomicUsize::new(0);
        let settle = || loop {
            // Extra spheres only while the batch proper is still settling.
            if next.load(Ordering::Relaxed) >= first && first_done.load(Ordering::Acquire) == first
            {
                return;
            }
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(d) = draws.get(i) else { return };
            let mut slot = slots[i].lock().unwrap_or_else(|e| e.into_inner());
            slot.trail.clear();
            let trail = RefCell::new(std::mem::take(&mut slot.trail));
            let terrain = Terrain::noting(container, grid, bed, &trail);
            let mut rng = d.rng.clone();
            let mut moves = 0;
            let rest = roll::settle(&terrain, d.r, d.start, rule, &mut rng, &mut moves);
            let (lo, hi) = terrain.asked();
            slot.trail = trail.into_inner();
            slot.found = Some(Found {
                top: grid.max_top(&d.start, &d.start, d.r),
                rest,
                rng,
                moves,
                lo,
                hi,
            });
            if i < first {
                first_done.fetch_add(1, Ordering::Release);
            }
        };
        (0..rayon::current_num_threads())
            .into_par_iter()
            .for_each(|_| settle());
        // Every index handed out was settled before its thread returned.
        let taken = next.load(Ordering::Relaxed).min(draws.len());
        let container = &self.plan.container;
        let mut redone = 0;
        placed.clear(container, self.grid.reach_beyond_margin());
        for (d, slot) in draws[..taken].iter().zip(slots.iter_mut()) {
            let Slot { found, trail } = slot.get_mut().unwrap_or_else(|e| e.into_inner());
            let f = found.as_ref().expect("every sphere handed out was settled");
            let columns = d.r + self.grid.reach_beyond_margin();
            let mut near = f.lo;
            let mut far = f.hi;
            for k in 0..D - 1 {
                near[k] = (near[k] - d.r - placed.r_max).min(d.start[k] - columns);
                far[k] = (far[k] + d.r + placed.r_max).max(d.start[k] + columns);
            }
            // Near its box, a sphere placed earlier in the batch changed the
            // answers only if it came near one of the legs (see `trail`).
            let mut spared = false;
            let met = placed.any_near(container, &near, &far, |c, r| {
                if could_have_met(container, &f.lo, &f.hi, d.r + r, c) {
                    let reach = d.r + r;
                    let reach = reach + super::trail::margin(reach, c);
                    // A full trail may lack the legs that came near.
                    if trail.len() >= roll::MOST_LEGS
                        || trail.iter().any(|leg| leg.near(container, c, reach))
                    {
                        return true;
                    }
                    spared = true;
                }
                could_have_met(container, &d.start, &d.start, columns, c)
                    && self.grid.max_top(&d.start, &d.start, d.r) != f.top
            });
            if cfg!(test) && spared && !met {
                self.check_spared(d, f);
            }
            let sphere = Sphere(d.r);
            let (settled, tipped) = if met {
                // It met a sphere of this batch: settled again, alone, on the
                // bed as it now is.
                redone += 1;
                self.rng = d.rng.clone();
                let settled = self.settle_from(&sphere, d.start);
                (settled, self.rng != d.rng)
            } else {
                self.rng = f.rng.clone();
                self.report.moves += f.moves;
                (f.rest, f.rng != d.rng)
            };
            let rest = self.find_rest(&sphere, Some(settled))?;
            let widens = self.grid.widens(d.r);
            let before = self.bed.len();
            let more = self.keep_body(&sphere, &rest, d.species, progress)?;
            if self.bed.len() > before {
                placed.push(container, self.bed.centres[before], d.r);
            }
            // Later draws assumed the generator untouched by this sphere and
            // queries widened as before it.
            if !more || tipped || settled.is_none() || widens {
                return Ok(Ended::Placed { more });
            }
        }
        *size = if 4 * redone > taken {
            (*size / 2).max(2)
        } else {
            (*size * 2).min(LARGEST_BATCH)
        };
        Ok(Ended::Placed { more: true })
    }
}

impl<const D: usize> Engine<'_, D> {
    /// Panics unless `d` settles on the bed as it now is as it did on the bed
    /// before its batch (the unit tests settle every spared sphere again).
    #[cfg(test)]
    fn check_spared(&self, d: &Draw<D>, f: &Found<D>) {
        tests::SPARED.fetch_add(1, Ordering::Relaxed);
        let terrain = Terrain::of(&self.plan.container, &self.grid, &self.bed);
        let mut rng = d.rng.clone();
        let mut moves = 0;
        let rest = roll::settle(&terrain, d.r, d.start, &self.settling, &mut rng, &mut moves);
        assert!(
            rest == f.rest && moves == f.moves && rng == f.rng,
            "a spared sphere settled otherwise: {rest:?} against {:?}",
            f.rest
        );
    }

    #[cfg(not(test))]
    fn check_spared(&self, _: &Draw<D>, _: &Found<D>) {}
}

/// True if a particle centred at `c` (any periodic image) lies within `reach`
/// of the horizontal box `[lo, hi]`.
///
/// Every query of a sphere's settling keeps only particles whose centres lie
/// within the sum of the two radii of the box it names (the fall: of the
/// vertical line; the arc search: of the arc's box; the rest-point checks:
/// of the point, within `2 tol`); the particles its grid walk visits beyond
/// that change nothing. The fall's start, the highest top under the entry
/// point, is read from whole columns and checked apart.
fn could_have_met<const D: usize>(
    container: &Container<D>,
    lo: &Vector<D>,
    hi: &Vector<D>,
    reach: Real,
    c: &Vector<D>,
) -> bool {
    (0..D - 1).all(|k| {
        // Rounding of the cell index of a centre: a hair more reach.
        let hair = 1e-9 * (reach + lo[k].abs() + hi[k].abs() + container.extent(k));
        let (a, b) = (lo[k] - reach - hair, hi[k] + reach + hair);
        if a > b {
            return false;
        }
        if container.periodic {
            let period = container.extent(k);
            b - a >= period || rem_euclid(c[k] - a, period) <= b - a
        } else {
            a <= c[k] && c[k] <= b
        }
    })
}

/// `x.rem_euclid(period)`, bit for bit, without its `fmod` where `x` lies
/// within a period of 0 (nearly always: centres are wrapped into the box).
#[inline]
fn rem_euclid(x: Real, period: Real) -> Real {
    if (0.0..period).contains(&x) {
        x
    } else if x < 0.0 && x > -period {
        x + period
    } else {
        x.rem_euclid(period)
    }
}

/// The spheres placed in a batch so far, binned in coarse columns of the
/// floor: a sphere's check visits the few near it, not the whole batch.
pub(super) struct Placed<const D: usize> {
    /// Wrapped centres and radii, in order placed.
    spheres: Vec<(Vector<D>, Real)>,
    r_max: Real,
    /// Columns per horizontal axis (1 on an unused axis), and their width.
    n: [usize; 2],
    width: [Real; 2],
    /// Per column: the last sphere binned there in batch `stamp`, chained
    /// through `next` (ids into `spheres`).
    head: Vec<u32>,
    stamp: Vec<u32>,
    next: Vec<u32>,
    batch: u32,
}

/// Most columns per axis of the batch's bins.
const MOST_BINS: usize = 256;

impl<const D: usize> Placed<D> {
    fn new() -> Self {
        Placed {
            spheres: Vec::new(),
            r_max: 0.0,
            n: [0; 2],
            width: [1.0; 2],
            head: Vec::new(),
            stamp: Vec::new(),
            next: Vec::new(),
            batch: 0,
        }
    }

    /// Empties it for a new batch; the first call sets columns about `width`
    /// wide (any width is exact; this one suits the checks' reach).
    fn clear(&mut self, container: &Container<D>, width: Real) {
        if self.n[0] == 0 {
            self.n = [1; 2];
            for k in 0..D - 1 {
                let extent = container.extent(k);
                let n = if width > 0.0 && (extent / width).is_finite() {
                    (extent / width).floor().clamp(1.0, MOST_BINS as Real) as usize
                } else {
                    1
                };
                self.n[k] = n;
                self.width[k] = extent / n as Real;
            }
            self.head = vec![0; self.n[0] * self.n[1]];
            self.stamp = vec![0; self.n[0] * self.n[1]];
        }
        self.batch = self.batch.wrapping_add(1);
        if self.batch == 0 {
            self.stamp.fill(0);
            self.batch = 1;
        }
        self.spheres.clear();
        self.next.clear();
        self.r_max = 0.0;
    }

    fn bin(&self, k: usize, x: Real) -> isize {
        (x / self.width[k]).floor() as isize
    }

    fn push(&mut self, container: &Container<D>, c: Vector<D>, r: Real) {
        let mut cell = 0;
        for k in (0..D - 1).rev() {
            let x = if container.periodic {
                container.wrap_coordinate(k, c[k])
            } else {
                c[k]
            };
            let i = self.bin(k, x);
            cell = cell * self.n[k] + i.clamp(0, self.n[k] as isize - 1) as usize;
        }
        let id = self.spheres.len() as u32;
        self.spheres.push((c, r));
        self.r_max = self.r_max.max(r);
        if self.stamp[cell] == self.batch {
            self.next.push(self.head[cell]);
        } else {
            self.stamp[cell] = self.batch;
            self.next.push(u32::MAX);
        }
        self.head[cell] = id;
    }

    /// True if `f(centre, radius)` holds for some sphere whose centre could
    /// lie in the horizontal box `[lo, hi]` (any periodic image).
    fn any_near(
        &self,
        container: &Container<D>,
        lo: &Vector<D>,
        hi: &Vector<D>,
        mut f: impl FnMut(&Vector<D>, Real) -> bool,
    ) -> bool {
        if self.spheres.is_empty() {
            return false;
        }
        let mut range = [(0isize, 0isize); 2];
        let mut cells = 1usize;
        for k in 0..D - 1 {
            let n = self.n[k] as isize;
            let (mut a, mut b) = (self.bin(k, lo[k]) - 1, self.bin(k, hi[k]) + 1);
            if a > b || b - a + 1 >= n {
                (a, b) = (0, n - 1);
            } else if !container.periodic {
                (a, b) = (a.max(0), b.min(n - 1));
            }
            range[k] = (a, b);
            cells = cells.saturating_mul((b - a + 1).max(0) as usize);
        }
        if cells >= self.spheres.len() {
            return self.spheres.iter().any(|(c, r)| f(c, *r));
        }
        let (ny0, ny1) = if D == 3 { range[1] } else { (0, 0) };
        for j in ny0..ny1 + 1 {
            let row = if D == 3 {
                j.rem_euclid(self.n[1] as isize) as usize * self.n[0]
            } else {
                0
            };
            for i in range[0].0..range[0].1 + 1 {
                let cell = row + i.rem_euclid(self.n[0] as isize) as usize;
                if self.stamp[cell] != self.batch {
                    continue;
                }
                let mut id = self.head[cell];
                while id != u32::MAX {
                    let (c, r) = &self.spheres[id as usize];
                    if f(c, *r) {
                        return true;
                    }
                    id = self.next[id as usize];
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;

    /// Spheres whose box met a sphere of their batch but none of their legs.
    pub(super) static SPARED: AtomicUsize = AtomicUsize::new(0);

    fn plan_of<const D: usize>(text: &str) -> Plan<D> {
        Config::from_toml(text, "test")
            .unwrap()
            .plan::<D>()
            .unwrap()
    }

    fn alone<const D: usize>(plan: &Plan<D>) -> (Bed<D>, DepositReport) {
        let engine = Engine::new(plan).unwrap();
        engine
            .run(&mut |_| ControlFlow::Continue(()), false)
            .unwrap()
    }

    fn in_batches<const D: usize>(plan: &Plan<D>, threads: usize) -> (Bed<D>, DepositReport) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut seen = Vec::new();
        let built = on_the_cores_of(Some(&pool), plan, &mut |n| {
            seen.push(n);
            ControlFlow::Continue(())
        })
        .unwrap();
        // Progress as the one-at-a-time engine reports it, ending at the bed.
        assert_eq!(seen.last(), Some(&(built.0.len() as u64)));
        assert!(seen.windows(2).all(|w| w[0] <= w[1]));
        built
    }

    fn same<const D: usize>(text: &str) {
        let plan = plan_of::<D>(text);
        let (bed, report) = alone(&plan);
        assert!(bed.len() > 10, "{text}");
        for threads in [1, 2, 3] {
            let (b, r) = in_batches(&plan, threads);
            assert_eq!(b.centres, bed.centres, "{text}, {threads} threads");
            assert_eq!(b.radii, bed.radii);
            assert_eq!(b.species, bed.species);
            assert_eq!(b.bodies, bed.bodies);
            let time = |r: &DepositReport| DepositReport {
                deposit_seconds: 0.0,
                ..r.clone()
            };
            assert_eq!(time(&r), time(&report), "{text}, {threads} threads");
        }
    }

    #[test]
    fn batches_build_the_one_at_a_time_bed_3d() {
        // Periodic equal spheres; a walled lognormal bed filled to the roof
        // (roof misses end it); radii 10 and 50 on a random base layer, whose
        // first large sphere widens the grid's queries.
        same::<3>(
            "dim = 3\nseed = 4\n[box]\nwidth = 300\ndepth = 300\nheight = 600\nperiodic = true\n\
             [fill]\ncount = 3000\nbase_layer = \"none\"\n[[species]]\nradius = 10\n",
        );
        same::<3>(
            "dim = 3\nseed = 5\n[box]\nwidth = 200\ndepth = 150\nheight = 120\n\
             [fill]\nroof_misses = 20\nbase_layer = \"none\"\n\
             [[species]]\nsize = { dist = \"lognormal\", median = 8.0, gsd = 1.6 }\n",
        );
        same::<3>(
            "dim = 3\nseed = 6\n[box]\nwidth = 500\ndepth = 500\nheight = 2000\nperiodic = true\n\
             [fill]\ncount = 2500\nbase_layer = \"random\"\n\
             [[species]]\nradius = 10\nratio = 1\n[[species]]\nradius = 50\nratio = 0.05\n",
        );
        // Spheres whose box met a sphere of their batch but none of their
        // legs were kept, and each settled the same again (`check_spared`).
        assert!(SPARED.load(Ordering::Relaxed) > 0);
    }

    #[test]
    fn batches_build_the_one_at_a_time_bed_2d() {
        // Discs in a box a few diameters wide (most batches meet themselves),
        // periodic discs, and discs with chains among them (chains drop alone).
        same::<2>(
            "dim = 2\nseed = 7\n[box]\nwidth = 80\nheight = 400\n\
             [fill]\ncount = 300\nbase_layer = \"none\"\n[[species]]\nradius = 10\n",
        );
        same::<2>(
            "dim = 2\nseed = 8\n[box]\nwidth = 3000\nheight = 3000\nperiodic = true\n\
             [fill]\ncount = 5000\n[[species]]\nradius = 10\nratio = 1\n\
             [[species]]\nradius = 20\nratio = 1\n",
        );
        same::<2>(
            "dim = 2\nseed = 9\n[box]\nwidth = 1000\nheight = 1000\n\
             [fill]\ncount = 1500\n[[species]]\nradius = 10\nratio = 3\n\
             [[species]]\nradius = 10\nshape = \"chain\"\nbeads = 3\nratio = 1\n",
        );
    }

    #[test]
    fn batches_build_the_one_at_a_time_bed_under_every_settling_rule() {
        // The sticking draws come from the entry point, not the run's
        // generator: batches stay as long as under the rolling rule. The
        // momentum rule's climbs over rims (and over blockers) are legs of the trail too; it
        // settles spheres and discs only, so its 2D bed has no chains.
        let rules = [
            "contacts = 1",
            "contacts = 2",
            "contacts = 3",
            "sticking = 0.4",
            "friction_angle = 20",
            "friction_angle = 30\nsticking = 0.2",
            "restitution = 0.5\ndrop_height = 30",
            "restitution = 0\nsliding_friction = 0.3\nsticking = 0.1",
            "restitution = 0.5\nfriction_angle = 25",
            "restitution = 0.95\ndrop_height = 80\nfriction_angle = 10\nclimb_over = true",
        ];
        for rule in rules {
            same::<3>(&format!(
                "dim = 3\nseed = 4\n[box]\nwidth = 300\ndepth = 300\nheight = 3000\nperiodic = true\n\
                 [fill]\ncount = 2000\nbase_layer = \"none\"\n\
                 [[species]]\nsize = {{ dist = \"lognormal\", median = 8.0, gsd = 1.4 }}\n\
                 [settling]\n{rule}\n"
            ));
            // A heap from a point feed: most batches meet themselves.
            same::<3>(&format!(
                "dim = 3\nseed = 5\n[box]\nwidth = 300\ndepth = 300\nheight = 3000\n\
                 [fill]\ncount = 1000\nbase_layer = \"none\"\n[[species]]\nradius = 8\n\
                 [feed]\npattern = \"point\"\nspread = 40\n[settling]\n{rule}\n"
            ));
            let chains =
                "ratio = 3\n[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 3\nratio = 1\n";
            same::<2>(&format!(
                "dim = 2\nseed = 9\n[box]\nwidth = 1000\nheight = 3000\n\
                 [fill]\ncount = 1500\n[[species]]\nradius = 10\n{chains}\
                 [settling]\n{rule}\n"
            ));
        }
    }

    proptest::proptest! {
        #[test]
        fn rem_euclid_is_the_standard_one_bit_for_bit(
            x in proptest::prelude::any::<f64>(),
            period in 1e-3f64..1e6,
            near in -1.0f64..1.0,
            which in 0..3u8,
        ) {
            // Offsets within a period either way, at its ends, and any others.
            let x = match which {
                0 => near * period,
                1 => near.signum() * period,
                _ => x,
            };
            proptest::prop_assert_eq!(
                rem_euclid(x, period).to_bits(),
                x.rem_euclid(period).to_bits(),
                "{} {}", x, period
            );
        }
    }

    #[test]
    fn a_sphere_near_the_box_is_met_through_any_image() {
        let plan = plan_of::<3>(
            "dim = 3\n[box]\nwidth = 100\ndepth = 50\nheight = 100\nperiodic = true\n\
             [[species]]\nradius = 1\n",
        );
        let c = &plan.container;
        let v = |x: Real, y: Real| Vector([x, y, 0.0]);
        // A box straddling x = 0 meets a centre near x = 100.
        assert!(could_have_met(
            c,
            &v(-3.0, 10.0),
            &v(2.0, 12.0),
            1.0,
            &v(98.5, 11.0)
        ));
        assert!(!could_have_met(
            c,
            &v(-3.0, 10.0),
            &v(2.0, 12.0),
            1.0,
            &v(95.0, 11.0)
        ));
        // Beyond the reach along the other axis.
        assert!(!could_have_met(
            c,
            &v(-3.0, 10.0),
            &v(2.0, 12.0),
            1.0,
            &v(98.5, 13.5)
        ));
        // A box wider than the period meets everything along that axis.
        assert!(could_have_met(
            c,
            &v(-30.0, 0.0),
            &v(30.0, 1.0),
            1.0,
            &v(70.0, 50.5)
        ));
        let walled = plan_of::<3>(
            "dim = 3\n[box]\nwidth = 100\ndepth = 50\nheight = 100\n[[species]]\nradius = 1\n",
        );
        assert!(!could_have_met(
            &walled.container,
            &v(-3.0, 10.0),
            &v(2.0, 12.0),
            1.0,
            &v(98.5, 11.0)
        ));
        // The bins find what the plain scan finds.
        let mut placed = Placed::<3>::new();
        placed.clear(c, 7.0);
        for (x, y) in [(1.0, 1.0), (99.0, 49.0), (50.0, 25.0), (13.0, 40.0)] {
            placed.push(c, v(x, y), 1.0);
        }
        for (lo, hi) in [
            (v(-2.0, -2.0), v(0.5, 0.5)),
            (v(48.0, 20.0), v(52.0, 22.0)),
            (v(14.5, 41.5), v(20.0, 45.0)),
            (v(-200.0, 3.0), v(200.0, 4.0)),
        ] {
            let mut binned = Vec::new();
            placed.any_near(c, &lo, &hi, |p, _| {
                if could_have_met(c, &lo, &hi, 2.0, p) {
                    binned.push(*p);
                }
                false
            });
            let plain: Vec<_> = placed
                .spheres
                .iter()
                .map(|(p, _)| *p)
                .filter(|p| could_have_met(c, &lo, &hi, 2.0, p))
                .collect();
            binned.sort_by(|a, b| a[0].total_cmp(&b[0]));
            let mut plain = plain;
            plain.sort_by(|a, b| a[0].total_cmp(&b[0]));
            assert_eq!(binned, plain, "{lo:?} {hi:?}");
        }
    }

    #[test]
    fn a_stopped_build_hears_no_more_progress() {
        // The caller is slow to answer, so the engine has sent more reports
        // before it sees the stop; none of them reaches the caller.
        let plan = plan_of::<2>(
            "dim = 2\nseed = 3\n[box]\nwidth = 400\nheight = 10000\nperiodic = true\n\
             [fill]\ncount = 400000\nbase_layer = \"none\"\n[[species]]\nradius = 1\n",
        );
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let mut calls = 0;
        let stopped = on_the_cores_of(Some(&pool), &plan, &mut |_| {
            calls += 1;
            std::thread::sleep(std::time::Duration::from_millis(30));
            ControlFlow::Break(())
        });
        assert!(
            matches!(stopped, Err(crate::Error::Interrupted)),
            "{:?}",
            stopped.map(|b| b.0.len())
        );
        assert_eq!(calls, 1);
    }
}
