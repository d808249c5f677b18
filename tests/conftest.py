import math

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")  # before pyplot: the tests draw without a display
import matplotlib.pyplot as plt

GAMMAS = [0.0, 1e-8, 0.3, 1 / math.sqrt(2), 1.0, 3.0, 100.0]

#: The long test files that compile into caches of their own (each minutes, most of it in subprocesses)
#: start first, the docs build (which loads the session's kernels) last: pytest-xdist hands whole groups
#: of tests to its workers in collection order (pyproject: --dist loadgroup, --no-loadscope-reorder).
FIRST = ["test_pipeline.py", "test_slurm.py", "test_compile_cache.py"]
LAST = ["test_docs.py"]
#: Files that use another file's session fixture run in its worker: the reduced pipeline is built once.
SAME_WORKER = {"test_slurm.py": "test_pipeline.py"}


@pytest.hookimpl(tryfirst=True)  # before xdist names the groups
def pytest_collection_modifyitems(items):
    rank = {name: i - len(FIRST) for i, name in enumerate(FIRST)} | {name: 1 + i for i, name in enumerate(LAST)}
    items.sort(key=lambda item: rank.get(item.path.name, 0))  # stable: the rest keep their order
    for item in items:  # one group per file (module fixtures are built in one worker)
        item.add_marker(pytest.mark.xdist_group(SAME_WORKER.get(item.path.name, item.path.name)))


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
@pytest.fixture(scope="session")
def cold_cache(tmp_path_factory):
    """An empty numba cache for the first run, as a new user has it."""
    return tmp_path_factory.mktemp("numba-cache-a")


@pytest.fixture(scope="session")
def repo(tmp_path_factory, cold_cache):
    """A copy of the workflow with the reduced run built in it: two jobs at a time, from an empty cache.

    Shared by test_pipeline.py and test_slurm.py (the local run the SLURM runs must reproduce)."""
    from pipeline_run import snakemake, workflow_copy

    repo = workflow_copy(tmp_path_factory, "pipeline")
    snakemake(repo, "--cores", "2", cache=cold_cache)
    return repo
