#!/usr/bin/env python3
"""Peer measurement (NOT a packbed dependency): permeability of a packed
sphere bed with PoreSpy (snow2 network extraction) + OpenPNM (StokesFlow).

Measured side by side with packbed's own permeability; run through
scripts/bench-peers.sh, which makes a scratch venv with `porespy openpnm`.

Bed: a packbed output folder (particles.csv with header id,species,body,x,y,z,r
plus summary.json). Periodic in x and y, floor at z = 0.
Slab: z in [2 d, H - 3 d], H = cake.height (or the mean of column tops),
full periodic x-y extent; voxelised with `--res` voxels per sphere diameter.

k = Q mu L / (A dp), mu = 1, lengths in the file's units.
Prints one JSON line per conductance model (prefix `RESULT `).
"""
import argparse
import json
import os
import resource
import sys
import time

import numpy as np


def load_bed(bed):
    data = np.loadtxt(os.path.join(bed, "particles.csv"), delimiter=",",
                      skiprows=1, usecols=(3, 4, 5, 6))
    with open(os.path.join(bed, "summary.json")) as f:
        summ = json.load(f)
    return data[:, :3], data[:, 3], summ


def column_tops_height(xyz, r, W, D, d):
    # mean over d x d columns of the highest sphere top
    ix = np.floor(xyz[:, 0] / d).astype(int) % max(1, int(round(W / d)))
    iy = np.floor(xyz[:, 1] / d).astype(int) % max(1, int(round(D / d)))
    key = ix * 100000 + iy
    top = xyz[:, 2] + r
    order = np.argsort(key)
    k, first = np.unique(key[order], return_index=True)
    return float(np.mean(np.maximum.reduceat(top[order], first)))


def voxelise(xyz, r, W, D, z0, z1, h):
    """Boolean pore image (True = void), axes (x, y, z), voxel size h,
    voxel centres at (i + 1/2) h; periodic images in x and y."""
    nx, ny, nz = int(round(W / h)), int(round(D / h)), int(round((z1 - z0) / h))
    im = np.ones((nx, ny, nz), dtype=bool)
    rmax = r.max()
    sel = (xyz[:, 2] > z0 - rmax) & (xyz[:, 2] < z1 + rmax)
    for (cx, cy, cz), rr in zip(xyz[sel], r[sel]):
        for sx in (-W, 0.0, W):
            for sy in (-D, 0.0, D):
                x, y = cx + sx, cy + sy
                lo = np.floor((np.array([x, y, cz - z0]) - rr) / h - 0.5).astype(int)
                hi = np.ceil((np.array([x, y, cz - z0]) + rr) / h - 0.5).astype(int) + 1
                lo = np.maximum(lo, 0)
                hi = np.minimum(hi, (nx, ny, nz))
                if np.any(hi <= lo):
                    continue
                gx = (np.arange(lo[0], hi[0]) + 0.5) * h - x
                gy = (np.arange(lo[1], hi[1]) + 0.5) * h - y
                gz = (np.arange(lo[2], hi[2]) + 0.5) * h + z0 - cz
                m = (gx[:, None, None] ** 2 + gy[None, :, None] ** 2
                     + gz[None, None, :] ** 2) <= rr * rr
                im[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]] &= ~m
    return im


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bed", help="packbed output folder (particles.csv, summary.json)")
    ap.add_argument("--res", type=float, default=5.0, help="voxels per sphere diameter")
    ap.add_argument("--d", type=float, default=None, help="sphere diameter (default 2 * mean r)")
    ap.add_argument("--axes", default="xyz", help="flow axes to solve, e.g. xyz or z")
    ap.add_argument("--models", default="pyramids_and_cuboids,cones_and_cylinders",
                    help="OpenPNM hydraulic size-factor models to compare")
    ap.add_argument("--json", default=None, help="also append results to this JSON-lines file")
    a = ap.parse_args()

    import porespy as ps
    import openpnm as op
    ps.settings.tqdm["disable"] = True

    t_all = time.perf_counter()
    xyz, r, summ = load_bed(a.bed)
    W, D = summ["box"]["width"], summ["box"]["depth"]
    d = a.d if a.d else 2.0 * float(r.mean())
    cake = summ.get("cake", {})
    H = cake.get("height") or column_tops_height(xyz, r, W, D, d)
    eps_kc = cake.get("porosity")
    z0, z1 = 2 * d, H - 3 * d
    h = d / a.res
    z1 = z0 + round((z1 - z0) / h) * h  # whole voxels
    t = time.perf_counter()
    im = voxelise(xyz, r, W, D, z0, z1, h)
    t_vox = time.perf_counter() - t
    eps_img = float(im.mean())
    print(f"image {im.shape} = {im.size/1e6:.1f} Mvox, h = {h}, slab z [{z0}, {z1:.3f}], "
          f"porosity image {eps_img:.4f} (summary {eps_kc}), {t_vox:.1f} s", flush=True)

    t = time.perf_counter()
    snow = ps.networks.snow2(im, voxel_size=h)  # library defaults otherwise
    t_snow = time.perf_counter() - t
    # snow2's (parallel) watershed may crop the image by a voxel: use the
    # extracted shape (minus the 3-voxel boundary pads) for L and A
    shape = [n - 6 for n in snow.regions.shape]
    if list(shape) != list(im.shape):
        print(f"image cropped to {shape} by snow2", flush=True)
    Lx, Ly, Lz = (n * h for n in shape)
    del im
    print(f"snow2 {t_snow:.1f} s", flush=True)

    t = time.perf_counter()
    pn = op.io.network_from_porespy(snow.network)
    del snow
    # As OpenPNM's own "import an extracted network" example does for snow2:
    pn["pore.diameter"] = pn["pore.equivalent_diameter"]
    pn["throat.diameter"] = pn["throat.inscribed_diameter"]
    pn["throat.spacing"] = pn["throat.total_length"]
    h_ = op.utils.check_network_health(pn) if hasattr(op.utils, "check_network_health") \
        else pn.check_network_health()
    trim = np.asarray(h_["disconnected_pores"], dtype=int)
    if trim.size:
        op.topotools.trim(network=pn, pores=trim)
    n_p, n_t = pn.Np, pn.Nt
    print(f"network {n_p} pores, {n_t} throats (trimmed {trim.size} disconnected)", flush=True)

    lengths = {"x": Lx, "y": Ly, "z": Lz}
    areas = {"x": Ly * Lz, "y": Lx * Lz, "z": Lx * Ly}
    kc = (eps_kc ** 3 * d * d / (180 * (1 - eps_kc) ** 2)) if eps_kc else None
    out = []
    for model in a.models.split(","):
        sf_model = getattr(op.models.geometry.hydraulic_size_factors, model)
        pn.add_model(propname="throat.hydraulic_size_factors", model=sf_model,
                     pore_diameter="pore.diameter", throat_diameter="throat.diameter")
        pn.regenerate_models()
        ph = op.phase.Phase(network=pn)
        ph["pore.viscosity"] = 1.0
        ph.add_model_collection(op.models.collections.physics.basic)
        ph.regenerate_models()
        ks = {}
        for ax in a.axes:
            sf = op.algorithms.StokesFlow(network=pn, phase=ph)
            sf.set_value_BC(pores=pn.pores(ax + "min"), values=1.0)
            sf.set_value_BC(pores=pn.pores(ax + "max"), values=0.0)
            ts = time.perf_counter()
            sf.run()
            Q = float(abs(sf.rate(pores=pn.pores(ax + "min"), mode="group")[0]))
            ks[ax] = Q * 1.0 * lengths[ax] / (areas[ax] * 1.0)
            print(f"  {model} k_{ax} = {ks[ax]:.5g} ({time.perf_counter()-ts:.1f} s, "
                  f"solver {sf.settings.get('solver', None) if hasattr(sf.settings, 'get') else ''})",
                  flush=True)
        rss = max(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,
                  resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
        res = dict(tool="porespy+openpnm", porespy=ps.__version__, openpnm=op.__version__,
                   bed=os.path.abspath(a.bed), res_per_d=a.res, voxel=h, shape=shape,
                   slab=[z0, z1], porosity_image=eps_img, porosity_summary=eps_kc,
                   pores=n_p, throats=n_t, size_factors=model,
                   conductance="generic_hydraulic (physics.basic)",
                   k={ax: ks[ax] for ax in ks}, k_over_d2={ax: ks[ax] / d ** 2 for ax in ks},
                   k_KC=kc, k_over_kKC={ax: (ks[ax] / kc if kc else None) for ax in ks},
                   t_voxelise=t_vox, t_snow2=t_snow,
                   t_total=time.perf_counter() - t_all, maxrss_kB=rss)
        out.append(res)
        print("RESULT " + json.dumps(res), flush=True)
        if a.json:
            with open(a.json, "a") as f:
                f.write(json.dumps(res) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
