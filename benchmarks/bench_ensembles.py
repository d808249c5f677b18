"""Ensemble throughput (issue: lattices, ensembles at scale).

Galton board (a1 = (2, 0), a2 = (1, sqrt 3), pegs r = 0.5, g = 1, dropped at unit
speed in a random direction, stopped 100 rows down) and a Sinai torus without
force (r = 0.25): collisions per second of ``simulate_many`` on one core (serial
kernel, 'sync') and on all cores (dask threads), then the paper-size Galton
experiment (100,000 particles for each law).  Run:
``python benchmarks/bench_ensembles.py [--paper]``.
"""
import argparse
import math
import os
import sys
import time

import numpy as np

import noslipsim as ns
from noslipsim import initial, tables
from noslipsim.experiments import galton_distribution

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import machine_line

ROWS = 100
DEPTH = ROWS * math.sqrt(3.0)


def rate(scene, q0, n, scheduler, chunk_size=None, **kw):
    v = initial.unit_velocities(n, seed=7)
    q = np.tile(q0, (n, 1))
    ns.simulate_many(scene, q[:4], v[:4], scheduler=scheduler, chunk_size=2, progress=False, **kw)  # compile
    t0 = time.perf_counter()
    ds = ns.simulate_many(scene, q, v, scheduler=scheduler, chunk_size=chunk_size, progress=False, **kw)
    dt = time.perf_counter() - t0
    return int(ds.n_collisions.sum()) / dt, dt


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--paper", action="store_true", help="also time the paper-size Galton experiment")
    args = ap.parse_args()
    print(machine_line(numpy=True))
    galton = tables.galton_board(2.0, 0.5, 1.0)
    sinai = tables.sinai_torus(0.25)
    cases = [
        ("Galton no-slip", galton, (1.0, 0.0), 2000, dict(max_collisions=10**7, stop_below=-DEPTH, max_time=1e4)),
        ("Galton specular", galton.replace(law="specular"), (1.0, 0.0), 2000,
         dict(max_collisions=10**7, stop_below=-DEPTH, max_time=1e4)),
        ("Sinai torus (no force)", sinai, (0.45, 0.1), 200, dict(max_collisions=100_000)),
    ]
    print(f"{'case':<24}{'1 core coll/s':>16}{'all cores coll/s':>18}{'speed-up':>10}")
    for name, scene, q0, n, kw in cases:
        one, _ = rate(scene, q0, n, "sync", **kw)
        many, _ = rate(scene, q0, n, "threads", chunk_size=max(1, n // 16), **kw)
        print(f"{name:<24}{one:>16,.0f}{many:>18,.0f}{many / one:>10.2f}")
    if args.paper:
        t0 = time.perf_counter()
        ds = galton_distribution(100_000, rows=ROWS, max_time=1000.0, progress=False)
        dt = time.perf_counter() - t0
        print(f"paper-size Galton experiment (2 x 100,000 particles, {ROWS} rows): {dt:.1f} s; "
              f"share not arrived: {dict(zip(ds.law.values.tolist(), ds.share_not_arrived.values.round(4)))}")


if __name__ == "__main__":
    main()
