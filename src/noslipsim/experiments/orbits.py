"""Single orbits that illustrate the paper's theorems and claims (Figures 1, 4, 5, 6, 8, 16).

Each function returns an :func:`~noslipsim.experiments.orbit_set` dataset (or the 3D bounce
log) with the numbers that back the figure's caption.
"""
from __future__ import annotations

import json
import math

import numpy as np
import xarray as xr

from .. import tables
from .._metadata import annotate
from .._validate import count, positive
from ..analysis import find_periodic_orbit, monodromy, two_disk_orbit, wedge_orbit
from ..sphere3d import simulate_sphere
from ..theory import two_disk_eigen_sum
from .orbit_sets import orbit_set


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
    return ds.assign_coords(role=("orbit", list(roles)))


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
    max_collisions = count(max_collisions, "max_collisions")
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
    ds["scatterer_collision"] = ("orbit", np.array(first))
    ds["exit_from_vertical"] = ("orbit", np.array(vertical))      # degrees
    ds["exit_to_corner"] = ("orbit", np.array(corner))
    ds = _label_orbits(ds, ["specular", "no-slip"])
    ds.attrs.update(title="specular and no-slip orbits from one start (rectangle with a scatterer)",
                    width=width, height=height, disk=list(disk), start=list(start), angle=angle, spin=spin,
                    gamma=gamma)
    return annotate(ds)


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


    n_generic = count(n_generic, "n_generic")
    n_corridor = count(n_corridor, "n_corridor")
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
    ds["periodic_residual"] = ((), found.residual)
    ds["periodic_iterations"] = ((), found.iterations)
    ds["periodic_kind"] = ((), m.kind)
    ds["eigenvalue_real"] = ("eigenvalue", m.eigenvalues.real)    # by decreasing modulus (monodromy)
    ds["eigenvalue_imag"] = ("eigenvalue", m.eigenvalues.imag)
    ds["rotation_angle"] = ((), abs(float(np.angle(pair))))
    ds["corridor_width"] = ((), width)
    ds.attrs.update(title="pentagon orbits: generic specular, no-slip corridor near a periodic point",
                    irregular_vertices=json.dumps(vertices.tolist()), regular_start=list(regular_start),
                    regular_angle=regular_angle, irregular_start=list(irregular_start),
                    irregular_angle=irregular_angle, guess_position=list(guess_position),
                    guess_velocity=list(guess_velocity), guess_spin=guess_spin, period=period, gamma=gamma,
                    perturbation=perturbation, tol=tol, periodic_position=list(found.position),
                    periodic_velocity=list(found.velocity), periodic_spin=found.spin)
    return annotate(ds)


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
    n_bounces = count(n_bounces, "n_bounces", minimum=3)
    gamma = float(gamma)
    if not (math.isfinite(gamma) and gamma > 0.0):
        raise ValueError(f"gamma: must be finite and > 0 (the spin is r v_x / gamma), got {gamma}")
    g = positive(gravity, "gravity")
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
    ds["spin_ratio"] = ("orbit", np.array(ratios))
    ds["drift"] = ("orbit", drift)
    ds["drift_spread"] = ("orbit", np.nanmax(np.abs(steps - drift[:, None]), axis=1))
    flights = np.c_[ds.vx_start.values, ds.vx.values[:, :1]]
    ds["back_and_forth"] = ("orbit", (flights[:, 0] * flights[:, 1] < 0).astype(np.int8))
    ds.attrs.update(title="no-slip bouncing ball on a floor", gamma=gamma, gravity=g, n_bounces=n_bounces)
    return annotate(ds)


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

    n_collisions = count(n_collisions, "n_collisions", minimum=2)
    wedge, wedge_state = wedge_orbit(phi, theta, ell, gamma, gravity=gravity)
    disks, disk_state = two_disk_orbit(disk_radius, disk_phi, gamma, theta=disk_theta, gravity=gravity)
    ds = orbit_set([wedge, disks], [s["position"] for s in (wedge_state, disk_state)],
                   [s["velocity"] for s in (wedge_state, disk_state)],
                   [s["spin"] for s in (wedge_state, disk_state)], max_collisions=n_collisions)
    R, c, s = float(disk_radius), math.cos(disk_phi), math.sin(disk_phi)
    q0 = np.array([[-ell * math.sin(phi), ell * math.cos(phi)], [-1.0 + R * c, R * s]])
    vertex = np.array([[0.0, 0.0], [0.0, R * s - (1.0 - R * c) * c / s]])
    geometry = {"q0_x": q0[:, 0], "q0_y": q0[:, 1], "q1_x": -q0[:, 0], "q1_y": q0[:, 1],
                "vertex_x": vertex[:, 0], "vertex_y": vertex[:, 1]}
    for name, values in geometry.items():
        ds[name] = ("orbit", values)
    ds["phi"] = ("orbit", np.array([phi, disk_phi], float))
    ds["theta"] = ("orbit", np.array([theta, disk_theta], float))
    ds = _label_orbits(ds, ["wedge", "tangential wedge"])
    ds.attrs.update(title="path-reversing 2-periodic orbits of a wedge and of a tangential wedge", gamma=gamma,
                    gravity=gravity, ell=ell, disk_radius=disk_radius)
    return annotate(ds)


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

    n_specular = count(n_specular, "n_specular")
    n_noslip = count(n_noslip, "n_noslip")
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
    ds["box_collisions"] = ("orbit", walls.sum(axis=1))
    ds["kind"] = ((), m.kind)
    ds["eigen_sum"] = ((), m.eigen_sum)                          # measured
    ds["eigen_sum_theory"] = ((), float(two_disk_eigen_sum(1.0 / radius, d, phi, gamma)))
    ds.attrs.update(title="two disks in a box: specular and no-slip orbits from one start", radius=radius,
                    phi=phi, gamma=gamma, box=[width, height], perturbation=perturbation,
                    n_specular=n_specular, n_noslip=n_noslip, periodic_position=list(state["position"]),
                    periodic_velocity=list(state["velocity"]), periodic_spin=state["spin"])
    return annotate(ds)


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
        ``q_{k+2} - q_k``, measured) along ``component``, ``drift_error`` (the
        largest deviation of one ``q_{k+2} - q_k`` from ``D``) and the bounce
        points' coordinates ``along_e1``, ``along_e2``.

    Raises
    ------
    ValueError
        For a start without drift (``v_T = gamma n x W_T``: no direction
        ``e1``), and as :func:`noslipsim.sphere3d.simulate_sphere`.
    """

    n_bounces = count(n_bounces, "n_bounces", minimum=3)
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
    ds["e1"] = (vec, e1)
    ds["e2"] = (vec, e2)
    ds["drift_theory"] = (vec, D)
    ds["drift"] = (vec, steps.mean(axis=0))
    ds["drift_error"] = ((), float(np.abs(steps - D).max()))
    ds["along_e1"] = ("collision", q @ e1)
    ds["along_e2"] = ("collision", q @ e2)
    ds.attrs.update(title="no-slip sphere bouncing on a plane", impact_speed=u, n_bounces=n_bounces)
    return annotate(ds)
