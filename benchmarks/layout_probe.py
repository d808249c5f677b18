"""How far a kernel's speed moves when only its code layout changes: the resolution of an ablation.

The same event loop (commit ``BASE``, each scene's own kernel variant) is compiled
three more times, each a copy of the package under another name: once unchanged
(the control), and twice with a branch that never runs added after the collision
loop (``if n == -12345: ...`` calling ``sin``/``exp`` or ``atan2``/``log1p``/...).
The branch computes nothing on any orbit; it only moves the loop's machine code
and changes the registers the compiler has to plan for.  Each round times one
orbit of ``N_TIMED`` collisions with every kernel, interleaved; the table gives
the median and quartiles of each copy's rate over the original's.  Every copy
is the old package, so each runs through its own API (``package_copy.OldLoop``:
its serial batch loop around the orbit kernel, one orbit per call, as the current
package's ``run_orbits`` runs a kernel; before, the orbit kernels were called
directly), on the arrays of the current kernel table (``kernel_table(scene)``).

A change to a kernel that moves its rate by less than the "never-run code" rows
do is not resolved: it cannot be told from where the code happens to land.
Run: ``python benchmarks/layout_probe.py`` (appends its table to
``benchmarks/results/ablation.md``; ``ABLATION_ROUNDS``, ``ABLATION_BASE`` as in
``ablation_exact.py``).
"""
import datetime
import os
import sys
import tempfile
import time

import numpy as np

from noslipsim import tables
from noslipsim.core import layout

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ablation import Orbit, own_variant
from machine import machine_line
from package_copy import OldLoop, package_copy

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "results", "ablation.md")
BASE = os.environ.get("ABLATION_BASE", "c1ce5d5")
ROUNDS = int(os.environ.get("ABLATION_ROUNDS", "25"))
N_TIMED = 1_000_000
NONE = layout.RECORD_NONE

#: Where the never-run branch goes: before the loop's final re-basing (the general loop).
ANCHOR = "        if lattice:  # the final state may lie in another cell (a stop in mid-flight)\n"
COLD = {
    "control (unchanged copy)": "",
    "never-run branch A": ("        if n == -12345:  # never: only moves code\n"
                           "            vx = math.sin(vx) * math.cos(vy) + math.exp(w)\n"),
    "never-run branch B": ("        if n == -12345:  # never: only moves code\n"
                           "            vx = math.atan2(vx, vy) + math.log1p(abs(w)) * math.tanh(x)\n"
                           "            vy = math.sinh(vy) - math.expm1(y)\n"),
}
SCENES = {  # the general loop's fastest scenes: plain tables without force
    "pentagon": (tables.regular_polygon(5), (0.1, 0.05), (0.83, 0.41), 0.1),
    "Sinai box": (tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]), (0.1, 0.1), (0.6, 0.8), 0.1),
}


def copy_of_base(name, cold):
    """The event loop of the package at ``BASE`` as ``name``, ``cold`` inserted before ``ANCHOR`` in core/loop.py."""
    pkg = package_copy(BASE, name, os.path.join(tempfile.gettempdir(), f"noslipsim_probe_{BASE}"), fresh=True)
    path = os.path.join(pkg, "core", "loop.py")
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    if text.count(ANCHOR) != 1:
        raise SystemExit(f"core/loop.py at {BASE}: the anchor line is not there once")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text.replace(ANCHOR, cold + ANCHOR))
    # numba keys the batch loop's cache on core/batch.py alone (its archive time, the same every run), not on
    # the orbit kernel inside it: a new time makes it recompile around the loop just written
    os.utime(os.path.join(pkg, "core", "batch.py"))
    return OldLoop(name)


def main():
    loops = {"original": copy_of_base("noslipsim_probe0", "")}
    for i, (label, cold) in enumerate(COLD.items(), start=1):
        loops[label] = copy_of_base(f"noslipsim_probe{i}", cold)
    machine = machine_line(numpy=True, load=True)
    print(machine)
    header = ("| scene, law | " + " | ".join(COLD) + " |\n|---|" + "---:|" * len(COLD))
    print(header, flush=True)
    rows = []
    for name, (base, q, v, w) in SCENES.items():
        for law in ("specular", "no-slip"):
            scene = base.replace(law=law)
            flags = own_variant(scene, NONE)  # OldLoop keeps the flags BASE knows
            orbit = Orbit(scene, q, v, w)
            for loop in loops.values():
                orbit.run_old(loop, flags, 10, NONE)
            ratios = {label: [] for label in COLD}
            for _ in range(ROUNDS):
                rates = {}
                for label, loop in loops.items():
                    t0 = time.perf_counter()
                    rates[label] = orbit.run_old(loop, flags, N_TIMED, NONE)[0] / (time.perf_counter() - t0)
                for label in COLD:
                    ratios[label].append(rates[label] / rates["original"])
            cells = []
            for label in COLD:
                q1, med, q3 = np.percentile(ratios[label], [25, 50, 75])
                cells.append(f"{med:.3f} [{q1:.3f}, {q3:.3f}]")
            rows.append(f"| {name}, {law} | " + " | ".join(cells) + " |")
            print(rows[-1], flush=True)
    when = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    with open(OUT, "a", encoding="utf-8") as fh:
        fh.write("\n## Layout probe: the same kernel with never-run code added (resolution of an ablation)\n\n")
        fh.write(f"Command: `python benchmarks/layout_probe.py` ({when})\n\n{machine}\n\n")
        fh.write(f"The general loop of commit {BASE}, each scene's own variant through its serial batch loop, "
                 "against copies of itself: "
                 f"median [quartiles] of the copy's rate over the original's, {ROUNDS} interleaved rounds of "
                 f"one orbit of {N_TIMED:,} collisions. The never-run branches compute nothing on any orbit.\n\n")
        fh.write(header + "\n" + "\n".join(rows) + "\n")
    print(f"\nappended to {os.path.relpath(OUT)}")


if __name__ == "__main__":
    main()
