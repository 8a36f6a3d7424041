"""Beds from Python against the command: the same bed bit for bit, the same
measures, contacts, files and breakage."""

import csv
import json
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import packbed
from conftest import optional


def read_particles(path: Path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows


def test_deposit_equals_run_bit_for_bit(tmp_path, run_cli):
    run_cli("run", "--radii", "10,20", "--seed", "5", "--out", str(tmp_path / "cli"), "--quiet", "--no-pictures")
    rows = read_particles(tmp_path / "cli" / "particles.csv")
    bed = packbed.deposit(dim=3, radii=[10, 20], seed=5)
    assert len(bed) == len(rows) > 100
    # float(text) of the shortest round-trip text is the exact double written.
    expected = np.array([[float(r["x"]), float(r["y"]), float(r["z"])] for r in rows])
    assert bed.positions.shape == (len(rows), 3)
    assert bed.positions.dtype == np.float64
    assert np.array_equal(bed.positions, expected)
    assert np.array_equal(bed.radii, np.array([float(r["r"]) for r in rows]))
    assert np.array_equal(bed.species, np.array([int(r["species"]) for r in rows]))
    assert np.array_equal(bed.body, np.array([int(r["body"]) for r in rows]))
    summary = json.loads((tmp_path / "cli" / "summary.json").read_text())
    measures = bed.analyze()
    for key in ("packing", "coordination", "percolation"):
        assert measures[key] == summary[key], key
    assert bed.box == {"width": 240.0, "depth": 240.0, "height": 240.0, "periodic": False}
    assert bed.summary["counts"] == summary["counts"]


def test_arrays_share_memory_and_are_read_only():
    bed = packbed.deposit(dim=2, radii=10, count=50, seed=1)
    r = bed.radii
    assert not r.flags.writeable
    with pytest.raises(ValueError):
        r[0] = 3.0
    # Two views of one bed share the memory (zero-copy), positions are a copy.
    assert np.shares_memory(bed.radii, bed.radii)
    assert bed.positions.flags.writeable
    assert bed.positions.shape == (50, 2)
    del bed
    assert r.sum() == 500.0  # the view keeps the bed alive


def test_contacts_files_and_pandas_match_the_command(tmp_path, run_cli):
    out = tmp_path / "cli"
    run_cli("run", "--dim", "2", "--radii", "10,20", "--seed", "3", "--out", str(out), "--quiet", "--no-pictures")
    bed = packbed.deposit(dim=2, radii=[10, 20], seed=3)
    i, j, gap = bed.contacts()
    rows = read_particles(out / "contacts.csv")
    assert len(i) == len(rows) > 0
    assert np.array_equal(i, [int(r["i"]) for r in rows])
    assert np.array_equal(j, [int(r["j"]) for r in rows])
    assert np.array_equal(gap, [float(r["gap"]) for r in rows])
    pd = optional("pandas")
    frame = bed.to_pandas()
    expected = pd.read_csv(out / "particles.csv")
    assert list(frame.columns) == list(expected.columns)
    pd.testing.assert_frame_equal(frame, expected, check_dtype=False, check_exact=True)
    written = bed.write(tmp_path / "py", pictures=False)
    for name in ("particles.csv", "contacts.csv", "wall_contacts.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (out / name).read_bytes(), name
        assert tmp_path / "py" / name in written
    mine = json.loads((tmp_path / "py" / "summary.json").read_text())
    theirs = json.loads((out / "summary.json").read_text())
    for key in ("counts", "packing", "coordination", "percolation", "config"):
        assert mine[key] == theirs[key], key


def test_read_every_format_analyze_reads(tmp_path, run_cli):
    out = tmp_path / "cli"
    run_cli("run", "--dim", "2", "--radii", "10", "--count", "60", "--seed", "2", "--out", str(out), "--quiet", "--no-pictures")
    built = packbed.deposit(dim=2, radii=10, count=60, seed=2)
    bed = packbed.read(out / "particles.csv")
    assert len(bed) == 60 and bed.dim == 2
    assert np.array_equal(bed.positions, built.positions)
    assert bed.box == built.box
    assert bed.summary is None
    # A plain table needs the box; it is the three discs of the library's doc.
    table = tmp_path / "three.txt"
    table.write_text("1 1 1\n3 1 1\n5 1 1\n")
    three = packbed.read(table, box="6,4")
    coordination = three.analyze(measures=["coordination"])["coordination"]
    assert abs(coordination["mean"] - 4 / 3) < 1e-12
    assert coordination["floor_contacts"] == 3
    with pytest.raises(packbed.PackbedError):
        packbed.read(table)  # no box
    analysed = tmp_path / "analysed"
    files = three.write(analysed, pictures=False)
    assert {f.name for f in files} >= {"contacts.csv", "summary.json"}


def test_fragment_equals_the_command(tmp_path, run_cli):
    out = tmp_path / "cli"
    run_cli("run", "--dim", "2", "--radii", "10", "--count", "120", "--seed", "4", "--periodic", "--box", "200,400",
            "--out", str(out), "--quiet", "--no-pictures")
    run_cli("fragment", str(out / "particles.csv"), "--breaks", "5", "--out", str(tmp_path / "frag"), "--no-pictures", "-q")
    theirs = json.loads((tmp_path / "frag" / "summary.json").read_text())
    bed = packbed.read(out / "particles.csv")
    mine = bed.fragment(breaks=5, out=tmp_path / "pyfrag", pictures=False)
    assert mine["fragmentation"] == theirs["fragmentation"]
    for name in ("bonds.csv", "breakage.csv"):
        assert (tmp_path / "pyfrag" / name).read_bytes() == (tmp_path / "frag" / name).read_bytes(), name


def test_progress_callable_and_interrupt():
    seen = []
    bed = packbed.deposit(dim=2, radii=1, count=30000, box="600,600", periodic=True, progress=lambda d, t: seen.append((d, t)))
    assert len(bed) == 30000
    # A progress callable that raises stops the work with that exception.
    class Stop(Exception):
        pass

    def stop(done, total):
        raise Stop()

    with pytest.raises(Stop):
        packbed.deposit(dim=2, radii=1, count=400000, box="3000,3000", periodic=True, progress=stop)


def test_ctrl_c_interrupts_a_long_call():
    import _thread
    import signal

    # interrupt_main does nothing while SIGINT is ignored, as it is for a
    # suite started in the background of a non-interactive shell (a CI
    # script run with `&` inherits SIG_IGN): Python's own handler for the test.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, _thread.interrupt_main)
    started = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            # About 10 s uninterrupted on the CI machine.
            packbed.deposit(dim=2, radii=1, count=2_000_000, box="8000,8000", periodic=True, progress=False)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    assert time.monotonic() - started < 5.0


def test_gil_is_released_while_depositing():
    ticks = []
    result = {}

    def work():
        result["bed"] = packbed.deposit(dim=2, radii=1, count=300000, box="2000,2000", periodic=True, progress=False)

    t = threading.Thread(target=work)
    t.start()
    while t.is_alive():
        ticks.append(time.monotonic())
        time.sleep(0.01)
    t.join()
    assert len(result["bed"]) == 300000
    # The main thread kept running Python while the bed was built.
    assert len(ticks) > 10


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: packbed.deposit(radii=[-1]), "radius"),
        (lambda: packbed.deposit({"dim": 2, "bogus": 1}), "bogus"),
        (lambda: packbed.deposit({"species": [{"radius": "ten"}]}), "radius"),
        (lambda: packbed.deposit(dim="3"), "dim"),
        (lambda: packbed.deposit(dim=4), "dim"),
        (lambda: packbed.deposit(radii="abc"), "radii"),
        (lambda: packbed.deposit(seed=-1), "seed"),
        (lambda: packbed.deposit(count=1.5), "count"),
        (lambda: packbed.deposit(box="nonsense"), "box"),
        (lambda: packbed.deposit(mode="fly"), "mode"),
        (lambda: packbed.deposit({"dim": None}), "dim"),
        (lambda: packbed.deposit(42), "config"),
        (lambda: packbed.deposit("/no/such/config.toml"), "config.toml"),
        (lambda: packbed.read("/no/such/bed.csv"), "bed.csv"),
        (lambda: packbed.read(3), "path"),
        (lambda: packbed.ensemble(runs="3"), "runs"),
        (lambda: packbed.ensemble(runs=0), "runs"),
        (lambda: packbed.ensemble(runs=2, jobs=0), "jobs"),
        (lambda: packbed.ensemble(runs=2**70), "runs"),
        (lambda: packbed.ensemble(runs=True), "runs"),
        (lambda: packbed.ensemble(runs=2, client="scheduler:8786"), "client"),
        (lambda: packbed.deposit(count=10**30), "count"),
        (lambda: packbed.deposit(radii=float("nan")), "keywords"),
        (lambda: packbed.deposit(dim=2.5), "dim"),
        (lambda: packbed.deposit(progress=5), "progress"),
        (lambda: packbed.deposit({"species": [{"radius": 10, "size": {"dist": "lognormal"}}]}), "size"),
        (lambda: packbed.read(__file__, box="a,b"), "box"),
        (lambda: packbed.deposit(dim=2, count=5).analyze(contact_tol=-1), "contact_tol"),
        (lambda: packbed.deposit(dim=2, count=5).analyze(nonsense=1), "nonsense"),
        (lambda: packbed.deposit(dim=2, count=5).fragment(load="twist"), "twist"),
        (lambda: packbed.deposit(dim=2, count=5).fragment(breaks=0), "breaks"),
    ],
)
def test_bad_input_raises_value_error(call, message):
    with pytest.raises(ValueError) as e:
        call()
    assert isinstance(e.value, packbed.PackbedError)
    text = str(e.value)
    assert message in text, text
    assert "\n" not in text


def test_config_dict_and_toml_file_agree(tmp_path):
    toml = tmp_path / "c.toml"
    toml.write_text('dim = 2\nseed = 9\n[box]\ndiameters = 6\n[[species]]\nradius = 10\n[[species]]\nradius = 5\nratio = 2\n')
    from_file = packbed.deposit(toml)
    from_dict = packbed.deposit({"dim": 2, "seed": 9, "box": {"diameters": 6},
                                 "species": [{"radius": 10}, {"radius": 5, "ratio": 2}]})
    assert np.array_equal(from_file.positions, from_dict.positions)
    # Keywords override the file as the command's options do.
    other = packbed.deposit(toml, seed=10)
    assert not np.array_equal(other.positions[:5], from_file.positions[:5])
    assert packbed.resolve_config(toml, seed=10)["seed"] == 10


def test_pores_and_permeability_match_the_command(tmp_path, run_cli):
    args = ("--radii", "10", "--box", "160,160,700", "--periodic", "--count", "1200", "--seed", "2")
    out = tmp_path / "cli"
    run_cli("run", *args, "--measures", "packing,pores,permeability", "--out", str(out), "--quiet", "--no-pictures")
    bed = packbed.deposit(dim=3, radii=10, box=[160, 160, 700], periodic=True, count=1200, seed=2)
    pd = optional("pandas")
    pores, throats = bed.pores()
    pd.testing.assert_frame_equal(pores, pd.read_csv(out / "pores.csv"), check_dtype=False, check_exact=True)
    pd.testing.assert_frame_equal(throats, pd.read_csv(out / "throats.csv"), check_dtype=False, check_exact=True)
    summary = json.loads((out / "summary.json").read_text())
    k = bed.permeability()
    assert k == summary["permeability"]
    assert k["k_x"] > 0 and k["k_y"] > 0 and k["k_z"] > 0
    # A bed with no bulk slab says why.
    small = packbed.deposit(dim=3, radii=10, count=20, seed=1)
    with pytest.raises(packbed.ImpossibleError, match="bulk slab"):
        small.permeability()


def test_drainage_matches_the_command(tmp_path, run_cli):
    args = ("--radii", "10", "--box", "160,160,700", "--periodic", "--count", "1200", "--seed", "2")
    out = tmp_path / "cli"
    run_cli("run", *args, "--measures", "packing,permeability,drainage", "--out", str(out), "--quiet", "--no-pictures")
    bed = packbed.deposit(dim=3, radii=10, box=[160, 160, 700], periodic=True, count=1200, seed=2)
    pd = optional("pandas")
    d = bed.drainage()
    summary = json.loads((out / "summary.json").read_text())
    assert d["summary"] == summary["drainage"]
    curve = pd.read_csv(out / "drainage.csv")
    pd.testing.assert_frame_equal(
        d["curve"], curve[["pc_reduced", "saturation", "connected", "trapped", "pendular"]], check_exact=True
    )
    assert curve["k_rw"].isna().all() and len(d["relative"]) == 0
    rel = bed.drainage(drainage={"relative_permeability": True})["relative"]
    assert len(rel) >= 10
    assert ((rel["k_rw"] >= 0) & (rel["k_rw"] <= 1 + 1e-9) & (rel["k_rg"] >= 0) & (rel["k_rg"] <= 1 + 1e-9)).all()
    assert rel["k_rw"].iloc[0] > 0.99 and rel["k_rw"].iloc[-1] < 0.05
    bridges = pd.read_csv(out / "liquid.csv").drop(columns=["state"])
    pd.testing.assert_frame_equal(d["bridges"], bridges, check_dtype=False, check_exact=True)
    pores = pd.read_csv(out / "pores.csv")
    pd.testing.assert_frame_equal(d["pores"], pores, check_dtype=False, check_exact=True)
    # The saturation falls as the pressure rises; a contact angle of 90
    # degrees is not a drainage.
    assert (d["curve"]["saturation"].diff().dropna() <= 1e-12).all()
    with pytest.raises(packbed.ConfigError, match="not a drainage"):
        bed.drainage(drainage={"contact_angle": 90})


def test_agglomeration_matches_the_command(tmp_path, run_cli):
    args = ("--radii", "10", "--box", "160,160,700", "--periodic", "--count", "1200", "--seed", "2")
    out = tmp_path / "cli"
    run_cli("run", *args, "--measures", "packing,agglomeration", "--out", str(out), "--quiet", "--no-pictures")
    bed = packbed.deposit(dim=3, radii=10, box=[160, 160, 700], periodic=True, count=1200, seed=2)
    pd = optional("pandas")
    a = bed.agglomeration()
    summary = json.loads((out / "summary.json").read_text())
    assert a["summary"] == summary["agglomeration"]
    assert a["drainage"] == summary["drainage"]
    bridges = pd.read_csv(out / "bridges.csv")
    pd.testing.assert_frame_equal(a["bridges"], bridges, check_dtype=False, check_exact=True)
    groups = pd.read_csv(out / "agglomerates.csv")
    pd.testing.assert_frame_equal(a["agglomerates"], groups, check_dtype=False, check_exact=True)
    # Each bond joins two particles of its agglomerate.
    bonds = a["bridges"][a["bridges"]["bond"] == 1]
    of = a["agglomerate_of"]
    assert (of[bonds["particle_a"]] == bonds["agglomerate"]).all()
    assert (of[bonds["particle_b"]] == bonds["agglomerate"]).all()
    # Nothing dissolved: nothing bonds.
    clean = bed.agglomeration(drying={"concentration": 0})
    assert clean["summary"]["agglomerates"] == 0 and len(clean["bridges"]) == 0
    with pytest.raises(packbed.ConfigError, match="above the solubility"):
        bed.agglomeration(drying={"concentration": 60, "solubility": 50})


def test_cake_psd_and_compare_match_the_command(tmp_path, run_cli):
    pd = optional("pandas")
    table = tmp_path / "sieve.csv"
    table.write_text("diameter_min_um,diameter_max_um,mass_percent\n40,60,10\n60,90,50\n90,120,40\n")
    config = tmp_path / "cake.toml"
    config.write_text(
        "dim = 3\nseed = 3\n[box]\nwidth = 400\ndepth = 400\nheight = 1200\nperiodic = true\n"
        '[[species]]\nsize = { table = "sieve.csv" }\n'
        '[analysis]\nlength_unit = "um"\nsolid_density = 1500\n'
    )
    out = tmp_path / "cli"
    run_cli("run", str(config), "--out", str(out), "--quiet", "--no-pictures")
    summary = json.loads((out / "summary.json").read_text())
    # A small box for its size distribution: the command warns, and so does Python.
    with pytest.warns(packbed.PackbedWarning, match="^psd: the placed mass curve departs"):
        bed = packbed.deposit(str(config))
    cake = bed.cake()
    assert cake == summary["cake"]
    assert cake["specific_resistance"] > 0 and 0.2 < cake["porosity"] < 0.6
    psd = bed.psd()
    pd.testing.assert_frame_equal(psd, pd.read_csv(out / "psd.csv"), check_dtype=False, check_exact=True)
    # Two runs compared: the same table as the command's compare.csv.
    other = tmp_path / "cli2"
    run_cli("run", str(config), "--seed", "4", "--out", str(other), "--quiet", "--no-pictures")
    frame = packbed.compare(out, other)
    assert frame.loc["cake.porosity", "cli.mean"] == summary["cake"]["porosity"]
    run_cli("compare", str(out), str(other), "--out", str(tmp_path / "cmp"), "--no-pictures")
    pd.testing.assert_frame_equal(frame, pd.read_csv(tmp_path / "cmp" / "compare.csv", index_col="measure"))
    # A read bed has no requested distribution.
    assert packbed.read(out / "particles.csv").psd() is None


def test_settling_rules_and_feeds_from_a_dict_equal_the_command(tmp_path, run_cli):
    # [settling] and [feed] in a config dict build the command's bed bit for bit;
    # hit-and-stick leaves a bulk mean coordination of 2.
    text = (
        "dim = 3\nseed = 4\n[box]\nwidth = 40\ndepth = 40\nheight = 2000\nperiodic = true\n"
        "[fill]\ncount = 2000\nbase_layer = \"none\"\n[[species]]\nradius = 1\n"
        "[settling]\nsticking = 0.4\nfriction_angle = 20\n"
        "[feed]\npattern = \"point\"\nspread = 6\n"
    )
    (tmp_path / "c.toml").write_text(text)
    run_cli("run", str(tmp_path / "c.toml"), "--out", str(tmp_path / "cli"), "--quiet", "--no-pictures")
    rows = read_particles(tmp_path / "cli" / "particles.csv")
    config = {
        "dim": 3, "seed": 4,
        "box": {"width": 40, "depth": 40, "height": 2000, "periodic": True},
        "fill": {"count": 2000, "base_layer": "none"},
        "species": [{"radius": 1}],
        "settling": {"sticking": 0.4, "friction_angle": 20},
        "feed": {"pattern": "point", "spread": 6},
    }
    bed = packbed.deposit(config)
    expected = np.array([[float(r["x"]), float(r["y"]), float(r["z"])] for r in rows])
    assert np.array_equal(bed.positions, expected)
    stick = packbed.deposit(
        {**config, "settling": {"contacts": 1}, "feed": {}},
    )
    # 2000 spheres leave a small bulk: Z within 0.05 of 2 (the Rust tests
    # check 0.02 on larger beds).
    z = stick.analyze()["coordination"]["mean_bulk"]
    assert abs(z - 2.0) < 0.05, z
    with pytest.raises(packbed.ConfigError, match="settling.sticking"):
        packbed.deposit({**config, "settling": {"sticking": 2}})
    # The momentum rule, the cohesion law with its exponent and the friction
    # angle with momentum, likewise.
    for k, (rule, lines) in enumerate([
        ({"restitution": 0.5, "sliding_friction": 0.3, "drop_height": 3},
         "restitution = 0.5\nsliding_friction = 0.3\ndrop_height = 3\n"),
        ({"cohesion_diameter": 2, "cohesion_exponent": 0.7},
         "cohesion_diameter = 2\ncohesion_exponent = 0.7\n"),
        ({"friction_angle": 25, "restitution": 0.9},
         "friction_angle = 25\nrestitution = 0.9\n"),
    ]):
        name = f"rule{k}"
        (tmp_path / f"{name}.toml").write_text(text.split("[settling]")[0] + "[settling]\n" + lines)
        run_cli("run", str(tmp_path / f"{name}.toml"), "--out", str(tmp_path / name), "--quiet",
                "--no-pictures")
        rows = read_particles(tmp_path / name / "particles.csv")
        expected = np.array([[float(r["x"]), float(r["y"]), float(r["z"])] for r in rows])
        bed = packbed.deposit({**config, "settling": rule, "feed": {}})
        assert np.array_equal(bed.positions, expected), rule
    # [[feeds]]: the feed of each particle, as the command's feed column.
    feeds = {
        **config,
        "species": [{"name": "a", "radius": 1.5}, {"name": "b", "radius": 1}],
        "fill": {"base_layer": "none"},
        "settling": {},
        "feed": {},
        "feeds": [
            {"species": ["a"], "count": 200, "settling": {"restitution": 0.5}},
            {"species": ["b"], "count": 300, "settling": {"sticking": 0.2}},
        ],
    }
    fed = packbed.deposit(feeds)
    assert fed.feed.tolist() == [0] * 200 + [1] * 300
    assert fed.to_pandas()["feed"].tolist() == fed.feed.tolist()
    assert list(fed.to_pandas().columns)[-1] == "feed"
    assert stick.feed is None
    (tmp_path / "feeds.toml").write_text(
        text.split("[settling]")[0].replace("[[species]]\nradius = 1\n", "")
        .replace("count = 2000\n", "")
        + "[[species]]\nname = \"a\"\nradius = 1.5\n[[species]]\nname = \"b\"\nradius = 1\n"
        + "[[feeds]]\nspecies = [\"a\"]\ncount = 200\nsettling = { restitution = 0.5 }\n"
        + "[[feeds]]\nspecies = [\"b\"]\ncount = 300\nsettling = { sticking = 0.2 }\n"
    )
    run_cli("run", str(tmp_path / "feeds.toml"), "--out", str(tmp_path / "fd"), "--quiet", "--no-pictures")
    rows = read_particles(tmp_path / "fd" / "particles.csv")
    assert [int(r["feed"]) for r in rows] == fed.feed.tolist()
    assert np.array_equal(
        fed.positions, np.array([[float(r["x"]), float(r["y"]), float(r["z"])] for r in rows])
    )
    with pytest.raises(packbed.ConfigError, match="settling.cohesion_exponent"):
        packbed.deposit({**config, "settling": {"cohesion_diameter": 2, "cohesion_exponent": 0}})


def test_a_compacted_bed_from_a_dict_equals_the_command(tmp_path, run_cli):
    # [compaction] in a config dict builds the command's bed bit for bit, and
    # the compacted discs are denser than the settled ones.
    text = (
        "dim = 2\nseed = 1\n[box]\nwidth = 12.3\nheight = 400\nperiodic = true\n"
        "[fill]\ncount = 150\nbase_layer = \"none\"\n[[species]]\nradius = 0.5\n"
        "[compaction]\nsteps = 40\n"
    )
    (tmp_path / "c.toml").write_text(text)
    run_cli("run", str(tmp_path / "c.toml"), "--out", str(tmp_path / "cli"), "--quiet", "--no-pictures")
    rows = read_particles(tmp_path / "cli" / "particles.csv")
    config = {
        "dim": 2, "seed": 1,
        "box": {"width": 12.3, "height": 400, "periodic": True},
        "fill": {"count": 150, "base_layer": "none"},
        "species": [{"radius": 0.5}],
        "compaction": {"steps": 40},
    }
    # 40 steps do not bring it to rest: the command's warning, as Python's.
    with pytest.warns(packbed.PackbedWarning, match="^compaction: stopped at its budget of 40 steps"):
        bed = packbed.deposit(config)
    expected = np.array([[float(r["x"]), float(r["y"])] for r in rows])
    assert np.array_equal(bed.positions, expected)
    settled = packbed.deposit({k: v for k, v in config.items() if k != "compaction"})
    phi = bed.analyze()["packing"]["bulk"]
    phi0 = settled.analyze()["packing"]["bulk"]
    assert phi > phi0 + 0.03, (phi0, phi)
    with pytest.raises(packbed.ConfigError, match="compaction.step"):
        packbed.deposit({**config, "compaction": {"step": 0.5}})


def test_a_filtered_bed_gives_its_capture_and_curve_as_the_command_writes_them(tmp_path, run_cli):
    optional("pandas")
    text = (
        "dim = 3\nseed = 3\n[box]\nwidth = 200\ndepth = 200\nheight = 20000\nperiodic = true\n"
        "[fill]\nbase_layer = \"none\"\n"
        "[[species]]\nname = \"precoat\"\nradius = 30.0\n"
        "[[species]]\nname = \"slurry\"\nsize = { dist = \"lognormal\", median = 8.0, gsd = 1.3 }\n"
        "[[feeds]]\nspecies = [\"precoat\"]\ncount = 150\nmedium = true\n"
        "[[feeds]]\nspecies = [\"slurry\"]\ncount = 4000\nsettling = { restitution = 0.5 }\n"
        "[analysis]\nmeasures = [\"packing\"]\nlength_unit = \"um\"\nsolid_density = 2650\n"
        "[filtration]\npressure = 1e5\nconcentration = 100\ncheckpoints = 10\n"
    )
    (tmp_path / "f.toml").write_text(text)
    # A small box for its size distribution: the command warns, and so does Python.
    with pytest.warns(packbed.PackbedWarning, match="^psd: the placed mass curve departs"):
        bed = packbed.deposit(str(tmp_path / "f.toml"))
    curve = bed.filtration()
    assert len(curve) == 11
    assert list(curve.columns)[:3] == ["time_s", "volume_m3_per_m2", "pressure_pa"]
    assert (curve["pressure_pa"] == 1e5).all()
    capture = bed.capture()
    totals = bed.summary["capture"]
    assert int(capture["fed"].sum()) == totals["fed"] == 4000
    assert totals["passed"] + totals["lodged"] + totals["cake"] == 4000
    run_cli("run", str(tmp_path / "f.toml"), "--out", str(tmp_path / "f"), "--quiet", "--no-pictures")
    with open(tmp_path / "f" / "filtration.csv") as f:
        rows = list(csv.DictReader(f))
    assert [float(r["r_total_per_m"]) for r in rows] == curve["r_total_per_m"].tolist()
    # The medium's constrictions beside the slurry: as constrictions.csv.
    constrictions = bed.constrictions()
    assert int(constrictions["slurry"].sum()) == 4000
    assert constrictions["constrictions_finer"].iloc[-1] == 1.0
    with open(tmp_path / "f" / "constrictions.csv") as f:
        rows = list(csv.DictReader(f))
    assert [int(r["constrictions"]) for r in rows] == constrictions["constrictions"].tolist()
    plain = packbed.deposit({"dim": 3, "fill": {"count": 50}})
    assert plain.filtration() is None and plain.capture() is None
    assert plain.constrictions() is None
