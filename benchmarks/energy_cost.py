"""What keeping the energy costs: collision rates of the scene kernels, to run against two source trees.

The energy settling of issue 13 item 5 (``core/energy.py``) is not a kernel
flag, so its cost is measured across two processes: this script times each
scene's own kernel variant (``Scene.kernel_variant(RECORD_NONE)``, no record,
as ``simulate_many`` runs it) on ``--collisions`` collisions, best of
``--repeat`` by the thread's CPU time (the machine is shared: wall time
counts other processes' turns on the core), and prints one line per scene.  Run it alternately with the
package before and after the change, e.g.::

    for i in 1 2 3; do
        PYTHONPATH=/tmp/head_src/src python benchmarks/energy_cost.py --tag before
        PYTHONPATH=$PWD/src python benchmarks/energy_cost.py --tag after
    done

and compare the rates of the same round (the machine's load changes between rounds).
Scenes: the ablation's pentagon, Sinai box, circle under gravity, Galton board and
Sinai torus r = 0.25 (lean loop), both laws where the law matters.
"""
import argparse
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ablation import CIRCLE_G, GALTON, PENTAGON, SINAI_BOX, STARTS, TORUS, Orbit

from noslipsim.core import layout
from noslipsim.core.loop import orbit_kernel

SCENES = [
    ("pentagon", PENTAGON, "pentagon"),
    ("pentagon specular", PENTAGON.replace(law="specular"), "pentagon"),
    ("Sinai box", SINAI_BOX, "Sinai box"),
    ("circle + gravity", CIRCLE_G, "circle + gravity"),
    ("Galton board", GALTON, "Galton board"),
    ("Sinai torus r=0.25", TORUS, "Sinai torus r=0.25"),
    ("Sinai torus r=0.25 specular", TORUS.replace(law="specular"), "Sinai torus r=0.25"),
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
    for label, scene, start in SCENES:
        orbit = Orbit(scene, *STARTS[start])
        kernel = orbit_kernel(*scene.kernel_variant(layout.RECORD_NONE))
        orbit.run(kernel, 10, layout.RECORD_NONE)
        best = 0.0
        for _ in range(args.repeat):
            t0 = time.thread_time()  # CPU time of this thread: another process on the core does not count
            out = orbit.run(kernel, n, layout.RECORD_NONE)
            best = max(best, out[0] / (time.thread_time() - t0))
        kin = out[7] ** 2 + out[8] ** 2
        print(f"{args.tag}\t{label}\t{best / 1e6:.3f}\tM/s\tn={out[0]}\tK={kin:.17g}\t"
              f"{'ok' if math.isfinite(kin) else 'nan'}", flush=True)


if __name__ == "__main__":
    main()
