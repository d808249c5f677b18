"""Which orbits the far-cell changes move: ~30 orbits of 10^4 collisions, this code against an earlier commit.

The far-cell changes (``core/cells.py``: ``far_hit_in_cell``, ``far_move``, and the exact
re-basing of a far hit in ``core/loop.py``) act only on flights whose hit copy or walked cell
lies ``FAR_CELLS`` (16) or more cells from the flight's start.  Every orbit here is run by
both versions (the old one a copy of the package at ``--before``, imported as
``noslipsim_before``: ``package_copy.py``); the final state and every record are compared bit
for bit, and the farthest any flight of the old orbit gets from its start (in cells, along
its path: a flight under a force may rise 20 rows and fall back) says whether the orbit could
have moved.  An orbit whose flights all stay within 15 cells must be identical; one that moved
is reported with the collision where it first differs and the last far flight before it.

Run: ``PYTHONPATH=src python benchmarks/far_force_bits.py [--before b4489a3] [--collisions 10000]``.
"""
import argparse
import math
import os
import sys

import numpy as np

import noslipsim as new

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from package_copy import package_copy

FAR_CELLS = 16
#: The paper's Galton board (config/config.yaml: spacing 2, pegs 0.89, gravity 1, top row 0, 10 rows)
PAPER_DEPTH = 10 * math.sqrt(3.0)
RECORDS = ("t", "x", "y", "vx", "vy", "spin", "vx_in", "vy_in", "spin_in", "s", "element", "cell_a1", "cell_a2")
FINAL = ("t_final", "x_final", "y_final", "vx_final", "vy_final", "spin_final", "cell_a1_final", "cell_a2_final",
         "n_collisions")


def diamond(p, law, force=(0.0, 0.0)):
    """A square lattice of diamonds on the cell corner (segments: the general loop's straight walk)."""
    c, h = 0.5, 0.25
    pts = [(c, c + h), (c + h, c), (c, c - h), (c - h, c)]
    segs = tuple(p.Segment(pts[i], pts[(i + 1) % 4], "left") for i in range(4))
    return p.Scene(segs, law=law, force=force, lattice={"a1": [1.0, 0.0], "a2": [0.0, 1.0]})


def orbits():
    """(name, scene of a package, start, velocity, spin, simulate options)."""
    out = []
    paper = dict(stop_below=-PAPER_DEPTH, max_time=2000.0)
    for law, g in (("specular", 0.0), ("no-slip", 0.0), ("no-slip", 1 / math.sqrt(2)), ("no-slip", 3.0)):
        for k, (q, v) in enumerate((((0.0, 2.0), (0.5, math.sqrt(3) / 2)), ((0.3, 1.8), (-0.6, 0.8)))):
            out.append((f"galton paper {law} g={g:.3g} #{k}",
                        lambda p, law=law, g=g: p.tables.galton_board(2.0, 0.89, 1.0, law=law, gamma=g, top_row=0),
                        q, v, 0.0, paper))
    for law in ("specular", "no-slip"):
        out += [
            (f"galton unbounded g=1 {law}", lambda p, law=law: p.tables.galton_board(2.0, 0.5, 1.0, law=law),
             (1.0, 0.0), (0.6, 0.8), 0.1, {}),
            (f"galton unbounded weak g=1e-3 {law}", lambda p, law=law: p.tables.galton_board(2.0, 0.5, 1e-3, law=law),
             (1.0, 0.0), (0.6, 0.8), 0.1, {}),
            (f"galton unbounded weak g=1e-3 {law} #2",
             lambda p, law=law: p.tables.galton_board(2.0, 0.3, 1e-3, law=law), (1.0, 0.0), (0.99, 0.141), 0.1, {}),
            (f"torus r=0.25 {law}", lambda p, law=law: p.tables.sinai_torus(0.25, law=law), (0.45, 0.1), (0.6, 0.8),
             0.1, {}),
            (f"torus r=0.1 {law}", lambda p, law=law: p.tables.sinai_torus(0.1, law=law), (0.45, 0.1), (0.6, 0.8),
             0.1, {}),
            (f"torus r=0.25 force (0.3,-1) {law}",
             lambda p, law=law: p.tables.sinai_torus(0.25, law=law, force=(0.3, -1.0)), (0.45, 0.1), (0.6, 0.8),
             0.1, {}),
            (f"torus r=0.1 force 1e-4 {law}",
             lambda p, law=law: p.tables.sinai_torus(0.1, law=law, force=(1e-4, 0.0)), (0.45, 0.1), (0.6, 0.8),
             0.1, {}),
            (f"hex r=0.3 {law}", lambda p, law=law: p.tables.hex_lorentz_cell(0.3, law=law), (0.0, 0.35),
             (0.6, 0.8), 0.1, {}),
            (f"hex r=0.3 force 1e-3 {law}",
             lambda p, law=law: p.tables.hex_lorentz_cell(0.3, law=law, force=(1e-3, 0.0)), (0.0, 0.35),
             (0.6, 0.8), 0.1, {}),
            (f"hex r=0.45 force (0,-1) {law}",
             lambda p, law=law: p.tables.hex_lorentz_cell(0.45, law=law, force=(0.0, -1.0)), (0.0, 0.49),
             (0.6, 0.8), 0.1, {}),
            (f"diamonds {law}", lambda p, law=law: diamond(p, law), (0.1, 0.1), (0.7, 0.31), 0.1, {}),
            (f"diamonds force (0.05,-1) {law}", lambda p, law=law: diamond(p, law, (0.05, -1.0)), (0.1, 0.1),
             (0.7, 0.31), 0.1, {}),
        ]
    return out


def excursions(scene, ds, q, v):
    """Per flight, the most lattice cells (in either lattice coordinate) it gets from its start.

    From the recorded states: each flight starts at the previous collision (the first at
    ``q, v``) with the velocity after it, under the scene's force, for the time to the next
    collision; its extent is the largest ``|B (v tau + a tau^2 / 2)|`` over the flight (ends and
    turning points), ``B`` the inverse of the lattice basis.  A flight that rises 20 rows and falls
    back to its start walks far cells though its hit is near.
    """
    A = np.array([scene.lattice["a1"], scene.lattice["a2"]], dtype=float).T
    B = np.linalg.inv(A)
    t = np.r_[0.0, ds.t.values]
    dt = np.diff(t)
    vx = np.r_[v[0], ds.vx.values[:-1]]
    vy = np.r_[v[1], ds.vy.values[:-1]]
    ax, ay = scene.force
    out = np.zeros(len(dt))
    for row in B:
        u1 = row[0] * vx + row[1] * vy  # rate of the lattice coordinate
        u2 = 0.5 * (row[0] * ax + row[1] * ay)
        taus = [dt]
        if u2 != 0.0:
            taus.append(np.clip(-u1 / (2 * u2), 0.0, dt))
        for tau in taus:
            out = np.maximum(out, np.abs(u1 * tau + u2 * tau * tau))
    return out


def first_difference(a, b):
    """The first collision whose record differs (bitwise, NaN equal to NaN) and the first field
    differing there, or None."""
    m = min(a.sizes["collision"], b.sizes["collision"])
    first = None
    for name in RECORDS:
        x, y = a[name].values[:m], b[name].values[:m]
        same = (x == y) | (np.isnan(x) & np.isnan(y)) if x.dtype.kind == "f" else x == y
        if not same.all() and (first is None or int(np.argmin(same)) < first[0]):
            first = int(np.argmin(same)), name
    if first is None and a.sizes["collision"] != b.sizes["collision"]:
        return m, "collision count"
    return first


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--before", default="b4489a3", help="commit of the old code")
    ap.add_argument("--collisions", type=int, default=10_000)
    ap.add_argument("--where", default="/tmp/far_force_bits", help="folder for the old package's copy")
    args = ap.parse_args()
    package_copy(args.before, "noslipsim_before", args.where)
    import noslipsim_before as old
    print(f"old: {old.__file__} ({args.before})\nnew: {new.__file__}\n{args.collisions} collisions per orbit")
    print(f"{'orbit':<44}{'n':>7}{'farthest (cells)':>16}  result")
    moved = 0
    for name, make, q, v, w, kw in orbits():
        scene = make(old)
        a = old.simulate(scene, q, v, w, max_collisions=args.collisions, **kw)
        b = new.simulate(make(new), q, v, w, max_collisions=args.collisions, **kw)
        ext = excursions(scene, a, q, v)
        far = float(ext.max(initial=0.0))
        diff = first_difference(a, b)
        final_same = all(np.array_equal(a[k].values, b[k].values) for k in FINAL)
        if diff is None and final_same:
            result = "identical"
        else:
            moved += 1
            k, what = diff if diff is not None else (a.sizes["collision"], "final state")
            before = np.flatnonzero(ext[:k + 1] >= FAR_CELLS - 1)
            last = (f"last flight reaching {FAR_CELLS - 1}+ cells: to collision {before[-1]} "
                    f"({ext[before[-1]]:.0f} cells)") if len(before) else "no flight before it reached 15 cells"
            result = f"MOVED at collision {k} ({what}); {last}"
        flag = "" if far >= FAR_CELLS - 1 or result == "identical" else "  <-- no far flight, yet moved"
        print(f"{name:<44}{int(a.n_collisions):>7}{far:>16.1f}  {result}{flag}", flush=True)
    print(f"{moved} orbits moved")


if __name__ == "__main__":
    main()
