"""Junctions: the points where two boundary elements meet (vertices, crossings, tangencies).

The corner rule can only fire at a hit within ``CONTACT_TOL`` of a second
element, which happens only near such a point.  The kernel therefore runs
the corner pass only for hits within ``JUNCTION_GATE * scale`` of a junction
of the element hit: a crossing at angle ``theta`` brings two elements within
``CONTACT_TOL`` of each other over ``CONTACT_TOL / sin(theta)``, a tangency
over ``sqrt(2 r CONTACT_TOL)``, both far below the gate for any table a scene
file can describe (angles above 1e-5 rad, radii below 1e8 scales).
"""
from __future__ import annotations

import math

import numpy as np

from ..core.tolerances import JUNCTION_GATE, NONCONVEX_END_FACTOR  # noqa: F401  (the gate: used by the kernel)
from ..elements import RoundCarrier, StraightCarrier

#: Relative tolerance for "on the element" and for near-tangencies.
_ON_TOL = 1e-9


def _on(e, pts, tol):
    if not len(pts):
        return pts
    pts = np.asarray(pts, float).reshape(-1, 2)
    return pts[e.distance(pts) <= tol]


def _meet(a, b, tol):
    """Points where elements ``a`` and ``b`` meet (within ``tol``): where their carriers meet, on both."""
    ca, cb = a.carrier(), b.carrier()
    if isinstance(ca, RoundCarrier) and isinstance(cb, StraightCarrier):
        a, b, ca, cb = b, a, cb, ca
    pts = []
    if isinstance(ca, StraightCarrier) and isinstance(cb, StraightCarrier):
        p, d = ca
        q, e = cb
        cross = d[0] * e[1] - d[1] * e[0]
        if abs(cross) > 1e-14 * np.linalg.norm(d) * np.linalg.norm(e):
            s = ((q - p)[0] * e[1] - (q - p)[1] * e[0]) / cross
            pts.append(p + s * d)
        else:  # parallel: ends of one lying on the other
            for el in (a, b):
                pts += [end for end, _, _ in el.end_frames()]
    elif isinstance(ca, StraightCarrier):
        p, d = ca
        c, r = cb
        u = d / np.linalg.norm(d)
        s0 = (c - p) @ u
        foot = p + s0 * u
        h = np.linalg.norm(c - foot)
        if h <= r + tol:
            half = math.sqrt(max(r * r - h * h, 0.0))
            pts += [foot - half * u, foot + half * u]
    else:
        c1, r1 = ca
        c2, r2 = cb
        dvec = c2 - c1
        dist = np.linalg.norm(dvec)
        if dist > 0 and abs(r1 - r2) - tol <= dist <= r1 + r2 + tol:
            along = (dist ** 2 + r1 ** 2 - r2 ** 2) / (2 * dist)
            half = math.sqrt(max(r1 ** 2 - along ** 2, 0.0))
            u = dvec / dist
            base = c1 + along * u
            perp = np.array([-u[1], u[0]])
            pts += [base - half * perp, base + half * perp]
    pts = np.array(pts, float).reshape(-1, 2)
    return _on(b, _on(a, pts, tol), tol)


def junction_arrays(elements, placed, scale):
    """Per-element junction points in each element's own frame, as kernel arrays.

    ``placed`` lists ``(index, element copy, shift)`` for every copy of the
    elements that reaches cell 0 (each element once, unshifted, in a plain
    scene); ``scale`` is the table's length scale.  Returns ``(start,
    points)``: the junctions of element ``e`` are ``points[start[e]:start[e +
    1]]``, each stored in the frame of the copy's element (shift removed).
    """
    items = placed
    tol = _ON_TOL * max(scale, 1e-300)
    per = [[] for _ in elements]
    # a meeting point lies within tol of both elements, hence in both boxes grown by tol:
    # pairs whose boxes are apart cannot meet, and skipping them changes no output
    boxes = np.array([e.bbox() for _, e, _ in items], float).reshape(-1, 4)
    lo, hi = boxes[:, :2] - tol, boxes[:, 2:] + tol
    for a in range(len(items)):
        near = np.flatnonzero(np.all(lo[a + 1:] <= hi[a], axis=1) & np.all(lo[a] <= hi[a + 1:], axis=1)) + a + 1
        for b in near:
            ia, ea, sa = items[a]
            ib, eb, sb = items[b]
            for p in _meet(ea, eb, tol):
                per[ia].append(p - sa)
                per[ib].append(p - sb)
    start = np.zeros(len(elements) + 1, dtype=np.int64)
    pts = []
    for i, lst in enumerate(per):
        uniq = np.unique(np.round(np.array(lst, float).reshape(-1, 2), 12), axis=0) if lst else np.zeros((0, 2))
        pts.append(uniq)
        start[i + 1] = start[i] + len(uniq)
    return start, (np.vstack(pts) if pts else np.zeros((0, 2)))


def _frame_at(f, pt, tol):
    """``(direction into f, inward normal)`` if ``pt`` is an end of segment/arc ``f``, else None."""
    for q, d, n in f.end_frames():
        if np.linalg.norm(q - pt) <= tol:
            return d, n
    return None


def end_factors(elements, placed, scale):
    """Band factor of each end of each segment and arc: ``(n_elements, 2)`` (arguments as :func:`junction_arrays`).

    1 where the end is a convex junction (the table lies inside the angle the
    two pieces make, so leaving either half plane leaves the table), else
    ``NONCONVEX_END_FACTOR``: a reflex junction (the table is locally the union
    of the half planes) or a free end.  A junction with a line, a circle or
    the interior of another piece counts as convex (the safe choice).
    """
    others = [copy for _, copy, _ in placed]
    tol = _ON_TOL * max(scale, 1e-300)
    out = np.zeros((len(elements), 2))
    for i, e in enumerate(elements):
        for k, (pt, d_e, n_e) in enumerate(e.end_frames()):
            convex = None
            for f in others:
                if f == e or len(_on(f, pt[None], tol)) == 0:
                    continue
                frame = _frame_at(f, pt, tol)
                if frame is None:  # a line, a circle or another piece's interior
                    convex = True
                    break
                d_f, n_f = frame
                m = d_e + d_f
                if np.linalg.norm(m) < 1e-12 or (n_e @ m > 0 and n_f @ m > 0):
                    convex = True
                    break
                convex = False
            out[i, k] = 1.0 if convex else NONCONVEX_END_FACTOR
    return out
