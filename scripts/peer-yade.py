# Peer measurement (NOT a packbed dependency): permeability of a packed
# sphere bed with Yade's FlowEngine (pore-scale finite volumes on the regular
# triangulation of the spheres). Run inside Yade, e.g.
#   yade -n -x scripts/peer-yade.py BED [AXES] [OUT.jsonl]
# (scripts/bench-peers.sh does this; Debian package `yade`).
#
# Bed: packbed output folder (particles.csv header id,species,body,x,y,z,r and
# summary.json), periodic in x and y, floor at z = 0.
# Core slab (the measured region): [0,W] x [0,D] x [2d, H-3d], H = cake.height.
# Yade's FlowEngine has no periodic x-y with pressure walls in z (its periodic
# variant imposes a gradient over a fully periodic cell), so the core is padded
# by m = 2d on every side -- with the periodic images of the spheres in x and
# y, and with the real spheres below/above it in z -- and closed by six box
# walls placed on the padded planes (boundaryUseMaxMin = False, so the walls
# cut through the spheres rather than hugging them). For flow along axis a
# the two walls normal to a carry pressures 1 and 0; the flux Q is read at the
# inlet wall and spread over the padded cross-section A; the pressure gradient
# is the least-squares slope of the cell pressures against position along a,
# over the cells whose centres lie in the core slab. k = mu (Q/A) / |dp/da|,
# mu = 1. useSolver = 3 (CHOLMOD).
import json
import os
import resource
import sys
import time

import numpy as np
from yade import O, utils
from yade.wrapper import (FlowEngine, ForceResetter, InsertionSortCollider,
                          Bo1_Sphere_Aabb, Bo1_Box_Aabb)
import yade

args = [a for a in sys.argv[1:] if not a.endswith("peer-yade.py")]
bed = args[0]
axes = args[1] if len(args) > 1 else "zx"
outp = args[2] if len(args) > 2 else None

data = np.loadtxt(os.path.join(bed, "particles.csv"), delimiter=",", skiprows=1,
                  usecols=(3, 4, 5, 6))
summ = json.load(open(os.path.join(bed, "summary.json")))
xyz, r = data[:, :3], data[:, 3]
W, D = summ["box"]["width"], summ["box"]["depth"]
d = 2.0 * float(r.mean())
H = summ["cake"]["height"]
eps = summ["cake"]["porosity"]
z0, z1 = 2 * d, H - 3 * d
m = 2 * d
lo = np.array([-m, -m, z0 - m])
hi = np.array([W + m, D + m, z1 + m])

# spheres: periodic images in x,y; keep those reaching into the padded box
pts, rad = [], []
for sx in (-W, 0.0, W):
    for sy in (-D, 0.0, D):
        p = xyz + np.array([sx, sy, 0.0])
        keep = np.all((p + r[:, None] > lo) & (p - r[:, None] < hi), axis=1)
        pts.append(p[keep])
        rad.append(r[keep])
pts, rad = np.vstack(pts), np.concatenate(rad)
print(f"yade {yade.config.revision if hasattr(yade.config, 'revision') else ''} "
      f"{len(pts)} spheres in padded box {lo} .. {hi}; core slab z [{z0}, {z1:.3f}]", flush=True)

results = []
t_all = time.perf_counter()
for ax in axes:
    a = "xyz".index(ax)
    O.reset()
    t = time.perf_counter()
    mid = (lo + hi) / 2
    big = (hi - lo)
    walls = []
    for k in range(3):
        for side, val in ((0, lo[k]), (1, hi[k])):
            c = mid.copy()
            c[k] = val
            ext = big / 2 * 1.01
            ext[k] = 0.0
            walls.append(utils.box(center=tuple(c), extents=tuple(ext), fixed=True, wire=True))
    wid = O.bodies.append(walls)  # order xmin,xmax,ymin,ymax,zmin,zmax = ids 0..5
    O.bodies.append([utils.sphere(tuple(p), float(rr), fixed=True) for p, rr in zip(pts, rad)])
    bc = [False] * 6
    bc[2 * a] = bc[2 * a + 1] = True
    val = [0.0] * 6
    val[2 * a] = 1.0
    flow = FlowEngine(useSolver=3, viscosity=1.0, wallIds=list(wid),
                      boundaryUseMaxMin=[False] * 6, bndCondIsPressure=bc,
                      bndCondValue=val, permeabilityFactor=1.0)
    O.engines = [ForceResetter(),
                 InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Box_Aabb()], verletDist=0),
                 flow]
    O.dt = 1e-6
    t_build = time.perf_counter() - t
    t = time.perf_counter()
    O.run(1, True)
    t_solve = time.perf_counter() - t
    Q = abs(flow.getBoundaryFlux(wid[2 * a]))
    Qout = abs(flow.getBoundaryFlux(wid[2 * a + 1]))
    n = flow.nCells()
    cen = np.array([flow.getCellCenter(i) for i in range(n)])
    pre = np.array([flow.getCellPressure(i) for i in range(n)])
    core = np.all((cen >= [0, 0, z0]) & (cen <= [W, D, z1]), axis=1)
    slope = np.polyfit(cen[core, a], pre[core], 1)[0]
    A = np.prod(np.delete(hi - lo, a))
    k = 1.0 * (Q / A) / abs(slope)
    Ltot = (hi - lo)[a]
    k_walls = 1.0 * Q * Ltot / (A * 1.0)  # using the wall-to-wall dp = 1 instead
    kc = eps ** 3 * d * d / (180 * (1 - eps) ** 2)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    res = dict(tool="yade FlowEngine", yade="2023.02a", bed=os.path.abspath(bed),
               axis=ax, spheres=len(pts), cells=n, useSolver=flow.useSolver,
               Q_in=Q, Q_out=Qout, dpdx_core=slope, k=k, k_over_d2=k / d ** 2,
               k_wall_to_wall=k_walls, k_KC=kc, k_over_kKC=k / kc,
               t_build=t_build, t_solve=t_solve, maxrss_kB=rss)
    results.append(res)
    print("RESULT " + json.dumps(res), flush=True)
    if outp:
        with open(outp, "a") as f:
            f.write(json.dumps(res) + "\n")
print(f"total {time.perf_counter() - t_all:.1f} s", flush=True)
sys.exit(0)
