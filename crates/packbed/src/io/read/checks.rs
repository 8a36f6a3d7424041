//! The checks every format shares: radii, box, length scale, particles inside
//! the box, crowding; then the bed in its dimension.

// `!(x > 0.0)` is how NaN is refused along with the non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::raw::{build, densify_species, Raw, Reader};
use super::report::{BoxHint, BoxSource, ReadReport, OUTSIDE_TOL};
use crate::bed::AnyBed;
use crate::error::Result;
use crate::math::Real;

impl Reader<'_> {
    /// The common checks, then the bed in its dimension.
    pub(super) fn finish(
        &self,
        mut raw: Raw,
        hint: Option<&BoxHint>,
    ) -> Result<(AnyBed, ReadReport)> {
        if raw.pos.is_empty() {
            return Err(self.err(1, "no particles in the file"));
        }
        for (k, &r) in raw.radii.iter().enumerate() {
            if !(r > 0.0) {
                return Err(self.err(raw.lines[k], format!("radius {r} must be > 0")));
            }
        }
        let file_box = raw.size.take();
        let (size, periodic, box_source) = match (hint, file_box) {
            (Some(h), _) => {
                if h.size.len() != raw.dim {
                    return Err(self.err(
                        1,
                        format!(
                            "the particles are {}D but the box given has {} extents",
                            raw.dim,
                            h.size.len()
                        ),
                    ));
                }
                (h.size.clone(), h.periodic, BoxSource::Given)
            }
            (None, Some((s, p))) => (s, p, raw.box_source),
            (None, None) => {
                return Err(self.err(
                    1,
                    format!(
                        "the file has no box; give the box ({})",
                        if raw.dim == 2 { "W,H" } else { "W,D,H" }
                    ),
                ))
            }
        };
        if size.iter().any(|&s| !(s > 0.0 && s.is_finite())) {
            return Err(self.err(1, format!("box extents {size:?} must be finite and > 0")));
        }
        let r_min = raw.radii.iter().copied().fold(Real::INFINITY, Real::min);
        let longest = (raw.radii.iter().chain(&size))
            .chain(raw.pos.iter().flatten())
            .fold(0.0, |m: Real, x| m.max(x.abs()));
        if let Some(why) = crate::config::length_scale_problem(r_min, longest) {
            // The line of the particle out of range: its radius is the
            // shortest length, or its radius or a coordinate the longest (line
            // 1 when the box is).
            let (lo, _) = crate::config::LENGTH_RANGE;
            let culprit = if r_min < lo {
                raw.radii.iter().position(|&r| r == r_min)
            } else {
                (0..raw.radii.len()).find(|&k| {
                    raw.radii[k].abs() == longest || raw.pos[k].iter().any(|x| x.abs() == longest)
                })
            };
            let line = culprit.map_or(1, |k| raw.lines[k]);
            return Err(self.err(line, format!("radii, box and positions: {why}")));
        }
        // As `run` refuses a box narrower than its largest particle: such a bed
        // has no packing fraction (a radius of 1e300 overflowed every volume).
        let narrowest = size.iter().copied().fold(Real::INFINITY, Real::min);
        if let Some(k) = (0..raw.radii.len()).find(|&k| 2.0 * raw.radii[k] > narrowest) {
            return Err(self.err(
                raw.lines[k],
                format!(
                    "radius {:?} is larger than the box: its diameter exceeds the box extent \
                     {narrowest:?}",
                    raw.radii[k]
                ),
            ));
        }
        for p in raw.pos.iter_mut() {
            for k in 0..3 {
                p[k] -= raw.origin[k];
            }
        }
        let wrapped = self.check_inside(&mut raw, &size, periodic, box_source)?;
        self.check_crowding(&raw)?;
        densify_species(&mut raw);
        let bed = match raw.dim {
            2 => AnyBed::D2(build::<2>(&raw, &size, periodic)),
            _ => AnyBed::D3(build::<3>(&raw, &size, periodic)),
        };
        Ok((
            bed,
            ReadReport {
                box_source,
                wrapped,
            },
        ))
    }

    /// Refuses particles sticking out of the box by more than [`OUTSIDE_TOL`] of
    /// their radius, through the floor, a side wall or (for a walled box given
    /// by the caller) the roof; wraps centres into `[0, W)` along periodic axes
    /// and returns how many it moved.
    ///
    /// The height of a box read from a file is not taken as a roof: packbed's
    /// own beds filled by count rise above their roof (the roof is ignored
    /// there, and the analysis takes the box up to the highest top), and so do
    /// their exports. A box the user gives is a statement about the bed.
    fn check_inside(
        &self,
        raw: &mut Raw,
        size: &[Real],
        periodic: bool,
        source: BoxSource,
    ) -> Result<u64> {
        let d = raw.dim;
        let v = d - 1;
        let roof = !periodic && source == BoxSource::Given;
        let mut wrapped = 0u64;
        let mut outside = 0u64;
        let mut first: Option<(usize, String)> = None;
        const AXES: [&str; 3] = ["x", "y", "z"];
        for k in 0..raw.pos.len() {
            let r = raw.radii[k];
            let tol = OUTSIDE_TOL * r;
            let p = &mut raw.pos[k];
            let mut out: Option<(&str, Real)> = None;
            for a in 0..v {
                let w = size[a];
                if periodic {
                    if !(0.0..w).contains(&p[a]) {
                        let mut x = p[a].rem_euclid(w);
                        // A tiny negative centre rounds to w itself.
                        if x >= w {
                            x = 0.0;
                        }
                        p[a] = x;
                        wrapped += 1;
                    }
                } else if p[a] - r < -tol {
                    out = out.or(Some((["wall x0", "wall y0"][a], r - p[a])));
                } else if p[a] + r > w + tol {
                    out = out.or(Some((["wall x1", "wall y1"][a], p[a] + r - w)));
                }
            }
            if p[v] - r < -tol {
                out = out.or(Some(("floor", r - p[v])));
            } else if roof && p[v] + r > size[v] + tol {
                out = out.or(Some(("roof", p[v] + r - size[v])));
            }
            if let Some((wall, by)) = out {
                outside += 1;
                if first.is_none() {
                    let at: Vec<String> = (0..d).map(|a| format!("{} {}", AXES[a], p[a])).collect();
                    first = Some((
                        raw.lines[k],
                        format!(
                            "the first ({}, r {r}) through the {wall} by {:.3} of its radius",
                            at.join(", "),
                            by / r
                        ),
                    ));
                }
            }
        }
        if let Some((line, what)) = first {
            let extents: Vec<String> = size.iter().map(|x| x.to_string()).collect();
            return Err(self.err(
                line,
                format!(
                    "{outside} particle{} stick{} out of the {} box {} (from the {}) by more \
                     than {} % of the radius; {what}",
                    if outside == 1 { "" } else { "s" },
                    if outside == 1 { "s" } else { "" },
                    if periodic { "periodic" } else { "walled" },
                    extents.join(" x "),
                    source.name(),
                    OUTSIDE_TOL * 100.0,
                ),
            ));
        }
        Ok(wrapped)
    }

    /// Refuses a file whose particles sit far more densely than any packing can:
    /// thousands of copies of one particle, say, from a broken export. Each
    /// contact would be listed and every measure would crawl through a graph of
    /// n² links (20,000 copies took minutes and gigabytes before being
    /// stopped). Balls of radius at least `r_min` whose centres lie in a cube of
    /// side `w` fit in the cube grown by `r_min` on every side, so at most
    /// `(w + 2 r_min)^d / V(r_min)` of them fit without overlapping; a cube
    /// holding `CROWDING` times that many is refused. That leaves room for soft
    /// particles overlapping a lot and for the overlapping beads of rods.
    fn check_crowding(&self, raw: &Raw) -> Result<()> {
        const CROWDING: Real = 64.0;
        let d = raw.dim;
        let r_min = raw.radii.iter().copied().fold(Real::INFINITY, Real::min);
        let r_max = raw.radii.iter().copied().fold(0.0, Real::max);
        let w = 2.0 * r_max;
        let ball = if d == 2 {
            crate::math::ball_volume::<2>(r_min)
        } else {
            crate::math::ball_volume::<3>(r_min)
        };
        let fit = (w + 2.0 * r_min).powi(d as i32) / ball;
        let cap = (CROWDING * fit).ceil();
        if !(cap.is_finite() && (raw.pos.len() as Real) > cap) {
            return Ok(());
        }
        // Bodies per cell of side `w`, counted by sorting. Bodies, not beads:
        // the beads of one rod overlap by design (spacing below 2 radii), but
        // each body holds a ball of radius `r_min` of its own.
        let mut cells: Vec<([i64; 3], u32, usize)> = raw
            .pos
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let cell = std::array::from_fn(|a| (p[a] / w).floor() as i64);
                (cell, raw.bodies[k], k)
            })
            .collect();
        cells.sort_unstable();
        // A straight chain with beads overlapping at most MAX_OWN_OVERLAPS of
        // their own on each side puts about 3.5 times that many beads of radius
        // `r_min` along a cube's diagonal; more means the analysis would visit
        // billions of pairs of one body's beads.
        let own_cap = 4.0 * crate::config::MAX_OWN_OVERLAPS as Real * r_max / r_min;
        for run in cells.chunk_by(|a, b| a.0 == b.0 && a.1 == b.1) {
            if run.len() as Real > own_cap {
                let first = run.iter().map(|c| c.2).min().unwrap_or(0);
                return Err(self.err(
                    raw.lines[first],
                    format!(
                        "{} beads of body {} have their centres within one cube of side {w} \
                         (twice the largest radius), more than {own_cap:.0}: a bead may overlap \
                         at most {} beads of its own body on each side",
                        run.len(),
                        run[0].1,
                        crate::config::MAX_OWN_OVERLAPS
                    ),
                ));
            }
        }
        for run in cells.chunk_by(|a, b| a.0 == b.0) {
            let bodies = 1 + run.windows(2).filter(|p| p[0].1 != p[1].1).count();
            if bodies as Real > cap {
                let first = run.iter().map(|c| c.2).min().unwrap_or(0);
                return Err(self.err(
                    raw.lines[first],
                    format!(
                        "{bodies} particles (bodies) have their centres within one cube of side \
                         {w} (twice the largest radius), far more than fit there without \
                         overlapping (about {:.0}): duplicated or mis-scaled particles? This is \
                         not a packed bed",
                        fit
                    ),
                ));
            }
        }
        Ok(())
    }
}
