"""Stability-grid wall time (issue 12: a 100 x 100 grid, 1000-collision cap, under 20 s on 2 cores).

The paper's three ``stabexp`` grids with gamma = 1/sqrt(2): R x phi without force, R x phi
with gravity g = 1 launched at theta = 0.5, and R x theta at phi = 0.4 with g = 1 (R in
[0.02, 0.98], phi and theta in [0.01, 1.56], 100 values each).  Each grid runs once
after a warm-up call that compiles the kernel variants it needs (reported separately:
numba compiles the batch kernels of ``simulate_many`` in every new process).  Prints the
machine, the load average before and after (the machine may be shared), the wall time, the
collisions simulated and the agreement share of survival with the linear classes.  Run:
``python benchmarks/bench_stability_grid.py [--n 100]``.
"""
import argparse
import math
import os
import sys
import time

import numpy as np

from noslipsim.analysis import stability_grid, stability_grid_theta

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import machine_line

GAMMA = 1.0 / math.sqrt(2.0)
TARGET_SECONDS = 20.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=100, help="grid points per axis (default 100)")
    ap.add_argument("--max-collisions", type=int, default=1000)
    args = ap.parse_args()
    print(machine_line(numpy=True))
    print(f"load average before: {os.getloadavg()}")
    radii = np.linspace(0.02, 0.98, args.n)
    angles = np.linspace(0.01, 1.56, args.n)
    cases = [
        ("R x phi, no force", lambda **kw: stability_grid(radii, angles, GAMMA, **kw)),
        ("R x phi, g = 1, theta = 0.5", lambda **kw: stability_grid(radii, angles, GAMMA, gravity=1.0, theta=0.5,
                                                                     **kw)),
        ("R x theta, g = 1, phi = 0.4", lambda **kw: stability_grid_theta(radii, angles, GAMMA, phi=0.4,
                                                                           gravity=1.0, **kw)),
    ]
    t0 = time.perf_counter()
    stability_grid([0.5], [0.3], GAMMA, max_collisions=10, progress=False)
    stability_grid([0.5], [0.3], GAMMA, gravity=1.0, theta=0.5, max_collisions=10, progress=False)
    print(f"warm-up (kernel compilation in this process): {time.perf_counter() - t0:.1f} s")
    print(f"{'grid':<30}{'wall s':>9}{'collisions':>14}{'agreement':>11}{'target':>9}")
    for name, run in cases:
        t0 = time.perf_counter()
        ds = run(max_collisions=args.max_collisions, progress=False)
        dt = time.perf_counter() - t0
        ok = "met" if dt < TARGET_SECONDS else "MISSED"
        print(f"{name:<30}{dt:>9.2f}{int(ds.n_collisions.sum()):>14,}{ds.attrs['agreement_share']:>11.4f}{ok:>9}")
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
