"""What keeping the energy costs: collision rates of the scene kernels, to run against two source trees.

The energy settling of issue 13 item 5 (``core/energy.py``) is not a kernel
flag, so its cost is measured across two processes: this script times each
scene's own kernel variant (no record, as ``simulate_many`` runs it) through the
package's one kernel call (``run_orbits`` on ``kernel_table(scene)``; a source tree
from before it through its own API, ``scene.kernel_variant(RECORD_NONE)`` and its
serial batch loop: ``package_copy.kernel_call``) on ``--collisions`` collisions, best of
``--repeat`` by the thread's CPU time (the machine is shared: wall time
counts other processes' turns on the core), and prints one line per scene.  Run it alternately with the
package before and after the change, e.g.::

    for i in 1 2 3; do
        PYTHONPATH=/tmp/head_src/src python benchmarks/energy_cost.py --tag before
        PYTHONPATH=$PWD/src python benchmarks/energy_cost.py --tag after
    done

and compare the rates of the same round (the machine's load changes between rounds).
Scenes: the ablation's pentagon, Sinai box, circle under gravity, Galton board and
Sinai torus r = 0.25 (lean loop), both laws where the law matters (written out here,
not imported from ``ablation.py``, which needs the current package).
"""
import argparse
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from package_copy import kernel_call

from noslipsim import Circle, Scene, tables
from noslipsim.simulate import start_cell

PENTAGON = tables.regular_polygon(5)
TORUS = tables.sinai_torus(0.25)
SCENES = [  # label, scene, start (q, v, w) as in ablation.STARTS
    ("pentagon", PENTAGON, ((0.1, 0.05), (0.83, 0.41), 0.1)),
    ("pentagon specular", PENTAGON.replace(law="specular"), ((0.1, 0.05), (0.83, 0.41), 0.1)),
    ("Sinai box", tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]), ((0.1, 0.1), (0.6, 0.8), 0.1)),
    ("circle + gravity", Scene([Circle((0.0, 0.0), 1.0, "inside")], force=(0.0, -1.0)),
     ((0.1, 0.2), (0.4, 0.1), 0.1)),
    ("Galton board", tables.galton_board(2.0, 0.5, 1.0), ((1.0, 0.0), (0.3, 0.95), 0.1)),
    ("Sinai torus r=0.25", TORUS, ((0.45, 0.1), (0.83, 0.41), 0.1)),
    ("Sinai torus r=0.25 specular", TORUS.replace(law="specular"), ((0.45, 0.1), (0.83, 0.41), 0.1)),
]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--collisions", type=float, default=2e6)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--tag", default="")
    args = ap.parse_args()
    n = int(args.collisions)
    import noslipsim

    print(f"# {args.tag} {os.path.dirname(noslipsim.__file__)}", flush=True)
    run = kernel_call("noslipsim")
    for label, scene, (q, v, w) in SCENES:
        _, _, r = start_cell(scene, np.asarray(q, float))
        start = (float(r[0]), float(r[1]), v[0], v[1], w)
        run(scene, start, 10)  # compile (or load from the cache)
        best = 0.0
        for _ in range(args.repeat):
            t0 = time.thread_time()  # CPU time of this thread: another process on the core does not count
            out = run(scene, start, n)
            best = max(best, out[0] / (time.thread_time() - t0))
        kin = out[7] ** 2 + out[8] ** 2
        print(f"{args.tag}\t{label}\t{best / 1e6:.3f}\tM/s\tn={out[0]}\tK={kin:.17g}\t"
              f"{'ok' if math.isfinite(kin) else 'nan'}", flush=True)


if __name__ == "__main__":
    main()
