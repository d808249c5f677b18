"""Boundary portraits: coordinates, invariants, the maps' preserved area and volume, round trips, errors."""
import math

import numpy as np
import pytest

import noslipsim as ns
from noslipsim import Circle, Scene, Segment, tables
from noslipsim.analysis import (
    birkhoff_coordinates,
    birkhoff_states,
    boundary_coordinate,
    reduced_portrait,
    reduced_states,
    velocity_portrait,
)
from noslipsim.experiments import phase_portrait
from noslipsim.initial import boundary_states

LEMON = tables.lemon(1.0, 1.0)                                       # specular, two arcs
SINAI = tables.sinai_torus(0.25)                                     # no-slip, one scatterer, periodic
CIRCLE = Scene((Circle((0.0, 0.0), 1.0, "inside"),), law="specular", gamma=0.0)
# a unit square drawn clockwise with the table on the right of every edge (orientation -1)
CW_SQUARE = Scene(tuple(Segment(a, b, "right") for a, b in [((0, 0), (0, 1)), ((0, 1), (1, 1)),
                                                          ((1, 1), (1, 0)), ((1, 0), (0, 0))]),
                  law="no-slip", gamma=1.0)
#: Central-difference step of the Jacobian checks, and what the determinant must meet.
FD_STEP = 1e-6
DET_TOL = 1e-6
#: Agreement of a re-run collision with the recorded one (exact engine, rounding only).
ROUND_TRIP_TOL = 1e-9


def one_step(scene, states):
    return ns.simulate_many(scene, states["positions"], states["velocities"], states["spins"],
                            start_elements=states["start_elements"], max_collisions=1, record="portrait",
                            scheduler="sync")


def test_lemon_birkhoff_invariants():
    ds = phase_portrait(LEMON, n_orbits=8, n_collisions=400, seed=2)
    b = birkhoff_coordinates(ds)
    assert b.attrs["boundary_length"] == pytest.approx(4 * math.pi / 3)
    assert b.attrs["element_orientation"] == [1.0, 1.0]
    ok = np.isfinite(b.s_boundary)
    assert ok.sum() == 8 * 400
    assert (b.s_boundary.values[ok] >= 0).all() and (b.s_boundary.values[ok] <= 4 * math.pi / 3).all()
    assert (np.abs(b.sin_angle.values[ok]) <= 1).all()
    # both arcs are visited and each point's arc matches its offset
    el = b.element.values[ok]
    assert set(el) == {0.0, 1.0}
    assert (b.s_boundary.values[ok][el == 1] >= 2 * math.pi / 3).all()
    # specular with zero spin: the velocity portrait collapses onto w = 0
    vp = velocity_portrait(ds)
    assert np.nanmax(np.abs(vp.w_unit.values)) == 0.0
    for name, var in b.data_vars.items():
        assert var.attrs["long_name"] and var.attrs["units"] == "1", name


def test_specular_circle_keeps_its_birkhoff_sine():
    states = birkhoff_states(CIRCLE, [0.3, 2.0, 5.5], [0.1, -0.6, 0.95])
    ds = ns.simulate_many(CIRCLE, states["positions"], states["velocities"], states["spins"],
                          start_elements=states["start_elements"], max_collisions=300, record="portrait")
    b = birkhoff_coordinates(ds)
    np.testing.assert_allclose(b.sin_angle.values, np.repeat([[0.1], [-0.6], [0.95]], 300, axis=1), atol=1e-12)
    # and s advances by the chord's arc pi - 2 alpha each bounce (mod 2 pi)
    step = np.diff(b.s_boundary.values, axis=1) % (2 * math.pi)
    alpha = np.arcsin([0.1, -0.6, 0.95])
    np.testing.assert_allclose(step, np.repeat(((math.pi - 2 * alpha) % (2 * math.pi))[:, None], 299, axis=1),
                               atol=1e-9)


def direction_of_increasing_s(e, x, y):
    """Unit tangent along which the element's own arclength grows, from its definition (not the module's)."""
    if isinstance(e, Segment):
        d = np.subtract(e.p1, e.p0)
        return np.broadcast_to(d / np.hypot(*d), (len(x), 2))
    ang = np.arctan2(y - e.center[1], x - e.center[0])
    return np.c_[-np.sin(ang), np.cos(ang)]  # counter-clockwise


@pytest.mark.parametrize("scene", [LEMON, CW_SQUARE, tables.regular_polygon(6, law="specular"), SINAI])
def test_birkhoff_sine_is_the_velocity_along_increasing_s(scene):
    """Independent oracle: the collision log's velocity and position against the portrait's (s, p)."""
    start = boundary_states(scene, 5, seed=8)
    kw = dict(start_elements=start["start_elements"], max_collisions=30, scheduler="sync")
    log = ns.simulate_many(scene, start["positions"], start["velocities"], start["spins"], record="log", **kw)
    por = ns.simulate_many(scene, start["positions"], start["velocities"], start["spins"], record="portrait", **kw)
    b = birkhoff_coordinates(por)
    lengths = [e.length() for e in scene.elements]
    for k, e in enumerate(scene.elements):
        on = log.element.values == k
        if not on.any():
            continue
        x, y = log.x.values[on], log.y.values[on]
        if scene.lattice is not None:  # unfolded positions: back to the cell of the scatterer
            x, y = x - np.round(x), y - np.round(y)
        v = np.c_[log.vx.values[on], log.vy.values[on]]
        want_p = np.sum(v * direction_of_increasing_s(e, x, y), axis=1) / np.hypot(v[:, 0], v[:, 1])
        np.testing.assert_allclose(b.sin_angle.values[on], want_p, atol=1e-12)
        if isinstance(e, Segment):
            own_s = np.hypot(x - e.p0[0], y - e.p0[1])
        else:
            start_angle = 0.0 if isinstance(e, Circle) else e.theta0
            own_s = e.radius * ((np.arctan2(y - e.center[1], x - e.center[0]) - start_angle) % (2 * math.pi))
        np.testing.assert_allclose(b.s_boundary.values[on], sum(lengths[:k]) + own_s, atol=1e-9)


def jacobian(image, x0):
    """Jacobian of ``image`` at ``x0`` by Richardson-extrapolated central differences (error O(h^4)).

    ``image(x)`` returns ``(element, y)``; ``None`` when a step lands on
    another element than the base point (the map is not smooth across it).
    """
    el0, _ = image(x0)
    cols = []
    for j in range(len(x0)):
        est = []
        for h in (2 * FD_STEP, FD_STEP):
            e = np.zeros(len(x0))
            e[j] = h
            (ep, yp), (em, ym) = image(x0 + e), image(x0 - e)
            if not ep == em == el0:
                return None
            est.append((yp - ym) / (2 * h))
        cols.append((4 * est[1] - est[0]) / 3)
    return np.array(cols).T


@pytest.mark.parametrize("scene,s,p", [
    (LEMON, [0.7, 1.6, 2.5, 3.3], [0.3, -0.2, 0.5, -0.45]),
    (CW_SQUARE.replace(law="specular"), [0.3, 1.45, 2.6, 3.7], [0.35, -0.2, 0.4, -0.3]),
    (tables.sinai_torus(0.3, law="specular"), [0.2, 0.9, 1.5], [0.2, -0.3, 0.6]),
])
def test_birkhoff_map_preserves_area(scene, s, p):
    """The specular billiard map in (s, p) has Jacobian determinant +1 (orientations consistent)."""
    def image(x):
        b = birkhoff_coordinates(one_step(scene, birkhoff_states(scene, [x[0]], [x[1]])), scene)
        return b.element.values[0, 0], np.array([float(b.s_boundary[0, 0]), float(b.sin_angle[0, 0])])

    for x0 in zip(s, p):
        jac = jacobian(image, np.array(x0))
        assert jac is not None, x0
        assert np.linalg.det(jac) == pytest.approx(1.0, abs=DET_TOL), x0


@pytest.mark.parametrize("scene", [SINAI, CW_SQUARE, tables.lemon(1.0, 1.2, law="no-slip", gamma=0.5)])
def test_reduced_map_preserves_volume(scene):
    """The no-slip billiard map preserves ds dv_t dw (the canonical measure |v_n| ds dsigma).

    Its determinant is -1 in these coordinates when every element has the same
    orientation: the no-slip rotation of (w, v_t) is a reflection of that plane.
    """
    L = boundary_coordinate(phase_portrait(scene, n_orbits=1, n_collisions=1)).attrs["boundary_length"]

    def image(x):
        out = reduced_portrait(one_step(scene, reduced_states(scene, [x[0]], [x[1]], [x[2]])), scene)
        return out.element.values[0, 0], np.array([float(out[k][0, 0]) for k in ("s_boundary", "vt_unit",
                                                                                   "w_unit")])

    rng = np.random.default_rng(11)
    done = 0
    while done < 3:
        x0 = np.array([rng.uniform(0.1, 0.9) * L, *rng.uniform(-0.5, 0.5, 2)])
        jac = jacobian(image, x0)
        if jac is None or np.abs(jac).max() > 0.1 / FD_STEP:
            continue  # neighbours landing on another element, or across the seam of s: draw another
        assert np.linalg.det(jac) == pytest.approx(-1.0, abs=DET_TOL), x0
        done += 1


@pytest.mark.parametrize("scene", [LEMON, SINAI, CW_SQUARE, tables.regular_polygon(5, gamma=0.3)])
def test_a_recorded_point_restarted_gives_the_next_one(scene):
    ds = phase_portrait(scene, n_orbits=4, n_collisions=20, seed=4)
    red = reduced_portrait(ds)
    s, vt, w = (red[k].values[:, :-1].ravel() for k in ("s_boundary", "vt_unit", "w_unit"))
    nxt = one_step(scene, reduced_states(scene, s, vt, w))
    again = reduced_portrait(nxt)
    for k in ("s_boundary", "vt_unit", "w_unit", "vn_unit"):
        got = again[k].values[:, 0]
        want = red[k].values[:, 1:].ravel()
        if k == "s_boundary":  # the same boundary point may read 0 or the full length
            L = red.attrs["boundary_length"]
            got, want = np.mod(got, L), np.mod(want, L)
            got = np.where(np.abs(got - want) > 0.5 * L, got - np.sign(got - want) * L, got)
        np.testing.assert_allclose(got, want, atol=ROUND_TRIP_TOL * max(1.0, L if k == "s_boundary" else 1.0),
                                   err_msg=k)
    if scene.law == "specular":
        b = birkhoff_coordinates(ds)
        st = birkhoff_states(scene, b.s_boundary.values[:, :-1].ravel(), b.sin_angle.values[:, :-1].ravel())
        np.testing.assert_allclose(birkhoff_coordinates(one_step(scene, st)).sin_angle.values[:, 0],
                                   b.sin_angle.values[:, 1:].ravel(), atol=ROUND_TRIP_TOL)


def test_sinai_torus_portraits_lie_on_the_disk_and_the_torus():
    ds = phase_portrait(SINAI, n_orbits=6, n_collisions=300, seed=1)
    red = reduced_portrait(ds)
    assert red.attrs["element_orientation"] == [-1.0]  # a scatterer: s counter-clockwise, t clockwise
    assert red.attrs["boundary_length"] == pytest.approx(2 * math.pi * 0.25)
    assert (red.s_boundary >= 0).all() and (red.s_boundary < 2 * math.pi * 0.25).all()
    vp = velocity_portrait(ds)
    r2 = vp.vt_unit ** 2 + vp.w_unit ** 2
    assert (r2 <= 1 + 1e-12).all() and (red.vn_unit <= 0).all()
    assert np.nanmax(np.abs(vp.w_unit)) > 0.1  # no-slip spins
    b = birkhoff_coordinates(ds)  # defined for no-slip too: the spatial part of the unit vector
    np.testing.assert_allclose(b.sin_angle, -red.vt_unit / np.hypot(red.vt_unit, red.vn_unit))


def test_elements_subset_and_padding():
    scene = tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)])
    ds = phase_portrait(scene, n_orbits=3, n_collisions=50, elements=[4], seed=3)
    b = boundary_coordinate(ds, elements=[4])
    assert b.attrs["boundary_length"] == pytest.approx(2 * math.pi * 0.2)
    ok = np.isfinite(b.s_boundary.values)
    assert ok.any() and (~ok).any()  # scatterer hits are fewer than the budget: NaN padding stays NaN
    np.testing.assert_allclose(b.s_boundary.values[ok], ds.s.values[ok])
    full = boundary_coordinate(ds)  # all five elements: the scatterer comes after the perimeter 6
    np.testing.assert_allclose(full.s_boundary.values[ok], 6.0 + ds.s.values[ok])
    with pytest.raises(ValueError, match="not among the chosen"):
        boundary_coordinate(phase_portrait(scene, n_orbits=2, n_collisions=20), elements=[4])


def test_arc_wrap_and_ends_are_folded_into_the_element():
    ds = phase_portrait(LEMON, n_orbits=1, n_collisions=2)
    L = 2 * math.pi / 3
    fake = ds.copy(deep=True)
    fake["element"][:] = [[0.0, 1.0]]
    fake["s"][:] = [[2 * math.pi - 1e-13, L + 1e-13]]  # just before theta0 (wrapped angle), just past the end
    b = boundary_coordinate(fake)
    np.testing.assert_allclose(b.s_boundary.values[0], [0.0, 2 * L], atol=1e-12)


def test_bad_inputs_are_refused():
    ds = phase_portrait(LEMON, n_orbits=2, n_collisions=5)
    with pytest.raises(TypeError, match="xarray"):
        boundary_coordinate(ds.s)
    with pytest.raises(ValueError, match="missing variable"):
        birkhoff_coordinates(ds.drop_vars("vt_unit"))
    with pytest.raises(ValueError, match="scene"):
        boundary_coordinate(ds.drop_attrs() if hasattr(ds, "drop_attrs") else ds.assign_attrs(scene=""))
    with pytest.raises(TypeError, match="Scene"):
        boundary_coordinate(ds, scene="lemon")
    with pytest.raises(ValueError, match="no element 7"):
        boundary_coordinate(ds, elements=[0, 7])
    wedge = tables.wedge(0.4, force=(0.0, 0.0))
    with pytest.raises(ValueError, match="infinite line"):
        boundary_coordinate(ds, scene=wedge)
    with pytest.raises(ValueError, match="unit vector"):
        velocity_portrait(ds.assign(w_unit=ds.w_unit + 0.5))
    with pytest.raises(ValueError, match="s_boundary"):
        birkhoff_states(LEMON, [5.0], [0.1])
    with pytest.raises(ValueError, match="sin_angle"):
        birkhoff_states(LEMON, [1.0], [1.0])
    with pytest.raises(ValueError, match="shape"):
        birkhoff_states(LEMON, [1.0, 2.0], [0.1])
    with pytest.raises(ValueError, match="inside the disk"):
        reduced_states(SINAI, [0.1], [0.8], [0.7])
    with pytest.raises(ValueError, match="speed"):
        reduced_states(SINAI, [0.1], [0.1], [0.1], speed=0.0)
    with pytest.raises(TypeError, match="Scene"):
        birkhoff_states(None, [1.0], [0.1])
