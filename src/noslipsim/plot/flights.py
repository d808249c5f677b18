r"""Exact states at any times of an orbit, from its collision log: the flights, never a time step.

Between collisions ``k`` and ``k + 1`` the particle flies the scene's exact
flight from the state ``(q_k, v_k, w_k)`` that begins it
(:meth:`noslipsim.Scene.flight_states`): under a force the parabola

.. math::

    q(t) = q_k + v_k (t - t_k) + \tfrac12 a (t - t_k)^2, \quad v(t) = v_k + a (t - t_k), \quad w(t) = w_k,

the closed-form path of the isokinetic thermostat, or the cyclotron circle of
a magnetic field, so the state at any time is the flight evaluated from the
last collision before it (docs/conventions.md).  Animations (``noslipsim
animate``), the explorer (``noslipsim explore``) and orbit plots draw with
these, sample every curved flight along its curve (:func:`flight_samples`:
an arc drawn by its ends is a chord), and a frame is snapped onto a collision
time so the particle is drawn on the wall it hits.
"""
from __future__ import annotations

import numpy as np

__all__ = ["collision_frames", "flight_samples", "flight_states", "fly", "straight_flights"]


def straight_flights(nodes):
    """True if every flight of ``nodes`` is a straight line (no force, no field): its two ends draw it."""
    scene = nodes.get("scene")
    if scene is None:  # nodes built by hand: free fall under their force
        return tuple(nodes["force"]) == (0.0, 0.0)
    return scene.force == (0.0, 0.0) and scene.magnetic == 0.0


def fly(nodes, x, y, vx, vy, tau):
    """Position and velocity ``(x, y, vx, vy)`` after flights of ``tau`` from ``(x, y, vx, vy)`` (broadcast).

    The scene's exact flight when ``nodes`` carry it (``nodes['scene']``,
    :meth:`noslipsim.Scene.flight_states`: parabola, thermostat or cyclotron
    arc), else the parabola of ``nodes['force']`` (nodes built by hand, free
    fall only).
    """
    scene = nodes.get("scene")
    if scene is not None:
        return scene.flight_states(x, y, vx, vy, tau)
    ax, ay = nodes["force"]
    return (x + vx * tau + 0.5 * ax * tau ** 2, y + vy * tau + 0.5 * ay * tau ** 2, vx + ax * tau, vy + ay * tau)


def flight_samples(nodes, ends, points):
    """Times and positions along flights, ``points`` samples each (two, the ends, for straight flights).

    Parameters
    ----------
    nodes : dict
        ``t, x, y, vx, vy`` of the states that begin the flights (and ``scene``
        or ``force``, see :func:`fly`).
    ends : array_like
        The time each flight ends (the next collision, or where drawing stops).
    points : int
        Samples per curved flight (>= 2).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        ``t, x, y`` of shape ``(flights, m)``, ``m = 2`` for straight flights, else ``points``.
    """
    m = 2 if straight_flights(nodes) else int(points)
    t0 = np.asarray(nodes["t"], dtype=float)
    tau = np.clip(np.asarray(ends, dtype=float) - t0, 0.0, None)[:, None] * np.linspace(0.0, 1.0, m)[None, :]
    col = {k: np.asarray(nodes[k], dtype=float)[:, None] for k in ("x", "y", "vx", "vy")}
    x, y, _, _ = fly(nodes, col["x"], col["y"], col["vx"], col["vy"], tau)
    return t0[:, None] + tau, x, y


def flight_states(nodes, times):
    """Position, velocity and spin of one orbit at ``times``.

    Parameters
    ----------
    nodes : dict
        ``t, x, y, vx, vy, spin`` arrays of the states that begin each flight
        (start, then every collision; :func:`noslipsim.plot.orbit_nodes`),
        ``scene`` (whose exact flight is flown, :func:`fly`) or, for free
        fall only, ``force`` ``(a_x, a_y)``.
    times : array_like
        Times (any order) at or after the start, ``t >= nodes['t'][0]``.  Past
        the last collision the last flight continues.

    Returns
    -------
    dict
        ``x, y, vx, vy, spin`` arrays of the shape of ``times`` and ``flight``,
        the index of the node each state flies from.
    """
    t = np.asarray(times, dtype=float)
    t0 = np.asarray(nodes["t"], dtype=float)
    if t0.size == 0:
        raise ValueError("nodes: an orbit needs its start state")
    if (t < t0[0]).any():
        raise ValueError(f"times: must be >= the start time {t0[0]}, got {float(t.min())}")
    # the flight that contains t: the last node at or before it (a collision at exactly t starts its flight)
    k = np.searchsorted(t0, t, side="right") - 1
    x, y, vx, vy = fly(nodes, *(np.asarray(nodes[c], dtype=float)[k] for c in ("x", "y", "vx", "vy")), t - t0[k])
    return {"x": x, "y": y, "vx": vx, "vy": vy, "spin": np.asarray(nodes["spin"])[k], "flight": k}


def collision_frames(frame_times, collision_times):
    """Frame times with the frame nearest each collision moved onto it.

    A frame at ``t_f`` whose half-frame window ``[t_f - dt/2, t_f + dt/2)``
    holds a collision is drawn at the first such collision's exact time
    instead, so the particle touches the wall in that frame; every other frame
    keeps its time (the shift is at most half a frame, invisible in playback).

    Parameters
    ----------
    frame_times : array_like (F,)
        Evenly spaced, increasing frame times (spacing ``dt``).
    collision_times : array_like
        Collision times of one orbit, increasing.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        The times to draw, and a bool mask of the frames moved onto a collision.
    """
    f = np.asarray(frame_times, dtype=float)
    c = np.asarray(collision_times, dtype=float)
    out = f.copy()
    if f.size < 2 or c.size == 0:
        return out, np.zeros(f.size, bool)
    dt = f[1] - f[0]
    # the first collision at or after each window's start
    idx = np.searchsorted(c, f - 0.5 * dt, side="left")
    has = idx < c.size
    first = np.where(has, c[np.minimum(idx, c.size - 1)], np.inf)
    hit = has & (first < f + 0.5 * dt)
    out[hit] = first[hit]
    return out, hit
