//! The statistics files and plots of one point, and a sweep's comparison.

use super::stats;
use super::{reports, Point, PointResult, Shard, ENSEMBLE_FILES, SWEEP_FILES};
use crate::config::Config;
use crate::error::Result;
use crate::io::Staging;
#[cfg(feature = "render")]
use crate::render::ensemble_plots as plots;
#[cfg(feature = "render")]
use rayon::prelude::*;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Stages every plot as `stem.png` and `stem.svg`; a plot that cannot be
/// drawn is left out and named in `warnings`, so that no rerun of the
/// ensemble fails on it again.
#[cfg(feature = "render")]
pub(super) fn stage_plots(
    s: &mut Staging,
    plots: &[(String, crate::render::plot::Plot)],
    warnings: &mut Vec<String>,
) -> Result<()> {
    use crate::render::run_files::PLOT_SIZE;
    // Rasterising is most of the cost; the files are written in order after.
    let made: Vec<(String, Result<Vec<u8>>)> = plots
        .par_iter()
        .flat_map_iter(|(stem, plot)| {
            [
                (format!("{stem}.png"), plot.to_png(PLOT_SIZE.0, PLOT_SIZE.1)),
                (
                    format!("{stem}.svg"),
                    plot.to_svg(PLOT_SIZE.0, PLOT_SIZE.1)
                        .map(String::into_bytes),
                ),
            ]
        })
        .collect();
    let mut drawn = crate::output::Drawn::default();
    for (name, bytes) in made {
        drawn.keep(name, bytes);
    }
    warnings.extend(drawn.missing);
    // A plot the disk has no room for is named, never the loss of the tables.
    crate::output::stage_pictures(s, &drawn.files, warnings);
    Ok(())
}

/// Writes the statistics files of one point into `dir`; returns its result.
#[allow(clippy::too_many_arguments)]
// Without pictures there is no plot to warn about.
#[cfg_attr(not(feature = "render"), allow(unused_variables, clippy::ptr_arg))]
pub(super) fn write_point(
    p: &Point,
    dir: PathBuf,
    runs: u64,
    shard: Shard,
    values: &[Value],
    (built, resumed): (u64, u64),
    wall: f64,
    pictures: bool,
    warnings: &mut Vec<String>,
) -> Result<PointResult> {
    let aggregate = stats::measures_of(values)?;
    let timing = stats::timings_of(values)?;
    let header = reports::Header {
        config: &p.config,
        runs,
        shard: shard.as_pair(),
        sweep: p
            .sweep
            .as_ref()
            .map(|(a, b, c)| (a.as_str(), b.as_str(), c.clone())),
    };
    let mut timing_json = json!({
        "note": "wall times: they depend on the machine and its load, so they are kept out of the ensemble statistics",
        "invocation_wall_seconds": wall,
        "replicates_built": built,
        "replicates_resumed": resumed,
    });
    let t = &mut timing_json;
    for m in &timing.measures {
        t[m.name.as_str()] = json!({
            "n": m.stats.n, "mean": m.stats.mean, "sd": m.stats.sd,
            "min": m.stats.min, "max": m.stats.max,
        });
    }
    let texts = [
        reports::ensemble_json(&header, &aggregate),
        reports::ensemble_csv(&aggregate),
        reports::histograms_csv(&aggregate),
        reports::ensemble_md(&header, &aggregate),
        format!(
            "{}\n",
            serde_json::to_string_pretty(&timing_json).unwrap_or_default()
        ),
    ];
    let mut s = Staging::new(&dir)?;
    for (name, text) in ENSEMBLE_FILES.iter().zip(&texts) {
        s.stage(name, |w| w.write_all(text.as_bytes()))?;
    }
    if pictures {
        #[cfg(feature = "render")]
        stage_plots(
            &mut s,
            &plots::ensemble_plots(
                &aggregate,
                p.config.dim as usize,
                p.config.analysis.chain_angle_from,
                p.config.analysis.length_unit,
            ),
            warnings,
        )?;
        #[cfg(not(feature = "render"))]
        return Err(crate::output::no_pictures());
    }
    let files = s.commit()?;
    Ok(PointResult {
        label: p.label.clone(),
        dir,
        percolation_asked: p.asks_for_percolation(),
        aggregate,
        built,
        resumed,
        files,
    })
}

/// Writes a sweep's comparison into `out` (or, without a sweep, lists the files
/// of the one point); returns the files.
// Without pictures there is no plot to warn about.
#[cfg_attr(not(feature = "render"), allow(unused_variables, clippy::ptr_arg))]
pub(super) fn write_sweep(
    config: &Config,
    out: &Path,
    points: &[PointResult],
    pictures: bool,
    warnings: &mut Vec<String>,
) -> Result<Vec<PathBuf>> {
    let Some(sw) = &config.sweep else {
        return Ok(points.iter().flat_map(|p| p.files.clone()).collect());
    };
    let rows: Vec<reports::SweepRow> = points
        .iter()
        .map(|p| reports::SweepRow {
            label: p.label.as_deref().unwrap_or(""),
            aggregate: &p.aggregate,
        })
        .collect();
    let mut base = config.clone();
    base.sweep = None;
    let texts = [
        reports::sweep_csv(&rows),
        reports::sweep_md(&sw.parameter, &base, &rows),
    ];
    let mut s = Staging::new(out)?;
    for (name, text) in SWEEP_FILES.iter().zip(&texts) {
        s.stage(name, |w| w.write_all(text.as_bytes()))?;
    }
    if pictures {
        #[cfg(feature = "render")]
        {
            let labelled: Vec<(&str, &stats::Aggregate)> = points
                .iter()
                .map(|p| (p.label.as_deref().unwrap_or(""), &p.aggregate))
                .collect();
            stage_plots(&mut s, &plots::sweep_plots(sw, &labelled), warnings)?;
        }
        #[cfg(not(feature = "render"))]
        return Err(crate::output::no_pictures());
    }
    s.commit()
}
