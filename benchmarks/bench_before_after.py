"""Old vs new code in one process: no scene in benchmarks/ slower than before (issue 13).

On a shared machine, rates measured in different processes minutes apart differ by up to 2x
(benchmarks/RESULTS.md); a ratio measured in one process, with the two versions called
alternately, is what the load cannot fake.  ``--before DIR`` is a copy of the package from an
earlier commit, renamed ``noslipsim_before`` (relative imports only, so it imports as a second
package and compiles its own kernels):

    git archive <commit> src | tar -x -C /tmp/old
    cp -r /tmp/old/src/noslipsim /tmp/old/pkg/noslipsim_before
    PYTHONPATH=src python benchmarks/bench_before_after.py --before /tmp/old/pkg

(``package_copy.package_copy(commit, "noslipsim_before", "/tmp/old/pkg")`` makes the same copy.)

Each case is the workload of a scene benchmark (``bench_collisions.py``: kernels without a log
and ``simulate`` with one; ``bench_ensembles.py``: ``simulate_many`` on one core, Galton board
and Sinai torus; ``bench_centred_torus.py``: the centred-disk torus) at about the same size (0.3 to 1 s per run), timed
``--rounds`` times with the order of the two versions swapped every round; per case: the best
rate of each version, and the median and range of the per-round ratios new / before.

Kernel cases run each version through its own one call (``package_copy.kernel_call``):
``run_orbits`` on the scene's kernel table for a package that has it, and for an
older one its own API (``scene.kernel_inputs()``, ``scene.kernel_variant``, its serial
batch loop ``batch_kernels(flags)[1]`` where it has one, else the orbit kernel);
one orbit of millions of collisions per call either way, so the call's own overhead
(some 30 us) does not count.
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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from package_copy import kernel_call

ROWS = 100
DEPTH = ROWS * math.sqrt(3.0)


def kernel_case(pkg, scene_fn, q, v, n):
    """The scene's own kernel variant, no record, one orbit: ``bench_collisions.kernel_rate``."""
    run = kernel_call(pkg.__name__)
    scene = scene_fn(pkg)
    start = (q[0], q[1], v[0], v[1], 0.0)

    def go(m):
        return run(scene, start, m)[0]
    go(10)
    return lambda: go(n)


def simulate_case(pkg, scene_fn, q, v, n):
    scene = scene_fn(pkg)
    pkg.simulate(scene, q, v, max_collisions=10)
    return lambda: int(pkg.simulate(scene, q, v, max_collisions=n).n_collisions)


def many_case(pkg, scene_fn, q0, n_orbits, kw):
    scene = scene_fn(pkg)
    v = pkg.initial.unit_velocities(n_orbits, seed=7)
    q = np.tile(q0, (n_orbits, 1))
    pkg.simulate_many(scene, q[:2], v[:2], scheduler="sync", progress=False, **{**kw, "max_collisions": 10})
    return lambda: int(pkg.simulate_many(scene, q, v, scheduler="sync", progress=False, **kw).n_collisions.sum())


def centred(law):
    return lambda p: p.Scene((p.Circle((0.5, 0.5), 0.25, "outside"),), law=law,
                             lattice={"a1": [1.0, 0.0], "a2": [0.0, 1.0]})


CASES = {  # name -> (case maker, scene of a package, start, velocity or orbits, size)
    "kernel: pentagon": (kernel_case, lambda p: p.tables.regular_polygon(5), (0.1, 0.05), (0.83, 0.41), 20_000_000),
    "kernel: Sinai box": (kernel_case, lambda p: p.tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]),
                          (0.1, 0.1), (0.6, 0.8), 10_000_000),
    "kernel: circle + gravity": (kernel_case, lambda p: p.Scene([p.Circle((0.0, 0.0), 1.0, "inside")],
                                                                force=(0.0, -1.0)), (0.1, 0.2), (0.4, 0.1), 2_000_000),
    "kernel: Sinai torus": (kernel_case, lambda p: p.tables.sinai_torus(0.25), (0.45, 0.1), (0.6, 0.8), 10_000_000),
    "simulate (log): pentagon": (simulate_case, lambda p: p.tables.regular_polygon(5), (0.1, 0.05), (0.83, 0.41),
                                 1_000_000),
    "simulate (log): Sinai box": (simulate_case, lambda p: p.tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]),
                                  (0.1, 0.1), (0.6, 0.8), 1_000_000),
    "ensemble: Galton no-slip": (many_case, lambda p: p.tables.galton_board(2.0, 0.5, 1.0), (1.0, 0.0), 1000,
                                 {"max_collisions": 10**7, "stop_below": -DEPTH, "max_time": 1e4}),
    "ensemble: Galton specular": (many_case, lambda p: p.tables.galton_board(2.0, 0.5, 1.0, law="specular"),
                                  (1.0, 0.0), 1000, {"max_collisions": 10**7, "stop_below": -DEPTH, "max_time": 1e4}),
    "ensemble: Sinai torus": (many_case, lambda p: p.tables.sinai_torus(0.25), (0.45, 0.1), 64,
                              {"max_collisions": 100_000}),
    "ensemble: centred torus, specular": (many_case, centred("specular"), (0.95, 0.6), 64,
                                          {"max_collisions": 100_000}),
    "ensemble: centred torus, no-slip": (many_case, centred("no-slip"), (0.95, 0.6), 64, {"max_collisions": 100_000}),
}


def scaled(make, spec, factor):
    """``spec`` with its size (collisions of a kernel or simulate case, orbits of an ensemble) times ``factor``."""
    i = 2 if make is many_case else 3
    return [*spec[:i], max(1, int(spec[i] * factor)), *spec[i + 1:]]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--before", required=True, help="folder holding the package noslipsim_before")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--only", default="", help="run the cases whose name contains this text")
    ap.add_argument("--scale", type=float, default=1.0,
                    help="multiplies each case's collisions or orbits (small values only check that it runs)")
    args = ap.parse_args()
    sys.path.insert(0, os.path.abspath(args.before))
    old = importlib.import_module("noslipsim_before")
    for pkg in (old, new):  # the submodules the cases use, as attributes of each package
        for sub in ("tables", "initial"):
            importlib.import_module(f"{pkg.__name__}.{sub}")
    print(f"before: {old.__file__}\nnew:    {new.__file__}\nload at start: {os.getloadavg()}")
    print(f"{'case':<38}{'before coll/s':>15}{'new coll/s':>15}{'new/before median':>19}{'range':>14}")
    for name, (make, *spec) in CASES.items():
        if args.only not in name:
            continue
        spec = scaled(make, spec, args.scale)
        runs = {"before": make(old, *spec), "new": make(new, *spec)}
        best = dict.fromkeys(runs, 0.0)
        ratios = []
        for r in range(args.rounds):
            rate = {}
            for key in (("before", "new") if r % 2 == 0 else ("new", "before")):
                t0 = time.perf_counter()
                n = runs[key]()
                rate[key] = n / (time.perf_counter() - t0)
                best[key] = max(best[key], rate[key])
            ratios.append(rate["new"] / rate["before"])
        print(f"{name:<38}{best['before']:>15,.0f}{best['new']:>15,.0f}{statistics.median(ratios):>19.3f}"
              f"{min(ratios):>7.2f}-{max(ratios):.2f}", flush=True)
    print(f"load at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
