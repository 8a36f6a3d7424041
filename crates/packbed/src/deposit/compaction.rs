//! Compaction after settling: the settled bed's potential energy is lowered by
//! small collective moves, as a frictionless DEM pour lowers it by shaking its
//! particles into one another's pockets, until no move of the whole bed lowers
//! it further. Drop-and-roll settles one particle at a time on a frozen bed;
//! a frictionless DEM pour (φ ≈ 0.64) is denser because the bed moves as a
//! whole.
//!
//! Each step solves a convex quadratic programme in the displacements `u`
//! (in mean diameters) of every sphere:
//!
//! - minimise `Σ wᵢ uᵢ·ẑ + Σ wᵢ |uᵢ|² / (2 step)` (the potential energy,
//!   weights `wᵢ` the masses, plus a proximal term under which a free sphere
//!   falls one step);
//! - each pair keeps `n·(uᵢ − uⱼ) ≥ −gap` (`n` the unit vector from j to i),
//!   and each wall its distance; with `friction` µ, pairs near contact keep
//!   their relative move in Anitescu's cone `n·Δu + gap ≥ µ |Δuₜ|` (a
//!   second-order cone: a contact slides only by opening µ times the
//!   slide), so the bed stops where Coulomb friction holds it.
//!
//! The step is refined as the bed converges, so that the contacts, opened by
//! the square of each slide, close: docs/settling.md,
//! "Compaction: denser than 0.60".
//!
//! The pair constraint keeps the pair apart exactly for any displacement, not
//! only small ones: the new distance `|d + Δd|` is at least its projection
//! `n·(d + Δd) = |d| + n·Δd ≥ rᵢ + rⱼ`. Pairs further apart than the moves can
//! close are left out. The interior-point solver (Clarabel) meets the
//! constraints to its tolerance only, so each step is checked exactly
//! afterwards and halved until it overlaps nothing; pairs are kept a hair
//! (`MARGIN`) apart so that a step is rarely halved.
//!
//! Spheres and discs only: a rigid chain's rotations are not linearised here.

use crate::bed::Bed;
pub use crate::config::Compaction;
use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::math::{Real, Vector};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SecondOrderConeT,
    SolverStatus, SupportedConeT,
};
use serde::Serialize;

/// `compaction.*` of `summary.json`: what the compaction did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct CompactionReport {
    /// Steps taken.
    pub steps: u32,
    /// How far the centre of mass (mass-weighted mean height) came down, in
    /// the config's length unit.
    pub descent: Real,
    /// The last step's descent of the centre of mass, in mean diameters.
    pub last_descent: Real,
    /// Why it stopped.
    pub stopped_by: CompactionStop,
    /// Wall time in seconds.
    pub seconds: f64,
}

/// Why a compaction stopped: `compaction.stopped_by` of `summary.json`, in
/// lower case.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CompactionStop {
    /// Converged: its stop rule held at the finest step.
    Until,
    /// The step budget ran out first.
    #[default]
    Steps,
    /// A step's quadratic programme was not solved to its tolerance; the bed
    /// is as the last step left it.
    Solver,
    /// Even 2⁻³⁰ of a step overlapped; the bed is as the last step left it.
    Overlap,
}

impl CompactionStop {
    /// Why it stopped, in the words of the run's text.
    pub fn says(self) -> &'static str {
        match self {
            Self::Until => "came to rest",
            Self::Steps => "stopped by the step budget",
            Self::Solver => "stopped by the solver",
            Self::Overlap => "stopped by an overlap",
        }
    }
}

impl CompactionReport {
    /// The warning of a compaction that stopped before its stop rule held
    /// (`None` once it did, or when `compaction.steps = 0` asked for no
    /// step): φ and Z are then those of a bed that may still be settling.
    pub fn warning(&self) -> Option<String> {
        let n = self.steps;
        match self.stopped_by {
            CompactionStop::Steps if n > 0 => Some(format!(
                "compaction: stopped at its budget of {n} steps before it came to rest (the last step still lowered the centre of mass by {:.1e} mean diameters); the bed may still be settling: raise compaction.steps",
                self.last_descent
            )),
            CompactionStop::Solver => Some(format!(
                "compaction: the quadratic programme of step {} was not solved to its tolerance; the bed is as step {n} left it (no overlap), not at rest",
                n + 1
            )),
            CompactionStop::Overlap => Some(format!(
                "compaction: step {} overlapped even at 2^-30 of its length; the bed is as step {n} left it (no overlap), not at rest",
                n + 1
            )),
            _ => None,
        }
    }
}

/// Gap kept between pairs and from walls, in mean diameters: about the
/// solver's feasibility error, so that a step seldom needs halving, and far
/// below the contact tolerance of the analysis (10⁻⁶ of a radius).
const MARGIN: Real = 1e-9;

/// The overlap a step may leave, in mean diameters: the rounding of the
/// distances of a bed some 10⁴ diameters across.
const ROUNDING: Real = 1e-12;

/// Longest move of a sphere in one step, in steps: a free sphere falls one
/// step; one pushed aside by its neighbours may go further, and the whole
/// step is shortened if one would go beyond this.
const LONGEST_MOVE: Real = 1.5;

/// The finest step, as a fraction of the first: a slide of `s` opens a
/// contact by about `s²/2`, 10⁻⁹ diameters at the finest default step.
const FINEST: Real = 1e-3;

/// At the finest step, a step that moves no sphere further than this share
/// of the step ends the compaction. Under the proximal term a sphere moves
/// its unbalanced share of its weight times the step, so every sphere is
/// then held up to 10⁻² of its weight (the tests measure 10⁻¹² on beds that
/// converge); smaller moves would soon be lost in the solver's tolerance
/// (about 10⁻⁹ d) and the margin.
const STILL: Real = 1e-2;

/// The linear solver of each interior-point iteration: faer's supernodal
/// Cholesky. The simpler QDLDL took 60 ms an iteration for 1,000 spheres,
/// most of it in the fill of the 3D contact graph.
const SOLVE_METHOD: &str = "faer";

/// A pair (or wall) constraint of one step.
struct Pair<const D: usize> {
    i: usize,
    /// `None` for a wall.
    j: Option<usize>,
    /// Unit normal pushing `i` away (from j, or out of the wall).
    n: Vector<D>,
    /// Centre-to-centre vector `cᵢ − cⱼ` (with the periodic image), or for a
    /// wall the height of `cᵢ` above it along `n`.
    d: Vector<D>,
    /// Gap in the config's length unit.
    gap: Real,
    /// Sum of radii (or the radius, for a wall).
    contact: Real,
}

/// Compacts `bed` of single spheres in place.
pub fn compact<const D: usize>(bed: &mut Bed<D>, c: &Compaction) -> Result<CompactionReport> {
    let start = std::time::Instant::now();
    let n = bed.centres.len();
    let mut report = CompactionReport::default();
    if n == 0 {
        report.stopped_by = CompactionStop::Until;
        return Ok(report);
    }
    let r_mean = bed.radii.iter().sum::<Real>() / n as Real;
    let unit = 2.0 * r_mean;
    let weights: Vec<Real> = bed
        .radii
        .iter()
        .map(|&r| (r / r_mean).powi(D as i32))
        .collect();
    let total: Real = weights.iter().sum();
    let finest = c.step * FINEST;
    let mut step = c.step;
    for _ in 0..c.steps {
        let pairs = pairs_within(bed, unit * reach(step));
        let Some(u) = solve_step(bed, &pairs, &weights, unit, step, c.friction) else {
            report.stopped_by = CompactionStop::Solver;
            break;
        };
        let furthest = u
            .chunks_exact(D)
            .map(|m| m.iter().map(|x| x * x).sum::<Real>().sqrt())
            .fold(0.0, Real::max);
        let cap = (LONGEST_MOVE * step / furthest).min(1.0);
        let Some(t) = largest_safe_fraction(&pairs, &u, unit, cap) else {
            report.stopped_by = CompactionStop::Overlap;
            break;
        };
        let mut descent = 0.0;
        for (i, p) in bed.centres.iter_mut().enumerate() {
            let mut moved = *p;
            for k in 0..D {
                moved[k] += t * unit * u[i * D + k];
            }
            descent -= weights[i] * t * u[i * D + D - 1];
            *p = bed.container.wrap(moved);
        }
        descent /= total;
        report.steps += 1;
        report.descent += descent * unit;
        report.last_descent = descent;
        let longest = t * furthest;
        if longest > 0.1 * step && step < c.step {
            // A sphere moves freely (off a support, out of an unstable
            // balance, down a slope): coarser steps bring it down sooner.
            step = (step * 4.0).min(c.step);
        } else if descent < c.until * step {
            // Converged at this step size: go on with finer steps, whose
            // slides open the contacts less (by the square of the step),
            // down to the finest; stop there once no sphere moves more than
            // `STILL` of the step.
            if step > finest {
                step = (step * 0.25).max(finest);
            } else if longest < STILL * step {
                report.stopped_by = CompactionStop::Until;
                break;
            }
        }
    }
    report.seconds = start.elapsed().as_secs_f64();
    if bed.centres.iter().any(|p| !p.is_finite()) {
        return Err(Error::Impossible(
            "compaction moved a particle to a non-finite place".into(),
        ));
    }
    Ok(report)
}

/// How far apart (in diameters) two spheres can be and still meet in a step
/// of `step`: twice the longest move.
fn reach(step: Real) -> Real {
    2.0 * LONGEST_MOVE * step + 2.0 * MARGIN
}

/// Every pair of spheres closer than `cut` (gap), and every sphere closer than
/// `cut` to a wall.
fn pairs_within<const D: usize>(bed: &Bed<D>, cut: Real) -> Vec<Pair<D>> {
    let grid = Grid::of_particles(&bed.container, &bed.centres, &bed.radii, 0.0);
    let mut pairs = Vec::new();
    for (i, (ci, &ri)) in bed.centres.iter().zip(&bed.radii).enumerate() {
        grid.for_each_in_box(ci, ci, ri + cut, |j, shift, _| {
            let j = j as usize;
            if j <= i {
                return;
            }
            let d = *ci - (bed.centres[j] + shift);
            let dist = d.norm();
            let contact = ri + bed.radii[j];
            if dist - contact <= cut && dist > 0.0 {
                pairs.push(Pair {
                    i,
                    j: Some(j),
                    n: d * (1.0 / dist),
                    d,
                    gap: dist - contact,
                    contact,
                });
            }
        });
        for wall in bed.container.walls() {
            let h = bed.container.wall_distance(wall, ci);
            if h - ri <= cut {
                let n = bed.container.wall_normal(wall);
                pairs.push(Pair {
                    i,
                    j: None,
                    n,
                    d: n * h,
                    gap: h - ri,
                    contact: ri,
                });
            }
        }
    }
    pairs
}

/// The step's displacements (in diameters, `D` per sphere), or `None` if the
/// programme was not solved.
///
/// With `friction` µ > 0, each pair closer than µ times the reach of the step
/// keeps its relative move in Anitescu's cone instead of the half-space:
/// `n·(uᵢ − uⱼ) + gap ≥ µ |(uᵢ − uⱼ)ₜ|` (ₜ: the part across `n`). A contact
/// then slides only by opening µ times the slide, so a sphere on a slope of
/// tilt θ slides down only where tan θ > µ (Coulomb's threshold), and the
/// cone is inside the half-space, so the pair still cannot overlap.
fn solve_step<const D: usize>(
    bed: &Bed<D>,
    pairs: &[Pair<D>],
    weights: &[Real],
    unit: Real,
    step: Real,
    friction: Real,
) -> Option<Vec<Real>> {
    let n = bed.centres.len() * D;
    let p = CscMatrix::new(
        n,
        n,
        (0..=n).collect(),
        (0..n).collect(),
        (0..n).map(|v| weights[v / D] / step).collect(),
    );
    let mut q = vec![0.0; n];
    for (i, w) in weights.iter().enumerate() {
        q[i * D + D - 1] = *w;
    }
    // Frictional pairs: those a step's slide could reach (a slide of up to
    // the reach opens a sliding contact by µ times it).
    let sticky = |pair: &Pair<D>| friction > 0.0 && pair.gap <= friction * reach(step) * unit;
    let (free, cones): (Vec<&Pair<D>>, Vec<&Pair<D>>) = pairs.iter().partition(|p| !sticky(p));
    // Rows: one per free pair (−n·uᵢ + n·uⱼ ≤ gap − margin), then D per
    // frictional pair: that row, then µ tᵢ·(uᵢ − uⱼ) for each tangent tᵢ.
    let (mut rows, mut cols, mut vals) = (Vec::new(), Vec::new(), Vec::new());
    let mut b = Vec::new();
    // The gap of each normal row (None for a tangent row), for the retry.
    let mut gap_of = Vec::new();
    let mut push = |row: usize, pair: &Pair<D>, v: &Vector<D>, scale: Real| {
        for k in 0..D {
            rows.push(row);
            cols.push(pair.i * D + k);
            vals.push(-scale * v[k]);
            if let Some(j) = pair.j {
                rows.push(row);
                cols.push(j * D + k);
                vals.push(scale * v[k]);
            }
        }
    };
    let tagged = free.iter().map(|p| (p, false));
    for (pair, cone) in tagged.chain(cones.iter().map(|p| (p, true))) {
        push(b.len(), pair, &pair.n, 1.0);
        b.push(pair.gap / unit - MARGIN);
        gap_of.push(Some(pair.gap));
        if !cone {
            continue;
        }
        for t in tangents(&pair.n) {
            push(b.len(), pair, &t, friction);
            b.push(0.0);
            gap_of.push(None);
        }
    }
    let a = CscMatrix::new_from_triplets(b.len(), n, rows, cols, vals);
    let mut kinds: Vec<SupportedConeT<Real>> = Vec::new();
    if !free.is_empty() {
        kinds.push(NonnegativeConeT(free.len()));
    }
    kinds.extend(cones.iter().map(|_| SecondOrderConeT(D)));
    // Pairs are pushed a margin apart, so that the solver's tolerance does
    // not overlap them. A row of spheres touching around a periodic box (or
    // from wall to wall) cannot all part: then each pair closer than the
    // margin is held at its gap instead, and the exact check may shorten
    // the step.
    solve(&p, &q, &a, &b, &kinds).or_else(|| {
        let held: Vec<Real> = gap_of
            .iter()
            .zip(&b)
            .map(|(gap, rhs)| match gap {
                Some(gap) => rhs.max(gap.min(0.0) / unit),
                None => *rhs,
            })
            .collect();
        solve(&p, &q, &a, &held, &kinds)
    })
}

/// `D − 1` orthonormal vectors across the unit vector `n`: Gram–Schmidt on
/// the axes, each time the axis that keeps the most length (the first keeps
/// at least √((D−1)/D) of it), so the basis is well conditioned for every `n`.
fn tangents<const D: usize>(n: &Vector<D>) -> Vec<Vector<D>> {
    let mut basis: Vec<Vector<D>> = Vec::with_capacity(D - 1);
    while basis.len() < D - 1 {
        let across = |k: usize| {
            let mut v = Vector::<D>::axis(k);
            v = v - *n * v.dot(n);
            for t in &basis {
                v = v - *t * v.dot(t);
            }
            v
        };
        let best = (0..D)
            .map(across)
            .max_by(|a, b| a.norm2().total_cmp(&b.norm2()))
            .and_then(|v| v.normalized());
        match best {
            Some(t) => basis.push(t),
            None => break,
        }
    }
    basis
}

/// The minimiser of `uᵀPu/2 + qᵀu` subject to `Au + s = b`, `s` in `cones`,
/// if it was found.
fn solve(
    p: &CscMatrix<Real>,
    q: &[Real],
    a: &CscMatrix<Real>,
    b: &[Real],
    cones: &[SupportedConeT<Real>],
) -> Option<Vec<Real>> {
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .max_threads(1)
        .direct_solve_method(SOLVE_METHOD.into())
        .build()
        .ok()?;
    let mut solver = DefaultSolver::new(p, q, a, b, cones, settings).ok()?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {}
        _ => return None,
    }
    let u = solver.solution.x.clone();
    u.iter().all(|x| x.is_finite()).then_some(u)
}

/// The largest fraction `t` of the step `u` (1, ½, ¼, …) that leaves every
/// pair and wall of `pairs` apart, checked with the exact distances; `None`
/// if even 2⁻³⁰ of it does not.
fn largest_safe_fraction<const D: usize>(
    pairs: &[Pair<D>],
    u: &[Real],
    unit: Real,
    from: Real,
) -> Option<Real> {
    let mut t = from;
    for _ in 0..=30 {
        let apart = pairs.iter().all(|pair| {
            let mut moved = pair.d;
            for k in 0..D {
                let uj = pair.j.map_or(0.0, |j| u[j * D + k]);
                moved[k] += t * unit * (u[pair.i * D + k] - uj);
            }
            let gap = match pair.j {
                Some(_) => moved.norm() - pair.contact,
                None => moved.dot(&pair.n) - pair.contact,
            };
            // No overlap beyond rounding, nor deeper than before.
            gap >= pair.gap.min(-ROUNDING * unit)
        });
        if apart {
            return Some(t);
        }
        t *= 0.5;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn default() -> Compaction {
        Compaction {
            steps: 1000,
            step: 0.05,
            until: 0.01,
            friction: 0.0,
        }
    }

    #[test]
    fn a_disc_balanced_on_another_slides_off_and_both_lie_on_the_floor() {
        // A disc on top of another, 0.3 r off its axis, is an unstable
        // balance: the lowest energy has both on the (frictionless) floor,
        // side by side. Hand-solved: both centres at height r, at least 2r
        // apart.
        let mut bed = Bed::of_discs(
            [20.0, 20.0],
            true,
            &[(10.0, 1.0, 1.0), (10.3, 1.0 + (4.0_f64 - 0.09).sqrt(), 1.0)],
        );
        let r = compact(&mut bed, &default()).unwrap();
        assert_eq!(r.stopped_by, CompactionStop::Until, "{r:?}");
        for c in &bed.centres {
            assert!((c[1] - 1.0).abs() < 1e-8, "{c:?}");
        }
        let apart = bed.container.displacement(&bed.centres[0], &bed.centres[1]);
        assert!(apart.norm() >= 2.0, "{apart:?}");
        // The centre of mass came down by half the top disc's fall.
        let fall = (4.0_f64 - 0.09).sqrt();
        assert!((r.descent - fall / 2.0).abs() < 1e-7, "{r:?}");
    }

    #[test]
    fn friction_holds_a_disc_on_a_slope_flatter_than_its_angle() {
        // A disc on top of another, 0.6 r off its axis: its contact normal is
        // tilted by θ with sin θ = 0.6 / 2, tan θ = 0.3145. By Coulomb's
        // threshold it stays for µ above tan θ, and below it slides off
        // (then both lie on the floor). The lower disc's floor contact carries
        // a share sin θ cos θ / 2 = 0.14 of the load across it, which µ holds
        // where the upper one stays.
        let top = 1.0 + (4.0_f64 - 0.36).sqrt();
        let tilt = (0.3_f64).asin().tan();
        for (mu, holds) in [(0.35, true), (0.5, true), (0.15, false), (0.0, false)] {
            assert_eq!(mu > tilt, holds);
            let mut bed = Bed::of_discs([20.0, 20.0], true, &[(10.0, 1.0, 1.0), (10.6, top, 1.0)]);
            let before = bed.centres.clone();
            let c = Compaction {
                friction: mu,
                ..default()
            };
            let r = compact(&mut bed, &c).unwrap();
            assert_eq!(r.stopped_by, CompactionStop::Until, "µ {mu}: {r:?}");
            if holds {
                for (a, b) in bed.centres.iter().zip(&before) {
                    assert!((*a - *b).norm() < 1e-5, "µ {mu}: {a:?} moved from {b:?}");
                }
            } else {
                for c in &bed.centres {
                    assert!((c[1] - 1.0).abs() < 1e-8, "µ {mu}: {c:?}");
                }
            }
        }
    }

    #[test]
    fn a_compaction_cut_short_says_so() {
        // The disc balanced off-axis of the first test: it needs dozens of
        // steps to reach the floor, so a budget of 2 cuts it short, and the
        // warning says how far its last step still brought the bed down.
        let bed = || {
            Bed::of_discs(
                [20.0, 20.0],
                true,
                &[(10.0, 1.0, 1.0), (10.3, 1.0 + (4.0_f64 - 0.09).sqrt(), 1.0)],
            )
        };
        let short = Compaction {
            steps: 2,
            ..default()
        };
        let r = compact(&mut bed(), &short).unwrap();
        assert_eq!((r.stopped_by, r.steps), (CompactionStop::Steps, 2), "{r:?}");
        assert!(r.last_descent > 1e-4, "{r:?}");
        let w = r.warning().expect("a warning");
        assert!(w.contains("budget of 2 steps"), "{w}");
        assert!(w.contains(&format!("{:.1e}", r.last_descent)), "{w}");
        let done = compact(&mut bed(), &default()).unwrap();
        assert_eq!(
            (done.stopped_by, done.warning()),
            (CompactionStop::Until, None)
        );
        let none = Compaction {
            steps: 0,
            ..default()
        };
        assert_eq!(compact(&mut bed(), &none).unwrap().warning(), None);
        for (why, says) in [
            (CompactionStop::Solver, "not solved"),
            (CompactionStop::Overlap, "overlapped"),
        ] {
            let cut = CompactionReport {
                stopped_by: why,
                steps: 7,
                ..r
            };
            let w = cut.warning().expect("a warning");
            assert!(
                w.contains(says) && w.contains("step 8") && w.contains("step 7 left"),
                "{w}"
            );
        }
    }

    #[test]
    fn tangents_are_orthonormal_and_across_the_normal() {
        let check = |n: Vector<3>| {
            let n = n.normalized().unwrap();
            let t = tangents(&n);
            assert_eq!(t.len(), 2);
            for (k, a) in t.iter().enumerate() {
                assert!((a.norm() - 1.0).abs() < 1e-14 && a.dot(&n).abs() < 1e-14);
                for b in &t[k + 1..] {
                    assert!(a.dot(b).abs() < 1e-14);
                }
            }
        };
        for n in [
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
            [0.3, -0.4, 0.5],
            [1.0, 1.0, 1.0],
        ] {
            check(Vector(n));
        }
        let t = tangents(&Vector([0.6, 0.8]));
        assert_eq!(t.len(), 1);
        assert!((t[0].dot(&Vector([0.6, 0.8]))).abs() < 1e-15);
    }

    #[test]
    fn a_disc_in_a_groove_pushes_its_supports_to_the_walls_and_sinks() {
        // Two discs on a frictionless floor between walls 5r apart, a third
        // in their groove: its weight pushes them apart until the walls hold
        // them (x = r and 4r), and it sinks into the wider groove, to height
        // r + √((2r)² − (1.5r)²). Hand-solved.
        let h = 1.0 + 3.0_f64.sqrt();
        let mut bed = Bed::of_discs(
            [5.0, 20.0],
            false,
            &[(1.5, 1.0, 1.0), (3.5, 1.0, 1.0), (2.5, h, 1.0)],
        );
        let r = compact(&mut bed, &default()).unwrap();
        assert_eq!(r.stopped_by, CompactionStop::Until, "{r:?}");
        let expect = [[1.0, 1.0], [4.0, 1.0], [2.5, 1.0 + 1.75_f64.sqrt()]];
        for (c, e) in bed.centres.iter().zip(expect) {
            assert!((*c - Vector(e)).norm() < 1e-7, "{c:?} != {e:?}");
        }
    }
}
