"""noslipsim: exact event-driven no-slip and specular billiards under a constant force."""
import importlib
from typing import Any

from ._version import __version__
from .elements import Arc, Circle, Line, Segment
from .ensemble import simulate_many
from .io import open_dataset, write_dataset
from .scenes import Scene
from .simulate import simulate

__all__ = ["Arc", "Circle", "Line", "Scene", "Segment", "__version__", "explore", "open_dataset", "simulate",
           "simulate_many", "write_dataset"]

#: Submodules reachable as attributes (``ns.experiments``), imported on first use so ``import noslipsim`` stays quick.
_SUBMODULES = ("analysis", "animation", "experiments", "initial", "io", "plot", "reference", "sphere3d", "tables",
               "theory")


def explore(scene: Scene, **options: Any) -> Any:
    """The explorer of ``scene`` in a notebook (:func:`noslipsim.explorer.explore`; needs the ``explore`` extra).

    Returns the Panel layout of the app (shown by a notebook cell; ``.show()`` opens a browser tab).
    """
    from .explorer import explore as _explore

    return _explore(scene, **options)


def __getattr__(name):
    if name in _SUBMODULES:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'noslipsim' has no attribute {name!r}")
