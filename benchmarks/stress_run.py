"""Run the stress checks at full size (not via pytest) and write ``benchmarks/results/stress.md``.

The core loops are the functions of ``tests/test_stress.py`` (one source of truth);
this script runs them in worker processes, applies the same assertions (a failure is
recorded, not raised) and writes the measured figures with the machine and the date.

    python benchmarks/stress_run.py                 # full size, 2 workers (~10-15 min on 2 cores)
    python benchmarks/stress_run.py --quick         # small sizes (a smoke test of the script)
    python benchmarks/stress_run.py --workers 4 --total 1e8
"""
from __future__ import annotations

import argparse
import datetime as dt
import math
import multiprocessing as mp
import os
import platform
import subprocess
import sys
import time
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests"))
sys.path.insert(0, HERE)
from machine import cpu_model  # noqa: E402


# ----------------------------------------------------------------------------- tasks (run in workers)
def _checked(fn, r, *args):
    """Apply an assertion of the test suite to a result row; record the failure instead of raising."""
    try:
        fn(r, *args)
        r["ok"] = True
    except AssertionError as exc:
        r["ok"] = False
        r["failure"] = str(exc).splitlines()[0][:400]
    return r


def task(job):
    """One unit of work: ``(section, args)`` -> ``(section, args, result rows, seconds)``."""
    import test_stress as ts

    section, args = job
    t0 = time.perf_counter()
    try:
        if section == "chain":
            name, n_target, chunk = args
            rows = [_checked(ts.assert_chain, ts.run_chain(name, n_target, chunk))]
        elif section == "reversal_regular":
            rows = [ts.reversal_regular(args[0], args[1])]
            r = rows[0]
            r["ok"] = bool(r["mirrored"] and r["error"] <= r["bound"])
        elif section == "reversal_horizon":
            rows = [ts.reversal_horizon(args[0])]
        elif section == "grazing":
            case, thetas, n = args
            rows = [_checked(ts.assert_grazing, ts.grazing_run(case, th, n=n)) for th in thetas]
        elif section == "corners":
            name, n = args
            rows = [_checked(ts.assert_corner, r) for r in ts.corner_runs(names=(name,), n=n)]
        elif section == "gamma":
            gamma, n = args
            rows = [_checked(ts.assert_gamma, ts.gamma_run(name, gamma, n)) for name in sorted(ts.chain_families())]
            rows += [dict(ts.gamma_zero_matches_specular(name, n), gamma_zero_check=True)
                     for name in ("pentagon", "wedge_gravity", "circle_container_gravity")] if gamma == 0.0 else []
        elif section == "force":
            g, n, n_steps, n_ref = args
            rows = [_checked(ts.assert_force, ts.force_run(name, g, n, n_steps=n_steps, n_ref=n_ref))
                    for name in ts.force_families()]
        elif section == "corridor":
            lattice, slope, law, n = args
            r = _checked(ts.assert_corridor, ts.corridor_run(slope, law, lattice=lattice, n=n))
            if law == "specular":
                p = _checked(ts.assert_corridor_precision, dict(r))
                r["precision_ok"] = p["ok"]
            rows = [r]
        elif section == "channel":
            theta, law, force, n = args
            rows = [_checked(ts.assert_channel, ts.channel_run(theta, law, force=force, n=n))]
        elif section == "scale":
            L, n, n_steps = args
            exact = L in ts.SCALES_POW2
            rows = [_checked(ts.assert_scale, ts.scale_run(name, L, n, n_steps=0 if exact else n_steps), exact)
                    for name in sorted(ts.chain_families())]
        else:
            raise ValueError(section)
    except Exception:  # a crash is a finding too
        rows = [dict(ok=False, failure="crash: " + traceback.format_exc().splitlines()[-1], args=str(args))]
    return section, args, rows, time.perf_counter() - t0


def jobs(total, quick):
    import test_stress as ts

    fams = sorted(ts.chain_families())
    per = -(-total // len(fams))
    chunk = min(ts.CHUNK, per)
    out = [("chain", (name, per, chunk)) for name in fams]
    T_long = 2e3 + 0.3 if quick else 1e6 + 0.3
    out += [("reversal_regular", (name, T_long)) for name in sorted(ts.REGULAR_TABLES)]
    out += [("reversal_horizon", (name,)) for name in fams]
    extra = () if quick else (1e-3, 1e-5, 1e-7)
    for case, spec in sorted(ts.GRAZING_CASES.items()):
        thetas = tuple(sorted({*spec[-1], *(t for t in extra if case != "container" or t >= 1e-5)}, reverse=True))
        out.append(("grazing", (case, thetas, 200 if quick else 20_000)))
    out += [("corners", (name, 100 if quick else 10_000)) for name in ts.POLYGONS]
    out += [("gamma", (g, 2000 if quick else 200_000)) for g in ts.GAMMAS]
    out += [("force", (g, 2000 if quick else 200_000, 50 if quick else 2000, 3 if quick else 30))
            for g in ts.FORCE_MAGNITUDES]
    for lattice in ("square", "hex"):
        for slope in ts.CORRIDOR_SLOPES:
            for law in ("specular", "no-slip"):
                out.append(("corridor", (lattice, slope, law, 20 if quick else 100)))
    for theta in ts.CHANNEL_ANGLES:
        for law in ("specular", "no-slip"):
            out.append(("channel", (theta, law, (0.0, 0.0), 20)))
    for theta in (1e-4, 1e-6):
        out.append(("channel", (theta, "no-slip", (1e-3, 0.0), 20)))
    out += [("scale", (L, 2000 if quick else 100_000, 50 if quick else 2000)) for L in ts.SCALES + ts.SCALES_POW2]
    return out


# ----------------------------------------------------------------------------- report
def fmt(x, spec=".1e"):
    if x is None:
        return "–"
    if isinstance(x, bool):
        return "yes" if x else "**no**"
    if isinstance(x, float):
        if math.isinf(x) or math.isnan(x):
            return str(x)
        return format(x, spec)
    return str(x)


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(fmt(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def machine():
    import numba
    import numpy
    import xarray

    import noslipsim

    cpu = cpu_model()
    try:
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--", "src"], capture_output=True,
                               text=True, check=True).stdout.strip()
        commit += " (src/ has uncommitted changes)" if dirty else ""
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    return (f"{platform.system()} {platform.release()} {platform.machine()}, CPU: {cpu}, "
            f"{os.cpu_count()} logical cores; Python {platform.python_version()}, numpy {numpy.__version__}, "
            f"numba {numba.__version__}, xarray {xarray.__version__}, noslipsim {noslipsim.__version__}, "
            f"git {commit}")


def report(results, args, wall, started):
    import test_stress as ts

    by = {}
    for section, a, rows, sec in results:
        by.setdefault(section, []).append((a, rows, sec))
    busy = {s: sum(sec for _, _, sec in v) for s, v in by.items()}
    failures = [(s, r) for s, v in by.items() for _, rows, _ in v for r in rows if r.get("ok") is False]
    out = ["# Stress run: measured figures\n",
           f"Date: {started:%Y-%m-%d %H:%M} UTC. Machine: {machine()}.\n",
           f"Command: `python benchmarks/stress_run.py{' --quick' if args.quick else ''} --workers {args.workers} "
           f"--total {args.total:.0e}`; wall time {wall / 60:.1f} min on {args.workers} worker processes "
           f"(other processes shared the machine). Core loops: `tests/test_stress.py`; tolerances are its named "
           f"constants. All errors are relative to the engine's length scale `max(scene.scale, |q|)` (|q| in the "
           f"cell frame on lattices) unless stated.\n",
           "Worker time per section (s): " + ", ".join(f"{s} {t:.0f}" for s, t in busy.items()) + ".\n"]

    # -------- (a, b)
    chains = sorted((rows[0] for _, rows, _ in by.get("chain", [])), key=lambda r: r.get("family", ""))
    total = sum(r.get("collisions", 0) for r in chains)
    secs = sum(r.get("seconds", 0.0) for r in chains)
    out.append("## (a) Long chains: no leak, no missed collision\n")
    out.append(f"{total:,} collisions in all ({total / 1e6:.1f} x 10^6) over {len(chains)} families, each one orbit "
               f"restarted every ~10^6 collisions from its state at a time limit; every chunk's log checked, then "
               f"discarded. {secs:.0f} worker-seconds including the checks ({total / max(secs, 1e-9):,.0f} "
               f"collisions/s simulated and checked per worker).\n")
    out.append("Columns: worst distance of a collision point to its element's line/circle (`on elem`), beyond "
               "a segment/arc end (`overshoot`, ends inclusive within EXTENT_TOL = 1e-11), of a corner-rule hit "
               "to its second element (`corner`), most negative depth of 3 sampled points per flight (`leak`; >= 0 "
               "is inside), deepest crossing of any element inside any flight (`missed`; the missed-collision "
               "check), collision-law residual (`law`), and the log's measurement floor on lattices (unfolded "
               "positions carry half an ulp of |q|).\n")
    out.append(table(["family", "collisions", "corner hits", "on elem", "overshoot", "corner", "leak", "missed",
                      "law", "floor", "stops", "s", "ok"],
                     [[r.get("family"), f"{r.get('collisions', 0):,}", r.get("corner"), r.get("on_element"),
                       r.get("overshoot"), r.get("corner_contact"), r.get("leak"), r.get("penetration"),
                       r.get("law_residual"), r.get("floor"), ",".join(r.get("stops", [])),
                       f"{r.get('seconds', 0):.0f}", r.get("ok")] for r in chains]))
    out.append(f"\nTolerances: on elem <= {ts.ON_ELEMENT_TOL:g}, overshoot <= {ts.OVERSHOOT_TOL:g}, corner <= "
               f"{ts.CORNER_TOL:g}, leak >= -{ts.LEAK_TOL:g}, missed >= -{ts.PENETRATION_TOL:g}, law <= "
               f"{ts.LAW_TOL:g} (each plus the floor).\n")

    out.append("## (b) Energy drift\n")
    out.append("`per 10^6`: largest relative error of E = (|v|^2 + w^2)/2 - a.q within any chunk of ~10^6 "
               "collisions (relative to the size of the terms of E, which grow on a falling lattice orbit); "
               "`chain`: the same over the whole chain.\n")
    rows_b = []
    for r in chains:
        slope, r2 = ts.energy_slope(r) if "energy_trace" in r else (None, None)
        rows_b.append([r.get("family"), f"{r.get('collisions', 0):,}", r.get("energy_chunk"), r.get("energy_chain"),
                       fmt(r["energy_chain"] / r["energy_chunk"], ".1f") if r.get("energy_chunk") else None,
                       fmt(slope, "+.1e"), fmt(r2, ".3f")])
    out.append("`chain/per 10^6` would be about sqrt(7) = 2.6 for a random walk and 7 for a steady drift; `slope`: "
               "least-squares drift per 10^6 collisions through the chunk ends, `R^2` of that straight line "
               "(near 1: a bias per collision, not a random walk).\n")
    out.append(table(["family", "collisions", "per 10^6", "chain", "chain/per 10^6", "slope per 10^6", "R^2"], rows_b))
    out.append(f"\nBounds: {ts.ENERGY_TOL_PER_MILLION:g} per 10^6 collisions, {ts.ENERGY_TOL_CHAIN:g} per chain "
               f"(the event loops keep the energy, core/energy.py: no drift is left).\n")

    # -------- (c)
    out.append("## (c) Reversibility\n")
    out.append("Reverse v and w mid-flight after time T, run for T again: `error` is the largest return "
               "error of position (over the length scale) and of (v, w) (over the speed); `mirrored`: the same "
               "elements in reverse order. Non-chaotic tables (shear: error ~ n^2):\n")
    regs = sorted((rows[0] for _, rows, _ in by.get("reversal_regular", [])), key=lambda r: r["table"])
    out.append(table(["table", "T", "collisions", "mirrored", "error", "bound C eps n^2", "error/(eps n^2)", "ok"],
                     [[r["table"], f"{r['T']:.0f}", f"{r['collisions']:,}", r["mirrored"], r["error"], r["bound"],
                       f"{r['error'] / (ts.EPS * max(r['collisions'], 1) ** 2):.1f}", r.get("ok")] for r in regs]))
    out.append("\nChaotic families: the longest reversal (T doubling from 2.5) that returns within 1e-8, and "
               "the error growth per collision beyond it (a Lyapunov-like rate; reversal fails after ~36/rate "
               "collisions whatever the arithmetic):\n")
    hs = sorted((rows[0] for _, rows, _ in by.get("reversal_horizon", [])), key=lambda r: r.get("family", ""))
    out.append(table(["family", "collisions within 1e-8", "error there", "growth / collision"],
                     [[r.get("family"), r.get("horizon_collisions"), r.get("horizon_error"),
                       fmt(r.get("growth_per_collision"), ".2f")] for r in hs]))
    out.append("")

    # -------- (d)
    out.append("## (d) Grazing incidence\n")
    out.append("A flight traced back from a target point P at angle theta to the boundary; 20,000 collisions "
               "then checked. `miss depth`: how deep the unreflected flight would go past the boundary "
               "(relative); below 1e-14 the collision is decided by the rounding of the start itself "
               "(`resolvable` = no: only the invariants are required). `hit err`: first hit vs P; `ref err`: vs "
               "the 50-digit reference from the same float start; `tol` = 64 eps / sin(theta).\n")
    g_rows = [r for _, rows, _ in sorted(by.get("grazing", []), key=lambda x: x[0][0]) for r in rows]
    out.append(table(["case", "theta", "miss depth", "resolvable", "found", "ref found", "hit err", "ref err", "tol",
                      "on elem", "leak", "missed", "stop", "ok"],
                     [[r.get("case"), fmt(r.get("theta"), ".0e"), r.get("depth_miss"), r.get("resolvable"),
                       r.get("found"), r.get("ref_found"), r.get("hit_error"), r.get("ref_error"), r.get("pos_tol"),
                       r.get("on_element"), r.get("leak"), r.get("penetration"), r.get("stop"), r.get("ok")]
                      for r in g_rows]))
    out.append("\nNot tested by construction: a force pressing the particle onto a straight wall (no interior "
               "flight reaches it at a small angle) and, without force, circular containers below theta ~ 1.4e-6 "
               "(a chord at angle theta lies within R theta^2/2 of the circle, inside the 1e-12 start margin).\n")

    # -------- (e)
    out.append("## (e) Flights aimed at polygon vertices\n")
    c_rows = [r for _, rows, _ in by.get("corners", []) for r in rows]
    groups = {}
    for r in c_rows:
        groups.setdefault((r.get("polygon"), r.get("law"), str(r.get("force"))), []).append(r)
    out.append(f"Offsets {', '.join(f'{o:g}' for o in ts.CORNER_OFFSETS)} (times the scale, across the flight) "
               f"from each vertex, up to 3 incoming directions per vertex, 10^4 collisions per run. "
               f"{len(c_rows)} runs, {sum(r.get('collisions', 0) for r in c_rows):,} collisions, "
               f"{sum(r.get('corner', 0) for r in c_rows):,} corner-rule collisions.\n")
    out.append(table(["polygon", "law", "force", "runs", "1st hit by corner rule", "1st hit err", "on elem",
                      "overshoot", "corner", "leak", "missed", "stops", "failed"],
                     [[p, law, f, len(rs), sum(r.get("first_corner", False) for r in rs),
                       max(r.get("first_hit_error", 0.0) for r in rs), max(r.get("on_element", 0.0) for r in rs),
                       max(r.get("overshoot", 0.0) for r in rs), max(r.get("corner_contact", 0.0) for r in rs),
                       min(r.get("leak", 0.0) for r in rs), min(r.get("penetration", 0.0) for r in rs),
                       ",".join(sorted({r.get("stop", "?") for r in rs})), sum(not r.get("ok") for r in rs)]
                      for (p, law, f), rs in sorted(groups.items())]))
    out.append("")

    # -------- (f)
    out.append("## (f) Mass distribution gamma\n")
    out.append("Every chain family with the no-slip law at each gamma (200,000 collisions each; worst over the "
               "families). `law`: residual of the no-slip map, i.e. of the reversal of the contact velocity.\n")
    gam = [r for _, rows, _ in by.get("gamma", []) for r in rows if "gamma" in r]
    rows_f = []
    for g in ts.GAMMAS:
        rs = [r for r in gam if r["gamma"] == g]
        if rs:
            rows_f.append([fmt(g, ".3g"), len(rs), sum(r.get("collisions", 0) for r in rs),
                           max(r.get("on_element", 0.0) for r in rs), max(r.get("overshoot", 0.0) for r in rs),
                           min(r.get("leak", 0.0) for r in rs), min(r.get("penetration", 0.0) for r in rs),
                           max(r.get("energy", 0.0) for r in rs), max(r.get("law_residual", 0.0) for r in rs),
                           sum(not r.get("ok") for r in rs)])
    out.append(table(["gamma", "families", "collisions", "on elem", "overshoot", "leak", "missed", "energy", "law",
                      "failed"], rows_f))
    zero = [r for _, rows, _ in by.get("gamma", []) for r in rows if r.get("gamma_zero_check")]
    if zero:
        out.append("\ngamma = 0 no-slip vs specular (the same path, spin reversed at each hit): " + "; ".join(
            f"{r['family']}: elements equal {fmt(r['same_elements'])}, max position difference "
            f"{r['position_difference']:.1e}, |w| change {r['spin_magnitude_change']:.1e}" for r in zero) + ".\n")

    # -------- (g)
    out.append("## (g) Force magnitude\n")
    out.append("Each family with a force, its force scaled to magnitude g and its start velocity and spin by "
               "lambda = sqrt(g / g0) (the same path, times over lambda). `1-step err/tol`: worst disagreement "
               "with the unscaled orbit over 2000 random flights started mid-flight, over its conditioning "
               "tolerance 64 eps / sin(incidence) (<= 1 passes); `pow2 bitwise`: with lambda rounded to a power of "
               "two, the whole orbit bitwise identical (reported, not required); `unit speed vs ref`: the force g "
               "with the family's own speed (a tiny force on a fast particle, a huge one on a slow one), 30 "
               "flights one at a time against the 50-digit reference.\n")
    frc = sorted([r for _, rows, _ in by.get("force", []) for r in rows if "g" in r],
                 key=lambda r: (r["g"], r["family"]))
    out.append(table(["g", "family", "collisions", "stop", "1-step err", "1-step err/tol", "pow2 bitwise",
                      "unit speed vs ref", "on elem", "leak", "missed", "energy", "ok"],
                     [[fmt(r["g"], ".0e"), r["family"], r.get("collisions"), r.get("stop"), r.get("step_error"),
                       r.get("step_error_over_tol"), r.get("bitwise_pow2"), r.get("unit_speed_vs_reference"),
                       r.get("on_element"), r.get("leak"), r.get("penetration"), r.get("energy"), r.get("ok")]
                      for r in frc]))
    out.append("")

    # -------- (h)
    out.append("## (h) Very long flights\n")
    cor = sorted([r for _, rows, _ in by.get("corridor", []) for r in rows if "lattice" in r],
                 key=lambda r: (r["lattice"], -r["slope"], r["law"]))
    out.append("Lorentz-gas corridors (square: r = 0.1, start (0.5, 0.23); hexagonal: r = 0.3, start (0, 0.35)), "
               "direction (1, slope): the first hit against exact arithmetic (60 digits), then 100 collisions "
               "checked. `v err`: velocity after the first hit vs the exact collision; `v tol` = 64 eps / "
               "sin(incidence), the precision the hit's conditioning allows.\n")
    out.append(table(["lattice", "slope", "law", "cells flown", "right disk", "t rel err", "sin(incidence)", "v err",
                      "v tol", "v err/tol", "on elem", "missed", "floor", "ok"],
                     [[r["lattice"], fmt(r["slope"], ".0e"), r["law"], fmt(r.get("cells"), ".2e"), r.get("cell_match"),
                       r.get("t_rel_error"), r.get("sin_incidence"), r.get("velocity_error"), r.get("velocity_tol"),
                       fmt(r["velocity_error"] / r["velocity_tol"], ".1f") if r.get("velocity_error") is not None
                       else None, r.get("on_element"), r.get("penetration"), r.get("floor"), r.get("ok")]
                      for r in cor]))
    chn = [r for _, rows, _ in by.get("channel", []) for r in rows if "theta" in r]
    out.append("\nChannel 0 < y < 1 (lines), start (0, 0.5) at angle theta to the walls, 20 collisions against "
               "the 50-digit reference:\n")
    out.append(table(["theta", "law", "force", "longest flight (time)", "elements equal", "t err", "position err",
                      "velocity err", "on elem", "missed", "ok"],
                     [[fmt(r["theta"], ".0e"), r["law"], str(r["force"]), fmt(r["longest_flight"], ".2e"),
                       r["same_elements"], r["t_error"], r["position_error"], r["velocity_error"], r.get("on_element"),
                       r.get("penetration"), r.get("ok")] for r in chn]))
    out.append("")

    # -------- (i)
    out.append("## (i) Tiny and huge tables\n")
    out.append("Every length times L and the force times L (times unchanged): the orbit should be the unscaled one "
               "times L. For L = 2^-20, 2^20 scaling is exact in binary: the whole orbit must be bitwise identical. "
               "For L = 1e-6, 1e6: the first 5 collisions within 1e-9 (`early err`), the same elements until the "
               "orbits part by 1e-6 (`chaos horizon`, in collisions), and 2000 random flights one at a time within "
               "their conditioning tolerance (`1-step err/tol`); invariants on the scaled orbit (relative).\n")
    sc = sorted([r for _, rows, _ in by.get("scale", []) for r in rows if "L" in r],
                key=lambda r: (r["L"], r["family"]))
    out.append(table(["L", "family", "collisions", "bitwise", "early err", "chaos horizon", "1-step err/tol",
                      "on elem", "leak", "missed", "energy", "ok"],
                     [[fmt(r["L"], ".3g"), r["family"], r.get("collisions"), r.get("bitwise"), r.get("early_error"),
                       r.get("chaos_horizon"), r.get("step_error_over_tol"), r.get("on_element"), r.get("leak"),
                       r.get("penetration"), r.get("energy"), r.get("ok")] for r in sc]))
    out.append("")

    # -------- failures
    out.append("## Failures\n")
    energy_known = [r for r in chains if r.get("energy_chain", 0.0) > ts.ENERGY_TOL_CHAIN]
    if energy_known:
        out.append(f"Over the chain energy bound ({ts.ENERGY_TOL_CHAIN:g}): "
                   + ", ".join(f"{r['family']} ({r['energy_chain']:.1e})" for r in energy_known) + ".\n")
    if failures:
        out.append("Failed checks (including the known ones above):\n")
        out += [f"* {s}: {r.get('failure', r)}" for s, r in failures]
    else:
        out.append("No other check failed.")
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--total", type=float, default=1e8, help="collisions over all chain families")
    ap.add_argument("--quick", action="store_true", help="small sizes everywhere (a smoke test)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "stress.md"))
    args = ap.parse_args()
    if args.quick and args.total == 1e8:
        args.total = 1e5
    started = dt.datetime.now(dt.timezone.utc)
    todo = jobs(int(args.total), args.quick)
    # longest first (chains), so the workers finish together
    order = {"chain": 0, "gamma": 1, "force": 1, "scale": 1, "reversal_regular": 2, "corners": 2}
    todo.sort(key=lambda j: order.get(j[0], 3))
    t0 = time.perf_counter()
    results = []
    ctx = mp.get_context("spawn")
    with ctx.Pool(args.workers, maxtasksperchild=4) as pool:
        for i, res in enumerate(pool.imap_unordered(task, todo), 1):
            results.append(res)
            section, a, rows, sec = res
            bad = sum(r.get("ok") is False for r in rows)
            print(f"[{i}/{len(todo)}] {section} {a} {sec:.1f}s{' FAILED ' + str(bad) if bad else ''}", flush=True)
    wall = time.perf_counter() - t0
    text = report(results, args, wall, started)
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    tmp = args.out + ".tmp"
    with open(tmp, "w", encoding="utf-8") as fh:
        fh.write(text)
    os.replace(tmp, args.out)
    print(f"wrote {args.out} ({wall / 60:.1f} min)")


if __name__ == "__main__":
    main()
