//! Atomic output: every file of a run is first written to a temporary file in the
//! output directory, and only renamed to its real name once all of them are
//! complete. An interrupted or failed run therefore never leaves a half-written
//! file under a name that looks finished, and a run that fails before its first
//! file leaves no directory behind.
//!
//! Temporary files are named `.NAME.PID.tmp`. Those being written are listed
//! in a registry, so that a handler of SIGINT/SIGTERM can remove them
//! ([`abandon_in_flight`]); those a killed process left behind (SIGKILL, power
//! loss) are removed by the next [`Staging`] of the same directory once their
//! process is gone.

use crate::error::{Error, Result};
use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// Temporary files being written by this process, in any thread.
static IN_FLIGHT: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn in_flight() -> MutexGuard<'static, Vec<PathBuf>> {
    // A thread that panicked while holding the lock left a valid list.
    IN_FLIGHT.lock().unwrap_or_else(|e| e.into_inner())
}

/// Creates `tmp` and registers it, under the registry's lock, so that a
/// signal handler never misses a file that exists.
fn create_tracked(tmp: &Path) -> std::io::Result<File> {
    let mut list = in_flight();
    let file = File::create(tmp)?;
    list.push(tmp.to_path_buf());
    Ok(file)
}

fn untrack(tmp: &Path) {
    let mut list = in_flight();
    if let Some(k) = list.iter().rposition(|p| p == tmp) {
        list.swap_remove(k);
    }
}

/// Removes every temporary file this process is writing, for a handler of
/// SIGINT or SIGTERM that ends the process right after. The registry stays
/// locked for good, so that no thread can start another file meanwhile (it
/// waits for an exit that is about to come).
pub fn abandon_in_flight() {
    let list = in_flight();
    for tmp in list.iter() {
        let _ = fs::remove_file(tmp);
    }
    std::mem::forget(list);
}

/// The temporary file name of `name` for process `pid`.
fn temp_name(name: &str, pid: u32) -> String {
    format!(".{name}.{pid}.tmp")
}

/// The process id in a temporary file name of packbed's (`.NAME.PID.tmp`).
fn temp_pid(file_name: &str) -> Option<u32> {
    let inner = file_name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (name, pid) = inner.rsplit_once('.')?;
    if name.is_empty() || pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pid.parse().ok()
}

/// Whether process `pid` may be running. Without `/proc` nothing can be told,
/// and every process counts as running (its files are left alone).
fn process_may_run(pid: u32) -> bool {
    let proc = Path::new("/proc");
    pid == std::process::id() || !proc.join("self").exists() || proc.join(pid.to_string()).exists()
}

/// Removes the temporary files of packbed's naming in `dir` whose process is
/// gone (killed before it could tidy up). Best effort: a file that cannot be
/// removed is left as it was.
fn remove_stale(dir: &Path) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(pid) = name.to_str().and_then(temp_pid) else {
            continue;
        };
        if !process_may_run(pid) && e.file_type().is_ok_and(|t| t.is_file()) {
            let _ = fs::remove_file(e.path());
        }
    }
}

/// An output directory being filled: files are staged, then committed together.
#[derive(Debug)]
pub struct Staging {
    dir: PathBuf,
    /// Directories this staging created, outermost first, removed again on failure.
    created: Vec<PathBuf>,
    /// (temporary path, final path) of each staged file, in commit order.
    staged: Vec<(PathBuf, PathBuf)>,
    committed: bool,
    /// Flush each file to the disk before renaming it (see [`Staging::without_sync`]).
    sync: bool,
}

fn io_err(path: &Path, source: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

impl Staging {
    /// Creates `dir` (and missing parents) to stage files in.
    pub fn new(dir: &Path) -> Result<Staging> {
        let mut missing = Vec::new();
        let mut p = Some(dir);
        while let Some(d) = p {
            if d.as_os_str().is_empty() || d.exists() {
                break;
            }
            // A link to nowhere: creating the directory would fail with a
            // bare "File exists" that names neither the link nor its target.
            if let Ok(target) = fs::read_link(d) {
                return Err(io_err(
                    d,
                    std::io::Error::other(format!(
                        "a symbolic link to {}, which does not exist (create that directory, or \
                         remove the link)",
                        target.display()
                    )),
                ));
            }
            missing.push(d.to_path_buf());
            p = d.parent();
        }
        missing.reverse();
        let mut staging = Staging {
            dir: dir.to_path_buf(),
            created: Vec::new(),
            staged: Vec::new(),
            committed: false,
            sync: true,
        };
        for d in missing {
            match fs::create_dir(&d) {
                Ok(()) => staging.created.push(d),
                // Another writer (a parallel replicate) made it meanwhile: it is
                // theirs to keep, not ours to remove on failure.
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && d.is_dir() => {}
                Err(e) => return Err(io_err(&d, e)),
            }
        }
        if !dir.is_dir() {
            return Err(io_err(
                dir,
                std::io::Error::other("exists and is not a directory"),
            ));
        }
        if staging.created.is_empty() {
            remove_stale(dir);
        }
        Ok(staging)
    }

    /// Skips the flush to disk before each rename. The rename stays atomic, so a
    /// killed process still leaves no half-written file under its final name;
    /// only a power failure can. For many small files that are cheap to redo
    /// (an ensemble's per-replicate summaries, which are checked on resume), the
    /// flush would cost more than the work.
    pub fn without_sync(mut self) -> Staging {
        self.sync = false;
        self
    }

    /// Writes `name` (a plain file name) to a temporary file through `fill`.
    /// A file that cannot be written (a full disk, say) is removed again at
    /// once, so that the files staged before it can still be committed and
    /// the space it took is free for the next.
    pub fn stage(
        &mut self,
        name: &str,
        fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
    ) -> Result<()> {
        let staged = self.staged.len();
        let done = self.stage_file(name, fill);
        if done.is_err() {
            for (tmp, _) in self.staged.drain(staged..) {
                let _ = fs::remove_file(&tmp);
                untrack(&tmp);
            }
        }
        done
    }

    /// True when no file is staged.
    pub fn is_empty(&self) -> bool {
        self.staged.is_empty()
    }

    /// Removes the staged file `name` again (to free its space for another).
    pub fn unstage(&mut self, name: &str) {
        let target = self.dir.join(name);
        self.staged.retain(|(tmp, t)| {
            let keep = *t != target;
            if !keep {
                let _ = fs::remove_file(tmp);
                untrack(tmp);
            }
            keep
        });
    }

    fn stage_file(
        &mut self,
        name: &str,
        fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
    ) -> Result<()> {
        let target = self.dir.join(name);
        // Hidden and named after the process, so that two runs into the same
        // directory never write the same temporary file.
        let tmp = self.dir.join(temp_name(name, std::process::id()));
        let file = create_tracked(&tmp).map_err(|e| io_err(&tmp, e))?;
        // Registered before writing, so that a failure below still removes it.
        self.staged.push((tmp.clone(), target.clone()));
        let mut w = BufWriter::new(file);
        fill(&mut w)
            .and_then(|()| w.flush())
            .map_err(|e| io_err(&target, e))?;
        let file = w
            .into_inner()
            .map_err(|e| io_err(&target, e.into_error()))?;
        // The data must be on disk before the rename makes it visible.
        if self.sync {
            file.sync_all().map_err(|e| io_err(&target, e))?;
        }
        Ok(())
    }

    /// Renames every staged file to its final name, in the order staged.
    pub fn commit(mut self) -> Result<Vec<PathBuf>> {
        self.rename_all()
    }

    fn rename_all(&mut self) -> Result<Vec<PathBuf>> {
        let mut done = Vec::with_capacity(self.staged.len());
        for (tmp, target) in &self.staged {
            fs::rename(tmp, target).map_err(|e| io_err(target, e))?;
            untrack(tmp);
            done.push(target.clone());
        }
        self.committed = true;
        Ok(done)
    }

    /// [`Staging::commit`], then removes the files of the directory that
    /// were not just committed and that `earlier` names as another run's
    /// (plain files only: hidden files and subdirectories are kept).
    pub fn commit_replacing(mut self, earlier: impl Fn(&str) -> bool) -> Result<Vec<PathBuf>> {
        let done = self.rename_all()?;
        if let Ok(entries) = fs::read_dir(&self.dir) {
            for e in entries.flatten() {
                let path = e.path();
                let stale = e.file_name().to_str().is_some_and(|n| {
                    !n.starts_with('.')
                        && earlier(n)
                        && !done.iter().any(|d| d.file_name() == path.file_name())
                });
                if stale && e.file_type().is_ok_and(|t| t.is_file()) {
                    fs::remove_file(&path).map_err(|e| io_err(&path, e))?;
                }
            }
        }
        Ok(done)
    }
}

/// Checks that files can be written into `dir` before any long work: creates
/// it (and missing parents), writes and removes a hidden probe file, then
/// removes again the directories it created. A run that would fail only when
/// writing its results thus fails at once, and leaves nothing behind.
pub fn probe_dir(dir: &Path) -> Result<()> {
    let staging = Staging::new(dir)?;
    let probe = dir.join(temp_name("packbed-probe", std::process::id()));
    let written = create_tracked(&probe).and_then(|mut f| f.write_all(b"probe"));
    // Whether or not the write worked, the probe must not stay.
    let _ = fs::remove_file(&probe);
    untrack(&probe);
    // Dropped uncommitted: the directories it created are removed again.
    drop(staging);
    // Said as what failed: the directory may exist and still refuse files
    // (/proc, a read-only mount), where the system's bare error misleads.
    written.map_err(|e| {
        io_err(
            dir,
            std::io::Error::new(e.kind(), format!("cannot create a file in it ({e})")),
        )
    })
}

impl Drop for Staging {
    fn drop(&mut self) {
        if self.committed {
            return;
        }
        // Best effort: the run has already failed, and the error that matters is
        // the one being reported, not a failure to tidy up.
        for (tmp, _) in &self.staged {
            let _ = fs::remove_file(tmp);
            untrack(tmp);
        }
        for d in self.created.iter().rev() {
            let _ = fs::remove_dir(d);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("packbed-atomic-{tag}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn commit_makes_files_visible() {
        let root = scratch("commit");
        let dir = root.join("a/b");
        let mut s = Staging::new(&dir).unwrap();
        s.stage("x.txt", |w| w.write_all(b"hello")).unwrap();
        assert!(!dir.join("x.txt").exists());
        s.commit().unwrap();
        assert_eq!(fs::read_to_string(dir.join("x.txt")).unwrap(), "hello");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn parallel_writers_share_a_new_parent() {
        // Replicates of an ensemble stage into runs/NNNN at the same time; the
        // parent they both create must not make either fail.
        let root = scratch("parallel");
        std::thread::scope(|sc| {
            for k in 0..8 {
                let dir = root.join("runs").join(format!("{k:04}"));
                sc.spawn(move || {
                    let mut s = Staging::new(&dir).unwrap();
                    s.stage("x.txt", |w| w.write_all(b"x")).unwrap();
                    s.commit().unwrap();
                });
            }
        });
        assert_eq!(fs::read_dir(root.join("runs")).unwrap().count(), 8);
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn probe_leaves_nothing() {
        let root = scratch("probe");
        probe_dir(&root.join("a/b")).unwrap();
        assert!(!root.exists());
        fs::create_dir(&root).unwrap();
        probe_dir(&root).unwrap();
        assert_eq!(fs::read_dir(&root).unwrap().count(), 0);
        // Below a file: refused.
        fs::write(root.join("f"), "x").unwrap();
        assert!(probe_dir(&root.join("f/out")).is_err());
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn temp_names_and_their_process() {
        assert_eq!(temp_pid(&temp_name("particles.csv", 4321)), Some(4321));
        assert_eq!(temp_pid(".summary.json.17.tmp"), Some(17));
        for other in [
            "particles.csv",
            ".particles.csv.tmp",
            ".particles.csv.12a.tmp",
            "..12.tmp",
            "x.particles.csv.12.tmp",
            ".particles.csv.12.tmp~",
        ] {
            assert_eq!(temp_pid(other), None, "{other}");
        }
    }

    #[test]
    fn failure_leaves_nothing() {
        let root = scratch("fail");
        let dir = root.join("out");
        {
            let mut s = Staging::new(&dir).unwrap();
            s.stage("x.txt", |w| w.write_all(b"complete")).unwrap();
            let e = s.stage("y.txt", |w| {
                w.write_all(b"half")?;
                Err(std::io::Error::other("disk full"))
            });
            assert!(e.is_err());
        }
        assert!(!root.exists());
    }
}
