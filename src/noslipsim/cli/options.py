"""What the subcommands share: the one-line argument errors, the start options, their error wording."""
from __future__ import annotations

import argparse

#: Exit status of a user error (as argparse uses for a bad command line).
EXIT_USAGE = 2
#: Exit status of an unexpected failure (a bug: rerun with --debug and report it).
EXIT_INTERNAL = 1

#: API field names as the options that set them, so a message names what the user typed.
_OPTIONS = {
    "position": "--position", "velocity": "--velocity", "spin": "--spin",
    "max_collisions": "-n/--max-collisions", "max_time": "--max-time", "stop_below": "--stop-below",
    "positions": "--position",  # noslipsim ensemble: every orbit starts at --position
    "n_collisions": "-n/--max-collisions",  # noslipsim lyapunov: -n is the run's length in collisions
}


class _Parser(argparse.ArgumentParser):
    """argparse with its errors on one line, in the same form as every other error."""

    def error(self, message):
        self.exit(EXIT_USAGE, f"noslipsim: error: {message} (see '{self.prog} --help')\n")



def _orbit_arguments(p, default_n):
    p.add_argument("scene", help="scene file (YAML; format in docs/scenes.md)")
    p.add_argument("--position", nargs=2, type=float, required=True, metavar=("X", "Y"),
                   help="start point, strictly inside the table")
    p.add_argument("--velocity", nargs=2, type=float, required=True, metavar=("VX", "VY"),
                   help="initial velocity (vx, vy)")
    p.add_argument("--spin", type=float, default=0.0, help="scaled spin w = gamma R omega (CCW positive)")
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
