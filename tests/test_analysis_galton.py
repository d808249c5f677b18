"""Galton arrival curves: exact survival counts, the plateau estimator on known tails, a real run."""
import math

import numpy as np
import pytest
import xarray as xr

from noslipsim.analysis import arrival_curve, excess_kurtosis, tail_share
from noslipsim.experiments import galton_distribution


def synthetic(times_by_law, max_time, laws=None):
    """A galton_distribution-shaped dataset from arrival times (NaN = not arrived)."""
    t = np.asarray(times_by_law, dtype=float)
    laws = laws or [f"law{i}" for i in range(len(t))]
    return xr.Dataset(
        {"t_terminal": (("law", "particle"), t), "arrived": (("law", "particle"), np.isfinite(t).astype(np.int8))},
        coords={"law": laws}, attrs={"max_time": max_time, "rows": 3})


def power_tail(n, t0, alpha, trapped, rng, max_time):
    """Arrival times with S(t) = P + (1 - P) (t / t0)^-alpha for t >= t0 (Pareto), cut at max_time."""
    t = t0 * rng.uniform(size=n) ** (-1.0 / alpha)
    t[rng.uniform(size=n) < trapped] = np.nan
    t[t > max_time] = np.nan
    return t


def test_survival_counts_are_exact_on_hand_made_times():
    ds = synthetic([[1.0, 2.0, 3.0, np.nan], [4.0, 4.0, 0.5, 2.0]], max_time=4.0)
    out = arrival_curve(ds, times=[0.25, 1.0, 1.5, 2.0, 3.0, 4.0])
    np.testing.assert_array_equal(out.share_not_arrived.sel(law="law0"), [1.0, 0.75, 0.75, 0.5, 0.25, 0.25])
    np.testing.assert_array_equal(out.share_not_arrived.sel(law="law1"), [1.0, 0.75, 0.75, 0.5, 0.5, 0.0])
    assert out.share_not_arrived_final.values.tolist() == [0.25, 0.0]
    assert out.n_particles.values.tolist() == [4, 4]
    np.testing.assert_allclose(out.share_not_arrived_stderr.sel(law="law0")[3], math.sqrt(0.5 * 0.5 / 4))
    for name, var in out.variables.items():
        assert var.attrs.get("long_name") and "units" in var.attrs, name
    assert out.attrs["source_rows"] == 3 and out.attrs["max_time"] == 4.0


def test_default_grid_is_log_spaced_from_the_first_arrival_to_max_time():
    ds = synthetic([[3.0, 7.0, np.nan]], max_time=50.0)
    out = arrival_curve(ds, n_times=5)
    np.testing.assert_allclose(out.time, np.geomspace(3.0, 50.0, 5))
    assert float(out.share_not_arrived[0, 0]) == pytest.approx(2 / 3)
    nobody = arrival_curve(synthetic([[np.nan, np.nan]], max_time=50.0), n_times=3)
    np.testing.assert_allclose(nobody.time, [0.05, 50 / math.sqrt(1000), 50.0])
    assert (nobody.share_not_arrived == 1.0).all()


@pytest.mark.parametrize("trapped,alpha", [(0.3, 1.0), (0.0, 0.5), (0.6, 2.0)])
def test_plateau_estimator_recovers_a_power_law_tail(trapped, alpha):
    rng = np.random.default_rng(7)
    max_time = 1000.0
    ds = synthetic([power_tail(400_000, 10.0, alpha, trapped, rng, max_time)], max_time)
    out = arrival_curve(ds).isel(law=0)
    err = float(out.trapped_share_stderr)
    assert err < 0.01
    assert abs(float(out.trapped_share) - trapped) < 4 * err + 1e-12
    assert float(out.tail_exponent) == pytest.approx(alpha, rel=0.05)
    # the raw share at max_time overstates trapping by the slow particles
    expected_final = trapped + (1 - trapped) * (max_time / 10.0) ** (-alpha)
    assert float(out.share_not_arrived_final) == pytest.approx(expected_final, abs=4e-3)
    assert float(out.slow_share) == pytest.approx(expected_final - trapped, abs=4 * err + 4e-3)


def test_plateau_is_undefined_before_the_tail_and_bounded_by_the_final_share():
    rng = np.random.default_rng(3)
    # arrivals still accelerating over the last decade (uniform in [0, max_time]): not a tail yet
    rising = synthetic([rng.uniform(1.0, 1000.0, 5000)], 1000.0)
    out = arrival_curve(rising).isel(law=0)
    assert int(out.arrivals_late) >= int(out.arrivals_early)
    assert np.isnan(out.trapped_share) and np.isnan(out.tail_exponent)
    # log-uniform arrivals: as many per log-window early as late, no measurable decay
    flat = synthetic([np.exp(rng.uniform(0.0, math.log(1000.0), 5000))], 1000.0)
    out = arrival_curve(flat).isel(law=0)
    assert abs(int(out.arrivals_late) - int(out.arrivals_early)) < 3 * math.sqrt(int(out.arrivals_early) * 2)
    assert np.isnan(out.trapped_share)
    # an exponential tail with nobody trapped: the power-law extrapolation over-counts, clipped at 0
    fast = synthetic([np.where(rng.uniform(size=20000) < 0.5, rng.exponential(80.0, 20000), np.nan)], 1000.0)
    out = arrival_curve(fast).isel(law=0)
    assert 0.0 <= float(out.trapped_share) <= float(out.share_not_arrived_final)
    # no late arrivals at all: everything left looks trapped
    done = synthetic([[1.0, 2.0, 50.0, np.nan]], 1000.0)
    out = arrival_curve(done).isel(law=0)
    assert float(out.trapped_share) == 0.25 and float(out.slow_share) == 0.0


def test_real_run_with_a_gamma_coordinate_and_several_gammas():
    ds = galton_distribution(300, rows=4, max_time=60.0, seed=5, progress=False)
    out = arrival_curve(ds, n_times=40)
    curve = out.share_not_arrived
    assert (curve.diff("time") <= 0).all() and (curve >= 0).all() and (curve <= 1).all()
    np.testing.assert_allclose(curve.isel(time=-1), ds.share_not_arrived)
    np.testing.assert_allclose(out.share_not_arrived_final, ds.share_not_arrived)
    # the figure pipeline's form: a gamma coordinate along law (NaN for specular)
    tagged = ds.assign_coords(gamma=("law", [np.nan, 2 ** -0.5]))
    out2 = arrival_curve(tagged, n_times=40)
    assert out2.gamma.dims == ("law",) and np.isnan(out2.gamma[0])
    xr.testing.assert_equal(out2.share_not_arrived.drop_vars("gamma"), curve.drop_vars("gamma", errors="ignore"))
    # several gammas along their own dimension
    other = galton_distribution(300, rows=4, max_time=60.0, seed=5, gamma=3.0, laws=("no-slip",), progress=False)
    both = xr.concat([ds.sel(law=["no-slip"]).drop_vars("gamma"), other.drop_vars("gamma")],
                     dim=xr.DataArray([2 ** -0.5, 3.0], dims="gamma", name="gamma"))
    out3 = arrival_curve(both, n_times=10)
    assert out3.share_not_arrived.dims == ("gamma", "law", "time")
    np.testing.assert_allclose(out3.share_not_arrived_final.sel(law="no-slip"),
                               [float(ds.share_not_arrived.sel(law="no-slip")),
                                float(other.share_not_arrived.sel(law="no-slip"))])


def test_several_gammas_along_law_as_galton_distribution_records_them():
    ds = galton_distribution(200, rows=4, max_time=60.0, seed=2, gamma=[2 ** -0.5, 3.0], progress=False)
    out = arrival_curve(ds, n_times=8)
    assert out.law.values.tolist() == ["specular", "no-slip", "no-slip"]
    np.testing.assert_array_equal(out.gamma.values, ds.gamma.values)
    np.testing.assert_allclose(out.share_not_arrived_final, ds.share_not_arrived)
    assert out.share_not_arrived.dims == ("law", "time")


@pytest.mark.parametrize("change,match", [
    (lambda d: d.drop_vars("t_terminal"), "t_terminal"),
    (lambda d: d.rename(particle="p"), "particle"),
    (lambda d: d.assign(arrived=d.arrived * 0), "arrived"),
    (lambda d: d.assign(t_terminal=d.t_terminal * 100), "after max_time"),
    (lambda d: d.assign(t_terminal=-d.t_terminal), "> 0"),
    (lambda d: d.assign_attrs(max_time=None), "max_time"),
])
def test_bad_datasets_are_refused(change, match):
    ds = synthetic([[1.0, 2.0, np.nan]], max_time=10.0)
    with pytest.raises(ValueError, match=match):
        arrival_curve(change(ds))


def test_bad_arguments_are_refused():
    ds = synthetic([[1.0, 2.0, np.nan]], max_time=10.0)
    with pytest.raises(TypeError, match="xarray"):
        arrival_curve(ds.t_terminal)
    with pytest.raises(ValueError, match="max_time"):
        arrival_curve(ds.drop_attrs() if hasattr(ds, "drop_attrs") else ds.assign_attrs(max_time=None))
    for times, match in [([1.0], "at least 2"), ([0.0, 1.0], "> 0"), ([2.0, 1.0], "increasing"),
                         ([1.0, 20.0], "past max_time")]:
        with pytest.raises(ValueError, match=match):
            arrival_curve(ds, times=times)
    with pytest.raises(ValueError, match="n_times"):
        arrival_curve(ds, n_times=1)
    with pytest.raises(ValueError, match="tail_span"):
        arrival_curve(ds, tail_span=1.0)


@pytest.mark.parametrize("draw, kappa", [("normal", 0.0), ("laplace", 3.0), ("uniform", -1.2)])
def test_excess_kurtosis_of_known_laws_within_its_bootstrap_error(draw, kappa):
    rng = np.random.default_rng(11)
    x = getattr(rng, draw)(size=40_000)
    k, err = excess_kurtosis(x)
    assert 0 < err < 0.2
    assert abs(k - kappa) < 4 * err
    # the normal's error matches the textbook sqrt(24 / n) within a factor 1.5
    if draw == "normal":
        assert err == pytest.approx(math.sqrt(24 / x.size), rel=0.5)
    assert excess_kurtosis(x) == (k, err)  # a fixed seed: the same number every run


def test_excess_kurtosis_refuses_what_has_none():
    with pytest.raises(ValueError, match="at least 4 finite"):
        excess_kurtosis([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="not finite"):
        excess_kurtosis([1.0, 2.0, 3.0, np.nan, 5.0])
    with pytest.raises(ValueError, match="all equal"):
        excess_kurtosis(np.ones(10))
    with pytest.raises(ValueError, match="resamples"):
        excess_kurtosis(np.arange(10.0), resamples=1)


def test_tail_share_tells_a_heavy_tail_from_the_normal_by_counts():
    rng = np.random.default_rng(12)
    p, err, normal = tail_share(rng.normal(size=100_000))
    assert normal == pytest.approx(0.0026998, rel=1e-4)                      # erfc(3 / sqrt 2)
    assert abs(p - normal) < 4 * err
    # Laplace: P(|x| > 3 sigma) = exp(-3 sqrt 2) = 1.44 %, five times the normal's
    p, err, _ = tail_share(rng.laplace(size=100_000))
    assert abs(p - math.exp(-3 * math.sqrt(2))) < 4 * err and p > normal + 10 * err
    assert tail_share([0.0, 0.0, 0.0, 1.0], sigmas=1.0)[0] == 0.25  # by hand: s = 0.5, only 1 is > s from 0.25
    with pytest.raises(ValueError, match="at least 2 finite"):
        tail_share([1.0, np.nan])
    with pytest.raises(ValueError, match="all equal"):
        tail_share(np.ones(5))
    with pytest.raises(ValueError, match="sigmas"):
        tail_share(np.arange(5.0), sigmas=0.0)


def test_figure_3s_board_has_tails_heavier_than_the_normal_for_both_laws():
    # The physics Figure 3 and docs/figures.md claim, not the estimator: on the configured board (10 rows, the
    # release above the top row, T = 2000) "apparently Gaussian" hides tails heavier than the normal. A normal
    # law puts 0.27 % beyond 3 sigma; the board about 1 % (40 of 4000 particles): at least twice the normal's
    # is 22 particles, 3 Poisson standard deviations below the expected count.
    ds = galton_distribution(4000, rows=10, radius=0.89, top_row=0, start=(0.0, 2.0), spread=0.5, max_time=2000.0,
                             seed=7, progress=False)
    for law in ("specular", "no-slip"):
        x = ds.x_terminal.sel(law=law).values
        x = x[np.isfinite(x)]
        assert x.size > 0.8 * 4000                                    # the sample is most of the particles
        p, err, normal = tail_share(x)
        assert p > 2 * normal, (law, p, err)
        assert excess_kurtosis(x)[0] > 0.5, law
