//! Contact forces and breakage (`docs/reference/fragmentation.md`) checked
//! against computations written from that model alone, not from `packbed::mechanics`:
//!
//! 1. a dense reference: the network, loads, stiffness matrix with ground
//!    springs, a dense Cholesky solve, the bond forces and the breakage loop,
//!    all built here from the bed and its contacts;
//! 2. the source study's own iterative relaxation (step 0.2 and alpha);
//! 3. hand-solved beds with their numbers worked out in comments;
//! 4. equilibrium, reactions and a symmetric stiffness on deposited beds.
//!
//! Vectors of the reference are 3-vectors whatever the dimension: a 2D point
//! `(x, y)` is `(x, y, 0)` and its rotation `θ` is the rotation vector `θ ẑ`
//! about the out-of-plane axis (index 2), so that one cross product serves
//! both dimensions.

use crate::common::{config, run};
use packbed::AnyBed;
use packbed::Bed;
use packbed::Wall;
use packbed::{find_contacts, Contacts};
use packbed::{fragment, Breaks, Fragmentation, FragmentationConfig, Load};
use packbed::{Real, Vector};
use packbed::{Solver, Springs};

type V3 = [Real; 3];

/// The total load of every load case (`docs/reference/fragmentation.md`, "Loads").
const F: Real = 1.0;
/// Ground spring relative to `k_n` (`docs/reference/fragmentation.md`, "Equilibrium").
const GROUND: Real = 1e-9;
const LOADS: [Load; 3] = [Load::Shear, Load::Compression, Load::Gravity];

// ---------------------------------------------------------------------------
// Small vector algebra
// ---------------------------------------------------------------------------

fn pad<const D: usize>(v: &Vector<D>) -> V3 {
    let mut o = [0.0; 3];
    o[..D].copy_from_slice(&v.0);
    o
}
fn unit(k: usize) -> V3 {
    let mut e = [0.0; 3];
    e[k] = 1.0;
    e
}

/// Shortest `b − a` over the periodic images of the horizontal axes.
fn min_image<const D: usize>(bed: &Bed<D>, a: V3, b: V3) -> V3 {
    let mut d = sub(b, a);
    if bed.container.periodic {
        for (k, dk) in d.iter_mut().enumerate().take(D - 1) {
            let w = bed.container.size[k];
            *dk -= w * (*dk / w).round();
        }
    }
    d
}

// ---------------------------------------------------------------------------
// The reference network (docs/reference/fragmentation.md, "The network" and "Loads")
// ---------------------------------------------------------------------------

#[derive(Clone, Debug)]
struct RBond {
    i: usize,
    j: Option<usize>,
    bead_i: usize,
    bead_j: Option<usize>,
    wall: Option<Wall>,
    /// Contact point (not wrapped), normal, and the point from each body's
    /// reference point (minimum image).
    p: V3,
    n: V3,
    arm_i: V3,
    arm_j: V3,
}

/// A group sharing a total: (body, lever arm of the point of action, weight).
#[derive(Clone, Debug)]
struct Group {
    members: Vec<(usize, V3, Real)>,
    total: V3,
}

#[derive(Clone, Debug)]
struct Net {
    dim: usize,
    ids: Vec<u32>,
    x: Vec<V3>,
    rho: Vec<Real>,
    bonds: Vec<RBond>,
    groups: Vec<Group>,
}

/// Loads as (body, arm, force).
type Applied = Vec<(usize, V3, V3)>;

impl Net {
    fn bodies(&self) -> usize {
        self.x.len()
    }
    /// Unknowns per body: D translations and 1 (2D) or 3 (3D) rotations.
    fn m(&self) -> usize {
        if self.dim == 2 {
            3
        } else {
            6
        }
    }
    /// Rotation axes of the rotation unknowns.
    fn axes(&self) -> Vec<V3> {
        if self.dim == 2 {
            vec![unit(2)]
        } else {
            vec![unit(0), unit(1), unit(2)]
        }
    }
    /// The motion of the material point at `arm` per unit of each unknown:
    /// translation `e_k`, rotation `axis × arm`.
    fn columns(&self, arm: V3) -> Vec<V3> {
        let mut c: Vec<V3> = (0..self.dim).map(unit).collect();
        c.extend(self.axes().into_iter().map(|a| cross(a, arm)));
        c
    }
    fn motion(&self, arm: V3, u: &[Real]) -> V3 {
        self.columns(arm)
            .iter()
            .zip(u)
            .fold([0.0; 3], |acc, (c, x)| add(acc, scale(*c, *x)))
    }
    /// `(force, torque)` of `f` at `arm` as a generalized force.
    fn generalized(&self, arm: V3, f: V3) -> Vec<Real> {
        self.columns(arm).iter().map(|c| dot(*c, f)).collect()
    }

    /// The loads on bodies with a bond (`bonded`); `None` when a group has
    /// no bonded member left.
    fn current(&self, bonded: &[bool]) -> Option<Applied> {
        let mut out = Vec::new();
        for g in &self.groups {
            let w: Real = g.members.iter().filter(|m| bonded[m.0]).map(|m| m.2).sum();
            if w <= 0.0 {
                return None;
            }
            for m in g.members.iter().filter(|m| bonded[m.0]) {
                out.push((m.0, m.1, scale(g.total, m.2 / w)));
            }
        }
        Some(out)
    }

    fn bonded(&self, alive: &[bool]) -> Vec<bool> {
        let mut b = vec![false; self.bodies()];
        for (g, _) in self.bonds.iter().zip(alive).filter(|(_, a)| **a) {
            b[g.i] = true;
            if let Some(j) = g.j {
                b[j] = true;
            }
        }
        b
    }
}

/// The 3 × 3 spring `k_n n nᵀ + k_t (I − n nᵀ)`.
fn spring(n: V3, kt: Real) -> [V3; 3] {
    let mut k = [[0.0; 3]; 3];
    for (r, row) in k.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            let i = if r == c { 1.0 } else { 0.0 };
            *v = n[r] * n[c] + kt * (i - n[r] * n[c]);
        }
    }
    k
}
fn apply3(k: &[V3; 3], v: V3) -> V3 {
    [dot(k[0], v), dot(k[1], v), dot(k[2], v)]
}

/// The union area (2D) or volume (3D) of equal overlapping beads of one
/// body with no three sharing a region: the balls minus each pairwise lens.
fn union_measure(dim: usize, beads: &[(V3, Real)]) -> Real {
    use std::f64::consts::PI;
    let mut total: Real = beads
        .iter()
        .map(|(_, r)| {
            if dim == 2 {
                PI * r * r
            } else {
                4.0 / 3.0 * PI * r * r * r
            }
        })
        .sum();
    for a in 0..beads.len() {
        for b in a + 1..beads.len() {
            let (r, rb) = (beads[a].1, beads[b].1);
            assert_eq!(r, rb, "the reference lens needs equal beads");
            let d = norm(sub(beads[a].0, beads[b].0));
            // (Beads touching end to end, `d` a rounding below 2r, share
            // nothing: the lens formula would cancel catastrophically.)
            if d < 2.0 * r * (1.0 - 1e-9) {
                total -= if dim == 2 {
                    2.0 * r * r * (d / (2.0 * r)).acos() - 0.5 * d * (4.0 * r * r - d * d).sqrt()
                } else {
                    PI * (4.0 * r + d) * (2.0 * r - d).powi(2) / 12.0
                };
            }
        }
    }
    total
}

/// The network and the loads of `bed`, from the model's description.
fn network<const D: usize>(bed: &Bed<D>, contacts: &Contacts, load: Load) -> Net {
    let n = bed.len();
    let up = D - 1;
    let c: Vec<V3> = bed.centres.iter().map(pad).collect();
    // Bodies numbered by first appearance; beads unwrapped by walking each
    // body's beads in bed order, each from the previous by minimum image.
    let mut ids: Vec<u32> = Vec::new();
    let mut body = vec![0usize; n];
    let mut unwrapped = vec![[0.0; 3]; n];
    let mut last: Vec<usize> = Vec::new();
    for k in 0..n {
        let b = match ids.iter().position(|&id| id == bed.bodies[k]) {
            Some(b) => b,
            None => {
                ids.push(bed.bodies[k]);
                last.push(usize::MAX);
                ids.len() - 1
            }
        };
        body[k] = b;
        unwrapped[k] = if last[b] == usize::MAX {
            c[k]
        } else {
            add(unwrapped[last[b]], min_image(bed, c[last[b]], c[k]))
        };
        last[b] = k;
    }
    let nb = ids.len();
    let mut x = vec![[0.0; 3]; nb];
    let mut count = vec![0.0; nb];
    for k in 0..n {
        x[body[k]] = add(x[body[k]], unwrapped[k]);
        count[body[k]] += 1.0;
    }
    for b in 0..nb {
        x[b] = scale(x[b], 1.0 / count[b]);
    }
    let mut rho = vec![0.0; nb];
    for k in 0..n {
        let b = body[k];
        rho[b] = Real::max(rho[b], norm(sub(unwrapped[k], x[b])) + bed.radii[k]);
    }
    // A lever arm from a reference point, by minimum image; it can be no
    // longer than the body's reach (else the image would be the wrong one).
    let arm = |b: usize, p: V3| {
        let a = min_image(bed, x[b], p);
        assert!(norm(a) <= rho[b] * (1.0 + 1e-9), "arm {a:?} of body {b}");
        a
    };
    let mut bonds = Vec::new();
    for pc in &contacts.pairs {
        let (a, b) = (pc.i as usize, pc.j as usize);
        let d = min_image(bed, c[a], c[b]);
        let nrm = scale(d, 1.0 / norm(d));
        let p = add(c[a], scale(nrm, bed.radii[a]));
        bonds.push(RBond {
            i: body[a],
            j: Some(body[b]),
            bead_i: a,
            bead_j: Some(b),
            wall: None,
            p,
            n: nrm,
            arm_i: arm(body[a], p),
            arm_j: arm(body[b], p),
        });
    }
    for wc in &contacts.walls {
        let a = wc.i as usize;
        // From the bead's centre towards the wall.
        let nrm = match wc.wall {
            Wall::Floor => scale(unit(up), -1.0),
            Wall::Low(k) => scale(unit(k), -1.0),
            Wall::High(k) => unit(k),
        };
        let p = add(c[a], scale(nrm, bed.radii[a]));
        bonds.push(RBond {
            i: body[a],
            j: None,
            bead_i: a,
            bead_j: None,
            wall: Some(wc.wall),
            p,
            n: nrm,
            arm_i: arm(body[a], p),
            arm_j: [0.0; 3],
        });
    }
    // Top bodies: no bond partner whose reference point is higher, and the
    // highest point within 2 r_max of the bed's highest point. Load at the
    // top of the body's highest bead (the first of equal beads).
    let mut covered = vec![false; nb];
    for g in &bonds {
        if let Some(j) = g.j {
            if x[j][up] > x[g.i][up] {
                covered[g.i] = true;
            }
            if x[g.i][up] > x[j][up] {
                covered[j] = true;
            }
        }
    }
    let mut high = vec![(usize::MAX, Real::NEG_INFINITY); nb];
    let mut low = vec![(usize::MAX, Real::INFINITY); nb];
    for k in 0..n {
        let (t, s) = (c[k][up] + bed.radii[k], c[k][up] - bed.radii[k]);
        if t > high[body[k]].1 {
            high[body[k]] = (k, t);
        }
        if s < low[body[k]].1 {
            low[body[k]] = (k, s);
        }
    }
    let top = high.iter().map(|h| h.1).fold(Real::NEG_INFINITY, Real::max);
    let r_max = bed.radii.iter().copied().fold(0.0, Real::max);
    let at = |b: usize, k: usize, dir: Real| arm(b, add(c[k], scale(unit(up), dir * bed.radii[k])));
    let tops = Group {
        members: (0..nb)
            .filter(|&b| !covered[b] && high[b].1 >= top - 2.0 * r_max)
            .map(|b| (b, at(b, high[b].0, 1.0), 1.0))
            .collect(),
        total: [0.0; 3],
    };
    let mut on_floor = vec![false; nb];
    for g in bonds.iter().filter(|g| g.wall == Some(Wall::Floor)) {
        on_floor[g.i] = true;
    }
    let bottoms = Group {
        members: (0..nb)
            .filter(|&b| on_floor[b])
            .map(|b| (b, at(b, low[b].0, -1.0), 1.0))
            .collect(),
        total: [0.0; 3],
    };
    let down = scale(unit(up), -F);
    let groups = match load {
        Load::Shear => vec![
            Group {
                total: scale(unit(0), F),
                ..tops
            },
            Group {
                total: scale(unit(0), -F),
                ..bottoms
            },
        ],
        Load::Compression => vec![Group {
            total: down,
            ..tops
        }],
        Load::Gravity => {
            let members = (0..nb)
                .map(|b| {
                    let beads: Vec<(V3, Real)> = (0..n)
                        .filter(|&k| body[k] == b)
                        .map(|k| (unwrapped[k], bed.radii[k]))
                        .collect();
                    (b, [0.0; 3], union_measure(D, &beads))
                })
                .collect();
            vec![Group {
                members,
                total: down,
            }]
        }
    };
    Net {
        dim: D,
        ids,
        x,
        rho,
        bonds,
        groups,
    }
}

// ---------------------------------------------------------------------------
// Dense stiffness, solve, bond forces
// ---------------------------------------------------------------------------

/// The dense stiffness matrix of the bonds `alive`, ground springs included.
fn stiffness(net: &Net, alive: &[bool], kt: Real) -> Vec<Vec<Real>> {
    let m = net.m();
    let size = net.bodies() * m;
    let mut a = vec![vec![0.0; size]; size];
    for (g, _) in net.bonds.iter().zip(alive).filter(|(_, a)| **a) {
        let k = spring(g.n, kt);
        // Δ = d_j − d_i: the ends with their signs.
        let mut ends = vec![(g.i, -1.0, net.columns(g.arm_i))];
        if let Some(j) = g.j {
            ends.push((j, 1.0, net.columns(g.arm_j)));
        }
        for (s, ss, cs) in &ends {
            for (t, st, ct) in &ends {
                for p in 0..m {
                    for q in 0..m {
                        a[s * m + p][t * m + q] += ss * st * dot(cs[p], apply3(&k, ct[q]));
                    }
                }
            }
        }
    }
    for b in 0..net.bodies() {
        for c in 0..m {
            a[b * m + c][b * m + c] += ground(net, b, c);
        }
    }
    a
}

fn ground(net: &Net, b: usize, c: usize) -> Real {
    if c < net.dim {
        GROUND
    } else {
        GROUND * net.rho[b] * net.rho[b]
    }
}

fn load_vector(net: &Net, loads: &Applied) -> Vec<Real> {
    let m = net.m();
    let mut f = vec![0.0; net.bodies() * m];
    for (b, arm, force) in loads {
        for (c, g) in net.generalized(*arm, *force).into_iter().enumerate() {
            f[b * m + c] += g;
        }
    }
    f
}

/// Solves `a x = b` by a dense Cholesky factorisation.
fn cholesky_solve(a: &[Vec<Real>], b: &[Real]) -> Vec<Real> {
    let n = b.len();
    let mut l = vec![vec![0.0; n]; n];
    for j in 0..n {
        let mut d = a[j][j];
        for k in 0..j {
            d -= l[j][k] * l[j][k];
        }
        assert!(d > 0.0, "not positive definite at {j}");
        let d = d.sqrt();
        l[j][j] = d;
        for i in j + 1..n {
            let mut s = a[i][j];
            for k in 0..j {
                s -= l[i][k] * l[j][k];
            }
            l[i][j] = s / d;
        }
    }
    let mut y = b.to_vec();
    for i in 0..n {
        for k in 0..i {
            y[i] -= l[i][k] * y[k];
        }
        y[i] /= l[i][i];
    }
    for i in (0..n).rev() {
        for k in i + 1..n {
            y[i] -= l[k][i] * y[k];
        }
        y[i] /= l[i][i];
    }
    y
}

/// The force each bond exerts on its body i (zero for a broken one).
fn bond_forces(net: &Net, alive: &[bool], u: &[Real], kt: Real) -> Vec<V3> {
    let m = net.m();
    net.bonds
        .iter()
        .zip(alive)
        .map(|(g, &on)| {
            if !on {
                return [0.0; 3];
            }
            let di = net.motion(g.arm_i, &u[g.i * m..g.i * m + m]);
            let dj =
                g.j.map_or([0.0; 3], |j| net.motion(g.arm_j, &u[j * m..j * m + m]));
            apply3(&spring(g.n, kt), sub(dj, di))
        })
        .collect()
}

fn solve_forces(net: &Net, alive: &[bool], loads: &Applied, kt: Real) -> (Vec<Real>, Vec<V3>) {
    let (a, b) = (stiffness(net, alive, kt), load_vector(net, loads));
    let mut u = cholesky_solve(&a, &b);
    // Two rounds of iterative refinement: mechanisms held by the ground
    // springs make the matrix ill-conditioned.
    for _ in 0..2 {
        let r: Vec<Real> = a
            .iter()
            .zip(&b)
            .map(|(row, bi)| bi - row.iter().zip(&u).map(|(x, y)| x * y).sum::<Real>())
            .collect();
        let du = cholesky_solve(&a, &r);
        for (x, d) in u.iter_mut().zip(du) {
            *x += d;
        }
    }
    let f = bond_forces(net, alive, &u, kt);
    (u, f)
}

// ---------------------------------------------------------------------------
// The reference breakage (docs/reference/fragmentation.md, "Breakage")
// ---------------------------------------------------------------------------

#[derive(Clone, Copy, Debug, PartialEq)]
struct RStep {
    bond: usize,
    magnitude: Real,
    fragments: u64,
    largest: u64,
}

/// Components of the network over the bodies and the five walls (floor,
/// x0, x1, y0, y1, each its own node): the root of every node.
fn components(net: &Net, alive: &[bool]) -> Vec<usize> {
    let nb = net.bodies();
    let node = |w: Wall| {
        nb + match w {
            Wall::Floor => 0,
            Wall::Low(k) => 1 + 2 * k,
            Wall::High(k) => 2 + 2 * k,
        }
    };
    // Label propagation: simple and plainly right.
    let mut label: Vec<usize> = (0..nb + 5).collect();
    loop {
        let mut changed = false;
        for (g, _) in net.bonds.iter().zip(alive).filter(|(_, a)| **a) {
            let o = g.j.unwrap_or_else(|| node(g.wall.unwrap()));
            let l = label[g.i].min(label[o]);
            if label[g.i] != l || label[o] != l {
                label[g.i] = l;
                label[o] = l;
                changed = true;
            }
        }
        if !changed {
            return label;
        }
    }
}

fn fragments(net: &Net, alive: &[bool]) -> (u64, u64) {
    let label = components(net, alive);
    let mut size = vec![0u64; label.len()];
    for &l in &label[..net.bodies()] {
        size[l] += 1;
    }
    (
        size.iter().filter(|&&s| s > 0).count() as u64,
        size.into_iter().max().unwrap(),
    )
}

/// A loaded body in a piece without any wall, or a load with nowhere to go.
fn failed(net: &Net, alive: &[bool], loads: Option<&Applied>) -> bool {
    let Some(loads) = loads else { return true };
    let label = components(net, alive);
    let nb = net.bodies();
    loads
        .iter()
        .filter(|l| norm(l.2) > 0.0)
        .any(|l| !(nb..nb + 5).any(|w| label[w] == label[l.0]))
}

/// The breaking sequence and the step of failure (0: the intact bed).
///
/// `theirs` is the sequence `fragment` broke. In a state where a mechanism
/// hangs on its ground springs (some body's ground force above `1e-6 F`)
/// the system is ill-conditioned and bonds that tie by symmetry come out of
/// any solve up to ~1e-7 apart; there the reference accepts `fragment`'s
/// pick if it is within `1e-6` of the largest (and follows it, counting
/// such steps in the third value). Elsewhere the pick must be the
/// reference's own.
fn breakage(
    net: &Net,
    kt: Real,
    breaks: Breaks,
    theirs: &[usize],
) -> (Vec<RStep>, Option<u64>, usize) {
    let m = net.m();
    let hanging = |u: &[Real]| {
        (0..net.bodies()).any(|b| {
            let g = |c: usize| ground(net, b, c) * u[b * m + c];
            let f = (0..net.dim).map(|c| g(c).powi(2)).sum::<Real>().sqrt();
            let t = (net.dim..m).map(|c| g(c).powi(2)).sum::<Real>().sqrt();
            f > 1e-6 * F || t > 1e-6 * F * net.rho[b]
        })
    };
    let mut alive = vec![true; net.bonds.len()];
    let loads = net.current(&net.bonded(&alive)).expect("loaded");
    let (u, f) = solve_forces(net, &alive, &loads, kt);
    let mut ill = hanging(&u);
    let mut followed = 0;
    let mut mag: Vec<Real> = f.iter().map(|f| norm(*f)).collect();
    let mut failure = failed(net, &alive, Some(&loads)).then_some(0);
    let mut steps = Vec::new();
    loop {
        match breaks {
            Breaks::Failure if failure.is_some() => break,
            Breaks::Count(n) if steps.len() as u64 >= n => break,
            _ => {}
        }
        // The largest; ties (equal to rounding: within 1e-9 of the largest,
        // the size of the ground springs' effect) to the first listed.
        let Some(top) = (0..mag.len())
            .filter(|&k| alive[k])
            .map(|k| mag[k])
            .reduce(Real::max)
        else {
            break;
        };
        let mut k = (0..mag.len())
            .find(|&k| alive[k] && mag[k] >= top * (1.0 - 1e-9))
            .unwrap();
        if let Some(&t) = theirs.get(steps.len()) {
            if t != k && ill && alive[t] && mag[t] >= top * (1.0 - 1e-6) {
                k = t;
                followed += 1;
            }
        }
        alive[k] = false;
        let now = net.current(&net.bonded(&alive));
        let (fragments, largest) = fragments(net, &alive);
        let step = steps.len() as u64 + 1;
        if failure.is_none() && failed(net, &alive, now.as_ref()) {
            failure = Some(step);
        }
        steps.push(RStep {
            bond: k,
            magnitude: mag[k],
            fragments,
            largest,
        });
        let more = match breaks {
            Breaks::Failure => failure.is_none(),
            Breaks::Count(n) => step < n,
        };
        let Some(now) = now.filter(|_| more) else {
            break;
        };
        let (u, f) = solve_forces(net, &alive, &now, kt);
        ill = hanging(&u);
        mag = f.iter().map(|f| norm(*f)).collect();
    }
    (steps, failure, followed)
}

// ---------------------------------------------------------------------------
// Comparison with `fragment`
// ---------------------------------------------------------------------------

/// Checks `fragment` on `bed` under `load` and `kt` against the reference:
/// the network, the loads, the stiffness operator, the forces of the intact
/// bed (to `1e-8 F`) and the breaking sequence (bonds, magnitudes to
/// `1e-7 F`, fragments). Returns the module's answer.
fn compare<const D: usize>(
    bed: &Bed<D>,
    what: &str,
    load: Load,
    kt: Real,
    breaks: Breaks,
) -> Fragmentation<D> {
    let what = format!("{what}, {}, kt {kt}", load.name());
    let contacts = find_contacts(bed, 1e-6);
    let net = network(bed, &contacts, load);
    let options = FragmentationConfig {
        load,
        breaks,
        kt_over_kn: kt,
    };
    let frag = fragment(bed, &contacts, &options).unwrap_or_else(|e| panic!("{what}: {e}"));
    let m = net.m();
    // Bodies.
    assert_eq!(frag.bodies.ids, net.ids, "{what}");
    for b in 0..net.bodies() {
        let off = min_image(bed, net.x[b], pad(&frag.bodies.reference[b]));
        assert!(norm(off) < 1e-9 * net.rho[b], "{what}: body {b} at {off:?}");
        assert!(
            (frag.bodies.reach[b] - net.rho[b]).abs() < 1e-9 * net.rho[b],
            "{what}"
        );
        for c in 0..m {
            let g = ground(&net, b, c);
            assert!((frag.ground[b * m + c] - g).abs() <= 1e-12 * g, "{what}");
        }
    }
    // Bonds: the same list in the same order, the same geometry.
    assert_eq!(frag.bonds.len(), net.bonds.len(), "{what}");
    for (k, (g, r)) in frag.bonds.iter().zip(&net.bonds).enumerate() {
        let same = (g.i as usize, g.j.map(|j| j as usize), g.bead_i as usize)
            == (r.i, r.j, r.bead_i)
            && g.bead_j.map(|j| j as usize) == r.bead_j
            && g.wall == r.wall;
        assert!(same, "{what}: bond {k}: {g:?} vs {r:?}");
        let tol = 1e-9 * net.rho[r.i];
        assert!(
            norm(sub(pad(&g.normal), r.n)) < 1e-12,
            "{what}: bond {k} normal"
        );
        assert!(
            norm(min_image(bed, r.p, pad(&g.point))) < tol,
            "{what}: bond {k} point"
        );
        assert!(
            norm(sub(pad(&g.arm_i), r.arm_i)) < tol,
            "{what}: bond {k} arm i"
        );
        if let Some(j) = r.j {
            let tol = 1e-9 * net.rho[j];
            assert!(
                norm(sub(pad(&g.arm_j), r.arm_j)) < tol,
                "{what}: bond {k} arm j"
            );
        }
    }
    // Loads: the same generalized load vector (arms from the points).
    let alive = vec![true; net.bonds.len()];
    let loads = net.current(&net.bonded(&alive)).expect("loaded");
    let theirs: Applied = frag
        .loads
        .iter()
        .map(|l| {
            let b = l.body as usize;
            (b, min_image(bed, net.x[b], pad(&l.point)), pad(&l.force))
        })
        .collect();
    let (lr, lm) = (load_vector(&net, &loads), load_vector(&net, &theirs));
    for (k, (a, b)) in lr.iter().zip(&lm).enumerate() {
        let s = net.rho[k / m].max(1.0);
        assert!(
            (a - b).abs() < 1e-12 * s,
            "{what}: load unknown {k}: {a} vs {b}"
        );
    }
    // The stiffness operator equals the dense matrix.
    let a = stiffness(&net, &alive, kt);
    let solver = Solver::new(
        &frag.bonds,
        &frag.bodies.reference,
        &frag.bodies.reach,
        Springs { kn: 1.0, kt },
    )
    .unwrap_or_else(|e| panic!("{what}: {e}"));
    let x: Vec<Real> = (0..lr.len())
        .map(|k| ((k * 7919) % 101) as Real / 50.0 - 1.0)
        .collect();
    let ax = solver.apply(&x);
    for (k, row) in a.iter().enumerate() {
        let want: Real = row.iter().zip(&x).map(|(a, x)| a * x).sum();
        let s: Real = row.iter().map(|a| a.abs()).sum::<Real>().max(1.0);
        assert!((ax[k] - want).abs() < 1e-12 * s, "{what}: (A x)[{k}]");
    }
    // Intact forces.
    let (_, forces) = solve_forces(&net, &alive, &loads, kt);
    let worst = forces
        .iter()
        .zip(&frag.forces)
        .map(|(r, f)| norm(sub(*r, pad(f))))
        .fold(0.0, Real::max);
    // A mechanism held by its ground springs (displacements ~1e8) makes the
    // system ill-conditioned (~1e10): both solves then round to ~1e-8.
    let tol = if frag.summary.unstable_bodies == 0 {
        1e-8
    } else {
        1e-7
    };
    assert!(worst < tol * F, "{what}: forces differ by {worst:e}");
    // Breakage.
    let got: Vec<usize> = frag.steps.iter().map(|s| s.bond).collect();
    let (steps, failure, followed) = breakage(&net, kt, breaks, &got);
    assert!(followed <= 2, "{what}: {followed} near ties followed");
    let want: Vec<usize> = steps.iter().map(|s| s.bond).collect();
    assert_eq!(got, want, "{what}: breaking order");
    for (s, r) in frag.steps.iter().zip(&steps) {
        assert!(
            (s.magnitude - r.magnitude).abs() < 1e-6 * r.magnitude.max(F),
            "{what}: step {} magnitude {} vs {}",
            s.step,
            s.magnitude,
            r.magnitude
        );
        assert_eq!(
            (s.fragments, s.largest_fragment),
            (r.fragments, r.largest),
            "{what}"
        );
    }
    assert_eq!(frag.summary.breaks_to_failure, failure, "{what}");
    assert_eq!(frag.summary.failed, failure.is_some(), "{what}");
    frag
}

fn deposited<const D: usize>(text: &str) -> Bed<D> {
    run::<D>(&config(text)).0
}

/// Discs and 3-bead chains of radius 10.
fn small_bed<const D: usize>(seed: u64, boxed: &str, count: u64) -> Bed<D> {
    deposited::<D>(&format!(
        "dim = {D}\nseed = {seed}\n[box]\n{boxed}\n[fill]\ncount = {count}\n\
         [[species]]\nradius = 10\n[[species]]\nradius = 10\nshape = \"chain\"\nbeads = 3\n"
    ))
}

fn chains_in(bed_bodies: &[u32]) -> usize {
    let mut ids = bed_bodies.to_vec();
    let n = ids.len();
    ids.sort_unstable();
    ids.dedup();
    n - ids.len()
}

// ---------------------------------------------------------------------------
// 1. The dense reference
// ---------------------------------------------------------------------------

#[test]
fn dense_reference_2d_walls_and_periodic_with_chains() {
    for (boxed, count) in [
        ("width = 100\nheight = 300", 24),
        ("width = 120\nheight = 300\nperiodic = true", 24),
    ] {
        let bed = small_bed::<2>(3, boxed, count);
        assert!(chains_in(&bed.bodies) > 0, "{boxed}: no chain");
        for load in LOADS {
            for kt in [1.0, 0.5] {
                compare(&bed, boxed, load, kt, Breaks::Failure);
            }
        }
    }
}

#[test]
fn dense_reference_3d_walls_and_periodic_with_chains() {
    for (boxed, count) in [
        ("width = 60\nheight = 300", 24),
        ("width = 80\nheight = 300\nperiodic = true", 24),
    ] {
        let bed = small_bed::<3>(2, boxed, count);
        assert!(chains_in(&bed.bodies) > 0, "{boxed}: no chain");
        for load in LOADS {
            for kt in [1.0, 0.5] {
                compare(&bed, boxed, load, kt, Breaks::Count(10));
            }
        }
    }
}

/// A periodic strip (width 8, radius 1) whose chain of two beads lies across
/// the periodic side: its beads at x = 7 and x = 1, its reference point at
/// x = 8 ≡ 0. Every lever arm of the chain must come from minimum images.
fn straddling_chain() -> Bed<2> {
    let h = 3.0_f64.sqrt();
    let mut bed = Bed::<2>::of_spheres([8.0, 20.0], true, Vec::new());
    bed.push_bead(Vector([7.0, 1.0 + h]), 1.0, 0, 0);
    bed.push_bead(Vector([1.0, 1.0 + h]), 1.0, 0, 0);
    for x in [0.0, 2.0, 4.0, 6.0] {
        bed.push(Vector([x, 1.0]), 1.0, 0);
    }
    for x in [3.0, 5.0] {
        bed.push(Vector([x, 1.0 + h]), 1.0, 0);
    }
    for x in [0.0, 4.0] {
        bed.push(Vector([x, 1.0 + 2.0 * h]), 1.0, 0);
    }
    bed
}

/// A walled box (width 8, radius 1) with a chain of three overlapping beads
/// (centres 1 apart) on the floor against the left wall, discs beside it and
/// on it.
fn overlapping_chain() -> Bed<2> {
    let h = 3.0_f64.sqrt();
    let mut bed = Bed::<2>::of_spheres([8.0, 20.0], false, Vec::new());
    for x in [1.0, 2.0, 3.0] {
        bed.push_bead(Vector([x, 1.0]), 1.0, 0, 0);
    }
    for (x, y) in [
        (5.0, 1.0),
        (7.0, 1.0),
        (4.0, 1.0 + h),
        (6.0, 1.0 + h),
        (5.0, 1.0 + 2.0 * h),
    ] {
        bed.push(Vector([x, y]), 1.0, 0);
    }
    bed
}

#[test]
fn dense_reference_hand_made_chains() {
    for (bed, what) in [
        (straddling_chain(), "chain across the periodic side"),
        (overlapping_chain(), "chain of overlapping beads"),
    ] {
        for load in LOADS {
            for kt in [1.0, 0.5] {
                compare(&bed, what, load, kt, Breaks::Failure);
            }
        }
    }
    // The chain's reference point is at x = 8 ≡ 0 (height 1 + √3), its
    // reach 2. Its bead at x = 7 touches the disc at (0, 1 + 2√3) through
    // that disc's image at x = 8: n = (1, √3)/2, point (7.5, 1 + 1.5√3),
    // arm from the reference point (−0.5, √3/2) (not 7.5 − 0 = 7.5 wide).
    let bed = straddling_chain();
    let f = fragment(
        &bed,
        &find_contacts(&bed, 1e-6),
        &FragmentationConfig::default(),
    )
    .unwrap();
    assert!((f.bodies.reach[0] - 2.0).abs() < 1e-12);
    let x0 = f.bodies.reference[0][0].rem_euclid(8.0);
    assert!(x0.abs() < 1e-12 || (x0 - 8.0).abs() < 1e-12, "{x0}");
    let g = f
        .bonds
        .iter()
        .find(|g| (g.bead_i, g.bead_j) == (0, Some(8)))
        .expect("the bond across the side");
    assert!((g.arm_i[0] + 0.5).abs() < 1e-12 && (g.arm_i[1] - 0.75_f64.sqrt()).abs() < 1e-12);
    assert!((g.normal[0] - 0.5).abs() < 1e-12, "{:?}", g.normal);
    // The gravity weights: the chain of overlapping beads weighs
    // 3π − 2 lens(d = 1) with lens = 2 acos(1/2) − (1/2)√3 = 2π/3 − √3/2.
    let bed = overlapping_chain();
    let f = fragment(
        &bed,
        &find_contacts(&bed, 1e-6),
        &FragmentationConfig {
            load: Load::Gravity,
            ..FragmentationConfig::default()
        },
    )
    .unwrap();
    let pi = std::f64::consts::PI;
    let chain = 3.0 * pi - 2.0 * (2.0 * pi / 3.0 - 0.75_f64.sqrt());
    let total = chain + 5.0 * pi;
    let w0 = f.loads.iter().find(|l| l.body == 0).unwrap().force[1];
    assert!((w0 + chain / total).abs() < 1e-12, "{w0}");
}

// ---------------------------------------------------------------------------
// 2. The source study's iterative relaxation
// ---------------------------------------------------------------------------

/// Relaxes the network body by body, as the source study did: each body's
/// translation moves by `step` × its out-of-balance force and its rotation
/// by `alpha = step / ρ²` × its out-of-balance torque (the bodies taken in
/// turn, each seeing its neighbours' latest shifts), until every body's
/// force and torque ÷ ρ fall below `tol`. Returns the displacements and
/// the number of sweeps.
fn relax(net: &Net, loads: &Applied, kt: Real, step: Real, tol: Real) -> (Vec<Real>, usize) {
    let m = net.m();
    let nb = net.bodies();
    let lv = load_vector(net, loads);
    let mut at: Vec<Vec<usize>> = vec![Vec::new(); nb];
    for (k, g) in net.bonds.iter().enumerate() {
        at[g.i].push(k);
        if let Some(j) = g.j {
            at[j].push(k);
        }
    }
    let mut u = vec![0.0; nb * m];
    for sweep in 1..=2_000_000 {
        let mut worst: Real = 0.0;
        for b in 0..nb {
            let mut r: Vec<Real> = (0..m)
                .map(|c| lv[b * m + c] - ground(net, b, c) * u[b * m + c])
                .collect();
            for &k in &at[b] {
                let g = &net.bonds[k];
                let di = net.motion(g.arm_i, &u[g.i * m..g.i * m + m]);
                let dj =
                    g.j.map_or([0.0; 3], |j| net.motion(g.arm_j, &u[j * m..j * m + m]));
                let f = apply3(&spring(g.n, kt), sub(dj, di));
                let (arm, f) = if g.i == b {
                    (g.arm_i, f)
                } else {
                    (g.arm_j, scale(f, -1.0))
                };
                for (rc, gc) in r.iter_mut().zip(net.generalized(arm, f)) {
                    *rc += gc;
                }
            }
            let alpha = step / (net.rho[b] * net.rho[b]);
            for c in 0..m {
                let (s, scale) = if c < net.dim {
                    (step, 1.0)
                } else {
                    (alpha, net.rho[b])
                };
                u[b * m + c] += s * r[c];
                worst = worst.max(r[c].abs() / scale);
            }
        }
        if worst < tol {
            return (u, sweep);
        }
    }
    panic!("the relaxation did not settle");
}

#[test]
fn the_study_s_relaxation_agrees() {
    // A few dozen discs of radii 1 and 1.5 deposited in a walled box.
    let bed = deposited::<2>(
        "dim = 2\nseed = 4\n[box]\nwidth = 12\nheight = 40\n[fill]\ncount = 30\n\
         [[species]]\nradius = 1\n[[species]]\nradius = 1.5\n",
    );
    let contacts = find_contacts(&bed, 1e-6);
    for load in [Load::Shear, Load::Compression] {
        let frag = fragment(
            &bed,
            &contacts,
            &FragmentationConfig {
                load,
                breaks: Breaks::Count(1),
                kt_over_kn: 1.0,
            },
        )
        .unwrap();
        assert_eq!(
            frag.summary.unstable_bodies, 0,
            "a mechanism would never settle"
        );
        let net = network(&bed, &contacts, load);
        let loads = net.current(&vec![true; net.bodies()]).unwrap();
        let alive = vec![true; net.bonds.len()];
        // The study stopped below 0.001; relaxing on to 1e-10 makes the
        // comparison a test of `fragment`, not of the study's tolerance.
        let (u, sweeps) = relax(&net, &loads, 1.0, 0.2, 1e-10);
        let forces = bond_forces(&net, &alive, &u, 1.0);
        let worst = forces
            .iter()
            .zip(&frag.forces)
            .map(|(r, f)| norm(sub(*r, pad(f))))
            .fold(0.0, Real::max);
        println!(
            "{}: {} bodies, {sweeps} sweeps, worst {worst:e}",
            load.name(),
            net.bodies()
        );
        assert!(
            worst < 1e-6 * F,
            "{}: forces differ by {worst:e}",
            load.name()
        );
    }
}

// ---------------------------------------------------------------------------
// 3. Hand-solved beds
// ---------------------------------------------------------------------------

fn compressed(bed: &Bed<2>) -> Fragmentation<2> {
    compare(bed, "hand-made", Load::Compression, 1.0, Breaks::Count(1))
}

#[test]
fn a_disc_on_the_floor_carries_the_whole_load() {
    // One disc, r = 1, at (5, 1) in a box 10 wide: one floor bond. The top
    // body takes −F ŷ at (5, 2); the floor bond (n = −ŷ, from the centre to
    // the floor) pushes back with +F ŷ: normal f·n = −1 (compression),
    // magnitude 1, tangential 0.
    let bed = Bed::of_spheres([10.0, 10.0], false, [([5.0, 1.0], 1.0, 0)]);
    let f = compressed(&bed);
    assert_eq!(f.bonds.len(), 1);
    assert_eq!(f.bonds[0].wall, Some(Wall::Floor));
    assert!((f.forces[0][1] - 1.0).abs() < 1e-8 && f.forces[0][0].abs() < 1e-8);
    assert!((f.normal(0) + 1.0).abs() < 1e-8 && f.tangential(0) < 1e-8);
    assert_eq!(f.summary.unstable_bodies, 0);
    assert_eq!((f.steps[0].bond, f.summary.failed), (0, true));
}

#[test]
fn a_column_of_three_discs_carries_the_load_through_every_bond() {
    // Discs r = 1 at (5, 1), (5, 3), (5, 5): bonds 0–1 and 1–2 (n = +ŷ) and
    // the floor (n = −ŷ). Only the top disc is loaded, −ŷ at (5, 6); each
    // disc passes it on, so every bond carries 1 in compression: the force
    // on the lower disc i of a pair is −ŷ (the upper pushes it down), normal
    // −1; the floor's on disc 0 is +ŷ, normal −1.
    let bed = Bed::of_spheres(
        [10.0, 10.0],
        false,
        [
            ([5.0, 1.0], 1.0, 0),
            ([5.0, 3.0], 1.0, 0),
            ([5.0, 5.0], 1.0, 0),
        ],
    );
    let f = compressed(&bed);
    assert_eq!(f.bonds.len(), 3);
    for k in 0..3 {
        assert!(
            (f.normal(k) + 1.0).abs() < 1e-8,
            "bond {k}: {}",
            f.normal(k)
        );
        assert!(f.tangential(k) < 1e-8 && (f.forces[k].norm() - 1.0).abs() < 1e-8);
    }
    assert_eq!(f.loads.len(), 1);
    assert_eq!(f.loads[0].body, 2);
}

#[test]
fn two_discs_between_walls_under_shear() {
    // Discs r = 1 at (1, 1) and (3, 1) in a box 4 wide: bonds, in the
    // listed order, B1 = 0–1 (n = x̂, point (2, 1)), B2 = disc 0 on the floor
    // (n = −ŷ), B3 = disc 0 on x0 (n = −x̂), B4 = disc 1 on the floor,
    // B5 = disc 1 on x1 (n = x̂). Both discs are top bodies (neither has a
    // partner higher than itself) and bottom bodies: each takes +½ x̂ at its
    // top and −½ x̂ at its bottom, no net force and a torque
    // (0,1)×(½,0) + (0,−1)×(−½,0) = −½ − ½ = −1.
    //
    // A point at arm a moves by (u − θ a_y, v + θ a_x); with k = k_t (k_n = 1)
    // the forces on body i (spring along n: 1, across: k) are
    //   B1 = (u1 − u0, k (v1 − v0 − θ1 − θ0)),  B2 = (−k (u0 + θ0), −v0),
    //   B3 = (−u0, −k (v0 − θ0)),               B4 = (−k (u1 + θ1), −v1),
    //   B5 = (−u1, −k (v1 + θ1)).
    // Try u0 = u1 = u, θ0 = θ1 = θ, v1 = −v0 = −v (the equations of disc 1
    // are then those of disc 0, so it is the solution):
    //   x of disc 0:  −k (u + θ) − u = 0             ⇒ u = −k θ / (1 + k)
    //   y of disc 0:  −2k (v + θ) − v − k (v − θ) = 0 ⇒ v = −k θ / (1 + 3k)
    //   torque:  B1_y + B2_x − B3_y − 1 = −k (v + u + 4θ) − 1 = 0
    //   ⇒ θ (4 − k/(1+k) − k/(1+3k)) = −1/k.
    // k = 1:   θ = −4/13, u = 2/13, v = 1/13: B1 = (0, 6/13), B2 = (2/13, −1/13),
    //          B3 = (−2/13, −5/13), B4 = (2/13, 1/13), B5 = (−2/13, 5/13).
    // k = 1/2: θ = −15/26, u = 5/26, v = 3/26: B1 = (0, 6/13), B2 = (5/26, −3/26),
    //          B3 = (−5/26, −9/26), B4 = (5/26, 3/26), B5 = (−5/26, 9/26).
    // Check: the floor and the walls push (4/13 − 4/13, −1/13 − 5/13 + 1/13 + 5/13)
    // = 0 in all, as the shear's net load is 0.
    let bed = Bed::of_spheres(
        [4.0, 10.0],
        false,
        [([1.0, 1.0], 1.0, 0), ([3.0, 1.0], 1.0, 0)],
    );
    let want = |k: Real| -> [[Real; 2]; 5] {
        let t = -1.0 / k / (4.0 - k / (1.0 + k) - k / (1.0 + 3.0 * k));
        let (u, v) = (-k * t / (1.0 + k), -k * t / (1.0 + 3.0 * k));
        [
            [0.0, -2.0 * k * (v + t)],
            [-k * (u + t), -v],
            [-u, -k * (v - t)],
            [-k * (u + t), v],
            [-u, -k * (-v + t)],
        ]
    };
    for (k, exact) in [
        (
            1.0,
            [
                [0.0, 6.0],
                [2.0, -1.0],
                [-2.0, -5.0],
                [2.0, 1.0],
                [-2.0, 5.0],
            ]
            .map(|f| f.map(|x| x / 13.0)),
        ),
        (
            0.5,
            [
                [0.0, 12.0],
                [5.0, -3.0],
                [-5.0, -9.0],
                [5.0, 3.0],
                [-5.0, 9.0],
            ]
            .map(|f| f.map(|x| x / 26.0)),
        ),
    ] {
        let f = compare(&bed, "two discs", Load::Shear, k, Breaks::Failure);
        let walls: Vec<_> = f.bonds.iter().map(|g| g.wall).collect();
        assert_eq!(
            walls,
            [
                None,
                Some(Wall::Floor),
                Some(Wall::Low(0)),
                Some(Wall::Floor),
                Some(Wall::High(0))
            ]
        );
        let formula = want(k);
        for b in 0..5 {
            for c in 0..2 {
                assert!(
                    (formula[b][c] - exact[b][c]).abs() < 1e-15,
                    "the algebra, bond {b}"
                );
                assert!(
                    (f.forces[b][c] - exact[b][c]).abs() < 1e-8,
                    "k {k}, bond {b}: {:?} vs {:?}",
                    f.forces[b],
                    exact[b]
                );
            }
        }
        assert_eq!(f.summary.unstable_bodies, 0);
    }
}

/// A bed mirror-symmetric about x = 4 (box 8 wide, walls): discs r = 1 in
/// three rows and a disc r = 1.5 on top in the middle. Every x is exact, so
/// the mirror image of each particle is exactly another particle.
fn mirror_bed() -> Bed<2> {
    let h = 3.0_f64.sqrt();
    let mut discs = Vec::new();
    for x in [1.0, 3.0, 5.0, 7.0] {
        discs.push(([x, 1.0], 1.0, 0));
    }
    for x in [2.0, 4.0, 6.0] {
        discs.push(([x, 1.0 + h], 1.0, 0));
    }
    for x in [1.0, 3.0, 5.0, 7.0] {
        discs.push(([x, 1.0 + 2.0 * h], 1.0, 0));
    }
    discs.push(([4.0, 1.0 + 2.0 * h + 5.25_f64.sqrt()], 1.5, 0));
    Bed::of_spheres([8.0, 20.0], false, discs)
}

#[test]
fn a_mirror_symmetric_bed_has_mirror_symmetric_forces() {
    let bed = mirror_bed();
    let mirror_of = |k: usize| {
        let c = bed.centres[k];
        (0..bed.len())
            .find(|&q| bed.centres[q][0] == 8.0 - c[0] && bed.centres[q][1] == c[1])
            .unwrap()
    };
    let mirror_wall = |w: Option<Wall>| match w {
        Some(Wall::Low(0)) => Some(Wall::High(0)),
        Some(Wall::High(0)) => Some(Wall::Low(0)),
        w => w,
    };
    for kt in [1.0, 0.5] {
        // The breakage in `compare` also checks that mirrored bonds tied
        // for the largest force break first listed first.
        let f = compare(&bed, "mirror bed", Load::Compression, kt, Breaks::Count(8));
        assert_eq!(
            f.loads.len(),
            3,
            "the big disc and the two outer discs of row 3"
        );
        for (k, g) in f.bonds.iter().enumerate() {
            // The mirror bond: beads mirrored (a pair may list them the other way).
            let (a, b) = (
                mirror_of(g.bead_i as usize),
                g.bead_j.map(|b| mirror_of(b as usize)),
            );
            let (q, swapped) = f
                .bonds
                .iter()
                .enumerate()
                .find_map(|(q, h)| {
                    let (hi, hj) = (h.bead_i as usize, h.bead_j.map(|b| b as usize));
                    if h.wall == mirror_wall(g.wall) && (hi, hj) == (a, b) {
                        Some((q, false))
                    } else if g.wall.is_none() && (Some(hi), hj) == (b, Some(a)) {
                        Some((q, true))
                    } else {
                        None
                    }
                })
                .unwrap_or_else(|| panic!("bond {k} has no mirror"));
            let s = if swapped { -1.0 } else { 1.0 };
            let (fk, fq) = (f.forces[k], f.forces[q]);
            assert!(
                (fk[0] + s * fq[0]).abs() < 1e-12 && (fk[1] - s * fq[1]).abs() < 1e-12,
                "kt {kt}: bond {k} {fk:?} and its mirror {q} {fq:?}"
            );
        }
        // The load reaches the floor: its bonds carry F upwards in all.
        let floor: Real = (0..f.bonds.len())
            .filter(|&k| f.bonds[k].wall == Some(Wall::Floor))
            .map(|k| f.forces[k][1])
            .sum();
        assert!(floor > 0.5 && floor < 1.0 + 1e-9, "{floor}");
    }
}

// ---------------------------------------------------------------------------
// 4. Equilibrium, reactions and symmetry on deposited beds
// ---------------------------------------------------------------------------

/// Every body's loads, bond forces and ground springs balance, torques
/// included (to `1e-6 F`, torques to `1e-6 F ρ_b`); bodies whose ground
/// springs carry more than `1e-6 F` (a torque counted at the reach) are
/// the unstable ones, counted as the summary does and few; every other
/// body balances its load with its bonds alone. The walls' reaction plus
/// the loads is zero. Returns the number of unstable bodies.
fn check_equilibrium<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    load: Load,
    what: &str,
) -> u64 {
    let what = format!("{what}, {}", load.name());
    let kt = 1.0;
    let frag = fragment(
        bed,
        contacts,
        &FragmentationConfig {
            load,
            breaks: Breaks::Count(1),
            kt_over_kn: kt,
        },
    )
    .unwrap_or_else(|e| panic!("{what}: {e}"));
    let net = network(bed, contacts, load);
    assert_eq!(net.bonds.len(), frag.bonds.len(), "{what}");
    let m = net.m();
    let mut r = vec![0.0; net.bodies() * m];
    let mut reaction = [0.0; 3];
    for (g, f) in net.bonds.iter().zip(&frag.forces) {
        let f = pad(f);
        for (c, x) in net.generalized(g.arm_i, f).into_iter().enumerate() {
            r[g.i * m + c] += x;
        }
        match g.j {
            Some(j) => {
                for (c, x) in net.generalized(g.arm_j, f).into_iter().enumerate() {
                    r[j * m + c] -= x;
                }
            }
            None => reaction = add(reaction, f),
        }
    }
    let mut applied = [0.0; 3];
    for l in &frag.loads {
        let b = l.body as usize;
        let arm = min_image(bed, net.x[b], pad(&l.point));
        for (c, x) in net.generalized(arm, pad(&l.force)).into_iter().enumerate() {
            r[b * m + c] += x;
        }
        applied = add(applied, pad(&l.force));
    }
    let total: Real = frag.loads.iter().map(|l| l.force.norm()).sum();
    assert!((total - if load == Load::Shear { 2.0 } else { 1.0 } * F).abs() < 1e-12);
    let mut unstable = 0;
    let mut held = [0.0; 3];
    for b in 0..net.bodies() {
        let (mut gf, mut gt, mut rf, mut rt) = (0.0, 0.0, 0.0, 0.0);
        for c in 0..m {
            let k = b * m + c;
            let gk = frag.ground[k] * frag.displacements[k];
            let resid = r[k] - gk;
            if c < D {
                held[c] += gk;
                gf += gk * gk;
                rf += r[k] * r[k];
                assert!(
                    resid.abs() < 1e-6 * F,
                    "{what}: body {b} force {c} off by {resid:e}"
                );
            } else {
                gt += gk * gk;
                rt += r[k] * r[k];
                let s = net.rho[b];
                assert!(
                    resid.abs() < 1e-6 * F * s,
                    "{what}: body {b} torque off by {resid:e}"
                );
            }
        }
        if gf.sqrt() > 1e-6 * F || gt.sqrt() / net.rho[b] > 1e-6 * F {
            unstable += 1;
        } else {
            assert!(
                rf.sqrt() < 1e-6 * F && rt.sqrt() < 1e-6 * F * net.rho[b],
                "{what}: body {b}"
            );
        }
    }
    assert_eq!(unstable, frag.summary.unstable_bodies, "{what}");
    assert!(
        unstable * 50 <= net.bodies() as u64,
        "{what}: {unstable} unstable bodies"
    );
    // The walls hold the loads, but for what the ground springs carry.
    let off = norm(add(add(reaction, applied), scale(held, -1.0)));
    assert!(
        off < 1e-6 * F,
        "{what}: reaction {reaction:?}, loads {applied:?}"
    );
    if unstable == 0 {
        assert!(
            norm(add(reaction, applied)) < 1e-6 * F,
            "{what}: {reaction:?}"
        );
    }
    // The stiffness is symmetric: xᵀ(Ay) = yᵀ(Ax).
    let solver = Solver::new(
        &frag.bonds,
        &frag.bodies.reference,
        &frag.bodies.reach,
        Springs { kn: 1.0, kt: 0.7 },
    )
    .unwrap();
    let n = net.bodies() * m;
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut random = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as Real / (1u64 << 53) as Real - 0.5
    };
    let x: Vec<Real> = (0..n).map(|_| random()).collect();
    let y: Vec<Real> = (0..n).map(|_| random()).collect();
    let (ax, ay) = (solver.apply(&x), solver.apply(&y));
    let xay: Real = x.iter().zip(&ay).map(|(a, b)| a * b).sum();
    let yax: Real = y.iter().zip(&ax).map(|(a, b)| a * b).sum();
    let scale_ = x.iter().zip(&ay).map(|(a, b)| (a * b).abs()).sum::<Real>();
    assert!((xay - yax).abs() < 1e-12 * scale_, "{what}: {xay} vs {yax}");
    unstable
}

fn finished(text: &str) -> packbed::FinishedBed {
    packbed::run_bed(&config(text), &mut |_| {}).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

#[test]
fn equilibrium_on_the_2d_thesis_bed() {
    let run = finished(
        "dim = 2\nseed = 5\n[box]\npreset = \"thesis\"\n[[species]]\nradius = 10\n[[species]]\nradius = 20\n",
    );
    let AnyBed::D2(bed) = &run.bed else {
        panic!("2D")
    };
    for load in LOADS {
        let u = check_equilibrium(bed, &run.contacts, load, "2D thesis bed");
        println!(
            "2D thesis bed ({} discs), {}: {u} unstable",
            bed.len(),
            load.name()
        );
    }
}

#[test]
fn equilibrium_on_a_small_3d_bed() {
    let run = finished(
        "dim = 3\nseed = 2\n[box]\nwidth = 120\nheight = 200\n[fill]\ncount = 150\n\
         [[species]]\nradius = 10\n[[species]]\nradius = 15\n",
    );
    let AnyBed::D3(bed) = &run.bed else {
        panic!("3D")
    };
    for load in LOADS {
        let u = check_equilibrium(bed, &run.contacts, load, "3D bed");
        println!(
            "3D bed ({} spheres), {}: {u} unstable",
            bed.len(),
            load.name()
        );
    }
}

#[test]
fn equilibrium_on_beds_of_chains() {
    for (dim, boxed) in [
        (2, "width = 300\nheight = 300\nperiodic = true"),
        (3, "width = 120\nheight = 300"),
    ] {
        let run = finished(&format!(
            "dim = {dim}\nseed = 7\n[box]\n{boxed}\n[fill]\ncount = 150\n\
             [[species]]\nradius = 10\nshape = \"chain\"\nbeads = 5\n"
        ));
        for load in LOADS {
            let u = match &run.bed {
                AnyBed::D2(bed) => check_equilibrium(bed, &run.contacts, load, "2D chains"),
                AnyBed::D3(bed) => check_equilibrium(bed, &run.contacts, load, "3D chains"),
            };
            println!("{dim}D chains, {}: {u} unstable", load.name());
        }
    }
}

// Arithmetic on plain triples, written here so that the test's computations
// stand apart from the library's.

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
