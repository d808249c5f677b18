import math

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")  # before pyplot: the tests draw without a display
import matplotlib.pyplot as plt  # noqa: E402

GAMMAS = [0.0, 1e-8, 0.3, 1 / math.sqrt(2), 1.0, 3.0, 100.0]

#: The longest test files (each several minutes from a cold cache, most of it in subprocesses), started
#: first: pytest-xdist hands whole files to its workers in this order (pyproject: --dist loadfile,
#: --no-loadscope-reorder), so no long file starts last while the other worker idles.
LONGEST_FIRST = ["test_pipeline.py", "test_compile_cache.py", "test_slurm.py", "test_docs.py",
                 "test_distributed.py", "test_explorer_browser.py", "test_ablation.py"]


def pytest_collection_modifyitems(items):
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))  # stable: the rest keep their order


@pytest.fixture
def rng():
    return np.random.default_rng(20261122)


@pytest.fixture
def ax():
    """A fresh matplotlib axes, closed after the test."""
    fig, ax = plt.subplots()
    yield ax
    plt.close(fig)
