"""Skipping exact zeros gives the same bits as computing them.

Three shortcuts spare a scene arithmetic whose result is known exactly: a
flight without force skips its acceleration terms (``events.advance``), a
plain scene skips the shifts of its unshifted element copies
(``hit_in_cell(..., shifted=False)``), and the slides-off test forms only
``c1`` of the crossing polynomial (``geometry.crossing_slope``) unless it is
zero.  Each is checked against the full computation, bit for bit.
"""
import math

import numpy as np
import pytest

from noslipsim import tables
from noslipsim._engine.table import kernel_table
from noslipsim.core.events import advance, flight_position
from noslipsim.core.free_flight import free_flight
from noslipsim.core.geometry import crossing_coefficients, crossing_slope
from noslipsim.core.layout import ARC, CIRCLE, LINE, SEGMENT
from noslipsim.core.search import cell_search
from noslipsim.core.tolerances import EXTENT_TOL


def test_advance_without_force_is_the_flight_with_zero_acceleration():
    rng = np.random.default_rng(20261123)
    times = np.concatenate([[0.0, 5e-324, 1e-300, 1e300], 10.0 ** rng.uniform(-16, 8, 400)])
    for t in times:
        x, y, vx, vy = rng.normal(size=4) * 10.0 ** rng.uniform(-8, 8, 4)
        for ax in (0.0, -0.0):
            hx, hy = flight_position(x, y, vx, vy, ax, ax, t)
            full = (hx, hy, vx + ax * t, vy + ax * t)
            lean = advance(x, y, vx, vy, ax, ax, t, False)
            assert lean == full, (t, x, y, vx, vy)
    # with a force, advance is the full flight
    full = (*flight_position(1.0, 2.0, 0.5, -0.25, 0.0, -1.0, 3.0), 0.5, -3.25)
    assert advance(1.0, 2.0, 0.5, -0.25, 0.0, -1.0, 3.0, True) == full


@pytest.mark.parametrize("kind", [LINE, SEGMENT, CIRCLE, ARC])
def test_crossing_slope_is_c1_of_the_crossing_polynomial(kind):
    rng = np.random.default_rng(kind)
    for _ in range(500):
        p = np.zeros(10)
        p[:2] = rng.normal(size=2) * 10.0 ** rng.uniform(-3, 3)
        if kind in (LINE, SEGMENT):
            ang = rng.uniform(0, 2 * math.pi)
            p[2:4] = math.cos(ang), math.sin(ang)
        else:
            p[2] = 10.0 ** rng.uniform(-3, 3)
            p[3] = rng.choice([-1.0, 1.0])
        x, y, vx, vy, ax, ay = rng.normal(size=6) * 10.0 ** rng.uniform(-6, 6, 6)
        assert crossing_slope(kind, p, x, y, vx, vy) == crossing_coefficients(kind, p, x, y, vx, vy, ax, ay)[1]


@pytest.mark.parametrize("force", [(0.0, 0.0), (0.0, -1.0)])
def test_plain_scene_copies_are_hit_the_same_unshifted(force):
    scene = tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)])
    kinds, params, copies, A = kernel_table(scene).arrays()[:4]
    ax, ay = force
    hit_in_cell = cell_search(free_flight(force != (0.0, 0.0)))
    rng = np.random.default_rng(7)
    hits = 0
    for _ in range(2000):
        x, y = rng.uniform(0.01, 0.99, 2)
        if math.hypot(x - 0.5, y - 0.5) <= 0.3:
            continue
        ang = rng.uniform(0, 2 * math.pi)
        vx, vy = math.cos(ang), math.sin(ang)
        cur = int(rng.integers(-1, len(kinds)))  # sometimes a deflated element (as just after a hit)
        args = (kinds, params, copies, A, 0, 0, (x, y, vx, vy, ax, ay), cur, 0, 0, math.inf,
                EXTENT_TOL * scene.scale, 0.0)
        shifted = hit_in_cell(*args, True)
        unshifted = hit_in_cell(*args, False)
        assert shifted == unshifted
        hits += shifted[1] >= 0
    assert hits > 1000  # the flights do hit the table
