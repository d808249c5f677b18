r"""Tangent dynamics on the boundary section: exact Jacobians of the collision-to-collision map.

Between two consecutive collisions ``i`` and ``i + 1`` of a logged orbit the map
sends the post-collision reduced state ``(s, w, v_t)`` at ``i`` (energy fixed)
to the post-collision reduced state at ``i + 1``.  Its Jacobian is the
composition of five exact linear maps (docs/analysis.md derives each):

1. *leave the boundary*: ``(ds, dw, dv_t) -> (dq, dv, dw)`` at the departure
   point, with ``dq = t dl``, ``dl = sigma ds``, the frame turning with the
   point (``dn = k t dl``, ``dt = -k n dl``) and ``dv_n`` from the energy,
   ``v_t dv_t + v_n dv_n + w dw = a . t dl``;
2. *fly* for the fixed time ``tau``: ``dq += tau dv`` (the force is constant,
   so the parabola's acceleration term has no variation);
3. *hit*: the hit time moves by ``dtau = -n_1 . dq / n_1 . v_1`` (implicit
   function theorem on the crossing ``n_1 . (q - q_1) = 0`` to first order),
   so ``dq_1 = dq + v_1 dtau`` (tangent to the boundary) and ``dv_1 = dv + a dtau``;
4. *read the new boundary coordinates*: ``dl_1 = t_1 . dq_1`` and
   ``dv_t^- = t_1 . dv_1 - k_1 v_n^- dl_1`` (the tangent turns along the
   boundary), ``ds_1 = sigma_1 dl_1``;
5. *collide*: ``(dw, dv_t) -> T (dw, dv_t)`` with the law's matrix
   ``T = [[-c, -s], [-s, c]]`` (no-slip) or the identity (specular).

Everything is evaluated from the collision log of the compiled engine with
vectorised numpy: one ``(3, 3)`` matrix per flight.
"""
from __future__ import annotations

import numpy as np

from ..core import layout
from ..scenes import Scene
from .section import boundary_frames


class CornerError(ValueError):
    """The orbit goes through a corner, where the return map has no derivative."""


def check_no_corner(log, what="orbit"):
    """Raise :class:`CornerError` if any logged collision is a corner collision."""
    corner = np.flatnonzero(log[:, layout.LOG_CORNER] != 0.0)
    if corner.size:
        k = int(corner[0])
        raise CornerError(f"{what}: collision {k} is a corner collision (two elements at once, elements "
                          f"{int(log[k - 1, layout.LOG_ELEMENT]) if k else '?'} and {int(log[k, layout.LOG_ELEMENT])}); "
                          "the return map has no derivative there, so its monodromy is undefined")


def step_jacobians(scene: Scene, log):
    """Jacobians of the maps between consecutive logged collisions, ``(N - 1, 3, 3)``.

    Row ``i`` maps ``(ds, dw, dv_t)`` just after collision ``i`` to the same
    coordinates just after collision ``i + 1`` (order: arclength, spin,
    tangential velocity; see :mod:`noslipsim.analysis.section` for the frame).

    Parameters
    ----------
    scene : Scene
        The scene the log was run in (geometry, law, force).
    log : ndarray (N, N_LOG)
        Collision log (``layout.LOG_*`` columns) without corner collisions.
    """
    log = np.asarray(log, dtype=float)
    element = log[:, layout.LOG_ELEMENT].astype(np.int64)
    _, t, n, turn, sigma = boundary_frames(scene, element, log[:, layout.LOG_S])
    ax, ay = scene.force
    noslip = scene.law_code == layout.NOSLIP
    c, s = scene.noslip_coefficients

    def col(a):  # an (N-1,) coefficient as a column, against the three basis directions
        return a[:, None]

    t0x, t0y, n0x, n0y = (col(a[:-1]) for a in (t[:, 0], t[:, 1], n[:, 0], n[:, 1]))
    t1x, t1y, n1x, n1y = (col(a[1:]) for a in (t[:, 0], t[:, 1], n[:, 0], n[:, 1]))
    k0, k1 = col(turn[:-1]), col(turn[1:])
    v0x, v0y, w0 = col(log[:-1, layout.LOG_VX]), col(log[:-1, layout.LOG_VY]), col(log[:-1, layout.LOG_W])
    v1x, v1y = col(log[1:, layout.LOG_VX_IN]), col(log[1:, layout.LOG_VY_IN])
    tau = col(np.diff(log[:, layout.LOG_T]))

    vt0 = v0x * t0x + v0y * t0y
    vn0 = v0x * n0x + v0y * n0y          # < 0: leaving into the table
    vn1 = v1x * n1x + v1y * n1y          # > 0: arriving at the wall

    # basis directions of the departure: columns (ds, dw, dv_t)
    e_s = np.array([[1.0, 0.0, 0.0]])
    dw = np.array([[0.0, 1.0, 0.0]])
    dvt = np.array([[0.0, 0.0, 1.0]])
    dl = col(sigma[:-1]) * e_s
    # 1. leave the boundary (energy fixes dv_n; the frame turns with the point)
    dvn = ((ax * t0x + ay * t0y) * dl - vt0 * dvt - w0 * dw) / vn0
    along = dvt + vn0 * k0 * dl
    normal = dvn - vt0 * k0 * dl
    dvx = along * t0x + normal * n0x
    dvy = along * t0y + normal * n0y
    # 2. fly for the logged time
    dqx = t0x * dl + tau * dvx
    dqy = t0y * dl + tau * dvy
    # 3. the hit time moves so that the end point stays on the boundary
    dtau = -(n1x * dqx + n1y * dqy) / vn1
    dqx = dqx + v1x * dtau
    dqy = dqy + v1y * dtau
    dvx = dvx + ax * dtau
    dvy = dvy + ay * dtau
    # 4. new boundary coordinates (pre-collision tangential velocity in the turned frame)
    dl1 = t1x * dqx + t1y * dqy
    dvt1 = t1x * dvx + t1y * dvy - k1 * vn1 * dl1
    dw1 = np.broadcast_to(dw, dvt1.shape)
    # 5. the collision law in the frame at the new point
    if noslip:
        dw1, dvt1 = -c * dw1 - s * dvt1, -s * dw1 + c * dvt1
    ds1 = col(sigma[1:]) * dl1
    return np.stack([ds1, dw1, dvt1], axis=1)


def chain(mats):
    """The product ``mats[-1] @ ... @ mats[0]`` of a stack ``(m, 3, 3)``, by pairwise (tree) reduction.

    ``log2(m)`` vectorised levels instead of ``m`` Python-level products.
    """
    m = np.asarray(mats)
    if len(m) == 0:
        return np.eye(3)
    while len(m) > 1:
        odd = m[-1:] if len(m) % 2 else None
        pairs = m[: len(m) - (len(m) % 2)]
        m = pairs[1::2] @ pairs[0::2]
        if odd is not None:
            m = np.concatenate([m, odd])
    return m[0]


def chain_blocks(mats, block):
    """Products of consecutive blocks of ``block`` matrices: ``(m // block, 3, 3)`` (a short tail is dropped)."""
    m = np.asarray(mats)
    nb = len(m) // block
    b = m[: nb * block].reshape(nb, block, 3, 3)
    while b.shape[1] > 1:
        width = b.shape[1]
        odd = b[:, -1:] if width % 2 else None
        pairs = b[:, : width - (width % 2)]
        b = pairs[:, 1::2] @ pairs[:, 0::2]
        if odd is not None:
            b = np.concatenate([b, odd], axis=1)
    return b[:, 0]
