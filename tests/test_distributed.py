"""Ensembles on dask.distributed worker processes: the same bits as a local run; a killed worker changes nothing.

The cluster is started the way a user starts one (docs/cluster.md): ``dask scheduler`` and two
``dask worker`` processes from the shell, all bound to 127.0.0.1.  The oracle is the local
synchronous run (checked against single orbits in test_ensemble.py).
"""
import json
import logging
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import noslipsim as ns
from noslipsim import initial, tables
from noslipsim.experiments import accessible_pair_census, invariant_regions

distributed = pytest.importorskip("distributed")

GALTON = tables.galton_board()
KW = dict(max_collisions=300, stop_below=-30.0, max_time=500.0)
#: The ``dask`` command of this interpreter (its console script may live beside another one, e.g. a venv over
#: system site-packages).
DASK = [sys.executable, "-m", "dask"]


def start_cluster(folder, n_workers=2):
    """``dask scheduler`` and ``n_workers`` ``dask worker`` processes on 127.0.0.1; returns (address, processes)."""
    file = folder / "scheduler.json"
    logs = [open(folder / f"{name}.log", "w") for name in ["scheduler"] + [f"worker{i}" for i in range(n_workers)]]
    procs = [subprocess.Popen([*DASK, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                               "--scheduler-file", str(file)], stdout=logs[0], stderr=subprocess.STDOUT)]
    deadline = time.monotonic() + 60
    while not file.exists() and time.monotonic() < deadline:
        time.sleep(0.1)
    for log in logs[1:]:
        procs.append(subprocess.Popen([*DASK, "worker", "--scheduler-file", str(file), "--host", "127.0.0.1",
                                       "--nthreads", "1", "--no-dashboard", "--memory-limit", "2GiB"],
                                      stdout=log, stderr=subprocess.STDOUT))
    address = json.loads(file.read_text())["address"]
    with distributed.Client(address, timeout=60) as client:
        client.wait_for_workers(n_workers, timeout=60)
    return address, procs


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    address, procs = start_cluster(tmp_path_factory.mktemp("dask"))
    yield address
    for p in reversed(procs):
        p.terminate()
    for p in procs:
        try:
            p.wait(timeout=20)
        except subprocess.TimeoutExpired:
            p.kill()


def test_scheduler_and_workers_listen_on_loopback_only(cluster):
    assert cluster.startswith("tcp://127.0.0.1:")
    with distributed.Client(cluster) as client:
        workers = client.scheduler_info(n_workers=-1)["workers"]
    assert len(workers) == 2 and all(w.startswith("tcp://127.0.0.1:") for w in workers)


def test_the_accessible_pair_census_runs_on_the_cluster_with_the_same_rows(cluster):
    """Figure S6's census, one table per task, by a scheduler address: the rows of the local run."""
    kw = dict(pairs=2, seed=4)
    there = accessible_pair_census(["wedge", "two disks"], scheduler=cluster, **kw)
    here = accessible_pair_census(["wedge", "two disks"], scheduler="sync", **kw)
    for name in ("table", "outcome", "reason", "s0", "s1", "n_found", "linear_kind", "eigen_sum"):
        np.testing.assert_array_equal(there[name].values, here[name].values)


def test_the_invariant_regions_run_on_the_cluster_with_the_same_starts(cluster):
    """Figure S7's starts, every simulate_many call by a scheduler address: the fates of the local run."""
    kw = dict(forces=[0.5], rings=2, starts=3, ring_step=0.3, max_collisions=500, tail=20)
    there = invariant_regions(scheduler=cluster, **kw)
    here = invariant_regions(scheduler="sync", **kw)
    for name in ("start_outcome", "n_collisions", "period", "tail_distance", "orbit_period"):
        np.testing.assert_array_equal(there[name].values, here[name].values)


@pytest.mark.parametrize("record", ["final", "log"])
def test_worker_processes_give_the_local_bits(cluster, record, tmp_path, caplog):
    """... and an undisturbed run reports no lost worker (a cached, worker-less view of the cluster once did)."""
    q, v = np.tile([1.0, 0.0], (40, 1)), initial.unit_velocities(40, 1)
    ref = ns.simulate_many(GALTON, q, v, scheduler="sync", record=record, **KW)
    with caplog.at_level(logging.WARNING, logger="noslipsim.ensemble"):
        assert ns.simulate_many(GALTON, q, v, chunk_size=7, scheduler=cluster, record=record, **KW).identical(ref)
        with distributed.Client(cluster) as client:
            on_disk = ns.simulate_many(GALTON, q, v, chunk_size=6, scheduler=client, record=record, out=tmp_path,
                                       **KW)
            assert on_disk.load().identical(ref)
    assert "left the cluster" not in caplog.text


def test_a_killed_worker_changes_nothing_and_the_log_names_what_was_rerun(tmp_path, caplog):
    """SIGKILL one of two worker processes (by its pid) while chunks run on it.

    Its own cluster: the worker's nanny restarts it, so the next tests would see a changed
    cluster.  Each chunk (3 no-slip Galton particles over a long time) takes about a second."""
    address, procs = start_cluster(tmp_path)
    n, kw = 36, dict(max_time=3000.0, stop_below=-200.0, max_collisions=10**6)
    q, v = np.tile([1.0, 0.0], (n, 1)), initial.unit_velocities(n, 3)
    folder = tmp_path / "chunks"
    killed = {}

    def kill_a_busy_worker():
        with distributed.Client(address) as client:
            while len(list(folder.glob("chunk-*"))) < 2:
                time.sleep(0.02)
            busy = next(w for w, keys in client.processing().items() if keys)
            killed[busy] = client.run(os.getpid, workers=[busy])[busy]
            os.kill(killed[busy], signal.SIGKILL)

    try:
        killer = threading.Thread(target=kill_a_busy_worker, daemon=True)
        killer.start()
        with caplog.at_level(logging.WARNING, logger="noslipsim.ensemble"):
            got = ns.simulate_many(GALTON, q, v, chunk_size=3, scheduler=address, out=folder, **kw)
        killer.join(timeout=10)
        assert killed, "the worker was not killed while the run went on"
        worker = next(iter(killed))
        lost = [r.getMessage() for r in caplog.records if worker in r.getMessage()]
        assert lost and "left the cluster with chunks assigned to it (orbits " in lost[0], caplog.text
        ref = ns.simulate_many(GALTON, q, v, num_workers=2, **kw)
        assert got.load().identical(ref)
        assert len(list(folder.glob("chunk-*"))) == n // 3
    finally:
        for p in procs:
            p.terminate()
        for p in procs:
            p.wait(timeout=30)
