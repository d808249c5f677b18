"""Ensembles on disk (simulate_many(out=...)): the same dataset as in memory, a killed run resumes to the same bits.

The oracle is the in-memory run (itself checked against single orbits in test_ensemble.py):
orbits are independent and deterministic, so writing chunk files, killing the run and
starting it again must change nothing, to the bit.
"""
import math
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import noslipsim as ns
from noslipsim import initial, tables
from noslipsim.experiments import galton_distribution

GALTON = tables.galton_board()
KW = dict(max_collisions=300, stop_below=-30.0, max_time=500.0)


def galton_starts(n, seed=1):
    return np.tile([1.0, 0.0], (n, 1)), initial.unit_velocities(n, seed)


def chunk_files(folder):
    return sorted(p for p in os.listdir(folder) if p.startswith("chunk-"))


@pytest.mark.parametrize("record", ["final", "log"])
def test_out_folder_holds_the_in_memory_dataset(tmp_path, record):
    q, v = galton_starts(50)
    ref = ns.simulate_many(GALTON, q, v, scheduler="sync", record=record, **KW)
    lazy = ns.simulate_many(GALTON, q, v, chunk_size=7, out=tmp_path / "run", record=record, **KW)
    assert len(chunk_files(tmp_path / "run")) == 8                     # ceil(50 / 7)
    assert lazy.x_final.chunks is not None                              # read lazily, not loaded
    assert lazy.load().identical(ref)


def test_lazy_starts_give_the_same_chunks_and_the_same_dataset(tmp_path):
    v = initial.unit_velocities(1000, 5)
    lazy = initial.UnitVelocities(1000, 5)
    for a, b in [(0, 1000), (0, 1), (333, 777), (999, 1000), (990, 2000)]:
        np.testing.assert_array_equal(lazy[a:b], v[a:b])
    q = np.broadcast_to([1.0, 0.0], (40, 2))                            # one start, no copies
    ref = ns.simulate_many(GALTON, q, initial.unit_velocities(40, 5), scheduler="sync", **KW)
    got = ns.simulate_many(GALTON, q, initial.UnitVelocities(40, 5), chunk_size=9, out=tmp_path, **KW)
    assert got.load().identical(ref)
    with pytest.raises(TypeError, match="slices"):
        lazy[3]


def test_a_second_run_computes_nothing_and_a_missing_chunk_only_that(tmp_path, capfd):
    q, v = galton_starts(30)
    first = ns.simulate_many(GALTON, q, v, chunk_size=10, out=tmp_path, **KW).load()
    files = chunk_files(tmp_path)
    stamps = {f: os.stat(tmp_path / f).st_mtime_ns for f in files}
    os.remove(tmp_path / files[1])
    (tmp_path / ".tmp-left-by-a-killed-run.nc").write_bytes(b"partial")
    capfd.readouterr()
    again = ns.simulate_many(GALTON, q, v, chunk_size=10, out=tmp_path, progress=True, **KW).load()
    err = capfd.readouterr().err
    assert "2 of 3 chunks already done; computing 1" in err
    assert again.identical(first)
    assert {f: os.stat(tmp_path / f).st_mtime_ns for f in (files[0], files[2])} == {f: stamps[f] for f in
                                                                                  (files[0], files[2])}
    assert not list(tmp_path.glob(".tmp-*"))


def test_a_folder_of_another_run_is_refused(tmp_path):
    q, v = galton_starts(20)
    ns.simulate_many(GALTON, q, v, chunk_size=10, out=tmp_path, **KW)
    with pytest.raises(ValueError, match=r"another run.*max_collisions|limits"):
        ns.simulate_many(GALTON, q, v, chunk_size=10, out=tmp_path, **{**KW, "max_collisions": 301})
    with pytest.raises(ValueError, match="chunk_size"):
        ns.simulate_many(GALTON, q, v, chunk_size=5, out=tmp_path, **KW)
    with pytest.raises(ValueError, match="other initial states"):
        ns.simulate_many(GALTON, q, galton_starts(20, seed=2)[1], chunk_size=10, out=tmp_path, **KW)


def test_bad_starts_name_the_orbit_and_its_chunk(tmp_path):
    q, v = galton_starts(20)
    q = q.copy()
    q[13] = [0.0, 0.0]                                                   # the centre of a peg
    with pytest.raises(ValueError, match="orbits 10-19: positions: orbit 3"):
        ns.simulate_many(GALTON, q, v, chunk_size=10, out=tmp_path, **KW)
    with pytest.raises(ValueError, match="velocities: expected shape"):
        ns.simulate_many(GALTON, q, v[:5], out=tmp_path / "b", **KW)


def test_progress_reports_chunks_and_an_eta(tmp_path, capfd):
    q, v = galton_starts(40)
    ns.simulate_many(GALTON, q, v, chunk_size=10, out=tmp_path, progress=True, scheduler="sync", **KW)
    lines = capfd.readouterr().err.strip().splitlines()
    assert lines[-1].startswith("[noslipsim] chunks 4/4 (100%), elapsed ") and "ETA 0:00" in lines[-1]


CHILD = textwrap.dedent("""
    import sys
    import numpy as np
    import noslipsim as ns
    from noslipsim import initial, tables
    n, folder = int(sys.argv[1]), sys.argv[2]
    ns.simulate_many(tables.galton_board(), np.broadcast_to([1.0, 0.0], (n, 2)), initial.UnitVelocities(n, 3),
                     max_time=3000.0, stop_below=-200.0, max_collisions=10**6, chunk_size=4,
                     out=folder, scheduler="sync", progress=True)
""")


def test_a_run_killed_mid_way_resumes_to_the_same_bits(tmp_path):
    """SIGKILL a run (in its own process) once a few chunks are on disk, run it again, compare.

    Each chunk holds 4 no-slip Galton particles over a long time (some trapped), about a
    second of work, so the kill lands with chunks on disk and chunks missing."""
    n, folder = 40, tmp_path / "run"
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(n), str(folder)], stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while (not folder.exists() or len(chunk_files(folder)) < 2) and time.monotonic() < deadline:
        assert child.poll() is None, child.stderr.read()
        time.sleep(0.02)
    os.kill(child.pid, signal.SIGKILL)
    child.wait()
    kept = chunk_files(folder)
    assert 2 <= len(kept) < n // 4, kept                                # killed mid-way
    resumed = ns.simulate_many(GALTON, np.broadcast_to([1.0, 0.0], (n, 2)), initial.UnitVelocities(n, 3),
                               max_time=3000.0, stop_below=-200.0, max_collisions=10**6, chunk_size=4,
                               out=folder, num_workers=2).load()
    whole = ns.simulate_many(GALTON, np.tile([1.0, 0.0], (n, 1)), initial.unit_velocities(n, 3), max_time=3000.0,
                             stop_below=-200.0, max_collisions=10**6, num_workers=2)
    assert resumed.identical(whole)
    assert len(chunk_files(folder)) == n // 4


def test_galton_distribution_through_disk_is_the_in_memory_one(tmp_path):
    kw = dict(rows=3, max_time=200.0, seed=4, radius=0.89)
    ref = galton_distribution(60, **kw)
    got = galton_distribution(60, **kw, out=tmp_path, chunk_size=16)
    assert got.x_terminal.chunks is not None
    assert got.load().identical(ref)
    assert sorted(os.listdir(tmp_path)) == [f"no-slip-{1 / math.sqrt(2)!r}", "specular"]
