"""The record mode read at run time against the mode fixed at compile time: what one kernel per scene costs.

Every record mode (no records, a log, a portrait) runs one kernel per scene, which reads the mode at
run time (``_engine/table.py``, ``recording_slot``).  This times, in one process and in turn, runs
without records of that kernel and of the kernel with ``RECORD_NONE`` fixed (the variant the pipeline
compiled besides it until 2026-11-29), on ensembles of the Galton boards, the pentagon, the
lean disk loop and a disk under gravity; process CPU time, median of five rounds, the order reversed
every other round; and checks the two give the same final states bit for bit.  Run it twice with one
``NUMBA_CACHE_DIR``: the first run times freshly compiled kernels, the second kernels loaded from the
cache.

    python benchmarks/bench_record_mode.py [--only galton]
"""
import argparse
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import machine_line

import noslipsim as ns
from noslipsim._engine.run import run_orbits
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout

DEPTH = 100 * math.sqrt(3.0)  # a hundred rows of the board


def cases():
    """Name -> (scene, start, orbits, limits, stop level)."""
    board = ns.tables.galton_board
    return {
        "Galton no-slip": (board(2.0, 0.5, 1.0), (1.0, 0.0), 200, dict(max_collisions=10**7, max_time=1e4), -DEPTH),
        "Galton specular": (board(2.0, 0.5, 1.0, law="specular"), (1.0, 0.0), 200,
                            dict(max_collisions=10**7, max_time=1e4), -DEPTH),
        "pentagon specular": (ns.tables.regular_polygon(5).replace(law="specular"), (0.1, 0.05), 8,
                              dict(max_collisions=1_000_000), -math.inf),
        "pentagon no-slip": (ns.tables.regular_polygon(5).replace(law="no-slip"), (0.1, 0.05), 8,
                             dict(max_collisions=1_000_000), -math.inf),
        "Sinai torus no-slip (lean loop)": (ns.tables.sinai_torus(0.25).replace(law="no-slip"), (0.45, 0.1), 16,
                                            dict(max_collisions=300_000), -math.inf),
        "circle + gravity": (ns.Scene([ns.Circle((0.0, 0.0), 1.0, "inside")], force=(0.0, -1.0)), (0.1, 0.2), 8,
                             dict(max_collisions=200_000), -math.inf),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default="", help="run the cases whose name contains this text")
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    print(machine_line(numpy=True, load=True))
    print(f"{'case':<34}{'fixed M/s':>10}{'run time M/s':>14}{'ratio':>8}  range        same bits")
    for name, (scene, q, n, limits, level) in cases().items():
        if args.only not in name:
            continue
        table = kernel_table(scene)
        starts = np.column_stack([np.tile(q, (n, 1)), ns.initial.unit_velocities(n, seed=7), np.zeros(n)])
        levels = np.full(n, level)
        shared = table.variant(layout.RECORD_NONE)
        kernels = {"fixed": shared._replace(mode=layout.RECORD_NONE), "run time": shared}
        for flags in kernels.values():
            run_orbits(table, starts[:1], max_collisions=10, flags=flags, levels=levels[:1])  # compile or load
        rates, finals = {key: [] for key in kernels}, {}
        for r in range(args.rounds):
            for key in (list(kernels) if r % 2 == 0 else list(kernels)[::-1]):
                t0 = time.process_time()
                finals[key] = run_orbits(table, starts, flags=kernels[key], levels=levels, **limits)
                rates[key].append(finals[key][:, 0].sum() / (time.process_time() - t0))
        fixed, run_time = np.median(rates["fixed"]), np.median(rates["run time"])
        # the last column is the variant each kernel reports, which differs by design
        same = np.array_equal(finals["fixed"][:, :-1], finals["run time"][:, :-1])
        lo, hi = min(rates["run time"]) / max(rates["fixed"]), max(rates["run time"]) / min(rates["fixed"])
        spread = f"{lo:.3f}-{hi:.3f}"
        print(f"{name:<34}{fixed / 1e6:10.2f}{run_time / 1e6:14.2f}{run_time / fixed:8.3f}  {spread:<13}{same}",
              flush=True)


if __name__ == "__main__":
    main()
