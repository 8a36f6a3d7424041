//! Pictures of beds and plots of measures.
//!
//! - `canvas`: one drawing API with an SVG and a PNG (tiny-skia) back end and
//!   embedded text, so both formats show the same picture.
//! - `bed2d`: 2D beds, every disc drawn exactly (SVG circles in bed coordinates).
//! - `bed3d`: 3D beds, a z-buffered raster of exact sphere surfaces, shaded.
//! - `frame`: title, legend and scale bar around a bed picture.
//! - `plot`: histograms, profiles, bars with error bars, from plain data.
//! - `fragmentation`: bond forces and breakage of a bed under load.
//! - `colour`: colour-blind-safe palettes.
//!
//! Colouring takes per-particle classes ([`ColorBy::Classes`]) so that any
//! measure that marks particles (percolation chains, clusters) can be shown.

mod bed2d;
mod bed3d;
pub(crate) mod canvas;
pub(crate) mod colour;
pub(crate) mod ensemble_plots;
pub(crate) mod fragmentation;
pub(crate) mod frame;
pub(crate) mod plot;
pub(crate) mod run_files;
pub(crate) mod run_plots;

use crate::analysis::percolation::{membership, LargeRule, Membership};
use crate::analysis::{coordination, find_contacts, Contacts};
use crate::bed::{AnyBed, Bed};
use crate::error::{Error, Result};
use canvas::Rgb;

pub use bed2d::placement;
pub use bed3d::{Cut, View};
pub use canvas::text_width;
pub use colour::{categorical, viridis};
pub use fragmentation::{
    fragmentation_pictures, particle_forces, HEIGHT as FRAGMENTATION_HEIGHT, NUMBERED_BREAKS,
    WIDTH as FRAGMENTATION_WIDTH,
};
pub use run_plots::{
    chain_angle_histogram, coordination_histogram, packing_profile, regional_packing,
};

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
    /// The radius, on a continuous scale from the smallest to the largest in
    /// the bed (the default for beds with a size distribution, see
    /// [`default_color`]).
    Radius,
    /// The largest contact force `|f|` among the bonds of the particle's body
    /// under the default load (shear, total 1), from `crate::mechanics`
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
    /// The unit of the bed's lengths, for the scale bar and the radius
    /// legend (`[analysis] length_unit`), where known.
    pub length_unit: Option<crate::config::LengthUnit>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 1200,
            height: 1000,
            color: ColorBy::Species,
            network: false,
            contact_tol: crate::config::DEFAULT_CONTACT_TOL,
            outlines: true,
            view: View::default(),
            cut: Cut::None,
            supersample: 2,
            title: None,
            length_unit: None,
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
        // The supersampled pixmap with its depth buffer, the image and its
        // encoding: about 8 bytes a sample and a pixel.
        let (w, h, ss) = (
            self.width as f64,
            self.height as f64,
            self.supersample as f64,
        );
        crate::input::check_memory(
            8.0 * w * h * (ss * ss + 1.0),
            &format!(
                "an image of {} × {} pixels drawn at {}× supersampling",
                self.width, self.height, self.supersample
            ),
        )?;
        if let Some(why) = crate::config::contact_tol_problem(self.contact_tol, "contact tolerance")
        {
            return Err(Error::Impossible(why));
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

/// The contacts given, or those of `bed` at the default tolerance.
fn given_or_found<'a, const D: usize>(
    contacts: Option<&'a Contacts>,
    bed: &Bed<D>,
) -> std::borrow::Cow<'a, Contacts> {
    match contacts {
        Some(c) => std::borrow::Cow::Borrowed(c),
        None => std::borrow::Cow::Owned(find_contacts(bed, crate::config::DEFAULT_CONTACT_TOL)),
    }
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

/// A viridis colouring of `values` from `lo` to `hi`, with a five-step
/// legend; one colour (the scale's middle) when they are all equal.
fn continuous_between(values: &[f64], lo: f64, hi: f64, heading: String) -> Palette {
    let span = hi - lo;
    // Also catches a NaN span: one colour rather than NaN colours.
    if span.is_nan() || span <= 1e-12 * hi.abs() {
        let c = colour::viridis(0.5);
        return Palette {
            colours: vec![c; values.len()],
            legend: vec![(c, plot::format_number(hi))],
            heading,
        };
    }
    let colours = values
        .iter()
        .map(|&v| colour::viridis((v - lo) / span))
        .collect();
    let legend = (0..=4)
        .rev()
        .map(|k| {
            let t = k as f64 / 4.0;
            (
                colour::viridis(t),
                plot::format_tick(lo + t * span, span / 4.0),
            )
        })
        .collect();
    Palette {
        colours,
        legend,
        heading,
    }
}

/// How a run colours its bed: by radius when a species' particles differ in
/// size (a size distribution: one colour per species would hide it), by
/// species when every species has one size.
pub fn default_color<const D: usize>(bed: &Bed<D>) -> ColorBy {
    let species = bed
        .species
        .iter()
        .map(|&s| s as usize + 1)
        .max()
        .unwrap_or(0);
    let mut lo = vec![f64::INFINITY; species];
    let mut hi = vec![0.0f64; species];
    for (&s, &r) in bed.species.iter().zip(&bed.radii) {
        lo[s as usize] = lo[s as usize].min(r);
        hi[s as usize] = hi[s as usize].max(r);
    }
    // The same relative tolerance as the species legend's "r = a–b".
    let sized = lo.iter().zip(&hi).any(|(&l, &h)| h - l > 1e-9 * h);
    if sized {
        ColorBy::Radius
    } else {
        ColorBy::Species
    }
}

/// The palette of a bed picture: [`palette`], with the radius legend in the
/// options' length unit.
pub(crate) fn picture_palette<const D: usize>(
    bed: &Bed<D>,
    opts: &RenderOptions,
    contacts: Option<&Contacts>,
) -> Result<Palette> {
    let mut pal = palette(bed, &opts.color, contacts)?;
    if let (ColorBy::Radius, Some(_)) = (&opts.color, opts.length_unit) {
        pal.heading = format!("radius ({})", run_plots::length_label(opts.length_unit));
    }
    Ok(pal)
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
            let contacts = given_or_found(contacts, bed);
            let z = coordination(bed, &contacts);
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
        ColorBy::Radius => {
            let lo = bed.radii.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = bed.radii.iter().copied().fold(0.0, f64::max);
            let lo = if lo.is_finite() { lo } else { hi };
            Ok(continuous_between(&bed.radii, lo, hi, "radius".into()))
        }
        ColorBy::Force => {
            let contacts = given_or_found(contacts, bed);
            let options = crate::mechanics::FragmentationConfig::default();
            let frag = crate::mechanics::forces(bed, &contacts, &options)?;
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
    let mut t = bed.describe();
    if opts.network {
        t.push_str(", contact network");
    }
    t
}

/// Classes for `--color chains`: the particles of the percolation analysis'
/// spanning clusters (wall to wall, or wrapping round a periodic box), the
/// other large particles, and the rest, from
/// `crate::analysis::percolation::membership`, so that the picture shows the
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

#[cfg(test)]
mod tests {
    use super::*;

    fn lightness(c: Rgb) -> f64 {
        0.299 * c.0 as f64 + 0.587 * c.1 as f64 + 0.114 * c.2 as f64
    }

    #[test]
    fn radius_colours_grow_with_the_radius_and_span_the_scale() {
        let radii = [3.0, 1.0, 2.5, 1.5, 2.0];
        let bed = Bed::of_discs([40.0, 20.0], false, &radii.map(|r| (5.0 + 6.0 * r, 5.0, r)));
        let p = palette(&bed, &ColorBy::Radius, None).unwrap();
        let mut order: Vec<usize> = (0..radii.len()).collect();
        order.sort_by(|&a, &b| radii[a].total_cmp(&radii[b]));
        // Viridis brightens monotonically: a larger radius, a lighter colour.
        for w in order.windows(2) {
            assert!(
                lightness(p.colours[w[1]]) > lightness(p.colours[w[0]]),
                "r {} vs {}",
                radii[w[0]],
                radii[w[1]]
            );
        }
        // The smallest and largest radii take the ends of the scale.
        assert_eq!(p.colours[1], colour::viridis(0.0));
        assert_eq!(p.colours[0], colour::viridis(1.0));
        assert_eq!(p.heading, "radius");
        let labels: Vec<&str> = p.legend.iter().map(|l| l.1.as_str()).collect();
        assert_eq!(labels, ["3.0", "2.5", "2.0", "1.5", "1.0"]);
    }

    #[test]
    fn one_radius_gets_one_colour() {
        let bed = Bed::of_discs([40.0, 20.0], false, &[(5.0, 5.0, 2.0), (15.0, 5.0, 2.0)]);
        let p = palette(&bed, &ColorBy::Radius, None).unwrap();
        assert_eq!(p.colours[0], p.colours[1]);
        assert_eq!(p.legend.len(), 1);
    }

    /// Discs of species 0, 1 and 0 in a row, of radii 2, 1 and `third`.
    fn two_species(third: f64) -> Bed<2> {
        let discs = [
            ([5.0, 5.0], 2.0, 0),
            ([15.0, 5.0], 1.0, 1),
            ([25.0, 5.0], third, 0),
        ];
        Bed::of_spheres([40.0, 20.0], false, discs)
    }

    #[test]
    fn beds_of_fixed_sizes_colour_by_species_and_distributions_by_radius() {
        // Two species of one size each: the species tell the sizes apart.
        assert_eq!(default_color(&two_species(2.0)), ColorBy::Species);
        // A species whose sizes differ (a size distribution).
        assert_eq!(default_color(&two_species(2.2)), ColorBy::Radius);
    }
}
