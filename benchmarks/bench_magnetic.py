"""Magnetic collisions against straight ones on the same tables: the issue's "at most 2x" target.

Each pair runs one table twice, without a field and with ``magnetic: W``, through ``simulate_many`` (the
batch kernel each scene's variant selects; process CPU time, best of three, after a warm-up that compiles
or loads it).  A Sinai torus without a field runs the lean disk loop (``core/disks.py``), which no other
flight has; the general loop's rate on it (the ``(general loop)`` row: the lean loop's variant with
``disks=False``) is the like-for-like comparison.  Prints collisions per second of each and the ratio
straight / magnetic (the cost of a magnetic collision in straight ones), with the machine line.

    python benchmarks/bench_magnetic.py [--orbits 16] [--collisions 100000]
"""
import argparse
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

TABLES = {  # name -> (scene, start, W)
    "Sinai box r=0.3": (ns.tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]), (0.1, 0.1), 0.7),
    "pentagon": (ns.tables.regular_polygon(5), (0.1, 0.05), 0.7),
    "stadium": (ns.tables.stadium(1.0, 1.0), (0.05, 0.02), 0.7),
    "Sinai torus r=0.3": (ns.tables.sinai_torus(0.3), (0.0, 0.45), 0.7),
}


def rate(scene, start, orbits, collisions, flags=None):
    """Best of three: collisions per CPU second of ``orbits`` orbits (the variant ``flags`` or the table's own)."""
    table = kernel_table(scene)
    v = ns.initial.unit_velocities(orbits, seed=7)
    starts = np.column_stack([np.tile(start, (orbits, 1)), v, np.zeros(orbits)])
    run_orbits(table, starts[:1], max_collisions=10, flags=flags)
    best = 0.0
    for _ in range(3):
        t0 = time.process_time()
        final = run_orbits(table, starts, max_collisions=collisions, flags=flags)
        best = max(best, final[:, 0].sum() / (time.process_time() - t0))
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--orbits", type=int, default=16)
    parser.add_argument("--collisions", type=int, default=100_000)
    args = parser.parse_args()
    print(machine_line())
    print(f"{'table':<22}{'law':<10}{'straight M/s':>14}{'magnetic M/s':>14}{'ratio':>8}")
    for name, (scene, start, W) in TABLES.items():
        for law in ("specular", "no-slip"):
            plain = scene.replace(law=law)
            straight = rate(plain, start, args.orbits, args.collisions)
            magnetic = rate(plain.replace(magnetic=W), start, args.orbits, args.collisions)
            print(f"{name:<22}{law:<10}{straight / 1e6:>14.3f}{magnetic / 1e6:>14.3f}{straight / magnetic:>8.2f}")
            if kernel_table(plain).disk_lattice:  # the general loop on the same torus, like for like
                # the lean loop's own slots (straight, lattice, no walls, one law), the general loop instead
                flags = kernel_table(plain).variant(layout.RECORD_NONE)._replace(disks=False)
                general = rate(plain, start, args.orbits, args.collisions, flags)
                print(f"{'  (general loop)':<22}{law:<10}{general / 1e6:>14.3f}{magnetic / 1e6:>14.3f}"
                      f"{general / magnetic:>8.2f}")


if __name__ == "__main__":
    main()
