"""Periodic-orbit finder (noslipsim.analysis.find_periodic_orbit): it finds the paper's orbits, and fails honestly.

Each found orbit is checked by the engine itself (ns.simulate from the returned state repeats after
``period`` collisions, over many periods when it is stable), by its minimal period, and by the
property the paper claims for it.  The starts below were found by a search from random starts
(seeded) and are recorded with the orbit they lead to.
"""
import math
import zlib

import numpy as np
import pytest

import noslipsim as ns
from noslipsim import tables
from noslipsim.analysis import (
    PeriodicOrbit,
    bounce_orbit,
    find_periodic_orbit,
    two_disk_orbit,
    wedge_noforce_orbit,
    wedge_orbit,
)

G = 1 / math.sqrt(2)


def states(scene, state, n):
    ds = ns.simulate(scene, **state, max_collisions=n)
    assert ds.attrs["stop_reason"] == "max_collisions"
    return ds, np.c_[ds.x, ds.y, ds.vx, ds.vy, ds.spin]


def period_drift(X, p):
    return np.abs(X[p:] - X[:-p]).max() / (1.0 + np.abs(X).max())


def minimal_period(X, p, tol=1e-8):
    return min(d for d in range(1, p + 1) if p % d == 0 and np.abs(X[d] - X[0]).max() < tol)


def impact_mismatch(scene, ds, k):
    """|v_t - gamma w| just before collision k (zero iff the impact reverses the path)."""
    n_out = -np.asarray(scene.elements[int(ds.element[k])].normal)
    t = np.array([-n_out[1], n_out[0]])
    vt = float(ds.vx_in[k]) * t[0] + float(ds.vy_in[k]) * t[1]
    return abs(vt - scene.gamma * float(ds.spin_in[k]))


# ----------------------------------------------------------------------------- the paper's orbits
def test_pentagon_14_periodic_orbit():
    """Paper, pentagon figure: a no-slip regular pentagon (gamma = 1/sqrt 2, no force) near a 14-periodic point.

    Start found by a seeded random search (seed 5, 300 starts: 102 converged to 2-periodic and 14-periodic
    orbits); rounded to three digits it still converges.  The orbit is elliptic with eigenvalues
    {1, exp(+-1.222 i)} and stays 14-periodic for 100 periods.
    """
    scene = tables.regular_polygon(5)
    res = find_periodic_orbit(scene, (0.288, 0.059), (-0.6, -0.8), -0.1, period=14)
    assert isinstance(res, PeriodicOrbit)
    assert res.converged and res.residual <= 1e-12 and res.iterations <= 10, res.message
    ds, X = states(scene, res.state, 14 * 100 + 1)
    assert minimal_period(X, 14) == 14  # not 1, 2 or 7
    assert period_drift(X, 14) < 1e-12
    m = res.monodromy
    assert m.kind == "elliptic" and m.unit_count() == 1
    angle = np.abs(np.angle(m.eigenvalues)).max()
    assert angle == pytest.approx(1.2222, abs=1e-3)
    assert sorted(set(ds.element.values[:14].tolist())) == [0, 1, 2, 3]  # visits four of the five edges


def test_wedge_with_gravity_two_periodic_orbit_that_is_not_path_reversing():
    """Paper, wedge figure (right) and conjecture (i): a 2-periodic orbit whose impacts have v_t != gamma w.

    Wedge half-angle 0.6, gamma = 1/sqrt 2, force (0, -1); start from a seeded search (seed 11).  The two
    flights differ (a long high one and a short low one), each mirror-symmetric about the bisector.
    """
    scene = tables.wedge(0.6, force=(0.0, -1.0))
    res = find_periodic_orbit(scene, (-0.041, 1.052), (0.29, -1.2), 0.249, period=2)
    assert res.converged and res.residual <= 1e-12, res.message
    ds, X = states(scene, res.state, 2 * 200 + 1)
    assert minimal_period(X, 2) == 2
    assert period_drift(X, 2) < 1e-12  # elliptic: stays periodic
    for k in range(2):
        assert impact_mismatch(scene, ds, k) > 1.0  # not path reversing (~1.548 at both impacts)
    flights = np.diff(ds.t.values[:3])
    assert abs(flights[0] - flights[1]) > 1.0
    assert res.monodromy.kind == "elliptic"
    # a path-reversing orbit of the same wedge, for contrast, has v_t = gamma w at every impact
    scene2, state2 = wedge_orbit(0.6, 0.5, 1.0, G)
    ds2 = ns.simulate(scene2, **state2, max_collisions=2)
    assert max(impact_mismatch(scene2, ds2, k) for k in range(2)) < 1e-12


def test_wedge_with_gravity_period_8_orbit():
    """Paper, wedge figure (right centre) and conjecture (ii): a period-8 orbit of a wedge under gravity.

    Wedge half-angle 0.6, gamma = 1/sqrt 2, force (0, -1); start from a seeded search (seed 7).  The orbit
    has minimal period 8 (itinerary left, left, right, left, right, left, left, right: two of its flights
    return to the wall they left) and is elliptic: eigenvalues {1, exp(+-0.3893 i)}.  It is isolated in
    the paper's sense (its neighbours are not periodic: M != I, unlike a persistently periodic force-free
    wedge), but NOT in the strict sense: the eigenvalue 1 means a one-parameter family of period-8 orbits
    at the same energy.  Every even-period wedge orbit our searches found has that eigenvalue 1 (and every
    odd-period one has -1), although this orbit is neither time-reversal nor mirror symmetric
    (docs/analysis.md); the next test shows a strictly isolated one.
    """
    scene = tables.wedge(0.6, force=(0.0, -1.0))
    res = find_periodic_orbit(scene, (-0.862, 1.732), (1.577, -0.763), -1.071, period=8)
    assert res.converged and res.residual <= 1e-12, res.message
    ds, X = states(scene, res.state, 8 * 200 + 1)
    assert minimal_period(X, 8) == 8
    assert period_drift(X, 8) < 1e-12
    assert ds.element.values[:8].tolist() in ([0, 0, 1, 0, 1, 0, 0, 1], [0, 1, 0, 1, 0, 0, 1, 0],
                                              [1, 0, 1, 0, 0, 1, 0, 0], [0, 1, 0, 0, 1, 0, 0, 1])
    m = res.monodromy
    assert m.kind == "elliptic"
    assert np.abs(np.angle(m.eigenvalues)).max() == pytest.approx(0.3893, abs=1e-3)
    assert m.unit_count() == 1 and not m.isolated
    assert np.abs(m.matrix - np.eye(3)).max() > 0.1  # not persistently periodic


def test_wedge_with_gravity_strictly_isolated_periodic_orbit():
    """A wedge orbit with no eigenvalue 1 at fixed energy: period 5, half-angle 0.7195, gamma = 0.3.

    Odd-period no-slip orbits have det M = -1; the searches found them with eigenvalue -1 instead of +1,
    so they are isolated fixed points of the 5-th return map (no family at fixed energy).  This one is
    elliptic, {-1, exp(+-1.4469 i)}: conjecture (ii) holds in the strict sense at period 5.
    """
    scene = tables.wedge(0.7195268216296624, gamma=0.3, force=(0.0, -1.0))
    res = find_periodic_orbit(scene, (-0.46, 1.811), (1.66, -0.505), -1.158, period=5)
    assert res.converged and res.residual <= 1e-12, res.message
    _ds, X = states(scene, res.state, 5 * 200 + 1)
    assert minimal_period(X, 5) == 5
    assert period_drift(X, 5) < 1e-12
    m = res.monodromy
    assert m.isolated and m.unit_count() == 0
    assert np.min(np.abs(m.eigenvalues + 1.0)) < 1e-9
    assert m.det == pytest.approx(-1.0, abs=1e-9)
    assert m.kind == "elliptic"


# ----------------------------------------------------------------------------- theorem orbits from 1e-3 away
THEOREM_ORBITS = {
    "two disks elliptic": lambda: two_disk_orbit(0.9, 1.2, 0.3),
    "two disks hyperbolic": lambda: two_disk_orbit(0.5, 0.3, G),
    "two disks gamma 0": lambda: two_disk_orbit(0.4, 0.0, 0.0),
    "two disks gravity": lambda: two_disk_orbit(0.5, 0.3, G, theta=0.4, gravity=1.0),
    "wedge up": lambda: wedge_orbit(0.5, 0.3, 1.0, G),
    "wedge up steep (hyperbolic)": lambda: wedge_orbit(0.5, 1.2, 1.0, G),
    "wedge down right": lambda: wedge_orbit(0.5, 0.3, 1.0, G, opening="down", wall="right"),
    "wedge no force": lambda: wedge_noforce_orbit(0.5, 1.0, G),
    "half plane": lambda: bounce_orbit(0.3, 1.2, G),
}


@pytest.mark.parametrize("name", sorted(THEOREM_ORBITS))
def test_theorem_orbits_are_found_from_a_start_1e3_away(name):
    scene, state = THEOREM_ORBITS[name]()
    rng = np.random.default_rng(zlib.crc32(name.encode()))  # hash() of a str changes with each process
    q = np.asarray(state["position"]) + 1e-3 * rng.standard_normal(2)
    v = np.asarray(state["velocity"]) + 1e-3 * rng.standard_normal(2)
    w = state["spin"] + 1e-3 * rng.standard_normal()
    res = find_periodic_orbit(scene, q, v, w, period=2)
    assert res.converged and res.residual <= 1e-12, (name, res.message, res.history)
    assert res.iterations <= 8
    _, X = states(scene, res.state, 8)
    # a start off the orbit by the residual (<= 1e-12) drifts off by |lambda| more each period
    lam = max(1.0, np.abs(res.monodromy.eigenvalues).max())
    drift = np.abs(X[2:] - X[:-2]).max(axis=1) / (1.0 + np.abs(X).max())
    assert np.all(drift < 1e-11 * lam ** (np.arange(len(drift)) // 2 + 1)), drift
    # the orbit found is the theorem's family member next to the start, not another orbit
    _, X0 = states(scene, state, 2)
    gap = min(np.abs(X[:2] - X0).max(), np.abs(X[:2] - X0[::-1]).max())  # the found start may be a flight later
    assert gap < 2e-2 * (1 + np.abs(X0).max())


def test_periodic_orbit_on_a_lattice():
    """Sinai torus (no-slip): the 2-periodic orbit between neighbouring disks, periodic up to a lattice shift."""
    scene = tables.sinai_torus(0.3)
    res = find_periodic_orbit(scene, (0.5, 0.001), (1.0, 0.002), 0.001, period=2)
    assert res.converged and res.residual <= 1e-12, res.message
    _ds, X = states(scene, res.state, 6)
    assert period_drift(X, 2) < 1e-9
    assert res.monodromy.kind == "hyperbolic"  # dispersing disks, nearly head-on: lambda + 1/lambda > 2
    assert abs(X[0, 0] - X[1, 0]) == pytest.approx(0.4, abs=1e-3)  # between two disk copies 1 apart


def test_periodic_orbit_through_a_disk_point_outside_the_parallelogram_cell():
    """Hexagonal gas at R = 0.45 (finite horizon): the vertical 2-periodic orbit hits the disk at (0, +-0.45), a
    point of the neighbouring parallelogram cell; the search refused it ('lies outside cell 0')."""
    scene = tables.hex_lorentz_cell(0.45)
    res = find_periodic_orbit(scene, (0.0, 0.6), (0.001, 1.0), 0.0, period=2)
    assert res.converged and res.residual <= 1e-12, res.message
    ds, X = states(scene, res.state, 6)
    assert period_drift(X, 2) < 1e-9
    assert np.abs(ds.x.values).max() < 1e-3  # between the disks at (0, 0) and (0, -sqrt 3), vertically
    np.testing.assert_allclose(np.sort(np.abs(ds.y.values))[[0, -1]], [0.45, math.sqrt(3) - 0.45], rtol=1e-6)


# ----------------------------------------------------------------------------- honest failure
def test_a_start_that_does_not_converge_says_so():
    scene = tables.sinai_torus(0.3, law="specular")
    res = find_periodic_orbit(scene, (0.45, 0.1), (0.8, 0.35), 0.0, period=9, max_iter=3)
    assert not res.converged
    assert res.residual > 1e-12 and math.isfinite(res.residual)
    assert res.iterations <= 3 and res.history[0] > 1e-6
    assert res.message
    res0 = find_periodic_orbit(tables.regular_polygon(5), (0.288, 0.059), (-0.6, -0.8), -0.1, period=14,
                               max_iter=0)
    assert not res0.converged and res0.iterations == 0 and res0.residual == res0.history[0] > 1e-6


def test_a_start_not_returning_to_its_element_is_not_converged():
    # pentagon: the orbit hits edges 2, 0, 3, ...; after 2 collisions it is on another edge than its first
    scene = tables.regular_polygon(5)
    res = find_periodic_orbit(scene, (0.1, 0.05), (0.6, 0.8), 0.3, period=2)
    assert not res.converged and res.iterations == 0
    assert res.residual == math.inf and "not on the start's element" in res.message
    assert scene.contains(np.array([res.position]))[0]  # still a valid start on the first flight
    assert res.monodromy is None


def test_found_orbits_are_never_a_wrong_success():
    """Whatever the start, converged implies the engine repeats the state after `period` collisions."""
    scene = tables.regular_polygon(5)
    rng = np.random.default_rng(3)
    for _ in range(12):
        a = rng.uniform(0, 2 * math.pi)
        res = find_periodic_orbit(scene, rng.uniform(-0.3, 0.3, 2), (math.cos(a), math.sin(a)),
                                  rng.uniform(-1, 1), period=int(rng.choice([2, 4, 6])), max_iter=15)
        if res.converged:
            _, X = states(scene, res.state, 2 * res.period + 1)
            assert period_drift(X, res.period) < 1e-9
        else:
            assert res.residual > 1e-12


def test_argument_errors():
    scene, state = two_disk_orbit(0.5, 0.3, G)
    for bad in (0, -1, 2.5, True):
        with pytest.raises(ValueError, match="period"):
            find_periodic_orbit(scene, **state, period=bad)
    with pytest.raises(ValueError, match="tol"):
        find_periodic_orbit(scene, **state, period=2, tol=0.0)
    with pytest.raises(ValueError, match="max_iter"):
        find_periodic_orbit(scene, **state, period=2, max_iter=-1)
    with pytest.raises(ValueError, match="scene"):
        find_periodic_orbit(None, **state, period=2)
    with pytest.raises(ValueError, match="no collision"):  # misses both disks
        find_periodic_orbit(scene, (0.0, 0.9), (1.0, 0.0), 0.0, period=2)
    with pytest.raises(ValueError, match="stops \\('escape'\\) after 1 collisions"):  # one disk, then away
        find_periodic_orbit(scene, (0.0, 0.3), (-1.0, 0.0), 0.0, period=2)
    with pytest.raises(ValueError, match="position"):
        find_periodic_orbit(scene, (-1.0, 0.0), (1.0, 0.0), 0.0, period=2)
    square = tables.rectangle(1.0, 1.0)
    with pytest.raises(ValueError, match="corner"):
        find_periodic_orbit(square, (0.5, 0.5), (-1.0, -1.0), 0.0, period=2)
