r"""The largest Lyapunov exponent of an orbit, from the exact tangent dynamics (Benettin's method).

The orbit is run with the compiled engine; the Jacobians of the
collision-to-collision map in the reduced coordinates ``(s, w, v_t)`` at
fixed energy (:mod:`noslipsim.analysis.tangent`, docs/analysis.md) are
multiplied onto a tangent vector, which is renormalised after every block of
:data:`BLOCK` collisions (Benettin, Galgani, Giorgilli & Strelcyn 1980).  The
exponent per unit time is

.. math::

    \lambda = \frac{1}{t_N - t_0} \sum_j \log \frac{\|B_j u_j\|}{\|u_j\|},
    \qquad u_{j+1} = \frac{B_j u_j}{\|B_j u_j\|},

``B_j`` the product of the block's Jacobians and ``t_0, t_N`` the times of the
first and last collision used.  The map's exponent per collision is
``lambda`` times the mean free time ``(t_N - t_0)/N`` (Abramov's formula); the
section coordinates carry the energy shell, so the flow's zero exponents along
the flight and the energy do not enter, and the tangent vector grows at the
largest rate.  Norm: the reduced coordinates scaled by the table's size (for a
table of lines through one point, a wedge: the orbit's extent) and the speed
(any norm gives the same limit).

References: G. Benettin, L. Galgani, A. Giorgilli, J.-M. Strelcyn, Meccanica 15
(1980) 9; C. Dellago, H. A. Posch, W. G. Hoover, Phys. Rev. E 53 (1996) 1485.
"""
from __future__ import annotations

import math

import numpy as np

from .._validate import finite_float
from ..core import layout
from ..scenes import Scene
from ..simulate import check_start, run_one
from .monodromy import _period
from .section import TWIN_LYAPUNOV, require_free_fall
from .tangent import check_no_corner, log_block_products

__all__ = ["lyapunov", "lyapunov_run"]

#: Collisions per renormalisation.  A block's product grows at most by the
#: product of its per-collision stretch factors (1 + 2 tau / (r cos phi) on a
#: disk): 8 of them stay far from float64 overflow even for near-grazing hits.
BLOCK = 8

#: Largest number of collisions one call logs (14 floats each, ~110 MB at this size).
MAX_COLLISIONS = 1_000_000


def _collision_budget(scene, q, v, w, n_collisions, max_time):
    """How many collisions to log: ``n_collisions``, or the count the orbit makes before ``max_time``."""
    if n_collisions is not None:
        return n_collisions
    empty = np.zeros((0, layout.N_LOG))
    n, *_ = run_one(scene, q, v, w, MAX_COLLISIONS + 1, max_time, -math.inf, layout.RECORD_NONE, empty)
    return n


def _norm_scales(scene, log, v, w):
    """The scales ``(L, V, V)`` of the reduced coordinates ``(s, w, v_t)`` in the norm of the renormalisation.

    ``L`` is the table's size; a table of lines through the origin alone (a
    wedge) has none (``Scene.scale`` is 0), and there the orbit's own extent,
    the largest coordinate of its collision points, serves (without a length,
    the arclength's scale overflowed the tangent vector).  ``V`` is the speed
    scale, positive even for a start at rest under a force.
    """
    length = scene.scale or float(np.abs(log[:, [layout.LOG_X, layout.LOG_Y]]).max())
    speed = math.sqrt(float(v @ v) + w * w + math.hypot(*scene.force) * length)
    return np.array([length, speed, speed])


def _block_growth(blocks, D, block):
    """``log |B_j u_j|`` of each block; ``u`` is renormalised after each, in the norm scaled by ``D``."""
    u = np.ones(3) / math.sqrt(3.0)
    growth = np.empty(len(blocks))
    with np.errstate(all="ignore"):  # an overflow is reported below, with what to change
        scaled = blocks * (1.0 / D)[None, :, None] * D[None, None, :]
        for j, B in enumerate(scaled):
            u = B @ u
            norm = math.sqrt(float(u @ u))
            if not (norm > 0.0 and math.isfinite(norm)):
                raise ValueError(f"n_collisions: the tangent vector overflowed or vanished between collisions "
                                 f"{j * block} and {(j + 1) * block} (a near-grazing collision stretches it beyond "
                                 f"the float range); end the run before collision {j * block} (fewer collisions "
                                 "or a shorter time)")
            growth[j] = math.log(norm)
            u /= norm
    return growth


def lyapunov_run(scene: Scene, position, velocity, spin=0.0, *, max_time=1e4, n_collisions=None, block=BLOCK):
    """The Benettin run behind :func:`lyapunov`, with its running estimate.

    Returns
    -------
    dict
        ``exponent`` (per unit time), ``per_collision`` (the map's exponent),
        ``time`` (``t_N - t_0``), ``n_collisions`` (used), ``mean_free_time``,
        and ``times``, ``running`` (the estimate after each block: the running
        ``sum log growth / elapsed time``, for convergence plots).
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
    require_free_fall(scene, "lyapunov", TWIN_LYAPUNOV)
    max_time = finite_float(max_time, "max_time") if max_time != math.inf else math.inf
    if not max_time > 0.0:
        raise ValueError(f"max_time: must be > 0, got {max_time}")
    if n_collisions is not None:
        n_collisions = _period(n_collisions)
        if n_collisions > MAX_COLLISIONS:
            raise ValueError(f"n_collisions: at most {MAX_COLLISIONS:,} per call, got {n_collisions:,}")
    elif max_time == math.inf:
        raise ValueError("max_time: give a finite max_time or n_collisions (the run needs an end)")
    block = _period(block)
    q, v, w = check_start(scene, position, velocity, spin)
    if n_collisions is not None:
        max_time = math.inf
    budget = _collision_budget(scene, q, v, w, n_collisions, max_time)
    if budget > MAX_COLLISIONS:
        raise ValueError(f"max_time: the orbit makes more than {MAX_COLLISIONS:,} collisions before t = {max_time}; "
                         "pass a smaller max_time or n_collisions")
    rec = np.zeros((budget, layout.N_LOG))
    _, stop, _, n_rec, *_ = run_one(scene, q, v, w, budget, max_time, -math.inf, layout.RECORD_LOG, rec)
    log = rec[:n_rec]
    if n_rec < block + 1:
        why = f"the orbit stopped ({layout.STOP_REASONS[stop]!r})" if stop != layout.STOP_MAX_TIME else "max_time"
        raise ValueError(f"position, velocity: only {n_rec} collisions before {why}; "
                         f"a Lyapunov exponent needs at least {block + 1}")
    check_no_corner(log)
    blocks = log_block_products(scene, log, block)
    n_used = len(blocks) * block
    times = log[block:n_used + 1:block, layout.LOG_T] - log[0, layout.LOG_T]

    growth = _block_growth(blocks, _norm_scales(scene, log, v, w), block)
    total = np.cumsum(growth)
    elapsed = float(times[-1])
    exponent = float(total[-1] / elapsed)
    return {"exponent": exponent, "per_collision": float(total[-1] / n_used), "time": elapsed,
            "n_collisions": int(n_used), "mean_free_time": elapsed / n_used,
            "times": times, "running": total / times}


def lyapunov(scene: Scene, position, velocity, spin=0.0, *, max_time=1e4, n_collisions=None):
    r"""The largest Lyapunov exponent per unit time of the orbit from ``(position, velocity, spin)``.

    Benettin's method on the exact tangent dynamics of the collision map in
    reduced coordinates ``(s, w, v_t)`` at fixed energy (module docstring,
    docs/analysis.md): specular or no-slip, with or without force, plain or
    periodic scenes.

    Parameters
    ----------
    scene : Scene
    position, velocity : (float, float)
        Start strictly inside the table.
    spin : float
        Scaled spin ``w``.
    max_time : float
        Run length in time (the orbit is logged up to its last collision
        before ``max_time``); ignored when ``n_collisions`` is given.
    n_collisions : int, optional
        Run length in collisions instead (at most :data:`MAX_COLLISIONS`).

    Returns
    -------
    float
        ``lambda`` in inverse time units.  A chaotic orbit gives a positive
        value; an orbit on an elliptic island gives a value that decays like
        ``log(t)/t``.

    Raises
    ------
    ValueError
        Bad arguments; an orbit with too few collisions (escape) or more than
        :data:`MAX_COLLISIONS`; a corner collision on the way
        (:class:`~noslipsim.analysis.tangent.CornerError`).

    Examples
    --------
    >>> from noslipsim import tables
    >>> lyapunov(tables.sinai_torus(0.25, law="specular"), (0.45, 0.1), (0.8, 0.6), max_time=1000)  # doctest: +SKIP
    1.7...
    """
    return lyapunov_run(scene, position, velocity, spin, max_time=max_time, n_collisions=n_collisions)["exponent"]
