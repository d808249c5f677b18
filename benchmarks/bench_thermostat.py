"""Thermostatted collisions per second against free fall under the same force (issue 23, item 1).

For each scene: the scene's own kernel variant, no record, one orbit of ``n`` collisions
(``bench_collisions.kernel_rate``), with the force flown as free fall and with the isokinetic
thermostat, alternately for ``--rounds`` rounds (the ratio is what a shared machine's load
cannot fake); best rates and the median ratio thermostat / free fall.

    PYTHONPATH=src python benchmarks/bench_thermostat.py [--n 300000] [--rounds 5]
"""
import argparse
import math
import os
import statistics
import sys

from noslipsim import tables

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_collisions import kernel_rate
from machine import machine_line

DISK = 1 / math.sqrt(2)
CASES = {  # name: (scene with the force, start, velocity)
    "pentagon, no-slip": (tables.regular_polygon(5, force=(0.3, -1.0)), (0.1, 0.05), (0.83, 0.41)),
    "Sinai box, no-slip": (tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.3)], force=(2.0, 0.7)), (0.2, 0.2),
                           (0.6, 0.8)),
    "hexagonal gas, specular": (tables.hex_lorentz_cell(0.45, force=(1.5, 0.4), law="specular"), (0.0, 0.48),
                                (0.6, 0.8)),
    "hexagonal gas, no-slip": (tables.hex_lorentz_cell(0.45, force=(1.5, 0.4)), (0.0, 0.48), (0.6, 0.8)),
}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=300_000)
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    print(machine_line(load=True))
    print(f"{'scene':28s} {'free fall coll/s':>17s} {'thermostat coll/s':>18s} {'ratio (median)':>15s} {'range':>12s}")
    for name, (scene, q, v) in CASES.items():
        therm = scene.replace(thermostat="isokinetic")
        best = {False: 0.0, True: 0.0}
        ratios = []
        for r in range(args.rounds):
            rates = {}
            for th in ((False, True) if r % 2 == 0 else (True, False)):
                rates[th] = kernel_rate(therm if th else scene, q, v, args.n)[0]
                best[th] = max(best[th], rates[th])
            ratios.append(rates[True] / rates[False])
        print(f"{name:28s} {best[False]:17,.0f} {best[True]:18,.0f} {statistics.median(ratios):15.3f} "
              f"{min(ratios):5.2f}-{max(ratios):.2f}")
    print(machine_line(load=True))


if __name__ == "__main__":
    main()
