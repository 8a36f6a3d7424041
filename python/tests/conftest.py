"""Shared fixtures: the `packbed` command built from the same sources, to
compare the package with, and a flag that turns optional skips into failures
(CI sets PACKBED_REQUIRE_PYTHON_EXTRAS=1 after installing the extras)."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def require_extras() -> bool:
    return os.environ.get("PACKBED_REQUIRE_PYTHON_EXTRAS") == "1"


def optional(module: str):
    """Imports an optional module, or skips (fails in CI) saying which is missing."""
    try:
        return __import__(module)
    except ImportError:
        if require_extras():
            pytest.fail(f"{module} is required here (PACKBED_REQUIRE_PYTHON_EXTRAS=1) but not installed")
        pytest.skip(f"SKIP: {module} is not installed")


@pytest.fixture(scope="session")
def cli() -> str:
    """Path of the `packbed` command: $PACKBED_BIN, else target/release/packbed, else on PATH."""
    candidates = [os.environ.get("PACKBED_BIN"), str(ROOT / "target" / "release" / "packbed"), shutil.which("packbed")]
    for c in candidates:
        if c and os.access(c, os.X_OK):
            return c
    if require_extras():
        pytest.fail("the packbed command is needed (set PACKBED_BIN or build target/release/packbed)")
    pytest.skip("SKIP: no packbed command to compare with (cargo build --release -p packbed-cli)")


@pytest.fixture()
def run_cli(cli):
    def run(*args: str) -> subprocess.CompletedProcess:
        done = subprocess.run([cli, *args], capture_output=True, text=True)
        assert done.returncode == 0, f"packbed {' '.join(args)}: {done.stderr}"
        return done

    return run


@pytest.fixture(scope="session", autouse=True)
def installed_package_is_current():
    """The tests run against the installed package: refuse a stale install of
    an older python/packbed (pip install ./python again)."""
    import packbed

    installed = Path(packbed.__file__).parent
    for source in sorted((ROOT / "python" / "packbed").glob("*.py*")):
        copy = installed / source.name
        if not copy.exists() or copy.read_bytes() != source.read_bytes():
            pytest.fail(f"the installed packbed ({installed}) is not built from this tree: {source.name} differs (pip install ./python)")
