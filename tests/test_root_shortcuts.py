"""The two shortcuts of the quartic/cubic exits on finite windows, against the exact twin.

``surely_positive`` (Bernstein bound) may only exclude polynomials that have no
root in ``[0, hi]``; ``surely_convex`` may only accept polynomials whose second
derivative has no root there; on convex windows ``convex_first_exit`` must find
the exits the full isolation finds.  The cases are the crossing polynomials the
Galton board produces: circles under a force, flights clipped to short windows,
many of them grazing.
"""
import math

import numpy as np
import pytest
from naive import naive_all_real_roots
from test_roots import compare_exits, loguni, seed_of

from noslipsim.core.geometry import crossing_coefficients
from noslipsim.core.layout import CIRCLE
from noslipsim.core.roots import convex_first_exit, surely_convex, surely_positive

INF = math.inf


def circle_cases(rng, n, grazing):
    """Crossing coefficients of a unit-ish circle (scatterer) along flights under a force, with a window."""
    p = np.zeros(10)
    p[2] = 1.0
    p[3] = 1.0
    out = []
    while len(out) < n:
        ang = rng.uniform(0, 2 * math.pi)
        dist = 1.0 + (loguni(rng, -10, -3) if grazing else loguni(rng, -3, 0.5))
        q = dist * np.array([math.cos(ang), math.sin(ang)])
        # aim past the circle at impact parameter b (grazing: b ~ 1)
        b = 1.0 + rng.choice([-1.0, 1.0]) * loguni(rng, -12, -4) if grazing else rng.uniform(-1.5, 1.5)
        to_c = -q / np.linalg.norm(q)
        side = np.array([-to_c[1], to_c[0]])
        speed = loguni(rng, -1, 1.5)
        v = speed * (to_c * math.sqrt(max(0.0, 1.0 - min(abs(b) / dist, 1.0) ** 2)) + side * min(b / dist, 1.0))
        a = rng.normal(size=2) * loguni(rng, -3, 1)
        c = crossing_coefficients(CIRCLE, p, q[0], q[1], v[0], v[1], a[0], a[1])
        if c[0] <= 0.0:
            continue
        out.append((list(c), loguni(rng, -2, 0.5) * dist / speed))
    return out


@pytest.mark.parametrize("grazing", [False, True], ids=["general", "grazing"])
def test_quartic_exits_on_circle_windows_match_twin(grazing):
    rng = np.random.default_rng(seed_of("circle windows", grazing))
    cases = circle_cases(rng, 400, grazing)
    convex = sum(surely_convex(c[2], c[3], c[4], hi) for c, hi in cases)
    assert convex > 100, "the cases must exercise the convex shortcut"
    failures = [m for m in (compare_exits(c, hi, 4, tag=f"circle windows/{grazing}") for c, hi in cases) if m]
    assert not failures, f"{len(failures)}/{len(cases)} cases disagree, first: {failures[0]}"


def _roots_in(c, lo, hi):
    return [r for r in naive_all_real_roots(c) if lo <= r <= hi]


def test_surely_positive_never_excludes_a_root():
    rng = np.random.default_rng(seed_of("bernstein"))
    cases = circle_cases(rng, 300, False) + circle_cases(rng, 300, True)
    excluded = 0
    for c, hi in cases:
        if surely_positive(*c, hi):
            excluded += 1
            assert not _roots_in(c, 0, hi), (c, hi)
    assert excluded > 50


def test_surely_convex_only_on_convex_windows():
    rng = np.random.default_rng(seed_of("convex"))
    accepted = 0
    for c, hi in circle_cases(rng, 300, False) + circle_cases(rng, 300, True):
        if surely_convex(c[2], c[3], c[4], hi):
            accepted += 1
            second = [2.0 * c[2], 6.0 * c[3], 12.0 * c[4]]
            assert second[0] > 0 and not _roots_in(second, 0, hi), (c, hi)
    assert accepted > 100


@pytest.mark.parametrize("c, hi, expected", [
    pytest.param((1.0, -2.0, 1.0, 0.0, 1e-30), 10.0, -1.0, id="tangency: handed to the isolation"),
    pytest.param((1.0, -2.0, 0.5, 0.0, 1e-30), 10.0, 2.0 - math.sqrt(2.0), id="simple root"),
    pytest.param((1.0, 1.0, 1.0, 0.0, 1.0), 10.0, INF, id="moving away"),
    pytest.param((1.0, -1.0, 1.0, 0.0, 1.0), 10.0, INF, id="dips but stays positive"),
    pytest.param((1.0, -4.0, 1.0, 0.0, 1.0), 0.1, INF, id="root past the window"),
])
def test_convex_first_exit_cases(c, hi, expected):
    got = convex_first_exit(*c, hi)
    assert got == expected if expected in (INF, -1.0) else abs(got - expected) <= 1e-15


def test_tangency_is_no_exit_through_the_shortcut():
    """An exact double root under the convex shortcut gives what the full isolation gives: no exit."""
    from noslipsim.core.roots import quartic_exits
    assert quartic_exits(1.0, -2.0, 1.0, 0.0, 1e-30, 10.0) == (INF, INF)
