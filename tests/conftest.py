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
