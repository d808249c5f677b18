import math

import numpy as np
import pytest

GAMMAS = [0.0, 1e-8, 0.3, 1 / math.sqrt(2), 1.0, 3.0, 100.0]


@pytest.fixture
def rng():
    return np.random.default_rng(20261122)
