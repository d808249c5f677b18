"""Stability experiments (Figures 7, 9, 14, 15): wedge periodic orbits, perturbed copies, the launch-angle scan,
the survival pattern of a grid.

Oracles: periodicity (residuals, minimal period), the path-reversal condition v_t = gamma w at every impact, a
family shown by the finder itself, the growth rate of a perturbation against the monodromy, the scale invariance
of the wedge under gravity, and synthetic grids with known patterns.
"""
import json
import math

import numpy as np
import pytest
import xarray as xr

from noslipsim import experiments as ex
from noslipsim.analysis import monodromy, wedge_orbit

G = 1 / math.sqrt(2)
PERIOD_8 = {"name": "period 8", "opening": "up", "position": [-0.862, 1.732], "velocity": [1.577, -0.763],
            "spin": -1.071, "period": 8}
NOT_REVERSING = {"name": "not path-reversing", "opening": "up", "position": [-0.041, 1.052],
                 "velocity": [0.29, -1.2], "spin": 0.249, "period": 2}


@pytest.fixture(scope="module")
def wedge_orbits():
    return ex.wedge_periodic_orbits(0.6, G, reversing=[{"opening": "up", "theta": 0.4, "ell": 1.0},
                                                       {"opening": "up", "theta": 1.2, "ell": 2.0},
                                                       {"opening": "down", "theta": 0.3, "ell": 1.5}],
                                    searches=[PERIOD_8, NOT_REVERSING], periods=5)


def test_theorem_orbits_are_periodic_and_path_reversing(wedge_orbits):
    ds = wedge_orbits.isel(orbit=slice(0, 3))
    assert (ds.residual < 1e-12).all() and (ds.minimal_period == 2).all()
    assert (ds.path_reversing == 1).all() and (ds.reversal_mismatch < 1e-12).all()
    assert list(ds.case.values) == ["path-reversing"] * 2 + ["path-reversing, wedge opening down"]
    assert list(ds.linear_kind.values) == ["elliptic", "hyperbolic", "elliptic"]   # 1.2 > pi/2 - 0.6
    # each run is 5 periods and retraces the orbit, up to rounding amplified by |lambda| per period
    for i in range(3):
        x = ds.x.values[i][np.isfinite(ds.x.values[i])]
        lam = np.abs(ds.eigenvalue_real.values[i] + 1j * ds.eigenvalue_imag.values[i]).max()
        assert x.size == 10
        np.testing.assert_allclose(x[2:], x[:-2], atol=1e-13 * lam ** 5)


def test_searched_orbits_period_8_and_not_path_reversing(wedge_orbits):
    p8, nr = wedge_orbits.isel(orbit=3), wedge_orbits.isel(orbit=4)
    assert int(p8.minimal_period) == 8 and int(nr.minimal_period) == 2
    assert float(p8.residual) < 1e-12 and float(nr.residual) < 1e-12
    assert int(p8.path_reversing) == 0 and int(nr.path_reversing) == 0
    assert float(nr.reversal_mismatch) > 0.5                        # v_t - gamma w far from 0 at an impact
    for o in (p8, nr):
        ev = o.eigenvalue_real.values + 1j * o.eigenvalue_imag.values
        assert np.prod(ev).real == pytest.approx(1.0, abs=1e-8)     # det M = (-1)^period = +1
        assert int(o.unit_count) == 1 and float(o.identity_distance) > 0.1   # a family, not persistently periodic
        # restarted family_step along the eigenvalue-1 direction: another periodic orbit about that far away
        assert float(o.family_distance) == pytest.approx(wedge_orbits.attrs["family_step"], rel=0.2)
    assert np.abs(np.angle(p8.eigenvalue_real.values + 1j * p8.eigenvalue_imag.values)).max() == \
        pytest.approx(0.3893, abs=1e-3)


def test_wedge_orbits_errors():
    with pytest.raises(ValueError, match="at least one"):
        ex.wedge_periodic_orbits(0.6, G)
    with pytest.raises(ValueError, match=r"reversing\[0\]: missing"):
        ex.wedge_periodic_orbits(0.6, G, reversing=[{"opening": "up", "theta": 0.4}])
    with pytest.raises(ValueError, match=r"searches\[0\] \(period 8\): no periodic orbit"):
        ex.wedge_periodic_orbits(0.6, G, searches=[PERIOD_8], max_iter=0)
    with pytest.raises(ValueError, match="family_step"):
        ex.wedge_periodic_orbits(0.6, G, searches=[PERIOD_8], family_step=0.0)


@pytest.fixture(scope="module")
def perturbed():
    cases = [{"opening": "up", "theta": 0.3, "ell": 1.0}, {"opening": "up", "theta": 1.126, "ell": 1.0}]
    return ex.perturbed_wedge_orbits(cases, phi=math.pi / 7, perturbation={"angle": 1e-4}, n_collisions=120)


def test_perturbed_orbits_layout_and_periodic_reference(perturbed):
    assert list(perturbed.role.values) == ["periodic", "periodic", "perturbed", "perturbed"]
    assert list(perturbed.case.values) == [0, 1, 0, 1]
    assert list(perturbed.n_collisions.values) == [3, 3, 120, 120]
    assert np.nanmax(perturbed.deviation.values[:2]) < 1e-12       # the periodic orbits against themselves
    assert json.loads(perturbed.attrs["perturbation"]) == {"angle": 1e-4, "spin": 0.0}


def test_perturbation_grows_at_the_monodromy_rate(perturbed):
    stable, unstable = perturbed.isel(orbit=2), perturbed.isel(orbit=3)
    assert str(stable.linear_kind.values) == "elliptic" and str(unstable.linear_kind.values) == "hyperbolic"
    assert np.nanmax(stable.deviation.values) < 1e-3               # stays near its periodic orbit
    scene, state = wedge_orbit(math.pi / 7, 1.126, 1.0, G)
    lam = float(np.abs(monodromy(scene, **state, period=2).eigenvalues).max())
    assert float(unstable.lambda_max) == pytest.approx(lam, rel=1e-12)
    env = np.maximum.accumulate(np.nan_to_num(unstable.deviation.values))
    k1, k2 = int(np.argmax(env >= 1e-3)), int(np.argmax(env >= 1e-1))
    assert k2 > k1 > 0
    rate = math.exp(2 * math.log(env[k2] / env[k1]) / (k2 - k1))   # growth per period, past the transient
    assert rate == pytest.approx(lam, rel=0.03)


def test_perturbation_errors():
    case = [{"opening": "up", "theta": 0.3, "ell": 1.0}]
    for bad, match in ((2.0, "small angle"), ({"angle": 0.1, "size": 1}, "unknown"), ({"spin": -1.0}, "spin"),
                       ("x", "perturbation")):
        with pytest.raises(ValueError, match=match):
            ex.perturbed_wedge_orbits(case, phi=0.6, perturbation=bad)
    with pytest.raises(ValueError, match="at least one"):
        ex.perturbed_wedge_orbits([], phi=0.6)


def test_launch_scan_transition_and_scale_invariance():
    thetas = np.linspace(0.05, 1.5, 30)
    phis = [math.pi / 7, 0.6]
    ds = ex.wedge_launch_scan(phis, thetas, G)
    for phi, t in zip(phis, ds.theta_transition.values):
        # the root of lambda + 1/lambda = 2, elliptic just below and hyperbolic just above ...
        below = ex.stability._wedge_monodromy(phi, t - 1e-6, G, 1.0, "up", 1.0)
        above = ex.stability._wedge_monodromy(phi, t + 1e-6, G, 1.0, "up", 1.0)
        assert below.kind == "elliptic" and above.kind == "hyperbolic"
        # ... at the launch parallel to the far wall (the law found for every phi and gamma tried)
        assert t == pytest.approx(math.pi / 2 - phi, abs=1e-9)
    # the wedge under gravity is scale invariant (q -> c^2 q, v -> c v): ell and g change nothing
    other = ex.wedge_launch_scan(phis, thetas, G, gravity=3.0, ell=0.2)
    np.testing.assert_allclose(other.eigen_sum, ds.eigen_sum, rtol=1e-7, atol=1e-9)
    # opening down: no orbit where theta >= pi/2 - phi
    down = ex.wedge_launch_scan([0.6], thetas, G, opening="down")
    gone = thetas >= math.pi / 2 - 0.6
    assert np.isnan(down.eigen_sum.values[0, gone]).all() and np.isfinite(down.eigen_sum.values[0, ~gone]).all()
    with pytest.raises(ValueError, match="thetas"):
        ex.wedge_launch_scan(phis, [0.5, 0.4], G)
    with pytest.raises(ValueError, match="phis"):
        ex.wedge_launch_scan([2.0], thetas, G)


def _grid(rows, theta):
    return xr.Dataset({"survived": (("radius", "theta"), np.array(rows, dtype=np.int8))},
                      coords={"radius": np.arange(len(rows)) * 0.1 + 0.1, "theta": theta})


def test_survival_pattern_reads_runs_and_merges_isolated_cells():
    theta = np.arange(9) * 0.1
    ds = _grid([[0, 0, 1, 1, 0, 1, 1, 0, 0],      # u-s-u with one isolated escape inside
                [1, 1, 1, 0, 0, 0, 1, 1, 1],      # s-u-s
                [1, 1, 1, 1, 1, 1, 1, 1, 0]], theta)   # an isolated escape at the end: merged
    rows = ex.survival_pattern(ds, min_run=2)
    assert [r["pattern"] for r in rows] == ["u-s-u", "s-u-s", "s"]
    assert rows[0]["intervals"] == [pytest.approx((0.15, 0.65))] and rows[0]["transitions"] == \
        [pytest.approx(0.15), pytest.approx(0.65)]
    assert rows[1]["intervals"] == [pytest.approx((0.0, 0.25)), pytest.approx((0.55, 0.8))]
    assert rows[2]["transitions"] == []
    assert ex.survival_pattern(ds, min_run=1)[0]["pattern"] == "u-s-u-s-u"   # kept when asked
    with pytest.raises(ValueError, match="dims"):
        ex.survival_pattern(ds, dim="phi")
