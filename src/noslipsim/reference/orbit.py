"""The result of a reference run: :class:`ReferenceOrbit` and its dataset layout."""
from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from .._metadata import annotate
from .._version import __version__
from ..core.layout import STOP_REASONS
from ..scenes import Scene

#: Variables recorded per collision (all mpf), in the order of :func:`noslipsim.simulate`.
RECORDED = ("t", "x", "y", "vx", "vy", "spin", "vx_in", "vy_in", "spin_in", "s", "energy")
FINAL = ("t", "x", "y", "vx", "vy", "spin")


@dataclass
class ReferenceOrbit:
    """A reference orbit at full working precision.

    Attributes
    ----------
    records : dict of str to list of mpf
        Per collision: ``t, x, y, vx, vy, spin`` (just after), ``vx_in, vy_in,
        spin_in`` (just before), ``s`` (arclength on the element) and ``energy``
        ``(|v|^2 + w^2)/2 - a.q``.
    element, corner : list of int
        Element index of each collision and 1 where the corner rule resolved it.
    cells : list of (int, int)
        Periodic scenes: the cell ``(cell_a1, cell_a2)`` holding each collision point.
    final : dict of str to mpf
        ``t, x, y, vx, vy, spin`` where the orbit ended.
    final_cell : (int, int)
        Periodic scenes: the cell holding the final position.
    stop_reason : str
        One of :data:`noslipsim.core.layout.STOP_REASONS`, or ``'pinned'`` (a magnetic
        orbit whose cyclotron circle meets no element: :data:`noslipsim.reference.magnetic.PINNED`).
    n_corner : int
        Number of corner collisions.
    dps : int
        Working precision in decimal digits.
    """

    scene: Scene
    dps: int
    start: dict
    records: dict = field(default_factory=lambda: {k: [] for k in RECORDED})
    element: list = field(default_factory=list)
    corner: list = field(default_factory=list)
    cells: list = field(default_factory=list)
    final: dict = field(default_factory=dict)
    final_cell: tuple = (0, 0)
    stop_reason: str = STOP_REASONS[0]
    n_corner: int = 0

    def __len__(self):
        return len(self.element)

    def to_dataset(self):
        """The orbit as an ``xarray.Dataset`` laid out like :func:`noslipsim.simulate` (float64 values)."""
        dim = ("collision",)
        n = len(self.element)
        data = {k: (dim, np.array([float(v) for v in self.records[k]], dtype=float).reshape(n))
                for k in RECORDED}
        data["element"] = (dim, np.array(self.element, dtype=np.int32).reshape(n))
        data["corner"] = (dim, np.array(self.corner, dtype=np.int8).reshape(n))
        for k in FINAL:
            data[f"{k}_final"] = ((), float(self.final[k]))
        data["n_collisions"] = ((), n)
        if self.scene.lattice is not None:
            cells = np.array(self.cells, dtype=np.int64).reshape(n, 2)
            data["cell_a1"] = (dim, cells[:, 0])
            data["cell_a2"] = (dim, cells[:, 1])
            data["cell_a1_final"] = ((), np.int64(self.final_cell[0]))
            data["cell_a2_final"] = ((), np.int64(self.final_cell[1]))
        ds = xr.Dataset(data, coords={"collision": np.arange(n)})
        scene = self.scene
        ds.attrs.update(
            title="noslipsim reference orbit",
            source=f"noslipsim {__version__}",
            stop_reason=self.stop_reason,
            n_corner=int(self.n_corner),
            law=scene.law,
            gamma=scene.gamma,
            force=list(scene.force),
            scene=scene.to_json(),
            start=json.dumps(self.start),
            dps=int(self.dps),
        )
        return annotate(ds)
