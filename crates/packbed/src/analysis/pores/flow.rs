//! Stokes flow through the pore network: the pore-scale finite volume of
//! Chareyre, Cortis, Catalano & Barthélemy (2012), one pressure per pore and
//! one conductance per throat, and the permeability along each axis.
//!
//! The pressure is driven by a unit mean gradient along the axis, written
//! `P = −x + p̃`. Along z the pores below and above the slab hold `P = −z` at
//! their own height, so the slab between them sees exactly the unit gradient
//! whatever their spread; along a periodic side axis `p̃` is periodic and a
//! throat to a translate carries the jump of one period. Then the Darcy
//! velocity is `k / μ` and `k = μ Q / A`.

// `!(a > b)` is meant: a NaN must take the closed or zero branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::network::{Network, Pore, ThroatShape};
use super::FlowOptions;
use crate::config::Conductance;
use crate::math::sparse::{solve_spd_shifted, SpdError, Systems};
use crate::math::{Real, Vector};
use rayon::prelude::*;
use serde::Serialize;

/// A throat shorter than this fraction of the mean radius of its spheres
/// joins its two pores into one node (their power centres coincide).
pub const LENGTH_FLOOR: Real = 1e-3;

/// A throat whose constriction is below this fraction of its spheres' mean
/// radius is shut: the default contact tolerance.
pub const SHUT: Real = 1e-6;

/// A net flux below this fraction of the summed throat fluxes is rounding.
const NOISE: Real = 1e-9;

/// The largest `imbalance` a permeability is reported with; beyond it the
/// solution does not carry one flux through the slab, and a `k` from it would
/// not be the network's (`docs/reference/pores.md`, "Flow and permeability").
pub const BALANCE: Real = 1e-9;

/// Throats with a conductance below this fraction of the median are closed.
pub const CLOSED: Real = 1e-12;

/// The permeability along one axis.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct AxisFlow {
    /// `x`, `y` or `z`.
    pub axis: &'static str,
    /// Permeability, length² (length per unit depth in 2D); `None` (null)
    /// when the flux balance fails ([`BALANCE`]): the number is not the
    /// network's.
    pub k: Option<Real>,
    /// Flux through the slab under the unit gradient with `μ` = viscosity.
    pub flux: Real,
    /// |inflow − outflow| / inflow (z), or the same between the flux across
    /// the periodic boundary and the mean flux (x, y).
    pub imbalance: Real,
    /// Pores whose pressure was solved for.
    pub pores: u64,
}

/// The flow solution along the requested axes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Flow {
    /// One entry per axis, in the order asked.
    pub axes: Vec<AxisFlow>,
    /// Conductance of each throat of the network (0 for a closed throat).
    pub conductance: Vec<Real>,
    /// Pressure per pore along each axis (NaN-free; 0 off the slab).
    pub pressure: Vec<Vec<Real>>,
    /// Flux per throat along each axis (from its first pore to its second).
    pub throat_flux: Vec<Vec<Real>>,
    /// Throats shorter than [`LENGTH_FLOOR`] whose pores were merged.
    pub merged: u64,
}

/// Why a flow could not be solved.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FlowError {
    /// The slab holds no pore with an open path between inlet and outlet.
    NoPath(&'static str),
    /// The linear system could not be factored.
    Solver(SpdError),
}

/// The network the pressure equations are written on: pores whose power
/// centres coincide (within [`LENGTH_FLOOR`]) are one node, as they are one
/// vertex of the power diagram; a lattice's cospherical cells are split by the
/// perturbation into tetrahedra that share their power centre, and the facets
/// between them enclose no fluid.
struct Nodes<'n, const D: usize> {
    /// The network's pores.
    pores: &'n [Pore<D>],
    /// Node of each pore, and the periods the pore lies from the node's centre.
    of_pore: Vec<(u32, [i8; 2])>,
    /// Each node's first pore, whose power centre is the node's (a copy of
    /// the centres here was 0.15 GB at 10^6 spheres).
    first: Vec<u32>,
    /// True for the nodes in the slab.
    in_slab: Vec<bool>,
}

/// (node a, node b, periods of b's image, throat).
type Link = (u32, u32, [i8; 2], u32);

impl<const D: usize> Nodes<'_, D> {
    fn centre(&self, node: usize) -> &[Real; D] {
        &self.pores[self.first[node] as usize].centre
    }

    fn len(&self) -> usize {
        self.first.len()
    }
}

fn nodes<'n, const D: usize>(
    net: &'n Network<D>,
    merge: &[bool],
    slab: (Real, Real),
) -> Nodes<'n, D> {
    let n = net.pores.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    let mut offset = vec![[0i8; 2]; n];
    for (t, th) in net.throats.iter().enumerate() {
        if !merge[t] {
            continue;
        }
        let (ra, oa) = root(&mut parent, &mut offset, th.pores[0] as usize);
        let (rb, ob) = root(&mut parent, &mut offset, th.pores[1] as usize);
        if ra == rb {
            continue;
        }
        // b's image at shift s is where a is: b = a − s.
        let s = th.shift;
        parent[rb] = ra as u32;
        offset[rb] = [oa[0] - s[0] - ob[0], oa[1] - s[1] - ob[1]];
    }
    let mut id = vec![u32::MAX; n];
    let mut first = Vec::new();
    let mut in_slab = Vec::new();
    let mut of_pore = Vec::with_capacity(n);
    for p in 0..n {
        let (r, o) = root(&mut parent, &mut offset, p);
        if id[r] == u32::MAX {
            id[r] = first.len() as u32;
            let c = net.pores[r].centre;
            first.push(r as u32);
            in_slab.push(c[D - 1] >= slab.0 && c[D - 1] <= slab.1);
        }
        of_pore.push((id[r], o));
    }
    Nodes {
        pores: &net.pores,
        of_pore,
        first,
        in_slab,
    }
}

/// The open throats between nodes, in throat order: (node a, node b, periods
/// of b's image, throat); the conductance is the throat's.
fn links<const D: usize>(
    net: &Network<D>,
    nodes: &Nodes<D>,
    g: &[Real],
    merge: &[bool],
) -> Vec<Link> {
    let open = |t: usize| !merge[t] && g[t] > 0.0;
    // Sized first: grown by doubling, the 0.2 GB of a 10^6-sphere bed's links
    // were copied on the way (`perf`: realloc), with up to half their room
    // unused at the end.
    let mut links = Vec::with_capacity((0..net.throats.len()).filter(|&t| open(t)).count());
    links.extend(
        net.throats
            .iter()
            .enumerate()
            .filter(|&(t, _)| open(t))
            .map(|(t, th)| {
                let (a, oa) = nodes.of_pore[th.pores[0] as usize];
                let (b, ob) = nodes.of_pore[th.pores[1] as usize];
                let shift = [ob[0] + th.shift[0] - oa[0], ob[1] + th.shift[1] - oa[1]];
                (a, b, shift, t as u32)
            }),
    );
    links
}

/// The root of `p` and `p`'s offset from it, halving the path.
fn root(parent: &mut [u32], offset: &mut [[i8; 2]], p: usize) -> (usize, [i8; 2]) {
    let mut path = Vec::new();
    let mut q = p;
    while parent[q] as usize != q {
        path.push(q);
        q = parent[q] as usize;
    }
    // Offsets along the path, from the root down.
    let mut acc = [0i8; 2];
    for &x in path.iter().rev() {
        acc = [acc[0] + offset[x][0], acc[1] + offset[x][1]];
        offset[x] = acc;
        parent[x] = q as u32;
    }
    (q, if p == q { [0; 2] } else { offset[p] })
}

/// Solves the flow along each axis of `axes` (0 = x, 1 = y, D−1 = z) through
/// the pores whose power centre lies in the slab `[z_lo, z_hi]`. `shapes` are
/// the network's throat shapes (`Network::shapes`, one per throat), taken so
/// that they are freed before the solve.
pub fn solve<const D: usize>(
    net: &Network<D>,
    shapes: Vec<ThroatShape>,
    size: &Vector<D>,
    slab: (Real, Real),
    options: &FlowOptions,
    axes: &[usize],
) -> Result<Flow, FlowError> {
    assert_eq!(shapes.len(), net.throats.len(), "one shape per throat");
    let viscosity = options.viscosity;
    // The solve's sweeps read its vectors at scattered rows (see
    // `memory::Allocator`).
    let _huge = crate::memory::huge_pages();
    let z = D - 1;
    let merge = merged(&shapes);
    let conductance = conductances(net, &shapes, &merge, options);
    drop(shapes);
    let nodes = nodes(net, &merge, slab);
    let relink = || links(net, &nodes, &conductance, &merge);
    let r2 = net.mean_squared_radius;
    let mut flow = Flow {
        merged: merge.iter().filter(|&&m| m).count() as u64,
        ..Flow::default()
    };
    let solved = solve_axes(&nodes, &relink, &conductance, size, slab, axes)?;
    for (&a, (mut f, p, q)) in axes.iter().zip(solved) {
        if let Some(k) = f.k.as_mut() {
            *k *= viscosity;
            // Below rounding of the sizes involved: no flow.
            if !(k.abs() > NOISE * r2) {
                *k = 0.0;
                f.flux = 0.0;
            }
        }
        // A flow whose inflow and outflow differ is not a permeability, not
        // even 0 (a slab half a d32 thick: 0.45 of the circulating flux
        // crossed the periodic side with no net flow, issue 57).
        if !(f.imbalance <= BALANCE) {
            f.k = None;
        }
        flow.axes.push(f);
        // Each pore takes its node's pressure, less the periods it lies away
        // along a side axis (P = −x + p̃).
        let side = a < z;
        flow.pressure.push(
            nodes
                .of_pore
                .iter()
                .map(|&(node, o)| {
                    let shift = if side {
                        Real::from(o[a]) * size[a]
                    } else {
                        0.0
                    };
                    finite(p[node as usize] - shift)
                })
                .collect(),
        );
        flow.throat_flux.push(q);
    }
    flow.conductance = conductance;
    Ok(flow)
}

/// Each throat's conductance under `options` (0 for a shut, merged or
/// negligible throat): what [`solve`] solves with, for the callers that
/// solve one network more than once ([`solve_z`]).
pub fn conductances<const D: usize>(
    net: &Network<D>,
    shapes: &[ThroatShape],
    merge: &[bool],
    options: &FlowOptions,
) -> Vec<Real> {
    let (viscosity, factor) = (options.viscosity, options.conductance_factor);
    let conductance: Vec<Real> = shapes
        .par_iter()
        .zip(&net.throats)
        .zip(merge)
        .map(|((shape, th), &merged)| {
            let mean_r = shape.mean_radius;
            let length = shape.length;
            if merged {
                return 0.0;
            }
            // Touching discs close the gap between them (no 3D facet closes:
            // three touching spheres leave a hole of 0.155 radii).
            if !(th.constriction_radius >= SHUT * mean_r) {
                return 0.0;
            }
            let radius = match options.conductance {
                Conductance::Constriction => th.constriction_radius,
                Conductance::HydraulicRadius => shape.hydraulic_radius,
            };
            let g =
                factor * super::geometry::conductance(shape.fluid_area, radius, length, viscosity);
            if g.is_finite() && g > 0.0 {
                g
            } else {
                0.0
            }
        })
        .collect();
    // A throat far narrower than a typical one carries nothing measurable but
    // can spoil the factorisation (touching discs leave gaps of 1e-12): closed.
    // Typical is the median: the cells over the loose top are huge.
    let mut open: Vec<Real> = conductance.iter().copied().filter(|&g| g > 0.0).collect();
    let typical = if open.is_empty() {
        0.0
    } else {
        let mid = open.len() / 2;
        *open.select_nth_unstable_by(mid, Real::total_cmp).1
    };
    // Not kept through the solves (0.1 GB at 10^6 spheres).
    drop(open);
    conductance
        .into_par_iter()
        .map(|g| if g > CLOSED * typical { g } else { 0.0 })
        .collect()
}

/// The flow along z through the slab of `net` with these throat
/// conductances (0: closed) at unit viscosity, throats `merge` merging their
/// pores as in [`solve`]: the one solver for the other transports of the
/// network (diffusion, each phase of a partly drained bed). Returns the
/// axis' figures and the throat fluxes; `k` is 0 when no open path crosses
/// the slab.
pub fn solve_z<const D: usize>(
    net: &Network<D>,
    merge: &[bool],
    conductance: &[Real],
    size: &Vector<D>,
    slab: (Real, Real),
) -> Result<(AxisFlow, Vec<Real>), FlowError> {
    let nodes = nodes(net, merge, slab);
    let relink = || links(net, &nodes, conductance, merge);
    match solve_axes(&nodes, &relink, conductance, size, slab, &[D - 1]) {
        Ok(mut axes) => {
            let (mut f, _, q) = axes.remove(0);
            if !(f.imbalance <= BALANCE) {
                f.k = None;
            }
            Ok((f, q))
        }
        Err(FlowError::NoPath(axis)) => Ok((
            AxisFlow {
                axis,
                k: Some(0.0),
                ..AxisFlow::default()
            },
            vec![0.0; conductance.len()],
        )),
        Err(e) => Err(e),
    }
}

/// Which throats [`solve`] merges: shorter than [`LENGTH_FLOOR`] of their
/// spheres' mean radius.
pub fn merged(shapes: &[ThroatShape]) -> Vec<bool> {
    shapes
        .par_iter()
        .map(|shape| !(shape.length >= LENGTH_FLOOR * shape.mean_radius))
        .collect()
}

/// One axis' result: the flow, node pressures and throat fluxes.
type AxisSolution = (AxisFlow, Vec<Real>, Vec<Real>);

/// Solves along each of `axes`; returns per axis its permeability at unit
/// viscosity, the node pressures and the throat fluxes.
///
/// Every axis has the same unknowns, the pressures of the slab's nodes, and
/// the same couplings, the links within the slab: the axes differ only in
/// their diagonals. Along z a link to a node beyond the slab ties its slab
/// node to the fixed pressure there; a component of the slab with no such
/// link, and along a side axis every component, is held by one of its nodes
/// tied to `p̃ = 0` (a ground of the node's own conductance: with the
/// right-hand side summing to zero over the component, its pressure is
/// exactly 0, as if it were removed). So one multigrid hierarchy serves all
/// three axes and one sweep carries them together: building the hierarchy
/// and sweeping the network are the solve's costs, and each is paid once.
fn solve_axes<const D: usize>(
    nodes: &Nodes<D>,
    relink: &dyn Fn() -> Vec<Link>,
    conductance: &[Real],
    size: &Vector<D>,
    slab: (Real, Real),
    axes: &[usize],
) -> Result<Vec<AxisSolution>, FlowError> {
    let z = D - 1;
    let n_nodes = nodes.len();
    let in_slab = &nodes.in_slab;
    let links = relink();
    // Along z, links with one end in the slab also take part.
    let open = |l: &Link, along_z: bool| {
        let (a, b) = (in_slab[l.0 as usize], in_slab[l.1 as usize]);
        (a && b) || (along_z && (a || b))
    };
    // Components of the slab's nodes; those that reach a node beyond the
    // slab are held along z by the fixed pressures there.
    let mut parent: Vec<u32> = (0..n_nodes as u32).collect();
    let mut touches_fixed = vec![false; n_nodes];
    for l in &links {
        let (a, b) = (l.0 as usize, l.1 as usize);
        match (in_slab[a], in_slab[b]) {
            (true, true) => union(&mut parent, a, b),
            (true, false) => touches_fixed[a] = true,
            (false, true) => touches_fixed[b] = true,
            (false, false) => {}
        }
    }
    let mut root_fixed = vec![false; n_nodes];
    for p in 0..n_nodes {
        if in_slab[p] && touches_fixed[p] {
            let r = find(&mut parent, p);
            root_fixed[r] = true;
        }
    }
    drop(touches_fixed);
    if axes.contains(&z) && !root_fixed.iter().any(|&f| f) {
        return Err(FlowError::NoPath("z"));
    }
    // Unknowns: every slab node. The first node of each component holds it.
    let mut index = vec![u32::MAX; n_nodes];
    let mut pinned = vec![u32::MAX; n_nodes];
    let mut points: Vec<Vector<D>> = Vec::new();
    let mut roots: Vec<u32> = Vec::new();
    // Each axis' held unknowns (p̃ = 0): along z those of the components that
    // reach no fixed node, along a side axis one in every component.
    let (mut held_z, mut held_side) = (Vec::new(), Vec::new());
    for p in 0..n_nodes {
        if !in_slab[p] {
            continue;
        }
        let r = find(&mut parent, p);
        if pinned[r] == u32::MAX {
            pinned[r] = p as u32;
            let i = points.len() as u32;
            held_side.push(i);
            if !root_fixed[r] {
                held_z.push(i);
            }
        }
        index[p] = points.len() as u32;
        points.push(Vector(*nodes.centre(p)));
        roots.push(r as u32);
    }
    drop(parent);
    let n = points.len();
    let mut diag = vec![0.0; n];
    let has_z = axes.contains(&z);
    // Along z: the conductance to fixed nodes (unused, and 0, otherwise).
    let mut to_fixed = vec![0.0; n];
    // The right-hand sides side by side, one cache line a node rather than
    // one per axis (split after the loop).
    let n_axes = axes.len();
    let mut rhs_side = vec![0.0; n * n_axes];
    // Each link's ends as unknowns (none: beyond the slab, fixed along z).
    let ends: Vec<(u32, u32)> = links
        .par_iter()
        .map(|l| (index[l.0 as usize], index[l.1 as usize]))
        .collect();
    let none = u32::MAX;
    // Each thread sums the terms of a range of unknowns, reading every link
    // in order: every unknown receives its terms in link order, as one
    // thread would add them (the same bits), and the scattered reads and
    // writes are shared out (one thread: 1.8 s at 10^6 spheres).
    let per = n.div_ceil(rayon::current_num_threads()).max(1 << 16);
    diag.par_chunks_mut(per)
        .zip(to_fixed.par_chunks_mut(per))
        .zip(rhs_side.par_chunks_mut(per * n_axes))
        .enumerate()
        .for_each(|(part, ((diag, to_fixed), rhs))| {
            let (lo, len) = (part * per, diag.len());
            // `none` lies past every range.
            let own = |i: u32| (i as usize).wrapping_sub(lo) < len;
            for (l, &(ia, ib)) in links.iter().zip(&ends) {
                // An owned end is in the slab: the link is open if both are,
                // or along z.
                if !(own(ia) || own(ib)) || !((ia != none && ib != none) || has_z) {
                    continue;
                }
                let (a, b, g) = (l.0 as usize, l.1 as usize, conductance[l.3 as usize]);
                if a == b {
                    // A node linked to its own image: no term, only a flux.
                    continue;
                }
                // An unknown's centre from the unknowns' own copy (one read,
                // not two through the node's first pore).
                let centre = |p: usize, i: u32| -> &[Real; D] {
                    if i == none {
                        nodes.centre(p)
                    } else {
                        &points[i as usize].0
                    }
                };
                let (ca, cb) = (centre(a, ia), centre(b, ib));
                let within = ia != none && ib != none;
                for (i, other) in [(ia, ib), (ib, ia)] {
                    if !own(i) {
                        continue;
                    }
                    if other == none {
                        to_fixed[i as usize - lo] += g;
                    } else {
                        diag[i as usize - lo] += g;
                    }
                }
                for (k, &axis) in axes.iter().enumerate() {
                    if !within && axis != z {
                        continue;
                    }
                    // P = −x + p̃ (z: p̃ = 0 on the fixed nodes): the drop of x
                    // across the link drives p̃. Solving for the departure
                    // from the mean gradient rather than for P itself starts
                    // the iteration at the linear profile, and measures its
                    // residual on the scale of the fluxes, not of the heights.
                    let shift = if axis < z {
                        Real::from(l.2[axis]) * size[axis]
                    } else {
                        0.0
                    };
                    // As `delta` below, from the centres read above.
                    let d = cb[axis] + shift - ca[axis];
                    if own(ia) {
                        rhs[(ia as usize - lo) * n_axes + k] -= g * d;
                    }
                    if own(ib) {
                        rhs[(ib as usize - lo) * n_axes + k] += g * d;
                    }
                }
            }
        });
    // The couplings within the slab, in link order.
    let off: Vec<(u32, u32, Real)> = links
        .iter()
        .zip(&ends)
        .filter(|(l, &(ia, ib))| l.0 != l.1 && ia != none && ib != none)
        .map(|(l, &(ia, ib))| (ia, ib, -conductance[l.3 as usize]))
        .collect();
    drop(ends);
    // Where b's image lies from a, along an axis.
    let delta = |l: &Link, axis: usize| -> Real {
        let shift = if axis < z {
            Real::from(l.2[axis]) * size[axis]
        } else {
            0.0
        };
        nodes.centre(l.1 as usize)[axis] + shift - nodes.centre(l.0 as usize)[axis]
    };
    let rhs: Vec<Vec<Real>> = (0..n_axes)
        .map(|k| rhs_side.iter().skip(k).step_by(n_axes).copied().collect())
        .collect();
    drop(rhs_side);
    let ground = |i: u32| {
        if diag[i as usize] > 0.0 {
            diag[i as usize]
        } else {
            1.0
        }
    };
    let shifts: Vec<Vec<Real>> = axes
        .iter()
        .map(|&axis| {
            let (mut s, held) = if axis == z {
                (to_fixed.clone(), &held_z)
            } else {
                (vec![0.0; n], &held_side)
            };
            for &i in held {
                s[i as usize] += ground(i);
            }
            s
        })
        .collect();
    drop(to_fixed);
    // The flux balance the permeability rests on, kept exact whatever the
    // iterative solve's tolerance: the residuals sum, weighted by `w`, to the
    // gap between what enters and what leaves. Along z (w = 1 on the
    // components that reach the fixed nodes) that is inflow against outflow;
    // along a periodic axis (w = the position less that of the component's
    // held node) the flux through the periodic boundary against the mean
    // flux, `cut` against `moment / period` below.
    let deflate: Vec<Vec<Real>> = axes
        .iter()
        .map(|&axis| {
            roots
                .iter()
                .zip(&points)
                .map(|(&r, x)| {
                    if axis == z {
                        if root_fixed[r as usize] {
                            1.0
                        } else {
                            0.0
                        }
                    } else {
                        x.0[axis] - nodes.centre(pinned[r as usize] as usize)[axis]
                    }
                })
                .collect()
        })
        .collect();
    drop((roots, pinned, root_fixed));
    // Not kept through the solve, which is the peak (0.2 GB at 10^6
    // spheres): made again after it.
    drop(links);
    let mut solution = solve_spd_shifted(Systems {
        points,
        diag,
        off,
        shifts,
        rhs,
        deflate: Some(deflate),
    })
    .map_err(FlowError::Solver)?;
    let links = relink();
    let floor_area: Real = (0..D - 1).map(|k| size[k]).product();
    let thickness = slab.1 - slab.0;
    // Each axis on its own thread: each reads only its own solution.
    let out = axes
        .par_iter()
        .zip(solution.par_iter_mut())
        .map(|(&axis, solution)| {
            let along_z = axis == z;
            let held = if along_z { &held_z } else { &held_side };
            // Exactly 0 where held (the solve leaves its rounding there).
            for &i in held {
                solution[i as usize] = 0.0;
            }
            let fixed = |p: usize| along_z && !in_slab[p];
            // P of every node: solved (held: p̃ = 0), fixed along z, or none.
            let pressure: Vec<Real> = (0..n_nodes)
                .map(|p| {
                    let base = -nodes.centre(p)[axis];
                    match (index[p], along_z) {
                        (u32::MAX, true) => base,
                        (u32::MAX, false) => 0.0,
                        (i, _) => base + solution[i as usize],
                    }
                })
                .collect();
            let mut flux = vec![0.0; conductance.len()];
            let (mut q_in, mut q_out, mut cut, mut moment) = (0.0, 0.0, 0.0, 0.0);
            let mut circulating = 0.0;
            for l in links.iter().filter(|l| open(l, along_z)) {
                let (a, b, g) = (l.0 as usize, l.1 as usize, conductance[l.3 as usize]);
                // P of b's image: one period's drop of x per period of shift.
                let image = if along_z {
                    0.0
                } else {
                    Real::from(l.2[axis]) * size[axis]
                };
                let q = g * (pressure[a] - (pressure[b] - image));
                flux[l.3 as usize] = q;
                circulating += q.abs();
                if along_z {
                    let below = |p: usize| nodes.centre(p)[z] < slab.0;
                    if fixed(b) {
                        if below(b) {
                            q_in -= q;
                        } else {
                            q_out += q;
                        }
                    } else if fixed(a) {
                        if below(a) {
                            q_in += q;
                        } else {
                            q_out -= q;
                        }
                    }
                } else {
                    cut += q * Real::from(l.2[axis]);
                    moment += q * delta(l, axis);
                }
            }
            let (mut q, mut imbalance, area) = if along_z {
                (0.5 * (q_in + q_out), relative(q_in, q_out), floor_area)
            } else {
                let q = moment / size[axis];
                let area = if D == 3 {
                    size[1 - axis] * thickness
                } else {
                    thickness
                };
                (q, relative(cut, q), area)
            };
            // A net flux at the rounding level of the fluxes that circulate is no
            // flow at all (a pore space closed by contacts).
            // Its imbalance is then one rounding error against another (1.2
            // in a slab thinner than a pore, issue 57): measured on the scale
            // of the fluxes that circulate instead.
            if !(q.abs() > NOISE * circulating) {
                q = 0.0;
                let (a, b) = if along_z {
                    (q_in, q_out)
                } else {
                    (cut, moment / size[axis])
                };
                imbalance = if circulating > 0.0 {
                    (a - b).abs() / circulating
                } else {
                    0.0
                };
            }
            (
                AxisFlow {
                    axis: ["x", "y", "z"][if axis == z { 2 } else { axis }],
                    k: Some(finite(q / area)),
                    flux: finite(q),
                    imbalance: finite(imbalance),
                    // The unknowns less the held nodes.
                    pores: (n - held.len()) as u64,
                },
                pressure.into_iter().map(finite).collect(),
                flux.into_iter().map(finite).collect(),
            )
        });
    Ok(out.collect())
}

fn relative(a: Real, b: Real) -> Real {
    let scale = a.abs().max(b.abs());
    if scale > 0.0 {
        (a - b).abs() / scale
    } else {
        0.0
    }
}

fn finite(x: Real) -> Real {
    if x.is_finite() {
        x
    } else {
        0.0
    }
}

fn find(parent: &mut [u32], mut p: usize) -> usize {
    while parent[p] as usize != p {
        let up = parent[parent[p] as usize];
        parent[p] = up;
        p = up as usize;
    }
    p
}

fn union(parent: &mut [u32], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        parent[hi] = lo as u32;
    }
}
