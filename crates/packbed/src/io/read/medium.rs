//! The bed file of a filter medium (`[[feeds]]` with `file = ...`), read
//! when a run is planned: with the box of the config as the box hint, in
//! the config's dimension, inside the box, its particles apart from each
//! other as the engine keeps them; then handed to the plan
//! ([`Plan::lay_medium_file`]), which makes its species and checks the room
//! above it.

use super::report::BoxHint;
use crate::analysis::filtration::medium_is_open;
use crate::analysis::pores::FlowOptions;
use crate::analysis::validate::{check_bed_with, InvariantChecks, Violation};
use crate::bed::Bed;
use crate::config::{AnyPlan, Plan};
use crate::error::{Error, Result};
use crate::math::{Real, Vector};
use std::path::Path;

/// How far particles of a medium file may overlap each other or stick out
/// of the box, relative to the (smaller) radius: the model's exactness
/// (`docs/reference/model.md`, "Exactness"), which every bed it builds keeps.
pub const MEDIUM_FILE_TOL: Real = 1e-9;

/// Reads the bed files of the media of `plan` not read yet. With `flow`
/// (a filtration's), each must let fluid through on its pore network.
pub(crate) fn read_media(plan: &mut AnyPlan, flow: Option<&FlowOptions>) -> Result<()> {
    match plan {
        AnyPlan::D2(p) => read_media_of(p, flow),
        AnyPlan::D3(p) => read_media_of(p, flow),
    }
}

/// True when `plan` has a medium file not read yet.
pub(crate) fn unread(plan: &AnyPlan) -> bool {
    let feeds = match plan {
        AnyPlan::D2(p) => &p.feeds,
        AnyPlan::D3(p) => &p.feeds,
    };
    feeds
        .iter()
        .any(|f| f.file.as_ref().is_some_and(|f| f.beads.is_none()))
}

fn read_media_of<const D: usize>(plan: &mut Plan<D>, flow: Option<&FlowOptions>) -> Result<()> {
    for k in 0..plan.feeds.len() {
        let Some(file) = &plan.feeds[k].file else {
            continue;
        };
        if file.beads.is_some() {
            continue;
        }
        let path = file.path.clone();
        let what = format!("feeds[{k}].file");
        let bed = read_in_box(&path, plan, &what)?;
        check_apart(&bed, &path, &what)?;
        if let Some(flow) = flow {
            check_open(&bed, flow, &path, &what)?;
        }
        let centres: Vec<[Real; 3]> = bed
            .centres
            .iter()
            .map(|c| std::array::from_fn(|a| if a < D { c[a] } else { 0.0 }))
            .collect();
        plan.lay_medium_file(k, &centres, &bed.radii, &bed.species, &bed.bodies)?;
    }
    Ok(())
}

/// The bed of `path` in the box of `plan`: refused (one line, naming the
/// feed `what`) when it is no bed, of another dimension, or outside the box.
fn read_in_box<const D: usize>(path: &Path, plan: &Plan<D>, what: &str) -> Result<Bed<D>> {
    let c = plan.container;
    let size: Vec<Real> = c.size.0.to_vec();
    let hint = BoxHint {
        size: size.clone(),
        periodic: c.periodic,
    };
    let (bed, report) = match super::read_bed_report(path, Some(&hint)) {
        Ok(read) => read,
        Err(e) => {
            // Read in the other dimension, the file is a bed: say so.
            let other = if D == 3 {
                vec![size[0], size[2]]
            } else {
                vec![size[0], size[0], size[1]]
            };
            let hint = BoxHint {
                size: other,
                periodic: c.periodic,
            };
            if let Ok((bed, _)) = super::read_bed_report(path, Some(&hint)) {
                return Err(Error::config(format!(
                    "{what}: {} is a {}D bed, but the config's dim is {D}: a medium is read in the bed's own dimension",
                    path.display(),
                    bed.dim()
                )));
            }
            return Err(Error::config(format!("{what}: {}", one_line(&e))));
        }
    };
    if report.wrapped > 0 {
        let sides = if D == 3 {
            format!("0 ≤ x < {}, 0 ≤ y < {}", size[0], size[1])
        } else {
            format!("0 ≤ x < {}", size[0])
        };
        return Err(Error::config(format!(
            "{what}: {}: {} centre coordinates lie outside the periodic cell of the box ({sides}): a medium is placed as read, so give its centres inside the cell",
            path.display(),
            report.wrapped
        )));
    }
    let mut out = Bed::new(c, bed.species_info().to_vec());
    let positions = bed.positions();
    for i in 0..bed.len() {
        let mut p = Vector::<D>::zero();
        for a in 0..D {
            p[a] = positions[i * D + a];
        }
        out.push_bead(p, bed.radii()[i], bed.species()[i], bed.bodies()[i]);
    }
    Ok(out)
}

/// Refuses a medium whose particles overlap each other (of different
/// bodies) or stick out of the box by more than [`MEDIUM_FILE_TOL`] of a
/// radius: the engine never builds a bed that breaks its invariants.
fn check_apart<const D: usize>(bed: &Bed<D>, path: &Path, what: &str) -> Result<()> {
    let checks = InvariantChecks {
        rest: false,
        ..InvariantChecks::new(MEDIUM_FILE_TOL)
    };
    let report = check_bed_with(bed, &checks);
    let path = path.display();
    if report.overlaps > 0 {
        let (i, j) = report
            .examples
            .iter()
            .find_map(|v| match v {
                Violation::Overlap { i, j, .. } => Some((*i, *j)),
                _ => None,
            })
            .unwrap_or((0, 0));
        return Err(Error::config(format!(
            "{what}: {path}: {} of particles of different bodies overlap by more than {MEDIUM_FILE_TOL:e} of the smaller radius (at most {:.3e}; the first, ids {} and {}, counting the file's particles from 0): the engine keeps its particles apart, so it builds no bed on an overlapping medium",
            plural(report.overlaps, "pair", "pairs"),
            report.max_overlap,
            i,
            j
        )));
    }
    if report.outside > 0 {
        let (i, wall, by) = report
            .examples
            .iter()
            .find_map(|v| match v {
                Violation::Outside { i, wall, by } => Some((*i, *wall, *by)),
                _ => None,
            })
            .unwrap_or((0, "floor", 0.0));
        return Err(Error::config(format!(
            "{what}: {path}: {} out of the box by more than {MEDIUM_FILE_TOL:e} of the radius (the first, id {} counting the file's particles from 0, through the {wall} by {by:.3e} of its radius): the medium lies inside the box, on its floor",
            plural(report.outside, "particle sticks", "particles stick"),
            i
        )));
    }
    if report.invalid > 0 {
        return Err(Error::config(format!(
            "{what}: {path}: {} particles have a centre or radius that is not a finite positive number",
            report.invalid
        )));
    }
    Ok(())
}

/// Refuses a medium that no fluid passes, from its bottom to its surface on
/// its pore network (`medium_is_open`): a filtration through it has no
/// curve, and a plate of one body's overlapping beads can be such a wall.
fn check_open<const D: usize>(
    bed: &Bed<D>,
    flow: &FlowOptions,
    path: &Path,
    what: &str,
) -> Result<()> {
    let path = path.display();
    match medium_is_open(bed, flow) {
        Ok(true) => Ok(()),
        Ok(false) => Err(Error::config(format!(
            "{what}: {path}: the medium has no opening: its pore network has no open path from its bottom to its surface, so no filtrate passes it and [filtration] has no curve (beads of one body that overlap deeply close the throats between them; give the plate openings, or run without [filtration])"
        ))),
        Err(e) => Err(Error::config(format!(
            "{what}: {path}: the flow through the medium could not be solved: {e}"
        ))),
    }
}

/// `n` and the noun `one` or `many` as `n` asks.
fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// `e` on one line (a reader's error is one already).
fn one_line(e: &Error) -> String {
    e.to_string().replace('\n', " ")
}
