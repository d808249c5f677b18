"""The magnetic flight's cell search (core/magnetic_flight.py through core/search.py): its filters drop no hit.

A copy is skipped before its root is formed when the window's box or the distance the path can fly before
``hi`` (its speed times the window, :func:`magnetic_flight.speed_bound`) cannot reach it, and a segment's
root off its extent before its time is formed.  Each search with ``hi`` equal to the earliest hit must find
that hit, at every speed: flights aimed at the disk's centre along a diagonal sit on the reach test's edge.
"""
import math

import numpy as np
import pytest

from noslipsim import tables
from noslipsim._engine.table import kernel_table
from noslipsim.core import magnetic, magnetic_flight, search

BOX = kernel_table(tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]))
STADIUM = kernel_table(tables.stadium(1.0, 1.0))
TOL = 1e-12


def _hit(table, F, hi):
    """``(t, element)``: the earliest hit in ``(0, hi]`` of the flight ``F`` from a point in free space."""
    hit_in_cell = search.cell_search(magnetic_flight)
    t, e, _, _ = hit_in_cell(table.kinds, table.params, table.copies, table.A, 0, 0, F, -1, 0, 0, hi, TOL, 0.0,
                             False)
    return t, e


def _flights(speed, rng):
    """Flights from the box's free space at ``speed``: random ones, and nearly straight ones aimed at the disk's
    centre along a diagonal (gap = speed x time: the reach test's edge)."""
    out = []
    for _ in range(40):
        x, y = rng.uniform(0.02, 0.98, 2)
        if math.hypot(x - 0.5, y - 0.5) < 0.32:
            continue
        phi = rng.uniform(0.0, 2.0 * math.pi)
        W = speed * rng.choice([0.7, -2.0, 1e-7])
        out.append((x, y, speed * math.cos(phi), speed * math.sin(phi), W))
    for d in (0.1, 0.2, 0.25):  # along the diagonal towards (0.5, 0.5)
        u = speed / math.sqrt(2.0)
        out.append((d, d, u, u, speed * 1e-9))
        out.append((1.0 - d, d, -u, u, -speed * 1e-9))
    return out


@pytest.mark.parametrize("speed", [1e-160, 1e-3, 1.0, 1e150])
def test_a_window_ending_at_the_hit_keeps_it(speed):
    """Without a bound (``hi = inf``) and with ``hi`` the hit's own time the search finds the same hit."""
    rng = np.random.default_rng(5)
    for table, shift in ((BOX, 0.0), (STADIUM, 0.5)):  # the box's flights moved into the stadium's middle
        for x, y, vx, vy, W in _flights(speed, rng):
            F = (x - shift, y - shift, vx, vy, W)
            t, e = _hit(table, F, math.inf)
            if e < 0:
                continue
            assert _hit(table, F, t) == (t, e), F


def test_speed_bound_covers_the_speed_or_gives_no_bound():
    """To rounding of ``|v|`` (the reach tests' margin is 1e-9), or inf where the squares leave the normal range."""
    rng = np.random.default_rng(3)
    for scale in (1e-150, 1e-20, 1.0, 1e20, 1e130):
        for vx, vy in rng.normal(size=(50, 2)) * scale:
            c = magnetic_flight.speed_bound(vx, vy)
            assert c * (1.0 + 1e-9) >= math.hypot(vx, vy)
    assert magnetic_flight.speed_bound(1e-160, 1e-160) == math.inf
    assert magnetic_flight.speed_bound(1e200, 0.0) == math.inf


def test_angle_bounds_bracket_atan2():
    """On a fine grid of directions in the first quadrant, the axes and the diagonal included, with room to spare."""
    phi = np.linspace(0.0, 0.5 * math.pi, 200_001)
    for X, Y, true in zip(np.cos(phi), np.sin(phi), phi):
        lo, hi = magnetic.angle_bounds(X, Y)
        assert lo + 1e-3 < math.atan2(Y, X) < hi - 1e-3, (X, Y, true)
    assert magnetic.angle_bounds(0.0, 2.0)[0] < 0.5 * math.pi < magnetic.angle_bounds(0.0, 2.0)[1]
    assert magnetic.angle_bounds(3.0, 0.0)[0] < 0.0 < magnetic.angle_bounds(3.0, 0.0)[1]


@pytest.mark.parametrize("W", [0.7, -2.0, 1e-7, 3e5])
def test_exit_after_never_drops_a_root_in_time(W):
    """``exit_after`` is false whenever the root's computed time is within ``hi`` (ties included: ``hi = lo + t``),
    and true for most roots at twice ``hi``'s distance: a bound, and a useful one."""
    rng = np.random.default_rng(11)
    late = 0
    n = 20_000
    for _ in range(n):
        num = rng.normal() * 10.0 ** rng.uniform(-6, 3)
        den = abs(rng.normal()) * 10.0 ** rng.uniform(-6, 3) * (rng.uniform() > 0.01)  # den = 0: half a period
        lo = rng.choice([0.0, rng.uniform(0.0, 50.0)])
        t = magnetic.zeta_time(num, den, W)
        if t == math.inf:
            continue
        assert not magnetic.exit_after(num, den, W, lo, lo + t), (num, den, W, lo)
        assert not magnetic.exit_after(num, den, W, lo, math.nextafter(lo + t, math.inf))
        late += magnetic.exit_after(num, den, W, lo, lo + 0.5 * t)
    assert late > n // 4


def test_exit_after_an_underflowed_root_keeps_it():
    """``|W| num`` and ``den`` both zero (a root's terms underflowed): no division by zero, and no root dropped
    that ``zeta_time`` keeps."""
    t = magnetic.zeta_time(1e-300, 0.0, 1e-30)
    assert not magnetic.exit_after(1e-300, 0.0, 1e-30, 0.0, t)
    assert magnetic.angle_bounds(0.0, 0.0) == (-magnetic.ATAN_ERROR, magnetic.ATAN_ERROR)
