"""The Sinai torus as most references write it: the disk at the centre of the unit cell (issue 13).

Unit square lattice, one disk of radius 0.25 at (0.5, 0.5) (DynamicalBilliards.jl's
``billiard_sinai``, Chernov & Markarian), no force: ``simulate_many`` with
``scheduler="sync"`` (one core), 64 orbits x 20,000 collisions, specular and
no-slip; then the same billiard written with the disk at the origin
(``tables.sinai_torus``), and the hand-written numba grid walk of
``baseline_sinai_torus.py`` (no engine, no guarantees), all in one process and
interleaved, so the rates compare on a shared machine.  The speed goal: the
centred torus at least as fast as the hand-written loop, for both laws.
Run: ``python benchmarks/bench_centred_torus.py [--repeat 5]``.
"""
import argparse
import os
import sys
import time

import numpy as np

import noslipsim as ns
from noslipsim import Circle, Scene, initial, tables

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from baseline_sinai_torus import sinai_torus as plain_loop
from machine import machine_line

ORBITS = 64
COLLISIONS = 20_000
RADIUS = 0.25


def centred_torus(law):
    """The disk of radius 0.25 at the centre of the unit cell of Z^2."""
    return Scene((Circle((0.5, 0.5), RADIUS, "outside"),), law=law,
                 lattice={"a1": [1.0, 0.0], "a2": [0.0, 1.0]})


def ensemble_rate(scene, q0):
    """Collisions/s of ``simulate_many`` (sync, one core) on ORBITS x COLLISIONS from ``q0``."""
    v = initial.unit_velocities(ORBITS, seed=7)
    q = np.tile(q0, (ORBITS, 1))
    t0 = time.perf_counter()
    ds = ns.simulate_many(scene, q, v, max_collisions=COLLISIONS, scheduler="sync", progress=False)
    dt = time.perf_counter() - t0
    return int(ds.n_collisions.sum()) / dt


def plain_rate():
    n = ORBITS * COLLISIONS
    t0 = time.perf_counter()
    plain_loop(0.45, 0.1, 0.6, 0.8, n, RADIUS)
    return n / (time.perf_counter() - t0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5, help="interleaved rounds (the best of each is kept)")
    args = ap.parse_args()
    print(machine_line(numpy=True))
    cases = {}
    for law in ("specular", "no-slip"):
        cases[f"centred disk (0.5, 0.5), {law}"] = (centred_torus(law), (0.95, 0.6))
        cases[f"disk at the origin, {law}"] = (tables.sinai_torus(RADIUS, law=law), (0.45, 0.1))
    plain_loop(0.45, 0.1, 0.6, 0.8, 10, RADIUS)  # compile
    for scene, q0 in cases.values():
        ns.simulate_many(scene, np.tile(q0, (2, 1)), initial.unit_velocities(2), max_collisions=10,
                         scheduler="sync", progress=False)
    best = dict.fromkeys(cases, 0.0)
    best_plain = 0.0
    for _ in range(args.repeat):
        best_plain = max(best_plain, plain_rate())
        for name, (scene, q0) in cases.items():
            best[name] = max(best[name], ensemble_rate(scene, q0))
    print(f"simulate_many, scheduler='sync', {ORBITS} orbits x {COLLISIONS:,} collisions, best of {args.repeat} "
          "interleaved rounds")
    print(f"{'case':<36}{'coll/s':>14}{'vs plain loop':>15}")
    print(f"{'hand-written loop (specular)':<36}{best_plain:>14,.0f}{1.0:>15.2f}")
    for name, rate in best.items():
        print(f"{name:<36}{rate:>14,.0f}{rate / best_plain:>15.2f}")


if __name__ == "__main__":
    main()
