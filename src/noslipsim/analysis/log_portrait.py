r"""Phase-portrait coordinates straight from a collision log (the explorer and animations fill portraits live).

The portrait the paper draws for a scene (:func:`paper_portrait`): the
velocity portrait ``(v_t, w)`` of the post-collision unit vector for a no-slip
table, Birkhoff coordinates ``(s, p = sin alpha)`` for a specular one
(:mod:`noslipsim.analysis.portraits`, docs/analysis.md "Boundary portraits").
:func:`log_portrait` computes them from the columns of a collision log
(:func:`noslipsim.simulate`, or ``simulate_many(..., record='log')``) through
the same functions the pipeline's portraits use, so a point drawn live is the
point a portrait dataset holds.
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..scenes import Scene
from .portraits import _layout, birkhoff_coordinates, velocity_portrait
from .section import boundary_frames

__all__ = ["PORTRAITS", "boundary_length", "log_portrait", "paper_portrait", "portrait_elements"]

#: The portrait kinds and their axes ``(x label, y label)``.
PORTRAITS = {"velocity": ("v_t", "w"), "birkhoff": ("s", "p = sin(alpha)")}


def paper_portrait(scene: Scene):
    """``'velocity'`` where some element collides by the no-slip law (the spin takes part), else ``'birkhoff'``.

    The paper's choice; a table of mixed laws counts as no-slip whatever its default law.
    """
    return "velocity" if scene.any_noslip else "birkhoff"


def portrait_elements(scene: Scene, kind=None):
    """The finite elements (segments, circles, arcs), laid end to end by Birkhoff's ``s``.

    Parameters
    ----------
    scene : Scene
    kind : {'velocity', 'birkhoff'}, optional
        The portrait they are chosen for (default :func:`paper_portrait`), named when there are none.

    Raises
    ------
    ValueError
        For a table of infinite lines only (no boundary length to lay out).
    """
    chosen = [k for k, e in enumerate(scene.elements) if math.isfinite(e.length())]
    if not chosen:
        if (kind or paper_portrait(scene)) == "birkhoff":
            raise ValueError("scene: every element is an infinite line, so the table has no boundary "
                             "coordinate s for a Birkhoff portrait")
        raise ValueError("scene: every element is an infinite line, so the table has no finite element "
                         "(segment, circle, arc) for a velocity portrait (v_t, w) to start its orbits on and "
                         "record their collisions with")
    return chosen


def log_portrait(scene: Scene, element, s, vx, vy, spin, kind="velocity"):
    """Portrait coordinates ``(x, y)`` of post-collision states.

    Parameters
    ----------
    scene : Scene
        The table (a periodic scene: the elements of one cell, as the log's
        ``element`` and ``s`` are).
    element, s : array_like (N,)
        Element hit and its own arclength (NaN rows are padding).
    vx, vy, spin : array_like (N,)
        Velocity and scaled spin just after each collision.
    kind : {'velocity', 'birkhoff'}
        ``velocity``: ``(v_t, w) / |(w, v_t, v_n)|``; ``birkhoff``:
        ``(s_boundary, sin alpha)`` over the finite elements
        (:func:`portrait_elements`).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        Abscissa and ordinate; NaN for padding and, in Birkhoff coordinates,
        for collisions on infinite lines (which have no place along ``s``).
    """
    if kind not in PORTRAITS:
        raise ValueError(f"kind: expected one of {sorted(PORTRAITS)}, got {kind!r}")
    el = np.asarray(element, dtype=float).ravel()
    s = np.asarray(s, dtype=float).ravel()
    v = np.c_[np.asarray(vx, dtype=float).ravel(), np.asarray(vy, dtype=float).ravel()]
    w = np.asarray(spin, dtype=float).ravel()
    known = np.isfinite(el) & np.isfinite(s)
    unit = np.full((3, el.size), np.nan)  # (w, v_t, v_n) / |.|
    if known.any():
        _, t, n, _, _ = boundary_frames(scene, el[known].astype(np.int64), s[known])
        vt = np.einsum("ij,ij->i", v[known], t)
        vn = np.einsum("ij,ij->i", v[known], n)
        norm = np.sqrt(w[known] ** 2 + vt ** 2 + vn ** 2)
        unit[:, known] = np.array([w[known], vt, vn]) / np.where(norm > 0, norm, np.nan)
    if kind == "velocity":
        on = np.where(known, el, np.nan)
        ds = velocity_portrait(_record(on, s, unit))
        return ds["vt_unit"].values, ds["w_unit"].values
    chosen = portrait_elements(scene)
    on = np.where(known & np.isin(el, chosen), el, np.nan)  # lines have no s: left out
    ds = birkhoff_coordinates(_record(on, s, unit), scene, elements=chosen)
    return ds["s_boundary"].values, ds["sin_angle"].values


def boundary_length(scene: Scene):
    """Total length of the finite elements: the extent of Birkhoff's ``s``."""
    _, _, lengths, _ = _layout(scene, portrait_elements(scene))
    return float(lengths.sum())


def _record(element, s, unit):
    dim = ("point",)
    return xr.Dataset({"element": (dim, element), "s": (dim, s), "w_unit": (dim, unit[0]),
                       "vt_unit": (dim, unit[1]), "vn_unit": (dim, unit[2])})
