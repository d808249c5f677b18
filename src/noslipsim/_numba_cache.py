"""Keep numba's on-disk cache of the kernels consistent with their sources.

numba keys a cached kernel on its own source file only: when a kernel it
calls changes in another module (``events.py`` under ``loop.py``, say), the
stale machine code is loaded silently.  At import, the cache of
``noslipsim/core`` is stamped with a hash of all the core sources and emptied
when they differ.  Races between processes are harmless (numba recompiles
what it cannot load); a read-only install or ``NUMBA_CACHE_DIR`` (a cache
elsewhere) is left alone.
"""
import hashlib
import os
from pathlib import Path

CORE = Path(__file__).parent / "core"
STAMP = "noslipsim-core-sources.sha256"


def source_digest():
    h = hashlib.sha256()
    for path in sorted(CORE.glob("*.py")):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def invalidate_if_stale():
    """Empty ``core/__pycache__`` of numba files if the core sources changed since they were cached."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    cache = CORE / "__pycache__"
    stamp = cache / STAMP
    try:
        digest = source_digest()
        if stamp.is_file() and stamp.read_text() == digest:
            return
        cache.mkdir(exist_ok=True)
        for pattern in ("*.nbi", "*.nbc"):
            for f in cache.glob(pattern):
                try:
                    f.unlink()
                except FileNotFoundError:
                    pass
        tmp = cache / f".{STAMP}.{os.getpid()}"
        tmp.write_text(digest)
        os.replace(tmp, stamp)
    except OSError:
        pass
