r"""Boundary phase portraits: arclength on the whole boundary, Birkhoff, velocity and reduced portraits.

Built on the ``portrait`` record of :func:`noslipsim.simulate_many` (and
:func:`noslipsim.experiments.phase_portrait`), which stores per collision on
the chosen elements the element index, the arclength ``s`` on that element and
the post-collision unit vector ``(w, v_t, v_n)/|(w, v_t, v_n)|`` in the
collision frame (outward normal ``n``, tangent ``t = J n``, docs/conventions.md).

Boundary coordinate.  The chosen elements, in scene order, are laid end to end:
element ``k`` covers ``[o_k, o_k + L_k)`` with ``o_k`` the sum of the lengths of
the chosen elements before it, and a point at arclength ``s`` on it gets
``s_boundary = o_k + s``.  The element's own ``s`` runs from ``p0`` to ``p1``
on a segment, counter-clockwise on circles and arcs (``r`` times the angle,
past ``theta0`` on an arc).  Infinite lines have no length to add, so they
cannot be part of the boundary coordinate (choose the finite elements with
``elements=``).  In a periodic scene the elements are those of one cell (the
torus).

Coordinates.  With ``e_s`` the unit tangent in the direction of increasing
``s`` (``e_s = +t`` on a line, a left-sided segment and a container arc or
circle; ``-t`` on a right-sided segment and a scatterer):

* Birkhoff (specular): ``(s_boundary, p)`` with ``p = sin(angle to the inward
  normal) = v . e_s / |v|``; the billiard map preserves ``ds dp``.
* Velocity portrait (no-slip): the disk ``(v_t, w)`` of the unit vector.
* Reduced portrait: ``s_boundary`` with the unit vector ``(w, v_t, v_n)`` on the
  hemisphere ``v_n <= 0`` (a solid torus); its projection
  ``(s_boundary, v_t, w)`` is a solid cylinder in which the no-slip billiard
  map preserves the volume ``ds dv_t dw`` (the canonical invariant measure
  ``|v_n| ds d sigma`` of the hemisphere, Cox, Feres & Ward 2016); each
  no-slip collision reflects the ``(w, v_t)`` plane (its matrix has
  determinant -1), so between elements of the same orientation the map's
  Jacobian determinant is -1.

:func:`birkhoff_states` and :func:`reduced_states` invert the coordinates into
starts for :func:`noslipsim.simulate_many` (boundary initial conditions).
Derivations and examples: docs/analysis.md.

References
----------
G. D. Birkhoff, *Dynamical systems* (1927); C. Cox, R. Feres, B. Ward,
*Differential geometry of rigid bodies collisions and non-standard billiards*,
Discrete Contin. Dyn. Syst. 36 (2016); the paper, section "No-slip billiards and
their phase spaces".
"""
from __future__ import annotations

import json
import math

import numpy as np
import xarray as xr

from .._metadata import annotate
from .._validate import positive
from ..scenes import Scene

__all__ = [
    "birkhoff_coordinates", "birkhoff_states", "boundary_coordinate", "reduced_portrait", "reduced_states",
    "velocity_portrait",
]

TWO_PI = 2.0 * math.pi

#: A unit vector read back from a record may exceed norm 1 by rounding; beyond this it is an error.
UNIT_TOL = 1e-9



# ----------------------------------------------------------------------------- the boundary layout
def _layout(scene, elements):
    """Chosen element indices, their offsets along the boundary, lengths and orientations."""
    n_el = len(scene.elements)
    if elements is None:
        chosen = list(range(n_el))
    else:
        try:
            chosen = sorted({int(k) for k in np.atleast_1d(np.asarray(elements))})
        except (TypeError, ValueError):
            raise ValueError(f"elements: expected element indices, got {elements!r}") from None
        if not chosen:
            raise ValueError("elements: choose at least one element")
        for k in chosen:
            if not 0 <= k < n_el:
                raise ValueError(f"elements: no element {k} in a scene of {n_el}")
    lengths = []
    for k in chosen:
        L = scene.elements[k].length()
        if not math.isfinite(L):
            raise ValueError(f"elements: element {k} is an infinite line, which has no length to lay along "
                             "the boundary; pass elements= the finite elements (segments, circles, arcs)")
        lengths.append(L)
    lengths = np.array(lengths)
    offsets = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
    orient = np.array([scene.elements[k].orientation() for k in chosen])
    return np.array(chosen), offsets, lengths, orient


def _scene_of(portrait, scene):
    if scene is not None:
        if not isinstance(scene, Scene):
            raise TypeError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
        return scene
    text = portrait.attrs.get("scene")
    if not text:
        raise ValueError("scene: the portrait has no 'scene' attribute; pass scene=")
    return Scene.from_dict(json.loads(text))


def _check_portrait(portrait, needs):
    if not isinstance(portrait, xr.Dataset):
        raise TypeError(f"portrait: expected an xarray.Dataset (simulate_many(..., record='portrait')), "
                        f"got {type(portrait).__name__}")
    missing = [name for name in needs if name not in portrait]
    if missing:
        raise ValueError(f"portrait: missing variable(s) {missing}; expected a portrait record "
                         "(simulate_many(..., record='portrait') or experiments.phase_portrait)")


def _s_boundary(portrait, scene, elements):
    chosen, offsets, lengths, orient = _layout(scene, elements)
    el = np.asarray(portrait["element"].values, dtype=float)
    s = np.asarray(portrait["s"].values, dtype=float)
    known = np.isfinite(el)
    stray = np.setdiff1d(np.unique(el[known]).astype(np.int64), chosen)
    if stray.size:
        raise ValueError(f"elements: the portrait has points on element(s) {stray.tolist()}, not among the "
                         f"chosen {chosen.tolist()}; select them out first or choose them too")
    out = np.full(el.shape, np.nan)
    sign = np.full(el.shape, np.nan)
    for k, o, sg in zip(chosen, offsets, orient):
        on = el == k
        out[on] = o + scene.elements[k].local_s(s[on])
        sign[on] = sg
    attrs = {"boundary_elements": chosen.tolist(), "element_offsets": offsets.tolist(),
             "element_lengths": lengths.tolist(), "element_orientation": orient.tolist(),
             "boundary_length": float(lengths.sum())}
    return out, sign, attrs


def _new(portrait, variables, attrs, title):
    dims = portrait["element"].dims
    data = {name: (dims, values) for name, values in variables.items()}
    coords = {name: c.variable.copy(deep=False) for name, c in portrait.coords.items()
              if set(c.dims) <= set(dims)}
    out = xr.Dataset(data, coords=coords)
    keep = {k: v for k, v in portrait.attrs.items() if k in ("law", "gamma", "force", "scene", "seed", "source")}
    out.attrs.update(keep, title=title, **attrs)
    return annotate(out)


# ----------------------------------------------------------------------------- forward: record -> coordinates
def boundary_coordinate(portrait, scene=None, *, elements=None):
    """Arclength of each portrait point along the whole table boundary.

    Parameters
    ----------
    portrait : xarray.Dataset
        A ``portrait`` record (variables ``element`` and ``s``, any dims,
        NaN-padded).
    scene : Scene, optional
        The table (default: rebuilt from ``portrait.attrs['scene']``).
    elements : sequence of int, optional
        The elements laid end to end, in scene order (default: all).  Every
        point must lie on one of them; infinite lines are refused.

    Returns
    -------
    xarray.Dataset
        ``element`` and ``s_boundary`` (in ``[0, boundary_length]``; NaN
        where the record is padding), with attributes ``boundary_elements``,
        ``element_offsets``, ``element_lengths``, ``element_orientation``
        (``+1`` where ``s`` runs along ``t = J n``) and ``boundary_length``.

    Examples
    --------
    >>> from noslipsim import tables, experiments
    >>> ds = experiments.phase_portrait(tables.lemon(1.0, 1.0), n_orbits=10, n_collisions=500)
    >>> b = boundary_coordinate(ds)           # b.attrs["boundary_length"] = 4 pi / 3 (two arcs)
    """
    _check_portrait(portrait, ("element", "s"))
    scene = _scene_of(portrait, scene)
    s_b, _, attrs = _s_boundary(portrait, scene, elements)
    return _new(portrait, {"element": portrait["element"].values, "s_boundary": s_b}, attrs,
                "boundary coordinate of portrait points")


def birkhoff_coordinates(portrait, scene=None, *, elements=None):
    r"""Specular Birkhoff coordinates ``(s_boundary, p)`` of portrait points.

    .. math::

        p = \sin\alpha = \frac{v \cdot e_s}{|v|}
          = \pm \frac{v_t}{\sqrt{v_t^2 + v_n^2}},

    ``alpha`` the angle of the post-collision velocity to the inward normal,
    positive towards increasing ``s`` (sign ``+`` where ``s`` runs along
    ``t = J n``).  The spin does not enter.  The specular billiard map
    preserves ``ds dp``.

    Parameters
    ----------
    portrait, scene, elements
        As :func:`boundary_coordinate`; ``portrait`` also needs ``vt_unit``
        and ``vn_unit``.

    Returns
    -------
    xarray.Dataset
        ``element``, ``s_boundary`` and ``sin_angle`` in ``[-1, 1]``, with the
        boundary attributes of :func:`boundary_coordinate`.

    Examples
    --------
    The paper's specular lemon portrait:

    >>> from noslipsim import tables, experiments
    >>> ds = experiments.phase_portrait(tables.lemon(1.0, 1.0), n_orbits=30, n_collisions=2000)
    >>> b = birkhoff_coordinates(ds)          # plot b.s_boundary against b.sin_angle
    """
    _check_portrait(portrait, ("element", "s", "vt_unit", "vn_unit"))
    scene = _scene_of(portrait, scene)
    s_b, sign, attrs = _s_boundary(portrait, scene, elements)
    vt = np.asarray(portrait["vt_unit"].values, dtype=float)
    vn = np.asarray(portrait["vn_unit"].values, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        p = np.clip(sign * vt / np.hypot(vt, vn), -1.0, 1.0)
    return _new(portrait, {"element": portrait["element"].values, "s_boundary": s_b, "sin_angle": p}, attrs,
                "Birkhoff coordinates of portrait points")


def velocity_portrait(portrait):
    """The no-slip velocity portrait: each point's unit vector projected on the disk ``(v_t, w)``.

    The post-collision unit vector ``(w, v_t, v_n)/|(w, v_t, v_n)|`` lies on the
    hemisphere ``v_n <= 0``; dropping ``v_n`` projects it onto the unit disk
    (the paper's velocity phase portrait; the collision position is
    forgotten, so closed invariant curves may overlap).

    Parameters
    ----------
    portrait : xarray.Dataset
        A ``portrait`` record (``element``, ``vt_unit``, ``w_unit``, ``vn_unit``).

    Returns
    -------
    xarray.Dataset
        ``element``, ``vt_unit`` (abscissa) and ``w_unit`` (ordinate), any
        dims of the record kept (one colour per ``orbit``).

    Examples
    --------
    The paper's Sinai torus (no-slip):

    >>> from noslipsim import tables, experiments
    >>> ds = experiments.phase_portrait(tables.sinai_torus(0.25), n_orbits=20, n_collisions=2000)
    >>> vp = velocity_portrait(ds)            # plot vp.vt_unit against vp.w_unit, per orbit
    """
    _check_portrait(portrait, ("element", "vt_unit", "w_unit", "vn_unit"))
    vt, w, vn = (np.asarray(portrait[k].values, dtype=float) for k in ("vt_unit", "w_unit", "vn_unit"))
    _check_unit(vt, w, vn)
    return _new(portrait, {"element": portrait["element"].values, "vt_unit": vt, "w_unit": w}, {},
                "velocity phase portrait (v_t, w) of the post-collision unit vector")


def reduced_portrait(portrait, scene=None, *, elements=None):
    """The reduced no-slip portrait: ``s_boundary`` with the unit vector (the solid torus ``S^1 x S^2_+``).

    Parameters
    ----------
    portrait, scene, elements
        As :func:`boundary_coordinate`; ``portrait`` also needs ``w_unit``,
        ``vt_unit`` and ``vn_unit``.

    Returns
    -------
    xarray.Dataset
        ``element``, ``s_boundary``, ``vt_unit``, ``w_unit`` and ``vn_unit``
        (``vn_unit = -sqrt(1 - vt_unit^2 - w_unit^2)``, kept for
        convenience); ``(s_boundary, vt_unit, w_unit)`` are solid-cylinder
        coordinates (ends identified) in which the billiard map preserves
        volume.

    Examples
    --------
    >>> from noslipsim import tables, experiments
    >>> ds = experiments.phase_portrait(tables.sinai_torus(0.25), n_orbits=20, n_collisions=2000)
    >>> r = reduced_portrait(ds)              # 3D scatter of (s_boundary, vt_unit, w_unit)
    """
    _check_portrait(portrait, ("element", "s", "w_unit", "vt_unit", "vn_unit"))
    scene = _scene_of(portrait, scene)
    s_b, _, attrs = _s_boundary(portrait, scene, elements)
    vt, w, vn = (np.asarray(portrait[k].values, dtype=float) for k in ("vt_unit", "w_unit", "vn_unit"))
    _check_unit(vt, w, vn)
    return _new(portrait, {"element": portrait["element"].values, "s_boundary": s_b, "vt_unit": vt,
                           "w_unit": w, "vn_unit": vn}, attrs,
                "reduced phase portrait (boundary arclength, unit velocity-and-spin)")


def _check_unit(vt, w, vn):
    with np.errstate(invalid="ignore"):
        norm = np.sqrt(vt * vt + w * w + vn * vn)
        bad = np.isfinite(norm) & (np.abs(norm - 1.0) > UNIT_TOL)
    if bad.any():
        raise ValueError(f"portrait: (w_unit, vt_unit, vn_unit) is not a unit vector (norm {norm[bad].flat[0]})")


# ----------------------------------------------------------------------------- inverse: coordinates -> starts
def _locate(scene, s_boundary, elements):
    """Element, point, outward normal and ``e_s`` at boundary coordinates ``s_boundary``."""
    chosen, offsets, lengths, orient = _layout(scene, elements)
    s = np.asarray(s_boundary, dtype=float).ravel()
    total = float(lengths.sum())
    if not np.all(np.isfinite(s)):
        raise ValueError("s_boundary: must be finite")
    if (s < 0.0).any() or (s > total).any():
        raise ValueError(f"s_boundary: must lie in [0, {total}] (the boundary length), got "
                         f"{s[(s < 0) | (s > total)][0]}")
    idx = np.clip(np.searchsorted(offsets, s, side="right") - 1, 0, len(chosen) - 1)
    local = np.clip(s - offsets[idx], 0.0, lengths[idx])
    point = np.empty((len(s), 2))
    n_out = np.empty((len(s), 2))
    for i, k in enumerate(chosen):
        on = idx == i
        point[on], n_out[on] = scene.elements[k].at_arclength(local[on])
    t = np.c_[-n_out[:, 1], n_out[:, 0]]
    return chosen[idx], point, n_out, orient[idx][:, None] * t


def _speed(value):
    return positive(value, "speed")


def birkhoff_states(scene, s_boundary, sin_angle, *, elements=None, speed=1.0):
    """Boundary starts from Birkhoff coordinates (the inverse of :func:`birkhoff_coordinates`).

    The velocity leaving the boundary point at ``s_boundary`` is
    ``speed (p e_s + sqrt(1 - p^2) n_in)``; the spin is 0.

    Parameters
    ----------
    scene : Scene
        The table.
    s_boundary, sin_angle : array_like
        Boundary arclength in ``[0, boundary_length]`` and ``p`` in
        ``(-1, 1)`` (``|p| = 1`` is a tangent start, which enters no table).
    elements : sequence of int, optional
        As :func:`boundary_coordinate`.
    speed : float
        Speed ``|v| > 0``.

    Returns
    -------
    dict
        ``positions`` (N, 2), ``velocities`` (N, 2), ``spins`` (N,) and
        ``start_elements`` (N,) for :func:`noslipsim.simulate_many` (or
        ``initial_states`` of :func:`noslipsim.experiments.phase_portrait`).
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
    p = np.asarray(sin_angle, dtype=float).ravel()
    if p.shape != np.asarray(s_boundary, dtype=float).ravel().shape:
        raise ValueError("sin_angle: must have the shape of s_boundary")
    if not np.all(np.isfinite(p)) or (np.abs(p) >= 1.0).any():
        raise ValueError("sin_angle: must lie in (-1, 1) (|p| = 1 is tangent to the boundary)")
    speed = _speed(speed)
    el, point, n_out, e_s = _locate(scene, s_boundary, elements)
    vel = speed * (p[:, None] * e_s - np.sqrt(1.0 - p * p)[:, None] * n_out)
    return {"positions": point, "velocities": vel, "spins": np.zeros(len(p)), "start_elements": el}


def reduced_states(scene, s_boundary, vt_unit, w_unit, *, elements=None, speed=1.0):
    """Boundary starts from reduced-portrait coordinates (the inverse of :func:`reduced_portrait`).

    With ``v_n = -sqrt(1 - v_t^2 - w^2)`` the unit vector ``(w, v_t, v_n)`` is
    scaled by ``speed = sqrt(|v|^2 + w^2)``: velocity ``speed (v_t t + v_n n)``
    (``t = J n``, ``n`` outward) and spin ``speed w``.

    Parameters
    ----------
    scene : Scene
        The table.
    s_boundary : array_like
        Boundary arclength in ``[0, boundary_length]``.
    vt_unit, w_unit : array_like
        Disk coordinates with ``vt_unit^2 + w_unit^2 < 1``.
    elements : sequence of int, optional
        As :func:`boundary_coordinate`.
    speed : float
        ``sqrt(|v|^2 + w^2) > 0``.

    Returns
    -------
    dict
        As :func:`birkhoff_states`, with the spins.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
    n = np.asarray(s_boundary, dtype=float).ravel().shape
    vt = np.asarray(vt_unit, dtype=float).ravel()
    w = np.asarray(w_unit, dtype=float).ravel()
    if vt.shape != n or w.shape != n:
        raise ValueError("vt_unit, w_unit: must have the shape of s_boundary")
    if not (np.all(np.isfinite(vt)) and np.all(np.isfinite(w))) or (vt * vt + w * w >= 1.0).any():
        raise ValueError("vt_unit, w_unit: must be finite with vt_unit^2 + w_unit^2 < 1 (inside the disk)")
    speed = _speed(speed)
    el, point, n_out, _ = _locate(scene, s_boundary, elements)
    t = np.c_[-n_out[:, 1], n_out[:, 0]]
    vn = -np.sqrt(1.0 - vt * vt - w * w)
    vel = speed * (vt[:, None] * t + vn[:, None] * n_out)
    return {"positions": point, "velocities": vel, "spins": speed * w, "start_elements": el}
