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
from .simulate import simulate


def _count(value, field, minimum=1):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{field}: expected an integer >= {minimum}, got {value!r}")
    return int(value)


def _gammas(gamma):
    """One gamma or a sequence of them, validated (finite, >= 0, no repeats)."""
    values = [gamma] if np.ndim(gamma) == 0 else list(gamma)
    if not values:
        raise ValueError("gamma: expected at least one value")
    out = []
    for g in values:
        try:
            g = float(g)
        except (TypeError, ValueError):
            raise ValueError(f"gamma: expected numbers, got {g!r}") from None
        if not (math.isfinite(g) and g >= 0.0):
            raise ValueError(f"gamma: must be finite and >= 0, got {g}")
        out.append(g)
    if len(set(out)) != len(out):
        raise ValueError(f"gamma: repeated values in {out}")
    return out


def galton_cases(laws, gamma):
    """``(law, gamma)`` pairs of a run: specular once (gamma NaN, it plays no part), no-slip once per gamma."""
    if isinstance(laws, str) or not laws:
        raise ValueError(f"laws: expected a non-empty sequence of laws, got {laws!r}")
    if len(set(laws)) != len(laws) or not set(laws) <= {"specular", "no-slip"}:
        raise ValueError(f"laws: expected distinct laws among ('specular', 'no-slip'), got {tuple(laws)}")
    gammas = _gammas(gamma)
    return [(law, g) for law in laws for g in ([math.nan] if law == "specular" else gammas)]


def galton_distribution(n_particles=100_000, *, laws=("specular", "no-slip"), gamma=1 / math.sqrt(2),
                        spacing=2.0, radius=0.5, gravity=1.0, rows=100, max_time=1000.0,
                        start=(1.0, 0.0), max_collisions=10**7, seed=0, chunk_size=None,
                        scheduler=None, progress=None, num_workers=None):
    r"""Terminal horizontal positions and arrival times on a Galton board (paper, introduction and Figure 3).

    Particles start at ``start`` (by default in the gap between two pegs of
    the top row) with unit speed in a uniformly random direction and zero
    spin, under the force ``(0, -gravity)``; an orbit ends when it crosses
    the terminal depth

    .. math::

        y = y_\mathrm{start} - \mathrm{rows} \cdot \mathrm{spacing} \sqrt{3}/2

    (exact crossing), or at ``max_time`` (not arrived).  The same seed gives
    the same directions for every law and gamma.  Nondimensional units: the
    scene's lengths, ``g`` and the unit start speed fix the time scale.

    Parameters
    ----------
    n_particles : int
        Particles per case.
    laws : sequence of {'specular', 'no-slip'}
        Collision laws.
    gamma : float or sequence of float
        Mass-distribution constant(s) of the no-slip runs (one case per
        value); the specular law does not use it.
    spacing, radius, gravity : float
        Board geometry (:func:`noslipsim.tables.galton_board`).
    rows : int
        Peg rows between the start and the terminal depth.
    max_time : float
        Termination time.
    start : (float, float)
        Drop point, strictly inside the table.
    max_collisions : int
        Collision budget per particle (a particle that spends it stops, not arrived).
    seed : int
        Seed of the initial directions (:func:`noslipsim.initial.unit_velocities`).
    chunk_size, scheduler, progress, num_workers
        Passed to :func:`noslipsim.simulate_many`.

    Returns
    -------
    xarray.Dataset
        Dims ``(law, particle)``, one entry of ``law`` per case (a law name
        repeats when several gammas are run), with the coordinate ``gamma``
        along ``law`` (NaN for specular): ``x_terminal`` (displacement from the
        start, NaN if not arrived), ``t_terminal`` (NaN if not arrived),
        ``arrived``, ``n_collisions``, ``stop_reason``; per case
        ``share_not_arrived``.  The geometry, limits and seed are attributes.
        Variables are described in docs/datasets.md.
    """
    n_particles = _count(n_particles, "n_particles")
    rows = _count(rows, "rows")
    cases = galton_cases(laws, gamma)
    depth = rows * spacing * math.sqrt(3.0) / 2.0
    level = start[1] - depth
    vel = initial.unit_velocities(n_particles, seed)
    pos = np.tile(np.asarray(start, float), (n_particles, 1))
    out = []
    for law, g in cases:
        scene = tables.galton_board(spacing, radius, gravity, law=law, gamma=0.0 if law == "specular" else g)
        ds = simulate_many(scene, pos, vel, np.zeros(n_particles), max_collisions=max_collisions,
                           max_time=max_time, stop_below=level, record="final", chunk_size=chunk_size,
                           scheduler=scheduler, progress=progress, num_workers=num_workers)
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
    res = xr.concat(out, dim=xr.DataArray([law for law, _ in cases], dims="law", name="law"))
    res = res.assign_coords(gamma=("law", [g for _, g in cases],
                                   {"long_name": "mass-distribution constant gamma (NaN: specular, not used)",
                                    "units": "1"}))
    res["law"].attrs.update(long_name="collision law", units="1")
    res["share_not_arrived"] = 1.0 - res.arrived.mean("particle")
    res["share_not_arrived"].attrs = {"long_name": "share of particles not at the terminal depth by max_time",
                                      "units": "1"}
    res.attrs.update(title="Galton board terminal distribution", spacing=spacing, radius=radius,
                     gravity=gravity, rows=rows, terminal_depth=depth, max_time=max_time,
                     start=list(start), seed=seed, n_particles=n_particles, max_collisions=max_collisions)
    return annotate(res)


def galton_radius_sweep(n_particles=2000, *, radii=(0.85, 0.9, 0.95), laws=("specular", "no-slip"),
                        gamma=1 / math.sqrt(2), **kwargs):
    """:func:`galton_distribution` for several peg radii (the same starts for every radius).

    Parameters
    ----------
    n_particles : int
        Particles per radius and case.
    radii : sequence of float
        Peg radii (increasing), each with ``0 < 2 radius < spacing``.
    laws, gamma, **kwargs
        As in :func:`galton_distribution` (``radius`` excluded).

    Returns
    -------
    xarray.Dataset
        The datasets of :func:`galton_distribution` stacked along a leading
        ``radius`` dimension (coordinate ``radius``, no ``radius`` attribute).
    """
    if "radius" in kwargs:
        raise ValueError("radius: give the peg radii as radii=[...]")
    radii = [float(r) for r in np.atleast_1d(np.asarray(radii, dtype=float))]
    if not radii or np.any(np.diff(radii) <= 0):
        raise ValueError(f"radii: expected increasing peg radii, got {radii}")
    parts = [galton_distribution(n_particles, laws=laws, gamma=gamma, radius=r, **kwargs) for r in radii]
    res = xr.concat(parts, dim=xr.DataArray(radii, dims="radius", name="radius",
                                            attrs={"long_name": "peg radius", "units": "1"}),
                    combine_attrs="drop_conflicts")
    res.attrs["title"] = "Galton board terminal distribution against peg radius"
    return res


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
        data[k] = ("orbit", pos[:, j], {"long_name": f"{k[0]} position at the start", "units": "1"})
    for j, k in enumerate(("vx_start", "vy_start")):
        data[k] = ("orbit", vel[:, j], {"long_name": f"{k[:2]} velocity at the start", "units": "1"})
    data["spin_start"] = ("orbit", w, {"long_name": "scaled spin at the start (CCW positive)", "units": "1"})
    data["stop_reason"] = ("orbit", np.array([o.attrs["stop_reason"] for o in orbits], dtype=object),
                           {"long_name": "why the orbit ended", "units": "1"})
    data["scene"] = ("orbit", np.array([sc.to_json() for sc in scenes], dtype=object),
                     {"long_name": "the orbit's scene as JSON (docs/scenes.md)", "units": "1"})
    ds = xr.Dataset(data, coords={
        "orbit": np.arange(n),
        "collision": np.arange(length),
        "law": ("orbit", [sc.law for sc in scenes], {"long_name": "collision law", "units": "1"}),
        "gamma": ("orbit", [sc.gamma if sc.law == "no-slip" else math.nan for sc in scenes],
                  {"long_name": "mass-distribution constant gamma (NaN: specular, not used)", "units": "1"}),
    })
    ds.attrs.update(title="orbits", max_collisions=max_collisions, max_time=float(max_time),
                    stop_below=math.nan if stop_below is None else float(stop_below))
    return annotate(ds)


def galton_orbits(gammas=(0.0, 1 / math.sqrt(2), 3.0), *, velocity=(0.6, 0.8), spin=0.0, spacing=2.0,
                  radius=0.5, gravity=1.0, rows=100, max_time=1000.0, start=(1.0, 0.0), max_collisions=10**5):
    """Galton-board orbits from one start for several gammas (paper, Figure 2).

    ``gamma = 0`` is run with the specular law (the same path as no-slip with
    gamma = 0, which only reverses the spin, docs/conventions.md); each orbit
    ends at the terminal depth ``rows`` peg rows below the start, or at
    ``max_time``.  Returns an :func:`orbit_set` dataset with the board's
    geometry as attributes.
    """
    rows = _count(rows, "rows")
    gammas = _gammas(gammas)
    scenes = [tables.galton_board(spacing, radius, gravity, law="specular" if g == 0.0 else "no-slip",
                                  gamma=g) for g in gammas]
    n = len(scenes)
    depth = rows * spacing * math.sqrt(3.0) / 2.0
    ds = orbit_set(scenes, [start] * n, [velocity] * n, [spin] * n, max_collisions=max_collisions,
                   max_time=max_time, stop_below=start[1] - depth)
    ds.attrs.update(title="Galton board orbits", spacing=spacing, radius=radius, gravity=gravity, rows=rows,
                    terminal_depth=depth, start=list(start), velocity=list(velocity), spin=spin)
    return ds


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


EXPERIMENTS = {"galton_distribution": galton_distribution, "galton_radius_sweep": galton_radius_sweep,
               "galton_orbits": galton_orbits}
