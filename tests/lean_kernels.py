"""Running the lean disk loop and the general loop side by side on one scene (tests of core/disks.py).

Shared by tests/test_disk_lattice.py (one disk per cell) and tests/test_disk_cells.py
(several disks per cell).
"""
import math

import numpy as np
from kernel_call import record_buffer, run_kernel

from noslipsim._engine.table import kernel_table
from noslipsim.core import layout

LOG, PORTRAIT, NONE = layout.RECORD_LOG, layout.RECORD_PORTRAIT, layout.RECORD_NONE


def kernels(scene, mode):
    """``(general, lean)``: the flags of the general path's lattice variant for this scene and of the lean loop."""
    flags = kernel_table(scene).variant(mode)
    assert flags.disks is True
    return flags._replace(disks=False, walls=None, mixed=None), flags


def run(flags, scene, q, v, w, n, mode=LOG, max_time=math.inf, level=-math.inf, start_element=-1):
    """Run the kernel variant ``flags`` from ``q`` (relative to cell 0); returns the 12 outputs and the records."""
    table = kernel_table(scene)
    rec = record_buffer(mode, n)
    mask = np.ones(len(table.kinds), dtype=np.bool_)
    out = run_kernel(table, flags, q, v, w, n, mode, rec=rec, mask=mask, max_time=max_time, level=level,
                     start_element=start_element)
    return out, rec


#: The stop reason each stop case of the tests must end with.
EXPECTED_STOP = {"max_time": layout.STOP_MAX_TIME, "level": layout.STOP_LEVEL, "escape": layout.STOP_ESCAPE,
                 "start_on_disk": layout.STOP_MAX_TIME}


def same_stop(scene, stop, q, v, kw):
    """Run both loops from the same start to ``stop``; assert the same reason, count, cells and end state.

    Returns the general loop's outputs (the callers check their collision counts).
    """
    general, lean = kernels(scene, NONE)
    out_g = run(general, scene, q, v, 0.1, 1000, mode=NONE, **kw)[0]
    out_l = run(lean, scene, q, v, 0.1, 1000, mode=NONE, **kw)[0]
    assert out_g[1] == out_l[1] == EXPECTED_STOP[stop]
    assert out_l[0] == out_g[0] and out_l[10:] == out_g[10:]
    if stop == "level":
        assert out_l[6] == kw["level"]
    np.testing.assert_allclose(out_l[4:10], out_g[4:10], rtol=1e-9, atol=1e-9)
    return out_g
