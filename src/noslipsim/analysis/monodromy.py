r"""Linear stability of an orbit segment: the monodromy matrix of the ``period``-th return map.

Coordinates (docs/analysis.md): at a collision, the post-collision reduced state
``(s, w, v_t)``: the kernel's boundary arclength ``s`` of the element hit, the
scaled spin ``w = gamma R omega`` (counter-clockwise positive) and the
tangential velocity ``v_t = v . t`` with ``t = J n``, ``n`` the outward normal
(docs/conventions.md).  The energy ``E = (|v|^2 + w^2)/2 - a . q`` is fixed, so
the normal velocity ``v_n < 0`` follows from ``(s, w, v_t)`` (it depends on
the height under a force).  The monodromy is the Jacobian of the map from the
orbit's first collision to its ``(period + 1)``-th, propagated exactly
through every flight and collision (:mod:`noslipsim.analysis.tangent`).

Eigenvalues.  The flight between two collisions preserves the measure
``ds dw dv_t`` on the section (the boundary form of Liouville measure; for
specular billiards it is ``ds d(sin phi)`` at unit speed), and each no-slip
collision reverses the orientation of ``(w, v_t)`` (its matrix has determinant
``-c^2 - s^2 = -1``).  So each step has ``det J_i = -1`` (no-slip) or ``+1``
(specular), times ``sigma_i sigma_{i+1}`` where the kernel's arclength runs
against ``t`` (circles seen from outside, right-handed segments); over a closed
orbit the signs pair up, so ``det M = (-1)^{period}`` (no-slip) or ``+1``.
Force-free no-slip 2-periodic orbits have eigenvalues ``{1, lambda, 1/lambda}``
(Cox, Feres & Zhang 2018): the 1 is the direction
along their one-parameter family at fixed energy.  Specular scenes: the spin
is a spectator, unchanged by every collision, so the ``w`` row of the matrix is
``(0, 1, 0)`` and 1 is always an eigenvalue; the ``(s, v_t)`` block is the
Jacobian of the ordinary billiard map at the speed ``|v|`` the energy leaves
after ``w^2/2`` (its ``w`` column is the effect of trading spin energy for speed).

Half plane (Theorem 1), derived here as an oracle.  On the floor ``y = 0``
(``s = x``, ``v_t = v_x``) with force ``(0, -g)``, two bounces restore
``(w, v_x)`` (the law is an involution and keeps ``w^2 + v_x^2``, hence the
vertical speed ``u``), and move the bounce point by the drift
``D(w, v_x) = 4 u (v_x - gamma w) / (g (1 + gamma^2))``
(:func:`noslipsim.theory.half_plane_drift`).  So the 2-bounce monodromy is

.. math::

    M = I + e_s \nabla D^T, \qquad
    \nabla D = \frac{4 u}{g (1 + \gamma^2)} (0, -\gamma, 1)
    \quad\text{at } v_x = \gamma w

(the derivative of ``u`` multiplies ``v_x - gamma w = 0``).  Its eigenvalue 1
is triple, with ``M - I`` of rank 1: a 2x2 Jordan block (the drift grows
linearly with a perturbation of ``v_x - gamma w``) plus the family direction.
The class is ``'parabolic'``.

References: C. Cox, R. Feres, H.-K. Zhang, *Stability of periodic orbits in
no-slip billiards*, Nonlinearity 31 (2018); M. Wojtkowski, *The system of two
spinning disks in the torus*, Physica D 71 (1994).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..core import layout
from ..scenes import Scene
from .section import interior_log, reduced_from_log, wrap_difference
from .tangent import check_no_corner, log_product

__all__ = ["KINDS", "Monodromy", "classify", "monodromy"]

KINDS = ("elliptic", "hyperbolic", "parabolic")

#: An eigenvalue within this distance of the unit circle counts as on it, and a
#: pair whose imaginary part is below it as real.  A Jordan block at 1 (the
#: half plane, the two-disk threshold) splits its eigenvalue by about
#: sqrt(rounding) ~ 1e-8 in floating point, so the tolerance sits well above that.
UNIT_TOL = 1e-6


#: An eigenvalue this close to 1 is taken as exactly 1 (the family direction) in
#: ``eigen_sum``: at the two-disk ellipticity threshold the eigenvalue 1 is triple
#: and rounding splits it by about cbrt(eps) ~ 1e-5, while ``trace - 1`` stays exact.
UNIT_SPLIT_TOL = 1e-4


def _period(period):
    if isinstance(period, bool) or not isinstance(period, (int, np.integer)):
        raise ValueError(f"period: expected an integer >= 1, got {period!r}")
    if period < 1:
        raise ValueError(f"period: must be >= 1, got {period}")
    return int(period)


def classify(eigenvalues, tol=UNIT_TOL):
    """The linear class of a monodromy from its eigenvalues.

    ``'hyperbolic'`` if one lies off the unit circle by more than ``tol``
    (``|lambda| > 1 + tol``: nearby orbits separate exponentially);
    ``'elliptic'`` if all lie on it and a pair is non-real (a rotation about
    the orbit); ``'parabolic'`` if all are ``+-1`` within ``tol`` (the
    boundary between the two, e.g. a Jordan block at 1).
    """
    ev = np.asarray(eigenvalues)
    if np.max(np.abs(ev)) > 1.0 + tol:
        return "hyperbolic"
    if np.any(np.abs(ev.imag) > tol):
        return "elliptic"
    return "parabolic"


@dataclass(frozen=True)
class Monodromy:
    r"""The linearised ``period``-th return map at the first collision of an orbit.

    Attributes
    ----------
    matrix : ndarray (3, 3)
        ``d(s, w, v_t)_{period} / d(s, w, v_t)_0`` at fixed energy (order:
        arclength, spin, tangential velocity; nondimensional when lengths and
        velocities are).
    eigenvalues : ndarray (3,), complex
        Sorted by decreasing modulus.
    kind : {'elliptic', 'hyperbolic', 'parabolic'}
        :func:`classify` with tolerance :data:`UNIT_TOL`.
    trace, det : float
        Of ``matrix``.
    unit_eigenvalue : float
        1 if an eigenvalue lies within :data:`UNIT_SPLIT_TOL` of 1 (the family
        direction of a periodic orbit that has one, split only by rounding),
        otherwise the real part of the eigenvalue closest to 1.
    eigen_sum : float
        ``trace - unit_eigenvalue``: the sum of the other two eigenvalues,
        ``lambda + 1/lambda`` when their product is 1 (compare
        :func:`noslipsim.theory.two_disk_eigen_sum`).
    period : int
        Collisions in the return map.
    period_time : float
        Time from the base collision to the ``period``-th next one.
    base : dict
        The base point: ``element``, ``s``, ``w``, ``v_t`` (reduced
        coordinates) and ``position``, ``velocity``, ``spin`` (post-collision
        phase-space state, position unfolded).
    closure : ndarray (3,) or None
        ``(s, w, v_t)`` after ``period`` collisions minus at the base point,
        when both lie on the same element (``None`` otherwise): zero for a
        periodic orbit.
    """

    matrix: np.ndarray
    eigenvalues: np.ndarray
    kind: str
    trace: float
    det: float
    unit_eigenvalue: float
    eigen_sum: float
    period: int
    period_time: float
    base: dict = field(repr=False)
    closure: np.ndarray | None = field(repr=False)

    coordinates = ("s", "w", "v_t")

    def unit_count(self, tol=UNIT_TOL):
        """How many eigenvalues lie within ``sqrt(tol)`` of 1 (a Jordan block at 1 splits by ~sqrt(eps))."""
        return int(np.sum(np.abs(self.eigenvalues - 1.0) <= math.sqrt(tol)))

    @property
    def isolated(self):
        """True if no eigenvalue is 1: a periodic orbit that is not part of a family at fixed energy."""
        return self.unit_count() == 0


def monodromy_of_log(scene: Scene, log):
    """The :class:`Monodromy` of the map from the first to the last row of a collision log."""
    log = np.asarray(log, dtype=float)
    period = len(log) - 1
    check_no_corner(log)
    with np.errstate(over="ignore", invalid="ignore"):  # overflow is reported below
        M = log_product(scene, log)
    if not np.all(np.isfinite(M)):
        raise ValueError(f"period: the monodromy over {period} collisions overflows float64 (the orbit is too "
                         "unstable for a matrix this long; use analysis.lyapunov for its growth rate)")
    ev = np.linalg.eigvals(M)
    ev = ev[np.argsort(-np.abs(ev), kind="stable")]
    nearest = ev[np.argmin(np.abs(ev - 1.0))]
    unit = 1.0 if abs(nearest - 1.0) <= UNIT_SPLIT_TOL else float(nearest.real)
    trace = float(np.trace(M))
    e, s, w, vt = reduced_from_log(scene, log[[0, -1]])
    closure = None
    if e[0] == e[1]:
        closure = np.array([wrap_difference(scene, e[0], s[1] - s[0]), w[1] - w[0], vt[1] - vt[0]])
    row = log[0]
    base = {"element": int(e[0]), "s": float(s[0]), "w": float(w[0]), "v_t": float(vt[0]),
            "position": (float(row[layout.LOG_X]), float(row[layout.LOG_Y])),
            "velocity": (float(row[layout.LOG_VX]), float(row[layout.LOG_VY])),
            "spin": float(row[layout.LOG_W])}
    return Monodromy(matrix=M, eigenvalues=ev, kind=classify(ev), trace=trace, det=float(np.linalg.det(M)),
                     unit_eigenvalue=unit, eigen_sum=trace - unit, period=period,
                     period_time=float(log[-1, layout.LOG_T] - log[0, layout.LOG_T]), base=base, closure=closure)


def monodromy(scene: Scene, position, velocity, spin=0.0, *, period):
    r"""Monodromy matrix of the ``period``-th return map, by exact derivative propagation.

    The orbit starting at ``(position, velocity, spin)`` (strictly inside the
    table, e.g. a state from :mod:`noslipsim.analysis.orbits` or
    :func:`noslipsim.analysis.find_periodic_orbit`) is run with the compiled
    engine for ``period + 1`` collisions; the base point is its first
    collision.  Each flight contributes the exact Jacobian

    .. math::

        J_i = T_{i+1}\, R_{i+1}\, H_i\, F_i\, L_i,

    (leave the boundary, fly, move the hit time, read the new boundary
    coordinates, collide; :mod:`noslipsim.analysis.tangent`, docs/analysis.md),
    and ``M = J_{period-1} ... J_0``.  For a periodic orbit (same element,
    ``closure ~ 0``) the eigenvalues of ``M`` decide linear stability.

    Parameters
    ----------
    scene : Scene
        Any scene (plain or periodic, specular or no-slip, with or without force).
    position, velocity : (float, float)
        Start strictly inside the table.
    spin : float
        Scaled spin ``w``.
    period : int
        Number of collisions of the return map (``>= 1``).

    Returns
    -------
    Monodromy
        ``.matrix``, ``.eigenvalues``, ``.kind``, ``.trace``, ``.eigen_sum``,
        ``.base``, ``.closure`` and more.

    Raises
    ------
    ValueError
        ``period < 1``; the orbit stops (escape, grazing, ...) before
        ``period + 1`` collisions; a corner collision among them
        (:class:`~noslipsim.analysis.tangent.CornerError`, no derivative there);
        overflow for very unstable long orbits.

    Examples
    --------
    >>> from noslipsim.analysis import two_disk_orbit, monodromy
    >>> scene, state = two_disk_orbit(0.9, 1.2, 0.3)
    >>> m = monodromy(scene, **state, period=2)
    >>> m.kind, round(m.eigen_sum, 6)
    ('elliptic', -1.726997)
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
    period = _period(period)
    log, stop = interior_log(scene, position, velocity, spin, period + 1)
    if len(log) < period + 1:
        raise ValueError(f"period: the orbit stops ({stop!r}) after {len(log)} collisions, before the "
                         f"{period + 1} that a {period}-collision return map from its first collision needs")
    return monodromy_of_log(scene, log)

