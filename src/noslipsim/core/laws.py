"""Collision laws in the collision frame of docs/conventions.md ("The collision frame").

At a boundary point with outward unit normal ``n`` and tangent ``t = J n``
(``n`` turned +90 degrees), write ``v_t = v . t`` and ``v_n = v . n``.  The
scaled spin is ``w = gamma R omega`` (counter-clockwise positive).

No-slip (Broomhead & Gutkin 1993; Cox & Feres 2016), with
``c = (1 - gamma^2)/(1 + gamma^2)`` and ``s = 2 gamma/(1 + gamma^2)``:

.. math::

    w^+ = -c w - s v_t, \\qquad v_t^+ = -s w + c v_t, \\qquad v_n^+ = -v_n .

It reverses the tangential velocity of the contact point, ``v_t + w/gamma``,
conserves ``|v|^2 + w^2`` and is an involution.  Specular keeps ``v_t`` and
``w`` and reverses ``v_n``.
"""
from .jit import jit
from .layout import NOSLIP


def noslip_coefficients(gamma):
    """Return ``(c, s)`` of the no-slip law for mass-distribution constant ``gamma >= 0``.

    ``c = cos(beta)``, ``s = sin(beta)`` with ``gamma = tan(beta/2)``; the rational form is exact at gamma = 0 and 1.
    """
    if gamma > 1e150:  # gamma^2 would overflow; c = -1 + O(1/gamma^2)
        return -1.0, 2.0 / gamma
    g2 = gamma * gamma
    return (1.0 - g2) / (1.0 + g2), 2.0 * gamma / (1.0 + g2)


@jit
def collide(law, c, s, vx, vy, w, nx, ny):
    """Post-collision ``(vx, vy, w)`` for incoming ``(vx, vy, w)`` at outward normal ``(nx, ny)``."""
    tx = -ny
    ty = nx
    vt = vx * tx + vy * ty
    vn = vx * nx + vy * ny
    if law == NOSLIP:
        w_new = -c * w - s * vt
        vt = -s * w + c * vt
        w = w_new
    vn = -vn
    return vt * tx + vn * nx, vt * ty + vn * ny, w
