#!/usr/bin/env python3
"""Experiments on why packbed's percolation differs from the source study's
(issue 32). Reads beds that `packbed ensemble ... --keep-beds` wrote and
prints markdown tables; needs only numpy.

    packbed ensemble examples/thesis/3d-percolation.toml --out D3 --keep-beds
    packbed ensemble examples/thesis/2d-percolation.toml --out D2 --keep-beds
    python3 scripts/percolation_experiments.py D2 D3 [--only=ABCDFGHWE] [--runs=N]
        [--keep=0.9,0.8,...] [--keep-fixed=P] [--wall-keep=...] [--per-ratio=N]
        [--placements=N] [--start=S] [--grid-beds=N]

scripts/validation.py runs them all and puts their tables in docs/validation.md.

Experiments (all deterministic: fixed seeds):
  A. wall contact by exact equality: how many wall-touching particles of
     packbed's beds have x == r (x == W - r) exactly in floating point.
  B. the study's chain search (recursive depth-first search over large-large
     contacts, from each large particle with x == r, at most 50 chains per
     start, paths of at most 250 particles, at most 20,000 chains) on
     packbed's beds, against packbed's cluster criterion; contacts by the
     study's absolute rule (gap <= 0.01).
  C. 3D: the study's stochastic placement (10 scales from 10 r_max down, 500
     random trials per scale, keep a trial that lowers the sum of the three
     support gaps without overlap) emulated on the supports of packbed's
     particles: the distribution of the gaps it leaves, and the share of
     supports within the study's 0.01 contact rule.
  D. 3D: packbed's beds with each contact given a gap drawn from a
     distribution (a contact counts when its gap <= 0.01): beds with a chain,
     chains and chain lengths by the study's search, against the study's
     tables. With --only=D a share P (--keep-fixed, default 0.6) of the
     contacts is kept at random; H uses the gaps its emulation left.
  F. 3D: contacts kept at random with probability p (bond dilution), and the
     study's search restricted to steps that advance along the axis.
  G. 3D: the study's search storing only the first chain of each start,
     neighbours tried furthest-advance first.
  H. 3D: the study's choice of supports (three closest below the lowest
     contour point near the impact) and its search, particle by particle on
     packbed's bed below; then D with the gaps it leaves.
  W. 3D: wall-touching particles recognised only with probability q.
  E. 2D: how large discs connect (large-large contacts per large disc, largest
     large cluster, local order) in packbed's beds, and in beds built on the
     study's integer contour grid with one-step sliding (emulated here).
"""

import csv
import glob
import json
import math
import os
import random
import sys

import numpy as np

ABS_TOL = 0.01  # the study's contact rule, length units


def load_bed(run_dir):
    s = json.load(open(os.path.join(run_dir, "summary.json")))
    box = s["box"]
    dim = s["dim"]
    cols = ["x", "y", "z"][:dim]
    xs, rs = [], []
    with open(os.path.join(run_dir, "particles.csv")) as f:
        for row in csv.DictReader(f):
            xs.append([float(row[c]) for c in cols])
            rs.append(float(row["r"]))
    size = [box["width"], box["depth"], box["height"]] if dim == 3 else [box["width"], box["height"]]
    return {
        "dim": dim,
        "x": np.array(xs),
        "r": np.array(rs),
        "size": size,
        "summary": s,
    }


def pairs_within(bed, tol_abs):
    """Pairs (i, j, gap) with gap <= tol_abs (absolute), O(n^2) in numpy."""
    x, r = bed["x"], bed["r"]
    out = []
    for i in range(len(r) - 1):
        d = np.sqrt(((x[i + 1:] - x[i]) ** 2).sum(axis=1)) - r[i] - r[i + 1:]
        for k in np.nonzero(d <= tol_abs)[0]:
            out.append((i, i + 1 + int(k), float(d[k])))
    return out


def wall_sets(bed, axis, exact, tol_abs=ABS_TOL):
    """Particles touching the low and high wall of `axis`: by exact equality
    x == r (W - x == r), or by gap <= tol_abs."""
    x, r, w = bed["x"][:, axis], bed["r"], bed["size"][axis]
    if exact:
        return set(np.nonzero(x == r)[0].tolist()), set(np.nonzero(w - x == r)[0].tolist())
    return set(np.nonzero(x - r <= tol_abs)[0].tolist()), set(np.nonzero(w - x - r <= tol_abs)[0].tolist())


def union_find(n, edges):
    """The root finder of the clusters that `edges` join among n particles."""
    parent = list(range(n))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for i, j in edges:
        parent[find(i)] = find(j)
    return find


def spans(n, large, edges, lo, hi):
    """Whether a cluster of large particles links lo to hi."""
    find = union_find(n, [(i, j) for i, j in edges if large[i] and large[j]])
    roots = {find(i) for i in lo if large[i]}
    return any(find(j) in roots for j in hi if large[j])


def study_search(adj, large, lo, hi, max_per_start=50, max_len=250, max_chains=20000, max_steps=200000, coord=None):
    """The study's recursive depth-first search: from each large particle of
    `lo`, simple paths of large particles to one in `hi`; a chain is stored
    when its set of particles is new. Returns (chains, step cap hit)."""
    chains = set()
    capped = False
    for s in sorted(i for i in lo if large[i]):
        found = 0
        steps = 0
        path = [s]
        on = {s}
        # iterative DFS: stack of neighbour iterators
        stack = [iter(adj[s])]
        if s in hi:
            chains.add(frozenset(path))
            continue
        while stack:
            if found >= max_per_start or len(chains) >= max_chains:
                break
            steps += 1
            if steps > max_steps:
                capped = True
                break
            v = next(stack[-1], None)
            if v is None:
                stack.pop()
                on.discard(path.pop())
                continue
            if v in on or not large[v]:
                continue
            if coord is not None and coord[v] <= coord[path[-1]]:
                continue
            if v in hi:
                key = frozenset(path + [v])
                if key not in chains:
                    chains.add(key)
                    found += 1
                continue
            if len(path) + 1 >= max_len:
                continue
            path.append(v)
            on.add(v)
            stack.append(iter(adj[v]))
        if len(chains) >= max_chains:
            break
    return chains, capped


def adjacency(n, edges):
    adj = [[] for _ in range(n)]
    for i, j in edges:
        adj[i].append(j)
        adj[j].append(i)
    return adj


def sweep_dirs(root):
    return sorted(glob.glob(os.path.join(root, "sweep", "*")))


def label(d):
    return os.path.basename(d).split("ratio-")[-1].replace("-", ":", 1).replace("-", ".")


def run_dirs(d):
    return sorted(glob.glob(os.path.join(d, "runs", "*")))


def sweeps(root, most):
    """Each sweep directory of `root` with its first `most` run directories."""
    for sd in sweep_dirs(root):
        yield sd, run_dirs(sd)[:most]


def against_study(sd, runs, study):
    """The label of a sweep directory, its number of beds, and the study's
    (beds with a chain, mean chains, mean length) there, dashes where the
    study has no such ratio."""
    lab = label(sd)
    return lab, len(runs), study.get(lab, ("-", "-", "-"))


def mean_text(values):
    return f"{np.mean(values):.2f}" if values else "-"


def print_head(titles, align, extra):
    """Prints a markdown table head: the columns `titles` ("a | b") aligned
    as `align` ("--- | ---:"), then a numeric column per title in `extra`."""
    print(f"| {titles} | {' | '.join(extra)} |")
    print(f"| {align} | " + " | ".join("---:" for _ in extra) + " |")


def is_large(r):
    # 20 is the large radius of every sweep here; the margin keeps a radius
    # that came back from text as 19.999999999 large.
    return r >= 20 * (1 - 1e-9)


def contact_graph(bed):
    """Particle count, mask of the large particles, and the contacts by the
    study's rule (gap <= ABS_TOL) of a bed."""
    edges = [(i, j) for i, j, _ in pairs_within(bed, ABS_TOL)]
    return len(bed["r"]), is_large(bed["r"]), edges


# ---------------------------------------------------------------- A and B
def exp_walls_and_search(root, sample):
    print(f"\n### A/B: wall equality and the study's chain search on packbed's beds ({root})\n")
    print("| ratio | beds | wall-touching particles (gap <= 0.01) | of them x == r exactly | beds with a chain: clusters span | study search, walls by x == r | study search, walls by gap <= 0.01 | beds where the search misses an existing chain | mean chains (study search, gap walls) | mean length |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for sd, runs in sweeps(root, sample):
        touch = exact = 0
        pb = st_exact = st_tol = missed = 0
        nchains, lengths = [], []
        for rd in runs:
            bed = load_bed(rd)
            n, large, edges = contact_graph(bed)
            adj = adjacency(n, edges)
            any_pb = any_e = any_t = False
            bed_chains = []
            for axis in range(bed["dim"] - 1):
                lo_e, hi_e = wall_sets(bed, axis, True)
                lo_t, hi_t = wall_sets(bed, axis, False)
                touch += len(lo_t) + len(hi_t)
                exact += len(lo_e & lo_t) + len(hi_e & hi_t)
                any_pb |= spans(n, large, edges, lo_t, hi_t)
                ce, _ = study_search(adj, large, lo_e, hi_e)
                ct, _ = study_search(adj, large, lo_t, hi_t)
                any_e |= bool(ce)
                any_t |= bool(ct)
                bed_chains.extend(ct)
            pb += any_pb
            st_exact += any_e
            st_tol += any_t
            missed += any_pb and not any_e
            nchains.append(len(bed_chains))
            lengths.extend(len(c) for c in bed_chains)
        k = len(runs)
        ml = f"{np.mean(lengths):.2f}" if lengths else "-"
        print(f"| {label(sd)} | {k} | {touch} | {exact} ({100 * exact / max(touch, 1):.1f} %) | {100 * pb / k:.0f} % | {100 * st_exact / k:.0f} % | {100 * st_tol / k:.0f} % | {missed} | {np.mean(nchains):.1f} | {ml} |")


# ---------------------------------------------------------------- C
def gaps3(p, sup):
    return [math.sqrt((p[0] - c[0]) ** 2 + (p[1] - c[1]) ** 2 + (p[2] - c[2]) ** 2) - rr for c, rr in sup]


def study_placement(p0, sup, r_max, rng):
    """The study's stochastic search from p0 over the supports `sup` (centre,
    r_i + r_j): 10 scales, step 10 r_max / 10^k, 500 trials each; a trial
    replaces the best when no gap is negative and the sum of gaps is lower."""
    best = list(p0)
    g = gaps3(best, sup)
    bsum = sum(g) if min(g) >= 0 else math.inf
    step = 10 * r_max
    for _ in range(10):
        for _ in range(500):
            t = [best[k] + rng.uniform(-step, step) for k in range(3)]
            gt = gaps3(t, sup)
            if min(gt) >= 0:
                s = sum(gt)
                if s < bsum:
                    best, bsum, g = t, s, gt
        step /= 10
    return g


def support_sets(bed):
    """Per particle resting on exactly three lower particles (packbed's exact
    supports): its centre and the supports (centre, r_i + r_j)."""
    x, r = bed["x"], bed["r"]
    out = []
    pairs = pairs_within(bed, 1e-6 * 10)
    below = {}
    for i, j, _ in pairs:
        lo_, hi_ = (i, j) if x[i][2] < x[j][2] else (j, i)
        below.setdefault(hi_, []).append(lo_)
    for i, sups in below.items():
        if len(sups) == 3 and x[i][2] - r[i] > 1e-6:
            out.append((x[i].tolist(), [(x[j].tolist(), r[i] + r[j]) for j in sups]))
    return out


def exp_placement(root, n_sets, start):
    rng = random.Random(12345)
    sets = []
    for sd in sweep_dirs(root):
        for rd in run_dirs(sd)[:3]:
            sets.extend(support_sets(load_bed(rd)))
    rng.shuffle(sets)
    sets = sets[:n_sets]
    gaps = []
    rejected = 0
    for centre, sup in sets:
        # The start: the lowest contour point near the impact, i.e. near the
        # resting place on the integer grid, at the height where it clears
        # every support.
        dx, dy = rng.uniform(-start, start), rng.uniform(-start, start)
        p = [centre[0] + dx, centre[1] + dy, centre[2]]
        while min(gaps3(p, sup)) < 0:
            p[2] += 0.01
        g = study_placement(p, sup, 20.0, rng)
        if max(g) <= 1.0:
            gaps.extend(g)
        else:
            rejected += 1
    return np.array(gaps), rejected, len(sets)


# ---------------------------------------------------------------- D
def exp_diluted(root, gap_pool, runs_per_ratio, study, source="the emulated placement"):
    rng = np.random.default_rng(7)
    p_keep = float((gap_pool <= ABS_TOL).mean())
    print(f"\n### D: packbed's 3D beds, each contact given a gap drawn from {source} (P(gap <= 0.01) = {p_keep:.3f})\n")
    print("| ratio | beds | with a chain, packbed exact | with a chain, emulated gaps | study | mean chains (study search) | study mean chains | mean length | study mean length | mean large-large contacts per large sphere, exact → emulated |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |")
    for sd, runs in sweeps(root, runs_per_ratio):
        pb = em = 0
        nch, lens, zl0, zl1 = [], [], [], []
        for rd in runs:
            bed = load_bed(rd)
            n = len(bed["r"])
            large = is_large(bed["r"])
            exact_edges = [(i, j) for i, j, g in pairs_within(bed, 1e-5)]
            drawn = rng.choice(gap_pool, size=len(exact_edges))
            kept = [e for e, g in zip(exact_edges, drawn) if g <= ABS_TOL]
            adj = adjacency(n, kept)
            nl = int(large.sum())
            zl0.append(2 * sum(1 for i, j in exact_edges if large[i] and large[j]) / max(nl, 1))
            zl1.append(2 * sum(1 for i, j in kept if large[i] and large[j]) / max(nl, 1))
            a0 = a1 = False
            chains = []
            for axis in range(2):
                lo, hi = wall_sets(bed, axis, False)
                a0 |= spans(n, large, exact_edges, lo, hi)
                a1 |= spans(n, large, kept, lo, hi)
                c, _ = study_search(adj, large, lo, hi)
                chains.extend(c)
            pb += a0
            em += a1
            nch.append(len(chains))
            lens.extend(len(c) for c in chains)
        lab, k, ref = against_study(sd, runs, study)
        ml = mean_text(lens)
        print(f"| {lab} | {k} | {100 * pb / k:.0f} % | {100 * em / k:.0f} % | {ref[0]} % | {np.mean(nch):.2f} | {ref[1]} | {ml} | {ref[2]} | {np.mean(zl0):.2f} → {np.mean(zl1):.2f} |")


def exp_directed_and_diluted(root, runs_per_ratio, study, ps):
    """3D: the study's search restricted to steps that advance along the
    chain's axis (a directed search), and packbed's contacts kept each with
    probability p (random bond dilution), against the study's table."""
    rng = np.random.default_rng(11)
    print("\n### F: 3D, a directed search (every step advances along the axis) and random contact dilution\n")
    print_head("ratio | beds | study: with a chain / mean chains / mean length | packbed: with a chain | directed search: with a chain / mean chains / mean length",
               "--- | ---: | --- | ---: | ---", [f"kept p = {p}" for p in ps])
    for sd, runs in sweeps(root, runs_per_ratio):
        pb = dr = 0
        dil = [0] * len(ps)
        nch, lens = [], []
        for rd in runs:
            bed = load_bed(rd)
            n, large, edges = contact_graph(bed)
            adj = adjacency(n, edges)
            a0 = a1 = False
            ad = [False] * len(ps)
            draws = rng.random(len(edges))
            chains = []
            for axis in range(2):
                lo, hi = wall_sets(bed, axis, False)
                a0 |= spans(n, large, edges, lo, hi)
                c, _ = study_search(adj, large, lo, hi, coord=bed["x"][:, axis])
                a1 |= bool(c)
                chains.extend(c)
                for k, p in enumerate(ps):
                    ad[k] |= spans(n, large, [e for e, u in zip(edges, draws) if u < p], lo, hi)
            pb += a0
            dr += a1
            for k in range(len(ps)):
                dil[k] += ad[k]
            nch.append(len(chains))
            lens.extend(len(c) for c in chains)
        lab, k, ref = against_study(sd, runs, study)
        ml = mean_text(lens)
        cells = " | ".join(f"{100 * v / k:.0f} %" for v in dil)
        print(f"| {lab} | {k} | {ref[0]} % / {ref[1]} / {ref[2]} | {100 * pb / k:.0f} % | {100 * dr / k:.0f} % / {np.mean(nch):.2f} / {ml} | {cells} |")


def exp_first_chain(root, runs_per_ratio, study, q):
    """3D: the study's search storing only the first chain found from each
    start, neighbours tried in order of their advance along the axis (a
    greedy depth-first search), on packbed's contacts and on the contacts
    kept with probability q."""
    rng = np.random.default_rng(13)
    print(f"\n### G: 3D, one chain per start, neighbours tried furthest-advance first (exact contacts; contacts kept with p = {q})\n")
    print("| ratio | beds | study: with a chain / mean chains / mean length | exact: with a chain / mean chains / mean length | kept p: with a chain / mean chains / mean length |")
    print("| --- | ---: | --- | --- | --- |")
    for sd, runs in sweeps(root, runs_per_ratio):
        res = [[0, [], []], [0, [], []]]
        for rd in runs:
            bed = load_bed(rd)
            n, large, edges = contact_graph(bed)
            draws = rng.random(len(edges))
            for slot, es in enumerate([edges, [e for e, u in zip(edges, draws) if u < q]]):
                chains = []
                for axis in range(2):
                    c = bed["x"][:, axis]
                    adj = adjacency(n, es)
                    for a in adj:
                        a.sort(key=lambda v: -c[v])
                    lo, hi = wall_sets(bed, axis, False)
                    found, _ = study_search(adj, large, lo, hi, max_per_start=1)
                    chains.extend(found)
                res[slot][0] += bool(chains)
                res[slot][1].append(len(chains))
                res[slot][2].extend(len(c) for c in chains)
        lab, k, ref = against_study(sd, runs, study)
        cells = [f"{100 * a / k:.0f} % / {np.mean(b):.2f} / {mean_text(c)}" for a, b, c in res]
        print(f"| {lab} | {k} | {ref[0]} % / {ref[1]} / {ref[2]} | {cells[0]} | {cells[1]} |")


def study_support_placement(bed, i, rng, max_triples=10):
    """The study's placement of particle i onto packbed's bed of the particles
    dropped before it (ids below i): the impact near packbed's resting place;
    the lowest point of the contour (integer grid, within one radius of the
    impact); the three particles below that point with the smallest surface
    gap as supports; the stochastic search from that point lowering the sum of
    the three gaps without overlapping any particle, wall or the floor;
    accepted when every gap <= 1, else the next triple of the five closest.
    Returns (gaps of the accepted triple or None, whether that triple is
    packbed's own supports of i)."""
    x, r = bed["x"], bed["r"]
    ri = r[i]
    W, D = bed["size"][0], bed["size"][1]
    env = np.arange(i)
    ix, iy = x[i][0] + rng.uniform(-ri / 2, ri / 2), x[i][1] + rng.uniform(-ri / 2, ri / 2)
    near = env[(np.abs(x[env, 0] - ix) < 2 * ri + r[env] + 2) & (np.abs(x[env, 1] - iy) < 2 * ri + r[env] + 2)]
    if len(near) < 3:
        return None, False
    gxs = np.arange(math.ceil(max(ri, ix - ri)), math.floor(min(W - ri, ix + ri)) + 1, dtype=float)
    gys = np.arange(math.ceil(max(ri, iy - ri)), math.floor(min(D - ri, iy + ri)) + 1, dtype=float)
    if not len(gxs) or not len(gys):
        return None, False
    GX, GY = np.meshgrid(gxs, gys)
    reach = r[near] + ri
    d2 = (GX[..., None] - x[near, 0]) ** 2 + (GY[..., None] - x[near, 1]) ** 2
    lift = np.where(d2 < reach ** 2, x[near, 2] + np.sqrt(np.maximum(reach ** 2 - d2, 0)), -np.inf)
    h = np.maximum(lift.max(axis=-1), ri)
    k = np.unravel_index(np.argmin(h), h.shape)
    p0 = [float(GX[k]), float(GY[k]), float(h[k])]
    below = near[x[near, 2] < p0[2]]
    if len(below) < 3:
        return None, False
    gap0 = np.sqrt(((x[below] - p0) ** 2).sum(axis=1)) - r[below] - ri
    order = below[np.argsort(gap0)][:5]
    obst = [(x[j].tolist(), r[j] + ri) for j in near]
    lows = [ri, W - ri, ri, D - ri]
    true_sup = set()
    for j in range(i):
        if np.sqrt(((x[j] - x[i]) ** 2).sum()) - r[j] - ri <= 1e-5 and x[j][2] < x[i][2]:
            true_sup.add(j)
    import itertools
    for tri in list(itertools.combinations(range(len(order)), 3))[:max_triples]:
        sup = [(x[order[t]].tolist(), r[order[t]] + ri) for t in tri]

        def ok(q):
            if q[2] < ri or q[0] < lows[0] or q[0] > lows[1] or q[1] < lows[2] or q[1] > lows[3]:
                return False
            for c, rr in obst:
                if (q[0] - c[0]) ** 2 + (q[1] - c[1]) ** 2 + (q[2] - c[2]) ** 2 < rr * rr * (1 - 1e-12):
                    return False
            return True

        best = list(p0)
        if not ok(best):
            continue
        bsum = sum(gaps3(best, sup))
        step = 10 * 20.0
        for _ in range(10):
            for _ in range(500):
                t = [best[m] + rng.uniform(-step, step) for m in range(3)]
                sm = sum(gaps3(t, sup))
                if sm < bsum and ok(t):
                    best, bsum = t, sm
            step /= 10
        g = gaps3(best, sup)
        if max(g) <= 1.0:
            return g, {int(order[t]) for t in tri} == true_sup
    return None, False


def exp_study_supports(root, per_ratio, seed):
    rng = random.Random(seed)
    print(f"\n### H: the study's support choice and search emulated particle by particle on packbed's 3D beds ({per_ratio} particles per ratio)\n")
    print("| ratio | particles placed | no triple accepted | accepted triple = packbed's supports | support gaps: median / 75 % / 90 % | share of support gaps <= 0.01 | of supports with a gap > 0.01, gap <= 0.1 |")
    print("| --- | ---: | ---: | ---: | --- | ---: | ---: |")
    pooled = []
    for sd in sweep_dirs(root):
        gaps, none, same, tried = [], 0, 0, 0
        for rd in run_dirs(sd)[:5]:
            bed = load_bed(rd)
            nb = bed["summary"]["counts"]["base_layer"]
            ids = list(range(nb, len(bed["r"])))
            rng.shuffle(ids)
            for i in ids[:per_ratio // 5]:
                tried += 1
                g, eq = study_support_placement(bed, i, rng)
                if g is None:
                    none += 1
                    continue
                gaps.extend(g)
                same += eq
        g = np.array(gaps)
        pooled.extend(gaps)
        q = np.quantile(g, [0.5, 0.75, 0.9])
        big = g[g > ABS_TOL]
        print(f"| {label(sd)} | {tried} | {none} | {same} | {q[0]:.2g} / {q[1]:.2g} / {q[2]:.2g} | {(g <= ABS_TOL).mean():.3f} | {(big <= 0.1).mean() if len(big) else float('nan'):.2f} |")
    return np.array(pooled)


def exp_wall_terminals(root, runs_per_ratio, study, qs):
    """3D: packbed's exact contacts, but each wall-touching large particle
    recognised as touching its wall only with probability q (as if the
    study's test x == r held exactly for a share q of them)."""
    rng = np.random.default_rng(17)
    print("\n### W: 3D, wall-touching particles recognised with probability q (contacts exact)\n")
    print_head("ratio | beds | study", "--- | ---: | ---:", [f"q = {q}" for q in qs])
    for sd, runs in sweeps(root, runs_per_ratio):
        hits = [0] * len(qs)
        for rd in runs:
            bed = load_bed(rd)
            n, large, edges = contact_graph(bed)
            u = rng.random((2, 2, n))
            for k, q in enumerate(qs):
                a = False
                for axis in range(2):
                    lo, hi = wall_sets(bed, axis, False)
                    lo = {i for i in lo if u[axis, 0, i] < q}
                    hi = {i for i in hi if u[axis, 1, i] < q}
                    a |= spans(n, large, edges, lo, hi)
                hits[k] += a
        lab, k, ref = against_study(sd, runs, study)
        cells = " | ".join(f"{100 * h / k:.0f} %" for h in hits)
        print(f"| {lab} | {k} | {ref[0]} % | {cells} |")


def tolerance_difference(root, runs_per_ratio):
    """(contacts by the study's rule gap <= 0.01, of them with a gap above
    packbed's 1e-6 of the smaller radius) over the first beds of each ratio."""
    tot = extra = 0
    for sd in sweep_dirs(root):
        for rd in run_dirs(sd)[:runs_per_ratio]:
            b = load_bed(rd)
            for i, j, g in pairs_within(b, ABS_TOL):
                tot += 1
                extra += g > 1e-6 * min(b["r"][i], b["r"][j])
    return tot, extra


def recheck_misses(root):
    """Beds whose clusters span but where the study's search (walls by gap <=
    0.01) stored no chain within its cap of search steps: the search again
    with 10^8 steps per start."""
    for sd in sweep_dirs(root):
        for rd in run_dirs(sd):
            b = load_bed(rd)
            n, large, edges = contact_graph(b)
            adj = adjacency(n, edges)
            found = capped = False
            spans_any = False
            for axis in range(b["dim"] - 1):
                lo, hi = wall_sets(b, axis, False)
                if not spans(n, large, edges, lo, hi):
                    continue
                spans_any = True
                c, cap = study_search(adj, large, lo, hi)
                found |= bool(c)
                capped |= cap
            if spans_any and not found:
                more = 0
                for axis in range(b["dim"] - 1):
                    lo, hi = wall_sets(b, axis, False)
                    more += len(study_search(adj, large, lo, hi, max_steps=10**8)[0])
                print(f"- {label(sd)}, bed {os.path.basename(rd)}: no chain within 200,000 steps per start (cap hit: {capped}); with 10^8 steps: {more} chains")


STUDY_3D = {"1:1": (100, 15.46, 7.56), "1:2": (100, 11.04, 7.79), "1:3": (98, 6.91, 7.94),
            "1:4": (84, 4.36, 7.80), "1:5": (59, 2.01, 8.14), "1:6": (36, 0.89, 8.02)}
STUDY_2D = {"1:1": 98, "1:1.5": 82, "1:2": 59, "1:2.25": 33, "1:2.5": 23}


# ---------------------------------------------------------------- E
def structure(x, r, size, tol):
    """Large-large contacts per large disc, largest large cluster / large
    discs, share of large discs with at least 4 large neighbours, and the mean
    |psi_6| of large discs over their large contacts."""
    n = len(r)
    large = is_large(r)
    bed = {"x": x, "r": r}
    edges = [(i, j) for i, j, _ in pairs_within(bed, tol) if large[i] and large[j]]
    nl = int(large.sum())
    adj = adjacency(n, edges)
    find = union_find(n, edges)
    sizes = {}
    for i in range(n):
        if large[i]:
            sizes[find(i)] = sizes.get(find(i), 0) + 1
    psi = []
    for i in range(n):
        if large[i] and adj[i]:
            a = [math.atan2(x[j][1] - x[i][1], x[j][0] - x[i][0]) for j in adj[i]]
            psi.append(abs(sum(complex(math.cos(6 * t), math.sin(6 * t)) for t in a)) / len(a))
    z = 2 * len(edges) / max(nl, 1)
    many = sum(1 for i in range(n) if large[i] and len(adj[i]) >= 4) / max(nl, 1)
    return z, max(sizes.values(), default=0) / max(nl, 1), many, float(np.mean(psi)) if psi else 0.0


def grid_bed(width, height, radii, ratio, rng, cyclic=False):
    """A 2D bed the study's way: each disc dropped at a random integer x; its
    contour h(x) (the centre height at which a disc of its radius dropped at x
    first touches the floor or a placed disc) on the integer grid; it slides
    one grid step at a time toward the lower neighbour (a random side on a
    tie) until both neighbours are higher; then its place is refined to real
    values: the exact rest on the two supports around the grid minimum
    (or on one support and the floor / wall), found by rolling from the grid
    point down the exact contour. Filled until 100 discs would stick out."""
    xs, rs = [], []
    misses = 0
    cols = np.arange(0, int(width) + 1, dtype=float)
    probs = np.array(ratio, dtype=float) / sum(ratio)
    drawn = np.zeros(len(radii))
    while misses < 100:
        if cyclic:
            # a fixed sequence by the ratio: the species furthest behind its share
            s = int(np.argmin((drawn + 1) / probs))
        else:
            s = int(rng.choice(len(radii), p=probs))
        drawn[s] += 1
        r = radii[s]
        lo, hi = int(math.ceil(r)), int(math.floor(width - r))
        gx = cols[lo:hi + 1]
        px, pr = np.array(xs).reshape(-1, 2), np.array(rs)

        def contour(x):
            x = np.atleast_1d(x)
            if not len(pr):
                return np.full(len(x), r)
            reach = pr[None, :] + r
            dx = x[:, None] - px[None, :, 0]
            lift = np.where(np.abs(dx) < reach, px[None, :, 1] + np.sqrt(np.maximum(reach ** 2 - dx ** 2, 0.0)), -np.inf)
            return np.maximum(lift.max(axis=1), r)

        h = contour(gx)
        k = int(rng.integers(0, len(gx)))
        while True:
            left = h[k - 1] if k > 0 else math.inf
            right = h[k + 1] if k + 1 < len(gx) else math.inf
            if left >= h[k] and right >= h[k]:
                break
            if left < right:
                k -= 1
            elif right < left:
                k += 1
            else:
                k += int(rng.choice([-1, 1]))
        x0, y0 = refine(gx[k], contour, r, width)
        if y0 + r > height:
            misses += 1
            continue
        xs.append((x0, y0))
        rs.append(r)
    return np.array(xs), np.array(rs)


def exp_2d_order(ratio, beds):
    """2D contour-grid beds with species drawn at random and in a fixed
    sequence by the ratio: beds with a chain and large-large contacts."""
    rng = np.random.default_rng(31)
    a, b = ratio
    print(f"\n### E2: 2D contour-grid beds, large:small {a:g}:{b:g}, species drawn at random or in a fixed sequence ({beds} beds each)\n")
    print("| order | beds with a chain | large-large contacts per large disc | largest large cluster / large discs |")
    print("| --- | ---: | ---: | ---: |")
    for cyclic in (False, True):
        rows, chains = [], 0
        for _ in range(beds):
            x, r = grid_bed(600.0, 600.0, [20.0, 10.0], [a, b], rng, cyclic)
            bed = {"x": x, "r": r, "size": [600.0, 600.0], "dim": 2}
            rows.append(structure(x, r, bed["size"], ABS_TOL))
            lo, hi = wall_sets(bed, 0, False)
            chains += spans(*contact_graph(bed), lo, hi)
        m = np.mean(rows, axis=0)
        print(f"| {'fixed sequence' if cyclic else 'random'} | {100 * chains / beds:.0f} % | {m[0]:.3f} | {m[1]:.3f} |")


def refine(x0, contour, r, width):
    """The exact resting place near the grid minimum x0: the lowest point of
    the exact contour within one grid step of x0 (golden-section search; the
    contour is unimodal there), or the wall position when that is lower."""
    a, b = max(r, x0 - 1.0), min(width - r, x0 + 1.0)
    g = (math.sqrt(5) - 1) / 2
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = contour(c)[0], contour(d)[0]
    for _ in range(90):
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = contour(c)[0]
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = contour(d)[0]
    xm = (a + b) / 2
    for xw in (r, width - r):
        if abs(xw - x0) <= 1.0 and contour(xw)[0] < contour(xm)[0]:
            xm = xw
    return xm, float(contour(xm)[0])


def exp_2d(root, runs_per_ratio, grid_beds):
    print(f"\n### E: 2D structure of the large discs ({runs_per_ratio} packbed beds and {grid_beds} contour-grid beds per ratio)\n")
    print("| ratio | bed | discs | packing (global) | large-large contacts per large disc | largest large cluster / large discs | large discs with >= 4 large contacts | mean abs(psi6) of large discs | beds with a chain |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    rng = np.random.default_rng(2024)
    for sd in sweep_dirs(root):
        lab = label(sd)
        a, b = (float(v) for v in lab.split(":"))
        rows = []
        chains = 0
        pack = []
        ndisc = []
        for rd in run_dirs(sd)[:runs_per_ratio]:
            bed = load_bed(rd)
            rows.append(structure(bed["x"], bed["r"], bed["size"], ABS_TOL))
            pack.append(bed["summary"]["packing"]["global"])
            ndisc.append(len(bed["r"]))
            lo, hi = wall_sets(bed, 0, False)
            chains += spans(*contact_graph(bed), lo, hi)
        m = np.mean(rows, axis=0)
        print(f"| {lab} | packbed | {np.mean(ndisc):.0f} | {np.mean(pack):.4f} | {m[0]:.3f} | {m[1]:.3f} | {m[2]:.3f} | {m[3]:.3f} | {100 * chains / len(rows):.0f} % |")
        rows, chains, pack, ndisc = [], 0, [], []
        for _ in range(grid_beds):
            x, r = grid_bed(600.0, 600.0, [20.0, 10.0], [a, b], rng)
            bed = {"x": x, "r": r, "size": [600.0, 600.0], "dim": 2}
            rows.append(structure(x, r, bed["size"], ABS_TOL))
            pack.append(float((math.pi * r ** 2).sum() / 600.0 ** 2))
            ndisc.append(len(r))
            lo, hi = wall_sets(bed, 0, False)
            chains += spans(*contact_graph(bed), lo, hi)
        m = np.mean(rows, axis=0)
        print(f"| {lab} | contour grid | {np.mean(ndisc):.0f} | {np.mean(pack):.4f} | {m[0]:.3f} | {m[1]:.3f} | {m[2]:.3f} | {m[3]:.3f} | {100 * chains / len(rows):.0f} % (study {STUDY_2D.get(lab, '-')} %) |")


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    opts = dict(a[2:].split("=", 1) for a in argv if a.startswith("--") and "=" in a)
    d2, d3 = args
    runs = int(opts.get("runs", 100))
    only = opts.get("only", "ABCDFGHE")
    if "A" in only or "B" in only:
        exp_walls_and_search(d3, runs)
        exp_walls_and_search(d2, runs)
    if "C" in only:
        n_sets, start = int(opts.get("placements", 600)), float(opts.get("start", 1.0))
        gaps, rejected, tried = exp_placement(d3, n_sets, start)
        print(f"\n### C: the study's stochastic search emulated on {tried} of packbed's own support triples (3D; start within ±{start} of the rest, at the height clearing every support)\n")
        qs = np.quantile(gaps, [0.1, 0.25, 0.5, 0.75, 0.9])
        print(f"- accepted {tried - rejected} of {tried} (every gap <= 1); support gaps: min {gaps.min():.2e}, quantiles 10/25/50/75/90 % = " + ", ".join(f"{q:.3g}" for q in qs) + f", max {gaps.max():.3g}")
        print(f"- share of support gaps <= 0.01 (counted as contacts by the study's rule): {(gaps <= ABS_TOL).mean():.3f}; <= 0.1: {(gaps <= 0.1).mean():.3f}")
    if "D" in only:
        q = float(opts.get("keep-fixed", 0.6))
        pool = np.where(np.arange(1000) < round(1000 * q), 0.0, 1.0)
        exp_diluted(d3, pool, runs, STUDY_3D, f"a share {q} of zeros, the rest 1 (contacts kept at random)")
    if "F" in only:
        ps = [float(v) for v in opts.get("keep", "0.9,0.8,0.7,0.65,0.6,0.5").split(",")]
        exp_directed_and_diluted(d3, runs, STUDY_3D, ps)
    if "W" in only:
        qs = [float(v) for v in opts.get("wall-keep", "0.5,0.3,0.2,0.1").split(",")]
        exp_wall_terminals(d3, runs, STUDY_3D, qs)
    if "G" in only:
        exp_first_chain(d3, runs, STUDY_3D, float(opts.get("keep-fixed", 0.6)))
    if "H" in only:
        pool = exp_study_supports(d3, int(opts.get("per-ratio", 100)), 99)
        exp_diluted(d3, pool, runs, STUDY_3D)
    if "O" in only:
        exp_2d_order((1.0, 2.0), int(opts.get("grid-beds", 20)))
    if "E" in only:
        exp_2d(d2, runs, int(opts.get("grid-beds", 20)))


if __name__ == "__main__":
    main(sys.argv[1:])
