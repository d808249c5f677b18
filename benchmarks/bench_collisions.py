"""Collisions per second of the event loop on three scenes (issue: core simulator).

Measures the compiled kernel with the lean recorder (no collision log), one
orbit through the package's one kernel call (``run_orbits``, the scene's own
variant; one call of ``n`` collisions, so its Python overhead of some 30 us does
not count), and the public ``simulate`` (full log), after a warm-up run that
compiles.  Prints the machine, then one line per scene.
Run: ``python benchmarks/bench_collisions.py [--collisions 2000000]``.
"""
import argparse
import os
import platform
import sys
import time

import numpy as np

from noslipsim import Circle, Scene, simulate, tables
from noslipsim._engine.run import run_orbits
from noslipsim._engine.table import kernel_table
from noslipsim.core.batch import F_N

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from package_copy import outputs

SCENES = {
    "pentagon (no force)": (tables.regular_polygon(5), (0.1, 0.05), (0.83, 0.41)),
    "Sinai box (no force)": (tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]), (0.1, 0.1), (0.6, 0.8)),
    "circle + gravity": (Scene([Circle((0.0, 0.0), 1.0, "inside")], force=(0.0, -1.0)), (0.1, 0.2), (0.4, 0.1)),
}


def kernel_rate(scene, q, v, n, repeat=1):
    """Best collisions/s over ``repeat`` timed runs of the scene's own kernel variant (no record).

    ``q`` is taken relative to cell 0 (the scene as written, not its canonical form).
    Returns ``(rate, outputs)``: ``outputs`` are the kernel's 12 outputs of the last run
    (the summary columns ``F_N`` to ``F_CELL2``).
    """
    table = kernel_table(scene)
    start = [[q[0], q[1], v[0], v[1], 0.1]]
    run_orbits(table, start, max_collisions=10)  # compile (or load from the cache)
    best = 0.0
    for _ in range(repeat):
        t0 = time.perf_counter()
        final = run_orbits(table, start, max_collisions=n)
        best = max(best, final[0, F_N] / (time.perf_counter() - t0))
    return best, outputs(final[0])


def simulate_rate(scene, q, v, n):
    simulate(scene, q, v, 0.1, max_collisions=10)
    t0 = time.perf_counter()
    ds = simulate(scene, q, v, 0.1, max_collisions=n)
    return int(ds.n_collisions) / (time.perf_counter() - t0)


def main(n=2_000_000):
    print(f"machine: {platform.machine()} {platform.processor() or ''} | {platform.system()} "
          f"| python {platform.python_version()} | numpy {np.__version__}")
    print(f"{'scene':<24}{'kernel (no log) coll/s':>24}{'simulate (log) coll/s':>24}")
    for name, (scene, q, v) in SCENES.items():
        print(f"{name:<24}{kernel_rate(scene, q, v, n)[0]:>24,.0f}{simulate_rate(scene, q, v, n // 4):>24,.0f}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--collisions", type=float, default=2e6, help="per kernel run (simulate: a quarter)")
    main(int(ap.parse_args().collisions))
