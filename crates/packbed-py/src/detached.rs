//! Long calls off the GIL: the work runs on a thread of its own while the
//! calling thread, without the GIL, waits for it and every tenth of a second
//! takes the GIL back for a moment to let Python handle signals (Ctrl-C) and
//! to report progress. On `KeyboardInterrupt` the work is asked to stop (the
//! library checks every 4096 particles, and between replicates) and its end
//! awaited, so nothing is left running or half-written.

use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;

/// What the work shares with the waiting thread.
#[derive(Default)]
pub struct Shared {
    /// Set when Python asks to stop (shared with an ensemble's options).
    pub stop: Arc<AtomicBool>,
    /// Units done (particles placed, replicates finished).
    pub done: AtomicU64,
    /// Units in all, 0 if unknown.
    pub total: AtomicU64,
}

impl Shared {
    /// Whether the work should stop.
    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

const POLL: Duration = Duration::from_millis(100);

/// Runs `work` off the GIL; `progress(done, total)` (a Python callable, or
/// None) is called from this thread now and then.
pub fn run<T, F>(py: Python<'_>, progress: Option<&Bound<'_, PyAny>>, work: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce(&Shared) -> PyResult<T> + Send,
{
    let shared = Shared::default();
    std::thread::scope(|scope| {
        let (tx, rx) = mpsc::channel();
        // Sync for `detach`; only this thread ever locks it.
        let rx = Mutex::new(rx);
        let shared_ref = &shared;
        scope.spawn(move || {
            // The receiver may be gone only if the waiting side panicked.
            let _ = tx.send(work(shared_ref));
        });
        let mut interrupted: Option<PyErr> = None;
        loop {
            let received = py.detach(|| match rx.lock() {
                Ok(r) => r.recv_timeout(POLL),
                Err(_) => Err(mpsc::RecvTimeoutError::Disconnected),
            });
            match received {
                Ok(result) => {
                    return match interrupted {
                        Some(e) => Err(e),
                        None => result,
                    };
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    return Err(crate::errors::ImpossibleError::new_err(
                        "the work thread ended without a result (please report this bug)",
                    ));
                }
            }
            if interrupted.is_some() {
                continue;
            }
            let checked = py.check_signals().and_then(|()| match progress {
                Some(p) => p
                    .call1((
                        shared.done.load(Ordering::Relaxed),
                        shared.total.load(Ordering::Relaxed),
                    ))
                    .map(drop),
                None => Ok(()),
            });
            if let Err(e) = checked {
                shared.stop.store(true, Ordering::Relaxed);
                interrupted = Some(e);
            }
        }
    })
}
