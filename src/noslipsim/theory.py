r"""Closed forms of the paper's theorems, corrected where the paper is wrong.

They are test oracles and inputs of the pipeline (e.g. the start of a
2-periodic wedge orbit to perturb).  Conventions are those of docs/conventions.md:
scaled spin ``w = gamma R omega`` counter-clockwise positive, outward normal
``n`` (out of the table), tangent ``t = J n``; the no-slip law is

.. math::

    w^+ = -c\,w - s\,v_t, \qquad v_t^+ = -s\,w + c\,v_t, \qquad v_n^+ = -v_n,

with ``c = (1 - gamma^2)/(1 + gamma^2)``, ``s = 2 gamma/(1 + gamma^2)``
(:func:`noslip_coefficients`).  Since ``c + gamma s = 1`` and
``gamma c - s = -gamma``, an impact with ``v_t = gamma w`` sends
``(w, v_t, v_n)`` to ``(-w, -v_t, -v_n)``: the whole velocity is reversed and
the particle retraces its path (path reversal).  Every 2-periodic orbit below is
built from that one fact.  The three errata of the paper are documented
in ``docs/errata.md``.

Reference: J. Ahmed, T. Chumley, S. Cook, C. Cox, H. Grant, N. Petela,
B. Rothrock, R. Xhafaj, *Dynamics of the no-slip Galton board*.
"""
from __future__ import annotations

import math

import numpy as np

from ._validate import finite_float, one_of, positive
from .core.laws import noslip_coefficients

__all__ = [
    "ellipticity_threshold", "half_plane_drift", "noslip_coefficients", "projectile_speed",
    "two_disk_eigen_sum", "wedge_noforce_gamma", "wedge_two_periodic_start",
]

_OPENINGS = ("up", "down")
_WALLS = ("left", "right")


# ----------------------------------------------------------------------------- argument checks
def _array(value, field):
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{field}: expected a number or an array of numbers, got {value!r}") from None
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{field}: must be finite, got {value!r}")
    return arr


def _out(arr):
    return float(arr) if np.ndim(arr) == 0 else arr


def _angle(value, field, low_open=True):
    """An angle in (0, pi/2) (or [0, pi/2) with ``low_open=False``)."""
    x = finite_float(value, field)
    ok = (x > 0.0 if low_open else x >= 0.0) and x < math.pi / 2
    if not ok:
        span = "(0, pi/2)" if low_open else "[0, pi/2)"
        raise ValueError(f"{field}: must lie in {span}, got {x}")
    return x


def _gamma_array(value, field="gamma"):
    g = _array(value, field)
    if np.any(g < 0.0):
        raise ValueError(f"{field}: must be >= 0, got {value!r}")
    return g


def _phi_array(value, field="phi"):
    p = _array(value, field)
    if np.any(p < 0.0) or np.any(p >= math.pi / 2):
        raise ValueError(f"{field}: must lie in [0, pi/2), got {value!r}")
    return p


# ----------------------------------------------------------------------------- half plane
def half_plane_drift(vx, w, u, gamma, g):
    r"""Horizontal drift per two bounces of the no-slip ball on a floor (Theorem 1).

    Table ``y > 0``, force ``(0, -g)``.  With ``k = v_x - gamma w`` (the same on
    every flight, since the law preserves it), the horizontal velocities of two
    consecutive flights sum to ``2 k / (1 + gamma^2)``; each flight lasts
    ``2 u / g``.  Hence

    .. math::

        D = \frac{4\,u\,(v_x - \gamma w)}{g\,(1 + \gamma^2)},

    zero (a 2-periodic orbit) iff ``v_x = gamma w``.  In three dimensions the
    same holds component-wise with ``v_x - gamma w`` replaced by
    ``v_T - gamma n x W_T`` (:mod:`noslipsim.sphere3d`).

    Parameters
    ----------
    vx, w : float or array
        Horizontal velocity and scaled spin on any flight (nondimensional).
    u : float or array
        Vertical impact speed ``>= 0`` (the take-off speed of every bounce).
    gamma : float or array
        Mass-distribution constant ``>= 0``.
    g : float or array
        Gravity ``> 0``.

    Returns
    -------
    float or ndarray
        The displacement ``x_{k+2} - x_k`` of bounce points.
    """
    vx = _array(vx, "vx")
    w = _array(w, "w")
    u = _array(u, "u")
    if np.any(u < 0.0):
        raise ValueError(f"u: the impact speed must be >= 0, got {u!r}")
    gamma = _gamma_array(gamma)
    g = _array(g, "g")
    if np.any(g <= 0.0):
        raise ValueError(f"g: must be > 0, got {g!r}")
    return _out(4.0 * u * (vx - gamma * w) / (g * (1.0 + gamma * gamma)))


# ----------------------------------------------------------------------------- wedges
def projectile_speed(g, d, theta):
    r"""Launch speed that carries a projectile a horizontal distance ``d`` at launch angle ``theta``.

    .. math::

        v = \sqrt{\frac{g\,d}{\sin 2\theta}}

    (range ``v^2 sin 2 theta / g = d``).  This is Theorem 2's speed; the paper
    prints ``2 sqrt(g d / sin 2 theta)``, which lands at range ``4 d``
    (erratum 1, ``docs/errata.md``).

    Parameters
    ----------
    g : float
        Gravity ``> 0``.
    d : float
        Horizontal distance ``> 0`` between launch and landing points at equal height.
    theta : float
        Launch angle above the horizontal, in ``(0, pi/2)``.
    """
    g = positive(g, "g")
    d = positive(d, "d")
    theta = _angle(theta, "theta")
    return math.sqrt(g * d / math.sin(2.0 * theta))


def wedge_two_periodic_start(phi, theta, ell, gamma, g=1.0, opening="up", wall="left"):
    r"""Start of the path-reversing 2-periodic orbit of a no-slip wedge under gravity (Theorem 2).

    The wedge is that of :func:`noslipsim.tables.wedge`: vertex at the origin,
    bisector vertical, half-angle ``phi``, force ``(0, -g)``.  The orbit leaves
    the point at distance ``ell`` from the vertex on ``wall`` towards the
    other wall at launch angle ``theta`` above the horizontal, lands on the
    opposite point (same height, ``d = 2 ell sin(phi)`` away) with velocity
    ``v (sx cos(theta), -sin(theta))`` where ``v`` is :func:`projectile_speed`,
    and is sent straight back when ``v_t = gamma w`` there.  With
    ``sx = +1`` from the left wall (``-1`` from the right) and ``sy = +1`` for a
    wedge opening up (``-1`` down), the far wall's tangent ``t = J n`` is
    ``(sy sin(phi), sx cos(phi))``, giving ``v_t = sx v sin(sy phi - theta)`` and

    .. math::

        w_0 = \frac{s_x\, v \sin(s_y \varphi - \theta)}{\gamma}.

    The four cases: up/left ``v sin(phi - theta)/gamma``, up/right
    ``v sin(theta - phi)/gamma`` (the paper's printed formula), down/left
    ``-v sin(phi + theta)/gamma``, down/right ``v sin(phi + theta)/gamma``.  The
    return flight arrives at the start with ``(-v_0, -w_0)`` and
    ``v_t = gamma (-w_0)`` there too, so the state after the second collision
    equals the start (erratum 2, ``docs/errata.md``).

    Parameters
    ----------
    phi : float
        Wedge half-angle (wall to bisector) in ``(0, pi/2)``.
    theta : float
        Launch angle above the horizontal in ``(0, pi/2)``; for ``opening='down'``
        also ``theta < pi/2 - phi`` (otherwise the launch leaves through the wall).
    ell : float
        Distance ``> 0`` of the launch point from the vertex.
    gamma : float
        Mass-distribution constant ``> 0`` (with ``gamma = 0`` only the
        perpendicular orbit would reverse).
    g : float
        Gravity ``> 0`` (force ``(0, -g)`` whatever the opening).
    opening : {'up', 'down'}
        Which way the wedge opens.
    wall : {'left', 'right'}
        Wall of the launch point (element 0 or 1 of :func:`noslipsim.tables.wedge`).

    Returns
    -------
    position : ndarray, shape (2,)
        The launch point, on the wall (a :func:`noslipsim.simulate` start must be
        strictly inside: advance along the flight first).
    velocity : ndarray, shape (2,)
        Velocity just after the collision at the launch point.
    spin : float
        Scaled spin ``w_0`` on the flight.
    """
    phi = _angle(phi, "phi")
    theta = _angle(theta, "theta")
    ell = positive(ell, "ell")
    gamma = positive(gamma, "gamma")
    g = positive(g, "g")
    one_of(opening, _OPENINGS, "opening")
    one_of(wall, _WALLS, "wall")
    sy = 1.0 if opening == "up" else -1.0
    sx = 1.0 if wall == "left" else -1.0
    if opening == "down" and not theta + phi < math.pi / 2:
        raise ValueError(f"theta: in a downward wedge the launch must satisfy theta < pi/2 - phi "
                         f"= {math.pi / 2 - phi}, got {theta}")
    d = 2.0 * ell * math.sin(phi)
    v = projectile_speed(g, d, theta)
    position = np.array([-sx * ell * math.sin(phi), sy * ell * math.cos(phi)])
    velocity = np.array([sx * v * math.cos(theta), v * math.sin(theta)])
    spin = sx * v * math.sin(sy * phi - theta) / gamma
    return position, velocity, spin


def wedge_noforce_gamma(vx, w, phi, opening="up"):
    r"""The ``gamma`` for which a horizontal flight across a force-free wedge is 2-periodic.

    A horizontal flight ``(v_x, 0)`` hits the far wall of a wedge opening up
    (tangent ``t = J n = (sin phi, +-cos phi)``) with ``v_t = v_x sin(phi)``,
    whichever wall it comes from; path reversal ``v_t = gamma w`` gives

    .. math::

        \gamma = +\frac{v_x}{w} \sin\varphi \quad\text{(opening up)}, \qquad
        \gamma = -\frac{v_x}{w} \sin\varphi \quad\text{(opening down)}.

    The paper prints the minus sign for a wedge opening upward (erratum 3,
    ``docs/errata.md``).

    Parameters
    ----------
    vx : float
        Horizontal velocity, nonzero.
    w : float
        Scaled spin, nonzero.
    phi : float
        Wedge half-angle in ``(0, pi/2)``.
    opening : {'up', 'down'}
        Which way the wedge opens.

    Raises
    ------
    ValueError
        If the signs of ``vx`` and ``w`` admit no ``gamma > 0``.
    """
    vx = finite_float(vx, "vx")
    w = finite_float(w, "w")
    phi = _angle(phi, "phi")
    one_of(opening, _OPENINGS, "opening")
    if vx == 0.0:
        raise ValueError("vx: must be nonzero (a horizontal flight across the wedge)")
    if w == 0.0:
        raise ValueError("w: must be nonzero (with w = 0 no gamma > 0 reverses an oblique impact)")
    sy = 1.0 if opening == "up" else -1.0
    gamma = sy * vx / w * math.sin(phi)
    if gamma <= 0.0:
        need = "the same sign as" if opening == "up" else "the opposite sign to"
        raise ValueError(f"w: for a wedge opening {opening} the spin must have {need} vx "
                         f"(got vx={vx}, w={w}); no gamma > 0 exists")
    return gamma


# ----------------------------------------------------------------------------- two disks
def two_disk_eigen_sum(kappa, d, phi, gamma):
    r"""``lambda + 1/lambda`` of the 2-bounce monodromy of a force-free no-slip 2-periodic orbit.

    Two disks of curvature ``kappa``, collision points ``d`` apart whose tangent
    lines meet at angle ``2 phi`` (``phi = 0``: along the line of centres).  The
    linearised 2-bounce map on the reduced state (boundary position and unit
    velocity ``(w, v_t, v_n)``) has eigenvalues ``{1, lambda, 1/lambda}`` with

    .. math::

        \lambda + \frac{1}{\lambda} = 4 C^2 \cos^2\varphi\,(\kappa d - u_0)^2 - 2,
        \qquad u_0 = \frac{1 - 2 C \cos^2\varphi}{C \cos\varphi},
        \qquad C = \frac{1}{1 + \gamma^2} = \cos^2(\beta/2).

    ``gamma = 0`` gives the specular ``4 (1 + kappa d)^2 - 2`` at ``phi = 0``;
    ``kappa = 0`` is the (always elliptic) force-free wedge.  The orbit is
    elliptic iff the value lies in ``(-2, 2)``, i.e. ``kappa d <``
    :func:`ellipticity_threshold` (Wojtkowski 1994; Cox, Feres & Zhang 2018).

    Parameters
    ----------
    kappa : float or array
        Curvature ``>= 0`` of both disks (``1/R``).
    d : float or array
        Distance ``> 0`` between the collision points.
    phi : float or array
        Half the angle between the tangent lines, in ``[0, pi/2)``.
    gamma : float or array
        Mass-distribution constant ``>= 0``.
    """
    kappa = _array(kappa, "kappa")
    if np.any(kappa < 0.0):
        raise ValueError(f"kappa: must be >= 0, got {kappa!r}")
    d = _array(d, "d")
    if np.any(d <= 0.0):
        raise ValueError(f"d: must be > 0, got {d!r}")
    phi = _phi_array(phi)
    gamma = _gamma_array(gamma)
    C = 1.0 / (1.0 + gamma * gamma)
    cphi = np.cos(phi)
    u0 = (1.0 - 2.0 * C * cphi ** 2) / (C * cphi)
    return _out(4.0 * C ** 2 * cphi ** 2 * (kappa * d - u0) ** 2 - 2.0)


def ellipticity_threshold(phi, gamma):
    r"""Largest ``kappa d`` for which the two-disk 2-periodic orbit is elliptic (equation ellipticity).

    .. math::

        \kappa d < \frac{2 - 2 C \cos^2\varphi}{C \cos\varphi}, \qquad C = \frac{1}{1 + \gamma^2},

    where :func:`two_disk_eigen_sum` reaches ``+2`` (``lambda = 1``); its lower
    root ``-2 cos(phi)`` is negative, so this is the only condition.  The paper
    prints it with ``cos^2(beta/2) = C``, correctly.

    Parameters
    ----------
    phi : float or array
        Half the angle between the tangent lines, in ``[0, pi/2)``.
    gamma : float or array
        Mass-distribution constant ``>= 0``.
    """
    phi = _phi_array(phi)
    gamma = _gamma_array(gamma)
    C = 1.0 / (1.0 + gamma * gamma)
    cphi = np.cos(phi)
    return _out((2.0 - 2.0 * C * cphi ** 2) / (C * cphi))
