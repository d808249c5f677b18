"""Ablation of the event-loop specialisations (issue: pay only for what a scene needs, measured).

``orbit_kernel(spin, lattice, mode, disks, walls, flight, mixed)`` (a
``core.variant.Variant``) fixes each slot at compile time (``None`` = read it from
the arguments: the general path); the flight slot is what a force flag was
(``STRAIGHT`` or ``FORCE`` fixed, or ``None``).  Each row times one
orbit of ~2e6 collisions (best of three, after a compile warm-up) with a
baseline kernel and a specialised one on the SAME scene and start, and checks
that the two final states (the 12 outputs of the kernel: the first 12 summary
columns, ``core.batch.F_N`` to ``F_CELL2``) are bitwise equal.  Every run goes
through the package's one kernel call, ``run_orbits(kernel_table(scene), ...,
flags=variant)`` (one orbit per call: its Python overhead, some 30 us, is
nothing against 2e6 collisions; before, the orbit kernels were called directly).

Sections:

* straight flights: pentagon and Sinai box, specular and no-slip, through the
  force code (``flight=FORCE`` on a zero force: exact-zero leading coefficients,
  so the same roots) against the scene's own flight (``STRAIGHT``), the slots
  ``spin, lattice, mode`` fixed in both;
* per flag: the same scenes, each of ``flight, spin, lattice, mode`` specialised
  alone (the others ``None``), flight and lattice together, and all four;
* no spin bookkeeping: specular tables, ``spin=None`` vs ``spin=False`` with the
  other flags already fixed;
* lean recorder: ``RECORD_LOG`` (full log array) vs ``RECORD_NONE`` on the same
  kernel (``n_rec`` differs by design; the other 11 outputs must not);
* force: circle under gravity and the Galton board (lattice, force);
* one disk per cell: the lean loop of ``core/disks.py`` (``disks=True``) vs
  the lattice variant of the general loop on the Sinai torus; other formulas,
  so checked per flight to 1e-12 (as in ``tests/test_disk_lattice.py``);
* several disks per cell: the same lean loop (its copy loop, ``disks_walk``) vs
  the lattice variant of the general loop on the kernels' (canonical) form of
  two-disk cells, a scattered Lorentz gas of five disks of different radii per
  cell and the hexagonal cell at r = 0.45 (one disk reaching into its
  neighbours); checked per flight to 1e-12 (as in ``tests/test_disk_cells.py``);
* neighbour-cell lookup: Sinai torus r = 0.25 as a lattice vs the same disks
  written out as a 61 x 61 block of explicit ``Circle`` copies (no enclosing box:
  the explicit orbit is timed until it escapes the block).  Positions are
  re-centred per cell on the lattice, so results agree to rounding, not
  bitwise; and since the Sinai billiard is chaotic (rounding differences grow
  ~10x per collision) a whole-orbit comparison can only agree for the first
  few collisions.  The check is therefore per flight, as in
  ``tests/test_lattice.py``: the explicit scene is restarted from the
  lattice state after each of the first 1000 collisions and must hit the same
  disk (element + cell) at the same time and place to 1e-9.

Run: ``python benchmarks/ablation.py`` (writes ``benchmarks/results/ablation.md`` too);
``python benchmarks/ablation.py --only "several disks per cell"`` runs one section and
replaces only its rows in the written table; ``--quick`` times orbits of ``QUICK_N``
collisions, once, and writes nothing (a check that every section runs, not a
measurement).
"""
import argparse
import datetime
import os
import sys
import time

import numpy as np

from noslipsim import Circle, Scene, tables
from noslipsim._engine.canonical import canonical_form
from noslipsim._engine.lattice import lattice_matrix
from noslipsim._engine.run import run_orbits
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout
from noslipsim.core.variant import FLIGHTS, FORCE, GENERAL, STRAIGHT, Variant
from noslipsim.simulate import start_cell

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import machine_line
from package_copy import outputs

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "results", "ablation.md")
N = 2_000_000
REPEAT = 3
#: Collisions per timed orbit with ``--quick`` (timed once).
QUICK_N = 20_000
#: The slots the general loop fixes in these rows (the old ``force, spin, lattice, mode``): the rest run time.
CORE = ("spin", "lattice", "mode", "flight")
NONE, LOG = layout.RECORD_NONE, layout.RECORD_LOG

PENTAGON = tables.regular_polygon(5)
SINAI_BOX = tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)])
CIRCLE_G = Scene([Circle((0.0, 0.0), 1.0, "inside")], force=(0.0, -1.0))
GALTON = tables.galton_board(2.0, 0.5, 1.0)
TORUS = tables.sinai_torus(0.25)
SQUARE = {"a1": [1.0, 0.0], "a2": [0.0, 1.0]}
SEVERAL_DISKS = {  # name -> scene as a user writes it (the kernels run its canonical form)
    "2 disks per cell": Scene((Circle((0.25, 0.25), 0.2), Circle((0.75, 0.75), 0.15)), lattice=SQUARE),
    "2 disks per cell, one reaching out": Scene((Circle((0.1, 0.5), 0.3), Circle((0.62, 0.5), 0.15)),
                                                lattice=SQUARE),
    "5 disks of different radii per cell": Scene(tuple(Circle((x, y), r) for x, y, r in (
        (0.1, 0.1, 0.08), (0.5, 0.2, 0.12), (0.3, 0.6, 0.1), (0.75, 0.7, 0.15), (0.85, 0.3, 0.06))),
        lattice=SQUARE),
    "hexagonal cell r=0.45 (reaches 4 neighbours)": tables.hex_lorentz_cell(0.45),
}

STARTS = {  # scene name -> start (q, v, w)
    "pentagon": ((0.1, 0.05), (0.83, 0.41), 0.1),
    "Sinai box": ((0.1, 0.1), (0.6, 0.8), 0.1),
    "circle + gravity": ((0.1, 0.2), (0.4, 0.1), 0.1),
    "Galton board": ((1.0, 0.0), (0.3, 0.95), 0.1),
    "Sinai torus r=0.25": ((0.45, 0.1), (0.83, 0.41), 0.1),
}


def label(flags):
    """``orbit_kernel(...)`` call text for a :class:`Variant` (the variant ``run_orbits(..., flags=...)`` runs)."""
    if all(f is None for f in flags):
        return "general"
    modes = {NONE: "NONE", LOG: "LOG", layout.RECORD_PORTRAIT: "PORTRAIT"}
    texts = {"mode": modes.get, "flight": FLIGHTS.__getitem__}
    parts = [f"{n}={texts.get(n, str)(f)}" for n, f in zip(Variant._fields, flags, strict=True) if f is not None]
    return ", ".join(parts)


def fixed(flags, *names):
    """The variant with only the slots ``names`` of ``flags`` fixed, the others read at run time."""
    return Variant(**{n: getattr(flags, n) for n in names})


def own_variant(scene, mode):
    """The scene's own kernel variant (``kernel_table(scene).variant(mode)``)."""
    return kernel_table(scene).variant(mode)


class Orbit:
    """One scene (as written, not its canonical form) and start, ready to be run by any kernel variant."""

    def __init__(self, scene, q, v, w):
        self.scene = scene
        self.table = kernel_table(scene)
        _, origin, r = start_cell(scene, np.asarray(q, float))
        self.origin = origin
        self.start = (float(r[0]), float(r[1]), float(v[0]), float(v[1]), float(w))

    def run(self, flags, n, mode, rec=None, start_element=-1):
        """The 12 outputs of the kernel variant ``flags`` through ``run_orbits`` (``rec``: 2-D, written in place)."""
        final = run_orbits(self.table, [self.start], max_collisions=n, mode=mode, flags=flags,
                           rec=None if rec is None else rec[None], start_elements=[start_element])
        return outputs(final[0])

    def run_old(self, old, flags, n, mode, rec=None, start_element=-1):
        """The same through the loop of an old package copy (``package_copy.OldLoop``), on this table's arrays."""
        return old.run(self.table, flags, self.start, n, mode, rec, start_element=start_element)


def bits(out, skip=()):
    """The outputs as int64 bit patterns (float64 holds every count and cell index exactly)."""
    return np.array([o for i, o in enumerate(out) if i not in skip], dtype=np.float64).view(np.int64)


def timed(orbit, runs):
    """Best rates over REPEAT interleaved runs of N collisions, and the final states.

    ``runs``: ``(flags, mode)`` pairs; a RECORD_LOG run gets a log array of every collision.
    """
    recs = [np.zeros((N if mode == LOG else 0, layout.N_LOG)) for _, mode in runs]
    for (flags, mode), rec in zip(runs, recs):
        orbit.run(flags, 10, mode, rec)  # compile (or load from the cache)
    best = [0.0] * len(runs)
    outs = [None] * len(runs)
    for _ in range(REPEAT):
        for i, ((flags, mode), rec) in enumerate(zip(runs, recs)):
            t0 = time.perf_counter()
            outs[i] = orbit.run(flags, N, mode, rec)
            dt = time.perf_counter() - t0
            best[i] = max(best[i], outs[i][0] / dt)
    return best, outs


def compare(rows, section, name, scene, base, variant, base_mode=NONE, var_mode=NONE):
    """Time ``base`` and ``variant`` (flag tuples) on one scene and start; append a table row."""
    orbit = Orbit(scene, *STARTS[name])
    (rate_b, rate_v), (out_b, out_v) = timed(orbit, [(base, base_mode), (variant, var_mode)])
    skip = (3,) if base_mode != var_mode else ()  # n_rec counts the log rows: differs by design
    same = np.array_equal(bits(out_b, skip), bits(out_v, skip))
    same_txt = "yes" if same else "**NO**"
    if out_b[0] != N:
        same_txt += f" (stop {layout.STOP_REASONS[out_b[1]]} at n={out_b[0]})"
    if skip:
        same_txt += " (11/12 outputs: n_rec differs by design)"
    mode_txt = {NONE: "", LOG: " [LOG]"}
    rows.append((section, f"{name}, {scene.law}", label(base) + mode_txt[base_mode],
                 label(variant) + mode_txt[var_mode], rate_b, rate_v, same_txt))
    print(fmt_row(rows[-1]), flush=True)


def fmt_row(r):
    section, scene, base, var, rb, rv, same = r
    return f"| {section} | {scene} | {base} | {var} | {rb:,.0f} | {rv:,.0f} | {rv / rb:.2f} | {same} |"


HEADER = ("| gain | scene, law | baseline | specialised | baseline coll/s | specialised coll/s | speed-up "
          "| identical |\n|---|---|---|---|---:|---:|---:|---|")


def explicit_block(scene, half):
    """The lattice scene written out as ``(2 half + 1)^2`` explicit copies (cell (i, j) -> element index)."""
    A = np.array([scene.lattice["a1"], scene.lattice["a2"]]).T
    cells = [(i, j) for i in range(-half, half + 1) for j in range(-half, half + 1)]
    elems = [e.shifted(*(A @ [i, j])) for i, j in cells for e in scene.elements]
    return Scene(tuple(elems), law=scene.law, gamma=scene.gamma, force=scene.force), np.array(cells)


def neighbour_cells(rows, law, half=30, n_check=1000):
    """Lattice cell walk vs explicit copies: rates, and the per-flight check of the first collisions."""
    name = "Sinai torus r=0.25"
    lat = TORUS.replace(law=law)
    flat, cells = explicit_block(lat, half)
    q, v, w = STARTS[name]
    lat_orbit = Orbit(lat, q, v, w)
    flat_orbit = Orbit(flat, q, v, w)
    assert np.all(lat_orbit.origin == 0.0)  # both start in cell (0, 0): same coordinates
    k_lat = own_variant(lat, NONE)
    k_flat = own_variant(flat, NONE)
    (rate_lat,), _ = timed(lat_orbit, [(k_lat, NONE)])
    # explicit copies: until the orbit leaves the block (escape), best of REPEAT
    flat_orbit.run(k_flat, 10, NONE)
    rate_flat, n_flat = 0.0, 0
    for _ in range(REPEAT):
        t0 = time.perf_counter()
        out = flat_orbit.run(k_flat, 10**7, NONE)
        dt = time.perf_counter() - t0
        rate_flat, n_flat = max(rate_flat, out[0] / dt), out[0]
        stop_flat = layout.STOP_REASONS[out[1]]

    # the lattice orbit, logged (cell (0, 0) start: log positions are absolute)
    log = np.zeros((n_check + 1, layout.N_LOG))
    lat_orbit.run(own_variant(lat, LOG), n_check + 1, LOG, log)
    index = {tuple(c): k for k, c in enumerate(cells)}  # one element per cell here
    k_flat_log = own_variant(flat, LOG)
    one = np.zeros((1, layout.N_LOG))
    checked = agree = 0
    worst = 0.0
    for k in range(n_check):
        a, b = log[k], log[k + 1]
        here = (int(a[layout.LOG_CELL_A1]), int(a[layout.LOG_CELL_A2]))
        there = (int(b[layout.LOG_CELL_A1]), int(b[layout.LOG_CELL_A2]))
        if max(map(abs, here + there)) >= half:  # the flight leaves the explicit block
            continue
        checked += 1
        # restart on the disk just hit, with the lattice's outgoing state (the t = 0 root deflated)
        start = Orbit(flat, (a[layout.LOG_X], a[layout.LOG_Y]), (a[layout.LOG_VX], a[layout.LOG_VY]),
                      a[layout.LOG_W])
        one[:] = 0.0
        out = start.run(k_flat_log, 1, LOG, one, start_element=index[here])
        hit = tuple(cells[int(one[0, layout.LOG_ELEMENT])])
        dev = max(abs(one[0, layout.LOG_T] - (b[layout.LOG_T] - a[layout.LOG_T])),
                  abs(one[0, layout.LOG_X] - b[layout.LOG_X]), abs(one[0, layout.LOG_Y] - b[layout.LOG_Y]),
                  abs(one[0, layout.LOG_VX] - b[layout.LOG_VX]), abs(one[0, layout.LOG_VY] - b[layout.LOG_VY]),
                  abs(one[0, layout.LOG_W] - b[layout.LOG_W]))
        ok = out[0] == 1 and hit == there and dev <= 1e-9
        agree += ok
        worst = max(worst, dev)

    # whole orbit, for the record: how long do the two computations stay together?
    flat_log = np.zeros((n_check + 1, layout.N_LOG))
    flat_orbit.run(k_flat_log, n_check + 1, LOG, flat_log)
    together = 0
    for a, b in zip(log, flat_log):
        same_disk = tuple(cells[int(b[layout.LOG_ELEMENT])]) == (int(a[layout.LOG_CELL_A1]),
                                                                 int(a[layout.LOG_CELL_A2]))
        if not (same_disk and abs(a[layout.LOG_T] - b[layout.LOG_T]) <= 1e-9):
            break
        together += 1

    same_txt = (f"per flight: {agree}/{checked} agree (max dev {worst:.1e}); "
                f"whole orbit: first {together} collisions within 1e-9")
    rows.append(("neighbour-cell lookup", f"{name}, {law}",
                 f"explicit {2 * half + 1}x{2 * half + 1} copies, {label(k_flat)} "
                 f"({n_flat} coll. until {stop_flat})",
                 f"lattice, {label(k_lat)}", rate_flat, rate_lat, same_txt))
    print(fmt_row(rows[-1]), flush=True)


def disk_cells(rows, law, n_check=1000):
    """The lean loop of one disk per cell vs the lattice variant of the general loop (same flags otherwise).

    Other formulas, so the check is per flight: the lean loop restarted on the disk
    just hit, from the general loop's state after each of the first ``n_check``
    collisions, must hit the same cell at the same time and place to 1e-12.
    """
    name = "Sinai torus r=0.25"
    scene = TORUS.replace(law=law)
    flags = own_variant(scene, NONE)
    orbit = Orbit(scene, *STARTS[name])
    (rate_g, rate_l), _ = timed(orbit, [(fixed(flags, *CORE), NONE), (flags, NONE)])
    log = np.zeros((n_check + 1, layout.N_LOG))
    orbit.run(fixed(own_variant(scene, LOG), *CORE), n_check + 1, LOG, log)
    lean_log = own_variant(scene, LOG)
    one = np.zeros((1, layout.N_LOG))
    agree = 0
    worst = 0.0
    for k in range(n_check):
        a, b = log[k], log[k + 1]
        cell = (int(a[layout.LOG_CELL_A1]), int(a[layout.LOG_CELL_A2]))
        start = Orbit(scene, (a[layout.LOG_X] - cell[0], a[layout.LOG_Y] - cell[1]),
                      (a[layout.LOG_VX], a[layout.LOG_VY]), a[layout.LOG_W])
        one[:] = 0.0
        out = start.run(lean_log, 1, LOG, one, start_element=0)
        dev = max(abs(one[0, layout.LOG_T] - (b[layout.LOG_T] - a[layout.LOG_T])),
                  *(abs(one[0, c] - b[c] + (cell[c - layout.LOG_X] if c in (layout.LOG_X, layout.LOG_Y) else 0))
                    for c in (layout.LOG_X, layout.LOG_Y, layout.LOG_VX, layout.LOG_VY, layout.LOG_W)))
        same_cell = (out[10] + cell[0], out[11] + cell[1]) == (b[layout.LOG_CELL_A1], b[layout.LOG_CELL_A2])
        agree += out[0] == 1 and same_cell and dev <= 1e-12
        worst = max(worst, dev)
    rows.append(("one disk per cell", f"{name}, {law}", label(fixed(flags, *CORE)), label(flags), rate_g, rate_l,
                 f"per flight: {agree}/{n_check} agree (max dev {worst:.1e})"))
    print(fmt_row(rows[-1]), flush=True)


def inside_start(scene):
    """A start strictly inside the table of ``scene`` (relative to cell 0)."""
    for q in ((0.45, 0.1), (0.0, 0.45), (0.45, -0.3), (-0.3, 0.45), (0.02, -0.45)):
        if scene.depth(np.array([q]))[0] > 1e-3:
            return q
    raise ValueError("no start found")


def _on_own_copy(scene, e, o1, o2, cache={}):  # noqa: B006 (a cache per scene and copy)
    """``scene`` with element ``e`` moved by ``o1 a1 + o2 a2`` (the same billiard), so that its copy
    ``(e, 0, 0)`` is the disk of that offset and a restart can deflate it (``start_element``)."""
    if o1 == 0 and o2 == 0:
        return scene
    key = (id(scene), e, o1, o2)
    if key not in cache:
        A, _ = lattice_matrix(scene.lattice)
        elements = list(scene.elements)
        elements[e] = elements[e].shifted(*(A @ np.array([o1, o2], float)))
        cache[key] = (scene, scene.replace(elements=tuple(elements)))
    return cache[key][1]


def _disk_offset(scene, e, q):
    """Lattice offset of the copy of disk ``e`` on which the point ``q`` (relative to its cell) lies."""
    A, _ = lattice_matrix(scene.lattice)
    d = np.asarray(q) - np.asarray(scene.elements[e].center)
    cands = [(o1, o2) for o1 in range(-2, 3) for o2 in range(-2, 3)]
    dist = [abs(float(np.hypot(*(d - A @ np.array(o, float)))) - scene.elements[e].radius) for o in cands]
    return cands[int(np.argmin(dist))]


def several_disks(rows, name, law, n_check=1000):
    """The lean loop on several disks per cell vs the lattice variant of the general loop.

    Per flight as :func:`disk_cells`: both loops restarted on the disk just hit
    (the scene rewritten so that this disk is the element's own copy), from the
    general loop's state after each of the first ``n_check`` collisions, must hit
    the same disk in the same cell at the same time and place to 1e-12.
    """
    scene = canonical_form(SEVERAL_DISKS[name].replace(law=law)).scene
    flags = own_variant(scene, NONE)
    assert flags.disks is True
    q = inside_start(scene)
    orbit = Orbit(scene, q, (0.83, 0.41), 0.1)
    (rate_g, rate_l), _ = timed(orbit, [(fixed(flags, *CORE), NONE), (flags, NONE)])
    log = np.zeros((n_check + 1, layout.N_LOG))
    general_log = fixed(own_variant(scene, LOG), *CORE)
    lean_log = own_variant(scene, LOG)
    orbit.run(general_log, n_check + 1, LOG, log)
    one_g = np.zeros((1, layout.N_LOG))
    one_l = np.zeros((1, layout.N_LOG))
    A, _ = lattice_matrix(scene.lattice)
    agree = 0
    worst = 0.0
    for k in range(n_check):
        a = log[k]
        cell = np.array([a[layout.LOG_CELL_A1], a[layout.LOG_CELL_A2]])
        p = np.array([a[layout.LOG_X], a[layout.LOG_Y]]) - A @ cell
        e = int(a[layout.LOG_ELEMENT])
        twin = _on_own_copy(scene, e, *_disk_offset(scene, e, p))
        start = Orbit(twin, p, (a[layout.LOG_VX], a[layout.LOG_VY]), a[layout.LOG_W])
        one_g[:] = 0.0
        one_l[:] = 0.0
        out_g = start.run(general_log, 1, LOG, one_g, start_element=e)
        out_l = start.run(lean_log, 1, LOG, one_l, start_element=e)
        cols = (layout.LOG_T, layout.LOG_X, layout.LOG_Y, layout.LOG_VX, layout.LOG_VY, layout.LOG_W)
        dev = max(abs(one_l[0, c] - one_g[0, c]) for c in cols) / max(1.0, one_g[0, layout.LOG_T])
        same = (out_l[:2] == out_g[:2] and out_l[10:] == out_g[10:]
                and one_l[0, layout.LOG_ELEMENT] == one_g[0, layout.LOG_ELEMENT])
        agree += same and dev <= 1e-12
        worst = max(worst, dev)
    n_disks = len(scene.elements)
    copies = len(kernel_table(scene).copies)
    rows.append(("several disks per cell", f"{name} ({n_disks} disks, {copies} copies reach a cell), {law}",
                 label(fixed(flags, *CORE)), label(flags), rate_g, rate_l,
                 f"per flight: {agree}/{n_check} agree (max dev {worst:.1e})"))
    print(fmt_row(rows[-1]), flush=True)


SEVERAL_NOTE = ("Several-disks rows (`--only \"several disks per cell\"`, {when}): the lean loop with its copy "
                "loop (core/disks.py `disks_walk`) vs the lattice variant of the general loop on the kernels' "
                "(canonical) form of the scene; start {start}, velocity (0.83, 0.41); per flight: both loops "
                "restarted on the disk just hit from the general loop's state after each of the first 1000 "
                "collisions, same disk, cell, time, position, velocity and spin within 1e-12 (relative to the "
                "flight time when it exceeds 1). Load: {load}.")


def update_section(section, rows, note):
    """Replace the rows of ``section`` in the written table (appending them if new) and its note."""
    with open(OUT, encoding="utf-8") as fh:
        lines = fh.read().rstrip("\n").split("\n")
    lines = [ln for ln in lines if not ln.startswith(f"| {section} |") and not ln.startswith(note[:40])]
    table_end = max(i for i, ln in enumerate(lines) if ln.startswith("|"))
    lines[table_end + 1:table_end + 1] = [fmt_row(r) for r in rows]
    lines += ["", note]
    with open(OUT, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")


def all_rows():
    """Every section's rows, in the table's order (each printed as it is measured)."""
    rows = []
    G = GENERAL
    # straight flights, per flag
    for name, base in (("pentagon", PENTAGON), ("Sinai box", SINAI_BOX)):
        for law in ("specular", "no-slip"):
            scene = base.replace(law=law)
            own = own_variant(scene, NONE)
            # what straight flights buy: the same scene through the force code (degree 4 and 3,
            # leading coefficients exactly zero) against its own variant
            compare(rows, "straight flights", name, scene, fixed(own, *CORE)._replace(flight=FORCE),
                    fixed(own, *CORE))
            for slots in (("flight",), ("spin",), ("lattice",), ("mode",), ("lattice", "flight"), CORE):
                compare(rows, "per flag", name, scene, G, fixed(own, *slots))
    # no spin bookkeeping (specular), on top of the other specialisations
    for name, base in (("Sinai box", SINAI_BOX), ("pentagon", PENTAGON)):
        scene = base.replace(law="specular")
        fixed_rest = Variant(lattice=False, mode=NONE, flight=STRAIGHT)
        compare(rows, "no spin bookkeeping", name, scene, fixed_rest, fixed_rest._replace(spin=False))
    # lean recorder: same kernel, full log vs nothing; and general (runtime mode) vs specialised
    for name, scene in (("Sinai box", SINAI_BOX), ("pentagon", PENTAGON.replace(law="specular")),
                        ("Galton board", GALTON)):
        compare(rows, "lean recorder", name, scene, G, G, LOG, NONE)
        compare(rows, "lean recorder", name, scene, own_variant(scene, LOG), own_variant(scene, NONE), LOG, NONE)
    # force
    for name, base in (("circle + gravity", CIRCLE_G), ("Galton board", GALTON)):
        for law in ("no-slip", "specular"):
            scene = base.replace(law=law)
            own = own_variant(scene, NONE)
            for slots in (("flight",), ("lattice",), CORE):
                compare(rows, "force", name, scene, G, fixed(own, *slots))
    # lattice: the cell walk vs explicit copies, and the lean loop of one disk per cell
    for law in ("no-slip", "specular"):
        neighbour_cells(rows, law)
    for law in ("no-slip", "specular"):
        disk_cells(rows, law)
    return rows + several_disk_rows()


def several_disk_rows():
    """The rows of the section "several disks per cell"."""
    rows = []
    for name in SEVERAL_DISKS:
        for law in ("specular", "no-slip"):
            several_disks(rows, name, law)
    return rows


def write_table(machine, rows):
    """Write the whole table to ``OUT``."""
    when = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    with open(OUT, "w", encoding="utf-8") as fh:
        fh.write("# Ablation: what each event-loop specialisation buys\n\n")
        fh.write(f"Command: `python benchmarks/ablation.py` ({when})\n\n{machine}\n\n")
        fh.write(f"Collisions/s of one orbit of {N:,} collisions (best of {REPEAT}, after a compile warm-up); "
                 "baseline and specialised kernel on the same scene and start. 'identical': the 12 kernel outputs "
                 "(counts, stop code, final time, position, velocity, spin, cell) are bitwise equal. "
                 "'general' = `orbit_kernel()`; a flag list = `orbit_kernel(...)` with the other flags None "
                 "(read at run time), each run through `run_orbits(table, ..., flags=...)`; [LOG] = run with "
                 "RECORD_LOG and a log array of every collision. "
                 "Neighbour-cell rows compare the lattice (cell walk) with a plain scene of explicit disk copies: "
                 "rounding differs (positions re-centred per cell), so the check is per flight (explicit scene "
                 "restarted from the lattice state after each of the first 1000 collisions, same disk + cell, "
                 "time, position, velocity, spin within 1e-9); the whole orbits part after a few collisions "
                 "because the billiard is chaotic. One-disk-per-cell rows compare the lean loop "
                 "(core/disks.py: other formulas, so rounding differs) with the lattice variant of the general "
                 "loop, per flight: the lean loop restarted from the general loop's state after each of the first "
                 "1000 collisions, same cell, time, position, velocity and spin within 1e-12.\n\n")
        fh.write(HEADER + "\n")
        for r in rows:
            fh.write(fmt_row(r) + "\n")


def main():
    global N, REPEAT  # --quick: a smaller size for every section
    ap = argparse.ArgumentParser()
    ap.add_argument("--only", choices=["several disks per cell"], help="run one section, replace its rows")
    ap.add_argument("--quick", action="store_true",
                    help=f"orbits of {QUICK_N:,} collisions, timed once; print the rows, write nothing")
    args = ap.parse_args()
    if args.quick:
        N, REPEAT = QUICK_N, 1
    if args.only:
        rows = several_disk_rows()
        if not args.quick:
            when = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
            load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
            update_section(args.only, rows, SEVERAL_NOTE.format(when=when, start="inside the cell", load=load))
            print(f"\nrows of '{args.only}' written to {os.path.relpath(OUT)}")
        return
    machine = machine_line(numpy=True)
    print(machine)
    print(f"collisions/s of one orbit of {N:,} collisions, best of {REPEAT}, after a compile warm-up\n")
    print(HEADER, flush=True)
    rows = all_rows()
    if args.quick:
        print("\n--quick: nothing written")
        return
    write_table(machine, rows)
    print(f"\nwritten to {os.path.relpath(OUT)}")


if __name__ == "__main__":
    main()
