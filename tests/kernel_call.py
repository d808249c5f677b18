"""One orbit through the package's one kernel call (``noslipsim._engine.run.run_orbits``), for the tests.

``run_kernel`` returns the kernel's twelve outputs as a tuple (counts, stop code
and cells as ints, the rest floats), in the order of ``core.batch.F_*``, and
the record buffer, so a test can compare variants output by output.
"""
import math

import numpy as np

from noslipsim._engine.run import run_orbits
from noslipsim.core import layout

_INTS = (0, 1, 2, 3, 10, 11)  # F_N, F_STOP, F_CORNER, F_NREC, F_CELL1, F_CELL2


def run_kernel(table, flags, q, v, w, n, mode=layout.RECORD_NONE, *, rec=None, mask=None, max_time=math.inf,
               level=-math.inf, start_element=-1):
    """Run the kernel variant ``flags`` of ``table`` from ``(q, v, w)`` (``q`` relative to cell 0).

    ``rec``: a 2-D record buffer written in place (rows x columns), or None.
    Returns the outputs tuple.
    """
    final = run_orbits(table, [[q[0], q[1], v[0], v[1], w]], max_collisions=n, max_time=max_time, levels=[level],
                       start_elements=[start_element], mode=mode, rec=None if rec is None else rec[None],
                       mask=mask, flags=flags)[0]
    return tuple(int(final[k]) if k in _INTS else float(final[k]) for k in range(12))


def record_buffer(mode, rows, fill=0.0):
    """A record buffer for ``mode`` (no rows when nothing is recorded)."""
    width = layout.N_PORTRAIT if mode == layout.RECORD_PORTRAIT else layout.N_LOG
    return np.full((rows if mode != layout.RECORD_NONE else 0, width), fill)
