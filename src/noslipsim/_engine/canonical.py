"""Canonical form of a periodic scene: the same billiard, written the way the kernels run fastest.

A periodic scene can be written in many ways that change no physics: the
scatterers anywhere in the cell (the Sinai torus with its disk at the centre
of the unit square, as most references write it, or at the origin), any basis
of the same lattice (``a2`` or ``a1 + a2``), any origin (a Galton board whose
first peg sits at ``(1, 0.5)``).  The kernels see the lattice through cells
centred at the lattice points, so the way a scene is written decides how many
element copies reach a cell, and whether a lean loop applies (one disk inside
each cell, :mod:`noslipsim.core.disks`).  Before choosing a kernel,
:func:`canonical_form` therefore rewrites a periodic scene:

1. the lattice basis is Lagrange–Gauss reduced (the cell is as compact as the
   lattice allows; an already reduced basis is kept);
2. each element is moved by a lattice vector next to the first one, and the
   scene is translated so that the centroid of the elements' box centres sits
   at the origin (a single scatterer: its centre);
3. the copies that reach a cell are found by exact geometry
   (:func:`noslipsim._engine.lattice.reaching_copies`), so none that can never be met
   in the cell is tested.

None of this changes the billiard: a translation and a lattice vector are
symmetries of the periodic table, and element indices are kept.  The rewritten
scene's numbers round differently (its coordinates are differences of the
user's), so its orbits agree with the user's to rounding.  Everything handed
back to the user is in the user's coordinates: unfolded positions (the
translation added back) and the cell indices ``cell_a1, cell_a2`` of the
user's basis (see docs/algorithm.md, "Canonical form").
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from .lattice import cell_of, cell_origin
from .memo import per_scene

#: Relative slack on the reduction conditions of a basis (``|a1 . a2| <= |a|^2 / 2``):
#: a basis reduced up to rounding (the hexagonal one, whose ``|a2|^2`` rounds below 1) is kept.
REDUCED_SLACK = 1e-12


@dataclass(frozen=True)
class CanonicalForm:
    """A scene in canonical form and the map back to the user's coordinates.

    Attributes
    ----------
    user : Scene
        The scene as the user wrote it.
    scene : Scene
        The scene the kernels run: same billiard, reduced basis, translated.
    shift : ndarray (2,)
        Translation: a user position is a canonical position plus ``shift``.
    U : ndarray of int (2, 2)
        The canonical lattice vectors are ``A_user @ U`` (as columns), so a
        canonical cell index ``m`` is the lattice point ``U @ m`` of the user's basis.
    identity : bool
        Nothing was rewritten: the kernels run the user's scene as it is, and
        results are those of the user's scene bit for bit.
    moves : ndarray of int (n_elements, 2) or None
        The canonical cell of each element as the user wrote it: element
        ``k`` of the user's scene is the copy of canonical element ``k`` in
        canonical cell ``moves[k]`` (``None``: every one in cell 0).
    """

    user: object
    scene: object
    shift: np.ndarray
    U: np.ndarray
    identity: bool
    moves: np.ndarray | None = None

    # ------------------------------------------------------------------ starts
    def kernel_starts(self, q, on=None):
        """Split user positions ``q`` (..., 2) into canonical cells and positions relative to them.

        ``on``: start elements (``-1`` or absent: an interior start).  An
        interior start's cell is the parallelogram cell that holds it; a
        boundary start on element ``k`` (the user's cell-0 copy, as
        :func:`noslipsim.ensemble.check_starts` requires) starts in the cell
        of that copy, which the kernel deflates (``t = 0`` root), even where
        the point lies in a neighbouring parallelogram (a disk reaching out
        of its cell: the kernels walk on from a start outside its cell).
        Returns ``(cells, origins, rel)``: canonical cell indices, their centres
        (canonical coordinates) and ``rel = q - shift - origins``.
        """
        q = np.asarray(q, float)
        if self.scene.lattice is None:
            shape = (*q.shape[:-1], 2)
            return np.zeros(shape, dtype=np.int64), np.zeros(shape), q
        qc = q - self.shift if not self.identity else q
        cells = cell_of(qc, self.scene.lattice)
        if on is not None:
            on = np.asarray(on, dtype=np.int64)
            boundary = on >= 0
            cells[boundary] = 0 if self.moves is None else self.moves[on[boundary]]
        origins = cell_origin(cells, self.scene.lattice)
        return cells, origins, qc - origins

    # ------------------------------------------------------------------ results
    def user_positions(self, x, y):
        """Canonical unfolded positions to the user's (the translation added back)."""
        if self.identity:
            return x, y
        return x + self.shift[0], y + self.shift[1]

    def user_level(self, level):
        """A height in the user's coordinates as the canonical scene sees it."""
        return level if self.identity else level - self.shift[1]

    def user_cells(self, m1, m2, x, y):
        """User cell indices of points given by canonical cells ``(m1, m2)`` and canonical unfolded ``(x, y)``.

        The user's cell of a point is the nearest lattice point of the user's
        basis: ``U m`` plus the user cell of the point's position relative to
        the canonical cell centre, translated by ``shift`` (small numbers, so
        the cell is decided at the cell's precision).  NaN entries (padding of
        records) stay NaN.
        """
        if self.identity:
            return m1, m2
        m1 = np.asarray(m1, float)
        m2 = np.asarray(m2, float)
        pad = np.isnan(m1)
        c1 = np.where(pad, 0.0, m1)
        c2 = np.where(pad, 0.0, m2)
        origins = cell_origin(np.stack([c1, c2], axis=-1), self.scene.lattice)
        rel = np.stack([np.asarray(x, float) - origins[..., 0] + self.shift[0],
                        np.asarray(y, float) - origins[..., 1] + self.shift[1]], axis=-1)
        rel = np.where(pad[..., None], 0.0, rel)
        k = cell_of(rel, self.user.lattice)
        U = self.U
        n1 = U[0, 0] * c1 + U[0, 1] * c2 + k[..., 0]
        n2 = U[1, 0] * c1 + U[1, 1] * c2 + k[..., 1]
        return np.where(pad, np.nan, n1), np.where(pad, np.nan, n2)


# ---------------------------------------------------------------------------- lattice basis
def _combine(A, u):
    """The lattice vector ``A @ u`` (integer ``u``), correctly rounded from exact arithmetic."""
    return np.array([float(Fraction(A[i, 0]) * int(u[0]) + Fraction(A[i, 1]) * int(u[1])) for i in range(2)])


def _is_reduced(a, b):
    ab = abs(float(a @ b))
    return ab <= 0.5 * min(float(a @ a), float(b @ b)) * (1.0 + REDUCED_SLACK)


def reduce_basis(A):
    """Lagrange–Gauss reduction of the lattice basis (columns of ``A``): returns the integer matrix ``U``.

    ``A @ U`` is reduced: ``|b1 . b2| <= |b1|^2 / 2 <= |b2|^2 / 2`` (up to
    ``REDUCED_SLACK``), i.e. ``b1`` is a shortest lattice vector and ``b2`` a
    shortest one independent of it; the cell they span is the most compact
    parallelogram of the lattice.  A basis already reduced is kept (``U = I``)
    except for its orientation convention: ``b1 . b2 >= 0`` (``b2 -> -b2``,
    which spans the same centred cell; at a tie ``|2 b1 . b2| = |b1|^2``,
    ``b2 -> b2 + b1``, the other reduced basis, so the hexagonal lattice
    written with a 120 degree angle gets the 60 degree cell).
    """
    A = np.asarray(A, float)
    U = np.eye(2, dtype=np.int64)
    if not _is_reduced(A[:, 0], A[:, 1]):
        b1, b2 = A[:, 0].copy(), A[:, 1].copy()
        if b1 @ b1 > b2 @ b2:
            U = U[:, ::-1].copy()
            b1, b2 = b2, b1
        for _ in range(10_000):  # each step shortens b2 by a lattice vector: ends well before
            mu = round(float(b1 @ b2) / float(b1 @ b1))
            if mu != 0:
                U[:, 1] -= mu * U[:, 0]
                b2 = _combine(A, U[:, 1])
            if b2 @ b2 < b1 @ b1:
                U = U[:, ::-1].copy()
                b1, b2 = b2, b1
                continue
            break
    b1, b2 = _combine(A, U[:, 0]), _combine(A, U[:, 1])
    ab = float(b1 @ b2)
    if ab < 0.0:
        shortest = min(float(b1 @ b1), float(b2 @ b2))
        if 2.0 * abs(ab) >= shortest * (1.0 - REDUCED_SLACK):
            if b1 @ b1 <= b2 @ b2:
                U[:, 1] += U[:, 0]
            else:
                U[:, 0] += U[:, 1]
        else:
            U[:, 1] = -U[:, 1]
    return U


# ---------------------------------------------------------------------------- the form
def _box_centre(e):
    x0, y0, x1, y1 = e.bbox()
    return np.array([0.5 * (x0 + x1), 0.5 * (y0 + y1)])


@per_scene
def canonical_form(scene):
    """The canonical form of ``scene`` (built once per scene); plain scenes are their own canonical form."""
    eye = np.eye(2, dtype=np.int64)
    if scene.lattice is None:
        return CanonicalForm(scene, scene, np.zeros(2), eye, True)
    A = np.array([scene.lattice["a1"], scene.lattice["a2"]], dtype=float).T
    U = reduce_basis(A)
    Ac = np.column_stack([_combine(A, U[:, 0]), _combine(A, U[:, 1])]) if not np.array_equal(U, eye) else A
    Bc = np.linalg.inv(Ac)
    # each element next to the first one (a lattice vector is a symmetry), then the centroid to the origin
    centres = np.array([_box_centre(e) for e in scene.elements])
    moves = np.rint((centres - centres[0]) @ Bc.T).astype(np.int64)
    lattice_moves = np.array([_combine(Ac, -m) if m.any() else np.zeros(2) for m in moves])
    placed = centres + lattice_moves
    shift = placed[0].copy() if len(placed) == 1 else placed.mean(axis=0)
    elements = tuple(e.shifted(mv[0] - shift[0], mv[1] - shift[1]) if (mv.any() or shift.any()) else e
                     for e, mv in zip(scene.elements, lattice_moves))
    same_basis = Ac is A
    if same_basis and not shift.any() and not lattice_moves.any():
        return CanonicalForm(scene, scene, np.zeros(2), eye, True)
    lattice = scene.lattice if same_basis else {"a1": Ac[:, 0].tolist(), "a2": Ac[:, 1].tolist()}
    canon = scene.replace(elements=elements, lattice=lattice,
                          top=None if scene.top is None else scene.top - float(shift[1]))
    return CanonicalForm(scene, canon, shift, U, False, moves)
