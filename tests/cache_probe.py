"""Run named kernel variants through the public API and print their results as JSON (a subprocess of the tests).

    python tests/cache_probe.py VARIANT [VARIANT ...]

Each VARIANT is ``table:law:record:scheduler`` (see ``CASES``); the results
are printed as ``{variant: [numbers]}`` with every float written exactly
(``float.hex``), so two processes' results compare bit for bit.  The numba
cache is whatever ``NUMBA_CACHE_DIR`` says: tests/test_compile_cache.py runs
this script in separate processes over one fresh cache.
"""
import json
import sys

import numpy as np

import noslipsim as ns
from noslipsim import tables

DISK = {"type": "circle", "center": [0, 0], "radius": 1, "side": "inside"}


def _scene(table, law):
    if table == "disk":  # the demonstration: a disk container without force
        return ns.Scene.from_dict({"law": law, "force": [0, 0], "elements": [DISK]}), (0.05, 0.02)
    if table == "disk+force":  # ... and with gravity
        return ns.Scene.from_dict({"law": law, "force": [0, -1], "elements": [DISK]}), (0.05, 0.02)
    if table == "torus":  # a lattice of disks: the lean loop
        return tables.sinai_torus(0.25, law=law), (0.4, 0.1)
    if table == "galton":  # a lattice under gravity: the general loop's cell walk
        return tables.galton_board(2.0, 0.5, law=law), (1.0, 0.0)
    if table == "wedge":  # two infinite walls: the long-wall check
        return tables.wedge(0.6, law=law, force=(0.0, -1.0)), (0.0, 1.0)
    raise ValueError(f"unknown table {table!r}")


def run(case):
    table, law, record, scheduler = case.split(":")
    scene, start = _scene(table, law)
    if record == "orbit":  # simulate(): one orbit, full log
        ds = ns.simulate(scene, start, (0.6, 0.8), 0.3, max_collisions=40)
        values = np.concatenate([ds.t.values, ds.x.values, ds.vx.values, ds.spin.values, [ds.t_final.item()]])
    else:
        ds = ns.simulate_many(scene, [start, (start[0] + 0.01, start[1])], [(0.6, 0.8), (0.8, 0.6)], [0.3, -0.2],
                              max_collisions=40, record=record, scheduler=scheduler, progress=False)
        values = np.concatenate([ds[v].values.ravel() for v in sorted(ds.data_vars)])
    return [float(v).hex() for v in values.astype(float)]


if __name__ == "__main__":
    print(json.dumps({case: run(case) for case in sys.argv[1:]}))
