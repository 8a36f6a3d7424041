#!/usr/bin/env python3
"""Plot the peer drainage curves (NOT a packbed dependency): P_c R/gamma
against wetting saturation, with and without trapping, from the JSON lines
written by scripts/peer-drainage.py and scripts/peer-yade-drainage.py.

    python3 scripts/plot-drainage-peers.py drainage.jsonl docs/drainage-peers.png

(needs matplotlib; the scratch venv of scripts/bench-drainage.sh has it).
Yade rows are drawn for closed side walls only.
"""
import json, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
rows=[json.loads(l) for l in open(sys.argv[1])]
fig, axs = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
cols={6:"C0",10:"C1",20:"C2",30:"C3"}
for r in rows:
    if r["tool"].startswith("porespy"):
        res=int(r["res_per_d"]); c=cols.get(res,"k")
        for key, ax, ls in (("curve_PcR_g_sw_trap",axs[0],"-"),("curve_ip_trap",axs[0],":"),("curve_PcR_g_sw_notrap",axs[1],"-")):
            x=[1.0]+[s for _,s in r[key]]; y=[0.0]+[p for p,_ in r[key]]
            lab=f"OpenPNM {res} vox/d" + (" (IP)" if key=="curve_ip_trap" else "")
            ax.step(x, y, where="pre", color=c, ls=ls, label=lab)
    else:
        if not r["isInvadeBoundary"]:
            ax = axs[0] if r["isPhaseTrapped"] else axs[1]
            x=[1.0]+[s for _,s in r["curve_PcR_g_sw"]]; y=[0.0]+[p for p,_ in r["curve_PcR_g_sw"]]
            ax.step(x, y, where="pre", color="k", lw=2, label="Yade 2PF, MS-P (closed side walls)")
for ax, t in zip(axs, ("with trapping", "without trapping")):
    ax.set_xlabel("wetting saturation $S_w$"); ax.set_title(f"primary drainage, {t}")
    ax.set_xlim(0, 1.02); ax.set_ylim(0, 12); ax.grid(alpha=.3)
axs[0].set_ylabel(r"$P_c R/\gamma$")
axs[0].legend(fontsize=7, loc="upper right"); axs[1].legend(fontsize=7, loc="upper right")
fig.suptitle("Peers on one packbed bed of 4,000 equal spheres (bulk porosity 0.418)", fontsize=10)
fig.tight_layout(); fig.savefig(sys.argv[2], dpi=110)
