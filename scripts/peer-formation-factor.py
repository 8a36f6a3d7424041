"""Formation factor of a packbed bed by a voxel finite-difference solve
(PoreSpy's `simulations.tortuosity_fd`): a reference for packbed's network
formation factor that needs no throat conductance.

The full periodic x-y square of the bed, z in [z0, z1], voxelised with
`res` voxels per diameter (scripts/peer-porespy.py's voxelise), a potential
drop along z, no-flux sides. Prints one JSON line. The voxel F falls as the
resolution rises (throats pinched by the grid); extrapolate `F + c / res`
from two resolutions.

    venv/bin/python scripts/peer-formation-factor.py BED_DIR RES Z0 Z1

BED_DIR holds the bed's particles.csv and summary.json; its box is read from
summary.json (periodic sides assumed).
"""
import importlib.util
import json
import os
import sys
import time

import numpy as np


def main():
    bed, res, z0, z1 = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
    here = os.path.dirname(os.path.abspath(__file__))
    spec = importlib.util.spec_from_file_location("peer_porespy", os.path.join(here, "peer-porespy.py"))
    pp = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(pp)
    import porespy as ps

    xyz, r, summ = pp.load_bed(bed)
    W, D = float(summ["box"]["width"]), float(summ["box"]["depth"])
    d = 2.0 * float(np.median(r))
    h = d / res
    t = time.time()
    im = pp.voxelise(xyz, r, W, D, z0, z1, h)
    t1 = time.time()
    out = ps.simulations.tortuosity_fd(im, axis=2)
    t2 = time.time()
    print(json.dumps(dict(
        bed=os.path.abspath(bed), res_per_d=res, z0=z0, z1=z1, shape=list(im.shape),
        porosity=float(im.mean()), formation_factor=float(out.formation_factor),
        tortuosity=float(out.tortuosity), voxelise_s=t1 - t, solve_s=t2 - t1,
        porespy=ps.__version__)), flush=True)


if __name__ == "__main__":
    main()
