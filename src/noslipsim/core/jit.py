"""The one place that decides how every kernel is compiled.

All kernels are compiled with ``cache=True`` (compile once per machine),
``nogil=True`` (so dask threads run kernels in parallel) and *without*
fastmath: the event solver relies on IEEE semantics (signed zeros, exact
comparisons, no reassociation of the quadratic formula).

The kernels run without numba's reference-counting runtime (``_nrt=False``):
they allocate nothing and return no arrays, so an array view (``params[e]``)
needs no owner, and every view would otherwise cost an atomic increment and
decrement.  Measured on the event loop: 2 to 5 times faster on plain scenes
(benchmarks/RESULTS.md).  A kernel that allocates fails to compile rather than
running unsafely.  ``NOSLIPSIM_NUMBA_NRT=1`` compiles with the runtime, uncached
(so the on-disk cache never mixes the two), for ``benchmarks/bench_runtime.py``.
"""
import hashlib
import os

from numba import njit, prange  # noqa: F401  (prange re-exported for kernels)

try:
    import fcntl
except ImportError:  # not POSIX: numba's own unlocked writes
    fcntl = None

#: The lock file, in each cache directory, that serialises writes to numba's cache index.
CACHE_LOCK = "noslipsim-cache.lock"

_OPTIONS = dict(cache=True, nogil=True, fastmath=False, error_model="numpy", _nrt=False)
if os.environ.get("NOSLIPSIM_NUMBA_NRT") == "1":
    _OPTIONS.update(cache=False, _nrt=True)


def _stable_uuid(func):
    """A name for the dispatcher of ``func`` that is the same in every process.

    numba keys the on-disk cache of a closure on the pickled contents of its
    cells; a cell holding another kernel pickles that kernel's dispatcher,
    whose identity is a random UUID drawn once per process.  A kernel built
    around another one (the batch loops around an orbit variant) then missed
    the cache in every new process and wrote a new entry each time.  Naming
    each dispatcher by its function and the values its closure captures makes
    the pickle, hence the cache key, reproducible.
    """
    cells = func.__closure__ or ()
    captured = []
    for cell in cells:
        value = cell.cell_contents
        uuid = getattr(value, "_uuid", None)  # another kernel: its own stable name
        captured.append(uuid if isinstance(uuid, str) else repr(value))
    key = "|".join([func.__module__, func.__qualname__, *captured])
    return "noslipsim-" + hashlib.sha256(key.encode()).hexdigest()


def _lock_cache_writes(dispatcher):
    """Make each write to the dispatcher's on-disk cache one step for other processes.

    numba saves an entry by reading the index, choosing the first free data
    file number, writing the index, then the data file, with no lock.  Two
    processes compiling two variants of one kernel at once (two Snakemake
    jobs, two dask workers) can both pick the same number: the index then
    maps one variant's key to the other variant's machine code, and every
    later process loads the wrong kernel without a word.  An exclusive
    ``flock`` on a file beside the index makes the read-modify-write atomic.
    Loads need no lock: numba replaces the index and data files atomically,
    and an index entry whose data is not written yet reads as a miss.
    """
    cache_file = getattr(getattr(dispatcher, "_cache", None), "_cache_file", None)
    if fcntl is None or cache_file is None:
        return
    save = cache_file.save
    lock_path = os.path.join(cache_file._cache_path, CACHE_LOCK)

    def locked_save(key, data):
        try:
            lock = open(lock_path, "a")
        except OSError:  # a read-only cache directory: numba's save fails (quietly) anyway
            return save(key, data)
        with lock:  # released when the file closes
            fcntl.flock(lock, fcntl.LOCK_EX)
            return save(key, data)

    cache_file.save = locked_save


def _compile(func, options):
    dispatcher = njit(**options)(func)
    dispatcher._set_uuid(_stable_uuid(func))
    _lock_cache_writes(dispatcher)
    return dispatcher


def jit(func=None, **overrides):
    """Compile ``func`` with the project's options (decorator, with or without arguments)."""
    options = dict(_OPTIONS, **overrides)
    if func is None:
        return lambda f: _compile(f, options)
    return _compile(func, options)
