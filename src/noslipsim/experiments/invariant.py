r"""Invariant regions around elliptic periodic orbits between two disks under a force (Figure S7).

The paper's conjecture: stable periodic orbits between circular scatterers
under a force create invariant regions.  The table is
:func:`noslipsim.tables.two_disks` (radius ``R``, centres ``(-1, 0)`` and
``(1, 0)``, open: an orbit that misses both disks escapes), the force
``(0, -g)``, and the orbit the path-reversing 2-periodic one between
``q0 = (-1 + R cos phi, R sin phi)`` and its mirror image ``q1``.  Two flights:

* *free fall* (energy conserved): the orbit leaves ``q0`` at unit speed, so
  ``sin 2 theta = g d`` (Theorem 2, corrected, docs/errata.md; ``d = |q0 q1|``)
  has two launch angles, the ``low`` and the ``high`` branch, while
  ``g d <= 1`` (:func:`noslipsim.analysis.two_disk_orbit`).  Free fall is scale
  invariant (``v -> c v``, ``g -> c^2 g``), so ``g`` at unit launch speed is
  the one dimensionless force ``g d / v^2``.
* *isokinetic* (``Scene.thermostat = 'isokinetic'``, unit speed): the flight
  from the apex ``(0, y0)``, heading along ``+x``, that meets the right disk at
  ``q1`` (one root ``y0``, found by bisection); its spin is ``v_t / gamma`` at
  ``q1``, the path-reversal condition.  The thermostat is time-reversible, so
  the mirror image closes the orbit.

Around each orbit, starts on rings in the plane (velocity turned by ``a``
radians, spin raised by ``b`` times the speed) of the orbit's apex state, ring
``k`` of radius ``k * ring_step``, each run ``max_collisions`` collisions
through :func:`noslipsim.simulate_many`.  A start *escapes* (misses both disks
before the budget), is *stopped* by the engine for another reason (grazing, search
limit; counted apart), or survives; a survivor's ``tail`` collisions more decide
whether it *converged* onto a periodic orbit (an attractor,
:func:`noslipsim.analysis.orbit_period` of its ``(s, v_t, w)``) or stays near
the orbit without repeating (an *invariant* region).  The region's radius is
the largest ring out to which every start survives without converging; its
area ``pi r^2`` in the ``(a, b)`` plane.
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr
from scipy.optimize import brentq

from .. import tables
from .._metadata import annotate
from .._validate import count, finite_float
from ..analysis import monodromy, orbit_period, two_disk_orbit
from ..core import layout
from ..ensemble import STOP_FLAGS, simulate_many
from ..simulate import simulate

__all__ = ["FLIGHTS", "OUTCOMES", "invariant_regions", "region_counts", "reversing_orbit", "start_outcomes"]

#: The two flights between collisions: energy-conserving free fall and the isokinetic thermostat.
FLIGHTS = ("free fall", "isokinetic")

#: Branches of the orbit: free fall has a low and a high launch angle, the thermostat one orbit.
BRANCHES = {"free fall": ("low", "high"), "isokinetic": ("apex",)}

#: The dataset's ``branch`` axis: every branch of every flight.
BRANCH_AXIS = ("low", "high", "apex")

#: What became of a start, in the order the figure stacks them: it stayed its whole budget without
#: repeating, converged onto a periodic orbit, escaped (missed both disks), or the engine stopped it
#: for another reason (grazing, search limit: counted apart, not as an escape).
OUTCOMES = ("invariant", "attracted", "escaped", "stopped")

#: The apex of a thermostatted orbit is searched up to this height above ``q1``.
APEX_SPAN = 3.0


def _geometry(radius, phi):
    """``q1`` on the right disk and the chord length ``d = |q0 q1|``."""
    q1 = np.array([1.0 - radius * math.cos(phi), radius * math.sin(phi)])
    return q1, 2.0 * q1[0]


def _free_fall_orbit(radius, phi, gamma, gravity, branch):
    """Unit launch speed at ``q0``: ``sin 2 theta = g d``; ``None`` where ``g d > 1`` (no orbit)."""
    _, d = _geometry(radius, phi)
    if gravity * d > 1.0:
        return None
    low = 0.5 * math.asin(gravity * d)
    theta = low if branch == "low" else math.pi / 2 - low
    return two_disk_orbit(radius, phi, gamma, theta=theta, gravity=gravity)


def _first_hit(scene, y0):
    """Angle (seen from the right centre) of the first impact of the apex flight from ``(0, y0)``, or NaN."""
    run = simulate(scene, (0.0, y0), (1.0, 0.0), 0.0, max_collisions=1)
    if run.sizes["collision"] == 0 or int(run.element[0]) != 1:
        return math.nan
    return math.atan2(float(run.y[0]), float(run.x[0]) - 1.0)


def _isokinetic_orbit(radius, phi, gamma, gravity):
    """The apex ``y0`` whose thermostatted flight meets ``q1``, spin ``v_t / gamma`` there; ``None`` if none."""
    scene = tables.two_disks(radius, distance=2.0, gamma=gamma, force=(0.0, -gravity)).replace(thermostat="isokinetic")
    q1, _ = _geometry(radius, phi)
    target = math.pi - phi
    heights = q1[1] + np.linspace(1e-6, APEX_SPAN, 31)
    miss = np.array([_first_hit(scene, y) - target for y in heights])
    change = np.flatnonzero(np.isfinite(miss[:-1]) & np.isfinite(miss[1:]) & (np.sign(miss[:-1]) != np.sign(miss[1:])))
    if change.size == 0:
        return None
    i = int(change[0])
    y0 = brentq(lambda y: _first_hit(scene, y) - target, heights[i], heights[i + 1], xtol=1e-15, rtol=1e-15)
    hit = simulate(scene, (0.0, y0), (1.0, 0.0), 0.0, max_collisions=1)
    n = (np.array([1.0, 0.0]) - np.array([float(hit.x[0]), float(hit.y[0])])) / radius  # outward: into the disk
    v_in = np.array([float(hit.vx_in[0]), float(hit.vy_in[0])])
    spin = float(v_in @ np.array([-n[1], n[0]])) / gamma
    return scene, {"position": (0.0, y0), "velocity": (1.0, 0.0), "spin": spin}


def reversing_orbit(radius, phi, gamma, gravity, flight, branch):
    """The path-reversing 2-periodic two-disk orbit of one flight and branch, at its apex.

    Parameters
    ----------
    radius, phi, gamma, gravity : float
        Disk radius in ``(0, 1)``, angle of ``q0`` in ``(0, pi/2)``, ``gamma > 0``, ``g > 0``.
    flight : {'free fall', 'isokinetic'}
    branch : str
        ``'low'`` or ``'high'`` (free fall), ``'apex'`` (isokinetic).

    Returns
    -------
    (Scene, dict) or None
        The scene and the apex state (``position``, ``velocity``, ``spin``),
        or ``None`` when the flight has no such orbit at this force.
    """
    if flight == "free fall":
        return _free_fall_orbit(radius, phi, gamma, gravity, branch)
    return _isokinetic_orbit(radius, phi, gamma, gravity)


def _ring_starts(state, ring_step, rings, starts):
    """Starts on ``rings`` rings of ``starts`` points in the (turn angle, spin / speed) plane of the apex state."""
    k = np.repeat(np.arange(1, rings + 1), starts)
    angle = np.tile(2 * math.pi * (np.arange(starts) + 0.5) / starts, rings)
    a, b = k * ring_step * np.cos(angle), k * ring_step * np.sin(angle)
    v = np.asarray(state["velocity"], dtype=float)
    speed = math.hypot(*v)
    c, s = np.cos(a), np.sin(a)
    vel = np.c_[c * v[0] - s * v[1], s * v[0] + c * v[1]]
    pos = np.tile(np.asarray(state["position"], dtype=float), (k.size, 1))
    return pos, vel, state["spin"] + b * speed, k


def start_outcomes(stop_reasons, periods):
    """Outcome index of each start (``OUTCOMES``) from its stop reason and the period of its tail.

    Parameters
    ----------
    stop_reasons : array_like of int
        Each start's stop code (``noslipsim.core.layout.STOP_REASONS``).
    periods : array_like of int
        Period of each start's tail (:func:`noslipsim.analysis.orbit_period`; 0: none).

    Returns
    -------
    numpy.ndarray of int8
        Budget reached: attracted when periodic, else invariant; ``escape``:
        escaped; any other stop: stopped.
    """
    stop, p = np.asarray(stop_reasons), np.asarray(periods)
    budget, escape = layout.STOP_REASONS.index("max_collisions"), layout.STOP_REASONS.index("escape")
    staying = np.where(p > 0, OUTCOMES.index("attracted"), OUTCOMES.index("invariant"))
    other = np.where(stop == escape, OUTCOMES.index("escaped"), OUTCOMES.index("stopped"))
    return np.where(stop == budget, staying, other).astype(np.int8)


#: A recorded collision state: which disk, arclength, and the unit ``(v_t, w)`` (the element is a
#: coordinate too, since ``s`` alone does not say which disk).
STATE_KEYS = ("element", "s", "vt_unit", "w_unit")


def _portrait_states(scene, pos, vel, spin, collisions, element, scheduler, num_workers):
    """``(orbit, point, 4)`` collision states (``STATE_KEYS``) of ``collisions`` collisions from each start."""
    rec = simulate_many(scene, pos, vel, spin, max_collisions=collisions, record="portrait", start_elements=element,
                        scheduler=scheduler, num_workers=num_workers, progress=False)
    return np.stack([rec[k].values for k in STATE_KEYS], axis=-1)


def _distance_to(states, reference, length):
    """Largest, over the recorded states, max-norm distance to the reference state on the same disk."""
    d = np.abs(states[:, None, 1:] - reference[None, :, 1:])
    d[..., 0] = np.minimum(d[..., 0], length - d[..., 0])        # s on a circle
    d = np.where(states[:, None, 0] == reference[None, :, 0], d.max(axis=-1), np.inf)
    return float(np.nanmax(d.min(axis=1)))


def _tails(scene, runs, reference, tail, scheduler, num_workers):
    """Continue each survivor ``tail`` collisions from its final impact: its period and its distance from the orbit.

    ``reference`` holds the orbit's own two collision states; a survivor far
    from them stays in some other region, which the distance tells.
    """
    alive = np.flatnonzero(runs.stop_reason.values == 0)
    periods = np.zeros(runs.sizes["orbit"], dtype=np.int64)
    distance = np.full(runs.sizes["orbit"], np.nan)
    if alive.size == 0:
        return periods, distance
    pick = runs.isel(orbit=alive)
    pos = np.c_[pick.x_final.values, pick.y_final.values]
    element = (pos[:, 0] > 0).astype(np.int64)   # the right disk is element 1
    states = _portrait_states(scene, pos, np.c_[pick.vx_final.values, pick.vy_final.values],
                              pick.spin_final.values, tail, element, scheduler, num_workers)
    length = 2 * math.pi * scene.elements[0].radius
    for i, x in zip(alive, states):
        periods[i] = orbit_period(x, wrap=(None, length, None, None))
        distance[i] = _distance_to(x[np.isfinite(x).all(axis=1)], reference, length)
    return periods, distance


def _linear_kind(scene, state, flight):
    """Class of the orbit's 2-bounce monodromy (free fall); the thermostat has no tangent map: ``''``."""
    if flight != "free fall":
        return ""
    return monodromy(scene, **state, period=2).kind


def _one_orbit(found, flight, p, scheduler, num_workers):
    """Outcome of every ring start around one orbit, and the orbit's own check (periodic, class)."""
    scene, state = found
    rings, starts, max_collisions = p["rings"], p["starts"], p["max_collisions"]
    pos, vel, spin, _ = _ring_starts(state, p["ring_step"], rings, starts)
    pos = np.vstack([state["position"], pos])   # start 0: the orbit itself, unperturbed
    vel = np.vstack([state["velocity"], vel])
    spin = np.r_[state["spin"], spin]
    runs = simulate_many(scene, pos, vel, spin, max_collisions=max_collisions, record="final",
                         scheduler=scheduler, num_workers=num_workers, progress=False)
    reference = _portrait_states(scene, pos[:1], vel[:1], spin[:1], 2, None, "sync", None)[0]
    periods, distance = _tails(scene, runs, reference, p["tail"], scheduler, num_workers)
    outcome = start_outcomes(runs.stop_reason.values, periods)
    per_start = [x[1:].reshape(rings, starts) for x in (outcome, runs.n_collisions.values, runs.stop_reason.values,
                                                        periods, distance)]
    return (*per_start, int(periods[0]), _linear_kind(scene, state, flight))


def _region_radius(outcome, ring_step):
    """Largest ring radius out to which every start stays without converging (0: not even the first ring)."""
    inside = (outcome == 0).all(axis=-1)
    k = int(np.argmin(inside)) if not inside.all() else inside.size
    return k * ring_step


def _checked(forces, radius, phi, gamma, ring_step, counts, flights):
    """The validated parameters of :func:`invariant_regions`, as one dict."""
    forces = np.atleast_1d(np.asarray(forces, dtype=float))
    if forces.ndim != 1 or forces.size == 0 or not np.all(np.isfinite(forces)) or (forces <= 0).any():
        raise ValueError(f"forces: expected a non-empty 1-D array of numbers > 0, got {forces!r}")
    radius, phi, gamma = (finite_float(x, f) for x, f in ((radius, "radius"), (phi, "phi"), (gamma, "gamma")))
    if not 0 < radius < 1:
        raise ValueError(f"radius: must lie in (0, 1) (disks centred 2 apart must not touch), got {radius}")
    if not 0 < phi < math.pi / 2:
        raise ValueError(f"phi: must lie in (0, pi/2), got {phi}")
    if not gamma > 0:
        raise ValueError(f"gamma: must be > 0, got {gamma}")
    ring_step = finite_float(ring_step, "ring_step")
    if not ring_step > 0:
        raise ValueError(f"ring_step: must be > 0, got {ring_step}")
    flights = list(flights)
    if not flights or any(f not in FLIGHTS for f in flights) or len(set(flights)) < len(flights):
        raise ValueError(f"flights: expected distinct names among {FLIGHTS}, got {flights!r}")
    return dict(forces=forces, radius=radius, phi=phi, gamma=gamma, ring_step=ring_step, flights=flights,
                **{name: count(value, name) for name, value in counts.items()})


def invariant_regions(forces, radius=0.8, phi=0.3, gamma=1 / math.sqrt(2), *, rings=12, starts=16,
                      ring_step=0.01, max_collisions=100_000, tail=60, flights=FLIGHTS, scheduler="numba",
                      num_workers=None):
    r"""Invariant regions (or attractors) around the two-disk path-reversing orbits as the force grows (Figure S7).

    For each flight (``'free fall'``, ``'isokinetic'``), force ``g`` and
    branch, the orbit of :func:`reversing_orbit` (none: counted as missing),
    its linear class (free fall, exact monodromy), and ``rings x starts``
    starts around it (module docstring), each run ``max_collisions``
    collisions; survivors run ``tail`` collisions more, whose ``(element, s,
    v_t, w)`` say whether they converged onto a periodic orbit.  The orbit
    itself is run as well: ``orbit_period`` 2 says it stayed on its cycle.

    Parameters
    ----------
    forces : array_like
        Forces ``g > 0`` (force ``(0, -g)``; unit speed: at launch in free fall, always with the thermostat).
    radius, phi, gamma : float
        Disk radius in ``(0, 1)``, angle of ``q0`` in ``(0, pi/2)``, ``gamma > 0``.
    rings, starts : int
        Rings around each orbit and starts per ring.
    ring_step : float
        Radius step of the rings in the ``(turn angle, spin / speed)`` plane (> 0).
    max_collisions, tail : int
        Collision budget of a start; collisions more that look for a period.
    flights : sequence of str
        Which of ``FLIGHTS`` to run.
    scheduler, num_workers
        Passed to :func:`noslipsim.simulate_many` (``'numba'``, threads, a
        ``dask.distributed`` Client or its address: ``noslipsim.cluster.ensemble_options``).

    Returns
    -------
    xarray.Dataset
        On ``(flight, force, branch, ring, start)``: ``start_outcome`` (index
        into ``OUTCOMES``, the ``outcome`` axis; -1 where there is no orbit),
        ``n_collisions``, ``stop_reason`` (-1: no orbit), ``period``, ``tail_distance`` (survivors: how far
        their tail strays from the orbit's own states); on ``(flight, force, branch)``:
        ``exists``, ``orbit_period``, ``linear_kind``, ``region_radius``,
        ``region_area`` and ``staying_area`` (each ring's share of staying
        starts times its annulus); on ``(flight, force, branch, ring, outcome)``: ``starts_by_outcome``.

    Raises
    ------
    ValueError
        Bad forces, geometry, counts or flights.
    """
    p = _checked(forces, radius, phi, gamma, ring_step,
                 dict(rings=rings, starts=starts, max_collisions=max_collisions, tail=tail), flights)
    shape = (len(p["flights"]), p["forces"].size, len(BRANCH_AXIS))
    per_start = (*shape, p["rings"], p["starts"])
    arr = dict(start_outcome=np.full(per_start, -1, dtype=np.int8), n_collisions=np.zeros(per_start, dtype=np.int64),
               stop_reason=np.full(per_start, -1, dtype=np.int8), period=np.zeros(per_start, dtype=np.int64),
               tail_distance=np.full(per_start, np.nan),
               exists=np.zeros(shape, np.int8),
               orbit_period=np.zeros(shape, np.int64), linear_kind=np.full(shape, "", dtype="<U10"))
    for i, flight in enumerate(p["flights"]):
        for j, g in enumerate(p["forces"]):
            for b in BRANCHES[flight]:
                idx = (i, j, BRANCH_AXIS.index(b))
                found = reversing_orbit(p["radius"], p["phi"], p["gamma"], float(g), flight, b)
                if found is None:
                    continue
                arr["exists"][idx] = 1
                out = _one_orbit(found, flight, p, scheduler, num_workers)
                for key, value in zip(("start_outcome", "n_collisions", "stop_reason", "period", "tail_distance",
                                             "orbit_period", "linear_kind"), out):
                    arr[key][idx] = value
    return _regions_dataset(arr, p)


def _annuli(rings, ring_step):
    """Area each ring stands for: ring ``k`` the annulus ``((k - 1/2) h, (k + 1/2) h)``, ring 1 from the centre."""
    outer = (np.arange(1, rings + 1) + 0.5) * ring_step
    inner = np.r_[0.0, outer[:-1]]
    return math.pi * (outer ** 2 - inner ** 2)


def _regions_dataset(arr, p):
    """The dataset of :func:`invariant_regions` from its arrays and validated parameters."""
    outcome, ring_step, exists = arr["start_outcome"], p["ring_step"], arr["exists"] == 1
    radius_of = np.full(exists.shape, np.nan)
    for idx in zip(*np.nonzero(exists)):
        radius_of[idx] = _region_radius(outcome[idx], ring_step)
    by_outcome = np.stack([(outcome == o).sum(axis=-1) for o in range(len(OUTCOMES))], axis=-1)
    staying_area = (by_outcome[..., 0] / p["starts"]) @ _annuli(p["rings"], ring_step)
    dims = ("flight", "force", "branch")
    full = (*dims, "ring", "start")
    ring = np.arange(1, p["rings"] + 1)
    ds = xr.Dataset(
        {**{k: (full, arr[k]) for k in ("start_outcome", "n_collisions", "period", "tail_distance")},
         "stop_reason": (full, arr["stop_reason"], dict(STOP_FLAGS)),
         **{k: (dims, arr[k]) for k in ("exists", "orbit_period", "linear_kind")},
         "region_radius": (dims, radius_of), "region_area": (dims, math.pi * radius_of ** 2),
         "staying_area": (dims, np.where(exists, staying_area, np.nan)),
         "starts_by_outcome": ((*dims, "ring", "outcome"), by_outcome.astype(np.int64))},
        coords={"flight": p["flights"], "force": p["forces"], "branch": list(BRANCH_AXIS), "ring": ring,
                "ring_radius": ("ring", ring * ring_step), "start": np.arange(p["starts"]),
                "outcome": list(OUTCOMES)})
    ds.attrs.update(
        title="invariant regions around two-disk path-reversing 2-periodic orbits under a force", law="no-slip",
        **{k: p[k] for k in ("radius", "phi", "gamma", "max_collisions", "tail", "ring_step")},
        outcomes=list(OUTCOMES),
        scene=("two no-slip disks of radius R centred at (-1, 0) and (1, 0), open table, force (0, -g) "
               "(noslipsim.tables.two_disks(R, distance=2))"),
        perturbation=("start on ring k at angle psi: the apex velocity turned by k ring_step cos psi rad, "
                      "the spin raised by k ring_step sin psi times the speed"),
        region=("region_radius: the largest ring radius out to which every start neither escapes nor converges; "
                "region_area = pi region_radius^2 in the (turn angle, spin / speed) plane"))
    return annotate(ds)


def region_counts(ds):
    """Starts by outcome per ``(flight, force, branch)``, summed over the rings.

    Parameters
    ----------
    ds : xarray.Dataset
        An :func:`invariant_regions` dataset.

    Returns
    -------
    xarray.Dataset
        ``starts`` on ``(flight, force, branch, outcome)`` and ``total`` (every start of an existing orbit).
    """
    starts = ds.starts_by_outcome.sum("ring")
    return xr.Dataset({"starts": starts, "total": starts.sum("outcome")})
