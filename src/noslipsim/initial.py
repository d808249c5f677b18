"""Initial conditions from ``numpy.random.SeedSequence``: the same seed gives the same starts.

- :func:`unit_velocities`: unit speed, direction uniform on the circle;
- :func:`uniform_in_region`: positions uniform in a box, kept where inside the table;
- :func:`boundary_states`: uniform on the boundary in the reduced phase space
  (arclength uniform over the chosen elements; the post-collision unit vector
  ``(w, v_t, v_n)`` uniform on the hemisphere ``S^2_+`` for no-slip, the exit
  angle uniform in ``(-pi/2, pi/2)`` with ``w = 0`` for specular).
"""
from __future__ import annotations

import math

import numpy as np

from .scenes import Scene

#: Rejection sampling gives up after this many rounds (each draws twice the remainder).
MAX_ROUNDS = 200


def rng_from(seed):
    """A Generator from an int, a SeedSequence or a Generator."""
    if isinstance(seed, np.random.Generator):
        return seed
    if isinstance(seed, np.random.SeedSequence):
        return np.random.default_rng(seed)
    return np.random.default_rng(np.random.SeedSequence(seed))


def _count(n):
    if isinstance(n, bool) or int(n) != n or n < 0:
        raise ValueError(f"n: expected a non-negative integer, got {n!r}")
    return int(n)


def unit_velocities(n, seed=0):
    """``(n, 2)`` unit velocities with directions uniform on the circle."""
    ang = rng_from(seed).uniform(0.0, 2.0 * math.pi, _count(n))
    return np.c_[np.cos(ang), np.sin(ang)]


class UnitVelocities:
    """The rows of :func:`unit_velocities` ``(n, seed)``, made only when sliced: an ``(n, 2)`` array-like.

    ``UnitVelocities(n, seed)[i:j]`` equals ``unit_velocities(n, seed)[i:j]`` bit for bit and costs
    memory for ``j - i`` rows only, so an ensemble written to disk chunk by chunk
    (``simulate_many(..., out=...)``) holds the starts of the chunks in flight, not of all ``n``.
    The generator (PCG64, one 64-bit draw per angle) jumps ahead ``i`` draws instead of making them.

    Parameters
    ----------
    n : int
        Rows.
    seed : int or numpy.random.SeedSequence
        As in :func:`unit_velocities` (a Generator is refused: its state cannot be replayed).
    """

    def __init__(self, n, seed=0):
        if isinstance(seed, np.random.Generator):
            raise ValueError("seed: expected an int or a SeedSequence (a Generator's draws cannot be replayed)")
        self.n, self.seed = _count(n), seed
        self.shape, self.dtype, self.ndim = (self.n, 2), np.dtype(float), 2
        if not isinstance(rng_from(seed).bit_generator, np.random.PCG64):
            raise ValueError("seed: UnitVelocities needs numpy's default PCG64 generator")

    def __len__(self):
        return self.n

    def __getitem__(self, key):
        if not isinstance(key, slice):
            raise TypeError("UnitVelocities: only slices of rows ([i:j]) are supported")
        start, stop, step = key.indices(self.n)
        if step != 1:
            raise TypeError("UnitVelocities: only contiguous slices of rows are supported")
        rng = rng_from(self.seed)
        rng.bit_generator.advance(start)
        ang = rng.uniform(0.0, 2.0 * math.pi, max(0, stop - start))
        return np.c_[np.cos(ang), np.sin(ang)]

    def __array__(self, dtype=None, copy=None):
        out = self[:]
        return out if dtype is None else out.astype(dtype)


def uniform_in_region(scene: Scene, n, box, seed=0):
    """``(n, 2)`` positions uniform in ``box = (x0, x1, y0, y1)`` and strictly inside the table."""
    n = _count(n)
    x0, x1, y0, y1 = map(float, box)
    if not (x1 > x0 and y1 > y0):
        raise ValueError(f"box: expected (x0, x1, y0, y1) with x1 > x0 and y1 > y0, got {box}")
    rng = rng_from(seed)
    out = np.empty((0, 2))
    for _ in range(MAX_ROUNDS):
        need = n - len(out)
        if need <= 0:
            break
        pts = np.c_[rng.uniform(x0, x1, 2 * need + 8), rng.uniform(y0, y1, 2 * need + 8)]
        out = np.vstack([out, pts[scene.contains(pts)]])
    if len(out) < n:
        raise ValueError(f"box: too little of {box} lies inside the table to draw {n} starts")
    return out[:n]


def boundary_states(scene: Scene, n, seed=0, elements=None):
    """Starts on the boundary, uniform in the reduced phase space.

    Returns a dict with ``positions``, ``velocities``, ``spins`` and
    ``start_elements`` for :func:`noslipsim.simulate_many`.  Speeds are such
    that ``|v|^2 + w^2 = 1``; the spin is drawn where some element collides by
    the no-slip law (a table of mixed laws too), else it is 0.  Only finite elements (segments, circles, arcs)
    can be sampled; in a periodic scene the elements of cell 0 are used.
    """
    n = _count(n)
    idx = list(range(len(scene.elements))) if elements is None else [int(i) for i in elements]
    for i in idx:
        if not 0 <= i < len(scene.elements) or not scene.elements[i].bounded:
            raise ValueError(f"elements: {i} is not a segment, circle or arc of the scene")
    lengths = np.array([scene.elements[i].length() for i in idx])
    rng = rng_from(seed)
    pick = rng.choice(len(idx), size=n, p=lengths / lengths.sum())
    u = rng.uniform(0.0, 1.0, n)
    pos = np.empty((n, 2))
    n_out = np.empty((n, 2))
    for k, i in enumerate(idx):
        sel = pick == k
        pos[sel], n_out[sel] = scene.elements[i].at_fraction(u[sel])
    t = np.c_[-n_out[:, 1], n_out[:, 0]]
    if scene.any_noslip:  # the spin takes part (some element collides by the no-slip law)
        z = rng.normal(size=(n, 3))
        z /= np.linalg.norm(z, axis=1, keepdims=True)
        w, vt, vn_in = z[:, 0], z[:, 1], np.abs(z[:, 2])
    else:
        ang = rng.uniform(-math.pi / 2, math.pi / 2, n)
        w, vt, vn_in = np.zeros(n), np.sin(ang), np.cos(ang)
    vel = vt[:, None] * t - vn_in[:, None] * n_out
    return {"positions": pos, "velocities": vel, "spins": w,
            "start_elements": np.array(idx, dtype=np.int64)[pick]}
