"""Ensembles from Python, locally and on a Dask LocalCluster of two worker
processes, against `packbed ensemble`: byte-identical files."""

import json

import pytest

import packbed
from conftest import optional

SETTINGS = ["--dim", "2", "--radii", "10,20", "--count", "150", "--seed", "11"]
KEYWORDS = dict(dim=2, radii=[10, 20], count=150, seed=11)

SWEEP = """dim = 2
seed = 4
[box]
diameters = 6
[[species]]
radius = 20
[[species]]
radius = 10
[sweep]
parameter = "ratio"
values = [[1, 1], [1, 3]]
"""


def test_local_ensemble_equals_the_command(tmp_path, run_cli):
    run_cli("ensemble", *SETTINGS, "--runs", "5", "--out", str(tmp_path / "cli"), "--quiet", "--no-pictures")
    stats = packbed.ensemble(runs=5, jobs=1, out=tmp_path / "py", pictures=False, **KEYWORDS)
    assert (tmp_path / "py" / "ensemble.csv").read_bytes() == (tmp_path / "cli" / "ensemble.csv").read_bytes()
    assert stats == json.loads((tmp_path / "cli" / "ensemble.json").read_text())
    assert stats["replicates"] == 5
    # Without out, the statistics alone, from a folder that is then removed.
    assert packbed.ensemble(runs=5, pictures=False, **KEYWORDS) == stats


@pytest.fixture(scope="module")
def dask_client():
    optional("distributed")
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(cluster)
    yield client
    client.close()
    cluster.close()


def test_dask_ensemble_is_byte_identical(tmp_path, run_cli, dask_client):
    run_cli("ensemble", *SETTINGS, "--runs", "7", "--out", str(tmp_path / "cli"), "--quiet", "--no-pictures")
    stats = packbed.ensemble(runs=7, out=tmp_path / "dask", client=dask_client, pictures=False, **KEYWORDS)
    for name in ("ensemble.csv", "ensemble.json", "histograms.csv", "ensemble.md"):
        assert (tmp_path / "dask" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert stats["replicates"] == 7
    # Both worker processes took part.
    assert len(dask_client.nthreads()) == 2


def test_dask_sweep_is_byte_identical(tmp_path, run_cli, dask_client):
    config = tmp_path / "sweep.toml"
    config.write_text(SWEEP)
    run_cli("ensemble", str(config), "--runs", "3", "--out", str(tmp_path / "cli"), "--quiet", "--no-pictures")
    stats = packbed.ensemble(config, runs=3, out=tmp_path / "dask", client=dask_client, pictures=False)
    assert (tmp_path / "dask" / "sweep.csv").read_bytes() == (tmp_path / "cli" / "sweep.csv").read_bytes()
    assert len(stats) == 2
    local = packbed.ensemble(config, runs=3, pictures=False)
    assert local == stats


def test_merge_of_shards(tmp_path, run_cli):
    for k in range(2):
        run_cli("ensemble", *SETTINGS, "--runs", "4", "--shard", f"{k}/2", "--out", str(tmp_path / f"s{k}"), "--quiet", "--no-pictures")
    run_cli("ensemble", *SETTINGS, "--runs", "4", "--out", str(tmp_path / "whole"), "--quiet", "--no-pictures")
    stats = packbed.merge([tmp_path / "s0", tmp_path / "s1"], tmp_path / "merged", pictures=False)
    assert (tmp_path / "merged" / "ensemble.csv").read_bytes() == (tmp_path / "whole" / "ensemble.csv").read_bytes()
    assert stats["replicates"] == 4


# A compaction cut short by its step budget: the command warns on stderr;
# Python raises the same texts as PackbedWarning (and with filterwarnings =
# error, a warning no test expects fails the suite).
SHORT = {
    "dim": 2,
    "box": {"width": 12.3, "height": 400, "periodic": True},
    "fill": {"count": 150, "base_layer": "none"},
    "species": [{"radius": 0.5}],
    "compaction": {"steps": 2},
}


def test_a_warning_of_the_command_is_a_python_warning(tmp_path):
    with pytest.warns(packbed.PackbedWarning, match=r"^compaction: stopped at its budget of 2 steps") as caught:
        bed = packbed.deposit(SHORT)
    assert [str(w.message) for w in caught] == bed.summary["warnings"]
    with pytest.warns(packbed.PackbedWarning, match=r"^2 of 2 replicates warned; the first, .*compaction: stopped"):
        packbed.ensemble(SHORT, runs=2, jobs=1, out=tmp_path / "ens", pictures=False)
    with pytest.warns(packbed.PackbedWarning, match=r"^2 of 2 replicates warned"):
        packbed.merge([tmp_path / "ens"], tmp_path / "merged", pictures=False)
    # Run to rest, nothing to say.
    whole = dict(SHORT, compaction={"steps": 0})
    bed = packbed.deposit(whole)
    packbed.ensemble(whole, runs=2, jobs=1, pictures=False)
    assert bed.summary.get("warnings", []) == []
