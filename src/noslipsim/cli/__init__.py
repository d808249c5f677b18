"""Command line: ``noslipsim simulate | plot | run | portrait | ensemble | periodic | lyapunov | animate | explore``.

``noslipsim simulate SCENE.yaml --position X Y --velocity VX VY [--spin W] -n N [-o orbit.nc]``
``noslipsim plot SCENE.yaml --position X Y --velocity VX VY [--spin W] -n N -o orbit.png``
``noslipsim run CONFIG.yaml -o dataset.nc`` (the paper's experiments)
``noslipsim portrait|ensemble|periodic|lyapunov SCENE.yaml ... -o out.nc [--figure out.png]``
(:mod:`.analyses`: every analysis for a scene file of one's own)
``noslipsim animate SCENE.yaml ... -o orbit.gif|mp4``, ``noslipsim explore SCENE.yaml`` (:mod:`.media`)

Every mistake a user can make (a missing or unreadable file, a YAML syntax
error, an unknown key, a wrong type, a start outside the table, a bad number)
ends as one line on stderr, ``noslipsim: error: <what, where, what was
expected>``, with exit status 2.  ``--debug`` shows the Python traceback
instead (for bug reports).  The scene-file format is described in
docs/scenes.md.
"""
from __future__ import annotations

import argparse
import math
import sys

from .._version import __version__
from .options import EXIT_INTERNAL, EXIT_USAGE, _orbit_arguments, _Parser, _start_errors, check_outputs


def _parser():
    p = _Parser(prog="noslipsim", description="noslipsim: no-slip billiards under a force")
    p.add_argument("--version", action="version", version=f"noslipsim {__version__}")
    p.add_argument("--debug", action="store_true", help="show the Python traceback of an error")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    # --debug is also accepted after the subcommand; SUPPRESS keeps the top-level value otherwise
    debug = dict(action="store_true", default=argparse.SUPPRESS, help="show the Python traceback of an error")

    s = sub.add_parser("simulate", help="simulate one orbit of a scene file")
    _orbit_arguments(s, default_n=20)
    s.add_argument("--max-time", type=float, default=math.inf, help="time limit (default: none)")
    s.add_argument("--stop-below", type=float, default=None, help="stop when crossing this height downwards")
    s.add_argument("-o", "--output", help="write the orbit to this netCDF file instead of printing it")
    s.add_argument("--debug", **debug)

    f = sub.add_parser("plot", help="draw the table of a scene file and one orbit in it")
    _orbit_arguments(f, default_n=50)
    f.add_argument("--max-time", type=float, default=math.inf, help="time limit (default: none)")
    f.add_argument("--stop-below", type=float, default=None, help="stop when crossing this height downwards")
    f.add_argument("-o", "--output", required=True,
                   help="image to write; the format follows the extension (.png, .pdf, .svg)")
    f.add_argument("--window", nargs=4, type=float, metavar=("X0", "X1", "Y0", "Y1"),
                   help="region shown (default: the table's elements and the whole orbit)")
    f.add_argument("--spin-every", type=int, default=None, metavar="K",
                   help="draw the particle with a spin arrow on every K-th flight")
    f.add_argument("--debug", **debug)

    r = sub.add_parser("run", help="run one of the paper's experiments from a YAML config and write its dataset",
                       description="Runs one of the paper's experiments (noslipsim.experiments) with keyword "
                                   "parameters from a YAML config. For a scene file of your own use portrait, "
                                   "ensemble, periodic or lyapunov.",
                       epilog="experiments: " + ", ".join(sorted(_experiment_names())))
    r.add_argument("config", help="YAML: {experiment: NAME, parameters: {...}}; NAME one of the experiments below")
    r.add_argument("-o", "--output", required=True, help="netCDF file to write")
    r.add_argument("--debug", **debug)

    from . import analyses, media

    COMMANDS.update(analyses.add_commands(sub, debug))
    COMMANDS.update(media.add_commands(sub, debug))
    return p


def _experiment_names():
    from ..experiments import EXPERIMENTS

    return EXPERIMENTS


# ---------------------------------------------------------------------------- commands
def _simulate(args):
    from ..io import write_dataset
    from ..scenes import Scene
    from ..simulate import simulate

    scene = Scene.from_yaml(args.scene)
    ds = _start_errors(simulate, scene, args.position, args.velocity, args.spin,
                       max_collisions=args.max_collisions, max_time=args.max_time, stop_below=args.stop_below)
    if args.output:
        write_dataset(ds, args.output)
        print(f"wrote {int(ds.n_collisions)} collisions to {args.output} ({ds.attrs['stop_reason']})")
    else:
        _print_table(ds, sys.stdout)


def _plot(args):
    import os

    import matplotlib

    matplotlib.use("Agg")  # files only: no display needed
    import matplotlib.pyplot as plt

    from .. import plot
    from ..scenes import Scene
    from ..simulate import simulate

    if args.window is not None:
        _start_errors(plot.check_window, args.window)
    if args.spin_every is not None and args.spin_every < 1:
        raise ValueError(f"--spin-every: must be >= 1, got {args.spin_every}")
    scene = Scene.from_yaml(args.scene)
    orbit = _start_errors(simulate, scene, args.position, args.velocity, args.spin,
                          max_collisions=args.max_collisions, max_time=args.max_time, stop_below=args.stop_below)
    with plot.style_context():
        fig, ax = plt.subplots(figsize=(5.0, 4.0))
        x, y = plot.orbit_path(orbit)
        window = args.window if args.window is not None else _plot_window(scene, x, y)
        plot.draw_table(ax, scene, window)
        plot.draw_orbit(ax, orbit, spin_every=args.spin_every)
        ax.set_title(f"{os.path.basename(args.scene)}: {scene.law}, {int(orbit.n_collisions)} collisions "
                     f"({orbit.attrs['stop_reason']})", fontsize="small")
        folder = os.path.dirname(os.path.abspath(args.output))
        os.makedirs(folder, exist_ok=True)
        fig.savefig(args.output)
        plt.close(fig)
    print(f"wrote {args.output} ({int(orbit.n_collisions)} collisions, {orbit.attrs['stop_reason']})")


def _plot_window(scene, x, y):
    """The table's elements (lines by their anchor, lattices by a few cells) and the whole orbit."""
    from .. import plot

    return plot.view_window(scene, (x, y))


def _run_experiment(args):
    from .._validate import read_yaml
    from ..experiments import EXPERIMENTS
    from ..io import write_dataset

    cfg, where = read_yaml(args.config, "config")
    if not isinstance(cfg, dict) or "experiment" not in cfg or set(cfg) - {"experiment", "parameters"}:
        raise ValueError(f"{where}: expected a mapping with keys 'experiment' and (optionally) 'parameters', "
                         f"got {_short(cfg)}")
    name = cfg["experiment"]
    if not isinstance(name, str) or name not in EXPERIMENTS:
        raise ValueError(f"{where}: experiment: unknown experiment {name!r}; expected one of {sorted(EXPERIMENTS)}")
    params = cfg.get("parameters") or {}
    if not isinstance(params, dict):
        raise ValueError(f"{where}: parameters: expected a mapping of keyword arguments, got {_short(params)}")
    try:
        ds = EXPERIMENTS[name](**params)
    except TypeError as err:  # an unknown or missing keyword
        raise ValueError(f"{where}: parameters: {err}") from None
    except ValueError as err:
        raise ValueError(f"{where}: parameters: {err}") from None
    write_dataset(ds, args.output, config=cfg)
    print(f"wrote {name} to {args.output}")


def _short(value, size=60):
    text = repr(value)
    return text if len(text) <= size else text[:size - 3] + "..."


def _print_table(ds, out):
    cols = ["t", "x", "y", "vx", "vy", "spin", "element", "s"]
    out.write("  ".join(f"{c:>12}" for c in ["collision", *cols]) + "\n")
    for i in range(ds.sizes["collision"]):
        vals = [f"{i:>12d}"] + [f"{int(ds[c][i]):>12d}" if c == "element" else f"{float(ds[c][i]):>12.6g}"
                               for c in cols]
        out.write("  ".join(vals) + "\n")
    out.write(f"stop_reason: {ds.attrs['stop_reason']}  collisions: {int(ds.n_collisions)}  "
              f"final t={float(ds.t_final):.6g} x={float(ds.x_final):.6g} y={float(ds.y_final):.6g}\n")


COMMANDS = {"simulate": _simulate, "plot": _plot, "run": _run_experiment}


# ---------------------------------------------------------------------------- entry point
def _one_line(err):
    """The message of an error on one line (an OSError as ``path: reason``)."""
    from .._validate import one_line

    return one_line(err)


def main(argv=None):
    """Run the command line; returns the exit status (0, 2 for a user error, 1 for a bug)."""
    args = _parser().parse_args(argv)
    try:
        check_outputs(args)  # a file that cannot be written is refused before any work
        COMMANDS[args.command](args)
    except (ValueError, TypeError, OSError) as err:
        if args.debug:
            raise
        print(f"noslipsim: error: {_one_line(err)}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        if args.debug:
            raise
        print("noslipsim: interrupted", file=sys.stderr)
        return 130
    except Exception as err:  # a bug, not a user error: still one line, with the way to report it
        if args.debug:
            raise
        print(f"noslipsim: internal error: {type(err).__name__}: {_one_line(err)} "
              "(rerun with --debug for the traceback and report it)", file=sys.stderr)
        return EXIT_INTERNAL
    return 0


if __name__ == "__main__":
    sys.exit(main())
