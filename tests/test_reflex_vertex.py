"""Exact and near hits on a reflex vertex of the table (a vertex of a polygonal scatterer).

The table is a square lattice of diamonds (four segments, clockwise, the table outside),
and the same diamond written out as segments inside a box (a plain scene).  Its left vertex
``P = (1/4, 1/2)`` is the end of edge 2 and the start of edge 3: a reflex junction of the
table, which is locally the union of the two edges' table sides.

* An exact hit on ``P`` (a flight crossing both edges' lines outwards at ``P``: both are hit
  at the same time, and the float64 engine takes the one rounding puts first) reflects
  once: the flight after it leaves the other edge's line at ``P``, whose crossing root is
  ``t = 0`` exactly (the reference drops it, ``t <= 0``; the engine deflates it,
  ``core/events.py`` ``hit_in_cell``).  The float64 engine used to keep that root as a hit
  a rounding-sized time later inside the other edge's end band, and the particle reversed.
  Oracle: the 30-digit reference resumed at ``P`` on the edge the engine hit, with the
  engine's outgoing state, predicts the engine's next two collisions.
* A flight passing ``1e-13`` beside ``P`` on either side hits one edge (no tie): the whole
  orbit agrees with :func:`noslipsim.reference.simulate_reference`.
* An exact hit on a convex corner (a box corner) still gets the corner rule: a second,
  zero-time collision on the other wall (``corner = 1``), as in the reference.

Both laws (specular; no-slip with gamma ``1/sqrt 2``), with and without gravity.
"""
import math

import numpy as np
import pytest
from kernel_call import record_buffer, run_kernel

from noslipsim import Scene, Segment, simulate, simulate_many, tables
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout
from noslipsim.reference import resume_reference, simulate_reference

DPS = 30
#: Agreement asked of the float64 engine, relative to the orbit's length and speed scales.
TOL = 1e-12
DISK = 1 / math.sqrt(2)
#: (law, gamma, spin): the spins make the no-slip reflection off either edge leave the other's line.
LAWS = [("specular", 0.0, 0.3), ("no-slip", DISK, -0.3)]
LAW_IDS = ["specular", "g0.707"]
GRAVITY = (0.0, -1.0)
P = (0.25, 0.5)
#: Flights meeting ``P`` at ``t = 1/4`` exactly (dyadic), crossing both edges' lines outwards there.
FLIGHTS = {
    "straight": ((0.0, 0.4375), (1.0, 0.25), (0.0, 0.0)),
    "gravity": ((0.0, 0.5), (1.0, 0.125), GRAVITY),
}
T_HIT = 0.25


def diamond(law, gamma, force, lattice, thermostat=None):
    """The diamond of centre (1/2, 1/2) and half-diagonal 1/4: on the unit square lattice, or in a box."""
    c, h = 0.5, 0.25
    pts = [(c, c + h), (c + h, c), (c, c - h), (c - h, c)]
    segs = tuple(Segment(pts[i], pts[(i + 1) % 4], "left") for i in range(4))
    if lattice:
        return Scene(segs, law=law, gamma=gamma, force=force, thermostat=thermostat,
                     lattice={"a1": [1.0, 0.0], "a2": [0.0, 1.0]})
    box = tables.polygon([(-0.5, -0.5), (1.5, -0.5), (1.5, 1.5), (-0.5, 1.5)]).elements
    return Scene(segs + box, law=law, gamma=gamma, force=force, thermostat=thermostat)


def scales(scene, ds):
    """``(length, speed)`` of an orbit: ``max(scale, |x|, |y|)`` and ``max |(v, w)|``."""
    length = max(scene.scale, float(np.abs(ds.x.values).max()), float(np.abs(ds.y.values).max()))
    speed = float(np.sqrt(ds.vx.values ** 2 + ds.vy.values ** 2 + ds.spin.values ** 2).max())
    return length, speed


def assert_collisions_agree(ref, flt, scene, t0=0.0, what=""):
    """Same elements and corner flags, and times, positions, velocities and spins within ``TOL``.

    ``flt`` holds the float64 collisions matching ``ref``'s, whose times count from ``t0``.
    """
    np.testing.assert_array_equal(flt.element.values, ref.element.values, err_msg=what)
    np.testing.assert_array_equal(flt.corner.values, ref.corner.values, err_msg=what)
    length, speed = scales(scene, ref)
    t_ref = ref.t.values + t0
    assert np.abs(flt.t.values - t_ref).max() <= TOL * max(1.0, float(np.abs(t_ref).max())), what
    for var, scale in (("x", length), ("y", length), ("vx", speed), ("vy", speed), ("spin", speed)):
        assert np.abs(flt[var].values - ref[var].values).max() <= TOL * scale, f"{what}: {var}"


@pytest.mark.parametrize("law, gamma, spin", LAWS, ids=LAW_IDS)
@pytest.mark.parametrize("flight", list(FLIGHTS))
@pytest.mark.parametrize("lattice", [True, False], ids=["lattice", "plain"])
def test_float_engine_reflects_once_at_a_reflex_vertex(lattice, flight, law, gamma, spin):
    """One reflection at ``P``, then the flight the reference continues from there (no zero-length flight)."""
    q, v, force = FLIGHTS[flight]
    scene = diamond(law, gamma, force, lattice)
    flt = simulate(scene, q, v, spin, max_collisions=3)
    e0 = int(flt.element[0])
    assert e0 in (2, 3) and int(flt.corner[0]) == 0
    assert abs(float(flt.t[0]) - T_HIT) <= 1e-15
    assert math.hypot(float(flt.x[0]) - P[0], float(flt.y[0]) - P[1]) <= 1e-15
    assert float(flt.t[1]) - float(flt.t[0]) > 0.1, "a second collision at the vertex itself"
    ref = resume_reference(scene, P, (float(flt.vx[0]), float(flt.vy[0])), float(flt.spin[0]), e0,
                           max_collisions=2, dps=DPS)
    assert ref.sizes["collision"] == 2
    assert_collisions_agree(ref, flt.isel(collision=slice(1, 3)), scene, float(flt.t[0]),
                            f"after the vertex hit on edge {e0}")


#: Flights from ``P`` on edge 3 into its table side, leaving edge 2's line (whose float distance
#: at ``P`` rounds to +3e-16: the table side): (force, thermostat).
FROM_P = {"straight": ((0.0, 0.0), None), "gravity": ((0.3, -0.5), None),
          "thermostat": ((0.3, -0.5), "isokinetic")}


@pytest.mark.parametrize("kind", list(FROM_P))
@pytest.mark.parametrize("lattice", [True, False], ids=["lattice", "plain"])
def test_a_flight_from_a_reflex_vertex_is_not_hit_by_the_other_piece(lattice, kind):
    """A boundary start on edge 3 at ``P``: edge 2's root ``t = 0`` is no collision (thermostat included).

    The engine's next two collisions are the reference's from the same state
    (``thermo_events.hit_in_cell`` has the same rule as ``events.hit_in_cell``).
    """
    force, thermostat = FROM_P[kind]
    scene = diamond("specular", 0.0, force, lattice, thermostat)
    v = (0.3, 1.0)
    flt = simulate_many(scene, [P], [v], [0.0], start_elements=[3], record="log", max_collisions=2,
                        scheduler="sync").isel(orbit=0)
    ref = resume_reference(scene, P, v, 0.0, 3, max_collisions=2, dps=DPS)
    assert float(flt.t[0]) > 0.1, "edge 2 hit at the start"
    assert_collisions_agree(ref, flt, scene, what=f"from P on edge 3 ({kind})")


def test_reference_reflects_once_at_a_reflex_vertex_under_gravity():
    """The reference itself at the exact vertex under gravity: one reflection (edge 2, the lower index)."""
    q, v, force = FLIGHTS["gravity"]
    ref = simulate_reference(diamond("specular", 0.0, force, True), q, v, 0.3, max_collisions=2, dps=DPS)
    assert ref.element.values.tolist()[0] == 2 and ref.corner.values.tolist() == [0, 0]
    assert float(ref.t[0]) == T_HIT and float(ref.t[1]) - T_HIT > 0.1


@pytest.mark.parametrize("side", [1.0, -1.0], ids=["above", "below"])
@pytest.mark.parametrize("law, gamma, spin", LAWS, ids=LAW_IDS)
@pytest.mark.parametrize("flight", list(FLIGHTS))
@pytest.mark.parametrize("lattice", [True, False], ids=["lattice", "plain"])
def test_near_a_reflex_vertex_both_pieces_agree_with_the_reference(lattice, flight, law, gamma, spin, side):
    """A flight ``1e-13`` above ``P`` hits edge 3, one below hits edge 2; the orbits agree with the reference."""
    (x0, y0), v, force = FLIGHTS[flight]
    q = (x0, y0 + side * 1e-13)
    scene = diamond(law, gamma, force, lattice)
    ref = simulate_reference(scene, q, v, spin, max_collisions=3, dps=DPS)
    flt = simulate(scene, q, v, spin, max_collisions=3)
    assert int(ref.element[0]) == (3 if side > 0 else 2)
    assert flt.attrs["stop_reason"] == ref.attrs["stop_reason"]
    assert_collisions_agree(ref, flt, scene, what=f"1e-13 {'above' if side > 0 else 'below'} the vertex")


@pytest.mark.parametrize("law, gamma, spin", LAWS, ids=LAW_IDS)
@pytest.mark.parametrize("force", [(0.0, 0.0), GRAVITY], ids=["straight", "gravity"])
def test_exact_hit_on_a_convex_corner_keeps_the_corner_rule(force, law, gamma, spin):
    """The box corner (1, 1) met exactly: a hit, then a corner collision at the same time, as the reference."""
    scene = tables.rectangle(1.0, 1.0, law=law, gamma=gamma, force=force)
    v = (1.0, 1.25) if force != (0.0, 0.0) else (1.0, 1.0)  # both reach (1, 1) at t = 1/2
    ref = simulate_reference(scene, (0.5, 0.5), v, spin, max_collisions=3, dps=DPS)
    flt = simulate(scene, (0.5, 0.5), v, spin, max_collisions=3)
    assert ref.corner.values.tolist()[:2] == [0, 1] and float(ref.t[1]) == float(ref.t[0]) == 0.5
    assert_collisions_agree(ref, flt, scene, what="convex corner")


def tilted_diamond(angle):
    """The diamond turned by ``angle`` about its centre, in the box: vertices with irrational coordinates.

    Returns the scene and the vertices; vertex 3 is the end of edge 2 and the start of edge 3.
    """
    c, s = math.cos(angle), math.sin(angle)
    pts = [(0.5 - 0.25 * s, 0.5 + 0.25 * c), (0.5 + 0.25 * c, 0.5 + 0.25 * s),
           (0.5 + 0.25 * s, 0.5 - 0.25 * c), (0.5 - 0.25 * c, 0.5 - 0.25 * s)]
    segs = tuple(Segment(pts[i], pts[(i + 1) % 4], "left") for i in range(4))
    box = tables.polygon([(-0.5, -0.5), (1.5, -0.5), (1.5, 1.5), (-0.5, 1.5)]).elements
    return Scene(segs + box, law="specular", gamma=0.0), pts


#: Turns of the diamond (rad): at 0.1 and 3.43 the 30-digit distance from the vertex to edge 2's
#: line rounds to the table side, so without the rule the reference hit edge 2 at t = 1e-31; at
#: 0.1, 0.285 and 1.21 the float64 distance does, and the engine hit edge 2 at t ~ 1e-16.
ANGLES = [0.1, 0.285, 1.21, 3.43]


@pytest.mark.parametrize("angle", ANGLES)
def test_tilted_reflex_vertex_is_left_once_by_both_engines(angle):
    """From the vertex on edge 3, into edge 3's table side and out of edge 2's line: edge 2 is not hit.

    Vertices with irrational coordinates, so neither engine computes the vertex's distance from
    edge 2's line as an exact zero: the rule (deflate the other piece of a reflex junction at
    its vertex) must not depend on the rounding's sign, in the float64 engine and in the reference.
    """
    scene, pts = tilted_diamond(angle)
    p = pts[3]
    u3 = (pts[0][0] - p[0], pts[0][1] - p[1])  # along edge 3: on edge 2's wall side
    bis = (-(pts[2][0] - p[0]) - u3[0], -(pts[2][1] - p[1]) - u3[1])  # away from the diamond
    v = (u3[0] + 0.3 * bis[0], u3[1] + 0.3 * bis[1])
    ref = resume_reference(scene, p, v, 0.0, 3, max_collisions=2, dps=DPS)
    assert float(ref.t[0]) > 0.1, "the reference hit edge 2 at the start"
    flt = simulate_many(scene, [p], [v], [0.0], start_elements=[3], record="log", max_collisions=2,
                        scheduler="sync").isel(orbit=0)
    assert float(flt.t[0]) > 0.1, "the float64 engine hit edge 2 at the start"
    assert_collisions_agree(ref, flt, scene, what=f"tilted by {angle}")


@pytest.mark.parametrize("flight", list(FLIGHTS))
@pytest.mark.parametrize("lattice", [True, False], ids=["lattice", "plain"])
def test_the_open_ends_slot_compiles_the_rule_in(lattice, flight):
    """A table with a reflex junction has the variant slot ``open_ends`` (the rule compiled in); a closed convex
    table has not.  Compiled out on the diamond, the rule's absence shows: the exact hit on ``P`` is followed
    by a second one a rounding-sized time later (the double hit the rule exists to prevent)."""
    q, v, force = FLIGHTS[flight]
    table = kernel_table(diamond("specular", 0.0, force, lattice))
    own = table.variant(layout.RECORD_LOG)
    assert table.open_ends and own.open_ends is True
    assert not kernel_table(tables.regular_polygon(5)).variant(layout.RECORD_LOG).open_ends
    gaps = {}
    for rule in (True, False):
        rec = record_buffer(layout.RECORD_LOG, 3)
        run_kernel(table, own._replace(open_ends=rule), q, v, 0.0, 3, layout.RECORD_LOG, rec=rec)
        gaps[rule] = rec[1, layout.LOG_T] - rec[0, layout.LOG_T]
    assert gaps[True] > 0.1
    assert gaps[False] < 1e-12
