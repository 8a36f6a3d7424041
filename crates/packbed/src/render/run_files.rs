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

/// Particle classes of agglomerate ids (`ids[p]`, 0: none; 1 the largest):
/// the `top` largest agglomerates each a class, the rest one class, single
/// particles the grey backdrop.
pub fn agglomerate_classes(ids: &[u32], top: u32) -> super::Classes {
    let mut count = std::collections::BTreeMap::new();
    for &g in ids.iter().filter(|&&g| g > 0) {
        *count.entry(g).or_insert(0u64) += 1;
    }
    let shown = (count.len() as u32).min(top);
    let mut labels: Vec<String> = (1..=shown)
        .map(|g| format!("agglomerate {g} ({} particles)", count[&g]))
        .collect();
    let rest = count.len() as u32 > shown;
    if rest {
        labels.push(format!(
            "{} smaller agglomerates",
            count.len() as u32 - shown
        ));
    }
    labels.push("single particles".into());
    let single = labels.len() as u32 - 1;
    let class = ids
        .iter()
        .map(|&g| match g {
            0 => single,
            g if g <= shown => g - 1,
            _ => shown,
        })
        .collect();
    super::Classes {
        labels,
        class,
        backdrop: Some(single),
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
        // The agglomerates the dried cake's bonds join, before and after
        // its agitation.
        if let Some(d) = &measures.dried {
            let mut shown = vec![("agglomerates", d.agglomerate_of.clone(), "agglomerates")];
            if d.summary.agitation.is_some() {
                let mut after = vec![0u32; bed.len()];
                for b in d.bridges.iter().filter(|b| b.agglomerate_after > 0) {
                    for p in b.particles {
                        after[p as usize] = b.agglomerate_after;
                    }
                }
                shown.push((
                    "agglomerates_agitated",
                    after,
                    "agglomerates after agitation",
                ));
            }
            for (name, ids, title) in shown {
                let opts = RenderOptions {
                    color: super::ColorBy::Classes(agglomerate_classes(&ids, 5)),
                    title: Some(title.to_string()),
                    ..opts.clone()
                };
                keep(&mut out, format!("{name}.png"), png_of(bed, &opts));
                if D == 2 {
                    keep(
                        &mut out,
                        format!("{name}.svg"),
                        svg_of(bed, &opts).map(String::into_bytes),
                    );
                }
            }
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

/// Adds `plot_grade_efficiency` and `plot_filtration` (`.png`, `.svg`) to
/// `out` for a bed built with a medium and filtered.
pub fn filtration_plots(
    out: &mut Pictures,
    capture: Option<&crate::analysis::capture::CaptureSummary>,
    filtration: Option<&crate::analysis::filtration::FiltrationSummary>,
    unit: Option<&str>,
) {
    let mut plots = Vec::new();
    if let Some(c) = capture.filter(|c| c.fed > 0) {
        plots.push((
            "plot_grade_efficiency",
            run_plots::grade_efficiency(c, unit),
        ));
    }
    if let Some(f) = filtration {
        plots.push(("plot_filtration", run_plots::filtration_curve(f)));
    }
    for (name, plot) in plots {
        keep(
            out,
            format!("{name}.png"),
            plot.to_png(PLOT_SIZE.0, PLOT_SIZE.1),
        );
        keep(
            out,
            format!("{name}.svg"),
            plot.to_svg(PLOT_SIZE.0, PLOT_SIZE.1)
                .map(String::into_bytes),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::agglomerate_classes;

    #[test]
    fn agglomerate_classes_name_the_largest_and_grey_the_singles() {
        let ids = [0, 1, 1, 2, 3, 3, 3, 0];
        let c = agglomerate_classes(&ids, 2);
        assert_eq!(
            c.labels,
            [
                "agglomerate 1 (2 particles)",
                "agglomerate 2 (1 particles)",
                "1 smaller agglomerates",
                "single particles"
            ]
        );
        assert_eq!(c.class, [3, 0, 0, 1, 2, 2, 2, 3]);
        assert_eq!(c.backdrop, Some(3));
        let none = agglomerate_classes(&[0, 0], 6);
        assert_eq!(none.labels, ["single particles"]);
        assert_eq!(none.class, [0, 0]);
    }
}
