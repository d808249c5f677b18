"""What the event loops write per collision: a log row or a phase-portrait point (``layout.RECORD_*``)."""
import math

from .geometry import arclength
from .jit import jit
from .layout import (
    LOG_CELL_A1,
    LOG_CELL_A2,
    LOG_CORNER,
    LOG_ELEMENT,
    LOG_S,
    LOG_T,
    LOG_VX,
    LOG_VX_IN,
    LOG_VY,
    LOG_VY_IN,
    LOG_W,
    LOG_W_IN,
    LOG_X,
    LOG_Y,
    POR_ELEMENT,
    POR_S,
    POR_VN,
    POR_VT,
    POR_W,
    RECORD_LOG,
    RECORD_PORTRAIT,
)


@jit
def record(mode, rec, n_rec, mask, t, x, y, ox, oy, m1, m2, vx, vy, w, vx_in, vy_in, w_in,
           kind, p, sx, sy, element, corner, nx, ny):
    """Write one collision into ``rec`` as ``mode`` asks; returns the new record count."""
    if n_rec >= rec.shape[0]:
        return n_rec
    if mode == RECORD_LOG:
        row = rec[n_rec]
        row[LOG_T] = t
        row[LOG_X] = x + ox
        row[LOG_Y] = y + oy
        row[LOG_VX] = vx
        row[LOG_VY] = vy
        row[LOG_W] = w
        row[LOG_VX_IN] = vx_in
        row[LOG_VY_IN] = vy_in
        row[LOG_W_IN] = w_in
        row[LOG_ELEMENT] = element
        row[LOG_S] = arclength(kind, p, x - sx, y - sy)
        row[LOG_CORNER] = corner
        row[LOG_CELL_A1] = m1
        row[LOG_CELL_A2] = m2
        return n_rec + 1
    if mode == RECORD_PORTRAIT and mask[element]:
        row = rec[n_rec]
        vt = -vx * ny + vy * nx
        vn = vx * nx + vy * ny
        norm = math.sqrt(w * w + vt * vt + vn * vn)
        row[POR_ELEMENT] = element
        row[POR_S] = arclength(kind, p, x - sx, y - sy)
        row[POR_W] = w / norm
        row[POR_VT] = vt / norm
        row[POR_VN] = vn / norm
        return n_rec + 1
    return n_rec
