"""Sets of orbits as one dataset: several single orbits, and the phase-portrait points of an ensemble."""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .. import initial
from .._metadata import annotate
from .._validate import count
from ..ensemble import simulate_many
from ..scenes import Scene
from ..simulate import simulate


def orbit_set(scenes, positions, velocities, spins=None, *, max_collisions=1000, max_time=math.inf,
              stop_below=None):
    """Several single orbits, each in its own scene, as one dataset (figures that draw orbits).

    Parameters
    ----------
    scenes : sequence of Scene
        One scene per orbit.
    positions, velocities : array_like (N, 2)
        Starts and initial velocities.
    spins : array_like (N,), optional
        Initial scaled spins (zeros by default).
    max_collisions, max_time, stop_below
        Stops, as in :func:`noslipsim.simulate` (the same for every orbit).

    Returns
    -------
    xarray.Dataset
        Dims ``(orbit, collision)``: the collision log of :func:`noslipsim.simulate`
        (NaN past each orbit's end), per orbit the start state ``x_start,
        y_start, vx_start, vy_start, spin_start``, the final state ``*_final``,
        ``n_collisions``, ``stop_reason`` (a name) and the ``scene`` (JSON);
        coordinates ``law`` and ``gamma`` along ``orbit``.  One orbit,
        ``ds.isel(orbit=i)``, is drawn by :func:`noslipsim.plot.draw_orbit`.
    """
    scenes = list(scenes)
    n = len(scenes)
    if n == 0:
        raise ValueError("scenes: expected at least one scene")
    for i, sc in enumerate(scenes):
        if not isinstance(sc, Scene):
            raise ValueError(f"scenes[{i}]: expected a noslipsim.Scene, got {type(sc).__name__}")
    pos = np.asarray(positions, dtype=float)
    vel = np.asarray(velocities, dtype=float)
    w = np.zeros(n) if spins is None else np.asarray(spins, dtype=float)
    if pos.shape != (n, 2) or vel.shape != (n, 2) or w.shape != (n,):
        raise ValueError(f"positions, velocities, spins: expected shapes ({n}, 2), ({n}, 2), ({n},) for "
                         f"{n} scenes, got {pos.shape}, {vel.shape}, {w.shape}")
    orbits = [simulate(sc, p, v, s, max_collisions=max_collisions, max_time=max_time, stop_below=stop_below)
              for sc, p, v, s in zip(scenes, pos, vel, w)]
    log_vars = [k for k, v in orbits[0].data_vars.items() if v.dims == ("collision",)]
    length = max(o.sizes["collision"] for o in orbits)
    data = {}
    for k in log_vars:
        rows = np.full((n, length), np.nan)
        for i, o in enumerate(orbits):
            rows[i, :o.sizes["collision"]] = o[k].values
        data[k] = (("orbit", "collision"), rows)
    for k in ("t_final", "x_final", "y_final", "vx_final", "vy_final", "spin_final", "n_collisions"):
        data[k] = ("orbit", np.array([o[k].values for o in orbits]))
    for j, k in enumerate(("x_start", "y_start")):
        data[k] = ("orbit", pos[:, j])
    for j, k in enumerate(("vx_start", "vy_start")):
        data[k] = ("orbit", vel[:, j])
    data["spin_start"] = ("orbit", w)
    data["stop_reason"] = ("orbit", np.array([o.attrs["stop_reason"] for o in orbits], dtype=object))
    data["scene"] = ("orbit", np.array([sc.to_json() for sc in scenes], dtype=object))
    ds = xr.Dataset(data, coords={
        "orbit": np.arange(n),
        "collision": np.arange(length),
        "law": ("orbit", [sc.law for sc in scenes]),
        "gamma": ("orbit", [sc.gamma if sc.any_noslip else math.nan for sc in scenes]),
    })
    ds.attrs.update(title="orbits", max_collisions=max_collisions, max_time=float(max_time),
                    stop_below=math.nan if stop_below is None else float(stop_below))
    return annotate(ds)


def phase_portrait(scene: Scene, n_orbits=20, n_collisions=1000, *, seed=0, elements=None, initial_states=None,
                   chunk_size=None, scheduler=None, progress=None):
    """Velocity phase-portrait points: per orbit, per collision on ``elements``, ``s`` and ``(w, v_t, v_n)``/norm.

    Orbits start from ``initial_states`` (a dict as returned by
    :func:`noslipsim.initial.boundary_states`) or, by default, from states
    uniform on the boundary of the chosen elements in the reduced phase space.
    """
    count(n_collisions, "n_collisions")
    if initial_states is None:
        initial_states = initial.boundary_states(scene, count(n_orbits, "n_orbits"), seed, elements)
    ds = simulate_many(scene, initial_states["positions"], initial_states["velocities"],
                       initial_states.get("spins"), max_collisions=n_collisions, record="portrait",
                       elements=elements, start_elements=initial_states.get("start_elements"),
                       chunk_size=chunk_size, scheduler=scheduler, progress=progress)
    ds.attrs.update(title="velocity phase portrait", seed=seed)
    return ds
