"""Running the lean disk loop and the general loop side by side on one scene (tests of core/disks.py).

Shared by tests/test_disk_lattice.py (one disk per cell) and tests/test_disk_cells.py
(several disks per cell).
"""
import math

import numpy as np

from noslipsim.core import layout
from noslipsim.core.loop import orbit_kernel

LOG, PORTRAIT, NONE = layout.RECORD_LOG, layout.RECORD_PORTRAIT, layout.RECORD_NONE


def kernels(scene, mode):
    """``(general, lean)``: the general path's lattice variant for this scene and the lean loop."""
    flags = scene.kernel_variant(mode)
    assert flags[4] is True
    return orbit_kernel(*flags[:4]), orbit_kernel(*flags)


def run(kernel, scene, q, v, w, n, mode=LOG, max_time=math.inf, level=-math.inf, start_element=-1):
    """Run ``kernel`` from ``q`` (relative to cell 0); returns the 12 outputs and the records."""
    kinds, params, copies, A, B, lattice, jstart, jpts = scene.kernel_inputs()
    c, s = scene.noslip_coefficients
    width = layout.N_PORTRAIT if mode == PORTRAIT else layout.N_LOG
    rec = np.zeros((n if mode != NONE else 0, width))
    mask = np.ones(len(kinds), dtype=np.bool_)
    out = kernel(kinds, params, copies, A, B, lattice, jstart, jpts, scene.law_code, c, s, 0.0, 0.0,
                 q[0], q[1], v[0], v[1], w, n, max_time, level, scene.scale, mode, rec, mask, start_element)
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
