//! The pendular bridges the gas leaves at the contacts of drained pores.
//!
//! A bridge sits on a pair of particles that is an edge of the
//! triangulation, when every pore around that edge has drained (liquid still
//! filling one of them is that pore's liquid, not a bridge) and the pair is
//! close enough for a bridge of the gas pressure's curvature
//! ([`super::bridge`]). Its volume is shared among the pores around the
//! edge in proportion to their dihedral angle at it: a bridge is a body of
//! revolution about its pair's line of centres, so a cell's wedge holds
//! that share of it exactly as long as the bridge does not reach the cell's
//! two other faces (in 2D each of the two triangles on an edge holds half).
//! A pore whose bridges would hold more than its void is counted as
//! funicular (the rings have merged) and holds its void.
//!
//! Assumptions: the bridges are at equilibrium with the gas pressure (they
//! exchange liquid through films while the pressure rises), their walls are
//! the particles only (wall contacts hold none), and a bridge takes the
//! shape of an isolated pair's (the toroidal meridian).
// NaN-rejecting guards read `!(x > 0.0)`: true for NaN as well.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::super::network::{Network, Site};
use super::bridge;
use super::BridgeRow;
use crate::bed::Bed;
use crate::math::Real;
use rayon::prelude::*;

/// The widest gap, in the pair's harmonic mean radius, considered for a
/// bridge: past it no bridge of a drained pore's curvature exists (a bridge
/// ruptures at a gap of about its volume's cube root, Lian et al. 1993, and
/// a ring wider than this has merged with its neighbours).
pub const MAX_GAP: Real = 0.5;

/// One pair of particles that may hold a bridge.
#[derive(Clone, Debug)]
struct Edge {
    particles: [u32; 2],
    shift: [i8; 2],
    radii: [Real; 2],
    gap: Real,
    /// The pair's bridges (3D), its fold found once.
    pair: Option<bridge::Pair>,
    /// Where its pores lie in [`Pendular::around`].
    pores: std::ops::Range<usize>,
}

/// The most kinds of contact (pairs of radii) whose bridges are shared
/// ([`Pendular::totals`]); a search among them is a short linear scan.
const SHARED_KINDS: usize = 16;

/// A contact's kind: its two radii as bits (`None` for a pair with a gap, or
/// in 2D, where a bridge is a closed form).
fn contact_kind(e: &Edge) -> Option<(u64, u64)> {
    let p = e.pair.as_ref()?;
    p.touching()
        .then(|| (e.radii[0].to_bits(), e.radii[1].to_bits()))
}

/// The bridges of the recurring kinds of contact at a curve's pressures.
struct SharedContacts {
    kinds: Vec<(u64, u64)>,
    /// Per kind, the bridge volume at each pressure (`None`: no bridge).
    volumes: Vec<Vec<Option<Real>>>,
}

impl SharedContacts {
    /// Edge `e`'s volumes, if it is a contact of a shared kind.
    fn volumes(&self, e: &Edge) -> Option<&[Option<Real>]> {
        if self.kinds.is_empty() {
            return None;
        }
        let k = contact_kind(e)?;
        let i = self.kinds.iter().position(|&x| x == k)?;
        Some(&self.volumes[i])
    }
}

/// The candidate bridges of a network.
pub struct Pendular {
    edges: Vec<Edge>,
    /// The pores around each edge, edge after edge: (network pore, share of
    /// the bridge it holds, whether it is a pore of the slab). One array for
    /// all edges rather than a list per edge: millions of edges.
    around: Vec<(u32, Real, bool)>,
    theta: Real,
    dim: usize,
    /// Slab index of each network pore (`u32::MAX` off the slab).
    slab_index: Vec<u32>,
}

/// Bridge volumes at one pressure, per pore of the slab.
pub struct Volumes {
    /// Liquid in bridges per pore of the slab (capped at the pore's void).
    pub per_pore: Vec<Real>,
    /// Their sum.
    pub total: Real,
    /// Pores whose bridges would have held more than the void.
    pub funicular: u64,
}

/// An edge's key: its two particles, the second's image shift, the image.
type Key = (u32, u32, [i8; 2], [i8; 2]);

/// The key of an edge: its two sites, the first with no image shift on
/// periodic beds (all translates of a pair are one pair), lower site first.
fn key(a: Site, b: Site, periodic: bool) -> Option<Key> {
    if periodic {
        let rel = |x: Site, y: Site| {
            [
                y.image[0].wrapping_sub(x.image[0]),
                y.image[1].wrapping_sub(x.image[1]),
            ]
        };
        let (lo, hi) = if (a.particle, a.image) <= (b.particle, b.image) {
            (a, b)
        } else {
            (b, a)
        };
        if lo.particle == hi.particle {
            return None; // a particle and its own image: a box narrower than it
        }
        let r = rel(lo, hi);
        let (first, second, shift) = if lo.particle < hi.particle {
            (lo.particle, hi.particle, r)
        } else {
            (
                hi.particle,
                lo.particle,
                [r[0].wrapping_neg(), r[1].wrapping_neg()],
            )
        };
        Some((first, second, shift, [0; 2]))
    } else {
        // Across a side wall (a particle and a mirror image) is no contact.
        if a.image != b.image || a.particle == b.particle {
            return None;
        }
        let (p, q) = if a.particle < b.particle {
            (a.particle, b.particle)
        } else {
            (b.particle, a.particle)
        };
        Some((p, q, [0; 2], a.image))
    }
}

/// An edge key and a pore in one integer ordered as the tuple `(key, pore)`:
/// particles, shifts (each `i8` offset by 128 to order as unsigned), pore.
fn pack(k: Key, p: u32) -> u128 {
    let b = |x: i8| u128::from(x as u8 ^ 0x80);
    (u128::from(k.0) << 96)
        | (u128::from(k.1) << 64)
        | (b(k.2[0]) << 56)
        | (b(k.2[1]) << 48)
        | (b(k.3[0]) << 40)
        | (b(k.3[1]) << 32)
        | u128::from(p)
}

/// The particles and shift of a packed key (the pore is its low 32 bits).
fn unpack(x: u128) -> ([u32; 2], [i8; 2]) {
    let b = |s: u32| ((x >> s) as u8 ^ 0x80) as i8;
    ([(x >> 96) as u32, (x >> 64) as u32], [b(56), b(48)])
}

/// The two vertices of a tetrahedron off its edge `(i, j)`.
fn others(i: usize, j: usize) -> [usize; 2] {
    let mut out = [0; 2];
    let mut n = 0;
    for k in 0..4 {
        if k != i && k != j {
            out[n] = k;
            n += 1;
        }
    }
    out
}

impl Pendular {
    /// The pairs of `net` close enough for a bridge; `in_slab` flags the
    /// network's pores of the slab; `theta` is the contact angle.
    ///
    /// Pairs that hold no bridge at `kappa_lo`, the lowest curvature asked
    /// for later, are left out: a 3D bridge's meridian radius is below
    /// `1/κ`, so it spans no gap a 2D meniscus of radius `1/κ` cannot
    /// (closed form), and a bridge at a higher curvature spans less.
    pub fn new<const D: usize>(
        bed: &Bed<D>,
        net: &Network<D>,
        in_slab: &[bool],
        theta: Real,
        kappa_lo: Real,
    ) -> Pendular {
        let periodic = bed.container.periodic;
        // (packed key and pore, share, gap): sorted by the key, every pore
        // of an edge follows the edge's first. One pass over the cells in
        // order and one sort: gathering them particle by particle from each
        // particle's cells would read every cell four times, out of order.
        type Entry = (u128, Real, Real);
        let mut entries: Vec<Entry> = net
            .pores
            .par_iter()
            .enumerate()
            .flat_map_iter(|(p, pore)| {
                let pos: [[Real; D]; 4] = std::array::from_fn(|m| {
                    if m <= D {
                        pore.sites[m].position(bed)
                    } else {
                        [0.0; D]
                    }
                });
                let mut out: [Option<Entry>; 6] = [None; 6];
                let mut n = 0;
                for i in 0..=D {
                    for j in i + 1..=D {
                        let (a, b) = (pore.sites[i], pore.sites[j]);
                        let Some(k) = key(a, b, periodic) else {
                            continue;
                        };
                        let (ra, rb) = (
                            bed.radii[a.particle as usize],
                            bed.radii[b.particle as usize],
                        );
                        let dist = (0..D)
                            .map(|x| (pos[i][x] - pos[j][x]).powi(2))
                            .sum::<Real>()
                            .sqrt();
                        let gap = dist - ra - rb;
                        // Contacts and overlaps always hold a bridge; a gap only
                        // up to the reach of the lowest curvature's.
                        if !(gap <= 0.0) {
                            let harmonic = 2.0 * ra * rb / (ra + rb);
                            let reach = bridge::rupture_gap_2d(ra, rb, theta, kappa_lo)
                                .unwrap_or(Real::INFINITY)
                                .min(MAX_GAP * harmonic);
                            if !(gap <= reach) {
                                continue;
                            }
                        }
                        let share = if D == 3 {
                            let v: [[Real; 3]; 4] =
                                std::array::from_fn(|m| std::array::from_fn(|x| pos[m][x]));
                            let [u, w] = others(i, j);
                            let angle = super::super::geometry::dihedral(v[i], v[j], v[u], v[w]);
                            if angle.is_finite() {
                                angle / std::f64::consts::TAU
                            } else {
                                0.0
                            }
                        } else {
                            0.5
                        };
                        out[n] = Some((pack(k, p as u32), share, gap));
                        n += 1;
                    }
                }
                out.into_iter().flatten()
            })
            .collect();
        entries.par_sort_unstable_by_key(|e| e.0);
        // An edge starts where the key changes; its pores run to the next.
        let starts: Vec<usize> = (0..entries.len())
            .into_par_iter()
            .filter(|&i| i == 0 || entries[i].0 >> 32 != entries[i - 1].0 >> 32)
            .collect();
        let mut edges: Vec<Edge> = starts
            .par_iter()
            .enumerate()
            .map(|(j, &start)| {
                let end = starts.get(j + 1).copied().unwrap_or(entries.len());
                let (x, _, gap) = entries[start];
                let (particles, shift) = unpack(x);
                Edge {
                    particles,
                    shift,
                    radii: particles.map(|q| bed.radii[q as usize]),
                    gap,
                    pair: None,
                    pores: start..end,
                }
            })
            .collect();
        let around: Vec<(u32, Real, bool)> = entries
            .par_iter()
            .map(|&(x, share, _)| {
                let p = x as u32;
                (p, share, in_slab[p as usize])
            })
            .collect();
        drop(entries);
        if D == 3 {
            edges.par_iter_mut().for_each(|e| {
                e.pair = bridge::Pair::new(e.radii[0], e.radii[1], e.gap, theta);
            });
            edges.retain(|e| e.pair.is_some_and(|p| p.kappa_max >= kappa_lo));
        }
        let mut slab_index = vec![u32::MAX; net.pores.len()];
        let mut n = 0;
        for (p, &s) in in_slab.iter().enumerate() {
            if s {
                slab_index[p] = n;
                n += 1;
            }
        }
        Pendular {
            edges,
            around,
            theta,
            dim: D,
            slab_index,
        }
    }

    /// The pores around edge `e`.
    fn around(&self, e: &Edge) -> &[(u32, Real, bool)] {
        &self.around[e.pores.clone()]
    }

    /// The bridge of edge `e` at curvature `kappa`, if every pore around it
    /// has drained by then (`drains_at` per network pore).
    fn bridge(&self, e: &Edge, drains_at: &[Real], kappa: Real) -> Option<bridge::Bridge> {
        if !self
            .around(e)
            .iter()
            .all(|&(p, _, _)| drains_at[p as usize] <= kappa)
        {
            return None;
        }
        self.bridge_of(e, kappa)
    }

    /// The bridge of edge `e` at curvature `kappa`, its pores drained.
    fn bridge_of(&self, e: &Edge, kappa: Real) -> Option<bridge::Bridge> {
        self.bridge_after(e, kappa, None)
    }

    /// [`Pendular::bridge_of`], with the meridian radius of its bridge at a
    /// lower curvature when known ([`bridge::Pair::bridge_below`]).
    fn bridge_after(&self, e: &Edge, kappa: Real, above: Option<Real>) -> Option<bridge::Bridge> {
        let [r1, r2] = e.radii;
        if self.dim == 3 {
            e.pair.as_ref()?.bridge_below(kappa, above)
        } else {
            bridge::bridge_2d(r1, r2, e.gap, self.theta, kappa).map(|b| bridge::Bridge {
                volume: b.area,
                neck_radius: b.neck_half_width,
                half_angle_1: b.half_angle_1,
                half_angle_2: b.half_angle_2,
                meridian_radius: b.meridian_radius,
            })
        }
    }

    /// The first of the ascending curvatures `kappas` at which every pore
    /// around `e` has drained (`kappas.len()`: none).
    fn first_drained(&self, e: &Edge, drains_at: &[Real], kappas: &[Real]) -> usize {
        let t = self
            .around(e)
            .iter()
            .map(|p| drains_at[p.0 as usize])
            .fold(Real::NEG_INFINITY, Real::max);
        kappas.partition_point(|&k| !(t <= k))
    }

    /// The liquid in bridges of the slab's pores at each of the ascending
    /// curvatures `kappas`, each pore's capped at its void (`voids`, by slab
    /// index): [`Pendular::volumes`]' totals, for a whole curve at once.
    ///
    /// Edge by edge rather than pressure by pressure: an edge's bridges are
    /// found from the pressure its pores have drained by on, and no per-pore
    /// table is built for each pressure. The cap is exact: a pore whose
    /// bridges at their largest (each at the lowest pressure it exists at
    /// here) fit its void is never capped; the few others are summed pore by
    /// pore. Sums in edge-block order: the same bits on any thread count.
    pub fn totals(&self, drains_at: &[Real], kappas: &[Real], voids: &[Real]) -> Vec<Real> {
        const BLOCK: usize = 4096;
        let n = kappas.len();
        let slab_share =
            |e: &Edge| -> Real { self.around(e).iter().filter(|p| p.2).map(|p| p.1).sum() };
        let shared = self.shared_contacts(kappas);
        let blocks: Vec<(Vec<Real>, Vec<Real>)> = self
            .edges
            .par_chunks(BLOCK)
            .map(|chunk| {
                let mut sums = vec![0.0; n];
                let mut largest = vec![0.0; chunk.len()];
                for (e, most) in chunk.iter().zip(&mut largest) {
                    let share = slab_share(e);
                    if !(share > 0.0) {
                        continue;
                    }
                    if let Some(volumes) = shared.volumes(e) {
                        let first = self.first_drained(e, drains_at, kappas);
                        for (sum, v) in sums[first..].iter_mut().zip(&volumes[first..]) {
                            if let Some(v) = *v {
                                *sum += share * v;
                                *most = Real::max(*most, v);
                            }
                        }
                        continue;
                    }
                    // The pressures in turn: each bridge's radius starts the next's search.
                    let mut above = None;
                    for k in self.first_drained(e, drains_at, kappas)..n {
                        if let Some(b) = self.bridge_after(e, kappas[k], above) {
                            above = Some(b.meridian_radius);
                            sums[k] += share * b.volume;
                            *most = Real::max(*most, b.volume);
                        }
                    }
                }
                (sums, largest)
            })
            .collect();
        let mut totals = vec![0.0; n];
        for (sums, _) in &blocks {
            for (t, s) in totals.iter_mut().zip(sums) {
                *t += s;
            }
        }
        let largest: Vec<Real> = blocks.into_iter().flat_map(|b| b.1).collect();
        // Pores the cap may bind: their bridges at their largest overflow.
        let mut upper = vec![0.0; voids.len()];
        for (e, &most) in self.edges.iter().zip(&largest) {
            if most > 0.0 {
                for &(p, share, slab) in self.around(e) {
                    if slab {
                        upper[self.slab_index[p as usize] as usize] += share * most;
                    }
                }
            }
        }
        let mut edges_of: Vec<Vec<(usize, Real)>> = Vec::new();
        let mut slot = vec![u32::MAX; voids.len()];
        let mut capped: Vec<usize> = Vec::new();
        for (i, (&u, &v)) in upper.iter().zip(voids).enumerate() {
            if u > v {
                slot[i] = capped.len() as u32;
                capped.push(i);
                edges_of.push(Vec::new());
            }
        }
        if capped.is_empty() {
            return totals;
        }
        for (k, (e, &most)) in self.edges.iter().zip(&largest).enumerate() {
            if most > 0.0 {
                for &(p, share, slab) in self.around(e) {
                    if slab {
                        let s = slot[self.slab_index[p as usize] as usize];
                        if s != u32::MAX {
                            edges_of[s as usize].push((k, share));
                        }
                    }
                }
            }
        }
        let corrections: Vec<Vec<Real>> = capped
            .par_iter()
            .zip(&edges_of)
            .map(|(&i, edges)| {
                let mut held = vec![0.0; n];
                for &(k, share) in edges {
                    let e = &self.edges[k];
                    for (j, h) in held
                        .iter_mut()
                        .enumerate()
                        .skip(self.first_drained(e, drains_at, kappas))
                    {
                        if let Some(b) = self.bridge_of(e, kappas[j]) {
                            *h += share * b.volume;
                        }
                    }
                }
                held.iter().map(|&h| h.min(voids[i]) - h).collect()
            })
            .collect();
        for c in &corrections {
            for (t, x) in totals.iter_mut().zip(c) {
                *t += x;
            }
        }
        totals
    }

    /// The bridge volumes at each of `kappas` of the kinds of contact that
    /// recur: a touching pair's bridge depends on its two radii alone (a
    /// gap below [`bridge::CONTACT_GAP`] is a contact), so the contacts of a
    /// bed of few sizes (equal spheres, a few species: most of its pairs)
    /// share one bridge per pressure, found once instead of once a contact.
    /// A bed of many sizes (more than [`SHARED_KINDS`] radii among its
    /// contacts) shares none.
    fn shared_contacts(&self, kappas: &[Real]) -> SharedContacts {
        let mut kinds: Vec<(u64, u64)> = Vec::new();
        if self.dim == 3 {
            for e in &self.edges {
                if let Some(k) = contact_kind(e) {
                    if !kinds.contains(&k) {
                        if kinds.len() == SHARED_KINDS {
                            kinds.clear();
                            break;
                        }
                        kinds.push(k);
                    }
                }
            }
        }
        let volumes = kinds
            .par_iter()
            .map(|&(r1, r2)| {
                let pair =
                    bridge::Pair::new(Real::from_bits(r1), Real::from_bits(r2), 0.0, self.theta);
                let mut above = None;
                kappas
                    .iter()
                    .map(|&kappa| {
                        let b = pair.as_ref()?.bridge_below(kappa, above)?;
                        above = Some(b.meridian_radius);
                        Some(b.volume)
                    })
                    .collect()
            })
            .collect();
        SharedContacts { kinds, volumes }
    }

    /// How many kinds of contact share their bridges.
    #[cfg(test)]
    pub(crate) fn shared_kinds(&self) -> usize {
        self.shared_contacts(&[1.0]).kinds.len()
    }

    /// Number of candidate pairs.
    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// Pair `e`'s particles, the periods the second lies from the first, its
    /// radii and its surface gap.
    pub fn pair(&self, e: usize) -> ([u32; 2], [i8; 2], [Real; 2], Real) {
        let x = &self.edges[e];
        (x.particles, x.shift, x.radii, x.gap)
    }

    /// Each network pore's pairs as a compressed table: the pairs of pore `p`
    /// are `links[start[p]..start[p + 1]]`, each (pair, the share of its
    /// bridge the pore holds).
    pub fn pores_pairs(&self, pores: usize) -> (Vec<u32>, Vec<(u32, Real)>) {
        let mut start = vec![0u32; pores + 1];
        for e in &self.edges {
            for &(p, _, _) in self.around(e) {
                start[p as usize + 1] += 1;
            }
        }
        for p in 0..pores {
            start[p + 1] += start[p];
        }
        let mut fill = start.clone();
        let mut links = vec![(0, 0.0); start[pores] as usize];
        for (k, e) in self.edges.iter().enumerate() {
            for &(p, share, _) in self.around(e) {
                links[fill[p as usize] as usize] = (k as u32, share);
                fill[p as usize] += 1;
            }
        }
        (start, links)
    }

    /// The volume of pair `e`'s bridge at curvature `kappa` (its pores
    /// drained or not), if one exists.
    pub fn bridge_volume(&self, e: usize, kappa: Real) -> Option<Real> {
        self.bridge_of(&self.edges[e], kappa).map(|b| b.volume)
    }

    /// The liquid of pair `e`'s bridge at `kappa` in the slab's pores (the
    /// volume `liquid.csv` gives it), 0 unless every pore around it has
    /// drained by then.
    pub fn slab_bridge(&self, e: usize, drains_at: &[Real], kappa: Real) -> Real {
        let x = &self.edges[e];
        let share: Real = self.around(x).iter().filter(|p| p.2).map(|p| p.1).sum();
        if !(share > 0.0) {
            return 0.0;
        }
        self.bridge(x, drains_at, kappa)
            .map_or(0.0, |b| share * b.volume)
    }

    /// The neck radius of a body of `volume` shaped as pair `e`'s pendular
    /// bridge ([`neck_for_volume`]).
    pub fn neck_for_volume(&self, e: usize, volume: Real) -> Option<Real> {
        let x = &self.edges[e];
        let bridge = |kappa: Real| self.bridge_of(x, kappa).map(|b| (b.volume, b.neck_radius));
        let fold = x.pair.map(|p| p.kappa_max).filter(|k| k.is_finite());
        neck_for_volume(bridge, x.radii[0].min(x.radii[1]), volume, fold)
    }

    /// The liquid in bridges per pore of the slab at curvature `kappa`.
    /// `members` are the slab's pores (network indices), `voids` their void.
    pub fn volumes(
        &self,
        drains_at: &[Real],
        kappa: Real,
        members: &[u32],
        voids: &[Real],
    ) -> Volumes {
        let mut per_pore = vec![0.0; members.len()];
        // The bridges on every core, added up in edge order (the same bits
        // whatever the thread count).
        let volumes: Vec<Real> = self
            .edges
            .par_iter()
            .map(|e| {
                if !self.around(e).iter().any(|p| p.2) {
                    return 0.0;
                }
                self.bridge(e, drains_at, kappa).map_or(0.0, |b| b.volume)
            })
            .collect();
        for (e, &v) in self.edges.iter().zip(&volumes) {
            if v > 0.0 {
                for &(p, share, slab) in self.around(e) {
                    if slab {
                        per_pore[self.slab_index[p as usize] as usize] += share * v;
                    }
                }
            }
        }
        let mut funicular = 0;
        for (v, &void) in per_pore.iter_mut().zip(voids) {
            if *v > void {
                *v = void;
                funicular += 1;
            }
        }
        Volumes {
            total: per_pore.iter().sum(),
            per_pore,
            funicular,
        }
    }

    /// The bridges at curvature `kappa` with a share in the slab's pores.
    pub fn bridges(&self, drains_at: &[Real], kappa: Real) -> Vec<BridgeRow> {
        self.edges
            .iter()
            .filter(|e| self.around(e).iter().any(|p| p.2))
            .filter_map(|e| {
                let b = self.bridge(e, drains_at, kappa)?;
                let share: Real = self.around(e).iter().filter(|p| p.2).map(|p| p.1).sum();
                Some(BridgeRow {
                    particles: e.particles,
                    shift: e.shift,
                    gap: e.gap,
                    volume: share * b.volume,
                    neck_radius: b.neck_radius,
                    filling_angle: [b.half_angle_1.to_degrees(), b.half_angle_2.to_degrees()],
                })
            })
            .collect()
    }
}

/// The neck radius of a body of `volume` shaped as a pendular bridge (the
/// shape a bridge's liquid leaves its solid in), `bridge(κ)` giving the
/// (volume, neck radius) of the pair's bridge at curvature `κ`, `r` the
/// smaller radius. The bridge of that volume is the root of
/// `ln V(κ) = ln volume` (a bridge's volume falls as its curvature rises),
/// found by Brent's method in `ln κ`. `None` when no bridge of that volume
/// spans the gap (it is smaller than the bridge at the gap's largest
/// curvature). A volume above the widest bridge the model holds (from
/// curvature `10⁻³/r` up) gets that bridge's neck. `fold`, when known, is
/// the highest curvature a bridge of the gap has (found by bisection
/// otherwise).
pub fn neck_for_volume(
    bridge: impl Fn(Real) -> Option<(Real, Real)>,
    r: Real,
    volume: Real,
    fold: Option<Real>,
) -> Option<Real> {
    if !(volume > 0.0 && r > 0.0) {
        return None;
    }
    // `x = ln(κ r) + 10` stays positive over the range searched, so that a
    // relative tolerance on it means a relative one on κ.
    let kappa = |x: Real| (x - 10.0).exp() / r;
    let at = |x: Real| bridge(kappa(x));
    let (lo0, top) = ((1e-3f64).ln() + 10.0, (1e9f64).ln() + 10.0);
    // The model may hold no bridge at the widest curvatures (filling
    // angles past its range): start from the first that has one.
    let steps = 48;
    let lo = (0..=steps)
        .map(|k| lo0 + (top - lo0) * k as Real / steps as Real)
        .find(|&x| at(x).is_some())?;
    let (v_lo, neck_lo) = at(lo)?;
    if v_lo <= volume {
        return Some(neck_lo);
    }
    // The highest curvature with a bridge: `top`, or a gap's fold.
    let hi = if let Some(x) = fold
        .map(|k| (k * r).ln() + 10.0)
        .filter(|&x| x > lo && x < top && at(x).is_some())
    {
        x
    } else if at(top).is_some() {
        top
    } else {
        let (mut a, mut b) = (lo, top);
        for _ in 0..60 {
            let mid = 0.5 * (a + b);
            if at(mid).is_some() {
                a = mid;
            } else {
                b = mid;
            }
        }
        a
    };
    let (v_hi, neck_hi) = at(hi)?;
    if v_hi >= volume {
        // Past a gap's fold the liquid would have ruptured into two caps
        // before shrinking to `volume`; at contact the bridge is that small.
        return if hi < top && v_hi > volume * (1.0 + 1e-9) {
            None
        } else {
            Some(neck_hi)
        };
    }
    let g = |x: Real| at(x).map(|b| volume.ln() - b.0.ln());
    let root = super::bridge::brent(
        &g,
        lo,
        volume.ln() - v_lo.ln(),
        hi,
        volume.ln() - v_hi.ln(),
        1e-14,
    )?;
    at(root).map(|b| b.1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    type Key = (u32, u32, [i8; 2], [i8; 2]);

    fn key_strategy() -> impl Strategy<Value = (Key, u32)> {
        (
            (
                any::<u32>(),
                any::<u32>(),
                any::<[i8; 2]>(),
                any::<[i8; 2]>(),
            ),
            any::<u32>(),
        )
    }

    proptest! {
        /// The packed keys sort as the tuples they pack, and give the
        /// particles and shift back.
        #[test]
        fn prop_pack_orders_as_the_tuple(a in key_strategy(), b in key_strategy()) {
            let (pa, pb) = (pack(a.0, a.1), pack(b.0, b.1));
            prop_assert_eq!(pa.cmp(&pb), a.cmp(&b));
            prop_assert_eq!(unpack(pa), ([a.0 .0, a.0 .1], a.0 .2));
            prop_assert_eq!(pa as u32, a.1);
            // Same edge exactly when the high 96 bits agree.
            prop_assert_eq!(pa >> 32 == pb >> 32, a.0 == b.0);
        }
    }
}
