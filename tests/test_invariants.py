"""No leak, energy conservation and reversibility over long orbits in every table family.

10^5 collisions per family here; the stress profile (tests/test_stress.py, ``-m stress``) runs the
same checks over 10^8 (benchmarks/results/stress.md).
"""

import numpy as np
import pytest
from invariants import FAMILIES, leak_depth, on_element_error, relative_energy_drift

from noslipsim import simulate, tables
from noslipsim.core.tolerances import CONTACT_TOL

N_LONG = 100_000
#: Tolerances (relative to the scene size): float64 positions are exact to a few ulps.
ON_ELEMENT_TOL = 1e-12
LEAK_TOL = 1e-12


@pytest.fixture(scope="module", params=sorted(FAMILIES))
def long_orbit(request):
    make, q, v, w = FAMILIES[request.param]
    scene = make()
    return request.param, scene, simulate(scene, q, v, w, max_collisions=N_LONG)


def test_orbit_runs_to_the_end(long_orbit):
    name, _scene, ds = long_orbit
    assert ds.attrs["stop_reason"] == "max_collisions", name
    assert int(ds.n_collisions) == N_LONG


def test_collisions_lie_on_their_elements(long_orbit):
    name, scene, ds = long_orbit
    assert on_element_error(scene, ds) <= ON_ELEMENT_TOL, name


def test_flights_stay_inside_the_table(long_orbit):
    name, scene, ds = long_orbit
    assert leak_depth(scene, ds) >= -LEAK_TOL, name


def test_energy_drift_over_the_orbit(long_orbit):
    name, _scene, ds = long_orbit
    drift = relative_energy_drift(ds)
    print(f"{name}: relative energy drift over {N_LONG} collisions = {drift:.2e}")
    assert drift < 1e-10, name


@pytest.mark.parametrize("name", ["pentagon", "pentagon_gravity", "wedge_gravity", "circle_container_gravity"])
def test_reversibility(name):
    """Reverse v and w mid-flight after many collisions: the orbit retraces itself to the start."""
    make, q, v, w = FAMILIES[name]
    scene = make()
    fwd = simulate(scene, q, v, w, max_collisions=10**6, max_time=40.3)
    assert fwd.attrs["stop_reason"] == "max_time"
    back = simulate(scene, (float(fwd.x_final), float(fwd.y_final)),
                    (-float(fwd.vx_final), -float(fwd.vy_final)), -float(fwd.spin_final),
                    max_collisions=10**6, max_time=40.3)
    assert int(back.n_collisions) == int(fwd.n_collisions)
    np.testing.assert_array_equal(back.element.values, fwd.element.values[::-1])
    np.testing.assert_allclose([back.x_final, back.y_final], q, atol=1e-8)
    np.testing.assert_allclose([-back.vx_final, -back.vy_final, -back.spin_final], [*v, w], atol=1e-8)


def test_ball_bounces_on_a_peg_twice_in_a_row():
    """A ball dropped on a circular peg off-centre hits the same peg again after a hop."""
    scene = tables.Scene([tables.Circle((0.0, 0.0), 1.0, "outside")], force=(0.0, -1.0))
    ds = simulate(scene, (0.05, 1.5), (0.0, 0.0), 0.0, max_collisions=5)
    assert list(ds.element.values[:2]) == [0, 0]
    assert float(ds.t[1] - ds.t[0]) > 0.1


def test_corner_rule_right_angle_reverses_velocity():
    box = tables.rectangle(1.0, 1.0)
    ds = simulate(box.replace(law="specular"), (0.5, 0.5), (1.0, 1.0), 0.0, max_collisions=2)
    assert list(ds.corner.values) == [0, 1]
    np.testing.assert_allclose([ds.vx[-1], ds.vy[-1]], [-1.0, -1.0], atol=1e-15)
    np.testing.assert_allclose([ds.x[-1], ds.y[-1]], [1.0, 1.0], atol=1e-15)


@pytest.mark.parametrize("offset", [0.0, 1e-15, -1e-15, 1e-13, -1e-13, 1e-12])
@pytest.mark.parametrize("law", ["specular", "no-slip"])
def test_flights_at_polygon_vertices_never_leak(offset, law):
    for n in (3, 4, 5, 7):
        poly = tables.regular_polygon(n, law=law)
        v0 = np.array(poly.elements[0].p1)
        start = np.array([0.0, 0.0])
        d = v0 - start + offset * np.array([1.0, -1.0])
        ds = simulate(poly, start, d, 0.3, max_collisions=2000)
        assert ds.attrs["stop_reason"] == "max_collisions"
        assert leak_depth(poly, ds) >= -LEAK_TOL
        assert on_element_error(poly, ds) <= ON_ELEMENT_TOL
        assert on_element_error(poly, ds, corner=True) <= CONTACT_TOL


@pytest.mark.parametrize("size", [1e-6, 1.0, 1e6])
def test_scale_invariance(size):
    """A table scaled by L with force scaled by L (time unchanged) gives the orbit scaled by L."""
    base = tables.stadium(1.0, 1.0, force=(0.0, -1.0))
    scaled = tables.stadium(size, size, force=(0.0, -size))
    a = simulate(base, (0.1, 0.2), (0.6, 0.3), 0.1, max_collisions=30)
    b = simulate(scaled, (0.1 * size, 0.2 * size), (0.6 * size, 0.3 * size), 0.1 * size, max_collisions=30)
    # the stadium is chaotic: rounding differences grow, so positions are compared
    # over the first collisions and the element sequence over all of them
    np.testing.assert_array_equal(a.element.values, b.element.values)
    np.testing.assert_allclose(b.x.values[:12] / size, a.x.values[:12], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(b.t.values[:12], a.t.values[:12], rtol=1e-9)
