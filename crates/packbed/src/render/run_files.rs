//! The pictures and plots of one run, as named byte buffers for the run's
//! atomic staging (see [`crate::output::write_run_with`]).

use super::run_plots;
use super::{default_color, png_of, svg_of, RenderOptions};
use crate::analysis::orientation::AngleFrom;
use crate::analysis::psd::PsdSummary;
use crate::analysis::{coordination, Contacts, Summary};
use crate::bed::Bed;
use crate::config::LengthUnit;
use crate::error::Result;
use crate::math::Real;

/// `(file name, contents)` of the pictures drawn, in writing order, and a
/// warning for each left out.
pub type Pictures = (Vec<(String, Vec<u8>)>, Vec<String>);

/// Keeps the picture `name` if `made` is one, else says it is missing: a
/// picture never costs the run its bed and measures.
fn keep(out: &mut Pictures, name: String, made: Result<Vec<u8>>) {
    match made {
        Ok(bytes) => out.0.push((name, bytes)),
        Err(e) => out.1.push(crate::error::picture_not_written(&name, &e)),
    }
}

/// Size of plot images in pixels.
pub const PLOT_SIZE: (u32, u32) = (1000, 700);

/// `(file name, contents)` of the picture of the bed and the plots of a run,
/// in writing order. The packing profile and the regional packing are drawn
/// from the analysis' own results (`measures`; no plot when packing was left
/// out). Axes of lengths name `length_unit` where the run gave one.
pub fn pictures<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    measures: &Summary,
    contact_tol: Real,
    angle_from: AngleFrom,
    length_unit: Option<LengthUnit>,
) -> Result<Pictures> {
    let mut out = Pictures::default();
    let z = coordination(bed, contacts);
    {
        let opts = RenderOptions {
            contact_tol,
            color: default_color(bed),
            length_unit,
            ..RenderOptions::default()
        };
        keep(&mut out, "bed.png".to_string(), png_of(bed, &opts));
        if D == 2 {
            keep(
                &mut out,
                "bed.svg".to_string(),
                svg_of(bed, &opts).map(String::into_bytes),
            );
        }
        let mut plots = vec![(
            "plot_coordination",
            run_plots::coordination_histogram(bed, &z),
        )];
        if let Some(packing) = &measures.packing {
            // The summary's slabs: a quarter of the largest diameter.
            let p = &packing.profile;
            let slabs: Vec<(Real, Real)> =
                p.z.iter()
                    .copied()
                    .zip(p.fraction.iter().copied())
                    .collect();
            if !slabs.is_empty() {
                plots.push((
                    "plot_profile",
                    run_plots::packing_profile(&slabs, p.slab, None, length_unit),
                ));
            }
            // Regional packing (floor, roof, wall, centre) as bars; regions the
            // box does not have (walls with periodic sides) are left out.
            let r = &packing.regions;
            let bars: Vec<(String, Real, Option<Real>)> = [
                ("floor", r.floor),
                ("roof", r.roof),
                ("wall", r.wall),
                ("centre", r.centre),
            ]
            .into_iter()
            .filter_map(|(name, v)| v.map(|v| (name.to_string(), v, None)))
            .collect();
            if !bars.is_empty() {
                plots.push(("plot_regions", run_plots::regional_packing(&bars)));
            }
        }
        if let Some(t) = &measures.pore_tables {
            let body: Vec<Real> = t
                .pores
                .iter()
                // As `pores.body_radius`: the pores with a tangent sphere.
                .filter(|p| p.in_slab && p.body_radius > 0.0)
                .map(|p| p.body_radius)
                .collect();
            let constriction: Vec<Real> = t
                .throats
                .iter()
                .filter(|th| {
                    t.pores[th.pores[0] as usize].in_slab && t.pores[th.pores[1] as usize].in_slab
                })
                .map(|th| th.constriction_radius)
                .collect();
            if !body.is_empty() {
                plots.push((
                    "plot_pores",
                    run_plots::pore_sizes(&body, &constriction, length_unit),
                ));
            }
        }
        if let Some(d) = measures.liquid.as_ref().filter(|d| !d.curve.is_empty()) {
            plots.push(("plot_drainage", run_plots::drainage_curve(d)));
        }
        let angles = run_plots::chain_angles(bed);
        if !angles.is_empty() {
            plots.push((
                "plot_chain_angles",
                run_plots::chain_angle_histogram(&angles, D, angle_from),
            ));
        }
        for (name, plot) in plots {
            keep(
                &mut out,
                format!("{name}.png"),
                plot.to_png(PLOT_SIZE.0, PLOT_SIZE.1),
            );
            keep(
                &mut out,
                format!("{name}.svg"),
                plot.to_svg(PLOT_SIZE.0, PLOT_SIZE.1)
                    .map(String::into_bytes),
            );
        }
    }
    Ok(out)
}

/// Adds `plot_psd.png` and `.svg` to `out`: cumulative mass passing against size, the
/// requested curve and the placed one.
pub fn psd_plot(out: &mut Pictures, psd: &PsdSummary, unit: Option<&str>) {
    let plot = run_plots::size_distribution(psd, unit);
    keep(
        out,
        "plot_psd.png".into(),
        plot.to_png(PLOT_SIZE.0, PLOT_SIZE.1),
    );
    keep(
        out,
        "plot_psd.svg".into(),
        plot.to_svg(PLOT_SIZE.0, PLOT_SIZE.1)
            .map(String::into_bytes),
    );
}
