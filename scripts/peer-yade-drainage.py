# Peer measurement (NOT a packbed dependency): primary drainage of a packed
# sphere bed with Yade's TwoPhaseFlowEngine (quasi-static invasion on the
# regular triangulation of the spheres, entry pressures by the MS-P method).
# Run inside Yade:
#   yade -n -x scripts/peer-yade-drainage.py BED [OUT.jsonl|-] [TRAP] [WALLS]
# TRAP: "both" (default), "trap" or "notrap" (isPhaseTrapped True / False).
# WALLS: "open" (default; isInvadeBoundary = True, the wall pores can be
# invaded) or "closed" (isInvadeBoundary = False: the throats to the side
# walls are closed and the wall pores left out of the saturation).
# (scripts/bench-drainage.sh does this; Debian package `yade`.)
#
# Bed: packbed output folder (particles.csv header id,species,body,x,y,z,r and
# summary.json), periodic in x and y, floor at z = 0.
# Core slab: [0,W] x [0,D] x [2d, H-3d], as scripts/peer-porespy.py.
#
# Yade's two-phase engine drains along its y axis: the wetting reservoir is the
# ymin boundary (boundingCells[2]), the non-wetting (gas) reservoir the ymax
# boundary (boundingCells[3]), and it has no periodic variant. So packbed's
# (x, y, z) is mapped to Yade's (x, z, y): gas enters from the top of the
# cake (packbed z max = Yade y max) and the liquid leaves at the bottom.
# Sideways the core is padded by m = 1 d with the periodic images of the
# spheres and closed by box walls on the padded planes; in the flow direction
# the walls sit on the slab planes z0, z1 (boundaryUseMaxMin = False, so the
# walls cut through spheres rather than hugging them).
#
# Drainage is event-driven and exact for the engine's model: the next applied
# capillary pressure is getMinDrainagePc() (the smallest entry pressure on the
# gas front, max(gamma/r_throat, gamma/r_body)) times (1 + 1e-9), then
# invasion() (recursive: everything reachable at that pressure drains; with
# isPhaseTrapped the wetting clusters cut from the ymin reservoir stay).
# Saturation: getSaturation(False) (whole box minus the wall cells), and the
# same sum restricted to cells whose centres lie in the core x-y square.
# Breakthrough: the first applied pressure at which a cell within R of the
# bottom wall belongs to the gas reservoir (getCellIsNWRes).
# Pc R / gamma with R the sphere radius, gamma = 1.
import json
import os
import resource
import sys
import time

import numpy as np
from yade import O, utils
from yade.wrapper import TwoPhaseFlowEngine
import yade

args = [a for a in sys.argv[1:] if not a.endswith("peer-yade-drainage.py")]
bed = args[0]
outp = args[1] if len(args) > 1 and args[1] != "-" else None
modes = {"both": (True, False), "trap": (True,), "notrap": (False,)}[args[2] if len(args) > 2 else "both"]
invade_boundary = (args[3] != "closed") if len(args) > 3 else True

data = np.loadtxt(os.path.join(bed, "particles.csv"), delimiter=",", skiprows=1,
                  usecols=(3, 4, 5, 6))
summ = json.load(open(os.path.join(bed, "summary.json")))
xyz, r = data[:, :3], data[:, 3]
W, D = summ["box"]["width"], summ["box"]["depth"]
d = 2.0 * float(r.mean())
R = d / 2
H = summ["cake"]["height"]
z0, z1 = 2 * d, H - 3 * d
m = 1.0 * d
lo = np.array([-m, -m, z0])
hi = np.array([W + m, D + m, z1])

pts, rad = [], []
for sx in (-W, 0.0, W):
    for sy in (-D, 0.0, D):
        p = xyz + np.array([sx, sy, 0.0])
        # centres inside the padded box (walls cut the spheres they cross)
        keep = np.all((p >= lo) & (p <= hi), axis=1)
        pts.append(p[keep])
        rad.append(r[keep])
pts, rad = np.vstack(pts), np.concatenate(rad)


def yv(p):  # packbed (x, y, z) -> Yade (x, z, y)
    return (float(p[0]), float(p[2]), float(p[1]))


ylo, yhi = yv(lo), yv(hi)
print(f"yade {len(pts)} spheres, box {ylo} .. {yhi} (Yade axes), core slab z [{z0}, {z1:.3f}]",
      flush=True)

results = []
for trapped in modes:
    t_all = time.perf_counter()
    O.reset()
    mid = [(a + b) / 2 for a, b in zip(ylo, yhi)]
    big = [b - a for a, b in zip(ylo, yhi)]
    walls = []
    for k in range(3):
        for val in (ylo[k], yhi[k]):
            c = list(mid)
            c[k] = val
            ext = [b / 2 * 1.01 for b in big]
            ext[k] = 0.0
            walls.append(utils.box(center=tuple(c), extents=tuple(ext), fixed=True, wire=True))
    wid = O.bodies.append(walls)  # xmin,xmax,ymin,ymax,zmin,zmax
    O.bodies.append([utils.sphere(yv(p), float(rr), fixed=True) for p, rr in zip(pts, rad)])
    flow = TwoPhaseFlowEngine()
    flow.wallIds = list(wid)
    flow.boundaryUseMaxMin = [False] * 6
    flow.bndCondIsPressure = [False, False, True, True, False, False]
    flow.bndCondValue = [0, 0, 0, 0, 0, 0]
    flow.surfaceTension = 1.0
    flow.entryPressureMethod = 1  # MS-P
    flow.isPhaseTrapped = trapped
    flow.isDrainageActivated = True
    flow.isImbibitionActivated = False
    flow.drainageFirst = True
    flow.isInvadeBoundary = invade_boundary
    flow.isCellLabelActivated = False
    O.engines = [flow]
    O.dt = 1e-6
    t = time.perf_counter()
    flow.initialization()
    t_init = time.perf_counter() - t
    n = flow.nCells()
    cen = np.array([flow.getCellCenter(i) for i in range(n)])
    fict = np.array([flow.getCellIsFictious(i) for i in range(n)], dtype=bool)
    vol = np.array([flow.getCellVoidVolume(i) if hasattr(flow, "getCellVoidVolume") else 0.0
                    for i in range(n)])
    core = (~fict) & (cen[:, 0] >= 0) & (cen[:, 0] <= W) & (cen[:, 2] >= 0) & (cen[:, 2] <= D)
    bottom = cen[:, 1] < ylo[1] + R
    bottom_core = bottom & (cen[:, 0] >= 0) & (cen[:, 0] <= W) & (cen[:, 2] >= 0) & (cen[:, 2] <= D)
    print(f"  trap={trapped}: {n} cells ({(~fict).sum()} not at walls, {core.sum()} in the core), "
          f"init {t_init:.1f} s", flush=True)

    def core_sw():
        s = np.array([flow.getCellSaturation(i) for i in range(n)])
        v = vol[core]
        return float((s[core] * v).sum() / v.sum()) if v.sum() > 0 else float("nan")

    curve, core_curve = [], []
    bt = None
    sw_bt = None
    bt_core = None
    steps = 0
    t = time.perf_counter()
    pc_applied = 0.0
    while True:
        pc = flow.getMinDrainagePc()
        if pc <= 0:
            break
        pc_applied = max(pc_applied, pc * (1 + 1e-9))
        flow.bndCondValue = [0, 0, -pc_applied, 0, 0, 0]
        flow.invasion()
        steps += 1
        sw = flow.getSaturation(False)
        curve.append([pc_applied * R, sw])
        if bt is None:
            nw = np.array([flow.getCellIsNWRes(int(i)) for i in np.where(bottom)[0]], dtype=bool)
            if nw.any():
                bt = pc_applied
                sw_bt = sw
        if bt_core is None:
            nw = np.array([flow.getCellIsNWRes(int(i)) for i in np.where(bottom_core)[0]], dtype=bool)
            if nw.any():
                bt_core = pc_applied
    t_drain = time.perf_counter() - t
    # the curve at the distinct pressures (last saturation at each pressure)
    cu = {}
    for p, s in curve:
        cu[round(p, 6)] = s
    keys = sorted(cu)
    full = [[k, round(cu[k], 5)] for k in keys]
    if len(full) > 300:  # thin out for the JSON line: the curve (a step
        # function) read at 300 pressures evenly spaced over its range
        ps_ = np.array([k for k, _ in full])
        ss_ = np.array([s for _, s in full])
        grid = np.linspace(ps_[0], ps_[-1], 300)
        idx = np.searchsorted(ps_, grid, side="right") - 1
        full = [[round(float(g), 5), float(ss_[i])] for g, i in zip(grid, idx)]
    sw_end = flow.getSaturation(False)
    res = dict(tool="yade TwoPhaseFlowEngine", yade=str(getattr(yade.config, "version", "2023.02a")),
               bed=os.path.abspath(bed), spheres=int(len(pts)), cells=int(n),
               cells_core=int(core.sum()), entry="MS-P (entryPressureMethod=1)",
               isPhaseTrapped=trapped, events=steps,
               first_entry_PcR_g=(curve[0][0] if curve else None),
               breakthrough_PcR_g=(bt * R if bt else None), sw_at_breakthrough=sw_bt,
               breakthrough_core_PcR_g=(bt_core * R if bt_core else None),
               isInvadeBoundary=invade_boundary,
               residual_sw=sw_end, residual_sw_core=(core_sw() if vol.sum() > 0 else None),
               pmax_PcR_g=(curve[-1][0] if curve else None),
               curve_PcR_g_sw=full, t_init=t_init, t_drainage=t_drain,
               t_total=time.perf_counter() - t_all,
               maxrss_kB=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
    results.append(res)
    short = {k: v for k, v in res.items() if not k.startswith("curve")}
    print("summary " + json.dumps(short), flush=True)
    print("RESULT " + json.dumps(res), flush=True)
    if outp:
        with open(outp, "a") as f:
            f.write(json.dumps(res) + "\n")
sys.exit(0)
