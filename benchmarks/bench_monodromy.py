"""Cost of the exact monodromy and of Lyapunov exponents against the plain orbit they follow.

Goal (issue 12): ``analysis.monodromy`` costs at most 3x ``ns.simulate`` of the same
collisions; a Lyapunov exponent over ~1e5 collisions takes seconds.  Each case times,
interleaved in one process (best of ``--repeat`` runs, after a warm-up that compiles
and loads the kernels): ``simulate`` for ``period + 1`` collisions (the orbit the
monodromy follows, with its log and Dataset), ``monodromy`` for ``period`` (which runs
that orbit itself), and their ratio; then ``lyapunov`` over 1e5 collisions.
Run: ``python benchmarks/bench_monodromy.py [--repeat 7]``.
"""
import argparse
import math
import os
import sys
import time

import noslipsim as ns
from noslipsim import tables
from noslipsim.analysis import lyapunov, monodromy, two_disk_orbit

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import machine_line


def best(fn, repeat):
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    print(f"{machine_line(numpy=True)} | load average {os.getloadavg()[0]:.1f}")
    disks, state = two_disk_orbit(0.9, 1.2, 0.3)  # elliptic: the orbit stays put for any period
    pentagon = tables.regular_polygon(5)
    gravity_box = tables.rectangle(2, 1, disks=[(1.0, 0.5, 0.3)], force=(0.0, -1.0))
    cases = [("two disks, 2-periodic", disks, state, [2, 100, 10_000, 100_000]),
             ("pentagon (segments)", pentagon, dict(position=(0.1, 0.05), velocity=(0.6, 0.8), spin=0.3),
              [14, 10_000, 100_000]),
             ("box + disk, gravity", gravity_box, dict(position=(0.2, 0.2), velocity=(0.9, 0.43), spin=0.1),
              [100, 1000])]  # chaotic: long products overflow float64, so periods stay short
    print(f"{'case':<24}{'period':>8}{'simulate ms':>13}{'monodromy ms':>14}{'ratio':>7}")
    for name, scene, st, periods in cases:
        for p in periods:
            t_sim = best(lambda scene=scene, st=st, p=p: ns.simulate(scene, **st, max_collisions=p + 1), args.repeat)
            t_mon = best(lambda scene=scene, st=st, p=p: monodromy(scene, **st, period=p), args.repeat)
            print(f"{name:<24}{p:>8}{t_sim * 1e3:>13.3f}{t_mon * 1e3:>14.3f}{t_mon / t_sim:>7.2f}")
    print(f"{'lyapunov, 1e5 collisions':<32}{'seconds':>10}{'exponent':>12}")
    runs = [("Sinai torus specular R=0.25", tables.sinai_torus(0.25, law="specular"), (0.45, 0.1), 0.0),
            ("Sinai torus no-slip R=0.3", tables.sinai_torus(0.3), (0.45, 0.1), 0.3),
            ("Galton board no-slip", tables.galton_board(), (1.0, 0.0), 0.2)]
    for name, scene, q, w in runs:
        v = (math.cos(0.7), math.sin(0.7))
        lyapunov(scene, q, v, w, n_collisions=1000)
        t0 = time.perf_counter()
        lam = lyapunov(scene, q, v, w, n_collisions=100_000)
        print(f"{name:<32}{time.perf_counter() - t0:>10.3f}{lam:>12.4f}")


if __name__ == "__main__":
    main()
