"""The paper's stated numbers, computed: one record per number and their markdown table.

Each subject of the workflow writes a JSON fragment ``{key: record}``; the
fragments are gathered into ``figures/numbers.json`` as
``{subject: {key: record}}`` and rendered by :func:`numbers_markdown` into the
table the README shows (a test checks that the two agree, so nobody types a
number; numbers quoted in prose are marked with their record and checked the
same way: :mod:`noslipsim.plot.prose`).  A record holds:

- ``description``: what the number is (one line);
- ``value``: the computed number (float) or a short text;
- ``format``: a format spec for floats (``".1%"``, ``".3g"``), optional;
- ``stderr``: a standard error (same format), optional;
- ``paper``: what the paper states (text), optional;
- ``note``: how it was computed, optional.

Every number is stored and printed only to the digits its computation
determines, so that another machine (another BLAS, another SIMD summation
order) writes the same ``numbers.json``: :func:`significant` and
:func:`rounded` cut a value to those digits, :func:`below` states a residual at
the rounding level as the bound its method guarantees, and
:func:`eigenvalues_text` prints a set of eigenvalues in one canonical order
(docs/figures.md, "Which numbers and figures are the same on every machine").
"""
from __future__ import annotations

import math
import re

import numpy as np

REQUIRED = ("description", "value")
OPTIONAL = ("format", "stderr", "paper", "note")


def check_record(key, record):
    """Validate one number record (see the module docstring); returns it.

    Raises
    ------
    ValueError
        For a missing or unknown field, or a value that is neither a finite
        number nor a string.
    """
    if not isinstance(record, dict):
        raise ValueError(f"{key}: expected a mapping, got {type(record).__name__}")
    missing = [f for f in REQUIRED if f not in record]
    unknown = sorted(set(record) - set(REQUIRED) - set(OPTIONAL))
    if missing or unknown:
        raise ValueError(f"{key}: missing fields {missing}, unknown fields {unknown}")
    value = record["value"]
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ValueError(f"{key}.value: expected a number or a string, got {type(value).__name__}")
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError(f"{key}.value: not finite ({value})")
    return record


def _format(x, fmt):
    """``format(x, fmt)`` without the sign of a zero: a value that prints as zero has no sign worth showing
    (``-0.00%`` and ``0.00%`` are the same share, one ulp apart)."""
    text = format(x, fmt)
    return text[1:] if text.startswith("-") and not re.search(r"[1-9]", text.split("e")[0]) else text


def format_value(record):
    """The record's value as text, with its standard error if it has one."""
    value, fmt = record["value"], record.get("format", ".4g")
    if isinstance(value, str):
        return value
    text = _format(value, fmt)
    if record.get("stderr") is not None:
        text += " ± " + _format(record["stderr"], fmt)
    return text


def numbers_markdown(numbers):
    """The markdown table of ``{subject: {key: record}}`` (subjects and keys in their given order)."""
    lines = ["| subject | quantity | computed | paper |", "|---|---|---|---|"]
    for subject, records in numbers.items():
        for key, record in records.items():
            check_record(f"{subject}.{key}", record)
            cells = [subject, record["description"], format_value(record), record.get("paper", "")]
            lines.append("| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |")
    return "\n".join(lines) + "\n"



def _positive_int(n, name):
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
        raise ValueError(f"{name}: expected an integer >= 0, got {n!r}")
    return int(n)


def significant(x, digits):
    """``x`` rounded to ``digits`` significant digits (``-0.0`` becomes ``0.0``).

    Parameters
    ----------
    x : float
        A finite number.
    digits : int
        Significant digits kept (``>= 1``): those the computation of ``x``
        determines, with a margin, so that the last bits of ``x`` (another
        BLAS, another summation order) do not reach them.

    Returns
    -------
    float
        The decimal rounding of ``x`` (correctly rounded by Python's format).
    """
    if _positive_int(digits, "digits") < 1:
        raise ValueError(f"digits: expected an integer >= 1, got {digits!r}")
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"x: not finite ({x})")
    return float(f"{x:.{digits - 1}e}") + 0.0


def rounded(x, places):
    """``x`` rounded to ``places`` decimals (``-0.0`` becomes ``0.0``): for a value known to an absolute accuracy."""
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"x: not finite ({x})")
    return round(x, _positive_int(places, "places")) + 0.0


def below(residual, bound):
    """``"< bound"``: a residual stated as the bound its method guarantees, not as its rounding-level value.

    A converged residual is rounding noise (``3.1e-16`` here, ``3.6e-16`` on
    another machine); what the method guarantees is its tolerance.

    Raises
    ------
    ValueError
        If ``residual`` is not below ``bound`` (the method did not reach its
        tolerance: printing the bound would hide that).
    """
    residual, bound = float(residual), float(bound)
    if not (math.isfinite(bound) and bound > 0.0):
        raise ValueError(f"bound: expected a finite number > 0, got {bound}")
    if not abs(residual) < bound:
        raise ValueError(f"residual {residual:.3g} is not below the bound {bound:g}")
    return f"< {bound:g}"


def canonical_eigenvalues(eigenvalues, places=4):
    """``[(modulus, argument)]`` of complex eigenvalues, rounded to ``places`` decimals, in one canonical order.

    Sorted by modulus, then argument in ``(-pi, pi]``, both rounded *before*
    sorting: eigenvalues whose printed moduli are equal (the three unit
    eigenvalues of an elliptic orbit) are ordered by their printed argument,
    never by rounding noise in the moduli.  An argument of ``-pi`` (a negative
    real eigenvalue with ``-0.0`` imaginary part) becomes ``pi``, ``-0.0``
    becomes ``0.0``.
    """
    places = _positive_int(places, "places")
    ev = np.asarray(eigenvalues, dtype=complex).ravel()
    if not np.all(np.isfinite(ev)):
        raise ValueError(f"eigenvalues: not finite ({ev})")
    half_turn = round(math.pi, places)
    pairs = []
    for z in ev:
        argument = round(float(np.angle(z)), places) + 0.0
        pairs.append((round(float(abs(z)), places) + 0.0, half_turn if argument == -half_turn else argument))
    return sorted(pairs)


def eigenvalues_text(eigenvalues, places=4):
    """Eigenvalues as ``"1.0000∠-0.3893, 1.0000∠+0.0000, ..."`` (modulus∠argument), canonical order.

    See :func:`canonical_eigenvalues`: the text is the same whatever order
    (and whatever last bits) the eigenvalue solver returns.
    """
    return ", ".join(f"{m:.{places}f}∠{a:+.{places}f}" for m, a in canonical_eigenvalues(eigenvalues, places))
