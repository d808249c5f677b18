"""A rough (no-slip) sphere bouncing on the horizontal plane ``z = 0`` under gravity.

State: position ``q`` and velocity ``v`` in R^3 (``z`` up, the table is ``z > 0``)
and the scaled spin ``W = gamma R omega`` in R^3.  Between bounces
``q(t) = q + v t - g t^2 e_z / 2`` and ``W`` is constant.  At a bounce, with
``n = e_z`` the plane normal pointing towards the sphere and
``sigma = n x W_T`` (docs/conventions.md, "Three dimensions: a rough sphere on a plane"):

.. math::

    v_n^+ = -v_n, \\quad W_n^+ = W_n, \\quad
    v_T^+ = c\\, v_T - s\\, \\sigma, \\quad
    \\sigma^+ = -c\\, \\sigma - s\\, v_T, \\quad
    W_T^+ = \\sigma^+ \\times n,

with ``c = (1 - gamma^2)/(1 + gamma^2)`` and ``s = 2 gamma/(1 + gamma^2)``.  It
reverses the velocity ``v + (n x W)/gamma`` of the contact point ``q - R n``
and conserves ``|v|^2 + |W|^2``.  For ``n = e_z``: ``sigma = (-W_y, W_x, 0)``
and ``sigma x n = (sigma_y, -sigma_x, 0)``.

Arrays and floats only, like every kernel in core; the public wrapper is
:func:`noslipsim.sphere3d.simulate_sphere`.
"""
import math

from .jit import jit

#: Columns of the bounce log.
LOG_T = 0
LOG_Q = 1     # x, y, z at the bounce (z = 0 exactly)
LOG_V = 4     # vx, vy, vz just after
LOG_W = 7     # Wx, Wy, Wz just after
LOG_V_IN = 10  # vx, vy, vz just before
LOG_W_IN = 13  # Wx, Wy, Wz just before
N_LOG = 16


@jit
def time_to_plane(z, vz, g):
    """Positive root of ``z + vz t - g t^2/2 = 0`` (``z >= 0``, ``g > 0``), without cancellation."""
    r = math.sqrt(vz * vz + 2.0 * g * z)
    if vz >= 0.0:
        return (vz + r) / g
    return 2.0 * z / (r - vz)


@jit
def bounce(c, s, vx, vy, vz, wx, wy, wz):
    """Post-bounce ``(v, W)`` on the plane ``z = 0`` (normal ``e_z`` towards the sphere)."""
    sx = -wy  # sigma = n x W_T
    sy = wx
    vx_new = c * vx - s * sx
    vy_new = c * vy - s * sy
    sx_new = -c * sx - s * vx
    sy_new = -c * sy - s * vy
    return vx_new, vy_new, -vz, sy_new, -sx_new, wz  # W_T+ = sigma+ x n


@jit
def run_sphere(c, s, g, x, y, z, vx, vy, vz, wx, wy, wz, log):
    """Fill ``log`` (shape ``(n_bounces, N_LOG)``) with one row per bounce from a start above the plane.

    Times are measured from the start; positions are advanced flight by flight (each relative to the previous bounce)
    and the bounce point is put exactly on the plane.  The impact speed is ``sqrt(vz^2 + 2 g z)`` so that
    ``|v|^2 + 2 g z`` is kept to rounding.
    """
    t = 0.0
    for k in range(log.shape[0]):
        dt = time_to_plane(z, vz, g)
        vz_in = -math.sqrt(vz * vz + 2.0 * g * z)
        x += vx * dt
        y += vy * dt
        z = 0.0
        t += dt
        row = log[k]
        row[LOG_T] = t
        row[LOG_Q] = x
        row[LOG_Q + 1] = y
        row[LOG_Q + 2] = z
        row[LOG_V_IN] = vx
        row[LOG_V_IN + 1] = vy
        row[LOG_V_IN + 2] = vz_in
        row[LOG_W_IN] = wx
        row[LOG_W_IN + 1] = wy
        row[LOG_W_IN + 2] = wz
        vx, vy, vz, wx, wy, wz = bounce(c, s, vx, vy, vz_in, wx, wy, wz)
        row[LOG_V] = vx
        row[LOG_V + 1] = vy
        row[LOG_V + 2] = vz
        row[LOG_W] = wx
        row[LOG_W + 1] = wy
        row[LOG_W + 2] = wz
