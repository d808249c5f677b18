"""One orbit: validate the start, run the compiled event loop, return an ``xarray.Dataset``."""
from __future__ import annotations

import json
import math
from collections.abc import Callable

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ._engine.canonical import canonical_form
from ._engine.lattice import cell_of, cell_origin
from ._engine.run import run_orbits
from ._engine.table import kernel_table
from ._metadata import annotate
from ._validate import finite_float, finite_vector, zeros
from ._version import __version__
from .core import layout
from .core.batch import F_CELL1, F_CELL2, F_CORNER, F_N, F_NREC, F_STOP, F_T, F_VX, F_VY, F_W, F_X, F_Y
from .scenes import _RANGE_DOC, MAX_MAGNITUDE, MAX_THERMOSTAT_FIELD, MIN_FEATURE, MIN_MAGNITUDE, Scene

_COLUMNS = {
    "t": layout.LOG_T, "x": layout.LOG_X, "y": layout.LOG_Y, "vx": layout.LOG_VX,
    "vy": layout.LOG_VY, "spin": layout.LOG_W, "vx_in": layout.LOG_VX_IN,
    "vy_in": layout.LOG_VY_IN, "spin_in": layout.LOG_W_IN, "s": layout.LOG_S,
}

#: How far inside the table a start must be, relative to the scene's scale.
START_MARGIN = 1e-12


def check_magnitudes(scene: Scene, rel: ArrayLike, v: ArrayLike, w: ArrayLike,
                     fields: tuple[str, str, str] = ("position", "velocity", "spin"),
                     orbit: str | Callable[[int], str] = "") -> None:
    """Refuse starts outside the range of scales the engine is exact for (docs/conventions.md).

    ``rel`` are the start positions relative to their cell's origin (``(N, 2)``), ``v`` the
    velocities, ``w`` the spins.  The length scale of an orbit is ``L = max(table size, |rel|)``;
    its speed scale ``V`` is ``|v|`` (no force, or the isokinetic thermostat, which keeps ``|v|``)
    or ``max(|v|, sqrt(|a| L))`` under free fall.  Both must lie in ``[MIN_MAGNITUDE,
    MAX_MAGNITUDE]``, ``|w| <= MAX_MAGNITUDE``, and the table's smallest piece must be at least
    ``MIN_FEATURE L`` (the engine's tolerances are relative to ``L``).  A thermostatted flight also
    needs ``|a| L / |v|^2 <= MAX_THERMOSTAT_FIELD`` (its turning radius ``|v|^2 / |a|`` not below
    ``L / MAX_THERMOSTAT_FIELD``: a sharper turn back into the element just left is missed).  ``orbit`` prefixes the
    messages: a string, or a callable of the orbit's index (``lambda i: f'orbit {i}: '`` for ensembles).
    """
    pos, vel, spin = fields
    rel, v, w = np.atleast_2d(rel), np.atleast_2d(v), np.atleast_1d(w)
    name = orbit if callable(orbit) else (lambda i: orbit)

    def first(bad):
        return int(np.argmax(bad))

    with np.errstate(all="ignore"):
        L = np.maximum(scene.scale, np.abs(rel).max(axis=1))
        speed = np.hypot(v[:, 0], v[:, 1])
        a = math.hypot(*scene.force)
        V = speed if (a == 0.0 or scene.thermostat is not None) else np.maximum(speed, np.sqrt(a * L))
    bad = L > MAX_MAGNITUDE
    if bad.any():
        i = first(bad)
        raise ValueError(f"{pos}: {name(i)}|q| = {L[i]:.3g} lies beyond {MAX_MAGNITUDE:g}, the largest length the "
                         f"engine is exact for ({_RANGE_DOC})")
    bad = L < MIN_MAGNITUDE
    if bad.any():
        i = first(bad)
        raise ValueError(f"{pos}: {name(i)}the start and the table lie within {L[i]:.3g} of the origin, below "
                         f"{MIN_MAGNITUDE:g}, the smallest length the engine is exact for ({_RANGE_DOC})")
    bad = scene.smallest_feature < MIN_FEATURE * L
    if bad.any():
        i = first(bad)
        raise ValueError(f"{pos}: {name(i)}|q| = {L[i]:.3g} is more than {1 / MIN_FEATURE:g} times the table's "
                         f"smallest piece ({scene.smallest_feature:.3g}), which would lie within the engine's "
                         f"tolerances there ({_RANGE_DOC})")
    bad = (speed > MAX_MAGNITUDE) | (V > MAX_MAGNITUDE)
    if bad.any():
        i = first(bad)
        what = f"speed {speed[i]:.3g}" if speed[i] > MAX_MAGNITUDE else f"speed scale sqrt(|a| L) = {V[i]:.3g}"
        raise ValueError(f"{vel}: {name(i)}{what} lies beyond {MAX_MAGNITUDE:g}, the largest speed the engine is "
                         f"exact for ({_RANGE_DOC})")
    bad = (V < MIN_MAGNITUDE) & (V > 0.0)
    if bad.any():
        i = first(bad)
        raise ValueError(f"{vel}: {name(i)}speed {V[i]:.3g} is below {MIN_MAGNITUDE:g}, the smallest speed the "
                         f"engine is exact for ({_RANGE_DOC})")
    bad = np.abs(w) > MAX_MAGNITUDE
    if bad.any():
        i = first(bad)
        raise ValueError(f"{spin}: {name(i)}|w| = {abs(w[i]):.3g} lies beyond {MAX_MAGNITUDE:g}, the largest spin "
                         f"the engine is exact for ({_RANGE_DOC})")
    if scene.thermostat is not None and a > 0.0:
        with np.errstate(all="ignore"):
            stiff = a * L / (speed * speed)
        bad = (speed > 0.0) & ~(stiff <= MAX_THERMOSTAT_FIELD)  # (zero speed: refused by name elsewhere)
        if bad.any():
            i = first(bad)
            raise ValueError(f"{vel}: {name(i)}the thermostatted field |a| L / |v|^2 = {stiff[i]:.3g} lies beyond "
                             f"{MAX_THERMOSTAT_FIELD:g}, the strongest field its flights are exact for: a turn "
                             f"back into the element just left would be missed; use a larger speed or a weaker "
                             f"force ({_RANGE_DOC})")


def check_start(scene: Scene, position, velocity, spin):
    """Validate one initial state; returns ``(q, v, w)`` as floats.

    The start must be strictly inside the table (not on its boundary) and the
    particle must move: zero speed needs a nonzero force.
    """
    q = finite_vector(position, "position")
    v = finite_vector(velocity, "velocity")
    w = finite_float(spin, "spin")
    rel = start_cell(scene, q)[2]
    check_magnitudes(scene, rel, v, w)
    margin = START_MARGIN * max(scene.scale, float(np.abs(rel).max()))
    try:
        depth = float(scene.depth(q[None])[0])
    except ValueError as err:  # the copies of the elements around a far cell collapse in rounding
        raise ValueError(f"position: {q.tolist()} is too far out on the lattice for this scene's "
                         f"smallest elements ({err})") from None
    if not depth > margin:
        where = "on the boundary of" if abs(depth) <= margin else "outside"
        raise ValueError(f"position: {q.tolist()} is {where} the table (depth {depth:.3g}); "
                         "a start must lie strictly inside")
    if v[0] == 0.0 and v[1] == 0.0 and scene.force == (0.0, 0.0):
        raise ValueError("velocity: zero speed with zero force never moves")
    if v[0] == 0.0 and v[1] == 0.0 and scene.thermostat is not None:
        raise ValueError("velocity: the isokinetic thermostat keeps the speed, so it needs a nonzero one")
    return q, v, w


def check_level(stop_below: float | None) -> float:
    """``-inf`` for no level, else ``stop_below`` as a finite height within the lengths the engine is exact for."""
    if stop_below is None:
        return -math.inf
    level = finite_float(stop_below, "stop_below")
    if abs(level) > MAX_MAGNITUDE:
        raise ValueError(f"stop_below: {level:.3g} lies beyond {MAX_MAGNITUDE:g}, the largest length the engine is "
                         f"exact for ({_RANGE_DOC})")
    return level


def check_limits(max_collisions, max_time):
    """Validate stop limits: a finite collision budget and a positive time limit."""
    if isinstance(max_collisions, bool) or not isinstance(max_collisions, (int, np.integer)):
        raise ValueError(f"max_collisions: expected an integer, got {max_collisions!r}")
    if max_collisions < 0:
        raise ValueError(f"max_collisions: must be >= 0, got {max_collisions}")
    try:
        max_time = float(max_time)
    except (TypeError, ValueError):
        raise ValueError(f"max_time: expected a number (or inf), got {max_time!r}") from None
    if math.isnan(max_time) or max_time <= 0.0:
        raise ValueError(f"max_time: must be > 0 (or inf), got {max_time}")
    return int(max_collisions), max_time


def simulate(scene: Scene, position: ArrayLike, velocity: ArrayLike, spin: float = 0.0,
             max_collisions: int = 1000, max_time: float = math.inf,
             stop_below: float | None = None) -> xr.Dataset:
    """Simulate one orbit exactly, collision by collision.

    Parameters
    ----------
    scene : Scene
        Table, law, gamma and force.
    position : (float, float)
        Start ``(x, y)``, strictly inside the table.
    velocity : (float, float)
        Initial velocity ``(v_x, v_y)``.
    spin : float
        Initial scaled spin ``w = gamma R omega`` (counter-clockwise positive).
    max_collisions : int
        Collision budget (corner collisions count).
    max_time : float
        Time limit; the final state is then advanced to it.
    stop_below : float, optional
        End the orbit when it crosses this height downwards.

    Returns
    -------
    xarray.Dataset
        Dim ``collision``: ``t, x, y, vx, vy, spin`` just after each collision,
        ``vx_in, vy_in, spin_in`` just before, ``element``, ``s``, ``corner`` and
        ``energy``; scalars ``*_final`` (the state where the orbit ended) and
        ``n_collisions``; attribute ``stop_reason`` (``max_collisions``,
        ``max_time``, ``escape``, ``stop_below``, ``corner``, ``grazing`` or
        ``search_limit``; docs/datasets.md).
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
    q, v, w = check_start(scene, position, velocity, spin)
    max_collisions, max_time = check_limits(max_collisions, max_time)
    level = check_level(stop_below)
    if level >= q[1]:
        raise ValueError(f"stop_below: {level} must lie below the start height {q[1]}")
    rec = zeros((max_collisions, layout.N_LOG), "max_collisions", f"a log of {max_collisions} collisions",
                "for long orbits use simulate_many(..., record='final')")
    out = run_one(scene, q, v, w, max_collisions, max_time, level, layout.RECORD_LOG, rec)
    _n, stop, n_corner, n_rec, final, cell = out
    return _orbit_dataset(scene, rec[:n_rec], stop, n_corner, final, cell,
                          dict(position=q.tolist(), velocity=v.tolist(), spin=w))


def start_cell(scene: Scene, q):
    """Split a start into its lattice cell and the position relative to that cell's centre."""
    if scene.lattice is None:
        return np.zeros(2, dtype=np.int64), np.zeros(2), q
    cell = cell_of(q, scene.lattice)
    origin = cell_origin(cell, scene.lattice)
    return cell, origin, q - origin


def run_one(scene: Scene, q, v, w, max_collisions, max_time, level, mode, rec):
    """Run the kernel for one validated start; positions and cells come back absolute.

    The kernel runs the scene's canonical form (:mod:`noslipsim._engine.canonical`);
    positions, levels and cell indices are mapped to and from the user's coordinates here.
    """
    form = canonical_form(scene)
    cell, origin, r = form.kernel_starts(q)
    table = kernel_table(form.scene)
    final = run_orbits(table, [[r[0], r[1], v[0], v[1], w]], max_collisions=max_collisions,
                       max_time=max_time, levels=[form.user_level(level) - origin[1]], mode=mode,
                       rec=rec[None], ceilings=[table.top - origin[1]])[0]
    n, stop, n_corner, n_rec = (int(final[k]) for k in (F_N, F_STOP, F_CORNER, F_NREC))
    t, x, y, vx, vy, w_f = final[[F_T, F_X, F_Y, F_VX, F_VY, F_W]]
    m1, m2 = int(final[F_CELL1]), int(final[F_CELL2])
    if mode == layout.RECORD_LOG and scene.lattice is not None:
        log = rec[:n_rec]
        xs = log[:, layout.LOG_X] + origin[0]
        ys = log[:, layout.LOG_Y] + origin[1]
        m1s, m2s = form.user_cells(log[:, layout.LOG_CELL_A1] + cell[0], log[:, layout.LOG_CELL_A2] + cell[1], xs, ys)
        log[:, layout.LOG_X], log[:, layout.LOG_Y] = form.user_positions(xs, ys)
        log[:, layout.LOG_CELL_A1], log[:, layout.LOG_CELL_A2] = m1s, m2s
    x, y = x + origin[0], y + origin[1]
    m = form.user_cells(m1 + int(cell[0]), m2 + int(cell[1]), x, y)
    x, y = form.user_positions(x, y)
    if stop == layout.STOP_LEVEL:
        y = level  # the stop is the exact crossing of the user's level
    final = (float(t), float(x), float(y), float(vx), float(vy), float(w_f))
    return n, stop, n_corner, n_rec, final, (int(m[0]), int(m[1]))


def _orbit_dataset(scene, log, stop, n_corner, final, cell, start):
    dim = ("collision",)
    data = {name: (dim, log[:, col].copy()) for name, col in _COLUMNS.items()}
    data["element"] = (dim, log[:, layout.LOG_ELEMENT].astype(np.int32))
    data["corner"] = (dim, log[:, layout.LOG_CORNER].astype(np.int8))
    ax, ay = scene.force if scene.thermostat is None else (0.0, 0.0)  # the thermostat keeps the kinetic energy
    data["energy"] = (dim, 0.5 * (log[:, layout.LOG_VX] ** 2 + log[:, layout.LOG_VY] ** 2
                                  + log[:, layout.LOG_W] ** 2)
                      - (ax * log[:, layout.LOG_X] + ay * log[:, layout.LOG_Y]))
    for name, value in zip(("t_final", "x_final", "y_final", "vx_final", "vy_final", "spin_final"), final):
        data[name] = ((), value)
    data["n_collisions"] = ((), len(log))
    if scene.lattice is not None:
        data["cell_a1"] = (dim, log[:, layout.LOG_CELL_A1].astype(np.int64))
        data["cell_a2"] = (dim, log[:, layout.LOG_CELL_A2].astype(np.int64))
        data["cell_a1_final"] = ((), cell[0])
        data["cell_a2_final"] = ((), cell[1])
    ds = xr.Dataset(data, coords={"collision": np.arange(len(log))})
    ds.attrs.update(
        title="noslipsim orbit",
        source=f"noslipsim {__version__}",
        stop_reason=layout.STOP_REASONS[stop],
        n_corner=int(n_corner),
        law=scene.law,
        gamma=scene.gamma,
        force=list(scene.force),
        scene=scene.to_json(),
        start=json.dumps(start),
    )
    return annotate(ds)
