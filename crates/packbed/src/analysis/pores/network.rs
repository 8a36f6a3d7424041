//! The pore network of a bed: the cells (pores) and shared facets (throats) of
//! the regular triangulation of its particles, each once.
//!
//! Periodic sides: the particles within a margin of each side are copied one
//! period over, the whole set is triangulated, and a cell is kept when the
//! vertex that comes first by (particle, image shift) is an original particle.
//! The translates of a cell all pick the same vertex, so exactly one of them
//! is kept; a throat to a translate records the shift.
//!
//! Side walls: the particles within the margin are mirrored in each wall, so
//! that the wall is a plane of symmetry of the pore space, and a cell is kept
//! when its power centre lies in the box. Throats to cells outside are walls
//! (no flow): a slip wall for the network, the cheapest treatment that keeps
//! a walled bed's pore space whole at the wall (docs/design/pore-network.md,
//! "Walls: mirror images").
//!
//! The margin is checked, not trusted: a pore in the part of the bed that is
//! asked for must have an orthogonal sphere that no point beyond the margin
//! can reach (`gap² > R² + r_max²`), else the margin doubles and the network
//! is built again.

use super::geometry;
use super::triangulation::{Triangulation, NONE};
use crate::analysis::StageTimes;
use crate::bed::Bed;
use crate::error::{Error, Result};
use crate::math::Real;
use rayon::prelude::*;
use std::collections::HashMap;

/// Which particle a point of the triangulation is, and which image of it:
/// per side axis the number of periods it is shifted by (periodic sides), or
/// −1 / +1 for its mirror image in the low / high wall (walls).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Site {
    /// Index of the particle in the bed.
    pub particle: u32,
    /// Image per side axis (x, then y in 3D; the unused entry is 0).
    pub image: [i8; 2],
}

impl Site {
    /// Where the site is: the particle's centre shifted by whole periods,
    /// or mirrored in a side wall.
    pub fn position<const D: usize>(&self, bed: &Bed<D>) -> [Real; D] {
        image_of(bed, bed.centres[self.particle as usize].0, self.image)
    }

    /// The priority of the site in the perturbation: (particle, image)
    /// lexicographically, which a translation by whole periods keeps.
    pub fn rank(&self) -> u64 {
        let code = |s: i8| u64::from((i16::from(s) + 128) as u8);
        (u64::from(self.particle) << 16) | (code(self.image[0]) << 8) | code(self.image[1])
    }
}

/// A pore: one cell of the triangulation.
#[derive(Clone, Debug, PartialEq)]
pub struct Pore<const D: usize> {
    /// The cell's vertices (the first `D + 1` entries): particles and images.
    pub sites: [Site; 4],
    /// Power centre: the node of the pore.
    pub centre: [Real; D],
    /// Volume of the cell (area in 2D).
    pub volume: Real,
    /// Its void volume: the cell less the vertex spheres (sectors, with the
    /// overlaps' lenses counted once).
    pub void_volume: Real,
    /// Radius of the largest sphere touching the four vertex spheres.
    pub body_radius: Real,
}

/// A throat: the facet between two pores, as the tables keep it.
#[derive(Clone, Debug, PartialEq)]
pub struct Throat {
    /// The two pores (indices into [`Network::pores`]).
    pub pores: [u32; 2],
    /// Where the second pore is: its kept cell shifted by these periods.
    pub shift: [i8; 2],
    /// Radius of the largest circle in the facet that touches its spheres
    /// (half the gap of the two discs in 2D).
    pub constriction_radius: Real,
}

/// What the distributions and the flow read of a throat once: kept apart
/// from [`Throat`] so that it is gone before the flow's solve (at 10^6
/// spheres it is 0.5 GB, and the solve is the peak).
#[derive(Clone, Debug, PartialEq)]
pub struct ThroatShape {
    /// Mean radius of the facet's spheres: the scale of the flow's floors.
    pub mean_radius: Real,
    /// Distance between the two power centres.
    pub length: Real,
    /// Facet area not covered by the vertex spheres' sectors.
    pub fluid_area: Real,
    /// Void volume of the region spanned by the facet and the two power
    /// centres.
    pub void_volume: Real,
    /// That void volume over the sphere surface in the region (0 with no
    /// surface). The surface itself is not kept: nothing after the
    /// network reads it, and at 10^6 spheres it was 0.1 GB.
    pub hydraulic_radius: Real,
}

/// The pores and throats of a bed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Network<const D: usize> {
    /// Every pore once.
    pub pores: Vec<Pore<D>>,
    /// Every throat once.
    pub throats: Vec<Throat>,
    /// The shape of each throat (same order), until the flow takes it.
    pub shapes: Vec<ThroatShape>,
    /// Particles with no cell (their sphere sits inside others').
    pub hidden: Vec<u32>,
    /// Pores whose void volume is not exact for overlapping spheres (a
    /// triple overlap, or an overlapping sphere past its opposite face:
    /// `geometry::CellVolume::overlap_inexact`), in order.
    pub overlap_inexact_pores: Vec<u32>,
    /// Throats (indices into `throats`) whose fluid area or region is not
    /// exact for overlapping spheres, in order.
    pub overlap_inexact_throats: Vec<u32>,
    /// The margin of images the network was built with.
    pub margin: Real,
    /// Points triangulated (particles and their images).
    pub points: usize,
    /// Mean of the bed's squared radii: the scale below which a flux is
    /// rounding.
    pub mean_squared_radius: Real,
}

/// Builds the network of `bed`; pores whose power centre height lies in
/// `check_z` must be exact (the margin grows until they are).
pub fn network<const D: usize>(bed: &Bed<D>, check_z: (Real, Real)) -> Result<Network<D>> {
    network_timed(bed, check_z, &mut StageTimes::default())
}

/// [`network`], timing the triangulation and the assembly into `times`.
pub fn network_timed<const D: usize>(
    bed: &Bed<D>,
    check_z: (Real, Real),
    times: &mut StageTimes,
) -> Result<Network<D>> {
    let r_max = bed.r_max();
    // Three largest diameters: a pore of the slab near a side and the cells
    // beyond its facets must all be exact; two diameters fell short of that
    // on a bed of 10^5 equal spheres (a neighbour's orthosphere reached past
    // the images) and cost a second triangulation.
    let mut margin = crate::config::PORE_MARGIN_RADII * r_max;
    for _ in 0..4 {
        let (sites, points, weights) = sites_with_images(bed, margin);
        let ranks: Vec<u64> = sites.iter().map(Site::rank).collect();
        let t = times.time("pores/triangulation", || {
            Triangulation::with_ranks(&points, &weights, &ranks)
        });
        let net = times.time("pores/network", || {
            assemble(bed, &t, &sites, margin, check_z)
        })?;
        if let Some(net) = net {
            return Ok(net);
        }
        margin *= 2.0;
    }
    Err(Error::Impossible(format!(
        "pores: the pore network needs images beyond {} of the sides; the bed is too sparse \
         for a pore network",
        crate::math::display_length(margin / 2.0)
    )))
}

/// The point `c` shifted by `image`: whole periods on periodic sides, a
/// mirror image in the low (−1) or high (+1) side wall otherwise.
fn image_of<const D: usize>(bed: &Bed<D>, c: [Real; D], image: [i8; 2]) -> [Real; D] {
    let size = bed.container.size;
    let mut p = c;
    for a in 0..D - 1 {
        let s = image[a];
        p[a] = if bed.container.periodic {
            c[a] + Real::from(s) * size[a]
        } else {
            match s {
                -1 => -c[a],
                1 => 2.0 * size[a] - c[a],
                _ => c[a],
            }
        };
    }
    p
}

/// The particles and their images within `margin` of the sides.
fn sites_with_images<const D: usize>(
    bed: &Bed<D>,
    margin: Real,
) -> (Vec<Site>, Vec<[f64; D]>, Vec<f64>) {
    let n = bed.len();
    let mut sites = Vec::with_capacity(n + n / 4);
    let mut points = Vec::with_capacity(n + n / 4);
    let mut weights = Vec::with_capacity(n + n / 4);
    for i in 0..n {
        sites.push(Site {
            particle: i as u32,
            image: [0; 2],
        });
        points.push(bed.centres[i].0);
        weights.push(bed.radii[i] * bed.radii[i]);
    }
    let sides = D - 1;
    let size = bed.container.size;
    // Periods needed on each side axis (a narrow box needs several).
    let reach: Vec<i32> = (0..sides)
        .map(|a| {
            if bed.container.periodic {
                (margin / size[a]).ceil().max(1.0) as i32
            } else {
                1
            }
        })
        .collect();
    let counts: Vec<i32> = reach.iter().map(|&k| 2 * k + 1).collect();
    let combos: i32 = counts.iter().product();
    for i in 0..n {
        let c = bed.centres[i].0;
        for code in 0..combos {
            let mut image = [0i8; 2];
            let mut rest = code;
            for a in 0..sides {
                image[a] = (rest % counts[a] - reach[a]) as i8;
                rest /= counts[a];
            }
            if image == [0; 2] {
                continue;
            }
            let p = image_of(bed, c, image);
            let inside = (0..sides).all(|a| p[a] >= -margin && p[a] <= size[a] + margin);
            if inside {
                sites.push(Site {
                    particle: i as u32,
                    image,
                });
                points.push(p);
                weights.push(bed.radii[i] * bed.radii[i]);
            }
        }
    }
    (sites, points, weights)
}

/// The network from a triangulation of the sites, or `None` when a pore that
/// must be exact could be reached from beyond the margin.
fn assemble<const D: usize>(
    bed: &Bed<D>,
    t: &Triangulation<D>,
    sites: &[Site],
    margin: Real,
    check_z: (Real, Real),
) -> Result<Option<Network<D>>> {
    let periodic = bed.container.periodic;
    let size = bed.container.size;
    let w_max = bed.r_max() * bed.r_max();
    let v_n = D + 1;
    let mut pore_of = vec![NONE; t.slots()];
    let mut cell_of_pore: Vec<u32> = Vec::new();
    // Pores that must be exact: their links to translates must all be found.
    let mut checked: Vec<bool> = Vec::new();
    let mut by_key: HashMap<[Site; 4], u32> = HashMap::new();
    // The geometry runs on every core, in cell order (the same bits whatever
    // the thread count); the bookkeeping around it is serial.
    let cells: Vec<u32> = t.input_cells().collect();
    let centres: Vec<([f64; D], f64)> = cells
        .par_iter()
        .map(|&c| power_centre(t, t.vertices(c)))
        .collect();
    // Which cells are pores, decided on every core (one cell's verdict reads
    // only that cell); the numbering after it is serial, in cell order.
    let verdicts: Vec<u8> = cells
        .par_iter()
        .zip(&centres)
        .map(|(&c, &(centre, power))| {
            let v = t.vertices(c);
            let keep = if periodic {
                anchor(sites, v).image == [0; 2]
            } else {
                (0..D - 1).all(|a| centre[a] >= 0.0 && centre[a] < size[a])
            };
            if !keep {
                return 0;
            }
            let z = centre[D - 1];
            let must = z >= check_z.0 && z <= check_z.1;
            if must {
                for a in 0..D - 1 {
                    let gap = (centre[a] + margin).min(size[a] + margin - centre[a]);
                    if !(gap > 0.0 && gap * gap > power + w_max) {
                        return SHORT;
                    }
                }
            }
            let may = periodic && may_have_translates(t, v, size, margin);
            KEPT | if must { MUST } else { 0 } | if may { MAY } else { 0 }
        })
        .collect();
    if verdicts.contains(&SHORT) {
        return Ok(None);
    }
    // Each pore's place in `cells`: its key and centre are read from there
    // on every core below (a serial loop that copied them, 64 bytes a pore,
    // took 0.9 s at 10^6 spheres).
    let mut kept: Vec<u32> = Vec::new();
    for (k, (&c, &verdict)) in cells.iter().zip(&verdicts).enumerate() {
        if verdict & KEPT == 0 {
            continue;
        }
        let id = kept.len() as u32;
        if verdict & MAY != 0 {
            by_key.insert(canonical(&sites_of(sites, t.vertices(c)), v_n).0, id);
        }
        pore_of[c as usize] = id;
        cell_of_pore.push(c);
        checked.push(verdict & MUST != 0);
        kept.push(k as u32);
    }
    drop(verdicts);
    let (pores, inexact): (Vec<Pore<D>>, Vec<bool>) = kept
        .par_iter()
        .map(|&k| {
            let v = t.vertices(cells[k as usize]);
            measure_pore(t, v, sites_of(sites, v), centres[k as usize].0)
        })
        .unzip();
    let overlap_inexact_pores = flagged(&inexact);
    drop(inexact);
    // Each stage's inputs go as soon as it is done: at 10^6 spheres the
    // centres, the kept cells and the key table held 1.1 GB past their use.
    drop((kept, centres));
    // Each pore's links on every core, chunk by chunk, each chunk written
    // into room for all its pores' facets, then moved up to close the gaps.
    // Vectors the threads allocated themselves stayed in their allocator's
    // pools past the network and raised a 10^6-sphere run's peak (in the
    // flow) by 0.08 GB; pages of the room never written are never touched.
    let mut links: Vec<Link> = vec![(0, 0, 0, [0, 0]); cell_of_pore.len() * v_n];
    let counts: Option<Vec<usize>> = links
        .par_chunks_mut(LINK_CHUNK * v_n)
        .zip(cell_of_pore.par_chunks(LINK_CHUNK))
        .enumerate()
        .map(|(k, (room, chunk))| {
            let mut m = 0;
            for (l, &c) in chunk.iter().enumerate() {
                let a = (k * LINK_CHUNK + l) as u32;
                for i in 0..v_n {
                    let n = t.neighbours(c)[i];
                    if n == NONE || !t.is_input_cell(n) {
                        continue;
                    }
                    let (b, shift) = if pore_of[n as usize] != NONE {
                        (pore_of[n as usize], [0i8; 2])
                    } else if periodic {
                        let (key, shift) = canonical(&sites_of(sites, t.vertices(n)), v_n);
                        match by_key.get(&key) {
                            Some(&b) => (b, shift),
                            // Its kept translate was cut by the margin.
                            None if checked[a as usize] => return None,
                            None => continue,
                        }
                    } else {
                        continue;
                    };
                    if (a, [0i8; 2]) >= (b, shift) {
                        continue;
                    }
                    room[m] = (a, b, i as u8, shift);
                    m += 1;
                }
            }
            Some(m)
        })
        .collect();
    let Some(counts) = counts else {
        return Ok(None);
    };
    let mut end = 0;
    for (k, &m) in counts.iter().enumerate() {
        let start = k * LINK_CHUNK * v_n;
        links.copy_within(start..start + m, end);
        end += m;
    }
    links.truncate(end);
    links.shrink_to_fit();
    drop((by_key, pore_of, checked));
    // A throat's power centres are its pores' (the same computation on the
    // same cell), save a translate's, which is worked out again.
    let centre_of = |cell: u32, pore: u32| {
        if cell_of_pore[pore as usize] == cell {
            pores[pore as usize].centre
        } else {
            power_centre(t, t.vertices(cell)).0
        }
    };
    let ((throats, shapes), inexact): ((Vec<Throat>, Vec<ThroatShape>), Vec<bool>) = links
        .par_iter()
        .map(|&(a, b, i, shift)| {
            let (c, i) = (cell_of_pore[a as usize], usize::from(i));
            let n = t.neighbours(c)[i];
            let ends = [centre_of(c, a), centre_of(n, b)];
            measure_throat(t, c, i, ends, [a, b], shift)
        })
        .unzip();
    drop(cell_of_pore);
    let overlap_inexact_throats = flagged(&inexact);
    drop(inexact);
    Ok(Some(Network {
        pores,
        throats,
        shapes,
        hidden: t
            .hidden()
            .iter()
            .filter(|&&h| sites[h as usize].image == [0; 2])
            .copied()
            .collect(),
        overlap_inexact_pores,
        overlap_inexact_throats,
        margin,
        points: t.input_len(),
        mean_squared_radius: bed.radii.iter().map(|r| r * r).sum::<Real>()
            / bed.radii.len().max(1) as Real,
    }))
}

/// The indices of the `true` entries.
fn flagged(flags: &[bool]) -> Vec<u32> {
    (0..flags.len() as u32)
        .filter(|&k| flags[k as usize])
        .collect()
}

/// A throat found in [`assemble`]: the two pores, the facet's index in the
/// first pore's cell, the second's period shift (12 bytes; the cell and its
/// neighbour follow from these).
type Link = (u32, u32, u8, [i8; 2]);

/// Pores whose links one task finds.
const LINK_CHUNK: usize = 1 << 14;

/// A cell's verdict in [`assemble`]: a pore, one that must be exact, one
/// that may have translates; or a pore that must be exact but could be
/// reached from beyond the margin.
const KEPT: u8 = 1;
const MUST: u8 = 2;
const MAY: u8 = 4;
const SHORT: u8 = 8;

/// False when no translate of the cell by whole periods can be a cell of the
/// triangulation, so that no link will look it up by its key: a translate
/// needs every vertex's image, and images exist only within `margin` of the
/// sides, so along the axis of the shift every vertex lies within `margin`
/// of the same side. Twice the margin keeps the test clear of rounding. At
/// 10^6 spheres the key table of every pore took 4.8 s and 0.3 GB.
fn may_have_translates<const D: usize>(
    t: &Triangulation<D>,
    v: &[u32],
    size: crate::math::Vector<D>,
    margin: Real,
) -> bool {
    (0..D - 1).any(|a| {
        let reach = 2.0 * margin;
        let along = v.iter().map(|&x| t.point(x)[a]);
        along.clone().all(|p| p <= reach) || along.clone().all(|p| p >= size[a] - reach)
    })
}

/// The sites of a cell's vertices (unused entries past `D + 1` last).
fn sites_of(sites: &[Site], v: &[u32]) -> [Site; 4] {
    let mut key = [Site {
        particle: u32::MAX,
        image: [0; 2],
    }; 4];
    for (k, &x) in v.iter().enumerate() {
        key[k] = sites[x as usize];
    }
    key
}

/// The vertex of a cell that comes first by (particle, image).
fn anchor(sites: &[Site], v: &[u32]) -> Site {
    v.iter()
        .map(|&x| sites[x as usize])
        .min()
        .expect("a cell has vertices")
}

/// The cell's sites moved so that its anchor is an original particle, sorted,
/// and the shift that was taken off.
fn canonical(key: &[Site; 4], v_n: usize) -> ([Site; 4], [i8; 2]) {
    let shift = key[..v_n].iter().min().expect("a cell has vertices").image;
    let mut out = *key;
    for s in out[..v_n].iter_mut() {
        for a in 0..2 {
            s.image[a] -= shift[a];
        }
    }
    out[..v_n].sort_unstable();
    (out, shift)
}

fn coords<const D: usize>(t: &Triangulation<D>, v: &[u32]) -> ([[f64; D]; 4], [f64; 4]) {
    let mut c = [[0.0; D]; 4];
    let mut r = [0.0; 4];
    for (k, &x) in v.iter().enumerate() {
        c[k] = *t.point(x);
        r[k] = t.weight(x).sqrt();
    }
    (c, r)
}

/// Power centre and power radius squared of the cell with vertices `v`. A
/// cell flat to rounding (a sliver the exact predicates still orient) has its
/// power centre far off or nowhere: its centroid stands in, with the smallest
/// power of a vertex there, so that nothing downstream meets an infinity.
fn power_centre<const D: usize>(t: &Triangulation<D>, v: &[u32]) -> ([f64; D], f64) {
    let (c, r) = coords(t, v);
    let mut out = [0.0; D];
    let found = match D {
        2 => geometry::power_centre_2d(&[to2(&c[0]), to2(&c[1]), to2(&c[2])], &[r[0], r[1], r[2]])
            .map(|(p, w)| {
                out[..2].copy_from_slice(&p);
                w
            }),
        _ => geometry::power_centre_3d(&[to3(&c[0]), to3(&c[1]), to3(&c[2]), to3(&c[3])], &r).map(
            |(p, w)| {
                out[..3].copy_from_slice(&p);
                w
            },
        ),
    };
    match found {
        Some(w) if w.is_finite() && out.iter().all(|x| x.is_finite()) => (out, w),
        _ => {
            let n = v.len() as f64;
            let mut centroid = [0.0; D];
            for k in 0..v.len() {
                for a in 0..D {
                    centroid[a] += c[k][a] / n;
                }
            }
            let power = (0..v.len())
                .map(|k| {
                    let d2: f64 = (0..D).map(|a| (centroid[a] - c[k][a]).powi(2)).sum();
                    d2 - r[k] * r[k]
                })
                .fold(f64::INFINITY, f64::min);
            (centroid, power)
        }
    }
}

fn to2<const D: usize>(p: &[f64; D]) -> [f64; 2] {
    [p[0], p[1]]
}

fn to3<const D: usize>(p: &[f64; D]) -> [f64; 3] {
    [p[0], p[1], p[2]]
}

fn measure_pore<const D: usize>(
    t: &Triangulation<D>,
    v: &[u32],
    sites: [Site; 4],
    centre: [f64; D],
) -> (Pore<D>, bool) {
    let (c, r) = coords(t, v);
    let (cell, body_radius) = match D {
        2 => {
            let c2 = [to2(&c[0]), to2(&c[1]), to2(&c[2])];
            let r2 = [r[0], r[1], r[2]];
            (
                geometry::cell_volumes_2d(&c2, &r2),
                geometry::pore_body_radius_2d(&c2, &r2),
            )
        }
        _ => {
            let c3 = [to3(&c[0]), to3(&c[1]), to3(&c[2]), to3(&c[3])];
            (
                geometry::cell_volumes_3d(&c3, &r),
                geometry::pore_body_radius_3d(&c3, &r),
            )
        }
    };
    (
        Pore {
            sites,
            centre,
            volume: cell.volume,
            void_volume: cell.void_volume,
            body_radius,
        },
        cell.overlap_inexact,
    )
}

fn measure_throat<const D: usize>(
    t: &Triangulation<D>,
    c: u32,
    i: usize,
    [p1, p2]: [[f64; D]; 2],
    pores: [u32; 2],
    shift: [i8; 2],
) -> ((Throat, ThroatShape), bool) {
    let v = t.vertices(c);
    let mut facet = [0u32; 3];
    for (slot, k) in (0..D + 1).filter(|&k| k != i).enumerate() {
        facet[slot] = v[k];
    }
    let facet = &facet[..D];
    let (fc, fr) = coords(t, facet);
    let (constriction_radius, geometry) = match D {
        2 => {
            let c2 = [to2(&fc[0]), to2(&fc[1])];
            let r2 = [fr[0], fr[1]];
            (
                geometry::constriction_radius_2d(&c2, &r2),
                geometry::throat_2d(to2(&p1), to2(&p2), &c2, &r2),
            )
        }
        _ => {
            let c3 = [to3(&fc[0]), to3(&fc[1]), to3(&fc[2])];
            let r3 = [fr[0], fr[1], fr[2]];
            (
                geometry::constriction_radius_3d(&c3, &r3),
                geometry::throat_3d(to3(&p1), to3(&p2), &c3, &r3),
            )
        }
    };
    (
        (
            Throat {
                pores,
                shift,
                constriction_radius,
            },
            ThroatShape {
                // The radii are the weights' square roots: √(r·r) is r to the
                // bit in binary floating point.
                mean_radius: fr[..D].iter().sum::<Real>() / D as Real,
                length: geometry.length,
                fluid_area: geometry.fluid_area,
                void_volume: geometry.void_volume,
                hydraulic_radius: geometry.hydraulic_radius,
            },
        ),
        geometry.overlap_inexact,
    )
}
