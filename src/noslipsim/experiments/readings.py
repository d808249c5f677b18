r"""Figure 15's lower right under every reading a referee would try: small survival scans along theta.

The paper's last experiment fixes ``phi = 0.4`` and varies the launch angle
``theta`` and the disk radius ``R``; it reports stable -> unstable -> stable
along ``theta`` with "a real stable region" for launch angles around 1.3.
Ours (:func:`noslipsim.analysis.stability_grid_theta`) shows no surviving
orbit past ``theta = pi/2 - phi``.  Each *reading* below changes one thing in
how the paper's words could be turned into initial conditions, a perturbation
or a stopping rule, and runs the same small scan (a few radii, ``theta`` in
``(0, pi/2)``), so that the pattern each reading gives can be compared with
the paper's (docs/analysis.md, "Figure 15's readings").

Geometry (all readings).  Two no-slip disks of radius ``R`` centred at
``(-1, 0)`` and ``(1, 0)``, force ``(0, -g)``; ``q0 = (-1 + R cos p, R sin p)``
on the left disk and its mirror image ``q1``, ``d = 2 - 2 R cos p`` apart.  The
position angle ``p`` of ``q0`` and the half-angle of the tangential wedge
(tangent lines at ``q0`` and ``q1`` against the vertical bisector) are the same
number here, so "phi as the position angle" and "phi as the paper's (half)
wedge angle" are one reading; the alternatives are ``2 p = phi`` (phi read as
the full wedge angle) and ``p = pi/2 - phi`` (phi measured from the vertical,
or the tangent's slope from the horizontal).

A launch leaves ``q0`` at elevation ``alpha`` above the horizontal (the chord)
with speed and spin (corrected Theorem 2, docs/errata.md)

.. math::

    v = \sqrt{\frac{g d}{\sin 2\alpha}}, \qquad w = \frac{v \sin(p - \alpha)}{\gamma},

and the run starts half-way, where the flight crosses ``x = 0``.  The
readings of ``theta`` map it to ``alpha``: from the chord ``alpha = theta``;
from the vertical ``alpha = pi/2 - theta``; from the tangent at ``q0``
(upward branch) ``alpha = pi/2 + p - theta``, (downward branch)
``alpha = theta + p - pi/2``; from the inward normal at ``q0`` towards the
vertical ``alpha = p + theta``, towards the chord ``alpha = p - theta``.  A
``theta`` whose ``alpha`` leaves ``(0, pi/2)`` launches nothing (``launched =
0``).  The printed Theorem 2 has ``v = 2 sqrt(g d / sin 2 alpha)`` and the spin
of the opposite sign (``w = v sin(alpha - p) / gamma``); readings use each
misprint alone and both together (the orbits are then not periodic, and the
survival count is what the paper's experiment would have recorded).

Perturbations (applied to the half-way state): ``angle`` turns the velocity
by ``size`` rad (speed kept); ``speed`` scales the velocity by ``1 + size``
(relative) or adds ``size`` to its length (absolute); ``spin`` multiplies the
spin by ``1 + size`` (relative) or adds ``size`` (absolute); ``position``
moves the start along the chord by ``size d`` (relative) or ``size``
(absolute); ``none`` runs the periodic orbit itself (rounding only).

Stopping rules: ``escape`` (ours): the run ends when the flight meets neither
disk; ``alternate``: it also ends at the first collision with the disk hit
just before ("fails to hit one of the scatterers" read as failing to hit the
other one); the collision cap (the paper: 1000) is a parameter of each
reading.

Brute force (``search = 'speed_spin'``): each cell launches every speed of
:data:`SPEED_FACTORS` times the corrected one with every spin of
:data:`SPIN_FACTORS` times the corrected one, each started where its flight
crosses ``x = 0`` (outside both disks), and keeps the most collisions any
survives: whatever speed and spin the paper used, a stable region it saw
would show here.  :func:`lambda_at` gives the largest ``|lambda|`` of our
2-periodic orbit at :data:`PAPER_THETA`, a row of the table.
"""
from __future__ import annotations

import argparse
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from .. import tables
from .._metadata import annotate
from ..analysis import two_disk_classes
from ..ensemble import simulate_many

__all__ = ["BASE", "PAPER_THETA", "READINGS", "SPEED_FACTORS", "SPIN_FACTORS", "lambda_at", "paper_pattern",
           "readings_pattern", "readings_table", "stability_readings"]

#: Our reading (Figure 15, lower right): every other reading changes some of these keys.
BASE = {
    "phi": 0.4,                 # the paper's phi; position angle of q0 = phi_scale * phi + phi_shift
    "position": "half",         # 'half' (position angle = phi), 'full' (= phi / 2), 'vertical' (= pi/2 - phi)
    "theta_from": "chord",      # chord | vertical | tangent_up | tangent_down | normal_up | normal_down
    "speed": "corrected",       # corrected | printed (the paper's 2 sqrt(g d / sin 2 theta))
    "spin": "corrected",        # corrected | printed (the opposite sign)
    "perturbation": "angle",    # angle | speed | spin | position | none
    "mode": "absolute",         # relative | absolute (angle: always radians)
    "size": 1e-3,
    "gamma": 1 / math.sqrt(2),
    "stop": "escape",           # escape | alternate
    "cap": 1000,
    "search": "none",           # none | speed_spin (a cell survives if any launch of SPEED_FACTORS x SPIN_FACTORS does)
}

#: The brute-force reading (``search = 'speed_spin'``): launch speeds as multiples of the corrected speed (the
#: printed one is 2) and spins as multiples of the corrected spin (the printed sign is -1, no spin 0).
SPEED_FACTORS = (0.5, 0.75, 0.9, 1.0, 1.1, 1.25, 1.5, 2.0, 3.0)
SPIN_FACTORS = (-2.0, -1.0, -0.5, 0.0, 0.5, 0.9, 1.0, 1.1, 1.5, 2.0)

#: Where the paper sees "a real stable region" (Figure 15, lower right): the table gives |lambda| there.
PAPER_THETA = 1.3

#: The readings: name -> (what it changes from :data:`BASE`, in words; the changed keys).
READINGS = {
    "ours": ("θ from the chord (= the horizontal), φ = position angle of q0 = half wedge angle; "
             "velocity turned 1e-3 rad; γ = 1/√2; stop when both disks are missed; cap 1000", {}),
    "phi full wedge angle": ("φ = 0.4 read as the full wedge angle: q0 at 0.2", {"position": "full"}),
    "phi from the vertical": ("φ = 0.4 measured from the vertical: q0 at π/2 − 0.4 = 1.171",
                              {"position": "vertical"}),
    "phi 0.2": ("another φ: 0.2", {"phi": 0.2}),
    "phi 0.8": ("another φ: 0.8", {"phi": 0.8}),
    "theta from the vertical": ("θ measured from the vertical: elevation π/2 − θ", {"theta_from": "vertical"}),
    "theta from the tangent (up)": ("θ from the tangent at q0, its upward branch: elevation π/2 + φ − θ",
                                    {"theta_from": "tangent_up"}),
    "theta from the tangent (down)": ("θ from the tangent at q0, its downward branch: elevation θ + φ − π/2",
                                      {"theta_from": "tangent_down"}),
    "theta from the normal (up)": ("θ from the normal at q0, towards the vertical: elevation φ + θ",
                                   {"theta_from": "normal_up"}),
    "theta from the normal (down)": ("θ from the normal at q0, towards the chord: elevation φ − θ",
                                     {"theta_from": "normal_down"}),
    "printed speed": ("the paper's printed speed 2√(gd/sin 2θ) (lands at 4d)", {"speed": "printed"}),
    "printed spin sign": ("the paper's printed spin condition (the opposite sign)", {"spin": "printed"}),
    "printed speed and spin": ("both misprints", {"speed": "printed", "spin": "printed"}),
    "no perturbation": ("the periodic orbit itself (rounding only)", {"perturbation": "none", "size": 0.0}),
    "angle 1e-4": ("velocity turned 1e-4 rad", {"size": 1e-4}),
    "angle 1e-2": ("velocity turned 1e-2 rad", {"size": 1e-2}),
    "angle 5e-2": ("velocity turned 5e-2 rad", {"size": 5e-2}),
    "speed relative 1e-3": ("speed × (1 + 1e-3)", {"perturbation": "speed", "mode": "relative"}),
    "speed absolute 1e-2": ("speed + 1e-2", {"perturbation": "speed", "size": 1e-2}),
    "spin relative 1e-3": ("spin × (1 + 1e-3)", {"perturbation": "spin", "mode": "relative"}),
    "spin relative 1e-1": ("spin × (1 + 0.1)", {"perturbation": "spin", "mode": "relative", "size": 0.1}),
    "spin absolute 1e-2": ("spin + 1e-2", {"perturbation": "spin", "size": 1e-2}),
    "position relative 1e-3": ("start moved along the chord by 1e-3 d",
                               {"perturbation": "position", "mode": "relative"}),
    "position absolute 1e-2": ("start moved along the chord by 1e-2", {"perturbation": "position", "size": 1e-2}),
    "gamma 0.3": ("γ = 0.3", {"gamma": 0.3}),
    "gamma 1": ("γ = 1 (a ring)", {"gamma": 1.0}),
    "stop alternate": ("stop also when the same disk is hit twice in a row", {"stop": "alternate"}),
    "cap 100": ("collision cap 100", {"cap": 100}),
    "cap 5000": ("collision cap 5000", {"cap": 5000}),
    "brute force: speed and spin": (
        "every launch speed × (0.5 … 3, the printed 2 included) and spin × (−2 … 2, the printed −1 and 0 "
        "included) from q0 at elevation θ: a cell survives if any of the 90 launches does", {"search": "speed_spin"}),
}

_THETA_FROM = {
    "chord": lambda t, p: t,
    "vertical": lambda t, p: math.pi / 2 - t,
    "tangent_up": lambda t, p: math.pi / 2 + p - t,
    "tangent_down": lambda t, p: t + p - math.pi / 2,
    "normal_up": lambda t, p: p + t,
    "normal_down": lambda t, p: p - t,
}
_POSITION = {"half": lambda phi: phi, "full": lambda phi: phi / 2, "vertical": lambda phi: math.pi / 2 - phi}
_CHOICES = {"position": _POSITION, "theta_from": _THETA_FROM, "speed": ("corrected", "printed"),
            "spin": ("corrected", "printed"), "perturbation": ("angle", "speed", "spin", "position", "none"),
            "mode": ("relative", "absolute"), "stop": ("escape", "alternate"), "search": ("none", "speed_spin")}

#: A launch elevation closer than this to 0 or pi/2 launches nothing (the speed diverges there).
_EDGE = 1e-6


def _options(changes):
    """:data:`BASE` updated with ``changes``, validated."""
    if not isinstance(changes, Mapping):
        raise TypeError(f"reading: expected a mapping of changes, got {type(changes).__name__}")
    unknown = set(changes) - set(BASE)
    if unknown:
        raise ValueError(f"reading: unknown key(s) {sorted(unknown)}; allowed: {sorted(BASE)}")
    opt = {**BASE, **changes}
    for key, allowed in _CHOICES.items():
        if opt[key] not in allowed:
            raise ValueError(f"reading.{key}: expected one of {sorted(allowed)}, got {opt[key]!r}")
    for key in ("phi", "size", "gamma"):
        if not isinstance(opt[key], (int, float)) or not math.isfinite(opt[key]):
            raise ValueError(f"reading.{key}: expected a finite number, got {opt[key]!r}")
    if not 0.0 < opt["phi"] < math.pi / 2:
        raise ValueError(f"reading.phi: must lie in (0, pi/2), got {opt['phi']}")
    if not opt["gamma"] > 0.0:
        raise ValueError(f"reading.gamma: must be > 0, got {opt['gamma']}")
    if isinstance(opt["cap"], bool) or not isinstance(opt["cap"], (int, np.integer)) or opt["cap"] < 1:
        raise ValueError(f"reading.cap: expected a positive integer, got {opt['cap']!r}")
    return opt


def _start(radius, theta, opt, gravity, speed_factor=1.0, spin_factor=1.0):
    """The perturbed half-way state of one reading at ``(R, theta)``, or ``None`` if it launches nothing;
    ``speed_factor`` and ``spin_factor`` scale the launch (the brute-force reading)."""
    p = _POSITION[opt["position"]](opt["phi"])
    alpha = _THETA_FROM[opt["theta_from"]](theta, p)
    if not _EDGE < alpha < math.pi / 2 - _EDGE:
        return None, alpha
    c, s = math.cos(p), math.sin(p)
    q0 = np.array([-1.0 + radius * c, radius * s])
    d = 2.0 - 2.0 * radius * c
    v = math.sqrt(gravity * d / math.sin(2.0 * alpha)) * (2.0 if opt["speed"] == "printed" else 1.0)
    w = v * math.sin(p - alpha) / opt["gamma"] * (-1.0 if opt["spin"] == "printed" else 1.0) * spin_factor
    v *= speed_factor   # after the spin: a scaled speed keeps the periodic orbit's spin
    v0 = v * np.array([math.cos(alpha), math.sin(alpha)])
    # where the flight crosses x = 0: half-way to q1 for the periodic launch, and outside both disks for any
    # launch (their centres are 1 from that line, their radii below 1), so always a state of the table
    tau = -q0[0] / v0[0]
    a = np.array([0.0, -gravity])
    q = q0 + v0 * tau + 0.5 * a * tau * tau
    vel = v0 + a * tau
    kind, mode, size = opt["perturbation"], opt["mode"], float(opt["size"])
    if kind == "angle":
        cs, sn = math.cos(size), math.sin(size)
        vel = np.array([cs * vel[0] - sn * vel[1], sn * vel[0] + cs * vel[1]])
    elif kind == "speed":
        speed = math.hypot(*vel)
        vel = vel * ((1.0 + size) if mode == "relative" else (speed + size) / speed)
    elif kind == "spin":
        w = w * (1.0 + size) if mode == "relative" else w + size
    elif kind == "position":
        q = q + np.array([size * d if mode == "relative" else size, 0.0])
    return (q, vel, w), alpha


def _survival(scene, starts, opt):
    """Collisions survived by each start under the reading's stopping rule (capped at ``cap``)."""
    q = np.array([s[0] for s in starts])
    v = np.array([s[1] for s in starts])
    w = np.array([s[2] for s in starts])
    cap = int(opt["cap"])
    if opt["stop"] == "escape":
        runs = simulate_many(scene, q, v, w, max_collisions=cap, record="count", scheduler="sync", progress=False)
        return runs.n_collisions.values.astype(np.int64)
    runs = simulate_many(scene, q, v, w, max_collisions=cap, record="log", scheduler="sync", progress=False)
    n = runs.n_collisions.values.astype(np.int64)
    element = runs.element.values
    out = n.copy()
    for i in range(len(n)):
        e = element[i, :n[i]]
        repeat = np.flatnonzero(e[1:] == e[:-1])
        if repeat.size:
            out[i] = int(repeat[0]) + 1  # collisions before the first one on the disk just hit
    return out


def lambda_at(radii, theta=PAPER_THETA, *, phi=BASE["phi"], gamma=BASE["gamma"], gravity=1.0):
    """Largest ``|lambda|`` per period of our 2-periodic orbit at launch angle ``theta``, for each radius.

    From :func:`noslipsim.analysis.two_disk_classes` (the exact 2-bounce
    monodromy): ``|lambda| = (|s| + sqrt(s^2 - 4)) / 2`` for ``s = lambda + 1/lambda``
    outside ``[-2, 2]``, 1 inside (elliptic), NaN where there is no such orbit.
    A perturbation grows by about ``|lambda|`` every two collisions.
    """
    out = []
    for R in np.asarray(radii, dtype=float):
        _, (s,) = two_disk_classes(float(R), [(phi, theta)], gamma, gravity=gravity)
        out.append(0.5 * (abs(s) + math.sqrt(s * s - 4.0)) if abs(s) > 2.0 else (1.0 if math.isfinite(s) else math.nan))
    return np.array(out)


def stability_readings(readings: Mapping | None = None, *, radii: Sequence[float] = (0.15, 0.3, 0.45, 0.7, 0.9),
                       thetas: Sequence[float] | np.ndarray | None = None, n_theta: int = 63,
                       gravity: float = 1.0) -> xr.Dataset:
    r"""Survival scans along ``theta`` for each reading of Figure 15's lower right.

    Parameters
    ----------
    readings : mapping, optional
        ``{name: (description, changes)}``, ``changes`` a mapping of
        :data:`BASE` keys; default :data:`READINGS`.
    radii : sequence of float
        Disk radii in ``(0, 1)`` (centres 2 apart).
    thetas : array_like, optional
        Values of the paper's ``theta`` in ``(0, pi/2)``; default
        ``n_theta`` points from 0.01 to 1.56 (the paper's axis).
    n_theta : int
        Points along ``theta`` when ``thetas`` is not given.
    gravity : float
        ``g > 0``, force ``(0, -g)`` (the pattern does not depend on it: the
        two-disk table is not scale free, but ``g`` only rescales the speed).

    Returns
    -------
    xarray.Dataset
        Dims ``(reading, radius, theta_read)`` (``theta_read``: the paper's
        ``theta``, read as each reading says): ``n_collisions`` (collisions
        survived, -1 where nothing is launched), ``survived`` (1 at the cap,
        0 before, -1 where nothing is launched), ``launched``;
        ``launch_elevation`` (``(reading, theta_read)``, the launch's elevation
        above the chord, the same at every radius);
        along ``reading``: ``reading_description``, ``collision_cap``,
        ``gamma``, ``position_angle`` and the reading's options as JSON
        (``reading_options``).  Attribute ``base`` (:data:`BASE` as JSON).

    Raises
    ------
    ValueError
        Radii outside ``(0, 1)``, ``theta`` outside ``(0, pi/2)``, a bad reading.
    """
    readings = READINGS if readings is None else readings
    if not isinstance(readings, Mapping) or not readings:
        raise ValueError("readings: expected a non-empty mapping {name: (description, changes)}")
    radii = np.asarray(radii, dtype=float)
    if radii.ndim != 1 or radii.size == 0 or not np.all((radii > 0) & (radii < 1)):
        raise ValueError(f"radii: expected radii in (0, 1), got {radii!r}")
    if thetas is None:
        if isinstance(n_theta, bool) or not isinstance(n_theta, (int, np.integer)) or n_theta < 2:
            raise ValueError(f"n_theta: expected an integer >= 2, got {n_theta!r}")
        thetas = np.linspace(0.01, 1.56, n_theta)
    thetas = np.asarray(thetas, dtype=float)
    if thetas.ndim != 1 or thetas.size == 0 or not np.all((thetas > 0) & (thetas < math.pi / 2)):
        raise ValueError(f"thetas: expected angles in (0, pi/2), got {thetas!r}")
    if not (isinstance(gravity, (int, float)) and math.isfinite(gravity) and gravity > 0):
        raise ValueError(f"gravity: expected a finite number > 0, got {gravity!r}")
    names = list(readings)
    shape = (len(names), radii.size, thetas.size)
    n_coll = np.full(shape, -1, dtype=np.int64)
    elevation = np.full((len(names), thetas.size), np.nan)
    opts, caps, gammas, positions, descriptions = [], [], [], [], []
    for i, name in enumerate(names):
        entry = readings[name]
        if not (isinstance(entry, Sequence) and len(entry) == 2):
            raise ValueError(f"readings[{name!r}]: expected (description, changes), got {entry!r}")
        opt = _options(entry[1])
        opts.append(opt)
        descriptions.append(str(entry[0]))
        caps.append(int(opt["cap"]))
        gammas.append(float(opt["gamma"]))
        positions.append(_POSITION[opt["position"]](opt["phi"]))
        launches = [(a, b) for a in SPEED_FACTORS for b in SPIN_FACTORS] if opt["search"] == "speed_spin" \
            else [(1.0, 1.0)]
        for j, R in enumerate(radii):
            scene = tables.two_disks(float(R), distance=2.0, gamma=opt["gamma"], force=(0.0, -gravity))
            starts, where = [], []
            for k, theta in enumerate(thetas):
                for speed, spin in launches:
                    start, alpha = _start(float(R), float(theta), opt, gravity, speed, spin)
                    elevation[i, k] = alpha
                    if start is not None:
                        starts.append(start)
                        where.append(k)
            if starts:   # a cell keeps its best launch (the brute force; one launch per cell otherwise)
                np.maximum.at(n_coll[i, j], where, _survival(scene, starts, opt))
    cap = np.array(caps)[:, None, None]
    survived = np.where(n_coll < 0, -1, (n_coll >= cap).astype(np.int64)).astype(np.int8)
    ds = xr.Dataset(
        {"n_collisions": (("reading", "radius", "theta_read"), n_coll),
         "survived": (("reading", "radius", "theta_read"), survived),
         "launched": (("reading", "radius", "theta_read"), (n_coll >= 0).astype(np.int8)),
         "launch_elevation": (("reading", "theta_read"), elevation),
         "reading_description": ("reading", np.array(descriptions, dtype=object)),
         "reading_options": ("reading", np.array([json.dumps(o, sort_keys=True) for o in opts], dtype=object)),
         "collision_cap": ("reading", np.array(caps, dtype=np.int64)),
         "gamma": ("reading", np.array(gammas)),
         "position_angle": ("reading", np.array(positions)),
         "lambda_at_paper_theta": ("radius", lambda_at(radii, gravity=gravity))},
        coords={"reading": np.array(names, dtype=object), "radius": radii, "theta_read": thetas,
                "curvature": ("radius", 1.0 / radii)})
    ds.attrs.update(title="Figure 15, lower right: survival along theta under each reading of the paper",
                    law="no-slip", gravity=float(gravity), force=[0.0, -float(gravity)],
                    base=json.dumps(BASE, sort_keys=True),
                    scene=("two no-slip disks of radius R centred at (-1, 0) and (1, 0), open table "
                           "(noslipsim.tables.two_disks(R, distance=2))"))
    return annotate(ds)


def _runs(states, min_run):
    """Runs of ``'s'``/``'u'``/``'x'`` with runs of ``'s'``/``'u'`` shorter than ``min_run`` merged away."""
    states = list(states)
    changed = True
    while changed:
        changed = False
        runs = _split(states)
        short = [(b - a, a, b) for c, a, b in runs if c != "x" and b - a < min_run and len(runs) > 1]
        if short:
            _, a, b = min(short)
            flip = "u" if states[a] == "s" else "s"
            # merge into a neighbour of the other state (never into 'x')
            left = states[a - 1] if a > 0 else None
            right = states[b] if b < len(states) else None
            if flip in (left, right):
                states[a:b] = [flip] * (b - a)
                changed = True
    return _split(states)


def _split(states):
    out, a = [], 0
    for k in range(1, len(states) + 1):
        if k == len(states) or states[k] != states[a]:
            out.append((states[a], a, k))
            a = k
    return out


def _launched(pattern):
    """``pattern`` without its ``x`` runs (nothing launched), equal neighbours joined: ``'x-s-u'`` -> ``'s-u'``."""
    out = []
    for c in pattern.split("-"):
        if c != "x" and (not out or out[-1] != c):
            out.append(c)
    return "-".join(out)


def readings_pattern(ds: xr.Dataset, reading: str, radius: float, *, min_run: int = 2) -> dict:
    """The survival pattern along ``theta`` of one reading at one radius.

    Returns
    -------
    dict
        ``pattern`` (e.g. ``'u-s-u'``; ``'x'`` where nothing is launched,
        runs shorter than ``min_run`` points merged into their neighbours),
        ``intervals``: the ``theta`` intervals survived (edges half-way
        between grid points), ``stable_near_1_3``: whether the point nearest
        ``theta = 1.3`` survived.
    """
    row = ds.survived.sel(reading=reading, radius=radius).values
    theta = ds.theta_read.values
    states = ["x" if x < 0 else ("s" if x else "u") for x in row]
    runs = _runs(states, min_run)
    edges = np.r_[theta[0], 0.5 * (theta[1:] + theta[:-1]), theta[-1]]
    k13 = int(np.argmin(np.abs(theta - 1.3)))
    return {"pattern": "-".join(c for c, _, _ in runs),
            "intervals": [(float(edges[a]), float(edges[b])) for c, a, b in runs if c == "s"],
            "stable_near_1_3": bool(row[k13] == 1)}


def paper_pattern(pattern: Mapping) -> bool:
    """Whether a :func:`readings_pattern` is the paper's: stable -> unstable -> stable, stable near theta = 1.3."""
    return pattern["stable_near_1_3"] and _launched(pattern["pattern"]).startswith("s-u-s")


def readings_table(ds: xr.Dataset, *, min_run: int = 2) -> str:
    """The readings as a Markdown table: one row per reading, one column per radius.

    A cell is the pattern along ``theta`` (``s`` survived the cap, ``u``
    escaped or stopped before it, ``x`` nothing launched) and the survived
    intervals.  The last columns name the radii where ``theta`` near 1.3
    survives, where stable -> unstable -> stable appears, and where both do
    (the paper's pattern: :func:`paper_pattern`).  One more row, ``inverted grey scale``, reads our
    map with dark meaning *few* collisions (the complement of ``ours``).
    """
    radii = ds.radius.values
    head = ("| reading | what changes | " + " | ".join(f"R = {r:g}" for r in radii)
            + " | stable at θ ≈ 1.3 | s-u-s | the paper's pattern |")
    rows = [head, "|" + "---|" * (len(radii) + 5)]

    def cell(p):
        spans = ", ".join(f"{a:.2f}–{b:.2f}" for a, b in p["intervals"])
        return f"{p['pattern']}" + (f" (s: {spans})" if spans else "")

    def line(name, text, pats):
        near = [f"{r:g}" for r, p in zip(radii, pats) if p["stable_near_1_3"]]
        sus = [f"{r:g}" for r, p in zip(radii, pats) if "s-u-s" in _launched(p["pattern"])]
        both = [f"{r:g}" for r, p in zip(radii, pats) if paper_pattern(p)]
        rows.append(f"| {name} | {text} | " + " | ".join(cell(p) for p in pats)
                    + "".join(f" | {'R = ' + ', '.join(x) if x else 'no'}" for x in (near, sus, both)) + " |")

    for name in ds.reading.values:
        line(name, str(ds.reading_description.sel(reading=name).values),
             [readings_pattern(ds, name, r, min_run=min_run) for r in radii])
    if "lambda_at_paper_theta" in ds:
        rows.append(f"| \\|λ\\| at θ = {PAPER_THETA:g} | ours, linear: the largest eigenvalue's modulus per period "
                    "(a perturbation grows about this much every two collisions) | "
                    + " | ".join(f"{x:.3g}" for x in ds.lambda_at_paper_theta.values) + " | – | – | – |")
    if "ours" in ds.reading.values:
        inv = ds.sel(reading=["ours"]).copy(deep=True)
        s = inv.survived.values
        inv["survived"] = (inv.survived.dims, np.where(s < 0, s, 1 - s).astype(np.int8))
        line("inverted grey scale", "our map, dark read as few collisions (the complement of ours)",
             [readings_pattern(inv, "ours", r, min_run=min_run) for r in radii])
    return "\n".join(rows) + "\n"


def main(argv: Sequence[str] | None = None) -> None:
    """``python -m noslipsim.experiments.readings --out DIR``: write readings.nc and readings.md."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True, help="directory for readings.nc and readings.md")
    parser.add_argument("--radii", type=float, nargs="+", default=[0.15, 0.3, 0.45, 0.7, 0.9])
    parser.add_argument("--n-theta", type=int, default=63)
    parser.add_argument("--min-run", type=int, default=2)
    args = parser.parse_args(argv)
    from ..io import write_dataset

    ds = stability_readings(radii=args.radii, n_theta=args.n_theta)
    args.out.mkdir(parents=True, exist_ok=True)
    write_dataset(ds, args.out / "readings.nc")
    (args.out / "readings.md").write_text(readings_table(ds, min_run=args.min_run), encoding="utf-8")


if __name__ == "__main__":
    main()
