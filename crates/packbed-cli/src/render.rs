//! `packbed render PATH`: draw a bed file.

use crate::bed_file::BedFileArgs;
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use packbed::render::{ColorBy, Cut, RenderOptions, View};
use packbed::LargeRule;
use std::path::Path;

/// What particle colours show.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Color {
    /// One colour per species.
    Species,
    /// Coordination number, with the contact network drawn (2D).
    Contacts,
    /// Coordination number only.
    Coordination,
    /// Large particles in wall-to-wall chains highlighted.
    Chains,
    /// Height of the centre.
    Height,
    /// Radius, on a continuous scale from the smallest to the largest.
    Radius,
    /// Largest contact force on each body under the default shear load.
    Force,
}

/// Arguments of `packbed render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub bed: BedFileArgs,
    /// Output picture, .png (2D and 3D) or .svg (2D); default: beside PATH as .png.
    #[arg(long, value_name = "FILE")]
    pub out: Option<std::path::PathBuf>,
    /// What colours show.
    #[arg(long, value_enum, default_value = "species")]
    pub color: Color,
    /// Draw the contact network (segments between touching centres; 2D).
    #[arg(long)]
    pub network: bool,
    /// Image width in pixels.
    #[arg(long, default_value_t = 1200)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 1000)]
    pub height: u32,
    /// 3D view as AZIMUTH,ELEVATION in degrees (azimuth from the front towards +x);
    /// default -30,30.
    #[arg(long, value_name = "AZ,EL", allow_hyphen_values = true)]
    pub view: Option<View>,
    /// 3D cut-away: `half` (back half), or a slab `x:LO:HI`, `y:LO:HI`, `z:LO:HI`.
    #[arg(long, value_name = "CUT", allow_hyphen_values = true)]
    pub cut: Option<Cut>,
    /// No outlines around particles.
    #[arg(long)]
    pub no_outlines: bool,
    /// Samples per pixel along each axis in 3D (1 to 4).
    #[arg(long, default_value_t = 2)]
    pub supersample: u32,
    /// Radius from which particles count as large (chains); default the largest
    /// of the species' volume-median radii.
    #[arg(long, value_name = "R")]
    pub large: Option<f64>,
    /// Title above the picture.
    #[arg(long)]
    pub title: Option<String>,
}

/// Runs `packbed render`.
pub fn render(args: RenderArgs) -> Result<()> {
    let path = &args.bed.path;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| path.with_extension("png"));
    let on_out = || format!("--out {}", out.display());
    packbed::picture_is_svg(&out).with_context(on_out)?;
    args.bed.check_contact_tol()?;
    if &out == path {
        bail!("--out {}: would overwrite the bed file", out.display());
    }
    let out_dir = out.parent().filter(|p| !p.as_os_str().is_empty());
    packbed::check_out_dir(out_dir.unwrap_or(Path::new("."))).with_context(on_out)?;
    let opts = RenderOptions {
        width: args.width,
        height: args.height,
        network: args.network || args.color == Color::Contacts,
        contact_tol: args.bed.contact_tol,
        outlines: !args.no_outlines,
        view: args.view.unwrap_or_default(),
        cut: args.cut.unwrap_or(Cut::None),
        supersample: args.supersample,
        title: args.title.clone(),
        color: match args.color {
            Color::Species | Color::Chains => ColorBy::Species,
            Color::Contacts | Color::Coordination => ColorBy::Coordination,
            Color::Height => ColorBy::Height,
            Color::Radius => ColorBy::Radius,
            Color::Force => ColorBy::Force,
        },
        ..RenderOptions::default()
    };
    let given_3d = [
        ("--view", args.view.is_some()),
        ("--cut", args.cut.is_some()),
    ];
    let given_3d: Vec<&str> = given_3d
        .iter()
        .filter_map(|&(o, g)| g.then_some(o))
        .collect();
    // The analysis' own rule for large particles, so that the picture and
    // summary.json agree.
    let chains = (args.color == Color::Chains)
        .then(|| args.large.map_or(LargeRule::Median, LargeRule::Radius));
    opts.check()?;
    let hint = args.bed.hint()?;
    Ok(packbed::render_file(
        path,
        hint.as_ref(),
        &out,
        &opts,
        &given_3d,
        chains,
    )?)
}
