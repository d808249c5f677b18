"""Old vs new code in one process, each as several package copies: no scene in benchmarks/ slower than before.

On a shared machine, rates measured in different processes minutes apart differ by up to 2x
(benchmarks/RESULTS.md); a ratio measured in one process, with the versions called in turn, is
what the load cannot fake.  And one version compiled twice in one process, under two package
names, can run a scene up to 10 % apart, run after run (RESULTS.md, "The settle's cost, probed"):
where the loader puts a kernel is drawn per copy.  So each version runs as ``--copies`` packages
(``package_copy.load_version``: relative imports only, each copy imports as a package of its own
and compiles its own kernels), and a version is judged by all of its copies.

    python benchmarks/bench_before_after.py --before <commit or package folder> [--copies 2]

``--before`` is a commit (extracted with ``git archive``) or a folder holding a copy of
``src/noslipsim``; "new" is this checkout's ``src/noslipsim``.

Each case is the workload of a scene benchmark (``bench_collisions.py``: kernels without a log
and ``simulate`` with one; ``bench_ensembles.py``: ``simulate_many`` on one core, Galton board
and Sinai torus; ``bench_centred_torus.py``: the centred-disk torus) at about the same size (0.3 to
1 s per run), timed ``--rounds`` times, every copy once per round, the order reversed every other
round.  Per case: the best rate of each version; new/before, the median over rounds of the
geometric mean of the new copies' rates over that of the before copies'; and each new copy's
median over rounds against the before copies (the spread of the draw).

Kernel cases run each version through its own one call (``package_copy.kernel_call``):
``run_orbits`` on the scene's kernel table for a package that has it, and for an
older one its own API (``scene.kernel_inputs()``, ``scene.kernel_variant``, its serial
batch loop ``batch_kernels(flags)[1]`` where it has one, else the orbit kernel);
one orbit of millions of collisions per call either way, so the call's own overhead
(some 30 us) does not count.
"""
import argparse
import math
import os
import shutil
import statistics
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bits_before_after import diamond_segments
from package_copy import kernel_call, load_version

NEW = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "src", "noslipsim")

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


def diamond(force=(0.0, 0.0)):
    """The square lattice of diamonds (half-diagonal 0.25): a lattice of segments, walked by ``cells.lattice_walk``."""
    def scene(p):
        return p.Scene(diamond_segments(p.Segment), force=force, lattice={"a1": [1.0, 0.0], "a2": [0.0, 1.0]})
    return scene


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
    "kernel: diamond lattice": (kernel_case, diamond(), (0.1, 0.1), (0.7, 0.31), 5_000_000),
    "kernel: diamond lattice + gravity": (kernel_case, diamond((0.05, -1.0)), (0.1, 0.1), (0.7, 0.31), 2_000_000),
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


def time_in_turn(runs, rounds):
    """``(rates, work)``: each run's rates over ``rounds`` rounds (every run once per round, the order
    reversed every other round) and the work (collisions) of its last call."""
    order = list(runs)
    rates = {key: [] for key in order}
    work = {}
    for r in range(rounds):
        for key in (order if r % 2 == 0 else order[::-1]):
            t0 = time.perf_counter()
            work[key] = runs[key]()
            rates[key].append(work[key] / (time.perf_counter() - t0))
    return rates, work


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", required=True, help="a commit, or a folder holding a copy of src/noslipsim")
    ap.add_argument("--copies", type=int, default=2, help="packages per version (a version is judged by all)")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--only", default="", help="run the cases whose name contains this text")
    ap.add_argument("--scale", type=float, default=1.0,
                    help="multiplies each case's collisions or orbits (small values only check that it runs)")
    args = ap.parse_args()
    if args.copies < 1 or args.rounds < 1:
        ap.error("--copies and --rounds must be at least 1")
    where = tempfile.mkdtemp(prefix="before_after_")
    pkgs = {(side, k): load_version(version, f"nss_{side}_{k}", where)
            for side, version in (("before", args.before), ("new", NEW)) for k in range(args.copies)}
    print(f"before: {args.before}\nnew:    {NEW}\ncopies per version: {args.copies}\nload at start: {os.getloadavg()}")
    print(f"{'case':<38}{'before coll/s':>15}{'new coll/s':>15}{'new/before':>12}{'range':>11}   new copies")
    for name, (make, *spec) in CASES.items():
        if args.only not in name:
            continue
        spec = scaled(make, spec, args.scale)
        rates = time_in_turn({key: make(pkg, *spec) for key, pkg in pkgs.items()}, args.rounds)[0]
        side_rate = {side: [statistics.geometric_mean([rates[(side, k)][r] for k in range(args.copies)])
                            for r in range(args.rounds)] for side in ("before", "new")}
        ratios = [a / b for a, b in zip(side_rate["new"], side_rate["before"])]
        per_copy = " ".join(f"{statistics.median([a / b for a, b in zip(rates[('new', k)], side_rate['before'])]):.3f}"
                            for k in range(args.copies))
        best = {side: max(max(rates[(side, k)]) for k in range(args.copies)) for side in ("before", "new")}
        print(f"{name:<38}{best['before']:>15,.0f}{best['new']:>15,.0f}{statistics.median(ratios):>12.3f}"
              f"{min(ratios):>6.2f}-{max(ratios):.2f}   {per_copy}", flush=True)
    print(f"load at end: {os.getloadavg()}")
    shutil.rmtree(where, ignore_errors=True)


if __name__ == "__main__":
    main()
