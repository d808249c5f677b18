"""The kernels' compile options, names and cache keys (core/jit.py)."""
import fcntl
import importlib
import os
import subprocess
import sys
import threading

import numpy as np
import pytest
from numba.core.errors import TypingError

from noslipsim.core import jit as jit_module
from noslipsim.core.jit import CACHE_LOCK, CoreCache, jit


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


_NAMES = """
from noslipsim.core.batch import batch_kernel
from noslipsim.core.loop import orbit_kernel
from noslipsim.core.variant import FORCE, STRAIGHT, Variant
for flags in [Variant(True, True, 0, False, False, FORCE), Variant(True, True, 0, False, False, STRAIGHT),
              Variant(False, False, 1, False, True, STRAIGHT), Variant(True, True, 2, True, False, STRAIGHT)]:
    for kernel in (batch_kernel(flags), orbit_kernel(*flags)):
        print(kernel.py_func.__qualname__, kernel._uuid)
"""


def test_every_variant_has_its_own_name_and_the_same_in_every_process():
    """numba names a kernel's machine code by its ``__qualname__`` (and a per-process counter).

    Variants built by one factory must not share a name, or two variants first
    compiled in two processes can end up with one symbol, and a process that
    loads both links one to the other's code; and the name must not depend on
    the process, or the cache misses in every new one.
    """
    runs = [subprocess.run([sys.executable, "-c", _NAMES], capture_output=True, text=True, check=True).stdout
            for _ in range(2)]
    assert runs[0] == runs[1]
    names = [line.split()[0] for line in runs[0].splitlines()]
    uuids = [line.split()[1] for line in runs[0].splitlines()]
    assert len(set(names)) == len(names) == 8 and len(set(uuids)) == 8
    assert all("_v" in name.rsplit(".", 1)[-1] for name in names)


def test_a_cache_entry_is_valid_only_for_the_core_sources_it_was_compiled_from(tmp_path, monkeypatch):
    """numba checks only a kernel's own file; a change in any core source must read as a miss."""
    (tmp_path / "probe_kernel.py").write_text(
        "from noslipsim.core.jit import jit\n\n\n@jit\ndef twice(x):\n    return 2.0 * x\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module("probe_kernel")
    assert module.twice(1.5) == 3.0  # compiled and saved
    sig = module.twice.signatures[0]
    context = module.twice.targetctx
    assert CoreCache(module.twice.py_func).load_overload(sig, context) is not None
    monkeypatch.setattr(jit_module, "SOURCE_DIGEST", "another version of the core sources")
    assert CoreCache(module.twice.py_func).load_overload(sig, context) is None


def test_a_cache_write_waits_while_another_process_writes():
    """numba's cache save is an unlocked read-modify-write of the index.

    Two processes compiling two variants of one kernel at once could pick the
    same data file, so that one variant's key loads the other variant's machine
    code in every later process.  Each save holds an exclusive lock beside the
    index: while another holder has it, the save must not touch the index.
    """

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
