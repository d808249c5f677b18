"""The orbit experiments of Figures 1, 4, 5, 6, 8 and 16 against theorems and hand computations."""
import math

import numpy as np
import pytest

from noslipsim import theory
from noslipsim.analysis import bounce_orbit
from noslipsim.experiments import (
    bounce_orbits,
    newwedge_orbits,
    pentagon_orbits,
    specular_noslip_orbits,
    sphere_bounce,
    two_disk_box_orbits,
)

G = 1 / math.sqrt(2)
#: Rounding slack of a few flights (lengths and speeds of order 1).
TOL = 1e-10


# ---------------------------------------------------------------- Figure 1
def test_specular_and_noslip_orbits_agree_until_the_scatterer_and_part_there():
    ds = specular_noslip_orbits(max_collisions=6)
    spec, ns_ = ds.isel(orbit=0), ds.isel(orbit=1)
    assert list(ds.role.values) == ["specular", "no-slip"]
    k = int(spec.scatterer_collision)
    assert k == int(ns_.scatterer_collision) == 0          # the default start flies straight at the disk
    assert float(spec.x[0]) == float(ns_.x[0]) and float(spec.y[0]) == float(ns_.y[0])
    # specular: the mirror image of the incoming velocity in the disk's normal, spin kept
    cx, cy, _ = ds.attrs["disk"]
    n = np.array([float(spec.x[0]) - cx, float(spec.y[0]) - cy])
    n /= np.hypot(*n)
    v_in = np.array([math.cos(math.radians(12.5)), math.sin(math.radians(12.5))])
    v_out = v_in - 2 * (v_in @ n) * n
    np.testing.assert_allclose([float(spec.vx[0]), float(spec.vy[0])], v_out, atol=TOL)
    assert np.allclose(spec.spin.values[:6], 0.6)
    want = math.degrees(math.atan2(abs(v_out[0]), abs(v_out[1])))
    assert float(spec.exit_from_vertical) == pytest.approx(want)
    # no-slip: the contact velocity v_t + w / gamma is reversed at the scatterer (t = J n_out, n_out = -n)
    t = np.array([n[1], -n[0]])
    before = v_in @ t + 0.6 / G
    after = np.array([float(ns_.vx[0]), float(ns_.vy[0])]) @ t + float(ns_.spin[0]) / G
    assert after == pytest.approx(-before)
    # the caption's claims hold for the configured start
    assert float(spec.exit_from_vertical) < 5.0 and float(ns_.exit_to_corner) < 5.0
    assert float(ns_.exit_from_vertical) > 45.0 and float(spec.exit_to_corner) > 45.0


def test_missing_scatterer_is_recorded_as_none():
    ds = specular_noslip_orbits(angle=90.0, max_collisions=1)   # straight up: hits the top first
    assert (ds.scatterer_collision.values == -1).all() and np.isnan(ds.exit_to_corner.values).all()
    with pytest.raises(ValueError, match="max_collisions"):
        specular_noslip_orbits(max_collisions=0)


# ---------------------------------------------------------------- Figure 4
def test_pentagon_periodic_orbit_closes_and_the_corridor_is_narrow():
    ds = pentagon_orbits(n_generic=20, n_corridor=140, perturbation=0.01)
    p = int(ds.attrs["period"])
    assert list(ds.role.values) == ["specular regular", "specular irregular", "no-slip corridor", "no-slip periodic"]
    assert str(ds.periodic_kind.values) == "elliptic" and float(ds.periodic_residual) <= 1e-12
    ev = ds.eigenvalue_real.values + 1j * ds.eigenvalue_imag.values
    np.testing.assert_allclose(np.abs(ev), 1.0, atol=1e-6)
    assert float(ds.rotation_angle) == pytest.approx(1.2222, abs=1e-3)   # docs/analysis.md
    # the periodic row holds one period; the corridor orbit's unperturbed twin repeats after it
    periodic = ds.isel(orbit=3)
    assert int(periodic.n_collisions) == p and np.isnan(periodic.x.values[p:]).all()
    # the corridor orbit has the periodic orbit's energy (the velocity was only turned)
    corridor = ds.isel(orbit=2)
    assert float(corridor.energy[0]) == pytest.approx(float(periodic.energy[0]), rel=1e-12)
    assert 0.0 < float(ds.corridor_width) < 0.1
    wider = pentagon_orbits(n_generic=5, n_corridor=140, perturbation=0.03)
    assert float(wider.corridor_width) > float(ds.corridor_width)
    assert (ds.law.values[:2] == "specular").all() and (ds.law.values[2:] == "no-slip").all()


def test_pentagon_guess_that_does_not_converge_is_an_error():
    with pytest.raises(ValueError, match="guess"):
        pentagon_orbits(n_generic=5, n_corridor=5, period=3, guess_position=(0.1, 0.2),
                        guess_velocity=(0.3, 0.9), guess_spin=0.7)
    with pytest.raises(ValueError, match="irregular_vertices"):
        pentagon_orbits(irregular_vertices=[(0, 0), (1, 0), (0, 1)])


# ---------------------------------------------------------------- Figure 5
@pytest.mark.parametrize("ratio", [1.0, 0.7, 0.2, 0.0, 1.6, -0.5])
def test_bounce_drift_is_theorem_1s(ratio):
    vx, u, g = 0.37, 1.3, 2.0
    ds = bounce_orbits([{"vx": vx, "u": u, "spin_ratio": ratio}], gravity=g, n_bounces=9)
    o = ds.isel(orbit=0)
    want = float(theory.half_plane_drift(vx, ratio * vx / G, u, G, g))
    assert float(o.drift) == pytest.approx(want, abs=TOL)
    assert float(o.drift_spread) < TOL                       # the same every two bounces
    assert int(o.back_and_forth) == (ratio > (1 - G * G) / 2)


def test_bounce_two_periodic_case_is_the_theorem_orbit():
    ds = bounce_orbits([{"vx": 0.5, "u": 1.0, "spin_ratio": 1.0}], n_bounces=4)
    _, state = bounce_orbit(0.5, 1.0, G)
    o = ds.isel(orbit=0)
    assert (float(o.x_start), float(o.y_start)) == state["position"]
    assert float(o.spin_start) == pytest.approx(state["spin"], rel=1e-15)
    np.testing.assert_allclose(o.x.values, [0.5, -0.5, 0.5, -0.5], atol=TOL)
    for bad in ([], [{"vx": 1.0, "u": 1.0}], [{"vx": 1.0, "u": 0.0, "spin_ratio": 1.0}]):
        with pytest.raises(ValueError, match="cases"):
            bounce_orbits(bad)
    with pytest.raises(ValueError, match="gamma"):
        bounce_orbits(gamma=0.0)
    with pytest.raises(ValueError, match="n_bounces"):
        bounce_orbits(n_bounces=2)


# ---------------------------------------------------------------- Figure 6
def test_newwedge_geometry_matches_the_orbits():
    ds = newwedge_orbits()
    for i in range(2):
        o = ds.isel(orbit=i)
        q0 = np.array([float(o.q0_x), float(o.q0_y)])
        q1 = np.array([float(o.q1_x), float(o.q1_y)])
        vertex = np.array([float(o.vertex_x), float(o.vertex_y)])
        # collision 0 is q1, collision 1 is q0, then the path reverses (2-periodic)
        np.testing.assert_allclose([float(o.x[0]), float(o.y[0])], q1, atol=TOL)
        np.testing.assert_allclose([float(o.x[1]), float(o.y[1])], q0, atol=TOL)
        np.testing.assert_allclose(o.x.values[2:4], o.x.values[0:2], atol=TOL)
        # the launch angle at q0 above the chord, and the wall's angle from the bisector
        assert math.atan2(float(o.vy[1]), float(o.vx[1])) == pytest.approx(float(o.theta))
        wall = q0 - vertex
        assert math.atan2(-wall[0], wall[1]) == pytest.approx(float(o.phi))
    # the tangential wedge: its walls are tangent to the disks at q0 and q1
    o = ds.isel(orbit=1)
    q0 = np.array([float(o.q0_x), float(o.q0_y)])
    radius = q0 - np.array([-1.0, 0.0])
    assert np.hypot(*radius) == pytest.approx(ds.attrs["disk_radius"])
    assert (q0 - [float(o.vertex_x), float(o.vertex_y)]) @ radius == pytest.approx(0.0, abs=TOL)


# ---------------------------------------------------------------- Figure 8
def test_two_disks_in_a_box_noslip_stays_specular_scatters():
    ds = two_disk_box_orbits(n_specular=40, n_noslip=400)
    assert str(ds.kind.values) == "elliptic"
    assert float(ds.eigen_sum) == pytest.approx(float(ds.eigen_sum_theory), abs=1e-9)
    spec, ns_ = ds.isel(orbit=0), ds.isel(orbit=1)
    assert int(ns_.box_collisions) == 0 and int(spec.box_collisions) > 0
    n = int(ns_.n_collisions)
    assert n == 400 and np.all(np.abs(ns_.x.values[:n]) < 1.0)           # between the disk centres
    assert int(spec.n_collisions) == 40 and np.isnan(spec.x.values[40:]).all()
    # the same start for both laws
    assert float(spec.vx_start) == float(ns_.vx_start) and float(spec.spin_start) == float(ns_.spin_start)
    with pytest.raises(ValueError, match="box"):
        two_disk_box_orbits(box=(3.0, 3.0))


def test_two_disks_hyperbolic_start_is_recorded():
    ds = two_disk_box_orbits(radius=0.5, phi=0.4, n_specular=2, n_noslip=2)
    assert str(ds.kind.values) == "hyperbolic"                          # kappa d above the threshold
    assert float(ds.eigen_sum) > 2.0


# ---------------------------------------------------------------- Figure 16
def test_sphere_drift_is_the_formula_and_e2_is_two_periodic():
    ds = sphere_bounce(n_bounces=9)
    np.testing.assert_allclose(ds.drift.values, ds.drift_theory.values, atol=TOL)
    assert float(ds.drift_error) < TOL
    e1, e2 = ds.e1.values, ds.e2.values
    assert e1 @ e2 == pytest.approx(0.0, abs=1e-15) and np.hypot(*e1[:2]) == pytest.approx(1.0)
    assert e1[2] == e2[2] == 0.0
    np.testing.assert_allclose(ds.along_e2.values[2:], ds.along_e2.values[:-2], atol=TOL)
    # the formula by hand: k = v_T - gamma n x W_T, u from the start's height
    g2 = 0.4
    k = np.array([0.28 + math.sqrt(g2) * -0.25, 0.51 - math.sqrt(g2) * 0.7])
    u = math.sqrt(2 * 0.5)
    np.testing.assert_allclose(ds.drift_theory.values[:2], 4 * u * k / (1 + g2), rtol=1e-12)


def test_sphere_in_a_plane_is_the_planar_bounce():
    # motion in the x-z plane with W = (0, -w, 0) is the planar ball with spin w
    vx, w, u = 0.5, 0.3, 1.0
    ds = sphere_bounce(position=(0.0, 0.0, 0.5), velocity=(vx, 0.0, 0.0), spin=(0.0, -w, 0.0), gamma=G)
    planar = bounce_orbits([{"vx": vx, "u": u, "spin_ratio": G * w / vx}], n_bounces=12)
    np.testing.assert_allclose(ds.drift.values[0], float(planar.drift[0]), atol=TOL)
    np.testing.assert_allclose(ds.position.values[:, 0], planar.x.values[0], atol=TOL)
    with pytest.raises(ValueError, match="2-periodic"):
        sphere_bounce(velocity=(vx, 0.0, 0.0), spin=(0.0, -vx / G, 0.0), gamma=G)
