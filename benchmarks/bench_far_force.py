"""Speed of the far-cell changes on the same work: old and new code in one process, interleaved.

The bench_before_after.py Galton rows use the unbounded board, whose orbits move with the
far-cell changes (benchmarks/far_force_bits.py), so their ratio compares different orbits.
Here: the paper's bounded Galton board (config/config.yaml; its orbits are the same bits in
both versions), both laws, and one 2.9e5-cell flight under a force (the far walk's cost per
cell).  ``--before DIR`` as in bench_before_after.py (a copy named ``noslipsim_before``).
Run: ``PYTHONPATH=src python benchmarks/bench_far_force.py --before /tmp/old/pkg``.

The rounds of one process agree to a few percent, but processes differ by up to 20 % (where the
loaded kernels land in memory is drawn per process): compare means over ten processes or more,
against an A/A run (a copy of the old commit as the new package), with ``--clock cpu`` (process
time, not wall time, on a shared host) and ``--only`` to time one case (benchmarks/RESULTS.md).
"""
import argparse
import importlib
import math
import os
import statistics
import sys
import time

import numpy as np

import noslipsim as new

ap = argparse.ArgumentParser()
ap.add_argument("--before", required=True)
ap.add_argument("--rounds", type=int, default=3)
ap.add_argument("--clock", choices=("wall", "cpu"), default="wall", help="wall time or this process's CPU time")
ap.add_argument("--only", default="", help="time only the cases whose name contains this")
ARGS = ap.parse_args()
sys.path.insert(0, os.path.abspath(ARGS.before))
old = importlib.import_module("noslipsim_before")
for pkg in (old, new):
    importlib.import_module(pkg.__name__ + ".tables")
    importlib.import_module(pkg.__name__ + ".initial")
ROUNDS = ARGS.rounds
CLOCK = time.perf_counter if ARGS.clock == "wall" else time.process_time

def paper(pkg, law, g):
    sc = pkg.tables.galton_board(2.0, 0.89, 1.0, law=law, gamma=g, top_row=0)
    rng = np.random.default_rng(1)
    n = 1000
    q = np.c_[rng.uniform(-0.5, 0.5, n), np.full(n, 2.0)]
    v = new.initial.unit_velocities(n, seed=7)
    kw = dict(stop_below=-10 * math.sqrt(3.0), max_time=2000.0, max_collisions=100000)
    pkg.simulate_many(sc, q[:2], v[:2], scheduler="sync", progress=False, **kw)
    return lambda: int(pkg.simulate_many(sc, q, v, scheduler="sync", progress=False, **kw).n_collisions.sum())

def far_flight(pkg, law):
    sc = pkg.tables.sinai_torus(0.1, law=law, force=(1e-4, 0.0))
    v = (1 / math.hypot(1, 1e-5), 1e-5 / math.hypot(1, 1e-5))
    pkg.simulate(sc, (0.5, 0.23), v, 0.0, max_collisions=1)
    return lambda: 291451 * int(pkg.simulate(sc, (0.5, 0.23), v, 0.0, max_collisions=1).n_collisions)

cases = {"paper Galton ensemble no-slip g=1/sqrt2 (coll/s)": (paper, ("no-slip", 1 / math.sqrt(2))),
         "paper Galton ensemble specular (coll/s)": (paper, ("specular", 0.0)),
         "torus r=0.1 force 1e-4: one 2.9e5-cell flight (cells/s)": (far_flight, ("specular",))}
print(f"load {os.getloadavg()}")
for name, (make, args) in cases.items():
    if ARGS.only not in name:
        continue
    runs = {"before": make(old, *args), "new": make(new, *args)}
    best = dict.fromkeys(runs, 0.0)
    ratios = []
    counts = {}
    for r in range(ROUNDS):
        rate = {}
        for key in (("before", "new") if r % 2 == 0 else ("new", "before")):
            t0 = CLOCK()
            n = runs[key]()
            rate[key] = n / (CLOCK() - t0)
            counts[key] = n
            best[key] = max(best[key], rate[key])
        ratios.append(rate["new"] / rate["before"])
    print(f"{name:<58} before {best['before']:>13,.0f} new {best['new']:>13,.0f} "
          f"new/before median {statistics.median(ratios):.3f} range {min(ratios):.2f}-{max(ratios):.2f} "
          f"(work {counts['before']} / {counts['new']})", flush=True)
print(f"load {os.getloadavg()}")
