//! Measured size distributions (PSD tables), read as sieve analyses and laser
//! diffraction report them. The header says what the columns are, because a
//! two-column file of numbers can mean diameters or radii, number or mass
//! fractions: read the wrong way, it builds a wrong bed without a word.
//!
//! Four layouts, each with `radius` or `diameter` sizes (optionally with a
//! unit, `diameter_um`) and `number`, `volume` or `mass` weights (equal
//! density: mass = volume):
//! - discrete sizes: `diameter_um,mass_percent`;
//! - classes given by their edges, as sieves retain them:
//!   `diameter_min_um,diameter_max_um,mass_percent`;
//! - a cumulative curve: `diameter_um,percent_passing` (mass unless the column
//!   says `number_percent_passing`);
//! - a sieve analysis as a lab writes it, the mass retained on each sieve:
//!   `sieve_mm,retained_percent`, a row `pan` for what passed the finest
//!   sieve. What a sieve retains lies between its aperture and the next larger
//!   one; the largest sieve must retain nothing (what it held would have no
//!   upper size); the pan's lower edge is [`TableOptions::pan_min`], by
//!   default half the finest aperture.
//!
//! Sizes within a class (and between two points of a curve) are drawn
//! log-uniformly unless the config says `within = "uniform"`: sieve classes
//! are geometric (each aperture a fixed factor above the last), and a
//! log-uniform class has the same share of each factor of size.

use crate::error::{Error, Result};
use crate::math::{display_length as length, Real};
use rand::RngExt;
use std::path::{Path, PathBuf};

/// The headers accepted, for the message that refuses any other.
pub const ACCEPTED_HEADERS: &str =
    "`diameter,mass_percent` (sizes; `radius` for radii; weights `number`, `volume` or `mass`), \
`diameter_min,diameter_max,mass_percent` (classes by their edges, as sieves give them), \
`diameter,percent_passing` (a cumulative mass curve; `number_percent_passing` by number), \
`sieve,retained_percent` (mass retained on each sieve, a row `pan` for the pan); \
a size column may name its unit: `diameter_um` (m, mm, um, nm)";

/// How a table is read, beyond what its header says.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct TableOptions {
    /// How sizes spread within a class.
    pub within: Within,
    /// The smallest size in the pan of a sieve table, in the table's size unit
    /// (`None`: half the finest aperture, one octave below it: the pan's
    /// fines have a size a log-uniform draw can start from, and a pan of a
    /// few percent moves the mass curve little whichever edge is chosen).
    pub pan_min: Option<Real>,
}

/// How sizes spread within a class of a table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Within {
    /// Uniform in the logarithm of the size (the default).
    #[default]
    LogUniform,
    /// Uniform in the size.
    Uniform,
}

impl Within {
    /// The config name: `log-uniform` or `uniform`.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Within::LogUniform => "log-uniform",
            Within::Uniform => "uniform",
        }
    }
}

/// What a table's weights count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Basis {
    /// Numbers of particles.
    Number,
    /// Volume of solid.
    Volume,
    /// Mass of solid (equal density: the same as volume).
    Mass,
}

impl Basis {
    /// `number`, `volume` or `mass`.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Basis::Number => "number",
            Basis::Volume => "volume",
            Basis::Mass => "mass",
        }
    }
}

/// How a table's rows give the distribution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// One size per row.
    Sizes,
    /// Classes by their smallest and largest size.
    Classes,
    /// A cumulative curve: the share finer than each size.
    Passing,
    /// Sieve apertures with the share retained on each (and a pan).
    Retained,
}

/// One class of radii `[lo, hi]` (`lo == hi`: a single size).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeClass {
    /// Smallest radius.
    pub lo: Real,
    /// Largest radius.
    pub hi: Real,
    /// Probability that a particle is of this class (by number).
    pub number: Real,
}

/// A measured size distribution: classes of radii with their number
/// probabilities, in order of size.
#[derive(Clone, Debug, PartialEq)]
pub struct SizeTable {
    classes: Vec<SizeClass>,
    /// Number probability of the classes up to each, the last exactly 1.
    cumulative: Vec<Real>,
    /// How sizes spread within a class.
    pub within: Within,
    /// How the file gave the distribution.
    pub layout: Layout,
    /// What the file's weights counted.
    pub basis: Basis,
    /// The file's size column: `radius` or `diameter`.
    pub size_word: &'static str,
    /// The unit the file named, if any.
    pub unit: Option<&'static str>,
    /// The file.
    pub source: PathBuf,
}

/// One column of the header, as understood.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Column {
    Size {
        diameter: bool,
        /// Named as sieve apertures (`sieve`, `aperture`).
        sieve: bool,
        bound: Option<Bound>,
        unit: Option<(&'static str, Real)>,
    },
    Weight {
        basis: Option<Basis>,
        fraction: bool,
        passing: bool,
        retained: bool,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Bound {
    Min,
    Max,
}

/// The unit names a size column may carry, in metres.
fn unit(token: &str) -> Option<(&'static str, Real)> {
    Some(match token {
        "m" => ("m", 1.0),
        "mm" => ("mm", 1e-3),
        "um" | "µm" | "μm" | "micron" | "microns" | "micrometre" | "micrometer" => ("um", 1e-6),
        "nm" => ("nm", 1e-9),
        _ => return None,
    })
}

/// Reads one header field; `Err` holds a reason beyond "unknown", if any.
fn column(field: &str) -> std::result::Result<Column, Option<String>> {
    let text = field
        .trim()
        .trim_matches('"')
        .to_lowercase()
        .replace('%', "_percent_");
    let tokens: Vec<&str> = text
        .split(|c: char| !(c.is_alphanumeric() || c == 'µ' || c == 'μ'))
        .filter(|t| !t.is_empty())
        .collect();
    let mut size = None;
    let mut bound = None;
    let mut unit_of = None;
    let mut basis = None;
    let mut fraction = false;
    let mut percent = false;
    let mut passing = false;
    let mut retained = false;
    let mut sieve = false;
    for t in &tokens {
        match *t {
            "radius" | "radii" => size = Some(false),
            "diameter" | "diameters" => size = Some(true),
            "sieve" | "sieves" | "aperture" | "apertures" => {
                size = Some(true);
                sieve = true;
            }
            "retained" | "oversize" => retained = true,
            "min" | "lower" | "from" => bound = Some(Bound::Min),
            "max" | "upper" | "to" => bound = Some(Bound::Max),
            "number" | "count" => basis = Some(Basis::Number),
            "volume" | "vol" => basis = Some(Basis::Volume),
            "mass" => basis = Some(Basis::Mass),
            "percent" | "pct" => percent = true,
            "fraction" | "frac" => fraction = true,
            "passing" | "undersize" | "finer" | "cumulative" => passing = true,
            "weight" | "wt" | "weights" => {
                return Err(Some(format!(
                    "`{field}` does not say what the weights count (number or mass?): \
                     name the column `number`, `volume` or `mass`"
                )))
            }
            t => match unit(t) {
                Some(u) => unit_of = Some(u),
                None => return Err(None),
            },
        }
    }
    if passing && retained {
        return Err(Some(format!(
            "`{field}` says both passing and retained: give the cumulative curve as \
             `percent_passing` (100 minus the cumulative percent retained), or the \
             `retained_percent` on each sieve"
        )));
    }
    let weighty = basis.is_some() || fraction || percent || passing || retained;
    match size {
        Some(diameter) if !weighty => Ok(Column::Size {
            diameter,
            sieve,
            bound,
            unit: unit_of,
        }),
        None if weighty && bound.is_none() && unit_of.is_none() => Ok(Column::Weight {
            basis,
            fraction: fraction && !percent,
            passing,
            retained,
        }),
        _ => Err(None),
    }
}

/// The header's layout: columns of sizes and the weight column.
struct Header {
    layout: Layout,
    diameter: bool,
    unit: Option<(&'static str, Real)>,
    basis: Basis,
    fraction: bool,
    /// Where the smallest and largest size of a class are (classes only).
    min_max: (usize, usize),
}

fn header(fields: &[&str]) -> std::result::Result<Header, Option<String>> {
    let cols = fields
        .iter()
        .map(|f| column(f))
        .collect::<std::result::Result<Vec<_>, _>>()?;
    // The weight column of a layout: plain weights, `passing` or `retained`.
    let weight = |c: &Column, passing_wanted: bool, retained_wanted: bool| match *c {
        Column::Weight {
            basis,
            fraction,
            passing,
            retained,
        } if passing == passing_wanted && retained == retained_wanted => {
            // A passing curve or a sieve residue is by mass unless it says
            // otherwise: sieve analyses and laser diffraction both report
            // mass (volume).
            let basis = match (basis, passing || retained) {
                (Some(b), _) => Some(b),
                (None, true) => Some(Basis::Mass),
                (None, false) => None,
            };
            basis.map(|b| (b, fraction))
        }
        _ => None,
    };
    match cols.as_slice() {
        [Column::Size {
            diameter,
            sieve,
            bound: None,
            unit,
        }, w] => {
            if let Some((basis, fraction)) = weight(w, false, true) {
                if !*diameter {
                    return Err(Some(
                        "what a sieve retains is given by its aperture: name the size \
                         column `sieve` (e.g. `sieve_mm`), not a radius"
                            .into(),
                    ));
                }
                return Ok(Header {
                    layout: Layout::Retained,
                    diameter: true,
                    unit: *unit,
                    basis,
                    fraction,
                    min_max: (0, 0),
                });
            }
            if *sieve && weight(w, true, false).is_none() {
                return Err(Some(
                    "sieve apertures with plain weights: say whether they are the share \
                     `retained_percent` on each sieve or the `percent_passing` it"
                        .into(),
                ));
            }
            if let Some((basis, fraction)) = weight(w, false, false) {
                return Ok(Header {
                    layout: Layout::Sizes,
                    diameter: *diameter,
                    unit: *unit,
                    basis,
                    fraction,
                    min_max: (0, 0),
                });
            }
            if let Some((basis, fraction)) = weight(w, true, false) {
                return Ok(Header {
                    layout: Layout::Passing,
                    diameter: *diameter,
                    unit: *unit,
                    basis,
                    fraction,
                    min_max: (0, 0),
                });
            }
            Err(None)
        }
        [Column::Size {
            diameter: d0,
            bound: Some(b0),
            unit: u0,
            ..
        }, Column::Size {
            diameter: d1,
            bound: Some(b1),
            unit: u1,
            ..
        }, w]
            if d0 == d1 && u0 == u1 && b0 != b1 =>
        {
            let (basis, fraction) = weight(w, false, false).ok_or(None)?;
            Ok(Header {
                layout: Layout::Classes,
                diameter: *d0,
                unit: *u0,
                basis,
                fraction,
                min_max: if *b0 == Bound::Min { (0, 1) } else { (1, 0) },
            })
        }
        _ => Err(None),
    }
}

/// The mean of `r³` over a class, and the share of its number and its volume
/// below `x`.
fn mean_cube(c: &SizeClass, within: Within) -> Real {
    let (a, b) = (c.lo, c.hi);
    if a == b {
        return a * a * a;
    }
    match within {
        // Density ∝ 1/r on [a, b]: ∫ r³ dr/r = (b³ − a³)/3, over ln(b/a).
        Within::LogUniform => (b * b * b - a * a * a) / (3.0 * (b / a).ln()),
        Within::Uniform => (b.powi(4) - a.powi(4)) / (4.0 * (b - a)),
    }
}

fn number_below(c: &SizeClass, within: Within, x: Real) -> Real {
    if x < c.lo {
        return 0.0;
    }
    if x >= c.hi {
        return 1.0;
    }
    match within {
        Within::LogUniform => (x / c.lo).ln() / (c.hi / c.lo).ln(),
        Within::Uniform => (x - c.lo) / (c.hi - c.lo),
    }
}

fn volume_below(c: &SizeClass, within: Within, x: Real) -> Real {
    if x < c.lo {
        return 0.0;
    }
    if x >= c.hi {
        return 1.0;
    }
    let p = match within {
        Within::LogUniform => 3,
        Within::Uniform => 4,
    };
    (x.powi(p) - c.lo.powi(p)) / (c.hi.powi(p) - c.lo.powi(p))
}

/// The radius of `c` at which `u` of its number lies below.
fn class_quantile(c: &SizeClass, within: Within, u: Real) -> Real {
    if c.lo == c.hi {
        return c.lo;
    }
    let r = match within {
        Within::LogUniform => c.lo * (c.hi / c.lo).powf(u),
        Within::Uniform => c.lo + u * (c.hi - c.lo),
    };
    r.clamp(c.lo, c.hi)
}

impl SizeTable {
    /// Reads a PSD table. `metres_per_unit` is the bed's length unit
    /// (`[analysis] length_unit`): sizes in a unit the file names are
    /// converted to it, and a file that names a unit needs one.
    pub fn read(path: &Path, within: Within, metres_per_unit: Option<Real>) -> Result<SizeTable> {
        let options = TableOptions {
            within,
            pan_min: None,
        };
        SizeTable::read_with(path, &options, metres_per_unit)
    }

    /// [`SizeTable::read`] with every option of `TableOptions`.
    pub(crate) fn read_with(
        path: &Path,
        options: &TableOptions,
        metres_per_unit: Option<Real>,
    ) -> Result<SizeTable> {
        let within = options.within;
        let text = crate::input::read_text(path)?;
        let err = |line: usize, message: String| Error::Data {
            path: path.to_path_buf(),
            line,
            message,
        };
        let mut rows = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let Some((header_line, header_text)) = rows.next() else {
            return Err(err(
                1,
                format!("the table is empty; it needs a header, one of {ACCEPTED_HEADERS}"),
            ));
        };
        let names = fields(header_text);
        if names.iter().all(|f| f.parse::<Real>().is_ok()) {
            return Err(err(
                header_line,
                format!(
                    "no header (the first row is `{header_text}`); the first row must say what the columns are, one of {ACCEPTED_HEADERS}"
                ),
            ));
        }
        let h = header(&names).map_err(|why| {
            err(
                header_line,
                match why {
                    Some(w) => format!("header `{header_text}`: {w}"),
                    None => format!("unknown header `{header_text}`; accepted: {ACCEPTED_HEADERS}"),
                },
            )
        })?;
        let scale = match (h.unit, metres_per_unit) {
            (Some((_, m)), Some(bed)) => m / bed,
            (Some((name, _)), None) => {
                return Err(err(
                    header_line,
                    format!(
                        "the sizes are in {name}, but the bed's length unit is not given: set `[analysis] length_unit` (e.g. \"{name}\")"
                    ),
                ))
            }
            (None, _) => 1.0,
        } * if h.diameter { 0.5 } else { 1.0 };
        let mut data: Vec<(usize, Vec<Real>)> = Vec::new();
        for (line, l) in rows {
            let f = fields(l);
            if f.len() != names.len() {
                return Err(err(
                    line,
                    format!(
                        "expected {} columns as the header `{header_text}` says, found {}",
                        names.len(),
                        f.len()
                    ),
                ));
            }
            let mut v = Vec::with_capacity(f.len());
            for (k, x) in f.into_iter().enumerate() {
                // The pan of a sieve table: its size is the option's (0 here).
                if h.layout == Layout::Retained && k == 0 && x.eq_ignore_ascii_case("pan") {
                    v.push(0.0);
                    continue;
                }
                match x.parse::<Real>() {
                    Ok(x) if x.is_finite() => v.push(x),
                    _ => return Err(err(line, format!("not a number: `{x}` in `{l}`"))),
                }
            }
            data.push((line, v));
        }
        let last_line = text.lines().count().max(1);
        // Sizes are cubed into volumes and masses: beyond packbed's length
        // range a cube overflows to infinity or vanishes, and the weights with it.
        let positive_size = |line: usize, s: Real| {
            let (lo, hi) = crate::math::LENGTH_RANGE;
            match s * scale {
                _ if s <= 0.0 => Err(err(line, format!("a size must be positive, got {s}"))),
                x if (lo..=hi).contains(&x) => Ok(x),
                x => Err(err(
                    line,
                    format!(
                        "a size must lie between {lo:e} and {hi:e} in the bed's unit, got {x:e}"
                    ),
                )),
            }
        };
        let weight = |line: usize, w: Real| {
            if w >= 0.0 {
                Ok(w)
            } else {
                Err(err(line, format!("a weight must be >= 0, got {w}")))
            }
        };
        // Classes with their weight on the file's basis.
        let mut classes: Vec<(SizeClass, Real)> = Vec::new();
        match h.layout {
            Layout::Sizes => {
                for (line, v) in &data {
                    let r = positive_size(*line, v[0])?;
                    classes.push((class(r, r), weight(*line, v[1])?));
                }
            }
            Layout::Classes => {
                for (line, v) in &data {
                    let lo = positive_size(*line, v[h.min_max.0])?;
                    let hi = positive_size(*line, v[h.min_max.1])?;
                    if lo >= hi {
                        return Err(err(
                            *line,
                            format!(
                                "the smallest size of a class must be below its largest, got {} and {}",
                                v[h.min_max.0], v[h.min_max.1]
                            ),
                        ));
                    }
                    classes.push((class(lo, hi), weight(*line, v[2])?));
                }
            }
            Layout::Passing => {
                let full = if h.fraction { 1.0 } else { 100.0 };
                let what = if h.fraction { "" } else { " %" };
                let mut prev: Option<(Real, Real)> = None;
                for (line, v) in &data {
                    let (s, p) = (positive_size(*line, v[0])?, v[1]);
                    if !(0.0..=full * 1.01).contains(&p) {
                        return Err(err(
                            *line,
                            format!("a share passing must be between 0 and {full}, got {p}"),
                        ));
                    }
                    match prev {
                        None if p > 0.0 => {
                            return Err(err(
                                *line,
                                format!(
                                    "the curve starts at {p}{what} passing: what is finer than its first size has no size range; start with a row of 0{what} passing at the smallest size present"
                                ),
                            ))
                        }
                        None => {}
                        Some((s0, p0)) => {
                            if s <= s0 {
                                return Err(err(*line, "sizes must increase down the curve".into()));
                            }
                            if p < p0 {
                                return Err(err(
                                    *line,
                                    format!("the share passing falls from {p0} to {p}; a cumulative curve never falls"),
                                ));
                            }
                            classes.push((class(s0, s), p - p0));
                        }
                    }
                    prev = Some((s, p));
                }
                if let Some((_, p)) = prev {
                    if (p - full).abs() > 0.01 * full {
                        return Err(err(
                            last_line,
                            format!(
                                "the curve ends at {p}{what} passing: what is coarser than its last size has no size range; end with a row of {full}{what} passing at the largest size present"
                            ),
                        ));
                    }
                }
            }
            Layout::Retained => {
                // Sieves by aperture, the pan (aperture 0) first.
                let mut sieves: Vec<(usize, Real, Real)> = Vec::with_capacity(data.len());
                for (line, v) in &data {
                    let a = if v[0] == 0.0 {
                        0.0
                    } else {
                        positive_size(*line, v[0])?
                    };
                    sieves.push((*line, a, weight(*line, v[1])?));
                }
                sieves.sort_by(|a, b| a.1.total_cmp(&b.1));
                for w in sieves.windows(2) {
                    if w[0].1 == w[1].1 {
                        let what = if w[1].1 == 0.0 { "the pan" } else { "a sieve" };
                        return Err(err(
                            w[1].0.max(w[0].0),
                            format!("{what} appears twice (also on line {})", w[1].0.min(w[0].0)),
                        ));
                    }
                }
                let (pan, sieves) = match sieves.first() {
                    Some(&(line, 0.0, w)) => (Some((line, w)), &sieves[1..]),
                    _ => (None, &sieves[..]),
                };
                let Some(&(top_line, top, top_weight)) = sieves.last() else {
                    return Err(err(
                        last_line,
                        "a sieve table needs at least one sieve".into(),
                    ));
                };
                if top_weight > 0.0 {
                    return Err(err(
                        top_line,
                        format!(
                            "the largest sieve, {}, retains {top_weight}: what it holds has no \
                             upper size; add the next larger sieve, retaining 0",
                            length(top / scale)
                        ),
                    ));
                }
                for w in sieves.windows(2) {
                    classes.push((class(w[0].1, w[1].1), w[0].2));
                }
                if let Some((line, w)) = pan {
                    let finest = sieves[0].1;
                    let lo = match options.pan_min {
                        None => 0.5 * finest,
                        Some(p) => match positive_size(line, p)? {
                            lo if lo < finest => lo,
                            _ => {
                                return Err(err(
                                    line,
                                    format!(
                                        "the pan's smallest size (pan_min {}) must lie below \
                                         the finest sieve, {}",
                                        length(p),
                                        length(finest / scale)
                                    ),
                                ))
                            }
                        },
                    };
                    classes.push((class(lo, finest), w));
                }
            }
        }
        // Rows of weight 0 are part of a sieve report, not sizes to draw.
        classes.retain(|(_, w)| *w > 0.0);
        if classes.is_empty() {
            return Err(err(
                last_line,
                "the table has no size with a positive weight".into(),
            ));
        }
        classes.sort_by(|a, b| a.0.lo.total_cmp(&b.0.lo).then(a.0.hi.total_cmp(&b.0.hi)));
        // Equal single sizes are one size; overlapping classes are a mistake.
        let mut merged: Vec<(SizeClass, Real)> = Vec::with_capacity(classes.len());
        for (c, w) in classes {
            if let Some(last) = merged.last_mut() {
                if last.0 == c {
                    last.1 += w;
                    continue;
                }
                if c.lo < last.0.hi {
                    let unit = h.unit.map_or(String::new(), |u| format!(" {}", u.0));
                    let word = if h.diameter { "diameters" } else { "radii" };
                    let back = if h.diameter { 2.0 / scale } else { 1.0 / scale };
                    return Err(err(
                        last_line,
                        format!(
                            "the classes of {word} [{}, {}] and [{}, {}]{unit} overlap",
                            length(last.0.lo * back),
                            length(last.0.hi * back),
                            length(c.lo * back),
                            length(c.hi * back)
                        ),
                    ));
                }
            }
            merged.push((c, w));
        }
        // Mass (volume) shares become number shares: each class's mass over
        // the mass of its mean particle.
        let numbers: Vec<Real> = merged
            .iter()
            .map(|(c, w)| match h.basis {
                Basis::Number => *w,
                Basis::Volume | Basis::Mass => w / mean_cube(c, within),
            })
            .collect();
        let total: Real = numbers.iter().sum();
        if !(total.is_finite() && total > 0.0) {
            return Err(err(
                last_line,
                "the table's weights give no particles (sizes too large or weights too small)"
                    .into(),
            ));
        }
        let mut acc = 0.0;
        let mut cumulative = Vec::with_capacity(numbers.len());
        let mut out = Vec::with_capacity(numbers.len());
        for ((c, _), n) in merged.into_iter().zip(numbers) {
            acc += n / total;
            cumulative.push(acc);
            out.push(SizeClass {
                number: n / total,
                ..c
            });
        }
        *cumulative.last_mut().expect("classes are not empty") = 1.0;
        Ok(SizeTable {
            classes: out,
            cumulative,
            within,
            layout: h.layout,
            basis: h.basis,
            size_word: if h.diameter { "diameter" } else { "radius" },
            unit: h.unit.map(|u| u.0),
            source: path.to_path_buf(),
        })
    }

    /// The sizes of particles placed as a file has them (a medium read from
    /// a bed file): one size per distinct radius of `radii`, by number, in
    /// the bed's own length unit; `source` names the file. `radii` holds at
    /// least one positive radius.
    pub(crate) fn of_radii(radii: &[Real], source: &Path) -> SizeTable {
        let mut sorted = radii.to_vec();
        sorted.sort_by(Real::total_cmp);
        let n = sorted.len() as Real;
        let mut classes: Vec<SizeClass> = Vec::new();
        for r in sorted {
            match classes.last_mut() {
                Some(c) if c.lo == r => c.number += 1.0 / n,
                _ => classes.push(SizeClass {
                    number: 1.0 / n,
                    ..class(r, r)
                }),
            }
        }
        let mut acc = 0.0;
        let mut cumulative: Vec<Real> = classes
            .iter()
            .map(|c| {
                acc += c.number;
                acc
            })
            .collect();
        if let Some(last) = cumulative.last_mut() {
            *last = 1.0;
        }
        SizeTable {
            classes,
            cumulative,
            within: Within::LogUniform,
            layout: Layout::Sizes,
            basis: Basis::Number,
            size_word: "radius",
            unit: Some("the bed's unit"),
            source: source.to_path_buf(),
        }
    }

    /// The classes, in order of size.
    pub fn classes(&self) -> &[SizeClass] {
        &self.classes
    }

    /// The smallest and largest radius drawn.
    pub fn bounds(&self) -> (Real, Real) {
        (self.classes[0].lo, self.classes[self.classes.len() - 1].hi)
    }

    /// Draws one radius.
    pub fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> Real {
        let u: Real = rng.random();
        let i = self
            .cumulative
            .partition_point(|&c| c <= u)
            .min(self.classes.len() - 1);
        let c = &self.classes[i];
        if c.lo == c.hi {
            c.lo
        } else {
            class_quantile(c, self.within, rng.random())
        }
    }

    /// Draws one radius of at most `room`, by the table's weights of the sizes
    /// that fit; `None` when no size fits.
    pub fn sample_at_most<R: rand::Rng + ?Sized>(&self, room: Real, rng: &mut R) -> Option<Real> {
        let weights: Vec<Real> = self
            .classes
            .iter()
            .map(|c| c.number * number_below(c, self.within, room))
            .collect();
        let total: Real = weights.iter().sum();
        if total <= 0.0 {
            return None;
        }
        let mut u = rng.random::<Real>() * total;
        let mut pick = self.classes.len() - 1;
        for (i, &w) in weights.iter().enumerate() {
            if w > 0.0 {
                pick = i;
                if u < w {
                    break;
                }
                u -= w;
            }
        }
        let c = &self.classes[pick];
        // Within a class cut at `room`, the draw keeps the class's own spread.
        let cut = SizeClass {
            hi: c.hi.min(room),
            ..*c
        };
        Some(class_quantile(&cut, self.within, rng.random()))
    }

    /// The number-median radius.
    pub fn median(&self) -> Real {
        let i = self
            .cumulative
            .partition_point(|&c| c < 0.5)
            .min(self.classes.len() - 1);
        let before = if i == 0 { 0.0 } else { self.cumulative[i - 1] };
        let c = &self.classes[i];
        let u = ((0.5 - before) / c.number).clamp(0.0, 1.0);
        class_quantile(c, self.within, u)
    }

    /// The mean of `r³` by number.
    pub fn mean_cube(&self) -> Real {
        self.classes
            .iter()
            .map(|c| c.number * mean_cube(c, self.within))
            .sum()
    }

    /// The share of particles (by number) of radius `<= x`.
    pub fn number_passing(&self, x: Real) -> Real {
        self.classes
            .iter()
            .map(|c| c.number * number_below(c, self.within, x))
            .sum::<Real>()
            .min(1.0)
    }

    /// The share of the solid volume (mass) in particles of radius `<= x`.
    pub fn volume_passing(&self, x: Real) -> Real {
        let part: Real = self
            .classes
            .iter()
            .map(|c| c.number * mean_cube(c, self.within) * volume_below(c, self.within, x))
            .sum();
        (part / self.mean_cube()).min(1.0)
    }

    /// The radii at which the table has rows: class edges and single sizes.
    pub(crate) fn sizes(&self) -> Vec<Real> {
        let mut v: Vec<Real> = self.classes.iter().flat_map(|c| [c.lo, c.hi]).collect();
        v.sort_by(Real::total_cmp);
        v.dedup();
        v
    }

    /// For a person: `r from psd.csv (7 sieve classes by mass, diameters in
    /// um, log-uniform within a class)`.
    pub fn describe(&self) -> String {
        let n = self.classes.len();
        let layout = match self.layout {
            Layout::Sizes => format!("{n} sizes by {}", self.basis.name()),
            Layout::Classes => format!("{n} classes by {}", self.basis.name()),
            Layout::Passing => format!("a cumulative {} curve", self.basis.name()),
            Layout::Retained => format!("{n} classes by {} retained on sieves", self.basis.name()),
        };
        let unit = self.unit.map_or(String::new(), |u| format!(" in {u}"));
        let within = match self.layout {
            Layout::Sizes => String::new(),
            _ => format!(", {} within a class", self.within.name()),
        };
        let words = if self.size_word == "radius" {
            "radii"
        } else {
            "diameters"
        };
        format!(
            "r from {} ({layout}, {words}{unit}{within})",
            self.source.display()
        )
    }
}

fn class(lo: Real, hi: Real) -> SizeClass {
    SizeClass {
        lo,
        hi,
        number: 0.0,
    }
}

/// The fields of a row: separated by commas, semicolons or tabs, or else by
/// spaces (so that a header `diameter (um),mass %` keeps its words together).
fn fields(line: &str) -> Vec<&str> {
    let delimited = line.contains([',', ';', '\t']);
    line.split(|c: char| {
        if delimited {
            c == ',' || c == ';' || c == '\t'
        } else {
            c.is_whitespace()
        }
    })
    .map(str::trim)
    .filter(|f| !f.is_empty())
    .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    #[test]
    fn a_files_radii_make_a_table_of_its_sizes_by_number() {
        let t = SizeTable::of_radii(&[2.0, 1.0, 2.0, 1.5], Path::new("m.csv"));
        assert_eq!(t.bounds(), (1.0, 2.0));
        let shares: Vec<(Real, Real)> = t.classes().iter().map(|c| (c.lo, c.number)).collect();
        assert_eq!(shares, [(1.0, 0.25), (1.5, 0.25), (2.0, 0.5)]);
        assert_eq!(t.cumulative.last(), Some(&1.0));
        assert!(
            t.describe().contains("3 sizes by number"),
            "{}",
            t.describe()
        );
    }

    fn table(text: &str, unit: Option<Real>) -> Result<SizeTable> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("psd.csv");
        std::fs::write(&path, text).unwrap();
        SizeTable::read(&path, Within::LogUniform, unit)
    }

    fn refusal(text: &str, unit: Option<Real>) -> String {
        let e = table(text, unit).expect_err(text).to_string();
        assert!(!e.contains('\n'), "one line: {e}");
        assert!(e.contains("psd.csv:"), "names the file: {e}");
        e
    }

    #[test]
    fn sizes_whose_cubes_overflow_or_vanish_are_refused() {
        // Found by the fuzzer (fuzz/regressions/psd_table): a 1e100 radius
        // made the mean cube infinite and every weight NaN.
        for (text, unit) in [
            ("radius,number\n1e100,1\n", None),
            ("radius,number\n1e-200,1\n2e-200,1\n", None),
            ("diameter_um,mass_percent\n1e40,100\n", Some(1e-6)),
        ] {
            let e = refusal(text, unit);
            assert!(e.contains("must lie between 1e-30 and 1e30"), "{e}");
        }
        // Converted to the bed's unit first: 1e33 nm is 1e24 m.
        assert!(table("diameter_nm,number\n1e33,1\n", Some(1.0)).is_ok());
    }

    fn draws(t: &SizeTable, n: usize) -> Vec<Real> {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        (0..n).map(|_| t.sample(&mut rng)).collect()
    }

    #[test]
    fn diameters_by_mass_become_radii_by_number() {
        // The file that was once read as radii 10 and 20 with number weights 1:1.
        let t = table("diameter_um,mass_percent\n10,50\n20,50\n", Some(1e-6)).unwrap();
        assert_eq!(t.bounds(), (5.0, 10.0));
        // Equal masses: eight radius-5 particles weigh what one radius-10 does.
        let c = t.classes();
        assert!((c[0].number - 8.0 / 9.0).abs() < 1e-15);
        let d = draws(&t, 90_000);
        let small = d.iter().filter(|&&r| r == 5.0).count() as Real / d.len() as Real;
        assert!((small - 8.0 / 9.0).abs() < 0.005, "{small}");
        assert!((t.volume_passing(5.0) - 0.5).abs() < 1e-15);
        // The same file in a bed measured in mm.
        let mm = table("diameter_um,mass_percent\n10,50\n20,50\n", Some(1e-3)).unwrap();
        assert!((mm.bounds().1 - 0.01).abs() < 1e-15);
    }

    #[test]
    fn headers_that_do_not_say_what_they_hold_are_refused() {
        let e = refusal("6,0.10\n8,0.25\n", None);
        assert!(e.contains("no header") && e.contains("`6,0.10`"), "{e}");
        assert!(e.contains(ACCEPTED_HEADERS), "{e}");
        let e = refusal("size,amount\n6,0.1\n", None);
        assert!(e.contains("unknown header `size,amount`"), "{e}");
        assert!(e.contains(ACCEPTED_HEADERS), "{e}");
        let e = refusal("radius,weight\n6,0.1\n", None);
        assert!(e.contains("number") && e.contains("mass"), "{e}");
        // A weight column that does not say number, volume or mass.
        refusal("diameter_min,diameter_max,fraction\n1,2,1\n", None);
        // A unit with no unit for the bed.
        let e = refusal("diameter_um,number\n6,1\n", None);
        assert!(e.contains("length_unit"), "{e}");
        // Classes whose edges are not of one kind.
        refusal("diameter_min,radius_max,mass\n1,2,1\n", None);
        refusal("", None);
    }

    #[test]
    fn headers_as_instruments_write_them_are_read() {
        for text in [
            "Diameter (µm);Mass %\n10;50\n20;50\n",
            "diameter_um\tmass_percent\n10\t50\n20\t50\n",
            "# sieve report\ndiameter um , mass fraction\n10, 0.5\n20, 0.5\n",
        ] {
            let t = table(text, Some(1e-6)).unwrap_or_else(|e| panic!("{text}: {e}"));
            assert_eq!(t.bounds(), (5.0, 10.0), "{text}");
            assert_eq!(t.basis, Basis::Mass);
        }
    }

    #[test]
    fn sieve_classes_are_drawn_within_their_edges() {
        let t = table(
            "diameter_min_um,diameter_max_um,mass_percent\n20,40,30\n40,80,50\n80,160,20\n160,320,0\n",
            Some(1e-6),
        )
        .unwrap();
        assert_eq!(t.layout, Layout::Classes);
        // The empty top class draws nothing and does not widen the bed's sizes.
        assert_eq!(t.bounds(), (10.0, 80.0));
        let d = draws(&t, 200_000);
        assert!(d.iter().all(|&r| (10.0..=80.0).contains(&r)));
        // Not collapsed onto one size per class: many distinct radii.
        let mut distinct = d.clone();
        distinct.sort_by(Real::total_cmp);
        distinct.dedup();
        assert!(distinct.len() > 100_000);
        // Log-uniform within a class: as many draws in [10, 10√2] as in [10√2, 20].
        let mid = 10.0 * 2f64.sqrt();
        let a = d.iter().filter(|&&r| r < mid).count() as Real;
        let b = d.iter().filter(|&&r| (mid..20.0).contains(&r)).count() as Real;
        assert!((a / b - 1.0).abs() < 0.03, "{a} {b}");
        // The draws' mass shares are the table's.
        let mass = |lo: Real, hi: Real| -> Real {
            d.iter()
                .filter(|&&r| lo <= r && r < hi)
                .map(|r| r * r * r)
                .sum()
        };
        let all = mass(0.0, 1e9);
        for (lo, hi, share) in [(10.0, 20.0, 0.3), (20.0, 40.0, 0.5), (40.0, 80.1, 0.2)] {
            let s = mass(lo, hi) / all;
            assert!((s - share).abs() < 0.01, "[{lo}, {hi}): {s}");
            assert!((t.volume_passing(hi.min(80.0)) - t.volume_passing(lo) - share).abs() < 1e-12);
        }
    }

    #[test]
    fn a_passing_curve_is_its_classes() {
        let curve = table(
            "diameter_um,percent_passing\n20,0\n40,30\n80,80\n160,100\n",
            Some(1e-6),
        )
        .unwrap();
        let classes = table(
            "diameter_min_um,diameter_max_um,mass_percent\n20,40,30\n40,80,50\n80,160,20\n",
            Some(1e-6),
        )
        .unwrap();
        assert_eq!(curve.classes(), classes.classes());
        assert_eq!(curve.layout, Layout::Passing);
        assert_eq!(curve.basis, Basis::Mass);
        // The curve read back at its own sizes.
        for (d, p) in [(20.0, 0.0), (40.0, 0.3), (80.0, 0.8), (160.0, 1.0)] {
            assert!((curve.volume_passing(d / 2.0) - p).abs() < 1e-12, "{d}");
        }
        let uniform = SizeTable::read(&curve.source, Within::Uniform, Some(1e-6));
        assert!(uniform.is_err(), "the file is gone with its directory");
    }

    /// The mass-median diameter of a table read in mm.
    fn d_mass(t: &SizeTable, q: Real) -> Real {
        let (lo, hi) = t.bounds();
        2.0 * crate::species::passing_quantile(lo, hi, q, |x| t.volume_passing(x))
    }

    #[test]
    fn a_lab_sieve_table_is_the_mass_retained_between_apertures() {
        // 30 % stays on the 0.25 mm sieve (it passed 0.5 mm), 50 % on 0.125 mm,
        // 20 % in the pan. By hand: 20 % passes 0.125 mm and 70 % passes
        // 0.25 mm; d50 lies 0.6 of the way through the 0.125–0.25 class by
        // mass, and log-uniform by number puts mass ∝ d² dd in a class:
        // d50³ = 0.125³ + 0.6 (0.25³ − 0.125³), d50 = 0.216560 mm.
        let text = "Sieve (mm);Retained %\n0.5;0\n0.25;30\n0.125;50\npan;20\n";
        let t = table(text, Some(1e-3)).unwrap();
        assert_eq!(t.layout, Layout::Retained);
        assert_eq!(t.basis, Basis::Mass);
        assert!((d_mass(&t, 0.5) - 0.216_559_776_335_225_7).abs() < 1e-9);
        assert!((t.volume_passing(0.125 / 2.0) - 0.2).abs() < 1e-12);
        assert!((t.volume_passing(0.25 / 2.0) - 0.7).abs() < 1e-12);
        // The pan by default from half the finest aperture: d10 by hand is
        // (0.0625³ + 0.5 (0.125³ − 0.0625³))^⅓ = 0.103185 mm.
        assert_eq!(t.bounds().0, 0.0625 / 2.0);
        assert!((d_mass(&t, 0.1) - 0.103_185_226_527_957_1).abs() < 1e-9);
        // Or from the size the config states, in the table's unit.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sieve.csv");
        std::fs::write(&path, text).unwrap();
        let options = TableOptions {
            within: Within::LogUniform,
            pan_min: Some(0.1),
        };
        let t = SizeTable::read_with(&path, &options, Some(1e-3)).unwrap();
        assert!((d_mass(&t, 0.1) - 0.113_872_086_445_337_4).abs() < 1e-9);
        // The same apertures read as discrete sizes, as before a sieve
        // layout existed: the d50 falls to the 0.25 mm size itself.
        let sizes = table(
            "diameter_mm,mass_percent\n0.25,30\n0.125,50\n0.0625,20\n",
            Some(1e-3),
        );
        assert!((d_mass(&sizes.unwrap(), 0.5) - 0.216_56).abs() > 0.03);
        // A table with no pan holds nothing finer than its finest sieve.
        let t = table(
            "sieve_um,retained_percent\n90,0\n63,40\n45,60\n",
            Some(1e-6),
        )
        .unwrap();
        assert_eq!(t.bounds(), (22.5, 45.0));
    }

    #[test]
    fn sieve_tables_that_do_not_say_what_they_hold_are_refused() {
        // The largest sieve holds something: no upper size.
        let e = refusal("sieve_mm,retained_percent\n0.5,5\n0.25,95\n", Some(1e-3));
        assert!(
            e.contains("psd.csv:2:") && e.contains("largest sieve, 0.5"),
            "{e}"
        );
        // Apertures with plain weights: retained or passing?
        let e = refusal("sieve_mm,mass_percent\n0.5,0\n0.25,100\n", Some(1e-3));
        assert!(
            e.contains("psd.csv:1:") && e.contains("retained_percent"),
            "{e}"
        );
        // Cumulative retained is not the mass on each sieve.
        let e = refusal(
            "sieve_mm,cumulative_percent_retained\n0.5,0\n0.25,100\n",
            Some(1e-3),
        );
        assert!(
            e.contains("psd.csv:1:") && e.contains("both passing and retained"),
            "{e}"
        );
        let e = refusal("radius_mm,retained_percent\n0.5,0\n0.25,100\n", Some(1e-3));
        assert!(e.contains("not a radius"), "{e}");
        let e = refusal(
            "sieve_mm,retained_percent\n0.5,0\npan,50\n0.25,25\npan,25\n",
            Some(1e-3),
        );
        assert!(
            e.contains("psd.csv:5:") && e.contains("pan appears twice"),
            "{e}"
        );
        // A pan edge at or above the finest sieve.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("psd.csv");
        std::fs::write(&path, "sieve_mm,retained_percent\n0.5,0\n0.25,80\npan,20\n").unwrap();
        let options = TableOptions {
            within: Within::LogUniform,
            pan_min: Some(0.3),
        };
        let e = SizeTable::read_with(&path, &options, Some(1e-3))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("pan_min 0.3") && e.contains("finest sieve, 0.25"),
            "{e}"
        );
        // Sieve apertures with a passing curve are a cumulative curve.
        let t = table(
            "sieve_mm,percent_passing\n0.125,0\n0.25,40\n0.5,100\n",
            Some(1e-3),
        );
        assert_eq!(t.unwrap().layout, Layout::Passing);
    }

    #[test]
    fn curves_that_leave_sizes_out_are_refused() {
        let e = refusal("diameter,percent_passing\n20,5\n40,100\n", None);
        assert!(e.contains("starts at 5 % passing"), "{e}");
        let e = refusal("diameter,percent_passing\n20,0\n40,90\n", None);
        assert!(e.contains("ends at 90 % passing"), "{e}");
        let e = refusal(
            "diameter,percent_passing\n20,0\n40,60\n60,50\n80,100\n",
            None,
        );
        assert!(e.contains("never falls"), "{e}");
        refusal("diameter,percent_passing\n20,0\n20,100\n", None);
        let e = refusal("diameter_min,diameter_max,mass\n10,30,1\n20,40,1\n", None);
        assert!(e.contains("overlap"), "{e}");
        let e = refusal("diameter_min,diameter_max,mass\n0,30,1\n", None);
        assert!(e.contains("positive"), "{e}");
    }

    #[test]
    fn a_number_table_keeps_its_weights_and_its_median() {
        let t = table("radius,number\n30,1\n10,2\n20,1.5\n", None).unwrap();
        // By radius: 10 → 2/4.5 = 0.44, 20 → 0.78: the number median is 20.
        assert_eq!(t.median(), 20.0);
        assert!((t.number_passing(10.0) - 2.0 / 4.5).abs() < 1e-15);
        assert_eq!(t.sizes(), vec![10.0, 20.0, 30.0]);
    }

    #[test]
    fn sizes_that_fit_keep_their_class_spread() {
        let t = table("radius_min,radius_max,number\n1,2,1\n2,4,1\n", None).unwrap();
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
        for _ in 0..1000 {
            let r = t.sample_at_most(3.0, &mut rng).unwrap();
            assert!((1.0..=3.0).contains(&r));
        }
        assert_eq!(t.sample_at_most(0.5, &mut rng), None);
    }

    proptest::proptest! {
        #[test]
        fn any_text_is_read_or_refused_never_a_panic(
            header in proptest::sample::select(vec![
                "diameter_um,mass_percent",
                "radius_min,radius_max,number",
                "diameter,percent_passing",
                "diameter_mm,number_fraction_passing",
                "radius,volume",
                "x,y",
                "",
            ]),
            rows in proptest::collection::vec(
                (-5.0f64..500.0, -5.0f64..500.0, -1.0f64..120.0),
                0..12,
            ),
            junk in "[0-9a-z,;.e+\\- \t]{0,40}",
            commented in proptest::bool::ANY,
        ) {
            // Rows of the header's width (a curve's sizes increasing), then
            // a line of junk, which a `#` sometimes makes a comment.
            let width = header.split(',').count();
            let mut text = format!("{header}\n");
            let mut size = 0.0;
            for (a, b, c) in &rows {
                size += a.abs() + 1.0;
                match width {
                    3 => text.push_str(&format!("{a},{b},{c}\n")),
                    _ if header.contains("passing") => text.push_str(&format!("{size},{c}\n")),
                    _ => text.push_str(&format!("{a},{c}\n")),
                }
            }
            if commented {
                text.push('#');
            }
            text.push_str(&junk);
            if let Ok(t) = table(&text, Some(1e-6)) {
                let (lo, hi) = t.bounds();
                proptest::prop_assert!(lo > 0.0 && lo <= hi && hi.is_finite());
                let total: Real = t.classes().iter().map(|c| c.number).sum();
                proptest::prop_assert!((total - 1.0).abs() < 1e-9);
                proptest::prop_assert!(t.mean_cube().is_finite() && t.mean_cube() > 0.0);
                let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
                for _ in 0..20 {
                    let r = t.sample(&mut rng);
                    proptest::prop_assert!(lo <= r && r <= hi);
                }
                proptest::prop_assert!((t.volume_passing(hi) - 1.0).abs() < 1e-9);
            }
        }
    }
}
