"""A thermostatted circle search that runs out of steps stops the orbit by name, never silently.

``thermo_events.round_hit`` advances by conservative steps; after ``MAX_STEPS`` (100,000; never
reached by a real flight in the tests and benchmarks) it used to return ``inf``, "no hit", and
the orbit flew on through the circle.  Now each layer says that it gave up: ``round_hit`` and
``element_hit`` return ``GAVE_UP``, ``hit_in_cell`` the element ``SEARCH_FAILED``, ``walk_hit`` the
status 3, and the event loop stops with ``search_limit`` (stop code 6).

The limit is a compile-time constant, so the tests run the kernels' Python source
(``py_func``, with the module's globals patched: a step limit of 1, the inner searches as Python)
on a flight that needs several steps to reach a disk.
"""
import json
import math
import os
import subprocess
import sys

import pytest
from python_flight import python_flight

from noslipsim import tables
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout, search, thermo_events, thermo_flight
from noslipsim.core.thermostat import flight
from noslipsim.core.tolerances import EXTENT_TOL, MAX_CELLS_PER_FLIGHT

FIELD = (0.0, -1.0)
START = (-0.45, 0.5, 1.0, 0.0)   # above left of the disk of radius 0.4, flying sideways: the field bends it onto it


def _scene(lattice):
    make = tables.hex_lorentz_cell if lattice else tables.closed_hex_cell
    return make(0.4, force=FIELD).replace(thermostat="isokinetic")


def _disk_search(table, fl, *, py):
    disk = len(table.kinds) - 1
    hit = thermo_events.round_hit
    hit = getattr(hit, "py_func", hit) if py else hit
    return hit(table.kinds[disk], table.params[disk], fl, 0.0, 0.0, 0.0, math.inf, False,
               EXTENT_TOL * table.scale, math.hypot(*FIELD))


@pytest.fixture
def one_step(monkeypatch):
    """The kernels' Python source with a step limit of 1: every layer calls the others as Python.

    Returns the thermostat's event search (:func:`search.event_search`) built over the flight's
    Python source: ``(hit_in_cell, walk_hit)`` as Python functions.
    """
    monkeypatch.setattr(thermo_events, "MAX_STEPS", 1)
    for name in ("round_hit", "element_hit"):
        monkeypatch.setattr(thermo_events, name, getattr(thermo_events, name).py_func)
    monkeypatch.setattr(thermo_flight, "element_hit", thermo_events.element_hit)
    hit_in_cell, walk_hit, _exact = search.event_search(python_flight(thermo_flight), compile=lambda func: func)
    return hit_in_cell, walk_hit


def test_the_search_finds_the_disk_and_its_python_source_agrees():
    """The flight of the tests needs more than one step; compiled and Python source give the same time."""
    table = kernel_table(_scene(False))
    fl = flight(*START, *FIELD)
    t = _disk_search(table, fl, py=False)
    assert 0.0 < t < math.inf
    assert _disk_search(table, fl, py=True) == t


def test_a_search_out_of_steps_says_so_at_every_layer(one_step):
    table = kernel_table(_scene(False))
    fl = flight(*START, *FIELD)
    E = math.hypot(*FIELD)
    tol = EXTENT_TOL * table.scale
    assert _disk_search(table, fl, py=True) == thermo_events.GAVE_UP < 0.0
    disk = len(table.kinds) - 1
    assert thermo_events.element_hit(table.kinds[disk], table.params[disk], fl, 0.0, 0.0, False, 0.0, math.inf,
                                     tol, E) == thermo_events.GAVE_UP
    kinds, params, copies, A, B = table.arrays()[:5]
    hit_in_cell, walk_hit = one_step
    t, e, *_cell = hit_in_cell(kinds, params, copies, A, 0, 0, (fl, E), -1, 0, 0, math.inf, tol, 0.0, False)
    assert (t, e) == (thermo_events.GAVE_UP, thermo_events.SEARCH_FAILED)
    lattice = kernel_table(_scene(True))
    kinds, params, copies, A, B = lattice.arrays()[:5]
    got = walk_hit(kinds, params, copies, A, B, (fl, E), -1, 0, 0, math.inf, tol, MAX_CELLS_PER_FLIGHT)
    assert got[1] == thermo_events.SEARCH_FAILED and got[4] == 3


_LOOP_CHILD = """
import json, math, sys
import numba
import numpy as np
assert numba.config.DISABLE_JIT
sys.path.insert(0, {tests!r})
import test_thermostat_search_limit as t
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout, loop, thermo_events
thermo_events.MAX_STEPS = 1  # the circle search gives up at its first step
table = kernel_table(t._scene(False))
run = loop.orbit_kernel(*table.variant(layout.RECORD_NONE))
x, y, vx, vy = t.START
out = run(*table.arrays(), table.law, table.c, table.s, table.ax, table.ay, table.thermostat, x, y, vx, vy, 0.1,
          10, math.inf, -math.inf, table.scale, layout.RECORD_NONE, np.zeros((0, 0)),
          np.zeros(len(table.kinds), dtype=np.bool_), -1)
print(json.dumps([int(out[0]), int(out[1]), [float(v) for v in out[5:9]]]))
"""


def test_the_event_loop_stops_with_search_limit():
    """The event loop as Python (``NUMBA_DISABLE_JIT=1``) with a circle search that gives up at its first step:
    stop code 6 where the orbit stands, no collision."""
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    code = _LOOP_CHILD.format(tests=os.path.dirname(os.path.abspath(__file__)))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    n, stop, state = json.loads(out.stdout.strip().splitlines()[-1])
    assert (n, stop) == (0, layout.STOP_SEARCH_LIMIT)
    assert layout.STOP_REASONS[stop] == "search_limit"
    assert tuple(state) == START     # the state where the search gave up, not one flown past a hit
