"""noslipsim: exact event-driven no-slip and specular billiards under a constant force."""
from ._version import __version__
from .elements import Arc, Circle, Line, Segment
from .scenes import Scene
from .ensemble import simulate_many
from .io import open_dataset, write_dataset
from .simulate import simulate

__all__ = ["__version__", "Arc", "Circle", "Line", "Segment", "Scene", "simulate", "simulate_many", "open_dataset", "write_dataset"]
