"""The collision laws: sign convention, invariants and special cases (docs/conventions.md)."""
import math

import numpy as np
import pytest
from conftest import GAMMAS

from noslipsim import Scene, simulate, tables
from noslipsim.core.laws import collide, noslip_coefficients
from noslipsim.core.layout import NOSLIP, SPECULAR


def frame(n):
    n = np.asarray(n, float) / np.linalg.norm(n)
    return n, np.array([-n[1], n[0]])


def random_cases(rng, k=200):
    for _ in range(k):
        ang = rng.uniform(0, 2 * math.pi)
        yield np.array([math.cos(ang), math.sin(ang)]), rng.normal(size=2), rng.normal()


@pytest.mark.parametrize("gamma", [g for g in GAMMAS if g > 0])
def test_contact_point_velocity_is_reversed(gamma, rng):
    c, s = noslip_coefficients(gamma)
    for n, v, w in random_cases(rng):
        n_, t = frame(n)
        vx, vy, w2 = collide(NOSLIP, c, s, v[0], v[1], w, n_[0], n_[1])
        before = v @ t + w / gamma
        after = np.array([vx, vy]) @ t + w2 / gamma
        assert after == pytest.approx(-before, rel=1e-12, abs=1e-12 * (1 + abs(w) / gamma))
        assert np.array([vx, vy]) @ n_ == pytest.approx(-(v @ n_), abs=1e-14)


@pytest.mark.parametrize("gamma", GAMMAS)
def test_noslip_is_an_involution_and_keeps_energy(gamma, rng):
    c, s = noslip_coefficients(gamma)
    for n, v, w in random_cases(rng):
        once = collide(NOSLIP, c, s, v[0], v[1], w, n[0], n[1])
        twice = collide(NOSLIP, c, s, *once, n[0], n[1])
        np.testing.assert_allclose(twice, (v[0], v[1], w), rtol=0, atol=1e-14 * (1 + abs(w) + abs(v).max()))
        e0 = v @ v + w * w
        e1 = once[0] ** 2 + once[1] ** 2 + once[2] ** 2
        assert e1 == pytest.approx(e0, rel=1e-14)


def test_sign_pinned_ball_rolling_right_gets_clockwise_spin():
    # floor: table above, outward normal (0, -1), tangent J n = (1, 0)
    c, s = noslip_coefficients(1 / math.sqrt(2))
    vx, vy, w = collide(NOSLIP, c, s, 1.0, -1.0, 0.0, 0.0, -1.0)
    assert w < 0  # clockwise
    assert vy == 1.0
    assert vx == pytest.approx(c)  # v_t+ = c v_t
    assert w == pytest.approx(-s)  # w+ = -s v_t


def test_gamma_zero_reverses_spin_and_reflects_specularly(rng):
    c, s = noslip_coefficients(0.0)
    assert (c, s) == (1.0, 0.0)
    for n, v, w in random_cases(rng, 50):
        ns = collide(NOSLIP, c, s, v[0], v[1], w, n[0], n[1])
        sp = collide(SPECULAR, c, s, v[0], v[1], w, n[0], n[1])
        np.testing.assert_allclose(ns[:2], sp[:2], atol=1e-15)
        assert ns[2] == -w and sp[2] == w


def test_gamma_zero_orbit_has_the_specular_path():
    box = tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)])
    a = simulate(box.replace(gamma=0.0), (0.3, 0.5), (1.0, 0.37), spin=0.4, max_collisions=200)
    b = simulate(box.replace(law="specular"), (0.3, 0.5), (1.0, 0.37), spin=0.4, max_collisions=200)
    for name in ("t", "x", "y", "vx", "vy", "element"):
        np.testing.assert_array_equal(a[name].values, b[name].values)
    assert np.all(np.abs(a.spin.values) == 0.4)
    assert np.all(b.spin.values == 0.4)
    np.testing.assert_array_equal(a.spin.values[::2], -0.4 * np.ones(100))


def test_path_reversal_iff_vt_equals_gamma_w():
    gamma = 0.8
    c, s = noslip_coefficients(gamma)
    n = np.array([0.6, -0.8])
    _, t = frame(n)
    w = 0.7
    v = gamma * w * t + (-0.5) * (-n)  # v_t = gamma w, moving into the wall
    out = collide(NOSLIP, c, s, v[0], v[1], w, n[0], n[1])
    np.testing.assert_allclose(out, (-v[0], -v[1], -w), atol=1e-15)
    v2 = (gamma * w + 0.1) * t + 0.5 * n
    out2 = collide(NOSLIP, c, s, v2[0], v2[1], w, n[0], n[1])
    assert not np.allclose(out2, (-v2[0], -v2[1], -w), atol=1e-6)


def test_large_gamma_limit():
    c, s = noslip_coefficients(1e200)
    assert c == -1.0 and 0 < s < 1e-199
    c, s = noslip_coefficients(100.0)
    assert (c, s) == pytest.approx(((1 - 1e4) / (1 + 1e4), 200 / (1 + 1e4)), rel=1e-15)


def test_scene_rotation_coefficients_are_unit_to_the_last_bit():
    from fractions import Fraction
    for gamma in GAMMAS:
        c, s = Scene([tables.half_plane().elements[0]], gamma=gamma).noslip_coefficients
        assert abs(Fraction(c) ** 2 + Fraction(s) ** 2 - 1) < Fraction(1, 2 ** 52)
