"""Collisions per second of the event loop on three scenes (issue: core simulator).

Measures the compiled kernel with the lean recorder (no collision log) and the
public ``simulate`` (full log), after a warm-up run that compiles.  Prints the
machine, then one line per scene.  Run: ``python benchmarks/bench_collisions.py``.
"""
import math
import platform
import time

import numpy as np

from noslipsim import Circle, Scene, simulate, tables
from noslipsim.core import layout
from noslipsim.core.loop import orbit_kernel

SCENES = {
    "pentagon (no force)": (tables.regular_polygon(5), (0.1, 0.05), (0.83, 0.41)),
    "Sinai box (no force)": (tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]), (0.1, 0.1), (0.6, 0.8)),
    "circle + gravity": (Scene([Circle((0.0, 0.0), 1.0, "inside")], force=(0.0, -1.0)), (0.1, 0.2), (0.4, 0.1)),
}


def kernel_rate(scene, q, v, n, repeat=1):
    """Best collisions/s over ``repeat`` timed runs of the scene's own kernel variant (no record).

    Returns ``(rate, outputs)``: ``outputs`` are the kernel's 12 outputs of the last run.
    """
    inputs = scene.kernel_inputs()
    kinds = inputs[0]
    c, s = scene.noslip_coefficients
    ax, ay = scene.force
    rec = np.zeros((0, layout.N_LOG))
    mask = np.zeros(len(kinds), dtype=np.bool_)
    args = (*inputs, scene.law_code, c, s, ax, ay, q[0], q[1], v[0], v[1], 0.1)
    run_orbit = orbit_kernel(*scene.kernel_variant(layout.RECORD_NONE))
    run_orbit(*args, 10, math.inf, -math.inf, scene.scale, layout.RECORD_NONE, rec, mask)  # compile
    best = 0.0
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = run_orbit(*args, n, math.inf, -math.inf, scene.scale, layout.RECORD_NONE, rec, mask)
        best = max(best, out[0] / (time.perf_counter() - t0))
    return best, out


def simulate_rate(scene, q, v, n):
    simulate(scene, q, v, 0.1, max_collisions=10)
    t0 = time.perf_counter()
    ds = simulate(scene, q, v, 0.1, max_collisions=n)
    return int(ds.n_collisions) / (time.perf_counter() - t0)


def main(n=2_000_000):
    print(f"machine: {platform.machine()} {platform.processor() or ''} | {platform.system()} "
          f"| python {platform.python_version()} | numpy {np.__version__}")
    print(f"{'scene':<24}{'kernel (no log) coll/s':>24}{'simulate (log) coll/s':>24}")
    for name, (scene, q, v) in SCENES.items():
        print(f"{name:<24}{kernel_rate(scene, q, v, n)[0]:>24,.0f}{simulate_rate(scene, q, v, n // 4):>24,.0f}")


if __name__ == "__main__":
    main()
