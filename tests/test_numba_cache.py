"""The kernel cache is emptied when the core sources change (numba does not track dependencies)."""
from noslipsim import _numba_cache


def test_stale_cache_is_emptied_and_restamped(monkeypatch):
    cache = _numba_cache.CORE / "__pycache__"
    cache.mkdir(exist_ok=True)
    stamp = cache / _numba_cache.STAMP
    stamp.write_text("a digest of other sources")
    stale = cache / "loop.run_orbit-0.py311.nbi"
    stale.write_text("stale index")
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    _numba_cache.invalidate_if_stale()
    assert not stale.exists()
    assert stamp.read_text() == _numba_cache.source_digest()
    fresh = cache / "loop.run_orbit-0.py311.nbi"
    fresh.write_text("current index")
    _numba_cache.invalidate_if_stale()  # sources unchanged: the cache stays
    assert fresh.exists()
    fresh.unlink()
