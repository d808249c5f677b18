r"""How much of a phase space is regular: finite-time Lyapunov exponents of uniformly sampled orbits.

The paper judges "invariant regions" by eye in velocity portraits (its
``lorentzgamma`` figure: "no signs of invariant regions until gamma > 0.3").
This module turns the judgement into a measured number.

1. **Starts uniform in the invariant measure** (:func:`uniform_reduced_states`):
   the no-slip billiard map preserves the volume ``ds dv_t dw`` of the reduced
   portrait (boundary arclength ``s``, post-collision unit vector
   ``(w, v_t, v_n)`` projected on the disk ``(v_t, w)``), the specular map the
   area ``ds dp`` (docs/analysis.md, "Boundary portraits").  So ``s`` is drawn
   uniform along the chosen elements and ``(v_t, w)`` uniform on the unit disk
   (specular: ``p`` uniform in ``(-1, 1)``, ``w = 0``).  The share of starts in
   a region is then its share of the invariant measure.
2. **Finite-time exponent per collision** (:func:`finite_time_lyapunov`):
   Benettin's method on the exact tangent dynamics
   (:func:`noslipsim.analysis.lyapunov.lyapunov_run`) over ``N`` collisions.
   A chaotic orbit gives a value of order one; an orbit on an invariant torus
   (an elliptic island) one that decays like ``log N / N``.  For flights
   without a tangent map (the isokinetic thermostat) :func:`twin_lyapunov`
   measures the same exponent from a renormalised twin orbit.
3. **Regular share** (:func:`regular_share`): the share of starts whose
   exponent lies below :data:`REGULAR_THRESHOLD`, with its binomial standard
   error ``sqrt(p (1 - p) / n)``,

   .. math::

       p = \frac{\#\{i : \lambda_i^{(N)} < \lambda_\mathrm{thr}\}}{n} .

4. **Onset** (:func:`onset_gamma`): the smallest ``gamma`` at which the
   regular share reaches a visibility level :data:`VISIBLE_SHARE` (an island
   holding 1 % of the phase space catches one orbit in a hundred-orbit
   portrait), by linear interpolation between the sweep's points, with a
   parametric bootstrap of the binomial counts for its uncertainty.

:func:`head_on_onset_gamma` is the linear theory beside it: on a lattice of
disks of radius ``R`` with nearest centres ``D`` apart, the head-on
2-periodic orbit between neighbours (``phi = 0``) is elliptic iff
``kappa d < ellipticity_threshold(0, gamma) = 2 gamma^2``, i.e.

.. math::

    \gamma > \gamma_0(R) = \sqrt{\frac{D}{2R} - 1} .

Method, thresholds and measured numbers: docs/analysis.md, "Regular share and
the onset of islands".

References
----------
G. Benettin, L. Galgani, A. Giorgilli, J.-M. Strelcyn, Meccanica 15 (1980) 9;
C. Cox, R. Feres, H.-K. Zhang, *Stability of periodic orbits in no-slip
billiards*, Nonlinearity 31 (2018); the paper, section "Stability of periodic
points and existence of invariant regions".
"""
from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from .._engine.lattice import cell_of, cell_origin, element_cells
from .._metadata import annotate
from .._validate import count, positive
from ..ensemble import simulate_many
from ..initial import rng_from
from ..scenes import Scene
from .lyapunov import lyapunov_run
from .portraits import birkhoff_states, reduced_states
from .section import TWIN_LYAPUNOV, require_free_fall

__all__ = [
    "REGULAR_THRESHOLD",
    "VISIBLE_SHARE",
    "finite_time_lyapunov",
    "head_on_onset_gamma",
    "interior_starts",
    "onset_gamma",
    "regular_share",
    "threshold_sensitivity",
    "twin_lyapunov",
    "uniform_reduced_states",
]

#: Finite-time exponent per collision below which an orbit counts as regular.  Measured on
#: the no-slip Sinai torus (R = 0.4 and 0.45, gamma in [0, 1], 1000 collisions, 23,200 orbits):
#: regular orbits give a median 0.004 (99 % below 0.016), chaotic ones 0.31 and more (99.5 %),
#: 0.26 % of orbits fall between 0.01 and 0.1 (docs/analysis.md).
REGULAR_THRESHOLD = 0.03

#: Regular share at which islands count as visible: one orbit in a hundred-orbit portrait.
VISIBLE_SHARE = 0.01

#: Starts whose first flight is shorter than this (in time) are grazing; they are redrawn.
MIN_FLIGHT = 1e-9

#: Twin orbits (:func:`twin_lyapunov`): the separation a twin starts at and is renormalised to
#: (state ``(x, y, v_x, v_y, w)``, lengths and speeds of order one; far above rounding, 1e-16,
#: and with room for the growth of a block), the collisions between two renormalisations, and
#: the separation past which a twin no longer follows the linearised map (it is then replaced).
TWIN_SEPARATION = 1e-10
TWIN_BLOCK = 4
TWIN_NONLINEAR = 1e-4


def _scene(scene):
    if not isinstance(scene, Scene):
        raise TypeError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
    return scene


def _finite_elements(scene, elements):
    idx = list(range(len(scene.elements))) if elements is None else sorted({int(i) for i in elements})
    if not idx:
        raise ValueError("elements: choose at least one element")
    for i in idx:
        if not 0 <= i < len(scene.elements):
            raise ValueError(f"elements: no element {i} in a scene of {len(scene.elements)}")
        if not scene.elements[i].bounded:
            raise ValueError(f"elements: element {i} is an infinite line, which has no arclength to sample; "
                             "choose the finite elements (segments, circles, arcs)")
    return idx


# ----------------------------------------------------------------------------- starts
def uniform_reduced_states(scene: Scene, n, seed=0, *, elements=None, speed=1.0):
    """Boundary starts uniform in the invariant measure of the billiard map.

    No-slip (some element collides by the no-slip law, so the spin is a phase
    variable: a table of mixed laws counts, whatever its default law): ``s``
    uniform along the chosen elements laid end to end and ``(v_t, w)`` uniform
    on the unit disk (the measure ``ds dv_t dw``, kept by both laws); specular
    (every element): ``s`` uniform and ``p = sin(exit angle)`` uniform in ``(-1, 1)``
    with ``w = 0`` (the measure ``ds dp``).  The draws depend only on ``n`` and
    ``seed``, not on the table, so two tables (or two gammas) get the same
    starts in scaled coordinates (common random numbers).

    Parameters
    ----------
    scene : Scene
        The table (plain or periodic; in a periodic scene, one cell's elements).
    n : int
        Number of starts.
    seed : int, SeedSequence or Generator
        Seed (:func:`noslipsim.initial.rng_from`).
    elements : sequence of int, optional
        The finite elements to start on (default: all).
    speed : float
        ``sqrt(|v|^2 + w^2)`` of every start (nondimensional).

    Returns
    -------
    dict
        ``positions`` (n, 2), ``velocities`` (n, 2), ``spins`` (n,),
        ``start_elements`` (n,) for :func:`noslipsim.simulate_many`, and the
        drawn coordinates ``s_boundary``, ``vt_unit``, ``w_unit`` (no-slip) or
        ``sin_angle`` (specular).
    """
    scene = _scene(scene)
    n = count(n, "n", minimum=0)
    idx = _finite_elements(scene, elements)
    total = float(sum(scene.elements[i].length() for i in idx))
    rng = rng_from(seed)
    u = rng.uniform(0.0, 1.0, n)
    radius = np.sqrt(rng.uniform(0.0, 1.0, n))
    angle = rng.uniform(0.0, 2.0 * math.pi, n)
    # keep s off the very ends so a start never sits on a corner of two elements
    s = total * np.clip(u, 1e-12, 1.0 - 1e-12)
    if not scene.any_noslip:  # every element specular: no spin in the phase space
        p = np.clip(2.0 * radius**2 - 1.0, -1.0 + 1e-12, 1.0 - 1e-12)  # radius^2 is uniform in (0, 1)
        st = birkhoff_states(scene, s, p, elements=idx, speed=speed)
        st.update(s_boundary=s, sin_angle=p)
        return st
    r = np.minimum(radius, 1.0 - 1e-12)
    vt, w = r * np.cos(angle), r * np.sin(angle)
    st = reduced_states(scene, s, vt, w, elements=idx, speed=speed)
    st.update(s_boundary=s, vt_unit=vt, w_unit=w)
    return st


def interior_starts(scene: Scene, states):
    r"""Move boundary starts half-way along their first flight, strictly inside the table.

    :func:`noslipsim.analysis.lyapunov` (and :func:`noslipsim.simulate`) need
    interior starts; the state at half the first flight time ``tau`` lies on
    the same orbit:

    .. math::

        q = q_0 + v_0 \tau/2 + a \tau^2/8, \qquad v = v_0 + a \tau/2, \qquad w = w_0

    (free fall; :meth:`Scene.flight_states`, the closed-form path under the
    isokinetic thermostat).

    Parameters
    ----------
    scene : Scene
    states : dict
        ``positions``, ``velocities``, ``spins``, ``start_elements`` (as from
        :func:`uniform_reduced_states` or :func:`noslipsim.initial.boundary_states`).

    Returns
    -------
    dict
        ``positions``, ``velocities``, ``spins`` (interior starts; unfolded
        positions in a periodic scene) and ``first_flight`` (``tau``).

    Raises
    ------
    ValueError
        When a start has no first collision (it escapes) or grazes the boundary
        (``tau`` < :data:`MIN_FLIGHT`).
    """
    scene = _scene(scene)
    q0 = np.asarray(states["positions"], dtype=float)
    v0 = np.asarray(states["velocities"], dtype=float)
    w0 = np.asarray(states["spins"], dtype=float)
    ds = simulate_many(scene, q0, v0, w0, start_elements=states.get("start_elements"), max_collisions=1,
                       record="final", scheduler="sync", progress=False)
    tau = ds.t_final.values
    bad = ~(np.isfinite(tau) & (ds.n_collisions.values == 1) & (tau > MIN_FLIGHT))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"states: start {i} has no usable first flight (time {tau[i]:.3g}, "
                         f"{int(ds.n_collisions.values[i])} collisions): it escapes or grazes the boundary")
    x, y, vx, vy = scene.flight_states(q0[:, 0], q0[:, 1], v0[:, 0], v0[:, 1], 0.5 * tau)  # any flight type
    return {"positions": np.stack([x, y], axis=-1), "velocities": np.stack([vx, vy], axis=-1),
            "spins": w0.copy(), "first_flight": tau}


# ----------------------------------------------------------------------------- exponents
def _one_ftle(scene, q, v, w, n_collisions):
    try:
        return lyapunov_run(scene, q, v, w, n_collisions=n_collisions)["per_collision"]
    except ValueError:  # a corner collision (CornerError) or an escape: no exponent
        return math.nan


def _orbit_starts(positions, velocities, spins):
    """``(q, v, w)`` as float arrays of shapes (n, 2), (n, 2), (n,) (no spins: zeros); a clear error otherwise."""
    q = np.asarray(positions, dtype=float)
    v = np.asarray(velocities, dtype=float)
    w = np.zeros(len(q)) if spins is None else np.asarray(spins, dtype=float)
    if q.ndim != 2 or q.shape[1] != 2 or v.shape != q.shape or w.shape != (len(q),):
        raise ValueError(f"positions, velocities, spins: expected shapes (n, 2), (n, 2), (n,), got "
                         f"{q.shape}, {v.shape}, {w.shape}")
    return q, v, w


def finite_time_lyapunov(scene: Scene, positions, velocities, spins=None, *, n_collisions=2000, num_workers=1):
    r"""Finite-time largest Lyapunov exponent per collision of each orbit.

    .. math::

        \lambda^{(N)} = \frac{1}{N} \sum_j \log \frac{\lVert B_j u_j \rVert}{\lVert u_j \rVert}

    (Benettin on the exact tangent dynamics of the collision map,
    :func:`noslipsim.analysis.lyapunov.lyapunov_run`; ``B_j`` products of 8
    step Jacobians).  Nondimensional (per collision).

    Parameters
    ----------
    scene : Scene
    positions, velocities : array_like (n, 2)
        Interior starts (see :func:`interior_starts`).
    spins : array_like (n,), optional
        Scaled spins (zeros by default).
    n_collisions : int
        Collisions per orbit (``N``; at least 9).
    num_workers : int
        Threads (the compiled orbit runs without the GIL).  The result does
        not depend on it.

    Returns
    -------
    numpy.ndarray (n,)
        ``lambda^(N)``; NaN for an orbit that meets a corner (no derivative)
        or escapes before ``N`` collisions.
    """
    scene = _scene(scene)
    require_free_fall(scene, "finite_time_lyapunov", TWIN_LYAPUNOV)  # before the per-orbit NaN for corners
    q, v, w = _orbit_starts(positions, velocities, spins)
    n_collisions = count(n_collisions, "n_collisions", minimum=9)
    num_workers = count(num_workers, "num_workers")
    if num_workers == 1 or len(q) < 2:
        return np.array([_one_ftle(scene, q[i], v[i], w[i], n_collisions) for i in range(len(q))])
    with ThreadPoolExecutor(num_workers) as pool:
        return np.array(list(pool.map(lambda i: _one_ftle(scene, q[i], v[i], w[i], n_collisions), range(len(q)))))


def _last_states(ds, rows):
    """``(state (n, 5), element (n,), collisions (n,))`` after the last collision of each orbit of a log."""
    n = ds.n_collisions.values[rows]
    last = np.maximum(n - 1, 0)
    take = lambda name: ds[name].values[rows, last]   # noqa: E731
    state = np.column_stack([take("x"), take("y"), take("vx"), take("vy"), take("spin")])
    return state, take("element"), n


def _cells_on(scene, points, elements):
    """The lattice cell of the copy of ``elements[i]`` that ``points[i]`` lies on (a point of no element: its own cell).

    Not the parallelogram cell that holds the point: a disk reaching out of its
    cell (the triangular gas of finite horizon, ``R > sqrt(3)/4``) has points in
    the neighbouring parallelograms, and a boundary start must lie on the base copy.
    """
    cells = np.zeros((len(points), 2), dtype=np.int64)
    known = np.isfinite(points).all(axis=1)
    on = known & np.isfinite(elements) & (elements >= 0)
    cells[known & ~on] = cell_of(points[known & ~on], scene.lattice)
    for e in np.unique(elements[on]).astype(np.int64):
        sel = on & (elements == e)
        cells[sel] = element_cells(scene.elements[e], points[sel], scene.lattice)
    return cells


def twin_collisions(n_collisions, block=TWIN_BLOCK):
    """The collisions :func:`twin_lyapunov` runs for ``n_collisions``: rounded up to whole blocks."""
    return -(-n_collisions // block) * block


def twin_lyapunov(scene: Scene, positions, velocities, spins=None, *, n_collisions=2000, block=TWIN_BLOCK,
                  separation=TWIN_SEPARATION, seed=0, num_workers=None):
    r"""Finite-time largest Lyapunov exponent per collision from a twin orbit, for any flight type.

    Benettin's method without a tangent map: beside each orbit runs a twin
    started ``delta_0 =`` ``separation`` away in the state ``u = (x, y, v_x,
    v_y, w)`` (random direction).  Every ``block`` collisions both are compared
    just after their collision of the same number (a point of the billiard
    map), the separation ``delta_k = |u_twin - u|`` is recorded and the twin is
    put back at ``u + delta_0 (u_twin - u) / delta_k`` on the same element,
    the step that keeps it in the linear regime and turns its offset towards
    the most expanding direction:

    .. math::

        \lambda^{(N)} = \frac{1}{N} \sum_k \log \frac{\delta_k}{\delta_0} .

    Where both apply it classifies orbits as :func:`finite_time_lyapunov` (the
    exact tangent dynamics) does, with regular exponents within 0.01 and the
    head-on orbit's closed form within 0.15 % (tests/test_analysis_islands.py);
    it needs nothing but the orbits, so it serves the isokinetic thermostat too
    (:class:`noslipsim.Scene` ``thermostat``), whose tangent map the package
    does not have.  A twin that parts from the
    orbit by more than :data:`TWIN_NONLINEAR` (a corner or a grazing hit that
    splits the two, or a block with a growth beyond the linear regime) counts
    that block as ``log(TWIN_NONLINEAR / delta_0)``, a lower bound of the
    growth, and a fresh twin starts from the orbit.

    Parameters
    ----------
    scene : Scene
        Any table, law, force and flight type.
    positions, velocities : array_like (n, 2)
        Interior starts (see :func:`interior_starts`).
    spins : array_like (n,), optional
        Scaled spins (zeros by default).
    n_collisions : int
        Collisions per orbit (``N``; at least ``block``), rounded up to whole blocks.
    block : int
        Collisions between two renormalisations (``>= 1``).
    separation : float
        ``delta_0`` (> 0, at most ``TWIN_NONLINEAR / 100``).
    seed : int
        Seed of the twins' directions.
    num_workers : int, optional
        Threads of :func:`noslipsim.simulate_many` (default: one per core).  The
        result does not depend on it.

    Returns
    -------
    numpy.ndarray (n,)
        ``lambda^(N)``; NaN for an orbit (or its twin) that stops before ``N``
        collisions (escape, corner, grazing, search limit).
    """
    scene = _scene(scene)
    q, v, w = _orbit_starts(positions, velocities, spins)
    block = count(block, "block")
    n_collisions = count(n_collisions, "n_collisions", minimum=block)
    separation = positive(separation, "separation")
    if separation > TWIN_NONLINEAR / 100:
        raise ValueError(f"separation: must be at most {TWIN_NONLINEAR / 100:g} (TWIN_NONLINEAR / 100), "
                         f"got {separation}")
    n = len(q)
    rng = rng_from(seed)

    def fresh(ref):
        u = rng.normal(size=ref.shape)
        return ref + separation * u / np.linalg.norm(u, axis=1, keepdims=True)

    ref = np.column_stack([q, v, w])
    twin = fresh(ref)
    el_ref = np.full(n, -1, dtype=np.int64)
    el_twin = np.full(n, -1, dtype=np.int64)
    growth = np.zeros(n)
    alive = np.ones(n, dtype=bool)
    done = 0
    cap = math.log(TWIN_NONLINEAR / separation)
    n_collisions = twin_collisions(n_collisions, block)
    while done < n_collisions and alive.any():
        idx = np.flatnonzero(alive)
        m = len(idx)
        both = np.concatenate([ref[idx], twin[idx]])
        ds = simulate_many(scene, both[:, :2], both[:, 2:4], both[:, 4],
                           start_elements=np.concatenate([el_ref[idx], el_twin[idx]]), max_collisions=block,
                           record="log", scheduler="numba" if m > 1 else "sync", progress=False,
                           num_workers=num_workers)
        a, ea, na = _last_states(ds, np.arange(m))
        b, eb, nb = _last_states(ds, np.arange(m, 2 * m))
        if scene.lattice is not None:  # back to the base cell (boundary starts lie there), the same shift for both
            origin = cell_origin(_cells_on(scene, a[:, :2], ea), scene.lattice)
            a[:, :2] -= origin
            b[:, :2] -= origin
        full = (na == block) & (nb == block)
        alive[idx[~full]] = False
        d = np.linalg.norm(b - a, axis=1)
        linear = full & (ea == eb) & np.isfinite(d) & (d < TWIN_NONLINEAR) & (d > 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            growth[idx] += np.where(linear, np.log(d / separation), cap)
        ref[idx] = a
        el_ref[idx] = np.where(full, ea, -1).astype(np.int64)
        renorm = a + (b - a) * (separation / np.where(linear, d, 1.0))[:, None]
        twin[idx] = np.where(linear[:, None], renorm, fresh(a))
        el_twin[idx] = el_ref[idx]
        done += block
    out = growth / done
    out[~alive] = np.nan
    return out


def regular_share(ftle, threshold=REGULAR_THRESHOLD, axis=-1):
    """Share of orbits whose exponent lies below ``threshold``, and its binomial standard error.

    Parameters
    ----------
    ftle : array_like
        Finite-time exponents (NaN entries are left out of both counts).
    threshold : float
        Exponent per collision below which an orbit is regular (> 0).
    axis : int
        The axis along the orbits.

    Returns
    -------
    (share, stderr, n) : numpy arrays (or floats for 1-D input)
        ``p = k/n`` and ``sqrt(p (1 - p)/n)``, ``n`` the orbits with an exponent.
    """
    threshold = positive(threshold, "threshold")
    lam = np.asarray(ftle, dtype=float)
    known = np.isfinite(lam)
    n = known.sum(axis=axis)
    k = (known & (lam < threshold)).sum(axis=axis)
    with np.errstate(invalid="ignore", divide="ignore"):
        p = np.where(n > 0, k / np.maximum(n, 1), np.nan)
        err = np.sqrt(p * (1.0 - p) / np.maximum(n, 1))
    if np.ndim(p) == 0:
        return float(p), float(err), int(n)
    return p, err, n


#: Fractions of the threshold at which the regular share is also reported (0.01, 0.02, 0.03 of the default):
#: an orbit near the line moves with it, a clear split does not (docs/analysis.md).
SENSITIVITY_FRACTIONS = (1 / 3, 2 / 3, 1.0)


def threshold_sensitivity(ftle, threshold=REGULAR_THRESHOLD, fractions=SENSITIVITY_FRACTIONS, axis=-1):
    """The regular share at several thresholds below ``threshold``: how much it depends on the line drawn.

    Parameters
    ----------
    ftle : array_like
        Finite-time exponents (NaN entries are left out).
    threshold : float
        The reference threshold (> 0).
    fractions : sequence of float
        Fractions of ``threshold`` (each > 0).
    axis : int
        The axis along the orbits.

    Returns
    -------
    dict
        ``{threshold * fraction: share}`` in the order of ``fractions``, each
        share as :func:`regular_share` gives it (a float for 1-D input).
    """
    threshold = positive(threshold, "threshold")
    out = {}
    for f in fractions:
        t = positive(f, "fractions") * threshold
        out[float(np.round(t, 12))] = regular_share(ftle, t, axis=axis)[0]   # rounded: 0.01, not 0.009999...
    return out


def _crossing(gammas, shares, level):
    above = np.flatnonzero(shares >= level)
    if above.size == 0:
        return math.nan
    i = int(above[0])
    if i == 0:
        return float(gammas[0])
    g0, g1, p0, p1 = gammas[i - 1], gammas[i], shares[i - 1], shares[i]
    return float(g0 + (level - p0) * (g1 - g0) / (p1 - p0))


def onset_gamma(gammas, counts, n, *, level=VISIBLE_SHARE, n_boot=2000, seed=0):
    """The smallest gamma at which the regular share reaches ``level``, with a bootstrap interval.

    The share ``counts / n`` is interpolated linearly between consecutive
    gammas; the onset is the first crossing of ``level``.  Its uncertainty is
    a parametric bootstrap: every count is redrawn from ``Binomial(n, counts/n)``
    and the crossing recomputed.

    Parameters
    ----------
    gammas : array_like
        Strictly increasing gammas of the sweep.
    counts : array_like of int
        Regular orbits at each gamma.
    n : int or array_like of int
        Orbits at each gamma (with an exponent).
    level : float
        Visibility level in ``(0, 1)``.
    n_boot : int
        Bootstrap resamples.
    seed : int
        Seed of the bootstrap.

    Returns
    -------
    dict
        ``value`` (NaN when the share never reaches ``level``; the first gamma
        when it starts above), ``stderr`` (standard deviation of the bootstrap
        crossings), ``low``, ``high`` (their 16th and 84th percentiles),
        ``never_reached`` (share of resamples without a crossing), ``level``.
    """
    g = np.asarray(gammas, dtype=float)
    k = np.asarray(counts)
    nn = np.broadcast_to(np.asarray(n), g.shape)
    if g.ndim != 1 or len(g) < 2 or k.shape != g.shape:
        raise ValueError(f"gammas, counts: expected two 1-D arrays of the same length >= 2, got {g.shape}, {k.shape}")
    if not np.all(np.isfinite(g)) or np.any(np.diff(g) <= 0):
        raise ValueError("gammas: must be finite and strictly increasing")
    if np.any(nn < 1) or np.any(k < 0) or np.any(k > nn):
        raise ValueError("counts, n: expected 0 <= counts <= n and n >= 1")
    level = float(level)
    if not 0.0 < level < 1.0:
        raise ValueError(f"level: must lie in (0, 1), got {level}")
    n_boot = count(n_boot, "n_boot")
    p = k / nn
    value = _crossing(g, p, level)
    rng = np.random.default_rng(seed)
    boot = rng.binomial(nn[None, :].astype(np.int64), p[None, :], size=(n_boot, len(g))) / nn[None, :]
    cross = np.array([_crossing(g, b, level) for b in boot])
    ok = np.isfinite(cross)
    if ok.any():
        low, high = np.percentile(cross[ok], [16, 84])
        stderr = float(np.std(cross[ok], ddof=1)) if ok.sum() > 1 else 0.0
    else:
        low = high = stderr = math.nan
    return {"value": value, "stderr": stderr, "low": float(low), "high": float(high),
            "never_reached": float(1.0 - ok.mean()), "level": level}


def classify_regular(ds, threshold=REGULAR_THRESHOLD):
    """A portrait dataset with its orbits classified: ``regular = 1`` where ``ftle < threshold``.

    The classification is cheap and its threshold a reading, not part of the
    simulation: datasets store the exponents ``ftle``, and the figure and the
    numbers that need the flag make it here with their own threshold (so a
    changed threshold reruns no simulation).

    Parameters
    ----------
    ds : xarray.Dataset
        With a variable ``ftle`` (finite-time exponent per collision; NaN: none).
    threshold : float
        Exponent per collision below which an orbit is regular (> 0).

    Returns
    -------
    xarray.Dataset
        A copy with ``regular`` (int8, 0 where ``ftle`` is NaN) and the attribute
        ``regular_threshold``.
    """
    threshold = positive(threshold, "threshold")
    if "ftle" not in ds:
        raise ValueError("ds: no variable 'ftle' (a portrait dataset made with lyapunov_collisions)")
    out = ds.copy()
    out["regular"] = (ds.ftle < threshold).astype(np.int8)
    out.attrs["regular_threshold"] = threshold
    return annotate(out)


def islands_onsets(ds, threshold=REGULAR_THRESHOLD, level=VISIBLE_SHARE):
    """The regular share against gamma and its onset, per radius, from a sweep of exponents.

    Parameters
    ----------
    ds : xarray.Dataset
        :func:`noslipsim.experiments.sinai_islands_sweep`: ``ftle`` along
        ``(radius, gamma, orbit)`` and the attribute ``seed``.
    threshold : float
        Regular threshold (:func:`regular_share`).
    level : float
        Visibility level of the onset (:func:`onset_gamma`).

    Returns
    -------
    xarray.Dataset
        A copy with ``share_regular``, ``share_regular_stderr``, ``n_regular``,
        ``n_valid`` per ``(radius, gamma)`` and ``onset_gamma``,
        ``onset_gamma_stderr``, ``onset_gamma_low``, ``onset_gamma_high`` per
        radius; attributes ``regular_threshold`` and ``visible_share``.
    """
    gammas = ds.gamma.values
    share, err, n_valid = regular_share(ds.ftle.values, threshold)
    k = np.rint(share * n_valid).astype(np.int64)
    onsets = [onset_gamma(gammas, k[i], n_valid[i], level=level, seed=int(ds.attrs.get("seed", 0)))
              for i in range(ds.sizes["radius"])]
    rg = ("radius", "gamma")
    out = ds.copy()
    out["share_regular"] = (rg, share)
    out["share_regular_stderr"] = (rg, err)
    out["n_regular"] = (rg, k)
    out["n_valid"] = (rg, n_valid)
    for key, name in (("value", "onset_gamma"), ("stderr", "onset_gamma_stderr"), ("low", "onset_gamma_low"),
                      ("high", "onset_gamma_high")):
        out[name] = ("radius", [o[key] for o in onsets])
    out.attrs.update(regular_threshold=float(threshold), visible_share=float(level))
    return annotate(out)


def head_on_onset_gamma(radius, distance=1.0):
    r"""Gamma above which the head-on 2-periodic orbit between neighbouring disks is elliptic.

    Disks of radius ``R`` with centres ``D`` apart; the orbit along the line of
    centres (``phi = 0``, no force) has ``kappa d = (D - 2R)/R`` and is
    elliptic iff ``kappa d <`` :func:`noslipsim.theory.ellipticity_threshold`
    ``(0, gamma) = 2 gamma^2``:

    .. math::

        \gamma_0 = \sqrt{\frac{D}{2R} - 1} .

    Parameters
    ----------
    radius : float
        Disk radius ``R`` with ``0 < 2R < D``.
    distance : float
        Distance ``D`` between neighbouring centres (1 on the unit torus and
        the unit triangular lattice).

    Returns
    -------
    float
    """
    R, D = float(radius), float(distance)
    if not (math.isfinite(R) and math.isfinite(D) and 0.0 < 2.0 * R < D):
        raise ValueError(f"radius, distance: expected 0 < 2 radius < distance, got {R}, {D}")
    # ellipticity_threshold(0, gamma) = 2 gamma^2, increasing in gamma: solve it equal to kappa d
    return math.sqrt((D - 2.0 * R) / R / 2.0)
