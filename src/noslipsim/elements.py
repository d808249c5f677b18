"""Boundary elements of a billiard table: lines, segments, circles and arcs.

Each element knows its table side, validates itself, writes its kernel row
(:mod:`noslipsim.core.layout`) and measures points for the inside test.  The
scene-file form of each is given in docs/scenes.md:

- ``{type: line, point: [x, y], normal: [nx, ny]}``: infinite line, ``normal``
  points INTO the table (normalised on construction);
- ``{type: segment, p0: [x, y], p1: [x, y], side: left}``: one-sided, the table is
  on the ``side`` of ``p0 -> p1`` (CCW polygons use ``left``); ends inclusive;
- ``{type: circle, center: [x, y], radius: r, side: outside}``: ``outside`` for a
  scatterer, ``inside`` for a container;
- ``{type: arc, center, radius, theta0, theta1, side}``: the CCW arc from
  ``theta0`` to ``theta1`` (radians, ``0 < theta1 - theta0 <= 2 pi``).

Every element may also carry its own collision law, ``law: specular`` or
``law: no-slip`` (keyword ``law=`` in Python); left out (``None``), the element
takes the scene's law.  A table may so mix laws: specular walls around a
no-slip scatterer.  The scene's ``gamma`` serves every no-slip element; a
specular element keeps the spin.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from ._unit import unit_pair
from ._validate import finite_float, finite_vector, no_unknown_keys, required
from .core import layout
from .outline import Curve, Disc, Wall

TWO_PI = 2.0 * math.pi


#: Collision law names (the spelling ``noslip`` is read as ``no-slip``).
LAW_NAMES = {"no-slip": "no-slip", "noslip": "no-slip", "specular": "specular"}


def law_name(value: Any, where: str = "law") -> str:
    """The canonical name (``'no-slip'`` or ``'specular'``) of a collision law; ValueError naming ``where`` else."""
    if not isinstance(value, str) or value not in LAW_NAMES:
        raise ValueError(f"{where}: unknown collision law {value!r}; expected 'no-slip' or 'specular'")
    return LAW_NAMES[value]


def _element_law(value, where):
    """``None`` (the scene's law) or the canonical name of an element's own law."""
    if value is None:
        return None
    return law_name(value, f"{where}.law")


def _with_law(d, law):
    """An element's file mapping ``d`` with its own law added, if it has one."""
    if law is not None:
        d["law"] = law
    return d


def _set(obj, **values):
    for k, v in values.items():
        object.__setattr__(obj, k, v)


def _floats(arr):
    return tuple(float(v) for v in arr)


def _radius(value, where):
    r = finite_float(value, f"{where}.radius")
    if r <= 0.0:
        raise ValueError(f"{where}.radius: must be > 0, got {r}")
    return r


def _build(cls, where, **fields):
    """Construct from file fields so that validation errors name the element's place in the file."""
    obj = cls.__new__(cls)
    _set(obj, **fields)
    obj._validate(where)
    return obj


def _side(value, allowed, field):
    if not isinstance(value, str) or value not in allowed:
        raise ValueError(f"{field}: must be one of {list(allowed)}, got {value!r}")
    return value


class StraightCarrier(NamedTuple):
    """The straight line an element lies on: through ``point`` along ``direction`` (arrays, not unit)."""

    point: np.ndarray
    direction: np.ndarray


class RoundCarrier(NamedTuple):
    """The circle an element lies on."""

    center: np.ndarray
    radius: float


#: The methods every element kind implements itself (``tests/test_element_protocol.py`` checks
#: them); :class:`BoundaryElement` gives the others a default that fits most kinds.
PROTOCOL = ("from_dict", "to_dict", "params", "size", "length", "bbox", "shifted", "side_distance",
            "distance", "features", "outline", "carrier", "frame_at", "at_fraction", "at_arclength",
            "orientation")


class BoundaryElement:
    """What every element kind knows about itself, so that nothing outside switches on its class.

    A kind subclasses this (as a frozen dataclass), sets the class attributes
    ``kind`` (its kernel code, :mod:`noslipsim.core.layout`), ``type_name``
    (its scene-file ``type``), ``finite`` (a finite set of points: the inside
    test measures the distance to it, not to its carrier) and ``bounded``
    (``False`` for an infinite line), implements every method named in
    :data:`PROTOCOL`, and is added to :data:`ELEMENT_TYPES`.  The methods with
    a body here are defaults that a kind overrides where they do not fit.
    docs/extending.md lists the other files a new kind touches.
    """

    bounded = True

    def _missing(self, name):
        raise NotImplementedError(f"{type(self).__name__} does not implement {name}() (elements.PROTOCOL)")

    @classmethod
    def from_dict(cls, d: Mapping[str, Any], where: str = "element"):
        """Build the element from its scene-file mapping (docs/scenes.md); errors name ``where`` and the field."""
        raise NotImplementedError(f"{cls.__name__} does not implement from_dict() (elements.PROTOCOL)")

    def to_dict(self) -> dict[str, Any]:
        """The element as its scene-file mapping (the inverse of :meth:`from_dict`)."""
        self._missing("to_dict")

    def params(self) -> list[float]:
        """The element's kernel parameter row (``core/layout.py``)."""
        self._missing("params")

    def exact_params(self) -> dict[int, float]:
        """Extra kernel columns ``{column: value}`` beyond :meth:`params` (none by default)."""
        return {}

    def size(self) -> float:
        """Largest coordinate magnitude of the element: its contribution to the scene's length scale."""
        self._missing("size")

    def length(self) -> float:
        """Arclength of the element (``inf`` for an unbounded one)."""
        self._missing("length")

    def bbox(self) -> tuple[float, float, float, float]:
        """``(x0, y0, x1, y1)``: an axis-aligned box holding the element."""
        self._missing("bbox")

    def shifted(self, dx: float, dy: float):
        """The same element translated by ``(dx, dy)``."""
        self._missing("shifted")

    def side_distance(self, pts: np.ndarray) -> np.ndarray:
        """Signed distance of ``pts`` (``(..., 2)``) to the element's carrier, positive on the table side."""
        self._missing("side_distance")

    def distance(self, pts: np.ndarray) -> np.ndarray:
        """Euclidean distance of ``pts`` (``(..., 2)``) to the element itself."""
        self._missing("distance")

    def features(self) -> list[tuple[str, float]]:
        """``[(what, size), ...]``: the lengths of the element that must resolve against the table's size."""
        self._missing("features")

    def feature_scale(self) -> float:
        """The element's first feature (a length or a radius; ``inf`` for none): what ``long_walls`` compares."""
        features = self.features()
        return features[0][1] if features else math.inf

    def long_wall(self, smallest: float) -> bool:
        """Whether a hit far from the element's start can cancel its plain distance (``layout.LONG_WALL``).

        ``smallest`` is the table's smallest :meth:`feature_scale`; curves never are.
        """
        return False

    def disk(self) -> tuple[tuple, float] | None:
        """``(center, radius)`` when the element is a disk scatterer (a full circle, table outside), else None."""
        return None

    def half_plane(self) -> tuple[tuple, tuple] | None:
        """``(point, inward normal)`` when the element bounds a half plane (an infinite line), else None."""
        return None

    def outline(self, dx: float = 0.0, dy: float = 0.0) -> tuple:
        """How the element is drawn, shifted by ``(dx, dy)``: a tuple of :mod:`noslipsim.outline` primitives.

        Infinite lines give none: the plot layer clips them to the window and
        to each other (:meth:`half_plane`).
        """
        self._missing("outline")

    def view_points(self) -> list[np.ndarray]:
        """Points a view of the table must hold to show the element (the corners of its box by default)."""
        x0, y0, x1, y1 = self.bbox()
        return [np.array([x0, y0]), np.array([x1, y1])]

    def carrier(self) -> StraightCarrier | RoundCarrier:
        """The straight line or circle the element lies on (where junctions are found)."""
        self._missing("carrier")

    def end_frames(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """For each end: ``(point, unit direction into the element, inward unit normal)``; none by default."""
        return []

    def frame_at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(point, n_out, turn, sigma)`` at arclength ``s`` in the engine's coordinate (``(N,)``).

        ``point`` and the outward unit normal ``n_out`` are ``(N, 2)``;
        ``turn`` is ``k`` with ``dn/dl = k t`` along ``t = J n_out``, and
        ``sigma`` is ``ds/dl`` (either may be a scalar).
        """
        self._missing("frame_at")

    def at_fraction(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(point, n_out)`` (each ``(N, 2)``) at the fractions ``u`` in ``[0, 1]`` of the way along."""
        self._missing("at_fraction")

    def at_arclength(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(point, n_out)`` (each ``(N, 2)``) at arclength ``s`` in ``[0, length]`` from the element's start."""
        self._missing("at_arclength")

    def orientation(self) -> float:
        """+1 if the element's own ``s`` increases along ``t = J n_out``, else -1."""
        self._missing("orientation")

    def local_s(self, s: np.ndarray) -> np.ndarray:
        """The element's own ``s`` (as the engine reports it) brought into ``[0, length]``."""
        return np.clip(s, 0.0, self.length())

    def wrap_arclength(self, ds: np.ndarray) -> np.ndarray:
        """``ds`` reduced to ``(-L/2, L/2]`` on a closed element of length ``L`` (unchanged by default)."""
        return ds


def _straight_frame(p, ux, uy, s):
    """:meth:`BoundaryElement.frame_at` of a straight piece: kernel row ``p``, ``s`` running along ``(ux, uy)``."""
    # n_out = -n_in, t = J n_out; s runs from the piece's point along t (line) or p0 -> p1 (segment)
    tx, ty = p[3], -p[2]
    point = np.c_[p[0] + s * ux, p[1] + s * uy]
    return point, np.broadcast_to(np.array([-p[2], -p[3]]), point.shape), 0.0, ux * tx + uy * ty


@dataclass(frozen=True)
class Line(BoundaryElement):
    """Infinite line through ``point``; ``normal`` is the unit normal into the table.

    ``law`` (keyword only): the element's own collision law, ``'specular'`` or
    ``'no-slip'``; ``None`` (the default) takes the scene's law.
    """

    point: tuple
    normal: tuple
    law: str | None = field(default=None, kw_only=True)
    kind = layout.LINE
    type_name = "line"
    finite = False
    bounded = False

    def __post_init__(self) -> None:
        self._validate("line")

    def _validate(self, where: str) -> None:
        """Check and normalise the fields; errors name ``where`` (the element's place in a file)."""
        point = finite_vector(self.point, f"{where}.point")
        normal = finite_vector(self.normal, f"{where}.normal")
        if normal[0] == 0.0 and normal[1] == 0.0:
            raise ValueError(f"{where}.normal: must be nonzero")
        _set(self, point=_floats(point), normal=unit_pair(*normal), law=_element_law(self.law, where))

    @classmethod
    def from_dict(cls, d: Mapping[str, Any], where: str = "element") -> Line:
        """Build the element from its scene-file mapping (docs/scenes.md); errors name ``where`` and the field."""
        no_unknown_keys(d, {"type", "point", "normal", "law"}, where)
        return _build(cls, where, point=required(d, "point", where), normal=required(d, "normal", where),
                      law=d.get("law"))

    def to_dict(self) -> dict[str, Any]:
        """The element as its scene-file mapping (the inverse of :meth:`from_dict`)."""
        return _with_law({"type": "line", "point": list(self.point), "normal": list(self.normal)}, self.law)

    def params(self) -> list[float]:
        """Kernel parameter row ``[px, py, nx, ny]`` (point; unit normal into the table; ``core/layout.py``)."""
        return [*self.point, *self.normal]

    def size(self) -> float:
        """Largest coordinate magnitude of the element: its contribution to the scene's length scale."""
        return max(abs(self.point[0]), abs(self.point[1]))

    def side_distance(self, pts: np.ndarray) -> np.ndarray:
        """Signed distance to the supporting line, positive on the table side."""
        return (pts[..., 0] - self.point[0]) * self.normal[0] + (pts[..., 1] - self.point[1]) * self.normal[1]

    def length(self) -> float:
        """Length of the line: infinite."""
        return math.inf

    def bbox(self) -> tuple[float, float, float, float]:
        """``(x0, y0, x1, y1)``: the axis-aligned bounding box (infinite for a line)."""
        return (-math.inf, -math.inf, math.inf, math.inf)

    def shifted(self, dx: float, dy: float) -> Line:
        """The same element translated by ``(dx, dy)``."""
        return Line((self.point[0] + dx, self.point[1] + dy), self.normal, law=self.law)

    def distance(self, pts: np.ndarray) -> np.ndarray:
        """Euclidean distance to the line: ``|side_distance|``."""
        return np.abs(self.side_distance(pts))

    def features(self) -> list[tuple[str, float]]:
        """None: a line has no length to resolve."""
        return []

    def long_wall(self, smallest: float) -> bool:
        """Always: a line carries hits arbitrarily far from its point."""
        return True

    def half_plane(self) -> tuple[tuple, tuple]:
        """``(point, inward normal)``: the table lies in this half plane."""
        return self.point, self.normal

    def outline(self, dx: float = 0.0, dy: float = 0.0) -> tuple:
        """None: the plot layer draws a line clipped to the window and the other lines (:meth:`half_plane`)."""
        return ()

    def view_points(self) -> list[np.ndarray]:
        """The line's anchor ``point``: a view of a floor under a peg holds the floor."""
        return [np.asarray(self.point, float)]

    def carrier(self) -> StraightCarrier:
        """The line itself, along ``J normal``."""
        n = np.array(self.normal)
        return StraightCarrier(np.array(self.point, float), np.array([-n[1], n[0]]))

    def frame_at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Frame at ``s`` along ``t = J n_out`` from ``point`` (see :meth:`BoundaryElement.frame_at`)."""
        p = self.params()
        return _straight_frame(p, p[3], -p[2], s)

    def at_fraction(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Refused: an infinite line has no fraction of the way along."""
        raise ValueError("an infinite line has no length to lay points along")

    def at_arclength(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Refused: an infinite line has no start to measure arclength from."""
        raise ValueError("an infinite line has no length to lay points along")

    def orientation(self) -> float:
        """+1: a line's ``s`` runs along ``t``."""
        return 1.0


@dataclass(frozen=True)
class Segment(BoundaryElement):
    """One-sided segment ``p0 -> p1``; the table lies on ``side`` ('left' or 'right').

    ``law`` (keyword only): the element's own collision law, ``'specular'`` or
    ``'no-slip'``; ``None`` (the default) takes the scene's law.
    """

    p0: tuple
    p1: tuple
    side: str = "left"
    law: str | None = field(default=None, kw_only=True)
    kind = layout.SEGMENT
    type_name = "segment"
    finite = True

    def __post_init__(self) -> None:
        self._validate("segment")

    def _validate(self, where: str) -> None:
        """Check and normalise the fields; errors name ``where`` (the element's place in a file)."""
        p0 = finite_vector(self.p0, f"{where}.p0")
        p1 = finite_vector(self.p1, f"{where}.p1")
        if np.array_equal(p0, p1):
            raise ValueError(f"{where}: zero-length segment (p0 == p1 == {p0.tolist()})")
        _side(self.side, ("left", "right"), f"{where}.side")
        _set(self, p0=_floats(p0), p1=_floats(p1), law=_element_law(self.law, where))

    @classmethod
    def from_dict(cls, d: Mapping[str, Any], where: str = "element") -> Segment:
        """Build the element from its scene-file mapping (docs/scenes.md); errors name ``where`` and the field."""
        no_unknown_keys(d, {"type", "p0", "p1", "side", "law"}, where)
        return _build(cls, where, p0=required(d, "p0", where), p1=required(d, "p1", where),
                      side=d.get("side", "left"), law=d.get("law"))

    def to_dict(self) -> dict[str, Any]:
        """The element as its scene-file mapping (the inverse of :meth:`from_dict`)."""
        return _with_law({"type": "segment", "p0": list(self.p0), "p1": list(self.p1), "side": self.side}, self.law)

    def _frame(self):
        dx, dy = self.p1[0] - self.p0[0], self.p1[1] - self.p0[1]
        L = math.hypot(dx, dy)
        ux, uy = unit_pair(dx, dy)
        sgn = 1.0 if self.side == "left" else -1.0
        return ux, uy, -sgn * uy, sgn * ux, L

    def params(self) -> list[float]:
        """Kernel parameter row ``[p0x, p0y, nx, ny, ux, uy, L]``: start, inward unit normal, unit direction, length."""
        ux, uy, nx, ny, L = self._frame()
        return [self.p0[0], self.p0[1], nx, ny, ux, uy, L]

    def exact_params(self) -> dict[int, float]:
        """Kernel columns for distances far along the segment: ``{column: value}`` (``core/layout.py``)."""
        sgn = 1.0 if self.side == "left" else -1.0
        return {layout.SEG_CROSS_SCALE: -sgn / self._frame()[4], layout.SEG_P1X: self.p1[0],
                layout.SEG_P1Y: self.p1[1]}

    def size(self) -> float:
        """Largest coordinate magnitude of the element: its contribution to the scene's length scale."""
        return max(abs(c) for c in (*self.p0, *self.p1))

    def length(self) -> float:
        """Length ``|p1 - p0|``."""
        return self._frame()[4]

    def bbox(self) -> tuple[float, float, float, float]:
        """``(x0, y0, x1, y1)``: the axis-aligned bounding box (infinite for a line)."""
        return (min(self.p0[0], self.p1[0]), min(self.p0[1], self.p1[1]),
                max(self.p0[0], self.p1[0]), max(self.p0[1], self.p1[1]))

    def shifted(self, dx: float, dy: float) -> Segment:
        """The same element translated by ``(dx, dy)``."""
        return Segment((self.p0[0] + dx, self.p0[1] + dy), (self.p1[0] + dx, self.p1[1] + dy), self.side,
                       law=self.law)

    def side_distance(self, pts: np.ndarray) -> np.ndarray:
        """Signed distance to the supporting line, positive on the table side."""
        _, _, nx, ny, _ = self._frame()
        return (pts[..., 0] - self.p0[0]) * nx + (pts[..., 1] - self.p0[1]) * ny

    def distance(self, pts: np.ndarray) -> np.ndarray:
        """Euclidean distance to the segment (a finite set)."""
        ux, uy, _, _, L = self._frame()
        rx, ry = pts[..., 0] - self.p0[0], pts[..., 1] - self.p0[1]
        u = np.clip(rx * ux + ry * uy, 0.0, L)
        return np.hypot(rx - u * ux, ry - u * uy)

    def features(self) -> list[tuple[str, float]]:
        """Its length."""
        return [("length", self.length())]

    def long_wall(self, smallest: float) -> bool:
        """Whether the segment is long against the table's smallest feature (``layout.LONG_WALL_RATIO``)."""
        return self.length() > layout.LONG_WALL_RATIO * smallest

    def outline(self, dx: float = 0.0, dy: float = 0.0) -> tuple:
        """One straight wall."""
        return (Wall([(self.p0[0] + dx, self.p0[1] + dy), (self.p1[0] + dx, self.p1[1] + dy)]),)

    def carrier(self) -> StraightCarrier:
        """The line through ``p0`` along ``p1 - p0``."""
        p0, p1 = np.array(self.p0, float), np.array(self.p1, float)
        return StraightCarrier(p0, p1 - p0)

    def end_frames(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """``p0`` and ``p1``, each with the unit direction into the segment and the inward normal."""
        p0, p1 = np.array(self.p0, float), np.array(self.p1, float)
        d = (p1 - p0) / np.linalg.norm(p1 - p0)
        n_in = np.array(self.params()[2:4])
        return [(p0, d, n_in), (p1, -d, n_in)]

    def frame_at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Frame at ``s`` from ``p0`` towards ``p1`` (see :meth:`BoundaryElement.frame_at`)."""
        p = self.params()
        return _straight_frame(p, p[4], p[5], s)

    def at_fraction(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(point, n_out)`` at ``p0 + u (p1 - p0)``."""
        p0, p1 = np.array(self.p0), np.array(self.p1)
        pt = p0 + u[:, None] * (p1 - p0)
        return pt, np.broadcast_to(-np.array(self.params()[2:4]), pt.shape)

    def at_arclength(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(point, n_out)`` at distance ``s`` from ``p0`` towards ``p1``."""
        x0, y0, nx, ny, ux, uy, _ = self.params()  # start, inward normal, unit direction, length
        pt = np.array([x0, y0]) + s[:, None] * np.array([ux, uy])
        return pt, np.broadcast_to(np.array([-nx, -ny]), pt.shape)

    def orientation(self) -> float:
        """+1 when the table is on the left (``s`` runs along ``t``), else -1."""
        return 1.0 if self.side == "left" else -1.0


class _Round(BoundaryElement):
    """What circles and arcs share: a curve of ``center`` and ``radius``, the table on ``side``."""

    #: The angle the engine's ``s`` is measured from (``frame_at``) and the one its own ``s`` starts at.
    _kernel_theta0 = 0.0
    _theta_start = 0.0

    @property
    def sigma(self) -> float:
        """``+1`` when the table lies outside the circle (a scatterer), ``-1`` inside (a container)."""
        return 1.0 if self.side == "outside" else -1.0

    def size(self) -> float:
        """Largest coordinate magnitude of the element: its contribution to the scene's length scale."""
        return max(abs(self.center[0]) + self.radius, abs(self.center[1]) + self.radius)

    def bbox(self) -> tuple[float, float, float, float]:
        """``(x0, y0, x1, y1)``: the bounding box of the full circle (conservative for an arc)."""
        c, r = self.center, self.radius
        return (c[0] - r, c[1] - r, c[0] + r, c[1] + r)

    def side_distance(self, pts: np.ndarray) -> np.ndarray:
        """Signed distance ``sigma (|q - c| - r)`` to the (supporting) circle, positive on the table side."""
        rho = np.hypot(pts[..., 0] - self.center[0], pts[..., 1] - self.center[1])
        return self.sigma * (rho - self.radius)

    def carrier(self) -> RoundCarrier:
        """The (supporting) circle."""
        return RoundCarrier(np.array(self.center, float), self.radius)

    def _points(self, angle):
        """``(point, n_out)`` at the polar angles ``angle``."""
        radial = np.c_[np.cos(angle), np.sin(angle)]
        return np.array(self.center) + self.radius * radial, -self.sigma * radial

    def frame_at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Frame at ``s = r (theta - theta0)`` (see :meth:`BoundaryElement.frame_at`)."""
        # point c + r e(theta), n_out = -sigma_c e, t = -sigma_c e_theta
        r, sig = self.radius, self.sigma
        theta = self._kernel_theta0 + s / r
        cos, sin = np.cos(theta), np.sin(theta)
        return (np.c_[self.center[0] + r * cos, self.center[1] + r * sin], np.c_[-sig * cos, -sig * sin],
                -sig / r, -sig)

    def at_arclength(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(point, n_out)`` at arclength ``s`` counter-clockwise from the start angle."""
        return self._points(self._theta_start + s / self.radius)

    def orientation(self) -> float:
        """``-sigma``: ``s`` runs counter-clockwise, ``t`` clockwise on a scatterer (``sigma = +1``)."""
        return -self.sigma


@dataclass(frozen=True)
class Circle(_Round):
    """Full circle; ``side='outside'`` is a scatterer, ``'inside'`` a container.

    ``law`` (keyword only): the element's own collision law, ``'specular'`` or
    ``'no-slip'``; ``None`` (the default) takes the scene's law.
    """

    center: tuple
    radius: float
    side: str = "outside"
    law: str | None = field(default=None, kw_only=True)
    kind = layout.CIRCLE
    type_name = "circle"
    finite = False  # a full circle bounds the table globally, like a line

    def __post_init__(self) -> None:
        self._validate("circle")

    def _validate(self, where: str) -> None:
        """Check and normalise the fields; errors name ``where`` (the element's place in a file)."""
        center = finite_vector(self.center, f"{where}.center")
        radius = _radius(self.radius, where)
        _side(self.side, ("outside", "inside"), f"{where}.side")
        _set(self, center=_floats(center), radius=radius, law=_element_law(self.law, where))

    @classmethod
    def from_dict(cls, d: Mapping[str, Any], where: str = "element") -> Circle:
        """Build the element from its scene-file mapping (docs/scenes.md); errors name ``where`` and the field."""
        no_unknown_keys(d, {"type", "center", "radius", "side", "law"}, where)
        return _build(cls, where, center=required(d, "center", where),
                      radius=required(d, "radius", where), side=d.get("side", "outside"), law=d.get("law"))

    def to_dict(self) -> dict[str, Any]:
        """The element as its scene-file mapping (the inverse of :meth:`from_dict`)."""
        return _with_law({"type": "circle", "center": list(self.center), "radius": self.radius, "side": self.side},
                         self.law)

    def params(self) -> list[float]:
        """Kernel parameter row ``[cx, cy, r, sigma]``."""
        return [self.center[0], self.center[1], self.radius, self.sigma]

    def length(self) -> float:
        """Circumference ``2 pi r``."""
        return TWO_PI * self.radius

    def shifted(self, dx: float, dy: float) -> Circle:
        """The same element translated by ``(dx, dy)``."""
        return Circle((self.center[0] + dx, self.center[1] + dy), self.radius, self.side, law=self.law)

    def distance(self, pts: np.ndarray) -> np.ndarray:
        """Euclidean distance to the circle: ``|side_distance|``."""
        return np.abs(self.side_distance(pts))

    def features(self) -> list[tuple[str, float]]:
        """Its radius."""
        return [("radius", self.radius)]

    def disk(self) -> tuple[tuple, float] | None:
        """``(center, radius)`` for a scatterer (``side='outside'``), None for a container."""
        return (self.center, self.radius) if self.side == "outside" else None

    def outline(self, dx: float = 0.0, dy: float = 0.0) -> tuple:
        """A filled disc (a scatterer) or an unfilled circle (a container)."""
        c = (self.center[0] + dx, self.center[1] + dy)
        return (Disc(c, self.radius) if self.side == "outside" else Curve(c, self.radius),)

    def at_fraction(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(point, n_out)`` at the angles ``2 pi u``."""
        return self._points(0.0 + u * (TWO_PI - 0.0))

    def local_s(self, s: np.ndarray) -> np.ndarray:
        """``s`` modulo the circumference."""
        return np.mod(s, TWO_PI * self.radius)

    def wrap_arclength(self, ds: np.ndarray) -> np.ndarray:
        """``ds`` reduced to ``(-L/2, L/2]``, ``L`` the circumference."""
        L = self.length()
        return ds - L * np.round(ds / L)


@dataclass(frozen=True)
class Arc(_Round):
    """CCW arc of a circle from ``theta0`` to ``theta1`` (radians); table on ``side``.

    ``law`` (keyword only): the element's own collision law, ``'specular'`` or
    ``'no-slip'``; ``None`` (the default) takes the scene's law.
    """

    center: tuple
    radius: float
    theta0: float
    theta1: float
    side: str = "inside"
    law: str | None = field(default=None, kw_only=True)
    kind = layout.ARC
    type_name = "arc"
    finite = True

    def __post_init__(self) -> None:
        self._validate("arc")

    def _validate(self, where: str) -> None:
        """Check and normalise the fields; errors name ``where`` (the element's place in a file)."""
        center = finite_vector(self.center, f"{where}.center")
        radius = _radius(self.radius, where)
        theta0 = finite_float(self.theta0, f"{where}.theta0")
        theta1 = finite_float(self.theta1, f"{where}.theta1")
        if theta1 <= theta0:
            raise ValueError(f"{where}.theta1: must exceed theta0 (arcs run CCW), got {theta0} -> {theta1}")
        if theta1 - theta0 > TWO_PI:
            raise ValueError(f"{where}: arc span {theta1 - theta0} exceeds 2 pi")
        _side(self.side, ("outside", "inside"), f"{where}.side")
        _set(self, center=_floats(center), radius=radius, theta0=theta0, theta1=theta1,
             law=_element_law(self.law, where))

    @classmethod
    def from_dict(cls, d: Mapping[str, Any], where: str = "element") -> Arc:
        """Build the element from its scene-file mapping (docs/scenes.md); errors name ``where`` and the field."""
        no_unknown_keys(d, {"type", "center", "radius", "theta0", "theta1", "side", "law"}, where)
        return _build(cls, where, center=required(d, "center", where),
                      radius=required(d, "radius", where), theta0=required(d, "theta0", where),
                      theta1=required(d, "theta1", where), side=d.get("side", "inside"), law=d.get("law"))

    def to_dict(self) -> dict[str, Any]:
        """The element as its scene-file mapping (the inverse of :meth:`from_dict`)."""
        return _with_law({"type": "arc", "center": list(self.center), "radius": self.radius,
                          "theta0": self.theta0, "theta1": self.theta1, "side": self.side}, self.law)

    @property
    def _kernel_theta0(self) -> float:
        return self.theta0 % TWO_PI  # the kernel row's start angle (params)

    @property
    def _theta_start(self) -> float:
        return self.theta0

    def params(self) -> list[float]:
        """Kernel parameter row ``[cx, cy, r, sigma, theta0 mod 2 pi, span]``."""
        return [self.center[0], self.center[1], self.radius, self.sigma,
                self.theta0 % TWO_PI, self.theta1 - self.theta0]

    def length(self) -> float:
        """Arc length ``r (theta1 - theta0)``."""
        return self.radius * (self.theta1 - self.theta0)

    def shifted(self, dx: float, dy: float) -> Arc:
        """The same element translated by ``(dx, dy)``."""
        return Arc((self.center[0] + dx, self.center[1] + dy), self.radius, self.theta0, self.theta1, self.side,
                   law=self.law)

    def endpoints(self) -> list[tuple[float, float]]:
        """The arc's two end points, at ``theta0`` and ``theta1``."""
        c, r = self.center, self.radius
        return [(c[0] + r * math.cos(a), c[1] + r * math.sin(a)) for a in (self.theta0, self.theta1)]

    def distance(self, pts: np.ndarray) -> np.ndarray:
        """Euclidean distance to the arc (a finite set): to the curve within its span, else to the nearer end."""
        dx, dy = pts[..., 0] - self.center[0], pts[..., 1] - self.center[1]
        rel = (np.arctan2(dy, dx) - self.theta0) % TWO_PI
        on_span = rel <= self.theta1 - self.theta0
        d_curve = np.abs(np.hypot(dx, dy) - self.radius)
        (ax, ay), (bx, by) = self.endpoints()
        d_ends = np.minimum(np.hypot(pts[..., 0] - ax, pts[..., 1] - ay),
                            np.hypot(pts[..., 0] - bx, pts[..., 1] - by))
        return np.where(on_span, d_curve, d_ends)

    def features(self) -> list[tuple[str, float]]:
        """Its radius and its arclength."""
        return [("radius", self.radius), ("arc length", self.length())]

    def outline(self, dx: float = 0.0, dy: float = 0.0) -> tuple:
        """One unfilled arc."""
        return (Curve((self.center[0] + dx, self.center[1] + dy), self.radius, self.theta0, self.theta1),)

    def view_points(self) -> list[np.ndarray]:
        """The corners of the arc's tight box: its ends and the axis points it passes through."""
        span = (self.theta1 - self.theta0) % TWO_PI or TWO_PI
        angles = [self.theta0, self.theta0 + span] + [k * math.pi / 2 for k in range(8)
                                                       if 0.0 <= (k * math.pi / 2 - self.theta0) % TWO_PI <= span]
        xs = [self.center[0] + self.radius * math.cos(a) for a in angles]
        ys = [self.center[1] + self.radius * math.sin(a) for a in angles]
        return [np.array([min(xs), min(ys)]), np.array([max(xs), max(ys)])]

    def end_frames(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """The ends at ``theta0`` and ``theta1``, each with the unit direction into the arc and the inward normal."""
        out = []
        for ang, sgn in ((self.theta0, 1.0), (self.theta1, -1.0)):
            radial = np.array([math.cos(ang), math.sin(ang)])
            pt = np.array(self.center, float) + self.radius * radial
            out.append((pt, sgn * np.array([-radial[1], radial[0]]), self.sigma * radial))
        return out

    def at_fraction(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(point, n_out)`` at the angles ``theta0 + u (theta1 - theta0)``."""
        return self._points(self.theta0 + u * (self.theta1 - self.theta0))

    def local_s(self, s: np.ndarray) -> np.ndarray:
        """``s`` in ``[0, length]``: a hit just before ``theta0`` comes back as nearly ``2 pi r`` (its angle wraps)."""
        s = np.where(s > 0.5 * (self.length() + TWO_PI * self.radius), s - TWO_PI * self.radius, s)
        return np.clip(s, 0.0, self.length())


#: Any table element.
Element = Line | Segment | Circle | Arc

#: Every element kind, by its scene-file ``type``.
ELEMENT_TYPES = {cls.type_name: cls for cls in (Line, Segment, Circle, Arc)}


def element_from_dict(d: Mapping[str, Any], where: str = "element") -> Element:
    """Build an element from its scene-file mapping."""
    if not isinstance(d, dict):
        raise ValueError(f"{where}: expected a mapping, got {type(d).__name__}")
    kind = d.get("type")
    if not isinstance(kind, str) or kind not in ELEMENT_TYPES:
        raise ValueError(f"{where}.type: unknown element type {kind!r}; expected one of {sorted(ELEMENT_TYPES)}")
    return ELEMENT_TYPES[kind].from_dict(d, where)


# ---------------------------------------------------------------------------- simple polygons
def _orient(a, b, c):
    """Sign of the turn ``a -> b -> c`` (arrays of points, broadcast): +1 left, -1 right, 0 collinear."""
    return np.sign((b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
                   - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0]))


def _on_box(a, b, p):
    """``p`` within the bounding box of ``a b`` (for collinear points: on the segment)."""
    return ((np.minimum(a[..., 0], b[..., 0]) <= p[..., 0]) & (p[..., 0] <= np.maximum(a[..., 0], b[..., 0]))
            & (np.minimum(a[..., 1], b[..., 1]) <= p[..., 1]) & (p[..., 1] <= np.maximum(a[..., 1], b[..., 1])))


def _point_segment_distance(p, a, b):
    """Distance from points ``p`` to segments ``a b`` (arrays of points, broadcast)."""
    ab, ap = b - a, p - a
    with np.errstate(divide="ignore", invalid="ignore"):  # an edge whose squared length underflows: its start
        u = np.nan_to_num(np.clip(np.sum(ap * ab, axis=-1) / np.sum(ab * ab, axis=-1), 0.0, 1.0))
    return np.hypot(*np.moveaxis(ap - u[..., None] * ab, -1, 0))


def polygon_defect(vertices, gap=0.0) -> tuple[str, int, int] | None:
    """Why the closed polygon through ``vertices`` (``(n, 2)``, ``n >= 2``) is not simple, or ``None``.

    Edge ``i`` runs from vertex ``i`` to vertex ``i + 1`` (cyclically).  The
    answer is ``('fold', i, i + 1)`` for an edge ``i + 1`` that turns straight
    back along edge ``i`` (a spike of zero width; any 2-gon), ``('meet', i,
    j)`` for two edges that cross or touch away from the vertex they share,
    or ``('near', i, j)`` for two edges without a common vertex that come
    within ``gap`` of each other (a spike or a neck thinner than the engine's
    tolerances, which its orbits cross).
    A polygon that is not simple has no inside: its lobes of opposite
    orientation make the "table side of the nearest edge" rule count points
    outside it as inside (the one check behind :func:`noslipsim.tables.polygon`
    and the closed chains of segments of a scene).
    """
    v = np.asarray(vertices, dtype=float)
    # scaled by a power of two (exact, so every sign below is the unscaled one): no product over- or underflows
    unit = math.ldexp(1.0, math.frexp(float(np.abs(v).max()))[1] - 1) if np.abs(v).max() > 0 else 1.0
    v, gap = v / unit, gap / unit
    n = len(v)
    a, b = v, np.roll(v, -1, axis=0)
    d0, d1 = b - a, np.roll(b - a, -1, axis=0)
    back = (d0[:, 0] * d1[:, 1] - d0[:, 1] * d1[:, 0] == 0) & (np.sum(d0 * d1, axis=1) < 0)
    if back.any():
        k = int(np.argmax(back))
        return "fold", k, (k + 1) % n
    i, j = np.triu_indices(n, 2)
    keep = ~((i == 0) & (j == n - 1))  # the last edge meets the first at vertex 0
    i, j = i[keep], j[keep]
    p1, p2, p3, p4 = a[i], b[i], a[j], b[j]
    o1, o2, o3, o4 = _orient(p1, p2, p3), _orient(p1, p2, p4), _orient(p3, p4, p1), _orient(p3, p4, p2)
    cross = (o1 * o2 < 0) & (o3 * o4 < 0)
    touch = (((o1 == 0) & _on_box(p1, p2, p3)) | ((o2 == 0) & _on_box(p1, p2, p4))
             | ((o3 == 0) & _on_box(p3, p4, p1)) | ((o4 == 0) & _on_box(p3, p4, p2)))
    bad = cross | touch
    if bad.any():
        k = int(np.argmax(bad))
        return "meet", int(i[k]), int(j[k])
    apart = (j - i > 1) & ~((i == 0) & (j == n - 1)) if n > 3 else np.zeros(len(i), bool)  # no shared vertex
    if gap > 0.0 and apart.any():
        near = np.minimum.reduce([_point_segment_distance(p1, p3, p4), _point_segment_distance(p2, p3, p4),
                                  _point_segment_distance(p3, p1, p2), _point_segment_distance(p4, p1, p2)])
        close = apart & (near < gap)
        if close.any():
            k = int(np.argmax(close))
            return "near", int(i[k]), int(j[k])
    return None


#: Two edges of a polygon without a common vertex must stay this far apart, relative to the polygon's
#: size (its largest coordinate magnitude): the engine's tolerances are 1e-11 of the size, and a
#: thinner spike or neck is crossed by its orbits (the smallest feature a scene accepts, as
#: ``noslipsim.scenes.MIN_FEATURE``).
MIN_GAP = 1e-9


def closed_chains(elements) -> list[list[int]]:
    """The closed chains of segments among ``elements``: each a list of element indices in the chain's order.

    Segments are joined where an end of one is exactly an end of another
    (the vertices of a polygon written as segments, or by
    :meth:`noslipsim.Scene.to_yaml`); a chain is closed when every vertex on
    it joins exactly two segments.  Which way each segment runs (and its
    ``side``) does not matter.  Other pieces (arcs, open chains, vertices
    where three or more segments meet) are left out.
    """
    at = {}
    for k, e in enumerate(elements):
        if isinstance(e, Segment):
            for p in (e.p0, e.p1):
                at.setdefault(p, []).append(k)
    seen, chains = set(), []
    for k, e in enumerate(elements):
        if not isinstance(e, Segment) or k in seen:
            continue
        chain, p, closed = [k], e.p1, False
        while len(at[p]) == 2:
            nxt = at[p][0] if at[p][1] == chain[-1] else at[p][1]
            if nxt == k:
                closed = True
                break
            chain.append(nxt)
            q = elements[nxt]
            p = q.p1 if q.p0 == p else q.p0
        seen.update(chain)
        if closed:
            chains.append(chain)
    return chains


def chain_vertices(elements, chain) -> np.ndarray:
    """Vertices ``(n, 2)`` of a closed chain of segments: vertex ``i`` starts the chain's ``i``-th segment."""
    first, second = elements[chain[0]], elements[chain[1]]
    p = first.p0 if first.p0 not in (second.p0, second.p1) else first.p1
    out = []
    for k in chain:
        e = elements[k]
        out.append(p)
        p = e.p1 if e.p0 == p else e.p0
    return np.array(out, dtype=float)


def _pinched_vertex(elements):
    """``(point, segment indices)`` of a vertex where four or more segments of closed chains meet, or ``None``.

    Segments joined end to end form closed chains when every vertex of their
    connected group joins an even number of them; a vertex joining four or more
    is a chain that passes through one point twice (a figure eight, a polygon
    whose vertex list repeats a point), which :func:`closed_chains` does not
    follow and :func:`polygon_defect` refuses.
    """
    at = {}
    for k, e in enumerate(elements):
        if isinstance(e, Segment):
            for p in (e.p0, e.p1):
                at.setdefault(p, []).append(k)
    group = {k: k for ks in at.values() for k in ks}

    def root(k):
        while group[k] != k:
            group[k] = group[group[k]]
            k = group[k]
        return k

    for ks in at.values():
        for k in ks[1:]:
            group[root(k)] = root(ks[0])
    odd = {root(ks[0]) for ks in at.values() if len(ks) % 2}
    for p, ks in at.items():
        if len(ks) >= 4 and root(ks[0]) not in odd:
            return p, ks
    return None


def check_closed_chains(elements) -> None:
    """Refuse a closed chain of segments that crosses or touches itself (a bow tie), naming the two segments.

    The same check as :func:`noslipsim.tables.polygon` makes of its vertices
    (:func:`noslipsim.elements.polygon_defect`): a polygon that is not simple
    has no inside, and points outside its lobes would count as in the table.
    """
    pinch = _pinched_vertex(elements)
    if pinch is not None:
        p, ks = pinch
        names = ", ".join(f"elements[{k}]" for k in sorted(ks))
        raise ValueError(f"elements[{max(ks)}]: the closed chain of segments through {list(p)} is not a simple "
                         f"polygon: {names} all meet there (the chain passes through the point twice)")
    for chain in closed_chains(elements):
        v = chain_vertices(elements, chain)
        defect = polygon_defect(v, MIN_GAP * float(np.abs(v).max()))
        if defect is None:
            continue
        kind, i, j = defect
        a, b = sorted((chain[i], chain[j]))
        what = {"fold": "run back along each other", "meet": "cross or touch away from a shared end",
                "near": f"come within {MIN_GAP:g} times the polygon's size of each other (inside the engine's "
                        "tolerances, which orbits cross)"}[kind]
        raise ValueError(f"elements[{b}]: the closed chain of segments {sorted(chain)} is not a simple polygon: "
                         f"elements[{a}] ({_ends(elements[a])}) and elements[{b}] ({_ends(elements[b])}) {what}")


def _ends(segment):
    return f"{list(segment.p0)} -> {list(segment.p1)}"
