"""The Galton ensembles against a plain compiled loop, per core, freshly compiled and loaded from the cache.

Issue 32's criterion: the Galton ensembles at least 1.2x the plain compiled loop per core.  The
ensemble is ``bench_ensembles.py``'s: ``tables.galton_board(2.0, 0.5, 1.0)``, 2000 orbits from
``(1, 0)`` with ``initial.unit_velocities(2000, seed=7)``, 100 rows down (``stop_below = -100
sqrt(3)``), ``max_time = 1e4``, ``max_collisions = 10**7``, specular and no-slip.  noslipsim runs
``simulate_many(..., scheduler="sync")``; the plain loop is ``baseline_galton.py`` (no guarantees).

Each fresh cache gets two processes, as ``bench_cache_load.py`` runs them: one on the empty
``NUMBA_CACHE_DIR`` (it compiles, then times: "fresh"), then one on the cache it filled (it loads,
then times: "cached").  In each, the plain loop and noslipsim run in interleaved rounds, both laws;
the rate is collisions per CPU second of the process (``time.process_time``).  Per law and kind: the
median rate and its range over the rounds, and noslipsim / plain (the ratio of the medians).

    python benchmarks/bench_galton_plain.py [--rounds 5] [--caches 1] [--max-load 1.3]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from baseline_galton import LIMITS, START, board_scene, plain_ensemble
from machine import machine_line

LAWS = ("specular", "no-slip")
CRITERION = 1.2


def noslipsim_rate(scene, v):
    """Collisions per CPU second of ``simulate_many`` (sync, one core) on the ensemble with velocities ``v``."""
    import noslipsim as ns

    q = np.tile(START, (len(v), 1))
    t0 = time.process_time()
    ds = ns.simulate_many(scene, q, v, scheduler="sync", progress=False, max_collisions=LIMITS["max_collisions"],
                          max_time=LIMITS["max_time"], stop_below=LIMITS["level"])
    return int(ds.n_collisions.sum()) / (time.process_time() - t0)


def plain_rate(law, v):
    """Collisions per CPU second of the plain loop on the same ensemble."""
    t0 = time.process_time()
    n = plain_ensemble(law, v)
    return n / (time.process_time() - t0)


def child(rounds, orbits):
    """One process's timings: a warm-up (compile or cache load), then ``rounds`` interleaved rounds; JSON out."""
    from noslipsim import initial

    v = initial.unit_velocities(orbits, seed=7)
    scenes = {law: board_scene(law) for law in LAWS}
    t0 = time.process_time()
    for law in LAWS:
        noslipsim_rate(scenes[law], v[:2])
    warm = time.process_time() - t0
    for law in LAWS:
        plain_rate(law, v[:2])
    rates = {kind: {law: [] for law in LAWS} for kind in ("plain", "noslipsim")}
    for _ in range(rounds):
        for law in LAWS:
            rates["plain"][law].append(plain_rate(law, v))
            rates["noslipsim"][law].append(noslipsim_rate(scenes[law], v))
    print(json.dumps({"warm_up_cpu_s": warm, "rates": rates}))


def wait_for_quiet(max_load, patience=600.0):
    """Wait (up to ``patience`` seconds) until the 1-minute load is under ``max_load``; returns the load."""
    deadline = time.monotonic() + patience
    while os.getloadavg()[0] >= max_load and time.monotonic() < deadline:
        time.sleep(10.0)
    return os.getloadavg()[0]


def run_child(cache, args):
    """Run :func:`child` in a new process on the numba cache folder ``cache``; its result and the load before it."""
    load = wait_for_quiet(args.max_load)
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, NUMBA_NUM_THREADS="1")
    cmd = [sys.executable, os.path.abspath(__file__), "--child", "--rounds", str(args.rounds),
           "--orbits", str(args.orbits)]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1]), load


def spread(rates):
    """``median (min-max)`` in M/s."""
    return (f"{statistics.median(rates) / 1e6:.2f} ({min(rates) / 1e6:.2f}-{max(rates) / 1e6:.2f})")


def report(kind, result, load):
    """One line per law: plain and noslipsim rates, their ratio, the load before the process."""
    rates = result["rates"]
    for law in LAWS:
        plain = statistics.median(rates["plain"][law])
        ours = statistics.median(rates["noslipsim"][law])
        print(f"{law:<10}{kind:<8}{spread(rates['plain'][law]):>20}{spread(rates['noslipsim'][law]):>20}"
              f"{ours / plain:>8.2f}{load:>7.2f}{result['warm_up_cpu_s']:>9.1f}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=5, help="interleaved rounds per process")
    ap.add_argument("--caches", type=int, default=1, help="fresh caches (each: one fresh, one cached process)")
    ap.add_argument("--orbits", type=int, default=2000, help="orbits of the ensemble")
    ap.add_argument("--max-load", type=float, default=1.3,
                    help="wait (up to 10 min) for the 1-minute load to fall under this before each process")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        child(args.rounds, args.orbits)
        return
    print(machine_line(numpy=True, load=True))
    print(f"Galton board, {args.orbits} orbits, 100 rows; {args.rounds} interleaved rounds per process; "
          f"M/s = million collisions per CPU second, median (range); criterion noslipsim/plain >= {CRITERION}")
    print(f"{'law':<10}{'kind':<8}{'plain M/s':>20}{'noslipsim M/s':>20}{'ratio':>8}{'load':>7}{'warm s':>9}")
    for _ in range(args.caches):
        with tempfile.TemporaryDirectory(prefix="nss_cache_") as cache:
            for kind in ("fresh", "cached"):
                result, load = run_child(cache, args)
                report(kind, result, load)


if __name__ == "__main__":
    main()
