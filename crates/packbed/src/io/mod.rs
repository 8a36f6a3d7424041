//! Files: the tables (`particles.csv`, `contacts.csv`, `wall_contacts.csv`),
//! `summary.json`, exports and readers, and the atomic staging of an output
//! directory. Layouts are in `spec/interfaces.md`; [`crate::output`] puts a
//! run's files together.

pub mod atomic;
pub mod export;
mod finite;
pub mod fragmentation;
pub mod pores;
pub mod psd;
pub mod read;
pub mod summary;
pub mod tables;

pub use atomic::Staging;
pub use summary::{AnalyzeSummary, RunSummary, Timing};

/// The text of an input file (bed file, config, PSD table). A file that is
/// not UTF-8 is refused at the line and column of its first bad byte, as any
/// other bad content is (`FILE:LINE: what`), not with the system's bare
/// "stream did not contain valid UTF-8".
pub fn read_text(path: &std::path::Path) -> crate::error::Result<String> {
    use crate::error::Error;
    // Held whole while it is parsed: a file larger than memory would abort.
    if let Ok(m) = std::fs::metadata(path) {
        crate::config::check_memory(
            m.len() as crate::math::Real,
            &format!("reading {}", path.display()),
        )?;
    }
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let at = e.utf8_error().valid_up_to();
        let line_start = bytes[..at]
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |k| k + 1);
        Error::Data {
            path: path.to_path_buf(),
            line: 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count(),
            message: format!(
                "not UTF-8 text: byte 0x{:02x} at column {} (save the file as UTF-8 or ASCII)",
                bytes[at],
                at - line_start + 1
            ),
        }
    })
}
