"""Hits far along a long wall are as exact as hits near its start (issue 13, item 3).

A segment's crossing value ``(q - p0) . n`` measured from its start ``p0`` with the
rounded unit normal carried ``eps |q - p0|``: a hit 1e6 along a wall was off by about
1e-10 in distance, so the flight time by up to 1e-10 relative and, under a force, the
impact velocity by about as much.  Where that form cancels, the hit on the element hit is
now redone with the distance formed from the segment's own end points in compensated
arithmetic (:func:`noslipsim.core.events.exact_line_hit`).

The table is a parallelogram of width 1 whose long sides (length 1e6) are tilted by
0.3 rad, so neither component of their normals is zero; it is placed with the bottom
side starting at the origin, or with the origin at the middle of the long sides (so a
hit there is 5e5 from both ends while its coordinates are small).  Without force the
particle bounces between the long sides; with a force pressing it onto the bottom side
it hops along that one.  Each collision is checked one step at a time against the
50-digit reference restarted from the float state, so nothing accumulates.

What remains is the rounding of the state itself: a point at ``|q|`` is stored to half
an ulp per coordinate, so the relocated point lies off a tilted wall by up to
``eps |q|``, and the next flight (to another wall) starts that far off: its time moves by
``eps |q| / |v_n|``.  The bound per collision is therefore ``STEP_TOL`` plus, for a
flight from one wall to another, ``REPR_ULPS eps |q| / (l sin(incidence))`` (``l`` its
length, ``q`` its start).
"""
import math

import numpy as np
import pytest

from noslipsim import simulate, tables
from noslipsim._engine.table import kernel_table
from noslipsim.reference import resume_reference, simulate_reference

EPS = float(np.finfo(float).eps)
LENGTH = 1e6
TILT = 0.3
U = np.array([math.cos(TILT), math.sin(TILT)])
N = np.array([-math.sin(TILT), math.cos(TILT)])
#: Where the origin sits along the long sides: at the bottom side's start, or at the middle.
PLACEMENTS = {"from_p0": 0.0, "centred": LENGTH / 2}
#: Along-wall starts (distance from the bottom side's start): both ends, 1e3 from them, the middle.
STARTS = (0.5, 1e3, LENGTH / 2, LENGTH - 1e3, LENGTH - 0.5)
FORCES = {"none": (0.0, 0.0), "onto_wall": tuple(-0.5 * N + 0.01 * U)}
#: Per collision, relative to the flight time and to the speed: measured <= 1.4e-15 where the
#: state's own rounding does not enter (before: up to 6e-10 time, 1.5e-9 velocity).
STEP_TOL = 1e-13
#: The state's rounding: each coordinate of a relocated point is rounded to half an ulp
#: and the projection rounds once more, so it lies off a tilted wall by up to about
#: ``2 eps max(|x|, |y|)`` (measured: errors <= 0.22 of this bound).
REPR_ULPS = 2.0
COLLISIONS = 12


def scene_and_start(placement, law, force, s):
    o = PLACEMENTS[placement] * U
    verts = [tuple(-o), tuple(LENGTH * U - o), tuple(LENGTH * U + N - o), tuple(N - o)]
    scene = tables.polygon(verts, law=law, force=force)
    return scene, verts, tuple(s * U + 0.5 * N - o)


def one_step_errors(placement, law, force, s):
    """Per-collision errors against the reference restarted at each collision, and their bounds."""
    scene, verts, q = scene_and_start(placement, law, force, s)
    v = tuple(0.7 * N + 0.31 * U)
    flt = simulate(scene, q, v, 0.2, max_collisions=COLLISIONS)
    assert flt.sizes["collision"] == COLLISIONS and not flt.corner.values.any()
    rows = []
    for k in range(-1, COLLISIONS - 1):
        if k < 0:
            ref = simulate_reference(scene, q, v, 0.2, max_collisions=1)
            t0, q0 = 0.0, np.array(q)
        else:
            q0 = np.array([float(flt.x[k]), float(flt.y[k])])
            ref = resume_reference(scene, tuple(q0), (float(flt.vx[k]), float(flt.vy[k])),
                                   float(flt.spin[k]), int(flt.element[k]), max_collisions=1)
            t0 = float(flt.t[k])
        e = int(flt.element[k + 1])
        assert int(ref.element[0]) == e
        # the start's rounding off its wall enters only a flight to another wall (the root
        # t = 0 of the wall just hit is removed exactly, and the first start is taken as given)
        relocated = k >= 0 and e != int(flt.element[k])
        t_ref = float(ref.t[0])
        hit = np.array([float(ref.x[0]), float(ref.y[0])])
        v_in = np.array([float(ref.vx_in[0]), float(ref.vy_in[0])])
        p0, p1 = np.array(verts[e]), np.array(verts[(e + 1) % len(verts)])
        tangent = (p1 - p0) / np.hypot(*(p1 - p0))
        sin_inc = abs(v_in[0] * tangent[1] - v_in[1] * tangent[0]) / np.hypot(*v_in)
        flight = float(np.hypot(*(hit - q0)))
        speed = math.sqrt(float(ref.vx[0]) ** 2 + float(ref.vy[0]) ** 2 + float(ref.spin[0]) ** 2)
        rows.append(dict(
            t_err=abs((float(flt.t[k + 1]) - t0) - t_ref) / t_ref,
            v_err=max(abs(float(ref[c][0]) - float(flt[c][k + 1])) for c in ("vx", "vy", "spin")) / speed,
            bound=STEP_TOL + (REPR_ULPS * EPS * float(np.abs(q0).max()) / (flight * sin_inc) if relocated else 0.0),
            force_gain=1.0 + math.hypot(*force) * t_ref / speed,  # dv = a dt under a force
            from_p0=float(np.hypot(*(hit - p0)))))
    return rows


@pytest.mark.parametrize("s", STARTS)
@pytest.mark.parametrize("force", list(FORCES))
@pytest.mark.parametrize("law", ["specular", "no-slip"])
@pytest.mark.parametrize("placement", list(PLACEMENTS))
def test_hits_along_a_long_wall_match_the_reference(placement, law, force, s):
    for k, r in enumerate(one_step_errors(placement, law, FORCES[force], s)):
        what = f"collision {k}: {r}"
        assert r["t_err"] <= r["bound"], what
        assert r["v_err"] <= r["bound"] * r["force_gain"], what


def test_cases_reach_far_along_the_wall_where_the_state_is_exact():
    """The cases do what they claim: hits ~1e6 from p0, and 5e5 from both ends where ``|q| ~ 1``."""
    rows = one_step_errors("from_p0", "specular", FORCES["none"], 0.5)
    assert max(r["from_p0"] for r in rows) > 0.99 * LENGTH  # the top side, seen from its far start
    for force in FORCES.values():
        rows = one_step_errors("centred", "no-slip", force, LENGTH / 2)
        assert min(r["from_p0"] for r in rows) > 0.49 * LENGTH
    assert max(r["bound"] for r in rows) < 1.5 * STEP_TOL  # the state's rounding is negligible here


def test_only_long_walls_are_checked_for_a_cancelled_distance():
    """A compact table's walls skip the long-wall check (its code alone cost the pentagon 2 % and the Galton
    board up to 20 %: such a table runs a loop compiled without it); long ones keep it."""
    from noslipsim.core import layout

    def flags(scene):
        table = kernel_table(scene)
        column = table.params[:, layout.LONG_WALL].tolist()
        # the scene's kernel has the check compiled in exactly when a wall is flagged
        assert table.variant(layout.RECORD_NONE).walls is table.long_walls is any(column)
        return column

    a = 2 * np.pi * np.arange(5) / 5
    assert flags(tables.polygon(np.c_[np.cos(a), np.sin(a)])) == [0.0] * 5
    assert flags(tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)])) == [0.0] * 5
    # the long sides of the 1e6 parallelogram (16x its short sides and more), not the short ones
    assert flags(scene_and_start("from_p0", "specular", FORCES["none"], 0.5)[0]) == [1.0, 0.0, 1.0, 0.0]
    assert flags(tables.channel(1.0)) == [1.0, 1.0]  # a line has no end: always
    # a square whose disk is 16x smaller than its sides makes the sides long
    assert flags(tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 1.0 / 32)]))[:4] == [1.0] * 4


def test_a_loop_compiled_without_the_check_is_off_far_along_the_wall(monkeypatch):
    """The compile-time flag is what keeps these hits exact: the loop without the check (``walls=False``,
    which every compact table runs) misses the bound here by orders of magnitude."""
    from noslipsim._engine.table import KernelTable

    variant = KernelTable.variant
    monkeypatch.setattr(KernelTable, "variant", lambda self, mode: variant(self, mode)._replace(walls=False))
    for law, force in (("specular", "none"), ("no-slip", "onto_wall")):
        rows = one_step_errors("centred", law, FORCES[force], LENGTH / 2)
        worst = max(max(r["t_err"], r["v_err"] / r["force_gain"]) / r["bound"] for r in rows)
        assert worst > 100, (law, force, worst)
