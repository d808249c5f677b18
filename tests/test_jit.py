"""The kernels' compile options (core/jit.py)."""
import numpy as np
import pytest
from numba.core.errors import TypingError

from noslipsim.core.jit import jit


def test_kernels_run_without_the_reference_counting_runtime():
    """Views of the scene arrays carry no reference counts, so a kernel must not allocate: it is refused."""

    def row_sum(a):
        p = a[1]
        return p[0] + p[1]

    assert jit(cache=False)(row_sum)(np.arange(4.0).reshape(2, 2)) == 5.0

    def allocates(n):
        return np.zeros(n).sum()

    with pytest.raises(TypingError):
        jit(cache=False)(allocates)(3)


_CACHE_KEY = """
import hashlib
from numba.core.serialize import dumps
from noslipsim.core.batch import batch_kernels
from noslipsim.core.loop import kernel_flags
for flags in [kernel_flags(True, True, True, 0), kernel_flags(False, False, False, 1), kernel_flags(False, True, True, 2, True)]:
    run_batch, run_batch_serial = batch_kernels(flags)
    one = run_batch.py_func.__closure__[0].cell_contents  # the per-orbit step, around the orbit kernel
    for kernel in (run_batch, one):
        cells = tuple(c.cell_contents for c in kernel.py_func.__closure__)
        print(hashlib.sha256(dumps(cells)).hexdigest())
"""


def test_kernels_built_around_kernels_have_the_same_cache_key_in_every_process():
    """numba keys a closure's cache entry on its pickled cells; a cell holding a kernel must pickle alike.

    Otherwise every new process (each Snakemake job, each dask worker) misses
    the on-disk cache of the batch loops, recompiles them and adds an entry.
    """
    import subprocess
    import sys

    keys = [subprocess.run([sys.executable, "-c", _CACHE_KEY], capture_output=True, text=True, check=True).stdout
            for _ in range(2)]
    assert keys[0] == keys[1]
    assert len(set(keys[0].split())) == 6  # and the three variants, at both levels, stay apart


def test_a_cache_write_waits_while_another_process_writes():
    """numba's cache save is an unlocked read-modify-write of the index.

    Two processes compiling two variants of one kernel at once could pick the
    same data file, so that one variant's key loads the other's machine code
    in every later process (seen: a no-slip batch kernel that ran the specular
    law).  Each save now holds an exclusive lock beside the index: while
    another holder has it, the save must not touch the index.
    """
    import fcntl
    import os
    import threading

    from noslipsim.core.jit import CACHE_LOCK

    def cached_twice(x):
        return 2.0 * x

    cache_file = jit(cached_twice)._cache._cache_file
    lock_path = os.path.join(cache_file._cache_path, CACHE_LOCK)
    key = ("a key no kernel has",)
    saved = threading.Event()
    worker = threading.Thread(target=lambda: (cache_file.save(key, [1.0, 2.0]), saved.set()))
    try:
        with open(lock_path, "a") as held:
            fcntl.flock(held, fcntl.LOCK_EX)  # another process is writing
            worker.start()
            assert not saved.wait(0.5)
            assert cache_file.load(key) is None
        worker.join(30)
        assert saved.is_set()
        assert cache_file.load(key) == [1.0, 2.0]
    finally:
        for name in os.listdir(cache_file._cache_path):
            if name.startswith(cache_file._index_name.rsplit(".", 1)[0]):
                os.remove(os.path.join(cache_file._cache_path, name))
