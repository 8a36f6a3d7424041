//! The filtration of the slurry through the medium, as a laboratory reads it:
//! the filtration curve t/V against V (Ruth), its fitted specific cake
//! resistance α and medium resistance R_m beside the network's own.
//!
//! The flow through medium and cake is Stokes flow on the pore network of
//! the finished bed ([`super::pores`]), solved along z from the medium's
//! bottom up to each checkpoint's level h: the resistance of the bed below h
//! is `R(h) = (h − z_bottom) / k(h)` (Darcy, in 1/m), with the medium's
//! bottom a mirror plane of the pore space (`mirrored_below`), and the solids below h
//! are the mass the filter has taken, `w(h)` per area. A sequential bed is
//! built bottom up and never moves, so the bed below h is the cake at the
//! time the cake stood at h; the particles that later fill the pockets of
//! that surface are within a particle of it. The filtrate volume per area
//! is `V = w / c`, Ruth's `c` the solids deposited per filtrate volume.
//!
//! At constant pressure Δp the filtrate flows at `dV/dt = Δp / (μ R)`, so
//! `t(V) = μ/Δp ∫₀^V R dV'`, integrated with R linear between checkpoints
//! (exact for a cake whose R grows linearly in its mass) from the clean
//! medium's R_m at V = 0. At constant rate q, `t = V / q` and
//! `Δp = μ q R`. Ruth's line `t/V = μ α c V / (2 Δp) + μ R_m / Δp` (or
//! `Δp = μ q (R_m + α c V)` at constant rate) is fitted to the checkpoints
//! by least squares, as a laboratory fits its measured curve.

use super::capture::CaptureSummary;
use super::pores::flow::{conductances, merged, solve_z};
use super::pores::network::network;
use super::pores::FlowOptions;
use crate::bed::Bed;
use crate::config::{Drive, FiltrationConfig, Mesh};
use crate::math::{ball_volume, Real};
use rayon::prelude::*;
use serde::Serialize;

/// How deep below the medium's bottom its mirror image reaches, in largest
/// radii: six, three largest diameters, as the network's side margin.
const MIRROR_DEPTH: Real = 6.0;

/// How far above the medium's bottom the slab starts, in largest radii.
const MIRROR_CUT: Real = 1e-9;

/// `bed` with every particle whose centre lies less than `depth` from the
/// plane `z = plane` on the bed's side mirrored in it, each image its own
/// body: below the plane (`up`, the bed above it) or above it. The
/// medium's bottom is then a plane of symmetry of the pore space, as a side
/// wall is ([`super::pores::network`]); without it the cells below the
/// lowest particles' centres are the triangulation's hull, slivers whose
/// centres lie anywhere (three diameters below the floor) and whose links
/// change with the rounding of the coordinates: the clean medium's R_m
/// moved 3.4 % between the same bed in µm and in mm. A mesh's top is
/// mirrored too for its own R_m: its upper wires' centres lie in one plane.
fn mirrored<const D: usize>(bed: &Bed<D>, plane: Real, depth: Real, up: bool) -> Bed<D> {
    let mut out = bed.clone();
    let mut body = bed.bodies.iter().copied().max().map_or(0, |b| b + 1);
    for i in 0..bed.len() {
        let mut c = bed.centres[i];
        let from = if up {
            c[D - 1] - plane
        } else {
            plane - c[D - 1]
        };
        if from < depth {
            c[D - 1] = 2.0 * plane - c[D - 1];
            out.push_bead(c, bed.radii[i], bed.species[i], body);
            body += 1;
        }
    }
    out
}

/// Armour & Cannon's (1968) viscous resistance of one plain square-weave
/// screen, 1/m: `R = α a² L / ε²` with α = 8.61 (their fit over plain,
/// twilled and Dutch weaves, ±30 % on later data, Azizi 2019), the screen's
/// thickness L = 2d, its porosity ε = 1 − π d / 4p and its wire surface
/// per screen volume a = (1 − ε) 4/d; the wires' crimp is left out, as the
/// mesh's geometry leaves it out. `unit` metres per length unit.
fn screen_resistance(mesh: &Mesh, unit: Real) -> Real {
    let d = 2.0 * mesh.r * unit;
    let p = mesh.pitch * unit;
    let solid = std::f64::consts::PI * d / (4.0 * p);
    let porosity = 1.0 - solid;
    let a = solid * 4.0 / d;
    8.61 * a * a * (2.0 * d) / (porosity * porosity)
}

/// The least centre distance of a wire's beads, in wire radii, that the
/// flow network sees.
const WIRE_SPACING: Real = 1.2;

/// `bed` with every body of the species `wires[s]` (a mesh's wires) kept
/// to every k-th bead, k the least divisor of its beads that spaces them
/// [`WIRE_SPACING`] radii or more. A wire is laid as beads a quarter radius
/// apart, so that no notch between beads holds a particle; to the pore
/// network such beads are each inside their neighbours, every facet with
/// two of them has no fluid area, and no throat beside a wire conducts.
/// Beads 1.2 radii apart overlap pairwise only, which the network's
/// geometry takes exactly, and leave notches 0.2 radii deep.
fn thinned_wires<const D: usize>(bed: &Bed<D>, wires: &[bool]) -> Bed<D> {
    let mut out = Bed::new(bed.container, bed.species_info.clone());
    let mut start = 0;
    while start < bed.len() {
        let mut end = start + 1;
        while end < bed.len() && bed.bodies[end] == bed.bodies[start] {
            end += 1;
        }
        let n = end - start;
        let wire = wires.get(bed.species[start] as usize).copied() == Some(true);
        let step = if wire && n > 2 {
            let gap = (bed.centres[start + 1] - bed.centres[start]).norm() / bed.radii[start];
            (1..=n / 2)
                .find(|&k| n % k == 0 && k as Real * gap >= WIRE_SPACING)
                .unwrap_or(1)
        } else {
            1
        };
        for i in (start..end).step_by(step) {
            out.push_bead(bed.centres[i], bed.radii[i], bed.species[i], bed.bodies[i]);
        }
        start = end;
    }
    out
}

/// One checkpoint of the filtration (a row of `filtration.csv`), in SI.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Checkpoint {
    /// Time since the start, s.
    pub time_s: Real,
    /// Filtrate volume per filter area, m³/m².
    pub volume_m3_per_m2: Real,
    /// Pressure drop across medium and cake, Pa.
    pub pressure_pa: Real,
    /// Cake height above the medium's surface, m.
    pub cake_height_m: Real,
    /// Solids taken by the filter per area (cake and lodged), kg/m².
    pub mass_kg_per_m2: Real,
    /// Resistance of medium and cake, 1/m.
    pub r_total_per_m: Real,
    /// Of it, the cake's: `r_total − r_medium`, 1/m.
    pub r_cake_per_m: Real,
    /// The clean medium's own resistance, 1/m.
    pub r_medium_per_m: Real,
}

/// `filtration.final`: where the curve ended, in SI (the last checkpoint's).
#[derive(Clone, Copy, Debug, Default, Serialize, PartialEq)]
pub struct End {
    /// Time since the start, s.
    pub time_s: Real,
    /// Filtrate volume per filter area, m³/m².
    pub volume_m3_per_m2: Real,
    /// Pressure drop across medium and cake, Pa.
    pub pressure_pa: Real,
    /// Cake height above the medium's surface, m.
    pub cake_height_m: Real,
    /// Solids taken by the filter per area (cake and lodged), kg/m².
    pub mass_kg_per_m2: Real,
    /// Resistance of medium and cake, 1/m.
    pub r_total_per_m: Real,
}

impl From<&Checkpoint> for End {
    fn from(c: &Checkpoint) -> End {
        End {
            time_s: c.time_s,
            volume_m3_per_m2: c.volume_m3_per_m2,
            pressure_pa: c.pressure_pa,
            cake_height_m: c.cake_height_m,
            mass_kg_per_m2: c.mass_kg_per_m2,
            r_total_per_m: c.r_total_per_m,
        }
    }
}

/// `filtration.*` of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct FiltrationSummary {
    /// `pressure` (constant pressure drop) or `flow_rate` (constant rate).
    pub drive: &'static str,
    /// The checkpoints, in order (`filtration.csv`).
    pub checkpoints: Vec<Checkpoint>,
    /// The clean medium's own resistance, from the network of the medium
    /// alone, 1/m.
    pub r_medium_per_m: Real,
    /// The medium's resistance with the particles lodged in it, at the end, 1/m.
    pub r_medium_clogged_per_m: Real,
    /// For a woven mesh: Armour & Cannon's (1968) correlation for one plain
    /// square-weave screen of its wires and pitch, viscous term, 1/m, beside
    /// the network's `r_medium_per_m` (whose mesh is mirrored at its bottom
    /// and top, a stack of screens: a network has no pores in open fluid).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r_medium_screen_per_m: Option<Real>,
    /// The network's specific resistance of the final cake: the rise of R
    /// over the rise of the mass per area above the medium's surface, m/kg.
    pub alpha_network_m_per_kg: Option<Real>,
    /// α fitted to the curve as a laboratory fits it (Ruth), m/kg.
    pub alpha_fit_m_per_kg: Option<Real>,
    /// R_m fitted to the curve (its intercept), 1/m.
    pub r_medium_fit_per_m: Option<Real>,
    /// The rms departure of the curve from its fitted line over the mean of
    /// the curve: how straight Ruth's line is.
    pub ruth_departure: Option<Real>,
    /// The last checkpoint, where the curve ended (the same as the last of
    /// `checkpoints`): the ensemble tables' time, volume, cake height and
    /// mass at the end, whichever checkpoint each bed stopped at.
    #[serde(rename = "final", skip_serializing_if = "Option::is_none")]
    pub end: Option<End>,
    /// Which stop ended the curve before the last checkpoint (`pressure`,
    /// `time`, `mass`), if one did.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped_by: Option<&'static str>,
    /// The standard error of `r_medium_fit_per_m` from the scatter of the
    /// checkpoints about Ruth's line (least squares, n − 2 degrees of
    /// freedom), 1/m; null with fewer than three points.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r_medium_fit_se_per_m: Option<Real>,
    /// Why the fitted R_m is not the medium's, when the curve does not
    /// resolve it (the intercept is not above twice its standard error).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// Wall time of the network and its solves, s.
    pub seconds: f64,
}

/// What the filtration knows of the medium.
pub struct Medium<'a> {
    /// Which species are the medium's.
    pub species: &'a [bool],
    /// A woven mesh, and which species are its wires.
    pub mesh: Option<(&'a Mesh, &'a [bool])>,
}

/// The permeability along z (length², at unit viscosity) of `bed` between
/// the plane `z_bottom`, mirrored (`mirrored`), and each of `levels`, from
/// one network; 0 below a level with no open path. `scale` is the bed's
/// largest radius. The slab starts a hair above the plane: the mirror puts
/// the power centres of the cells that straddle it on that plane, and
/// their side of the cut would be a rounding coin (the pores on it hold
/// `P = −z` there either way).
fn permeabilities<const D: usize>(
    bed: &Bed<D>,
    z_bottom: Real,
    scale: Real,
    levels: &[Real],
    flow: &FlowOptions,
) -> Result<Vec<Real>, String> {
    let unit_flow = FlowOptions {
        viscosity: 1.0,
        ..*flow
    };
    let inlet = z_bottom + MIRROR_CUT * scale;
    let top_level = levels.iter().copied().fold(z_bottom, Real::max);
    let bed = mirrored(bed, z_bottom, MIRROR_DEPTH * scale, true);
    let net = network(&bed, (z_bottom, top_level)).map_err(|e| e.to_string())?;
    let merge = merged(&net.shapes);
    let g = conductances(&net, &net.shapes, &merge, &unit_flow);
    // Each level's solve on its own thread where one is free: a solve's
    // set-up is partly serial, and the levels are independent.
    levels
        .par_iter()
        .map(|&h| {
            let (axis, _) = solve_z(&net, &merge, &g, &bed.container.size, (inlet, h))
                .map_err(|e| format!("the flow below {h} could not be solved ({e:?})"))?;
            match axis.k {
                Some(k) if k > 0.0 => Ok(k),
                Some(_) => Ok(0.0),
                None => Err(format!("the flux below {h} does not balance")),
            }
        })
        .collect()
}

/// Whether fluid passes `medium` (a filter medium alone, on its floor)
/// from its bottom to its surface, its mean top, on its pore network:
/// `Ok(false)` when no path is open. Spheres of different bodies that do
/// not overlap always leave one in 3D; beads of one body that overlap
/// deeply close the throats between them (the network gives a facet of two
/// such beads no fluid area), and so can a sintered plate read from a
/// file.
pub fn medium_is_open<const D: usize>(medium: &Bed<D>, flow: &FlowOptions) -> Result<bool, String> {
    let z_bottom = (0..medium.len())
        .map(|i| medium.centres[i][D - 1] - medium.radii[i])
        .fold(Real::INFINITY, Real::min);
    let Some(surface) = super::capture::mean_top(medium, &|_| true) else {
        return Ok(true);
    };
    if !z_bottom.is_finite() || surface <= z_bottom {
        return Ok(true);
    }
    let scale = medium.radii.iter().copied().fold(0.0, Real::max);
    let (stack, level) = capped(medium, surface, scale);
    Ok(permeabilities(&stack, z_bottom, scale, &[level], flow)?[0] > 0.0)
}

/// A clean granular medium with its mirror image above the plane its
/// highest particle touches, so that the pores over its surface are cells
/// of particles, not the triangulation's hull: a medium one particle thick
/// has no cells above its centres at all, and its flow no outlet. With the
/// level its resistance is taken to: its `surface`, but a hair below that
/// plane, on which the cells between a layer and its image centre (a
/// monolayer's mean top is the plane). `scale` is the largest radius.
fn capped<const D: usize>(medium: &Bed<D>, surface: Real, scale: Real) -> (Bed<D>, Real) {
    let peak = (0..medium.len())
        .map(|i| medium.centres[i][D - 1] + medium.radii[i])
        .fold(Real::NEG_INFINITY, Real::max);
    (
        mirrored(medium, peak, MIRROR_DEPTH * scale, false),
        surface.min(peak - MIRROR_CUT * scale),
    )
}

/// The filtration of `bed` (built with a medium, whose capture is `capture`)
/// under `options`; `unit` metres per length unit, `rho` the solid density
/// (kg/m³), `flow` the network's conductance settings. `Err` says why there
/// is none.
pub fn filtration<const D: usize>(
    bed: &Bed<D>,
    medium: &Medium,
    capture: &CaptureSummary,
    options: &FiltrationConfig,
    unit: Real,
    rho: Real,
    flow: &FlowOptions,
) -> Result<FiltrationSummary, String> {
    let started = std::time::Instant::now();
    let Medium {
        species: medium,
        mesh,
    } = *medium;
    let drive = options.drive().map_err(|e| e.to_string())?;
    let is_medium = |i: usize| {
        medium
            .get(bed.species[i] as usize)
            .copied()
            .unwrap_or(false)
    };
    let z_bottom = capture.medium_bottom;
    let wires = mesh.map_or(&[][..], |m| m.1);
    let is_wire = |b: &Bed<D>, i: usize| wires.get(b.species[i] as usize).copied() == Some(true);
    // A bare mesh's filtration starts over its upper wires: its mid-plane
    // (the capture's surface) would halve it, and the cells of its
    // symmetric wires centre on that plane, a rounding coin for the cut. A
    // mesh under a precoat is part of a granular medium, whose surface is
    // the precoat's top.
    let precoated = (0..bed.len()).any(|i| is_medium(i) && !is_wire(bed, i));
    let mesh_top = (0..bed.len())
        .filter(|&i| !precoated && is_wire(bed, i))
        .map(|i| bed.centres[i][D - 1] + bed.radii[i])
        .fold(Real::NEG_INFINITY, Real::max);
    let mesh_top = mesh_top.is_finite().then_some(mesh_top);
    let surface = mesh_top.unwrap_or(capture.medium_surface);
    let d_max = (0..bed.len())
        .filter(|&i| !is_medium(i))
        .map(|i| 2.0 * bed.radii[i])
        .fold(0.0, Real::max);
    let top = super::capture::mean_top(bed, &|_| true).unwrap_or(surface);
    // The cake's last level stands a largest diameter below its mean top:
    // above it lies the rough surface, where later particles would still
    // settle.
    let end = top - d_max;
    if end.partial_cmp(&(surface + d_max)) != Some(std::cmp::Ordering::Greater) {
        return Err(format!(
            "the cake is too thin for a filtration curve: its top ({top:.4}) stands less than two \
             of its largest diameters ({d_max:.4}) above the medium's surface ({surface:.4}); feed more"
        ));
    }
    let n = options.checkpoints as usize;
    let levels: Vec<Real> = (0..=n)
        .map(|j| surface + (end - surface) * j as Real / n as Real)
        .collect();
    let scale = bed.radii.iter().copied().fold(0.0, Real::max);
    let inlet = z_bottom + MIRROR_CUT * scale;
    // The resistance of `bed` below each level (1/m), from one network.
    let resistances = |bed: &Bed<D>, levels: &[Real]| -> Result<Vec<Real>, String> {
        let k = permeabilities(bed, z_bottom, scale, levels, flow)?;
        levels
            .iter()
            .zip(k)
            .map(|(&h, k)| match k {
                k if k > 0.0 => Ok((h - inlet) / k / unit),
                _ => Err(format!(
                    "no open path through the bed below {h}: the filter is closed"
                )),
            })
            .collect()
    };
    // The masses are the bed's; the flow sees the wires as beads a little
    // more than a radius apart (`thinned_wires`).
    let thinned = mesh.map(|_| thinned_wires(bed, wires));
    let flow_bed = thinned.as_ref().unwrap_or(bed);
    let medium_bed = super::capture::medium_bed(flow_bed, &|i| {
        medium.get(flow_bed.species[i] as usize) == Some(&true)
    });
    let r_medium = match mesh_top {
        Some(top) => resistances(
            &mirrored(&medium_bed, top, MIRROR_DEPTH * scale, false),
            &[top - MIRROR_CUT * scale],
        )?[0],
        None => {
            let (stack, level) = capped(&medium_bed, surface, scale);
            resistances(&stack, &[level])?[0]
        }
    };
    drop(medium_bed);
    let r = resistances(flow_bed, &levels)?;
    drop(thinned);
    // Solids per area below each level (kg/m²), the medium's left out (3D:
    // the config refuses a 2D filtration).
    let area: Real = (0..D - 1).map(|k| bed.container.size[k] * unit).product();
    let mass = |i: usize| rho * ball_volume::<D>(bed.radii[i]) * unit.powi(3);
    let mut below: Vec<(Real, Real)> = (0..bed.len())
        .filter(|&i| !is_medium(i))
        .map(|i| (bed.centres[i][D - 1], mass(i)))
        .collect();
    below.sort_by(|a, b| a.0.total_cmp(&b.0));
    let w: Vec<Real> = levels
        .iter()
        .map(|&h| {
            let k = below.partition_point(|e| e.0 < h);
            below[..k].iter().map(|e| e.1).sum::<Real>() / area
        })
        .collect();
    let (mu, c) = (options.viscosity, options.concentration);
    // The curve: (V, R) from the clean medium at V = 0 through every level.
    let mut rows = Vec::with_capacity(n + 1);
    let (mut t, mut v_prev, mut r_prev) = (0.0, 0.0, r_medium);
    for j in 0..=n {
        let v = w[j] / c;
        let (time, pressure) = match drive {
            Drive::Pressure(dp) => {
                t += mu / dp * 0.5 * (r_prev + r[j]) * (v - v_prev);
                (t, dp)
            }
            Drive::FlowRate(q) => (v / q, mu * q * r[j]),
        };
        (v_prev, r_prev) = (v, r[j]);
        rows.push(Checkpoint {
            time_s: time,
            volume_m3_per_m2: v,
            pressure_pa: pressure,
            cake_height_m: (levels[j] - surface) * unit,
            mass_kg_per_m2: w[j],
            r_total_per_m: r[j],
            r_cake_per_m: r[j] - r_medium,
            r_medium_per_m: r_medium,
        });
    }
    let mut stopped_by = None;
    if let Some(stop) = &options.stop {
        let reached = |row: &Checkpoint| {
            if stop.pressure.is_some_and(|p| row.pressure_pa >= p) {
                Some("pressure")
            } else if stop.time.is_some_and(|s| row.time_s >= s) {
                Some("time")
            } else if stop.mass.is_some_and(|m| row.mass_kg_per_m2 >= m) {
                Some("mass")
            } else {
                None
            }
        };
        if let Some(k) = rows.iter().position(|row| reached(row).is_some()) {
            stopped_by = reached(&rows[k]);
            rows.truncate(k + 1);
        }
    }
    // Ruth's line through the checkpoints past the medium's surface.
    let points: Vec<(Real, Real)> = rows
        .iter()
        .skip(1)
        .filter(|row| row.volume_m3_per_m2 > 0.0)
        .map(|row| {
            let v = row.volume_m3_per_m2;
            match drive {
                Drive::Pressure(_) => (v, row.time_s / v),
                Drive::FlowRate(_) => (v, row.pressure_pa),
            }
        })
        .collect();
    let fit = line(&points);
    // The intercept's scale from the curve's units to 1/m.
    let to_r = match drive {
        Drive::Pressure(dp) => dp / mu,
        Drive::FlowRate(q) => 1.0 / (mu * q),
    };
    let (alpha_fit, r_fit) = match (fit, drive) {
        (Some((slope, icpt)), Drive::Pressure(dp)) => {
            (Some(2.0 * dp * slope / (mu * c)), Some(icpt * to_r))
        }
        (Some((slope, icpt)), Drive::FlowRate(q)) => {
            (Some(slope / (mu * q * c)), Some(icpt * to_r))
        }
        (None, _) => (None, None),
    };
    let r_fit_se = fit
        .and_then(|f| intercept_error(&points, f))
        .map(|se| se * to_r)
        .filter(|se| se.is_finite());
    // A medium far less resistant than the cake is within the curve's
    // scatter: its intercept can come out anywhere, below zero too.
    let note = match (r_fit.filter(|r| r.is_finite()), r_fit_se) {
        (Some(fitted), Some(se)) if fitted <= 2.0 * se => Some(format!(
            "Ruth's intercept ({fitted:.3e} ± {se:.3e} 1/m) does not resolve the medium: its resistance \
             ({r_medium:.3e} 1/m clean, {:.3e} in place) is {:.2} % of the filter's at the end \
             ({:.3e}), within the curve's scatter about the line; read r_medium_per_m and \
             r_medium_clogged_per_m",
            r[0],
            100.0 * r[0] / r[n].max(Real::MIN_POSITIVE),
            r[n]
        )),
        _ => None,
    };
    let departure = fit.map(|(slope, icpt)| {
        let mean = points.iter().map(|p| p.1).sum::<Real>() / points.len() as Real;
        let rms = (points
            .iter()
            .map(|p| (p.1 - slope * p.0 - icpt).powi(2))
            .sum::<Real>()
            / points.len() as Real)
            .sqrt();
        rms / mean
    });
    let dw = w[n] - w[0];
    let alpha_network = (dw > 0.0).then(|| (r[n] - r[0]) / dw);
    Ok(FiltrationSummary {
        drive: match drive {
            Drive::Pressure(_) => "pressure",
            Drive::FlowRate(_) => "flow_rate",
        },
        end: rows.last().map(End::from),
        checkpoints: rows,
        r_medium_per_m: r_medium,
        r_medium_screen_per_m: mesh.map(|m| screen_resistance(m.0, unit)),
        r_medium_clogged_per_m: r[0],
        alpha_network_m_per_kg: alpha_network,
        alpha_fit_m_per_kg: alpha_fit.filter(|a| a.is_finite()),
        r_medium_fit_per_m: r_fit.filter(|r| r.is_finite()),
        ruth_departure: departure.filter(|d| d.is_finite()),
        stopped_by,
        r_medium_fit_se_per_m: r_fit_se,
        note,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// The least-squares line `y = a x + b` through `points` (at least two
/// distinct x), as `(a, b)`: Ruth's line here and in its plot.
pub fn line(points: &[(Real, Real)]) -> Option<(Real, Real)> {
    let n = points.len() as Real;
    if points.len() < 2 {
        return None;
    }
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
    let sxx: Real = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: Real = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| {
        let a = sxy / sxx;
        (a, my - a * mx)
    })
}

/// The standard error of the intercept of the least-squares `fit` (slope,
/// intercept) of `points`: `s √(1/n + x̄² / Sxx)`, `s²` the residuals'
/// sum of squares over `n − 2`; `None` with fewer than three points.
fn intercept_error(points: &[(Real, Real)], fit: (Real, Real)) -> Option<Real> {
    let n = points.len();
    if n < 3 {
        return None;
    }
    let nf = n as Real;
    let mx = points.iter().map(|p| p.0).sum::<Real>() / nf;
    let sxx: Real = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let ssr: Real = points
        .iter()
        .map(|p| (p.1 - fit.0 * p.0 - fit.1).powi(2))
        .sum();
    (sxx > 0.0).then(|| (ssr / (nf - 2.0) * (1.0 / nf + mx * mx / sxx)).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_through_points_on_a_line_is_that_line() {
        let pts: Vec<(Real, Real)> = (0..5).map(|i| (i as Real, 3.0 * i as Real + 2.0)).collect();
        let (a, b) = line(&pts).unwrap();
        assert!((a - 3.0).abs() < 1e-12 && (b - 2.0).abs() < 1e-12);
        assert!(line(&pts[..1]).is_none());
        assert!(line(&[(1.0, 1.0), (1.0, 2.0)]).is_none());
    }

    /// By hand: points (0, 1), (1, 2), (2, 2), (3, 4): the fit y = 0.9 x + 0.9,
    /// residuals 0.1, 0.2, −0.7, 0.4, SSR 0.7, s² 0.35, x̄ 1.5, Sxx 5, so
    /// se² = 0.35 (1/4 + 2.25/5) = 0.245.
    #[test]
    fn the_intercepts_error_is_the_textbooks() {
        let pts = [(0.0, 1.0), (1.0, 2.0), (2.0, 2.0), (3.0, 4.0)];
        let fit = line(&pts).unwrap();
        assert!((fit.0 - 0.9).abs() < 1e-12 && (fit.1 - 0.9).abs() < 1e-12);
        let se = intercept_error(&pts, fit).unwrap();
        assert!((se * se - 0.245).abs() < 1e-12, "{se}");
        assert_eq!(intercept_error(&pts[..2], fit), None);
        let on_line: Vec<(Real, Real)> =
            (0..5).map(|i| (i as Real, 2.0 * i as Real + 1.0)).collect();
        assert!(intercept_error(&on_line, line(&on_line).unwrap()).unwrap() < 1e-12);
    }
}
