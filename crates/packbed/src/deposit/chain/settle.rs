//! The descent of a chain to rest, iteration by iteration (the algorithm is
//! described in the parent module).

use super::rest::Rare;
use super::{
    debug_on, Candidate, ChainShape, Pose, Settler, FORCE_TOL, MAX_STEP, MAX_TOUCHING, REST_GAP,
};
use crate::config::Settling;
use crate::deposit::obstacle::Obstacle;
use crate::deposit::roll::{Motion, Terrain};
use crate::deposit::rule::{counts, holds, Sticks};
use crate::math::{nnls_gen, Gen, Real, Vector};
use std::collections::VecDeque;

/// Iterations after which a chain counts as stuck.
const MAX_ITERATIONS: usize = 20_000;
/// Gap below which an obstacle touches the chain (times the bead radius).
const CONTACT_TOL: Real = 1e-7;
/// NNLS residual below which the forces balance, relative to the sum of the
/// contact forces (in units of the weight), as for spheres.
const REST_TOL: Real = 1e-10;
/// Largest residual of a balance after its supports are shut (forces solved
/// again), in units of the weight: a hundredth of the independent checker's
/// bound (`1e-7`; the engine's metric gives the larger residual).
const POST_REST_TOL: Real = 1e-9;
/// Most tipping moves after failed line searches, per chain.
const MAX_NUDGES: usize = 8;
/// Most pockets a chain with momentum leaves before it stays in the next.
const MOST_EXITS: usize = 32;

/// Settles a chain entering at `start` (its horizontal position and axis; it is
/// first lowered to just above everything under it). Returns its resting pose
/// (not wrapped into a periodic box), or `None` if it found no rest within
/// [`MAX_ITERATIONS`].
pub(crate) fn settle_chain<const D: usize, R: rand::Rng + ?Sized>(
    terrain: &Terrain<'_, D>,
    shape: ChainShape,
    start: Pose<D>,
    rule: &Settling,
    rng: &mut R,
    moves: &mut u64,
) -> Option<Pose<D>> {
    let settler = Settler {
        terrain,
        shape,
        rho: shape.gyration::<D>(),
        chunk: ((4.0 / shape.spacing).floor() as u32).max(1),
    };
    let pose = settler.lift(start);
    // The sticking draws' seed: the entry's horizontal position and axis
    // (no allocation: at most 2 + 3 numbers).
    let mut entry = [0.0; 5];
    entry[..D - 1].copy_from_slice(&start.com.0[..D - 1]);
    entry[D - 1..2 * D - 1].copy_from_slice(&start.axis.0);
    let rule = Rule {
        settling: rule,
        ruled: !rule.is_rolling(),
        sticks: Sticks::new(rule, shape.r, &entry[..2 * D - 1]),
        met: Vec::new(),
    };
    let motion = rule.settling.momentum.map(|m| Motion::new(&m, shape.r));
    Descent::new(&settler, pose, rule, motion).run(rng, moves)
}

impl<const D: usize> Settler<'_, '_, D> {
    /// The entry pose with a unit axis, moved to just above everything the
    /// chain could touch on its way down.
    fn lift(&self, start: Pose<D>) -> Pose<D> {
        let r = self.shape.r;
        let mut pose = start;
        if let Some(a) = pose.axis.normalized() {
            pose.axis = a;
        } else {
            pose.axis = Vector::up();
        }
        let (lo, hi) = self.bead_box(&pose, 0, self.shape.beads);
        let low = lo[D - 1];
        let top = self.terrain.grid.max_top(&lo, &hi, r);
        pose.com[D - 1] += top + r * (1.0 + 1e-6) - low;
        pose
    }
}

/// What one step of an iteration decided.
enum Flow {
    /// At rest where the chain is.
    Rest,
    /// No rest to be found: the chain is stuck.
    Stuck,
    /// Iterate again.
    Again,
    /// Iterate again, the last step length forgotten (the chain fell, tipped
    /// or was nudged: the next step starts afresh).
    Fresh,
    /// Not a balance: descend.
    Descend,
}

/// The settling rule as one chain's descent applies it.
struct Rule<'r> {
    settling: &'r Settling,
    /// Whether a rule may stop the chain before it balances.
    ruled: bool,
    sticks: Sticks,
    /// Every contact (bead, obstacle) touched so far: a contact is new, and
    /// may stick, only the first time (a descent's contacts flicker in and
    /// out of the touching band from one step to the next).
    met: Vec<(u32, u64)>,
}

/// One chain's descent: its pose and what one iteration leaves for the next.
struct Descent<'s, 't, 'a, 'r, const D: usize> {
    rule: Rule<'r>,
    settler: &'s Settler<'t, 'a, D>,
    pose: Pose<D>,
    /// Gap below which an obstacle touches.
    contact: Real,
    /// Largest displacement of any bead point in one step.
    max_step: Real,
    /// The weight as a generalised force to balance.
    target: Gen,
    candidates: Vec<Candidate<D>>,
    /// Number of touching candidates, their indices, rows and forces.
    m: usize,
    which: [usize; MAX_TOUCHING],
    touching: [Gen; MAX_TOUCHING],
    lambda: [Real; MAX_TOUCHING],
    /// The touching contacts carrying a force.
    supports: Vec<(u32, Obstacle<D>)>,
    /// The touching contacts of the last iteration (bead, obstacle key).
    held: Vec<(u32, u64)>,
    /// The last accepted step length.
    h_prev: Real,
    /// One iteration that counts only shut contacts (gap within `REST_GAP`) as
    /// touching, after a balance whose supports could not all be shut.
    tight: bool,
    /// Tipping moves tried after failed line searches.
    nudges: usize,
    trace: Trace,
    /// The momentum rule's account of the chain's motion (see
    /// `chain::momentum`), if the rule has one.
    momentum: Option<Momentum<D>>,
    /// The rule (sticking, contacts, friction) stopped the chain: it stays.
    by_rule: bool,
}

/// The kinetic energy a chain carries, and what its account needs.
struct Momentum<const D: usize> {
    motion: Motion,
    /// The unit generalised direction of the last move (an impact keeps the
    /// part of the energy tangent to the contact met).
    heading: Gen,
    /// The fall of the last iteration, if it fell.
    fell: Option<Real>,
    /// The touching contacts before the last selection: one not among them
    /// is an impact.
    was_held: Vec<(u32, u64)>,
    /// The rests left so far: a chain back in one of them stays.
    rests: Vec<Pose<D>>,
}

impl<'s, 't, 'a, 'r, const D: usize> Descent<'s, 't, 'a, 'r, D> {
    fn new(
        settler: &'s Settler<'t, 'a, D>,
        pose: Pose<D>,
        rule: Rule<'r>,
        motion: Option<Motion>,
    ) -> Self {
        let r = settler.shape.r;
        let mut target = Gen::zero();
        target[D - 1] = 1.0;
        Descent {
            rule,
            settler,
            pose,
            contact: CONTACT_TOL * r,
            max_step: MAX_STEP * r,
            target,
            candidates: Vec::new(),
            m: 0,
            which: [0; MAX_TOUCHING],
            touching: [Gen::zero(); MAX_TOUCHING],
            lambda: [0.0; MAX_TOUCHING],
            supports: Vec::new(),
            held: Vec::with_capacity(MAX_TOUCHING),
            h_prev: Real::INFINITY,
            tight: false,
            nudges: 0,
            trace: Trace::new(),
            momentum: motion.map(|motion| Momentum {
                motion,
                heading: -target,
                fell: None,
                was_held: Vec::with_capacity(MAX_TOUCHING),
                rests: Vec::new(),
            }),
            by_rule: false,
        }
    }

    fn run<R: rand::Rng + ?Sized>(mut self, rng: &mut R, moves: &mut u64) -> Option<Pose<D>> {
        for it in 0..MAX_ITERATIONS {
            *moves += 1;
            let before = self.pose;
            let flow = self.iterate(it, rng);
            if let Some(m) = self.momentum.as_mut() {
                match m.fell.take() {
                    Some(dz) => m.motion.fell(dz),
                    None => m.motion.slid(&before.com, &self.pose.com),
                }
            }
            match flow {
                Flow::Rest if self.leave_pocket(moves) => self.h_prev = Real::INFINITY,
                Flow::Rest => return Some(self.pose),
                Flow::Stuck => return None,
                Flow::Fresh => self.h_prev = Real::INFINITY,
                Flow::Again | Flow::Descend => {}
            }
        }
        self.trace.dump();
        dbg_fail("iterations", MAX_ITERATIONS, &());
        None
    }

    /// Gathers the contacts, balances the forces, and either certifies a rest
    /// or steps down.
    fn iterate<R: rand::Rng + ?Sized>(&mut self, it: usize, rng: &mut R) -> Flow {
        let r = self.settler.shape.r;
        let margin = self.max_step * 1.01 + self.contact;
        self.settler
            .gather(&self.pose, margin, &mut self.candidates);
        let was_tight = std::mem::take(&mut self.tight);
        let band = if was_tight {
            REST_GAP * r
        } else {
            self.contact
        };
        if let Some(mo) = self.momentum.as_mut() {
            mo.was_held.clear();
            mo.was_held.extend_from_slice(&self.held);
        }
        self.select_touching(band, was_tight);
        let m = self.m;
        if m == 0 {
            let dz = self.settler.fall_distance(&self.pose);
            self.pose.com[D - 1] -= dz;
            if let Some(mo) = self.momentum.as_mut() {
                mo.fell = Some(dz);
                mo.heading = -self.target;
            }
            return Flow::Fresh;
        }
        self.impacts();
        if self.rule.ruled && self.stops_here() && self.shut() {
            self.by_rule = true;
            return Flow::Rest;
        }
        for j in 0..m {
            self.touching[j] = self.candidates[self.which[j]].row;
        }
        let residual = nnls_gen(&self.touching[..m], self.target, &mut self.lambda);
        // The height falls at the rate |u|² along u = −residual, which is |u|
        // per unit of motion in the kinetic metric: the descent's slope (for
        // one sphere, the sine of its path's angle below the horizontal).
        if self
            .rule
            .settling
            .slope
            .is_some_and(|s| residual.norm() < s)
            && self.spent()
            && self.shut()
        {
            return Flow::Rest;
        }
        let total: Real = self.lambda[..m].iter().sum();
        if self.trace.on {
            self.trace_iteration(it, was_tight, &residual);
        }
        self.supports.clear();
        for j in 0..m {
            if self.lambda[j] > FORCE_TOL * total.max(1.0) {
                let c = &self.candidates[self.which[j]];
                self.supports.push((c.bead, c.obstacle));
            }
        }
        if residual.norm() <= REST_TOL * total.max(1.0) {
            match self.at_balance(it, was_tight, rng) {
                Flow::Descend => {}
                flow => return flow,
            }
        }
        self.descend(it, &residual, band, rng)
    }

    /// Whether the chain has no kinetic energy left (always, without the
    /// momentum rule): friction may hold it.
    fn spent(&self) -> bool {
        self.momentum
            .as_ref()
            .is_none_or(|m| m.motion.energy() <= 0.0)
    }

    /// The momentum rule's impacts: each touching contact that did not touch
    /// before takes its share of the energy, `E' = E (1 − (1 − e²) cos² θ)`
    /// with θ between the last move's direction and the contact's
    /// generalised normal (as for a sphere; for one bead the same angle).
    /// Of several met at once, the most head-on counts.
    fn impacts(&mut self) {
        let Some(mo) = self.momentum.as_mut() else {
            return;
        };
        let mut cos2: Real = 0.0;
        for &i in &self.which[..self.m] {
            let c = &self.candidates[i];
            if mo
                .was_held
                .iter()
                .any(|&(b, k)| b == c.bead && k == c.obstacle.key)
            {
                continue;
            }
            let along = c.row.dot(&mo.heading);
            if along < 0.0 {
                cos2 = cos2.max(along * along / c.row.norm2());
            }
        }
        if cos2 > 0.0 {
            mo.motion.impact(cos2);
        }
    }

    /// At a rest, with momentum: leaves the pocket over its lowest rim the
    /// energy clears (`Settler::way_out`), unless a rule stopped the chain,
    /// it has left [`MOST_EXITS`] pockets, or it is back in one it left.
    /// Returns whether it left.
    fn leave_pocket(&mut self, moves: &mut u64) -> bool {
        let Some(mo) = self.momentum.as_mut() else {
            return false;
        };
        let r = self.settler.shape.r;
        let pose = self.pose;
        let back = mo
            .rests
            .iter()
            .any(|p| (p.com - pose.com).norm() < 1e-6 * r && (p.axis - pose.axis).norm() < 1e-6);
        if self.by_rule || back || mo.rests.len() >= MOST_EXITS || mo.motion.energy() <= 0.0 {
            return false;
        }
        mo.rests.push(pose);
        let Some(exit) = self.settler.way_out(&pose, &mo.motion, self.contact) else {
            return false;
        };
        *moves += exit.steps;
        mo.motion.set_energy(exit.energy);
        let mut heading = Gen::zero();
        for k in 0..D {
            heading[k] = exit.pose.com[k] - pose.com[k];
        }
        if let Some(h) = heading.normalized() {
            mo.heading = h;
        }
        self.pose = exit.pose;
        self.held.clear();
        true
    }

    /// Whether the chain stops where it touches before it balances: it
    /// touches the rule's number of contacts (bead–obstacle pairs), or it
    /// touches a holding contact for the first time and sticks. The contacts
    /// count as met even if the stop's contacts then cannot be shut (rare):
    /// the chain descends on and does not draw for them again.
    fn stops_here(&mut self) -> bool {
        let mut holding = 0;
        let mut fresh = false;
        for &i in &self.which[..self.m] {
            let c = &self.candidates[i];
            if counts(&c.obstacle) {
                holding += 1;
            }
            if !holds(&c.obstacle, &self.settler.bead(&self.pose, c.bead)) {
                continue;
            }
            let pair = (c.bead, c.obstacle.key);
            if !self.rule.met.contains(&pair) {
                self.rule.met.push(pair);
                fresh = true;
            }
        }
        self.rule
            .settling
            .contacts
            .is_some_and(|k| holding >= usize::from(k))
            || (fresh && self.rule.sticks.stick())
    }

    /// Shuts the touching contacts exactly (as a balance's supports are
    /// shut), so that a chain a rule stops mid-descent touches within
    /// rounding, not within the descent's band; false, and the chain left
    /// where it is, if they cannot all be shut by a move within the band.
    fn shut(&mut self) -> bool {
        let s = self.settler;
        let r = s.shape.r;
        let mut set: Vec<(u32, Obstacle<D>)> = self.which[..self.m]
            .iter()
            .map(|&i| (self.candidates[i].bead, self.candidates[i].obstacle))
            .collect();
        let mut exact = self.pose;
        if s.project_all(&mut exact, &mut set, &self.candidates, 0.0)
            .is_none()
        {
            return false;
        }
        let moved = (exact.com - self.pose.com).norm() + (exact.axis - self.pose.axis).norm() * r;
        if moved > 2.0 * self.contact {
            return false;
        }
        self.pose = exact;
        true
    }

    /// Picks the touching candidates: gap within `band`, or, for a contact
    /// touching in the last iteration, within twice the band (hysteresis: a
    /// support pinned near the band's edge does not flicker in and out of the
    /// touching set; each flicker changes the descent direction and cuts the
    /// step). At most [`MAX_TOUCHING`], the closest.
    fn select_touching(&mut self, band: Real, was_tight: bool) {
        let mut m = 0;
        for (i, c) in self.candidates.iter().enumerate() {
            let near = c.gap < band
                || (!was_tight
                    && c.gap < 2.0 * band
                    && self
                        .held
                        .iter()
                        .any(|&(b, k)| b == c.bead && k == c.obstacle.key));
            if near {
                if m == MAX_TOUCHING {
                    // Keep the closest contacts (a tie of many is degenerate).
                    let (worst, _) = self.which[..m]
                        .iter()
                        .enumerate()
                        .max_by(|a, b| {
                            self.candidates[*a.1]
                                .gap
                                .total_cmp(&self.candidates[*b.1].gap)
                        })
                        .expect("non-empty");
                    if self.candidates[self.which[worst]].gap > c.gap {
                        self.which[worst] = i;
                    }
                    continue;
                }
                self.which[m] = i;
                m += 1;
            }
        }
        self.held.clear();
        self.held.extend(
            self.which[..m]
                .iter()
                .map(|&i| (self.candidates[i].bead, self.candidates[i].obstacle.key)),
        );
        self.m = m;
    }

    /// At a balance of the fast path: shuts the supports exactly, then measures
    /// the balance again and tests its stability.
    fn at_balance<R: rand::Rng + ?Sized>(
        &mut self,
        it: usize,
        was_tight: bool,
        rng: &mut R,
    ) -> Flow {
        let s = self.settler;
        let r = s.shape.r;
        let mut set = self.supports.clone();
        let mut exact = self.pose;
        if s.project_all(&mut exact, &mut set, &self.candidates, REST_GAP * r)
            .is_none()
        {
            if was_tight {
                // Nearly parallel contacts within rounding of each other
                // (a chain along a chain): the balance as the independent
                // rest test measures it decides.
                return match s.rare_rest(&mut self.pose, &self.candidates, &mut self.supports, rng)
                {
                    Rare::Rest => Flow::Rest,
                    Rare::Tipped => Flow::Fresh,
                    Rare::No => {
                        self.trace.dump();
                        dbg_fail("rest projection", it, &self.supports.len());
                        Flow::Stuck
                    }
                };
            }
            // Some support a little open cannot be shut while the others
            // stay shut: it is no support here. Look again with only the
            // contacts that are shut.
            self.trace
                .note(format_args!("   rest projection failed: tight"));
            self.tight = true;
            return Flow::Again;
        }
        let moved = (exact.com - self.pose.com).norm() + (exact.axis - self.pose.axis).norm() * r;
        self.pose = exact;
        if moved > self.contact {
            return Flow::Again; // the projection moved it noticeably: look again
        }
        // The balance was measured before the projection, which may have
        // turned the normals (a move of `1e-7 r` turns them by about as
        // much): measure it again where the chain now is, forces
        // re-solved, as the independent rest test does.
        // Only contacts shut there count (the others carry no force).
        let mut k = 0;
        for j in 0..self.m {
            let c = &self.candidates[self.which[j]];
            let e = s.evaluate(&self.pose, c.bead, c.obstacle);
            if e.gap <= REST_GAP * r {
                self.touching[k] = e.row;
                k += 1;
            }
        }
        let after = nnls_gen(&self.touching[..k], self.target, &mut self.lambda);
        let verdict = if after.norm() <= POST_REST_TOL {
            match s.tip(&self.pose, &set, &self.candidates, rng) {
                Some(tipped) => {
                    self.pose = tipped;
                    Rare::Tipped
                }
                None => Rare::Rest,
            }
        } else {
            // Forces that nearly cancel (a bead pinched between two
            // obstacles) make the relative test above weak, and nearly
            // parallel supports the normal equations: the balance
            // measured as the independent rest test does decides.
            self.trace.note(format_args!(
                "   moved {moved:.3e}: residual after the projection {:.3e}",
                after.norm()
            ));
            let mut scratch = Vec::new();
            s.rare_rest(&mut self.pose, &self.candidates, &mut scratch, rng)
        };
        match verdict {
            Rare::Rest => Flow::Rest,
            Rare::Tipped => Flow::Fresh,
            // Not a balance after all: descend.
            Rare::No => Flow::Descend,
        }
    }

    /// Steepest descent: `u = −residual`, along which the height falls at the
    /// rate `|u|²` (in the kinetic metric), as far as the step bounds and the
    /// line search allow; when no step is resolvable, the rare path decides.
    fn descend<R: rand::Rng + ?Sized>(
        &mut self,
        it: usize,
        residual: &Gen,
        band: Real,
        rng: &mut R,
    ) -> Flow {
        let u = -*residual;
        let rate_z = u.norm2();
        let (speed, turn) = self.settler.speed(&u);
        let mut h = (2.0 * self.h_prev).min(self.max_step / speed);
        if turn > 0.0 {
            h = h.min(0.5 / turn);
        }
        h = self.advancement_bound(h, &u, turn, band);
        if let Some(h) = self.line_search(&u, h, speed, rate_z) {
            self.trace
                .note(format_args!("   step h {h:.3e} rate {rate_z:.3e}"));
            if let Some(mo) = self.momentum.as_mut() {
                mo.heading = u / u.norm();
            }
            self.h_prev = h;
            return Flow::Again;
        }
        self.no_step(it, residual.norm(), h, rng)
    }

    /// Bounds the step `h` along `u` by conservative advancement
    /// (`Settler::advancement`) against every candidate not touching (`turn`
    /// the rate of turning).
    fn advancement_bound(&self, mut h: Real, u: &Gen, turn: Real, band: Real) -> Real {
        let m = self.m;
        for (i, c) in self.candidates.iter().enumerate() {
            if c.gap < band || (c.gap < 2.0 * band && self.which[..m].contains(&i)) {
                continue;
            }
            h = h.min(self.settler.advancement(c, u, turn));
        }
        h
    }

    /// An Armijo line search on the height from step `h0`, halving: moves the
    /// chain and returns the step taken, or `None` if no step length works.
    ///
    /// First with the supports shut (closing one that is a little open is
    /// itself a descent when the rate of descent is below rounding); if no step
    /// length works, with supports open by less than `contact` left as they
    /// are: shutting them can be impossible (two neighbouring beads of a rod on
    /// one obstacle, one at gap 0, one a little open).
    fn line_search(&mut self, u: &Gen, h0: Real, speed: Real, rate_z: Real) -> Option<Real> {
        let s = self.settler;
        let r = s.shape.r;
        // How far the chain may get from where the candidates were gathered.
        let reach = self.max_step * 1.01;
        let rounding = 16.0 * Real::EPSILON * self.pose.com.0.iter().fold(r, |m, x| m.max(x.abs()));
        for slack in [0.0, 2.0 * self.contact] {
            let mut h = h0;
            let mut unprojectable = 0;
            for _ in 0..60 {
                if h * speed <= rounding {
                    // A step below the rounding of the coordinates only
                    // seems to descend (a chain was caught cycling on the
                    // same pose with such steps): no step.
                    break;
                }
                let mut trial = self.pose;
                let mut dz = s.advance(&mut trial, u, h);
                let mut set = self.supports.clone();
                let projected = s
                    .project_all(&mut trial, &mut set, &self.candidates, slack)
                    // A projection that carried a bead out of the gathered
                    // neighbourhood could hide an overlap with an obstacle
                    // never looked at: no projection.
                    .filter(|_| s.reach(&self.pose, &trial) <= reach);
                match projected {
                    Some(d) => {
                        dz += d;
                        // The height's own change must agree: the summed
                        // increments can claim a descent of a few roundings
                        // while the projection puts the chain back where it
                        // was (a chain was caught cycling so on one pose).
                        if dz <= -0.1 * h * rate_z && trial.com[D - 1] < self.pose.com[D - 1] {
                            self.pose = trial;
                            return Some(h);
                        }
                    }
                    // Supports that cannot be shut stay so at any step
                    // length: after a few tries, go on to leaving them open
                    // rather than paying for every halving.
                    None if slack == 0.0 => {
                        unprojectable += 1;
                        if unprojectable >= 4 {
                            break;
                        }
                    }
                    None => {}
                }
                h *= 0.5;
            }
        }
        None
    }

    /// No step along the descent direction is resolvable. If the shut contacts
    /// balance the weight when measured as the independent rest test does (QR,
    /// where the normal equations lost digits), this is a balance: a rest
    /// unless it tips. Otherwise (its rate is below rounding, or the supports
    /// cannot follow it) the tipping moves of a balance are tried, which go a
    /// finite distance along the supports' tangent directions.
    fn no_step<R: rand::Rng + ?Sized>(
        &mut self,
        it: usize,
        residual: Real,
        h: Real,
        rng: &mut R,
    ) -> Flow {
        let s = self.settler;
        match s.rare_rest(&mut self.pose, &self.candidates, &mut self.supports, rng) {
            Rare::Rest => return Flow::Rest,
            Rare::Tipped => return Flow::Fresh,
            Rare::No => {}
        }
        let n = self.supports.len();
        self.trace
            .note(format_args!("   no step, no QR balance ({n} supports)"));
        if self.nudges < MAX_NUDGES {
            if let Some(tipped) = s.tip(&self.pose, &self.supports, &self.candidates, rng) {
                self.nudges += 1;
                self.pose = tipped;
                return Flow::Fresh;
            }
        }
        self.trace.dump();
        dbg_fail("line search", it, &(residual, self.m, n, h));
        Flow::Stuck
    }

    /// Notes the iteration's contacts and forces in the trace.
    #[cold]
    #[inline(never)]
    fn trace_iteration(&mut self, it: usize, was_tight: bool, residual: &Gen) {
        let m = self.m;
        let gaps: Vec<_> = self.which[..m]
            .iter()
            .map(|&i| {
                let c = &self.candidates[i];
                (c.bead, c.obstacle.key, c.gap)
            })
            .collect();
        self.trace.note(format_args!(
            "it {it} z {:.12} res {:.3e} m {m} tight {was_tight} gaps {gaps:?} lam {:?}",
            self.pose.com[D - 1],
            residual.norm(),
            &self.lambda[..m]
        ));
    }
}

/// The last iterations' diagnostics, kept when `PACKBED_CHAIN_DEBUG` is set
/// (for investigating re-drops).
struct Trace {
    on: bool,
    lines: VecDeque<String>,
}

impl Trace {
    fn new() -> Self {
        Trace {
            on: debug_on(),
            lines: VecDeque::new(),
        }
    }

    fn note(&mut self, line: std::fmt::Arguments) {
        if self.on {
            self.push(line);
        }
    }

    #[cold]
    #[inline(never)]
    fn push(&mut self, line: std::fmt::Arguments) {
        if self.lines.len() > 80 {
            self.lines.pop_front();
        }
        self.lines.push_back(line.to_string());
    }

    fn dump(&self) {
        for t in &self.lines {
            eprintln!("  {t}");
        }
    }
}

/// Explains a stuck chain on stderr when `PACKBED_CHAIN_DEBUG` is set.
fn dbg_fail(what: &str, it: usize, x: &dyn std::fmt::Debug) {
    if debug_on() {
        eprintln!("chain stuck: {what} at iteration {it}: {x:?}");
    }
}
