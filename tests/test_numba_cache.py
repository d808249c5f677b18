"""The kernel cache is emptied when the core sources change (numba does not track dependencies)."""
import shutil

from noslipsim import _numba_cache


def test_stale_cache_is_emptied_and_restamped(monkeypatch, tmp_path):
    core = tmp_path / "core"
    shutil.copytree(_numba_cache.CORE, core, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(_numba_cache, "CORE", core)
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    cache = core / "__pycache__"
    cache.mkdir()
    stamp = cache / _numba_cache.STAMP
    kernel = cache / "loop.orbit_kernel.locals.run_orbit-0.py311.nbi"

    kernel.write_text("index")
    _numba_cache.invalidate_if_stale()  # no stamp yet: nothing proves the cache current
    assert not kernel.exists() and stamp.read_text() == _numba_cache.source_digest()

    kernel.write_text("index")
    _numba_cache.invalidate_if_stale()  # sources unchanged: the cache stays
    assert kernel.exists()

    (core / "events.py").write_text((core / "events.py").read_text() + "\n# changed\n")
    _numba_cache.invalidate_if_stale()  # a dependency changed: the cache goes
    assert not kernel.exists() and stamp.read_text() == _numba_cache.source_digest()
