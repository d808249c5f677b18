"""The paper's numbers print the same on every machine (noslipsim.plot.numbers, figures/numbers.json).

Another machine of our family (another BLAS build, another SIMD summation order) changes the last
bits of a computed number: a converged Newton residual (3.05e-16 here, 3.61e-16 there), a width in
its 10th digit, the order in which the eigenvalue solver returns three unit eigenvalues.  These tests
perturb the inputs of each formatting by one ulp (np.nextafter) or recompute them from starts one
ulp apart, and require the same text; and they require the committed numbers.json to hold no digit
below what its computation determines.
"""
import itertools
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from noslipsim.plot.numbers import below, canonical_eigenvalues, eigenvalues_text, format_value, rounded, significant
from noslipsim.plot.prose import marked_numbers

ROOT = Path(__file__).resolve().parents[1]
PROSE = ["README.md", "config/README.md", "docs/figures.md"]
#: Significant digits no stored number exceeds: a double carries 15-17, of which the last few are the
#: machine's (the numbers scripts keep at most 12, most 6 or fewer).
MAX_DIGITS = 12


@pytest.fixture(scope="module")
def committed():
    return json.loads((ROOT / "figures" / "numbers.json").read_text(encoding="utf-8"))


def ulp_neighbours(x):
    """``x`` and its two neighbouring doubles."""
    return [x, float(np.nextafter(x, -math.inf)), float(np.nextafter(x, math.inf))]


def float_fields(numbers):
    """``(subject.key.field, value)`` of every float stored in ``numbers`` (values and standard errors)."""
    for subject, records in numbers.items():
        for key, record in records.items():
            for field in ("value", "stderr"):
                if isinstance(record.get(field), float):
                    yield f"{subject}.{key}.{field}", record[field]


def digits_of(x):
    """Significant digits of the shortest repr of ``x`` (``0.11597000000000002`` has 17)."""
    mantissa = repr(abs(x)).split("e")[0].replace(".", "").lstrip("0")
    return len(mantissa.rstrip("0")) if mantissa else 0


# ---------------------------------------------------------------- the formatting helpers
@pytest.mark.parametrize("x", [0.0996715290743392, 0.0653630242883586, 1.1219973762820878, 0.11597000000000002,
                               0.39999999999999974, 314.4716223643552, -0.6909535552555233, 0.008246097751120035])
def test_a_value_cut_to_its_digits_is_the_same_one_ulp_away(x):
    for digits in (3, 6, 10):
        assert len({significant(y, digits) for y in ulp_neighbours(x)}) == 1
    for places in (4, 8, 10):
        assert len({rounded(y, places) for y in ulp_neighbours(x)}) == 1
    assert significant(x, 6) == float(f"{x:.5e}") and digits_of(significant(x, 6)) <= 6


def test_cut_values_lose_the_sign_of_zero_and_refuse_bad_input():
    assert math.copysign(1.0, significant(-0.0, 3)) == 1.0 and math.copysign(1.0, rounded(-1e-20, 6)) == 1.0
    for bad in (lambda: significant(1.0, 0), lambda: significant(math.nan, 3), lambda: rounded(math.inf, 2),
                lambda: rounded(1.0, -1), lambda: significant(1.0, True)):
        with pytest.raises(ValueError):
            bad()


def test_a_value_that_prints_as_zero_has_no_sign():
    """A share of 0 one ulp below zero prints "0.00%", not "-0.00%"; a negative value keeps its sign."""
    record = {"description": "d", "value": float(np.nextafter(0.0, -1.0)), "stderr": -0.0, "format": ".2%"}
    assert format_value(record) == "0.00% ± 0.00%"
    assert format_value(dict(record, value=-0.004)) == "-0.40% ± 0.00%"
    assert format_value(dict(record, value=-1e-5, format=".1e")) == "-1.0e-05 ± 0.0e+00"
    assert format_value(dict(record, value=-0.0004, format=".3f")) == "0.000 ± 0.000"


def test_a_residual_prints_as_its_bound():
    """The Figure 4 residual here and on the other machine: the same text, the finder's tolerance."""
    assert below(3.0531133177191805e-16, 1e-12) == below(3.61e-16, 1e-12) == below(0.0, 1e-12) == "< 1e-12"
    with pytest.raises(ValueError, match="not below"):
        below(2e-12, 1e-12)                     # a residual that missed the tolerance is not hidden
    with pytest.raises(ValueError, match="bound"):
        below(1e-16, 0.0)


def test_eigenvalues_print_in_one_order_whatever_the_solver_returns():
    """The wedge's period-8 eigenvalues {1, exp(+-0.3893 i)}: every order, every last bit, the same text."""
    ev = np.array([1.0 + 0.0j, np.exp(0.3893j), np.exp(-0.3893j)])
    want = "1.0000∠-0.3893, 1.0000∠+0.0000, 1.0000∠+0.3893"
    texts = set()
    for order in itertools.permutations(range(3)):
        for step in (-math.inf, math.inf):
            bumped = [complex(np.nextafter(z.real, step), np.nextafter(z.imag, step)) for z in ev[list(order)]]
            texts.add(eigenvalues_text(bumped))
        texts.add(eigenvalues_text(ev[list(order)]))
    assert texts == {want}
    # a real eigenvalue with a -0.0 or tiny imaginary part: no "-0.0000", and -pi prints as +pi
    assert eigenvalues_text([1 - 1e-17j, 1 + 1e-17j]) == "1.0000∠+0.0000, 1.0000∠+0.0000"
    assert eigenvalues_text([complex(-2.0, -0.0)]) == eigenvalues_text([complex(-2.0, 0.0)]) == "2.0000∠+3.1416"
    # moduli equal in their printed digits are ordered by argument, not by their noise
    assert canonical_eigenvalues([1.00000000001 * np.exp(0.5j), 0.99999999999 * np.exp(-0.5j)]) == [
        (1.0, -0.5), (1.0, 0.5)]
    with pytest.raises(ValueError, match="finite"):
        eigenvalues_text([complex(math.nan, 0.0)])


# ---------------------------------------------------------------- recomputed from starts one ulp apart
@pytest.mark.parametrize("case", ["pentagon", "wedge"])
def test_a_periodic_orbit_found_from_a_start_one_ulp_away_prints_the_same(case):
    """The numbers' texts of a periodic orbit (residual, eigenvalues) do not follow the last bits of its start.

    The Figure 4 pentagon orbit and Figure 7's period-8 wedge orbit (docs/analysis.md), each found from
    its start and from the start moved by one ulp: Newton lands on the same orbit with another
    rounding-level residual, which the bound and the canonical eigenvalue text absorb.
    """
    from noslipsim import tables
    from noslipsim.analysis import find_periodic_orbit

    if case == "pentagon":
        scene, start, period = tables.regular_polygon(5), ((0.288, 0.059), (-0.6, -0.8), -0.1), 14
    else:
        scene, start, period = tables.wedge(0.6, force=(0.0, -1.0)), ((-0.862, 1.732), (1.577, -0.763), -1.071), 8
    (x, y), velocity, spin = start
    texts = set()
    for x_start in ulp_neighbours(x):
        found = find_periodic_orbit(scene, (x_start, y), velocity, spin, period=period, tol=1e-12)
        assert found.converged, found.message
        texts.add((below(found.residual, 1e-12), eigenvalues_text(found.monodromy.eigenvalues)))
    assert len(texts) == 1, texts


# ---------------------------------------------------------------- the committed numbers
def test_committed_numbers_hold_no_digit_below_their_computation(committed):
    """Every stored float is cut to the digits its computation determines (not 0.11597000000000002)."""
    noisy = {name: value for name, value in float_fields(committed) if digits_of(value) > MAX_DIGITS}
    assert noisy == {}


def test_committed_numbers_print_the_same_one_ulp_away(committed):
    """Each record's text (the table's and every prose format) is the same with its floats one ulp away."""
    formats = {}
    for name in PROSE:
        for _, ref, fmt in marked_numbers((ROOT / name).read_text(encoding="utf-8")):
            formats.setdefault(ref, {None}).add(fmt)
    for subject, records in committed.items():
        for key, record in records.items():
            if not isinstance(record["value"], float):
                continue
            for fmt in formats.get(f"{subject}.{key}", {None}):
                texts = set()
                for value in ulp_neighbours(record["value"]):
                    for stderr in ulp_neighbours(record["stderr"]) if "stderr" in record else [None]:
                        bumped = dict(record, value=value, stderr=stderr)
                        if fmt is not None:
                            bumped["format"] = fmt
                        texts.add(format_value(bumped))
                assert len(texts) == 1, (subject, key, fmt, texts)


def test_committed_notes_state_residuals_as_bounds(committed):
    """No residual in a value or note is printed at the rounding level (``residual 5.8e-15``)."""
    texts = [str(r.get(f, "")) for records in committed.values() for r in records.values() for f in ("value", "note")]
    assert [t for t in texts if re.search(r"residual (?!<)", t)] == []
    assert committed["orbits"]["pentagon_periodic_residual"]["value"] == "< 1e-12"
