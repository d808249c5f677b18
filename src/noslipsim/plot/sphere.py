r"""The path of a sphere bouncing on a plane in 3D, from its bounce log.

Between bounces the centre flies on the parabola

.. math::

    q(t) = q_k + v_k (t - t_k) - \tfrac12 g\, e_z (t - t_k)^2,

so the path is rebuilt exactly from the log of
:func:`noslipsim.sphere3d.simulate_sphere` (bounce times, positions and
velocities after each bounce, the start in the ``start`` attribute) and sampled
along every flight.
"""
from __future__ import annotations

import json

import numpy as np

from .orbits import POINTS_PER_FLIGHT


def sphere_path(bounce, points_per_flight=POINTS_PER_FLIGHT):
    """The continuous path ``(x, y, z)`` of a bouncing sphere, from the start to its last bounce.

    Parameters
    ----------
    bounce : xarray.Dataset
        A :func:`noslipsim.sphere3d.simulate_sphere` log (or a dataset built
        on it, e.g. :func:`noslipsim.experiments.sphere_bounce`): ``time``,
        ``position`` and ``velocity`` along ``(collision, component)``, the
        ``gravity`` and ``start`` attributes.
    points_per_flight : int
        Samples per flight (>= 2).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray)

    Raises
    ------
    ValueError
        For a dataset without the log or the attributes, or a bad ``points_per_flight``.
    """
    if isinstance(points_per_flight, bool) or int(points_per_flight) != points_per_flight or points_per_flight < 2:
        raise ValueError(f"points_per_flight: expected an integer >= 2, got {points_per_flight!r}")
    missing = [k for k in ("time", "position", "velocity") if k not in bounce.variables]
    missing += [k for k in ("gravity", "start") if k not in bounce.attrs]
    if missing:
        raise ValueError(f"bounce: missing {missing} (expected a noslipsim.sphere3d.simulate_sphere log)")
    start = json.loads(bounce.attrs["start"])
    g = float(bounce.attrs["gravity"])
    t = np.concatenate([[0.0], np.asarray(bounce.time.values, float)])
    q = np.vstack([start["position"], np.asarray(bounce.position.values, float)])
    v = np.vstack([start["velocity"], np.asarray(bounce.velocity.values, float)])
    dur = np.diff(t)                                   # flights that end at a bounce
    tau = dur[:, None] * np.linspace(0.0, 1.0, int(points_per_flight))[None, :]
    x, y, z = (q[:-1, i, None] + v[:-1, i, None] * tau for i in range(3))
    z = z - 0.5 * g * tau ** 2
    return x.ravel(), y.ravel(), z.ravel()


def draw_arrow3d(ax, start, vector, *, color="k", linewidth=0.8, mutation_scale=8.0, zorder=5):
    """An arrow in a 3D axes whose head is drawn on the page, joined to its shaft at every view.

    ``Axes3D.quiver`` builds the head from two short lines in data coordinates;
    under a box aspect that is not the data's (Figure 16 squeezes z) they
    project away from the shaft and the head looks detached.  Here the two
    end points are projected and a 2D arrow (head included) joins them.

    Parameters
    ----------
    ax : mpl_toolkits.mplot3d.axes3d.Axes3D
    start, vector : sequence of 3 float
        Tail and extent of the arrow (data coordinates).

    Returns
    -------
    matplotlib.patches.FancyArrowPatch
    """
    from matplotlib.patches import FancyArrowPatch
    from mpl_toolkits.mplot3d import proj3d

    p0, d = np.asarray(start, dtype=float), np.asarray(vector, dtype=float)
    if p0.shape != (3,) or d.shape != (3,) or not np.isfinite(np.r_[p0, d]).all():
        raise ValueError(f"start, vector: expected finite 3D points, got {start!r}, {vector!r}")
    if getattr(ax, "name", None) != "3d":
        raise ValueError("ax: expected a 3D axes (projection='3d')")
    p1 = p0 + d

    class _Arrow3D(FancyArrowPatch):
        def do_3d_projection(self, renderer=None):
            xs, ys, zs = proj3d.proj_transform(*np.c_[p0, p1], self.axes.M)
            self.set_positions((xs[0], ys[0]), (xs[1], ys[1]))
            return float(np.min(zs))

    arrow = _Arrow3D((0.0, 0.0), (0.0, 0.0), arrowstyle="-|>", color=color, linewidth=linewidth,
                     mutation_scale=mutation_scale, shrinkA=0.0, shrinkB=0.0, zorder=zorder)
    ax.add_artist(arrow)
    return arrow
