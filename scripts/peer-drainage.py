#!/usr/bin/env python3
"""Peer measurement (NOT a packbed dependency): primary drainage of a packed
sphere bed with PoreSpy (snow2 network extraction) + OpenPNM (Drainage and
InvasionPercolation), to set beside packbed's own drainage (issue 58).

Run through scripts/bench-drainage.sh (scratch venv with `porespy openpnm`).

Bed and slab as in scripts/peer-porespy.py (whose loader and voxeliser this
script reuses): a packbed output folder, periodic in x and y, floor at z = 0;
slab z in [2 d, H - 3 d] over the full x-y extent, voxelised at `--res`
voxels per sphere diameter, network by snow2 with the library's defaults.

Drainage set-up:
- gas (non-wetting, the invader) enters from the top face (snow2's `zmax`
  boundary pores), the wetting liquid leaves at the bottom (`zmin` boundary
  pores) -- the cake on its filter medium;
- throat entry pressure: OpenPNM's `washburn` model, Pc = -2 gamma cos(theta)/r
  with r = throat.inscribed_diameter / 2 and theta = 180 deg for the gas
  (= 0 deg for the liquid), so Pc = 4 gamma / D_t;
- saturation: pore volumes of the internal pores (snow2's boundary pores,
  about 1 % of the volume, are left out; throats carry no volume in snow2);
- OpenPNM `Drainage`, quasi-static, at every distinct throat entry pressure
  (or `--levels` log-spaced ones when there are more): without trapping, then
  with `set_outlet_BC` + `apply_trapping` (trapping evaluated after the
  invasion at every pressure step, as OpenPNM does it);
- OpenPNM `InvasionPercolation` (one throat at a time, numba) with its
  `apply_trapping` (Masson 2016 reverse-sequence trapping); its Pc-S curve is
  taken with the applied pressure = running maximum of the entry pressures.

Dimensionless pressure: Pc R / gamma with R = d/2 (the sphere radius).
Breakthrough: the lowest applied pressure at which the gas reaches an outlet
pore. Residual: wetting saturation at the highest pressure with trapping.
Prints one JSON line per run (prefix `RESULT `).
"""
import argparse
import importlib.util
import json
import os
import resource
import sys
import time

import numpy as np


def load_peer_porespy():
    here = os.path.dirname(os.path.abspath(__file__))
    spec = importlib.util.spec_from_file_location(
        "peer_porespy", os.path.join(here, "peer-porespy.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def rss_kB():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("bed", help="packbed output folder (particles.csv, summary.json)")
    ap.add_argument("--res", type=float, default=10.0, help="voxels per sphere diameter")
    ap.add_argument("--d", type=float, default=None, help="sphere diameter (default 2 * mean r)")
    ap.add_argument("--gamma", type=float, default=1.0, help="surface tension")
    ap.add_argument("--levels", type=int, default=400,
                    help="at most this many pressure steps for Drainage")
    ap.add_argument("--json", default=None, help="also append results to this JSON-lines file")
    a = ap.parse_args()

    pp = load_peer_porespy()
    import porespy as ps
    import openpnm as op
    ps.settings.tqdm["disable"] = True
    import logging
    logging.getLogger("openpnm").setLevel(logging.ERROR)

    t_all = time.perf_counter()
    xyz, r, summ = pp.load_bed(a.bed)
    W, D = summ["box"]["width"], summ["box"]["depth"]
    d = a.d if a.d else 2.0 * float(r.mean())
    R = d / 2
    gamma = a.gamma
    cake = summ.get("cake", {})
    H = cake.get("height") or pp.column_tops_height(xyz, r, W, D, d)
    z0, z1 = 2 * d, H - 3 * d
    h = d / a.res
    z1 = z0 + round((z1 - z0) / h) * h

    t = time.perf_counter()
    im = pp.voxelise(xyz, r, W, D, z0, z1, h)
    t_vox = time.perf_counter() - t
    eps_img = float(im.mean())
    print(f"image {im.shape} = {im.size/1e6:.1f} Mvox, h = {h:.4g}, porosity {eps_img:.4f}, "
          f"{t_vox:.1f} s", flush=True)
    t = time.perf_counter()
    snow = ps.networks.snow2(im, voxel_size=h)
    t_snow = time.perf_counter() - t
    shape = [n - 6 for n in snow.regions.shape]
    del im
    pn = op.io.network_from_porespy(snow.network)
    del snow
    pn["pore.diameter"] = pn["pore.equivalent_diameter"]
    pn["throat.diameter"] = pn["throat.inscribed_diameter"]
    h_ = op.utils.check_network_health(pn) if hasattr(op.utils, "check_network_health") \
        else pn.check_network_health()
    trim = np.asarray(h_["disconnected_pores"], dtype=int)
    if trim.size:
        op.topotools.trim(network=pn, pores=trim)
    t_extract = t_vox + t_snow
    rss_extract = rss_kB()
    inlet, outlet = pn.pores("zmax"), pn.pores("zmin")
    internal = ~pn["pore.boundary"]
    print(f"snow2 {t_snow:.1f} s; network {pn.Np} pores ({internal.sum()} internal), "
          f"{pn.Nt} throats; inlets {inlet.size}, outlets {outlet.size}", flush=True)

    gas = op.phase.Phase(network=pn, name="gas")
    gas["throat.surface_tension"] = gamma
    gas["throat.contact_angle"] = 180.0
    gas.add_model(propname="throat.entry_pressure",
                  model=op.models.physics.capillary_pressure.washburn,
                  diameter="throat.diameter")
    gas.regenerate_models()
    pe = gas["throat.entry_pressure"]
    conns = pn["throat.conns"]
    t_internal = internal[conns].all(axis=1)
    levels = np.unique(pe[np.isfinite(pe) & (pe > 0)])
    n_distinct = int(levels.size)
    n_distinct_internal = int(np.unique(pe[t_internal]).size)
    if levels.size > a.levels:
        levels = np.logspace(np.log10(levels[0]), np.log10(levels[-1]), a.levels)
    # Volumes: internal pores only; throats carry none (snow2).
    vp = np.where(internal, pn["pore.volume"], 0.0)
    pn["pore.volume"] = vp
    pn["throat.volume"] = np.zeros(pn.Nt)
    vtot = vp.sum()

    def sw_at(pinv, p):
        return float(1.0 - vp[pinv <= p].sum() / vtot)

    def curve(pinv, ps_):
        return [[round(float(p) * R / gamma, 5), round(sw_at(pinv, p), 5)] for p in ps_]

    # ---- OpenPNM Drainage (quasi-static, pressure steps)
    t = time.perf_counter()
    drn = op.algorithms.Drainage(network=pn, phase=gas)
    drn.set_inlet_BC(pores=inlet)
    drn.run(pressures=levels)
    t_drn = time.perf_counter() - t
    pinv_nt = drn["pore.invasion_pressure"].copy()
    bt = float(np.min(pinv_nt[outlet]))
    sw_bt_nt = sw_at(pinv_nt, bt)
    first = float(np.min(pinv_nt[np.isfinite(pinv_nt)]))
    t = time.perf_counter()
    drn.set_outlet_BC(pores=outlet)
    drn.apply_trapping()
    t_trap = time.perf_counter() - t
    pinv_tr = drn["pore.invasion_pressure"].copy()
    sw_bt_tr = sw_at(pinv_tr, bt)
    pmax = float(levels[-1])
    res_nt = sw_at(pinv_nt, pmax)
    res_tr = sw_at(pinv_tr, pmax)
    rss_drn = rss_kB()

    # ---- OpenPNM InvasionPercolation (+ Masson trapping)
    t = time.perf_counter()
    ip = op.algorithms.InvasionPercolation(network=pn, phase=gas)
    ip.set_inlet_BC(pores=inlet)
    ip.run()
    pseq = ip["pore.invasion_sequence"].astype(float).copy()
    tseq = ip["throat.invasion_sequence"].astype(float).copy()
    # applied pressure at each throat step = running max of entry pressures
    order = np.argsort(tseq)
    tpe = ip["throat.entry_pressure"][order]
    papp = np.maximum.accumulate(tpe)
    seq_sorted = tseq[order]

    def applied(seq):  # pressure applied when step `seq` happened
        i = np.searchsorted(seq_sorted, seq, side="left")
        i = np.clip(i, 0, len(papp) - 1)
        return np.where(seq <= 0, 0.0, papp[i])

    ppore_ip = applied(pseq)
    ip_bt = float(np.min(ppore_ip[outlet]))
    ip.set_outlet_BC(pores=outlet)
    ip.apply_trapping()
    trapped = ip["pore.trapped"]
    ppore_ip_tr = np.where(trapped, np.inf, ppore_ip)
    t_ip = time.perf_counter() - t
    ip_res = sw_at(ppore_ip_tr, pmax)

    out = dict(
        tool="porespy+openpnm drainage", porespy=ps.__version__, openpnm=op.__version__,
        bed=os.path.abspath(a.bed), res_per_d=a.res, voxel=h, shape=shape,
        porosity_image=eps_img, pores=int(pn.Np), pores_internal=int(internal.sum()),
        throats=int(pn.Nt), inlets=int(inlet.size), outlets=int(outlet.size),
        entry="washburn, throat.inscribed_diameter, theta_gas=180",
        distinct_entry_levels=n_distinct, distinct_entry_levels_internal=n_distinct_internal,
        drainage_steps=int(levels.size),
        first_entry_PcR_g=first * R / gamma,
        breakthrough_PcR_g=bt * R / gamma,
        sw_at_breakthrough_notrap=sw_bt_nt, sw_at_breakthrough_trap=sw_bt_tr,
        residual_sw_notrap=res_nt, residual_sw_trap=res_tr,
        pmax_PcR_g=pmax * R / gamma,
        ip_breakthrough_PcR_g=ip_bt * R / gamma, ip_residual_sw_trap=ip_res,
        ip_sw_at_breakthrough_trap=sw_at(ppore_ip_tr, ip_bt),
        curve_PcR_g_sw_notrap=curve(pinv_nt, levels),
        curve_PcR_g_sw_trap=curve(pinv_tr, levels),
        curve_ip_trap=curve(ppore_ip_tr, levels),
        t_voxelise=t_vox, t_snow2=t_snow, t_extraction=t_extract,
        t_drainage=t_drn, t_trapping=t_trap, t_ip=t_ip,
        t_total=time.perf_counter() - t_all,
        maxrss_kB_after_extraction=rss_extract, maxrss_kB_after_drainage=rss_drn,
        maxrss_kB=rss_kB(),
    )
    short = {k: v for k, v in out.items() if not k.startswith("curve")}
    print("summary " + json.dumps(short), flush=True)
    print("RESULT " + json.dumps(out), flush=True)
    if a.json:
        with open(a.json, "a") as f:
            f.write(json.dumps(out) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
