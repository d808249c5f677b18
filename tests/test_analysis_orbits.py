"""Theorem orbits (noslipsim.analysis.orbits): each is periodic in the float engine, path reversing, as built.

Oracle: the engine itself.  A 2-periodic orbit repeats its post-collision state
every second collision; the check compares collision k + 2 with collision k
for every k of a long run (hundreds of periods), so a construction error of any
size shows at once and rounding has to stay at ~1e-12 for the whole run.
Long runs are only meaningful for stable orbits (a hyperbolic orbit amplifies
rounding by |lambda| per period): those get a few periods.
"""
import math

import numpy as np
import pytest

import noslipsim as ns
from noslipsim import theory
from noslipsim.analysis import bounce_orbit, monodromy, two_disk_orbit, wedge_noforce_orbit, wedge_orbit

#: Largest change of the post-collision state over one period, relative to the state's size.
PERIODIC_TOL = 1e-12
LONG = 400   # collisions: 200 periods
SHORT = 7    # a few periods of a hyperbolic orbit

GAMMAS = [0.05, 0.3, 1 / math.sqrt(2), 1.0, 3.0, 100.0]


def states(ds):
    return np.c_[ds.x, ds.y, ds.vx, ds.vy, ds.spin]


def drifts(scene, state, n):
    """|X[k+2] - X[k]| (largest component) for each k of a run of ``n`` collisions, relative to the state's size."""
    ds = ns.simulate(scene, **state, max_collisions=n)
    assert ds.attrs["stop_reason"] == "max_collisions", ds.attrs["stop_reason"]
    X = states(ds)
    return np.abs(X[2:] - X[:-2]).max(axis=1) / (1.0 + np.abs(X).max())


def period_drift(scene, state, n):
    """Largest |X[k+2] - X[k]| over a run of ``n`` collisions, relative to the largest state component."""
    return drifts(scene, state, n).max()


def growth_bound(lam, n):
    """Rounding growth allowed for X[k+2] - X[k], k < n - 2: |lambda|^(k/2 + 1), lambda the largest eigenvalue."""
    return max(1.0, abs(lam)) ** (np.arange(n - 2) // 2 + 1)


def largest_eigenvalue(eigen_sum):
    """The larger root of x + 1/x = eigen_sum (in modulus)."""
    return abs(eigen_sum) / 2 + math.sqrt(max(eigen_sum ** 2 / 4 - 1, 0.0))


def assert_path_reversing(scene, state):
    """At the first two impacts v_t = gamma w, and the state after each is the reversed state before."""
    ds = ns.simulate(scene, **state, max_collisions=2)
    for k in range(2):
        v_in = np.array([float(ds.vx_in[k]), float(ds.vy_in[k])])
        w_in = float(ds.spin_in[k])
        n_out = outward_normal(scene, int(ds.element[k]), float(ds.x[k]), float(ds.y[k]))
        vt = v_in @ np.array([-n_out[1], n_out[0]])
        scale = 1.0 + abs(w_in) + np.abs(v_in).max()
        assert vt == pytest.approx(scene.gamma * w_in, abs=1e-12 * scale)
        np.testing.assert_allclose([ds.vx[k], ds.vy[k], ds.spin[k]], [-v_in[0], -v_in[1], -w_in],
                                   rtol=0, atol=1e-12 * scale)


def outward_normal(scene, element, x, y):
    e = scene.elements[element]
    if isinstance(e, ns.Circle):
        r = np.array([x - e.center[0], y - e.center[1]]) / e.radius
        return -r if e.side == "outside" else r
    return -np.asarray(e.normal)


# ----------------------------------------------------------------------------- two disks, no force
@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("radius, phi", [(0.9, 1.2), (0.5, 1.0), (0.3, 0.3), (0.95, 0.2)])
def test_two_disk_orbit_without_force_is_two_periodic(radius, phi, gamma):
    scene, state = two_disk_orbit(radius, phi, gamma)
    d = 2 - 2 * radius * math.cos(phi)
    eigen_sum = theory.two_disk_eigen_sum(1 / radius, d, phi, gamma)
    if abs(eigen_sum) < 2:  # elliptic: rounding stays rounding
        assert period_drift(scene, state, LONG) < PERIODIC_TOL
    else:  # hyperbolic: rounding grows by |lambda| per period, no faster
        assert np.all(drifts(scene, state, SHORT) < PERIODIC_TOL * growth_bound(largest_eigenvalue(eigen_sum), SHORT))
    assert_path_reversing(scene, state)
    ds = ns.simulate(scene, **state, max_collisions=2)
    q0 = (-1 + radius * math.cos(phi), radius * math.sin(phi))
    np.testing.assert_allclose(np.c_[ds.x, ds.y], [(-q0[0], q0[1]), q0], atol=1e-13)
    assert list(ds.element.values) == [1, 0]


def test_two_disk_orbit_gamma_zero_is_the_line_of_centres():
    scene, state = two_disk_orbit(0.4, 0.0, 0.0)
    assert state["spin"] == 0.0 and state["velocity"] == (1.0, 0.0) and state["position"][1] == 0.0
    assert period_drift(scene, state, SHORT) == 0.0  # hyperbolic, but on the symmetry axis: exact
    with pytest.raises(ValueError, match="gamma = 0 only a perpendicular"):
        two_disk_orbit(0.4, 0.3, 0.0)


# ----------------------------------------------------------------------------- two disks with gravity
@pytest.mark.parametrize("gamma", [0.3, 1 / math.sqrt(2), 3.0, 100.0])
@pytest.mark.parametrize("radius, phi", [(0.9, 1.2), (0.2, 0.7), (0.5, 0.0)])
@pytest.mark.parametrize("theta", [0.2, 0.9, 1.3])
def test_two_disk_orbit_with_gravity_is_two_periodic_for_a_few_periods(radius, phi, gamma, theta):
    # unstable cases amplify the start's rounding by |lambda| per period (lambda from the monodromy)
    scene, state = two_disk_orbit(radius, phi, gamma, theta=theta, gravity=1.0)
    assert scene.force == (0.0, -1.0)
    lam = np.abs(monodromy(scene, **state, period=2).eigenvalues).max()
    assert np.all(drifts(scene, state, SHORT) < PERIODIC_TOL * growth_bound(lam, SHORT))
    assert_path_reversing(scene, state)


@pytest.mark.parametrize("radius, phi, gamma, theta, gravity", [
    (0.9, 1.2, 3.0, 0.2, 1.0), (0.9, 1.2, 3.0, 0.3, 9.81), (0.2, 0.7, 100.0, 0.3, 0.5),
])
def test_two_disk_orbit_with_gravity_stable_cases_over_hundreds_of_periods(radius, phi, gamma, theta, gravity):
    # elliptic by the monodromy (tests/test_analysis_monodromy.py pins that)
    scene, state = two_disk_orbit(radius, phi, gamma, theta=theta, gravity=gravity)
    assert period_drift(scene, state, LONG) < PERIODIC_TOL


def test_two_disk_orbit_with_gravity_matches_the_wedge_theorem():
    """phi > 0 takes theory.wedge_two_periodic_start; the launch is its velocity, shifted to q0."""
    R, phi, gamma, theta, g = 0.6, 0.5, 0.8, 0.7, 2.0
    _scene, state = two_disk_orbit(R, phi, gamma, theta=theta, gravity=g)
    d = 2 - 2 * R * math.cos(phi)
    _, v0, w0 = theory.wedge_two_periodic_start(phi, theta, d / (2 * math.sin(phi)), gamma, g=g)
    assert state["spin"] == w0
    assert math.hypot(*v0) == pytest.approx(theory.projectile_speed(g, d, theta), rel=1e-15)
    tau = d / v0[0]
    np.testing.assert_allclose(state["velocity"], v0 + np.array([0.0, -g]) * tau / 2, rtol=1e-15)


def test_two_disk_orbit_argument_errors():
    with pytest.raises(ValueError, match="theta: the launch angle is required"):
        two_disk_orbit(0.5, 0.3, 0.7, gravity=1.0)
    with pytest.raises(ValueError, match="theta: only meaningful"):
        two_disk_orbit(0.5, 0.3, 0.7, theta=0.4)
    with pytest.raises(ValueError, match="radius"):
        two_disk_orbit(1.0, 0.3, 0.7)
    with pytest.raises(ValueError, match="far side"):
        two_disk_orbit(0.5, math.pi / 2, 0.7)
    with pytest.raises(ValueError, match="theta: must lie"):
        two_disk_orbit(0.5, 0.3, 0.7, theta=0.0, gravity=1.0)
    with pytest.raises(ValueError, match="gravity"):
        two_disk_orbit(0.5, 0.3, 0.7, theta=0.4, gravity=-1.0)
    with pytest.raises(ValueError, match="gamma"):
        two_disk_orbit(0.5, 0.3, -0.1)
    with pytest.raises(ValueError, match="gamma = 0"):
        two_disk_orbit(0.5, 0.3, 0.0, theta=0.4, gravity=1.0)
    # gamma = 0 with a perpendicular landing (theta = phi) is the specular 2-periodic orbit
    scene, state = two_disk_orbit(0.5, 0.3, 0.0, theta=0.3, gravity=1.0)
    assert state["spin"] == 0.0 and period_drift(scene, state, SHORT) < PERIODIC_TOL


# ----------------------------------------------------------------------------- wedges
CASES = [(o, w) for o in ("up", "down") for w in ("left", "right")]


@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("opening, wall", CASES)
def test_wedge_orbit_is_two_periodic_over_hundreds_of_periods(opening, wall, gamma):
    # downward wedges at small gamma lose stability: elliptic launches are checked over 200 periods,
    # the others over a few, with rounding allowed to grow by |lambda| per period
    for phi, theta, ell in [(0.5, 0.3, 1.0), (0.9, 0.2, 2.5), (0.3, 0.6, 0.7)]:
        scene, state = wedge_orbit(phi, theta, ell, gamma, gravity=1.0, opening=opening, wall=wall)
        m = monodromy(scene, **state, period=2)
        if m.kind == "elliptic":
            assert period_drift(scene, state, LONG) < PERIODIC_TOL, (phi, theta, ell)
        else:
            lam = np.abs(m.eigenvalues).max()
            assert np.all(drifts(scene, state, SHORT) < PERIODIC_TOL * growth_bound(lam, SHORT))
            assert opening == "down" and gamma < 0.7  # the unstable ones are these
        if opening == "up":
            assert m.kind == "elliptic"
        assert_path_reversing(scene, state)
        ds = ns.simulate(scene, **state, max_collisions=2)
        far = 1 if wall == "left" else 0
        assert list(ds.element.values) == [far, 1 - far]


@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("opening, wall", CASES)
def test_wedge_noforce_orbit_is_two_periodic_over_hundreds_of_periods(opening, wall, gamma):
    for phi, ell, speed in [(0.5, 1.0, 1.0), (1.2, 2.5, 0.3), (0.1, 0.7, 4.0)]:
        scene, state = wedge_noforce_orbit(phi, ell, gamma, speed=speed, opening=opening, wall=wall)
        assert scene.force == (0.0, 0.0)
        assert period_drift(scene, state, LONG) < PERIODIC_TOL, (phi, ell)
        assert_path_reversing(scene, state)
        vx = state["velocity"][0]
        assert theory.wedge_noforce_gamma(vx, state["spin"], phi, opening=opening) == pytest.approx(gamma, rel=1e-14)


def test_wedge_argument_errors():
    with pytest.raises(ValueError, match="opening"):
        wedge_orbit(0.5, 0.3, 1.0, 0.7, opening="sideways")
    with pytest.raises(ValueError, match="wall"):
        wedge_noforce_orbit(0.5, 1.0, 0.7, wall="middle")
    with pytest.raises(ValueError, match="theta"):
        wedge_orbit(1.0, 0.8, 1.0, 0.7, opening="down")  # launch leaves through the wall
    with pytest.raises(ValueError, match="gamma"):
        wedge_noforce_orbit(0.5, 1.0, 0.0)
    with pytest.raises(ValueError, match="ell"):
        wedge_noforce_orbit(0.5, -1.0, 0.7)
    with pytest.raises(ValueError, match="g"):
        wedge_orbit(0.5, 0.3, 1.0, 0.7, gravity=0.0)


# ----------------------------------------------------------------------------- half plane
@pytest.mark.parametrize("gamma", GAMMAS)
def test_bounce_orbit_is_two_periodic_over_hundreds_of_periods(gamma):
    for vx, u, g in [(0.3, 1.2, 1.0), (-2.0, 0.5, 9.81), (0.0, 1.0, 1.0)]:
        scene, state = bounce_orbit(vx, u, gamma, gravity=g)
        assert period_drift(scene, state, LONG) < PERIODIC_TOL
        assert_path_reversing(scene, state)
        ds = ns.simulate(scene, **state, max_collisions=2)
        np.testing.assert_allclose(ds.x, [vx * u / g, -vx * u / g], atol=1e-14)
        assert theory.half_plane_drift(vx, state["spin"], u, gamma, g) == pytest.approx(0.0, abs=1e-14)


def test_bounce_orbit_argument_errors():
    with pytest.raises(ValueError, match="gamma = 0"):
        bounce_orbit(0.3, 1.0, 0.0)
    with pytest.raises(ValueError, match="u:"):
        bounce_orbit(0.3, 0.0, 0.7)
    with pytest.raises(ValueError, match="gravity"):
        bounce_orbit(0.3, 1.0, 0.7, gravity=0.0)
    _scene, state = bounce_orbit(0.0, 1.0, 0.0)
    assert state["spin"] == 0.0
