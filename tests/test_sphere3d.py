"""Rough sphere bouncing on a plane (the paper's 3D bouncing figure; docs/conventions.md).

Oracles: the impulse form of the no-slip law (slow twin), Theorem 1 in vector
form, and the planar engine for motions confined to the x-z plane.
"""
import math

import numpy as np
import pytest

from noslipsim import simulate, tables
from noslipsim.core import sphere3d as kernel
from noslipsim.core.laws import noslip_coefficients
from noslipsim.sphere3d import UNIFORM_BALL, simulate_sphere

GAMMAS_3D = [0.3, UNIFORM_BALL, 1 / math.sqrt(2), 1.0, 3.0]
N = np.array([0.0, 0.0, 1.0])  # plane normal, towards the sphere


def random_start(rng):
    q = np.array([*rng.normal(size=2), rng.uniform(0.1, 2.0)])
    return q, rng.normal(size=3), rng.normal(size=3)


def sigma(W):
    """``n x W_T`` for the plane z = 0."""
    return np.cross(N, W * np.array([1.0, 1.0, 0.0]))


def tangential(v):
    return v * np.array([1.0, 1.0, 0.0])


# ------------------------------------------------------------------ slow twin
def naive_bounce(v, W, gamma):
    """Impulse at the contact point ``r = -R n`` (R = m = 1, I = gamma^2) reversing the contact velocity.

    Solves ``u(P) = -u`` with ``u = v + omega x r`` for the impulse ``P``: no
    frame, no sigma, just momentum and angular momentum bookkeeping.
    """
    inertia = gamma * gamma
    r = -N
    omega = W / gamma

    def contact(v_, omega_):
        return v_ + np.cross(omega_, r)

    u = contact(v, omega)
    M = np.empty((3, 3))
    for j in range(3):
        P = np.eye(3)[j]
        M[:, j] = contact(v + P, omega + np.cross(r, P) / inertia) - u
    P = np.linalg.solve(M, -2.0 * u)
    return v + P, gamma * (omega + np.cross(r, P) / inertia)


def naive_orbit(q, v, W, gamma, g, n):
    q, v, W = (np.array(a, float) for a in (q, v, W))
    t, rows = 0.0, []
    for _ in range(n):
        dt = (v[2] + math.sqrt(v[2] ** 2 + 2 * g * q[2])) / g
        q = q + v * dt + 0.5 * np.array([0, 0, -g]) * dt ** 2
        v = v + np.array([0, 0, -g]) * dt
        t += dt
        q[2] = 0.0
        v, W = naive_bounce(v, W, gamma)
        rows.append((t, q.copy(), v.copy(), W.copy()))
    return rows


@pytest.mark.parametrize("gamma", GAMMAS_3D)
def test_kernel_matches_impulse_twin(gamma, rng):
    for _ in range(20):
        q, v, W = random_start(rng)
        ds = simulate_sphere(q, v, W, gamma=gamma, gravity=1.3, n_bounces=6)
        for k, (t, qk, vk, Wk) in enumerate(naive_orbit(q, v, W, gamma, 1.3, 6)):
            scale = 1 + np.abs(qk).max() + np.abs(vk).max() + np.abs(Wk).max()
            assert float(ds.time[k]) == pytest.approx(t, rel=1e-12)
            np.testing.assert_allclose(ds.position[k], qk, rtol=0, atol=1e-12 * scale)
            np.testing.assert_allclose(ds.velocity[k], vk, rtol=0, atol=1e-12 * scale)
            np.testing.assert_allclose(ds.spin[k], Wk, rtol=0, atol=1e-12 * scale)


def test_single_bounce_kernel_against_twin(rng):
    for gamma in GAMMAS_3D:
        c, s = noslip_coefficients(gamma)
        for _ in range(50):
            v, W = rng.normal(size=3), rng.normal(size=3)
            v[2] = -abs(v[2])
            out = np.array(kernel.bounce(c, s, *v, *W))
            v2, W2 = naive_bounce(v, W, gamma)
            np.testing.assert_allclose(out, np.r_[v2, W2], rtol=0, atol=1e-13 * (1 + abs(W).max() / gamma))


def test_sign_pinned_ball_moving_in_x_gets_forward_roll_spin():
    # A non-spinning ball moving in +x leaves spinning like a ball rolling in +x:
    # omega along +y (v + omega x (-R e_z) = 0 for rolling); in the planar x-z
    # picture that is clockwise, the planar w+ = -s v_x < 0 with W = (0, -w, 0).
    ds = simulate_sphere([0, 0, 1], [1.0, 0, 0], [0, 0, 0], gamma=UNIFORM_BALL, n_bounces=1)
    c, s = noslip_coefficients(UNIFORM_BALL)
    np.testing.assert_allclose(ds.spin[0], [0.0, s, 0.0], atol=1e-15)  # planar w+ = -s v_x, W_y = -w
    assert float(ds.velocity[0, 0]) == pytest.approx(c)


# ------------------------------------------------------------------ Theorem 1 in 3D
@pytest.mark.parametrize("gamma", GAMMAS_3D)
def test_drift_per_two_bounces_vector_form(gamma, rng):
    g = 0.8
    for _ in range(20):
        q, v, W = random_start(rng)
        ds = simulate_sphere(q, v, W, gamma=gamma, gravity=g, n_bounces=9)
        pos, vel, spin = ds.position.values, ds.velocity.values, ds.spin.values
        u = vel[0, 2]
        k0 = tangential(vel[0]) - gamma * sigma(spin[0])  # the same on every flight
        for k in range(9):
            np.testing.assert_allclose(tangential(vel[k]) - gamma * sigma(spin[k]), k0, rtol=0,
                                       atol=1e-13 * (1 + gamma) * (1 + np.abs(spin).max()))
        D = 4 * u * k0 / (g * (1 + gamma ** 2))
        for k in range(7):
            np.testing.assert_allclose(pos[k + 2] - pos[k], D, rtol=0,
                                       atol=1e-12 * (1 + np.abs(pos).max()))
        # the paper's picture: no motion across the drift direction from bounce to bounce+2
        e2 = np.cross(N, D) / np.linalg.norm(D)
        assert np.ptp(pos[::2] @ e2) < 1e-11 * (1 + np.abs(pos).max())


@pytest.mark.parametrize("gamma", GAMMAS_3D)
def test_two_periodic_iff_rolling_condition(gamma, rng):
    for _ in range(10):
        q, v, W = random_start(rng)
        # choose W_T with v_T = gamma n x W_T  <=>  W_T = (v_y, -v_x) / gamma; keep W_z
        W_per = np.array([v[1] / gamma, -v[0] / gamma, W[2]])
        ds = simulate_sphere(q, v, W_per, gamma=gamma, n_bounces=8)
        for name in ("position", "velocity", "spin"):
            a = ds[name].values
            np.testing.assert_allclose(a[2:], a[:-2], rtol=0, atol=1e-12 * (1 + np.abs(a).max()))
        # any other tangential spin drifts (by exactly the drift formula, checked above)
        ds = simulate_sphere(q, v, W_per + np.array([1e-3, 0, 0]), gamma=gamma, n_bounces=4)
        pos = ds.position.values
        assert np.linalg.norm(pos[2] - pos[0]) > 1e-5


@pytest.mark.parametrize("gamma", GAMMAS_3D)
def test_velocity_and_spin_always_two_periodic(gamma, rng):
    for _ in range(10):
        q, v, W = random_start(rng)
        ds = simulate_sphere(q, v, W, gamma=gamma, n_bounces=8)
        for name in ("velocity", "spin", "velocity_in", "spin_in"):
            a = ds[name].values
            np.testing.assert_allclose(a[2:], a[:-2], rtol=0, atol=1e-13 * (1 + np.abs(a).max()))
        # flight times are all 2 u / g after the first
        t = ds.time.values
        np.testing.assert_allclose(np.diff(t), 2 * ds.velocity.values[:-1, 2], rtol=1e-14)


@pytest.mark.parametrize("gamma", [0.0, *GAMMAS_3D, 1e6])
def test_bounce_keeps_kinetic_energy_and_normal_spin(gamma, rng):
    for _ in range(20):
        q, v, W = random_start(rng)
        ds = simulate_sphere(q, v, W, gamma=gamma, gravity=2.0, n_bounces=5)
        e_in = (ds.velocity_in ** 2).sum("component") + (ds.spin_in ** 2).sum("component")
        e_out = (ds.velocity ** 2).sum("component") + (ds.spin ** 2).sum("component")
        np.testing.assert_allclose(e_out, e_in, rtol=1e-14)
        np.testing.assert_allclose(ds.spin.sel(component="z"), W[2], rtol=0, atol=0)
        np.testing.assert_allclose(ds.velocity.sel(component="z"), -ds.velocity_in.sel(component="z"), rtol=0, atol=0)
        # total energy |v|^2/2 + |W|^2/2 + g z is that of the start
        e0 = 0.5 * (v @ v + W @ W) + 2.0 * q[2]
        np.testing.assert_allclose(0.5 * e_out, e0, rtol=1e-13)


@pytest.mark.parametrize("gamma", GAMMAS_3D)
def test_contact_point_velocity_is_reversed(gamma, rng):
    # contact point q - R n: velocity v + omega x (-R n) = v + (n x W) / gamma
    for _ in range(20):
        q, v, W = random_start(rng)
        ds = simulate_sphere(q, v, W, gamma=gamma, n_bounces=4)
        for k in range(4):
            before = ds.velocity_in.values[k] + np.cross(N, ds.spin_in.values[k]) / gamma
            after = ds.velocity.values[k] + np.cross(N, ds.spin.values[k]) / gamma
            np.testing.assert_allclose(after, -before, rtol=0, atol=1e-13 * (1 + np.abs(before).max()))


# ------------------------------------------------------------------ reduction to the planar engine
@pytest.mark.parametrize("gamma", [0.3, 1 / math.sqrt(2), 1.0, 3.0])
def test_planar_motion_reproduces_the_2d_engine(gamma, rng):
    g = 1.7
    for _ in range(5):
        x, z = rng.normal(), rng.uniform(0.2, 2.0)
        vx, vz, w = rng.normal(size=3)
        n = 12
        ds3 = simulate_sphere([x, 0.0, z], [vx, 0.0, vz], [0.0, -w, 0.0], gamma=gamma, gravity=g, n_bounces=n)
        ds2 = simulate(tables.half_plane(gamma=gamma, gravity=g), (x, z), (vx, vz), w, max_collisions=n)
        assert ds2.sizes["collision"] == n
        pos, vel, spin = ds3.position.values, ds3.velocity.values, ds3.spin.values
        scale = 1 + np.abs(pos).max()
        np.testing.assert_allclose(ds3.time, ds2.t, rtol=1e-12)
        np.testing.assert_allclose(pos[:, 0], ds2.x, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(pos[:, 2], ds2.y, rtol=0, atol=1e-12)
        np.testing.assert_allclose(vel[:, 0], ds2.vx, rtol=0, atol=1e-12)
        np.testing.assert_allclose(vel[:, 2], ds2.vy, rtol=0, atol=1e-12)
        np.testing.assert_allclose(-spin[:, 1], ds2.spin, rtol=0, atol=1e-12)
        np.testing.assert_allclose(-ds3.spin_in.values[:, 1], ds2.spin_in, rtol=0, atol=1e-12)
        assert np.all(pos[:, 1] == 0) and np.all(vel[:, 1] == 0)
        assert np.all(spin[:, 0] == 0) and np.all(spin[:, 2] == 0)


# ------------------------------------------------------------------ dataset and validation
def test_dataset_layout_and_metadata():
    ds = simulate_sphere([0, 0, 1], [0.1, 0.2, 0.3], [0.3, -0.1, 0.2], n_bounces=3)
    assert dict(ds.sizes) == {"collision": 3, "component": 3}
    assert list(ds.component.values) == ["x", "y", "z"]
    assert set(ds.data_vars) == {"time", "position", "velocity", "spin", "velocity_in", "spin_in"}
    assert ds.time.dims == ("collision",)
    for name in ("position", "velocity", "spin", "velocity_in", "spin_in"):
        assert ds[name].dims == ("collision", "component")
    for name, var in ds.variables.items():
        assert var.attrs.get("long_name"), name
        assert var.attrs.get("units") == "1", name
    assert np.all(ds.position.sel(component="z") == 0.0)
    assert ds.attrs["gamma"] == UNIFORM_BALL
    assert simulate_sphere([0, 0, 1], [0, 0, 0], [0, 0, 0], n_bounces=0).sizes["collision"] == 0


@pytest.mark.parametrize("kwargs, field", [
    (dict(position=[0, 0, 0]), "position"),
    (dict(position=[0, 0, -1]), "position"),
    (dict(position=[0, np.nan, 1]), "position"),
    (dict(position=[0, 1]), "position"),
    (dict(velocity=[0, np.inf, 1]), "velocity"),
    (dict(velocity="fast"), "velocity"),
    (dict(spin=[0, 0]), "spin"),
    (dict(spin=[0, 0, np.nan]), "spin"),
    (dict(gamma=-0.1), "gamma"),
    (dict(gamma=np.nan), "gamma"),
    (dict(gravity=0.0), "gravity"),
    (dict(gravity=-1.0), "gravity"),
    (dict(gravity=np.inf), "gravity"),
    (dict(n_bounces=-1), "n_bounces"),
    (dict(n_bounces=2.5), "n_bounces"),
    (dict(n_bounces=True), "n_bounces"),
])
def test_invalid_inputs_name_the_field(kwargs, field):
    args = dict(position=[0, 0, 1], velocity=[0.1, 0.2, 0.3], spin=[0, 0, 0])
    args.update(kwargs)
    with pytest.raises(ValueError, match=f"^{field}"):
        simulate_sphere(**args)
