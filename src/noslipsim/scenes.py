"""Scenes: a table (boundary elements), a collision law, a mass distribution and a force.

A scene is the public way to define a billiard (docs/scenes.md)::

    law: no-slip            # or specular
    gamma: 0.7071067811865476
    force: [0.0, -1.0]
    elements: [...]          # see noslipsim.elements
    lattice: {a1: [1, 0], a2: [0, 1]}   # optional: periodic repetition

The table is the set of points on the table side of every line and full
circle and of the nearest segment or arc (for a closed polygon this is its
interior; at a shared vertex both pieces agree).
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np
import yaml

from ._unit import unit_pair
from ._validate import finite_vector, no_unknown_keys, nonnegative, read_yaml, required
from .core import layout
from .core.laws import noslip_coefficients
from .core.loop import kernel_flags
from .elements import Arc, Circle, Line, Segment, element_from_dict
from .lattice import cell_of, disks_apart, lattice_matrix, reaching_copies

LAWS = {"no-slip": layout.NOSLIP, "noslip": layout.NOSLIP, "specular": layout.SPECULAR}
_SCENE_KEYS = {"law", "gamma", "force", "elements", "lattice"}


def _law_name(law):
    if not isinstance(law, str) or law not in LAWS:
        raise ValueError(f"law: unknown collision law {law!r}; expected 'no-slip' or 'specular'")
    return "no-slip" if LAWS[law] == layout.NOSLIP else "specular"


#: Most element copies a periodic scene may need around one cell (counted from the
#: elements' bounding boxes).  Every flight through a cell tests them all and building the
#: scene pairs them up (junctions), so an ill-posed lattice (``a1`` and ``a2`` nearly
#: parallel, or elements spanning many cells) is refused instead of hanging.
MAX_LATTICE_COPIES = 1000

#: Disks of a lattice run the lean loop (:attr:`Scene.disk_lattice`) when no two come within
#: this gap, relative to the cell's size: far outside the corner rule's contact band
#: (``CONTACT_TOL``), so the general loop could never treat two of them as touching.
DISK_GAP = 1e-9


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
            continue  # an infinite element: reaching_copies names it
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
        if not isinstance(e, (Line, Segment, Circle, Arc)):
            raise TypeError(f"elements[{i}]: expected a Line, Segment, Circle or Arc (or use Scene.from_dict "
                            f"for mappings), got {type(e).__name__}")
    return out


#: On a lattice a segment must be longer than this, relative to the longer lattice vector:
#: its copies are shifted by lattice vectors, and a shorter one collapses to a point in rounding.
LATTICE_MIN_SEGMENT = 1e-9


def _check_lattice_segments(elements, lattice):
    size = max(math.hypot(*lattice["a1"]), math.hypot(*lattice["a2"]))
    for i, e in enumerate(elements):
        if e.type_name == "segment" and not e.length() > LATTICE_MIN_SEGMENT * size:
            raise ValueError(f"elements[{i}]: a segment of length {e.length():.3g} is too short for a lattice "
                             f"of size {size:.3g} (at least {LATTICE_MIN_SEGMENT:g} times it)")


@dataclass(frozen=True)
class Scene:
    """A billiard table with its physics.

    Parameters
    ----------
    elements : sequence of Line, Segment, Circle, Arc
        Boundary pieces; their order fixes the ``element`` index in outputs.
    law : {'no-slip', 'specular'}
        Collision law (docs/conventions.md).
    gamma : float
        Mass-distribution constant ``gamma = sqrt(I / (m R^2))`` (nondimensional,
        >= 0): 0 point mass, ``1/sqrt(2)`` uniform disk, 1 ring.
    force : (float, float)
        Constant acceleration ``(a_x, a_y)`` acting between collisions.
    lattice : dict or None
        ``{'a1': [..], 'a2': [..]}`` to repeat the elements periodically.
    """

    elements: tuple
    law: str = "no-slip"
    gamma: float = 1.0 / math.sqrt(2.0)
    force: tuple = (0.0, 0.0)
    lattice: dict | None = field(default=None)

    def __post_init__(self):
        object.__setattr__(self, "law", _law_name(self.law))
        object.__setattr__(self, "gamma", nonnegative(self.gamma, "gamma"))
        object.__setattr__(self, "force", tuple(float(f) for f in finite_vector(self.force, "force")))
        object.__setattr__(self, "elements", _element_tuple(self.elements))
        if not self.elements:
            raise ValueError("elements: a scene needs at least one element")
        if self.lattice is not None:
            no_unknown_keys(self.lattice, {"a1", "a2"}, "lattice")
            a1 = finite_vector(required(self.lattice, "a1", "lattice"), "lattice.a1")
            a2 = finite_vector(required(self.lattice, "a2", "lattice"), "lattice.a2")
            if abs(a1[0] * a2[1] - a1[1] * a2[0]) == 0.0:
                raise ValueError("lattice: a1 and a2 must be linearly independent")
            object.__setattr__(self, "lattice", {"a1": [float(v) for v in a1], "a2": [float(v) for v in a2]})
            _check_copies(self.elements, self.lattice)
            _check_lattice_segments(self.elements, self.lattice)
            reaching_copies(self.elements, self.lattice)  # rejects infinite elements

    # ---------------------------------------------------------------- file format
    @classmethod
    def from_dict(cls, d):
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
        )

    @classmethod
    def from_yaml(cls, source):
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

    def to_dict(self):
        d = {"law": self.law, "gamma": self.gamma, "force": list(self.force),
             "elements": [e.to_dict() for e in self.elements]}
        if self.lattice is not None:
            d["lattice"] = self.lattice
        return d

    def to_yaml(self, path=None):
        """The scene as YAML text; also written to ``path`` if given."""
        text = yaml.safe_dump(self.to_dict(), sort_keys=False, default_flow_style=None)
        if path is not None:
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(text)
        return text

    def to_json(self):
        return json.dumps(self.to_dict(), sort_keys=True)

    def replace(self, **changes):
        """A copy with some of ``elements, law, gamma, force, lattice`` changed."""
        d = dict(elements=self.elements, law=self.law, gamma=self.gamma, force=self.force,
                 lattice=self.lattice)
        d.update(changes)
        return Scene(**d)

    # ---------------------------------------------------------------- kernel form
    @property
    def law_code(self):
        return LAWS[self.law]

    def kernel_variant(self, mode):
        """The compile-time flags of the event loop this scene needs (:func:`core.loop.orbit_kernel`).

        A scene without force never pays for cubic or quartic exits, a
        specular one for spin updates, a plain one for the cell walk, and
        ``mode = RECORD_NONE`` for the recorder, and a table without long walls
        (:attr:`has_long_walls`) for their exact check.
        """
        return kernel_flags(self.force != (0.0, 0.0), self.law_code == layout.NOSLIP,
                            self.lattice is not None, mode, self.disk_lattice, self.has_long_walls)

    @property
    def has_long_walls(self):
        """True if a line or a segment is long against the table's smallest feature (``layout.LONG_WALL``).

        Only such a wall can carry a hit far from its ``p0``, where the plain
        distance cancels; the event loop checks those hits exactly
        (:func:`noslipsim.core.events.exact_line_hit`), and a table without
        one runs a loop compiled without the check.
        """
        return any(flag != 0.0 for flag in self._long_walls())

    @property
    def disk_lattice(self):
        """True for a lattice of disjoint disk scatterers without force (Sinai torus, Lorentz gases).

        One or several disks per cell, of any radii, each inside its cell or
        reaching into neighbouring ones; no two disks (lattice copies included)
        come within ``DISK_GAP`` of each other (relative to the cell's size).
        Such a scene runs the lean loop of :mod:`noslipsim.core.disks`: its
        disks are convex and never touch, so it needs no deflation, corner rule
        or extent test.
        """
        if self.lattice is None or self.force != (0.0, 0.0):
            return False
        if not all(isinstance(e, Circle) and e.side == "outside" for e in self.elements):
            return False
        cached = self.__dict__.get("_disk_lattice")
        if cached is None:
            A, _ = lattice_matrix(self.lattice)
            size = max(self.scale, float(np.abs(A).sum(axis=1).max()))
            cached = disks_apart([(e.center, e.radius) for e in self.elements], self.lattice, DISK_GAP * size)
            object.__setattr__(self, "_disk_lattice", cached)
        return cached

    @property
    def one_disk_per_cell(self):
        """True for a lattice of one disk scatterer inside each cell, without force (Sinai torus, Lorentz gas).

        The special case of :attr:`disk_lattice` whose lean loop needs no copy
        loop (:func:`noslipsim.core.disks.disk_walk`).
        """
        if self.lattice is None or self.force != (0.0, 0.0) or len(self.elements) != 1:
            return False
        e = self.elements[0]
        if not (isinstance(e, Circle) and e.side == "outside"):
            return False
        copies = self.kernel_inputs()[2]
        return copies.shape == (1, 3) and not copies[0, 1:].any()

    @property
    def noslip_coefficients(self):
        """``(c, s)`` of the no-slip law for this scene's gamma, with ``c^2 + s^2`` closest to 1."""
        return unit_pair(*noslip_coefficients(self.gamma))

    def arrays(self):
        """``(kinds, params)`` arrays for the kernels (with the end-band factors of segments and arcs)."""
        from .junctions import end_factors

        kinds = np.array([e.kind for e in self.elements], dtype=np.int64)
        params = np.zeros((len(self.elements), layout.N_PARAMS))
        for i, e in enumerate(self.elements):
            row = e.params()
            params[i, : len(row)] = row
            if isinstance(e, Segment):  # its own end point, for distances far along it
                for col, value in e.exact_params().items():
                    params[i, col] = value
        params[:, layout.END_START:layout.END_END + 1] = end_factors(self)
        params[:, layout.LONG_WALL] = self._long_walls()
        return kinds, params

    def _long_walls(self):
        """1.0 per line and per segment long against the table's smallest feature (``layout.LONG_WALL``)."""
        features = [e.length() if isinstance(e, Segment) else e.radius
                    for e in self.elements if isinstance(e, (Segment, Circle, Arc))]
        smallest = min(features, default=math.inf)
        return [1.0 if isinstance(e, Line) or (isinstance(e, Segment)
                                               and e.length() > layout.LONG_WALL_RATIO * smallest) else 0.0
                for e in self.elements]

    def kernel_inputs(self):
        """Everything the event loop needs about the table.

        ``(kinds, params, copies, A, B, lattice, jstart, jpts)``: elements, the
        copies that reach a cell, lattice matrix and inverse, the periodic flag
        and the junction points (see :mod:`noslipsim.junctions`).
        """
        cached = self.__dict__.get("_kernel_inputs")
        if cached is not None:
            return cached
        from .junctions import junction_arrays

        kinds, params = self.arrays()
        if self.lattice is None:
            copies = np.zeros((len(kinds), 3), dtype=np.int64)
            copies[:, 0] = np.arange(len(kinds))
            A = B = np.zeros((2, 2))
        else:
            A, B = lattice_matrix(self.lattice)
            copies = reaching_copies(self.elements, self.lattice)
        out = (kinds, params, copies, A, B, self.lattice is not None, *junction_arrays(self))
        object.__setattr__(self, "_kernel_inputs", out)
        return out

    def cell_scene(self, cell=(0, 0)):
        """The plain scene of every element copy that reaches ``cell`` (for inside tests)."""
        if self.lattice is None:
            return self
        copies = reaching_copies(self.elements, self.lattice)
        A, _ = lattice_matrix(self.lattice)
        elems = []
        for e, o1, o2 in copies:
            dx, dy = A @ np.array([o1 + cell[0], o2 + cell[1]], float)
            elems.append(self.elements[e].shifted(dx, dy))
        return self.replace(elements=tuple(elems), lattice=None)

    @property
    def scale(self):
        """Length scale of the table (largest coordinate magnitude of its elements)."""
        return float(max(e.size() for e in self.elements))

    # ---------------------------------------------------------------- inside test
    def depth(self, points):
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
                out[sel] = self.cell_scene(tuple(cell)).depth(flat[sel])
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

    def contains(self, points):
        """True for points strictly inside the table."""
        return self.depth(points) > 0.0
