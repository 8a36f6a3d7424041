//! Reading input within this machine's limits: the memory budget every
//! input-sized allocation is checked against before the work, and input
//! files as text. On the lowest floor, beside the error type, so that the
//! config, species tables and bed readers all use the same checks.

use crate::error::{Error, Result};
use std::path::Path;

/// Physical memory of this machine (from /proc/meminfo), or 8 GiB if unknown;
/// less when the process may not address that much (`ulimit -v`), since an
/// allocation beyond that limit aborts just the same.
pub fn memory_budget_bytes() -> u64 {
    let total = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|m| {
            m.lines()
                .find(|l| l.starts_with("MemTotal:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<u64>().ok())
        })
        .map(|kb| kb * 1024)
        .unwrap_or(8 << 30);
    let limit = std::fs::read_to_string("/proc/self/limits")
        .ok()
        .and_then(|m| {
            m.lines()
                .find(|l| l.starts_with("Max address space"))
                .and_then(|l| l.split_whitespace().nth(3))
                .and_then(|b| b.parse::<u64>().ok())
        });
    limit.map_or(total, |l| total.min(l))
}

/// Refuses, before the work, what would need more than half the memory
/// [`memory_budget_bytes`] allows (the rest is the process's and the
/// system's): one line naming `what` and both sizes, where the allocation
/// would otherwise abort the process.
pub fn check_memory(bytes: f64, what: &str) -> Result<()> {
    let budget = memory_budget_bytes() as f64;
    if bytes > budget / 2.0 {
        let gib = |b: f64| b / (1u64 << 30) as f64;
        return Err(Error::Impossible(format!(
            "{what} would need about {:.1} GiB of memory, more than this machine allows \
             for it ({:.1} GiB: half of its memory)",
            gib(bytes),
            gib(budget / 2.0)
        )));
    }
    Ok(())
}

/// The text of an input file (bed file, config, PSD table). A file that is
/// not UTF-8 is refused at the line and column of its first bad byte, as any
/// other bad content is (`FILE:LINE: what`), not with the system's bare
/// "stream did not contain valid UTF-8".
pub fn read_text(path: &Path) -> Result<String> {
    // Held whole while it is parsed: a file larger than memory would abort.
    if let Ok(m) = std::fs::metadata(path) {
        check_memory(m.len() as f64, &format!("reading {}", path.display()))?;
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
