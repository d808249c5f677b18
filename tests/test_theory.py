"""Closed forms of noslipsim.theory against the float engine and against each other."""
import math

import numpy as np
import pytest

from noslipsim import simulate, tables
from noslipsim.core import laws
from noslipsim.theory import (
    ellipticity_threshold,
    half_plane_drift,
    noslip_coefficients,
    projectile_speed,
    two_disk_eigen_sum,
    wedge_noforce_gamma,
    wedge_two_periodic_start,
)

GAMMAS = [0.3, 1 / math.sqrt(2), 1.0, 3.0]


def test_noslip_coefficients_is_the_core_law():
    assert noslip_coefficients is laws.noslip_coefficients


# ----------------------------------------------------------------------------- half plane
@pytest.mark.parametrize("gamma", [0.0, *GAMMAS])
def test_half_plane_drift_matches_engine(gamma, rng):
    g = 1.3
    scene = tables.half_plane(gamma=gamma, gravity=g)
    for _ in range(10):
        x, y = rng.normal(), rng.uniform(0.1, 2.0)
        vx, vy, w = rng.normal(size=3)
        ds = simulate(scene, (x, y), (vx, vy), w, max_collisions=8)
        u = float(ds.vy[0])
        D = half_plane_drift(float(ds.vx[0]), float(ds.spin[0]), u, gamma, g)
        # the drift is the same from any flight: v_x - gamma w is invariant
        assert half_plane_drift(float(ds.vx[1]), float(ds.spin[1]), u, gamma, g) == pytest.approx(D, abs=1e-13)
        xs = ds.x.values
        np.testing.assert_allclose(xs[2:] - xs[:-2], D, rtol=0, atol=1e-12 * (1 + np.abs(xs).max()))


def test_half_plane_drift_values_and_arrays():
    assert half_plane_drift(1.0, 0.0, 1.0, 1.0, 1.0) == 2.0
    assert half_plane_drift(0.5, 0.5, 2.0, 1.0, 1.0) == 0.0  # v_x = gamma w: 2-periodic
    out = half_plane_drift(np.array([1.0, 2.0]), 0.0, 1.0, 0.0, 2.0)
    np.testing.assert_allclose(out, [2.0, 4.0])
    for kwargs, field in [(dict(u=-1.0), "u"), (dict(g=0.0), "g"), (dict(gamma=-1.0), "gamma"),
                          (dict(vx=np.nan), "vx"), (dict(w="a"), "w")]:
        args = dict(vx=1.0, w=0.0, u=1.0, gamma=1.0, g=1.0)
        args.update(kwargs)
        with pytest.raises(ValueError, match=f"^{field}"):
            half_plane_drift(**args)


# ----------------------------------------------------------------------------- wedges
@pytest.mark.parametrize("theta", [0.1, 0.7, 1.4])
def test_projectile_speed_gives_range_d(theta):
    g, d = 2.5, 0.8
    v = projectile_speed(g, d, theta)
    t_land = 2 * v * math.sin(theta) / g
    assert v * math.cos(theta) * t_land == pytest.approx(d, rel=1e-14)


@pytest.mark.parametrize("args, field", [
    ((0.0, 1.0, 0.5), "g"), ((1.0, -1.0, 0.5), "d"), ((1.0, 1.0, 0.0), "theta"),
    ((1.0, 1.0, math.pi / 2), "theta"), ((1.0, np.inf, 0.5), "d"),
])
def test_projectile_speed_validates(args, field):
    with pytest.raises(ValueError, match=f"^{field}"):
        projectile_speed(*args)


def _wall_frame(opening, wall, phi):
    """Outward normal n and tangent t = J n of a wall of tables.wedge."""
    scene = tables.wedge(phi, opening=opening)
    inward = np.array(scene.elements[0 if wall == "left" else 1].normal)
    n = -inward
    return n, np.array([-n[1], n[0]])


@pytest.mark.parametrize("opening", ["up", "down"])
@pytest.mark.parametrize("wall", ["left", "right"])
def test_wedge_start_geometry_and_reversal_condition(opening, wall):
    phi, theta, ell, gamma, g = 0.5, 0.6, 1.7, 0.8, 1.4
    q, v, w = wedge_two_periodic_start(phi, theta, ell, gamma, g=g, opening=opening, wall=wall)
    scene = tables.wedge(phi, opening=opening, gamma=gamma, force=(0.0, -g))
    assert abs(scene.depth(q[None])[0]) < 1e-15  # on the wall ...
    assert np.linalg.norm(q) == pytest.approx(ell, rel=1e-15)  # ... at distance ell from the vertex
    n0, _ = _wall_frame(opening, wall, phi)
    assert v @ n0 < 0  # leaves into the table
    assert math.atan2(v[1], abs(v[0])) == pytest.approx(theta, rel=1e-14)
    assert np.sign(v[0]) == (1 if wall == "left" else -1)
    # the flight lands on the mirror point with v_t = gamma w there (convention-free reversal)
    T = 2 * v[1] / g
    q1 = q + v * T + 0.5 * np.array([0.0, -g]) * T ** 2
    np.testing.assert_allclose(q1, [-q[0], q[1]], atol=1e-14)
    _n1, t1 = _wall_frame(opening, "right" if wall == "left" else "left", phi)
    v1 = v + np.array([0.0, -g]) * T
    assert v1 @ t1 == pytest.approx(gamma * w, rel=1e-13)


def test_wedge_start_four_cases_in_closed_form():
    phi, theta, gamma = 0.4, 0.9, 0.6
    v = projectile_speed(1.0, 2 * math.sin(phi), theta)
    expected = {("up", "left"): v * math.sin(phi - theta) / gamma,
                ("up", "right"): v * math.sin(theta - phi) / gamma,  # the paper's printed case
                ("down", "left"): -v * math.sin(phi + theta) / gamma,
                ("down", "right"): v * math.sin(phi + theta) / gamma}
    for (opening, wall), w0 in expected.items():
        _, vel, w = wedge_two_periodic_start(phi, theta, 1.0, gamma, opening=opening, wall=wall)
        assert w == pytest.approx(w0, rel=1e-14), (opening, wall)
        assert np.hypot(*vel) == pytest.approx(v, rel=1e-15)


@pytest.mark.parametrize("kwargs, field", [
    (dict(phi=0.0), "phi"), (dict(phi=math.pi / 2), "phi"), (dict(theta=0.0), "theta"),
    (dict(theta=2.0), "theta"), (dict(ell=0.0), "ell"), (dict(gamma=0.0), "gamma"),
    (dict(gamma=-1.0), "gamma"), (dict(g=-1.0), "g"), (dict(opening="sideways"), "opening"),
    (dict(wall="top"), "wall"), (dict(opening="down", phi=0.8, theta=0.8), "theta"),
    (dict(ell=np.nan), "ell"),
])
def test_wedge_start_validates(kwargs, field):
    args = dict(phi=0.5, theta=0.6, ell=1.0, gamma=0.7)
    args.update(kwargs)
    with pytest.raises(ValueError, match=f"^{field}"):
        wedge_two_periodic_start(**args)


def test_wedge_noforce_gamma_values_and_validation():
    assert wedge_noforce_gamma(2.0, 1.0, math.pi / 6) == pytest.approx(1.0)
    assert wedge_noforce_gamma(-2.0, -1.0, math.pi / 6) == pytest.approx(1.0)
    assert wedge_noforce_gamma(2.0, -1.0, math.pi / 6, opening="down") == pytest.approx(1.0)
    for args, field in [((2.0, -1.0, 0.5), "w"), ((0.0, 1.0, 0.5), "vx"), ((1.0, 0.0, 0.5), "w"),
                        ((1.0, 1.0, 0.0), "phi"), ((1.0, 1.0, 2.0), "phi"), ((np.inf, 1.0, 0.5), "vx")]:
        with pytest.raises(ValueError, match=f"^{field}"):
            wedge_noforce_gamma(*args)
    with pytest.raises(ValueError, match=r"^opening"):
        wedge_noforce_gamma(1.0, 1.0, 0.5, opening="left")


# ----------------------------------------------------------------------------- two disks: closed forms
def test_two_disk_eigen_sum_special_cases():
    # gamma = 0, phi = 0: the specular two-mirror value 4 (1 + kappa d)^2 - 2
    for kd in [0.1, 1.0, 3.0]:
        assert two_disk_eigen_sum(kd, 1.0, 0.0, 0.0) == pytest.approx(4 * (1 + kd) ** 2 - 2, rel=1e-14)
    # flat walls (the force-free wedge) are always elliptic
    for gamma in GAMMAS:
        for phi in [0.1, 0.7, 1.4]:
            assert abs(two_disk_eigen_sum(0.0, 1.0, phi, gamma)) < 2
    # +2 exactly at the ellipticity threshold, and the threshold uses C = cos^2(beta/2)
    for gamma in [0.0, *GAMMAS]:
        for phi in [0.0, 0.5, 1.2]:
            kd = ellipticity_threshold(phi, gamma)
            assert two_disk_eigen_sum(kd, 1.0, phi, gamma) == pytest.approx(2.0, rel=1e-12)
            if kd > 0:  # (gamma = phi = 0: specular, never elliptic)
                below, above = (two_disk_eigen_sum(f * kd, 1.0, phi, gamma) for f in (0.99, 1.01))
                assert below < 2 < above
            cb = math.cos(math.atan(gamma)) ** 2  # cos^2(beta/2), gamma = tan(beta/2)
            printed = (2 - 2 * cb * math.cos(phi) ** 2) / (cb * math.cos(phi))
            assert kd == pytest.approx(printed, rel=1e-13)
    np.testing.assert_allclose(ellipticity_threshold(np.array([0.0, 0.0]), np.array([0.0, 1.0])), [0.0, 2.0],
                               atol=1e-15)


@pytest.mark.parametrize("args, field", [
    ((-1.0, 1.0, 0.0, 1.0), "kappa"), ((1.0, 0.0, 0.0, 1.0), "d"), ((1.0, 1.0, -0.1, 1.0), "phi"),
    ((1.0, 1.0, math.pi / 2, 1.0), "phi"), ((1.0, 1.0, 0.0, -1.0), "gamma"), ((np.nan, 1.0, 0.0, 1.0), "kappa"),
])
def test_two_disk_eigen_sum_validates(args, field):
    with pytest.raises(ValueError, match=f"^{field}"):
        two_disk_eigen_sum(*args)
    if field in ("phi", "gamma"):
        with pytest.raises(ValueError, match=f"^{field}"):
            ellipticity_threshold(args[2], args[3])


# ----------------------------------------------------------------------------- two disks: monodromy
DISTANCE = 2.0  # centres at (-1, 0) and (1, 0), tables.two_disks' default


def periodic_reduced_state(phi, gamma):
    """Reduced state (alpha, v_t, w) at the left disk of the horizontal 2-periodic orbit, |(v, w)| = 1.

    The collision point is at angle ``alpha = phi`` on the left disk; the flight is
    horizontal; path reversal at the mirror point needs ``v_t = gamma w`` with
    ``v_t = v_x sin(phi)``.
    """
    vx = 1.0 / math.sqrt(1.0 + (math.sin(phi) / gamma) ** 2)
    return np.array([phi, vx * math.sin(phi), vx * math.sin(phi) / gamma])


def state_at_left_disk(a, R):
    """Position, velocity and spin just after a collision on the left disk, from reduced coordinates.

    On the left disk at angle ``alpha`` the outward normal (into the disk) is
    ``-e(alpha)``, so ``t = J n = (sin alpha, -cos alpha)`` and the post-collision
    normal speed ``sqrt(1 - v_t^2 - w^2)`` is along ``+e(alpha)``.
    """
    alpha, vt, w = a
    e = np.array([math.cos(alpha), math.sin(alpha)])
    t = np.array([e[1], -e[0]])
    q = np.array([-DISTANCE / 2, 0.0]) + R * e
    return q, vt * t + math.sqrt(1.0 - vt * vt - w * w) * e, w


def reduced_at_left_disk(ds, k):
    x, y, vx, vy, w = (float(ds[name][k]) for name in ("x", "y", "vx", "vy", "spin"))
    norm = math.sqrt(vx * vx + vy * vy + w * w)
    alpha = math.atan2(y, x + DISTANCE / 2)
    return np.array([alpha, (vx * math.sin(alpha) - vy * math.cos(alpha)) / norm, w / norm])


def run_from_left_disk(scene, a, R, n):
    """Simulate ``n`` collisions from the reduced state ``a`` (started half-way along the first flight)."""
    q, v, w = state_at_left_disk(a, R)
    half_gap = 0.5 * (DISTANCE - 2 * R * math.cos(a[0]))
    return simulate(scene, q + v * half_gap / abs(v[0]), v, w, max_collisions=n)


def two_bounce_map(scene, a, R):
    ds = run_from_left_disk(scene, a, R, 2)
    assert list(ds.element.values) == [1, 0]
    return reduced_at_left_disk(ds, 1)


def monodromy(scene, a0, R, h=1e-5):
    """Jacobian of the 2-bounce map by central differences with one Richardson step (error O(h^4))."""
    def central(step):
        J = np.empty((3, 3))
        for j in range(3):
            e = np.zeros(3)
            e[j] = step
            J[:, j] = (two_bounce_map(scene, a0 + e, R) - two_bounce_map(scene, a0 - e, R)) / (2 * step)
        return J
    return (4 * central(h / 2) - central(h)) / 3


@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("phi", [0.0, 0.3, 0.7])
@pytest.mark.parametrize("R", [0.35, 0.6, 0.85])
def test_two_disk_monodromy_matches_eigen_sum(gamma, phi, R):
    scene = tables.two_disks(R, distance=DISTANCE, gamma=gamma)
    a0 = periodic_reduced_state(phi, gamma)
    np.testing.assert_allclose(two_bounce_map(scene, a0, R), a0, rtol=0, atol=1e-14)  # a fixed point
    J = monodromy(scene, a0, R)
    d = DISTANCE - 2 * R * math.cos(phi)
    expected = two_disk_eigen_sum(1 / R, d, phi, gamma)
    # characteristic polynomial of {1, lambda, 1/lambda}: (mu - 1)(mu^2 - S mu + 1)
    trace = np.trace(J)
    minors = sum(np.linalg.det(J[np.ix_(ix, ix)]) for ix in ([0, 1], [0, 2], [1, 2]))
    assert trace - 1 == pytest.approx(expected, rel=1e-7, abs=1e-7)
    assert minors - 1 == pytest.approx(expected, rel=1e-6, abs=1e-6)
    assert np.linalg.det(J) == pytest.approx(1.0, abs=1e-6)
    mu = np.linalg.eigvals(J)
    one = np.argmin(np.abs(mu - 1))
    assert abs(mu[one] - 1) < 1e-5
    rest = np.delete(mu, one)
    assert (rest.sum()).real == pytest.approx(expected, rel=1e-6, abs=1e-6)
    assert abs(np.prod(rest) - 1) < 1e-5
    assert (abs(expected) < 2) == bool(np.all(np.abs(np.abs(rest) - 1) < 1e-6))  # elliptic: on the unit circle


def _radius_at(kd_over_threshold, phi, gamma):
    """Disk radius R (centres 2 apart) with kappa d = factor * threshold at the angle phi."""
    kd = kd_over_threshold * ellipticity_threshold(phi, gamma)
    return 2.0 / (kd + 2.0 * math.cos(phi))  # kappa d = 2/R - 2 cos(phi)


@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("phi", [0.0, 0.5])
def test_elliptic_and_hyperbolic_on_either_side_of_threshold(gamma, phi):
    """Perturbed by 1e-6, elliptic orbits stay close for 1000 collisions; hyperbolic ones leave."""
    perturbation = 1e-6 * np.array([1.0, 0.7, -0.4])
    for factor, elliptic in [(0.8, True), (0.5, True), (1.25, False), (1.6, False)]:
        R = _radius_at(factor, phi, gamma)
        if not R < 0.999:  # disks must not touch (small gamma: the threshold is tiny)
            continue
        d = DISTANCE - 2 * R * math.cos(phi)
        assert (abs(two_disk_eigen_sum(1 / R, d, phi, gamma)) < 2) == elliptic
        scene = tables.two_disks(R, distance=DISTANCE, gamma=gamma)
        a0 = periodic_reduced_state(phi, gamma)
        ds = run_from_left_disk(scene, a0 + perturbation, R, 1000)
        on_left = ds.element.values == 0
        alpha = np.arctan2(ds.y.values[on_left], ds.x.values[on_left] + DISTANCE / 2)
        if elliptic:
            assert ds.attrs["stop_reason"] == "max_collisions"
            assert np.array_equal(ds.element.values, (np.arange(1000) + 1) % 2)  # 1, 0, 1, 0, ...
            assert np.abs(alpha - phi).max() < 1e-3
        else:
            # it leaves the orbit: escapes the open table or wanders far from the collision point
            left = ds.attrs["stop_reason"] == "escape" or np.abs(alpha - phi).max() > 0.1
            assert left, (factor, ds.attrs["stop_reason"], np.abs(alpha - phi).max())
            if gamma <= 1.0:
                assert ds.attrs["stop_reason"] == "escape" and int(ds.n_collisions) < 1000
