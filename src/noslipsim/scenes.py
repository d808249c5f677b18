"""Scenes: a table (boundary elements), a collision law, a mass distribution and a force.

A scene is the public way to define a billiard (docs/scenes.md)::

    law: no-slip            # or specular
    gamma: 0.7071067811865476
    force: [0.0, -1.0]
    thermostat: isokinetic   # optional: fly the force with the Gaussian isokinetic thermostat
    magnetic: 0.5            # optional: cyclotron angular frequency W of a field normal to the table
    elements: [...]          # see noslipsim.elements; each may set its own law
    lattice: {a1: [1, 0], a2: [0, 1]}   # optional: periodic repetition
    top: 0.8660254037844386  # optional, with a lattice of circles: no copies above this height

The table is the set of points on the table side of every line and full
circle and of the nearest segment or arc (for a closed polygon this is its
interior; at a shared vertex both pieces agree).
"""
from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import yaml
from numpy.typing import ArrayLike

from ._engine.lattice import cell_of, covering_radius, disks_cover_plane, lattice_matrix
from ._unit import unit_pair
from ._validate import finite_vector, no_unknown_keys, nonnegative, read_yaml, required
from .core import layout
from .core.laws import noslip_coefficients
from .elements import BoundaryElement, check_closed_chains, element_from_dict, law_name

LAWS = {"no-slip": layout.NOSLIP, "noslip": layout.NOSLIP, "specular": layout.SPECULAR}
_SCENE_KEYS = {"law", "gamma", "force", "thermostat", "magnetic", "elements", "lattice", "top"}
#: Thermostats a scene may fly its force with (``None``: none, free fall).
THERMOSTATS = ("isokinetic",)


def _law_name(law):
    return law_name(law, "law")


def _thermostat_name(thermostat):
    """``None`` (no thermostat; also written ``'none'``) or ``'isokinetic'``; anything else is refused by name."""
    if thermostat is None or thermostat == "none":
        return None
    if isinstance(thermostat, str) and thermostat in THERMOSTATS:
        return thermostat
    raise ValueError(f"thermostat: unknown thermostat {thermostat!r}; expected 'isokinetic' or none")


def _magnetic_value(magnetic):
    """``magnetic`` as a finite float (bools and non-numbers refused by name)."""
    if isinstance(magnetic, bool) or not isinstance(magnetic, (int, float, np.floating, np.integer)):
        raise TypeError(f"magnetic: expected a number (the cyclotron angular frequency), "
                        f"got {type(magnetic).__name__}")
    value = float(magnetic)
    if not math.isfinite(value):
        raise ValueError(f"magnetic: must be finite, got {value} (0 for no field)")
    return value


def _check_magnetic(scene):
    """Refuse a magnetic field together with what its flight does not combine with yet, by name."""
    if scene.magnetic == 0.0:
        return
    if scene.force != (0.0, 0.0):
        raise ValueError(f"magnetic: a field (magnetic = {scene.magnetic}) together with a force "
                         f"{list(scene.force)} is not supported; use one or the other")
    if scene.thermostat is not None:
        raise ValueError(f"magnetic: a field (magnetic = {scene.magnetic}) is not supported with thermostat "
                         f"{scene.thermostat!r}")


#: Most element copies a periodic scene may need around one cell (counted from the
#: elements' bounding boxes).  Every flight through a cell tests them all and building the
#: scene pairs them up (junctions), so an ill-posed lattice (``a1`` and ``a2`` nearly
#: parallel, or elements spanning many cells) is refused instead of hanging.
MAX_LATTICE_COPIES = 1000


def _check_copies(elements, lattice):
    """Refuse a lattice whose elements would need more than ``MAX_LATTICE_COPIES`` copies per cell."""
    try:
        with np.errstate(all="ignore"):
            _, B = lattice_matrix(lattice)
    except np.linalg.LinAlgError:
        B = np.full((2, 2), np.nan)
    if not np.all(np.isfinite(B)):
        raise ValueError(f"lattice: a1 = {lattice['a1']} and a2 = {lattice['a2']} are too close to parallel")
    total = 0.0
    for e in elements:
        x0, y0, x1, y1 = e.bbox()
        if not all(map(math.isfinite, (x0, y0, x1, y1))):
            continue  # an infinite element: refused by name in Scene.__post_init__
        with np.errstate(all="ignore"):
            coords = np.array([[x0, y0], [x1, y0], [x0, y1], [x1, y1]]) @ B.T
            span = coords.max(axis=0) - coords.min(axis=0)
            total += float(np.prod(np.floor(span) + 2.0))  # cells a box of that span can meet, per direction
    if not total <= MAX_LATTICE_COPIES:
        raise ValueError(f"lattice: the elements would need about {total:.3g} copies around each cell "
                         f"(at most {MAX_LATTICE_COPIES}): a1 = {lattice['a1']} and a2 = {lattice['a2']} "
                         "are nearly parallel, or the elements are much larger than a cell")


def _element_tuple(elements):
    """The elements as a tuple, each a Line, Segment, Circle or Arc (TypeError naming the one that is not)."""
    try:
        out = tuple(elements)
    except TypeError:
        raise TypeError(f"elements: expected a sequence of Line, Segment, Circle or Arc, "
                        f"got {type(elements).__name__}") from None
    for i, e in enumerate(out):
        if not isinstance(e, BoundaryElement):
            raise TypeError(f"elements[{i}]: expected a Line, Segment, Circle or Arc (or use Scene.from_dict "
                            f"for mappings), got {type(e).__name__}")
    return out


#: On a lattice a segment must be longer than this, relative to the longer lattice vector:
#: its copies are shifted by lattice vectors, and a shorter one collapses to a point in rounding.
LATTICE_MIN_SEGMENT = 1e-9


def _check_lattice_segments(elements, lattice):
    size = max(math.hypot(*lattice["a1"]), math.hypot(*lattice["a2"]))
    for i, e in enumerate(elements):
        for what, value in e.features():
            if what == "length" and not value > LATTICE_MIN_SEGMENT * size:
                raise ValueError(f"elements[{i}]: a {e.type_name} of length {value:.3g} is too short for a "
                                 f"lattice of size {size:.3g} (at least {LATTICE_MIN_SEGMENT:g} times it)")


#: Range of validity (docs/conventions.md, "Range of validity"): lengths (the table's size, a
#: start's distance from its cell's origin) and speeds must lie in ``[MIN_MAGNITUDE, MAX_MAGNITUDE]``.
#: The engine multiplies lengths ``L``, speeds ``V`` and forces ``~V^2/L`` into terms such as
#: ``|q|^2``, ``(q.v)^2`` and ``(a.v)^2 ~ V^6/L^2``; with both in ``1e+-30`` every product of up to
#: eight of them stays a normal float (``1e+-240``), and the scaled twins of
#: ``benchmarks/magnitudes.py`` are exact to the bit well beyond (1e+-149 in length alone, 1e+-72
#: in both, 1e+-48 in speed alone under a force, where ``(a.v)^2`` is the first to overflow).
MAX_MAGNITUDE = 1e30
MIN_MAGNITUDE = 1e-30
#: A force's magnitude ``|a|`` (an acceleration: a speed squared over a length) must lie in this
#: range when it is not zero: ``MIN_MAGNITUDE**3 .. MAX_MAGNITUDE**3``.
MIN_FORCE = MIN_MAGNITUDE ** 3
MAX_FORCE = MAX_MAGNITUDE ** 3
#: Every segment, radius and arc must be at least this fraction of the table's size: the engine's
#: tolerances are ``1e-11`` of it (core/tolerances.py), and a smaller piece would lie inside them.
MIN_FEATURE = 1e-9
#: The largest field a thermostatted flight is exact for, in the orbit's own units: ``|a| L / |v|^2``
#: (``L`` the length scale).  Above about 4.5e7 a particle leaving a disk is turned back into it
#: within ~1e-12 of the flight's time, a root the float engine misses (the hexagonal gas, 1e8 at
#: R = 0.45: it flew on through the disk); up to 1.4e7 the flight audit found no leak on the
#: hexagonal gas, a Sinai box, a circle and a stadium (benchmarks/RESULTS.md).
MAX_THERMOSTAT_FIELD = 1e6
_RANGE_DOC = "docs/conventions.md, 'Range of validity'"


def table_size(elements, lattice=None) -> float:
    """The table's length scale: its largest coordinate magnitude (and lattice vector), ``0`` for lines through 0."""
    size = max(e.size() for e in elements)
    if lattice is not None:
        size = max(size, *(math.hypot(*lattice[k]) for k in ("a1", "a2")))
    return float(size)


def _check_magnitudes(scene):
    """Refuse a table or force outside the range the engine is exact for, naming the quantity."""
    size = table_size(scene.elements, scene.lattice)
    if size > MAX_MAGNITUDE:
        raise ValueError(f"elements: the table's coordinates reach {size:.3g}; the engine is exact for tables up "
                         f"to {MAX_MAGNITUDE:g} ({_RANGE_DOC}): use a larger length unit")
    if 0.0 < size < MIN_MAGNITUDE:
        raise ValueError(f"elements: the table's size is {size:.3g}; the engine is exact for tables of at least "
                         f"{MIN_MAGNITUDE:g} ({_RANGE_DOC}): use a smaller length unit")
    floor = max(MIN_FEATURE * size, MIN_MAGNITUDE)
    for i, e in enumerate(scene.elements):
        for what, value in e.features():
            if not value >= floor:
                why = (f"{MIN_FEATURE:g} times the table's size {size:.3g}: it would lie within the engine's "
                       "tolerances" if floor > MIN_MAGNITUDE else
                       f"{MIN_MAGNITUDE:g}, the smallest length the engine is exact for")
                raise ValueError(f"elements[{i}]: a {e.type_name} {what} of {value:.3g} is below {why} "
                                 f"({_RANGE_DOC})")
    a = math.hypot(*scene.force)
    if a != 0.0 and not MIN_FORCE <= a <= MAX_FORCE:
        raise ValueError(f"force: |a| = {a:.3g} lies outside [{MIN_FORCE:g}, {MAX_FORCE:g}], the range the engine "
                         f"is exact for ({_RANGE_DOC}); use 0 for no force")


def _flown(kernel, arrays, *field):
    """``(x, y, vx, vy)`` from ``kernel(x, y, vx, vy, *field, tau, out)`` over broadcast arrays of one shape."""
    flat = [np.ascontiguousarray(a.ravel()) for a in arrays]
    out = np.empty((flat[0].size, 4))
    kernel(*flat[:4], *field, flat[4], out)
    return tuple(out[:, k].reshape(arrays[0].shape) for k in range(4))


def _check_not_covered(elements, lattice):
    """Refuse a lattice whose disk scatterers cover the plane: its table would have no point at all.

    Only the full circles with ``side: outside`` are counted (every other element can only
    take more away); the test is :func:`noslipsim._engine.lattice.disks_cover_plane`, exact
    for one disk and never refusing a table that has points for several.
    """
    which = [i for i, e in enumerate(elements) if e.disk() is not None]
    if not which or not disks_cover_plane([elements[i].disk() for i in which], lattice):
        return
    if len(which) == 1:
        i = which[0]
        raise ValueError(f"elements[{i}].radius: {elements[i].radius} is at least the lattice's covering "
                         f"radius {covering_radius(lattice)} (the largest distance from a point to its nearest "
                         "lattice site), so the disk's copies cover the plane and the table is empty; use a smaller "
                         "radius or longer lattice vectors")
    names = ", ".join(f"elements[{i}]" for i in which)
    raise ValueError(f"elements: the circles {names} and their lattice copies cover "
                     "the plane, so the table is empty; use smaller radii or longer lattice vectors")


@dataclass(frozen=True)
class Scene:
    """A billiard table with its physics.

    Parameters
    ----------
    elements : sequence of Line, Segment, Circle, Arc
        Boundary pieces; their order fixes the ``element`` index in outputs.
    law : {'no-slip', 'specular'}
        Collision law (docs/conventions.md) of every element that does not
        set its own (``Segment(..., law='specular')``: a mixed table, such as
        specular walls around a no-slip scatterer; :attr:`element_laws`).
    gamma : float
        Mass-distribution constant ``gamma = sqrt(I / (m R^2))`` (nondimensional,
        >= 0): 0 point mass, ``1/sqrt(2)`` uniform disk, 1 ring.  One per
        scene: every no-slip element uses it, a specular one ignores it.
    force : (float, float)
        Constant acceleration ``(a_x, a_y)`` acting between collisions.
    thermostat : {None, 'isokinetic'}
        ``None``: the force accelerates the particle (free fall, parabolic
        flights).  ``'isokinetic'``: the Gaussian isokinetic thermostat,
        ``dv/dt = F - alpha v`` with ``alpha = F.v/|v|^2``: the speed and the
        spin are constant in flight and the heading turns towards the field
        (the driven, thermostatted Lorentz gas; docs/scenes.md).
    lattice : dict or None
        ``{'a1': [..], 'a2': [..]}`` to repeat the elements periodically.
    magnetic : float
        ``W``, the cyclotron angular frequency of a magnetic field normal to
        the table (inverse time; 0: no field).  Between collisions
        ``dv/dt = W J v``: the velocity turns counter-clockwise at the rate
        ``W`` (clockwise for ``W < 0``) on a circle of radius ``|v|/|W|``, and
        the spin is untouched.  Not with a force or the thermostat.  Today
        only :mod:`noslipsim.reference` flies it; the compiled entry points
        refuse a scene with ``magnetic != 0`` (docs/scenes.md).
    top : float or None
        A bounded lattice: no element copy whose centre lies above the height
        ``top`` (a Galton board's top row with nothing above it; a particle
        released above it falls onto it).  Only with a lattice of circle
        scatterers, and not with the thermostat.  Put it between two rows: a
        centre at exactly ``top`` is kept, and a rewritten (canonical) scene
        rounds differently.  ``None``: the lattice continues everywhere.
    """

    elements: tuple
    law: str = "no-slip"
    gamma: float = 1.0 / math.sqrt(2.0)
    force: tuple = (0.0, 0.0)
    lattice: dict | None = field(default=None)
    thermostat: str | None = None
    top: float | None = None
    magnetic: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "law", _law_name(self.law))
        object.__setattr__(self, "thermostat", _thermostat_name(self.thermostat))
        object.__setattr__(self, "magnetic", _magnetic_value(self.magnetic))
        object.__setattr__(self, "gamma", nonnegative(self.gamma, "gamma"))
        object.__setattr__(self, "force", tuple(float(f) for f in finite_vector(self.force, "force")))
        object.__setattr__(self, "elements", _element_tuple(self.elements))
        if not self.elements:
            raise ValueError("elements: a scene needs at least one element")
        check_closed_chains(self.elements)
        if self.lattice is not None:
            no_unknown_keys(self.lattice, {"a1", "a2"}, "lattice")
            a1 = finite_vector(required(self.lattice, "a1", "lattice"), "lattice.a1")
            a2 = finite_vector(required(self.lattice, "a2", "lattice"), "lattice.a2")
            for name, a in (("a1", a1), ("a2", a2)):
                length = math.hypot(*a)
                if not MIN_MAGNITUDE <= length <= MAX_MAGNITUDE:
                    raise ValueError(f"lattice.{name}: |{name}| = {length:.3g} lies outside [{MIN_MAGNITUDE:g}, "
                                     f"{MAX_MAGNITUDE:g}], the lengths the engine is exact for ({_RANGE_DOC})")
            if abs(a1[0] * a2[1] - a1[1] * a2[0]) == 0.0:
                raise ValueError("lattice: a1 and a2 must be linearly independent")
            object.__setattr__(self, "lattice", {"a1": [float(v) for v in a1], "a2": [float(v) for v in a2]})
            _check_copies(self.elements, self.lattice)
            _check_lattice_segments(self.elements, self.lattice)
            for i, e in enumerate(self.elements):
                if not e.bounded:
                    raise ValueError(f"elements[{i}]: infinite lines cannot be repeated on a lattice")
            if self.top is None:  # a bounded lattice has its table above the top row
                _check_not_covered(self.elements, self.lattice)
        if self.top is not None:
            self._check_top()
        _check_magnitudes(self)
        _check_magnetic(self)

    def _check_top(self):
        """Validate ``top`` (a bounded lattice) and store it as a float; errors name the problem."""
        if isinstance(self.top, bool) or not isinstance(self.top, (int, float, np.floating, np.integer)):
            raise TypeError(f"top: expected a number (a height), got {type(self.top).__name__}")
        top = float(self.top)
        if not math.isfinite(top):
            raise ValueError(f"top: must be finite, got {top} (leave it out for an unbounded lattice)")
        if abs(top) > MAX_MAGNITUDE:
            raise ValueError(f"top: {top:.3g} lies beyond {MAX_MAGNITUDE:g}, the largest length the engine is exact "
                             f"for ({_RANGE_DOC})")
        if self.lattice is None:
            raise ValueError("top: only a lattice has a top row; this scene has no lattice")
        for i, e in enumerate(self.elements):
            if e.disk() is None:
                raise ValueError(f"top: a bounded lattice needs circle scatterers (side outside) only; "
                                 f"elements[{i}] is a {e.type_name}")
        if self.thermostat is not None:
            raise ValueError("top: a bounded lattice is not supported with the isokinetic thermostat")
        object.__setattr__(self, "top", top)

    # ---------------------------------------------------------------- file format
    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Scene:
        """Build a scene from its mapping form (docs/scenes.md); unknown keys are errors."""
        no_unknown_keys(d, _SCENE_KEYS, "scene")
        elems = required(d, "elements", "scene")
        if not isinstance(elems, (list, tuple)):
            raise ValueError("elements: expected a list of element mappings")
        return cls(
            elements=tuple(element_from_dict(e, f"elements[{i}]") for i, e in enumerate(elems)),
            law=d.get("law", "no-slip"),
            gamma=d.get("gamma", 1.0 / math.sqrt(2.0)),
            force=d.get("force", (0.0, 0.0)),
            lattice=d.get("lattice"),
            thermostat=d.get("thermostat"),
            top=d.get("top"),
            magnetic=d.get("magnetic", 0.0),
        )

    @classmethod
    def from_yaml(cls, source: str | os.PathLike) -> Scene:
        """Read a scene from a YAML file path or a YAML string.

        Errors name the file and the field (``scene.yaml: elements[2].radius:
        must be > 0, got -1``); the format is described in docs/scenes.md.

        Raises
        ------
        FileNotFoundError
            ``source`` is the path of a file that does not exist.
        ValueError
            Invalid YAML (with its line and column), or a scene that does not
            validate.
        """
        data, where = read_yaml(source, "scene")
        if not isinstance(data, dict):
            raise ValueError(f"{where}: expected a YAML mapping with keys {sorted(_SCENE_KEYS)}, "
                             f"got {type(data).__name__}")
        if where == "scene":
            return cls.from_dict(data)
        try:
            return cls.from_dict(data)
        except (ValueError, TypeError) as err:
            raise type(err)(f"{where}: {err}") from None

    def to_dict(self) -> dict[str, Any]:
        """The scene as its scene-file mapping (the inverse of :meth:`from_dict`)."""
        d = {"law": self.law, "gamma": self.gamma, "force": list(self.force)}
        if self.thermostat is not None:
            d["thermostat"] = self.thermostat
        if self.magnetic != 0.0:  # absent when 0, so the JSON of field-free scenes is as before
            d["magnetic"] = self.magnetic
        d["elements"] = [e.to_dict() for e in self.elements]
        if self.lattice is not None:
            d["lattice"] = self.lattice
        if self.top is not None:
            d["top"] = self.top
        return d

    def to_yaml(self, path: str | os.PathLike | None = None) -> str:
        """The scene as YAML text; also written to ``path`` if given."""
        text = yaml.safe_dump(self.to_dict(), sort_keys=False, default_flow_style=None)
        if path is not None:
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(text)
        return text

    def to_json(self) -> str:
        """The scene as a JSON string (sorted keys): how datasets store it."""
        return json.dumps(self.to_dict(), sort_keys=True)

    def replace(self, **changes: Any) -> Scene:
        """A copy with some of ``elements, law, gamma, force, lattice, thermostat, top, magnetic`` changed."""
        d = dict(elements=self.elements, law=self.law, gamma=self.gamma, force=self.force,
                 lattice=self.lattice, thermostat=self.thermostat, top=self.top, magnetic=self.magnetic)
        d.update(changes)
        return Scene(**d)

    # ---------------------------------------------------------------- physics
    @property
    def law_code(self) -> int:
        """The scene's law as the kernels take it (``layout.SPECULAR`` or ``layout.NOSLIP``).

        The law of the elements that do not set their own; see :attr:`element_laws`.
        """
        return LAWS[self.law]

    @property
    def element_laws(self) -> tuple[str, ...]:
        """The collision law of each element: its own ``law``, or the scene's where it sets none."""
        return tuple(self.law if e.law is None else e.law for e in self.elements)

    @property
    def mixed_laws(self) -> bool:
        """True if the elements do not all collide by one law (specular walls around a no-slip disk)."""
        return len(set(self.element_laws)) > 1

    @property
    def any_noslip(self) -> bool:
        """True if some element collides by the no-slip law (then the spin takes part in the energy)."""
        return "no-slip" in self.element_laws

    def flight_states(self, x: ArrayLike, y: ArrayLike, vx: ArrayLike, vy: ArrayLike,
                      tau: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Position and velocity ``(x, y, vx, vy)`` after flights of duration ``tau >= 0`` (arrays, broadcast).

        Free fall ``q + v tau + a tau^2/2`` (a straight line without force),
        the closed-form path of the isokinetic thermostat
        (:mod:`noslipsim.core.thermostat`), or the cyclotron circle of a
        magnetic field (:mod:`noslipsim.core.magnetic`).  For drawing and
        checking orbits; the event loop evaluates the same forms.
        """
        x, y, vx, vy, tau = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (x, y, vx, vy, tau)))
        if self.magnetic != 0.0:
            from .core.magnetic import advance_many as magnetic_many

            return _flown(magnetic_many, (x, y, vx, vy, tau), self.magnetic)
        ax, ay = self.force
        if self.thermostat is None or (ax, ay) == (0.0, 0.0):
            return (x + vx * tau + 0.5 * ax * tau ** 2, y + vy * tau + 0.5 * ay * tau ** 2,
                    vx + ax * tau, vy + ay * tau)
        from .core.thermostat import advance_many

        return _flown(advance_many, (x, y, vx, vy, tau), ax, ay)

    @property
    def noslip_coefficients(self) -> tuple[float, float]:
        """``(c, s)`` of the no-slip law for this scene's gamma, with ``c^2 + s^2`` closest to 1."""
        return unit_pair(*noslip_coefficients(self.gamma))

    # ---------------------------------------------------------------- geometry
    def cell_scene(self, cell: tuple[int, int] = (0, 0)) -> Scene:
        """The plain scene of every element copy that reaches ``cell`` (for inside tests)."""
        if self.lattice is None:
            return self
        elems = self._cell_copies(cell)
        if not elems:
            raise ValueError(f"cell {tuple(cell)} lies above the top ({self.top}): no element copy reaches it")
        return self._plain_scene(elems)

    def _plain_scene(self, elems):
        """The plain scene of element copies of this one (a cell's), built without validation: the copies
        are validated elements, and the scene of a far cell is for inside tests only (the kernel runs
        relative to the cell), so it is not measured against the range of validity again."""
        out = object.__new__(Scene)
        for name, value in dict(elements=tuple(elems), law=self.law, gamma=self.gamma, force=self.force,
                                lattice=None, thermostat=self.thermostat, top=None,
                                magnetic=self.magnetic).items():
            object.__setattr__(out, name, value)
        return out

    def _cell_copies(self, cell):
        """The element copies that reach ``cell`` of a periodic scene (none above a bounded lattice's top)."""
        from ._engine.table import scene_copies

        A, _ = lattice_matrix(self.lattice)
        elems = []
        for e, o1, o2 in scene_copies(self):
            dx, dy = A @ np.array([o1 + cell[0], o2 + cell[1]], float)
            copy = self.elements[e].shifted(dx, dy)
            if self.top is None or copy.center[1] <= self.top:
                elems.append(copy)
        return elems

    @property
    def smallest_feature(self) -> float:
        """The shortest segment, smallest radius or arc length of the table (``inf`` for lines only)."""
        return float(min((v for e in self.elements for _, v in e.features()), default=math.inf))

    @property
    def scale(self) -> float:
        """Length scale of the table (largest coordinate magnitude of its elements)."""
        return float(max(e.size() for e in self.elements))

    # ---------------------------------------------------------------- inside test
    def depth(self, points: ArrayLike) -> np.ndarray:
        """Signed depth of points in the table: > 0 inside, < 0 outside, ~distance to the boundary.

        Global constraints (lines, full circles) use their signed distance;
        finite pieces (segments, arcs) use the side of the nearest piece.
        Periodic scenes measure each point against the copies that reach its cell.
        """
        pts = np.asarray(points, dtype=float)
        if self.lattice is not None:
            flat = pts.reshape(-1, 2)
            cells = cell_of(flat, self.lattice)
            out = np.empty(len(flat))
            for cell in np.unique(cells, axis=0):
                sel = np.all(cells == cell, axis=1)
                elems = self._cell_copies(tuple(cell))
                out[sel] = (self._plain_scene(elems).depth(flat[sel])
                            if elems else np.inf)  # above a bounded lattice's top: nothing there
            return out.reshape(pts.shape[:-1])
        depth = np.full(pts.shape[:-1], np.inf)
        finite = [e for e in self.elements if e.finite]
        for e in self.elements:
            if not e.finite:
                depth = np.minimum(depth, e.side_distance(pts))
        if finite:
            dist = np.stack([e.distance(pts) for e in finite])
            side = np.stack([e.side_distance(pts) for e in finite])
            dmin = dist.min(axis=0)
            # among the nearest pieces (a shared vertex), trust the one the point is farthest off
            near = dist <= dmin * (1.0 + 1e-12)
            pick = np.argmax(np.where(near, np.abs(side), -1.0), axis=0)
            sgn = np.sign(np.take_along_axis(side, pick[None], axis=0)[0])
            depth = np.minimum(depth, sgn * dmin)
        return depth

    def contains(self, points: ArrayLike) -> np.ndarray:
        """True for points strictly inside the table."""
        return self.depth(points) > 0.0
