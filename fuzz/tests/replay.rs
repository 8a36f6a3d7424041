//! Every seed and every regression input of every fuzz target, replayed
//! through the target without AFL++: a crash the fuzzer found stays fixed, and
//! the seeds stay inputs the readers accept (a seed a format change turned
//! into a refusal would leave the fuzzer exploring error paths only).

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Longest a regression input may run: a hang once found must stay fixed.
const LIVENESS_SECONDS: f64 = 10.0;

type Target = fn(&[u8]) -> bool;

const TARGETS: [(&str, Target); 6] = [
    ("bed", packbed_fuzz::bed),
    ("config", packbed_fuzz::config),
    ("psd_table", packbed_fuzz::psd_table),
    ("merge", packbed_fuzz::merge),
    ("resume", packbed_fuzz::resume),
    ("compare", packbed_fuzz::compare),
];

fn inputs(kind: &str, target: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(kind)
        .join(target);
    let mut files: Vec<PathBuf> = match fs::read_dir(&dir) {
        Ok(d) => d.map(|e| e.expect("directory entry").path()).collect(),
        Err(_) => Vec::new(),
    };
    files.sort();
    files
}

#[test]
fn seeds_are_accepted_and_regressions_survived() {
    for (target, run) in TARGETS {
        let seeds = inputs("seeds", target);
        assert!(!seeds.is_empty(), "no seeds for {target}");
        for seed in seeds {
            let data = fs::read(&seed).expect("seed");
            assert!(run(&data), "{target}: seed {} is refused", seed.display());
        }
        for input in inputs("regressions", target) {
            let data = fs::read(&input).expect("regression input");
            // Accepted or refused, both fine: what it must not do is panic
            // or abort, as it once did, or run without end (the `hang-*`
            // inputs took 20 s to forever; fixed, each takes well under a
            // second). The bound is for liveness only, far from any speed.
            let start = Instant::now();
            let _ = run(&data);
            let took = start.elapsed().as_secs_f64();
            assert!(
                took < LIVENESS_SECONDS,
                "{target}: {} took {took:.0} s",
                input.display()
            );
        }
    }
    packbed_fuzz::remove_scratch();
}
