"""Small input checks shared by the public layer: each error names the field."""
import math

import numpy as np


def finite_float(value, field):
    """``value`` as a finite float, or ``ValueError`` naming ``field``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{field}: expected a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{field}: must be finite, got {x}")
    return x


def finite_vector(value, field, size=2):
    """``value`` as a finite float vector of length ``size``."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{field}: expected {size} numbers, got {value!r}") from None
    if arr.shape != (size,):
        raise ValueError(f"{field}: expected {size} numbers, got {value!r}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{field}: must be finite, got {value!r}")
    return arr


def no_unknown_keys(mapping, allowed, where):
    """Reject keys of ``mapping`` outside ``allowed``."""
    if not isinstance(mapping, dict):
        raise ValueError(f"{where}: expected a mapping, got {type(mapping).__name__}")
    unknown = sorted(set(mapping) - set(allowed))
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {unknown}; allowed: {sorted(allowed)}")


def required(mapping, key, where):
    if key not in mapping:
        raise ValueError(f"{where}.{key}: missing")
    return mapping[key]
