"""The kernels' compile options (core/jit.py)."""
import numpy as np
import pytest
from numba.core.errors import TypingError

from noslipsim.core.jit import jit


def test_kernels_run_without_the_reference_counting_runtime():
    """Views of the scene arrays carry no reference counts, so a kernel must not allocate: it is refused."""

    def row_sum(a):
        p = a[1]
        return p[0] + p[1]

    assert jit(cache=False)(row_sum)(np.arange(4.0).reshape(2, 2)) == 5.0

    def allocates(n):
        return np.zeros(n).sum()

    with pytest.raises(TypingError):
        jit(cache=False)(allocates)(3)
