r"""The boundary section: reduced coordinates ``(s, w, v_t)``, boundary frames, runs from a boundary state.

A post-collision state on element ``e`` is given by its arclength ``s``
(the kernel's coordinate, :func:`noslipsim.core.geometry.arclength`), the
scaled spin ``w`` and the tangential velocity ``v_t = v . t``; at fixed energy
``E = (|v|^2 + w^2)/2 - a . q`` the normal component follows,

.. math::

    v_n = -\sqrt{2 (E + a \cdot q(s)) - w^2 - v_t^2} \qquad (\text{into the table: } v \cdot n < 0),

with ``n`` the outward normal and ``t = J n`` (docs/conventions.md).  Along
the boundary the frame turns: moving a distance ``l`` along ``t``,

.. math::

    \frac{dn}{dl} = k\, t, \qquad \frac{dt}{dl} = -k\, n, \qquad \frac{ds}{dl} = \sigma = \pm 1,

with ``k = 0`` on lines and segments and ``k = -sigma_c / r`` on circles and
arcs (``sigma_c = +1`` for a scatterer, ``-1`` for a container); ``sigma``
says whether the kernel's ``s`` runs along ``t`` or against it.  Derivation:
docs/analysis.md.
"""
from __future__ import annotations

import math

import numpy as np

from .._engine.run import run_orbits
from .._engine.table import kernel_table
from ..core import layout
from ..core.batch import F_NREC, F_STOP
from ..scenes import Scene
from ..simulate import check_limits, check_start, run_one

#: What computes a Lyapunov exponent for any flight, for the free-fall tools' refusal to say.
TWIN_LYAPUNOV = "noslipsim.analysis.twin_lyapunov (twin orbits) serves every flight"


def require_free_fall(scene: Scene, what, instead=""):
    """Refuse a thermostatted or magnetic scene by name: ``what`` assumes parabolic flights (energy ``|v|^2/2 - a.q``).

    The isokinetic thermostat (``Scene.thermostat``) and a magnetic field
    (``Scene.magnetic``) bend flights along other paths; the tangent maps and
    the energy-surface coordinates here are derived for free fall only.
    ``instead``: what serves such a scene, appended to the message.
    """
    tail = f"; {instead}" if instead else ""
    if scene.thermostat is not None and scene.force != (0.0, 0.0):
        raise ValueError(f"scene: {what} is derived for free fall under the force; it does not support "
                         f"thermostat {scene.thermostat!r}{tail}")
    if scene.magnetic != 0.0:
        raise ValueError(f"scene: {what} is derived for free fall under the force; it does not support "
                         f"a magnetic field (magnetic = {scene.magnetic}){tail}")


def boundary_frames(scene: Scene, element, s):
    """Geometry at boundary points given by element index and arclength, vectorised.

    Parameters
    ----------
    scene : Scene
    element : int array (N,)
        Element indices.
    s : float array (N,)
        Kernel arclength coordinates on those elements.

    Returns
    -------
    point : (N, 2)
        The boundary point, in the element's own coordinates (cell 0 of a lattice).
    t, n : (N, 2)
        Tangent ``t = J n`` and outward unit normal ``n``.
    turn : (N,)
        ``k`` with ``dn/dl = k t`` along ``t`` (0 on straight pieces, ``-sigma_c/r`` on circles).
    sigma : (N,)
        ``ds/dl``, +1 or -1.
    """
    kernel_table(scene)  # s is the compiled engine's coordinate: refuse a scene it does not pack
    e = np.asarray(element, dtype=np.int64)
    s = np.asarray(s, dtype=float)
    N = len(e)
    point = np.empty((N, 2))
    n = np.empty((N, 2))
    turn = np.empty(N)
    sigma = np.empty(N)
    # one pass per element (a table has few): each piece's formula on its own collisions only
    for k in np.flatnonzero(np.bincount(e, minlength=len(scene.elements))):
        idx = np.flatnonzero(e == k)
        if len(idx) == N:  # one element only: plain slices, no gather or scatter
            idx = slice(None)
        point[idx], n[idx], turn[idx], sigma[idx] = scene.elements[k].frame_at(s[idx])
    t = np.empty_like(n)
    t[:, 0] = -n[:, 1]
    t[:, 1] = n[:, 0]
    return point, t, n, turn, sigma


def boundary_length(scene: Scene, element):
    """Length of element ``element`` (``inf`` for lines; the arclength period of a full circle)."""
    return scene.elements[int(element)].length()


def wrap_difference(scene: Scene, element, ds):
    """``ds`` reduced to ``(-L/2, L/2]`` on a full circle of circumference ``L`` (other kinds unchanged)."""
    return scene.elements[int(element)].wrap_arclength(ds)


# ----------------------------------------------------------------------------- runs
def interior_log(scene: Scene, position, velocity, spin, n):
    """Collision log (``layout.LOG_*`` columns) of the orbit from an interior start, up to ``n`` collisions.

    Returns ``(log, stop_reason)``; positions unfolded, cells absolute.
    """
    q, v, w = check_start(scene, position, velocity, spin)
    n, _ = check_limits(n, math.inf)
    rec = np.zeros((n, layout.N_LOG))
    _, stop, _, n_rec, _, _ = run_one(scene, q, v, w, n, math.inf, -math.inf, layout.RECORD_LOG, rec)
    return rec[:n_rec], layout.STOP_REASONS[stop]


def boundary_log(scene: Scene, element, q, v, w, n):
    """Collision log of the orbit leaving boundary point ``q`` of ``element`` (cell 0) with ``(v, w)``.

    The start is treated as just reflected by ``element`` (its ``t = 0`` root
    is deflated by the kernel).  On a lattice ``q`` lies on the element as
    written (its copy of cell 0), which the kernel runs from cell 0 even where
    the point lies in a neighbouring parallelogram (a disk reaching out of its
    cell).  Returns ``(log, stop_reason)``.
    """
    rec = np.zeros((1, n, layout.N_LOG))
    table = kernel_table(scene)
    final = run_orbits(table, [[float(q[0]), float(q[1]), float(v[0]), float(v[1]), float(w)]],
                       max_collisions=n, start_elements=[int(element)], mode=layout.RECORD_LOG, rec=rec,
                       ceilings=[table.top])[0]  # cell 0: its origin is the scene's
    return rec[0, :int(final[F_NREC])], layout.STOP_REASONS[int(final[F_STOP])]


# ----------------------------------------------------------------------------- conversions
def reduced_from_log(scene: Scene, log):
    """``(element, s, w, v_t)`` of the post-collision states of a log (arrays)."""
    e = log[:, layout.LOG_ELEMENT].astype(np.int64)
    s = log[:, layout.LOG_S]
    _, t, _, _, _ = boundary_frames(scene, e, s)
    vt = log[:, layout.LOG_VX] * t[:, 0] + log[:, layout.LOG_VY] * t[:, 1]
    return e, s, log[:, layout.LOG_W].copy(), vt


def energy_at(scene: Scene, point, velocity, spin):
    """``E = (|v|^2 + w^2)/2 - a . q`` with ``q`` in the element's own (cell-0) coordinates."""
    require_free_fall(scene, "energy_at")
    ax, ay = scene.force
    return 0.5 * (velocity[0] ** 2 + velocity[1] ** 2 + spin ** 2) - (ax * point[0] + ay * point[1])


def state_from_reduced(scene: Scene, element, s, w, vt, energy):
    """The post-collision phase-space state ``(q, v, w)`` of reduced coordinates at energy ``energy``.

    Returns ``None`` where ``(w, v_t)`` leave no kinetic energy for ``v_n``
    (outside the energy surface).
    """
    require_free_fall(scene, "state_from_reduced")
    point, t, n, _, _ = boundary_frames(scene, np.array([element]), np.array([float(s)]))
    q = point[0]
    ax, ay = scene.force
    kin2 = 2.0 * (energy + ax * q[0] + ay * q[1]) - w * w - vt * vt
    if not kin2 > 0.0:
        return None
    vn = -math.sqrt(kin2)
    v = vt * t[0] + vn * n[0]
    return q, v, float(w)
