#!/usr/bin/env python3
"""The pore network's permeability on the settling rules' beds, from the
loosest (hit-and-stick) to the densest (momentum), against Carman-Kozeny and
van der Hoef, Beetstra & Kuipers (2005) at each bed's own bulk porosity.

Equal spheres of radius 1, 3D, periodic box 30 x 30, 8,000 spheres, seeds
1..S. k is the mean of the three axes over d^2 (`permeability.
k_over_d32_squared`); Carman-Kozeny's ratio is packbed's own
(`permeability.k_over_kozeny_carman`, eps^3 / (180 (1 - eps)^2)); van der
Hoef's is k / (d^2 (1 - phi) / (18 phi F)), F = 10 phi / (1 - phi)^2 +
(1 - phi)^2 (1 + 1.5 sqrt(phi)), their fit to lattice-Boltzmann drag on
random arrays of equal spheres, phi 0.1-0.6.

Usage, from the repository root after `cargo build --release`:
    python3 scripts/settling-permeability.py [--seeds 2]
Prints a Markdown table.
"""
import argparse
import math
import tempfile

from settling_bed import settle
RULES = [
    ("contacts = 1", "hit-and-stick"),
    ("sticking = 0.6", ""),
    ("friction_angle = 35", ""),
    ("sticking = 0.3", ""),
    ("contacts = 2", "two contacts"),
    ("friction_angle = 25", ""),
    ("friction_angle = 15", ""),
    ("sticking = 0.1", ""),
    ("", "the default rule"),
    ("restitution = 0.5", "momentum"),
    ("restitution = 0.3", "momentum"),
]


def van_der_hoef(phi):
    f = 10.0 * phi / (1.0 - phi) ** 2 + (1.0 - phi) ** 2 * (1.0 + 1.5 * math.sqrt(phi))
    return (1.0 - phi) / (18.0 * phi * f)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=2)
    args = ap.parse_args()
    work = tempfile.mkdtemp()
    print("| rule | bulk φ | k/d² (mean of x, y, z) | anisotropy k_z/k_x | ÷ Carman–Kozeny | ÷ van der Hoef |")
    print("|---|---|---|---|---|---|")
    for rule, name in RULES:
        rows = []
        for seed in range(1, args.seeds + 1):
            v = settle(work, seed=seed, count=8000, width=30, size="radius = 1", rule=rule,
                       measures=["packing", "pores", "permeability"])
            phi = v["packing"]["bulk"]
            k = v["permeability"]
            kd2 = k["k_over_d32_squared"]
            rows.append((phi, kd2, k["anisotropy"], k["k_over_kozeny_carman"], kd2 / van_der_hoef(phi)))
        mean = [sum(r[i] for r in rows) / len(rows) for i in range(5)]
        label = f"`{rule}`" if rule else ""
        if name:
            label = f"{label} ({name})" if label else name
        print(f"| {label} | {mean[0]:.3f} | {mean[1]:.3g} | {mean[2]:.2f} | {mean[3]:.2f} | {mean[4]:.2f} |")


if __name__ == "__main__":
    main()
