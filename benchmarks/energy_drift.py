"""Energy drift per 10^6 collisions in every stress family (issue 13, item 5).

One orbit per family (the families of ``tests/test_stress.py``), ``--collisions``
collisions (default 10^6), logged; the energy ``E = (|v|^2 + w^2)/2 - a.q`` of
every 1000th collision, relative to the size of its terms, is fitted by a
straight line through the start: its slope is the drift per 10^6 collisions
(a bias per collision gives a line with R^2 near 1; unbiased rounding, a random
walk with no slope, of order 1e-13 per 10^6 collisions).  ``--families`` picks
some.  The quicker twin of ``benchmarks/stress_run.py``'s energy section.
Run: ``python benchmarks/energy_drift.py [--collisions 1000000] [--families a,b]``.
"""
import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))
sys.path.insert(0, HERE)
from machine import machine_line  # noqa: E402 (benchmarks/ on sys.path first)

#: Target (issue 13): every family below this drift per 10^6 collisions.
TARGET = 1e-12
STRIDE = 1000


def drift(name, n):
    """``(slope per 10^6, R^2, largest |dE| relative, seconds)`` of one family's orbit of ``n`` collisions."""
    import test_stress as ts

    from noslipsim.core import layout
    from noslipsim.simulate import run_one

    make, q, v, w = ts.chain_families()[name]
    scene = make()
    rec = np.zeros((n, layout.N_LOG))
    t0 = time.perf_counter()
    out = run_one(scene, np.asarray(q, float), np.asarray(v, float), float(w), n, np.inf, -np.inf,
                  layout.RECORD_LOG, rec)
    dt = time.perf_counter() - t0
    m = out[3]
    rows = rec[:m:STRIDE]
    ax, ay = scene.force
    kin = 0.5 * (rows[:, layout.LOG_VX] ** 2 + rows[:, layout.LOG_VY] ** 2 + rows[:, layout.LOG_W] ** 2)
    pot = -(ax * rows[:, layout.LOG_X] + ay * rows[:, layout.LOG_Y])
    e0 = 0.5 * (v[0] ** 2 + v[1] ** 2 + w * w) - (ax * q[0] + ay * q[1])
    size = max(abs(e0), float(kin.max()), float(np.abs(pot).max()))
    err = ((kin + pot) - e0) / size
    k = np.arange(0, m, STRIDE)[: len(err)] / 1e6
    slope = float(k @ err / (k @ k)) if k @ k > 0 else 0.0
    ss = float(((err - err.mean()) ** 2).sum())
    r2 = 1.0 - float(((err - slope * k) ** 2).sum()) / ss if ss > 0 else 0.0
    return slope, r2, float(np.abs(err).max()), dt, m


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--collisions", type=float, default=1e6)
    ap.add_argument("--families", default="")
    args = ap.parse_args()
    import test_stress as ts

    names = args.families.split(",") if args.families else sorted(ts.chain_families())
    n = int(args.collisions)
    print(machine_line())
    print(f"{n:,} collisions per family; slope: least-squares drift of E per 10^6 collisions (relative); "
          f"target |slope| < {TARGET:g}")
    print(f"{'family':<26}{'collisions':>12}{'slope per 1e6':>15}{'R^2':>8}{'max |dE|':>11}{'s':>7}  ok")
    for name in names:
        slope, r2, worst, dt, m = drift(name, n)
        print(f"{name:<26}{m:>12,}{slope:>+15.2e}{r2:>8.3f}{worst:>11.1e}{dt:>7.1f}  "
              f"{'yes' if abs(slope) < TARGET else 'NO'}", flush=True)


if __name__ == "__main__":
    main()
