"""For scale: the Sinai box as a hand-written numba loop, with none of the engine's guarantees.

Unit square with a disk of radius 0.3 at its centre, specular.  No extents,
no corner rule, no grazing guard, no relocation onto the element, no cell
walk, no records: the floor an event loop on this scene can reach on this
machine.  Compare with ``bench_collisions.py`` (Sinai box, kernel) on the same
host.  Run: ``python benchmarks/baseline_sinai_box.py``.
"""
import math
import os
import sys

from numba import njit

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import report_baseline


@njit
def sinai_box(x, y, vx, vy, n, r):
    cx = 0.5
    cy = 0.5
    last = -1
    for _ in range(n):
        tb = math.inf
        hit = -1
        if vx > 0 and last != 0:
            tb = (1.0 - x) / vx
            hit = 0
        elif vx < 0 and last != 1:
            tb = -x / vx
            hit = 1
        if vy > 0 and last != 2:
            t = (1.0 - y) / vy
            if t < tb:
                tb = t
                hit = 2
        elif vy < 0 and last != 3:
            t = -y / vy
            if t < tb:
                tb = t
                hit = 3
        if last != 4:
            dx = x - cx
            dy = y - cy
            b = dx * vx + dy * vy
            if b < 0:
                c = dx * dx + dy * dy - r * r
                d = b * b - (vx * vx + vy * vy) * c
                if d > 0:
                    t = c / (-b + math.sqrt(d))
                    if t < tb:
                        tb = t
                        hit = 4
        x += vx * tb
        y += vy * tb
        if hit <= 1:
            vx = -vx
        elif hit <= 3:
            vy = -vy
        else:
            nx = (x - cx) / r
            ny = (y - cy) / r
            p = vx * nx + vy * ny
            vx -= 2 * p * nx
            vy -= 2 * p * ny
        last = hit
    return x, y, vx, vy


def main(n=10_000_000):
    report_baseline("hand-written Sinai box", sinai_box, (0.1, 0.1, 0.6, 0.8), n, 0.3)


if __name__ == "__main__":
    main()
