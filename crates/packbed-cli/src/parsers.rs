//! The value parsers of the command's own options. The options of the
//! library's settings (the overrides of `run`, `ensemble` and `slurm`, the
//! analysis of `analyze`, the bench bed, the Slurm resources) are the
//! library's structs themselves, through its `cli` feature.

/// A whole number of at least 1, for clap.
pub fn at_least_one(text: &str) -> std::result::Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("`{text}`: must be a whole number, at least 1")),
    }
}

/// A value the library parses (`--load shear`), for clap.
pub fn parsed<T: std::str::FromStr<Err = packbed::Error>>(
    text: &str,
) -> std::result::Result<T, String> {
    text.parse().map_err(|e: packbed::Error| e.message())
}
