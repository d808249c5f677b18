"""Theorem 1 (no-slip bouncing ball) with the float engine: periodicity and drift (docs/conventions.md)."""
import math

import numpy as np
import pytest
from conftest import GAMMAS

from noslipsim import simulate, tables


def drift_formula(u, vx, w, gamma, g):
    return 4.0 * u * (vx - gamma * w) / (g * (1.0 + gamma ** 2))


@pytest.mark.parametrize("gamma", GAMMAS)
@pytest.mark.parametrize("g", [1e-12, 1.0, 9.81, 1e6])
def test_drift_per_two_bounces(gamma, g):
    scene = tables.half_plane(gamma=gamma, gravity=g)
    ds = simulate(scene, (0.0, 1.0), (0.37, 0.2), spin=-0.25, max_collisions=40)
    u = abs(float(ds.vy_in[0]))
    vx, w = float(ds.vx[0]), float(ds.spin[0])
    D = drift_formula(u, vx, w, gamma, g)
    x = ds.x.values
    np.testing.assert_allclose(x[2::2] - x[:-2:2], D, rtol=1e-9, atol=1e-12 * abs(x).max())
    # velocities are 2-periodic
    for name in ("vx", "vy", "spin"):
        np.testing.assert_allclose(ds[name].values[2:], ds[name].values[:-2], rtol=1e-12, atol=1e-15)
    # v_x - gamma w is the same on every flight
    np.testing.assert_allclose(ds.vx.values - gamma * ds.spin.values, vx - gamma * w, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("gamma", [g for g in GAMMAS if g > 0])
def test_two_periodic_iff_vx_equals_gamma_w(gamma):
    scene = tables.half_plane(gamma=gamma)
    # choose the post-collision state directly: v_x = gamma w on a flight from the floor
    w = 0.3
    start = simulate(scene, (0.0, 1.0), (gamma * w, 0.0), spin=w, max_collisions=1)
    vx, w1 = float(start.vx[0]), float(start.spin[0])
    assert vx == pytest.approx(gamma * w1, rel=1e-12, abs=1e-15)  # the ratio survives the bounce
    ds = simulate(scene, (0.0, 1.0), (gamma * w, 0.0), spin=w, max_collisions=20)
    np.testing.assert_allclose(ds.x.values[2:], ds.x.values[:-2], atol=1e-12)
    off = simulate(scene, (0.0, 1.0), (gamma * w + 1e-3, 0.0), spin=w, max_collisions=21)
    u = abs(float(off.vy_in[0]))
    D = drift_formula(u, float(off.vx[0]), float(off.spin[0]), gamma, 1.0)
    assert D != 0.0
    assert float(off.x[-1] - off.x[0]) == pytest.approx(10 * D, rel=1e-8)


def test_no_slip_gamma_zero_matches_specular_drift():
    ds = simulate(tables.half_plane(gamma=0.0), (0.0, 1.0), (0.5, 0.0), spin=0.0, max_collisions=4)
    u = math.sqrt(2.0)
    assert float(ds.x[2] - ds.x[0]) == pytest.approx(drift_formula(u, 0.5, 0.0, 0.0, 1.0), rel=1e-14)
