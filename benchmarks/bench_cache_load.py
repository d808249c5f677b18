"""Kernels as users run them: the rate freshly compiled against the rate loaded from the numba cache.

A process that compiles a kernel and a process that loads it from the cache need not run the same
machine code: numba links every callee into its caller as a weak definition, and the dynamic linker
keeps the definition loaded first.  A fresh process has compiled (and loaded) the callees first, so
the batch kernel calls their own code; a process that loads only the batch kernel runs the batch's
own copies, optimised a second time inside its module.  ``_engine.run`` therefore loads the orbit
kernel before the batch kernel (``_load_orbit_kernel_first``); ``--without-preload`` switches that
off to show what it mends.

Each case runs in processes of its own, in turn: one with an empty cache (it compiles, then times),
then ``--loads`` processes on the cache it filled (each loads, then times).  Per case: the median
rate (process CPU time, collisions per second) of each kind and cached / fresh.

    python benchmarks/bench_cache_load.py [--only galton] [--without-preload] [--rounds 2]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import machine_line

CASES = {  # name -> (scene expression with `ns`, start, orbits, limits)
    "Galton board, specular": ("ns.tables.galton_board(2.0, 0.5, 1.0, law='specular')", (1.0, 0.0), 64,
                               {"max_collisions": 10**7, "stop_below": -173.2, "max_time": 1e4}),
    "Galton board, no-slip": ("ns.tables.galton_board(2.0, 0.5, 1.0)", (1.0, 0.0), 64,
                              {"max_collisions": 10**7, "stop_below": -173.2, "max_time": 1e4}),
    "Sinai torus, no-slip": ("ns.tables.sinai_torus(0.25)", (0.45, 0.1), 16, {"max_collisions": 100_000}),
    "centred torus, specular": ("ns.Scene((ns.Circle((0.5, 0.5), 0.25, 'outside'),), law='specular', "
                                "lattice={'a1': [1.0, 0.0], 'a2': [0.0, 1.0]})", (0.95, 0.6), 16,
                                {"max_collisions": 100_000}),
    "pentagon, no-slip": ("ns.tables.regular_polygon(5)", (0.1, 0.05), 4, {"max_collisions": 500_000}),
    "Sinai box, no-slip": ("ns.tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)])", (0.1, 0.1), 4,
                           {"max_collisions": 500_000}),
    "magnetic Sinai box, no-slip": ("ns.tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]).replace(magnetic=0.7)",
                                    (0.1, 0.1), 4, {"max_collisions": 200_000}),
    "magnetic Sinai torus, specular": ("ns.tables.sinai_torus(0.3, law='specular').replace(magnetic=0.7)",
                                       (0.0, 0.45), 8, {"max_collisions": 100_000}),
}

CHILD = """
import json, sys, time
import numpy as np
import noslipsim as ns
if {without}:
    import noslipsim._engine.run as run
    run._load_orbit_kernel_first = lambda *args: None
scene = {scene}
n = {orbits}
v = ns.initial.unit_velocities(n, seed=7)
q = np.tile({start}, (n, 1))
kw = {limits}
ns.simulate_many(scene, q[:2], v[:2], scheduler="sync", progress=False, **{{**kw, "max_collisions": 10}})
rates = []
for _ in range(3):
    t0 = time.process_time()
    c = int(ns.simulate_many(scene, q, v, scheduler="sync", progress=False, **kw).n_collisions.sum())
    rates.append(c / (time.process_time() - t0))
print(json.dumps(max(rates)))
"""


def run_child(case, cache, without):
    scene, start, orbits, limits = CASES[case]
    code = CHILD.format(without=without, scene=scene, orbits=orbits, start=tuple(start), limits=repr(limits))
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, NUMBA_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", default="", help="run the cases whose name contains this text")
    ap.add_argument("--rounds", type=int, default=2, help="fresh caches per case")
    ap.add_argument("--loads", type=int, default=2, help="loading processes per fresh cache")
    ap.add_argument("--without-preload", action="store_true",
                    help="do not load the orbit kernel before the batch kernel (the behaviour before the fix)")
    args = ap.parse_args()
    print(machine_line(numpy=True, load=True))
    print(f"orbit kernel loaded first: {not args.without_preload}")
    print(f"{'case':<28}{'fresh M/s':>11}{'cached M/s':>12}{'cached/fresh':>14}")
    for case in CASES:
        if args.only not in case:
            continue
        fresh, cached = [], []
        for _ in range(args.rounds):
            with tempfile.TemporaryDirectory(prefix="nss_cache_") as cache:
                fresh.append(run_child(case, cache, args.without_preload))
                cached += [run_child(case, cache, args.without_preload) for _ in range(args.loads)]
        f, c = statistics.median(fresh), statistics.median(cached)
        spread = (f"fresh {min(fresh) / 1e6:.2f}-{max(fresh) / 1e6:.2f}, "
                  f"cached {min(cached) / 1e6:.2f}-{max(cached) / 1e6:.2f}")
        print(f"{case:<28}{f / 1e6:>11.2f}{c / 1e6:>12.2f}{c / f:>14.2f}   ({spread})", flush=True)


if __name__ == "__main__":
    main()
