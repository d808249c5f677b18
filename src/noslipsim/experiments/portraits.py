"""Phase portraits of many orbits per table (Figures 10-13).

Orbits start uniformly in the billiard map's invariant measure, each with its finite-time
Lyapunov exponent (:mod:`noslipsim.analysis.islands`), so a figure can tell the chaotic sea
from the islands and a number can say how much is regular.
"""
from __future__ import annotations

import math
import sys

import numpy as np
import xarray as xr

from .. import tables
from .._metadata import annotate
from .._validate import count
from ..analysis import islands
from ..analysis.attractors import ATTRACTOR_REPEATS, ATTRACTOR_TOLERANCE, portrait_attractors
from ..analysis.portraits import birkhoff_coordinates, boundary_coordinate
from ..ensemble import simulate_many
from ..scenes import Scene
from .galton import gamma_values


def _portrait_case(scene, n_orbits, n_collisions, seed, elements, lyapunov_collisions, chunk_size, scheduler,
                   progress, num_workers, lyapunov="tangent"):
    """One table's portrait (dims orbit, point) with its starts and, optionally, exponents per orbit."""

    boundary = islands.uniform_reduced_states(scene, n_orbits, seed, elements=elements)
    start = islands.interior_starts(scene, boundary)
    rec = simulate_many(scene, start["positions"], start["velocities"], start["spins"], max_collisions=n_collisions,
                        record="portrait", elements=elements, chunk_size=chunk_size, scheduler=scheduler,
                        progress=progress, num_workers=num_workers)
    specular = not scene.any_noslip  # no spin in the phase space: Birkhoff coordinates
    coords = (birkhoff_coordinates if specular else boundary_coordinate)(rec, scene, elements=elements)
    o, p = ("orbit",), ("orbit", "point")
    data = {
        "element": (p, rec.element.values.astype(np.float32), rec.element.attrs),
        "s_boundary": (p, coords.s_boundary.values),
        "vt_unit": (p, rec.vt_unit.values, rec.vt_unit.attrs),
        "w_unit": (p, rec.w_unit.values, rec.w_unit.attrs),
        "n_points": (o, rec.n_points.values, rec.n_points.attrs),
        "x_start": (o, start["positions"][:, 0]),     # the interior start: mid first flight
        "y_start": (o, start["positions"][:, 1]),
        "vx_start": (o, start["velocities"][:, 0]),
        "vy_start": (o, start["velocities"][:, 1]),
        "spin_start": (o, start["spins"]),
    }
    if specular:
        data["sin_angle"] = (p, coords.sin_angle.values)
    if lyapunov_collisions is not None:
        exponent = islands.twin_lyapunov if lyapunov == "twin" else islands.finite_time_lyapunov
        lam = exponent(scene, start["positions"], start["velocities"], start["spins"],
                       n_collisions=lyapunov_collisions)
        data["ftle"] = (o, lam)    # over lyapunov_collisions collisions (a dataset attribute)
    return xr.Dataset(data), coords.attrs


def portrait_set(scenes, labels, *, dim="case", n_orbits=20, n_collisions=1000, seed=0, elements=None,
                 lyapunov_collisions=None, lyapunov="tangent", chunk_size=None, scheduler=None, progress=None,
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
        Name of the case dimension (``"table"``, ``"gamma"``, ``"force"`` ...); a name
        without an entry of its own in docs/datasets.md is described as ``case``.
    n_orbits, n_collisions : int
        Orbits per case and collisions per orbit (points are recorded only on
        ``elements``).
    seed : int
        Seed of the starts (the same for every case).
    elements : sequence of int, optional
        Elements recorded and started on (default: all; they must be finite).
    lyapunov_collisions : int, optional
        If given, each orbit's finite-time exponent per collision over this
        many collisions (``ftle``); :func:`noslipsim.analysis.classify_regular`
        flags the regular orbits with a threshold of the reader's choice.
    lyapunov : {'tangent', 'twin'}
        How the exponent is measured: the exact tangent dynamics
        (:func:`noslipsim.analysis.finite_time_lyapunov`, free fall only) or a
        renormalised twin orbit (:func:`noslipsim.analysis.twin_lyapunov`, any
        flight, the isokinetic thermostat included).
    chunk_size, scheduler, progress, num_workers
        Passed to :func:`noslipsim.simulate_many`.

    Returns
    -------
    xarray.Dataset
        Dims ``(dim, orbit, point)``: ``element``, ``s_boundary``, ``vt_unit``,
        ``w_unit`` (NaN-padded), ``sin_angle`` (specular cases only, NaN for
        the others), ``n_points``; the interior starts ``x_start`` ...
        ``spin_start``; ``ftle``; per case ``scene`` (JSON),
        ``law``, ``gamma``, ``force_x``, ``force_y``, ``boundary_length``.
    """

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
    n_orbits = count(n_orbits, "n_orbits")
    n_collisions = count(n_collisions, "n_collisions")
    if lyapunov_collisions is not None:
        lyapunov_collisions = count(lyapunov_collisions, "lyapunov_collisions", minimum=9)
    if lyapunov not in ("tangent", "twin"):
        raise ValueError(f"lyapunov: expected 'tangent' or 'twin', got {lyapunov!r}")
    parts, lengths = [], []
    for sc in scenes:
        part, battrs = _portrait_case(sc, n_orbits, n_collisions, seed, elements, lyapunov_collisions, chunk_size,
                                      scheduler, progress, num_workers, lyapunov)
        parts.append(part)
        lengths.append(battrs["boundary_length"])
    if any("sin_angle" in part for part in parts):   # Birkhoff p only means something for specular cases
        for part in parts:
            if "sin_angle" not in part:
                part["sin_angle"] = (part.vt_unit.dims, np.full(part.vt_unit.shape, np.nan))
    ds = xr.concat(parts, dim=xr.DataArray(labels, dims=dim, name=dim), data_vars="all", join="outer",
                   fill_value=np.nan)
    ds = ds.isel(point=slice(0, max(1, int(ds.n_points.max()))))   # drop the padding no orbit uses
    case = (dim,)
    ds["scene"] = (case, np.array([sc.to_json() for sc in scenes], dtype=object))
    ds["boundary_length"] = (case, np.array(lengths))
    per_case = {
        "law": [sc.law for sc in scenes],
        "gamma": [sc.gamma if sc.any_noslip else math.nan for sc in scenes],
        "force_x": [sc.force[0] for sc in scenes],
        "force_y": [sc.force[1] for sc in scenes],
    }
    ds = ds.assign_coords({k: (case, v) for k, v in per_case.items() if k != dim})
    ds.attrs.update(title="phase portraits", n_orbits=n_orbits, n_collisions=n_collisions, seed=seed,
                    elements="all" if elements is None else list(elements),
                    lyapunov_collisions=-1 if lyapunov_collisions is None else lyapunov_collisions,
                    lyapunov_method=lyapunov,
                    sampling="uniform in the invariant measure: ds dv_t dw (no-slip), ds dp (specular)")
    return annotate(ds, case_dim=dim)


def sinai_gamma_portraits(gammas=(0.0, 0.25, 0.5, 0.75, 1.0), *, radius=0.45, n_orbits=100, n_collisions=2000,
                          seed=0, lyapunov_collisions=1000, chunk_size=None, scheduler=None, progress=None,
                          num_workers=None):
    """Velocity portraits of the no-slip Sinai torus for several gammas (paper, Figure ``lorentzgamma``).

    :func:`portrait_set` on :func:`noslipsim.tables.sinai_torus` ``(radius)``,
    one case per gamma (dim ``gamma``), each orbit with its finite-time
    exponent (``ftle``).  ``gamma = 0`` is the specular billiard
    with the spin reversed at every collision (its portrait shows
    horizontal lines: ``|w|`` is constant).
    """
    gammas = gamma_values(gammas)
    ds = portrait_set([tables.sinai_torus(radius, gamma=g) for g in gammas], gammas, dim="gamma",
                      n_orbits=n_orbits, n_collisions=n_collisions, seed=seed,
                      lyapunov_collisions=lyapunov_collisions, chunk_size=chunk_size, scheduler=scheduler,
                      progress=progress, num_workers=num_workers)
    ds.attrs.update(title="velocity portraits of the no-slip Sinai torus against gamma", radius=radius)
    return ds


#: gamma = 0, 0.05, ..., 1 (rounded so that the values print as typed)
GAMMAS_21 = tuple(float(g) for g in np.round(np.linspace(0.0, 1.0, 21), 10))


def sinai_islands_sweep(radii=(0.45, 0.4), gammas=GAMMAS_21, *,
                        n_orbits=500, n_collisions=1000, seed=0, progress=False):
    r"""Finite-time exponents of the no-slip Sinai torus against gamma, for several scatterer radii.

    For each radius and gamma, ``n_orbits`` starts uniform in the invariant
    measure ``ds dv_t dw`` (the same scaled draws everywhere) and each orbit's
    finite-time Lyapunov exponent per collision over ``n_collisions``
    collisions; :func:`noslipsim.analysis.islands_onsets` turns them into the
    regular share ``p`` (exponent below a threshold) with its binomial error
    and the onset of islands.  Beside them, the linear theory's onset
    :math:`\gamma_0(R) = \sqrt{1/(2R) - 1}` (the head-on 2-periodic orbit
    between neighbouring disks turns elliptic).

    Parameters
    ----------
    radii : sequence of float
        Scatterer radii in ``(0, 1/2)`` (unit torus).
    gammas : sequence of float
        Increasing gammas ``>= 0``.
    n_orbits, n_collisions : int
        Orbits per point and collisions per exponent.
    seed : int
        Seed of the starts (and of the onset's bootstrap).
    progress : bool
        Print one line per (radius, gamma) to stderr.

    Returns
    -------
    xarray.Dataset
        Dims ``(radius, gamma, orbit)``: ``ftle``; ``head_on_onset`` per radius.
        The attribute ``lyapunov_collisions`` (``n_collisions``) is the exponents' length.
    """

    radii = [float(r) for r in np.atleast_1d(np.asarray(radii, dtype=float))]
    if not radii or len(set(radii)) != len(radii):
        raise ValueError(f"radii: expected distinct radii, got {radii}")
    gammas = gamma_values(gammas)
    if len(gammas) < 2 or np.any(np.diff(gammas) <= 0):
        raise ValueError(f"gammas: expected at least two increasing values, got {gammas}")
    n_orbits = count(n_orbits, "n_orbits")
    n_collisions = count(n_collisions, "n_collisions", minimum=9)
    lam = np.full((len(radii), len(gammas), n_orbits), np.nan)
    for i, R in enumerate(radii):
        for j, g in enumerate(gammas):
            scene = tables.sinai_torus(R, gamma=g)
            start = islands.interior_starts(scene, islands.uniform_reduced_states(scene, n_orbits, seed))
            lam[i, j] = islands.finite_time_lyapunov(scene, start["positions"], start["velocities"],
                                                     start["spins"], n_collisions=n_collisions)
            if progress:
                print(f"sinai_islands_sweep: R = {R:g}, gamma = {g:g}: median exponent "
                      f"{np.nanmedian(lam[i, j]):.3f}", file=sys.stderr, flush=True)
    ds = xr.Dataset({
        "ftle": (("radius", "gamma", "orbit"), lam),
        "head_on_onset": ("radius", [islands.head_on_onset_gamma(R) for R in radii]),
    }, coords={"radius": radii, "gamma": gammas, "orbit": np.arange(n_orbits)})
    ds.attrs.update(title="finite-time exponents of the no-slip Sinai torus against gamma", n_orbits=n_orbits,
                    n_collisions=n_collisions, lyapunov_collisions=n_collisions, seed=seed,
                    sampling="uniform in the invariant measure ds dv_t dw (the same scaled draws everywhere)")
    return annotate(ds)


#: Figure 13's readings of "a disk-shaped scatterer in a hexagonal cell under a force" (docs/figures.md,
#: "Figure 13"): the table, its collision law and flight, and the element recorded (the disk).
HEX_READINGS = {
    "closed": "closed hexagonal cell, no-slip walls and disk, free fall",
    "specular_walls": "closed hexagonal cell, specular walls around a no-slip disk, free fall",
    "periodic": "periodic hexagonal cell (the Lorentz gas), no-slip disk, free fall",
    "thermostat": "periodic hexagonal cell (the Lorentz gas), no-slip disk, isokinetic thermostat",
    "specular_thermostat": "periodic hexagonal cell (the Lorentz gas), specular disk, isokinetic thermostat",
}

#: Readings whose flow contracts phase volume (the thermostat): only they can have attracting cycles.
DISSIPATIVE_READINGS = ("thermostat", "specular_thermostat")


def hex_reading_scene(reading, radius, gamma, g):
    """``(scene, disk element)`` of one of :data:`HEX_READINGS` with the force ``(0, -g)``.

    ``closed``: :func:`noslipsim.tables.closed_hex_cell` (no-slip, element 6 is
    the disk); ``specular_walls``: the same cell with specular walls around the
    same no-slip disk (a table of mixed laws, ``wall_law='specular'``): what the
    walls add to the closed cell's structure;
    ``periodic``: :func:`noslipsim.tables.hex_lorentz_cell` (element 0);
    ``thermostat``: the same with ``thermostat = 'isokinetic'`` (the speed is
    kept, the force turns the heading; with no force the thermostat is inert:
    the straight flights, bit for bit); ``specular_thermostat``: the same with a
    specular disk (``gamma`` plays no part), the driven Lorentz gas of the
    specular results the paper's caption calls analogous.
    """
    if reading not in HEX_READINGS:
        raise ValueError(f"reading: expected one of {sorted(HEX_READINGS)}, got {reading!r}")
    force = (0.0, -g if g else 0.0)
    if reading in ("closed", "specular_walls"):
        wall_law = "specular" if reading == "specular_walls" else None
        return tables.closed_hex_cell(radius, gamma=gamma, force=force, wall_law=wall_law), 6
    law = "specular" if reading == "specular_thermostat" else "no-slip"
    scene = tables.hex_lorentz_cell(radius, law=law, gamma=gamma, force=force)
    return (scene.replace(thermostat="isokinetic") if reading in DISSIPATIVE_READINGS else scene), 0


def _forces(forces):
    forces = [float(g) for g in forces]
    if not forces or any(not (math.isfinite(g) and g >= 0.0) for g in forces) or len(set(forces)) != len(forces):
        raise ValueError(f"forces: expected distinct force strengths >= 0, got {forces}")
    return forces


def hex_force_portraits(gammas=(1 / math.sqrt(2), 1.0), forces=(0.0, 0.1, 4.0), *, reading="closed", radius=0.4,
                        n_orbits=100, n_collisions=5000, seed=0, lyapunov_collisions=5000, energy_collisions=None,
                        chunk_size=None, scheduler=None, progress=None, num_workers=None):
    """Velocity portraits of a disk in a hexagonal cell under a force (paper, Figure ``VPPforce``).

    The table is the ``reading`` of :data:`HEX_READINGS` (:func:`hex_reading_scene`)
    with the force ``(0, -g)``; points are recorded on the disk only (the
    "disk-shaped scatterer" of the paper's caption) and orbits start on it.
    Dims ``(gamma, force, orbit, point)`` (:func:`portrait_set`); the
    exponents ``ftle`` come from twin orbits (:func:`noslipsim.analysis.twin_lyapunov`,
    the method that serves every reading).  The portrait's ``(v_t, w)`` is the
    post-collision velocity normalised by its length, so a particle that
    speeds up as it falls (periodic cell, free fall) stays on the unit disk.
    Also, from the same starts on the disk, the kinetic energy ``(|v|^2 +
    w^2)/2`` after ``energy_collisions`` collisions (default ``n_collisions``)
    in the closed cell and in the periodic gas under free fall, dim ``cell``:
    in the periodic gas the force makes it grow without bound as the particle
    falls through the lattice; in the closed cell the energy bounds it.
    """
    gammas = gamma_values(gammas)
    forces = _forces(forces)
    energy_collisions = n_collisions if energy_collisions is None else count(energy_collisions,
                                                                              "energy_collisions")
    rows, energy = [], []
    for gm in gammas:
        cells = [hex_reading_scene(reading, radius, gm, g) for g in forces]
        disk = cells[0][1]
        rows.append(portrait_set([sc for sc, _ in cells], forces, dim="force", n_orbits=n_orbits,
                                 n_collisions=n_collisions, seed=seed, elements=[disk],
                                 lyapunov_collisions=lyapunov_collisions, lyapunov="twin", chunk_size=chunk_size,
                                 scheduler=scheduler, progress=progress, num_workers=num_workers).drop_vars("gamma"))
        per_force = []
        for g in forces:
            kin = []
            for sc, el in (hex_reading_scene("closed", radius, gm, g), hex_reading_scene("periodic", radius, gm, g)):
                st = islands.uniform_reduced_states(sc, n_orbits, seed, elements=[el])
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
    ds["kinetic_final"] = (("gamma", "force", "cell", "orbit"), np.array(energy))   # after energy_collisions
    ds = ds.assign_coords(cell=["closed", "periodic"])
    ds.attrs.update(title=f"velocity portraits of a disk in a hexagonal cell under a force ({reading})",
                    reading=reading, table=HEX_READINGS[reading], radius=radius,
                    energy_collisions=energy_collisions, recorded_elements=f"the disk (element {disk})")
    return annotate(ds)


def _reading_case(reading, radius, gamma, g, n_orbits, lyapunov_collisions, attractor_collisions, seed,
                  num_workers):
    """Exponents of one case of :func:`hex_force_readings`, and its orbits' attracting cycles (or None)."""
    scene, disk = hex_reading_scene(reading, radius, gamma, g)
    start = islands.interior_starts(scene, islands.uniform_reduced_states(scene, n_orbits, seed, elements=[disk]))
    lam = islands.twin_lyapunov(scene, start["positions"], start["velocities"], start["spins"],
                                n_collisions=lyapunov_collisions, seed=seed, num_workers=num_workers)
    if attractor_collisions is None or reading not in DISSIPATIVE_READINGS:
        return lam, None
    # the same starts (portrait_set draws them as above), recorded on the disk long enough for long cycles
    drawn = portrait_set([scene], [g], dim="force", n_orbits=n_orbits, n_collisions=attractor_collisions, seed=seed,
                         elements=[disk], num_workers=num_workers)
    found = portrait_attractors(drawn).isel(force=0)
    return lam, (found.attractor_period.values, found.attractor.values)


def hex_force_readings(gammas=(1 / math.sqrt(2), 1.0), forces=(0.0, 0.1, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0), *,
                       readings=tuple(HEX_READINGS), radius=0.4, n_orbits=100, lyapunov_collisions=1000,
                       attractor_collisions=None, seed=0, num_workers=None, progress=False):
    r"""Finite-time exponents of Figure 13's readings against the force (Figure S3), and attracting cycles.

    For each reading of :data:`HEX_READINGS`, gamma and force strength ``g``
    (force ``(0, -g)``), ``n_orbits`` starts on the disk uniform in the
    invariant measure of the force-free map (``ds dv_t dw`` on a no-slip disk,
    ``ds dp`` on the specular one; the same scaled draws everywhere, as in
    Figure 13) and each orbit's finite-time exponent per collision over
    ``lyapunov_collisions`` collisions from a twin orbit
    (:func:`noslipsim.analysis.twin_lyapunov`).
    :func:`noslipsim.analysis.regular_share` turns them into the share of
    regular orbits, the quantity the caption's "structure", "dissipates" and
    "new invariant regions" are about.  In the thermostatted readings
    (:data:`DISSIPATIVE_READINGS`, the only ones whose flow contracts phase
    volume) a regular orbit may instead have fallen onto an attracting cycle:
    with ``attractor_collisions`` the same starts are followed that many disk
    collisions and :func:`noslipsim.analysis.portrait_attractors` names the
    cycle each ends on.  The specular reading does not depend on gamma: it is
    run once and repeated along ``gamma``.

    Parameters
    ----------
    gammas : sequence of float
        Mass distributions (the paper: ``1/sqrt 2`` and ``1``).
    forces : sequence of float
        Distinct force strengths ``g >= 0``.
    readings : sequence of str
        Keys of :data:`HEX_READINGS`.
    radius : float
        Disk radius (unit triangular lattice; ``(0, 1/2)``).
    n_orbits, lyapunov_collisions : int
        Orbits per case and collisions per exponent.
    attractor_collisions : int, optional
        Disk collisions recorded per orbit to find attracting cycles (None: not looked for).
    seed : int
        Seed of the starts and of the twins.
    num_workers : int, optional
        Threads (the result does not depend on it).
    progress : bool
        One line per case on stderr.

    Returns
    -------
    xarray.Dataset
        Dims ``(reading, gamma, force, orbit)``: ``ftle``; with
        ``attractor_collisions``, ``attractor_period`` and ``attractor`` (0 and
        -1 in the readings without a thermostat); ``reading_table`` per
        reading (a description).
    """
    gammas = gamma_values(gammas)
    forces = _forces(forces)
    readings = list(readings)
    if not readings or len(set(readings)) != len(readings) or any(r not in HEX_READINGS for r in readings):
        raise ValueError(f"readings: expected distinct names among {sorted(HEX_READINGS)}, got {readings}")
    n_orbits = count(n_orbits, "n_orbits")
    lyapunov_collisions = count(lyapunov_collisions, "lyapunov_collisions", minimum=9)
    if attractor_collisions is not None:
        attractor_collisions = count(attractor_collisions, "attractor_collisions", minimum=3)
    shape = (len(readings), len(gammas), len(forces), n_orbits)
    lam, period, label = np.full(shape, np.nan), np.zeros(shape, dtype=int), np.full(shape, -1)
    for i, reading in enumerate(readings):
        for j, gm in enumerate(gammas):
            for k, g in enumerate(forces):
                if reading == "specular_thermostat" and j > 0:   # gamma plays no part in a specular reading
                    lam[i, j, k], period[i, j, k], label[i, j, k] = lam[i, 0, k], period[i, 0, k], label[i, 0, k]
                    continue
                lam[i, j, k], cycles = _reading_case(reading, radius, gm, g, n_orbits, lyapunov_collisions,
                                                     attractor_collisions, seed, num_workers)
                if cycles is not None:
                    period[i, j, k], label[i, j, k] = cycles
                if progress:
                    print(f"hex_force_readings: {reading}, gamma = {gm:g}, g = {g:g}: median exponent "
                          f"{np.nanmedian(lam[i, j, k]):.3f}", file=sys.stderr, flush=True)
    dims = ("reading", "gamma", "force", "orbit")
    data = {"ftle": (dims, lam), "reading_table": ("reading", [HEX_READINGS[r] for r in readings])}
    if attractor_collisions is not None:
        data.update(attractor_period=(dims, period), attractor=(dims, label))
    ds = xr.Dataset(data, coords={"reading": readings, "gamma": gammas, "force": forces,
                                  "orbit": np.arange(n_orbits)})
    ds.attrs.update(title="finite-time exponents of Figure 13's readings against the force", radius=radius,
                    n_orbits=n_orbits, lyapunov_collisions=lyapunov_collisions, lyapunov_method="twin", seed=seed,
                    attractor_collisions=-1 if attractor_collisions is None else attractor_collisions,
                    force_direction="(0, -g)",
                    sampling="starts on the disk uniform in the force-free invariant measure (the same scaled draws "
                             "everywhere)")
    if attractor_collisions is not None:
        ds.attrs.update(attractor_tolerance=ATTRACTOR_TOLERANCE, attractor_repeats=ATTRACTOR_REPEATS)
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
    sides = [count(n, "sides", minimum=3) for n in sides]
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
    ds = ds.assign_coords(sides=("table", sides))
    ds.attrs.update(title="velocity portraits of no-slip polygons", rectangle_aspect=aspect)
    return annotate(ds)


def lemon_sinai_portraits(*, lemon_radius=1.0, lemon_distance=1.0, sinai_radius=0.45, gamma=1 / math.sqrt(2),
                          n_orbits=60, n_collisions=3000, seed=0, lyapunov_collisions=1000, chunk_size=None,
                          scheduler=None, progress=None, num_workers=None):
    """The specular lemon and the no-slip Sinai torus (paper, Figure ``phaseportraits``).

    A :func:`portrait_set` dataset with dim ``table`` = ``["lemon", "sinai"]``:
    the specular lemon (:func:`noslipsim.tables.lemon`) in Birkhoff coordinates
    ``(s_boundary, sin_angle)``, the no-slip Sinai torus
    (:func:`noslipsim.tables.sinai_torus`) in reduced coordinates
    ``(s_boundary, vt_unit, w_unit)``; each orbit with its exponent.
    """
    scenes = [tables.lemon(lemon_radius, lemon_distance), tables.sinai_torus(sinai_radius, gamma=gamma)]
    ds = portrait_set(scenes, ["lemon", "sinai"], dim="table", n_orbits=n_orbits, n_collisions=n_collisions,
                      seed=seed, lyapunov_collisions=lyapunov_collisions, chunk_size=chunk_size,
                      scheduler=scheduler, progress=progress, num_workers=num_workers)
    ds.attrs.update(title="phase portraits: specular lemon, no-slip Sinai torus", lemon_radius=lemon_radius,
                    lemon_distance=lemon_distance, sinai_radius=sinai_radius)
    return ds
