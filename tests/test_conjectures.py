"""The two conjecture experiments (Figures S4, S5): known answers on small cases, counts that add up."""
import math

import numpy as np
import pytest

from noslipsim import tables, theory
from noslipsim.analysis import find_periodic_orbit, two_disk_classes, wedge_orbit
from noslipsim.experiments import census_counts, launch_angle_classes, wedge_periodic_census
from noslipsim.experiments.conjectures import _cycle, _found_orbit, _same_cycle

GAMMA = 1 / math.sqrt(2)

#: The isolated period-5 wedge orbit of docs/analysis.md (half-angle 0.71953, gamma 0.3, g = 1).
PERIOD5 = dict(phi=0.71953, gamma=0.3, position=(-0.46, 1.811), velocity=(1.66, -0.505), spin=-1.158)


def test_a_tiny_launch_angle_gives_the_force_free_closed_form():
    """theta -> 0 is the force-free chord (scale invariance): lambda + 1/lambda of theory.two_disk_eigen_sum."""
    phis = np.array([0.2, 0.6, 1.0])
    for R in (0.3, 0.6, 0.9):
        kinds, es = two_disk_classes(R, [(p, 1e-7) for p in phis], GAMMA, gravity=1.0)
        expect = theory.two_disk_eigen_sum(1 / R, 2 - 2 * R * np.cos(phis), phis, GAMMA)
        np.testing.assert_allclose(es, expect, rtol=1e-5, atol=1e-5)
        thr = np.asarray(theory.ellipticity_threshold(phis, GAMMA))
        elliptic = (2 - 2 * R * np.cos(phis)) / R < thr
        assert list(kinds) == ["elliptic" if e else "hyperbolic" for e in elliptic]


def test_a_combination_without_orbit_is_counted_not_raised():
    kinds, es = two_disk_classes(0.5, [(0.3, 0.2), (-1.0, 0.2)], GAMMA, gravity=1.0)  # phi < 0: no such orbit
    assert kinds[0] in ("elliptic", "hyperbolic") and kinds[1] == "" and np.isnan(es[1])


def test_the_measured_boundary_meets_the_closed_form_as_theta_goes_to_zero():
    radii = np.linspace(0.3, 0.95, 66)
    phis = np.array([0.2, 0.5, 0.8])
    ds = launch_angle_classes(radii, phis, [1e-6, 0.5], GAMMA, gravity=1.0)
    step = radii[1] - radii[0]
    assert np.abs(ds.radius_shift.sel(theta=1e-6).values).max() < 0.1 * step   # interpolation error only
    # at theta = 0.5 the force moves the boundary: the launch angle alone changes the class in some columns
    assert np.nanmax(ds.radius_shift.sel(theta=0.5).values) > 5 * step
    changes = ds.class_changes.values.astype(bool)
    assert changes.any() and not changes.all()
    kinds = ds.linear_kind.values
    np.testing.assert_array_equal(changes, kinds[..., 0] != kinds[..., 1])
    assert ds.attrs["n_changing"] == changes.sum() and ds.attrs["n_columns"] == changes.size
    # both launch angles lie below the parabolic line theta = pi/2 - phi: the same count there
    np.testing.assert_array_equal(ds.elliptic_hyperbolic_below.values, ds.elliptic_hyperbolic.values)
    assert ds.attrs["n_above"] == 0


def test_above_the_parabolic_line_the_orbits_are_hyperbolic():
    """Launched above the tangent at q1 (theta > pi/2 - phi) the orbits we classify are hyperbolic, elliptic below."""
    ds = launch_angle_classes([0.9], [0.8], [0.3, 0.6, 0.9, 1.2], GAMMA, gravity=1.0)
    assert list(ds.linear_kind.values[0, 0]) == ["elliptic", "elliptic", "hyperbolic", "hyperbolic"]
    assert (ds.attrs["n_above"], ds.attrs["n_above_hyperbolic"]) == (2, 2)
    assert ds.attrs["n_changing"] == 1 and ds.attrs["n_changing_below"] == 0 and ds.attrs["n_columns_below"] == 1


def test_launch_angle_classes_refuses_bad_axes():
    with pytest.raises(ValueError, match="radii"):
        launch_angle_classes([0.5, 1.2], [0.3], [0.3])
    with pytest.raises(ValueError, match="thetas"):
        launch_angle_classes([0.5], [0.3], [0.3, 0.2])
    with pytest.raises(ValueError, match="gravity"):
        launch_angle_classes([0.5], [0.3], [0.3], gravity=0.0)


def test_the_period5_orbit_is_isolated_and_a_path_reversing_orbit_is_on_a_family():
    scene = tables.wedge(PERIOD5["phi"], gamma=PERIOD5["gamma"], force=(0.0, -1.0))
    res = find_periodic_orbit(scene, PERIOD5["position"], PERIOD5["velocity"], PERIOD5["spin"], period=5)
    assert res.converged
    facts = _found_orbit(scene, res.state, 5)
    assert facts["minimal_period"] == 5 and facts["isolated"] == 1 and facts["unit_count"] == 0
    assert len(facts["itinerary"]) == 5 and set(facts["itinerary"]) == {"L", "R"}
    # found as period 10, it is still counted at its minimal period 5
    assert _found_orbit(scene, res.state, 10)["minimal_period"] == 5
    scene2, state = wedge_orbit(0.6, 0.3, 1.0, GAMMA, gravity=1.0)
    facts2 = _found_orbit(scene2, state, 2)
    assert facts2["minimal_period"] == 2 and facts2["isolated"] == 0 and facts2["unit_count"] >= 1


def test_one_orbit_is_one_orbit_whatever_its_scale_and_starting_point():
    scene, state = wedge_orbit(0.6, 0.3, 1.0, GAMMA, gravity=1.0)
    c = 1.7   # the wedge under a force is scale invariant: q -> c^2 q, v -> c v, w -> c w
    scaled = {"position": tuple(c * c * x for x in state["position"]),
              "velocity": tuple(c * v for v in state["velocity"]), "spin": c * state["spin"]}
    _, _, a = _cycle(scene, state, 2)
    _, _, b = _cycle(scene, scaled, 2)
    assert _same_cycle(a, b) and _same_cycle(a, np.roll(a, 1, axis=0))
    _, _, other = _cycle(*wedge_orbit(0.6, 0.5, 1.0, GAMMA, gravity=1.0), 2)
    assert not _same_cycle(a, other)


def test_the_census_counts_every_search_and_repeats_itself():
    kw = dict(starts=3, seed=1)
    ds = wedge_periodic_census([0.6], [0.0, 0.2], [2, 3], GAMMA, **kw)
    counts = census_counts(ds)
    assert ds.sizes["search"] == 2 * 2 * 3 == int(counts.searches.sum())
    found = ds.outcome.values == "found"
    assert ((ds.minimal_period.values > 0) == found).all() and ((ds.isolated.values >= 0) == found).all()
    assert (counts.isolated + counts.family == counts.distinct).all()
    assert int(counts.distinct.sum()) <= int(found.sum())
    assert set(ds.outcome.values) <= {"found", "not converged", "no return"}
    again = wedge_periodic_census([0.6], [0.0, 0.2], [2, 3], GAMMA, scheduler="threads", num_workers=2, **kw)
    for name in ("outcome", "minimal_period", "isolated", "distinct", "itinerary"):
        np.testing.assert_array_equal(again[name].values, ds[name].values)


def test_the_census_refuses_bad_input():
    with pytest.raises(ValueError, match="phis"):
        wedge_periodic_census([1.7], [0.0], [2])
    with pytest.raises(ValueError, match="periods"):
        wedge_periodic_census([0.6], [0.0], [0])
