"""Numbers quoted in prose (README, config/README, docs pages, report captions) are the pipeline's numbers.

A number the pipeline computes is quoted with a marker naming its record in figures/numbers.json
(noslipsim.plot.prose: ``0.319 ± 0.008<!--=portraits.islands_onset_gamma_R0.45-->`` in markdown,
a substitution ``|subject.key|`` in a caption); these tests fail when a quoted value differs from the
committed numbers.json.  ``python -m noslipsim.plot.prose figures/numbers.json FILE...`` rewrites them.
"""
import json
from pathlib import Path

import pytest

from noslipsim.plot import prose as nb

ROOT = Path(__file__).resolve().parents[1]
PROSE = ["README.md", "config/README.md", "docs/figures.md", "docs/conjectures.md", "docs/analysis.md"]
CAPTIONS = sorted((ROOT / "workflow" / "report").glob("*.rst"))

NUMBERS = {"portraits": {"onset": {"description": "d", "value": 0.31875, "format": ".3f", "stderr": 0.0081},
                         "radius": {"description": "d", "value": 0.4587, "format": ".3f"},
                         "share": {"description": "d", "value": 0.9864, "format": ".1%"},
                         "kind": {"description": "d", "value": "elliptic"},
                         "residual": {"description": "d", "value": "< 1e-12"}}}


@pytest.fixture(scope="module")
def committed():
    return json.loads((ROOT / "figures" / "numbers.json").read_text(encoding="utf-8"))


@pytest.mark.parametrize("name", PROSE)
def test_marked_numbers_in_the_readmes_are_numbers_json(name, committed):
    text = (ROOT / name).read_text(encoding="utf-8")
    assert nb.marked_numbers(text), f"{name}: no marked number (the markers were lost?)"
    assert nb.prose_mismatches(text, committed) == []


@pytest.mark.parametrize("name", PROSE)
def test_no_record_is_quoted_in_the_readmes_without_its_marker(name, committed):
    """A record's number typed by hand (no marker) would not follow the next run: docs/analysis.md had
    "97 %" and "89 %" that numbers.json had moved away from."""
    assert nb.unmarked_numbers((ROOT / name).read_text(encoding="utf-8"), committed) == []


def test_an_unmarked_record_is_found_and_a_marked_or_chance_one_is_not():
    text = ("agreement 98.6 % here, 98.6%<!--=portraits.share--> there; onset 0.319 ± 0.008; radius 0.459;\n"
            "198.6 % and 98.65 % are other numbers.\n<!-- numbers:start -->\n| 98.6% |\n<!-- numbers:end -->\n")
    assert sorted(nb.unmarked_numbers(text, NUMBERS)) == ["line 1: 0.319 ± 0.008 (portraits.onset)",
                                                          "line 1: 98.6 % (portraits.share)"]


@pytest.mark.parametrize("rst", CAPTIONS, ids=lambda p: p.stem)
def test_marked_numbers_in_the_captions_are_numbers_json(rst, committed):
    assert nb.prose_mismatches(rst.read_text(encoding="utf-8"), committed, "rst") == []


def test_a_changed_number_is_caught_in_markdown():
    good = ("γ = 0.319 ± 0.008<!--=portraits.onset--> and R ≈ 0.46<!--=portraits.radius:.2f-->, "
            "on 98.6 %<!--=portraits.share-->")
    assert [r for _, r, _ in nb.marked_numbers(good)] == ["portraits.onset", "portraits.radius", "portraits.share"]
    assert nb.prose_mismatches(good, NUMBERS) == []
    bad = good.replace("0.319", "0.32").replace("0.46", "0.45")
    problems = nb.prose_mismatches(bad, NUMBERS)
    assert len(problems) == 2 and "'0.32 ± 0.008'" in problems[0] and "'0.46'" in problems[1]
    assert nb.fill_prose(bad, NUMBERS) == good                           # the generator restores the text
    assert nb.prose_mismatches("x = 1.5<!--=portraits.nothing-->", NUMBERS) == [
        "portraits.nothing: no such number in numbers.json (expected subject.key)"]
    assert "text value" in nb.prose_mismatches("1<!--=portraits.kind-->", NUMBERS)[0]


def test_a_changed_number_is_caught_in_a_caption():
    good = "onset |portraits.onset|, share |portraits.share|.\n\n.. |portraits.onset| replace:: 0.319 ± 0.008\n" \
           ".. |portraits.share| replace:: 98.6 %\n"
    assert len(nb.marked_numbers(good, "rst")) == 2 and nb.prose_mismatches(good, NUMBERS, "rst") == []
    bad = good.replace("98.6 %", "98.7 %")
    assert nb.prose_mismatches(bad, NUMBERS, "rst") == ["portraits.share: the prose says '98.7 %', numbers.json "
                                                        "gives '98.6%'"]
    assert nb.fill_prose(bad, NUMBERS, "rst") == good
    with pytest.raises(ValueError, match="kind"):
        nb.marked_numbers(good, "latex")


def test_a_bound_is_quoted_like_a_number():
    """A residual stated as its bound (``< 1e-12``, a text value) is marked and checked like a number."""
    good = "residual < 1e-12<!--=portraits.residual-->.\n"
    assert nb.marked_numbers(good) == [("< 1e-12", "portraits.residual", None)]
    assert nb.prose_mismatches(good, NUMBERS) == []
    bad = good.replace("1e-12", "1e-13")
    assert nb.prose_mismatches(bad, NUMBERS) == ["portraits.residual: the prose says '< 1e-13', numbers.json "
                                                 "gives '< 1e-12'"]
    assert nb.fill_prose(bad, NUMBERS) == good
    rst = ".. |portraits.residual| replace:: < 1e-12\n"
    assert nb.prose_mismatches(rst, NUMBERS, "rst") == [] and nb.marked_numbers(rst, "rst")
    assert "text value" in nb.prose_mismatches("< 1e-12<!--=portraits.residual:.1e-->", NUMBERS)[0]
