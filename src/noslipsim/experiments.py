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
        ``arrived``, ``x_end, y_end`` (displacement from the start where the
        orbit ended: at the terminal depth, or at ``max_time`` for particles
        not arrived), ``n_collisions``, ``stop_reason``; per case
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
            "x_end": ("particle", ds.x_final.values - start[0],
                      {"long_name": "horizontal displacement where the orbit ended (terminal depth or max_time)",
                       "units": "1"}),
            "y_end": ("particle", ds.y_final.values - start[1],
                      {"long_name": "vertical displacement where the orbit ended (terminal depth or max_time)",
                       "units": "1"}),
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


# ----------------------------------------------------------------------------- orbits (Figures 1, 4, 5, 6, 8, 16)
# Single orbits that illustrate the paper's theorems and claims; each function returns an orbit_set
# dataset (or the 3D bounce log) with the numbers that back the figure's caption.

def _unit_direction(angle_deg):
    """Unit velocity at ``angle_deg`` degrees counter-clockwise from +x."""
    a = math.radians(float(angle_deg))
    return (math.cos(a), math.sin(a))


def _turned(velocity, angle):
    """``velocity`` turned by ``angle`` radians counter-clockwise (speed kept)."""
    c, s = math.cos(angle), math.sin(angle)
    vx, vy = velocity
    return (c * vx - s * vy, s * vx + c * vy)


def _angle_between(u, v):
    """Angle in degrees between two plane vectors."""
    cos = (u[0] * v[0] + u[1] * v[1]) / (math.hypot(*u) * math.hypot(*v))
    return math.degrees(math.acos(max(-1.0, min(1.0, cos))))


def _label_orbits(ds, roles):
    ds = ds.assign_coords(role=("orbit", list(roles), {"long_name": "what the orbit shows", "units": "1"}))
    return ds


def specular_noslip_orbits(*, width=2.0, height=1.0, disk=(1.2, 0.5, 0.3), start=(0.1, 0.5), angle=12.5,
                           spin=0.6, gamma=1 / math.sqrt(2), max_collisions=10):
    r"""The same start in a rectangle with one disk scatterer, specular and no-slip, no force (paper, Figure 1).

    The particle starts at ``start`` with unit speed at ``angle`` degrees above
    the horizontal and scaled spin ``spin`` (counter-clockwise positive,
    docs/conventions.md).  The specular law keeps the spin; the no-slip law
    exchanges spin and tangential velocity (``c = (1-gamma^2)/(1+gamma^2)``,
    ``s = 2 gamma/(1+gamma^2)``):

    .. math::

        w^+ = -c\,w - s\,v_t, \qquad v_t^+ = -s\,w + c\,v_t, \qquad v_n^+ = -v_n,

    so the two orbits part at their first collision with the scatterer.  The
    caption's claims are recorded per orbit at that collision: the angle of
    the outgoing velocity from the vertical, and from the direction of the
    table's upper left corner.

    Parameters
    ----------
    width, height : float
        Rectangle ``[0, width] x [0, height]`` (:func:`noslipsim.tables.rectangle`).
    disk : (float, float, float)
        Scatterer ``(cx, cy, r)`` (element 4).
    start : (float, float)
        Start, strictly inside the table.
    angle : float
        Direction of the unit start velocity, degrees counter-clockwise from +x.
    spin : float
        Initial scaled spin ``w``.
    gamma : float
        Mass-distribution constant of the no-slip orbit.
    max_collisions : int
        Collisions of each orbit.

    Returns
    -------
    xarray.Dataset
        An :func:`orbit_set` of two orbits (``role`` 'specular', 'no-slip') with,
        per orbit, ``scatterer_collision`` (index of the first collision with
        the disk, -1 if none), ``exit_from_vertical`` and ``exit_to_corner``
        (degrees; NaN if the disk is never hit).
    """
    max_collisions = _count(max_collisions, "max_collisions")
    scenes = [tables.rectangle(width, height, disks=[tuple(disk)], law=law, gamma=gamma)
              for law in ("specular", "no-slip")]
    velocity = _unit_direction(angle)
    ds = orbit_set(scenes, [start] * 2, [velocity] * 2, [spin] * 2, max_collisions=max_collisions)
    scatterer = 4  # rectangle edges are elements 0-3
    first, vertical, corner = [], [], []
    for i in range(2):
        hits = np.flatnonzero(ds.element.values[i] == scatterer)
        if len(hits) == 0:
            first.append(-1), vertical.append(math.nan), corner.append(math.nan)
            continue
        k = int(hits[0])
        v = (float(ds.vx[i, k]), float(ds.vy[i, k]))
        to_corner = (0.0 - float(ds.x[i, k]), height - float(ds.y[i, k]))
        first.append(k)
        vertical.append(min(_angle_between(v, (0.0, 1.0)), _angle_between(v, (0.0, -1.0))))
        corner.append(_angle_between(v, to_corner))
    ds["scatterer_collision"] = ("orbit", np.array(first), {
        "long_name": "index of the first collision with the scatterer (-1: none)", "units": "1"})
    ds["exit_from_vertical"] = ("orbit", np.array(vertical), {
        "long_name": "angle of the velocity leaving the scatterer from the vertical", "units": "degree"})
    ds["exit_to_corner"] = ("orbit", np.array(corner), {
        "long_name": "angle between the velocity leaving the scatterer and the direction of the upper left "
                     "corner", "units": "degree"})
    ds = _label_orbits(ds, ["specular", "no-slip"])
    ds.attrs.update(title="specular and no-slip orbits from one start (rectangle with a scatterer)",
                    width=width, height=height, disk=list(disk), start=list(start), angle=angle, spin=spin,
                    gamma=gamma)
    return ds


def pentagon_orbits(*, regular_start=(0.1, 0.05), regular_angle=20.0, irregular_vertices=(
        (-0.9, -0.7), (0.8, -0.8), (1.0, 0.3), (0.1, 1.0), (-1.0, 0.4)), irregular_start=(0.1, 0.05),
        irregular_angle=20.0, n_generic=300, guess_position=(0.288, 0.059), guess_velocity=(-0.6, -0.8),
        guess_spin=-0.1, period=14, gamma=1 / math.sqrt(2), perturbation=0.03, n_corridor=2000, tol=1e-12):
    r"""Generic specular pentagon orbits and a no-slip orbit in a corridor near a periodic point (paper, Figure 4).

    No force.  Two generic specular orbits (unit speed, no spin): one in the
    regular pentagon of circumradius 1 (:func:`noslipsim.tables.regular_polygon`),
    one in the non-regular pentagon ``irregular_vertices``.  In the no-slip
    regular pentagon a ``period``-periodic orbit is found by Newton's method
    on the return map (:func:`noslipsim.analysis.find_periodic_orbit`) from
    the guess, its monodromy ``M`` classified (elliptic: eigenvalues
    ``{1, e^{+-i alpha}}``), and an orbit started from the periodic start with
    the velocity turned by ``perturbation`` radians (speed and spin kept, so
    the energy is the periodic orbit's) is followed for ``n_corridor``
    collisions.  Near an elliptic orbit it stays in a corridor around it; the
    corridor's width is measured as

    .. math::

        \max_k \min_j |q_k - p_j|,

    ``q_k`` the perturbed orbit's collision points, ``p_j`` the periodic
    orbit's (docs/analysis.md for the finder and the classes).

    Parameters
    ----------
    regular_start, irregular_start : (float, float)
        Starts of the generic specular orbits (inside their pentagons).
    regular_angle, irregular_angle : float
        Their directions, degrees counter-clockwise from +x.
    irregular_vertices : sequence of 5 (x, y)
        The non-regular pentagon (convex; either orientation).
    n_generic : int
        Collisions of each generic orbit.
    guess_position, guess_velocity, guess_spin
        Initial guess for the periodic orbit (inside the regular pentagon).
    period : int
        Period sought.
    gamma : float
        Mass-distribution constant of the no-slip pentagon.
    perturbation : float
        Turn of the periodic start's velocity (radians) for the corridor orbit.
    n_corridor : int
        Collisions of the corridor orbit.
    tol : float
        Residual tolerance of the finder.

    Returns
    -------
    xarray.Dataset
        An :func:`orbit_set` of four orbits, ``role`` 'specular regular',
        'specular irregular', 'no-slip corridor', 'no-slip periodic' (one
        period), with the finder's ``periodic_residual``, ``periodic_iterations``,
        ``periodic_kind``, the monodromy's ``eigenvalue_real``/``eigenvalue_imag``
        (dim ``eigenvalue``), ``rotation_angle`` (the argument ``alpha`` of the
        complex pair) and ``corridor_width``; the periodic start in the
        attributes ``periodic_position``, ``periodic_velocity``, ``periodic_spin``.

    Raises
    ------
    ValueError
        If the finder does not converge from the guess (the message says why).
    """
    import json

    from .analysis import find_periodic_orbit

    n_generic = _count(n_generic, "n_generic")
    n_corridor = _count(n_corridor, "n_corridor")
    vertices = np.asarray(irregular_vertices, dtype=float)
    if vertices.shape != (5, 2):
        raise ValueError(f"irregular_vertices: expected 5 points (x, y), got shape {vertices.shape}")
    regular = tables.regular_polygon(5, law="specular")
    irregular = tables.polygon(vertices, law="specular")
    noslip = tables.regular_polygon(5, law="no-slip", gamma=gamma)
    found = find_periodic_orbit(noslip, guess_position, guess_velocity, guess_spin, period=period, tol=tol)
    if not found.converged:
        raise ValueError(f"guess_position, guess_velocity, guess_spin: no {period}-periodic orbit found from the "
                         f"guess (residual {found.residual:.3g} after {found.iterations} steps: {found.message})")
    perturbed = _turned(found.velocity, float(perturbation))
    generic = orbit_set([regular, irregular], [regular_start, irregular_start],
                        [_unit_direction(regular_angle), _unit_direction(irregular_angle)],
                        max_collisions=n_generic)
    corridor = orbit_set([noslip, noslip], [found.position, found.position], [perturbed, found.velocity],
                         [found.spin, found.spin], max_collisions=n_corridor)
    # the periodic orbit is kept for one period only (NaN after), to draw its path
    one = corridor.isel(orbit=[1]).copy()
    keep = one.collision.values < period
    for k, var in one.data_vars.items():
        if var.dims == ("orbit", "collision"):
            one[k] = var.where(keep)
    one["n_collisions"][:] = period
    last = period - 1
    for k in ("x", "y", "vx", "vy", "spin"):
        one[f"{k}_final"][:] = float(corridor[k][1, last])
    one["t_final"][:] = float(corridor.t[1, last])
    ds = xr.concat([generic, corridor.isel(orbit=[0]), one], dim="orbit", join="outer", combine_attrs="override")
    ds = ds.assign_coords(orbit=np.arange(4))
    ds = _label_orbits(ds, ["specular regular", "specular irregular", "no-slip corridor", "no-slip periodic"])

    q = np.c_[ds.x.values[2], ds.y.values[2]]
    q = q[np.isfinite(q[:, 0])]
    p = np.c_[ds.x.values[3, :period], ds.y.values[3, :period]]
    width = float(np.max(np.min(np.hypot(*(q[:, None, :] - p[None, :, :]).transpose(2, 0, 1)), axis=1)))
    m = found.monodromy
    pair = m.eigenvalues[np.argmax(np.abs(m.eigenvalues.imag))]
    ds["periodic_residual"] = ((), found.residual, {
        "long_name": "scaled residual of the periodic orbit (find_periodic_orbit)", "units": "1"})
    ds["periodic_iterations"] = ((), found.iterations, {"long_name": "Newton steps of the finder", "units": "1"})
    ds["periodic_kind"] = ((), m.kind, {"long_name": "linear class of the periodic orbit's monodromy", "units": "1"})
    ds["eigenvalue_real"] = ("eigenvalue", m.eigenvalues.real, {
        "long_name": "real part of the monodromy's eigenvalues", "units": "1"})
    ds["eigenvalue_imag"] = ("eigenvalue", m.eigenvalues.imag, {
        "long_name": "imaginary part of the monodromy's eigenvalues", "units": "1"})
    ds["rotation_angle"] = ((), abs(float(np.angle(pair))), {
        "long_name": "argument of the monodromy's complex eigenvalue pair", "units": "rad"})
    ds["corridor_width"] = ((), width, {
        "long_name": "largest distance of a corridor-orbit collision from the periodic orbit's collision points",
        "units": "1"})
    ds.attrs.update(title="pentagon orbits: generic specular, no-slip corridor near a periodic point",
                    irregular_vertices=json.dumps(vertices.tolist()), regular_start=list(regular_start),
                    regular_angle=regular_angle, irregular_start=list(irregular_start),
                    irregular_angle=irregular_angle, guess_position=list(guess_position),
                    guess_velocity=list(guess_velocity), guess_spin=guess_spin, period=period, gamma=gamma,
                    perturbation=perturbation, tol=tol, periodic_position=list(found.position),
                    periodic_velocity=list(found.velocity), periodic_spin=found.spin)
    return ds


def bounce_orbits(cases=({"vx": 0.5, "u": 1.0, "spin_ratio": 1.0}, {"vx": 0.5, "u": 1.0, "spin_ratio": 0.7},
                         {"vx": 0.5, "u": 1.0, "spin_ratio": 0.0}), *, gamma=1 / math.sqrt(2), gravity=1.0,
                  n_bounces=8):
    r"""The no-slip ball bouncing on a floor under gravity, one orbit per case (paper, Theorem 1 and Figure 5).

    Table ``y > 0`` (:func:`noslipsim.tables.half_plane`), force ``(0, -g)``.
    Each case starts at the apex ``(0, u^2/(2 g))`` of a flight with velocity
    ``(v_x, 0)`` and spin ``w = r v_x / gamma``, ``r`` the case's
    ``spin_ratio`` (``gamma w / v_x``, the inverse of the paper's
    tangential-rotational ratio over ``gamma``).  The velocities are
    2-periodic; the bounce points move by

    .. math::

        D = \frac{4 u (v_x - \gamma w)}{g (1 + \gamma^2)} = \frac{4 u v_x (1 - r)}{g (1 + \gamma^2)}

    every two bounces (:func:`noslipsim.theory.half_plane_drift`): ``r = 1``
    is the 2-periodic orbit of :func:`noslipsim.analysis.bounce_orbit`.  The
    horizontal velocity of the next flight is
    ``v_x (1 - gamma^2 - 2 r)/(1 + gamma^2)``, so for ``r > (1 - gamma^2)/2``
    the ball goes back and forth (with a net drift unless ``r = 1``), below it
    drifts steadily one way.

    Parameters
    ----------
    cases : sequence of mappings
        Each with ``vx`` (horizontal velocity of the first flight), ``u``
        (vertical take-off speed ``> 0``) and ``spin_ratio`` ``r``.
    gamma : float
        Mass-distribution constant ``> 0``.
    gravity : float
        ``g > 0``.
    n_bounces : int
        Bounces per orbit (``>= 3`` to measure a drift).

    Returns
    -------
    xarray.Dataset
        An :func:`orbit_set` with, per orbit, ``spin_ratio``, ``drift`` (the
        mean of ``x_{k+2} - x_k`` over the bounces), ``drift_spread`` (the
        largest deviation of one ``x_{k+2} - x_k`` from it) and
        ``back_and_forth`` (1 if consecutive flights move in opposite
        directions).
    """
    n_bounces = _count(n_bounces, "n_bounces", minimum=3)
    gamma = float(gamma)
    if not (math.isfinite(gamma) and gamma > 0.0):
        raise ValueError(f"gamma: must be finite and > 0 (the spin is r v_x / gamma), got {gamma}")
    g = float(gravity)
    if not (math.isfinite(g) and g > 0.0):
        raise ValueError(f"gravity: must be finite and > 0, got {gravity}")
    cases = list(cases)
    if not cases:
        raise ValueError("cases: expected at least one case")
    pos, vel, spins, ratios = [], [], [], []
    for i, case in enumerate(cases):
        missing = {"vx", "u", "spin_ratio"} - set(case)
        if missing:
            raise ValueError(f"cases[{i}]: missing keys {sorted(missing)} (expected vx, u, spin_ratio)")
        vx, u, r = (float(case[k]) for k in ("vx", "u", "spin_ratio"))
        if not all(map(math.isfinite, (vx, u, r))) or not u > 0.0:
            raise ValueError(f"cases[{i}]: vx, u, spin_ratio must be finite and u > 0, got {dict(case)}")
        pos.append((0.0, 0.5 * u * u / g))
        vel.append((vx, 0.0))
        spins.append(r * vx / gamma)
        ratios.append(r)
    scene = tables.half_plane(gamma=gamma, gravity=g)
    ds = orbit_set([scene] * len(cases), pos, vel, spins, max_collisions=n_bounces)
    x = ds.x.values
    steps = x[:, 2:] - x[:, :-2]
    drift = np.nanmean(steps, axis=1)
    ds["spin_ratio"] = ("orbit", np.array(ratios), {"long_name": "gamma w / v_x at the start", "units": "1"})
    ds["drift"] = ("orbit", drift, {"long_name": "mean displacement of the bounce point per two bounces",
                                    "units": "1"})
    ds["drift_spread"] = ("orbit", np.nanmax(np.abs(steps - drift[:, None]), axis=1), {
        "long_name": "largest deviation of one two-bounce displacement from the mean", "units": "1"})
    flights = np.c_[ds.vx_start.values, ds.vx.values[:, :1]]
    ds["back_and_forth"] = ("orbit", (flights[:, 0] * flights[:, 1] < 0).astype(np.int8), {
        "long_name": "1 if consecutive flights move in opposite horizontal directions", "units": "1"})
    ds.attrs.update(title="no-slip bouncing ball on a floor", gamma=gamma, gravity=g, n_bounces=n_bounces)
    return ds


def newwedge_orbits(*, phi=0.5, theta=0.9, ell=1.5, disk_radius=0.6, disk_phi=0.7, disk_theta=0.6,
                    gamma=1 / math.sqrt(2), gravity=1.0, n_collisions=4):
    r"""The path-reversing 2-periodic orbit of a wedge and of a tangential wedge (paper, Theorem 2, Figure 6).

    Left: the wedge of half-angle ``phi`` (vertex at the origin, opening up,
    force ``(0, -g)``), the orbit leaving ``q0`` at distance ``ell`` on the
    left wall at launch angle ``theta`` (:func:`noslipsim.analysis.wedge_orbit`).
    Right: the same theorem on a more general table, two disks of radius
    ``disk_radius`` centred at ``(-+1, 0)``: the points ``q0``, ``q1`` at angle
    ``disk_phi`` on the disks have tangent lines forming an upward wedge of
    half-angle ``disk_phi`` (the tangential wedge), vertex

    .. math::

        \Big(0,\ R \sin\varphi - \frac{(1 - R\cos\varphi)\cos\varphi}{\sin\varphi}\Big),

    and the orbit is :func:`noslipsim.analysis.two_disk_orbit` with launch
    angle ``disk_theta``.  Speeds and spins are the corrected Theorem 2
    (docs/errata.md).

    Parameters
    ----------
    phi, theta, ell : float
        The wedge's half-angle, launch angle (radians) and distance of ``q0``
        from the vertex.
    disk_radius, disk_phi, disk_theta : float
        The two-disk table's radius and the tangential wedge's half-angle and
        launch angle (radians).
    gamma, gravity : float
        Mass-distribution constant and ``g`` of both orbits.
    n_collisions : int
        Collisions of each orbit (4: the start flies to ``q1``, back to ``q0``,
        to ``q1`` and back).

    Returns
    -------
    xarray.Dataset
        An :func:`orbit_set` of two orbits (``role`` 'wedge', 'tangential
        wedge') with, per orbit, ``q0_x, q0_y, q1_x, q1_y`` (the launch and far
        points), ``vertex_x, vertex_y`` (the (tangential) wedge's vertex),
        ``phi`` and ``theta``.
    """
    from .analysis import two_disk_orbit, wedge_orbit

    n_collisions = _count(n_collisions, "n_collisions", minimum=2)
    wedge, wedge_state = wedge_orbit(phi, theta, ell, gamma, gravity=gravity)
    disks, disk_state = two_disk_orbit(disk_radius, disk_phi, gamma, theta=disk_theta, gravity=gravity)
    ds = orbit_set([wedge, disks], [s["position"] for s in (wedge_state, disk_state)],
                   [s["velocity"] for s in (wedge_state, disk_state)],
                   [s["spin"] for s in (wedge_state, disk_state)], max_collisions=n_collisions)
    R, c, s = float(disk_radius), math.cos(disk_phi), math.sin(disk_phi)
    q0 = np.array([[-ell * math.sin(phi), ell * math.cos(phi)], [-1.0 + R * c, R * s]])
    vertex = np.array([[0.0, 0.0], [0.0, R * s - (1.0 - R * c) * c / s]])
    geometry = {
        "q0_x": (q0[:, 0], "x of the launch point q0"), "q0_y": (q0[:, 1], "y of the launch point q0"),
        "q1_x": (-q0[:, 0], "x of the far point q1"), "q1_y": (q0[:, 1], "y of the far point q1"),
        "vertex_x": (vertex[:, 0], "x of the (tangential) wedge's vertex"),
        "vertex_y": (vertex[:, 1], "y of the (tangential) wedge's vertex"),
    }
    for name, (values, long_name) in geometry.items():
        ds[name] = ("orbit", values, {"long_name": long_name, "units": "1"})
    ds["phi"] = ("orbit", np.array([phi, disk_phi], float), {
        "long_name": "half-angle of the (tangential) wedge, wall to bisector", "units": "rad"})
    ds["theta"] = ("orbit", np.array([theta, disk_theta], float), {
        "long_name": "launch angle at q0 above the chord q0 q1", "units": "rad"})
    ds = _label_orbits(ds, ["wedge", "tangential wedge"])
    ds.attrs.update(title="path-reversing 2-periodic orbits of a wedge and of a tangential wedge", gamma=gamma,
                    gravity=gravity, ell=ell, disk_radius=disk_radius)
    return ds


def two_disk_box_orbits(*, radius=0.7, phi=0.6, gamma=1 / math.sqrt(2), box=(5.0, 3.0), perturbation=0.1,
                        n_specular=40, n_noslip=5000):
    r"""Two disks in a box, no force: one start, specular and no-slip (paper, Figure 8).

    The start is the force-free path-reversing 2-periodic orbit between the
    disks (:func:`noslipsim.analysis.two_disk_orbit`: disks of ``radius``
    centred at ``(-+1, 0)``, collision points at angle ``phi``) with its
    velocity turned by ``perturbation`` radians, in the table
    :func:`noslipsim.tables.two_disks` closed by a centred ``box``.  Its 2-bounce
    monodromy has eigenvalues ``{1, lambda, 1/lambda}`` with (Cox, Feres & Zhang
    2018; :func:`noslipsim.theory.two_disk_eigen_sum`)

    .. math::

        \lambda + 1/\lambda = 4 C^2 \cos^2\varphi\,(\kappa d - u_0)^2 - 2, \qquad \kappa = 1/R,
        \quad d = 2 - 2 R \cos\varphi,

    elliptic when it lies in ``(-2, 2)``: then the no-slip orbit stays near it,
    between the disks, while the specular orbit from the same start scatters
    over the box (docs/analysis.md).

    Parameters
    ----------
    radius, phi : float
        Disk radius in ``(0, 1)`` and the angle of the collision points.
    gamma : float
        Mass-distribution constant of the no-slip orbit (and of the periodic start).
    box : (float, float)
        Width and height of the box, centred at the origin (it must hold both disks).
    perturbation : float
        Turn of the periodic start's velocity (radians).
    n_specular, n_noslip : int
        Collisions of each orbit.

    Returns
    -------
    xarray.Dataset
        An :func:`orbit_set` of two orbits (``role`` 'specular', 'no-slip')
        with, per orbit, ``box_collisions`` (collisions with the box walls,
        elements 0-3); the periodic orbit's ``kind``, ``eigen_sum`` (measured,
        :func:`noslipsim.analysis.monodromy`) and ``eigen_sum_theory``.
    """
    from .analysis import monodromy, two_disk_orbit
    from .theory import two_disk_eigen_sum

    n_specular = _count(n_specular, "n_specular")
    n_noslip = _count(n_noslip, "n_noslip")
    width, height = (float(b) for b in box)
    if not (width > 2.0 + 2.0 * radius and height > 2.0 * radius):
        raise ValueError(f"box: a ({width}, {height}) box does not hold two disks of radius {radius} centred at "
                         "(-1, 0) and (1, 0)")
    open_scene, state = two_disk_orbit(radius, phi, gamma)
    m = monodromy(open_scene, **state, period=2)
    d = 2.0 - 2.0 * radius * math.cos(phi)
    velocity = _turned(state["velocity"], float(perturbation))
    parts = [orbit_set([tables.two_disks(radius, box=(width, height), law=law, gamma=gamma)],
                       [state["position"]], [velocity], [state["spin"]], max_collisions=n)
             for law, n in (("specular", n_specular), ("no-slip", n_noslip))]
    ds = xr.concat(parts, dim="orbit", join="outer", combine_attrs="override")
    ds = ds.assign_coords(orbit=np.arange(2))
    ds = _label_orbits(ds, ["specular", "no-slip"])
    walls = np.where(np.isfinite(ds.element.values), ds.element.values < 4, False)
    ds["box_collisions"] = ("orbit", walls.sum(axis=1), {
        "long_name": "collisions with the box walls", "units": "1"})
    ds["kind"] = ((), m.kind, {"long_name": "linear class of the periodic orbit's 2-bounce monodromy",
                               "units": "1"})
    ds["eigen_sum"] = ((), m.eigen_sum, {
        "long_name": "lambda + 1/lambda of the periodic orbit's monodromy (measured)", "units": "1"})
    ds["eigen_sum_theory"] = ((), float(two_disk_eigen_sum(1.0 / radius, d, phi, gamma)), {
        "long_name": "lambda + 1/lambda from the closed form (Cox, Feres & Zhang 2018)", "units": "1"})
    ds.attrs.update(title="two disks in a box: specular and no-slip orbits from one start", radius=radius,
                    phi=phi, gamma=gamma, box=[width, height], perturbation=perturbation,
                    n_specular=n_specular, n_noslip=n_noslip, periodic_position=list(state["position"]),
                    periodic_velocity=list(state["velocity"]), periodic_spin=state["spin"])
    return ds


def sphere_bounce(*, position=(0.0, 0.0, 0.5), velocity=(0.28, 0.51, 0.0), spin=(0.7, -0.25, 0.2),
                  gamma=math.sqrt(2.0 / 5.0), gravity=1.0, n_bounces=12):
    r"""A no-slip sphere bouncing on a plane in 3D: drift along ``e1``, 2-periodic along ``e2`` (paper, Figure 16).

    The bounce log of :func:`noslipsim.sphere3d.simulate_sphere` (plane
    ``z = 0``, normal ``n = e_z``, force ``(0, 0, -g)``) with the frame of the
    paper's 3D bouncing theorem: ``k = v_T - gamma n x W_T`` is the same on
    every flight, and the bounce point moves by

    .. math::

        D = \frac{4 u\,(v_T - \gamma\, n \times W_T)}{g (1 + \gamma^2)}

    every two bounces (``u`` the vertical impact speed; docs/conventions.md),
    so along ``e1 = D/|D|`` the ball drifts while along ``e2 = n x e1`` its
    motion is 2-periodic.

    Parameters
    ----------
    position, velocity, spin : (float, float, float)
        Start of the centre (``z > 0``), velocity and scaled spin ``W = gamma R omega``.
    gamma : float
        Mass-distribution constant (``sqrt(2/5)``: a uniform ball).
    gravity : float
        ``g > 0``.
    n_bounces : int
        Bounces (``>= 3``).

    Returns
    -------
    xarray.Dataset
        The bounce log (dims ``collision``, ``component``) with ``e1``, ``e2``,
        ``drift_theory`` (``D``) and ``drift`` (the mean of
        ``q_{k+2} - q_k``, measured) along ``component``, ``drift_spread`` (the
        largest deviation of one ``q_{k+2} - q_k`` from ``D``) and the bounce
        points' coordinates ``along_e1``, ``along_e2``.

    Raises
    ------
    ValueError
        For a start without drift (``v_T = gamma n x W_T``: no direction
        ``e1``), and as :func:`noslipsim.sphere3d.simulate_sphere`.
    """
    from .sphere3d import simulate_sphere

    n_bounces = _count(n_bounces, "n_bounces", minimum=3)
    ds = simulate_sphere(position, velocity, spin, gamma=gamma, gravity=gravity, n_bounces=n_bounces)
    q0, v0, w0 = (np.asarray(a, dtype=float) for a in (position, velocity, spin))
    g = float(gravity)
    n = np.array([0.0, 0.0, 1.0])
    k = v0 - gamma * np.cross(n, w0)
    k[2] = 0.0                                   # tangential part only
    u = math.sqrt(v0[2] ** 2 + 2.0 * g * q0[2])  # vertical impact speed
    D = 4.0 * u * k / (g * (1.0 + gamma * gamma))
    size = float(np.hypot(D[0], D[1]))
    if not size > 0.0:
        raise ValueError("velocity, spin: the start is 2-periodic (v_T = gamma n x W_T), it has no drift "
                         "direction e1")
    e1 = D / size
    e2 = np.cross(n, e1)
    q = ds.position.values
    steps = q[2:] - q[:-2]
    vec = ("component",)
    ds["e1"] = (vec, e1, {"long_name": "unit drift direction e1 = D/|D|", "units": "1"})
    ds["e2"] = (vec, e2, {"long_name": "tangential direction e2 = n x e1 (2-periodic motion)", "units": "1"})
    ds["drift_theory"] = (vec, D, {"long_name": "drift per two bounces, 4 u (v_T - gamma n x W_T)/(g (1+gamma^2))",
                                   "units": "1"})
    ds["drift"] = (vec, steps.mean(axis=0), {"long_name": "mean displacement of the bounce point per two bounces",
                                             "units": "1"})
    ds["drift_spread"] = ((), float(np.abs(steps - D).max()), {
        "long_name": "largest deviation of one two-bounce displacement from the formula", "units": "1"})
    ds["along_e1"] = ("collision", q @ e1, {"long_name": "bounce point along e1", "units": "1"})
    ds["along_e2"] = ("collision", q @ e2, {"long_name": "bounce point along e2", "units": "1"})
    ds.attrs.update(title="no-slip sphere bouncing on a plane", impact_speed=u, n_bounces=n_bounces)
    return ds


EXPERIMENTS.update(specular_noslip_orbits=specular_noslip_orbits, pentagon_orbits=pentagon_orbits,
                   bounce_orbits=bounce_orbits, newwedge_orbits=newwedge_orbits,
                   two_disk_box_orbits=two_disk_box_orbits, sphere_bounce=sphere_bounce)


# ----------------------------------------------------------------------------- stability (Figures 7, 9, 14, 15)
# Periodic orbits of no-slip wedges under gravity, perturbed copies of them, the linear class
# along the launch angle, and the survival pattern of a stability grid (docs/analysis.md).

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
    from .analysis import find_periodic_orbit
    from .analysis.section import state_from_reduced

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
        ``(orbit, eigenvalue)``.

    Raises
    ------
    ValueError
        Bad parameters, or a search that does not converge (the message says
        which and why): a figure must not show a non-periodic orbit as periodic.
    """
    from .analysis import find_periodic_orbit, monodromy, wedge_orbit

    reversing = _case_list(reversing, "reversing", ("opening", "theta", "ell"))
    searches = _case_list(searches, "searches", ("name", "opening", "position", "velocity", "spin", "period"))
    if not reversing and not searches:
        raise ValueError("reversing, searches: expected at least one orbit")
    periods = _count(periods, "periods")
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
        "case": ("what the orbit shows", "1", np.array([r["case"] for r in rows], dtype=object)),
        "opening": ("which way the wedge opens (force (0, -g) in both)", "1",
                    np.array([r["opening"] for r in rows], dtype=object)),
        "period": ("collisions per period", "1", np.array([r["period"] for r in rows])),
        "minimal_period": ("smallest number of collisions after which the run's state repeats", "1",
                           np.array([_minimal_period(ds.isel(orbit=i), r["period"]) for i, r in enumerate(rows)])),
        "theta": ("launch angle above the horizontal (path-reversing orbits)", "rad",
                  np.array([r["theta"] for r in rows])),
        "ell": ("distance of the launch point q0 from the vertex (path-reversing orbits)", "1",
                np.array([r["ell"] for r in rows])),
        "residual": ("periodicity residual max(|ds|/L, |dw|/V, |dv_t|/V) after one period", "1",
                     np.array([r["residual"] for r in rows])),
        "linear_kind": ("linear class of the monodromy of one period", "1",
                        np.array([r["mono"].kind for r in rows], dtype=object)),
        "eigen_sum": ("trace of the monodromy minus its eigenvalue closest to 1 (lambda + 1/lambda)", "1",
                      np.array([r["mono"].eigen_sum for r in rows])),
        "unit_count": ("eigenvalues equal to 1 (a family direction at fixed energy)", "1",
                       np.array([r["mono"].unit_count() for r in rows])),
        "identity_distance": ("max |M - I| (0 for a persistently periodic neighbourhood)", "1",
                              np.array([np.abs(r["mono"].matrix - np.eye(3)).max() for r in rows])),
        "reversal_mismatch": ("max over one period of |v_t - gamma w| / speed just before an impact "
                              "(0: every impact reverses the path)", "1", mismatch),
        "path_reversing": ("1 if every impact of a period reverses the path", "1",
                           (mismatch <= REVERSAL_TOL).astype(np.int8)),
        "family_distance": ("distance (scaled like the residual) of the periodic orbit found from family_step "
                            "along the eigenvalue-1 direction (NaN: no eigenvalue 1)", "1",
                            np.array([r["family"][0] for r in rows])),
        "family_rotation": ("largest eigenvalue argument of that neighbouring orbit's monodromy", "rad",
                            np.array([r["family"][1] for r in rows])),
    }
    for k, (long_name, units, values) in extra.items():
        ds[k] = ("orbit", values, {"long_name": long_name, "units": units})
    ds["eigenvalue_real"] = (("orbit", "eigenvalue"), ev.real, {"long_name": "monodromy eigenvalues, real part "
                                                                 "(by decreasing modulus)", "units": "1"})
    ds["eigenvalue_imag"] = (("orbit", "eigenvalue"), ev.imag, {"long_name": "monodromy eigenvalues, imaginary "
                                                                 "part", "units": "1"})
    ds.attrs.update(title="periodic orbits of no-slip wedges under gravity", phi=float(phi), gamma=float(gamma),
                    gravity=float(gravity), periods=periods, family_step=family_step, n_orbits=n,
                    reversal_tolerance=REVERSAL_TOL)
    return ds


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
    import json

    from .analysis import monodromy, wedge_orbit

    cases = _case_list(cases, "cases", ("opening", "theta", "ell"))
    if not cases:
        raise ValueError("cases: expected at least one case")
    perturbation = _stab_perturbation(perturbation)
    n_collisions = _count(n_collisions, "n_collisions")
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
    ds = ds.assign_coords(case=("orbit", twice(np.arange(n)), {"long_name": "case index", "units": "1"}),
                          role=("orbit", np.array(["periodic"] * n + ["perturbed"] * n, dtype=object),
                                {"long_name": "periodic orbit or its perturbed copy", "units": "1"}))
    extra = {
        "theta": ("launch angle above the horizontal", "rad", [float(c["theta"]) for c in cases]),
        "ell": ("distance of q0 from the vertex", "1", [float(c["ell"]) for c in cases]),
        "opening": ("which way the wedge opens (force (0, -g) in both)", "1",
                    np.array([c["opening"] for c in cases], dtype=object)),
        "linear_kind": ("linear class of the periodic orbit's 2-bounce monodromy", "1",
                        np.array([m.kind for m in monos], dtype=object)),
        "eigen_sum": ("lambda + 1/lambda of the periodic orbit's 2-bounce monodromy", "1",
                      [m.eigen_sum for m in monos]),
        "lambda_max": ("largest |eigenvalue| of the periodic orbit's 2-bounce monodromy", "1",
                       [float(np.abs(m.eigenvalues).max()) for m in monos]),
    }
    for k, (long_name, units, values) in extra.items():
        ds[k] = ("orbit", twice(np.asarray(values)), {"long_name": long_name, "units": units})
    ds["deviation"] = (("orbit", "collision"), deviation,
                       {"long_name": "distance from the periodic orbit's impact on the same wall, "
                                     "max(|ds|/ell, |dw|/V, |dv_t|/V)", "units": "1"})
    ds.attrs.update(title="perturbed 2-periodic orbits of no-slip wedges under gravity", phi=float(phi),
                    gamma=float(gamma), gravity=float(gravity), n_collisions=n_collisions,
                    perturbation=json.dumps(perturbation, sort_keys=True),
                    perturbation_description=("start (half-way along q0 -> q1) with its velocity turned "
                                              "counter-clockwise by 'angle' rad, speed kept, and its spin "
                                              "multiplied by 1 + 'spin'"))
    return ds


def _wedge_monodromy(phi, theta, gamma, gravity, opening, ell):
    from .analysis import monodromy, wedge_orbit

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
            transition[i] = _bisect(lambda th: _wedge_monodromy(phi, th, gamma, gravity, opening, ell).eigen_sum - 2.0,
                                    a, b, xtol)
    ds = xr.Dataset(
        {"eigen_sum": (("phi", "theta"), es, {"long_name": "lambda + 1/lambda of the 2-bounce monodromy",
                                              "units": "1"}),
         "lambda_max": (("phi", "theta"), lam, {"long_name": "largest |eigenvalue| of the 2-bounce monodromy",
                                                "units": "1"}),
         "linear_kind": (("phi", "theta"), kinds.astype(str), {"long_name": "linear class ('' where the orbit "
                                                                "does not exist)", "units": "1"}),
         "theta_transition": ("phi", transition, {"long_name": "launch angle where the class first changes from "
                                                  "elliptic to hyperbolic (lambda + 1/lambda = 2)", "units": "rad"}),
         "theta_parallel": ("phi", math.pi / 2 - phis, {"long_name": "pi/2 - phi: launch parallel to the far wall",
                                                        "units": "rad"})},
        coords={"phi": ("phi", phis, {"long_name": "wedge half-angle (wall to bisector)", "units": "rad"}),
                "theta": ("theta", thetas, {"long_name": "launch angle above the horizontal", "units": "rad"})})
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
    min_run = _count(min_run, "min_run")
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


EXPERIMENTS.update(wedge_periodic_orbits=wedge_periodic_orbits, perturbed_wedge_orbits=perturbed_wedge_orbits,
                   wedge_launch_scan=wedge_launch_scan)


# ----------------------------------------------------------------------------- portraits (Figures 10-13)
# Phase portraits of many orbits per table, started uniformly in the billiard map's invariant
# measure, each orbit with its finite-time Lyapunov exponent (noslipsim.analysis.islands), so a
# figure can tell the chaotic sea from the islands and a number can say how much is regular.

def _portrait_case(scene, n_orbits, n_collisions, seed, elements, lyapunov_collisions, chunk_size, scheduler,
                   progress, num_workers):
    """One table's portrait (dims orbit, point) with its starts and, optionally, exponents per orbit."""
    from .analysis import islands
    from .analysis.portraits import birkhoff_coordinates, boundary_coordinate

    boundary = islands.uniform_reduced_states(scene, n_orbits, seed, elements=elements)
    start = islands.interior_starts(scene, boundary)
    rec = simulate_many(scene, start["positions"], start["velocities"], start["spins"], max_collisions=n_collisions,
                        record="portrait", elements=elements, chunk_size=chunk_size, scheduler=scheduler,
                        progress=progress, num_workers=num_workers)
    coords = (birkhoff_coordinates if scene.law == "specular" else boundary_coordinate)(rec, scene, elements=elements)
    o, p = ("orbit",), ("orbit", "point")
    data = {
        "element": (p, rec.element.values.astype(np.float32), rec.element.attrs),
        "s_boundary": (p, coords.s_boundary.values, coords.s_boundary.attrs),
        "vt_unit": (p, rec.vt_unit.values, rec.vt_unit.attrs),
        "w_unit": (p, rec.w_unit.values, rec.w_unit.attrs),
        "n_points": (o, rec.n_points.values, rec.n_points.attrs),
        "x_start": (o, start["positions"][:, 0], {"long_name": "x of the interior start (mid first flight)",
                                                  "units": "1"}),
        "y_start": (o, start["positions"][:, 1], {"long_name": "y of the interior start (mid first flight)",
                                                  "units": "1"}),
        "vx_start": (o, start["velocities"][:, 0], {"long_name": "x velocity at the interior start", "units": "1"}),
        "vy_start": (o, start["velocities"][:, 1], {"long_name": "y velocity at the interior start", "units": "1"}),
        "spin_start": (o, start["spins"], {"long_name": "scaled spin at the start (CCW positive)", "units": "1"}),
    }
    if scene.law == "specular":
        data["sin_angle"] = (p, coords.sin_angle.values, coords.sin_angle.attrs)
    if lyapunov_collisions is not None:
        lam = islands.finite_time_lyapunov(scene, start["positions"], start["velocities"], start["spins"],
                                           n_collisions=lyapunov_collisions)
        data["ftle"] = (o, lam, {"long_name": f"finite-time Lyapunov exponent per collision over "
                                              f"{lyapunov_collisions} collisions (NaN: corner)", "units": "1"})
    return xr.Dataset(data), coords.attrs


def portrait_set(scenes, labels, *, dim="case", n_orbits=20, n_collisions=1000, seed=0, elements=None,
                 lyapunov_collisions=None, threshold=None, chunk_size=None, scheduler=None, progress=None,
                 num_workers=None):
    r"""Phase portraits of several tables (or one table under several parameters) as one dataset.

    Every orbit starts on the boundary uniformly in the billiard map's
    invariant measure (:func:`noslipsim.analysis.islands.uniform_reduced_states`:
    ``ds dv_t dw`` no-slip, ``ds dp`` specular; the same scaled draws for every
    case), moved half-way along its first flight so the exponent and the
    portrait follow the same orbit.  At each collision on ``elements`` the
    record keeps the boundary arclength ``s_boundary`` and the post-collision
    unit vector projected on the disk:

    .. math::

        (v_t, w) / \lVert (w, v_t, v_n) \rVert

    (the velocity portrait; docs/analysis.md, "Boundary portraits").

    Parameters
    ----------
    scenes : sequence of Scene
        One table per case.
    labels : sequence
        The coordinate of each case along ``dim`` (names or numbers).
    dim : str
        Name of the case dimension (``"table"``, ``"gamma"``, ``"force"`` ...).
    n_orbits, n_collisions : int
        Orbits per case and collisions per orbit (points are recorded only on
        ``elements``).
    seed : int
        Seed of the starts (the same for every case).
    elements : sequence of int, optional
        Elements recorded and started on (default: all; they must be finite).
    lyapunov_collisions : int, optional
        If given, each orbit's finite-time exponent per collision over this
        many collisions (``ftle``) and the flag ``regular`` (``ftle <
        threshold``).
    threshold : float, optional
        Regular-orbit threshold (default
        :data:`noslipsim.analysis.islands.REGULAR_THRESHOLD`).
    chunk_size, scheduler, progress, num_workers
        Passed to :func:`noslipsim.simulate_many`.

    Returns
    -------
    xarray.Dataset
        Dims ``(dim, orbit, point)``: ``element``, ``s_boundary``, ``vt_unit``,
        ``w_unit`` (NaN-padded), ``sin_angle`` (specular cases only, NaN for
        the others), ``n_points``; the interior starts ``x_start`` ...
        ``spin_start``; ``ftle`` and ``regular``; per case ``scene`` (JSON),
        ``law``, ``gamma``, ``force_x``, ``force_y``, ``boundary_length``.
    """
    from .analysis import islands

    scenes = list(scenes)
    labels = list(labels)
    if not scenes or len(labels) != len(scenes):
        raise ValueError(f"scenes, labels: expected as many labels as scenes (at least one), got "
                         f"{len(scenes)} scenes and {len(labels)} labels")
    for i, sc in enumerate(scenes):
        if not isinstance(sc, Scene):
            raise ValueError(f"scenes[{i}]: expected a noslipsim.Scene, got {type(sc).__name__}")
    if not isinstance(dim, str) or not dim or dim in ("orbit", "point"):
        raise ValueError(f"dim: expected a name other than 'orbit' and 'point', got {dim!r}")
    n_orbits = _count(n_orbits, "n_orbits")
    n_collisions = _count(n_collisions, "n_collisions")
    if lyapunov_collisions is not None:
        lyapunov_collisions = _count(lyapunov_collisions, "lyapunov_collisions", minimum=9)
    threshold = islands.REGULAR_THRESHOLD if threshold is None else float(threshold)
    parts, lengths = [], []
    for sc in scenes:
        part, battrs = _portrait_case(sc, n_orbits, n_collisions, seed, elements, lyapunov_collisions, chunk_size,
                                      scheduler, progress, num_workers)
        parts.append(part)
        lengths.append(battrs["boundary_length"])
    if any("sin_angle" in part for part in parts):   # Birkhoff p only means something for specular cases
        for part in parts:
            if "sin_angle" not in part:
                part["sin_angle"] = xr.full_like(part.vt_unit, np.nan)
        for part in parts:
            part["sin_angle"].attrs = {"long_name": "Birkhoff p: sine of the exit angle to the inward normal "
                                                    "(specular cases; NaN for no-slip ones)", "units": "1"}
    ds = xr.concat(parts, dim=xr.DataArray(labels, dims=dim, name=dim), data_vars="all", join="outer",
                   fill_value=np.nan)
    ds = ds.isel(point=slice(0, max(1, int(ds.n_points.max()))))   # drop the padding no orbit uses
    if lyapunov_collisions is not None:
        ds["regular"] = (ds.ftle < threshold).astype(np.int8)
        ds["regular"].attrs = {"long_name": f"1 if ftle < {threshold:g} (an orbit on an invariant torus)",
                               "units": "1"}
    case = (dim,)
    ds["scene"] = (case, np.array([sc.to_json() for sc in scenes], dtype=object),
                   {"long_name": "the case's scene as JSON (docs/scenes.md)", "units": "1"})
    ds["boundary_length"] = (case, np.array(lengths), {"long_name": "length of the recorded boundary",
                                                       "units": "1"})
    per_case = {
        "law": ([sc.law for sc in scenes], {"long_name": "collision law", "units": "1"}),
        "gamma": ([sc.gamma if sc.law == "no-slip" else math.nan for sc in scenes],
                  {"long_name": "mass-distribution constant gamma (NaN: specular, not used)", "units": "1"}),
        "force_x": ([sc.force[0] for sc in scenes], {"long_name": "force per unit mass, x", "units": "1"}),
        "force_y": ([sc.force[1] for sc in scenes], {"long_name": "force per unit mass, y", "units": "1"}),
    }
    ds = ds.assign_coords({k: (case, v, a) for k, (v, a) in per_case.items() if k != dim})
    ds[dim].attrs.setdefault("units", "1")
    ds[dim].attrs.setdefault("long_name", dim)
    ds.attrs.update(title="phase portraits", n_orbits=n_orbits, n_collisions=n_collisions, seed=seed,
                    elements="all" if elements is None else list(elements),
                    lyapunov_collisions=-1 if lyapunov_collisions is None else lyapunov_collisions,
                    regular_threshold=threshold,
                    sampling="uniform in the invariant measure: ds dv_t dw (no-slip), ds dp (specular)")
    return annotate(ds)


def sinai_gamma_portraits(gammas=(0.0, 0.25, 0.5, 0.75, 1.0), *, radius=0.45, n_orbits=100, n_collisions=2000,
                          seed=0, lyapunov_collisions=1000, threshold=None, chunk_size=None, scheduler=None,
                          progress=None, num_workers=None):
    """Velocity portraits of the no-slip Sinai torus for several gammas (paper, Figure ``lorentzgamma``).

    :func:`portrait_set` on :func:`noslipsim.tables.sinai_torus` ``(radius)``,
    one case per gamma (dim ``gamma``), each orbit with its finite-time
    exponent (``ftle``, ``regular``).  ``gamma = 0`` is the specular billiard
    with the spin reversed at every collision (its portrait shows
    horizontal lines: ``|w|`` is constant).
    """
    gammas = _gammas(gammas)
    ds = portrait_set([tables.sinai_torus(radius, gamma=g) for g in gammas], gammas, dim="gamma",
                      n_orbits=n_orbits, n_collisions=n_collisions, seed=seed,
                      lyapunov_collisions=lyapunov_collisions, threshold=threshold, chunk_size=chunk_size,
                      scheduler=scheduler, progress=progress, num_workers=num_workers)
    ds["gamma"].attrs.update(long_name="mass-distribution constant gamma", units="1")
    ds.attrs.update(title="velocity portraits of the no-slip Sinai torus against gamma", radius=radius)
    return ds


def sinai_islands_sweep(radii=(0.45, 0.4), gammas=tuple(np.round(np.linspace(0.0, 1.0, 21), 10)), *,
                        n_orbits=500, n_collisions=1000, seed=0, threshold=None, level=None, progress=False):
    r"""Regular share of the no-slip Sinai torus against gamma, for several scatterer radii.

    For each radius and gamma, ``n_orbits`` starts uniform in the invariant
    measure ``ds dv_t dw`` (the same scaled draws everywhere), each orbit's
    finite-time Lyapunov exponent per collision over ``n_collisions``
    collisions, and the regular share ``p`` (exponent below ``threshold``)
    with its binomial error (:mod:`noslipsim.analysis.islands`).  Beside it,
    the linear theory's onset :math:`\gamma_0(R) = \sqrt{1/(2R) - 1}` (the
    head-on 2-periodic orbit between neighbouring disks turns elliptic).

    Parameters
    ----------
    radii : sequence of float
        Scatterer radii in ``(0, 1/2)`` (unit torus).
    gammas : sequence of float
        Increasing gammas ``>= 0``.
    n_orbits, n_collisions : int
        Orbits per point and collisions per exponent.
    seed : int
        Seed of the starts.
    threshold, level : float, optional
        Regular threshold and visibility level (defaults
        :data:`~noslipsim.analysis.islands.REGULAR_THRESHOLD`,
        :data:`~noslipsim.analysis.islands.VISIBLE_SHARE`).
    progress : bool
        Print one line per (radius, gamma) to stderr.

    Returns
    -------
    xarray.Dataset
        Dims ``(radius, gamma, orbit)``: ``ftle``; ``share_regular``,
        ``share_regular_stderr``, ``n_regular``, ``n_valid`` per point;
        ``head_on_onset`` per radius; the measured onset (first crossing of
        ``level``, bootstrap error) as ``onset_gamma``, ``onset_gamma_stderr``,
        ``onset_gamma_low``, ``onset_gamma_high`` per radius.
    """
    import sys

    from .analysis import islands

    radii = [float(r) for r in np.atleast_1d(np.asarray(radii, dtype=float))]
    if not radii or len(set(radii)) != len(radii):
        raise ValueError(f"radii: expected distinct radii, got {radii}")
    gammas = _gammas(gammas)
    if len(gammas) < 2 or np.any(np.diff(gammas) <= 0):
        raise ValueError(f"gammas: expected at least two increasing values, got {gammas}")
    n_orbits = _count(n_orbits, "n_orbits")
    n_collisions = _count(n_collisions, "n_collisions", minimum=9)
    threshold = islands.REGULAR_THRESHOLD if threshold is None else float(threshold)
    level = islands.VISIBLE_SHARE if level is None else float(level)
    lam = np.full((len(radii), len(gammas), n_orbits), np.nan)
    for i, R in enumerate(radii):
        for j, g in enumerate(gammas):
            scene = tables.sinai_torus(R, gamma=g)
            start = islands.interior_starts(scene, islands.uniform_reduced_states(scene, n_orbits, seed))
            lam[i, j] = islands.finite_time_lyapunov(scene, start["positions"], start["velocities"],
                                                     start["spins"], n_collisions=n_collisions)
            if progress:
                print(f"sinai_islands_sweep: R = {R:g}, gamma = {g:g}: regular share "
                      f"{islands.regular_share(lam[i, j], threshold)[0]:.3f}", file=sys.stderr, flush=True)
    share, err, n_valid = islands.regular_share(lam, threshold)
    k = np.rint(share * n_valid).astype(np.int64)
    onsets = [islands.onset_gamma(gammas, k[i], n_valid[i], level=level, seed=seed) for i in range(len(radii))]
    rg, rgo = ("radius", "gamma"), ("radius", "gamma", "orbit")
    one = {"units": "1"}
    ds = xr.Dataset({
        "ftle": (rgo, lam, {"long_name": f"finite-time Lyapunov exponent per collision over {n_collisions} "
                                         "collisions (NaN: corner)", **one}),
        "share_regular": (rg, share, {"long_name": f"share of orbits with ftle < {threshold:g} (regular)", **one}),
        "share_regular_stderr": (rg, err, {"long_name": "binomial standard error of share_regular", **one}),
        "n_regular": (rg, k, {"long_name": "orbits with ftle below the threshold", **one}),
        "n_valid": (rg, n_valid, {"long_name": "orbits with an exponent", **one}),
        "head_on_onset": ("radius", [islands.head_on_onset_gamma(R) for R in radii],
                          {"long_name": "gamma above which the head-on 2-periodic orbit between neighbouring "
                                        "disks is elliptic, sqrt(1/(2R) - 1)", **one}),
        "onset_gamma": ("radius", [o["value"] for o in onsets],
                        {"long_name": f"smallest gamma with share_regular >= {level:g} (linear interpolation)",
                         **one}),
        "onset_gamma_stderr": ("radius", [o["stderr"] for o in onsets],
                               {"long_name": "bootstrap standard deviation of onset_gamma", **one}),
        "onset_gamma_low": ("radius", [o["low"] for o in onsets],
                            {"long_name": "16th percentile of the bootstrap onsets", **one}),
        "onset_gamma_high": ("radius", [o["high"] for o in onsets],
                             {"long_name": "84th percentile of the bootstrap onsets", **one}),
    }, coords={"radius": ("radius", radii, {"long_name": "scatterer radius (unit torus)", **one}),
               "gamma": ("gamma", gammas, {"long_name": "mass-distribution constant gamma", **one}),
               "orbit": np.arange(n_orbits)})
    ds.attrs.update(title="regular share of the no-slip Sinai torus against gamma", n_orbits=n_orbits,
                    n_collisions=n_collisions, seed=seed, regular_threshold=threshold, visible_share=level,
                    sampling="uniform in the invariant measure ds dv_t dw (the same scaled draws everywhere)")
    return annotate(ds)


def closed_hex_cell(radius=0.4, *, law="no-slip", gamma=1 / math.sqrt(2), force=(0.0, 0.0)):
    """The hexagonal Wigner-Seitz cell of :func:`noslipsim.tables.hex_lorentz_cell`, closed by walls.

    Six segments (counter-clockwise, elements 0-5; vertices at ``(cos a, sin a)
    / sqrt(3)``, ``a = pi/6 + k pi/3``: vertical sides at ``x = +-1/2``, a vertex
    at the top and one at the bottom) and the disk of ``radius`` at the origin
    (element 6).  Unlike the periodic cell, a particle cannot leave it, so its
    energy ``(|v|^2 + w^2)/2 - a.q`` bounds the kinetic energy under a force.
    """
    if not 0 < radius < 0.5:
        raise ValueError(f"radius: must lie in (0, 1/2) (the cell's inradius), got {radius}")
    a = math.pi / 6 + math.pi / 3 * np.arange(6)
    return tables.polygon(np.c_[np.cos(a), np.sin(a)] / math.sqrt(3.0), disks=[(0.0, 0.0, radius)], law=law,
                          gamma=gamma, force=force)


def hex_force_portraits(gammas=(1 / math.sqrt(2), 1.0), forces=(0.0, 0.1, 4.0), *, radius=0.4, n_orbits=100,
                        n_collisions=5000, seed=0, lyapunov_collisions=5000, threshold=None,
                        energy_collisions=None, chunk_size=None, scheduler=None, progress=None, num_workers=None):
    """Velocity portraits of a disk in a closed hexagonal cell under a force (paper, Figure ``VPPforce``).

    The table is :func:`closed_hex_cell` with the force ``(0, -g)``; points are
    recorded on the disk only (the "disk-shaped scatterer" of the paper's
    caption) and orbits start on it.  Dims ``(gamma, force, orbit, point)``
    (:func:`portrait_set`).  For the choice of table the dataset also holds,
    from the same starts on the disk, the kinetic energy ``(|v|^2 + w^2)/2``
    after ``energy_collisions`` collisions (default ``n_collisions``) in the
    closed cell and in the periodic Lorentz gas
    (:func:`noslipsim.tables.hex_lorentz_cell`), dim ``cell``: in the periodic
    gas a force makes it grow without bound as the particle falls through
    the lattice; in the closed cell it is bounded by the energy.
    """
    from .analysis import islands

    gammas = _gammas(gammas)
    forces = [float(g) for g in forces]
    if not forces or any(not (math.isfinite(g) and g >= 0.0) for g in forces) or len(set(forces)) != len(forces):
        raise ValueError(f"forces: expected distinct force strengths >= 0, got {forces}")
    energy_collisions = n_collisions if energy_collisions is None else _count(energy_collisions,
                                                                              "energy_collisions")
    disk = 6
    rows, energy = [], []
    for gm in gammas:
        cells = [closed_hex_cell(radius, gamma=gm, force=(0.0, -g if g else 0.0)) for g in forces]
        rows.append(portrait_set(cells, forces, dim="force", n_orbits=n_orbits, n_collisions=n_collisions,
                                 seed=seed, elements=[disk], lyapunov_collisions=lyapunov_collisions,
                                 threshold=threshold, chunk_size=chunk_size, scheduler=scheduler, progress=progress,
                                 num_workers=num_workers).drop_vars("gamma"))
        per_force = []
        for g, closed in zip(forces, cells):
            lattice = tables.hex_lorentz_cell(radius, gamma=gm, force=(0.0, -g if g else 0.0))
            kin = []
            for sc, el in ((closed, [disk]), (lattice, [0])):
                st = islands.uniform_reduced_states(sc, n_orbits, seed, elements=el)
                fin = simulate_many(sc, st["positions"], st["velocities"], st["spins"],
                                    start_elements=st["start_elements"], max_collisions=energy_collisions,
                                    record="final", chunk_size=chunk_size, scheduler=scheduler, progress=progress,
                                    num_workers=num_workers)
                kin.append(0.5 * (fin.vx_final.values**2 + fin.vy_final.values**2 + fin.spin_final.values**2))
            per_force.append(kin)
        energy.append(per_force)
    size = max(r.sizes["point"] for r in rows)      # each row was trimmed to its own longest orbit
    rows = [r.pad(point=(0, size - r.sizes["point"]), constant_values=np.nan) for r in rows]
    ds = xr.concat(rows, dim=xr.DataArray(gammas, dims="gamma", name="gamma"), data_vars="all")
    ds["kinetic_final"] = (("gamma", "force", "cell", "orbit"), np.array(energy), {
        "long_name": f"kinetic energy (|v|^2 + w^2)/2 after {energy_collisions} collisions from the same starts "
                     "on the disk (start: 1/2)", "units": "1"})
    ds = ds.assign_coords(cell=("cell", ["closed", "periodic"], {
        "long_name": "closed: hexagonal cell with no-slip walls (the figure's table); periodic: the hexagonal "
                     "Lorentz gas", "units": "1"}))
    ds["gamma"].attrs.update(long_name="mass-distribution constant gamma", units="1")
    ds["force"].attrs.update(long_name="force strength g (force (0, -g) per unit mass)", units="1")
    ds.attrs.update(title="velocity portraits of a disk in a closed hexagonal cell under a force", radius=radius,
                    energy_collisions=energy_collisions, recorded_elements="the disk (element 6)",
                    table_choice="closed hexagonal cell with no-slip walls: in the periodic Lorentz gas a constant "
                                 "force makes the kinetic energy grow without bound (kinetic_final, cell='periodic'), "
                                 "so the normalised portrait of a long orbit drifts towards the force-free one; the "
                                 "closed cell keeps it bounded by the energy")
    return annotate(ds)


#: Names of the polygons of Figure vppregpoly (other side counts are called "n-gon").
POLYGON_NAMES = {3: "triangle", 4: "rectangle", 5: "pentagon", 6: "hexagon", 8: "octagon", 12: "dodecagon",
                 20: "icosagon"}


def polygon_portraits(sides=(4, 6, 12, 20), *, aspect=2.0, gamma=1 / math.sqrt(2), n_orbits=30,
                      n_collisions=10000, seed=0, chunk_size=None, scheduler=None, progress=None, num_workers=None):
    """Velocity portraits of no-slip polygons without force (paper, Figure ``vppregpoly``).

    ``4`` sides is the ``aspect : 1`` rectangle (:func:`noslipsim.tables.rectangle`),
    any other count the regular polygon of circumradius 1
    (:func:`noslipsim.tables.regular_polygon`); dim ``table`` (names from
    :data:`POLYGON_NAMES`), a :func:`portrait_set` dataset without exponents
    (a polygon has none: its velocity turns by fixed orthogonal maps).
    """
    sides = [_count(n, "sides", minimum=3) for n in sides]
    if not sides or len(set(sides)) != len(sides):
        raise ValueError(f"sides: expected distinct side counts >= 3, got {sides}")
    aspect = float(aspect)
    if not (math.isfinite(aspect) and aspect > 0.0):
        raise ValueError(f"aspect: must be finite and > 0, got {aspect}")
    scenes = [tables.rectangle(aspect, 1.0, gamma=gamma) if n == 4 else tables.regular_polygon(n, gamma=gamma)
              for n in sides]
    ds = portrait_set(scenes, [POLYGON_NAMES.get(n, f"{n}-gon") for n in sides], dim="table", n_orbits=n_orbits,
                      n_collisions=n_collisions, seed=seed, chunk_size=chunk_size, scheduler=scheduler,
                      progress=progress, num_workers=num_workers)
    ds = ds.assign_coords(sides=("table", sides, {"long_name": "number of sides", "units": "1"}))
    ds.attrs.update(title="velocity portraits of no-slip polygons", rectangle_aspect=aspect)
    return ds


def lemon_sinai_portraits(*, lemon_radius=1.0, lemon_distance=1.0, sinai_radius=0.45, gamma=1 / math.sqrt(2),
                          n_orbits=60, n_collisions=3000, seed=0, lyapunov_collisions=1000, threshold=None,
                          chunk_size=None, scheduler=None, progress=None, num_workers=None):
    """The specular lemon and the no-slip Sinai torus (paper, Figure ``phaseportraits``).

    A :func:`portrait_set` dataset with dim ``table`` = ``["lemon", "sinai"]``:
    the specular lemon (:func:`noslipsim.tables.lemon`) in Birkhoff coordinates
    ``(s_boundary, sin_angle)``, the no-slip Sinai torus
    (:func:`noslipsim.tables.sinai_torus`) in reduced coordinates
    ``(s_boundary, vt_unit, w_unit)``; each orbit with its exponent.
    """
    scenes = [tables.lemon(lemon_radius, lemon_distance), tables.sinai_torus(sinai_radius, gamma=gamma)]
    ds = portrait_set(scenes, ["lemon", "sinai"], dim="table", n_orbits=n_orbits, n_collisions=n_collisions,
                      seed=seed, lyapunov_collisions=lyapunov_collisions, threshold=threshold, chunk_size=chunk_size,
                      scheduler=scheduler, progress=progress, num_workers=num_workers)
    ds.attrs.update(title="phase portraits: specular lemon, no-slip Sinai torus", lemon_radius=lemon_radius,
                    lemon_distance=lemon_distance, sinai_radius=sinai_radius)
    return ds


EXPERIMENTS.update(sinai_gamma_portraits=sinai_gamma_portraits, sinai_islands_sweep=sinai_islands_sweep,
                   hex_force_portraits=hex_force_portraits, polygon_portraits=polygon_portraits,
                   lemon_sinai_portraits=lemon_sinai_portraits)
