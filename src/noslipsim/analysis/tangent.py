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
from .section import boundary_frames, require_free_fall


class CornerError(ValueError):
    """The orbit goes through a corner, where the return map has no derivative."""


def check_no_corner(log, what="orbit"):
    """Raise :class:`CornerError` if any logged collision is a corner collision."""
    corner = np.flatnonzero(log[:, layout.LOG_CORNER] != 0.0)
    if corner.size:
        k = int(corner[0])
        before = int(log[k - 1, layout.LOG_ELEMENT]) if k else "?"
        raise CornerError(f"{what}: collision {k} is a corner collision (two elements at once, elements {before} "
                          f"and {int(log[k, layout.LOG_ELEMENT])}); the return map has no derivative there, "
                          "so its monodromy is undefined")


#: Flights processed per vectorised pass.  Arrays of this many floats (64 KiB)
#: come from the allocator's pool; much larger temporaries are fresh memory maps
#: whose page faults cost ~10x the arithmetic on this kind of host (measured:
#: 0.2 ns per element-operation up to 16k elements, 2-3 ns from 32k on).
CHUNK = 8192


def _chunk_entries(scene: Scene, log):
    r"""Jacobians of the maps between consecutive logged collisions, entry-major: ``(3, 3, N - 1)``.

    ``E[:, :, i]`` maps ``(ds, dw, dv_t)`` just after collision ``i`` to the
    same coordinates just after collision ``i + 1`` (order: arclength, spin,
    tangential velocity; :mod:`noslipsim.analysis.section` for the frame).
    Entry-major storage keeps every operation a flat vectorised one.

    The five steps of the module docstring are written out per column.  With
    ``C = n_1 . n_0 = t_1 . t_0`` and ``S = t_1 . n_0 = -n_1 . t_0``, a departure
    ``(dl, dv = alpha t_0 + beta n_0)`` flies to ``dq = g_t t_0 + g_n n_0``
    (``g_t = dl + tau alpha``, ``g_n = tau beta``) and arrives with

    .. math::

        dl_1 = t_1 \cdot dq - \frac{v_t^-}{v_n^-}\, n_1 \cdot dq, \qquad
        dv_t^- = t_1 \cdot dv - \frac{a \cdot t_1}{v_n^-}\, n_1 \cdot dq - k_1 v_n^- dl_1,

    where the three basis directions depart with ``(dl, alpha, beta)`` =
    ``(sigma_0, v_n k_0 sigma_0, (a . t_0 / v_n - v_t k_0) sigma_0)`` for ``ds``,
    ``(0, 0, -w/v_n)`` for ``dw`` and ``(0, 1, -v_t/v_n)`` for ``dv_t``.
    """
    # the log's columns are strided; every later operation runs on contiguous copies
    cols = np.array(np.asarray(log, dtype=float).T[:layout.LOG_CORNER])
    _, _, n, turn, sigma = boundary_frames(scene, cols[layout.LOG_ELEMENT].astype(np.int64), cols[layout.LOG_S])
    ax, ay = scene.force
    nx, ny = np.array(n[:, 0]), np.array(n[:, 1])
    n0x, n0y, n1x, n1y = nx[:-1], ny[:-1], nx[1:], ny[1:]
    C = n1x * n0x + n1y * n0y
    S = n1x * n0y - n1y * n0x
    vx0, vy0, w0 = cols[layout.LOG_VX, :-1], cols[layout.LOG_VY, :-1], cols[layout.LOG_W, :-1]
    vx1, vy1 = cols[layout.LOG_VX_IN, 1:], cols[layout.LOG_VY_IN, 1:]
    vt0 = vy0 * n0x - vx0 * n0y          # t = J n = (-n_y, n_x)
    vn0 = vx0 * n0x + vy0 * n0y          # < 0: leaving into the table
    vt1 = vy1 * n1x - vx1 * n1y
    vn1 = vx1 * n1x + vy1 * n1y          # > 0: arriving at the wall
    at0 = ay * n0x - ax * n0y
    at1 = ay * n1x - ax * n1y
    k0, k1, s0, s1 = turn[:-1], turn[1:], sigma[:-1], sigma[1:]
    tau = np.diff(cols[layout.LOG_T])
    slip = vt1 / vn1                      # hit-time correction along the new tangent
    pull = at1 / vn1                      # the force during that correction
    bend = k1 * vn1                       # the new tangent turning along the boundary

    def arrive(dl, alpha, beta):
        """``(ds_1, dv_t^-)`` at the next collision for a departure ``(dl, alpha t_0 + beta n_0)``."""
        gt = dl + tau * alpha
        gn = tau * beta
        nq = C * gn - S * gt
        dl1 = (C * gt + S * gn) - slip * nq
        return s1 * dl1, (C * alpha + S * beta) - pull * nq - bend * dl1

    inv_vn0 = 1.0 / vn0
    E = np.empty((3, 3, len(tau)))
    E[0, 0], dvt_s = arrive(s0, vn0 * k0 * s0, (at0 * inv_vn0 - vt0 * k0) * s0)
    E[0, 1], dvt_w = arrive(0.0, 0.0, -w0 * inv_vn0)
    E[0, 2], dvt_v = arrive(0.0, 1.0, -vt0 * inv_vn0)
    if scene.mixed_laws:  # each collision by the law of its element: no-slip's T or specular's identity
        c, s = scene.noslip_coefficients
        noslip = np.array([law == "no-slip" for law in scene.element_laws])[cols[layout.LOG_ELEMENT, 1:]
                                                                              .astype(np.int64)]
        E[1, 0], E[2, 0] = np.where(noslip, -s * dvt_s, 0.0), np.where(noslip, c * dvt_s, dvt_s)
        E[1, 1], E[2, 1] = np.where(noslip, -c - s * dvt_w, 1.0), np.where(noslip, -s + c * dvt_w, dvt_w)
        E[1, 2], E[2, 2] = np.where(noslip, -s * dvt_v, 0.0), np.where(noslip, c * dvt_v, dvt_v)
    elif scene.any_noslip:  # (dw, dv_t) -> T (dw, dv_t), T = [[-c, -s], [-s, c]]
        c, s = scene.noslip_coefficients
        E[1, 0], E[2, 0] = -s * dvt_s, c * dvt_s
        E[1, 1], E[2, 1] = -c - s * dvt_w, -s + c * dvt_w
        E[1, 2], E[2, 2] = -s * dvt_v, c * dvt_v
    else:  # specular: spin unchanged, v_t read in the new frame
        E[1] = [[0.0], [1.0], [0.0]]
        E[2, 0], E[2, 1], E[2, 2] = dvt_s, dvt_w, dvt_v
    return E


def _chunks(log):
    """Overlapping row ranges ``[a, b]`` of the log, each holding at most ``CHUNK`` flights."""
    n = len(log) - 1
    return [(a, min(a + CHUNK, n)) for a in range(0, n, CHUNK)]


def step_entries(scene: Scene, log):
    """All step Jacobians of a log, entry-major ``(3, 3, N - 1)`` (see :func:`_chunk_entries`)."""
    require_free_fall(scene, "the tangent map")
    log = np.asarray(log, dtype=float)
    E = np.empty((3, 3, max(len(log) - 1, 0)))
    for a, b in _chunks(log):
        E[:, :, a:b] = _chunk_entries(scene, log[a:b + 1])
    return E


def step_jacobians(scene: Scene, log):
    """The step Jacobians of :func:`step_entries` as a stack of matrices, ``(N - 1, 3, 3)``."""
    return np.moveaxis(step_entries(scene, log), -1, 0)


def log_product(scene: Scene, log):
    """``J_{N-2} ... J_0``: the Jacobian from the first to the last logged collision (chunk by chunk)."""
    require_free_fall(scene, "the tangent map")
    log = np.asarray(log, dtype=float)
    M = np.eye(3)
    for a, b in _chunks(log):
        M = chain(_chunk_entries(scene, log[a:b + 1])) @ M
    return M


def log_block_products(scene: Scene, log, block):
    """Products of consecutive blocks of ``block`` step Jacobians of a log, ``(n_blocks, 3, 3)``.

    A tail shorter than ``block`` is dropped.
    """
    require_free_fall(scene, "the tangent map")
    log = np.asarray(log, dtype=float)
    per = max(1, CHUNK // block) * block
    n = (len(log) - 1) // block * block
    out = [chain_blocks(_chunk_entries(scene, log[a:min(a + per, n) + 1]), block) for a in range(0, n, per)]
    return np.concatenate(out) if out else np.zeros((0, 3, 3))


def _multiply(later, earlier):
    """Entry-major 3x3 products along the trailing axes: ``later @ earlier`` for each column."""
    return np.einsum("ij...,jk...->ik...", later, earlier)


def chain(entries):
    """The product ``J_{m-1} ... J_0`` of entry-major Jacobians ``(3, 3, m)``, by pairwise (tree) reduction.

    ``log2(m)`` vectorised levels instead of ``m`` Python-level products.
    """
    E = np.asarray(entries)
    if E.shape[-1] == 0:
        return np.eye(3)
    while E.shape[-1] > 1:
        m = E.shape[-1]
        odd = E[..., -1:] if m % 2 else None
        E = _multiply(E[..., 1:m - m % 2:2], E[..., 0:m - m % 2:2])
        if odd is not None:
            E = np.concatenate([E, odd], axis=-1)
    return np.ascontiguousarray(E[..., 0])


def chain_blocks(entries, block):
    """Products of consecutive blocks of ``block`` Jacobians: ``(m // block, 3, 3)`` (a short tail is dropped)."""
    E = np.asarray(entries)
    nb = E.shape[-1] // block
    B = E[..., : nb * block].reshape(3, 3, nb, block)
    while B.shape[-1] > 1:
        m = B.shape[-1]
        odd = B[..., -1:] if m % 2 else None
        B = _multiply(B[..., 1:m - m % 2:2], B[..., 0:m - m % 2:2])
        if odd is not None:
            B = np.concatenate([B, odd], axis=-1)
    return np.moveaxis(B[..., 0], -1, 0)
