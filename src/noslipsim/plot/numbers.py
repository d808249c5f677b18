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
"""
from __future__ import annotations

import math

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


def format_value(record):
    """The record's value as text, with its standard error if it has one."""
    value, fmt = record["value"], record.get("format", ".4g")
    if isinstance(value, str):
        return value
    text = format(value, fmt)
    if record.get("stderr") is not None:
        text += " ± " + format(record["stderr"], fmt)
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

