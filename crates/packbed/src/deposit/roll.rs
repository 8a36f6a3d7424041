//! Drop and roll of one sphere (disc in 2D) onto the fixed bed: fall, roll along
//! the steepest descent that keeps the active contacts, until at rest.
//!
//! The moving centre stays outside the inflated obstacles. With the contacts that
//! carry a compressive force it moves along a known curve (a vertical line, or a
//! circle), so each move is "find the first event on the curve" in closed form:
//! a new contact, or a contact force turning tensile (the contact is released).

use super::arc_search::{Batch, Sweep};
use super::obstacle::{is_floor, particle_key, wall_obstacle, Obstacle};
use super::rule::{counts, holds, Sticks};
use super::trail::Leg;
use crate::bed::Bed;
use crate::config::Settling;
use crate::container::Container;
use crate::geometry::{Arc, Crossing, Surface, Trig};
use crate::grid::Grid;
use crate::math::{nnls, Real, Vector};
use rand::RngExt;
use std::cell::{Cell, RefCell};

mod momentum;

pub(crate) use momentum::Motion;

/// Most contacts tracked at once (more happen only in degenerate ties).
const MAX_ACTIVE: usize = 6;
/// Moves after which a particle counts as stuck and is dropped again elsewhere.
/// Generous: a fine particle percolating down through a deep skeleton of large
/// ones makes thousands of legitimate moves (radii 10 and 50: up to ~3000 in a
/// bed 10 large diameters deep).
pub(crate) const MAX_MOVES: usize = 100_000;
/// Most legs a speculative settling notes (see `trail`): a sphere that moves
/// more often (a fine percolating deep, a sphere stuck until `MAX_MOVES`) is
/// judged by the box of its queries alone, and the trails of a batch stay
/// within a few megabytes.
pub(crate) const MOST_LEGS: usize = 4096;
/// Relative size of "zero" for gaps (times the moving radius).
const GAP_TOL: Real = 1e-12;
/// Length of the NNLS residual below which forces balance, relative to the sum of
/// the contact forces (in units of the weight): a particle wedged between nearly
/// coplanar contacts carries forces of hundreds of weights, and the rounding of
/// the residual grows with them.
const REST_TOL: Real = 1e-10;
/// Contact forces below this (relative to the weight) are no forces.
const FORCE_TOL: Real = 1e-12;

/// The fixed bed as the rolling particle sees it.
pub(crate) struct Terrain<'a, const D: usize> {
    pub container: &'a Container<D>,
    pub grid: &'a Grid<D>,
    pub centres: &'a [Vector<D>],
    pub radii: &'a [Real],
    /// The horizontal box every grid query of a sphere's settling has named
    /// so far (before the grid widens it): what a speculative drop read
    /// (`deposit::speculate`). Chains query `grid` directly and are never
    /// speculated.
    asked: Cell<(Vector<D>, Vector<D>)>,
    /// Where a speculative settling's centre went, leg by leg (`None` for
    /// one at a time): what its answers depended on, finer than `asked`.
    trail: Option<&'a RefCell<Vec<Leg<D>>>>,
}

impl<'a, const D: usize> Terrain<'a, D> {
    /// The particles of `bed` as fixed obstacles, found through `grid`.
    pub(crate) fn of(container: &'a Container<D>, grid: &'a Grid<D>, bed: &'a Bed<D>) -> Self {
        Terrain {
            container,
            grid,
            centres: &bed.centres,
            radii: &bed.radii,
            asked: Cell::new((Vector([Real::INFINITY; D]), Vector([Real::NEG_INFINITY; D]))),
            trail: None,
        }
    }

    /// [`Terrain::of`], noting every leg of a settling in `trail`.
    pub(crate) fn noting(
        container: &'a Container<D>,
        grid: &'a Grid<D>,
        bed: &'a Bed<D>,
        trail: &'a RefCell<Vec<Leg<D>>>,
    ) -> Self {
        Terrain {
            trail: Some(trail),
            ..Terrain::of(container, grid, bed)
        }
    }

    /// Notes a leg whose queries are asked (or were just answered); a trail
    /// is full at [`MOST_LEGS`] and says no more.
    #[inline]
    fn went(&self, leg: Leg<D>) {
        if let Some(trail) = self.trail {
            let mut trail = trail.borrow_mut();
            if trail.len() < MOST_LEGS {
                trail.push(leg);
            }
        }
    }

    /// The horizontal box (lower and upper corners; heights meaningless) of
    /// every query so far; empty (lower above upper) before the first.
    pub(crate) fn asked(&self) -> (Vector<D>, Vector<D>) {
        self.asked.get()
    }

    #[inline]
    fn ask(&self, lo: &Vector<D>, hi: &Vector<D>) {
        let (mut a, mut b) = self.asked.get();
        for k in 0..D - 1 {
            a[k] = a[k].min(lo[k]);
            b[k] = b[k].max(hi[k]);
        }
        self.asked.set((a, b));
    }

    /// [`Grid::max_top`], noted.
    fn max_top(&self, lo: &Vector<D>, hi: &Vector<D>, margin: Real) -> Real {
        self.ask(lo, hi);
        self.grid.max_top(lo, hi, margin)
    }

    /// [`Grid::for_each_in_box`], noted.
    #[inline]
    fn for_each_in_box(
        &self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        margin: Real,
        f: impl FnMut(u32, Vector<D>, u16),
    ) {
        self.ask(lo, hi);
        self.grid.for_each_in_box(lo, hi, margin, f)
    }

    /// [`Grid::any_in_box`], noted.
    #[inline]
    fn any_in_box(
        &self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        margin: Real,
        f: impl FnMut(u32, Vector<D>, u16) -> bool,
    ) -> bool {
        self.ask(lo, hi);
        self.grid.any_in_box(lo, hi, margin, f)
    }

    /// [`Grid::scan_down`], noted.
    #[inline]
    fn scan_down(
        &self,
        lo: &Vector<D>,
        hi: &Vector<D>,
        margin: Real,
        f: impl FnMut(u32, Vector<D>, u16) -> Real,
    ) {
        self.ask(lo, hi);
        self.grid.scan_down(lo, hi, margin, f)
    }
}

/// A small set of contacts (cleared by resetting its length: no memset in the
/// hot loop).
#[derive(Clone, Copy)]
struct ContactSet<const D: usize> {
    items: [Obstacle<D>; MAX_ACTIVE],
    len: usize,
}

impl<const D: usize> ContactSet<D> {
    fn new() -> Self {
        let none = Obstacle {
            surface: Surface::Plane {
                normal: Vector::up(),
                offset: 0.0,
            },
            key: u64::MAX,
        };
        ContactSet {
            items: [none; MAX_ACTIVE],
            len: 0,
        }
    }
    #[inline]
    fn get(&self, i: usize) -> Obstacle<D> {
        self.items[i]
    }
    #[inline]
    fn push(&mut self, o: Obstacle<D>) {
        if self.len < MAX_ACTIVE && !self.contains(o.key) {
            self.items[self.len] = o;
            self.len += 1;
        }
    }
    #[inline]
    fn contains(&self, key: u64) -> bool {
        self.items[..self.len].iter().any(|o| o.key == key)
    }
    fn remove_key(&mut self, key: u64) {
        if let Some(i) = (0..self.len).find(|&i| self.items[i].key == key) {
            self.items[i] = self.items[self.len - 1];
            self.len -= 1;
        }
    }
    #[inline]
    fn clear(&mut self) {
        self.len = 0;
    }
}

/// Settles a sphere of radius `r` dropped at the horizontal position of `start`.
/// Returns its resting centre (not wrapped into the periodic box), or `None` if
/// it found no rest within [`MAX_MOVES`] moves.
pub(crate) fn settle<const D: usize, R: rand::Rng + ?Sized>(
    terrain: &Terrain<'_, D>,
    r: Real,
    start: Vector<D>,
    rule: &Settling,
    rng: &mut R,
    moves: &mut u64,
) -> Option<Vector<D>> {
    let tol = GAP_TOL * r;
    let mut sticks = Sticks::new(rule, r, &start.0[..D - 1]);
    // Asked once, not per move: whether a rule may stop the particle early.
    let ruled = !rule.is_rolling();
    // The last move made new contacts (a landing, or a hit while rolling).
    let mut fresh = false;
    let mut p = start;
    // Just above everything the particle could touch on its way down.
    p[D - 1] = terrain.max_top(&p, &p, r) + r;
    let mut active = ContactSet::<D>::new();
    let mut lambda = [0.0; MAX_ACTIVE];
    let mut keep = ContactSet::<D>::new();
    let mut hits = ContactSet::<D>::new();
    // The arc search's batch, set up once per particle, not once per arc.
    let mut batch = Batch::<D>::new();
    // Zero-length moves in a row, and the contacts after the last of them.
    let mut still = 0;
    let mut still_contacts: Option<ContactSet<D>> = None;
    // The momentum rule's energy, and the way on over a rim just climbed.
    let mut motion = rule.momentum.map(|m| momentum::Motion::new(&m, r));
    let mut onward: Option<Vector<D>> = None;
    for _ in 0..MAX_MOVES {
        *moves += 1;
        if active.len == 0 {
            let from = p;
            let dz = fall(terrain, &p, r, tol, &mut active);
            p[D - 1] -= dz;
            terrain.went(Leg::Fall { from, to: p[D - 1] });
            fresh = (0..active.len).any(|i| holds(&active.get(i), &p));
            if let Some(m) = motion.as_mut() {
                m.fell(dz);
                m.impact(momentum::head_on(&active, &p, &-Vector::<D>::up()));
            }
            continue;
        }
        if ruled && stops_here(rule, &active, std::mem::take(&mut fresh), &mut sticks) {
            return Some(p);
        }
        let p_before = p;
        let mut drew = false;
        let mut keep_lambda = [0.0; MAX_ACTIVE];
        let direction = if let Some(direction) = onward.take() {
            // Over a rim: on along the circle it climbed, down the far side.
            keep = active;
            direction
        } else {
            let (residual, balanced) = weight_on(&active, &p, &mut lambda);
            keep.clear();
            for i in 0..active.len {
                if lambda[i] > FORCE_TOL {
                    keep_lambda[keep.len] = lambda[i];
                    keep.push(active.get(i));
                }
            }
            let direction = if balanced {
                if is_stable(&keep, &p) {
                    if let Some(m) = motion.as_mut() {
                        if let Some(exit) =
                            momentum::way_out(terrain, &keep, &p, r, tol, m, &mut batch)
                        {
                            m.descended(-exit.barrier);
                            p = exit.top;
                            active = exit.kept;
                            onward = Some(exit.onward);
                            continue;
                        }
                    }
                    return Some(snap(terrain, &keep, p, r, tol));
                }
                if held_in_place(terrain, &keep, &p, r, tol) {
                    // Balanced on a crest, with touching walls or particles closing
                    // every way it could tip (a disc on a disc in a box one diameter
                    // wide): a zero-force contact blocks as well as a loaded one.
                    return Some(p);
                }
                if rule.slope.is_some() && spent(&motion) {
                    // Balanced, every way on starts level: friction holds it
                    // (a moving particle passes over).
                    return Some(p);
                }
                // Balanced but unstable (on top of a sphere, or of a circle): any
                // push tips it over; the push's direction is drawn at random.
                drew = true;
                random_tangent(&keep, &p, rng)?
            } else {
                (-residual).normalized()?
            };
            if rule.slope.is_some_and(|s| -direction[D - 1] < s) && spent(&motion) {
                // Held by friction: the way down is less steep than its angle
                // (a moving particle slides on and slows down).
                return Some(p);
            }
            direction
        };
        let balls = (0..keep.len)
            .filter(|&i| keep.get(i).surface.is_ball())
            .count();
        if balls == 0 {
            // Only side walls hold it sideways: it slides straight down.
            active.clear();
            continue;
        }
        if keep.len >= D {
            // Degenerate (dependent normals): let the weakest contact go.
            let weakest = (0..keep.len)
                .min_by(|&a, &b| keep_lambda[a].total_cmp(&keep_lambda[b]))
                .expect("non-empty");
            keep.remove_key(keep.get(weakest).key);
        }
        let (arc, releases) = build_arc(&keep, &p, &direction)?;
        // The arc ends where a contact force turns tensile (or, as a safeguard,
        // at the lowest point of the circle). Events are points of the unit
        // circle ranked by their diamond angle: no trigonometry in this loop.
        let mut end = arc.lowest_crossing();
        let mut end_rank = end.diamond();
        let mut released = None;
        for i in 0..keep.len {
            if let Some(x) = releases[i].downcrossing(1e-14) {
                let rank = x.diamond();
                if rank < end_rank {
                    end = x;
                    end_rank = rank;
                    released = Some(keep.get(i).key);
                }
            }
        }
        // With friction the arc also ends where its slope falls below the
        // angle (in a groove, before its lowest point): held there.
        let mut held = false;
        // Held where a moving particle's energy ran out: checked against its
        // supports' forces below, since an arc on from a rim may lean on a
        // support that no longer pushes.
        let mut moving = false;
        if let (Some(s), Some(m)) = (rule.slope, motion.as_ref().filter(|m| m.energy() > 0.0)) {
            // Moving: held where its energy is spent on a stretch less steep
            // than the angle, not where the stretch begins.
            if let Some(x) = momentum::spent_on_arc(&arc, &p, m.energy(), m.mu(), s, &end) {
                end = x;
                end_rank = x.diamond();
                released = None;
                held = true;
                moving = true;
            }
        } else if let Some(s) = rule.slope {
            if let Some(x) = slope_trig(&arc, s).downcrossing(1e-14) {
                let rank = x.diamond();
                if rank < end_rank {
                    end = x;
                    end_rank = rank;
                    released = None;
                    held = true;
                }
            }
        }
        let (hit, hit_rank) = first_contact_on_arc(
            terrain, &arc, &keep, r, &end, end_rank, tol, &mut hits, &mut batch,
        );
        let stop = if hit_rank <= end_rank { hit } else { end };
        p = arc.point_at(&stop);
        terrain.went(Leg::Roll { arc, stop });
        if let Some(m) = motion.as_mut() {
            m.slid(&p_before, &p);
            if hit_rank <= end_rank {
                m.impact(momentum::head_on(&hits, &p, &arc.tangent_at(&stop)));
            }
        }
        if held && end_rank < hit_rank && (!moving || friction_holds(&keep, &p, rule.slope)) {
            return Some(p);
        }
        fresh = hit_rank <= end_rank && (0..hits.len).any(|i| holds(&hits.get(i), &p));
        std::mem::swap(&mut active, &mut keep);
        if hit_rank <= end_rank {
            for i in 0..hits.len {
                active.push(hits.get(i));
            }
        }
        if end_rank <= hit_rank {
            if let Some(key) = released {
                active.remove_key(key);
            }
        }
        // A move that leaves the centre and the contacts as they were and drew
        // nothing from the generator repeats forever (a fine whose descent is
        // tangent to a neighbour it already touches): give up now, not after
        // the whole move budget. The re-drop, and so the bed, is the same; only
        // the time is saved. The contacts are copied only once the centre has
        // stood still for two moves, so ordinary moves pay one comparison.
        if !drew && p == p_before {
            still += 1;
            if still >= 2 {
                if still_contacts.is_some_and(|c| same_contacts(&c, &active)) {
                    return None;
                }
                still_contacts = Some(active);
            }
        } else {
            still = 0;
            still_contacts = None;
        }
    }
    None
}

/// Whether static friction holds a particle at `p` on the supports `keep`
/// under the friction angle's sine `slope`: its forces balance, or the way
/// its weight pushes it (along the supports that push back) is less steep.
fn friction_holds<const D: usize>(
    keep: &ContactSet<D>,
    p: &Vector<D>,
    slope: Option<Real>,
) -> bool {
    let Some(s) = slope else {
        return true;
    };
    let (residual, balanced) = weight_on(keep, p, &mut [0.0; MAX_ACTIVE]);
    balanced || (-residual).normalized().is_none_or(|d| -d[D - 1] < s)
}

/// The weight (a unit force up, to be met) on the contacts `set` at `p`: the
/// non-negative contact forces that best meet it, into `lambda`; the part
/// they leave unmet; and whether that part is nil (to `REST_TOL` of the
/// forces), so that the particle is balanced.
fn weight_on<const D: usize>(
    set: &ContactSet<D>,
    p: &Vector<D>,
    lambda: &mut [Real; MAX_ACTIVE],
) -> (Vector<D>, bool) {
    let mut normals = [Vector::<D>::zero(); MAX_ACTIVE];
    for (i, n) in normals.iter_mut().enumerate().take(set.len) {
        *n = set.get(i).surface.normal_at(p);
    }
    let residual = nnls(&normals[..set.len], Vector::up(), lambda);
    let total: Real = lambda[..set.len].iter().sum();
    (residual, residual.norm() <= REST_TOL * (1.0 + total))
}

/// True for a particle with no kinetic energy left (every particle of a
/// quasi-static rule): static friction may hold it.
fn spent(motion: &Option<momentum::Motion>) -> bool {
    motion.as_ref().is_none_or(|m| m.energy() <= 0.0)
}

/// Whether a particle touching `active` stops there before it balances: it
/// touches the rule's number of `contacts`, or it just made new holding ones
/// (`fresh`) and sticks.
fn stops_here<const D: usize>(
    rule: &Settling,
    active: &ContactSet<D>,
    fresh: bool,
    sticks: &mut Sticks,
) -> bool {
    let touching = (0..active.len).filter(|&i| counts(&active.get(i))).count();
    rule.contacts.is_some_and(|k| touching >= usize::from(k)) || (fresh && sticks.stick())
}

/// The downhill slope of `arc` (the sine of its tangent's angle below the
/// horizontal) less `s`, as a function of the arc parameter: along
/// `p(t) = m + ρ (u cos t + v sin t)` the unit tangent's height is
/// `−u_z sin t + v_z cos t`.
fn slope_trig<const D: usize>(arc: &Arc<D>, s: Real) -> Trig {
    Trig {
        a: -arc.v.height(),
        b: arc.u.height(),
        c: -s,
    }
}

/// The same contacts in the same order.
fn same_contacts<const D: usize>(a: &ContactSet<D>, b: &ContactSet<D>) -> bool {
    a.len == b.len && (0..a.len).all(|i| a.get(i).key == b.get(i).key)
}

/// The exact resting point: where the `D` supporting surfaces meet.
///
/// A contact met at the tolerance level (see [`Trig::downcrossing`]) is off by up
/// to `1e-12 r`; in a wedge of nearly opposed contacts that shifts the resting
/// point by `1e-12 r / n_z`, far more. Computing the meeting point of the
/// supports in closed form removes it. The snap is taken only if it is small
/// and overlaps nothing.
fn snap<const D: usize>(
    terrain: &Terrain<'_, D>,
    keep: &ContactSet<D>,
    p: Vector<D>,
    r: Real,
    tol: Real,
) -> Vector<D> {
    if keep.len != D || (0..D).all(|i| keep.get(i).surface.gap(&p).abs() <= 0.1 * tol) {
        return p;
    }
    let mut surfaces = [keep.get(0).surface; D];
    for (i, s) in surfaces.iter_mut().enumerate() {
        *s = keep.get(i).surface;
    }
    let (points, n) = crate::geometry::intersection_points(&surfaces);
    let Some(q) = points[..n]
        .iter()
        .copied()
        .min_by(|a, b| (*a - p).norm2().total_cmp(&(*b - p).norm2()))
    else {
        return p;
    };
    if !q.is_finite() || (q - p).norm() > 1e-4 * r {
        return p;
    }
    // Nothing else may be closer than touching at the snapped point.
    let c = terrain.container;
    let (walls, n_walls) = c.wall_array();
    for &wall in &walls[..n_walls] {
        if wall_obstacle(c, wall, r).surface.gap(&q) < -tol {
            return p;
        }
    }
    let mut clear = true;
    terrain.went(Leg::Point(q));
    terrain.for_each_in_box(&q, &q, r, |id, shift, _| {
        let centre = terrain.centres[id as usize] + shift;
        let need = r + terrain.radii[id as usize] - tol;
        if (q - centre).norm2() < need * need {
            clear = false;
        }
    });
    if clear {
        q
    } else {
        p
    }
}

/// At rest for good: on the floor, or held by `D` independent contacts.
fn is_stable<const D: usize>(keep: &ContactSet<D>, p: &Vector<D>) -> bool {
    if (0..keep.len).any(|i| is_floor(keep.get(i).key)) {
        return true;
    }
    let mut basis = [Vector::<D>::zero(); MAX_ACTIVE];
    orthonormal_normals(keep, p, &mut basis) == D
}

/// True if every direction tangent to `keep` (the ways a particle balanced on
/// a crest could tip) runs into something already touching at `p`: a wall or a
/// particle at zero gap. Only asked of a balanced, unstable particle, which in a
/// random bed is rare, so the neighbour search here costs nothing overall.
fn held_in_place<const D: usize>(
    terrain: &Terrain<'_, D>,
    keep: &ContactSet<D>,
    p: &Vector<D>,
    r: Real,
    tol: Real,
) -> bool {
    let mut basis = [Vector::<D>::zero(); MAX_ACTIVE];
    let rank = orthonormal_normals(keep, p, &mut basis);
    // The tangent space: the unit axes with the contact normals taken out.
    let mut tangents = [Vector::<D>::zero(); D];
    let mut free = 0;
    for k in 0..D {
        let mut t = Vector::<D>::zero();
        t[k] = 1.0;
        for b in basis.iter().take(rank).chain(tangents.iter().take(free)) {
            t -= *b * t.dot(b);
        }
        if let Some(u) = (t.norm() > 1e-6).then(|| t.normalized()).flatten() {
            tangents[free] = u;
            free += 1;
        }
    }
    if free == 0 || free > 2 {
        return free == 0;
    }
    // The touching obstacles' normals, as seen in the tangent space: each
    // blocks the half of it that it faces.
    let mut blocking: Vec<[Real; 2]> = Vec::new();
    let mut add = |n: Vector<D>| {
        let m = [
            n.dot(&tangents[0]),
            if free == 2 { n.dot(&tangents[1]) } else { 0.0 },
        ];
        if m[0].hypot(m[1]) > 1e-9 {
            blocking.push(m);
        }
    };
    let c = terrain.container;
    let (walls, n_walls) = c.wall_array();
    for &wall in &walls[..n_walls] {
        let s = wall_obstacle(c, wall, r).surface;
        if s.gap(p) <= tol {
            add(s.normal_at(p));
        }
    }
    terrain.went(Leg::Point(*p));
    terrain.for_each_in_box(p, p, r, |id, shift, _| {
        let s = Surface::Ball {
            centre: terrain.centres[id as usize] + shift,
            radius: r + terrain.radii[id as usize],
        };
        if s.gap(p) <= 2.0 * tol {
            add(s.normal_at(p));
        }
    });
    positively_spanning(&blocking, free)
}

/// True if the vectors leave no direction of the plane (or, for `dim` 1, of
/// the line along the first component) free: no `d` with `m·d >= 0` for all.
fn positively_spanning(vectors: &[[Real; 2]], dim: usize) -> bool {
    if dim == 1 {
        return vectors.iter().any(|m| m[0] > 0.0) && vectors.iter().any(|m| m[0] < 0.0);
    }
    // In the plane: no angular gap of half a turn or more between neighbours.
    let mut angles: Vec<Real> = vectors.iter().map(|m| m[1].atan2(m[0])).collect();
    if angles.len() < 3 {
        return false;
    }
    angles.sort_by(Real::total_cmp);
    let wrap = angles[0] + std::f64::consts::TAU - angles[angles.len() - 1];
    let widest = angles.windows(2).map(|w| w[1] - w[0]).fold(wrap, Real::max);
    widest < std::f64::consts::PI - 1e-9
}

/// Gram–Schmidt on the contact normals; returns the rank.
fn orthonormal_normals<const D: usize>(
    set: &ContactSet<D>,
    p: &Vector<D>,
    basis: &mut [Vector<D>; MAX_ACTIVE],
) -> usize {
    let mut rank = 0;
    for i in 0..set.len {
        let mut n = set.get(i).surface.normal_at(p);
        for b in basis.iter().take(rank) {
            n -= *b * n.dot(b);
        }
        if let Some(u) = (n.norm() > 1e-9).then(|| n.normalized()).flatten() {
            basis[rank] = u;
            rank += 1;
        }
    }
    rank
}

/// A random unit direction that keeps every contact of `set` (tangent to all).
fn random_tangent<const D: usize, R: rand::Rng + ?Sized>(
    set: &ContactSet<D>,
    p: &Vector<D>,
    rng: &mut R,
) -> Option<Vector<D>> {
    let mut basis = [Vector::<D>::zero(); MAX_ACTIVE];
    let rank = orthonormal_normals(set, p, &mut basis);
    for _ in 0..16 {
        let mut w = Vector::<D>::zero();
        for k in 0..D {
            w[k] = rng.random_range(-1.0..1.0);
        }
        for b in basis.iter().take(rank) {
            w -= *b * w.dot(b);
        }
        if let Some(u) = (w.norm() > 1e-6).then(|| w.normalized()).flatten() {
            return Some(u);
        }
    }
    None
}

/// Straight fall from `p`: returns the distance to the first contact and writes
/// the contacts made there into `hits` (the floor, or spheres; ties together).
fn fall<const D: usize>(
    terrain: &Terrain<'_, D>,
    p: &Vector<D>,
    r: Real,
    tol: Real,
    hits: &mut ContactSet<D>,
) -> Real {
    let mut best_t = p[D - 1] - r;
    hits.clear();
    hits.push(wall_obstacle(
        terrain.container,
        crate::container::Wall::Floor,
        r,
    ));
    let (mut lo, hi) = (*p, *p);
    lo[D - 1] = 0.0;
    // Best hits as (id, centre, inflated radius, image); their identities are
    // worked out at the end.
    let mut best = [(0u32, Vector::<D>::zero(), 0.0, 0u16); MAX_ACTIVE];
    let mut n_best = 0;
    terrain.scan_down(&lo, &hi, r, |id, shift, image| {
        let c = terrain.centres[id as usize] + shift;
        let big_r = r + terrain.radii[id as usize];
        let w = *p - c;
        let h2 = w.horizontal().norm2();
        let r2 = big_r * big_r;
        // Below the obstacle's equator the fall only moves away from it (a sphere
        // sliding off the side of another, just released). A graze within 1e-9
        // of the equator penetrates by less than 1e-17 R: no contact either.
        if h2 < r2 && w[D - 1] > 1e-9 * big_r {
            let t = (w[D - 1] - (r2 - h2).sqrt()).max(0.0);
            if t < best_t - tol {
                best_t = t;
                n_best = 0;
            }
            if t <= best_t + tol && n_best < MAX_ACTIVE {
                best[n_best] = (id, c, big_r, image);
                n_best += 1;
            }
        }
        p[D - 1] - best_t
    });
    let floor_t = p[D - 1] - r;
    if best_t < floor_t - tol {
        // A sphere is hit before the floor: the floor is no contact.
        hits.clear();
    }
    for &(id, centre, radius, image) in &best[..n_best] {
        hits.push(Obstacle {
            surface: Surface::Ball { centre, radius },
            key: particle_key(id, image),
        });
    }
    best_t.max(0.0)
}

/// The circle the centre follows while keeping the contacts of `keep` (one sphere,
/// possibly with walls, or two spheres in 3D), starting at `p` in `direction`; and
/// for each contact the function whose sign is that of its force along the arc.
fn build_arc<const D: usize>(
    keep: &ContactSet<D>,
    p: &Vector<D>,
    direction: &Vector<D>,
) -> Option<(Arc<D>, [Trig; MAX_ACTIVE])> {
    arc_of::<D, true>(keep, p, direction)
}

/// [`build_arc`]'s circle alone, the same bits: the momentum rule's rims
/// need no release functions, and are built at every rest.
fn circle<const D: usize>(
    keep: &ContactSet<D>,
    p: &Vector<D>,
    direction: &Vector<D>,
) -> Option<Arc<D>> {
    arc_of::<D, false>(keep, p, direction).map(|(arc, _)| arc)
}

/// [`build_arc`], with the release functions only if `RELEASES`.
#[inline(always)]
fn arc_of<const D: usize, const RELEASES: bool>(
    keep: &ContactSet<D>,
    p: &Vector<D>,
    direction: &Vector<D>,
) -> Option<(Arc<D>, [Trig; MAX_ACTIVE])> {
    let mut balls = [(Vector::<D>::zero(), 0.0); 2];
    let mut nb = 0;
    let mut planes = [(Vector::<D>::zero(), 0.0); MAX_ACTIVE];
    let mut np = 0;
    for i in 0..keep.len {
        match keep.get(i).surface {
            Surface::Ball { centre, radius } => {
                if nb == 2 {
                    return None;
                }
                balls[nb] = (centre, radius);
                nb += 1;
            }
            Surface::Plane { normal, offset } => {
                planes[np] = (normal, offset);
                np += 1;
            }
        }
    }
    let mut releases = [Trig {
        a: 0.0,
        b: 0.0,
        c: 0.0,
    }; MAX_ACTIVE];
    match nb {
        1 => {
            // One sphere, cut by the wall planes (side walls are orthogonal).
            let (c, big_r) = balls[0];
            let mut m = c;
            for &(n, h) in &planes[..np] {
                m -= n * (n.dot(&m) - h);
            }
            let rho2 = big_r * big_r - (c - m).norm2();
            if rho2 <= (1e-9 * big_r).powi(2) {
                return None;
            }
            let mut q = *p - m;
            for &(n, _) in &planes[..np] {
                q -= n * n.dot(&q);
            }
            let u = q.normalized()?;
            let mut v = *direction - u * direction.dot(&u);
            for &(n, _) in &planes[..np] {
                v -= n * n.dot(&v);
            }
            let v = along_circle(v, direction)?;
            let arc = Arc {
                m,
                rho: rho2.sqrt(),
                u,
                v,
            };
            if !RELEASES {
                return Some((arc, releases));
            }
            // Every force here is proportional to the height above the circle's
            // centre: all are released at its equator.
            for rel in releases.iter_mut().take(keep.len) {
                *rel = arc.height_trig();
            }
            Some((arc, releases))
        }
        2 => {
            let ((c1, r1), (c2, r2)) = (balls[0], balls[1]);
            let e = c2 - c1;
            let dist = e.norm();
            if dist <= 0.0 || np > 0 {
                return None;
            }
            let a = e / dist;
            let s1 = (dist * dist + r1 * r1 - r2 * r2) / (2.0 * dist);
            let rho2 = r1 * r1 - s1 * s1;
            if rho2 <= (1e-9 * r1).powi(2) {
                return None;
            }
            let rho = rho2.sqrt();
            let m = c1 + a * s1;
            let mut q = *p - m;
            q -= a * a.dot(&q);
            let u = q.normalized()?;
            let v = along_circle(
                *direction - u * direction.dot(&u) - a * direction.dot(&a),
                direction,
            )?;
            let arc = Arc { m, rho, u, v };
            if !RELEASES {
                return Some((arc, releases));
            }
            // Force balance in the plane of (radial, axis): λ1 ∝ a_z ρ − s2 q_z and
            // λ2 ∝ s1 q_z − a_z ρ, with q_z the height of the radial unit vector.
            let s2 = s1 - dist;
            let az = a.height();
            let h = arc.height_trig();
            let scale = |f: Real, c: Real| Trig {
                a: f * h.a,
                b: f * h.b,
                c,
            };
            for i in 0..keep.len {
                releases[i] = match keep.get(i).surface {
                    Surface::Ball { centre, .. } if centre == c1 => scale(-s2, az * rho),
                    _ => scale(s1, -az * rho),
                };
            }
            Some((arc, releases))
        }
        _ => None,
    }
}

/// The unit tangent of a circle from `v`, the part of `direction` along it;
/// none where `direction` is square to the circle (its part along it no more
/// than rounding): a normalised rounding error would point anywhere, off
/// the supports (as for a climb over a blocker heading along a wall, its
/// supports' centres in the plane of its path).
fn along_circle<const D: usize>(v: Vector<D>, direction: &Vector<D>) -> Option<Vector<D>> {
    if v.norm() <= 1e-12 * direction.norm() {
        return None;
    }
    v.normalized()
}

/// First new contact along `arc` up to `end`: where (as a point of the unit
/// circle), its diamond-angle rank (infinite if none), and the obstacles met there.
#[allow(clippy::too_many_arguments)]
fn first_contact_on_arc<const D: usize>(
    terrain: &Terrain<'_, D>,
    arc: &Arc<D>,
    keep: &ContactSet<D>,
    r: Real,
    end: &Crossing,
    end_rank: Real,
    tol: Real,
    hits: &mut ContactSet<D>,
    batch: &mut Batch<D>,
) -> (Crossing, Real) {
    let tie = 1e-12;
    let mut best = *end;
    let mut best_rank = end_rank;
    let mut found = false;
    hits.clear();
    let mut consider = |x: Crossing, o: Obstacle<D>, hits: &mut ContactSet<D>| {
        let rank = x.diamond();
        if rank > best_rank + tie {
            return;
        }
        if keep.contains(o.key) {
            return;
        }
        if rank < best_rank - tie || !found {
            best_rank = rank.min(best_rank);
            best = x;
            hits.clear();
            found = true;
        }
        hits.push(o);
    };
    let c = terrain.container;
    let (walls, n_walls) = c.wall_array();
    for &wall in &walls[..n_walls] {
        let o = wall_obstacle(c, wall, r);
        if let Surface::Plane { normal, offset } = o.surface {
            if let Some(x) = arc.plane_trig(&normal, offset).downcrossing(tol) {
                consider(x, o, hits);
            }
        }
    }
    let (arc_lo, arc_hi) = arc.bounds_to(end);
    let mut met = |x: Crossing, centre: Vector<D>, big_r: Real, id: u32, image: u16| {
        let o = Obstacle {
            surface: Surface::Ball {
                centre,
                radius: big_r,
            },
            // The identity is worked out only for obstacles actually met.
            key: particle_key(id, image),
        };
        consider(x, o, hits);
    };
    let ball = |id: u32, shift: Vector<D>| {
        (
            terrain.centres[id as usize] + shift,
            r + terrain.radii[id as usize],
        )
    };
    if D == 2 {
        // Discs: a handful of candidates per arc, too few for a batch to pay
        // (5–10 % slower at 10^6 discs, docs/history/benchmarks.md): each is asked alone.
        terrain.for_each_in_box(&arc_lo, &arc_hi, r, |id, shift, image| {
            let (centre, big_r) = ball(id, shift);
            let outside =
                (0..D).any(|k| centre[k] < arc_lo[k] - big_r || centre[k] > arc_hi[k] + big_r);
            if outside {
                return;
            }
            let f = arc.ball_trig(&centre, big_r);
            // Entered, if at all, well beyond the end: the ranking drops it.
            if f.clear_until(end) {
                return;
            }
            if let Some(x) = f.downcrossing(2.0 * big_r * tol) {
                met(x, centre, big_r, id, image);
            }
        });
    } else {
        // The grid walk only gathers; a branch-free sift of each batch leaves
        // the few candidates worth an exact crossing (see `arc_search`).
        let sweep = Sweep {
            arc: *arc,
            lo: arc_lo,
            hi: arc_hi,
            end: *end,
            tol,
        };
        batch.len = 0;
        terrain.for_each_in_box(&arc_lo, &arc_hi, r, |id, shift, image| {
            let (centre, big_r) = ball(id, shift);
            if batch.push(&centre, big_r, id, image) {
                batch.for_each_crossing(&sweep, &mut met);
                batch.len = 0;
            }
        });
        batch.for_each_crossing(&sweep, &mut met);
    }
    (best, if found { best_rank } else { Real::INFINITY })
}

/// Whether [`first_contact_on_arc`] would meet anything (its rank finite),
/// asking the grid the same box: the first obstacle entered up to `end` (or
/// within the tie window beyond it) that `keep` does not hold answers it, so
/// the walk stops there.
#[allow(clippy::too_many_arguments)]
fn blocked_on_arc<const D: usize>(
    terrain: &Terrain<'_, D>,
    arc: &Arc<D>,
    keep: &ContactSet<D>,
    r: Real,
    end: &Crossing,
    end_rank: Real,
    tol: Real,
    batch: &mut Batch<D>,
) -> bool {
    // `first_contact_on_arc` keeps an obstacle unless its rank exceeds the
    // end's by more than the tie (so a NaN rank meets, as there).
    let limit = end_rank + 1e-12;
    let meets = |x: Crossing, key: u64| {
        x.diamond().partial_cmp(&limit) != Some(std::cmp::Ordering::Greater) && !keep.contains(key)
    };
    let c = terrain.container;
    let (walls, n_walls) = c.wall_array();
    for &wall in &walls[..n_walls] {
        let o = wall_obstacle(c, wall, r);
        if let Surface::Plane { normal, offset } = o.surface {
            if let Some(x) = arc.plane_trig(&normal, offset).downcrossing(tol) {
                if meets(x, o.key) {
                    return true;
                }
            }
        }
    }
    let (arc_lo, arc_hi) = arc.bounds_to(end);
    let ball = |id: u32, shift: Vector<D>| {
        (
            terrain.centres[id as usize] + shift,
            r + terrain.radii[id as usize],
        )
    };
    if D == 2 {
        terrain.any_in_box(&arc_lo, &arc_hi, r, |id, shift, image| {
            let (centre, big_r) = ball(id, shift);
            let outside =
                (0..D).any(|k| centre[k] < arc_lo[k] - big_r || centre[k] > arc_hi[k] + big_r);
            if outside {
                return false;
            }
            let f = arc.ball_trig(&centre, big_r);
            if f.clear_until(end) {
                return false;
            }
            f.downcrossing(2.0 * big_r * tol)
                .is_some_and(|x| meets(x, particle_key(id, image)))
        })
    } else {
        let sweep = Sweep {
            arc: *arc,
            lo: arc_lo,
            hi: arc_hi,
            end: *end,
            tol,
        };
        let mut met = |x: Crossing, _: Vector<D>, _: Real, id: u32, image: u16| {
            meets(x, particle_key(id, image))
        };
        batch.len = 0;
        terrain.any_in_box(&arc_lo, &arc_hi, r, |id, shift, image| {
            let (centre, big_r) = ball(id, shift);
            if batch.push(&centre, big_r, id, image) {
                let blocked = batch.any_crossing(&sweep, &mut met);
                batch.len = 0;
                return blocked;
            }
            false
        }) || batch.any_crossing(&sweep, &mut met)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A circle of radius 2 about (0, 0, 5) in a plane tilted by `tilt`
    /// toward `phi`, started at angle `theta` of the plane.
    pub(super) fn tilted_arc(theta: Real, phi: Real, tilt: Real) -> Arc<3> {
        let n = Vector([tilt.sin() * phi.cos(), tilt.sin() * phi.sin(), tilt.cos()]);
        let mut e = Vector([1.0, 0.0, 0.0]);
        e -= n * n.dot(&e);
        let e1 = e.normalized().unwrap();
        let e2 = Vector([
            n[1] * e1[2] - n[2] * e1[1],
            n[2] * e1[0] - n[0] * e1[2],
            n[0] * e1[1] - n[1] * e1[0],
        ]);
        Arc {
            m: Vector([0.0, 0.0, 5.0]),
            rho: 2.0,
            u: e1 * theta.cos() + e2 * theta.sin(),
            v: e2 * theta.cos() - e1 * theta.sin(),
        }
    }

    /// A groove of two spheres whose centres lie in one plane with the
    /// moving centre: its circle crosses that plane square to it.
    fn groove_in_a_plane(y: Real) -> (ContactSet<3>, Vector<3>) {
        let (c1, c2) = (Vector([24.5, y, 2.2]), Vector([26.05, y, 3.7]));
        let mut set = ContactSet::<3>::new();
        for (k, centre) in [c1, c2].into_iter().enumerate() {
            set.push(Obstacle {
                surface: Surface::Ball {
                    centre,
                    radius: 2.0,
                },
                key: particle_key(k as u32, 0),
            });
        }
        // On both spheres, in their plane.
        let e = c2 - c1;
        let d = e.norm();
        let a = e / d;
        let side = Vector([-a[2], 0.0, a[0]]);
        let p = c1 + a * (d / 2.0) + side * (4.0 - d * d / 4.0).sqrt();
        (set, p)
    }

    #[test]
    fn a_direction_square_to_the_circle_gives_no_arc() {
        // A climb over a blocker beside a wall: the way on asked along the
        // plane of the centres, where the circle runs across it (along y).
        // No direction in that plane gives an arc.
        for y in [29.0, 0.3, -7.125] {
            let (set, p) = groove_in_a_plane(y);
            for g in set.items[..set.len].iter() {
                assert!(g.surface.gap(&p).abs() < 1e-12, "{p:?}");
            }
            for dir in [[1.0, 0.0, 0.0], [0.6, 0.0, -0.8], [0.0, 0.0, -1.0]] {
                assert!(circle(&set, &p, &Vector(dir)).is_none(), "y {y}, {dir:?}");
            }
            // A part across the plane well above rounding
            // gives the circle's own tangent, square to both normals.
            for tilt in [1e-3, 0.3, 1.0] {
                let dir = Vector([1.0, tilt, 0.0]);
                let arc = circle(&set, &p, &dir).expect("an arc");
                assert!((arc.v[1].abs() - 1.0).abs() < 1e-12, "{:?}", arc.v);
                assert!(arc.v[1] > 0.0);
                for g in set.items[..set.len].iter() {
                    assert!(arc.v.dot(&g.surface.normal_at(&p)).abs() < 1e-12);
                }
            }
        }
    }

    proptest! {
        /// The friction event of an arc is where its downhill slope has
        /// fallen to `s`: the unit tangent there points down by exactly `s`,
        /// and every point before it is steeper.
        #[test]
        fn the_slope_event_is_where_the_arc_is_as_steep_as_the_angle(
            theta in 0.05 as Real..1.5,
            phi in 0.0 as Real..6.2,
            tilt in -1.2 as Real..1.2,
            s in 0.02 as Real..0.9,
        ) {
            // A circle in a tilted plane, started heading down more steeply than s.
            let mut arc = tilted_arc(theta, phi, tilt);
            if arc.v[2] > 0.0 {
                arc.v = -arc.v;
            }
            let (u, v) = (arc.u, arc.v);
            prop_assume!(-v[2] > s + 1e-6);
            let tangent = |t: Real| u * -t.sin() + v * t.cos();
            match slope_trig(&arc, s).downcrossing(1e-14) {
                Some(x) => {
                    let t = x.angle();
                    prop_assert!((-tangent(t)[2] - s).abs() < 1e-9, "slope {} at {t}", -tangent(t)[2]);
                    for k in 0..50 {
                        let tk = t * k as Real / 50.0;
                        prop_assert!(-tangent(tk)[2] >= s - 1e-12);
                    }
                }
                // Around a whole circle the slope averages zero: it always
                // falls to s somewhere.
                None => prop_assert!(false, "no event"),
            }
        }
    }
}
