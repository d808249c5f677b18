"""Figure S6 (conjecture, part i): non-path-reversing 2-periodic orbits between pairs of boundary points.

The experiment's claims are checked against what it does not use: a brute-force least-squares solve of the whole
two-flight system (both impacts, all of the no-slip law, written out here from docs/conventions.md) and the
engine's own orbits.
"""
import math

import numpy as np
import pytest
from scipy.optimize import least_squares

from noslipsim import simulate
from noslipsim.experiments import accessible_pair_census, pair_counts
from noslipsim.experiments.accessible import (
    OUTCOMES,
    _mid_state,
    _pair_geometry,
    accessible_table,
    two_periodic_candidates,
)

GAMMA = 1 / math.sqrt(2)

#: The brute force looks for orbits with ``T' >= UNEVEN T`` only (away from the path-reversing one).
UNEVEN = 1.05


def _law(v, w, n, gamma):
    """The no-slip collision (docs/conventions.md), outward normal ``n``, ``t = J n``."""
    t = np.array([-n[1], n[0]])
    c, s = (1 - gamma ** 2) / (1 + gamma ** 2), 2 * gamma / (1 + gamma ** 2)
    vt, vn = v @ t, v @ n
    return (-s * w + c * vt) * t - vn * n, -c * w - s * vt


def _cycle_residual(x, g, a, gamma):
    """Mismatch of the state after ``q0 -> q1 -> q0`` with the start; ``x = (log T, log(T'/T - 1.05), w)``.

    ``T' >= 1.05 T`` keeps the search off the path-reversing orbit (``T' = T``).
    """
    T, w = np.exp(x[0]), x[2]
    T2 = T * (UNEVEN + np.exp(x[1]))
    d = g["q1"] - g["q0"]
    v0 = d / T - 0.5 * a * T
    u0, w2 = _law(v0 + a * T, w, g["n1"], gamma)
    miss = g["q1"] + u0 * T2 + 0.5 * a * T2 ** 2 - g["q0"]          # the second flight must come back to q0
    v, w3 = _law(u0 + a * T2, w2, g["n0"], gamma)
    return np.r_[miss, v - v0, w3 - w] / math.hypot(*v0)


def _brute_force(g, a, gamma, starts=60, seed=3):
    """Smallest residual of the whole two-flight system from many random starts, and where."""
    rng = np.random.default_rng(seed)
    best = None
    for _ in range(starts):
        x0 = np.r_[rng.uniform(-2.5, 1.5, 2), rng.uniform(-3.0, 3.0)]
        fit = least_squares(_cycle_residual, x0, args=(g, a, gamma), xtol=1e-15, ftol=1e-15, gtol=1e-15)
        if best is None or fit.cost < best.cost:
            best = fit
    return math.sqrt(2 * best.cost), best.x


def test_an_unbalanced_accessible_pair_has_no_non_path_reversing_2_periodic_orbit():
    """Two walls of the pentagon, not balanced: the full system has no solution with T' != T."""
    scene = accessible_table("pentagon", GAMMA)
    g = _pair_geometry(scene, 0, 0.3, 2, 0.5)
    assert g["reason"] == "" and abs(g["balance"]) > 0.05
    a = np.asarray(scene.force)
    assert _brute_force(g, a, GAMMA)[0] > 1e-3
    candidates, family, _ = two_periodic_candidates(g, a, GAMMA)
    assert candidates == [] and not family


def test_the_brute_force_finds_the_family_of_the_wedge_mirror_pair():
    """The same brute force does find orbits where the census says there are: its silence above means something."""
    scene = accessible_table("wedge", GAMMA)
    g = _pair_geometry(scene, 0, -1.5, 1, 1.5)
    residual, x = _brute_force(g, np.asarray(scene.force), GAMMA, starts=10)
    assert residual < 1e-10 and UNEVEN + np.exp(x[1]) > UNEVEN


def test_the_wedge_mirror_pair_carries_a_family_that_the_engine_runs_as_2_periodic():
    scene = accessible_table("wedge", GAMMA)
    g = _pair_geometry(scene, 0, -1.5, 1, 1.5)   # directly opposite on the wedge, force along the bisector
    assert g["reason"] == "" and g["mirror"] and abs(g["balance"]) < 1e-12
    a = np.asarray(scene.force)
    candidates, family, _ = two_periodic_candidates(g, a, GAMMA)
    assert family and len(candidates) >= 4
    for T, T2 in candidates:
        assert T2 > 1.01 * T                                  # not the path-reversing orbit (T = T')
        run = simulate(scene, **_mid_state(g, a, T, T2, GAMMA), max_collisions=5)
        X = np.c_[run.x, run.y, run.vx, run.vy, run.spin]
        np.testing.assert_allclose(X[2], X[0], atol=1e-9)    # period 2 ...
        np.testing.assert_allclose(X[3], X[1], atol=1e-9)
        np.testing.assert_allclose(X[[0, 1], :2], [g["q1"], g["q0"]], atol=1e-9)   # ... between q1 and q0
        # not path reversing: at q1 the velocity leaving is not the arriving one reversed
        back = X[0, 2:4] + np.r_[run.vx_in.values[0], run.vy_in.values[0]]
        assert math.hypot(*back) > 1e-3 * math.hypot(*X[0, 2:4])


def test_the_brute_force_agrees_on_the_wedge_mirror_pair():
    scene = accessible_table("wedge", GAMMA)
    g = _pair_geometry(scene, 0, -1.5, 1, 1.5)
    a = np.asarray(scene.force)
    T, T2 = two_periodic_candidates(g, a, GAMMA)[0][0]
    w = _mid_state(g, a, T, T2, GAMMA)["spin"]
    assert np.abs(_cycle_residual(np.r_[math.log(T), math.log(T2 / T - UNEVEN), w], g, a, GAMMA)).max() < 1e-12


def test_a_balanced_pair_that_is_not_a_mirror_pair_only_has_roots_with_the_spin_reversed():
    scene = accessible_table("pentagon", GAMMA)
    g = _pair_geometry(scene, 0, 0.3, 4, 0.20475011133501037)
    assert g["reason"] == "" and abs(g["balance"]) < 1e-9 and not g["mirror"]
    candidates, family, spurious = two_periodic_candidates(g, np.asarray(scene.force), GAMMA)
    assert candidates == [] and not family and spurious >= 1
    assert _brute_force(g, np.asarray(scene.force), GAMMA)[0] > 1e-3   # the spin law does fail there


def test_inaccessible_pairs_say_why():
    rect = accessible_table("rectangle and disk", GAMMA)
    assert _pair_geometry(rect, 0, 1.0, 2, 1.0)["reason"] == "tangent lines form no wedge"   # floor, ceiling
    assert _pair_geometry(rect, 3, 0.75, 1, 0.75)["reason"] == "tangent lines form no wedge"  # parallel sides
    notch = accessible_table("notched polygon", GAMMA)
    assert _pair_geometry(notch, 4, 0.2, 1, 1.4)["reason"] in ("chord obstructed", "tangent lines form no wedge")


def test_the_census_counts_every_pair_and_repeats_itself():
    names = ["wedge", "two disks"]
    ds = accessible_pair_census(names, GAMMA, pairs=2, seed=4)
    counts = pair_counts(ds)
    assert list(counts.table.values) == names
    assert (counts.pairs.sel(sample="random").sum("outcome") == 2).all()
    assert set(ds.outcome.values) <= set(OUTCOMES)
    found = ds.outcome.values == "found"
    assert ((ds.n_found.values > 0) == found).all()
    assert (ds.n_elliptic + ds.n_hyperbolic + ds.n_parabolic == ds.n_found).all()
    assert (ds.sample.values[found] == "balanced").all() and ds.mirror.values[found].all()
    assert counts.pairs.sel(table="wedge", sample="balanced", outcome="found") == 2
    again = accessible_pair_census(names, GAMMA, pairs=2, seed=4, scheduler="threads", num_workers=2)
    for name in ("outcome", "reason", "n_found", "linear_kind", "s0", "s1"):
        np.testing.assert_array_equal(again[name].values, ds[name].values)


def test_the_census_refuses_bad_input():
    with pytest.raises(ValueError, match="tables"):
        accessible_pair_census(["moon"])
    with pytest.raises(ValueError, match="gamma"):
        accessible_pair_census(["wedge"], 0.0)
    with pytest.raises(ValueError, match="pairs"):
        accessible_pair_census(["wedge"], pairs=0)
