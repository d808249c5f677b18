r"""Non-path-reversing 2-periodic orbits between accessible points (the paper's conjecture, part i; Figure S6).

A 2-periodic orbit between boundary points ``q0`` and ``q1`` under a
constant force ``a`` is two parabolic flights, ``q0 -> q1`` of duration ``T``
and ``q1 -> q0`` of duration ``T'``.  Both impacts reverse the normal velocity
(``v_n -> -v_n`` whatever the spin, docs/conventions.md), and with
``d = q1 - q0`` and outward normals ``n0``, ``n1`` that gives exactly

.. math::

    (T' - T)\,\Bigl(\frac{d\cdot n_1}{T T'} - \frac{a\cdot n_1}{2}\Bigr) = 0, \qquad
    (T' - T)\,\Bigl(\frac{d\cdot n_0}{T T'} + \frac{a\cdot n_0}{2}\Bigr) = 0 .

``T = T'`` is the path-reversing orbit (the arrival velocity at ``q1`` is
reversed).  A non-path-reversing one (``T != T'``) therefore needs
``T T' = 2 d.n1 / a.n1 = -2 d.n0 / a.n0 > 0``: the pair must be *balanced*,

.. math::

    \beta = \frac{(d\cdot n_1)(a\cdot n_0) + (d\cdot n_0)(a\cdot n_1)}{|d|\,|a|} = 0,

one condition on the pair, which a directly opposite pair with the force
along its tangential wedge's bisector meets by symmetry.  An unbalanced pair
has provably no such orbit.  On a balanced pair, one equation in ``T`` is left
(the tangential velocity at ``q0``; the spin law must close as well, which the
tangential law fixes only up to sign).  On a pair mirror-symmetric about a
line along the force it holds for every ``T``: a one-parameter family of
orbits between the same two points.  Otherwise its roots are the candidates.
The engine then confirms or refutes each candidate:
:func:`noslipsim.analysis.find_periodic_orbit` (period 2) is started on it
and must return a periodic orbit through ``q0`` and ``q1``.

:func:`accessible_pair_census` samples random pairs and balanced pairs on
several tables and records every pair with its outcome.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import xarray as xr
from scipy.optimize import brentq

from .. import tables
from .._metadata import annotate
from .._scheduler import run_tasks
from .._validate import count, finite_float
from ..analysis import find_periodic_orbit
from ..analysis.section import boundary_frames, interior_log
from ..core import layout

__all__ = ["ACCESSIBLE_TABLES", "accessible_pair_census", "accessible_table", "pair_counts", "two_periodic_candidates"]

#: Outcomes of a pair, in the order the figure stacks them.
OUTCOMES = ("found", "not found", "not periodic", "not minimal", "unbalanced", "inaccessible")

#: A candidate orbit must land within this distance (relative to the table's scale) of ``q0`` and ``q1``.
LANDING_TOL = 1e-7

#: Candidates with ``|T - T'| / (T + T')`` below this are the path-reversing orbit, not a new one.
REVERSING_TOL = 1e-6

#: Flight times scanned for roots, as fractions of ``sqrt(T T')``: speeds up to about this inverse.
T_RANGE = (0.02, 1.0)

#: The tangential equation vanishes identically (a family) when below this times ``|d|`` over the whole scan.
FAMILY_TOL = 1e-12

#: Flight times tried on a family (geometric, from ``T_RANGE[0]`` to ``FAMILY_TOP``).
FAMILY_SAMPLES = 8

#: The largest of them, as a fraction of ``sqrt(T T')`` (at 1 the orbit is the path-reversing one).
FAMILY_TOP = 0.98

#: A pair is balanced when ``|beta|`` is below this (a root of ``beta`` lands within rounding of 0).
BALANCE_TOL = 1e-9

#: Tolerance of the mirror-symmetry test (relative; the pair's points come from root finding).
MIRROR_TOL = 1e-7

#: Grid points of the scans (boundary parameter for balanced partners; flight time for roots).
SCAN = 400

#: A point of an element is on the table's boundary when a point this far inside (relative to scale) is inside.
INSIDE_PROBE = 1e-6


def _wedge(gamma, force):
    return tables.wedge(0.6, gamma=gamma, force=force)


def _tilted_wedge(gamma, force):
    return tables.wedge(0.6, gamma=gamma, force=(0.3 * math.hypot(*force), force[1]))


def _pentagon(gamma, force):
    return tables.regular_polygon(5, gamma=gamma, force=force)


def _notched(gamma, force):
    return tables.polygon([(0, 0), (2, 0), (2, 1.5), (1, 0.7), (0, 1.5)], gamma=gamma, force=force)


def _two_disks(gamma, force):
    return tables.two_disks(0.6, gamma=gamma, force=force)


def _disks_in_box(gamma, force):
    return tables.two_disks(0.5, box=(4.0, 3.0), gamma=gamma, force=force)


def _rectangle_disk(gamma, force):
    return tables.rectangle(2.0, 1.5, disks=[(1.0, 0.75, 0.3)], gamma=gamma, force=force)


#: Sampled tables: name -> constructor ``(gamma, force) -> Scene`` (wedges, polygons, disks, mixed).
ACCESSIBLE_TABLES = {
    "wedge": _wedge, "tilted wedge": _tilted_wedge, "pentagon": _pentagon, "notched polygon": _notched,
    "two disks": _two_disks, "disks in a box": _disks_in_box, "rectangle and disk": _rectangle_disk,
}


def accessible_table(name, gamma=1 / math.sqrt(2), gravity=1.0):
    """The sampled table ``name`` of :data:`ACCESSIBLE_TABLES` under the force ``(0, -gravity)``.

    The tilted wedge's force is ``(0.3 g, -g)``: not along its bisector.
    """
    if name not in ACCESSIBLE_TABLES:
        raise ValueError(f"tables: unknown table {name!r}; expected one of {sorted(ACCESSIBLE_TABLES)}")
    return ACCESSIBLE_TABLES[name](gamma, (0.0, -gravity))


# ----------------------------------------------------------------------------- geometry of a pair
def _size(scene):
    """The table's length scale: its finite pieces' size, 1 for a table of infinite lines only (a wedge)."""
    return scene.scale if scene.scale > 0 else 1.0


def _window(scene, element):
    """Arclength range sampled on an element: a finite piece whole, an infinite line within 3 scales."""
    length = scene.elements[element].length()
    return (0.0, length) if math.isfinite(length) else (-3.0 * _size(scene), 3.0 * _size(scene))


def _frame(scene, element, s):
    point, t, n, _, _ = boundary_frames(scene, np.array([element]), np.array([float(s)]))
    return point[0], t[0], n[0]


def _on_boundary(scene, element, s):
    """The point ``s`` of ``element`` bounds the table (an infinite line reaches past the wedge's vertex)."""
    q, _, n = _frame(scene, element, s)
    return bool(scene.contains((q - INSIDE_PROBE * _size(scene) * n)[None])[0])


def _chord_clear(scene, e0, q0, e1, q1):
    """The straight chord ``q0 q1`` runs inside the table and meets the boundary only at its two ends.

    Run by the engine without force from the chord's midpoint both ways: the
    first collision must be ``q1`` on ``e1`` forwards and ``q0`` on ``e0`` backwards.
    """
    free = dataclasses.replace(scene, force=(0.0, 0.0))
    mid, d = 0.5 * (q0 + q1), q1 - q0
    if not free.contains(mid[None])[0]:
        return False
    tol = LANDING_TOL * max(_size(scene), float(np.abs(np.r_[q0, q1]).max()))
    for target, element, v in ((q1, e1, d), (q0, e0, -d)):
        log, _ = interior_log(free, mid, v, 0.0, 1)
        if len(log) == 0 or int(log[0, layout.LOG_ELEMENT]) != element:
            return False
        if math.hypot(*(log[0, [layout.LOG_X, layout.LOG_Y]] - target)) > tol:
            return False
    return True


def _tangent_half_angle(n0, n1):
    """Half-angle ``phi`` of the tangential wedge: half the angle between the two tangent lines, inside."""
    return 0.5 * (math.pi - math.acos(max(-1.0, min(1.0, float(np.dot(n0, n1))))))


def _balance(d, n0, n1, a):
    """``beta`` of the module docstring: zero on a balanced pair."""
    return float((d @ n1) * (a @ n0) + (d @ n0) * (a @ n1)) / (math.hypot(*d) * math.hypot(*a))


def _pair_geometry(scene, e0, s0, e1, s1):
    """Points, frames, tangential half-angle, accessibility (and why not) and balance of one pair."""
    q0, t0, n0 = _frame(scene, e0, s0)
    q1, t1, n1 = _frame(scene, e1, s1)
    phi = _tangent_half_angle(n0, n1)
    reason = ""
    if not 0.0 < phi < math.pi / 2 or np.allclose(q0, q1):
        reason = "tangent lines form no wedge"
    elif not _chord_clear(scene, e0, q0, e1, q1):
        reason = "chord obstructed"
    a = np.asarray(scene.force, dtype=float)
    return dict(q0=q0, t0=t0, n0=n0, q1=q1, t1=t1, n1=n1, phi=phi, reason=reason,
                balance=_balance(q1 - q0, n0, n1, a), mirror=_mirror(q1 - q0, n0, n1, a))


def _mirror(d, n0, n1, a):
    """The pair is mirror-symmetric about a line along the force: chord across it, normals each other's images."""
    u = a / math.hypot(*a)
    image = 2.0 * (n0 @ u) * u - n0
    return bool(abs(d @ u) <= MIRROR_TOL * math.hypot(*d) and np.abs(image - n1).max() <= MIRROR_TOL)


# ----------------------------------------------------------------------------- the two-flight equations
def _flights(g, a, T, T2):
    """Velocities leaving ``q0`` and arriving at ``q1`` (duration ``T``), leaving ``q1`` and arriving at ``q0``."""
    d = g["q1"] - g["q0"]
    return d / T - 0.5 * a * T, d / T + 0.5 * a * T, -d / T2 - 0.5 * a * T2, -d / T2 + 0.5 * a * T2


def _spins(g, a, T, T2, gamma):
    """Spin on the first flight (from the tangential law at ``q1``), on the second, and the velocities."""
    c, s = (1 - gamma * gamma) / (1 + gamma * gamma), 2 * gamma / (1 + gamma * gamma)
    v0, v1, u0, u1 = _flights(g, a, T, T2)
    w = (c * (v1 @ g["t1"]) - u0 @ g["t1"]) / s
    return w, -c * w - s * (v1 @ g["t1"]), (v0, v1, u0, u1)


def _tangential_residual(g, a, C, gamma, T):
    """Tangential law at ``q0`` (times ``T``): zero on a 2-periodic orbit with ``T T' = C``."""
    c, s = (1 - gamma * gamma) / (1 + gamma * gamma), 2 * gamma / (1 + gamma * gamma)
    _, w2, (v0, _, _, u1) = _spins(g, a, T, C / T, gamma)
    return T * float(v0 @ g["t0"] + s * w2 - c * (u1 @ g["t0"]))


def _spin_closes(g, a, T, T2, gamma):
    """The spin law at ``q0`` returns the first flight's spin (the tangential law fixes it only up to sign)."""
    c, s = (1 - gamma * gamma) / (1 + gamma * gamma), 2 * gamma / (1 + gamma * gamma)
    w, w2, (v0, _, _, u1) = _spins(g, a, T, T2, gamma)
    back = -c * w2 - s * (u1 @ g["t0"])
    return abs(back - w) <= 1e-7 * math.sqrt(float(v0 @ v0) + w * w)


def _flight_product(g, a):
    """``T T' = 2 d.n1 / a.n1`` of a non-path-reversing orbit (NaN if the force is tangent at ``q1``)."""
    an1 = float(a @ g["n1"])
    return 2.0 * float((g["q1"] - g["q0"]) @ g["n1"]) / an1 if an1 != 0.0 else math.nan


def two_periodic_candidates(g, force, gamma):
    """Flight-time pairs ``(T, T')``, ``T < T'``, solving the two-flight equations of a balanced pair.

    The tangential equation left on a balanced pair either has isolated
    roots, or vanishes for every ``T`` (a pair mirror-symmetric about a line
    along the force: a one-parameter family of orbits between the same two
    points); then ``FAMILY_SAMPLES`` flight times spread over ``T_RANGE`` stand for it.

    Parameters
    ----------
    g : dict
        Pair geometry (``q0``, ``q1`` and their frames ``t0``, ``n0``, ``t1``, ``n1``, outward normals).
    force : (float, float)
    gamma : float
        ``> 0``.

    Returns
    -------
    candidates : list of (float, float)
        Empty when ``T T' = 2 d.n1 / a.n1`` is not positive or the tangential equation has no
        root in ``T_RANGE`` (time-reversed partners ``(T', T)`` are left out).
    family : bool
        The equation vanishes identically.
    spurious : int
        Roots of the tangential law left out because the spin law at ``q0``
        returns the opposite spin (the tangential law fixes it only up to sign).
    """
    a = np.asarray(force, dtype=float)
    d = g["q1"] - g["q0"]
    C = _flight_product(g, a)
    if not C > 0.0:
        return [], False, 0
    root = math.sqrt(C)
    Ts = root * np.geomspace(*T_RANGE, SCAN)
    f = np.array([_tangential_residual(g, a, C, gamma, T) for T in Ts])
    if np.abs(f).max() <= FAMILY_TOL * math.hypot(*d):
        Ts = root * np.geomspace(T_RANGE[0], FAMILY_TOP, FAMILY_SAMPLES)  # T = T' is path reversing
        return [(T, C / T) for T in Ts if _spin_closes(g, a, T, C / T, gamma)], True, 0
    out, spurious = [], 0
    for k in np.flatnonzero(np.sign(f[:-1]) * np.sign(f[1:]) < 0):
        T = brentq(lambda x: _tangential_residual(g, a, C, gamma, x), Ts[k], Ts[k + 1], xtol=1e-15 * root)
        if abs(C / T - T) <= REVERSING_TOL * (T + C / T):
            continue
        if _spin_closes(g, a, T, C / T, gamma):
            out.append((T, C / T))
        else:
            spurious += 1
    return out, False, spurious


def _betas(scene, q0, n0, e1, s1):
    """``beta`` of ``q0`` against the points ``s1`` (array) of element ``e1``, vectorised (1 where they coincide)."""
    q1, _, n1, _, _ = boundary_frames(scene, np.full(len(s1), e1), np.asarray(s1, dtype=float))
    a = np.asarray(scene.force, dtype=float)
    d = q1 - q0
    norm = np.hypot(d[:, 0], d[:, 1])
    beta = ((d * n1).sum(axis=1) * (a @ n0) + (d @ n0) * (n1 @ a)) / np.where(norm > 0, norm, 1.0) / math.hypot(*a)
    return np.where(norm > 1e-12 * _size(scene), beta, 1.0)


def _balanced_partners(scene, e0, s0, e1):
    """Points ``s1`` of ``e1`` making ``(q0, q1)`` balanced (roots of ``beta`` along the element)."""
    if e1 == e0 and scene.elements[e0].kind in (layout.LINE, layout.SEGMENT):
        return []   # a chord along one straight piece: beta = 0 all along, and no wedge
    q0, _, n0 = _frame(scene, e0, s0)
    grid = np.linspace(*_window(scene, e1), SCAN)
    b = _betas(scene, q0, n0, e1, grid)
    beta = lambda s: float(_betas(scene, q0, n0, e1, [s])[0])  # noqa: E731
    roots = (brentq(beta, grid[k], grid[k + 1], xtol=1e-14 * _size(scene))
             for k in np.flatnonzero(np.sign(b[:-1]) * np.sign(b[1:]) < 0))
    return [r for r in roots if abs(beta(r)) <= BALANCE_TOL]   # not a jump (where q1 meets q0)


# ----------------------------------------------------------------------------- the engine's verdict
def _mid_state(g, a, T, T2, gamma):
    """The state half-way along the first flight (strictly inside the table)."""
    w, _, (v0, _, _, _) = _spins(g, a, T, T2, gamma)
    h = 0.5 * T
    q = g["q0"] + v0 * h + 0.5 * a * h * h
    v = v0 + a * h
    return {"position": (float(q[0]), float(q[1])), "velocity": (float(v[0]), float(v[1])), "spin": float(w)}


def _bounces_between(scene, g, state):
    """The orbit from ``state`` bounces ``q1, q0, q1, q0`` or ``q0, q1, q0, q1`` (within ``LANDING_TOL``)."""
    try:
        log, _ = interior_log(scene, state["position"], state["velocity"], state["spin"], 4)
    except ValueError:   # the flight's midpoint lies outside the table: it leaves the table on its way
        return False
    hits = log[:, [layout.LOG_X, layout.LOG_Y]]
    if len(hits) < 4:
        return False
    tol = LANDING_TOL * max(_size(scene), float(np.abs(hits).max()))
    ends = [g["q1"], g["q0"]] if math.dist(hits[0], g["q1"]) < math.dist(hits[0], g["q0"]) else [g["q0"], g["q1"]]
    return all(math.dist(h, q) <= tol for h, q in zip(hits, ends * 2))


def _verdict(scene, g, state):
    """``'found'`` (with the finder's result), ``'not periodic'`` or ``'not minimal'`` for one candidate.

    The candidate is run by the engine first: if its flights do not bounce
    between ``q0`` and ``q1`` (one meets another piece of the table, or
    leaves it) it is not periodic.  Then the finder (period 2) polishes it:
    if it does not converge the candidate is not periodic either; if it
    converges to an orbit that no longer bounces between ``q0`` and ``q1``
    (another orbit of a family, or a shorter one), it is not minimal.
    """
    if not _bounces_between(scene, g, state):
        return "not periodic", None
    try:
        res = find_periodic_orbit(scene, **state, period=2)
    except ValueError:
        return "not periodic", None
    if not res.converged or res.monodromy is None:
        return "not periodic", None
    return ("found", res) if _bounces_between(scene, g, res.state) else ("not minimal", None)


def _judge_pair(scene, g, gamma):
    """Outcome, orbits found, their classes, and the first one, of one accessible balanced pair."""
    a = np.asarray(scene.force, dtype=float)
    cands, family, spurious = two_periodic_candidates(g, a, gamma)
    row = {**_judge_empty("not found"), "family": int(family), "n_candidates": len(cands)}
    verdicts = []
    for T, T2 in cands:
        verdict, res = _verdict(scene, g, _mid_state(g, a, T, T2, gamma))
        verdicts.append(verdict)
        if verdict != "found":
            continue
        mono = res.monodromy
        row[f"n_{mono.kind}"] += 1
        row["n_found"] += 1
        if row["n_found"] == 1 or T2 / T < row["flight_time_back"] / row["flight_time"]:   # the most even kept
            row.update(flight_time=T, flight_time_back=T2, linear_kind=mono.kind, eigen_sum=float(mono.eigen_sum),
                       residual=float(res.residual), position=res.position, velocity=res.velocity, spin=res.spin)
    if not cands:
        row["reason"] = ("T T' not positive" if not _flight_product(g, a) > 0
                         else "spin reversed" if spurious else "no root")
    if row["n_found"]:
        row["outcome"] = "found"
    elif verdicts:
        row["outcome"] = "not minimal" if "not minimal" in verdicts else "not periodic"
    return row


def _pair_row(scene, name, kind, e0, s0, e1, s1, gamma):
    g = _pair_geometry(scene, e0, s0, e1, s1)
    row = dict(table=name, sample=kind, element0=e0, s0=float(s0), element1=e1, s1=float(s1),
               q0_x=float(g["q0"][0]), q0_y=float(g["q0"][1]), q1_x=float(g["q1"][0]), q1_y=float(g["q1"][1]),
               phi=g["phi"], balance=g["balance"], mirror=int(g["mirror"]), reason=g["reason"])
    if g["reason"]:
        return {**row, **_judge_empty("inaccessible")}
    if abs(g["balance"]) > BALANCE_TOL:
        return {**row, **_judge_empty("unbalanced")}
    return {**row, **_judge_pair(scene, g, gamma)}


def _judge_empty(outcome):
    return dict(outcome=outcome, family=0, n_candidates=0, n_found=0, n_elliptic=0, n_hyperbolic=0, n_parabolic=0,
                flight_time=math.nan, flight_time_back=math.nan, linear_kind="", eigen_sum=math.nan, residual=math.nan,
                position=(math.nan,) * 2, velocity=(math.nan,) * 2, spin=math.nan)


def _random_point(rng, scene):
    """An element and arclength, uniform over the elements and then along the element, on the boundary."""
    for _ in range(1000):
        e = int(rng.integers(len(scene.elements)))
        s = rng.uniform(*_window(scene, e))
        if _on_boundary(scene, e, s):
            return e, s
    raise ValueError("tables: no boundary point found in 1000 draws (an element that bounds nothing?)")


def _table_rows(name, gamma, gravity, pairs, seed):
    """Every sampled pair of one table: ``pairs`` random pairs, then the balanced partners of ``pairs`` points."""
    scene = accessible_table(name, gamma, gravity)
    rng = np.random.default_rng(seed)
    rows = []
    for _ in range(pairs):
        (e0, s0), (e1, s1) = _random_point(rng, scene), _random_point(rng, scene)
        rows.append(_pair_row(scene, name, "random", e0, s0, e1, s1, gamma))
    for _ in range(pairs):
        e0, s0 = _random_point(rng, scene)
        for e1 in range(len(scene.elements)):
            for s1 in _balanced_partners(scene, e0, s0, e1):
                if _on_boundary(scene, e1, s1):
                    rows.append(_pair_row(scene, name, "balanced", e0, s0, e1, s1, gamma))
    return rows


def accessible_pair_census(names=None, gamma=1 / math.sqrt(2), *, gravity=1.0, pairs=20, seed=0, scheduler="sync",
                           num_workers=None, progress=None):
    r"""Non-path-reversing 2-periodic orbits between pairs of boundary points on several tables (Figure S6).

    On every table (:data:`ACCESSIBLE_TABLES`, force ``(0, -gravity)``), two
    samples of pairs ``(q0, q1)``: ``pairs`` *random* pairs (each point uniform
    over the elements, then along the element), and the *balanced* partners
    ``q1`` (roots of ``beta``, module docstring) on every element of
    ``pairs`` random points ``q0``.  Every pair is a row with its outcome:

    * ``'inaccessible'``: the tangent lines at ``q0``, ``q1`` form no wedge
      (parallel, or the same line) or the chord ``q0 q1`` meets the table
      elsewhere (``reason`` says which);
    * ``'unbalanced'``: accessible, but ``beta != 0``, so no non-path-reversing
      2-periodic orbit exists (proven; module docstring);
    * on balanced accessible pairs, the roots of the remaining equation are
      candidates (``n_candidates``), each polished by the finder (period 2):
      ``'found'`` (at least one confirmed: periodic, bouncing between ``q0``
      and ``q1``), ``'not found'`` (no candidate), ``'not periodic'`` (every
      candidate's finder run fails or has no return map), ``'not minimal'``
      (a candidate's finder run converges to another orbit).

    Parameters
    ----------
    names : sequence of str, optional
        Tables (default: all of :data:`ACCESSIBLE_TABLES`).
    gamma : float
        Mass-distribution constant ``> 0``.
    gravity : float
        Force magnitude ``> 0``.
    pairs : int
        Random pairs, and random points ``q0`` for balanced partners, per table.
    seed : int
        Table ``k`` draws from ``numpy.random.default_rng([seed, k])``, whatever the scheduler.
    scheduler, num_workers, progress
        One task per table: ``'sync'``, local threads, or a ``dask.distributed``
        Client or its address (``noslipsim.cluster.ensemble_options``).

    Returns
    -------
    xarray.Dataset
        Along ``pair``: ``table``, ``sample`` (``random``/``balanced``),
        ``element0``, ``s0``, ``element1``, ``s1``, ``q0_x``, ``q0_y``, ``q1_x``, ``q1_y``,
        ``phi`` (tangential half-angle), ``balance`` (``beta``), ``mirror`` (1 if
        the pair is mirror-symmetric about a line along the force), ``reason``,
        ``family`` (1 if its orbits form a one-parameter family),
        ``outcome``, ``n_candidates``, ``n_found`` and ``n_elliptic``,
        ``n_hyperbolic``, ``n_parabolic`` (the confirmed orbits by linear
        class), and of the confirmed orbit with the smallest ``T'/T``:
        ``flight_time``, ``flight_time_back`` (``T``, ``T'``),
        ``linear_kind``, ``eigen_sum``, ``residual``, ``x_start``, ``y_start``,
        ``vx_start``, ``vy_start``, ``spin_start`` (a start for ``noslipsim.simulate``).

    Raises
    ------
    ValueError
        Unknown tables, ``gamma <= 0``, ``gravity <= 0``, bad ``pairs``.
    """
    names = list(ACCESSIBLE_TABLES) if names is None else [str(n) for n in np.atleast_1d(names)]
    for n in names:
        accessible_table(n)
    pairs, seed = count(pairs, "pairs"), int(seed)
    gamma, gravity = finite_float(gamma, "gamma"), finite_float(gravity, "gravity")
    if not gamma > 0 or not gravity > 0:
        raise ValueError(f"gamma, gravity: both must be > 0, got {gamma}, {gravity}")
    jobs = ((k, (name, gamma, gravity, pairs, [seed, k])) for k, name in enumerate(names))
    done = {}
    run_tasks(_table_rows, jobs, done.__setitem__, scheduler=scheduler, num_workers=num_workers, progress=progress,
              total=len(names))
    rows = [r for k in range(len(names)) for r in done[k]]   # the order of the tables, not of completion
    return annotate(_census_dataset(rows, dict(gamma=gamma, gravity=gravity, pairs=pairs, seed=seed, tables=names)))


_TEXT = {"table": "<U20", "sample": "<U8", "reason": "<U28", "outcome": "<U12", "linear_kind": "<U10"}
_INTS = ("element0", "element1", "mirror", "family", "n_candidates", "n_found", "n_elliptic", "n_hyperbolic",
         "n_parabolic")


def _census_dataset(rows, attrs):
    data = {}
    for key in rows[0]:
        if key in ("position", "velocity"):
            continue
        dtype = _TEXT.get(key, np.int64 if key in _INTS else float)
        data[key] = ("pair", np.array([r[key] for r in rows], dtype=dtype))
    data["spin_start"] = data.pop("spin")
    for key, names in (("position", ("x_start", "y_start")), ("velocity", ("vx_start", "vy_start"))):
        arr = np.array([r[key] for r in rows], dtype=float).reshape(-1, 2)
        data.update({names[0]: ("pair", arr[:, 0]), names[1]: ("pair", arr[:, 1])})
    ds = xr.Dataset(data, coords={"pair": np.arange(len(rows))})
    ds.attrs.update(title="non-path-reversing 2-periodic orbits between pairs of boundary points", law="no-slip",
                    landing_tolerance=LANDING_TOL, reversing_tolerance=REVERSING_TOL,
                    flight_time_range=list(T_RANGE), force_description="(0, -gravity); tilted wedge (0.3 g, -g)",
                    **attrs)
    return ds


def pair_counts(ds):
    """Pairs by table, sample and outcome, and confirmed orbits by table and linear class.

    Parameters
    ----------
    ds : xarray.Dataset
        An :func:`accessible_pair_census` dataset.

    Returns
    -------
    xarray.Dataset
        ``pairs`` on ``(table, sample, outcome)``; ``orbits`` on ``(table, linear_kind)``.
    """
    table, sample, outcome = (ds[k].values.astype(str) for k in ("table", "sample", "outcome"))
    names = list(dict.fromkeys(table))   # in the census's order (a list attribute may read back as one string)
    pairs = np.array([[[int(((table == t) & (sample == s) & (outcome == o)).sum()) for o in OUTCOMES]
                       for s in ("random", "balanced")] for t in names])
    kinds = ("elliptic", "hyperbolic", "parabolic")
    orbits = np.array([[int(ds[f"n_{k}"].values[table == t].sum()) for k in kinds] for t in names])
    return xr.Dataset({"pairs": (("table", "sample", "outcome"), pairs), "orbits": (("table", "linear_kind"), orbits)},
                      coords={"table": names, "sample": ["random", "balanced"], "outcome": list(OUTCOMES),
                              "linear_kind": list(kinds)})
