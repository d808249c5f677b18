"""Range of scales the engine is exact for (issue 23 item 5): scaled twins of a few scenes.

The dynamics has two free units.  A scene scaled by ``L`` in length and ``V``
in velocity (coordinates and radii times ``L``, velocities and spins times
``V``, forces times ``V^2/L``, times times ``L/V``) has the same orbit, scaled.
With ``L`` and ``V`` powers of two every product in the engine is scaled by a
power of two too, so as long as nothing overflows, underflows into subnormals
or meets an absolute constant, the scaled run gives the reference run's
numbers *to the bit* after unscaling.  This script sweeps ``log2 L`` and
``log2 V`` over the whole float range (one at a time, and ``L = V``, in which
times are unchanged) and prints, for every scene, the widest window of
exponents around 0 where the orbit (elements hit, times, positions,
velocities, spins) still matches; past it, where it first fails and how.

It also sweeps the dimensionless ratios a scene can hold: ``|w|/|v|`` (spin
to speed) and ``|a| L/|v|^2`` (force to speed), whose extremes make the
energy ``(|v|^2 + w^2)/2`` lose one of its terms.

Run: ``python benchmarks/magnitudes.py [--collisions 30] [--step 8]``; it runs
below the public checks (``noslipsim._engine.run`` through
:func:`noslipsim.simulate.run_one`), so it measures the engine itself, not the
refusals.  The numbers are in docs/conventions.md, "Range of validity".
"""
import argparse
import math
import os
import sys
import time
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from machine import machine_line  # noqa: E402 (benchmarks/ on sys.path first)

from noslipsim import Scene, tables  # noqa: E402
from noslipsim.core import layout  # noqa: E402
from noslipsim.simulate import run_one  # noqa: E402


def _scaled_element(d, L):
    d = dict(d)
    for key in ("point", "p0", "p1", "center"):
        if key in d:
            d[key] = [c * L for c in d[key]]
    if "radius" in d:
        d["radius"] = d["radius"] * L
    return d


def scaled_scene(scene, L, V):
    """``scene`` with lengths times ``L`` and the force times ``V^2/L`` (built without the public checks)."""
    d = scene.to_dict()
    d["elements"] = [_scaled_element(e, L) for e in d["elements"]]
    d["force"] = [f * (V * V / L) if f else 0.0 for f in d["force"]]
    if d.get("lattice"):
        d["lattice"] = {k: [c * L for c in a] for k, a in d["lattice"].items()}
    # the scaled scene may lie outside the checked range: build it field by field, unchecked
    s = object.__new__(Scene)
    for k, v in (("elements", tuple(_raw(e) for e in d["elements"])), ("law", scene.law),
                 ("gamma", scene.gamma), ("force", tuple(d["force"])), ("lattice", d.get("lattice")),
                 ("thermostat", scene.thermostat)):
        object.__setattr__(s, k, v)
    return s


def _raw(d):
    from noslipsim.elements import ELEMENT_TYPES

    cls = ELEMENT_TYPES[d["type"]]
    obj = object.__new__(cls)
    for k, v in d.items():
        if k != "type":
            object.__setattr__(obj, k, tuple(v) if isinstance(v, list) else v)
    if d["type"] == "line":  # the unit normal is kept as built (scale free)
        object.__setattr__(obj, "normal", tuple(d["normal"]))
    return obj


SCENES = {
    "box+disk no-slip": (tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.3)]), (0.2, 0.2), (1.0, 1.0), 0.3),
    "box+disk specular, gravity": (tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.3)], law="specular",
                                                    force=(0.0, -1.0)), (0.2, 0.7), (0.8, 0.3), 0.0),
    "stadium no-slip, gravity": (tables.stadium(1.0, 1.0, force=(0.0, -1.0)), (0.1, 0.2), (0.7, 0.4), -0.5),
    "half plane (bouncing ball)": (tables.half_plane(), (0.0, 1.0), (0.5, 0.0), 0.4),
    "sinai torus no-slip": (tables.sinai_torus(0.3), (0.5, 0.45), (0.6, 0.8), 0.2),
    "hex cell, thermostat": (tables.hex_lorentz_cell(0.4, force=(0.3, 0.1)).replace(thermostat="isokinetic"),
                             (0.45, 0.1), (0.6, 0.8), 0.3),
}


def run(scene, q, v, w, n):
    """Collision log and final state of one orbit, or the exception it raised."""
    rec = np.zeros((n, layout.N_LOG))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with np.errstate(all="ignore"):
            out = run_one(scene, np.asarray(q, float), np.asarray(v, float), float(w), n, math.inf, -math.inf,
                          layout.RECORD_LOG, rec)
    return rec[:out[3]], out


def compare(ref, got, L, V):
    """``None`` if the scaled orbit ``got`` unscales to ``ref``; otherwise what differs first."""
    (log0, _), (log1, out1) = ref, got
    if len(log1) != len(log0):
        return f"{len(log1)} collisions instead of {len(log0)} ({layout.STOP_REASONS[out1[1]]})"
    e0, e1 = log0[:, layout.LOG_ELEMENT], log1[:, layout.LOG_ELEMENT]
    if not np.array_equal(e0, e1):
        k = int(np.argmax(e0 != e1))
        return f"collision {k} on element {int(e1[k])} instead of {int(e0[k])}"
    units = {layout.LOG_T: L / V, layout.LOG_X: L, layout.LOG_Y: L, layout.LOG_VX: V, layout.LOG_VY: V,
             layout.LOG_W: V, layout.LOG_S: L}
    worst = 0.0
    for col, unit in units.items():
        a, b = log0[:, col], log1[:, col] / unit
        with np.errstate(all="ignore"):
            err = np.abs(a - b) / np.maximum(np.abs(a), 1.0)
        if not np.all(np.isfinite(b)):
            return "non-finite values"
        worst = max(worst, float(err.max(initial=0.0)))
    return None if worst == 0.0 else f"differs by {worst:.2g} (relative)"


def window(name, mapping, exps, n):
    """The widest run of exponents around 0 where the scaled orbit matches, and the first failures."""
    scene, q, v, w = SCENES[name]
    ref = run(scene, q, v, w, n)
    verdict = {}
    for k in exps:
        L, V = mapping(k)
        s = scaled_scene(scene, L, V)
        try:
            got = run(s, np.multiply(q, L), np.multiply(v, V), w * V, n)
            verdict[k] = compare(ref, got, L, V)
        except Exception as err:  # a failure is a measurement here
            verdict[k] = f"{type(err).__name__}: {err}"
    keys = sorted(verdict)
    i0 = keys.index(0)
    lo = hi = i0
    while lo > 0 and verdict[keys[lo - 1]] is None:
        lo -= 1
    while hi + 1 < len(keys) and verdict[keys[hi + 1]] is None:
        hi += 1
    below = f"2^{keys[lo - 1]}: {verdict[keys[lo - 1]]}" if lo > 0 else "-"
    above = f"2^{keys[hi + 1]}: {verdict[keys[hi + 1]]}" if hi + 1 < len(keys) else "-"
    return keys[lo], keys[hi], below, above, verdict


def ratio_sweep(n, exps):
    """Spin to speed and force to speed: the box+disk under gravity with ``|w| = 2^k |v|`` or ``a = 2^k v^2/L``."""
    scene, q, v, _ = SCENES["box+disk specular, gravity"]
    scene = scene.replace(law="no-slip")
    rows = []
    for k in exps:
        w = 2.0 ** k
        log, out = run(scene, q, v, w, n)
        ok = np.all(np.isfinite(log)) and len(log) == n
        with np.errstate(all="ignore"):
            e = 0.5 * (log[:, layout.LOG_VX] ** 2 + log[:, layout.LOG_VY] ** 2 + log[:, layout.LOG_W] ** 2) \
                - (scene.force[1] * log[:, layout.LOG_Y])
            e0 = 0.5 * (v[0] ** 2 + v[1] ** 2 + w * w) - scene.force[1] * q[1]
        rows.append(("spin/speed", k, ok, float(np.max(np.abs(e - e0)) / e0) if ok else math.nan,
                     layout.STOP_REASONS[out[1]]))
    return rows


def force_sweep(n, exps, thermostat=False):
    """Force to speed, ``|a| L/|v|^2 = 2^k``: tiny forces must give the straight-flight orbit, and nothing may hang.

    Free fall in the closed box+disk (specular, so the comparison is not chaotic over ``n`` collisions):
    below ``2^-60`` the orbit must be the zero-force orbit to about ``2^k`` relative.  The thermostat in
    the hexagonal cell: the orbit must stay finite and the run quick.  Returns rows
    ``(k, verdict, seconds)``."""
    if thermostat:
        scene, q, v, w = SCENES["hex cell, thermostat"]
    else:
        scene, q, v, w = SCENES["box+disk specular, gravity"]
    straight = run(scene.replace(force=(0.0, 0.0), thermostat=None), q, v, w, n)
    rows = []
    for k in exps:
        a = 2.0 ** k
        s = scaled_scene(scene, 1.0, 1.0)
        object.__setattr__(s, "force", (0.6 * a, -0.8 * a))
        t0 = time.perf_counter()
        try:
            got = run(s, q, v, w, n)
            log = got[0]
            if not np.all(np.isfinite(log)):
                verdict = "non-finite values"
            elif k < -60:
                verdict = compare(straight, got, 1.0, 1.0) or "= straight flights to the bit"
            else:
                verdict = f"{len(log)} collisions, finite ({layout.STOP_REASONS[got[1][1]]})"
        except Exception as err:  # a failure is a measurement here
            verdict = f"{type(err).__name__}: {err}"
        rows.append((k, verdict, time.perf_counter() - t0))
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--collisions", type=int, default=30)
    p.add_argument("--step", type=int, default=8, help="step of the exponent sweep (powers of two)")
    p.add_argument("--only", choices=["scales", "ratios"], default=None, help="run one part")
    p.add_argument("--scenes", default=";".join(SCENES), help="names separated by ;")
    args = p.parse_args()
    print(machine_line())
    exps = sorted(set(range(0, -1070, -args.step)) | set(range(0, 1021, args.step)))
    sweeps = {
        "length L (V = 1)": lambda k: (2.0 ** k, 1.0),
        "velocity V (L = 1)": lambda k: (1.0, 2.0 ** k),
        "both, L = V (times unchanged)": lambda k: (2.0 ** k, 2.0 ** k),
        "both, L = 1/V (times scaled by L^2)": lambda k: (2.0 ** k, 2.0 ** -k) if abs(k) < 1020 else (math.inf, 0.0),
    }
    for label, mapping in (sweeps.items() if args.only != "ratios" else ()):
        print(f"\n## scaled in {label}: exponents k of 2^k where the orbit matches to the bit")
        for name in args.scenes.split(";"):
            t0 = time.perf_counter()
            lo, hi, below, above, _ = window(name, mapping, exps, args.collisions)
            print(f"- {name}: 2^{lo} .. 2^{hi} (1e{lo * math.log10(2):.0f} .. 1e{hi * math.log10(2):.0f}); "
                  f"below: {below}; above: {above}  [{time.perf_counter() - t0:.1f} s]")
    if args.only == "scales":
        return
    for thermo in (False, True):
        print(f"\n## force to speed, |a| L/|v|^2 = 2^k ({'thermostat, hex cell' if thermo else 'free fall, box+disk'})")
        for k, verdict, sec in force_sweep(args.collisions, range(-1000, 1001, 40), thermo):
            print(f"  2^{k:5d}: {verdict}  [{sec:.2f} s]")
    print("\n## spin to speed, |w|/|v| = 2^k (box+disk no-slip under gravity): energy error")
    for _, k, ok, err, stop in ratio_sweep(args.collisions, range(-1000, 1001, 50)):
        print(f"  2^{k:5d}: {'ok ' if ok else 'BAD'} max |dE|/E = {err:.2g} ({stop})")


if __name__ == "__main__":
    main()
