//! `packbed render PATH`: draw a bed file.

use crate::overrides::{numbers, Numbers};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use packbed::analysis::find_contacts;
use packbed::bed::AnyBed;
use packbed::io::read::{read_bed, BoxHint};
use packbed::render::{self, ColorBy, Cut, RenderOptions, View};
use std::path::{Path, PathBuf};

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
    /// The bed file: particles.csv, plain `x y [z] r` table, LAMMPS dump, XYZ, bed.vtu.
    pub path: PathBuf,
    /// Output picture, .png (2D and 3D) or .svg (2D); default: beside PATH as .png.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
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
    /// Box for files without one: W,H (2D) or W,D,H (3D).
    #[arg(long = "box", value_name = "BOX", value_parser = numbers)]
    pub box_size: Option<Numbers>,
    /// The box given with --box has periodic sides.
    #[arg(long)]
    pub periodic: bool,
    /// Contact tolerance relative to the smaller radius, 0 to 1 (coordination, network, chains, force).
    #[arg(long, default_value_t = 1e-6)]
    pub contact_tol: f64,
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
    let out = match &args.out {
        Some(o) => o.clone(),
        None => args.path.with_extension("png"),
    };
    let svg = match out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
    {
        Some(e) if e == "svg" => true,
        Some(e) if e == "png" => false,
        _ => bail!(
            "--out {}: the picture must end in .png or .svg",
            out.display()
        ),
    };
    if let Some(why) = packbed::config::contact_tol_problem(args.contact_tol, "--contact-tol") {
        bail!("{why}");
    }
    if out == args.path {
        bail!("--out {}: would overwrite the bed file", out.display());
    }
    let out_dir = out.parent().filter(|p| !p.as_os_str().is_empty());
    packbed::output::check_out_dir(out_dir.unwrap_or(Path::new(".")))
        .with_context(|| format!("--out {}", out.display()))?;
    let hint = args.box_size.as_ref().map(|size| BoxHint {
        size: size.clone(),
        periodic: args.periodic,
    });
    let mut opts = RenderOptions {
        width: args.width,
        height: args.height,
        network: args.network || args.color == Color::Contacts,
        contact_tol: args.contact_tol,
        outlines: !args.no_outlines,
        view: args.view.unwrap_or_default(),
        cut: args.cut.unwrap_or(Cut::None),
        supersample: args.supersample,
        title: args.title.clone(),
        ..RenderOptions::default()
    };
    opts.check()?;
    let bed = read_bed(&args.path, hint.as_ref())?;
    // A 2D picture has no viewing direction and nothing in front to cut
    // away: taking the options silently would hide a mistaken file.
    let given: Vec<&str> = [
        ("--view", args.view.is_some()),
        ("--cut", args.cut.is_some()),
    ]
    .into_iter()
    .filter_map(|(o, g)| g.then_some(o))
    .collect();
    if bed.dim() == 2 && !given.is_empty() {
        let path = args.path.display();
        bail!(
            "{}: {path} is a 2D bed (views and cut-aways are for 3D beds)",
            given.join(" and ")
        );
    }
    opts.color = match args.color {
        Color::Species => ColorBy::Species,
        Color::Contacts | Color::Coordination => ColorBy::Coordination,
        Color::Height => ColorBy::Height,
        Color::Radius => ColorBy::Radius,
        Color::Force => ColorBy::Force,
        Color::Chains => ColorBy::Classes(match &bed {
            AnyBed::D2(b) => chains(b, &args)?,
            AnyBed::D3(b) => chains(b, &args)?,
        }),
    };
    let bytes = if svg {
        render::render_svg(&bed, &opts)?.into_bytes()
    } else {
        render::render_png(&bed, &opts)?
    };
    packbed::output::write_file(&out, &bytes)
        .with_context(|| format!("--out {}", out.display()))?;
    Ok(())
}

fn chains<const D: usize>(
    bed: &packbed::bed::Bed<D>,
    args: &RenderArgs,
) -> Result<render::Classes> {
    let contacts = find_contacts(bed, args.contact_tol);
    // The analysis' own rule, so that the picture and summary.json agree.
    let large = args.large.map_or(
        packbed::analysis::LargeRule::Median,
        packbed::analysis::LargeRule::Radius,
    );
    Ok(render::chain_classes(bed, &contacts, large))
}
