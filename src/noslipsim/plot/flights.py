r"""Exact states at any times of an orbit, from its collision log: the flights, never a time step.

Between collisions ``k`` and ``k + 1`` the particle flies on

.. math::

    q(t) = q_k + v_k (t - t_k) + \tfrac12 a (t - t_k)^2, \quad v(t) = v_k + a (t - t_k), \quad w(t) = w_k,

so the state at any time is the flight formula evaluated from the last
collision before it (docs/conventions.md).  Animations (``noslipsim animate``)
and the explorer (``noslipsim explore``) draw frames with these, and snap a
frame onto a collision time so the particle is drawn on the wall it hits.
"""
from __future__ import annotations

import numpy as np

__all__ = ["collision_frames", "flight_states"]


def flight_states(nodes, times):
    """Position, velocity and spin of one orbit at ``times``.

    Parameters
    ----------
    nodes : dict
        ``t, x, y, vx, vy, spin`` arrays of the states that begin each flight
        (start, then every collision; :func:`noslipsim.plot.orbit_nodes`) and
        ``force`` ``(a_x, a_y)``.
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
    tau = t - t0[k]
    ax, ay = nodes["force"]
    return {
        "x": nodes["x"][k] + nodes["vx"][k] * tau + 0.5 * ax * tau ** 2,
        "y": nodes["y"][k] + nodes["vy"][k] * tau + 0.5 * ay * tau ** 2,
        "vx": nodes["vx"][k] + ax * tau,
        "vy": nodes["vy"][k] + ay * tau,
        "spin": np.asarray(nodes["spin"])[k],
        "flight": k,
    }


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
