"""The paper's errata (docs/conventions.md, docs/errata.md), each pinned with the float engine.

A path-reversing 2-periodic wedge orbit leaves a wall point ``q0`` with state
``(v0, w0)``; after two collisions (opposite wall, then ``q0`` again) the
post-collision state must equal ``(q0, v0, w0)``.  The corrected forms pass to
~1e-10; the printed forms miss by O(1).

``simulate`` needs a start strictly inside the table, so each run starts at
the apex of the first flight (the exact state there, from the flight
equations) and collision 1 is the return to ``q0``.
"""
import math

import numpy as np
import pytest

from noslipsim import simulate, tables
from noslipsim.theory import projectile_speed, wedge_noforce_gamma, wedge_two_periodic_start

GAMMAS = [0.3, 1 / math.sqrt(2), 1.0, 3.0]
PHIS = [0.3, 0.6, 1.0]
THETAS = [0.2, 0.5, 0.9, 1.3]
CASES = [(opening, wall) for opening in ("up", "down") for wall in ("left", "right")]
PERIODIC_TOL = 1e-10


def launches(opening):
    """(phi, theta, ell) triples: several angles, two distances; downward wedges need theta < pi/2 - phi."""
    for i, phi in enumerate(PHIS):
        for theta in THETAS:
            if opening == "down" and theta + phi > math.pi / 2 - 0.05:
                continue
            yield phi, theta, (1.0, 2.5)[i % 2]


def along_flight(q0, v0, g, tau):
    """State at time ``tau`` on the flight leaving ``q0`` with velocity ``v0`` under force ``(0, -g)``."""
    a = np.array([0.0, -g])
    return q0 + v0 * tau + 0.5 * a * tau ** 2, v0 + a * tau


def after_return(scene, q0, v0, w0, g, tau=None, n=4):
    """Simulate from the flight leaving ``q0`` (by default from its apex, time ``v0_y / g``)."""
    q, v = along_flight(q0, v0, g, v0[1] / g if tau is None else tau)
    return simulate(scene, q, v, w0, max_collisions=n)


def state(ds, k):
    return np.array([float(ds[name][k]) for name in ("x", "y", "vx", "vy", "spin")])


def mismatch(ds, k, q0, v0, w0):
    """Largest difference between the state after collision ``k`` and the start, relative to its size."""
    if ds.sizes["collision"] <= k:
        return math.inf
    start = np.array([*q0, *v0, w0])
    return np.abs(state(ds, k) - start).max() / (1.0 + np.abs(start).max())


def outward_tangent(scene, element):
    n = -np.array(scene.elements[element].normal)
    return np.array([-n[1], n[0]])


# ----------------------------------------------------------------------------- erratum 2 (and the orbit itself)
@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("opening, wall", CASES)
def test_corrected_spin_gives_path_reversing_two_periodic_orbit(opening, wall, gamma):
    g = 1.0
    far = 1 if wall == "left" else 0
    for phi, theta, ell in launches(opening):
        scene = tables.wedge(phi, opening=opening, gamma=gamma, force=(0.0, -g))
        q0, v0, w0 = wedge_two_periodic_start(phi, theta, ell, gamma, g=g, opening=opening, wall=wall)
        ds = after_return(scene, q0, v0, w0, g)
        assert list(ds.element.values) == [far, 1 - far, far, 1 - far]
        assert mismatch(ds, 1, q0, v0, w0) < PERIODIC_TOL, (phi, theta)
        assert mismatch(ds, 3, q0, v0, w0) < 100 * PERIODIC_TOL, (phi, theta)
        # the far impact is at the mirror point, with v_t = gamma w and the whole velocity reversed
        np.testing.assert_allclose([ds.x[0], ds.y[0]], [-q0[0], q0[1]], atol=1e-12 * ell)
        v_in = np.array([float(ds.vx_in[0]), float(ds.vy_in[0])])
        w_in = float(ds.spin_in[0])
        assert v_in @ outward_tangent(scene, far) == pytest.approx(gamma * w_in, rel=1e-12, abs=1e-12)
        np.testing.assert_allclose([ds.vx[0], ds.vy[0], ds.spin[0]], [-v_in[0], -v_in[1], -w_in],
                                   rtol=0, atol=1e-12 * (1 + abs(w_in)))


@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("opening, wall", CASES)
def test_printed_spin_formula_only_fits_the_right_wall_of_an_upward_wedge(opening, wall, gamma):
    """Printed: gamma = (v / x0')(sin(theta) cos(phi) - cos(theta) sin(phi)), i.e. w0 = v sin(theta - phi) / gamma."""
    g = 1.0
    for phi, theta, ell in launches(opening):
        scene = tables.wedge(phi, opening=opening, gamma=gamma, force=(0.0, -g))
        q0, v0, _ = wedge_two_periodic_start(phi, theta, ell, gamma, g=g, opening=opening, wall=wall)
        v = math.hypot(*v0)
        w_printed = v * math.sin(theta - phi) / gamma
        ds = after_return(scene, q0, v0, w_printed, g)
        if (opening, wall) == ("up", "right"):
            assert mismatch(ds, 1, q0, v0, w_printed) < PERIODIC_TOL
        else:
            assert mismatch(ds, 1, q0, v0, w_printed) > 1e-3, (phi, theta)


# ----------------------------------------------------------------------------- erratum 1
@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("opening, wall", CASES)
def test_printed_speed_overshoots_to_range_4d(opening, wall, gamma):
    """Printed: v = 2 sqrt(g d / sin 2 theta).  It misses the opposite point (range 4 d), so no 2-periodic orbit."""
    g = 1.0
    for phi, theta, ell in launches(opening):
        scene = tables.wedge(phi, opening=opening, gamma=gamma, force=(0.0, -g))
        q0, v0, w0 = wedge_two_periodic_start(phi, theta, ell, gamma, g=g, opening=opening, wall=wall)
        d = 2 * ell * math.sin(phi)
        assert math.hypot(*v0) == pytest.approx(projectile_speed(g, d, theta), rel=1e-15)
        # printed speed, spin rescaled with it so that only the speed is wrong; start just after the
        # launch (the apex of this longer flight may lie outside the table)
        ds = after_return(scene, q0, 2 * v0, 2 * w0, g, tau=0.05 * d / abs(v0[0]))
        if ds.sizes["collision"]:
            assert np.hypot(float(ds.x[0]) + q0[0], float(ds.y[0]) - q0[1]) > 1e-3 * ell  # not the mirror point
        assert mismatch(ds, 1, q0, 2 * v0, 2 * w0) > 1e-3, (phi, theta)


def test_projectile_speed_is_the_range_formula():
    # landing a horizontal distance d away at the launch height: v^2 sin(2 theta) / g = d
    for g, d, theta in [(1.0, 1.0, 0.3), (9.81, 0.2, 1.1), (0.5, 3.0, math.pi / 4)]:
        v = projectile_speed(g, d, theta)
        assert v ** 2 * math.sin(2 * theta) / g == pytest.approx(d, rel=1e-14)
        assert (2 * v) ** 2 * math.sin(2 * theta) / g == pytest.approx(4 * d, rel=1e-14)


# ----------------------------------------------------------------------------- erratum 3
@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("opening", ["up", "down"])
@pytest.mark.parametrize("vx", [1.0, -0.7])
def test_noforce_wedge_sign(opening, vx, gamma):
    """No force, horizontal flight at height ell cos(phi): 2-periodic iff gamma = +(v_x / w) sin(phi) opening up.

    The printed ``gamma = -(v_x / w) sin(phi)`` is the downward-opening case.
    """
    sy = 1.0 if opening == "up" else -1.0
    for phi in PHIS:
        for ell in (1.0, 2.5):
            scene = tables.wedge(phi, opening=opening, gamma=gamma, force=(0.0, 0.0))
            h = sy * ell * math.cos(phi)
            q0 = np.array([-math.copysign(ell * math.sin(phi), vx), h])  # the wall the flight leaves
            v0 = np.array([vx, 0.0])
            w_right = sy * vx * math.sin(phi) / gamma
            assert wedge_noforce_gamma(vx, w_right, phi, opening=opening) == pytest.approx(gamma, rel=1e-14)
            w_wrong = -w_right  # the other sign: gamma = -sy (v_x / w) sin(phi)
            ds = simulate(scene, (0.0, h), v0, w_right, max_collisions=5)
            assert ds.attrs["stop_reason"] == "max_collisions"
            assert mismatch(ds, 1, q0, v0, w_right) < PERIODIC_TOL
            assert mismatch(ds, 3, q0, v0, w_right) < PERIODIC_TOL
            ds = simulate(scene, (0.0, h), v0, w_wrong, max_collisions=5)
            assert mismatch(ds, 1, q0, v0, w_wrong) > 1e-3
            if opening == "up":  # the printed sign
                assert -(vx / w_wrong) * math.sin(phi) == pytest.approx(gamma, rel=1e-14)


# ----------------------------------------------------------------------------- reading of errata 2 and 3
@pytest.mark.parametrize("gamma", GAMMAS)
def test_printed_formulas_hold_for_left_wall_launch_with_clockwise_spin(gamma):
    """Read with the rotation coordinate clockwise-positive (x0' = -w), both printed spin formulas are right
    for the paper's picture (launch from the left wall towards +x, wedge opening up): errata 2 and 3 are
    one unstated orientation convention.  Erratum 1 (the factor 2) is not a convention.
    """
    for phi, theta, ell in launches("up"):
        scene = tables.wedge(phi, gamma=gamma)
        q0, v0, _ = wedge_two_periodic_start(phi, theta, ell, gamma, wall="left")
        x0_dot = math.hypot(*v0) * math.sin(theta - phi) / gamma  # printed Theorem 2
        assert mismatch(after_return(scene, q0, v0, -x0_dot, 1.0), 1, q0, v0, -x0_dot) < PERIODIC_TOL
    for phi in PHIS:  # printed (spw), no force: gamma = -(y0' / x0') sin(phi)
        vx = 0.8
        x0_dot = -vx * math.sin(phi) / gamma
        scene = tables.wedge(phi, gamma=gamma, force=(0.0, 0.0))
        q0, v0 = np.array([-math.sin(phi), math.cos(phi)]), np.array([vx, 0.0])
        ds = simulate(scene, (0.0, math.cos(phi)), v0, -x0_dot, max_collisions=2)
        assert mismatch(ds, 1, q0, v0, -x0_dot) < PERIODIC_TOL
