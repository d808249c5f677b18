"""Small input checks shared by the public layer: each error names the field."""
import math
import os

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


def positive(value, field):
    """``value`` as a finite float ``> 0``, or ``ValueError`` naming ``field``."""
    x = finite_float(value, field)
    if not x > 0.0:
        raise ValueError(f"{field}: must be > 0, got {x}")
    return x


def nonnegative(value, field):
    """``value`` as a finite float ``>= 0``, or ``ValueError`` naming ``field``."""
    x = finite_float(value, field)
    if x < 0.0:
        raise ValueError(f"{field}: must be >= 0, got {x}")
    return x


def one_of(value, allowed, field):
    """``value`` if it is one of ``allowed``, else ``ValueError`` naming ``field`` and the choices."""
    try:
        ok = value in allowed
    except TypeError:  # unhashable values cannot be a choice
        ok = False
    if not ok:
        raise ValueError(f"{field}: must be one of {list(allowed)}, got {value!r}")
    return value


def no_unknown_keys(mapping, allowed, where):
    """Reject keys of ``mapping`` outside ``allowed``."""
    if not isinstance(mapping, dict):
        raise ValueError(f"{where}: expected a mapping, got {type(mapping).__name__}")
    unknown = sorted(set(mapping) - set(allowed), key=repr)  # YAML keys may be numbers, None, ...
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {unknown}; allowed: {sorted(allowed)}")


def required(mapping, key, where):
    """``mapping[key]``, or ValueError naming ``where`` and the missing key."""
    if key not in mapping:
        raise ValueError(f"{where}.{key}: missing")
    return mapping[key]


def read_yaml(source, what):
    """Parse YAML from a file path or from YAML text; returns ``(data, where)``.

    ``where`` names the source in later error messages: the path of a file,
    or ``what`` for text.  A one-line string that is neither an existing path
    nor a YAML mapping is taken as a path that does not exist.

    Raises
    ------
    FileNotFoundError
        ``source`` names a file that does not exist.
    OSError
        The file exists but cannot be read (a folder, no permission).
    ValueError
        The text is not UTF-8, or not valid YAML (the message gives the line
        and column of the problem).
    TypeError
        ``source`` is neither a string nor a path.
    """
    import yaml

    if not isinstance(source, (str, os.PathLike)):
        raise TypeError(f"{what}: expected a file path or YAML text, got {type(source).__name__}")
    text = os.fspath(source)
    if not isinstance(text, str):
        raise TypeError(f"{what}: expected a file path or YAML text, got {source!r}")
    where = what
    if isinstance(source, os.PathLike) or ("\n" not in text and os.path.exists(text)):
        where = text
        try:
            with open(text, encoding="utf-8") as fh:
                text = fh.read()
        except UnicodeDecodeError as err:
            raise ValueError(f"{where}: not a UTF-8 text file ({err.reason} at byte {err.start})") from None
    try:
        data = yaml.safe_load(text)
    except yaml.MarkedYAMLError as err:
        raise ValueError(f"{where}: {_yaml_problem(err)}") from None
    except yaml.YAMLError as err:  # unmarked errors (rare): still one line
        raise ValueError(f"{where}: invalid YAML: {' '.join(str(err).split())}") from None
    except RecursionError:
        raise ValueError(f"{where}: YAML nested too deeply") from None
    if where == what and "\n" not in text and (isinstance(data, str) or (data is None and text.strip())):
        raise FileNotFoundError(f"{what}: no such file {text!r} (expected the path of a YAML file, or YAML text)")
    return data, where


def _yaml_problem(err):
    """``YAML syntax error at line L, column C: problem (context)`` from a PyYAML error (1-based)."""
    mark = err.problem_mark or err.context_mark
    at = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
    problem = err.problem or "invalid YAML"
    if err.context:
        cmark = err.context_mark
        started = (f" started at line {cmark.line + 1}, column {cmark.column + 1}"
                   if cmark is not None and cmark is not mark else "")
        problem = f"{problem} ({err.context}{started})"
    return " ".join(f"YAML syntax error{at}: {problem}".split())


def count(value, field, minimum=1):
    """``value`` as an int ``>= minimum`` (bools and floats refused), or ``ValueError`` naming ``field``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{field}: expected an integer >= {minimum}, got {value!r}")
    return int(value)


def memory_bytes():
    """This machine's physical memory in bytes, or ``None`` where the system does not say."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, OSError, ValueError):
        return None


def _too_big(n_bytes, field, what, hint):
    tail = f"; {hint}" if hint else ""
    return ValueError(f"{field}: {what} does not fit in memory ({n_bytes / 2**30:.3g} GiB){tail}")


def check_memory(n_bytes, field, what, hint=""):
    """Refuse, before any work, to hold ``n_bytes`` at once when they exceed this machine's memory.

    A request that size would end in a ``MemoryError`` (or the system killing
    the process) only after the work before it; the refusal names the option.

    Parameters
    ----------
    n_bytes : int or float
        Bytes the request would hold at once.
    field : str
        The option or argument at fault, as the user wrote it.
    what : str
        What would be held, e.g. ``"a log of 10 collisions"``.
    hint : str
        What to do instead (appended after a semicolon).

    Raises
    ------
    ValueError
        ``field: what does not fit in memory (N GiB); hint``.
    """
    total = memory_bytes()
    if total is not None and n_bytes > total:
        raise _too_big(n_bytes, field, what, hint)


def zeros(shape, field, what, hint=""):
    """``numpy.zeros(shape)`` (float), refused as :func:`check_memory` refuses, or when allocating fails."""
    n_bytes = 8 * math.prod(int(k) for k in shape)
    check_memory(n_bytes, field, what, hint)
    try:
        return np.zeros(shape)
    except MemoryError:  # within the machine's memory, but not free now
        raise _too_big(n_bytes, field, what, hint) from None


def one_line(err):
    """The message of an error on one line (an OSError as ``path: reason``): what the CLI and the explorer show."""
    if isinstance(err, OSError) and err.filename is not None and err.strerror:
        text = f"{err.filename}: {err.strerror}"
    else:
        text = str(err) or type(err).__name__
    return " ".join(text.split())
