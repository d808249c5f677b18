import math

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")  # before pyplot: the tests draw without a display
import matplotlib.pyplot as plt  # noqa: E402

GAMMAS = [0.0, 1e-8, 0.3, 1 / math.sqrt(2), 1.0, 3.0, 100.0]


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
