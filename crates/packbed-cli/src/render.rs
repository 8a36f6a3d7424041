//! `packbed render PATH`: draw a bed file.

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use packbed::analysis::find_contacts;
use packbed::bed::AnyBed;
use packbed::io::read::{read_bed, BoxHint};
use packbed::io::Staging;
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
    /// Contact forces (not computed by packbed yet: refused with the reason).
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
    pub view: Option<String>,
    /// 3D cut-away: `half` (back half), or a slab `x:LO:HI`, `y:LO:HI`, `z:LO:HI`.
    #[arg(long, value_name = "CUT")]
    pub cut: Option<String>,
    /// No outlines around particles.
    #[arg(long)]
    pub no_outlines: bool,
    /// Samples per pixel along each axis in 3D (1 to 4).
    #[arg(long, default_value_t = 2)]
    pub supersample: u32,
    /// Box for files without one: W,H (2D) or W,D,H (3D).
    #[arg(long = "box", value_name = "BOX")]
    pub box_size: Option<String>,
    /// The box given with --box has periodic sides.
    #[arg(long)]
    pub periodic: bool,
    /// Contact tolerance relative to the smaller radius (coordination, network, chains).
    #[arg(long, default_value_t = 1e-6)]
    pub contact_tol: f64,
    /// Radius from which particles count as large (chains); default the largest.
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
    if out == args.path {
        bail!("--out {}: would overwrite the bed file", out.display());
    }
    let out_dir = out
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    packbed::io::atomic::probe_dir(out_dir).with_context(|| format!("--out {}", out.display()))?;
    let hint = match &args.box_size {
        Some(b) => Some(BoxHint {
            size: numbers(b, "--box")?,
            periodic: args.periodic,
        }),
        None => None,
    };
    let view = match &args.view {
        Some(text) => {
            let v = numbers(text, "--view")?;
            if v.len() != 2 {
                bail!("--view {text}: give AZIMUTH,ELEVATION in degrees");
            }
            View {
                azimuth: v[0],
                elevation: v[1],
            }
        }
        None => View::default(),
    };
    let mut opts = RenderOptions {
        width: args.width,
        height: args.height,
        network: args.network || args.color == Color::Contacts,
        contact_tol: args.contact_tol,
        outlines: !args.no_outlines,
        view,
        cut: parse_cut(args.cut.as_deref())?,
        supersample: args.supersample,
        title: args.title.clone(),
        ..RenderOptions::default()
    };
    opts.check()?;
    let bed = read_bed(&args.path, hint.as_ref())?;
    if let AnyBed::D2(_) = &bed {
        // A 2D picture has no viewing direction and nothing in front to cut
        // away: taking the options silently would hide a mistaken file.
        let given: Vec<&str> = [
            ("--view", args.view.is_some()),
            ("--cut", args.cut.is_some()),
        ]
        .iter()
        .filter_map(|&(o, g)| g.then_some(o))
        .collect();
        if !given.is_empty() {
            bail!(
                "{} {}: {} is a 2D bed (views and cut-aways are for 3D beds)",
                given.join(" and "),
                if given.len() == 1 {
                    "applies only in 3D"
                } else {
                    "apply only in 3D"
                },
                args.path.display()
            );
        }
    }
    opts.color = match args.color {
        Color::Species => ColorBy::Species,
        Color::Contacts | Color::Coordination => ColorBy::Coordination,
        Color::Height => ColorBy::Height,
        Color::Force => bail!(
            "--color force: packbed does not compute contact forces yet (use species, contacts, coordination, chains or height)"
        ),
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
    write_atomically(&out, &bytes)?;
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

/// `1,2,3` → numbers, naming the option on failure.
fn numbers(text: &str, option: &str) -> Result<Vec<f64>> {
    text.split(',')
        .map(|s| {
            let v: f64 = s
                .trim()
                .parse()
                .with_context(|| format!("{option} {text}: \"{}\" is not a number", s.trim()))?;
            if !v.is_finite() {
                bail!("{option} {text}: {v} is not a finite number");
            }
            Ok(v)
        })
        .collect()
}

/// `half`, `x:LO:HI`, `y:LO:HI`, `z:LO:HI`.
fn parse_cut(text: Option<&str>) -> Result<Cut> {
    let Some(t) = text else { return Ok(Cut::None) };
    if t == "half" {
        return Ok(Cut::Half);
    }
    let parts: Vec<&str> = t.split(':').collect();
    let axis = match parts.first().copied() {
        Some("x") => 0,
        Some("y") => 1,
        Some("z") => 2,
        _ => bail!("--cut {t}: give half, or x:LO:HI, y:LO:HI, z:LO:HI"),
    };
    if parts.len() != 3 {
        bail!("--cut {t}: give half, or x:LO:HI, y:LO:HI, z:LO:HI");
    }
    let lo = numbers(parts[1], "--cut")?[0];
    let hi = numbers(parts[2], "--cut")?[0];
    // `lo < hi` is false for NaN too, which is refused with the same message.
    if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
        bail!("--cut {t}: LO must be below HI");
    }
    Ok(Cut::Slab { axis, lo, hi })
}

/// Writes a single file through a temporary file and a rename.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .with_context(|| format!("--out {}: not a file name", path.display()))?;
    let mut s = Staging::new(dir)?;
    s.stage(name, |w| w.write_all(bytes))?;
    s.commit()?;
    Ok(())
}
