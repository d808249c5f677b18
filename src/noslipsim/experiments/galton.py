"""Galton board experiments (paper, introduction and Figures 2 and 3; Figure S1 beyond it)."""
from __future__ import annotations

import math
import os

import numpy as np
import xarray as xr

from .. import initial, tables
from .._metadata import annotate
from .._validate import count, finite_vector, nonnegative
from ..core import layout
from ..ensemble import simulate_many
from .orbit_sets import orbit_set


def gamma_values(gamma):
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
    gammas = gamma_values(gamma)
    return [(law, g) for law in laws for g in ([math.nan] if law == "specular" else gammas)]


def galton_distribution(n_particles=100_000, *, laws=("specular", "no-slip"), gamma=1 / math.sqrt(2),
                        spacing=2.0, radius=0.5, gravity=1.0, rows=100, max_time=1000.0,
                        start=(1.0, 0.0), max_collisions=10**7, seed=0, top_row=None, spread=0.0, speed=1.0,
                        width=None, wall_law=None, chunk_size=None, scheduler=None, progress=None, num_workers=None,
                        out=None):
    r"""Terminal horizontal positions and arrival times on a Galton board (paper, introduction and Figure 3).

    Two boards.  **Unbounded** (``top_row=None``, the paper's drop as read
    before): the lattice continues upwards, and particles start at ``start``
    (by default in the gap between two pegs of a row); the terminal depth is

    .. math::

        y = y_\mathrm{start} - \mathrm{rows} \cdot \mathrm{spacing} \sqrt{3}/2 .

    **Bounded** (``top_row=0``): row 0 (pegs at height 0) is the top row, with
    nothing above it (``Scene.top``), particles are released above it at
    ``start`` and fall onto it, and the terminal depth is ``rows`` rows below
    the top row, ``y = -rows spacing sqrt(3)/2``.  **Walled** (``top_row=0``
    and a ``width``): the bounded board cut to its pegs between two side walls
    at ``x = +-width`` (:func:`noslipsim.tables.walled_galton_board`), as a
    Galton board is built; the unbounded lattice lets a particle wander
    sideways along the top row without end.

    Release: each particle starts at ``start`` plus an offset uniform in the
    square ``[-spread, spread]^2`` (``spread = 0``: all at ``start``), with
    speed ``speed`` in a uniformly random direction and zero spin, under the
    force ``(0, -gravity)``; an orbit ends when it crosses the terminal depth
    (exact crossing), or at ``max_time`` (not arrived).  The same seed gives
    the same starts for every law and gamma.  Nondimensional units: the
    scene's lengths and ``g`` fix the time scale.

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
        Release point (the centre of the spread), strictly inside the table.
    max_collisions : int
        Collision budget per particle (a particle that spends it stops, not arrived).
    seed : int
        Seed of the initial directions (:func:`noslipsim.initial.unit_velocities`)
        and of the release offsets.
    top_row : int or None
        ``None``: the unbounded lattice; ``0``: the bounded board, row 0 its
        top row (:func:`noslipsim.tables.galton_board`).
    spread : float
        Half-width (>= 0) of the square of release points around ``start``.
    speed : float
        Release speed (>= 0; 0 drops every particle from rest).
    width : float or None
        ``None``: no side walls; a number: the walled board, walls at
        ``x = +-width`` (needs ``top_row``).
    wall_law : {None, 'no-slip', 'specular'}
        The walls' own collision law (``None``: the case's law, as the pegs).
    chunk_size, scheduler, progress, num_workers
        Passed to :func:`noslipsim.simulate_many`.
    out : str or path-like, optional
        A folder for the chunk files of each case (``out/specular``,
        ``out/no-slip-<gamma>``; :func:`noslipsim.simulate_many`): memory stays
        bounded whatever ``n_particles`` (the starts are made chunk by chunk,
        :class:`noslipsim.initial.UnitVelocities`), a killed run resumes, and the
        dataset returned is lazy (dask arrays over the chunk files; writing it
        with :func:`noslipsim.write_dataset` streams it).  The same values as
        without ``out``.

    Returns
    -------
    xarray.Dataset
        Dims ``(law, particle)``, one entry of ``law`` per case (a law name
        repeats when several gammas are run), with the coordinate ``gamma``
        along ``law`` (NaN for specular): ``x_terminal`` (displacement from the
        start, NaN if not arrived), ``t_terminal`` (NaN if not arrived),
        ``arrived``, ``x_end, y_end`` (displacement from the start where the
        orbit ended: at the terminal depth, or at ``max_time`` for particles
        not arrived), ``n_collisions``, ``stop_reason``; per case
        ``share_not_arrived``.  The geometry, limits and seed are attributes.
        Variables are described in docs/datasets.md.  Displacements are
        measured from ``start`` (the centre of the release).
    """
    n_particles = count(n_particles, "n_particles")
    rows = count(rows, "rows")
    cases = galton_cases(laws, gamma)
    spread = nonnegative(spread, "spread")
    speed = nonnegative(speed, "speed")
    start = tuple(float(c) for c in finite_vector(start, "start"))
    depth = rows * spacing * math.sqrt(3.0) / 2.0
    if top_row is None:
        level = start[1] - depth
    else:
        if isinstance(top_row, bool) or not isinstance(top_row, (int, np.integer)):
            raise TypeError(f"top_row: expected an integer row index or None, got {top_row!r}")
        level = int(top_row) * spacing * math.sqrt(3.0) / 2.0 - depth
    if out is None or spread > 0.0 or speed != 1.0:
        vel = initial.unit_velocities(n_particles, seed) * speed
        pos = np.tile(np.asarray(start, float), (n_particles, 1))
        if spread > 0.0:
            pos += np.random.default_rng([seed, 1]).uniform(-spread, spread, (n_particles, 2))
    else:  # made chunk by chunk: nothing of size n_particles in memory
        vel = initial.UnitVelocities(n_particles, seed)
        pos = np.broadcast_to(np.asarray(start, float), (n_particles, 2))
    spins = np.broadcast_to(0.0, (n_particles,))
    if width is not None and top_row is None:
        raise ValueError("width: side walls need a top row (top_row=0): the unbounded lattice has no walled form")
    parts = []
    for law, g in cases:
        scene = _board(spacing, radius, gravity, law=law, gamma=0.0 if law == "specular" else g, top_row=top_row,
                       rows=rows, width=width, wall_law=wall_law)
        folder = None if out is None else os.path.join(os.fspath(out), law if law == "specular" else f"{law}-{g!r}")
        ds = simulate_many(scene, pos, vel, spins, max_collisions=max_collisions,
                           max_time=max_time, stop_below=level, record="final", chunk_size=chunk_size,
                           scheduler=scheduler, progress=progress, num_workers=num_workers, out=folder)
        arrived = ds.stop_reason == layout.STOP_LEVEL       # lazy with out: nothing is loaded here
        dx, dy = ds.x_final - start[0], ds.y_final - start[1]
        parts.append(xr.Dataset({
            "x_terminal": ("particle", xr.where(arrived, dx, np.nan).data),
            "t_terminal": ("particle", xr.where(arrived, ds.t_final, np.nan).data),
            "arrived": ("particle", arrived.astype(np.int8).data),
            "x_end": ("particle", dx.data),
            "y_end": ("particle", dy.data),
            "n_collisions": ("particle", ds.n_collisions.data),
            "stop_reason": ("particle", ds.stop_reason.data, ds.stop_reason.attrs),
        }))
    res = xr.concat(parts, dim=xr.DataArray([law for law, _ in cases], dims="law", name="law"))
    res = res.assign_coords(gamma=("law", [g for _, g in cases]))
    res["share_not_arrived"] = 1.0 - res.arrived.mean("particle")
    res.attrs.update(title="Galton board terminal distribution", spacing=spacing, radius=radius,
                     gravity=gravity, rows=rows, terminal_depth=depth, terminal_level=level, max_time=max_time,
                     start=list(start), seed=seed, n_particles=n_particles, max_collisions=max_collisions,
                     board="unbounded" if top_row is None else "bounded",
                     top_row=-1 if top_row is None else int(top_row), spread=spread, speed=speed,
                     width=math.inf if width is None else float(width),
                     wall_law="none" if width is None else (wall_law or "pegs"))
    return annotate(res)


def _board(spacing, radius, gravity, *, law, gamma, top_row, rows, width, wall_law):
    """The lattice board (``width=None``) or the walled one, ``rows`` rows below ``top_row``."""
    if width is None:
        if wall_law is not None:
            raise ValueError("wall_law: a board without side walls (width=None) has no wall law")
        return tables.galton_board(spacing, radius, gravity, law=law, gamma=gamma, top_row=top_row)
    return tables.walled_galton_board(spacing, radius, gravity, rows=rows, width=width, top_row=top_row, law=law,
                                      gamma=gamma, wall_law=wall_law)


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
        As in :func:`galton_distribution` (``radius`` excluded; with ``out``,
        one subfolder ``radius-<r>`` per radius).

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
    out = kwargs.pop("out", None)
    parts = [galton_distribution(n_particles, laws=laws, gamma=gamma, radius=r, **kwargs,
                                 out=None if out is None else os.path.join(os.fspath(out), f"radius-{r!r}"))
             for r in radii]
    res = xr.concat(parts, dim=xr.DataArray(radii, dims="radius", name="radius"), combine_attrs="drop_conflicts")
    res.attrs["title"] = "Galton board terminal distribution against peg radius"
    return annotate(res)


def galton_orbits(gammas=(0.0, 1 / math.sqrt(2), 3.0), *, velocity=(0.6, 0.8), spin=0.0, spacing=2.0,
                  radius=0.5, gravity=1.0, rows=100, max_time=1000.0, start=(1.0, 0.0), max_collisions=10**5,
                  top_row=None):
    """Galton-board orbits from one start for several gammas (paper, Figure 2).

    ``gamma = 0`` is run with the specular law (the same path as no-slip with
    gamma = 0, which only reverses the spin, docs/conventions.md); each orbit
    ends at the terminal depth or at ``max_time``.  The board and its
    terminal depth are those of :func:`galton_distribution` (``top_row``:
    ``None`` for the unbounded lattice, the depth ``rows`` rows below the
    start; ``0`` for the bounded board, ``rows`` rows below its top row).
    Returns an :func:`orbit_set` dataset with the board's geometry as
    attributes (``terminal_level``: the height where the orbits stop).
    """
    rows = count(rows, "rows")
    gammas = gamma_values(gammas)
    scenes = [tables.galton_board(spacing, radius, gravity, law="specular" if g == 0.0 else "no-slip",
                                  gamma=g, top_row=top_row) for g in gammas]
    n = len(scenes)
    row = spacing * math.sqrt(3.0) / 2.0
    depth = rows * row
    level = start[1] - depth if top_row is None else int(top_row) * row - depth
    ds = orbit_set(scenes, [start] * n, [velocity] * n, [spin] * n, max_collisions=max_collisions,
                   max_time=max_time, stop_below=level)
    ds.attrs.update(title="Galton board orbits", spacing=spacing, radius=radius, gravity=gravity, rows=rows,
                    terminal_depth=depth, terminal_level=level, start=list(start), velocity=list(velocity),
                    spin=spin, board="unbounded" if top_row is None else "bounded",
                    top_row=-1 if top_row is None else int(top_row))
    return ds


#: The release and board settings a case of :func:`galton_evidence` may change.
def _walls_coordinate(width):
    """The ``width`` coordinate of an evidence case: its walls' half-width, 0 for a board without side walls
    (a coordinate is finite; a walled board is never 0 wide, ``tables.walled_galton_board``)."""
    return 0.0 if math.isinf(width) else float(width)


EVIDENCE_KEYS = ("top_row", "start", "spread", "speed", "radius", "rows", "width", "wall_law", "max_time")


def galton_evidence(cases, n_particles=1000, *, laws=("no-slip",), gamma=1 / math.sqrt(2), seed=0,
                    max_time=2000.0, termination_time=None, **board):
    """Arrival times of :func:`galton_distribution` for several boards and releases, one dataset.

    The evidence behind the Galton board's not-arrived share (Figure S2): the
    same run repeated with one setting changed at a time, so that its
    dependence on the drop (the unbounded lattice's gap, or the bounded
    board's release above its top row), the release point, spread and speed,
    the peg radius, the number of rows and the side walls can be read side by
    side.

    Parameters
    ----------
    cases : sequence of dict
        One mapping per case: ``name`` (unique), ``group`` (what the case
        varies, a label), and any of ``top_row, start, spread, speed, radius,
        rows, width, wall_law, max_time`` (:func:`galton_distribution`), which override
        ``board`` (``max_time``: the case's own time limit, e.g. one that
        grows with its rows).
    n_particles : int
        Particles per case and law.
    laws, gamma, seed, max_time
        As in :func:`galton_distribution` (every case uses the same seed).
    termination_time : float, optional
        The experiment's termination time ``T`` (stored as an attribute; the
        run follows the particles to ``max_time``, e.g. 10 T).
    **board
        The board and release every case starts from (``spacing, radius,
        gravity, rows, start, top_row, spread, speed``) and the ensemble
        options of :func:`noslipsim.simulate_many`.

    Returns
    -------
    xarray.Dataset
        Dims ``(case, law, particle)``: ``t_terminal``, ``x_terminal``,
        ``x_end``, ``y_end`` (from each case's ``start``), ``n_collisions``
        and ``share_not_arrived`` (by ``max_time``); per case
        the coordinates ``group``, ``board`` (``'bounded'`` or
        ``'unbounded'``), ``start_x``, ``start_y``, ``spread``, ``speed``,
        ``radius``, ``rows``, ``width`` (0: no side walls), ``wall_law``
        (``'none'``, ``'pegs'``: the pegs' law, or a law name) and
        ``max_time``; the attribute ``max_time`` is the longest case's.
    """
    if not cases:
        raise ValueError("cases: expected at least one case")
    names = [c.get("name") for c in cases]
    if any(not isinstance(n, str) or not n for n in names) or len(set(names)) != len(names):
        raise ValueError(f"cases: every case needs a unique non-empty name, got {names}")
    parts, rows_of = [], []
    for case in cases:
        unknown = set(case) - {"name", "group", *EVIDENCE_KEYS}
        if unknown:
            raise ValueError(f"cases[{case['name']!r}]: unknown keys {sorted(unknown)}; expected name, group "
                             f"and any of {EVIDENCE_KEYS}")
        settings = {"max_time": max_time, **board, **{k: v for k, v in case.items() if k in EVIDENCE_KEYS}}
        ds = galton_distribution(n_particles, laws=laws, gamma=gamma, seed=seed, **settings)
        parts.append(ds[["t_terminal", "x_terminal", "x_end", "y_end", "n_collisions", "share_not_arrived"]])
        a = ds.attrs
        rows_of.append(dict(group=str(case.get("group", "")), board=a["board"], start_x=a["start"][0],
                            start_y=a["start"][1], spread=a["spread"], speed=a["speed"], radius=a["radius"],
                            rows=a["rows"], width=_walls_coordinate(a["width"]), wall_law=a["wall_law"],
                            max_time=a["max_time"]))
    res = xr.concat(parts, dim=xr.DataArray(names, dims="case", name="case"), combine_attrs="drop")
    for key in rows_of[0]:
        res = res.assign_coords({key: ("case", [r[key] for r in rows_of])})
    # the longest case's limit: no arrival time of any case lies past it (arrival_curve checks)
    res.attrs.update(title="Galton board: not-arrived share against board and release",
                     max_time=max(r["max_time"] for r in rows_of),
                     n_particles=n_particles, seed=seed, spacing=board.get("spacing", 2.0),
                     gravity=board.get("gravity", 1.0),
                     termination_time=max_time if termination_time is None else termination_time)
    return annotate(res)
