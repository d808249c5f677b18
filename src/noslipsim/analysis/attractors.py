r"""Attracting periodic orbits of a dissipative flow: orbits that settle onto a cycle of collisions.

In a measure-preserving billiard a regular orbit lies on an invariant torus and
never repeats itself.  With a thermostat the flow contracts phase volume
(docs/analysis.md, "The thermostatted Lorentz gas"), and an orbit with a
finite-time exponent near zero may instead have fallen onto an attracting
periodic orbit: after a transient it returns to the same state after ``p``
collisions, again and again.  This module tells the two apart from a recorded
sequence of collision states (a portrait's ``(s, v_t, w)``).

1. **Period of one orbit** (:func:`orbit_period`): the smallest ``p`` such that
   the last ``(repeats + 1) p`` recorded states repeat after ``p`` steps,

   .. math::

       \max_{k \ge n - (r + 1) p} \lVert x_{k + p} - x_k \rVert_\infty \le \epsilon ,

   with ``n`` the recorded states, ``r`` the repeats and ``epsilon`` the
   tolerance (a boundary coordinate compared modulo its period).  ``0``: no
   such ``p`` (chaos, a torus, or a cycle not yet reached).
2. **Which attractor** (:func:`attractor_labels`): two orbits with the same
   period share an attractor when the last state of one lies within the
   tolerance of a state of the other's last cycle.  Attractors are numbered by
   the orbits they hold, most first.

A chaotic orbit returns near its last state now and then, but not for two whole
periods in a row within ``1e-6``: that would take a coincidence of probability
about ``epsilon^(d r p)``.
"""
from __future__ import annotations

import numpy as np

from .._metadata import annotate
from .._validate import count, positive

__all__ = ["ATTRACTOR_REPEATS", "ATTRACTOR_TOLERANCE", "attractor_census", "attractor_labels", "orbit_period",
           "portrait_attractors"]

#: Largest distance (max norm over the coordinates) at which two recorded states count as the same.
#: Coordinates of order one; a cycle reached by contraction sits at rounding level, 1e-12 and below,
#: while a torus orbit drifts along its circle by more than this every passage.
ATTRACTOR_TOLERANCE = 1e-6

#: Times the whole cycle must repeat at the end of the record (besides its first passage).
ATTRACTOR_REPEATS = 2


def _states(points, wrap):
    """The finite rows of ``points`` (trailing NaN padding dropped) and the wrap periods as an array."""
    x = np.asarray(points, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2:
        raise ValueError(f"points: expected an array (point, coordinate), got shape {x.shape}")
    keep = np.all(np.isfinite(x), axis=1)
    n = int(np.argmin(keep)) if not keep.all() else len(x)
    if keep[n:].any():
        raise ValueError("points: NaN rows are allowed only as trailing padding")
    if wrap is None:
        periods = np.zeros(x.shape[1])
    else:
        periods = np.asarray([0.0 if p is None else float(p) for p in wrap])
        if periods.shape != (x.shape[1],) or np.any(~np.isfinite(periods)) or np.any(periods < 0):
            raise ValueError(f"wrap: expected one period >= 0 (0 or None: no wrap) per coordinate, got {wrap}")
    return x[:n], periods


def _distance(a, b, periods):
    """Max-norm distance between states ``a`` and ``b`` (broadcast), coordinates with a period wrapped."""
    d = np.abs(a - b)
    wrapped = periods > 0
    if wrapped.any():
        d[..., wrapped] = np.minimum(d[..., wrapped] % periods[wrapped],
                                     periods[wrapped] - d[..., wrapped] % periods[wrapped])
    return d.max(axis=-1)


def orbit_period(points, *, tolerance=ATTRACTOR_TOLERANCE, repeats=ATTRACTOR_REPEATS, wrap=None):
    """Period of the cycle an orbit ends on, in recorded collisions (0: none).

    Parameters
    ----------
    points : array_like, shape (n, d) or (n,)
        The orbit's recorded states in order (e.g. ``s_boundary``, ``vt_unit``,
        ``w_unit`` at each disk collision); trailing NaN rows are padding.
    tolerance : float
        Largest max-norm distance between two states counted as the same (> 0).
    repeats : int
        Times the cycle must repeat after its first passage (>= 1).
    wrap : sequence of float, optional
        Per coordinate, its period (a closed boundary's length), or 0 / None
        for a coordinate compared as it is.

    Returns
    -------
    int
        The smallest ``p`` whose last ``(repeats + 1) p`` states repeat after
        ``p`` steps within ``tolerance``; 0 if there is none with
        ``(repeats + 1) p <= n``.
    """
    tolerance = positive(tolerance, "tolerance")
    repeats = count(repeats, "repeats")
    x, periods = _states(points, wrap)
    n = len(x)
    longest = n // (repeats + 1)
    if longest < 1:
        return 0
    # cheap screen first: the last state must come back after p steps, only then the whole tail is checked
    back = _distance(x[n - 1 - np.arange(1, longest + 1)], x[n - 1], periods)
    for p in np.flatnonzero(back <= tolerance) + 1:
        tail = x[n - (repeats + 1) * p:]
        if np.all(_distance(tail[p:], tail[:-p], periods) <= tolerance):
            return int(p)
    return 0


def attractor_labels(orbits, periods, *, tolerance=ATTRACTOR_TOLERANCE, wrap=None):
    """Which attracting cycle each orbit ends on: labels numbered by population, most first.

    Parameters
    ----------
    orbits : sequence of array_like, each (n_i, d)
        The orbits' recorded states (trailing NaN rows are padding).
    periods : sequence of int
        Each orbit's period from :func:`orbit_period` (0: none).
    tolerance, wrap
        As in :func:`orbit_period`.

    Returns
    -------
    numpy.ndarray of int
        Per orbit, its attractor (0 the one most orbits end on, 1 the next ...,
        ties broken by the first orbit that reaches it); -1 for an orbit
        without a period.
    """
    tolerance = positive(tolerance, "tolerance")
    periods = [int(p) for p in periods]
    if len(periods) != len(orbits):
        raise ValueError(f"periods: expected one per orbit ({len(orbits)}), got {len(periods)}")
    cycles, members = [], []      # per attractor found: (period, its last cycle), and its orbits
    found = np.full(len(orbits), -1)
    for i, (pts, p) in enumerate(zip(orbits, periods)):
        if p <= 0:
            continue
        x, wrap_periods = _states(pts, wrap)
        for a, (q, cycle) in enumerate(cycles):
            if q == p and np.min(_distance(cycle, x[-1], wrap_periods)) <= tolerance:
                found[i] = a
                members[a].append(i)
                break
        else:
            found[i] = len(cycles)
            cycles.append((p, x[-p:]))
            members.append([i])
    order = sorted(range(len(cycles)), key=lambda a: (-len(members[a]), members[a][0]))
    rank = {a: r for r, a in enumerate(order)}
    return np.array([rank[a] if a >= 0 else -1 for a in found], dtype=int)


def attractor_census(periods, labels):
    """The attractors of one case, most populated first: ``[(period, orbits on it), ...]``.

    Parameters
    ----------
    periods, labels : array_like of int, (orbit,)
        ``attractor_period`` and ``attractor`` of one case (:func:`portrait_attractors`).

    Returns
    -------
    list of (int, int)
        One pair per attractor in label order (0 first); empty when no orbit
        ends on a cycle.
    """
    periods, labels = np.asarray(periods, dtype=int), np.asarray(labels, dtype=int)
    if periods.shape != labels.shape or periods.ndim != 1:
        raise ValueError(f"periods, labels: expected two 1-D arrays of one shape, got {periods.shape}, "
                         f"{labels.shape}")
    found = labels >= 0
    if np.any(periods[found] <= 0) or np.any(periods[~found] != 0):
        raise ValueError("periods, labels: an orbit has a period exactly when it has an attractor")
    return [(int(periods[labels == a][0]), int(np.sum(labels == a))) for a in range(int(labels.max(initial=-1)) + 1)]


def portrait_attractors(ds, *, tolerance=ATTRACTOR_TOLERANCE, repeats=ATTRACTOR_REPEATS):
    """A portrait dataset with the attracting cycle of each orbit: ``attractor_period`` and ``attractor``.

    The states compared are the portrait's ``(s_boundary, vt_unit, w_unit)`` at
    each recorded collision, ``s_boundary`` modulo the case's
    ``boundary_length``.  Orbits are grouped into attractors case by case
    (every dimension but ``orbit`` and ``point``).

    Parameters
    ----------
    ds : xarray.Dataset
        A :func:`noslipsim.experiments.portrait_set` dataset (dims ``(..., orbit, point)``).
    tolerance, repeats
        As in :func:`orbit_period`.

    Returns
    -------
    xarray.Dataset
        A copy with ``attractor_period`` (collisions recorded per cycle, 0: none)
        and ``attractor`` (-1: none) over the dims of ``n_points``, and the
        attributes ``attractor_tolerance`` and ``attractor_repeats``.
    """
    missing = [k for k in ("s_boundary", "vt_unit", "w_unit", "boundary_length") if k not in ds]
    if missing:
        raise ValueError(f"ds: not a portrait dataset, missing {missing}")
    tolerance = positive(tolerance, "tolerance")
    repeats = count(repeats, "repeats")
    case_dims = [d for d in ds.s_boundary.dims if d not in ("orbit", "point")]
    order = (*case_dims, "orbit", "point")      # one order for the three, whatever each was stored in
    states = np.stack([ds[k].transpose(*order).values for k in ("s_boundary", "vt_unit", "w_unit")], axis=-1)
    length = ds.boundary_length.broadcast_like(ds.s_boundary.isel(orbit=0, point=0)).transpose(*case_dims).values
    period = np.zeros(states.shape[:-2], dtype=int)
    label = np.full(states.shape[:-2], -1, dtype=int)
    for case in np.ndindex(*states.shape[:-3]):
        wrap = (float(length[case]), None, None)
        period[case] = [orbit_period(x, tolerance=tolerance, repeats=repeats, wrap=wrap) for x in states[case]]
        label[case] = attractor_labels(list(states[case]), period[case], tolerance=tolerance, wrap=wrap)
    out = ds.copy()
    dims = (*case_dims, "orbit")
    out["attractor_period"] = (dims, period)
    out["attractor"] = (dims, label)
    out.attrs.update(attractor_tolerance=tolerance, attractor_repeats=repeats)
    return annotate(out)
