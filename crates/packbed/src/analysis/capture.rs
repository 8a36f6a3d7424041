//! What a filter medium captures: of the bodies fed after the medium
//! (`[[feeds]]` with `medium = true` first), how many passed it through the
//! open floor, how many lodged inside it and how many formed the cake above
//! it, per size class; the grade-efficiency curve and its cut size `x50`;
//! where inside the medium the lodged ones sit.
//!
//! The medium's surface is the mean height of its top over the columns of the
//! floor it covers (a profilometer's mean surface): a body whose centre (a
//! chain's centre of mass) lies below it has lodged inside the medium, one
//! above it belongs to the cake. A body's size is its bead diameter.

use crate::bed::{Bed, Filtrate};
use crate::math::Real;
use serde::Serialize;

/// Size classes of the grade-efficiency curve (log-spaced between the
/// smallest and largest body fed after the medium).
pub const CLASSES: usize = 12;

/// Bins of the depth profile of the lodged bodies, across the medium.
pub const DEPTH_BINS: usize = 10;

/// Columns of the height map along each horizontal axis, at most (3D: this
/// squared).
const MAX_COLUMNS: usize = 512;

/// One size class of the capture.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct CaptureClass {
    /// Smallest diameter of the class (its lower edge).
    pub d_lo: Real,
    /// Its upper edge (the last class includes it).
    pub d_hi: Real,
    /// Bodies fed in the class.
    pub fed: u64,
    /// Of those, passed through the medium.
    pub passed: u64,
    /// Lodged inside the medium.
    pub lodged: u64,
    /// In the cake above it.
    pub cake: u64,
    /// `(lodged + cake) / fed`; null for an empty class.
    pub grade_efficiency: Option<Real>,
}

/// The classic retention criteria of granular filters, from the sizes of the
/// medium and of the slurry fed after it and the medium's own pore network.
/// Diameters in the bed's unit; percentiles of bead diameters by mass
/// unless named otherwise.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct FilterCriteria {
    /// The medium's D15 (15 % of its mass is finer).
    pub medium_d15: Real,
    /// The slurry's d85 (85 % of its mass is finer).
    pub slurry_d85: Real,
    /// The slurry's d85 by surface area (weights d², as Indraratna et al.).
    pub slurry_d85_by_surface: Real,
    /// Constriction diameters of the medium's throats (its pore network,
    /// between its bottom and its surface), by number: 10, 35, 50, 90 %.
    pub constriction_diameter: [Real; 4],
    /// Terzaghi's retention ratio D15 / d85: the medium retains the slurry
    /// when it is at most 4 (filters against soils).
    pub terzaghi_ratio: Real,
    /// Kenney et al. (1985)'s controlling constriction of a granular filter,
    /// D15 / 5: particles finer than it can pass a thick filter.
    pub kenney_constriction: Real,
    /// Indraratna et al. (2007)'s ratio d_c35 / d85,SA (the medium's
    /// constriction 35 % of its throats are finer than, here by number, over
    /// the slurry's d85 by surface area): the medium retains when at most 1.
    pub indraratna_ratio: Real,
}

/// Classes of the constriction distribution (`constrictions.csv`).
pub const CONSTRICTION_CLASSES: usize = 20;

/// One class of the medium's constriction diameters beside the slurry's
/// diameters, on one log-spaced axis over both (`constrictions.csv`): what
/// a particle of a size meets against how many of that size were fed.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct ConstrictionClass {
    /// Lower edge of the class, diameter.
    pub d_lo: Real,
    /// Upper edge (the last class includes it).
    pub d_hi: Real,
    /// The medium's throats whose constriction diameter is in the class.
    pub constrictions: u64,
    /// The fraction of the medium's throats finer than `d_hi` (by number;
    /// 1 in the last class).
    pub constrictions_finer: Real,
    /// Bodies fed after the medium whose diameter is in the class.
    pub slurry: u64,
    /// The fraction of those bodies finer than `d_hi` (by number).
    pub slurry_finer: Real,
}

/// One bin of the lodged bodies' depth below the medium's surface.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct DepthBin {
    /// Depth of the bin's top below the surface.
    pub depth_lo: Real,
    /// Depth of its bottom.
    pub depth_hi: Real,
    /// Lodged bodies whose centre lies in it.
    pub lodged: u64,
}

/// `capture.*` of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct CaptureSummary {
    /// Bodies fed after the medium (`passed + lodged + cake`).
    pub fed: u64,
    /// Of those, passed through the medium (rows of `filtrate.csv`).
    pub passed: u64,
    /// Lodged inside the medium.
    pub lodged: u64,
    /// In the cake above it.
    pub cake: u64,
    /// `passed / fed` (null when nothing was fed).
    pub passed_fraction: Option<Real>,
    /// `lodged / fed`.
    pub lodged_fraction: Option<Real>,
    /// `cake / fed`.
    pub cake_fraction: Option<Real>,
    /// Bodies of the medium.
    pub medium_bodies: u64,
    /// How far the medium stands above the open floor.
    pub medium_lift: Real,
    /// The lowest point of the medium.
    pub medium_bottom: Real,
    /// The mean height of the medium's top (see the module's doc).
    pub medium_surface: Real,
    /// The diameter captured (lodged or in the cake) with probability 1/2:
    /// where the grade efficiency first reaches 0.5, by size, interpolated
    /// in log d between class centres; null when no class is on either side.
    pub x50: Option<Real>,
    /// Why `x50` is null, when it is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// The grade-efficiency classes (`capture.csv`).
    pub classes: Vec<CaptureClass>,
    /// The lodged bodies by depth below the surface.
    pub depth_profile: Vec<DepthBin>,
    /// The classic granular-filter retention criteria for this medium and
    /// slurry, beside the simulated capture; null when the medium's pore
    /// network could not be built (`note` says why).
    pub criteria: Option<FilterCriteria>,
    /// The bodies that passed (`filtrate.csv`), in the order fed.
    #[serde(skip)]
    pub filtrate: Vec<Filtrate>,
    /// The medium's full constriction distribution beside the slurry's
    /// sizes (`constrictions.csv`; its percentiles are in `criteria`);
    /// empty where `criteria` is null.
    pub constrictions: Vec<ConstrictionClass>,
}

/// Which species of `bed` are the medium's: those of the `[[feeds]]` marked
/// `medium = true`, and a mesh's.
pub fn medium_species<const D: usize>(
    feeds: &[crate::config::FeedStageConfig],
    bed: &Bed<D>,
) -> Vec<bool> {
    species_fed_by(feeds, bed, |f| f.is_medium())
}

/// Which species of `bed` are a woven mesh's wires (laid by a `mesh` feed
/// of `feeds`).
pub fn mesh_species<const D: usize>(
    feeds: &[crate::config::FeedStageConfig],
    bed: &Bed<D>,
) -> Vec<bool> {
    species_fed_by(feeds, bed, |f| f.mesh.is_some())
}

/// Which species of `bed` belong to a feed of `feeds` that `pick` picks.
fn species_fed_by<const D: usize>(
    feeds: &[crate::config::FeedStageConfig],
    bed: &Bed<D>,
    pick: impl Fn(&crate::config::FeedStageConfig) -> bool,
) -> Vec<bool> {
    bed.species_info
        .iter()
        .map(|s| {
            s.feed
                .is_some_and(|k| feeds.get(k as usize).is_some_and(&pick))
        })
        .collect()
}

/// The height of a woven mesh's mid-plane above its bottom, when the
/// medium of `feeds` is a mesh alone: there its surface lies (see
/// [`capture`]). Under a precoat the medium's surface is the precoat's
/// top, as for any granular medium, so this is `None`.
pub fn mesh_mid_plane<const D: usize>(feeds: &[crate::config::FeedStageConfig]) -> Option<Real> {
    if feeds.iter().any(|f| f.medium && f.mesh.is_none()) {
        return None;
    }
    let mesh = feeds.iter().find_map(|f| f.mesh)?;
    Some(mesh.resolve("mesh").ok()?.mid_plane::<D>())
}

/// The capture of `bed`, whose species `medium[s]` are the medium's, with
/// the bodies that passed; `None` without a medium. The medium's surface is
/// its mean top, or for a woven mesh its mid-plane, `mid_plane` above its
/// bottom ([`mesh_mid_plane`]): a body held in an opening (a sieve's
/// blinding) is retained at the mesh's surface, and only one whose centre
/// passed between the layers has lodged in it.
pub fn capture<const D: usize>(
    bed: &Bed<D>,
    medium: &[bool],
    filtrate: &[Filtrate],
    lift: Real,
    mid_plane: Option<Real>,
) -> Option<CaptureSummary> {
    if !medium.iter().any(|&m| m) {
        return None;
    }
    let is_medium = |i: usize| {
        medium
            .get(bed.species[i] as usize)
            .copied()
            .unwrap_or(false)
    };
    let medium_bottom = (0..bed.len())
        .filter(|&i| is_medium(i))
        .map(|i| bed.centres[i][D - 1] - bed.radii[i])
        .fold(Real::INFINITY, Real::min);
    let medium_surface = match mid_plane {
        Some(h) if medium_bottom.is_finite() => medium_bottom + h,
        _ => mean_top(bed, &is_medium)?,
    };
    // Bodies after the medium: (diameter, centre height) of each.
    let mut bodies: Vec<(Real, Real)> = Vec::new();
    let mut medium_bodies = 0;
    let mut start = 0;
    while start < bed.len() {
        let mut end = start + 1;
        while end < bed.len() && bed.bodies[end] == bed.bodies[start] {
            end += 1;
        }
        if is_medium(start) {
            medium_bodies += 1;
        } else {
            let z =
                (start..end).map(|i| bed.centres[i][D - 1]).sum::<Real>() / (end - start) as Real;
            bodies.push((2.0 * bed.radii[start], z));
        }
        start = end;
    }
    let sizes = bodies
        .iter()
        .map(|b| b.0)
        .chain(filtrate.iter().map(|f| 2.0 * f.radius));
    let (d_min, d_max) = sizes.fold((Real::INFINITY, 0.0), |(lo, hi): (Real, Real), d| {
        (lo.min(d), hi.max(d))
    });
    let mut classes = edges(d_min, d_max)
        .windows(2)
        .map(|w| CaptureClass {
            d_lo: w[0],
            d_hi: w[1],
            ..Default::default()
        })
        .collect::<Vec<_>>();
    let class_of = |d: Real| {
        classes
            .iter()
            .position(|c| d < c.d_hi)
            .unwrap_or(classes.len().saturating_sub(1))
    };
    let mut tally = vec![(0u64, 0u64, 0u64); classes.len()];
    let thickness = (medium_surface - medium_bottom).max(0.0);
    let mut depth_profile: Vec<DepthBin> = (0..DEPTH_BINS)
        .map(|k| DepthBin {
            depth_lo: thickness * k as Real / DEPTH_BINS as Real,
            depth_hi: thickness * (k + 1) as Real / DEPTH_BINS as Real,
            lodged: 0,
        })
        .collect();
    for f in filtrate {
        if !classes.is_empty() {
            tally[class_of(2.0 * f.radius)].0 += 1;
        }
    }
    for &(d, z) in &bodies {
        let c = class_of(d);
        if z < medium_surface {
            tally[c].1 += 1;
            let depth = medium_surface - z;
            let bin = if thickness > 0.0 {
                ((depth / thickness * DEPTH_BINS as Real) as usize).min(DEPTH_BINS - 1)
            } else {
                0
            };
            depth_profile[bin].lodged += 1;
        } else {
            tally[c].2 += 1;
        }
    }
    for (c, &(passed, lodged, cake)) in classes.iter_mut().zip(&tally) {
        c.passed = passed;
        c.lodged = lodged;
        c.cake = cake;
        c.fed = passed + lodged + cake;
        c.grade_efficiency = (c.fed > 0).then(|| (lodged + cake) as Real / c.fed as Real);
    }
    let (x50, note) = cut_size(&classes);
    let slurry: Vec<Real> = bodies
        .iter()
        .map(|b| b.0)
        .chain(filtrate.iter().map(|f| 2.0 * f.radius))
        .collect();
    let (criteria, constrictions) =
        criteria(bed, &is_medium, &slurry, medium_bottom, medium_surface)
            .map_or((None, Vec::new()), |(c, d)| (Some(c), d));
    let passed = filtrate.len() as u64;
    let lodged: u64 = tally.iter().map(|t| t.1).sum();
    let cake: u64 = tally.iter().map(|t| t.2).sum();
    let fed = passed + lodged + cake;
    let fraction = |n: u64| (fed > 0).then(|| n as Real / fed as Real);
    Some(CaptureSummary {
        fed,
        passed,
        lodged,
        cake,
        passed_fraction: fraction(passed),
        lodged_fraction: fraction(lodged),
        cake_fraction: fraction(cake),
        medium_bodies,
        medium_lift: lift,
        medium_bottom,
        medium_surface,
        x50,
        note,
        classes,
        depth_profile,
        criteria,
        filtrate: filtrate.to_vec(),
        constrictions,
    })
}

/// The bed of the particles `is_medium` picks alone: the clean medium.
pub(crate) fn medium_bed<const D: usize>(
    bed: &Bed<D>,
    is_medium: &dyn Fn(usize) -> bool,
) -> Bed<D> {
    let mut medium = Bed::new(bed.container, bed.species_info.clone());
    for i in (0..bed.len()).filter(|&i| is_medium(i)) {
        medium.push_bead(bed.centres[i], bed.radii[i], bed.species[i], bed.bodies[i]);
    }
    medium
}

/// The retention criteria of the medium against the slurry diameters
/// `slurry` (every body fed after the medium), with the constriction
/// distribution they are read from; `None` when the medium's pore network
/// has no throat between its bottom and surface.
fn criteria<const D: usize>(
    bed: &Bed<D>,
    is_medium: &dyn Fn(usize) -> bool,
    slurry: &[Real],
    bottom: Real,
    surface: Real,
) -> Option<(FilterCriteria, Vec<ConstrictionClass>)> {
    let medium: Vec<Real> = (0..bed.len())
        .filter(|&i| is_medium(i))
        .map(|i| 2.0 * bed.radii[i])
        .collect();
    let space = super::pores::pore_space(
        &medium_bed(bed, is_medium),
        (bottom, surface),
        None,
        None,
        None,
    )
    .ok()?;
    let c = &space.pores.constriction_radius;
    if c.count == 0 {
        return None;
    }
    let d_c35 = 2.0 * c.p35;
    let medium_d15 = weighted_percentile(&medium, 0.15, D as i32);
    let slurry_d85 = weighted_percentile(slurry, 0.85, D as i32);
    let slurry_d85_by_surface = weighted_percentile(slurry, 0.85, D as i32 - 1);
    // The throats the percentiles count: both pores in the slab.
    let t = &space.tables;
    let throats: Vec<Real> = t
        .throats
        .iter()
        .filter(|th| th.pores.iter().all(|&p| t.pores[p as usize].in_slab))
        .map(|th| 2.0 * th.constriction_radius)
        .collect();
    let criteria = FilterCriteria {
        medium_d15,
        slurry_d85,
        slurry_d85_by_surface,
        constriction_diameter: [2.0 * c.p10, d_c35, 2.0 * c.p50, 2.0 * c.p90],
        terzaghi_ratio: medium_d15 / slurry_d85,
        kenney_constriction: medium_d15 / 5.0,
        indraratna_ratio: d_c35 / slurry_d85_by_surface,
    };
    Some((criteria, constriction_classes(&throats, slurry)))
}

/// The constriction diameters `throats` and the slurry diameters `slurry`
/// counted in [`CONSTRICTION_CLASSES`] log-spaced classes over both (the
/// throats of zero width, closed by contacts, in the first).
fn constriction_classes(throats: &[Real], slurry: &[Real]) -> Vec<ConstrictionClass> {
    let open = throats.iter().chain(slurry).copied().filter(|&d| d > 0.0);
    let (lo, hi) = open.fold((Real::INFINITY, 0.0), |(lo, hi): (Real, Real), d| {
        (lo.min(d), hi.max(d))
    });
    let e = log_edges(lo, hi, CONSTRICTION_CLASSES);
    if e.is_empty() {
        return Vec::new();
    }
    let n = e.len() - 1;
    let class = |d: Real| e[1..].partition_point(|&hi| hi <= d).min(n - 1);
    let count = |v: &[Real]| {
        let mut c = vec![0u64; n];
        for &d in v {
            c[class(d)] += 1;
        }
        c
    };
    let (ct, cs) = (count(throats), count(slurry));
    let (mut at, mut as_) = (0u64, 0u64);
    let fraction = |k: u64, of: usize| if of > 0 { k as Real / of as Real } else { 0.0 };
    (0..n)
        .map(|k| {
            at += ct[k];
            as_ += cs[k];
            ConstrictionClass {
                d_lo: e[k],
                d_hi: e[k + 1],
                constrictions: ct[k],
                constrictions_finer: fraction(at, throats.len()),
                slurry: cs[k],
                slurry_finer: fraction(as_, slurry.len()),
            }
        })
        .collect()
}

/// The diameter a fraction `q` of the total weight `d^power` is finer than
/// (mass: `power` = dimension; surface: one less); 0 for no diameter.
fn weighted_percentile(d: &[Real], q: Real, power: i32) -> Real {
    let mut v: Vec<Real> = d.to_vec();
    v.sort_by(Real::total_cmp);
    let total: Real = v.iter().map(|x| x.powi(power)).sum();
    let mut acc = 0.0;
    for &x in &v {
        acc += x.powi(power);
        if acc >= q * total {
            return x;
        }
    }
    v.last().copied().unwrap_or(0.0)
}

/// `CLASSES + 1` log-spaced edges from `lo` to `hi`; one class when they
/// are equal, none when nothing was fed.
fn edges(lo: Real, hi: Real) -> Vec<Real> {
    log_edges(lo, hi, CLASSES)
}

/// `n + 1` log-spaced edges from `lo` to `hi`; one class when they are
/// equal, none when `lo` is not a positive number at most `hi`.
fn log_edges(lo: Real, hi: Real, n: usize) -> Vec<Real> {
    if !(lo > 0.0 && hi >= lo) {
        return Vec::new();
    }
    if hi <= lo * (1.0 + 1e-12) {
        return vec![lo, hi];
    }
    let step = (hi / lo).ln() / n as Real;
    let mut e: Vec<Real> = (0..=n).map(|k| lo * (step * k as Real).exp()).collect();
    // The ends exactly, not as rounded by exp.
    e[0] = lo;
    e[n] = hi;
    e
}

/// Where the grade efficiency first reaches 0.5 going up in size,
/// interpolated in log d between the geometric centres of the classes on
/// either side; or why there is no such place.
fn cut_size(classes: &[CaptureClass]) -> (Option<Real>, Option<String>) {
    let points: Vec<(Real, Real)> = classes
        .iter()
        .filter_map(|c| Some(((c.d_lo * c.d_hi).sqrt().ln(), c.grade_efficiency?)))
        .collect();
    let Some(first) = points.first() else {
        return (None, Some("nothing was fed after the medium".into()));
    };
    if first.1 >= 0.5 {
        return (
            None,
            Some(
                "every size class is captured at least half: x50 lies below the smallest size fed"
                    .into(),
            ),
        );
    }
    for w in points.windows(2) {
        let ((a, ea), (b, eb)) = (w[0], w[1]);
        if ea < 0.5 && eb >= 0.5 {
            let t = (0.5 - ea) / (eb - ea);
            return (Some((a + t * (b - a)).exp()), None);
        }
    }
    (
        None,
        Some("no size class is captured half: x50 lies above the largest size fed".into()),
    )
}

/// The mean height of the top of the particles `is_medium` picks over the
/// columns they cover: a height map of their highest surface above a grid of column centres
/// (cells of a quarter of the smallest medium radius, at most
/// [`MAX_COLUMNS`] a side). `None` when it covers no column.
pub(crate) fn mean_top<const D: usize>(
    bed: &Bed<D>,
    is_medium: &dyn Fn(usize) -> bool,
) -> Option<Real> {
    let c = &bed.container;
    let r_min = (0..bed.len())
        .filter(|&i| is_medium(i))
        .map(|i| bed.radii[i])
        .fold(Real::INFINITY, Real::min);
    let sides: Vec<Real> = (0..D - 1).map(|k| c.size[k]).collect();
    let n: Vec<usize> = sides
        .iter()
        .map(|&l| ((l / (0.25 * r_min)).ceil() as usize).clamp(1, MAX_COLUMNS))
        .collect();
    let cell: Vec<Real> = sides.iter().zip(&n).map(|(&l, &n)| l / n as Real).collect();
    let columns: usize = n.iter().product();
    let mut top = vec![Real::NEG_INFINITY; columns];
    for i in (0..bed.len()).filter(|&i| is_medium(i)) {
        let (p, r) = (bed.centres[i], bed.radii[i]);
        // The column indices its footprint reaches along each axis (wrapped
        // when periodic, clipped by walls).
        let range = |k: usize| {
            let lo = ((p[k] - r) / cell[k] - 0.5).ceil() as isize;
            let hi = ((p[k] + r) / cell[k] - 0.5).floor() as isize;
            (lo, hi)
        };
        let index = |k: usize, j: isize| -> Option<usize> {
            let m = n[k] as isize;
            if c.periodic {
                Some(j.rem_euclid(m) as usize)
            } else {
                (0..m).contains(&j).then_some(j as usize)
            }
        };
        let (x0, x1) = range(0);
        let (y0, y1) = if D == 3 { range(1) } else { (0, 0) };
        for jx in x0..=x1 {
            let Some(ix) = index(0, jx) else { continue };
            let dx = (jx as Real + 0.5) * cell[0] - p[0];
            for jy in y0..=y1 {
                let (iy, dy) = if D == 3 {
                    let Some(iy) = index(1, jy) else { continue };
                    (iy, (jy as Real + 0.5) * cell[1] - p[1])
                } else {
                    (0, 0.0)
                };
                let h2 = dx * dx + dy * dy;
                if h2 <= r * r {
                    let z = p[D - 1] + (r * r - h2).sqrt();
                    let t = &mut top[ix + n[0] * iy];
                    *t = t.max(z);
                }
            }
        }
    }
    let covered: Vec<Real> = top.into_iter().filter(|t| t.is_finite()).collect();
    (!covered.is_empty()).then(|| covered.iter().sum::<Real>() / covered.len() as Real)
}
