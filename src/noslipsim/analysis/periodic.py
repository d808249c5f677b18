r"""Periodic orbits by Newton's method on the return map, with the exact monodromy as Jacobian.

The unknown is the post-collision reduced state ``x = (s, w, v_t)`` on the
element of the start's first collision, at the start's energy
(docs/analysis.md).  With ``P`` the collision-to-collision map of
:mod:`noslipsim.analysis.tangent`, a ``period``-periodic orbit solves

.. math::

    F(x) = P^{p}(x) - x = 0, \qquad DF = M - I,

``M`` the monodromy.  A conservative no-slip billiard has families of
periodic orbits (e.g. every force-free 2-periodic orbit: eigenvalue 1 along
the family), so ``M - I`` is typically singular: each Newton step is the
minimum-norm least-squares solution (in coordinates scaled by the table's
size and the speed), which moves across the family, not along it.  A step
that does not reduce the residual is halved (backtracking); if that fails, a
Levenberg-Marquardt step is tried; if that fails too the search stops and
says so (``converged=False``), never raising.

On a lattice, "periodic" means returning to the same element up to a
lattice translation (a periodic orbit of the torus).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._validate import finite_float
from ..core import layout
from ..scenes import Scene
from .monodromy import Monodromy, _period, monodromy
from .section import (
    boundary_frames,
    boundary_log,
    energy_at,
    interior_log,
    reduced_from_log,
    state_from_reduced,
    wrap_difference,
)
from .tangent import CornerError, check_no_corner, log_product

__all__ = ["PeriodicOrbit", "find_periodic_orbit"]

#: Step halvings tried before the Levenberg-Marquardt fallback.
MAX_HALVINGS = 30

#: Damping factors (relative to the largest squared singular value) of the
#: Levenberg-Marquardt fallback, smallest first.
LM_DAMPINGS = (1e-8, 1e-5, 1e-2, 1.0, 1e2)

#: Relative cut-off below which singular values of the scaled ``M - I`` count as
#: zero in the minimum-norm step (the family direction).
RCOND = 1e-10

#: A converged orbit is re-run from the returned interior state; its closure
#: (scaled like the residual) may exceed ``tol`` by rounding amplified along
#: the orbit, but not by more than this factor times ``(1 + |lambda|_max)``.
RECHECK_FACTOR = 1e3


@dataclass(frozen=True)
class PeriodicOrbit:
    """Result of :func:`find_periodic_orbit`.

    Attributes
    ----------
    position, velocity : tuple of float
        A start strictly inside the table, half-way (in time) along the flight
        leaving the base point: ``ns.simulate(scene, position, velocity, spin)``
        runs the orbit (its collision ``period - 1`` is the base point).
    spin : float
        Scaled spin on that flight.
    residual : float
        ``max(|ds|/L, |dw|/V, |dv_t|/V)`` of ``P^p(x) - x`` at the last iterate,
        ``L`` the table's size, ``V = sqrt(|v|^2 + w^2)`` at the base point
        (``inf`` if the last iterate's orbit did not return to its element).
    converged : bool
        ``residual <= tol`` (and the re-run from the returned state closes).
    iterations : int
        Newton steps taken.
    monodromy : Monodromy or None
        Of the returned orbit (from its first collision), when it returns to
        its element; its ``closure`` is an independent check of periodicity.
    period : int
    base : dict
        ``element``, ``s``, ``w``, ``v_t`` of the last iterate, and its ``energy``.
    history : tuple of float
        Residual at each iterate, the start first.
    message : str
        Why the search stopped.
    """

    position: tuple
    velocity: tuple
    spin: float
    residual: float
    converged: bool
    iterations: int
    monodromy: Monodromy | None = field(repr=False)
    period: int
    base: dict = field(repr=False)
    history: tuple = field(repr=False)
    message: str = ""

    @property
    def state(self):
        """``{"position", "velocity", "spin"}`` for ``ns.simulate(scene, **result.state, ...)``."""
        return {"position": self.position, "velocity": self.velocity, "spin": self.spin}


class _Section:
    """The return map ``P^p`` at fixed energy on one element, evaluated with the compiled engine."""

    def __init__(self, scene, element, energy, period, length, speed):
        self.scene, self.element, self.energy, self.period = scene, element, energy, period
        self.scale = np.array([length, speed, speed])

    def run(self, x):
        """``(residual, log)`` of the orbit from reduced state ``x``, or ``(None, reason)``."""
        start = state_from_reduced(self.scene, self.element, *x, self.energy)
        if start is None:
            return None, "off the energy surface (no kinetic energy left for v_n)"
        q, v, w = start
        try:
            log, stop = boundary_log(self.scene, self.element, q, v, w, self.period)
        except ValueError as err:
            return None, str(err)
        if len(log) < self.period:
            return None, f"the orbit stops ({stop!r}) after {len(log)} of {self.period} collisions"
        base = np.zeros(layout.N_LOG)
        base[[layout.LOG_X, layout.LOG_Y]] = q
        base[[layout.LOG_VX, layout.LOG_VY]] = v
        base[[layout.LOG_VX_IN, layout.LOG_VY_IN]] = v
        base[[layout.LOG_W, layout.LOG_W_IN]] = w
        base[layout.LOG_ELEMENT] = self.element
        base[layout.LOG_S] = x[0]
        full = np.vstack([base, log])
        if full[:, layout.LOG_CORNER].any():
            return None, "the orbit goes through a corner (no derivative there)"
        last = int(log[-1, layout.LOG_ELEMENT])
        if last != self.element:
            return None, f"collision {self.period} is on element {last}, not on the start's element {self.element}"
        _, s, w1, vt = reduced_from_log(self.scene, log[-1:])
        r = np.array([wrap_difference(self.scene, self.element, s[0] - x[0]), w1[0] - x[1], vt[0] - x[2]])
        return r, full

    def size(self, r):
        return float(np.max(np.abs(r) / self.scale))


def _scaled(M, scale):
    """``M - I`` in coordinates scaled by ``scale`` (length, speed, speed)."""
    return (M - np.eye(3)) * scale[None, :] / scale[:, None]


def _newton_steps(A, r, scale, rho):
    """Minimum-norm least-squares solutions of ``A y = -r/scale``, one per singular-value cut-off.

    Near a family of periodic orbits the singular value of ``M - I`` along
    the family is only ``O(residual)``, not 0: the plain pseudo-inverse would
    step far along the family.  So the cut-off (relative to the largest
    singular value) is tried at ``RCOND`` (the plain Newton step, quadratic
    near an isolated orbit) and at multiples of the residual ``rho``.
    """
    U, sv, Vt = np.linalg.svd(A)
    b = U.T @ (-r / scale)
    steps = []
    for cut in (RCOND, rho, 10.0 * rho, 100.0 * rho, math.sqrt(rho)):
        keep = sv > min(cut, 0.5) * sv[0]
        y = Vt.T[:, keep] @ (b[keep] / sv[keep])
        if not any(np.array_equal(y, z) for z in steps):
            steps.append(y)
    return [y * scale for y in steps]


def _lm_steps(A, r, scale):
    """Levenberg-Marquardt steps ``(A^T A + mu I) y = -A^T r`` for growing damping ``mu``."""
    AtA = A.T @ A
    g = A.T @ (r / scale)
    top = max(np.linalg.eigvalsh(AtA).max(), 1e-300)
    for mu in LM_DAMPINGS:
        yield -np.linalg.solve(AtA + mu * top * np.eye(3), g) * scale


def find_periodic_orbit(scene: Scene, position, velocity, spin=0.0, *, period, tol=1e-12, max_iter=50):
    r"""Find a ``period``-periodic orbit near a start, by Newton's method on the return map.

    The start ``(position, velocity, spin)`` (strictly inside the table) is run
    to its first collision; its post-collision reduced state ``x0 = (s, w, v_t)``
    on that element and its energy ``E`` are the initial guess and the fixed
    energy.  Newton's method on ``F(x) = P^p(x) - x`` with the exact Jacobian
    ``M - I`` (:func:`noslipsim.analysis.monodromy`) then looks for a fixed
    point; steps are minimum-norm least squares (``M - I`` is singular along
    families of periodic orbits), halved when they do not reduce the residual,
    with a Levenberg-Marquardt fallback.

    Parameters
    ----------
    scene : Scene
        Any scene (plain or periodic; specular, no-slip; with or without force).
    position, velocity : (float, float)
        Start strictly inside the table.
    spin : float
        Scaled spin ``w`` (counter-clockwise positive).
    period : int
        Collisions per period (``>= 1``).
    tol : float
        Target for the scaled residual ``max(|ds|/L, |dw|/V, |dv_t|/V)``
        (``L`` the table's size, ``V = sqrt(|v|^2 + w^2)``).
    max_iter : int
        Newton steps at most.

    Returns
    -------
    PeriodicOrbit
        ``.position``, ``.velocity``, ``.spin`` (ready for ``ns.simulate``),
        ``.residual``, ``.converged``, ``.iterations``, ``.monodromy`` and more.
        A search that fails returns ``converged=False`` with the last residual
        and a ``message``; it does not raise.

    Raises
    ------
    ValueError
        For ``period < 1``, a bad ``tol`` or ``max_iter``, a start that is not
        strictly inside the table, or a start whose orbit escapes, stops or goes
        through a corner before ``period`` collisions after its first (so there
        is no return map to solve).
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
    period = _period(period)
    tol = finite_float(tol, "tol")
    if not tol > 0.0:
        raise ValueError(f"tol: must be > 0, got {tol}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 0:
        raise ValueError(f"max_iter: expected an integer >= 0, got {max_iter!r}")

    first, stop = interior_log(scene, position, velocity, spin, period + 1)
    if len(first) == 0:
        raise ValueError(f"position, velocity: the start's orbit has no collision ({stop!r}), so no return map")
    check_no_corner(first, "position, velocity: the start's orbit")
    if len(first) < period + 1:
        raise ValueError(f"position, velocity: the start's orbit stops ({stop!r}) after {len(first)} collisions, "
                         f"before returning {period} collisions after its first")
    first = first[:1]
    element, s0, w0, vt0 = (a[0] for a in reduced_from_log(scene, first))
    element = int(element)
    point = boundary_frames(scene, np.array([element]), np.array([s0]))[0][0]
    v0 = first[0, [layout.LOG_VX, layout.LOG_VY]]
    energy = energy_at(scene, point, v0, w0)
    speed = math.sqrt(float(v0 @ v0) + w0 * w0)
    length = max(scene.scale, float(np.abs(point).max()), 1e-300)
    section = _Section(scene, element, energy, period, length, speed)

    x = np.array([s0, w0, vt0])
    r, full = section.run(x)
    if r is None:
        if "not on the start's element" in full:
            return _result(scene, section, x, None, math.inf, False, 0, (math.inf,), full, tol)
        raise ValueError(f"position, velocity: no {period}-collision return map from this start: {full}")
    rho = section.size(r)
    history = [rho]
    message = "max_iter reached"
    iterations = 0
    while rho > tol and iterations < max_iter:
        A = _scaled(log_product(scene, full), section.scale)
        # the full steps of every cut-off first, the best one taken; then each halved in turn
        accepted = None
        for lam in 0.5 ** np.arange(MAX_HALVINGS):
            for step in _newton_steps(A, r, section.scale, rho):
                trial = section.run(x + lam * step)
                if trial[0] is not None and section.size(trial[0]) < rho and (
                        accepted is None or section.size(trial[0]) < section.size(accepted[1])):
                    accepted = (x + lam * step, *trial)
            if accepted is not None:
                break
        if accepted is None:
            for lm in _lm_steps(A, r, section.scale):
                trial = section.run(x + lm)
                if trial[0] is not None and section.size(trial[0]) < rho:
                    accepted = (x + lm, *trial)
                    break
        if accepted is None:
            message = "no step reduces the residual (stalled: rounding floor, or no periodic orbit nearby)"
            break
        x, r, full = accepted
        rho = section.size(r)
        history.append(rho)
        iterations += 1
    if rho <= tol:
        message = "converged"
    return _result(scene, section, x, full, rho, rho <= tol, iterations, tuple(history), message, tol)


def _result(scene, section, x, full, rho, converged, iterations, history, message, tol):
    """Build the :class:`PeriodicOrbit`: interior start on the first flight, re-run check, monodromy."""
    start = state_from_reduced(scene, section.element, *x, section.energy)
    q, v, w = start
    if full is not None:
        tau = float(full[1, layout.LOG_T])
    else:  # no return: still give the start on the flight leaving x
        log, _ = boundary_log(scene, section.element, q, v, w, 1)
        tau = float(log[0, layout.LOG_T]) if len(log) else 0.0
    a = np.asarray(scene.force)
    h = 0.5 * tau
    q_mid = q + v * h + 0.5 * a * h * h
    v_mid = v + a * h
    mono = None
    if full is not None:
        try:
            mono = monodromy(scene, q_mid, v_mid, w, period=section.period)
        except (ValueError, CornerError):
            mono = None
        if converged:
            ok = mono is not None and mono.closure is not None
            if ok:
                lam = float(np.abs(mono.eigenvalues).max())
                ok = section.size(mono.closure) <= RECHECK_FACTOR * tol * (1.0 + lam)
            if not ok:
                converged = False
                message = "the re-run from the returned state does not close (rounding amplified along the orbit)"
    base = {"element": section.element, "s": float(x[0]), "w": float(x[1]), "v_t": float(x[2]),
            "energy": float(section.energy)}
    return PeriodicOrbit(position=(float(q_mid[0]), float(q_mid[1])), velocity=(float(v_mid[0]), float(v_mid[1])),
                         spin=float(w), residual=float(rho), converged=bool(converged), iterations=int(iterations),
                         monodromy=mono, period=section.period, base=base, history=history, message=message)
