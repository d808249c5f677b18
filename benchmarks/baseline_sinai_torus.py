"""For scale: the Sinai torus as a hand-written numba grid walk, with none of the engine's guarantees.

Unit square lattice with a disk of radius 0.25 at every lattice point,
specular, no force: the "compiled grid walk" the lattice issue quotes (about
18 M collisions/s per core, measured on another machine).  The walk steps
cell by cell with incremental face times and tests the one disk of each cell
entered; the hit point is projected onto the disk (``hypot``), as any
long run needs to keep the speed from drifting.  No re-centring of long
flights, no cell-exit window, no records, no corner or grazing guard.
Compare with ``bench_ensembles.py`` (Sinai torus) on the same host.
Run: ``python benchmarks/baseline_sinai_torus.py``.
"""
import math
import os
import sys

from numba import njit

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import report_baseline


@njit
def sinai_torus(x, y, vx, vy, n, r):
    """``n`` collisions from ``(x, y)`` in cell 0 at unit speed; returns the state and the cell reached."""
    m1 = 0
    m2 = 0
    r2 = r * r
    t = 0.0
    for _ in range(n):
        s1 = 1 if vx > 0 else -1
        s2 = 1 if vy > 0 else -1
        ivx = 1.0 / vx
        ivy = 1.0 / vy
        ta = (0.5 * s1 - x) * ivx
        tb = (0.5 * s2 - y) * ivy
        d1 = 0
        d2 = 0
        while True:  # the disk of the cell just left cannot be hit again (it is convex): step first
            if ta < tb:
                d1 += s1
                ta += s1 * ivx
            else:
                d2 += s2
                tb += s2 * ivy
            dx = x - d1
            dy = y - d2
            b = dx * vx + dy * vy
            c = dx * dx + dy * dy - r2
            disc = b * b - c
            if disc >= 0.0 and b < 0.0:
                t = c / (-b + math.sqrt(disc))
                break
        x += vx * t - d1
        y += vy * t - d2
        m1 += d1
        m2 += d2
        rho = math.hypot(x, y)
        nx = x / rho
        ny = y / rho
        x = r * nx
        y = r * ny
        p = vx * nx + vy * ny
        vx -= 2.0 * p * nx
        vy -= 2.0 * p * ny
    return x, y, vx, vy, m1, m2


def main(n=10_000_000):
    report_baseline("hand-written Sinai torus grid walk", sinai_torus, (0.45, 0.1, 0.6, 0.8), n, 0.25)


if __name__ == "__main__":
    main()
