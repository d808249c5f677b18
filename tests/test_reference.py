"""The float64 engine against its high-precision twin :mod:`noslipsim.reference`.

(a) The reference alone reproduces the half-plane theorem (docs/conventions.md) at 1e-40.
(b) ``simulate`` agrees with ``simulate_reference`` to 1e-9 (relative to the orbit's length
    and speed scales), with identical element indices, corner flags and stop reasons, over
    the first collisions of every table family, both laws and gamma in {0, 1/sqrt 2, 1, 3, 100}.
    ``N`` is chosen per scene so that chaos cannot amplify rounding (1e-16) past about 1e-11.
(c) Long orbits: a full comparison of 300 collisions where the table is not chaotic, and on
    every family a one-step (shadowing) comparison: the reference restarted from each float64
    post-collision state must predict the next float64 collision, so no collision is missed
    and none is invented, whatever chaos does to the orbit as a whole.
"""
import json
import math

import mpmath
import numpy as np
import pytest
from shadowing import one_step_references

from noslipsim import Arc, Circle, Line, Scene, Segment, simulate, tables
from noslipsim.reference import ReferenceOrbit, resume_reference, simulate_reference

RTOL = 1e-9
DISK = 1 / math.sqrt(2)
LAWS = [("specular", 0.0), ("no-slip", 0.0), ("no-slip", DISK), ("no-slip", 1.0),
        ("no-slip", 3.0), ("no-slip", 100.0)]
LAW_IDS = ["specular", "g0", "g0.707", "g1", "g3", "g100"]

POSITIONS = ("x", "y", "s")
SPEEDS = ("vx", "vy", "spin", "vx_in", "vy_in", "spin_in")


# ----------------------------------------------------------------------------- tables
def ramp(alpha=0.3, force=(0.0, -1.0)):
    """The half plane above the line y = x tan(alpha) (a ramp rising to the right)."""
    return Scene((Line((0.0, 0.0), (-math.sin(alpha), math.cos(alpha))),), force=force)


def bowl():
    """Lower half disk (an arc) closed by a lid segment, under gravity."""
    return Scene((Arc((0.0, 0.0), 1.0, math.pi, 2 * math.pi, "inside"),
                  Segment((1.0, 0.0), (-1.0, 0.0), "left")), force=(0.0, -1.0))


def dome_box():
    """A box whose floor carries a half-disk dome (an arc scatterer), under gravity."""
    return Scene((Segment((-2.0, 0.0), (-0.5, 0.0)), Arc((0.0, 0.0), 0.5, 0.0, math.pi, "outside"),
                  Segment((0.5, 0.0), (2.0, 0.0)), Segment((2.0, 0.0), (2.0, 3.0)),
                  Segment((2.0, 3.0), (-2.0, 3.0)), Segment((-2.0, 3.0), (-2.0, 0.0))),
                 force=(0.0, -1.0))


def galton(rows=4, width=3):
    """Pegs of radius 0.5 on the lattice a1 = (2, 0), a2 = (1, sqrt 3) between walls x = +-(width + 1)."""
    pegs = []
    for j in range(rows):
        for i in range(-width, width + 1):
            cx = 2.0 * i + (1.0 if j % 2 else 0.0)
            if abs(cx) < width + 0.5:
                pegs.append(Circle((cx, -math.sqrt(3.0) * j), 0.5, "outside"))
    walls = [Line((-(width + 1.0), 0.0), (1.0, 0.0)), Line((width + 1.0, 0.0), (-1.0, 0.0))]
    return Scene(tuple(walls + pegs), force=(0.0, -1.0))


L_SHAPE = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
IRREGULAR = [(0.0, 0.0), (2.0, 0.1), (2.3, 1.2), (1.1, 2.0), (-0.3, 1.1)]
GRAVITY = (0.0, -1.0)


def _toward(start, target, offset, speed=1.0):
    """Velocity from ``start`` aimed at ``target`` moved by ``offset`` across the line of sight."""
    d = np.subtract(target, start)
    d /= np.linalg.norm(d)
    aim = np.asarray(target) + offset * np.array([-d[1], d[0]])
    v = aim - np.asarray(start)
    return tuple(speed * v / np.linalg.norm(v))


_pent = tables.regular_polygon(5)
_pent_vertex = _pent.elements[2].p0  # vertex between edges 1 and 2
_circle_box = tables.rectangle(4.0, 2.0, disks=[(2.0, 1.0, 0.5)])

# name: (scene, position, velocity, spin, collisions compared, extra simulate kwargs)
CASES = {
    "half_plane": (tables.half_plane(), (0.0, 1.0), (0.3, 0.2), 0.4, 30, {}),
    "half_plane_g9.81": (tables.half_plane(gravity=9.81), (0.5, 2.0), (-1.3, 0.0), -0.7, 30, {}),
    "ramp": (ramp(), (0.0, 1.0), (0.2, 0.0), 0.3, 30, {}),
    "ramp_side_force": (ramp(0.5, (0.3, -1.0)), (0.0, 1.0), (-0.2, 0.5), 0.0, 30, {}),
    "wedge_up_0.5": (tables.wedge(0.5, force=GRAVITY), (0.1, 1.0), (0.3, 0.1), 0.2, 40, {}),
    "wedge_up_1.2": (tables.wedge(1.2, force=GRAVITY), (0.1, 1.0), (0.7, 0.4), -0.3, 22, {}),
    "wedge_down": (tables.wedge(0.6, opening="down", force=GRAVITY), (0.0, -1.0), (0.4, 2.0), 0.3,
                   40, {}),
    "triangle": (tables.regular_polygon(3), (0.05, -0.1), (1.0, 0.37), 0.2, 40, {}),
    "square_g": (tables.regular_polygon(4, force=GRAVITY), (0.1, 0.05), (1.0, 0.37), 0.2, 14, {}),
    "pentagon": (tables.regular_polygon(5), (0.0, 0.0), (0.3, 0.2), 0.1, 40, {}),
    "pentagon_g": (tables.regular_polygon(5, force=GRAVITY), (0.0, 0.0), (0.3, 0.2), 0.1, 20, {}),
    "hexagon": (tables.regular_polygon(6), (0.1, 0.2), (-0.4, 1.0), 0.5, 40, {}),
    "irregular": (tables.polygon(IRREGULAR), (1.0, 1.0), (1.0, 0.37), 0.2, 40, {}),
    "irregular_g": (tables.polygon(IRREGULAR, force=GRAVITY), (1.0, 1.0), (1.0, 0.37), 0.2, 25, {}),
    "L_shape": (tables.polygon(L_SHAPE), (0.5, 0.5), (1.0, 0.37), 0.2, 40, {}),
    "L_shape_g": (tables.polygon(L_SHAPE, force=GRAVITY), (0.5, 1.5), (0.8, 0.3), 0.2, 30, {}),
    "near_vertex_square_in": (tables.regular_polygon(4, circumradius=math.sqrt(2)), (0.1, -0.2),
                              _toward((0.1, -0.2), (1.0, 1.0), 1e-9), 0.3, 12, {}),
    "near_vertex_square_out": (tables.regular_polygon(4, circumradius=math.sqrt(2)), (0.1, -0.2),
                               _toward((0.1, -0.2), (1.0, 1.0), -1e-9), 0.3, 12, {}),
    "near_vertex_pentagon_in": (_pent, (0.1, 0.0), _toward((0.1, 0.0), _pent_vertex, 1e-9), 0.3, 12, {}),
    "near_vertex_pentagon_out": (_pent, (0.1, 0.0), _toward((0.1, 0.0), _pent_vertex, -1e-9), 0.3,
                                 12, {}),
    "near_vertex_L_reflex": (tables.polygon(L_SHAPE), (0.5, 0.2), _toward((0.5, 0.2), (1.0, 1.0), 1e-9),
                             0.3, 12, {}),
    "exact_corner_square": (tables.rectangle(1.0, 1.0), (0.5, 0.5), (1.0, 1.0), 0.3, 12, {}),
    "grazing_disk": (_circle_box, (0.3, 1.0 + 0.5 * (1 - 1e-8)), (1.0, 0.0), 0.1, 12, {}),
    "grazing_ceiling": (tables.channel(1.0, force=GRAVITY), (0.0, 0.5), (1.0, math.sqrt(1.0 + 2e-9)),
                        0.2, 12, {}),
    "grazing_peg": (Scene((Line((0.0, -2.0), (0.0, 1.0)), Circle((1.0, 0.0), 0.5, "outside")),
                          force=GRAVITY),
                    (0.0, 0.0), (1.0, math.sqrt(2 * (0.5 - 1e-9))), 0.2, 10, {}),
    "circle_g": (Scene((Circle((0.0, 0.0), 1.0, "inside"),), force=GRAVITY), (0.1, 0.2), (1.0, 0.37),
                 0.2, 14, {}),
    "bowl": (bowl(), (0.1, -0.2), (1.0, 0.37), 0.2, 14, {}),
    "dome_box": (dome_box(), (-1.0, 1.5), (1.0, -0.3), 0.2, 14, {}),
    "lemon": (tables.lemon(1.0, 1.0), (0.0, 0.1), (0.3, 1.0), 0.2, 20, {}),
    "stadium": (tables.stadium(), (0.1, 0.2), (1.0, 0.37), 0.2, 16, {}),
    "stadium_g": (tables.stadium(force=GRAVITY), (0.1, 0.2), (1.0, 0.37), 0.2, 12, {}),
    "two_disks_box": (tables.two_disks(0.5, box=(4.0, 2.0)), (0.0, 0.5), (1.0, 0.37), 0.2, 10, {}),
    "galton": (galton(), (-0.6, 1.5), (0.05, 0.0), 0.0, 7, dict(stop_below=-9.0)),
    "max_time": (tables.regular_polygon(6, force=GRAVITY), (0.1, 0.2), (-0.4, 1.0), 0.5, 40,
                 dict(max_time=7.25)),
    "stop_below_bowl": (Scene((Arc((0.0, 0.0), 1.0, 1.25 * math.pi, 1.75 * math.pi, "inside"),),
                              force=GRAVITY), (-0.3, 0.0), (0.2, 0.0), 0.1, 20, dict(stop_below=-2.0)),
}


#: Cases compared over fewer collisions for one law.  With gamma = 1 (c = 0, s = 1) the no-slip
#: law only permutes and negates (v_t, w), so from (0.5, 0.5) with velocity (1, 1) the exact orbit
#: returns to a vertex of the unit square after collision 2 (an exact tie between two edges) while
#: the float64 positions are off it by an ulp; which edge comes first then decides an O(1) outcome.
#: Only the first corner is a float64-exact tie.
SHORTER = {("exact_corner_square", "no-slip", 1.0): 3}


def with_law(scene, law, gamma):
    return scene.replace(law=law, gamma=gamma)


# ----------------------------------------------------------------------------- comparison
def assert_orbits_agree(ref, flt, rtol=RTOL, what=""):
    """Same events (elements, corners, stop reason) and values within ``rtol`` of the orbit's scales."""
    assert flt.attrs["stop_reason"] == ref.attrs["stop_reason"], what
    assert flt.sizes["collision"] == ref.sizes["collision"], what
    np.testing.assert_array_equal(flt.element.values, ref.element.values, err_msg=what)
    np.testing.assert_array_equal(flt.corner.values, ref.corner.values, err_msg=what)
    scene = Scene.from_dict(json.loads(ref.attrs["scene"]))
    x, y = np.append(ref.x.values, float(ref.x_final)), np.append(ref.y.values, float(ref.y_final))
    length = max(scene.scale, np.abs(x).max(), np.abs(y).max())
    speeds = np.append(np.sqrt(ref.vx.values ** 2 + ref.vy.values ** 2 + ref.spin.values ** 2),
                       math.sqrt(float(ref.vx_final) ** 2 + float(ref.vy_final) ** 2
                                 + float(ref.spin_final) ** 2))
    speed = speeds.max()
    time = max(1.0, float(ref.t_final))
    energy = max(float(np.abs(ref.energy.values).max(initial=0.0)), speed ** 2, 1.0)
    scales = {**{k: length for k in POSITIONS}, **{k: speed for k in SPEEDS}, "t": time,
              "energy": energy}
    for name, scale in scales.items():
        np.testing.assert_allclose(flt[name].values, ref[name].values, rtol=0, atol=rtol * scale,
                                   err_msg=f"{what} {name}")
    for name in ("t", "x", "y", "vx", "vy", "spin"):
        scale = scales[name]
        assert abs(float(flt[f"{name}_final"]) - float(ref[f"{name}_final"])) <= rtol * scale, \
            f"{what} {name}_final"


def run_both(scene, q, v, w, n, **kw):
    ref = simulate_reference(scene, q, v, w, max_collisions=n, **kw)
    flt = simulate(scene, q, v, w, max_collisions=n, **kw)
    return ref, flt


# ----------------------------------------------------------------------------- (a) half plane
def _mp(x):
    return mpmath.mpf(x)  # exact for floats and for the reference's mpf values


@pytest.mark.parametrize("gamma, g, start, velocity, spin", [
    (DISK, 1.0, (0.0, 1.0), (0.3, 0.2), 0.4),
    (1.0, 9.81, (0.25, 2.0), (-1.3, 0.0), -0.7),
    (3.0, 1.0, (-1.0, 0.5), (0.5, -0.3), 0.1),
    (100.0, 2.0, (0.0, 1.5), (0.2, 1.0), 0.03),
    (0.0, 1.0, (0.0, 1.0), (0.7, 0.1), 5.0),
])
def test_half_plane_drift_per_two_bounces(gamma, g, start, velocity, spin):
    scene = tables.half_plane(gamma=gamma, gravity=g)
    orbit = simulate_reference(scene, start, velocity, spin, max_collisions=12, as_mpf=True)
    assert isinstance(orbit, ReferenceOrbit) and len(orbit) == 12
    with mpmath.workdps(60):
        gm, gg = _mp(gamma), _mp(g)
        u = mpmath.sqrt(_mp(velocity[1]) ** 2 + 2 * gg * _mp(start[1]))  # vertical impact speed
        invariant = _mp(velocity[0]) - gm * _mp(spin)  # v_x - gamma w, the same on every flight
        drift = 4 * u * invariant / (gg * (1 + gm ** 2))
        xs, rec = [_mp(x) for x in orbit.records["x"]], orbit.records
        for k in range(len(orbit)):
            assert abs(_mp(rec["y"][k])) < mpmath.mpf(10) ** -45
            assert abs(_mp(rec["vy"][k]) - u) < mpmath.mpf(10) ** -40
            assert abs(_mp(rec["vx"][k]) - gm * _mp(rec["spin"][k]) - invariant) < mpmath.mpf(10) ** -40
            if k + 2 < len(orbit):
                assert abs(xs[k + 2] - xs[k] - drift) < mpmath.mpf(10) ** -40 * max(1, abs(drift))
                for name in ("vx", "vy", "spin"):  # velocities are 2-periodic
                    assert abs(_mp(rec[name][k + 2]) - _mp(rec[name][k])) < mpmath.mpf(10) ** -40
        if gamma > 0:  # the drift vanishes only on v_x = gamma w
            assert abs(drift) > mpmath.mpf(10) ** -3


@pytest.mark.parametrize("gamma, vx, spin", [(1.0, 0.3, 0.3), (0.5, -0.4, -0.8), (4.0, 2.0, 0.5)])
def test_half_plane_two_periodic_iff_vx_equals_gamma_w(gamma, vx, spin):
    scene = tables.half_plane(gamma=gamma)
    orbit = simulate_reference(scene, (0.2, 1.0), (vx, 0.5), spin, max_collisions=8, as_mpf=True)
    rec = orbit.records
    with mpmath.workdps(60):
        for k in range(len(orbit) - 2):
            for name in ("x", "y", "vx", "vy", "spin"):
                assert abs(_mp(rec[name][k + 2]) - _mp(rec[name][k])) < mpmath.mpf(10) ** -40
        assert abs(_mp(rec["x"][1]) - _mp(rec["x"][0])) > 0.1  # 2-periodic, not a fixed bounce
    # and not 2-periodic once v_x - gamma w is off by 1e-12: the drift is 4u 1e-12/(g(1+gamma^2))
    off = simulate_reference(scene, (0.2, 1.0), (vx + 1e-12, 0.5), spin, max_collisions=4, as_mpf=True)
    with mpmath.workdps(60):
        u = mpmath.sqrt(_mp(0.5) ** 2 + 2)
        expected = 4 * u * (_mp(vx + 1e-12) - _mp(gamma) * _mp(spin)) / (1 + _mp(gamma) ** 2)
        got = _mp(off.records["x"][2]) - _mp(off.records["x"][0])
        assert abs(got - expected) < mpmath.mpf(10) ** -40 and abs(got) > 1e-13


def test_float_engine_half_plane_periodic_orbit_matches():
    scene = tables.half_plane(gamma=1.0)
    ref, flt = run_both(scene, (0.2, 1.0), (0.3, 0.5), 0.3, 200)
    assert_orbits_agree(ref, flt, what="half plane, v_x = gamma w")
    assert np.ptp(flt.x.values[::2]) < 1e-12


# ----------------------------------------------------------------------------- (b) short orbits
@pytest.mark.parametrize("law, gamma", LAWS, ids=LAW_IDS)
@pytest.mark.parametrize("name", list(CASES))
def test_float_engine_agrees_with_reference(name, law, gamma):
    scene, q, v, w, n, kw = CASES[name]
    n = SHORTER.get((name, law, gamma), n)
    ref, flt = run_both(with_law(scene, law, gamma), q, v, w, n, **kw)
    assert_orbits_agree(ref, flt, what=f"{name} {law} gamma={gamma}")


def test_cases_exercise_what_they_claim():
    """The scenes reach the features they are meant to test (guards against silent start changes)."""
    def ref(name, law="no-slip", gamma=DISK):
        scene, q, v, w, n, kw = CASES[name]
        return simulate_reference(with_law(scene, law, gamma), q, v, w, max_collisions=n, **kw)

    assert ref("wedge_down").attrs["stop_reason"] == "escape"
    assert ref("galton", law="specular").attrs["stop_reason"] == "stop_below"
    assert ref("stop_below_bowl").attrs["stop_reason"] == "stop_below"
    assert ref("max_time").attrs["stop_reason"] == "max_time"
    corner = ref("exact_corner_square", law="specular")
    assert corner.corner.sum() >= 2 and set(corner.element.values[:2]) == {1, 2}
    assert ref("near_vertex_square_in").element.values[0] != ref("near_vertex_square_out").element.values[0]
    assert ref("near_vertex_pentagon_in").element.values[0] != \
        ref("near_vertex_pentagon_out").element.values[0]
    for name in ("grazing_disk", "grazing_peg"):
        hits = ref(name)
        assert 1 in hits.element.values  # the near-tangent scatterer is hit
    assert ref("grazing_ceiling").element.values[0] == 1
    assert {0, 1} <= set(ref("dome_box").element.values)
    assert {0, 1} <= set(ref("bowl").element.values)
    assert len(set(ref("galton").element.values)) >= 3 and 0 in ref("galton").element.values


# ----------------------------------------------------------------------------- (c) long orbits
LONG_REGULAR = {  # tables where these orbits are not chaotic: compare the whole orbit
    "half_plane": (tables.half_plane(gamma=DISK), (0.0, 1.0), (0.3, 0.2), 0.4),
    "wedge_up": (tables.wedge(0.5, force=GRAVITY, gamma=DISK), (0.1, 1.0), (0.3, 0.1), 0.2),
    "L_shape_specular": (tables.polygon(L_SHAPE, law="specular"), (0.5, 0.5), (1.0, 0.37), 0.2),
    "hexagon_g3": (tables.regular_polygon(6, gamma=3.0), (0.1, 0.2), (-0.4, 1.0), 0.5),
}


@pytest.mark.parametrize("name", list(LONG_REGULAR))
def test_long_regular_orbit_agrees(name):
    scene, q, v, w = LONG_REGULAR[name]
    ref, flt = run_both(scene, q, v, w, 300)
    assert_orbits_agree(ref, flt, what=name)


LONG_SHADOW = {  # name: (scene, (position, velocity, spin), collision budget, simulate kwargs)
    "pentagon_g": (tables.regular_polygon(5, force=GRAVITY), ((0.0, 0.0), (0.3, 0.2), 0.1), 300, {}),
    "L_shape_g": (tables.polygon(L_SHAPE, force=GRAVITY, gamma=1.0), ((0.5, 1.5), (0.8, 0.3), 0.2),
                  300, {}),
    "irregular_specular": (tables.polygon(IRREGULAR, law="specular"), ((1.0, 1.0), (1.0, 0.37), 0.2),
                           300, {}),
    "wedge_up_specular": (tables.wedge(0.7, force=GRAVITY, law="specular"),
                          ((0.1, 1.0), (0.7, 0.4), 0.0), 300, {}),
    "wedge_down": (tables.wedge(0.3, opening="down", force=GRAVITY, gamma=DISK),
                   ((0.12, -1.0), (1.85, 0.45), -0.07), 300, {}),  # trapped under the vertex
    "stadium": (tables.stadium(gamma=3.0), ((0.1, 0.2), (1.0, 0.37), 0.2), 300, {}),
    "stadium_g": (tables.stadium(force=GRAVITY), ((0.1, 0.2), (1.0, 0.37), 0.2), 120, {}),
    "two_disks_box": (tables.two_disks(0.5, box=(4.0, 2.0), law="specular"),
                      ((0.0, 0.5), (1.0, 0.37), 0.2), 300, {}),
    "circle_g": (Scene((Circle((0.0, 0.0), 1.0, "inside"),), force=GRAVITY, gamma=1.0),
                 ((0.1, 0.2), (1.0, 0.37), 0.2), 150, {}),
    "bowl": (bowl(), ((0.1, -0.2), (1.0, 0.37), 0.2), 100, {}),
    "dome_box": (dome_box(), ((-1.0, 1.5), (1.0, -0.3), 0.2), 80, {}),
    "lemon": (tables.lemon(1.0, 1.0, law="no-slip", gamma=DISK), ((0.0, 0.1), (0.3, 1.0), 0.2), 300, {}),
    "galton": (galton(5), ((0.1, 1.0), (0.05, 0.0), 0.0), 100, dict(stop_below=-10.0)),
}


@pytest.mark.parametrize("name", list(LONG_SHADOW))
def test_long_orbit_one_step_shadowing(name):
    """Restart the reference at every float64 collision: it must predict the next event.

    Chaos cannot amplify anything here: each restart starts from the float64 state itself,
    so a missed or invented collision anywhere along the orbit fails the test.
    """
    scene, (q, v, w), n, kw = LONG_SHADOW[name]
    flt = simulate(scene, q, v, w, max_collisions=n, **kw)
    m = flt.sizes["collision"]
    assert m >= min(n, 20), f"{name}: only {m} collisions"
    col = {k: flt[k].values for k in ("t", "element", "corner", *POSITIONS, *SPEEDS)}
    speed = float(np.sqrt(flt.vx ** 2 + flt.vy ** 2 + flt.spin ** 2).max())
    for k, step, t_prev in one_step_references(scene, q, v, w, flt, f"{name}: ", **kw):
        what = f"{name}: event after collision {k}"
        assert int(step.element[0]) == col["element"][k + 1], what
        assert int(step.corner[0]) == col["corner"][k + 1], what
        length = max(scene.scale, abs(col["x"][k + 1]), abs(col["y"][k + 1]))
        assert abs(float(step.t[0]) - (col["t"][k + 1] - t_prev)) <= RTOL * max(1.0, col["t"][k + 1]), what
        for var in POSITIONS:
            assert abs(float(step[var][0]) - col[var][k + 1]) <= RTOL * length, f"{what} {var}"
        for var in SPEEDS:
            assert abs(float(step[var][0]) - col[var][k + 1]) <= RTOL * speed, f"{what} {var}"
    assert k == m - 2, f"{name}: checked {k + 2} of {m} collisions"


REFLEX = {  # flights near the inner (reflex) vertex (1, 1) of the L, exact orbit elements
    # crosses x = 1 below the vertex and y = 1 left of it (1e-12 past edge 2's end): no hit
    "pass_by": ((1.5, 0.5), (1.0 - 1e-12 - 1.5, 1.0 - 0.5), [5, 4, 3]),
    # hits edge 3 1e-12 above the vertex, then flies up the arm, away from edge 2
    "hit_above": ((1e-3, 0.999), (1.0, (0.001 + 1e-12) / 0.999), [3, 5, 3]),
}


@pytest.mark.parametrize("case", list(REFLEX))
def test_flight_near_a_reflex_vertex(case):
    q, v, elements = REFLEX[case]
    ref, flt = run_both(tables.polygon(L_SHAPE, law="specular"), q, v, 0.0, 3)
    np.testing.assert_array_equal(ref.element.values, elements)
    assert_orbits_agree(ref, flt, what=f"reflex vertex: {case}")


def test_exact_corner_orbits():
    """Float64-exact vertex hits: the corner rule fires in both engines, in the same order."""
    box = tables.rectangle(1.0, 1.0)
    for law, gamma in [("specular", 0.0), ("no-slip", 0.0)]:  # reversal: back into the opposite corner
        ref, flt = run_both(box.replace(law=law, gamma=gamma), (0.5, 0.5), (1.0, 1.0), 0.3, 40)
        assert_orbits_agree(ref, flt, what=f"corner {law} {gamma}")
        assert int(ref.corner.sum()) == 20
        np.testing.assert_array_equal(ref.element.values[:4], [1, 2, 0, 3])
    for gamma in (DISK, 3.0):  # generic gamma leaves the corner along a generic path
        ref, flt = run_both(box.replace(gamma=gamma), (0.5, 0.5), (1.0, 1.0), 0.3, 30)
        assert_orbits_agree(ref, flt, what=f"corner no-slip {gamma}")


# ----------------------------------------------------------------------------- the reference itself
@pytest.mark.parametrize("name", ["circle_g", "dome_box", "galton", "L_shape_g", "exact_corner_square"])
def test_reference_conserves_energy_and_stays_on_elements(name):
    scene, q, v, w, n, kw = CASES[name]
    orbit = simulate_reference(scene, q, v, w, max_collisions=n, as_mpf=True, **kw)
    rec = orbit.records
    with mpmath.workdps(60):
        e0 = (_mp(v[0]) ** 2 + _mp(v[1]) ** 2 + _mp(w) ** 2) / 2 \
            - (_mp(scene.force[0]) * _mp(q[0]) + _mp(scene.force[1]) * _mp(q[1]))
        for k in range(len(orbit)):
            assert abs(_mp(rec["energy"][k]) - e0) < mpmath.mpf(10) ** -40
            el = scene.elements[orbit.element[k]]
            x, y = _mp(rec["x"][k]), _mp(rec["y"][k])
            if isinstance(el, (Circle, Arc)):
                d = mpmath.hypot(x - _mp(el.center[0]), y - _mp(el.center[1])) - _mp(el.radius)
            elif isinstance(el, Segment):
                (x0, y0), (x1, y1) = (map(_mp, el.p0)), (map(_mp, el.p1))
                d = ((x - x0) * (y1 - y0) - (y - y0) * (x1 - x0)) / mpmath.hypot(x1 - x0, y1 - y0)
            else:
                d = (x - _mp(el.point[0])) * _mp(el.normal[0]) + (y - _mp(el.point[1])) * _mp(el.normal[1])
            assert abs(d) < mpmath.mpf(10) ** -45


def _outward_normal(el, x, y):
    """Outward unit normal of an element at a point, from the element's definition (docs/conventions.md)."""
    if isinstance(el, Line):
        n = (-_mp(el.normal[0]), -_mp(el.normal[1]))
    elif isinstance(el, Segment):
        dx, dy = _mp(el.p1[0]) - _mp(el.p0[0]), _mp(el.p1[1]) - _mp(el.p0[1])
        sgn = 1 if el.side == "left" else -1
        n = (sgn * dy, -sgn * dx)  # minus the table's normal +-J(p1 - p0)
    else:
        sgn = 1 if el.side == "outside" else -1
        n = (-sgn * (x - _mp(el.center[0])), -sgn * (y - _mp(el.center[1])))
    norm = mpmath.hypot(*n)
    return n[0] / norm, n[1] / norm


def test_reference_contact_velocity_reversed_at_every_noslip_collision():
    gamma = 0.6
    scene = dome_box().replace(gamma=gamma)
    orbit = simulate_reference(scene, (-1.0, 1.5), (1.0, -0.3), 0.2, max_collisions=12, as_mpf=True)
    rec = orbit.records
    with mpmath.workdps(60):
        for k in range(len(orbit)):
            x, y = _mp(rec["x"][k]), _mp(rec["y"][k])
            n = _outward_normal(scene.elements[orbit.element[k]], x, y)
            t = (-n[1], n[0])  # t = J n
            vin = (_mp(rec["vx_in"][k]), _mp(rec["vy_in"][k]))
            vout = (_mp(rec["vx"][k]), _mp(rec["vy"][k]))
            assert vin[0] * n[0] + vin[1] * n[1] > 0  # arriving through the boundary
            assert abs(vout[0] * n[0] + vout[1] * n[1] + vin[0] * n[0] + vin[1] * n[1]) < mpmath.mpf(10) ** -40
            before = vin[0] * t[0] + vin[1] * t[1] + _mp(rec["spin_in"][k]) / _mp(gamma)
            after = vout[0] * t[0] + vout[1] * t[1] + _mp(rec["spin"][k]) / _mp(gamma)
            assert abs(after + before) < mpmath.mpf(10) ** -40


def test_reference_sign_pin_ball_moving_right_onto_floor_spins_clockwise():
    orbit = simulate_reference(tables.half_plane(), (0.0, 1.0), (1.0, 0.0), 0.0, max_collisions=1,
                               as_mpf=True)
    assert orbit.records["spin"][0] < 0


def test_dataset_layout_matches_simulate():
    scene, q, v, w, _n, _kw = CASES["dome_box"]
    ref, flt = run_both(scene, q, v, w, 5)
    assert set(ref.data_vars) == set(flt.data_vars)
    for name in flt.data_vars:
        assert ref[name].dims == flt[name].dims and ref[name].dtype == flt[name].dtype, name
        assert ref[name].attrs["units"] == flt[name].attrs["units"]
    assert ref.attrs["dps"] == 50 and ref.attrs["stop_reason"] == flt.attrs["stop_reason"]


def test_higher_precision_agrees():
    scene = CASES["stadium_g"][0]
    a = simulate_reference(scene, (0.1, 0.2), (1.0, 0.37), 0.2, max_collisions=10, as_mpf=True)
    b = simulate_reference(scene, (0.1, 0.2), (1.0, 0.37), 0.2, max_collisions=10, dps=70, as_mpf=True)
    assert a.element == b.element
    with mpmath.workdps(80):
        for name in ("t", "x", "y", "vx", "vy", "spin"):
            for p, r in zip(a.records[name], b.records[name]):
                assert abs(_mp(p) - _mp(r)) < mpmath.mpf(10) ** -40


@pytest.mark.parametrize("kwargs, match", [
    (dict(position=(0.0, -1.0)), "position"),
    (dict(position=(0.0, 0.0)), "position"),
    (dict(velocity=(math.nan, 1.0)), "velocity"),
    (dict(max_collisions=-1), "max_collisions"),
    (dict(max_collisions=2.5), "max_collisions"),
    (dict(max_time=0.0), "max_time"),
    (dict(stop_below=2.0), "stop_below"),
    (dict(dps=10), "dps"),
    (dict(dps=True), "dps"),
])
def test_bad_input_raises(kwargs, match):
    args = dict(position=(0.0, 1.0), velocity=(0.3, 0.2), spin=0.1, max_collisions=3)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        simulate_reference(tables.half_plane(), **args)


def test_resume_bad_element_raises():
    with pytest.raises(ValueError, match="element"):
        resume_reference(tables.half_plane(), (0.0, 0.0), (0.3, 0.2), 0.0, 1)
    with pytest.raises(ValueError, match="scene"):
        simulate_reference("half plane", (0.0, 1.0), (0.3, 0.2))
