"""Every analysis for a scene file of one's own: ``portrait``, ``ensemble``, ``periodic``, ``lyapunov``.

Each takes a scene file (docs/scenes.md), writes a netCDF dataset (``-o``)
with the scene, the command's options and the result, and, with
``--figure``, a figure of it.  The numbers come from the package's public
functions: :func:`noslipsim.experiments.phase_portrait`,
:func:`noslipsim.simulate_many`, :func:`noslipsim.analysis.find_periodic_orbit`
and :func:`noslipsim.analysis.lyapunov`.
"""
from __future__ import annotations

import math
import os

import numpy as np

from .._validate import check_memory
from ..core.layout import N_PORTRAIT
from .options import _orbit_arguments, _start_errors


def add_commands(sub, debug):
    """Register the four subcommands on ``sub`` (an argparse subparsers object)."""
    p = sub.add_parser("portrait", help="phase portrait of a scene file (velocity for no-slip, Birkhoff for specular)",
                       description="Orbits from starts uniform on the boundary (in the reduced phase space, "
                                   "speed 1), each collision on a finite element recorded; the velocity portrait "
                                   "(v_t, w) for a no-slip scene, Birkhoff coordinates (s, sin alpha) for a "
                                   "specular one (docs/analysis.md).")
    p.add_argument("scene", help="scene file (YAML; format in docs/scenes.md)")
    p.add_argument("--orbits", type=int, default=20, help="number of orbits (default 20)")
    p.add_argument("-n", "--collisions", type=int, default=1000, help="collisions per orbit (default 1000)")
    p.add_argument("--seed", type=int, default=0, help="seed of the random starts (default 0)")
    p.add_argument("--kind", choices=["velocity", "birkhoff"], default=None,
                   help="portrait to compute (default: velocity for no-slip, birkhoff for specular)")
    p.add_argument("-o", "--output", required=True, help="netCDF file to write")
    p.add_argument("--figure", help="also draw the portrait to this image (.png, .pdf, .svg)")
    p.add_argument("--debug", **debug)

    e = sub.add_parser("ensemble", help="many orbits of a scene file from one point: final states",
                       description="N orbits from one start point with directions uniform on the circle "
                                   "(seeded) at one speed, each run until its collision budget, a time limit, "
                                   "a height or an escape; the final state of each.")
    e.add_argument("scene", help="scene file (YAML; format in docs/scenes.md)")
    e.add_argument("--position", nargs=2, type=float, required=True, metavar=("X", "Y"),
                   help="start point of every orbit, strictly inside the table")
    e.add_argument("--speed", type=float, default=1.0, help="initial speed |v| (default 1)")
    e.add_argument("--orbits", type=int, default=1000, help="number of orbits (default 1000)")
    e.add_argument("--seed", type=int, default=0, help="seed of the random directions (default 0)")
    e.add_argument("-n", "--max-collisions", type=int, default=1000, help="collision budget per orbit (default 1000)")
    e.add_argument("--max-time", type=float, default=math.inf, help="time limit per orbit (default: none)")
    e.add_argument("--stop-below", type=float, default=None, help="stop an orbit when it crosses this height downwards")
    e.add_argument("-o", "--output", required=True, help="netCDF file to write")
    e.add_argument("--figure", help="also draw the final positions and their x histogram (.png, .pdf, .svg)")
    e.add_argument("--debug", **debug)

    q = sub.add_parser("periodic", help="find a periodic orbit near a start (Newton on the return map)",
                       description="Newton's method on the period-P return map from the start's first "
                                   "collision, with the exact Jacobian; writes the orbit found (P periods), "
                                   "its residual and the eigenvalues of its monodromy.")
    _orbit_arguments(q, default_n=None)  # the period and --periods set the length
    q.add_argument("--period", type=int, required=True, help="collisions per period")
    q.add_argument("--periods", type=int, default=3, help="periods written to the dataset (default 3)")
    q.add_argument("--tol", type=float, default=1e-12, help="target scaled residual (default 1e-12)")
    q.add_argument("-o", "--output", required=True, help="netCDF file to write")
    q.add_argument("--figure", help="also draw the orbit found over the table (.png, .pdf, .svg)")
    q.add_argument("--debug", **debug)

    ly = sub.add_parser("lyapunov", help="largest Lyapunov exponent of an orbit (Benettin, exact tangent map)",
                        description="Benettin's method on the exact tangent dynamics of the collision map; "
                                    "writes the running estimate and the exponent per unit time and per collision.")
    _orbit_arguments(ly, default_n=0)
    ly.add_argument("--max-time", type=float, default=1e4, help="run length in time (default 1e4; "
                                                                 "ignored with -n)")
    ly.add_argument("--twin", action="store_true",
                    help="measure it from a renormalised twin orbit (analysis.twin_lyapunov) instead: any flight, "
                         "a magnetic field and the isokinetic thermostat included; needs -n, draws no figure")
    ly.add_argument("-o", "--output", required=True, help="netCDF file to write")
    ly.add_argument("--figure", help="also draw the running estimate against time (.png, .pdf, .svg)")
    ly.add_argument("--debug", **debug)
    # -n is "collisions of the run" here; 0 means: use --max-time
    for action in ly._actions:
        if action.dest == "max_collisions":
            action.help = "run length in collisions instead of --max-time (default 0: use --max-time)"
    return {"portrait": portrait, "ensemble": ensemble, "periodic": periodic, "lyapunov": lyapunov}


# ---------------------------------------------------------------------------- shared
def _positive_int(value, option):
    if value < 1:
        raise ValueError(f"{option}: must be >= 1, got {value}")
    return value


def _figure(path, draw, size=(5.0, 4.0), ncols=1):
    """Draw with ``draw(axes)`` into ``path`` (a format matplotlib writes: :func:`.options.check_outputs`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .. import plot

    with plot.style_context():
        fig, axes = plt.subplots(1, ncols, figsize=size)
        draw(axes)
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        fig.savefig(path)
        plt.close(fig)


def _config(args, command):
    keep = {k: v for k, v in vars(args).items() if k not in ("debug", "command", "output", "figure")}
    return {"command": f"noslipsim {command}", **{k: (list(v) if isinstance(v, tuple) else v) for k, v in keep.items()}}


# ---------------------------------------------------------------------------- portrait
def portrait(args):
    """``noslipsim portrait``: the paper's portrait of the scene's law, as a dataset and a figure."""
    from .. import analysis, plot
    from ..analysis.log_portrait import paper_portrait, portrait_elements
    from ..experiments import phase_portrait
    from ..io import write_dataset
    from ..scenes import Scene

    scene = Scene.from_yaml(args.scene)
    n = _positive_int(args.orbits, "--orbits")
    m = _positive_int(args.collisions, "-n/--collisions")
    # each orbit's buffer holds a row of N_PORTRAIT floats per collision (found by the CLI fuzz: --orbits 1e12)
    check_memory(n * (ENSEMBLE_ORBIT_BYTES + m * N_PORTRAIT * 8), "--orbits, -n/--collisions",
                 f"a portrait of {n} orbits x {m} collisions", "use fewer orbits or collisions")
    kind = args.kind or paper_portrait(scene)
    chosen = portrait_elements(scene, kind)
    ds = phase_portrait(scene, n_orbits=n, n_collisions=m, seed=args.seed, elements=chosen, progress=False)
    if kind == "birkhoff":
        b = analysis.birkhoff_coordinates(ds, scene, elements=chosen)
        ds = ds.assign(s_boundary=b.s_boundary, sin_angle=b.sin_angle)
        ds.attrs["boundary_length"] = b.attrs["boundary_length"]
    ds.attrs["portrait"] = kind
    out = write_dataset(ds, args.output, config=_config(args, "portrait"))
    if args.figure:
        def draw(ax):
            if kind == "birkhoff":
                plot.draw_birkhoff(ax, out, size=1.0)
            else:
                plot.draw_layered_portrait(ax, out, size=1.0)
            ax.set_title(f"{os.path.basename(args.scene)}: {scene.law}, {kind} portrait", fontsize="small")
        _figure(args.figure, draw, size=(4.5, 4.5))
    points = int(np.isfinite(np.asarray(ds["vt_unit"].values)).sum())
    print(f"wrote {kind} portrait of {n} orbits ({points} points) to {args.output}"
          + (f" and {args.figure}" if args.figure else ""))


# ---------------------------------------------------------------------------- ensemble
#: Bytes one orbit of ``noslipsim ensemble`` holds at the peak (its direction, start and final state;
#: measured with tracemalloc at 1e5 and 4e5 orbits: 401 bytes), for refusing a run that cannot fit.
ENSEMBLE_ORBIT_BYTES = 400


def ensemble(args):
    """``noslipsim ensemble``: N orbits from one point, directions uniform, final states."""
    from .. import plot
    from ..ensemble import simulate_many
    from ..initial import unit_velocities
    from ..io import write_dataset
    from ..scenes import Scene

    scene = Scene.from_yaml(args.scene)
    n = _positive_int(args.orbits, "--orbits")
    check_memory(n * ENSEMBLE_ORBIT_BYTES, "--orbits", f"a run of {n} orbits",
                 "split it into runs with other --seed values")
    if not (math.isfinite(args.speed) and args.speed > 0):
        raise ValueError(f"--speed: must be finite and > 0, got {args.speed}")
    v = args.speed * unit_velocities(n, seed=args.seed)
    ds = _start_errors(simulate_many, scene, [args.position] * n, v, max_collisions=args.max_collisions,
                       max_time=args.max_time, stop_below=args.stop_below, record="final", progress=False)
    out = write_dataset(ds, args.output, config=_config(args, "ensemble"))
    reasons = out.stop_reason.values.astype(int)
    from ..core.layout import STOP_REASONS

    counts = ", ".join(f"{STOP_REASONS[k]}: {int((reasons == k).sum())}" for k in np.unique(reasons))
    if args.figure:
        x, y = out.x_final.values, out.y_final.values

        def draw(axes):
            ax, hx = axes
            plot.draw_table(ax, scene, plot.view_window(scene, (x, y)))
            ax.plot(x, y, ".", markersize=2, color=plot.law_color(scene.law))
            ax.plot([args.position[0]], [args.position[1]], "k+", markersize=8)
            ax.set_title(f"final positions of {n} orbits", fontsize="small")
            hx.hist(x, bins=min(60, max(10, n // 20)), color=plot.law_color(scene.law))
            hx.set_xlabel("x (final)")
            hx.set_ylabel("orbits")
        _figure(args.figure, draw, size=(9.0, 4.0), ncols=2)
    print(f"wrote {n} orbits to {args.output} ({counts})" + (f" and {args.figure}" if args.figure else ""))


# ---------------------------------------------------------------------------- periodic
def periodic(args):
    """``noslipsim periodic``: Newton's method for a periodic orbit near a start."""
    from .. import plot
    from .._metadata import annotate
    from ..analysis import find_periodic_orbit
    from ..core.layout import N_LOG
    from ..io import write_dataset
    from ..scenes import Scene
    from ..simulate import simulate

    period = _positive_int(args.period, "--period")
    periods = _positive_int(args.periods, "--periods")
    check_memory(period * periods * N_LOG * 8, "--period, --periods", f"a log of {period * periods} collisions")
    scene = Scene.from_yaml(args.scene)
    found = _start_errors(find_periodic_orbit, scene, args.position, args.velocity, args.spin, period=period,
                          tol=args.tol)
    if not found.converged:
        raise ValueError(f"--position/--velocity: {_not_found(found, period, args.tol)}")
    orbit = simulate(scene, found.position, found.velocity, found.spin, max_collisions=period * periods)
    mono = found.monodromy
    kind = mono.kind if mono is not None else "unknown"
    eig = np.asarray(mono.eigenvalues if mono is not None else [], dtype=complex)
    orbit = annotate(orbit.assign(eigenvalue_real=("eigenvalue", eig.real), eigenvalue_imag=("eigenvalue", eig.imag),
                                  period=((), period), residual=((), float(found.residual)),
                                  linear_kind=((), kind)))
    orbit.attrs.update(iterations=int(found.iterations), message=found.message)
    write_dataset(orbit, args.output, config=_config(args, "periodic"))
    if args.figure:
        def draw(ax):
            x, y = plot.orbit_path(orbit)
            plot.draw_table(ax, scene, plot.view_window(scene, (x, y)))
            plot.draw_orbit(ax, orbit)
            ax.set_title(f"{period}-periodic orbit, residual {found.residual:.1e}", fontsize="small")
        _figure(args.figure, draw)
    speed = float(np.hypot(*found.velocity))
    print(f"found a {period}-periodic orbit: position {_digits(found.position, scene.scale)}, velocity "
          f"{_digits(found.velocity, speed)}, spin {_digit(found.spin, speed)}, "
          f"residual {_residual(found.residual)}, {kind}; wrote {args.output}"
          + (f" and {args.figure}" if args.figure else ""))


def _not_found(found, period, tol):
    """What the search did, in words, when it returned no orbit (the residual only where it means one)."""
    if found.residual <= tol:  # Newton closed the map, but the orbit from its state does not close again
        return (f"the search reached residual {_residual(found.residual)}, but the orbit run again from the state "
                f"it returned does not close after {period} collisions (rounding amplified along it), so no "
                f"{period}-periodic orbit is confirmed; try another --period or start")
    if math.isinf(found.residual):
        return f"the start has no {period}-collision return map ({found.message}); try a start closer to an orbit"
    return (f"no {period}-periodic orbit found near this start: the search stopped at residual "
            f"{found.residual:.3g} ({found.message}); try a start closer to one")


#: Below this fraction of its scale a printed component is rounding (the dataset keeps every digit).
ROUNDING = 1e-12


def _digit(x, scale):
    """``x`` to 10 digits, or 0 under ``ROUNDING * scale``: Newton's last step leaves such a component at
    the rounding of the machine's linear algebra, which differs between CPUs, and ten digits of it
    would only print that noise."""
    return f"{0.0 if abs(x) < ROUNDING * scale else x:.10g}"


def _digits(values, scale):
    """``[a, b]``, each component as :func:`_digit` prints it."""
    return "[" + ", ".join(_digit(x, scale) for x in values) + "]"


def _residual(residual):
    """The residual, or a bound where it is at rounding level (its digits differ between CPUs)."""
    return f"{residual:.1e}" if residual >= 1e-14 else "< 1e-14"


# ---------------------------------------------------------------------------- lyapunov
def lyapunov(args):
    """``noslipsim lyapunov``: the largest Lyapunov exponent and its running estimate."""
    import xarray as xr

    from .._metadata import annotate
    from ..analysis.lyapunov import lyapunov_run
    from ..io import write_dataset
    from ..scenes import Scene

    scene = Scene.from_yaml(args.scene)
    if args.twin:
        return _twin_lyapunov(args, scene)
    n = args.max_collisions if args.max_collisions > 0 else None
    run = _start_errors(lyapunov_run, scene, args.position, args.velocity, args.spin, max_time=args.max_time,
                        n_collisions=n)
    ds = xr.Dataset({"lyapunov_running": ("block", np.asarray(run["running"], float)),
                     "elapsed_time": ("block", np.asarray(run["times"], float)),
                     "lyapunov_exponent": ((), float(run["exponent"])),
                     "lyapunov_per_collision": ((), float(run["per_collision"])),
                     "mean_free_time": ((), float(run["mean_free_time"])),
                     "n_collisions": ((), int(run["n_collisions"]))})
    ds.attrs.update(title="largest Lyapunov exponent", lyapunov_method="tangent", scene=scene.to_json(), law=scene.law,
                    gamma=scene.gamma)
    write_dataset(annotate(ds), args.output, config=_config(args, "lyapunov"))
    if args.figure:
        def draw(ax):
            ax.plot(run["times"], run["running"], color="k")
            ax.axhline(run["exponent"], color="0.6", linewidth=0.8)
            ax.set_xlabel("time")
            ax.set_ylabel("running estimate of lambda (per unit time)")
            ax.set_title(f"lambda = {run['exponent']:.4g} per unit time", fontsize="small")
        _figure(args.figure, draw)
    print(f"lambda = {run['exponent']:.6g} per unit time ({run['per_collision']:.6g} per collision, "
          f"{run['n_collisions']} collisions); wrote {args.output}" + (f" and {args.figure}" if args.figure else ""))


def _twin_lyapunov(args, scene):
    """``noslipsim lyapunov --twin``: the exponent from a twin orbit (:func:`noslipsim.analysis.twin_lyapunov`).

    The twin gives the exponent per collision over ``N`` collisions (``-n`` rounded up to whole blocks);
    the orbit's own time over those collisions, ``t_N``, turns it into one per unit time,
    ``lambda_coll N / t_N``.  An orbit or twin that stops before ``N`` collisions has no exponent: an error.
    """
    import xarray as xr

    from .._metadata import annotate
    from ..analysis.islands import twin_collisions, twin_lyapunov
    from ..ensemble import simulate_many
    from ..io import write_dataset

    if args.max_collisions <= 0:
        raise ValueError("-n: --twin runs a number of collisions; give -n (a positive count)")
    if args.figure:
        raise ValueError("--figure: --twin has no running estimate to draw")
    per_collision = float(_start_errors(twin_lyapunov, scene, [args.position], [args.velocity], [args.spin],
                                        n_collisions=args.max_collisions)[0])
    n = twin_collisions(args.max_collisions)
    if math.isnan(per_collision):
        raise ValueError(f"the orbit or its twin stopped before {n} collisions (an escape, a corner, a graze or "
                         "the search limit): no exponent; try another start or a smaller -n")
    # the orbit's time at its N-th collision: its final state (no log of N rows)
    elapsed = float(simulate_many(scene, [args.position], [args.velocity], [args.spin], max_collisions=n,
                                  record="final", scheduler="sync", progress=False).t_final[0])
    exponent = per_collision * n / elapsed
    ds = xr.Dataset({"lyapunov_exponent": ((), exponent),  # per collision x N / t_N
                     "lyapunov_per_collision": ((), per_collision),
                     "mean_free_time": ((), elapsed / n),
                     "n_collisions": ((), n)})
    ds.attrs.update(title="largest Lyapunov exponent", lyapunov_method="twin", scene=scene.to_json(), law=scene.law,
                    gamma=scene.gamma)
    write_dataset(annotate(ds), args.output, config=_config(args, "lyapunov"))
    print(f"lambda = {exponent:.6g} per unit time ({per_collision:.6g} per collision, {n} collisions, twin orbit); "
          f"wrote {args.output}")
