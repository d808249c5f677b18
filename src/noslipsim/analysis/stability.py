r"""Stability grids of the two-disk 2-periodic orbits: experiment (survival) beside linear theory.

The paper's last experiment (its ``stabexp`` figure): two no-slip disks of
radius ``R`` centred at ``(-1, 0)`` and ``(1, 0)``, and the path-reversing
2-periodic orbit between ``q0`` (angle ``phi`` above the horizontal on the left
disk) and its mirror image ``q1``, along the chord without force or launched at
angle ``theta`` with gravity (:func:`noslipsim.analysis.two_disk_orbit`).  For
each grid point the orbit is perturbed and run until it misses both disks
(escape) or reaches ``max_collisions``; beside that count stand the linear
class of the unperturbed orbit and ``lambda + 1/lambda`` of its 2-bounce
monodromy (:func:`noslipsim.analysis.monodromy`, exact derivative propagation,
with or without force).  Without force the closed form

.. math::

    \kappa d < \frac{2 - 2 C \cos^2\varphi}{C \cos\varphi}, \qquad
    C = \frac{1}{1 + \gamma^2}, \quad \kappa = \frac{1}{R}, \quad d = 2 - 2 R \cos\varphi,

(the paper's equation ``ellipticity``, :func:`noslipsim.theory.ellipticity_threshold`)
says where the orbit is elliptic: ``R > R^*(phi) = 2 / (thr + 2 cos phi)``.

Perturbation (the paper does not state its own).  The start returned by
:func:`~noslipsim.analysis.two_disk_orbit` (the state half-way along the
flight ``q0 -> q1``) has its velocity turned counter-clockwise by ``angle``
radians, its speed kept, and its spin multiplied by ``1 + spin``.  An angle is
dimensionless and means the same at every grid point whatever the speed (the
launch speed grows without bound as ``theta -> 0`` under gravity), and a
turned velocity has components along every direction of the reduced section
(boundary point and exit direction change at the next impact), so an unstable
orbit cannot hide its growing direction.  Default: ``angle = 1e-3``,
``spin = 0``.  Docs: docs/analysis.md (also for what the grids show: under
gravity the line ``phi + theta = pi/2``, a launch parallel to the tangent at
``q1``, is parabolic for every ``R`` and ``gamma`` tried).

References: the paper, section "Stability of periodic points"; C. Cox,
R. Feres, H.-K. Zhang, *Stability of periodic orbits in no-slip billiards*,
Nonlinearity 31 (2018); M. Wojtkowski, Physica D 71 (1994).
"""
from __future__ import annotations

import json
import math
import sys
from collections.abc import Mapping

import numpy as np
import xarray as xr

from .. import theory
from .._metadata import annotate
from .._validate import finite_float
from ..core import layout
from ..ensemble import STOP_FLAGS, simulate_many
from .monodromy import KINDS, UNIT_TOL, classify
from .orbits import two_disk_orbit
from .tangent import check_no_corner, step_jacobians

__all__ = ["DEFAULT_PERTURBATION", "agreement_share", "elliptic_boundary", "stability_grid", "stability_grid_theta",
           "two_disk_classes"]

#: The default perturbation of the start: velocity turned by 1e-3 rad, spin unchanged.
DEFAULT_PERTURBATION = {"angle": 1e-3, "spin": 0.0}

#: Collisions of the unperturbed run whose log gives the 2-bounce monodromy (base at collision 0).
_LOG_ROWS = 3

#: Log columns rebuilt from an ensemble ``log`` dataset (the inverse of ``ensemble``'s naming).
_LOG_COLUMNS = {
    "t": layout.LOG_T, "x": layout.LOG_X, "y": layout.LOG_Y, "vx": layout.LOG_VX, "vy": layout.LOG_VY,
    "spin": layout.LOG_W, "vx_in": layout.LOG_VX_IN, "vy_in": layout.LOG_VY_IN, "spin_in": layout.LOG_W_IN,
    "element": layout.LOG_ELEMENT, "s": layout.LOG_S, "corner": layout.LOG_CORNER,
}



# ----------------------------------------------------------------------------- input checks
def _axis(values, field, low, high, what):
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{field}: expected numbers, got {values!r}") from None
    arr = np.atleast_1d(arr)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{field}: expected a non-empty 1-D array, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{field}: must be finite")
    bad = (arr <= low) | (arr >= high)
    if bad.any():
        raise ValueError(f"{field}: every value must lie in {what}, got {arr[bad][0]}")
    if arr.size > 1 and (np.diff(arr) <= 0.0).any():
        raise ValueError(f"{field}: must be strictly increasing (a grid coordinate)")
    return arr


def _perturbation(value):
    """``{'angle': a, 'spin': s}`` from a number (the angle) or a mapping."""
    if isinstance(value, Mapping):
        unknown = set(value) - set(DEFAULT_PERTURBATION)
        if unknown:
            raise ValueError(f"perturbation: unknown key(s) {sorted(unknown)}; allowed: "
                             f"{sorted(DEFAULT_PERTURBATION)}")
        out = dict(DEFAULT_PERTURBATION)
        out.update({k: finite_float(v, f"perturbation.{k}") for k, v in value.items()})
    else:
        out = {"angle": finite_float(value, "perturbation"), "spin": 0.0}
    if abs(out["angle"]) >= math.pi / 2:
        raise ValueError(f"perturbation.angle: must be a small angle (|angle| < pi/2), got {out['angle']}")
    if out["spin"] <= -1.0:
        raise ValueError(f"perturbation.spin: the relative spin change must be > -1, got {out['spin']}")
    return out


def _max_collisions(value):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"max_collisions: expected a positive integer, got {value!r}")
    return int(value)


def _gamma(value):
    g = finite_float(value, "gamma")
    if not g > 0.0:
        raise ValueError(f"gamma: must be > 0 (with gamma = 0 only a perpendicular impact reverses the "
                         f"path, which no grid point with phi > 0 has), got {g}")
    return g


# ----------------------------------------------------------------------------- per radius
def _logs(ds, rows):
    """``(N, rows, N_LOG)`` collision logs from an ensemble ``record='log'`` dataset."""
    n = ds.sizes["orbit"]
    out = np.zeros((n, rows, layout.N_LOG))
    for name, col in _LOG_COLUMNS.items():
        out[:, :, col] = ds[name].values[:, :rows]
    return out


def _two_bounce(scene, logs):
    """Monodromy of the 2-bounce return map at collision 0 of each log: matrices, kinds, eigen sums.

    The same matrices as ``analysis.monodromy(scene, **state, period=2)``, with
    one vectorised :func:`~noslipsim.analysis.tangent.step_jacobians` call for
    all orbits of the scene: the logs are laid end to end and the Jacobians
    between rows of different orbits are dropped.
    """
    n = len(logs)
    flat = logs.reshape(n * _LOG_ROWS, layout.N_LOG)
    check_no_corner(flat, "orbit")
    with np.errstate(all="ignore"):  # the dropped cross-orbit steps may be meaningless
        J = step_jacobians(scene, flat)
    first = J[0::_LOG_ROWS]
    second = J[1::_LOG_ROWS]
    M = second @ first
    ev = np.linalg.eigvals(M)
    unit = np.take_along_axis(ev, np.argmin(np.abs(ev - 1.0), axis=1)[:, None], axis=1)[:, 0].real
    eigen_sum = np.trace(M, axis1=1, axis2=2) - unit
    kinds = [classify(e) for e in ev]
    return M, kinds, eigen_sum


def _rotate(v, angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.c_[c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]]


def _check_bounces(radius, points, logs):
    """The unperturbed orbits must bounce q1, q0, q1 (elements 1, 0, 1): the 2-bounce map the monodromy is of."""
    el = logs[:, :, layout.LOG_ELEMENT]
    bad = ~((el[:, 0] == 1) & (el[:, 1] == 0) & (el[:, 2] == 1))
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"radius={radius}, (phi, theta)={points[i]}: the unperturbed orbit does not bounce "
                         f"between the two disks (elements hit {el[i].tolist()})")


def _one_radius(radius, points, gamma, gravity, perturbation, max_collisions, scheduler):
    """Survival counts, stop reasons, kinds and eigen sums along one row of the grid (one scene)."""
    orbits = [two_disk_orbit(radius, phi, gamma, theta=theta, gravity=gravity) for phi, theta in points]
    scene = orbits[0][0]  # the same table for every point of the row
    q = np.array([state["position"] for _, state in orbits])
    v = np.array([state["velocity"] for _, state in orbits])
    w = np.array([state["spin"] for _, state in orbits])
    base = simulate_many(scene, q, v, w, max_collisions=_LOG_ROWS, record="log", scheduler=scheduler,
                         progress=False)
    short = base.n_collisions.values < _LOG_ROWS
    if short.any():
        i = int(np.argmax(short))
        raise ValueError(f"radius={radius}, (phi, theta)={points[i]}: the unperturbed orbit stopped "
                         f"({layout.STOP_REASONS[int(base.stop_reason[i])]}) before two bounces")
    logs = _logs(base, _LOG_ROWS)
    _check_bounces(radius, points, logs)
    _, kinds, eigen_sum = _two_bounce(scene, logs)
    vp = _rotate(v, perturbation["angle"])
    wp = w * (1.0 + perturbation["spin"])
    runs = simulate_many(scene, q, vp, wp, max_collisions=max_collisions, record="count", scheduler=scheduler,
                         progress=False)
    return runs.n_collisions.values, runs.stop_reason.values, kinds, eigen_sum


def _grid(radii, second, values, points_of, gamma, gravity, perturbation, max_collisions, scheduler, progress,
          attrs):
    rows = []
    show = sys.stderr.isatty() if progress is None else bool(progress)
    for i, R in enumerate(radii):
        rows.append(_one_radius(float(R), [points_of(x) for x in values], gamma, gravity, perturbation,
                                max_collisions, scheduler))
        if show:
            print(f"\rstability grid: radius {i + 1}/{len(radii)}", end="", file=sys.stderr, flush=True)
    if show:
        print(file=sys.stderr)
    n_coll = np.array([r[0] for r in rows], dtype=np.int64)
    stop = np.array([r[1] for r in rows], dtype=np.int8)
    kinds = np.array([r[2] for r in rows], dtype="<U10")
    eigen_sum = np.array([r[3] for r in rows])
    dims = ("radius", second)
    ds = xr.Dataset(
        {
            "n_collisions": (dims, n_coll),
            "stop_reason": (dims, stop, dict(STOP_FLAGS)),
            "survived": (dims, (n_coll >= max_collisions).astype(np.int8)),
            "linear_kind": (dims, kinds),
            "eigen_sum": (dims, eigen_sum),
        },
        coords={"radius": ("radius", np.asarray(radii, float)), second: (second, np.asarray(values, float)),
                "curvature": ("radius", 1.0 / np.asarray(radii, float))},
    )
    ds.attrs.update(
        title="two-disk 2-periodic orbits: collisions survived after a perturbation, and linear stability",
        law="no-slip", gamma=gamma, gravity=gravity, force=[0.0, -gravity], max_collisions=max_collisions,
        perturbation=json.dumps(perturbation, sort_keys=True),
        perturbation_description=("start (half-way along q0 -> q1) with its velocity turned counter-clockwise "
                                  "by 'angle' rad, speed kept, and its spin multiplied by 1 + 'spin'"),
        scene=("two no-slip disks of radius R centred at (-1, 0) and (1, 0), open table "
               "(noslipsim.tables.two_disks(R, distance=2))"),
        classification_tolerance=UNIT_TOL,
        **attrs,
    )
    return ds


def _finish(ds):
    kinds = ds.linear_kind.values
    decided = (kinds == "elliptic") | (kinds == "hyperbolic")
    ds.attrs["agreement_share"] = agreement_share(ds)
    ds.attrs["n_decided"] = int(decided.sum())
    annotate(ds)
    ds["linear_kind"].attrs["flag_meanings"] = " ".join(KINDS)
    return ds


def agreement_share(ds):
    """Share of grid points, among those classed elliptic or hyperbolic, where the experiment agrees.

    Agreement: an elliptic orbit's perturbation survives ``max_collisions``
    collisions, a hyperbolic one's escapes before.  Parabolic points (the
    threshold line, within the monodromy's tolerance) are left out.  NaN if no
    point is decided.
    """
    kinds = np.asarray(ds["linear_kind"].values)
    survived = np.asarray(ds["survived"].values).astype(bool)
    ell = kinds == "elliptic"
    hyp = kinds == "hyperbolic"
    decided = ell | hyp
    if not decided.any():
        return float("nan")
    return float(((ell & survived) | (hyp & ~survived)).sum() / decided.sum())


def elliptic_boundary(ds: xr.Dataset, *, margin: float = 0.05) -> xr.Dataset:
    r"""Where the elliptic region of an R x phi grid begins, column by column, and its distance from R*(phi).

    Along each column (fixed ``phi``) ``lambda + 1/lambda`` of the
    unperturbed orbit falls through 2 as ``R`` grows (small disks are
    hyperbolic): the boundary ``R_e(phi)`` is the largest radius where it
    crosses 2 from above, interpolated linearly between the two grid radii
    that bracket it.  Without force ``R_e = R^*(phi)``, the closed form
    (equation ``ellipticity``), up to the interpolation error; under gravity
    the shift

    .. math::

        \Delta(\varphi) = R^*(\varphi) - R_e(\varphi)

    says how far the force moves the threshold (positive: the elliptic
    region reaches smaller disks).  Columns with ``phi + theta`` within
    ``margin`` of ``pi/2`` (the parabolic line under gravity) or without a
    crossing are NaN.

    Parameters
    ----------
    ds : xarray.Dataset
        An R x phi grid of :func:`stability_grid` (``eigen_sum``,
        ``radius_threshold``, attribute ``theta``: NaN without force).
    margin : float
        Columns with ``phi > pi/2 - theta - margin`` are left out (under gravity).

    Returns
    -------
    xarray.Dataset
        Along ``phi``: ``boundary`` (``R_e``) and ``radius_shift`` (``Delta``);
        attributes ``max_shift``, ``phi_of_max``, ``mean_shift`` and
        ``phi_max`` (the largest ``phi`` used).

    Raises
    ------
    ValueError
        For a dataset without dims ``(radius, phi)`` or ``eigen_sum``.
    """
    if "eigen_sum" not in ds or set(ds.eigen_sum.dims) != {"radius", "phi"}:
        raise ValueError("ds: expected an R x phi stability grid with 'eigen_sum' on (radius, phi)")
    R = np.asarray(ds.radius.values, float)
    phis = np.asarray(ds.phi.values, float)
    es = ds.eigen_sum.transpose("radius", "phi").values
    theta = float(ds.attrs.get("theta", float("nan")))
    limit = math.pi / 2 - theta - float(margin) if math.isfinite(theta) else math.inf
    boundary = np.full(phis.size, np.nan)
    for j, phi in enumerate(phis):
        if phi > limit:
            continue
        col = es[:, j]
        down = np.flatnonzero((col[:-1] >= 2.0) & (col[1:] < 2.0))
        if down.size:
            i = int(down[-1])
            boundary[j] = R[i] + (col[i] - 2.0) / (col[i] - col[i + 1]) * (R[i + 1] - R[i])
    shift = np.asarray(ds.radius_threshold.values, float) - boundary
    out = xr.Dataset({"boundary": ("phi", boundary), "radius_shift": ("phi", shift)}, coords={"phi": phis})
    ok = np.isfinite(shift)
    k = int(np.nanargmax(shift)) if ok.any() else 0
    out.attrs.update(max_shift=float(shift[k]) if ok.any() else float("nan"),
                     phi_of_max=float(phis[k]) if ok.any() else float("nan"),
                     mean_shift=float(shift[ok].mean()) if ok.any() else float("nan"),
                     phi_max=float(phis[ok].max()) if ok.any() else float("nan"))
    return out


# ----------------------------------------------------------------------------- public
def stability_grid(radii, phis, gamma, *, gravity=0.0, theta=None, perturbation=DEFAULT_PERTURBATION,
                   max_collisions=1000, scheduler="numba", progress=None):
    r"""R x phi stability grid of the two-disk 2-periodic orbits (paper, ``stabexp``, upper and lower left).

    Parameters
    ----------
    radii : array_like
        Disk radii in ``(0, 1)``, strictly increasing (nondimensional; centres 2 apart).
    phis : array_like
        Angles of ``q0`` in ``(0, pi/2)``, strictly increasing (radians).
    gamma : float
        Mass-distribution constant ``> 0`` (``1/sqrt(2)`` uniform disk).
    gravity : float
        ``g >= 0``; force ``(0, -g)``.  With ``g > 0`` every orbit is launched
        at ``theta`` above the chord (corrected Theorem 2, docs/errata.md).
    theta : float, optional
        Launch angle in ``(0, pi/2)``; required exactly when ``gravity > 0``.
    perturbation : float or dict
        ``{'angle': a, 'spin': s}``: the start's velocity turned by ``a`` rad
        (speed kept) and its spin multiplied by ``1 + s``; a number is the
        angle.  Default ``{'angle': 1e-3, 'spin': 0}``; the same at every point.
    max_collisions : int
        Collision cap of the survival runs (the paper: 1000).
    scheduler : str or distributed.Client
        Passed to :func:`noslipsim.simulate_many` for each radius (one scene
        per radius).  Default ``'numba'``: one parallel compiled call per
        radius (a row is too small for dask's task overhead to pay).
    progress : bool, optional
        Report the radii done on stderr (default: when stderr is a terminal).

    Returns
    -------
    xarray.Dataset
        Dims ``(radius, phi)``: ``n_collisions`` (int), ``stop_reason``,
        ``survived`` (int8), ``linear_kind`` (``'elliptic'``,
        ``'hyperbolic'`` or ``'parabolic'``, from the exact 2-bounce
        monodromy of the unperturbed orbit), ``eigen_sum``
        (``lambda + 1/lambda``), ``chord_length``; ``radius_threshold``
        (dim ``phi``, the force-free closed form).  Coordinates ``radius``,
        ``phi``, ``curvature``.  Attributes: every parameter, the
        perturbation (JSON and in words), ``agreement_share``
        (:func:`agreement_share`).

    Raises
    ------
    ValueError
        Radii outside ``(0, 1)``, angles outside ``(0, pi/2)``, ``gamma <= 0``,
        ``gravity < 0``, ``theta`` missing with gravity or given without it, a
        bad perturbation or collision cap.

    Examples
    --------
    >>> ds = stability_grid(np.linspace(0.2, 0.95, 100), np.linspace(0.01, 1.55, 100), 2 ** -0.5)
    >>> ds.n_collisions.plot(x="phi", y="radius")     # doctest: +SKIP
    >>> ds.radius_threshold.plot()                    # doctest: +SKIP
    """
    radii = _axis(radii, "radii", 0.0, 1.0, "(0, 1) (disks centred 2 apart must not touch)")
    phis = _axis(phis, "phis", 0.0, math.pi / 2, "(0, pi/2)")
    gamma = _gamma(gamma)
    gravity = finite_float(gravity, "gravity")
    if gravity < 0.0:
        raise ValueError(f"gravity: must be >= 0 (the force is (0, -gravity)), got {gravity}")
    if gravity > 0.0:
        if theta is None:
            raise ValueError("theta: the launch angle is required when gravity > 0")
        theta = finite_float(theta, "theta")
        if not 0.0 < theta < math.pi / 2:
            raise ValueError(f"theta: must lie in (0, pi/2), got {theta}")
    elif theta is not None:
        raise ValueError("theta: only meaningful with gravity > 0 (without force the orbit follows the chord)")
    perturbation = _perturbation(perturbation)
    max_collisions = _max_collisions(max_collisions)
    ds = _grid(radii, "phi", phis, lambda p: (p, theta), gamma, gravity, perturbation, max_collisions,
               scheduler, progress, dict(theta=float("nan") if theta is None else theta,
                                         threshold_applies=int(gravity == 0.0)))
    R = ds.radius.values[:, None]
    ds["chord_length"] = (("radius", "phi"), 2.0 - 2.0 * R * np.cos(phis)[None, :])
    thr = theory.ellipticity_threshold(phis, gamma)
    ds["radius_threshold"] = ("phi", 2.0 / (np.asarray(thr) + 2.0 * np.cos(phis)))
    return _finish(ds)


def stability_grid_theta(radii, thetas, gamma, *, phi, gravity, perturbation=DEFAULT_PERTURBATION,
                         max_collisions=1000, scheduler="numba", progress=None):
    r"""R x theta stability grid at fixed ``phi`` under gravity (paper, ``stabexp``, lower right).

    Parameters
    ----------
    radii : array_like
        Disk radii in ``(0, 1)``, strictly increasing.
    thetas : array_like
        Launch angles above the chord in ``(0, pi/2)``, strictly increasing (radians).
    gamma : float
        Mass-distribution constant ``> 0``.
    phi : float
        Angle of ``q0`` in ``(0, pi/2)`` (the paper: 0.4).
    gravity : float
        ``g > 0``; force ``(0, -g)``.
    perturbation, max_collisions, scheduler, progress
        As :func:`stability_grid`.

    Returns
    -------
    xarray.Dataset
        As :func:`stability_grid` with dim ``theta`` instead of ``phi``;
        ``radius_threshold`` is a scalar (the force-free threshold at
        ``phi``: the ``theta -> 0`` limit, where the launch speed diverges and
        the force no longer bends the flight); attribute ``phi``.
    """
    radii = _axis(radii, "radii", 0.0, 1.0, "(0, 1) (disks centred 2 apart must not touch)")
    thetas = _axis(thetas, "thetas", 0.0, math.pi / 2, "(0, pi/2)")
    gamma = _gamma(gamma)
    phi = finite_float(phi, "phi")
    if not 0.0 < phi < math.pi / 2:
        raise ValueError(f"phi: must lie in (0, pi/2), got {phi}")
    gravity = finite_float(gravity, "gravity")
    if not gravity > 0.0:
        raise ValueError(f"gravity: must be > 0 for a launch-angle grid (without force there is no launch "
                         f"angle), got {gravity}")
    perturbation = _perturbation(perturbation)
    max_collisions = _max_collisions(max_collisions)
    ds = _grid(radii, "theta", thetas, lambda t: (phi, t), gamma, gravity, perturbation, max_collisions,
               scheduler, progress, dict(phi=phi, threshold_applies=0))
    ds["chord_length"] = ("radius", 2.0 - 2.0 * ds.radius.values * math.cos(phi))
    thr = float(theory.ellipticity_threshold(phi, gamma))
    ds["radius_threshold"] = ((), 2.0 / (thr + 2.0 * math.cos(phi)))
    return _finish(ds)


def _existing_orbits(radius, points, gamma, gravity):
    """The orbits of :func:`two_disk_orbit` at ``points``; ``None`` where it refuses (no such orbit)."""
    out = []
    for phi, theta in points:
        try:
            out.append(two_disk_orbit(radius, phi, gamma, theta=theta, gravity=gravity))
        except ValueError:  # the flight meets the table elsewhere, or never reaches q1
            out.append(None)
    return out


def two_disk_classes(radius, points, gamma, *, gravity=0.0, scheduler="numba", num_workers=None):
    """Linear class and ``lambda + 1/lambda`` of the two-disk 2-periodic orbits at many ``(phi, theta)`` of one radius.

    The classes of :func:`stability_grid` without its survival runs, for
    points where the orbit may not exist: one :func:`noslipsim.simulate_many`
    call (``record='log'``, three collisions) runs every orbit of the radius
    (one scene), and the exact 2-bounce monodromy of each is classified.
    Where :func:`~noslipsim.analysis.two_disk_orbit` refuses the combination,
    or the run does not bounce ``q1, q0, q1``, there is no such orbit.

    Parameters
    ----------
    radius : float
        Disk radius in ``(0, 1)`` (centres 2 apart).
    points : sequence of (float, float or None)
        ``(phi, theta)`` per orbit; ``theta`` None without force.
    gamma : float
        Mass-distribution constant ``> 0``.
    gravity : float
        ``g >= 0``; force ``(0, -g)``.
    scheduler, num_workers
        Passed to :func:`noslipsim.simulate_many` (a ``dask.distributed``
        Client spreads the orbits over a cluster).

    Returns
    -------
    kinds : ndarray of str
        ``'elliptic'``, ``'hyperbolic'``, ``'parabolic'``, or ``''`` where there is no orbit.
    eigen_sum : ndarray of float
        ``lambda + 1/lambda`` (NaN where there is no orbit).
    """
    orbits = _existing_orbits(float(radius), points, gamma, gravity)
    kinds = np.full(len(points), "", dtype="<U10")
    eigen_sum = np.full(len(points), np.nan)
    ok = np.flatnonzero([o is not None for o in orbits])
    if ok.size == 0:
        return kinds, eigen_sum
    scene = orbits[ok[0]][0]  # the same table for every point of the radius
    states = [orbits[i][1] for i in ok]
    base = simulate_many(scene, [s["position"] for s in states], [s["velocity"] for s in states],
                         [s["spin"] for s in states], max_collisions=_LOG_ROWS, record="log", scheduler=scheduler,
                         num_workers=num_workers, progress=False)
    logs = _logs(base, _LOG_ROWS)
    el = logs[:, :, layout.LOG_ELEMENT]
    bounced = (base.n_collisions.values >= _LOG_ROWS) & (el[:, 0] == 1) & (el[:, 1] == 0) & (el[:, 2] == 1)
    if bounced.any():
        _, k, es = _two_bounce(scene, logs[bounced])
        kinds[ok[bounced]] = k
        eigen_sum[ok[bounced]] = es
    return kinds, eigen_sum
