"""One periodic 3D bed settled by a rule, run by packbed; its summary.json.
Shared by the settling scripts (cohesion-fit.py, settling-permeability.py)."""
import json
import os
import subprocess

PACKBED = os.path.realpath(os.environ.get("PACKBED", "target/release/packbed"))


def settle(work, *, seed, count, width, size, rule, measures):
    """Settle `count` spheres (`size`: a species line) in a periodic box of
    `width` by `width` with the `[settling]` lines `rule`; the summary."""
    cfg = (
        f"dim = 3\nseed = {seed}\n[box]\nwidth = {width}\ndepth = {width}\n"
        f"height = {100.0 * width}\nperiodic = true\n[fill]\ncount = {count}\n"
        f'base_layer = "none"\n[[species]]\n{size}\n[settling]\n{rule}\n'
        f"[analysis]\nmeasures = {json.dumps(measures)}\n"
    )
    path = os.path.join(work, "c.toml")
    with open(path, "w") as f:
        f.write(cfg)
    out = os.path.join(work, "o")
    subprocess.run([PACKBED, "run", path, "--out", out, "--quiet"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)
