//! Pictures of beds and plots of measures.
//!
//! - [`canvas`]: one drawing API with an SVG and a PNG (tiny-skia) back end and
//!   embedded text, so both formats show the same picture.
//! - [`bed2d`]: 2D beds, every disc drawn exactly (SVG circles in bed coordinates).
//! - [`bed3d`]: 3D beds, a z-buffered raster of exact sphere surfaces, shaded.
//! - [`frame`]: title, legend and scale bar around a bed picture.
//! - [`plot`]: histograms, profiles, bars with error bars, from plain data.
//! - [`fragmentation`]: bond forces and breakage of a bed under load.
//! - [`colour`]: colour-blind-safe palettes.
//!
//! Colouring takes per-particle classes ([`ColorBy::Classes`]) so that any
//! measure that marks particles (percolation chains, clusters) can be shown.

pub mod bed2d;
pub mod bed3d;
pub mod canvas;
pub mod colour;
pub mod fragmentation;
pub(crate) mod frame;
pub(crate) mod plot;
pub(crate) mod run_files;
pub mod run_plots;

use crate::analysis::percolation::{membership, LargeRule, Membership};
use crate::analysis::{coordination, find_contacts, Contacts};
use crate::bed::{AnyBed, Bed};
use crate::error::{Error, Result};
use canvas::Rgb;

pub use bed3d::{Cut, View};
pub use fragmentation::fragmentation_pictures;

/// Per-particle classes with names, e.g. "in a percolation chain" / "other".
#[derive(Clone, Debug, PartialEq)]
pub struct Classes {
    /// Name of each class (the legend).
    pub labels: Vec<String>,
    /// Class of each particle (index into `labels`).
    pub class: Vec<u32>,
    /// Class drawn in light grey as the backdrop (usually "other"), if any.
    pub backdrop: Option<u32>,
}

/// What the colour of a particle shows.
#[derive(Clone, Debug, PartialEq)]
pub enum ColorBy {
    /// One colour per species.
    Species,
    /// The coordination number (touching bodies), from the contacts.
    Coordination,
    /// The height of the centre.
    Height,
    /// The largest contact force `|f|` among the bonds of the particle's body
    /// under the default load (shear, total 1), from [`crate::mechanics`]
    /// (see [`fragmentation::particle_forces`]).
    Force,
    /// Given classes (percolation chains, clusters, …).
    Classes(Classes),
}

/// How to draw a bed.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// What colours show.
    pub color: ColorBy,
    /// Draw the contact network (segments between touching centres; 2D).
    pub network: bool,
    /// Contact tolerance relative to the smaller radius (coordination, network).
    pub contact_tol: f64,
    /// Outlines around particles.
    pub outlines: bool,
    /// Viewing direction (3D).
    pub view: View,
    /// Part of the bed left out to see inside (3D).
    pub cut: Cut,
    /// Samples per pixel along each axis in 3D (antialiasing); 1 to 4.
    pub supersample: u32,
    /// A title above the picture (a default one describes the bed).
    pub title: Option<String>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 1200,
            height: 1000,
            color: ColorBy::Species,
            network: false,
            contact_tol: 1e-6,
            outlines: true,
            view: View::default(),
            cut: Cut::None,
            supersample: 2,
            title: None,
        }
    }
}

impl RenderOptions {
    /// Refuses sizes that cannot make a useful image (or would exhaust memory).
    pub fn check(&self) -> Result<()> {
        const MAX: u32 = 16_384;
        if self.width < 200 || self.height < 150 || self.width > MAX || self.height > MAX {
            return Err(Error::Impossible(format!(
                "image size {} × {} pixels: width must be 200 to {MAX} and height 150 to {MAX}",
                self.width, self.height
            )));
        }
        if !(1..=4).contains(&self.supersample) {
            return Err(Error::Impossible(format!(
                "supersampling {} must be 1 to 4",
                self.supersample
            )));
        }
        if !(self.contact_tol >= 0.0 && self.contact_tol.is_finite()) {
            return Err(Error::Impossible(format!(
                "contact tolerance {} must be a finite number >= 0",
                self.contact_tol
            )));
        }
        self.view.check()?;
        if let ColorBy::Classes(c) = &self.color {
            if c.labels.is_empty() || c.class.iter().any(|&k| k as usize >= c.labels.len()) {
                return Err(Error::Impossible(
                    "particle classes name a class that has no label".into(),
                ));
            }
        }
        Ok(())
    }
}

/// The PNG picture of a bed (2D: antialiased discs; 3D: shaded spheres).
pub fn render_png(bed: &AnyBed, opts: &RenderOptions) -> Result<Vec<u8>> {
    crate::bed::each_dim!(bed, b => png_of(b, opts))
}

/// The SVG picture of a 2D bed (one `<circle class="particle">` per disc, in bed
/// coordinates). 3D beds have no SVG picture (an error says so).
pub fn render_svg(bed: &AnyBed, opts: &RenderOptions) -> Result<String> {
    crate::bed::each_dim!(bed, b => svg_of(b, opts))
}

/// [`render_png`] for a bed of either dimension, without wrapping it.
pub fn png_of<const D: usize>(bed: &Bed<D>, opts: &RenderOptions) -> Result<Vec<u8>> {
    opts.check()?;
    match (bed.as_2d(), bed.as_3d()) {
        (Some(b), _) => bed2d::png(b, opts),
        (_, Some(b)) => bed3d::png(b, opts),
        _ => Err(Error::Impossible(format!("{D}D beds cannot be drawn"))),
    }
}

/// [`render_svg`] for a bed of either dimension, without wrapping it.
pub fn svg_of<const D: usize>(bed: &Bed<D>, opts: &RenderOptions) -> Result<String> {
    opts.check()?;
    match bed.as_2d() {
        Some(b) => bed2d::svg(b, opts),
        None => Err(Error::Impossible(
            "SVG pictures are for 2D beds; a 3D bed is drawn as PNG".into(),
        )),
    }
}

/// Colours of the particles and the legend entries `(colour, label)`, with the
/// legend's heading.
pub struct Palette {
    /// Colour of each particle.
    pub colours: Vec<Rgb>,
    /// Legend entries.
    pub legend: Vec<(Rgb, String)>,
    /// Heading of the legend.
    pub heading: String,
}

/// The contacts, when the options need them (coordination or force colour,
/// network).
pub(crate) fn contacts_if_needed<const D: usize>(
    bed: &Bed<D>,
    opts: &RenderOptions,
) -> Option<Contacts> {
    (opts.network || matches!(opts.color, ColorBy::Coordination | ColorBy::Force))
        .then(|| find_contacts(bed, opts.contact_tol))
}

/// A viridis colouring of `values` from 0 to `top`, with a five-step legend.
fn continuous(values: &[f64], top: f64, heading: String) -> Palette {
    let colours = values.iter().map(|&v| colour::viridis(v / top)).collect();
    let legend = (0..=4)
        .rev()
        .map(|k| {
            let t = k as f64 / 4.0;
            (colour::viridis(t), plot::format_tick(t * top, top / 4.0))
        })
        .collect();
    Palette {
        colours,
        legend,
        heading,
    }
}

/// Works out the colour of every particle.
pub fn palette<const D: usize>(
    bed: &Bed<D>,
    color: &ColorBy,
    contacts: Option<&Contacts>,
) -> Result<Palette> {
    let n = bed.len();
    match color {
        ColorBy::Species => {
            let count = bed
                .species
                .iter()
                .map(|&s| s as usize + 1)
                .max()
                .unwrap_or(0);
            let colours = bed
                .species
                .iter()
                .map(|&s| colour::categorical(s as usize))
                .collect();
            let legend = (0..count)
                .filter(|&s| bed.species.contains(&(s as u32)))
                .map(|s| (colour::categorical(s), species_label(bed, s)))
                .collect();
            Ok(Palette {
                colours,
                legend,
                heading: "species".into(),
            })
        }
        ColorBy::Coordination => {
            let owned;
            let contacts = match contacts {
                Some(c) => c,
                None => {
                    owned = find_contacts(bed, 1e-6);
                    &owned
                }
            };
            let z = coordination(bed, contacts);
            let zmax = z.iter().copied().max().unwrap_or(0).max(1);
            let colours = z
                .iter()
                .map(|&k| colour::viridis(k as f64 / zmax as f64))
                .collect();
            let mut present: Vec<u32> = z.clone();
            present.sort_unstable();
            present.dedup();
            let legend = present
                .iter()
                .map(|&k| (colour::viridis(k as f64 / zmax as f64), k.to_string()))
                .collect();
            Ok(Palette {
                colours,
                legend,
                heading: "coordination number".into(),
            })
        }
        ColorBy::Height => {
            let h = bed.container.height().max(bed.top()).max(f64::MIN_POSITIVE);
            let heights: Vec<f64> = bed.centres.iter().map(|c| c.height()).collect();
            Ok(continuous(&heights, h, "centre height".into()))
        }
        ColorBy::Force => {
            let owned;
            let contacts = match contacts {
                Some(c) => c,
                None => {
                    owned = find_contacts(bed, 1e-6);
                    &owned
                }
            };
            let options = crate::mechanics::Options::default();
            let frag = crate::mechanics::forces(bed, contacts, &options)?;
            let f = fragmentation::particle_forces(bed, &frag);
            let largest = f.iter().copied().fold(0.0, f64::max);
            let top = if largest > 0.0 { largest } else { 1.0 };
            let heading = format!("largest bond force ({})", options.load.name());
            Ok(continuous(&f, top, heading))
        }
        ColorBy::Classes(c) => {
            if c.class.len() != n {
                return Err(Error::Impossible(format!(
                    "{} particle classes for {n} particles",
                    c.class.len()
                )));
            }
            let colour_of = |k: u32| -> Rgb {
                if Some(k) == c.backdrop {
                    colour::BACKGROUND_PARTICLE
                } else {
                    // The first highlighted class gets the highlight colour.
                    let rank = (0..k).filter(|&j| Some(j) != c.backdrop).count();
                    if rank == 0 {
                        colour::HIGHLIGHT
                    } else {
                        colour::categorical(rank - 1)
                    }
                }
            };
            Ok(Palette {
                colours: c.class.iter().map(|&k| colour_of(k)).collect(),
                legend: (0..c.labels.len() as u32)
                    .map(|k| (colour_of(k), c.labels[k as usize].clone()))
                    .collect(),
                heading: String::new(),
            })
        }
    }
}

/// "large, r = 20": the species name and its radius (or radius range) in this bed.
fn species_label<const D: usize>(bed: &Bed<D>, s: usize) -> String {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for (k, &sp) in bed.species.iter().enumerate() {
        if sp as usize == s {
            lo = lo.min(bed.radii[k]);
            hi = hi.max(bed.radii[k]);
        }
    }
    let name = bed
        .species_info
        .get(s)
        .map(|i| i.name.clone())
        .unwrap_or_else(|| format!("species {s}"));
    let beads = bed.species_info.get(s).and_then(|i| match i.shape {
        crate::species::Shape::Chain { beads, .. } => Some(beads),
        _ => None,
    });
    let shape = beads
        .map(|b| format!(", chains of {b}"))
        .unwrap_or_default();
    if hi - lo <= 1e-9 * hi {
        format!("{name}, r = {}{shape}", plot::format_number(hi))
    } else {
        format!(
            "{name}, r = {}–{}{shape}",
            plot::format_number(lo),
            plot::format_number(hi)
        )
    }
}

/// The default title: dimension, count, what colours show.
pub(crate) fn default_title<const D: usize>(bed: &Bed<D>, opts: &RenderOptions) -> String {
    let what = match (D, bed.len()) {
        (2, 1) => "disc",
        (2, _) => "discs",
        (_, 1) => "sphere",
        _ => "spheres",
    };
    let mut t = format!("{}D bed, {} {what}", D, bed.len());
    let bodies = bed.body_count();
    if bodies != bed.len() {
        t.push_str(&format!(" in {bodies} bodies"));
    }
    if bed.container.periodic {
        t.push_str(", periodic sides");
    }
    if opts.network {
        t.push_str(", contact network");
    }
    t
}

/// Classes for `--color chains`: the particles of the percolation analysis'
/// spanning clusters (wall to wall, or wrapping round a periodic box), the
/// other large particles, and the rest, from
/// [`crate::analysis::percolation::membership`], so that the picture shows the
/// chains `summary.json` counts.
pub fn chain_classes<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    large: LargeRule,
) -> Classes {
    let class = membership(bed, contacts, large)
        .into_iter()
        .map(|m| match m {
            Membership::Spanning => 0,
            Membership::Large => 1,
            Membership::Small => 2,
        })
        .collect();
    let spanning = if bed.container.periodic {
        "large, in a cluster wrapping round the box"
    } else {
        "large, in a wall-to-wall chain"
    };
    Classes {
        labels: vec![
            spanning.into(),
            "large, not spanning".into(),
            "smaller particles".into(),
        ],
        class,
        backdrop: Some(2),
    }
}
