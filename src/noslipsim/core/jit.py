"""The one place that decides how every kernel is compiled, named and cached.

Every kernel is compiled with ``cache=True``, ``nogil=True`` (threads run kernels in parallel) and
*without* fastmath: the event solver relies on IEEE semantics (signed zeros, exact comparisons, no
reassociation of the quadratic formula).  Kernels allocate nothing and run without numba's
reference-counting runtime (``_nrt=False``: no owner per array view; one that allocates fails to
compile).  ``NOSLIPSIM_NUMBA_NRT=1`` compiles with the runtime, uncached (so the on-disk cache never
mixes the two), for ``benchmarks/bench_runtime.py``.

numba's cache needs three things it does not do (docs/algorithm.md, "One kernel call, and a compile
cache that cannot hand back another variant"): a machine-code symbol of its own per closure variant
(:func:`_name_variant`; numba issue #10486), entries keyed on every ``core`` source
(:class:`CoreCache`) and atomic index writes (:func:`_lock_cache_writes`).  And a guard that trusts
none of it: every orbit kernel returns the variant it was compiled for, with :data:`SOURCE_STAMP`
(:mod:`noslipsim.core.variant`), and the caller refuses a result from any other.
"""
import functools
import hashlib
import os
from pathlib import Path

from numba import config, njit, prange  # noqa: F401  (prange re-exported for kernels)
from numba.core.caching import FunctionCache

from .inline_copy import compile_with_one_copy

try:
    import fcntl
except ImportError:  # not POSIX: numba's own unlocked writes
    fcntl = None

#: The lock file, in each cache directory, that serialises writes to numba's cache index.
CACHE_LOCK = "noslipsim-cache.lock"

_OPTIONS = dict(cache=True, nogil=True, fastmath=False, error_model="numpy", _nrt=False)
if os.environ.get("NOSLIPSIM_NUMBA_NRT") == "1":
    _OPTIONS.update(cache=False, _nrt=True)

CORE = Path(__file__).parent


def source_digest(folder=CORE):
    """SHA-256 of every ``*.py`` file under ``folder``, subfolders included (relative paths and contents,
    in path order): every source a kernel can be built from."""
    h = hashlib.sha256()
    for path in sorted(folder.rglob("*.py"), key=lambda p: p.relative_to(folder).as_posix()):
        h.update(path.relative_to(folder).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()


#: Hash of the compiled core's sources: the cache stamp of every kernel.
SOURCE_DIGEST = source_digest()
#: Its first 32 bits, compiled into every orbit kernel and reported with its variant.
SOURCE_STAMP = int(SOURCE_DIGEST[:8], 16)


class CoreCache(FunctionCache):
    """numba's function cache, valid only for the exact core sources it was compiled from.

    numba stamps an index with its own source file's modification time and size; a different stamp reads as
    an empty index, which the next save replaces.  Adding :data:`SOURCE_DIGEST` to that stamp makes a change
    anywhere in ``core`` do the same.
    """

    def __init__(self, py_func):
        super().__init__(py_func)
        self._cache_file._source_stamp = (self._cache_file._source_stamp, SOURCE_DIGEST)


def _captured(func):
    """What a closure captures, as stable text: another kernel by its stable name, a value by its repr."""
    out = []
    for cell in func.__closure__ or ():
        value = cell.cell_contents
        uuid = getattr(value, "_uuid", None)
        out.append(uuid if isinstance(uuid, str) else repr(value))
    return out


def _variant_tag(func):
    """A short hash of a closure's factory and of what it captures: the same in every process."""
    key = "|".join([func.__module__, func.__qualname__, *_captured(func)])
    return hashlib.sha256(key.encode()).hexdigest()[:20]


def _name_variant(func):
    """Give a closure a ``__qualname__`` of its own, so that its machine-code symbol names this variant only.

    ``orbit_kernel.<locals>.run_orbit`` becomes ``orbit_kernel.<locals>.run_orbit_v<tag>``;
    numba derives the symbol, the cache file name and the index key from it.
    A function defined at module level is unique by its module and name already.
    """
    if func.__closure__:
        func.__qualname__ = f"{func.__qualname__}_v{_variant_tag(func)}"
        func.__name__ = func.__qualname__.rsplit(".", 1)[-1]


def _lock_cache_writes(dispatcher):
    """Make each write to the dispatcher's on-disk cache one step for other processes.

    numba saves an entry by reading the index, choosing the first free data file number, writing the index,
    then the data file, with no lock: two processes compiling two variants at once (two Snakemake jobs) could
    pick the same number.  An exclusive ``flock`` beside the index makes the read-modify-write atomic.  Loads
    need no lock: numba replaces both files atomically, and an entry whose data is not written yet is a miss.
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
    if config.DISABLE_JIT:  # NUMBA_DISABLE_JIT=1: kernels run as the Python they are (debugging, coverage)
        return func
    _name_variant(func)
    dispatcher = njit(**options)(func)
    # the dispatcher's identity, pickled into the cache key of a closure that calls it (numba keys a
    # closure on its pickled cells; the default identity is a random UUID drawn once per process)
    dispatcher._set_uuid("noslipsim-" + hashlib.sha256(
        f"{func.__module__}|{func.__qualname__}".encode()).hexdigest())
    if options.get("cache"):
        dispatcher._cache = CoreCache(dispatcher.py_func)
        _lock_cache_writes(dispatcher)
    compile_with_one_copy(dispatcher)  # numba's inliner copies a callee's scope once per block (inline_copy)
    return dispatcher


def jit(func=None, **overrides):
    """Compile ``func`` with the project's options (decorator, with or without arguments)."""
    options = dict(_OPTIONS, **overrides)
    if func is None:
        return lambda f: _compile(f, options)
    return _compile(func, options)


#: :func:`jit` inlined at every call site (``inline="always"``).
INLINE_ALWAYS = functools.partial(jit, inline="always")
#: :func:`jit` out of line, as a decorator of its own: a factory that takes ``compile=jit`` to mean "as the
#: flight says" (:func:`search.cell_search`) compiles out of line when passed this.
OUT_OF_LINE = functools.partial(jit)


def inlined(inline):
    """The decorator of a factory's instance: :data:`INLINE_ALWAYS` where ``inline`` (a walk near the loop),
    else :data:`OUT_OF_LINE` (a far walk few flights take)."""
    return INLINE_ALWAYS if inline else OUT_OF_LINE
