"""The paper's experiments as functions that return self-describing datasets."""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from . import initial, tables
from .core import layout
from .ensemble import simulate_many
from .metadata import annotate
from .scenes import Scene


def galton_distribution(n_particles=100_000, *, laws=("specular", "no-slip"), gamma=1 / math.sqrt(2),
                        spacing=2.0, radius=0.5, gravity=1.0, rows=100, max_time=1000.0,
                        start=(1.0, 0.0), max_collisions=10**7, seed=0, chunk_size=None,
                        scheduler=None, progress=None):
    """Terminal horizontal positions on a Galton board (paper, introduction and Figure 3).

    Particles start at ``start`` (between two pegs of the top row) with unit
    speed in a uniformly random direction and zero spin; an orbit ends when it
    crosses the terminal depth ``rows`` peg rows below the start (exact
    crossing), or at ``max_time`` (not arrived).  The same seed gives the same
    directions for every law.

    Returns
    -------
    xarray.Dataset
        Dims ``(law, particle)``: ``x_terminal`` (NaN if not arrived),
        ``t_terminal``, ``arrived``, ``n_collisions``, ``stop_reason``; per law
        ``share_not_arrived``.
    """
    depth = rows * spacing * math.sqrt(3.0) / 2.0
    level = start[1] - depth
    vel = initial.unit_velocities(n_particles, seed)
    pos = np.tile(np.asarray(start, float), (n_particles, 1))
    out = []
    for law in laws:
        scene = tables.galton_board(spacing, radius, gravity, law=law, gamma=gamma if law == "no-slip" else 0.0)
        ds = simulate_many(scene, pos, vel, np.zeros(n_particles), max_collisions=max_collisions,
                           max_time=max_time, stop_below=level, record="final", chunk_size=chunk_size,
                           scheduler=scheduler, progress=progress)
        arrived = ds.stop_reason.values == layout.STOP_LEVEL
        out.append(xr.Dataset({
            "x_terminal": ("particle", np.where(arrived, ds.x_final.values - start[0], np.nan),
                           {"long_name": "horizontal displacement at the terminal depth", "units": "1"}),
            "t_terminal": ("particle", np.where(arrived, ds.t_final.values, np.nan),
                           {"long_name": "time of arrival at the terminal depth", "units": "1"}),
            "arrived": ("particle", arrived.astype(np.int8),
                        {"long_name": "1 if the particle reached the terminal depth by max_time", "units": "1"}),
            "n_collisions": ("particle", ds.n_collisions.values),
            "stop_reason": ("particle", ds.stop_reason.values, ds.stop_reason.attrs),
        }))
    res = xr.concat(out, dim=xr.DataArray(list(laws), dims="law", name="law"))
    res["share_not_arrived"] = 1.0 - res.arrived.mean("particle")
    res["share_not_arrived"].attrs = {"long_name": "share of particles not at the terminal depth by max_time",
                                      "units": "1"}
    res.attrs.update(title="Galton board terminal distribution", gamma=gamma, spacing=spacing, radius=radius,
                     gravity=gravity, rows=rows, terminal_depth=depth, max_time=max_time,
                     start=list(start), seed=seed)
    return annotate(res)


def phase_portrait(scene: Scene, n_orbits=20, n_collisions=1000, *, seed=0, elements=None, initial_states=None,
                   chunk_size=None, scheduler=None, progress=None):
    """Velocity phase-portrait points: per orbit, per collision on ``elements``, ``s`` and ``(w, v_t, v_n)``/norm.

    Orbits start from ``initial_states`` (a dict as returned by
    :func:`noslipsim.initial.boundary_states`) or, by default, from states
    uniform on the boundary of the chosen elements in the reduced phase space.
    """
    if initial_states is None:
        initial_states = initial.boundary_states(scene, n_orbits, seed, elements)
    ds = simulate_many(scene, initial_states["positions"], initial_states["velocities"],
                       initial_states.get("spins"), max_collisions=n_collisions, record="portrait",
                       elements=elements, start_elements=initial_states.get("start_elements"),
                       chunk_size=chunk_size, scheduler=scheduler, progress=progress)
    ds.attrs.update(title="velocity phase portrait", seed=seed)
    return ds


EXPERIMENTS = {"galton_distribution": galton_distribution}
