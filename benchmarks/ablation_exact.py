"""Ablation: exact long flights and long walls (issue 13, item 3) against the evaluation before them.

The baseline is the event loop of commit ``BASE`` (the branch point), imported in the
same process from a copy of its sources under the package name ``noslipsim_old``
(``git archive``; the package imports itself only relatively, and the copy keeps its
own numba cache).  Both kernels get the same kernel inputs, the current kernel table
(``kernel_table(scene)``; the new layout's extra columns are ignored by the old loop),
on each scene's own kernel variant (``table.variant(RECORD_NONE)``, spelt in the
base's five flags for the old loop, ``package_copy.OldLoop``): the Sinai torus and the hexagonal Lorentz
cell (lean loop, ``core/disks.py``), the Galton board (general lattice loop under a
force), the pentagon and the Sinai box (plain scenes: the segment crossing changed).
The new kernel runs through the package's one kernel call (``run_orbits``), the old
one through its own API: its serial batch loop (``batch_kernels(flags)[1]``,
``package_copy.OldLoop``), so both are a compiled loop over orbits around the orbit
kernel, one orbit per call.  (Before the one call, both orbit kernels were called
directly; ``run_orbits`` around the current kernel ran within 1 % of the direct call
on the pentagon and the Sinai torus, one orbit of 5e5 collisions.)

Timing: ``ROUNDS`` rounds, each running the old kernel, the new one and the old one
again (one orbit of ``N_TIMED`` collisions each, same start); the table gives the
median and quartiles of new/old and, as the control, of old-again/old (A/A): what
the method scatters with no change at all.  Differences of a percent or two are not
resolved by any method here: the same kernel with never-run code added after its
loop moves by up to 2 % (``benchmarks/layout_probe.py``).

Bits: the final states after N collisions are compared bit for bit.  Where they
differ, the per-flight check says by how much each flight differs: both kernels are
restarted from the old kernel's state after each of the first 1000 collisions (on
the element just hit) and their next collisions (time, position, velocity, spin,
cell) must agree to 1e-12.

Run: ``python benchmarks/ablation_exact.py`` (appends its table to
``benchmarks/results/ablation.md``;
``ABLATION_ROUNDS`` sets the rounds, ``ABLATION_BASE`` the commit);
``--quick`` runs ``QUICK_ROUNDS`` rounds of ``QUICK_N`` collisions and appends nothing
(a check that it runs, not a measurement).
"""
import argparse
import datetime
import os
import sys
import tempfile
import time

import numpy as np

from noslipsim import tables
from noslipsim.core import layout

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ablation import Orbit, label, own_variant
from machine import machine_line
from package_copy import OldLoop, package_copy

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "results", "ablation.md")
#: The commit before the exact evaluation (branch i13-exact's base).
BASE = os.environ.get("ABLATION_BASE", "c1ce5d5")
NONE, LOG = layout.RECORD_NONE, layout.RECORD_LOG
N_CHECK = 1000
#: Interleaved rounds and collisions per timed orbit.
ROUNDS = int(os.environ.get("ABLATION_ROUNDS", "25"))
N_TIMED = 1_000_000
TOL = 1e-12
#: Rounds and collisions per timed orbit with ``--quick``.
QUICK_ROUNDS = 3
QUICK_N = 20_000

SCENES = {  # name -> (scene, start q, v, w)
    "Sinai torus r=0.25": (tables.sinai_torus(0.25), (0.45, 0.1), (0.83, 0.41), 0.1),
    "hexagonal Lorentz cell r=0.3": (tables.hex_lorentz_cell(0.3), (0.4, 0.1), (0.7, 0.31), 0.2),
    "Galton board": (tables.galton_board(2.0, 0.5, 1.0), (1.0, 0.0), (0.3, 0.95), 0.1),
    "pentagon": (tables.regular_polygon(5), (0.1, 0.05), (0.83, 0.41), 0.1),
    "Sinai box": (tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]), (0.1, 0.1), (0.6, 0.8), 0.1),
}


def old_package():
    """The event loop of ``noslipsim_old`` (the sources of ``BASE``, importable next to the current package)."""
    package_copy(BASE, "noslipsim_old", os.path.join(tempfile.gettempdir(), f"noslipsim_old_{BASE}"))
    return OldLoop("noslipsim_old")


def per_flight(scene, q, v, w, old):
    """Both kernels restarted from the old kernel's state after each of the first collisions."""
    flags = own_variant(scene, LOG)
    log = np.zeros((N_CHECK + 1, layout.N_LOG))
    Orbit(scene, q, v, w).run_old(old, flags, N_CHECK + 1, LOG, log)
    cols = (layout.LOG_T, layout.LOG_X, layout.LOG_Y, layout.LOG_VX, layout.LOG_VY, layout.LOG_W,
            layout.LOG_CELL_A1, layout.LOG_CELL_A2)
    worst, agree, same_bits = 0.0, 0, 0
    a_old = np.zeros((1, layout.N_LOG))
    a_new = np.zeros((1, layout.N_LOG))
    for k in range(N_CHECK):
        a = log[k]
        start = Orbit(scene, (a[layout.LOG_X], a[layout.LOG_Y]), (a[layout.LOG_VX], a[layout.LOG_VY]), a[layout.LOG_W])
        a_old[:] = 0.0
        a_new[:] = 0.0
        e = int(a[layout.LOG_ELEMENT])
        n_old = start.run_old(old, flags, 1, LOG, a_old, start_element=e)[0]
        n_new = start.run(flags, 1, LOG, a_new, start_element=e)[0]
        length = max(scene.scale, abs(a_old[0, layout.LOG_X]), abs(a_old[0, layout.LOG_Y]))
        dev = max(abs(a_new[0, c] - a_old[0, c]) / (length if c in (layout.LOG_X, layout.LOG_Y) else 1.0)
                  for c in cols)
        agree += n_old == n_new and dev <= TOL
        same_bits += n_old == n_new and np.array_equal(a_old[0, list(cols)], a_new[0, list(cols)])
        worst = max(worst, dev)
    return agree, same_bits, worst


def rounds(orbit, old, flags):
    """The old kernel's median rate, per round new/old and old-again/old (``ROUNDS`` interleaved rounds),
    both final states."""
    runs = {"old": lambda n: orbit.run_old(old, flags, n, NONE), "new": lambda n: orbit.run(flags, n, NONE)}
    for run in runs.values():
        run(10)  # compile (or load from the cache)
    ratios, control, olds = [], [], []
    for _ in range(ROUNDS):
        rates = []
        for key in ("old", "new", "old"):
            t0 = time.perf_counter()
            out = runs[key](N_TIMED)
            rates.append(out[0] / (time.perf_counter() - t0))
            if key == "new":
                out_new = out
            else:
                out_old = out
        ratios.append(rates[1] / rates[0])
        control.append(rates[2] / rates[0])
        olds.append(rates[0])
    return float(np.median(olds)), np.array(ratios), np.array(control), out_old, out_new


def quartiles(x):
    q1, med, q3 = np.percentile(x, [25, 50, 75])
    return f"{med:.3f} [{q1:.3f}, {q3:.3f}]"


def scene_row(name, scene, q, v, w, old):
    """One table row: the rounds, the final states' bits and the per-flight check of one scene."""
    flags = own_variant(scene, NONE)
    rate_old, ratios, control, out_old, out_new = rounds(Orbit(scene, q, v, w), old, flags)
    same = np.array_equal(np.array(out_old, dtype=np.float64).view(np.int64),
                          np.array(out_new, dtype=np.float64).view(np.int64))
    agree, same_bits, worst = per_flight(scene, q, v, w, old)
    return (f"| {name}, {scene.law} | {label(flags)} | {rate_old:,.0f} | {quartiles(ratios)} | {quartiles(control)} "
            f"| {'bitwise identical' if same else 'differs'} "
            f"| {agree}/{N_CHECK} within {TOL:g} (max dev {worst:.1e}), {same_bits}/{N_CHECK} bitwise |")


def append_table(machine, header, rows):
    """Append the section, its note and ``rows`` to ``OUT``."""
    when = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    with open(OUT, "a", encoding="utf-8") as fh:
        fh.write("\n## The kernels against the wave's start (issue 13): exact long flights, energy kept\n\n")
        fh.write(f"Command: `python benchmarks/ablation_exact.py` ({when})\n\n{machine}\n\n")
        fh.write(f"{ROUNDS} interleaved rounds of one orbit of {N_TIMED:,} collisions each (old, new, old again), "
                 f"each scene's own kernel variant; 'before' is the same variant compiled from commit "
                 f"{BASE} in the same process; the new kernel through `run_orbits`, the old one through its "
                 "serial batch loop (one orbit per call each); the A/A control is the old kernel's second run "
                 "over its first. "
                 "Changed since: far cells of the lean disk loop (past 16 cells, out of line: exact lattice "
                 "offset, compensated cross product), straight hits 16 or more cells away in the general "
                 "lattice loop (cells.far_hit_point), a line's or segment's distance on tables with a long wall "
                 "(events.exact_line_hit; other tables run a loop compiled without it, kernel flag walls), and "
                 "the energy settled between blocks of 256 collisions (core/energy.py). Per flight: both "
                 "kernels restarted from the old kernel's state after each of the first 1000 collisions; "
                 "deviations of time, velocity, spin (absolute) and position (relative to max(scale, |q|)).\n\n")
        fh.write(header + "\n" + "\n".join(rows) + "\n")


def main():
    global ROUNDS, N_TIMED  # --quick: a smaller size for every scene
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help=f"{QUICK_ROUNDS} rounds of {QUICK_N:,} collisions; print the rows, append nothing")
    args = ap.parse_args()
    if args.quick:
        ROUNDS, N_TIMED = QUICK_ROUNDS, QUICK_N
    old = old_package()
    machine = machine_line(numpy=True, load=True)
    print(machine)
    header = ("| scene, law | variant | before (BASE) coll/s, median | after / before, median [quartiles] "
              "| A/A control | final state after N | per flight (1000, restarted from the old state) |\n"
              "|---|---|---:|---:|---:|---|---|")
    print(header, flush=True)
    rows = []
    for name, (base, q, v, w) in SCENES.items():
        for law in ("specular", "no-slip"):
            rows.append(scene_row(name, base.replace(law=law), q, v, w, old))
            print(rows[-1], flush=True)
    if args.quick:
        print("\n--quick: nothing appended")
        return
    append_table(machine, header, rows)
    print(f"\nappended to {os.path.relpath(OUT)}")


if __name__ == "__main__":
    main()
