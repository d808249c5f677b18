"""The invariant-regions conjecture (Figure S7): the orbits, their neighbours' fates, counts that add up."""
import math

import numpy as np
import pytest

from noslipsim import simulate
from noslipsim._metadata import entry
from noslipsim.analysis import orbit_period
from noslipsim.core.layout import STOP_REASONS
from noslipsim.experiments import invariant_regions, region_counts
from noslipsim.experiments.invariant import OUTCOMES, reversing_orbit, start_outcomes

GAMMA = 1 / math.sqrt(2)
SMALL = dict(rings=2, starts=4, max_collisions=2000, tail=30)


@pytest.fixture(scope="module")
def small():
    """g = 0.5 (both flights have an orbit) and g = 3 (g d > 1: no free-fall orbit), rings close to the orbit."""
    return invariant_regions([0.5, 3.0], 0.8, 0.3, GAMMA, ring_step=0.02, **SMALL)


@pytest.mark.parametrize("flight, branch", [("free fall", "low"), ("isokinetic", "apex")])
def test_the_orbit_reverses_its_path_at_both_disks(flight, branch):
    scene, state = reversing_orbit(0.8, 0.3, GAMMA, 0.5, flight, branch)
    run = simulate(scene, **state, max_collisions=4)
    assert run.element.values.tolist() == [1, 0, 1, 0]
    for k in range(4):   # path reversal: the velocity and the spin come back reversed
        np.testing.assert_allclose([run.vx[k], run.vy[k], run.spin[k]],
                                   [-run.vx_in[k], -run.vy_in[k], -run.spin_in[k]], atol=1e-9)
    q1 = (1 - 0.8 * math.cos(0.3), 0.8 * math.sin(0.3))
    np.testing.assert_allclose([run.x[0], run.y[0]], q1, atol=1e-12)


def test_a_start_on_the_orbit_stays_periodic_and_its_neighbours_stay(small):
    ff, iso = small.sel(flight="free fall", force=0.5), small.sel(flight="isokinetic", force=0.5)
    assert int(ff.orbit_period.sel(branch="low")) == 2 and int(iso.orbit_period.sel(branch="apex")) == 2
    assert str(ff.linear_kind.sel(branch="low").item()) == "elliptic"
    for case in (ff.sel(branch="low"), iso.sel(branch="apex")):
        assert (case.start_outcome.values == OUTCOMES.index("invariant")).all()
        assert float(case.region_radius) == pytest.approx(2 * 0.02)
        # they stay near the orbit, the farther out the farther they roam (a nested region, not a drift away)
        far = case.tail_distance.max("start").values
        assert np.isfinite(far).all() and far[0] < far[1] < 0.2


def test_the_hyperbolic_branch_and_far_starts_escape(small):
    high = small.sel(flight="free fall", force=0.5, branch="high")
    assert str(high.linear_kind.item()) == "hyperbolic"
    assert (high.start_outcome.values == OUTCOMES.index("escaped")).all() and float(high.region_radius) == 0
    assert np.isnan(high.tail_distance.values).all()
    far = invariant_regions([0.5], 0.8, 0.3, GAMMA, ring_step=1.2, flights=["free fall"], **SMALL)
    low = far.sel(flight="free fall", branch="low").squeeze()
    assert (low.start_outcome.values == OUTCOMES.index("escaped")).all()
    assert (low.n_collisions.values < SMALL["max_collisions"]).all()
    assert (low.stop_reason.values == STOP_REASONS.index("escape")).all()


def test_a_converging_orbit_is_classed_attracted_and_an_early_stop_wins():
    """A constructed sequence converging onto a 2-cycle has a period; an orbit that stopped early is an escape
    (missed both disks) or a stop of another kind, whatever its tail."""
    cycle = np.array([[0.3, 0.1], [0.7, -0.2]])
    k = np.arange(80)
    converging = cycle[k % 2] + 0.5 ** k[:, None] * np.array([1.0, -1.0])
    drifting = cycle[k % 2] + 1e-3 * k[:, None]
    periods = [orbit_period(converging), orbit_period(drifting), orbit_period(converging), orbit_period(converging)]
    assert periods[:2] == [2, 0]
    stops = [STOP_REASONS.index(r) for r in ("max_collisions", "max_collisions", "escape", "grazing")]
    fates = start_outcomes(stops, periods)
    assert [OUTCOMES[f] for f in fates] == ["attracted", "invariant", "escaped", "stopped"]


def test_counts_add_up(small):
    counts = region_counts(small)
    per_orbit = SMALL["rings"] * SMALL["starts"]
    np.testing.assert_array_equal(counts.total.values, small.exists.values * per_orbit)
    for o, name in enumerate(OUTCOMES):
        np.testing.assert_array_equal(counts.starts.sel(outcome=name).values,
                                      (small.start_outcome.values == o).sum(axis=(-2, -1)))
    # g d > 1: no free-fall orbit at g = 3; the thermostat has one (its own apex branch only)
    assert small.exists.sel(flight="free fall", force=3.0).values.tolist() == [0, 0, 0]
    assert small.exists.sel(flight="isokinetic").values.tolist() == [[0, 0, 1], [0, 0, 1]]
    assert (small.start_outcome.where(small.exists == 0).fillna(-1).values[small.exists.values == 0] == -1).all()
    area = small.region_area.values
    np.testing.assert_allclose(area[np.isfinite(area)], math.pi * small.region_radius.values[np.isfinite(area)] ** 2)
    assert (small.staying_area.values[small.exists.values == 1] >= area[small.exists.values == 1] - 1e-15).all()


def test_every_variable_is_described(small):
    for name, var in small.variables.items():
        assert entry(name) is not None, f"{name}: not in noslipsim._metadata.VARIABLES"
        assert var.attrs["long_name"] == entry(name)[0]


@pytest.mark.parametrize("kwargs, match", [
    (dict(forces=[-1.0]), "forces"), (dict(forces=[]), "forces"), (dict(forces=[0.5], radius=1.0), "radius"),
    (dict(forces=[0.5], phi=2.0), "phi"), (dict(forces=[0.5], gamma=0.0), "gamma"),
    (dict(forces=[0.5], rings=0), "rings"), (dict(forces=[0.5], ring_step=-0.1), "ring_step"),
    (dict(forces=[0.5], flights=["nose-hoover"]), "flights"),
    (dict(forces=[0.5], flights=["free fall", "free fall"]), "flights"),
])
def test_bad_input_is_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        invariant_regions(**kwargs)
