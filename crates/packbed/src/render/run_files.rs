//! The pictures and plots of one run, as named byte buffers for the run's
//! atomic staging (see [`crate::output::write_run_with`]).

use super::run_plots;
use super::{png_of, svg_of, RenderOptions};
use crate::analysis::orientation::AngleFrom;
use crate::analysis::{coordination, profile, Contacts};
use crate::bed::Bed;
use crate::error::Result;
use crate::math::Real;

/// Size of plot images in pixels.
pub const PLOT_SIZE: (u32, u32) = (1000, 700);

/// `(file name, contents)` of the picture of the bed and the plots of a run,
/// in writing order.
pub fn pictures<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    contact_tol: Real,
    angle_from: AngleFrom,
) -> Result<Vec<(String, Vec<u8>)>> {
    let mut out = Vec::new();
    let z = coordination(bed, contacts);
    {
        let opts = RenderOptions {
            contact_tol,
            ..RenderOptions::default()
        };
        out.push(("bed.png".to_string(), png_of(bed, &opts)?));
        if D == 2 {
            out.push(("bed.svg".to_string(), svg_of(bed, &opts)?.into_bytes()));
        }
        let mut plots = vec![(
            "plot_coordination",
            run_plots::coordination_histogram(bed, &z),
        )];
        // The spec's slabs: a quarter of the largest diameter.
        let slab = bed.r_max() / 2.0;
        let slabs = profile::profile(bed, slab);
        if !slabs.is_empty() {
            plots.push((
                "plot_profile",
                run_plots::packing_profile(&slabs, slab, None),
            ));
        }
        // Regional packing (floor, roof, wall, centre) as bars; regions the box
        // does not have (walls with periodic sides) are left out.
        let regional = crate::analysis::regions::regional_packing(bed);
        let bars: Vec<(String, Real, Option<Real>)> = [
            ("floor", regional.floor),
            ("roof", regional.roof),
            ("wall", regional.wall),
            ("centre", regional.centre),
        ]
        .into_iter()
        .filter_map(|(name, v)| v.map(|v| (name.to_string(), v, None)))
        .collect();
        if !bars.is_empty() {
            plots.push(("plot_regions", run_plots::regional_packing(&bars)));
        }
        let angles = run_plots::chain_angles(bed);
        if !angles.is_empty() {
            plots.push((
                "plot_chain_angles",
                run_plots::chain_angle_histogram(&angles, D, angle_from),
            ));
        }
        for (name, plot) in plots {
            out.push((
                format!("{name}.png"),
                plot.to_png(PLOT_SIZE.0, PLOT_SIZE.1)?,
            ));
            out.push((
                format!("{name}.svg"),
                plot.to_svg(PLOT_SIZE.0, PLOT_SIZE.1)?.into_bytes(),
            ));
        }
    }
    Ok(out)
}
