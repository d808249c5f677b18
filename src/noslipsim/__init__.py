"""noslipsim: exact event-driven no-slip and specular billiards under a constant force."""
import importlib

from ._version import __version__
from .elements import Arc, Circle, Line, Segment
from .scenes import Scene
from .ensemble import simulate_many
from .io import open_dataset, write_dataset
from .simulate import simulate

__all__ = ["__version__", "Arc", "Circle", "Line", "Segment", "Scene", "simulate", "simulate_many", "open_dataset",
           "write_dataset", "explore"]

#: Submodules reachable as attributes (``ns.experiments``), imported on first use so ``import noslipsim`` stays quick.
_SUBMODULES = ("analysis", "animation", "experiments", "initial", "io", "plot", "reference", "sphere3d", "tables",
               "theory")


def explore(scene, **options):
    """The explorer of ``scene`` in a notebook (:func:`noslipsim.explorer.explore`; needs the ``explore`` extra)."""
    from .explorer import explore as _explore

    return _explore(scene, **options)


def __getattr__(name):
    if name in _SUBMODULES:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'noslipsim' has no attribute {name!r}")
