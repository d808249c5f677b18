import fcntl
import math
import os
import shutil

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")  # before pyplot: the tests draw without a display
import matplotlib.pyplot as plt

GAMMAS = [0.0, 1e-8, 0.3, 1 / math.sqrt(2), 1.0, 3.0, 100.0]

#: The long test files that compile into caches of their own (minutes each, most of it in subprocesses)
#: start first; last the SLURM tests (they wait for the reduced pipeline the first file builds) and the
#: docs build (it loads the kernels the session compiled): pytest-xdist hands whole files to its workers
#: in collection order (pyproject: --dist loadfile, --no-loadscope-reorder).
FIRST = ["test_pipeline.py", "test_compile_cache.py"]
LAST = ["test_slurm.py", "test_docs.py"]


def pytest_collection_modifyitems(items):
    rank = {name: i - len(FIRST) for i, name in enumerate(FIRST)} | {name: 1 + i for i, name in enumerate(LAST)}
    items.sort(key=lambda item: rank.get(item.path.name, 0))  # stable: the rest keep their order


@pytest.fixture
def rng():
    return np.random.default_rng(20261122)


@pytest.fixture
def ax():
    """A fresh matplotlib axes, closed after the test."""
    fig, ax = plt.subplots()
    yield ax
    plt.close(fig)


# ---------------------------------------------------------------- the reduced pipeline, built once
def _session_folder(tmp_path_factory):
    """A folder of this test session that every pytest-xdist worker sees (each has a basetemp of its own)."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


@pytest.fixture(scope="session")
def repo(tmp_path_factory):
    """A copy of the workflow with the reduced run built in it: two jobs at a time.

    Its jobs use the test session's numba cache (``NUMBA_CACHE_DIR`` if set, else numba's default
    beside the sources), empty when CI starts: a variant the pipeline compiles the tests load, and the
    other way round, instead of compiling it twice (a cache of the pipeline's own cost CI minutes).
    Every job and test process thus loads variants other processes compiled, the compile-cache issue's
    case; tests/test_compile_cache.py compiles each variant in a process and a fresh cache of its own.

    Shared by test_pipeline.py and test_slurm.py (the local run the SLURM runs must reproduce), which
    pytest-xdist may run in different workers: the first to ask builds it under a file lock, the
    other waits for it and reuses it."""
    from pipeline_run import copy_workflow, snakemake

    shared = _session_folder(tmp_path_factory)
    repo, built = shared / "pipeline", shared / "pipeline.built"
    with open(shared / "pipeline.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not built.exists():
            shutil.rmtree(repo, ignore_errors=True)  # a half-built run of a worker that failed
            snakemake(copy_workflow(repo), "--cores", "2")
            built.touch()
    return repo
