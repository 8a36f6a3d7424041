//! Reading input within this machine's limits: the memory budget every
//! input-sized allocation is checked against before the work, and input
//! files as text. On the lowest floor, beside the error type, so that the
//! config, species tables and bed readers all use the same checks.

use crate::error::{Error, Result};
use std::path::Path;

/// The memory this process may use: the least of the machine's physical
/// memory (`/proc/meminfo`), the process' address-space limit (`ulimit -v`,
/// from `/proc/self/limits`; an allocation beyond it aborts just the same)
/// and its cgroup's limit (`memory.max`: what a Slurm job or a container is
/// given); 8 GiB where none is known. A cluster job that asked for 4 GB on a
/// 512 GB node must be refused at 4 GB, not killed by the scheduler later.
pub fn memory_budget_bytes() -> u64 {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let physical = read("/proc/meminfo").and_then(|m| meminfo_total(&m));
    let address_space = read("/proc/self/limits").and_then(|l| address_space_limit(&l));
    let cgroup = read("/sys/fs/cgroup/memory.max").and_then(|m| m.trim().parse::<u64>().ok());
    [physical, address_space, cgroup]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(8 << 30)
}

/// `MemTotal` of `/proc/meminfo`, in bytes.
fn meminfo_total(meminfo: &str) -> Option<u64> {
    let kb = meminfo
        .lines()
        .find(|l| l.starts_with("MemTotal:"))?
        .split_whitespace()
        .nth(1)?
        .parse::<u64>()
        .ok()?;
    Some(kb * 1024)
}

/// The soft `Max address space` of `/proc/self/limits`, in bytes (`None`
/// when unlimited).
fn address_space_limit(limits: &str) -> Option<u64> {
    limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?
        .trim_start_matches("Max address space")
        .split_whitespace()
        .next()?
        .parse::<u64>()
        .ok()
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

/// Refuses, before the work, a stage that would reserve `bytes` more of
/// address space than `ulimit -v` leaves beside what the process holds
/// (`VmSize`): an allocation beyond it aborts the process, even one whose
/// pages are never touched. Without an address-space limit, nothing to check.
pub fn check_address_space(bytes: f64, what: &str) -> Result<()> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let Some(limit) = read("/proc/self/limits").and_then(|l| address_space_limit(&l)) else {
        return Ok(());
    };
    let used = read("/proc/self/status")
        .and_then(|s| status_kib(&s, "VmSize:"))
        .map_or(0, |k| k * 1024);
    if used as f64 + bytes > limit as f64 {
        let gib = |b: f64| b / (1u64 << 30) as f64;
        return Err(Error::Impossible(format!(
            "{what} would reserve about {:.1} GiB of address space, more than the {:.1} GiB              that `ulimit -v` ({:.1} GiB) leaves",
            gib(bytes),
            gib(limit.saturating_sub(used) as f64),
            gib(limit as f64)
        )));
    }
    Ok(())
}

/// A `KEY: N kB` line of `/proc/self/status`, in KiB.
fn status_kib(status: &str, key: &str) -> Option<u64> {
    status
        .lines()
        .find(|l| l.starts_with(key))?
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_limits_are_read_from_procfs_text() {
        let meminfo = "MemTotal:       24576000 kB\nMemFree:        1000 kB\n";
        assert_eq!(meminfo_total(meminfo), Some(24_576_000 * 1024));
        let limits =
            "Limit                     Soft Limit           Hard Limit           Units     \n\
Max cpu time              unlimited            unlimited            seconds   \n\
Max address space         4294967296           unlimited            bytes     \n";
        assert_eq!(address_space_limit(limits), Some(4_294_967_296));
        let unlimited =
            "Max address space         unlimited            unlimited            bytes     \n";
        assert_eq!(address_space_limit(unlimited), None);
        assert!(memory_budget_bytes() > 0);
    }
}
