r"""The Einstein relation of the thermostatted hexagonal Lorentz gas, measured (issue 23, item 2).

Specular periodic hexagonal Lorentz gas (``tables.hex_lorentz_cell(r)``: unit triangular lattice,
disk radius ``r``; finite horizon for ``r > sqrt(3)/4``), speed ``c``.  An ensemble of starts drawn
from the zero-field invariant measure (positions uniform in the free region, headings uniform) is
run for a time ``T``, with no field and with a field ``E`` along x and the Gaussian isokinetic
thermostat.  docs/analysis.md ("The thermostatted Lorentz gas") derives, to first order in ``E``
and for every ``T``,

.. math:: \langle X(T)\rangle_E = \frac{E}{2c^2}\,\langle X(T)^2\rangle_0 + O(E^3),

``X`` the displacement along the field.  Divided by ``T`` and with ``T -> inf`` this is the
Einstein relation ``<v_F>/E = D/c^2``, ``<|q(t) - q(0)|^2> -> 4 D t``.  Printed:

* ``D`` from the slope of the zero-field mean squared displacement between ``T/4`` and ``T``
  (standard error over orbits), against Machta-Zwanzig's
  ``D_MZ = c g / (pi (sqrt(3) - 2 pi r^2))`` (gap ``g = 1 - 2 r``; unit spacing; Klages and
  Dellago's simulated values were not reachable, docs/analysis.md);
* per field: the mean current ``<X(T)>/T`` with its standard error, and the ratio
  ``2 c^2 <X(T)>_E / (E <X(T)^2>_0)`` (-> 1 as ``E -> 0``), its error from both ensembles;
* the no-slip law (``--noslip``, instead of the specular one): the same with the weighted displacement
  ``X_w = sum_i dx_i / c_i^2`` (each flight at its own speed), ``<X(T)>_E = (E/2) <X_w X>_0``;
* collisions per second of each run (the machine and load on the first and last line).

    PYTHONPATH=src nice -n 5 python benchmarks/einstein_relation.py [--orbits 4000] [--T 100]
        [--fields 0.1 0.2 0.4] [--noslip]
"""
import argparse
import math
import os
import sys
import time

import numpy as np

from noslipsim import simulate_many, tables
from noslipsim.initial import uniform_in_region

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import machine_line

# Klages & Dellago, J. Stat. Phys. 101 (2000) 145 (chao-dyn/9910038) use disks of radius 1 on a
# triangular lattice of spacing 2 + g', speed 1: there D_MZ = g' (2 + g')^2 / (pi (sqrt(3) (2 + g')^2
# - 2 pi)); ours (unit spacing, r = 1 / (2 + g')) is that over (2 + g').


def machta_zwanzig(r, c=1.0):
    """Machta-Zwanzig ``D`` of the hexagonal gas, unit spacing, disk radius ``r``, speed ``c``.

    Hops between the triangular traps (two per cell, area ``(sqrt(3)/2 - pi r^2)/2``, three exits of
    width ``g = 1 - 2 r``, hop length ``1/sqrt(3)``) at the rate ``3 c g / (pi A)``; ``D = rate l^2/4``.
    """
    return c * (1.0 - 2.0 * r) / (math.pi * (math.sqrt(3.0) - 2.0 * math.pi * r * r))


def equilibrium_starts(scene, n, c, seed, noslip=False):
    """Starts from the zero-field invariant measure: positions uniform in the free region (the
    rectangle ``[0, 1) x [0, sqrt 3)`` holds two whole cells), headings uniform; no-slip: on the
    shell ``|v|^2 + w^2 = c^2`` uniformly (``w`` uniform on ``[-c, c]``, Archimedes)."""
    rng = np.random.default_rng(seed)
    q = uniform_in_region(scene, n, (0.0, 1.0, 0.0, math.sqrt(3.0)), seed=seed)
    th = rng.uniform(0.0, 2.0 * math.pi, n)
    w = rng.uniform(-c, c, n) if noslip else np.zeros(n)
    s = np.sqrt(c * c - w * w)
    return q, np.c_[s * np.cos(th), s * np.sin(th)], w


def run(scene, starts, T, max_collisions):
    q, v, w = starts
    t0 = time.perf_counter()
    ds = simulate_many(scene, q, v, w, max_collisions=max_collisions, max_time=T, scheduler="numba",
                       num_workers=1)
    dt = time.perf_counter() - t0
    if not (ds.stop_reason.values == 1).all():
        raise RuntimeError(f"{int((ds.stop_reason.values != 1).sum())} orbits did not reach T = {T}")
    n_coll = int(ds.n_collisions.sum())
    return np.c_[ds.x_final.values, ds.y_final.values] - q, n_coll / dt


def run_log(scene, starts, T, max_collisions, chunk=250):
    """Displacements and weighted displacements ``sum dq_i / c_i^2`` (each flight at its own speed)."""
    q, v, w = starts
    d, dw, n_coll, wall = [], [], 0, 0.0
    for i in range(0, len(q), chunk):
        t0 = time.perf_counter()
        ds = simulate_many(scene, q[i:i + chunk], v[i:i + chunk], w[i:i + chunk], max_collisions=max_collisions,
                           max_time=T, record="log", scheduler="numba", num_workers=1)
        wall += time.perf_counter() - t0
        if not (ds.stop_reason.values == 1).all():
            raise RuntimeError("an orbit did not reach T (raise --max-collisions)")
        for k in range(len(ds.orbit)):
            m = int(ds.n_collisions[k])
            x = np.r_[q[i + k, 0], ds.x.values[k, :m], ds.x_final.values[k]]
            y = np.r_[q[i + k, 1], ds.y.values[k, :m], ds.y_final.values[k]]
            c2 = np.r_[v[i + k] @ v[i + k], ds.vx.values[k, :m] ** 2 + ds.vy.values[k, :m] ** 2]
            d.append((x[-1] - x[0], y[-1] - y[0]))
            dw.append((np.sum(np.diff(x) / c2), np.sum(np.diff(y) / c2)))
            n_coll += m
    return np.array(d), np.array(dw), n_coll / wall


def mean_se(a):
    a = np.asarray(a, dtype=float)
    return float(a.mean()), float(a.std(ddof=1) / math.sqrt(len(a)))


def specular(args):
    r, c, T = args.radius, args.speed, args.T
    scene = tables.hex_lorentz_cell(r, law="specular")
    mc = int(20 * T * c / (math.pi * (math.sqrt(3) / 2 - math.pi * r * r) / (2 * math.pi * r))) + 100
    z = equilibrium_starts(scene, args.zero_orbits, c, seed=args.seed + 1)
    d1, _ = run(scene, z, T / 4, mc)
    d2, rate0 = run(scene, z, T, mc)
    sq1, sq2 = (d1 ** 2).sum(axis=1), (d2 ** 2).sum(axis=1)
    D, D_se = mean_se((sq2 - sq1) / (4 * (T - T / 4)))
    msd_x, msd_x_se = mean_se(d2[:, 0] ** 2)          # <X(T)^2>_0, one component
    msd_2, msd_2_se = mean_se(0.5 * sq2)               # the same from both components (isotropy)
    mz = machta_zwanzig(r, c)
    print(f"specular, r = {r}, c = {c}, T = {T}: {args.zero_orbits} zero-field orbits, {rate0:,.0f} coll/s")
    print(f"  D (MSD slope T/4..T) = {D:.5f} +- {D_se:.5f};  <|dq|^2>/(4T) at T = {sq2.mean() / (4 * T):.5f};"
          f"  Machta-Zwanzig {mz:.5f} (D/D_MZ = {D / mz:.3f} +- {D_se / mz:.3f})")
    print(f"  <X(T)^2>_0 = {msd_2:.3f} +- {msd_2_se:.3f} (both components; x alone {msd_x:.3f} +- {msd_x_se:.3f})")
    print(f"  {'E':>6s} {'orbits':>7s} {'<v_F> = <X>/T':>15s} {'+-':>8s} {'E D/c^2':>9s} "
          f"{'ratio 2c^2<X>/(E<X^2>_0)':>25s} {'+-':>6s} {'coll/s':>9s}")
    for E in args.fields:
        th = scene.replace(force=(E, 0.0), thermostat="isokinetic")
        st = equilibrium_starts(scene, args.orbits, c, seed=args.seed + 2)
        dE, rate = run(th, st, T, mc)
        X, X_se = mean_se(dE[:, 0])
        ratio = 2 * c * c * X / (E * msd_2)
        ratio_se = abs(ratio) * math.hypot(X_se / X, msd_2_se / msd_2)
        print(f"  {E:6.3f} {args.orbits:7d} {X / T:15.6f} {X_se / T:8.6f} {E * D / c ** 2:9.6f} "
              f"{ratio:25.3f} {ratio_se:6.3f} {rate:9,.0f}")


def noslip(args):
    r, c, T = args.radius, args.speed, args.T
    scene = tables.hex_lorentz_cell(r, law="no-slip")
    mc = int(40 * T * c / (math.pi * (math.sqrt(3) / 2 - math.pi * r * r) / (2 * math.pi * r))) + 100
    z = equilibrium_starts(scene, args.zero_orbits_noslip, c, seed=args.seed + 3, noslip=True)
    d0, dw0, rate0 = run_log(scene, z, T, mc)
    xx, xx_se = mean_se(0.5 * (d0 * dw0).sum(axis=1))      # <X_w X>_0 (both components)
    msd, msd_se = mean_se(0.5 * (d0 ** 2).sum(axis=1))
    print(f"no-slip (gamma = {scene.gamma:.4f}), r = {r}, total energy c^2/2 with c = {c}, T = {T}: "
          f"{args.zero_orbits_noslip} zero-field orbits, {rate0:,.0f} coll/s")
    print(f"  <X^2>_0 = {msd:.3f} +- {msd_se:.3f}  (D = <X^2>/(2T) = {msd / (2 * T):.5f});"
          f"  <X_w X>_0 = {xx:.3f} +- {xx_se:.3f};  <X^2>_0/c^2 = {msd / c ** 2:.3f}")
    print(f"  {'E':>6s} {'orbits':>7s} {'<X>/T':>10s} {'+-':>8s} {'ratio 2<X>/(E<X_w X>_0)':>24s} {'+-':>6s} "
          f"{'2c^2<X>/(E<X^2>_0)':>19s} {'+-':>6s} {'coll/s':>9s}")
    for E in args.fields:
        th = scene.replace(force=(E, 0.0), thermostat="isokinetic")
        st = equilibrium_starts(scene, args.orbits_noslip, c, seed=args.seed + 4, noslip=True)
        dE, rate = run(th, st, T, mc)
        X, X_se = mean_se(dE[:, 0])
        ratio = 2 * X / (E * xx)
        ratio_se = abs(ratio) * math.hypot(X_se / X, xx_se / xx)
        naive = 2 * c * c * X / (E * msd)
        naive_se = abs(naive) * math.hypot(X_se / X, msd_se / msd)
        print(f"  {E:6.3f} {args.orbits_noslip:7d} {X / T:10.6f} {X_se / T:8.6f} {ratio:24.3f} {ratio_se:6.3f} "
              f"{naive:19.3f} {naive_se:6.3f} {rate:9,.0f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--radius", type=float, default=0.45)
    ap.add_argument("--speed", type=float, default=1.0)
    ap.add_argument("--T", type=float, default=100.0)
    ap.add_argument("--orbits", type=int, default=4000, help="orbits per field (thermostatted)")
    ap.add_argument("--zero-orbits", type=int, default=40000, help="zero-field orbits (straight flights)")
    ap.add_argument("--fields", type=float, nargs="*", default=[0.1, 0.2, 0.4])
    ap.add_argument("--seed", type=int, default=0, help="offset of the ensembles' seeds (independent repeats)")
    ap.add_argument("--noslip", action="store_true", help="the no-slip law instead of the specular one")
    ap.add_argument("--orbits-noslip", type=int, default=2000)
    ap.add_argument("--zero-orbits-noslip", type=int, default=4000)
    args = ap.parse_args()
    print(machine_line(numpy=True, load=True))
    if args.noslip:
        noslip(args)
    else:
        specular(args)
    print(machine_line(load=True))


if __name__ == "__main__":
    main()
