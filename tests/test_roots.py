"""Exit roots of crossing polynomials: the kernels of ``core.roots`` against their exact twins.

The twin (``naive.py``) isolates every real root of the *exact* polynomial the
float coefficients stand for (Sturm sequence in exact rational arithmetic,
bisection to ~1e-42 relative) and keeps the + to - sign changes.

Accuracy we can ask of a float method (and no more): the kernel evaluates the
polynomial in floats, so it works on a polynomial perturbed by
``delta(t) ~ k eps sum |c_i| t^i``.  A simple root moves by
``delta / |p'(r)|``; a near-double root by up to ``sqrt(2 delta / |p''(r)|)``,
i.e. ``~sqrt(eps) ~ 1e-8`` relative, a near-triple one by ``~eps^(1/3)``: no
float method does better (``naive.predicted_root_error``).  So:

* well-conditioned roots (predicted error <= 1e-13 relative) must agree to 1e-12 relative;
* every other root must lie within a small multiple of its predicted error;
* the *count* of exits must agree wherever the twin's real roots are separated by
  more than 1e-6 relative (and by more than their predicted errors); inside a
  cluster closer than that, at least one exit must be reported when the sign
  goes from + to - across it (the flight certainly leaves), and every exit the
  kernel reports must be a root of a polynomial within rounding (backward residual).
"""
import math
import zlib
from fractions import Fraction

import mpmath
import naive
import numpy as np
import pytest
from naive import naive_all_real_roots, naive_exit_roots, naive_real_roots, naive_roots_between

from noslipsim.core.roots import (
    bracket_step,
    cubic_exits,
    cubic_roots_in,
    linear_exit,
    quadratic_exit,
    quadratic_roots,
    quartic_exits,
    secant_start,
    straight_circle_exit,
)

INF = math.inf
EPS = 2.0 ** -52
#: Rounding units of polynomial evaluation the kernels may make (Horner on degree <= 4 needs 2n;
#: a margin for the closed forms and the critical points).
K_EVAL = 16
#: Slack on the predicted error (first-order conditioning is an estimate, not a bound).
C_PRED = 8.0
#: Predicted relative error below which a root is "well conditioned".
WELL = 1e-13
#: Relative agreement required on well-conditioned roots.
REL_TOL = 1e-12
#: Roots separated by more than this (relative) must be counted alike.
SEP = 1e-6
#: Backward residual allowed on a root the twin does not have (units of eps * sum |c_i t^i|).
RESID = 64.0

#: Largest relative error seen on well-conditioned roots, per test (reported by
#: ``test_report_accuracy`` at the end of the module).
MEASURED = {}


def seed_of(*parts):
    return zlib.crc32(repr(parts).encode())


def kernel_exits(c, hi, degree):
    """Exit roots from the kernel of the given degree (the degree the caller needs), finite only."""
    c = [float(v) for v in c] + [0.0] * (5 - len(c))
    if degree == 1:
        out = (linear_exit(c[0], c[1], hi),)
    elif degree == 2:
        out = (quadratic_exit(c[0], c[1], c[2], hi),)
    elif degree == 3:
        out = cubic_exits(c[0], c[1], c[2], c[3], hi)
    else:
        out = quartic_exits(c[0], c[1], c[2], c[3], c[4], hi)
    return [t for t in out if t != INF]


def compare_exits(c, hi, degree, tag="", mags=None):
    """Compare kernel and twin exits of ``c`` in ``(0, hi]``; return a failure message or None.

    The twin's real roots are grouped into clusters a float method cannot resolve
    (``naive.root_clusters``).  A cluster of one clean exit must be found to its allowed error; a
    clean entry must not be reported; an unresolvable cluster across which the sign goes from
    + to - must yield at least one exit (count parity: the flight certainly leaves there), and
    every kernel exit the twin does not have must be a root to rounding (backward residual).
    Clusters within their error of t = 0 or of ``hi`` may go either way.
    """
    c = [float(v) for v in c]
    mags = [abs(v) for v in c] if mags is None else mags
    kern = kernel_exits(c, hi, degree)
    roots = naive_real_roots(c, hi)
    twin = [(float(r), kind) for r, kind, _ in roots]
    where = f"{tag} coeffs={c!r} hi={hi!r} degree={degree}: kernel={kern} twin={twin}"
    if kern != sorted(kern):
        return f"kernel exits not sorted; {where}"
    if any(not (0.0 < t <= hi) for t in kern):
        return f"kernel exit outside (0, hi]; {where}"
    with mpmath.workdps(50):
        for cl in naive.root_clusters(c, roots, mags, K_EVAL, C_PRED, WELL, REL_TOL, SEP):
            inside = [t for t in kern if cl["lo"] <= t <= cl["hi"]]
            edge = cl["lo"] <= 0 or cl["hi"] >= hi
            (x, *more) = cl["roots"]
            clean = not more and not edge and x["well"]
            if clean and x["kind"] == "exit":
                if len(inside) != 1:
                    return (f"clean exit {float(x['t'])!r} (allowed error {float(x['allowed']):.2e}) "
                            f"found {len(inside)} times; {where}")
                MEASURED[tag] = max(MEASURED.get(tag, 0.0), float(abs(inside[0] - x["t"]) / x["t"]))
            elif clean and x["kind"] == "entry" and inside:
                return f"kernel reports the clean entry {float(x['t'])!r} as an exit; {where}"
            elif cl["left"] > 0 > cl["right"] and not edge and not inside:
                return (f"no exit near {[(float(r['t']), r['kind']) for r in cl['roots']]} (window "
                        f"{float(cl['lo']):.17g}..{float(cl['hi']):.17g}) although p goes from + to - "
                        f"across it; {where}")
    # every exit the kernel reports is a root of a polynomial within rounding of this one
    for t in kern:
        res = naive.backward_residual(c, t, mags)
        if res > RESID:
            return f"kernel exit {t!r} is no root of any nearby polynomial (residual {float(res):.3g} eps); {where}"
    return None


# --------------------------------------------------------------------------- case generators

def expand(lead, real, pairs):
    """Exact coefficients of ``lead prod (t - r) prod (t^2 - 2 a t + a^2 + b^2)``, rounded to floats."""
    c = [Fraction(lead)]

    def mul(c, f):
        out = [Fraction(0)] * (len(c) + len(f) - 1)
        for i, x in enumerate(c):
            for j, y in enumerate(f):
                out[i + j] += x * y
        return out

    for r in real:
        c = mul(c, [-Fraction(r), Fraction(1)])
    for a, b in pairs:
        a, b = Fraction(a), Fraction(b)
        c = mul(c, [a * a + b * b, -2 * a, Fraction(1)])
    return [float(v) for v in c]


def loguni(rng, lo, hi):
    return 10.0 ** rng.uniform(lo, hi)


def spread_roots(rng, n, scale):
    """``n`` real roots of random sign, magnitudes log-uniform over 4 decades, ratio >= 1.3 apart."""
    while True:
        mags = np.sort(scale * 10.0 ** rng.uniform(-2, 2, n))
        if n < 2 or np.all(mags[1:] / mags[:-1] > 1.3):
            break
    signs = np.where(rng.random(n) < 0.7, 1.0, -1.0)
    return list(mags * signs)


def make_case(rng, family, degree):
    """A polynomial of exactly ``degree`` with roots placed as ``family`` says, and a horizon ``hi``."""
    T = loguni(rng, -6, 6)            # time scale
    lead = rng.choice([-1.0, 1.0]) * loguni(rng, -30, 30)
    if family == "near_double_complex":
        npairs = 1
    elif family in ("near_triple", "double_pairs"):
        npairs = 0
    else:
        npairs = int(rng.integers(0, degree // 2 + 1))
    nreal = degree - 2 * npairs
    pairs = []
    for _ in range(npairs):
        a = rng.choice([-1.0, 1.0]) * T * loguni(rng, -2, 2)
        pairs.append((a, abs(a) * loguni(rng, -1, 1)))
    real = spread_roots(rng, nreal, T) if nreal else []
    if family == "clustered" and nreal >= 2:
        r = abs(real[0])
        real[1] = r * (1.0 + loguni(rng, -5.5, -1))
        real[0] = r
    elif family == "near_zero" and nreal >= 1:
        real[0] = rng.choice([-1.0, 1.0, 1.0]) * T * loguni(rng, -15, -9)
    elif family == "near_double" and nreal >= 2:
        r = abs(real[0])
        real[1] = r * (1.0 + rng.choice([-1.0, 1.0]) * loguni(rng, -12, -6))
        real[0] = r
    elif family == "near_triple" and nreal >= 3:
        # three roots within s of each other: the crossing of a flight osculating a circle
        r = abs(real[0])
        real[1] = r * (1.0 + loguni(rng, -9, -3) * rng.normal())
        real[2] = r * (1.0 + loguni(rng, -9, -3) * rng.normal())
        real[0] = r
    elif family == "near_quadruple":   # (t - r)^4 -+ delta: two real roots or none, eps^(1/4)-conditioned
        r = abs(real[0]) if real else T
        c = expand(lead, [r] * degree, [])
        c[0] -= lead * (r * loguni(rng, -9, -1)) ** degree * rng.choice([-1.0, 1.0])
        return c, (INF if rng.random() < 0.6 else T * loguni(rng, -2.5, 2.5))
    elif family == "double_pairs" and nreal >= 4:
        r, r2 = abs(real[0]), abs(real[2])
        real[1] = r * (1.0 + loguni(rng, -9, -2))
        real[3] = r2 * (1.0 + loguni(rng, -9, -2))
    elif family == "near_double_complex":
        a = T * loguni(rng, -2, 2)
        pairs[0] = (a, a * loguni(rng, -12, -5))
    c = expand(lead, real, pairs)
    u = rng.random()
    if u < 0.6:
        hi = INF
    else:
        hi = T * loguni(rng, -2.5, 2.5)
    return c, hi


FAMILIES = ["separated", "clustered", "near_zero", "near_double", "near_double_complex", "near_quadruple"]
N_CASES = 160


# (t - r)^3 -+ delta is a near-triple root: see test_near_triple_roots_match_twin
FAMILY_DEGREES = [(f, d) for f in FAMILIES for d in (2, 3, 4) if (f, d) != ("near_quadruple", 3)]


@pytest.mark.parametrize("family, degree", FAMILY_DEGREES)
def test_exits_match_twin(family, degree):
    """Planted roots: separated, clustered (1e-5.5..1e-1 apart), one near t = 0 (1e-15..1e-9 of
    the time scale), near-double (1e-12..1e-6 apart), a near-real complex pair, (t - r)^n -+ delta;
    time scales 1e-6..1e6, coefficient scales 1e-30..1e30, horizons finite or infinite."""
    rng = np.random.default_rng(seed_of("exits", family, degree))
    failures = []
    for i in range(N_CASES):
        c, hi = make_case(rng, family, degree)
        msg = compare_exits(c, hi, degree, tag=f"{family}/deg{degree}")
        if msg:
            failures.append(f"case {i}: {msg}")
    assert not failures, f"{len(failures)}/{N_CASES} cases disagree, first: " + "\n".join(failures[:3])


def test_two_near_double_pairs_match_twin():
    rng = np.random.default_rng(seed_of("exits", "double_pairs", 4))
    failures = []
    for i in range(N_CASES):
        c, hi = make_case(rng, "double_pairs", 4)
        msg = compare_exits(c, hi, 4, tag="double_pairs/deg4")
        if msg:
            failures.append(f"case {i}: {msg}")
    assert not failures, f"{len(failures)}/{N_CASES} cases disagree, first: " + "\n".join(failures[:3])


@pytest.mark.parametrize("degree", [3, 4])
def test_near_triple_roots_match_twin(degree):
    """Three roots within 1e-9..1e-3 relative (p changes sign once or three times there)."""
    rng = np.random.default_rng(seed_of("exits", "near_triple", degree))
    failures = []
    for i in range(N_CASES):
        c, hi = make_case(rng, "near_triple", degree)
        msg = compare_exits(c, hi, degree, tag=f"near_triple/deg{degree}")
        if msg:
            failures.append(f"case {i}: {msg}")
    assert not failures, f"{len(failures)}/{N_CASES} cases disagree, first: " + "\n".join(failures[:3])


@pytest.mark.parametrize("coeffs, exits", [
    pytest.param((1.0, -2.0, 0.0, 2.0, -1.0), [1.0], id="quartic -(t-1)^3 (t+1)"),
    pytest.param((479721175775.3895, -3214695454.664936, 7180745.391347918, -5346.603341076437),
                 [447.68476701799693], id="cubic near-triple"),
    pytest.param((1.0, -3.0, 3.0, -1.0), [1.0], id="cubic -(t-1)^3"),
])
def test_exit_through_a_triple_root(coeffs, exits):
    """An exit of odd multiplicity (p goes + to -) must be reported, to cube-root-eps accuracy."""
    assert [float(r) for r in naive_exit_roots(list(coeffs))] == exits
    got = kernel_exits(list(coeffs), INF, len(coeffs) - 1)
    assert len(got) == len(exits) and all(abs(g - e) <= 1e-4 * e for g, e in zip(got, exits)), got


@pytest.mark.parametrize("degree", [2, 3, 4])
def test_random_coefficients_match_twin(degree):
    """IID coefficients of random sign and exponents: no planted structure at all."""
    rng = np.random.default_rng(seed_of("iid", degree))
    failures = []
    n = 300
    for i in range(n):
        c = list(rng.normal(size=degree + 1) * 10.0 ** rng.uniform(-8, 8, degree + 1))
        hi = INF if rng.random() < 0.5 else loguni(rng, -4, 4)
        msg = compare_exits(c, hi, degree, tag=f"iid/deg{degree}")
        if msg:
            failures.append(f"case {i}: {msg}")
    assert not failures, f"{len(failures)}/{n} cases disagree, first: " + "\n".join(failures[:3])


@pytest.mark.parametrize("family", ["separated", "near_zero", "clustered"])
def test_degree_drop_on_exact_zero_leading_coefficients(family):
    """quartic_exits/cubic_exits with exact (+/-)0.0 leading coefficients solve the lower degree."""
    rng = np.random.default_rng(seed_of("drop", family))
    failures = []
    n = 0
    for true_degree in (1, 2, 3):
        for called in range(true_degree + 1, 5):
            if called < 3:
                continue
            for _i in range(60):
                if true_degree == 1:
                    c = [rng.choice([-1, 1]) * loguni(rng, -3, 3), rng.choice([-1, 1]) * loguni(rng, -3, 3)]
                    hi = INF
                else:
                    c, hi = make_case(rng, family, true_degree)
                zero = 0.0 if rng.random() < 0.5 else -0.0
                padded = list(c) + [zero] * (called + 1 - len(c))
                msg = compare_exits(padded, hi, called, tag=f"drop{true_degree}->{called}")
                n += 1
                if msg:
                    failures.append(msg)
                # and the answer is bit-for-bit the lower-degree kernel's
                lower = kernel_exits(c, hi, true_degree)
                if kernel_exits(padded, hi, called) != lower:
                    failures.append(f"degree {called} with zero lead != degree {true_degree}: {padded!r} hi={hi}")
    assert not failures, f"{len(failures)}/{n} disagree, first: " + "\n".join(failures[:3])


def test_zero_inner_coefficients():
    """Exact zeros below the leading term (``t^4 - k``, ``a t^3 + c``, ...) are not degree drops."""
    rng = np.random.default_rng(seed_of("inner"))
    failures = []
    n = 0
    for degree in (2, 3, 4):
        for _i in range(120):
            c = list(rng.normal(size=degree + 1) * 10.0 ** rng.uniform(-3, 3, degree + 1))
            for j in range(degree):
                if rng.random() < 0.5:
                    c[j] = 0.0
            msg = compare_exits(c, INF, degree, tag=f"inner/deg{degree}")
            n += 1
            if msg:
                failures.append(msg)
    assert not failures, f"{len(failures)}/{n} disagree, first: " + "\n".join(failures[:3])


# --------------------------------------------------------------------------- linear and quadratic

def test_linear_exit_is_correctly_rounded():
    """``-c0 / c1`` is one IEEE division: the kernel's exit is the twin's root rounded to nearest."""
    rng = np.random.default_rng(seed_of("linear"))
    bad = []
    for _i in range(1500):
        c0 = rng.choice([-1.0, 1.0, 1.0, 1.0]) * loguni(rng, -12, 12)
        c1 = rng.choice([-1.0, -1.0, 1.0]) * loguni(rng, -12, 12)
        hi = INF if rng.random() < 0.7 else loguni(rng, -14, 14)
        exits = naive_exit_roots([c0, c1], hi)
        want = float(exits[0]) if exits else INF
        got = linear_exit(c0, c1, hi)
        if got != want:
            bad.append((c0, c1, hi, got, want))
    assert not bad, f"{len(bad)} linear exits differ, first (c0, c1, hi, kernel, twin): {bad[:3]}"


@pytest.mark.parametrize("c0, c1, expected", [
    (1.0, -2.0, 0.5),
    (0.0, -1.0, INF),      # on the element moving out: the root t = 0 is excluded
    (-0.0, -1.0, INF),
    (-1.0, -1.0, INF),     # outside, moving further out: no root in t > 0
    (-1.0, 1.0, INF),      # an entry, not an exit
    (1.0, 0.0, INF),       # parallel
    (1.0, -0.0, INF),
    (5e-324, -1.0, 5e-324),
])
def test_linear_exit_special_values(c0, c1, expected):
    assert linear_exit(c0, c1, INF) == expected
    twin = naive_exit_roots([c0, c1], INF)
    assert (float(twin[0]) if twin else INF) == expected


@pytest.mark.parametrize("degree", [1, 2])
def test_root_exactly_at_hi_is_included_closed_forms(degree):
    c = [1.0, -1.0] if degree == 1 else [1.0, 0.0, -1.0]
    assert kernel_exits(c, 1.0, degree) == [1.0]
    assert [float(r) for r in naive_exit_roots(c, 1.0)] == [1.0]


@pytest.mark.parametrize("degree", [3, 4])
def test_root_exactly_at_hi_is_included_isolation(degree):
    c = [1.0, 0.0, 0.0, -1.0] if degree == 3 else [1.0, 0.0, 0.0, 0.0, -1.0]
    assert [float(r) for r in naive_exit_roots(c, 1.0)] == [1.0]
    assert kernel_exits(c, 1.0, degree) == [1.0]


def root_close(got, want, c):
    """``got`` agrees with the exact root ``want`` of ``c`` within what its conditioning allows."""
    mags = [abs(v) for v in c]
    pred = naive.predicted_root_error(c, want, mags, K_EVAL)
    if pred <= WELL * abs(want):
        return abs(got - want) <= REL_TOL * abs(want)
    return abs(got - want) <= C_PRED * pred + 4 * EPS * abs(want)


def test_quadratic_roots_match_twin():
    """All real roots (both signs) of ``quadratic_roots`` against the twin."""
    rng = np.random.default_rng(seed_of("quadroots"))
    bad = []
    n = 500
    for i in range(n):
        family = ["separated", "near_zero", "clustered"][i % 3]
        c, _ = make_case(rng, family, 2)
        if rng.random() < 0.3:  # complex pair
            c = expand(c[2], [], [(loguni(rng, -2, 2), loguni(rng, -2, 2))])
        k, r1, r2 = quadratic_roots(*c)
        got = [r1, r2][:k]
        want = naive_all_real_roots(c)
        if len(got) != len(want) or not all(root_close(g, w, c) for g, w in zip(got, want)):
            bad.append((c, (k, r1, r2), [float(w) for w in want]))
    assert not bad, f"{len(bad)}/{n} quadratic_roots differ, first (coeffs, kernel, twin): {bad[:3]}"


def test_quadratic_roots_double_and_degenerate():
    assert quadratic_roots(1.0, -2.0, 1.0) == (1, 1.0, INF)          # double root counts once
    assert quadratic_roots(1.0, 0.0, 1.0)[0] == 0                    # complex pair
    assert quadratic_roots(-3.0, 2.0, 0.0) == (1, 1.5, INF)          # linear
    assert quadratic_roots(1.0, 0.0, 0.0)[0] == 0                    # constant
    assert quadratic_roots(0.0, 1.0, 1.0) == (2, -1.0, 0.0)          # a root exactly at 0


def test_cubic_roots_in_match_twin():
    """All real roots of a cubic in ``[lo, hi]`` (used for the critical points of quartics)."""
    rng = np.random.default_rng(seed_of("cubicroots"))
    bad = []
    n = 400
    for i in range(n):
        family = ["separated", "near_zero", "clustered"][i % 3]
        c, _ = make_case(rng, family, 3)
        T = max([abs(v) for v in naive_all_real_roots(c)] or [1.0])
        lo = float(-T * rng.uniform(0, 1.5)) if rng.random() < 0.5 else 0.0
        hi = float(T * rng.uniform(0.2, 1.5))
        got = [r for r in cubic_roots_in(*c, lo, hi) if r != INF]
        want = naive_roots_between(c, lo, hi)
        ok = len(got) == len(want) and all(root_close(g, w, c) for g, w in zip(got, want))
        if not ok:
            # a root within rounding of lo or hi may fall either side
            edge = any(min(abs(w - lo), abs(w - hi)) <= 1e-12 * T for w in want)
            if not edge:
                bad.append((c, lo, hi, got, [float(w) for w in want]))
    assert not bad, f"{len(bad)}/{n} cubic_roots_in differ, first (coeffs, lo, hi, kernel, twin): {bad[:3]}"


def test_twin_self_check():
    """The twin on polynomials whose roots are known exactly (guards the oracle itself)."""
    # (t - 1)(t - 2)(t - 3)(t - 4): exits where the sign goes + -> -
    c = [24.0, -50.0, 35.0, -10.0, 1.0]
    assert [float(r) for r in naive_exit_roots(c)] == [1.0, 3.0]
    assert [float(r) for r in naive_exit_roots([-v for v in c])] == [2.0, 4.0]
    assert [float(r) for r in naive_exit_roots(c, 2.5)] == [1.0]
    # double root (tangency) is no exit; triple root with + -> - is
    assert naive_exit_roots([1.0, -2.0, 1.0]) == []
    assert [float(r) for r in naive_exit_roots([1.0, -3.0, 3.0, -1.0])] == [1.0]
    # root at t = 0 is excluded
    assert naive_exit_roots([0.0, -1.0]) == []
    # sqrt 2 to 50 digits
    with mpmath.workdps(50):
        (r,) = naive_exit_roots([2.0, 0.0, -1.0])
        assert abs(r - mpmath.sqrt(2)) < mpmath.mpf(10) ** -40


def test_report_accuracy():
    """Not a check: prints the largest relative error measured on well-conditioned roots."""
    if MEASURED:
        worst = max(MEASURED.values())
        print(f"\nmax relative error on well-conditioned exit roots: {worst:.3e} "
              f"({worst / EPS:.2f} eps) over families {sorted(MEASURED)}")
        assert worst <= REL_TOL


@pytest.mark.parametrize("degree", [1, 2, 3, 4])
def test_exact_rescaling_is_bitwise_invariant(degree):
    """Scaling ``p`` by ``2^k`` (and time by ``2^j`` with a finite horizon) is exact in floats, so
    the exits must be the same bits (scaled by ``2^j``): the solvers have no absolute epsilons."""
    rng = np.random.default_rng(seed_of("rescale", degree))
    bad = []
    for i in range(300):
        family = FAMILIES[i % len(FAMILIES)] if degree > 1 else "separated"
        if degree == 1:
            c = [rng.choice([-1.0, 1.0]) * loguni(rng, -3, 3), rng.choice([-1.0, 1.0]) * loguni(rng, -3, 3)]
            hi = INF
        else:
            c, hi = make_case(rng, family, degree)
        base = kernel_exits(c, hi, degree)
        k = int(rng.integers(-150, 151))
        scaled = [math.ldexp(v, k) for v in c]
        if kernel_exits(scaled, hi, degree) != base:
            bad.append((f"p * 2^{k}", c, hi, base, kernel_exits(scaled, hi, degree)))
        if hi < INF:
            j = int(rng.integers(-20, 21))
            # p(t) = sum c_i t^i, s = 2^j t: p = sum (c_i 2^{-i j}) s^i
            tc = [math.ldexp(v, -i * j) for i, v in enumerate(c)]
            want = [math.ldexp(t, j) for t in base]
            got = kernel_exits(tc, math.ldexp(hi, j), degree)
            if got != want:
                bad.append((f"t * 2^{j}", c, hi, want, got))
    assert not bad, f"{len(bad)} rescaled cases differ, first (what, coeffs, hi, expected, got): {bad[:3]}"


# ---------------------------------------------------------------------------- the shared pieces


def test_secant_start_is_regula_falsi_or_the_midpoint():
    """The start of every polish: the regula falsi point inside the open bracket, else its midpoint."""
    assert secant_start(1.0, 3.0, 1.0, -1.0) == 2.0
    assert secant_start(0.0, 4.0, 3.0, -1.0) == 3.0
    # fb = -0 and fa tiny: the secant lands on b, not inside the open bracket
    assert secant_start(1.0, 2.0, 1e-300, -0.0) == 1.5


@pytest.mark.parametrize("sa", [True, False])
def test_bracket_step_keeps_the_sign_change_and_takes_newton_inside(sa):
    """``t`` replaces the end of its sign; the Newton iterate is taken inside the new bracket."""
    s = 1.0 if sa else -1.0  # f = s (2 - t) on [1, 3]: f(a) > 0 iff sa
    a, b, tn, done = bracket_step(1.0, 3.0, 1.5, s * 0.5, -s, sa)
    assert (a, b, tn, done) == (1.5, 3.0, 2.0, False)
    a, b, tn, done = bracket_step(1.0, 3.0, 2.5, -s * 0.5, -s, sa)
    assert (a, b, tn, done) == (1.0, 2.5, 2.0, False)


def test_bracket_step_bisects_where_newton_leaves_the_bracket_or_stalls():
    """A Newton iterate outside the bracket, or a zero derivative, gives the bisection point."""
    assert bracket_step(0.0, 4.0, 1.0, 1.0, -0.01, True) == (1.0, 4.0, 2.5, False)  # Newton: 101
    assert bracket_step(0.0, 4.0, 1.0, 1.0, 0.0, True) == (1.0, 4.0, 2.5, False)


def test_bracket_step_stops_at_a_zero_and_at_rounding():
    """An exact zero is the root; a step or a bracket down to rounding is done."""
    assert bracket_step(0.0, 4.0, 1.25, 0.0, -1.0, True) == (0.0, 4.0, 1.25, True)
    t = 1.0 + 2.0 ** -52
    _, _, tn, done = bracket_step(0.0, 4.0, t, 2.0 ** -52, -1.0, True)  # Newton: 1 + 2^-51
    assert done and tn == 1.0 + 2.0 ** -51
    a, b, tn, done = bracket_step(1.0, 1.0 + 2.0 ** -51, 1.0 + 2.0 ** -52, 1.0, -1e-300, True)
    assert done and (a, b) == (1.0 + 2.0 ** -52, 1.0 + 2.0 ** -51)


def exact_circle_exit(d, v, sig, r):
    """The exit time of the exact straight flight ``d + v t`` (float inputs taken exactly) from the circle."""
    with mpmath.workprec(300):
        dx, dy, vx, vy, r = (mpmath.mpf(u) for u in (*d, *v, r))
        a = vx * vx + vy * vy
        b = 2 * (dx * vx + dy * vy)
        c = dx * dx + dy * dy - r * r
        disc = b * b - 4 * a * c
        if disc <= 0:
            return INF
        ts = sorted([(-b - mpmath.sqrt(disc)) / (2 * a), (-b + mpmath.sqrt(disc)) / (2 * a)])
        t = ts[0] if sig > 0 else ts[1]  # outside the circle: entering it; inside: leaving it
        return float(t) if t > 0 else INF


@pytest.mark.parametrize("sig", [1.0, -1.0])
def test_straight_circle_exit_matches_the_exact_intersection(sig):
    """Random straight flights from outside (``sig = 1``) or inside (``sig = -1``) a circle: the exit is the
    exact line-circle intersection, to the rounding of a well-conditioned root."""
    rng = np.random.default_rng(seed_of("straight circle", sig))
    worst, hits = 0.0, 0
    for _ in range(400):
        r = loguni(rng, -2, 2)
        ang, speed = rng.uniform(0, 2 * math.pi), loguni(rng, -2, 2)
        dist = r * (rng.uniform(1.05, 5.0) if sig > 0 else rng.uniform(0.0, 0.95))
        d = (dist * math.cos(ang), dist * math.sin(ang))
        aim = ang + math.pi + rng.normal(0, 0.4 if sig > 0 else 2.0)
        v = (speed * math.cos(aim), speed * math.sin(aim))
        want = exact_circle_exit(d, v, sig, r)
        got = straight_circle_exit(d[0], d[1], v[0], v[1], sig, r, False, INF)
        if want == INF or got == INF:
            # only near-tangent flights may disagree on whether they hit
            miss = abs(d[0] * v[1] - d[1] * v[0]) / speed
            assert got == want or abs(miss - r) <= 1e-6 * r, (d, v, sig, r, want, got)
            continue
        hits += 1
        worst = max(worst, abs(got - want) / want)
    assert hits > 100
    assert worst <= REL_TOL


@pytest.mark.parametrize("sig, inward, expected", [(-1.0, True, "chord"), (-1.0, False, "none"),
                                                   (1.0, False, "none")])
def test_straight_circle_exit_after_a_hit(sig, inward, expected):
    """Just hit at ``t = 0`` (deflated): from inside, the chord's other end ``-2 d.v / |v|^2``; a flight
    leaving the circle outward, or one outside moving away, never meets it again."""
    d = (0.6, 0.8)
    v = (-0.3, -0.5) if inward else (0.3, 0.5)
    got = straight_circle_exit(d[0], d[1], v[0], v[1], sig, 1.0, True, INF)
    if expected == "none":
        assert got == INF
    else:
        want = -2.0 * (d[0] * v[0] + d[1] * v[1]) / (v[0] * v[0] + v[1] * v[1])
        assert got == pytest.approx(want, rel=1e-15)
        assert straight_circle_exit(d[0], d[1], v[0], v[1], sig, 1.0, True, 0.5 * want) == INF
