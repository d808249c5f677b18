"""Many orbits in one compiled call.

``run_batch`` loops over orbits with ``prange`` (one parallel call);
``run_batch_serial`` runs the same loop without threads, for dask tasks
(numba's default threading layer must not be entered from several threads at
once).  They are two definitions, not one function compiled twice, because
numba's on-disk cache does not key entries by the ``parallel`` flag.  Orbits
are independent and deterministic, so any split into batches gives identical
results.  Both are built per kernel variant (:func:`loop.orbit_kernel`).
"""
import functools

from .jit import jit, prange
from .loop import GENERAL, orbit_kernel

#: Columns of the per-orbit summary written by the batch kernels.
F_N, F_STOP, F_CORNER, F_NREC, F_T, F_X, F_Y, F_VX, F_VY, F_W, F_CELL1, F_CELL2 = range(12)
N_FINAL = 12


@functools.lru_cache(maxsize=None)
def batch_kernels(flags=GENERAL):
    """``(run_batch, run_batch_serial)`` around the orbit kernel variant ``orbit_kernel(*flags)``.

    ``run_batch`` runs the orbits in parallel (``prange``); ``run_batch_serial``
    one after another.  Arguments: ``starts[i] = (x, y, vx, vy, w)`` relative
    to the start cell; ``start_elements[i]`` is ``-1`` or the element the
    orbit starts on; ``stop_below[i]`` the level (relative to the start cell,
    ``-inf`` for none); ``rec[i]`` receives orbit ``i``'s records; ``final[i]``
    its summary (columns ``F_*``).  Other arguments as in :func:`loop.run_orbit`.
    """
    orbit = orbit_kernel(*flags)

    @jit
    def one(i, kinds, params, copies, A, B, lattice, jstart, jpts, law, c, s, ax, ay, starts, start_elements,
            max_collisions, max_time, stop_below, scale, mode, rec, mask, final):
        n, stop, n_corner, n_rec, t, x, y, vx, vy, w, m1, m2 = orbit(
            kinds, params, copies, A, B, lattice, jstart, jpts, law, c, s, ax, ay,
            starts[i, 0], starts[i, 1], starts[i, 2], starts[i, 3], starts[i, 4],
            max_collisions, max_time, stop_below[i], scale, mode, rec[i], mask, start_elements[i])
        row = final[i]
        row[F_N] = n
        row[F_STOP] = stop
        row[F_CORNER] = n_corner
        row[F_NREC] = n_rec
        row[F_T] = t
        row[F_X] = x
        row[F_Y] = y
        row[F_VX] = vx
        row[F_VY] = vy
        row[F_W] = w
        row[F_CELL1] = m1
        row[F_CELL2] = m2

    @jit(parallel=True)
    def run_batch(kinds, params, copies, A, B, lattice, jstart, jpts, law, c, s, ax, ay, starts, start_elements,
                  max_collisions, max_time, stop_below, scale, mode, rec, mask, final):
        for i in prange(starts.shape[0]):
            one(i, kinds, params, copies, A, B, lattice, jstart, jpts, law, c, s, ax, ay, starts, start_elements,
                max_collisions, max_time, stop_below, scale, mode, rec, mask, final)

    @jit
    def run_batch_serial(kinds, params, copies, A, B, lattice, jstart, jpts, law, c, s, ax, ay, starts,
                         start_elements, max_collisions, max_time, stop_below, scale, mode, rec, mask, final):
        for i in range(starts.shape[0]):
            one(i, kinds, params, copies, A, B, lattice, jstart, jpts, law, c, s, ax, ay, starts, start_elements,
                max_collisions, max_time, stop_below, scale, mode, rec, mask, final)

    return run_batch, run_batch_serial
