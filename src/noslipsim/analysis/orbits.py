r"""The theorems' periodic orbits as ready-to-run starts.

Each function returns ``(scene, state)`` with
``state = {"position": (x, y), "velocity": (vx, vy), "spin": w}`` so that
``noslipsim.simulate(scene, **state, max_collisions=...)`` runs the orbit.  The
start is the exact state half-way (in time) along the flight that leaves the
first collision point ``q0``: strictly inside the table, as ``simulate``
requires.  Collision 0 of the run is therefore the far point ``q1``,
collision 1 the return to ``q0``, and the state after every second collision
repeats.

All orbits here are path reversing: at the far impact ``v_t = gamma w``, which
the no-slip law maps to the reversed state ``(-w, -v_t, -v_n)``, so the particle
retraces its path (docs/conventions.md for the frame: outward normal ``n``,
``t = J n``, spin counter-clockwise positive; docs/errata.md for the corrected
Theorem 2).  Derivations and the linear stability of these orbits:
docs/analysis.md.

Reference: J. Ahmed, T. Chumley, S. Cook, C. Cox, H. Grant, N. Petela,
B. Rothrock, R. Xhafaj, *Dynamics of the no-slip Galton board*, Theorems 1
and 2; C. Cox, R. Feres, H.-K. Zhang, *Stability of periodic orbits in no-slip
billiards*, Nonlinearity 31 (2018).
"""
from __future__ import annotations

import math

import numpy as np

from .. import tables, theory
from .._validate import finite_float, nonnegative, one_of
from ..core import layout
from .section import interior_log

__all__ = ["bounce_orbit", "two_disk_orbit", "wedge_noforce_orbit", "wedge_orbit"]

#: Relative size of ``v_t`` (against the speed) below which an impact counts as
#: perpendicular, the only path-reversing impact when ``gamma = 0``.
PERPENDICULAR_TOL = 1e-12

#: How close (relative to the table's scale) the first collision of a built
#: orbit must come to the intended far point ``q1``; a construction check.
LANDING_TOL = 1e-9

_OPENINGS = ("up", "down")
_WALLS = ("left", "right")


# ----------------------------------------------------------------------------- shared pieces
def _state(q0, v0, w0, force, tau):
    """The state half-way along the flight ``q0 + v0 t + a t^2/2`` of duration ``tau``."""
    a = np.asarray(force, dtype=float)
    h = 0.5 * tau
    q = np.asarray(q0, float) + np.asarray(v0, float) * h + 0.5 * a * h * h
    v = np.asarray(v0, float) + a * h
    return {"position": (float(q[0]), float(q[1])), "velocity": (float(v[0]), float(v[1])),
            "spin": float(w0)}


def _reversing_spin(v_arrival, n_out, gamma, where):
    r"""The spin ``w`` with ``v_t = gamma w`` at an impact (path reversal), ``t = J n``.

    ``gamma = 0`` reverses only a perpendicular impact (``v_t = 0``), with ``w = 0``.
    """
    t = np.array([-n_out[1], n_out[0]])
    vt = float(np.dot(v_arrival, t))
    if gamma == 0.0:
        if abs(vt) > PERPENDICULAR_TOL * float(np.hypot(*v_arrival)):
            raise ValueError(f"gamma: with gamma = 0 only a perpendicular impact reverses the path, but the "
                             f"impact at {where} has v_t = {vt:.6g}; use gamma > 0 or a perpendicular chord")
        return 0.0
    return vt / gamma


def _check_landing(scene, state, element, q1, what):
    """Run the built orbit to its first collision; it must land on ``element`` at ``q1``.

    A construction check: it turns a parameter combination whose first flight
    meets another piece of the table, or none, into a clear error.
    """
    log, stop = interior_log(scene, state["position"], state["velocity"], state["spin"], 1)
    tol = LANDING_TOL * max(1.0, scene.scale, float(np.abs(q1).max()))
    if len(log) == 0:
        raise ValueError(f"{what}: the flight from q0 misses the table and escapes "
                         f"(stop reason {stop!r}) instead of landing on q1 = {list(q1)}")
    hit = log[0, [layout.LOG_X, layout.LOG_Y]]
    el = int(log[0, layout.LOG_ELEMENT])
    if el != element or not np.hypot(*(hit - q1)) <= tol:
        raise ValueError(f"{what}: the flight from q0 hits element {el} at {hit.tolist()} before reaching "
                         f"q1 = {list(q1)} on element {element}")


# ----------------------------------------------------------------------------- two disks
def two_disk_orbit(radius, phi, gamma, *, theta=None, gravity=0.0):
    r"""The path-reversing 2-periodic orbit between two no-slip disks (with or without gravity).

    The table is :func:`noslipsim.tables.two_disks` (``radius``, centres
    ``(-1, 0)`` and ``(1, 0)``, open).  The orbit bounces between
    ``q0 = (-1 + R cos phi, R sin phi)`` on the left disk and its mirror image
    ``q1 = (1 - R cos phi, R sin phi)``, ``d = |q0 q1| = 2 - 2 R cos phi`` apart.
    The tangent lines at ``q0`` and ``q1`` form an upward wedge of half-angle
    ``phi`` (its full angle ``2 phi`` is the one of
    :func:`noslipsim.theory.two_disk_eigen_sum`).

    *Without force* (``gravity = 0``) the particle flies along the chord
    ``q0 -> q1`` at unit speed with spin

    .. math::

        w = \frac{v \sin\varphi}{\gamma},

    so that ``v_t = gamma w`` at ``q1`` (tangent ``t = J n = (sin phi, cos phi)``
    there).  *With gravity* ``g > 0`` (force ``(0, -g)``) it leaves ``q0`` at
    angle ``theta`` above the chord with the corrected Theorem 2 speed and spin
    (docs/errata.md, errata 1 and 2)

    .. math::

        v = \sqrt{\frac{g d}{\sin 2\theta}}, \qquad w = \frac{v \sin(\varphi - \theta)}{\gamma}.

    Parameters
    ----------
    radius : float
        Disk radius ``R`` in ``(0, 1)`` (curvature ``kappa = 1/R``; nondimensional,
        centre distance 2).
    phi : float
        Angle of ``q0`` above the horizontal, seen from the left centre, in
        ``[0, pi/2)`` (``phi >= pi/2`` would put ``q1`` on the far side of the
        right disk).
    gamma : float
        Mass-distribution constant ``>= 0``.  ``gamma = 0`` reverses only a
        perpendicular impact: ``phi = 0`` without force, ``theta = phi`` with it.
    theta : float, optional
        Launch angle above the chord, in ``(0, pi/2)``; required exactly when
        ``gravity > 0``.
    gravity : float
        ``g >= 0``; the force is ``(0, -g)``.

    Returns
    -------
    scene : Scene
        No-slip two-disk table (element 0 the left disk, 1 the right disk).
    state : dict
        ``position``, ``velocity``, ``spin``: the state half-way along the flight
        ``q0 -> q1``.  Collision 0 of ``simulate`` is ``q1``, collision 1 is ``q0``.

    Raises
    ------
    ValueError
        For parameters out of range, a missing or superfluous ``theta``, or
        ``gamma = 0`` with an oblique impact.

    Examples
    --------
    >>> scene, state = two_disk_orbit(0.5, 0.3, 2 ** -0.5)
    >>> orbit = ns.simulate(scene, **state, max_collisions=100)  # doctest: +SKIP
    """
    R = finite_float(radius, "radius")
    if not 0.0 < R < 1.0:
        raise ValueError(f"radius: must lie in (0, 1) (disks centred 2 apart must not touch), got {R}")
    phi = finite_float(phi, "phi")
    if not 0.0 <= phi < math.pi / 2:
        raise ValueError(f"phi: must lie in [0, pi/2), got {phi}; at phi >= pi/2 the chord q0 q1 would "
                         "meet the right disk on its far side")
    gamma = nonnegative(gamma, "gamma")
    g = finite_float(gravity, "gravity")
    if g < 0.0:
        raise ValueError(f"gravity: must be >= 0 (the force is (0, -gravity)), got {g}")
    if g > 0.0 and theta is None:
        raise ValueError("theta: the launch angle is required when gravity > 0")
    if g == 0.0 and theta is not None:
        raise ValueError("theta: only meaningful with gravity > 0 (without force the orbit follows the chord)")

    c, s = math.cos(phi), math.sin(phi)
    q0 = np.array([-1.0 + R * c, R * s])
    q1 = np.array([1.0 - R * c, R * s])
    d = 2.0 - 2.0 * R * c
    n_out_q1 = np.array([c, -s])  # out of the table, into the right disk
    scene = tables.two_disks(R, distance=2.0, gamma=gamma, force=(0.0, -g))
    if g == 0.0:
        v0 = np.array([1.0, 0.0])
        w0 = _reversing_spin(v0, n_out_q1, gamma, "q1")
        state = _state(q0, v0, w0, scene.force, d)
        what = "radius, phi"
    else:
        theta = finite_float(theta, "theta")
        if not 0.0 < theta < math.pi / 2:
            raise ValueError(f"theta: must lie in (0, pi/2), got {theta}")
        v = theory.projectile_speed(g, d, theta)
        v0 = v * np.array([math.cos(theta), math.sin(theta)])
        if gamma > 0.0 and phi > 0.0:
            # the tangential wedge at q0, q1 is theory's upward wedge, q0 on its left wall
            _, v_w, w0 = theory.wedge_two_periodic_start(phi, theta, d / (2.0 * s), gamma, g=g,
                                                         opening="up", wall="left")
            v0 = v_w
        else:  # phi = 0 (parallel tangents) or gamma = 0: the same condition v_t = gamma w at q1
            w0 = _reversing_spin(v * np.array([math.cos(theta), -math.sin(theta)]), n_out_q1, gamma, "q1")
        state = _state(q0, v0, w0, scene.force, d / v0[0])
        what = "radius, phi, theta"
    _check_landing(scene, state, 1, q1, what)
    return scene, state


# ----------------------------------------------------------------------------- wedges
def wedge_orbit(phi, theta, ell, gamma, *, gravity=1.0, opening="up", wall="left"):
    r"""The path-reversing 2-periodic orbit of a no-slip wedge under gravity (Theorem 2, corrected).

    The wedge is :func:`noslipsim.tables.wedge` (vertex at the origin, bisector
    vertical, half-angle ``phi``, force ``(0, -g)``).  The orbit leaves the
    point ``q0`` at distance ``ell`` from the vertex on ``wall`` at angle
    ``theta`` above the horizontal and lands on the opposite point ``q1``
    (``d = 2 ell sin phi`` away), with :func:`noslipsim.theory.wedge_two_periodic_start`'s
    speed and spin

    .. math::

        v = \sqrt{\frac{g d}{\sin 2\theta}}, \qquad
        w_0 = \frac{s_x\, v \sin(s_y \varphi - \theta)}{\gamma}

    (``s_x = +1`` from the left wall, ``s_y = +1`` opening up; docs/errata.md).

    Parameters
    ----------
    phi : float
        Half-angle in ``(0, pi/2)``.
    theta : float
        Launch angle in ``(0, pi/2)``; opening down also ``theta < pi/2 - phi``.
    ell : float
        Distance ``> 0`` of ``q0`` from the vertex.
    gamma : float
        Mass-distribution constant ``> 0``.
    gravity : float
        ``g > 0``; the force is ``(0, -g)`` whatever the opening.
    opening : {'up', 'down'}
    wall : {'left', 'right'}
        Wall of ``q0`` (element 0 or 1).

    Returns
    -------
    scene, state
        As :func:`two_disk_orbit`: the state half-way along the flight ``q0 -> q1``.
    """
    one_of(opening, _OPENINGS, "opening")
    one_of(wall, _WALLS, "wall")
    q0, v0, w0 = theory.wedge_two_periodic_start(phi, theta, ell, gamma, g=gravity, opening=opening, wall=wall)
    g = float(gravity)
    scene = tables.wedge(float(phi), opening=opening, gamma=float(gamma), force=(0.0, -g))
    q1 = np.array([-q0[0], q0[1]])
    state = _state(q0, v0, w0, scene.force, abs(2.0 * q0[0] / v0[0]))
    _check_landing(scene, state, 1 if wall == "left" else 0, q1, "phi, theta, ell")
    return scene, state


def wedge_noforce_orbit(phi, ell, gamma, *, speed=1.0, opening="up", wall="left"):
    r"""The horizontal path-reversing 2-periodic orbit of a force-free no-slip wedge.

    A horizontal flight between the points at distance ``ell`` from the vertex
    on the two walls of :func:`noslipsim.tables.wedge` (no force) is
    2-periodic iff ``v_t = gamma w`` at the far wall, i.e. (docs/errata.md,
    erratum 3, :func:`noslipsim.theory.wedge_noforce_gamma`)

    .. math::

        \gamma = s_y \frac{v_x}{w} \sin\varphi

    (``s_y = +1`` opening up).  These orbits are elliptic
    (Cox, Feres & Zhang 2018; docs/analysis.md).

    Parameters
    ----------
    phi : float
        Half-angle in ``(0, pi/2)``.
    ell : float
        Distance ``> 0`` of the launch point from the vertex.
    gamma : float
        Mass-distribution constant ``> 0``.
    speed : float
        ``|v_x| > 0``.
    opening : {'up', 'down'}
    wall : {'left', 'right'}
        Wall of the launch point ``q0`` (element 0 or 1); the flight goes
        towards the other wall.

    Returns
    -------
    scene, state
        As :func:`two_disk_orbit`.
    """
    phi = finite_float(phi, "phi")
    if not 0.0 < phi < math.pi / 2:
        raise ValueError(f"phi: wedge half-angle must lie in (0, pi/2), got {phi}")
    ell = finite_float(ell, "ell")
    if not ell > 0.0:
        raise ValueError(f"ell: must be > 0, got {ell}")
    gamma = nonnegative(gamma, "gamma")
    if gamma == 0.0:
        raise ValueError("gamma: must be > 0 (a horizontal impact on a tilted wall is never "
                         "perpendicular, so gamma = 0 has no path-reversing orbit here)")
    speed = finite_float(speed, "speed")
    if not speed > 0.0:
        raise ValueError(f"speed: must be > 0, got {speed}")
    one_of(opening, _OPENINGS, "opening")
    one_of(wall, _WALLS, "wall")
    sx = 1.0 if wall == "left" else -1.0
    sy = 1.0 if opening == "up" else -1.0
    scene = tables.wedge(phi, opening=opening, gamma=gamma, force=(0.0, 0.0))
    q0 = np.array([-sx * ell * math.sin(phi), sy * ell * math.cos(phi)])
    q1 = np.array([-q0[0], q0[1]])
    far = 1 if wall == "left" else 0
    v0 = np.array([sx * speed, 0.0])
    n_out = -np.asarray(scene.elements[far].normal)
    w0 = _reversing_spin(v0, n_out, gamma, "q1")
    state = _state(q0, v0, w0, scene.force, 2.0 * ell * math.sin(phi) / speed)
    _check_landing(scene, state, far, q1, "phi, ell")
    return scene, state


# ----------------------------------------------------------------------------- half plane
def bounce_orbit(vx, u, gamma, *, gravity=1.0):
    r"""The 2-periodic bouncing-ball orbit on a no-slip floor (Theorem 1).

    Table ``y > 0`` (:func:`noslipsim.tables.half_plane`), force ``(0, -g)``.  The
    velocities are 2-periodic for every start; the orbit is 2-periodic iff
    ``v_x = gamma w`` (otherwise it drifts by
    :func:`noslipsim.theory.half_plane_drift` per two bounces), so

    .. math::

        w = \frac{v_x}{\gamma}.

    The start is the apex of a flight, ``(0, u^2/(2 g))``, with velocity
    ``(v_x, 0)``; the ball bounces at ``x = +- v_x u / g``.

    Parameters
    ----------
    vx : float
        Horizontal velocity on the flight leaving ``q0 = (-v_x u/g, 0)``.
    u : float
        Vertical take-off (and impact) speed ``> 0``.
    gamma : float
        Mass-distribution constant ``>= 0``; ``gamma = 0`` requires ``vx = 0``
        (only the vertical bounce reverses).
    gravity : float
        ``g > 0``.

    Returns
    -------
    scene, state
        The half plane and the apex state; collision 0 is at ``x = v_x u / g``.
    """
    vx = finite_float(vx, "vx")
    u = finite_float(u, "u")
    if not u > 0.0:
        raise ValueError(f"u: the vertical take-off speed must be > 0, got {u}")
    gamma = nonnegative(gamma, "gamma")
    g = finite_float(gravity, "gravity")
    if not g > 0.0:
        raise ValueError(f"gravity: must be > 0, got {g}")
    scene = tables.half_plane(gamma=gamma, gravity=g)
    w = _reversing_spin(np.array([vx, -u]), np.array([0.0, -1.0]), gamma, "the floor")
    state = {"position": (0.0, 0.5 * u * u / g), "velocity": (vx, 0.0), "spin": float(w)}
    _check_landing(scene, state, 0, np.array([vx * u / g, 0.0]), "vx, u")
    return scene, state
