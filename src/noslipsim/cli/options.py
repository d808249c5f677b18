"""What the subcommands share: the one-line argument errors, the start options, their error wording."""
from __future__ import annotations

import argparse
import os

#: Exit status of a user error (as argparse uses for a bad command line).
EXIT_USAGE = 2
#: Exit status of an unexpected failure (a bug: rerun with --debug and report it).
EXIT_INTERNAL = 1

#: API field names as the options that set them, so a message names what the user typed.
_OPTIONS = {
    "position": "--position", "velocity": "--velocity", "spin": "--spin",
    "max_collisions": "-n/--max-collisions", "max_time": "--max-time", "stop_below": "--stop-below",
    "positions": "--position",  # noslipsim ensemble: every orbit starts at --position
    # noslipsim animate
    "dpi": "--dpi", "duration": "--duration", "fps": "--fps", "dpi, duration, fps": "--dpi, --duration, --fps",
    "duration, fps": "--duration, --fps", "trail": "--trail", "window": "--window", "radius": "--radius",
    "output": "-o/--output",
    # noslipsim periodic and lyapunov
    "period": "--period", "tol": "--tol", "n_collisions": "-n/--max-collisions",
}

#: What each command writes, by option: a netCDF dataset, an image (matplotlib) or an animation.
OUTPUTS = {
    "simulate": {"output": "dataset"}, "plot": {"output": "image"}, "run": {"output": "dataset"},
    "portrait": {"output": "dataset", "figure": "image"}, "ensemble": {"output": "dataset", "figure": "image"},
    "periodic": {"output": "dataset", "figure": "image"}, "lyapunov": {"output": "dataset", "figure": "image"},
    "animate": {"output": "animation"},
}
_FLAGS = {"output": "-o/--output", "figure": "--figure"}


class _Parser(argparse.ArgumentParser):
    """argparse with its errors on one line, in the same form as every other error."""

    def error(self, message):
        self.exit(EXIT_USAGE, f"noslipsim: error: {message} (see '{self.prog} --help')\n")



def _orbit_arguments(p, default_n):
    """The scene and start options, and ``-n`` (skipped with ``default_n=None``: the command sets the length)."""
    p.add_argument("scene", help="scene file (YAML; format in docs/scenes.md)")
    p.add_argument("--position", nargs=2, type=float, required=True, metavar=("X", "Y"),
                   help="start point, strictly inside the table")
    p.add_argument("--velocity", nargs=2, type=float, required=True, metavar=("VX", "VY"),
                   help="initial velocity (vx, vy)")
    p.add_argument("--spin", type=float, default=0.0, help="scaled spin w = gamma R omega (CCW positive)")
    if default_n is not None:
        p.add_argument("-n", "--max-collisions", type=int, default=default_n,
                       help=f"number of collisions (default {default_n})")


def _start_errors(func, *args, **kwargs):
    """Call ``func``; a ValueError naming an API field is re-worded with the option that sets it."""
    try:
        return func(*args, **kwargs)
    except ValueError as err:
        field, sep, rest = str(err).partition(":")
        if sep and field in _OPTIONS:
            raise ValueError(f"{_OPTIONS[field]}:{rest}") from err
        raise


def check_outputs(args):
    """Check every file the command will write, before any work: its format and that it can be made.

    Raises
    ------
    ValueError
        Naming the option: a format the command does not write, an existing
        folder in its place, or a folder on its way that cannot be made or
        written in.
    """
    for dest, kind in OUTPUTS.get(args.command, {}).items():
        path = getattr(args, dest, None)
        if path is not None:
            _check_folder(os.fspath(path), _FLAGS[dest])
            _check_format(os.fspath(path), kind, _FLAGS[dest])


def _check_format(path, kind, option):
    if kind == "dataset":
        from ..io import check_dataset_path

        check_dataset_path(path, option)
        return
    if kind == "image":
        from matplotlib.backend_bases import FigureCanvasBase

        formats = sorted(FigureCanvasBase.get_supported_filetypes())
    else:
        from ..animation import FORMATS as formats
    ext = os.path.splitext(path)[1].lower().lstrip(".")
    if ext not in formats:
        raise ValueError(f"{option}: unknown {kind} format {ext!r} of {path!r}; expected one of {list(formats)}")


def _check_folder(path, option):
    """The file can be made: no folder in its place, and its nearest existing folder is one that can be written."""
    if os.path.isdir(path):
        raise ValueError(f"{option}: {path!r} is a folder; give the name of the file to write")
    folder = os.path.dirname(os.path.abspath(path))
    while not os.path.exists(folder):  # folders that do not exist yet are made when the file is written
        folder = os.path.dirname(folder)
    if not os.path.isdir(folder):
        raise ValueError(f"{option}: cannot write {path!r}: {folder!r} is a file, not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ValueError(f"{option}: cannot write {path!r}: no permission to write in {folder!r}")
