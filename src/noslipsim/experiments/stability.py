"""Wedge and two-disk stability experiments (Figures 7, 9, 14, 15).

Periodic orbits of no-slip wedges under gravity, perturbed copies of them, the linear class
along the launch angle, and the survival pattern of a stability grid (docs/analysis.md).
"""
from __future__ import annotations

import json
import math

import numpy as np
import xarray as xr

from .. import tables
from .._metadata import annotate
from .._validate import count
from ..analysis import find_periodic_orbit, monodromy, wedge_orbit
from ..analysis.section import state_from_reduced
from ..simulate import simulate
from .orbit_sets import orbit_set

#: An impact reverses the path when ``|v_t - gamma w|`` is below this share of the speed there.
REVERSAL_TOL = 1e-9

#: Two states of a run are the same (minimal period) when they differ by less than this,
#: relative to the orbit's scale (positions, velocities, spin).
PERIOD_TOL = 1e-8


def _stab_perturbation(value):
    """``{'angle': a, 'spin': s}`` from a number (the angle, radians) or a mapping."""
    if isinstance(value, dict):
        unknown = set(value) - {"angle", "spin"}
        if unknown:
            raise ValueError(f"perturbation: unknown key(s) {sorted(unknown)}; allowed: ['angle', 'spin']")
        out = {"angle": float(value.get("angle", 0.0)), "spin": float(value.get("spin", 0.0))}
    else:
        try:
            out = {"angle": float(value), "spin": 0.0}
        except (TypeError, ValueError):
            raise ValueError(f"perturbation: expected a number or {{'angle', 'spin'}}, got {value!r}") from None
    if not all(math.isfinite(x) for x in out.values()):
        raise ValueError(f"perturbation: must be finite, got {out}")
    if abs(out["angle"]) >= math.pi / 2:
        raise ValueError(f"perturbation.angle: must be a small angle (|angle| < pi/2), got {out['angle']}")
    if out["spin"] <= -1.0:
        raise ValueError(f"perturbation.spin: the relative spin change must be > -1, got {out['spin']}")
    return out


def _perturbed_start(state, perturbation):
    """``state`` with its velocity turned by ``angle`` (speed kept) and its spin times ``1 + spin``."""
    c, s = math.cos(perturbation["angle"]), math.sin(perturbation["angle"])
    vx, vy = state["velocity"]
    return {"position": state["position"], "velocity": (c * vx - s * vy, s * vx + c * vy),
            "spin": state["spin"] * (1.0 + perturbation["spin"])}


def _case_list(cases, field, required):
    """Validate a sequence of mappings with the ``required`` keys."""
    if isinstance(cases, (str, dict)) or not hasattr(cases, "__iter__"):
        raise ValueError(f"{field}: expected a sequence of mappings, got {cases!r}")
    out = []
    for i, case in enumerate(cases):
        if not isinstance(case, dict):
            raise ValueError(f"{field}[{i}]: expected a mapping, got {case!r}")
        missing = [k for k in required if k not in case]
        if missing:
            raise ValueError(f"{field}[{i}]: missing key(s) {missing}")
        out.append(dict(case))
    return out


def _impact_frames(scene, element):
    """Outward normals and tangents ``t = J n`` of the (line) elements hit, one row per collision."""
    n_in = np.array([scene.elements[int(e)].normal for e in element], dtype=float).reshape(-1, 2)
    n_out = -n_in
    return n_out, np.c_[-n_out[:, 1], n_out[:, 0]]


def _reversal_mismatch(scene, orbit, period):
    r"""``max |v_t - gamma w| / sqrt(|v|^2 + w^2)`` just before each impact of one period (0: path reversing)."""
    e = orbit.element.values[:period]
    _, t = _impact_frames(scene, e)
    vx, vy, w = (orbit[k].values[:period] for k in ("vx_in", "vy_in", "spin_in"))
    vt = vx * t[:, 0] + vy * t[:, 1]
    return float(np.max(np.abs(vt - scene.gamma * w) / np.sqrt(vx ** 2 + vy ** 2 + w ** 2)))


def _minimal_period(orbit, period):
    """Smallest divisor ``d`` of ``period`` after which the post-collision state repeats (``period`` if none)."""
    X = np.c_[orbit.x.values, orbit.y.values, orbit.vx.values, orbit.vy.values, orbit.spin.values]
    scale = 1.0 + np.abs(X[:period + 1]).max()
    for d in range(1, period + 1):
        if period % d == 0 and np.abs(X[d] - X[0]).max() <= PERIOD_TOL * scale:
            return d
    return period


def _scaled_closure(mono, length):
    """``max(|ds|/L, |dw|/V, |dv_t|/V)`` of a monodromy's closure (the finder's residual), ``inf`` if none."""
    if mono.closure is None:
        return math.inf
    b = mono.base
    speed = math.sqrt(b["velocity"][0] ** 2 + b["velocity"][1] ** 2 + b["spin"] ** 2)
    return float(max(abs(mono.closure[0]) / length, abs(mono.closure[1]) / speed, abs(mono.closure[2]) / speed))


def _family_neighbour(scene, result, step, tol, max_iter):
    """Distance and eigen-rotation of the periodic orbit found from ``step`` along the eigenvalue-1 direction.

    A periodic orbit whose monodromy has the eigenvalue 1 (at fixed energy)
    is, generically, a member of a one-parameter family: the finder started
    ``step`` away along that eigenvector converges to another periodic orbit
    about ``step`` away (not back to the first one), with a slightly
    different rotation angle.  Returns ``(nan, nan)`` without an eigenvalue 1.
    """

    mono = result.monodromy
    if mono.unit_count() == 0:
        return math.nan, math.nan
    vals, vecs = np.linalg.eig(mono.matrix)
    e1 = vecs[:, int(np.argmin(np.abs(vals - 1.0)))].real
    b = mono.base
    x0 = np.array([b["s"], b["w"], b["v_t"]])
    speed = math.sqrt(b["velocity"][0] ** 2 + b["velocity"][1] ** 2 + b["spin"] ** 2)
    length = max(scene.scale, float(np.abs(b["position"]).max()))
    scale = np.array([length, speed, speed])
    energy = result.base["energy"]
    e1 = e1 / np.abs(e1 / scale).max() * step  # along e1, `step` long in the finder's scaled max-norm
    q, v, w = state_from_reduced(scene, b["element"], *(x0 + e1), energy)
    a = np.asarray(scene.force)
    tau = 1e-3 * result.monodromy.period_time / result.period
    nb = find_periodic_orbit(scene, q + v * tau + 0.5 * a * tau * tau, v + a * tau, w, period=result.period,
                             tol=tol, max_iter=max_iter)
    if not nb.converged or nb.monodromy is None:
        return math.nan, math.nan
    # how close the neighbour's cycle passes to the first orbit's base point (same element, same scaling)
    run = simulate(scene, **nb.state, max_collisions=result.period)
    _, ts = _impact_frames(scene, run.element.values)
    cyc = np.c_[run.s.values, run.spin.values, run.vx.values * ts[:, 0] + run.vy.values * ts[:, 1]]
    same = run.element.values == b["element"]
    dist = np.abs(cyc[same] - x0) / scale
    return float(dist.max(axis=1).min()), float(np.abs(np.angle(nb.monodromy.eigenvalues)).max())


def wedge_periodic_orbits(phi=0.6, gamma=1 / math.sqrt(2), *, gravity=1.0, reversing=(), searches=(), periods=10,
                          family_step=1e-2, tol=1e-12, max_iter=50):
    r"""Periodic orbits of no-slip wedges under gravity, with the facts that classify them (paper, Figure 7).

    Two kinds of rows.  *Path-reversing* 2-periodic orbits (Theorem 2 and
    its corollary, corrected, docs/errata.md): one per entry of ``reversing``
    (``opening`` ``'up'`` or ``'down'``, launch angle ``theta``, distance
    ``ell`` of ``q0`` from the vertex), launched from the left wall with

    .. math::

        v = \sqrt{\frac{g d}{\sin 2\theta}}, \qquad w_0 = \frac{v \sin(s_y\varphi - \theta)}{\gamma},
        \qquad d = 2\ell\sin\varphi

    (:func:`noslipsim.analysis.wedge_orbit`).  *Searched* orbits: one per entry
    of ``searches`` (``name``, ``opening``, ``position``, ``velocity``,
    ``spin``, ``period``), polished by Newton's method on the return map
    (:func:`noslipsim.analysis.find_periodic_orbit`), for the paper's
    conjecture: an isolated higher-period orbit and a 2-periodic orbit that is
    not path reversing.

    For every row the dataset records the monodromy of one period at fixed
    energy (eigenvalues, class, ``lambda + 1/lambda``, how many eigenvalues
    are 1, ``max |M - I|``), the residual of periodicity, the minimal period
    seen in the run, and ``max |v_t - gamma w| / speed`` just before the
    impacts of one period: 0 iff every impact reverses the path
    (docs/conventions.md).  Where the eigenvalue 1 is present, the finder is
    restarted ``family_step`` away along its eigenvector: converging to
    another periodic orbit about that far away shows a one-parameter family
    at fixed energy (``family_distance``, ``family_rotation``).

    Parameters
    ----------
    phi : float
        Wedge half-angle (wall to bisector; the paper's "wedge angle"), in ``(0, pi/2)``.
    gamma : float
        Mass-distribution constant ``> 0``.
    gravity : float
        ``g > 0``; the force is ``(0, -g)`` for both openings.
    reversing : sequence of dict
        ``{'opening', 'theta', 'ell'}`` per path-reversing orbit.
    searches : sequence of dict
        ``{'name', 'opening', 'position', 'velocity', 'spin', 'period'}``: a start near a periodic orbit.
    periods : int
        Periods run per orbit, each of its own length (the figure draws them;
        the orbit retraces itself, an unstable one until the rounding it
        amplifies by ``|lambda|`` per period shows).
    family_step : float
        Step (scaled like the finder's residual) along the eigenvalue-1 direction.
    tol, max_iter
        Passed to :func:`~noslipsim.analysis.find_periodic_orbit`.

    Returns
    -------
    xarray.Dataset
        An :func:`orbit_set` (dims ``orbit``, ``collision``) with, along
        ``orbit``: ``case``, ``opening``, ``period``, ``minimal_period``,
        ``theta``, ``ell`` (NaN for searched orbits), ``residual``,
        ``linear_kind``, ``eigen_sum``, ``unit_count``, ``identity_distance``,
        ``reversal_mismatch``, ``path_reversing``, ``family_distance``,
        ``family_rotation``; ``eigenvalue_real``, ``eigenvalue_imag`` along
        ``(orbit, eigenvalue)``.  The attribute ``tol`` (the finder's
        tolerance) bounds every searched orbit's ``residual``.

    Raises
    ------
    ValueError
        Bad parameters, or a search that does not converge (the message says
        which and why): a figure must not show a non-periodic orbit as periodic.
    """

    reversing = _case_list(reversing, "reversing", ("opening", "theta", "ell"))
    searches = _case_list(searches, "searches", ("name", "opening", "position", "velocity", "spin", "period"))
    if not reversing and not searches:
        raise ValueError("reversing, searches: expected at least one orbit")
    periods = count(periods, "periods")
    family_step = float(family_step)
    if not (math.isfinite(family_step) and family_step > 0.0):
        raise ValueError(f"family_step: must be finite and > 0, got {family_step}")
    rows = []
    for case in reversing:
        scene, state = wedge_orbit(phi, case["theta"], case["ell"], gamma, gravity=gravity, opening=case["opening"])
        mono = monodromy(scene, **state, period=2)
        name = "path-reversing" + (", wedge opening down" if case["opening"] == "down" else "")
        rows.append(dict(case=name, opening=case["opening"], scene=scene, state=state, period=2, mono=mono,
                         theta=float(case["theta"]), ell=float(case["ell"]),
                         residual=_scaled_closure(mono, max(scene.scale, case["ell"])), family=(math.nan,) * 2))
    for i, case in enumerate(searches):
        scene = tables.wedge(float(phi), opening=case["opening"], gamma=float(gamma), force=(0.0, -float(gravity)))
        res = find_periodic_orbit(scene, case["position"], case["velocity"], case["spin"], period=case["period"],
                                  tol=tol, max_iter=max_iter)
        if not res.converged:
            raise ValueError(f"searches[{i}] ({case['name']}): no periodic orbit of period {case['period']} found "
                             f"near the start ({res.message}; residual {res.residual:.3g})")
        rows.append(dict(case=str(case["name"]), opening=case["opening"], scene=scene, state=res.state,
                         period=res.period, mono=res.monodromy, theta=math.nan, ell=math.nan, residual=res.residual,
                         family=_family_neighbour(scene, res, family_step, tol, max_iter)))
    # each orbit for `periods` of its own periods (a hyperbolic orbit amplifies rounding by |lambda| per period)
    parts = [orbit_set([r["scene"]], [r["state"]["position"]], [r["state"]["velocity"]], [r["state"]["spin"]],
                       max_collisions=periods * r["period"]) for r in rows]
    ds = xr.concat(parts, dim="orbit", join="outer", data_vars="all", coords="minimal", compat="override",
                   combine_attrs="override").assign_coords(orbit=np.arange(len(rows)))
    ds.attrs["max_collisions"] = periods * max(r["period"] for r in rows)
    n = len(rows)
    ev = np.array([r["mono"].eigenvalues for r in rows])
    mismatch = np.array([_reversal_mismatch(r["scene"], ds.isel(orbit=i), r["period"]) for i, r in enumerate(rows)])
    extra = {
        "case": np.array([r["case"] for r in rows], dtype=object),
        "opening": np.array([r["opening"] for r in rows], dtype=object),
        "period": np.array([r["period"] for r in rows]),
        "minimal_period": np.array([_minimal_period(ds.isel(orbit=i), r["period"]) for i, r in enumerate(rows)]),
        "theta": np.array([r["theta"] for r in rows]),
        "ell": np.array([r["ell"] for r in rows]),
        "residual": np.array([r["residual"] for r in rows]),
        "linear_kind": np.array([r["mono"].kind for r in rows], dtype=object),
        "eigen_sum": np.array([r["mono"].eigen_sum for r in rows]),
        "unit_count": np.array([r["mono"].unit_count() for r in rows]),
        "identity_distance": np.array([np.abs(r["mono"].matrix - np.eye(3)).max() for r in rows]),
        "reversal_mismatch": mismatch,
        "path_reversing": (mismatch <= REVERSAL_TOL).astype(np.int8),
        "family_distance": np.array([r["family"][0] for r in rows]),
        "family_rotation": np.array([r["family"][1] for r in rows]),
    }
    for k, values in extra.items():
        ds[k] = ("orbit", values)
    ds["eigenvalue_real"] = (("orbit", "eigenvalue"), ev.real)    # by decreasing modulus (monodromy)
    ds["eigenvalue_imag"] = (("orbit", "eigenvalue"), ev.imag)
    ds.attrs.update(title="periodic orbits of no-slip wedges under gravity", phi=float(phi), gamma=float(gamma),
                    gravity=float(gravity), periods=periods, family_step=family_step, n_orbits=n,
                    reversal_tolerance=REVERSAL_TOL, tol=float(tol))
    return annotate(ds)


def perturbed_wedge_orbits(cases, *, phi, gamma=1 / math.sqrt(2), gravity=1.0, perturbation=1e-3,
                           n_collisions=2000):
    r"""Path-reversing 2-periodic wedge orbits and perturbed copies of them (paper, Figures 9 and 14).

    For each case (``opening``, launch angle ``theta``, distance ``ell`` of
    ``q0`` from the vertex) the periodic orbit of
    :func:`noslipsim.analysis.wedge_orbit` (two collisions) and a perturbed
    copy (``n_collisions``) are run.  The perturbation is the same for every
    case: the start (half-way along the flight ``q0 -> q1``) has its velocity
    turned counter-clockwise by ``angle`` radians, speed kept, and its spin
    multiplied by ``1 + spin``.  Beside them stand the linear class of the
    periodic orbit, ``lambda + 1/lambda`` and the largest ``|lambda|`` of its
    2-bounce monodromy: a perturbation grows like ``|lambda|^(k/2)`` over
    ``k`` collisions while it is small.

    The perturbed orbit's distance from the periodic one is measured at each
    collision in reduced coordinates on the wall hit, against the periodic
    orbit's impact on that wall:

    .. math::

        \delta_k = \max\left(\frac{|s_k - s^*|}{\ell}, \frac{|w_k - w^*|}{V}, \frac{|v_{t,k} - v_t^*|}{V}\right),

    ``V`` the speed ``sqrt(|v|^2 + w^2)`` at that impact.

    Parameters
    ----------
    cases : sequence of dict
        ``{'opening': 'up' | 'down', 'theta': float, 'ell': float}``.
    phi : float
        Wedge half-angle (wall to bisector) in ``(0, pi/2)``.
    gamma : float
        Mass-distribution constant ``> 0``.
    gravity : float
        ``g > 0``; force ``(0, -g)``.
    perturbation : float or dict
        ``{'angle': a, 'spin': s}``, or the angle alone.
    n_collisions : int
        Collisions of each perturbed run.

    Returns
    -------
    xarray.Dataset
        An :func:`orbit_set` of ``2 N`` orbits (orbit ``i`` the periodic orbit
        of case ``i``, over three collisions: one loop; orbit ``N + i`` its
        perturbed copy), with coordinates
        ``case`` and ``role`` (``'periodic'``, ``'perturbed'``) along
        ``orbit``; per orbit ``theta``, ``ell``, ``opening``, ``linear_kind``,
        ``eigen_sum``, ``lambda_max``; ``deviation`` along
        ``(orbit, collision)``.
    """


    cases = _case_list(cases, "cases", ("opening", "theta", "ell"))
    if not cases:
        raise ValueError("cases: expected at least one case")
    perturbation = _stab_perturbation(perturbation)
    n_collisions = count(n_collisions, "n_collisions")
    scenes, periodic, perturbed, monos = [], [], [], []
    for case in cases:
        scene, state = wedge_orbit(phi, case["theta"], case["ell"], gamma, gravity=gravity, opening=case["opening"])
        scenes.append(scene)
        periodic.append(state)
        perturbed.append(_perturbed_start(state, perturbation))
        monos.append(monodromy(scene, **state, period=2))
    # the periodic orbits over three collisions (q1, q0, q1: the whole loop from the start half-way along it)
    parts = [orbit_set(scenes, [s["position"] for s in starts], [s["velocity"] for s in starts],
                       [s["spin"] for s in starts], max_collisions=m)
             for starts, m in ((periodic, 3), (perturbed, n_collisions))]
    ds = xr.concat(parts, dim="orbit", join="outer", data_vars="all", coords="minimal", compat="override",
                   combine_attrs="override").assign_coords(orbit=np.arange(2 * len(cases)))
    n = len(cases)
    deviation = np.full((2 * n, ds.sizes["collision"]), np.nan)
    for i, case in enumerate(cases):
        star = {}
        for j in (i, n + i):
            run = ds.isel(orbit=j)
            k = int(run.n_collisions)
            e = run.element.values[:k].astype(int)
            _, t = _impact_frames(scenes[i], e)
            vx, vy, w, s = (run[v].values[:k] for v in ("vx", "vy", "spin", "s"))
            vt = vx * t[:, 0] + vy * t[:, 1]
            if j == i:  # the periodic orbit's impact on each wall
                star = {int(a): (b, c, d, math.sqrt(x * x + y * y + c * c))
                        for a, b, c, d, x, y in zip(e, s, w, vt, vx, vy)}
            ref_s, ref_w, ref_vt, ref_v = (np.array([star[int(a)][m] for a in e]) for m in range(4))
            deviation[j, :k] = np.max([np.abs(s - ref_s) / float(case["ell"]), np.abs(w - ref_w) / ref_v,
                                       np.abs(vt - ref_vt) / ref_v], axis=0)
    twice = lambda values: np.concatenate([values, values])  # noqa: E731
    ds = ds.assign_coords(case=("orbit", twice(np.arange(n))),
                          role=("orbit", np.array(["periodic"] * n + ["perturbed"] * n, dtype=object)))
    extra = {
        "theta": [float(c["theta"]) for c in cases],
        "ell": [float(c["ell"]) for c in cases],
        "opening": np.array([c["opening"] for c in cases], dtype=object),
        "linear_kind": np.array([m.kind for m in monos], dtype=object),
        "eigen_sum": [m.eigen_sum for m in monos],
        "lambda_max": [float(np.abs(m.eigenvalues).max()) for m in monos],
    }
    for k, values in extra.items():
        ds[k] = ("orbit", twice(np.asarray(values)))
    ds["deviation"] = (("orbit", "collision"), deviation)
    ds.attrs.update(title="perturbed 2-periodic orbits of no-slip wedges under gravity", phi=float(phi),
                    gamma=float(gamma), gravity=float(gravity), n_collisions=n_collisions,
                    perturbation=json.dumps(perturbation, sort_keys=True),
                    perturbation_description=("start (half-way along q0 -> q1) with its velocity turned "
                                              "counter-clockwise by 'angle' rad, speed kept, and its spin "
                                              "multiplied by 1 + 'spin'"))
    return annotate(ds)


def _wedge_monodromy(phi, theta, gamma, gravity, opening, ell):

    scene, state = wedge_orbit(phi, theta, ell, gamma, gravity=gravity, opening=opening)
    return monodromy(scene, **state, period=2)


def _bisect(f, a, b, xtol):
    """A root of ``f`` in ``[a, b]`` with ``f(a) < 0 <= f(b)`` (the midpoint if the signs do not bracket)."""
    fa, fb = f(a), f(b)
    if not (fa < 0.0 <= fb):
        return 0.5 * (a + b)
    while b - a > xtol:
        m = 0.5 * (a + b)
        if f(m) < 0.0:
            a = m
        else:
            b = m
    return 0.5 * (a + b)


def wedge_launch_scan(phis, thetas, gamma=1 / math.sqrt(2), *, gravity=1.0, opening="up", ell=1.0, xtol=1e-13):
    r"""Linear class of the path-reversing 2-periodic wedge orbit along the launch angle (paper, Figure 14).

    For each half-angle ``phi`` and launch angle ``theta`` the 2-bounce
    monodromy of :func:`noslipsim.analysis.wedge_orbit` gives
    ``lambda + 1/lambda`` (elliptic in ``(-2, 2)``, hyperbolic above 2).  The
    wedge is scale invariant under gravity (``q -> c^2 q``, ``v -> c v``,
    ``t -> c t``), so neither ``ell`` nor ``g`` changes the class.  The
    launch angle where the class first changes from elliptic to hyperbolic
    (``lambda + 1/lambda = 2``) is refined by bisection between the grid
    points that bracket it (``theta_transition``); for a wedge opening up it
    is found at the launch parallel to the far wall,

    .. math::

        \theta^* = \frac{\pi}{2} - \varphi

    (``theta_parallel``, a reference; docs/analysis.md).

    Parameters
    ----------
    phis : array_like
        Half-angles in ``(0, pi/2)``.
    thetas : array_like
        Launch angles in ``(0, pi/2)``, strictly increasing.
    gamma, gravity, opening, ell
        As :func:`noslipsim.analysis.wedge_orbit`.
    xtol : float
        Absolute tolerance of the transition angle.

    Returns
    -------
    xarray.Dataset
        Dims ``(phi, theta)``: ``eigen_sum``, ``lambda_max``, ``linear_kind``
        (NaN / ``''`` where the orbit does not exist, e.g. ``theta >= pi/2 - phi``
        opening down); along ``phi``: ``theta_transition`` (NaN if the grid
        shows no elliptic-to-hyperbolic change) and ``theta_parallel``.
    """
    phis = np.atleast_1d(np.asarray(phis, dtype=float))
    thetas = np.atleast_1d(np.asarray(thetas, dtype=float))
    for name, arr in (("phis", phis), ("thetas", thetas)):
        if arr.ndim != 1 or arr.size == 0 or not np.all(np.isfinite(arr)) or ((arr <= 0) | (arr >= math.pi / 2)).any():
            raise ValueError(f"{name}: expected a non-empty 1-D array of angles in (0, pi/2), got {arr!r}")
    if thetas.size > 1 and (np.diff(thetas) <= 0).any():
        raise ValueError("thetas: must be strictly increasing")
    es = np.full((phis.size, thetas.size), np.nan)
    lam = np.full_like(es, np.nan)
    kinds = np.full(es.shape, "", dtype=object)
    transition = np.full(phis.size, np.nan)
    for i, phi in enumerate(phis):
        for j, theta in enumerate(thetas):
            if opening == "down" and not theta + phi < math.pi / 2:
                continue
            m = _wedge_monodromy(phi, theta, gamma, gravity, opening, ell)
            es[i, j], lam[i, j], kinds[i, j] = m.eigen_sum, float(np.abs(m.eigenvalues).max()), m.kind
        turn = np.flatnonzero((kinds[i, :-1] == "elliptic") & (kinds[i, 1:] != "elliptic") & (kinds[i, 1:] != ""))
        if turn.size:
            a, b = thetas[turn[0]], thetas[turn[0] + 1]
            transition[i] = _bisect(
                lambda th, phi=phi: _wedge_monodromy(phi, th, gamma, gravity, opening, ell).eigen_sum - 2.0,
                                    a, b, xtol)
    ds = xr.Dataset(
        {"eigen_sum": (("phi", "theta"), es),
         "lambda_max": (("phi", "theta"), lam),
         "linear_kind": (("phi", "theta"), kinds.astype(str)),
         "theta_transition": ("phi", transition),
         "theta_parallel": ("phi", math.pi / 2 - phis)},
        coords={"phi": phis, "theta": thetas})
    ds.attrs.update(title="linear class of 2-periodic wedge orbits along the launch angle", gamma=float(gamma),
                    gravity=float(gravity), opening=opening, ell=float(ell), xtol=float(xtol))
    return annotate(ds)


def survival_pattern(grid, *, dim="theta", min_run=2):
    """Where along ``dim`` the perturbed orbits of a stability grid survive, row by row.

    Each row of ``grid.survived`` (one disk radius) is cut into runs of
    survived (``'s'``) and escaped (``'u'``) points; runs shorter than
    ``min_run`` points (isolated cells: resonances, a grazing start) are
    merged into their neighbours before the pattern is read.

    Parameters
    ----------
    grid : xarray.Dataset
        A stability grid (:func:`noslipsim.analysis.stability_grid_theta` or
        :func:`~noslipsim.analysis.stability_grid`).
    dim : str
        The dimension along which to read the pattern.
    min_run : int
        Shortest run kept.

    Returns
    -------
    list of dict
        Per row: ``radius``, ``pattern`` (e.g. ``'u-s-u'``), ``intervals``
        (``[(lo, hi), ...]`` of ``dim`` where orbits survive, edges half-way
        between grid points) and ``transitions`` (the ``dim`` values where the
        pattern changes).
    """
    min_run = count(min_run, "min_run")
    if dim not in grid.dims or "radius" not in grid.dims:
        raise ValueError(f"grid: expected dims ('radius', {dim!r}), got {tuple(grid.dims)}")
    x = np.asarray(grid[dim].values, dtype=float)
    edges = np.r_[x[0], 0.5 * (x[1:] + x[:-1]), x[-1]]
    out = []
    for radius, row in zip(grid.radius.values, grid.survived.transpose("radius", dim).values.astype(bool)):
        state = row.copy()
        changed = True
        while changed:  # merge runs shorter than min_run, shortest first
            changed = False
            starts = np.r_[0, np.flatnonzero(state[1:] != state[:-1]) + 1]
            lengths = np.diff(np.r_[starts, state.size])
            if starts.size > 1 and lengths.min() < min_run:
                k = int(np.argmin(lengths))
                state[starts[k]:starts[k] + lengths[k]] = ~state[starts[k]]
                changed = True
        starts = np.r_[0, np.flatnonzero(state[1:] != state[:-1]) + 1]
        ends = np.r_[starts[1:], state.size]
        runs = [(bool(state[a]), float(edges[a]), float(edges[b])) for a, b in zip(starts, ends)]
        out.append({"radius": float(radius), "pattern": "-".join("s" if s else "u" for s, _, _ in runs),
                    "intervals": [(lo, hi) for s, lo, hi in runs if s],
                    "transitions": [float(edges[a]) for a in starts[1:]]})
    return out
