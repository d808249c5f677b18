"""Which term biases the energy: the law, the flight or the projection onto the element (issue 13, item 5).

Two measurements, both in extended precision (``numpy.longdouble``, 64-bit
mantissa: a square of a float64 is off by at most 2^-64 relative, so a mean
of 1e-19 is resolved; a sample is checked against exact rational arithmetic):

1. **orbits** (``--collisions`` per stress family of ``tests/test_stress.py``):
   the change of ``E = (|v|^2 + w^2)/2 - a.q`` at each collision, split into
   the collision law (``K_out - K_in``, ``K = (|v|^2 + w^2)/2``, at the same
   point) and the flight from the previous collision (``E_in - E_out`` of the
   previous one; no force: exactly zero, ``v`` is not touched).  Under a force
   the flight term is split again, on plain scenes, into the flight itself (to
   the unprojected hit point ``h``, recomputed with the kernel's own
   functions and checked bit for bit against the log) and the projection onto
   the element (``-a.(q - h)``).  Each term's mean per collision, times 10^6,
   relative to the size of the terms of ``E``, is its drift per 10^6
   collisions; their sum matches the measured slope.  The flight column also
   holds the loops' energy settling (``core/energy.py``), which acts between
   collisions: with it, the law's bias is given back there.
2. **the law alone** on random inputs (:func:`noslipsim.core.laws.collide`
   and the lean loop's reflection): mean ``dK/K`` per collision, split into the
   *defect* (what exact arithmetic with the same float normal ``n`` and
   ``(c, s)`` gives: ``|n|^2 - 1`` and ``c^2 + s^2 - 1`` are not zero) and the
   *rounding* of the float operations.

Run: ``python benchmarks/energy_terms.py [--collisions 100000] [--families a,b] [--samples 1000000]``.
"""
import argparse
import math
import os
import sys
import time
from fractions import Fraction

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))

LD = np.longdouble


def _k(vx, vy, w):
    vx, vy, w = (np.asarray(a, dtype=LD) for a in (vx, vy, w))
    return 0.5 * (vx * vx + vy * vy + w * w)


def orbit_terms(name, n):
    """Per-collision energy terms of one family's orbit: a dict of means per 10^6 collisions (relative)."""
    import test_stress as ts

    from noslipsim._engine.canonical import canonical_form
    from noslipsim._engine.table import kernel_table
    from noslipsim.core import layout
    from noslipsim.core.events import advance
    from noslipsim.core.free_flight import falling
    from noslipsim.core.geometry import place_on_element
    from noslipsim.core.search import cell_search
    from noslipsim.core.tolerances import EXTENT_TOL
    from noslipsim.simulate import run_one

    hit_in_cell = cell_search(falling)
    make, q, v, w = ts.chain_families()[name]
    scene = make()
    rec = np.zeros((n, layout.N_LOG))
    out = run_one(scene, np.asarray(q, float), np.asarray(v, float), float(w), n, np.inf, -np.inf,
                  layout.RECORD_LOG, rec)
    m = out[3]
    L = rec[:m]
    ax, ay = scene.force
    x, y = L[:, layout.LOG_X].astype(LD), L[:, layout.LOG_Y].astype(LD)
    k_out = _k(L[:, layout.LOG_VX], L[:, layout.LOG_VY], L[:, layout.LOG_W])
    k_in = _k(L[:, layout.LOG_VX_IN], L[:, layout.LOG_VY_IN], L[:, layout.LOG_W_IN])
    pot = -(LD(ax) * x + LD(ay) * y)
    size = float(max(np.abs(k_out + pot).max(), k_out.max(), np.abs(pot).max()))
    law = (k_out - k_in)[1:]
    flight = ((k_in + pot)[1:] - (k_out + pot)[:-1])
    res = {"family": name, "collisions": m, "law": float(law.mean()) / size * 1e6,
           "flight_total": float(flight.mean()) / size * 1e6, "flight": None, "projection": None, "matched": None}
    e_all = (k_out + pot)
    kk = np.arange(m) / 1e6
    de = np.asarray((e_all - e_all[0]) / LD(size), dtype=float)
    res["slope"] = float(kk @ de / (kk @ kk))
    res["law_sd"] = float(np.asarray(law, dtype=float).std()) / size
    has_force = ax != 0.0 or ay != 0.0
    if has_force and not scene.lattice:
        # split flight / projection: redo each flight with the kernel's functions (plain scenes: one cell),
        # on the table run_one ran (the scene's canonical form)
        table = kernel_table(canonical_form(scene).scene)
        kinds, params, copies, A = table.kinds, table.params, table.copies, table.A
        nf = min(m - 1, 20000)
        fl = np.zeros(nf, dtype=LD)
        pr = np.zeros(nf, dtype=LD)
        ok = 0
        for i in range(nf):
            r = L[i]
            xs, ys, vxs, vys = r[layout.LOG_X], r[layout.LOG_Y], r[layout.LOG_VX], r[layout.LOG_VY]
            tol = EXTENT_TOL * max(scene.scale, abs(xs), abs(ys))
            t_hit, e, _, _ = hit_in_cell(kinds, params, copies, A, 0, 0, (xs, ys, vxs, vys, ax, ay),
                                         int(r[layout.LOG_ELEMENT]), 0, 0, math.inf, tol, 0.0, False)
            hx, hy, vxi, vyi = advance(xs, ys, vxs, vys, ax, ay, t_hit, True)
            px, py = place_on_element(kinds[e], params[e], hx, hy)[:2]
            nxt = L[i + 1]
            ok += (px == nxt[layout.LOG_X] and py == nxt[layout.LOG_Y] and vxi == nxt[layout.LOG_VX_IN]
                   and vyi == nxt[layout.LOG_VY_IN])
            e_h = _k(vxi, vyi, r[layout.LOG_W]) - (LD(ax) * LD(hx) + LD(ay) * LD(hy))
            fl[i] = e_h - (k_out[i] + pot[i])
            pr[i] = -(LD(ax) * (LD(px) - LD(hx)) + LD(ay) * (LD(py) - LD(hy)))
        res["flight"] = float(fl.mean()) / size * 1e6
        res["projection"] = float(pr.mean()) / size * 1e6
        res["matched"] = ok / nf
    # a sample against exact rational arithmetic
    j = slice(1, min(m, 300))
    exact = [float(sum(Fraction(a) ** 2 for a in L[i, [layout.LOG_VX, layout.LOG_VY, layout.LOG_W]])
                   - sum(Fraction(a) ** 2 for a in L[i, [layout.LOG_VX_IN, layout.LOG_VY_IN, layout.LOG_W_IN]])) / 2
             for i in range(j.start, j.stop)]
    res["ld_vs_exact"] = float(np.abs(np.asarray(exact) - np.asarray((k_out - k_in)[j], dtype=float)).max()) / size
    return res


def law_terms(samples, seed=1):
    """Mean relative ``dK`` per collision of the laws on random inputs, split into defect and rounding."""
    from noslipsim import tables
    from noslipsim._engine.table import kernel_table
    from noslipsim._unit import unit_pair
    from noslipsim.core.jit import jit
    from noslipsim.core.laws import collide, noslip_coefficients

    @jit
    def apply(law, c, s, V, N, out):
        for i in range(V.shape[0]):
            out[i, 0], out[i, 1], out[i, 2] = collide(law, c, s, V[i, 0], V[i, 1], V[i, 2], N[i, 0], N[i, 1])
        return out

    @jit
    def lean_reflect(V, H, ir2, out):
        for i in range(V.shape[0]):
            hx, hy = H[i, 0], H[i, 1]
            hh = hx * hx + hy * hy
            delta = hh * ir2 - 1.0
            ihh = ir2 * (1.0 - delta)
            k = 2.0 * (V[i, 0] * hx + V[i, 1] * hy) * ihh
            out[i, 0] = V[i, 0] - k * hx
            out[i, 1] = V[i, 1] - k * hy
        return out

    rng = np.random.default_rng(seed)
    rows = []

    def exact_law(law, c, s, V, N):
        """The law in extended precision with the same float n, c, s (no rounding to speak of)."""
        v = V.astype(LD)
        nx, ny = N[:, 0].astype(LD), N[:, 1].astype(LD)
        tx, ty = -ny, nx
        vt = v[:, 0] * tx + v[:, 1] * ty
        vn = v[:, 0] * nx + v[:, 1] * ny
        w = v[:, 2]
        if law == 1:
            c, s = LD(c), LD(s)
            vt, w = -s * w + c * vt, -c * w - s * vt
        vn = -vn
        return np.c_[vt * tx + vn * nx, vt * ty + vn * ny, w]

    def measure(label, law, c, s, N, V=None):
        if V is None:
            ang = rng.uniform(0.0, 2.0 * math.pi, samples)
            V = np.c_[np.cos(ang), np.sin(ang), rng.uniform(-1.0, 1.0, samples) if law == 1 else np.zeros(samples)]
            flip = V[:, 0] * N[:, 0] + V[:, 1] * N[:, 1] < 0.0  # incoming: v . n > 0
            V[flip, :2] *= -1.0
        k0 = _k(V[:, 0], V[:, 1], V[:, 2])
        got = apply(law, c, s, V, N, np.zeros((len(V), 3)))
        ex = exact_law(law, c, s, V, N)
        dk = (_k(got[:, 0], got[:, 1], got[:, 2]) - k0) / k0
        dk_def = (_k(ex[:, 0], ex[:, 1], ex[:, 2]) - k0) / k0
        sd = float(np.asarray(dk, dtype=float).std())
        rows.append((label, float(dk.mean()), float(dk_def.mean()), float((dk - dk_def).mean()),
                     sd / math.sqrt(samples)))

    # stored line normals (pentagon edges, after _unit.py): a fixed |n|^2 - 1
    p = kernel_table(tables.regular_polygon(5)).params
    for j in (1, 2):
        nx, ny = -p[j, 2], -p[j, 3]
        d = float(Fraction(nx) ** 2 + Fraction(ny) ** 2 - 1)
        measure(f"specular, pentagon edge {j} (|n|^2-1 = {d:.1e})", 0, 1.0, 0.0, np.tile([nx, ny], (samples, 1)))
    # circle normals d/hypot(d) at radius r, as place_on_element forms them
    for r in (1.0, 0.25, 0.3):
        ang = rng.uniform(0.0, 2.0 * math.pi, samples)
        dx, dy = r * np.cos(ang), r * np.sin(ang)
        rho = np.hypot(dx, dy)
        N = np.c_[dx / rho, dy / rho]
        measure(f"specular, circle normal d/hypot(d), r = {r}", 0, 1.0, 0.0, N)
    # random normals (cos, sin) with the no-slip law
    for g in (1.0 / math.sqrt(2.0), 0.5, 0.3, 1.0):
        c, s = unit_pair(*noslip_coefficients(g))
        kap = float(Fraction(c) ** 2 + Fraction(s) ** 2 - 1)
        ang = rng.uniform(0.0, 2.0 * math.pi, samples)
        N = np.c_[np.cos(ang), np.sin(ang)]
        measure(f"no-slip gamma = {g:.4g} (c^2+s^2-1 = {kap:.1e}), random n", 1, c, s, N)
    # the lean loop's specular reflection v - 2 (v.h) h / |h|^2 with the Newton 1/|h|^2
    for r in (0.25, 0.3):
        ang = rng.uniform(0.0, 2.0 * math.pi, samples)
        H = np.c_[r * np.cos(ang), r * np.sin(ang)]
        a2 = rng.uniform(0.0, 2.0 * math.pi, samples)
        V = np.c_[np.cos(a2), np.sin(a2)]
        flip = V[:, 0] * H[:, 0] + V[:, 1] * H[:, 1] > 0.0
        V[flip] *= -1.0
        k0 = _k(V[:, 0], V[:, 1], np.zeros(samples))
        got = lean_reflect(V, H, (1.0 / r) ** 2, V.copy())
        dk = (_k(got[:, 0], got[:, 1], np.zeros(samples)) - k0) / k0
        hv = H.astype(LD)
        vv = V.astype(LD)
        kk = 2 * (vv[:, 0] * hv[:, 0] + vv[:, 1] * hv[:, 1]) / (hv[:, 0] ** 2 + hv[:, 1] ** 2)
        ex = np.c_[vv[:, 0] - kk * hv[:, 0], vv[:, 1] - kk * hv[:, 1]]
        dk_def = (_k(ex[:, 0], ex[:, 1], np.zeros(samples)) - k0) / k0
        rows.append((f"lean loop reflection in h, r = {r}", float(dk.mean()), float(dk_def.mean()),
                     float((dk - dk_def).mean()), float(np.asarray(dk, dtype=float).std()) / math.sqrt(samples)))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--collisions", type=float, default=1e5)
    ap.add_argument("--families", default="")
    ap.add_argument("--samples", type=float, default=1e6)
    args = ap.parse_args()
    import test_stress as ts

    t0 = time.perf_counter()
    names = args.families.split(",") if args.families else sorted(ts.chain_families())
    n = int(args.collisions)
    print(f"(1) orbits, {n:,} collisions each; per 10^6 collisions, relative to the size of E's terms")
    print(f"{'family':<26}{'slope':>11}{'law':>11}{'flight+proj':>13}{'flight':>11}{'projection':>12}"
          f"{'matched':>9}{'law se':>10}")
    for name in names:
        r = orbit_terms(name, n)
        se = r["law_sd"] / math.sqrt(r["collisions"]) * 1e6
        def fmt(v):
            return f"{v:+.1e}" if v is not None else "-"

        matched = f"{r['matched']:.3f}" if r["matched"] is not None else "-"
        print(f"{name:<26}{r['slope']:>+11.1e}{r['law']:>+11.1e}{r['flight_total']:>+13.1e}{fmt(r['flight']):>11}"
              f"{fmt(r['projection']):>12}{matched:>9}"
              f"{se:>10.1e}", flush=True)
    print(f"\n(2) the law on {int(args.samples):,} random inputs: mean dK/K per collision")
    print(f"{'case':<62}{'total':>11}{'defect':>11}{'rounding':>11}{'std err':>10}")
    for label, tot, dfc, rnd, se in law_terms(int(args.samples)):
        print(f"{label:<62}{tot:>+11.2e}{dfc:>+11.2e}{rnd:>+11.2e}{se:>10.1e}", flush=True)
    print(f"\n{time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
