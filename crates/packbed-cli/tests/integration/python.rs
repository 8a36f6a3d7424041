//! The Python package's pytest suite (`python/tests`), run from `cargo test`
//! so that one command tests everything. It needs a Python with the package
//! installed (`pip install './python[test,notebook]'`), named by
//! `PACKBED_PYTHON`; without it the test says "skipped: …" and passes, and
//! `PACKBED_REQUIRE_PYTHON=1` (set by `.ci/run`, which makes that Python in a
//! fresh virtual environment) turns the skip into a failure. The suite
//! compares the package with this very build of the command.

use std::path::Path;
use std::process::Command;

#[test]
fn python_package_suite() {
    let required = std::env::var("PACKBED_REQUIRE_PYTHON").as_deref() == Ok("1");
    let Ok(python) = std::env::var("PACKBED_PYTHON") else {
        assert!(
            !required,
            "PACKBED_REQUIRE_PYTHON=1 but PACKBED_PYTHON is not set"
        );
        eprintln!("skipped: the Python package tests (set PACKBED_PYTHON to a Python with `pip install './python[test,notebook]'`; PACKBED_REQUIRE_PYTHON=1 makes this a failure)");
        return;
    };
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut pytest = Command::new(&python);
    pytest
        .args([
            "-m",
            "pytest",
            "-q",
            "-p",
            "no:cacheprovider",
            "python/tests",
        ])
        .current_dir(&root)
        .env("PACKBED_BIN", env!("CARGO_BIN_EXE_packbed"));
    if required {
        pytest.env("PACKBED_REQUIRE_PYTHON_EXTRAS", "1");
    }
    let done = pytest
        .output()
        .unwrap_or_else(|e| panic!("cannot run {python}: {e}"));
    let report = format!(
        "{}{}",
        String::from_utf8_lossy(&done.stdout),
        String::from_utf8_lossy(&done.stderr)
    );
    assert!(done.status.success(), "python/tests failed:\n{report}");
    eprintln!("{}", report.lines().last().unwrap_or_default());
}
