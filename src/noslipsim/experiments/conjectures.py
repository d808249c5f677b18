r"""Two of the paper's conjectures as experiments with counts (Figures S4 and S5, docs/conjectures.md).

*Launch angle* (the paper's conjecture ``launchstability``: the stability of
path-reversing 2-periodic orbits of no-slip billiards with force depends on the
launch angle).  :func:`launch_angle_classes` classifies the two-disk 2-periodic
orbit of Figure 15 (:func:`noslipsim.analysis.two_disk_orbit`) over an
``R x phi x theta`` grid by the exact monodromy, counts the ``(R, phi)`` columns
whose class changes with ``theta`` alone, and measures the elliptic boundary
``R_e(phi)`` at each ``theta`` against the force-free closed form ``R^*(phi)``.

*Isolated periodic orbits* (the paper's conjecture, part ii: isolated higher-order
periodic orbits exist on a wedge under a force).  :func:`wedge_periodic_census`
runs the periodic-orbit finder (:func:`noslipsim.analysis.find_periodic_orbit`)
from many seeded random starts on wedges of several half-angles under forces of
several directions, for each requested period; every search is a row (failures
included), and :func:`census_counts` counts distinct orbits per minimal period,
isolated (no eigenvalue 1 of the monodromy, ``Monodromy.isolated``, the test of
Figure 7) or in a family.
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .. import tables, theory
from .._metadata import annotate
from .._scheduler import run_tasks
from .._validate import count, finite_float
from ..analysis import elliptic_boundary, find_periodic_orbit, monodromy, two_disk_classes
from ..simulate import simulate

__all__ = ["census_counts", "launch_angle_classes", "wedge_periodic_census"]

#: Two found orbits are the same when their scale-free cycle states differ by less than this.
SAME_ORBIT_TOL = 1e-6

#: Search outcomes, in the order the figure stacks them.
OUTCOMES = ("found", "not converged", "no return")


# ----------------------------------------------------------------------------- launch angle
def _angles(values, field):
    arr = np.atleast_1d(np.asarray(values, dtype=float))
    if arr.ndim != 1 or arr.size == 0 or not np.all(np.isfinite(arr)):
        raise ValueError(f"{field}: expected a non-empty 1-D array of finite numbers, got {values!r}")
    if arr.size > 1 and (np.diff(arr) <= 0).any():
        raise ValueError(f"{field}: must be strictly increasing")
    return arr


def _column_changes(kinds):
    """Per ``(R, phi)`` column: distinct classes along ``theta`` and whether both elliptic and hyperbolic occur."""
    present = np.stack([(kinds == k) for k in ("elliptic", "hyperbolic", "parabolic")]).any(axis=-1)
    return present.sum(axis=0), (present[0] & present[1])


def _sides(kinds, phis, thetas, margin):
    """Changes below the parabolic line ``theta < pi/2 - phi - margin``, and the classes above it.

    Under gravity the launch parallel to the tangent at ``q1``
    (``phi + theta = pi/2``) is parabolic for every ``R``, so a column that
    crosses it may change class there alone; below it a change is the launch
    angle's doing away from that line.
    """
    below = thetas[None, :] < math.pi / 2 - phis[:, None] - margin     # (phi, theta)
    above = thetas[None, :] > math.pi / 2 - phis[:, None] + margin
    kb = np.where(below[None], kinds, "")
    counted = (kb != "").sum(axis=-1) >= 2
    both = (kb == "elliptic").any(axis=-1) & (kb == "hyperbolic").any(axis=-1) & counted
    ka = kinds[np.broadcast_to(above[None], kinds.shape)]
    return both, counted, int((ka != "").sum()), int((ka == "hyperbolic").sum())


def _boundaries(eigen_sum, radii, phis, thetas, threshold, margin):
    """``R_e(phi)`` and ``R^* - R_e`` at each ``theta`` (:func:`noslipsim.analysis.elliptic_boundary`)."""
    rows = []
    for j, theta in enumerate(thetas):
        grid = xr.Dataset({"eigen_sum": (("radius", "phi"), eigen_sum[:, :, j]),
                           "radius_threshold": ("phi", threshold)},
                          coords={"radius": radii, "phi": phis}, attrs={"theta": float(theta)})
        rows.append(elliptic_boundary(grid, margin=margin))
    return (np.array([r.boundary.values for r in rows]).T, np.array([r.radius_shift.values for r in rows]).T)


def launch_angle_classes(radii, phis, thetas, gamma=1 / math.sqrt(2), *, gravity=1.0, margin=0.05,
                         scheduler="numba", num_workers=None):
    r"""Linear class of the two-disk 2-periodic orbits over ``R x phi x theta``: does ``theta`` alone change it?

    For each radius, one :func:`noslipsim.analysis.two_disk_classes` call
    classifies every ``(phi, theta)`` (elliptic, hyperbolic, parabolic, from
    the exact 2-bounce monodromy).  The wedge geometry is scale invariant under
    gravity, so neither ``g`` nor the launch speed changes a class; as
    ``theta -> 0`` the orbit becomes the force-free chord, elliptic exactly for

    .. math::

        R > R^*(\varphi) = \frac{2}{\mathrm{thr}(\varphi) + 2\cos\varphi},

    ``thr`` the paper's ellipticity threshold
    (:func:`noslipsim.theory.ellipticity_threshold`).

    Parameters
    ----------
    radii : array_like
        Disk radii in ``(0, 1)``, strictly increasing (centres 2 apart).
    phis, thetas : array_like
        Angles of ``q0`` and launch angles above the chord, in ``(0, pi/2)``, strictly increasing.
    gamma : float
        Mass-distribution constant ``> 0``.
    gravity : float
        ``g > 0``; force ``(0, -g)``.
    margin : float
        Boundary columns with ``phi + theta`` within ``margin`` of ``pi/2``
        (the launch parallel to the tangent at ``q1``, parabolic for every
        ``R``) are left out (:func:`noslipsim.analysis.elliptic_boundary`).
    scheduler, num_workers
        Passed to :func:`noslipsim.simulate_many` (one call per radius).

    Returns
    -------
    xarray.Dataset
        ``linear_kind`` and ``eigen_sum`` on ``(radius, phi, theta)`` (``''``
        and NaN where no orbit exists); on ``(radius, phi)``: ``n_classes``
        (distinct classes along ``theta``), ``class_changes`` and
        ``elliptic_hyperbolic`` (int8), ``elliptic_hyperbolic_below`` (both
        classes met with ``theta < pi/2 - phi - margin``, below the parabolic
        line); on ``(phi, theta)``: ``boundary``
        (``R_e``) and ``radius_shift`` (``R^* - R_e``); on ``phi``:
        ``radius_threshold`` (``R^*``).  Attributes: ``n_columns`` (columns
        with an orbit at two launch angles at least), ``n_changing``,
        ``n_elliptic_hyperbolic``, ``n_missing`` (grid points without orbit),
        ``n_columns_below``, ``n_changing_below`` (the same below the line),
        ``n_above``, ``n_above_hyperbolic`` (points above the line, and the hyperbolic ones).

    Raises
    ------
    ValueError
        Bad axes (outside their intervals, not increasing), ``gamma <= 0``, ``gravity <= 0``.
    """
    radii, phis, thetas = (_angles(a, f) for a, f in ((radii, "radii"), (phis, "phis"), (thetas, "thetas")))
    if ((radii <= 0) | (radii >= 1)).any():
        raise ValueError("radii: every radius must lie in (0, 1) (disks centred 2 apart must not touch)")
    for name, arr in (("phis", phis), ("thetas", thetas)):
        if ((arr <= 0) | (arr >= math.pi / 2)).any():
            raise ValueError(f"{name}: every angle must lie in (0, pi/2)")
    gamma, gravity = finite_float(gamma, "gamma"), finite_float(gravity, "gravity")
    if not gamma > 0 or not gravity > 0:
        raise ValueError(f"gamma, gravity: both must be > 0, got {gamma}, {gravity}")
    points = [(p, t) for p in phis for t in thetas]
    kinds = np.full((radii.size, phis.size, thetas.size), "", dtype="<U10")
    eigen_sum = np.full(kinds.shape, np.nan)
    for i, R in enumerate(radii):
        k, e = two_disk_classes(R, points, gamma, gravity=gravity, scheduler=scheduler, num_workers=num_workers)
        kinds[i], eigen_sum[i] = k.reshape(phis.size, thetas.size), e.reshape(phis.size, thetas.size)
    threshold = 2.0 / (np.asarray(theory.ellipticity_threshold(phis, gamma)) + 2.0 * np.cos(phis))
    boundary, shift = _boundaries(eigen_sum, radii, phis, thetas, threshold, margin)
    n_classes, both = _column_changes(kinds)
    counted = (kinds != "").sum(axis=-1) >= 2
    below, counted_below, n_above, n_above_hyperbolic = _sides(kinds, phis, thetas, margin)
    ds = xr.Dataset(
        {"linear_kind": (("radius", "phi", "theta"), kinds), "eigen_sum": (("radius", "phi", "theta"), eigen_sum),
         "n_classes": (("radius", "phi"), n_classes.astype(np.int64)),
         "class_changes": (("radius", "phi"), ((n_classes > 1) & counted).astype(np.int8)),
         "elliptic_hyperbolic": (("radius", "phi"), (both & counted).astype(np.int8)),
         "elliptic_hyperbolic_below": (("radius", "phi"), below.astype(np.int8)),
         "boundary": (("phi", "theta"), boundary), "radius_shift": (("phi", "theta"), shift),
         "radius_threshold": ("phi", threshold)},
        coords={"radius": radii, "phi": phis, "theta": thetas})
    ds.attrs.update(title="linear class of two-disk 2-periodic orbits over radius, phi and launch angle",
                    law="no-slip", gamma=gamma, gravity=gravity, margin=float(margin),
                    scene=("two no-slip disks of radius R centred at (-1, 0) and (1, 0), open table "
                           "(noslipsim.tables.two_disks(R, distance=2))"),
                    n_columns=int(counted.sum()), n_changing=int(ds.class_changes.sum()),
                    n_elliptic_hyperbolic=int(ds.elliptic_hyperbolic.sum()), n_missing=int((kinds == "").sum()),
                    n_columns_below=int(counted_below.sum()), n_changing_below=int(below.sum()), n_above=n_above,
                    n_above_hyperbolic=n_above_hyperbolic)
    return annotate(ds)


# ----------------------------------------------------------------------------- periodic census
def _force(angle, gravity):
    """Force of magnitude ``gravity`` turned ``angle`` rad counter-clockwise from straight down."""
    return (gravity * math.sin(angle), -gravity * math.cos(angle))


def _random_start(rng, phi):
    """A start inside the wedge (opening up): height, place across, direction, speed and spin at random."""
    y = rng.uniform(0.5, 2.0)
    x = rng.uniform(-0.9, 0.9) * y * math.tan(phi)
    a, speed = rng.uniform(0.0, 2.0 * math.pi), rng.uniform(0.3, 2.5)
    return (x, y), (speed * math.cos(a), speed * math.sin(a)), rng.uniform(-2.0, 2.0)


def _cycle(scene, state, period):
    """Minimal period, itinerary and scale-free post-collision states ``(element, s/V^2, w/V, v_t/V)`` of a cycle.

    ``V`` is the largest speed ``sqrt(|v|^2 + w^2)`` on the cycle: the wedge
    under a force is scale invariant (``q -> c^2 q``, ``v -> c v``), so the
    scaled states name an orbit whatever the energy the search landed on.
    """
    run = simulate(scene, **state, max_collisions=period + 1)
    el = run.element.values.astype(int)
    n_out = np.array([scene.elements[e].normal for e in el], dtype=float) * -1.0
    vx, vy, w, s = (run[k].values for k in ("vx", "vy", "spin", "s"))
    vt = vx * -n_out[:, 1] + vy * n_out[:, 0]
    V = float(np.sqrt(vx ** 2 + vy ** 2 + w ** 2)[:period].max())
    X = np.c_[el, s / V ** 2, w / V, vt / V]
    d = next((d for d in range(1, period + 1) if period % d == 0 and el[d] == el[0]
             and np.abs(X[d, 1:] - X[0, 1:]).max() <= SAME_ORBIT_TOL), period)
    return d, "".join("LR"[e] for e in el[:d]), X[:d]


def _search(phi, angle, gravity, gamma, period, seed, tol, max_iter):
    """One search from a seeded random start: its outcome and, if found, the orbit's facts."""
    rng = np.random.default_rng(seed)
    scene = tables.wedge(phi, gamma=gamma, force=_force(angle, gravity))
    q, v, w = _random_start(rng, phi)
    out = {"outcome": "no return", "minimal_period": 0, "residual": math.nan, "unit_count": -1, "isolated": -1,
           "linear_kind": "", "itinerary": "", "cycle": None}
    try:
        res = find_periodic_orbit(scene, q, v, w, period=period, tol=tol, max_iter=max_iter)
    except ValueError:  # the start escapes or stops before it returns to its element: no return map
        return out
    out["residual"] = float(res.residual)
    if not res.converged:
        out["outcome"] = "not converged"
        return out
    out.update(outcome="found", **_found_orbit(scene, res.state, period))
    return out


def _found_orbit(scene, state, period):
    """Minimal period, isolation (no eigenvalue 1), class, itinerary and scale-free cycle of a periodic orbit."""
    d, itinerary, cycle = _cycle(scene, state, period)
    mono = monodromy(scene, **state, period=d)  # of the minimal period: M^k may gain a 1 from roots of unity
    return dict(minimal_period=d, unit_count=mono.unit_count(), isolated=int(mono.isolated), linear_kind=mono.kind,
                itinerary=itinerary, cycle=cycle)


def _search_batch(phi, angle, gravity, gamma, period, seeds, tol, max_iter):
    return [_search(phi, angle, gravity, gamma, period, s, tol, max_iter) for s in seeds]


def _same_cycle(a, b):
    """Two scale-free cycles of the same length are one orbit when one starts somewhere on the other."""
    if len(a) != len(b):
        return False
    return any(np.array_equal(np.roll(b[:, 0], -k), a[:, 0])
               and np.abs(np.roll(b[:, 1:], -k, axis=0) - a[:, 1:]).max() <= SAME_ORBIT_TOL for k in range(len(b)))


def _mark_distinct(rows, case):
    """``distinct`` = 1 on the first search that found each orbit of one ``(phi, force)`` case, 0 on repeats."""
    seen = []
    for i in case:
        row = rows[i]
        row["distinct"] = 0
        if row["cycle"] is not None and not any(_same_cycle(row["cycle"], c) for c in seen):
            seen.append(row["cycle"])
            row["distinct"] = 1


def wedge_periodic_census(phis, force_angles, periods, gamma=1 / math.sqrt(2), *, gravity=1.0, starts=20, seed=0,
                          tol=1e-12, max_iter=40, scheduler="sync", num_workers=None, progress=None):
    r"""Periodic orbits of no-slip wedges under a force, found from many random starts, counted (Figure S5).

    For each half-angle ``phi`` (wedge opening up), force direction (turned
    ``angle`` from straight down, magnitude ``gravity``) and requested period
    ``p``, ``starts`` searches (:func:`noslipsim.analysis.find_periodic_orbit`)
    start from seeded random states inside the wedge (height 0.5 to 2, speed
    0.3 to 2.5, any direction, spin -2 to 2).  Each search is a row, whatever
    its outcome: ``'found'``, ``'not converged'`` (the Newton search stalled or
    ran out of iterations) or ``'no return'`` (the start escapes or stops before
    returning to its element: no return map).  A found orbit is run again for
    its minimal period ``d`` (a divisor of ``p``), its wall itinerary, and the
    monodromy of ``d`` collisions: *isolated* when no eigenvalue is 1
    (``Monodromy.isolated``, the test of Figure 7), otherwise on a
    one-parameter family at fixed energy.  Found orbits are compared up to the
    wedge's scale symmetry (``q -> c^2 q``, ``v -> c v``): ``distinct`` marks
    the first search to find each orbit of its ``(phi, force)`` case (members
    of one family found at different points count as distinct orbits).

    Parameters
    ----------
    phis : array_like
        Wedge half-angles in ``(0, pi/2)``.
    force_angles : array_like
        Force directions, radians counter-clockwise from straight down.
    periods : sequence of int
        Periods requested (``>= 1``).
    gamma : float
        Mass-distribution constant ``> 0``.
    gravity : float
        Force magnitude ``> 0``.
    starts : int
        Searches per ``(phi, angle, period)``.
    seed : int
        The searches' starts come from ``numpy.random.default_rng([seed, i, j, p, k])``:
        the same whatever the scheduler.
    tol, max_iter
        Passed to :func:`~noslipsim.analysis.find_periodic_orbit`.
    scheduler, num_workers, progress
        One task per ``(phi, angle, period)``: ``'sync'``, local threads, or a
        ``dask.distributed`` Client or its address (``noslipsim.cluster.ensemble_options``).

    Returns
    -------
    xarray.Dataset
        Along ``search``: ``phi``, ``force_angle``, ``period`` (requested),
        ``outcome``, ``minimal_period`` (0 if none found), ``residual``,
        ``unit_count``, ``isolated`` (1, 0; -1 if none found),
        ``linear_kind``, ``itinerary`` (walls, ``L``/``R``), ``distinct``.

    Raises
    ------
    ValueError
        Bad half-angles, periods, counts, ``gamma`` or ``gravity``.
    """
    phis = _angles(phis, "phis")
    if ((phis <= 0) | (phis >= math.pi / 2)).any():
        raise ValueError("phis: every half-angle must lie in (0, pi/2)")
    angles = _angles(force_angles, "force_angles")
    periods = [count(p, "periods") for p in np.atleast_1d(periods)]
    starts, seed = count(starts, "starts"), int(seed)
    gamma, gravity = finite_float(gamma, "gamma"), finite_float(gravity, "gravity")
    if not gamma > 0 or not gravity > 0:
        raise ValueError(f"gamma, gravity: both must be > 0, got {gamma}, {gravity}")
    cases = [(i, j, p) for i in range(phis.size) for j in range(angles.size) for p in periods]
    jobs = (((i, j, p), (float(phis[i]), float(angles[j]), gravity, gamma, p,
                         [[seed, i, j, p, k] for k in range(starts)], tol, max_iter)) for i, j, p in cases)
    found = {}
    run_tasks(_search_batch, jobs, found.__setitem__, scheduler=scheduler, num_workers=num_workers,
              progress=progress, total=len(cases))
    rows, meta = [], []
    for i, j, p in cases:  # the order of the cases, not of completion
        for row in found[(i, j, p)]:
            rows.append(row)
            meta.append((phis[i], angles[j], p, i, j))
    for i in range(phis.size):
        for j in range(angles.size):
            _mark_distinct(rows, [k for k, m in enumerate(meta) if m[3] == i and m[4] == j])
    column = lambda key, dtype=None: np.array([r[key] for r in rows], dtype=dtype)  # noqa: E731
    ds = xr.Dataset(
        {"phi": ("search", np.array([m[0] for m in meta])), "force_angle": ("search", np.array([m[1] for m in meta])),
         "period": ("search", np.array([m[2] for m in meta], dtype=np.int64)),
         "outcome": ("search", column("outcome", "<U13")),
         "minimal_period": ("search", column("minimal_period", np.int64)),
         "residual": ("search", column("residual", float)), "unit_count": ("search", column("unit_count", np.int64)),
         "isolated": ("search", column("isolated", np.int8)), "linear_kind": ("search", column("linear_kind", "<U10")),
         "itinerary": ("search", column("itinerary", "<U32")), "distinct": ("search", column("distinct", np.int8))},
        coords={"search": np.arange(len(rows))})
    ds.attrs.update(title="periodic orbits of no-slip wedges under a force, from random starts", law="no-slip",
                    opening="up", gamma=gamma, gravity=gravity, starts=starts, seed=seed, tol=float(tol),
                    max_iter=int(max_iter), phis=phis.tolist(), force_angles=angles.tolist(), periods=periods,
                    same_orbit_tolerance=SAME_ORBIT_TOL,
                    force_description="magnitude gravity, turned force_angle rad counter-clockwise from (0, -1)")
    return annotate(ds)


def census_counts(ds):
    """Counts of a :func:`wedge_periodic_census`: searches by outcome, distinct orbits by minimal period.

    Parameters
    ----------
    ds : xarray.Dataset
        A census dataset.

    Returns
    -------
    xarray.Dataset
        Along ``period`` (the requested periods): ``searches`` by ``outcome``;
        along ``minimal_period`` (1 to the largest requested): ``distinct``,
        ``isolated`` and ``family`` (distinct orbits without and with the eigenvalue 1).
    """
    periods = np.atleast_1d(np.asarray(ds.attrs["periods"], dtype=np.int64))  # a one-item list reads back a scalar
    p, outcome = ds.period.values, ds.outcome.values.astype(str)
    searches = np.array([[int(((p == q) & (outcome == o)).sum()) for o in OUTCOMES] for q in periods])
    minimal = np.arange(1, periods.max() + 1)
    new = ds.distinct.values.astype(bool)
    d, iso = ds.minimal_period.values, ds.isolated.values
    per = lambda mask: np.array([int((new & mask & (d == m)).sum()) for m in minimal])  # noqa: E731
    return xr.Dataset({"searches": (("period", "outcome"), searches), "distinct": ("minimal_period", per(new)),
                       "isolated": ("minimal_period", per(iso == 1)), "family": ("minimal_period", per(iso == 0))},
                      coords={"period": periods, "outcome": list(OUTCOMES), "minimal_period": minimal})
