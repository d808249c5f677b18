r"""Galton-board arrival curves: the share of particles not yet arrived against time.

A :func:`noslipsim.experiments.galton_distribution` run records, per law and
particle, the arrival time ``t_terminal`` at the terminal depth (NaN when the
particle had not arrived by ``max_time``).  The paper reports only the share
not arrived at ``max_time``; that number mixes two kinds of particle:

* **slow** particles, still descending: they arrive later (on the specular
  board the depth reached grows like ``t^(2/3)``, Chernov & Dolgopyat 2009, so
  the arrival times at a fixed depth have a tail);
* **trapped** particles, which never arrive (an invariant region of the
  no-slip board).

The survival curve ``S(t)`` (share not arrived by time ``t``) decays to 0 in
the first case and to a plateau ``P > 0`` in the second.
:func:`arrival_curve` tabulates ``S`` on a time grid for log-log axes and
estimates ``P`` by extrapolating the tail of the arrivals (see
:func:`arrival_curve` for the estimator and its limits, and docs/analysis.md).
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .._metadata import annotate
from .._validate import finite_float, positive

__all__ = ["arrival_curve", "excess_kurtosis", "tail_share"]

#: Default number of points of the log-spaced time grid.
N_TIMES = 100
#: Default ratio ``t_end / t_start`` of the tail window used by the plateau estimator (one decade).
TAIL_SPAN = 10.0
#: The arrivals must fall from the early to the late tail window by this many Poisson standard
#: deviations, ``n1 - n2 > z sqrt(n1 + n2)``, for the plateau to be extrapolated (else NaN).
TAIL_SIGNIFICANCE = 2.0
#: When no particle arrived, the time grid starts this factor below ``max_time``.
EMPTY_GRID_DECADES = 3.0



def _check_dataset(ds, max_time):
    """The arrival times (particle last) and the run's ``max_time``, validated."""
    if not isinstance(ds, xr.Dataset):
        raise TypeError(f"ds: expected an xarray.Dataset from galton_distribution, got {type(ds).__name__}")
    if "t_terminal" not in ds:
        raise ValueError("ds: no variable 't_terminal' (expected a galton_distribution dataset)")
    t = ds["t_terminal"]
    if "particle" not in t.dims:
        raise ValueError(f"ds.t_terminal: expected a 'particle' dimension, got dims {t.dims}")
    if t.sizes["particle"] == 0:
        raise ValueError("ds.t_terminal: no particles")
    if max_time is None:
        if "max_time" not in ds.attrs:
            raise ValueError("max_time: the dataset has no 'max_time' attribute; pass max_time=")
        max_time = ds.attrs["max_time"]
    max_time = positive(max_time, "max_time")
    values = t.values.astype(float)
    fin = np.isfinite(values)
    if np.isinf(values).any():
        raise ValueError("ds.t_terminal: infinite arrival time (not arrived must be NaN)")
    if fin.any() and (values[fin] <= 0.0).any():
        raise ValueError("ds.t_terminal: arrival times must be > 0")
    if fin.any() and (values[fin] > max_time).any():
        raise ValueError(f"ds.t_terminal: arrival time {values[fin].max()} after max_time = {max_time}")
    if "arrived" in ds:
        arrived = ds["arrived"].broadcast_like(t).transpose(*t.dims).values.astype(bool)
        if not np.array_equal(arrived, fin):
            raise ValueError("ds.arrived: disagrees with t_terminal (arrived must be 1 exactly where "
                             "t_terminal is finite)")
    return t.transpose(..., "particle"), max_time


def _time_grid(values, times, n_times, max_time):
    if times is not None:
        grid = np.asarray(times, dtype=float)
        if grid.ndim != 1 or len(grid) < 2:
            raise ValueError(f"times: expected a 1-D array of at least 2 times, got shape {grid.shape}")
        if not np.all(np.isfinite(grid)) or (grid <= 0.0).any():
            raise ValueError("times: must be finite and > 0 (log-log axes)")
        if (np.diff(grid) <= 0.0).any():
            raise ValueError("times: must be strictly increasing")
        if grid[-1] > max_time:
            raise ValueError(f"times: the last time {grid[-1]} is past max_time = {max_time} "
                             "(no particle is followed beyond it)")
        return grid
    if isinstance(n_times, bool) or int(n_times) != n_times or n_times < 2:
        raise ValueError(f"n_times: expected an integer >= 2, got {n_times!r}")
    fin = values[np.isfinite(values)]
    first = float(fin.min()) if fin.size else max_time / 10.0 ** EMPTY_GRID_DECADES
    if first >= max_time:
        first = max_time / 10.0 ** EMPTY_GRID_DECADES
    return np.geomspace(first, max_time, int(n_times))


def _survival(values, grid):
    """``S[..., k]``: share of particles (last axis) with no arrival at or before ``grid[k]``."""
    flat = values.reshape(-1, values.shape[-1])
    n = flat.shape[1]
    out = np.empty((len(flat), len(grid)))
    for i, row in enumerate(flat):
        fin = np.sort(row[np.isfinite(row)])
        out[i] = 1.0 - np.searchsorted(fin, grid, side="right") / n
    return out.reshape((*values.shape[:-1], len(grid)))


def _plateau(values, max_time, tail_span):
    """Aitken (geometric-series) extrapolation of the arrivals in the last ``tail_span`` of the run."""
    n = values.shape[-1]
    r = math.sqrt(tail_span)
    t1, t2, t3 = max_time / tail_span, max_time / r, max_time
    with np.errstate(invalid="ignore"):
        early = ((values >= t1) & (values < t2)).sum(axis=-1).astype(float)
        late = ((values >= t2) & (values <= t3)).sum(axis=-1).astype(float)
    final = (~np.isfinite(values)).sum(axis=-1) / n
    none_late = late == 0.0
    decaying = (late > 0.0) & (early - late > TAIL_SIGNIFICANCE * np.sqrt(early + late))
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(early > 0, late / early, np.nan)
        # particles still to arrive after max_time: sum_k n2 q^k over k >= 1
        future = np.where(none_late, 0.0, np.where(decaying, late * late / (early - late), np.nan))
        alpha = np.where(decaying, -np.log(q) / math.log(r), np.where(none_late & (early > 0), np.inf, np.nan))
        d_late = late * (2.0 * early - late) / (early - late) ** 2
        d_early = -(late / (early - late)) ** 2
        var_future = np.where(none_late, 0.0,
                              np.where(decaying, d_late ** 2 * late + d_early ** 2 * early, np.nan))
    trapped = np.clip(final - future / n, 0.0, final)
    var = var_future / n ** 2 + final * (1.0 - final) / n
    return dict(early=early, late=late, q=q, alpha=alpha, trapped=trapped, stderr=np.sqrt(var),
                final=final, windows=(t1, t2, t3))


def arrival_curve(ds, *, times=None, n_times=N_TIMES, max_time=None, tail_span=TAIL_SPAN):
    r"""Share of Galton-board particles not yet arrived against time, and its long-time level.

    The survival curve of the arrival times ``T_i`` of ``N`` particles (``T_i``
    infinite for a particle that has not arrived by ``max_time``),

    .. math::

        S(t) = \frac{1}{N} \#\{i : T_i > t\}, \qquad 0 < t \le t_\mathrm{max},

    is tabulated on a log-spaced grid for log-log axes, for every law (and
    every other dimension of ``ds`` but ``particle``, e.g. several ``gamma``).
    Its long-time level ``P = lim S(t)`` is the share of particles that never
    arrive (trapped); ``S(t_max) - P`` are slow particles.

    **Plateau estimator.**  Split the last ``tail_span`` of the run into two
    windows of equal log-width, ``[t1, t2)`` and ``[t2, t3]`` with
    ``t3 = t_max``, ``t2 = t3 / sqrt(span)``, ``t1 = t3 / span``, and count the
    arrivals ``n1``, ``n2`` in each.  If the tail is a power law
    ``S(t) - P ~ A t^(-alpha)``, arrivals in successive windows of equal
    log-width form a geometric series of ratio ``q = n2/n1 = span^(-alpha/2)``,
    so the particles still to arrive after ``t_max`` number
    ``n2 q / (1 - q) = n2^2 / (n1 - n2)`` (Aitken's extrapolation), and

    .. math::

        P \approx S(t_\mathrm{max}) - \frac{n_2^2}{N (n_1 - n_2)},
        \qquad \alpha = -\frac{2 \ln q}{\ln \mathrm{span}},

    clipped to ``[0, S(t_max)]``.  ``n2 = 0`` (no late arrivals) gives
    ``P = S(t_max)``.  Limits: the estimate is NaN when the arrivals are not
    measurably decaying (``n1 - n2 <= 2 sqrt(n1 + n2)``, two Poisson standard
    deviations, :data:`TAIL_SIGNIFICANCE`): the run is too short to be in the
    tail, or too few particles; run longer or more particles.  A tail that
    decays faster than a power law (e.g. exponentially) is over-extrapolated,
    so ``P`` is then biased low (towards "slow"), and one slower than the fitted power law (or a decay that starts after
    ``t_max``) is read as trapping, so ``P`` is biased high.  Doubling
    ``max_time`` and comparing is the test.  The standard error combines the
    Poisson noise of ``n1``, ``n2`` (delta method) with the binomial noise of
    ``S(t_max)``; it is large when ``n1 - n2`` is small.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`noslipsim.experiments.galton_distribution`: ``t_terminal``
        (dims ``(law, particle)`` or more; NaN when not arrived), optionally
        ``arrived`` (checked against ``t_terminal``) and a ``gamma``
        coordinate along ``law`` (carried to the output); attribute
        ``max_time``.  Times are nondimensional (the scene's units).
    times : array_like, optional
        Increasing times in ``(0, max_time]``; default ``n_times`` log-spaced
        times from the first arrival to ``max_time``.
    n_times : int
        Size of the default grid (>= 2).
    max_time : float, optional
        The run's time limit (default: ``ds.attrs['max_time']``).
    tail_span : float
        Ratio (> 1) of ``max_time`` to the start of the tail window of the
        plateau estimator (default one decade).

    Returns
    -------
    xarray.Dataset
        Dim ``time`` and every dim of ``ds.t_terminal`` but ``particle``:
        ``share_not_arrived`` and ``share_not_arrived_stderr``
        (``sqrt(S (1 - S)/N)``) per time; ``n_particles``,
        ``share_not_arrived_final`` (``S(t_max)``), ``arrivals_early``,
        ``arrivals_late``, ``tail_ratio``, ``tail_exponent``,
        ``trapped_share``, ``trapped_share_stderr`` and ``slow_share``
        (``S(t_max) - P``) per curve.  Attributes: ``max_time``,
        ``tail_span``, ``tail_windows`` ``(t1, t2, t3)``, the estimator, and
        the source dataset's attributes (prefixed ``source_``).

    References
    ----------
    N. Chernov, D. Dolgopyat, *The Galton board: limit theorems and
    recurrence*, J. Amer. Math. Soc. 22 (2009) 821-858 (the ``t^(2/3)``
    descent of the specular board).  Derivation: docs/analysis.md.
    """
    t, max_time = _check_dataset(ds, max_time)
    tail_span = finite_float(tail_span, "tail_span")
    if not tail_span > 1.0:
        raise ValueError(f"tail_span: must be > 1, got {tail_span}")
    values = t.values.astype(float)
    grid = _time_grid(values, times, n_times, max_time)
    n = values.shape[-1]
    surv = _survival(values, grid)
    tail = _plateau(values, max_time, tail_span)

    dims = t.dims[:-1]
    coords = {name: c.variable.copy(deep=False) for name, c in t.coords.items() if "particle" not in c.dims}
    coords["time"] = ("time", grid)
    per_curve = dims
    out = xr.Dataset(
        {
            "share_not_arrived": ((*dims, "time"), surv),
            "share_not_arrived_stderr": ((*dims, "time"), np.sqrt(surv * (1.0 - surv) / n)),
            "n_particles": (per_curve, np.full(values.shape[:-1], n, dtype=np.int64)),
            "share_not_arrived_final": (per_curve, tail["final"]),
            "arrivals_early": (per_curve, tail["early"].astype(np.int64)),
            "arrivals_late": (per_curve, tail["late"].astype(np.int64)),
            "tail_ratio": (per_curve, tail["q"]),
            "tail_exponent": (per_curve, tail["alpha"]),
            "trapped_share": (per_curve, tail["trapped"]),
            "trapped_share_stderr": (per_curve, tail["stderr"]),
            "slow_share": (per_curve, tail["final"] - tail["trapped"]),
        },
        coords=coords,
    )
    out.attrs.update({f"source_{k}": v for k, v in ds.attrs.items()})
    out.attrs.update(
        title="Galton board: share of particles not arrived against time",
        max_time=max_time,
        tail_span=tail_span,
        tail_windows=list(tail["windows"]),
        estimator=("trapped_share = S(max_time) - n2^2 / (N (n1 - n2)), n1, n2 arrivals in "
                   "[t1, t2), [t2, t3]; geometric (power-law) tail assumed; NaN unless n1 - n2 > "
                   f"{TAIL_SIGNIFICANCE} sqrt(n1 + n2)"),
    )
    return annotate(out)


#: Bootstrap resamples of :func:`excess_kurtosis`'s standard error.
KURTOSIS_RESAMPLES = 200


def excess_kurtosis(values, *, resamples=KURTOSIS_RESAMPLES, seed=0):
    r"""Excess kurtosis of a sample and its bootstrap standard error (0 for a normal law).

    .. math::

        \kappa = \frac{\overline{(x - \bar x)^4}}{\left(\overline{(x - \bar x)^2}\right)^2} - 3 .

    A normal law has ``kappa = 0``; heavier tails than the normal of the same
    standard deviation give ``kappa > 0``.  For a normal sample of size ``n``
    the standard error is about ``sqrt(24 / n)``; the bootstrap (``resamples``
    resamples with replacement, a fixed ``seed``: the same number every run)
    also holds for the heavy-tailed samples where that formula does not.

    Parameters
    ----------
    values : array_like
        The sample (finite numbers, at least 4 that are not all equal).
    resamples : int
        Bootstrap resamples (>= 2).
    seed : int
        Seed of the resampling.

    Returns
    -------
    (float, float)
        ``kappa`` and its bootstrap standard error.
    """
    x = np.asarray(values, dtype=float).ravel()
    if x.size < 4 or not np.all(np.isfinite(x)):
        raise ValueError(f"values: expected at least 4 finite numbers, got {x.size} values "
                         f"({int((~np.isfinite(x)).sum())} not finite)")
    if not resamples >= 2:
        raise ValueError(f"resamples: must be >= 2, got {resamples}")

    def kappa(sample):
        z = sample - sample.mean(axis=-1, keepdims=True)
        m2 = np.mean(z * z, axis=-1)
        return np.mean(z ** 4, axis=-1) / m2 ** 2 - 3.0

    if not np.ptp(x) > 0:
        raise ValueError("values: all equal, the kurtosis is undefined")
    rng = np.random.default_rng(seed)
    boot = np.array([kappa(x[rng.integers(0, x.size, x.size)]) for _ in range(int(resamples))])
    return float(kappa(x)), float(np.std(boot[np.isfinite(boot)], ddof=1))


#: The robust tail statistic's threshold, in standard deviations.
TAIL_SIGMAS = 3.0


def tail_share(values, *, sigmas=TAIL_SIGMAS):
    r"""Share of a sample beyond ``sigmas`` standard deviations from its mean, against the normal law's.

    .. math::

        p = \frac{1}{n} \#\{i : |x_i - \bar x| > k s\}, \qquad
        p_\mathrm{normal} = \operatorname{erfc}(k / \sqrt 2),

    with ``s`` the sample standard deviation (``ddof=1``) and ``k = sigmas``
    (``p_normal = 0.27 %`` at ``k = 3``).  Unlike the excess kurtosis, which a
    handful of far particles sets (its fourth moment), ``p`` counts particles:
    its standard error is the binomial ``sqrt(p (1 - p) / n)``, so a
    heavy-tailed sample (``p > p_normal``) is told from a normal one by counts
    that do not hinge on the farthest few.

    Parameters
    ----------
    values : array_like
        The sample (finite numbers, at least 2 that are not all equal).
    sigmas : float
        The threshold ``k`` (> 0), in sample standard deviations.

    Returns
    -------
    (float, float, float)
        ``p``, its binomial standard error, and ``p_normal``.
    """
    x = np.asarray(values, dtype=float).ravel()
    if x.size < 2 or not np.all(np.isfinite(x)):
        raise ValueError(f"values: expected at least 2 finite numbers, got {x.size} values "
                         f"({int((~np.isfinite(x)).sum())} not finite)")
    k = positive(sigmas, "sigmas")
    if not np.ptp(x) > 0:
        raise ValueError("values: all equal, the standard deviation is 0")
    p = float(np.mean(np.abs(x - x.mean()) > k * x.std(ddof=1)))
    return p, math.sqrt(p * (1.0 - p) / x.size), math.erfc(k / math.sqrt(2.0))
