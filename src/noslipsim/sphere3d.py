"""A rough sphere bouncing on a horizontal plane under gravity (the paper's 3D bouncing figure).

The three-dimensional no-slip law (Cox & Feres 2016; docs/conventions.md) for a
sphere on the plane ``z = 0`` with ``n = e_z`` pointing towards the sphere,
``sigma = n x W_T`` and ``W = gamma R omega`` the scaled spin:

.. math::

    v_n^+ = -v_n, \\quad W_n^+ = W_n, \\quad
    v_T^+ = c\\, v_T - s\\, \\sigma, \\quad
    \\sigma^+ = -c\\, \\sigma - s\\, v_T, \\quad W_T^+ = \\sigma^+ \\times n,

``c = (1 - gamma^2)/(1 + gamma^2)``, ``s = 2 gamma/(1 + gamma^2)``.  Velocities
are 2-periodic; ``v_T - gamma n x W_T`` is the same on every flight and the
position drifts by ``D = 4 u (v_T - gamma n x W_T) / (g (1 + gamma^2))`` per two
bounces (``u`` the vertical impact speed), so the motion is 2-periodic iff
``v_T = gamma n x W_T`` (the paper's Theorem 1 in three dimensions).

Motion in the ``x``-``z`` plane with ``W = (0, -w, 0)`` is the planar bouncing
ball of :func:`noslipsim.tables.half_plane` with spin ``w`` (planar ``(x, y)``
is ``(x, z)`` here; counter-clockwise in that plane is rotation about ``-e_y``).
"""
from __future__ import annotations

import json
import math

import numpy as np
import xarray as xr

from ._metadata import annotate
from ._unit import unit_pair
from ._validate import finite_float, finite_vector
from ._version import __version__
from .core import sphere3d as kernel
from .core.laws import noslip_coefficients

#: gamma of a uniform ball, sqrt(2/5).
UNIFORM_BALL = math.sqrt(2.0 / 5.0)

COMPONENTS = ("x", "y", "z")

_COLUMNS = {
    # name: (log column, vector?); long names and units: noslipsim._metadata
    "time": (kernel.LOG_T, False),
    "position": (kernel.LOG_Q, True),
    "velocity": (kernel.LOG_V, True),
    "spin": (kernel.LOG_W, True),
    "velocity_in": (kernel.LOG_V_IN, True),
    "spin_in": (kernel.LOG_W_IN, True),
}


def _check_n_bounces(n_bounces):
    if isinstance(n_bounces, bool) or not isinstance(n_bounces, (int, np.integer)):
        raise ValueError(f"n_bounces: expected an integer, got {n_bounces!r}")
    if n_bounces < 0:
        raise ValueError(f"n_bounces: must be >= 0, got {n_bounces}")
    return int(n_bounces)


def simulate_sphere(position, velocity, spin, gamma=UNIFORM_BALL, gravity=1.0, n_bounces=10):
    """Bounce a rough sphere on the plane ``z = 0`` exactly, bounce by bounce.

    Parameters
    ----------
    position : (float, float, float)
        Start ``(x, y, z)`` of the centre, ``z > 0`` (nondimensional; the radius is negligible).
    velocity : (float, float, float)
        Initial velocity ``v``.
    spin : (float, float, float)
        Initial scaled spin ``W = gamma R omega`` (a velocity; right-handed).
    gamma : float
        Mass-distribution constant ``sqrt(I / (m R^2)) >= 0``; ``sqrt(2/5)`` for a
        uniform ball, 0 for a point mass (the spin then flips its tangential part).
    gravity : float
        ``g > 0``: the acceleration is ``(0, 0, -g)``.
    n_bounces : int
        Number of bounces to record.

    Returns
    -------
    xarray.Dataset
        Dims ``collision`` and ``component`` (``'x', 'y', 'z'``): ``time``,
        ``position``, ``velocity`` and ``spin`` just after each bounce,
        ``velocity_in`` and ``spin_in`` just before.  Every variable has
        ``long_name`` and ``units`` (``'1'``, nondimensional; docs/datasets.md).

    Raises
    ------
    ValueError
        Naming the offending field: non-finite or mis-shaped vectors, ``z <= 0``,
        ``gamma < 0``, ``gravity <= 0``, ``n_bounces`` not a non-negative integer.
    """
    q = finite_vector(position, "position", size=3)
    v = finite_vector(velocity, "velocity", size=3)
    w = finite_vector(spin, "spin", size=3)
    if not q[2] > 0.0:
        raise ValueError(f"position: z must be > 0 (above the plane), got {q[2]}")
    gamma = finite_float(gamma, "gamma")
    if gamma < 0.0:
        raise ValueError(f"gamma: must be >= 0, got {gamma}")
    gravity = finite_float(gravity, "gravity")
    if not gravity > 0.0:
        raise ValueError(f"gravity: must be > 0, got {gravity}")
    n_bounces = _check_n_bounces(n_bounces)
    c, s = unit_pair(*noslip_coefficients(gamma))
    log = np.zeros((n_bounces, kernel.N_LOG))
    kernel.run_sphere(c, s, gravity, *q, *v, *w, log)
    return _dataset(log, q, v, w, gamma, gravity)


def _dataset(log, q, v, w, gamma, gravity):
    data = {}
    for name, (col, vector) in _COLUMNS.items():
        if vector:
            data[name] = (("collision", "component"), log[:, col:col + 3].copy())
        else:
            data[name] = (("collision",), log[:, col].copy())
    coords = {"collision": ("collision", np.arange(len(log))), "component": ("component", list(COMPONENTS))}
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(
        title="noslipsim rough sphere bouncing on a plane",
        source=f"noslipsim {__version__}",
        law="no-slip",
        gamma=gamma,
        gravity=gravity,
        start=json.dumps(dict(position=q.tolist(), velocity=v.tolist(), spin=w.tolist())),
    )
    return annotate(ds)
