"""Numbers quoted in prose (README files, report captions) are the pipeline's numbers.

A number that ``figures/numbers.json`` holds is never typed by hand in prose:
it is quoted with a marker naming its record, and a test
(tests/test_prose_numbers.py) compares every marked number with the committed
``numbers.json``.  In markdown the marker is an HTML comment right after the
number (invisible when rendered)::

    γ = 0.319 ± 0.008<!--=portraits.islands_onset_gamma_R0.45-->
    R ≈ 0.46<!--=portraits.islands_radius_for_paper_onset:.2f-->   (a format of its own)
    < 1e-12<!--=orbits.pentagon_periodic_residual-->                (a bound, a text value)

In a report caption (reStructuredText) the number is a substitution named after
its record, defined once::

    θ* = |stability.wedge_transition_theta|
    .. |stability.wedge_transition_theta| replace:: 1.121997

The quoted text must equal the record formatted as in the numbers table
(:func:`noslipsim.plot.numbers.format_value`), up to typography (spaces,
thousands commas, ``−`` for ``-``).  After a paper-size run,
``python -m noslipsim.plot.prose figures/numbers.json README.md config/README.md workflow/report/*.rst``
rewrites every marked number from the new ``numbers.json``.
"""
from __future__ import annotations

import re

from .numbers import format_value

__all__ = ["MARKDOWN_MARK", "RST_MARK", "fill_prose", "marked_numbers", "prose_mismatches", "quoted_value",
           "unmarked_numbers"]

#: A number quoted in markdown, marked with the record it comes from (the marker is an HTML comment, invisible
#: when rendered): ``0.319 ± 0.008<!--=portraits.islands_onset_gamma_R0.45-->``, or with a format of its own,
#: ``0.46<!--=portraits.islands_radius_for_paper_onset:.2f-->``.
_NUMBER = r"[-−]?\d[\d,]*(?:\.\d+)?(?:e[-+]?\d+)?(?:\s?%)?"
#: A bound (``< 1e-12``): a record whose text value is a bound can be quoted like a number.
_BOUND = rf"<\s?{_NUMBER}"
_QUOTED = rf"{_BOUND}|{_NUMBER}(?:\s?±\s?{_NUMBER})?"
MARKDOWN_MARK = re.compile(rf"(?P<text>{_QUOTED})<!--=(?P<ref>[^\s:>]+)(?::(?P<fmt>[^\s>]+))?-->")
#: The same in reStructuredText (report captions): a substitution named after the record, defined once,
#: ``θ* = |stability.wedge_transition_theta|`` with ``.. |stability.wedge_transition_theta| replace:: 1.121997``.
RST_MARK = re.compile(rf"^\.\. \|(?P<ref>[a-z]+\.[^\s|:]+)(?::(?P<fmt>[^\s|]+))?\| replace:: (?P<text>{_QUOTED})"
                      r"[ \t]*$", re.M)


def _record(numbers, ref):
    subject, _, key = ref.partition(".")
    try:
        return numbers[subject][key]
    except KeyError:
        raise ValueError(f"{ref}: no such number in numbers.json (expected subject.key)") from None


def quoted_value(numbers, ref, fmt=None):
    """The text a quoted number must read: the record ``ref`` (``subject.key``) formatted as in the table.

    ``fmt`` overrides the record's own format (``".2f"``: fewer digits in prose).  A text value can be
    quoted only if it is a bound (``"< 1e-12"``, :func:`noslipsim.plot.numbers.below`), as it is.
    """
    record = dict(_record(numbers, ref))
    if isinstance(record["value"], str):
        if fmt is None and re.fullmatch(_BOUND, record["value"]):
            return record["value"]
        raise ValueError(f"{ref}: a text value ({record['value']!r}) cannot be quoted as a number")
    if fmt is not None:
        record["format"] = fmt
    return format_value(record)


def _canonical(text):
    """A quoted number's text without the typographic variants (spaces, thousands commas, the minus sign)."""
    return re.sub(r"[\s,]", "", text).replace("−", "-")


def marked_numbers(text, kind="markdown"):
    """``[(quoted text, 'subject.key', format or None)]`` of the numbers marked in ``text``.

    Parameters
    ----------
    text : str
    kind : {'markdown', 'rst'}
        Markdown (:data:`MARKDOWN_MARK`, README files) or reStructuredText
        (:data:`RST_MARK`, report captions).
    """
    if kind not in ("markdown", "rst"):
        raise ValueError(f"kind: expected 'markdown' or 'rst', got {kind!r}")
    pattern = MARKDOWN_MARK if kind == "markdown" else RST_MARK
    return [(m["text"], m["ref"], m["fmt"]) for m in pattern.finditer(text)]


def prose_mismatches(text, numbers, kind="markdown"):
    """The marked numbers of ``text`` that differ from ``numbers`` (``{subject: {key: record}}``).

    Returns
    -------
    list of str
        One line per mismatch: the quoted text, the reference and the value it
        should read.  Unknown references are mismatches too.
    """
    out = []
    for quoted, ref, fmt in marked_numbers(text, kind):
        try:
            want = quoted_value(numbers, ref, fmt)
        except ValueError as err:
            out.append(str(err))
            continue
        if _canonical(quoted) != _canonical(want):
            out.append(f"{ref}: the prose says {quoted!r}, numbers.json gives {want!r}")
    return out


#: The generated numbers table of the README: every number in it is a record's, by construction.
_TABLE_BLOCK = re.compile(r"<!-- numbers:start -->.*?<!-- numbers:end -->", re.S)


def _distinctive(text):
    """Whether a record's printed value is unlikely to occur by chance in prose: a share (``93.8%``) or an
    uncertainty (``± 0.008``) of 3 digits or more, or any number of 4 significant digits or more."""
    digits = len(re.sub(r"\D", "", text).lstrip("0"))
    return digits >= (3 if ("%" in text or "±" in text) else 4)


def unmarked_numbers(text, numbers):
    """The numbers of markdown ``text`` that print exactly as a record does but carry no marker.

    Such a number was typed by hand: it would not follow the record after the next run.  Only values
    distinctive enough not to match by chance are looked for (a share or ``±`` with 3 digits, others with
    4 significant digits); the README's generated numbers table is skipped.

    Returns
    -------
    list of str
        ``"line N: TEXT (subject.key)"`` for each unmarked occurrence.
    """
    body = _TABLE_BLOCK.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    out = []
    for subject, records in numbers.items():
        for key, record in records.items():
            if isinstance(record["value"], str) or not _distinctive(format_value(record)):
                continue
            want = format_value(record)
            spelled = re.escape(want).replace("%", r"\s?%").replace(r"\ ±\ ", r"\s?±\s?").replace("-", "[-−]")
            for m in re.finditer(rf"(?<![\d.]){spelled}(?![\d]|\.\d|<!--=)", body):
                out.append(f"line {body.count(chr(10), 0, m.start()) + 1}: {m.group(0)} ({subject}.{key})")
    return out


def _styled(numbers, m):
    """The value of mark ``m`` in the typography of the text it replaces (``98.6 %``, ``−0.691``)."""
    want = quoted_value(numbers, m["ref"], m["fmt"])
    if re.search(r"\s%", m["text"]):
        want = want.replace("%", " %")
    if "−" in m["text"]:
        want = want.replace("-", "−")
    return want


def fill_prose(text, numbers, kind="markdown"):
    """``text`` with every marked number rewritten from ``numbers`` (the markers and the typography stay)."""
    if kind == "markdown":
        return MARKDOWN_MARK.sub(lambda m: f"{_styled(numbers, m)}<!--={m['ref']}"
                                 + (f":{m['fmt']}" if m["fmt"] else "") + "-->", text)
    if kind == "rst":
        return RST_MARK.sub(lambda m: f".. |{m['ref']}" + (f":{m['fmt']}" if m["fmt"] else "")
                            + f"| replace:: {_styled(numbers, m)}", text)
    raise ValueError(f"kind: expected 'markdown' or 'rst', got {kind!r}")


def _main(argv=None):
    """``python -m noslipsim.plot.prose figures/numbers.json FILE...``: rewrite the marked numbers of each file."""
    import json
    import sys
    from pathlib import Path

    args = sys.argv[1:] if argv is None else argv
    if len(args) < 2:
        raise SystemExit("usage: python -m noslipsim.plot.prose figures/numbers.json FILE...")
    numbers = json.loads(Path(args[0]).read_text(encoding="utf-8"))
    for name in args[1:]:
        path = Path(name)
        kind = "rst" if path.suffix == ".rst" else "markdown"
        old = path.read_text(encoding="utf-8")
        new = fill_prose(old, numbers, kind)
        if new != old:
            path.write_text(new, encoding="utf-8")
            print(f"{name}: marked numbers rewritten")


if __name__ == "__main__":  # pragma: no cover
    _main()
