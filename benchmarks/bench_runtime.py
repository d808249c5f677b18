"""What numba's reference-counting runtime costs the event loop (issue: pay only for what a scene needs).

The kernels are compiled without it (``core/jit.py``: ``_nrt=False``); setting
``NOSLIPSIM_NUMBA_NRT=1`` compiles them with it, uncached, so the two can be
timed on the same machine.  Each configuration runs in its own process: the
scene's own kernel variant, no record, one orbit per scene through the one
kernel call ``run_orbits`` (``bench_collisions.kernel_rate``; best of three after
a compile warm-up), and the final states must be bitwise equal (the runtime
only owns memory; it does not touch arithmetic).
Run: ``python benchmarks/bench_runtime.py [--scale 0.01]`` (``--scale`` multiplies
the collisions per orbit; small values only check that it runs).
"""
import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import machine_line

CHILD = r"""
import json, sys
import numpy as np
sys.path.insert(0, sys.argv[1])
scale = float(sys.argv[2])
from bench_collisions import kernel_rate
from noslipsim import tables
scenes = {
    "pentagon": (tables.regular_polygon(5), (0.1, 0.05), (0.83, 0.41), 2_000_000),
    "Sinai box": (tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]), (0.1, 0.1), (0.6, 0.8), 2_000_000),
    "Sinai torus": (tables.sinai_torus(0.25), (0.45, 0.1), (0.6, 0.8), 1_000_000),
    "Galton board": (tables.galton_board(2.0, 0.5, 1.0), (1.0, 0.0), (0.6, 0.8), 300_000),
}
out = {}
for name, (scene, q, v, n) in scenes.items():
    rate, res = kernel_rate(scene, q, v, max(1, int(n * scale)), repeat=3)
    out[name] = (rate, np.asarray(res, dtype=np.float64).view(np.int64).tolist())
print(json.dumps(out))
"""


def measure(with_runtime, scale=1.0):
    env = dict(os.environ)
    env.pop("NOSLIPSIM_NUMBA_NRT", None)
    if with_runtime:
        env["NOSLIPSIM_NUMBA_NRT"] = "1"
    here = os.path.dirname(os.path.abspath(__file__))
    done = subprocess.run([sys.executable, "-c", CHILD, here, str(scale)], env=env, capture_output=True, text=True,
                          check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scale", type=float, default=1.0, help="multiplies the collisions per orbit")
    args = ap.parse_args()
    print(machine_line())
    lean = measure(False, args.scale)
    full = measure(True, args.scale)
    print(f"{'scene':<14}{'with runtime coll/s':>22}{'without (shipped)':>20}{'gain':>8}  identical")
    for name in lean:
        (r0, b0), (r1, b1) = full[name], lean[name]
        print(f"{name:<14}{r0:>22,.0f}{r1:>20,.0f}{r1 / r0:>7.2f}x  {b0 == b1}")
        if b0 != b1:
            raise SystemExit(f"{name}: final states differ with and without the runtime")


if __name__ == "__main__":
    main()
