"""Many orbits in one compiled call: ``batch_kernel(flags)`` runs them one after another.

Parallel runs call it on several threads at once, one block of orbits each (it releases the GIL), not
numba's ``prange`` (docs/algorithm.md, "One kernel call, and a compile cache ..."); orbits are
independent and deterministic, so any split into blocks gives identical results.
"""
import functools

from .jit import jit
from .loop import orbit_kernel
from .variant import GENERAL

#: Columns of the per-orbit summary written by the batch kernel.
F_N, F_STOP, F_CORNER, F_NREC, F_T, F_X, F_Y, F_VX, F_VY, F_W, F_CELL1, F_CELL2, F_VARIANT = range(13)
N_FINAL = 13


@functools.cache
def batch_kernel(flags=GENERAL):
    """The batch loop around the orbit kernel variant ``orbit_kernel(*flags)`` (``flags``: a :class:`variant.Variant`).

    Arguments: ``starts[i] = (x, y, vx, vy, w)`` relative to the start cell; ``start_elements[i]`` is ``-1`` or the
    element the orbit starts on; ``stop_below[i]`` the level (relative to the start cell, ``-inf`` for none); ``rec[i]``
    receives orbit ``i``'s records; ``final[i]`` its summary (columns ``F_*``; ``F_VARIANT`` is what the orbit kernel
    that ran reports, :func:`variant.report`); ``ceilings[i]`` the top of a bounded lattice relative to the start cell
    (``inf`` for none); ``W`` the magnetic field's cyclotron frequency (0 for none).  Other arguments as in
    :func:`loop.run_orbit`.
    """
    orbit = orbit_kernel(*flags)

    @jit
    def run_batch(kinds, params, copies, A, B, lattice, jstart, jpts, law, c, s, ax, ay, thermostat, starts,
                  start_elements, max_collisions, max_time, stop_below, scale, mode, rec, mask, final, ceilings, W):
        for i in range(starts.shape[0]):
            n, stop, n_corner, n_rec, t, x, y, vx, vy, w, m1, m2, variant = orbit(
                kinds, params, copies, A, B, lattice, jstart, jpts, law, c, s, ax, ay, thermostat,
                starts[i, 0], starts[i, 1], starts[i, 2], starts[i, 3], starts[i, 4],
                max_collisions, max_time, stop_below[i], scale, mode, rec[i], mask, start_elements[i], ceilings[i], W)
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
            row[F_VARIANT] = variant

    return run_batch
