//! The value parsers of the command's options, and the command-line
//! overrides of the common config settings (so that a config
//! file is optional): parsed here, applied by the library's
//! [`packbed::Overrides`], the same edits a sweep makes.

use clap::Args;
use packbed::{parse_numbers, BoxSpec, Measure, Mode};

/// `10,20` → numbers, for clap.
pub fn numbers(text: &str) -> std::result::Result<Numbers, String> {
    parse_numbers(text)
}

/// A whole number of at least 1, for clap.
pub fn at_least_one(text: &str) -> std::result::Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("`{text}`: must be a whole number, at least 1")),
    }
}

/// A comma-separated list of numbers, one option value (an alias, so that clap
/// takes it as one value and not as a repeated option).
pub type Numbers = Vec<f64>;

/// The overrides of `packbed run` and `packbed ensemble`.
#[derive(Debug, Default, Args)]
pub struct Overrides {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=3))]
    pub dim: Option<u8>,
    /// Radii of the species, e.g. 10,20 (one species per radius).
    #[arg(long, value_name = "R,R,...", allow_hyphen_values = true, value_parser = numbers)]
    pub radii: Option<Numbers>,
    /// Number ratios of the species, e.g. 1,2 (one per species).
    #[arg(long, value_name = "N,N,...", allow_hyphen_values = true, value_parser = numbers)]
    pub ratio: Option<Numbers>,
    /// Make every species a rigid chain of N beads.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub beads: Option<u32>,
    /// Box: thesis | W,H | W,D,H | diameters=N.
    #[arg(long = "box", value_name = "BOX", allow_hyphen_values = true)]
    pub container: Option<BoxSpec>,
    /// Periodic side boundaries (no side walls).
    #[arg(long)]
    pub periodic: bool,
    /// Place exactly N particles (the roof is ignored).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub count: Option<u64>,
    /// Seed of the random generator.
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub seed: Option<u64>,
    /// deposit (drop and roll) or rsa (random sequential addition).
    #[arg(long, value_parser = named::<Mode>(&["deposit", "rsa"]))]
    pub mode: Option<Mode>,
    /// Percolation threshold: particles with radius >= R count as large.
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub large: Option<f64>,
    #[command(flatten)]
    pub measures: MeasuresArg,
}

/// `--measures`, shared with `packbed analyze`.
#[derive(Debug, Default, Args)]
pub struct MeasuresArg {
    /// Measures to compute, e.g. packing,coordination (default: packing,
    /// coordination, percolation, voids, orientation, segregation; add pores
    /// and permeability for the pore space, or all).
    #[arg(long = "measures", value_name = "LIST", value_parser = measure_list)]
    pub list: Option<MeasureList>,
}

/// A comma-separated list of measures, one option value (an alias, as [`Numbers`]).
pub type MeasureList = Vec<Measure>;

fn measure_list(text: &str) -> std::result::Result<MeasureList, String> {
    Measure::parse_list(text)
}

impl Overrides {
    /// The library's overrides.
    pub fn settings(&self) -> packbed::Overrides {
        packbed::Overrides {
            dim: self.dim,
            radii: self.radii.clone(),
            ratio: self.ratio.clone(),
            beads: self.beads,
            container: self.container.clone(),
            periodic: self.periodic,
            count: self.count,
            seed: self.seed,
            mode: self.mode,
            large: self.large,
            measures: self.measures.list.clone(),
        }
    }
}

/// A value the library parses (`--load shear`), for clap.
pub fn parsed<T: std::str::FromStr<Err = packbed::Error>>(
    text: &str,
) -> std::result::Result<T, String> {
    text.parse().map_err(|e: packbed::Error| e.message())
}

/// One of `names`, spelt as in a config file (`um`) and read as the library
/// reads it there, for clap (which lists `names` in the help).
pub fn named<T>(names: &'static [&'static str]) -> impl clap::builder::TypedValueParser<Value = T>
where
    T: serde::de::DeserializeOwned + Clone + Send + Sync + 'static,
{
    use clap::builder::TypedValueParser;
    use serde::de::value::{Error, StrDeserializer};
    clap::builder::PossibleValuesParser::new(names).try_map(|s: String| {
        T::deserialize(StrDeserializer::<Error>::new(&s)).map_err(|e| e.to_string())
    })
}
