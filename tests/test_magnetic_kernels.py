"""The closed-form magnetic flight kernels (core/magnetic.py) against their mpmath twin (reference/magnetic.py).

Random and hand-picked flights: the path, exit roots through lines and circles (deflated, near t = 0,
grazing), extents of segments and arcs, W -> 0 against the straight flight, huge and negative W.
"""
import math

import mpmath
import numba
import numpy as np
import pytest

from noslipsim.core import magnetic as mg
from noslipsim.reference.magnetic import MagneticPath

DPS = 40
CTX = mpmath.MPContext()
CTX.dps = DPS
FLOOR = CTX.mpf(10) ** (-(2 * DPS) // 5)
F = CTX.mpf


def path(x, y, vx, vy, W):
    return MagneticPath(CTX, F(x), F(y), F(vx), F(vy), F(W))


def ref_line_exit(x, y, vx, vy, W, px, py, nx, ny, deflate=False):
    """The reference's first exit through the line (outward normal n), or inf; and the slope there."""
    p = path(x, y, vx, vy, W)
    g0 = F(0) if deflate else -(F(nx) * (F(x) - F(px)) + F(ny) * (F(y) - F(py)))
    roots = p.exits(*p.line_terms(g0, -F(nx), -F(ny)), deflate, FLOOR)
    return float(roots[0]) if roots else math.inf


def ref_circle_exit(x, y, vx, vy, W, cx, cy, r, sigma, deflate=False):
    p = path(x, y, vx, vy, W)
    roots = p.exits(*p.circle_terms(F(cx), F(cy), F(r), F(sigma), deflate), deflate, FLOOR)
    return float(roots[0]) if roots else math.inf


# ---------------------------------------------------------------------------- exits through whole elements
# Built from the core's exits as the tests need them (the engine's cell search has its own,
# magnetic_flight.element_exit); compiled so that whole orbits run at kernel speed.
@numba.njit
def segment_exit(x, y, vx, vy, W, px, py, nx, ny, ux, uy, length, tol, deflate):
    """``mg.line_exit`` within the segment from ``p`` along the unit ``u`` (``0 <= s <= length`` within ``tol``)."""
    t = mg.line_exit(x, y, vx, vy, W, px, py, nx, ny, deflate)
    if t == math.inf:
        return math.inf
    hx, hy, _, _ = mg.advance(x, y, vx, vy, W, t)
    s = (hx - px) * ux + (hy - py) * uy
    return t if -tol <= s <= length + tol else math.inf


@numba.njit
def arc_exit(x, y, vx, vy, W, cx, cy, r, sigma, theta0, span, tol, deflate):
    """``mg.circle_exit`` within the arc counter-clockwise from ``theta0`` over ``span`` (ends within ``tol``)."""
    t = mg.circle_exit(x, y, vx, vy, W, cx, cy, r, sigma, deflate)
    if t == math.inf:
        return math.inf
    hx, hy, _, _ = mg.advance(x, y, vx, vy, W, t)
    ang = (math.atan2(hy - cy, hx - cx) - theta0) % (2.0 * math.pi)
    slack = tol / r
    if ang <= span + slack or ang >= 2.0 * math.pi - slack:
        return t
    return math.inf


@numba.njit
def line_meets(x, y, vx, vy, W, px, py, nx, ny):
    """The cyclotron circle (``W = 0``: the flight's whole line) touches or crosses the line (certified as grazing)."""
    c0, c1, c2, m0, m1, m2 = mg.line_coefficients(x, y, vx, vy, W, px, py, nx, ny, False)
    return mg.can_meet(c0, c1, c2, m0, m1, m2)


@numba.njit
def circle_meets(x, y, vx, vy, W, cx, cy, r):
    """The cyclotron circle (``W = 0``: the flight's whole line) touches or crosses the circle."""
    c0, c1, c2, m0, m1, m2 = mg.circle_coefficients(x, y, vx, vy, W, cx, cy, r, 1.0, False)
    return mg.can_meet(c0, c1, c2, m0, m1, m2)


def random_flight(rng):
    ang = rng.uniform(0, 2 * math.pi)
    speed = rng.uniform(0.3, 3.0)
    W = rng.choice([-1.0, 1.0]) * 10 ** rng.uniform(-2, 1.5)
    return rng.uniform(-1, 1), rng.uniform(-1, 1), speed * math.cos(ang), speed * math.sin(ang), W


# ---------------------------------------------------------------------------- the path
def test_path_against_the_twin_on_random_flights():
    rng = np.random.default_rng(1)
    for _ in range(200):
        x, y, vx, vy, W = random_flight(rng)
        t = rng.uniform(0, 3 * 2 * math.pi / abs(W))
        got = mg.advance(x, y, vx, vy, W, t)
        p = path(x, y, vx, vy, W)
        want = [float(v) for v in (*p.position(F(t)), *p.velocity(F(t)))]
        scale = max(1.0, abs(x), abs(y), math.hypot(vx, vy) / abs(W))
        np.testing.assert_allclose(got[:2], want[:2], rtol=0, atol=64 * mg.EPS * scale * max(1, abs(W * t)))
        speed = math.hypot(vx, vy)
        np.testing.assert_allclose(got[2:], want[2:], rtol=0, atol=16 * mg.EPS * speed * max(1, abs(W * t)))


def test_path_is_a_circle_about_its_exact_centre():
    x, y, vx, vy, W = 0.3, -0.2, 0.6, 0.8, 2.5
    mx, my, rho = mg.centre(x, y, vx, vy, W)
    assert (mx, my, rho) == (0.3 - 0.8 / 2.5, -0.2 + 0.6 / 2.5, 1.0 / 2.5)
    for t in np.linspace(0, 7, 50):
        px, py, qx, qy = mg.advance(x, y, vx, vy, W, t)
        assert abs(math.hypot(px - mx, py - my) - rho) <= 8 * mg.EPS
        assert abs(math.hypot(qx, qy) - 1.0) <= 4 * mg.EPS
    # counter-clockwise for W > 0: the velocity has turned by W t
    _, _, qx, qy = mg.advance(x, y, vx, vy, W, 0.1)
    assert math.isclose(math.atan2(qy, qx) - math.atan2(vy, vx), 0.25, rel_tol=1e-14)
    assert mg.period(W) == 2 * math.pi / 2.5 and mg.period(0.0) == math.inf and mg.period(-W) == mg.period(W)


@pytest.mark.parametrize("W", [1e-9, 1e-30, 1e-300, 5e-324, 0.0])
def test_weak_field_is_the_straight_flight(W):
    x, y, vx, vy, t = 0.25, -0.5, 0.7, -1.3, 3.7
    px, py, qx, qy = mg.advance(x, y, vx, vy, W, t)
    assert abs(px - (x + vx * t)) <= 2 * mg.EPS * 5 + abs(W) * 10
    assert abs(py - (y + vy * t)) <= 2 * mg.EPS * 5 + abs(W) * 10
    if W <= 1e-30:
        assert (px, py, qx, qy) == (x + vx * t, y + vy * t, vx, vy)


# ---------------------------------------------------------------------------- exit roots
def agreeing_hits(pairs):
    """Assert each ``(kernel, twin, meets)`` agrees (both inf, or equal roots; ``meets`` iff a root); the hits."""
    hits = 0
    for got, want, meets in pairs:
        assert meets == (want < math.inf)
        if want == math.inf:
            assert got == math.inf
            continue
        hits += 1
        assert got == pytest.approx(want, rel=1e-11, abs=1e-13)
    return hits


def test_line_exits_against_the_twin():
    rng = np.random.default_rng(2)
    pairs = []
    for _ in range(300):
        x, y, vx, vy, W = random_flight(rng)
        ang = rng.uniform(0, 2 * math.pi)
        nx, ny = math.cos(ang), math.sin(ang)
        px, py = x + nx * rng.uniform(0.01, 2), y + ny * rng.uniform(0.01, 2)  # the start on the table side
        pairs.append((mg.line_exit(x, y, vx, vy, W, px, py, nx, ny, False),
                      ref_line_exit(x, y, vx, vy, W, px, py, nx, ny),
                      line_meets(x, y, vx, vy, W, px, py, nx, ny)))
    assert agreeing_hits(pairs) > 100


def test_circle_exits_against_the_twin():
    rng = np.random.default_rng(3)
    pairs = []
    for _ in range(300):
        x, y, vx, vy, W = random_flight(rng)
        r = rng.uniform(0.05, 1.5)
        ang = rng.uniform(0, 2 * math.pi)
        if rng.uniform() < 0.5:  # a scatterer beside the start
            sigma, dist = 1.0, r + rng.uniform(0.01, 1.5)
        else:  # a container around it
            sigma, dist = -1.0, r * rng.uniform(0.0, 0.95)
        cx, cy = x + dist * math.cos(ang), y + dist * math.sin(ang)
        pairs.append((mg.circle_exit(x, y, vx, vy, W, cx, cy, r, sigma, False),
                      ref_circle_exit(x, y, vx, vy, W, cx, cy, r, sigma),
                      circle_meets(x, y, vx, vy, W, cx, cy, r)))
    assert agreeing_hits(pairs) > 100


def test_deflated_roots_against_the_twin():
    """From a point on the element moving into the table: the next exit, with t = 0 removed analytically."""
    rng = np.random.default_rng(4)
    for _ in range(100):
        _, _, vx, vy, W = random_flight(rng)
        # a container circle about the origin, the particle on it moving inwards
        r, a = 1.0, rng.uniform(0, 2 * math.pi)
        x, y = r * math.cos(a), r * math.sin(a)
        if vx * x + vy * y > 0:
            vx, vy = -vx, -vy
        got = mg.circle_exit(x, y, vx, vy, W, 0.0, 0.0, r, -1.0, True)
        want = ref_circle_exit(x, y, vx, vy, W, 0.0, 0.0, r, -1.0, True)
        assert got == pytest.approx(want, rel=1e-11)
        # the line y = 0 with the table above, the particle on it moving up
        got = mg.line_exit(x, 0.0, vx, abs(vy), W, 0.3, 0.0, 0.0, -1.0, True)
        want = ref_line_exit(x, 0.0, vx, abs(vy), W, 0.3, 0.0, 0.0, -1.0, True)
        assert got == pytest.approx(want, rel=1e-12)
        # on the line and moving out: its exit is t = 0 itself, never a later hit
        assert mg.line_exit(x, 0.0, vx, -abs(vy), W, 0.3, 0.0, 0.0, -1.0, True) == math.inf


def test_deflated_line_is_met_again_after_a_turn():
    """A field turns a flight off a floor back onto it: x(t) = (sin t, 1 - cos t) from the origin, W = 1, v = (0, 1)
    rotated: the exit is the other end of the chord, at t = 2 atan2(B, A) exactly."""
    W = 1.0
    for beta in (0.1, 0.7, 1.5707963267948966, 2.5, 3.1):
        vx, vy = math.cos(beta), math.sin(beta)  # leaving the floor y = 0 at angle beta
        t = mg.line_exit(0.0, 0.0, vx, vy, W, 0.0, 0.0, 0.0, -1.0, True)
        assert t == pytest.approx(2 * math.pi - 2 * beta, rel=1e-14)
        t = mg.line_exit(0.0, 0.0, vx, vy, -W, 0.0, 0.0, 0.0, -1.0, True)
        assert t == pytest.approx(2 * beta, rel=1e-14)


@pytest.mark.parametrize("gap", [1e-8, 1e-12, 1e-15])
def test_roots_near_t0(gap):
    """A start ``gap`` inside a line, moving out: the exit at ~gap/|v_n|, to its own relative precision."""
    for W in (3.0, -3.0, 1e-6):
        got = mg.line_exit(0.0, -gap, 0.6, 0.8, W, 0.0, 0.0, 0.0, 1.0, False)
        want = ref_line_exit(0.0, -gap, 0.6, 0.8, W, 0.0, 0.0, 0.0, 1.0)
        assert got == pytest.approx(want, rel=1e-13)
        assert got == pytest.approx(gap / 0.8, rel=1e-6)


def test_grazing_is_certified():
    """Cyclotron circle about (0, 1) of radius 1: the line y = 2 is tangent to it (touched, never crossed)."""
    x, y, vx, vy, W = 0.0, 0.0, 1.0, 0.0, 1.0
    tangent = (0.0, 2.0, 0.0, 1.0)  # point, outward normal: the table below y = 2
    assert mg.line_exit(x, y, vx, vy, W, *tangent, False) == math.inf
    assert ref_line_exit(x, y, vx, vy, W, *tangent) == math.inf
    assert line_meets(x, y, vx, vy, W, *tangent)
    for shift, hit in ((1e-9, True), (-1e-9, False), (1e-3, True)):
        line = (0.0, 2.0 - shift, 0.0, 1.0)
        assert line_meets(x, y, vx, vy, W, *line) == hit
        got = mg.line_exit(x, y, vx, vy, W, *line, False)
        want = ref_line_exit(x, y, vx, vy, W, *line)
        assert (got < math.inf) == hit == (want < math.inf)
        if hit:
            assert got == pytest.approx(want, rel=1e-7)  # sqrt-conditioned near a tangency
    # a circle tangent from outside: the circle about (0, 3) of radius 1 touches the cyclotron circle at (0, 2)
    assert mg.circle_exit(x, y, vx, vy, W, 0.0, 3.0, 1.0, 1.0, False) == math.inf
    assert circle_meets(x, y, vx, vy, W, 0.0, 3.0, 1.0)
    assert not circle_meets(x, y, vx, vy, W, 0.0, 3.0 + 1e-9, 1.0)


@pytest.mark.parametrize("W", [1e-8, -1e-8, 1e-13, 1e-200])
def test_weak_field_exits_equal_the_straight_ones(W):
    x, y, vx, vy = 0.1, 0.2, 0.6, -0.8
    # the floor y = -1: straight exit at 1.2 / 0.8
    t = mg.line_exit(x, y, vx, vy, W, 0.0, -1.0, 0.0, -1.0, False)
    assert t == pytest.approx(1.5, rel=max(4 * mg.EPS, 10 * abs(W)))
    if abs(W) >= 1e-13:  # the twin's plain 1 - cos(W t) keeps DPS - 2 |log10(W t)| digits
        assert t == pytest.approx(ref_line_exit(x, y, vx, vy, W, 0.0, -1.0, 0.0, -1.0), rel=1e-13)
    # a unit container about the origin: the straight chord's exit
    b = x * vx + y * vy
    straight = -b + math.sqrt(b * b + 1 - x * x - y * y)
    t = mg.circle_exit(x, y, vx, vy, W, 0.0, 0.0, 1.0, -1.0, False)
    assert t == pytest.approx(straight, rel=max(8 * mg.EPS, 10 * abs(W)))
    assert mg.line_exit(x, y, vx, vy, 0.0, 0.0, -1.0, 0.0, -1.0, False) == pytest.approx(1.5, rel=4 * mg.EPS)


def test_huge_field_circles_in_place():
    """W = 1e8: a cyclotron circle of radius 1e-8 meets only what lies within 2e-8 of its start."""
    x, y, vx, vy, W = 0.0, 0.0, 1.0, 0.0, 1e8
    assert not line_meets(x, y, vx, vy, W, 0.0, 1e-6, 0.0, 1.0)
    assert mg.line_exit(x, y, vx, vy, W, 0.0, 1e-6, 0.0, 1.0, False) == math.inf
    line = (0.0, 1.5e-8, 0.0, 1.0)
    got = mg.line_exit(x, y, vx, vy, W, *line, False)
    want = ref_line_exit(x, y, vx, vy, W, *line)
    assert got == pytest.approx(want, rel=1e-12) and got < 2 * math.pi / W


def test_negative_field_is_the_mirror_image():
    """Mirror y -> -y: W -> -W, the same exit times."""
    rng = np.random.default_rng(5)
    for _ in range(50):
        x, y, vx, vy, W = random_flight(rng)
        cx, cy, r = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.2, 2.0)
        a = mg.circle_exit(x, y, vx, vy, W, cx, cy, r, 1.0, False)
        b = mg.circle_exit(x, -y, vx, -vy, -W, cx, -cy, r, 1.0, False)
        assert a == pytest.approx(b, rel=1e-12) or a == b == math.inf


def test_segment_and_arc_extents():
    """The exit point decides: inside the segment's or arc's extent a hit, outside never (on any turn)."""
    x, y, vx, vy, W = 0.0, 0.0, 1.0, 0.0, 1.0  # the circle about (0, 1): crosses y = 1.5 leaving at x = -sqrt(3)/2
    t = mg.line_exit(x, y, vx, vy, W, 0.0, 1.5, 0.0, 1.0, False)
    hx, _, _, _ = mg.advance(x, y, vx, vy, W, t)
    assert hx == pytest.approx(math.sqrt(0.75), rel=1e-14)  # counter-clockwise: up the right side first
    seg = dict(px=0.0, py=1.5, nx=0.0, ny=1.0, ux=1.0, uy=0.0)
    for length, hit in ((1.0, True), (0.8, False)):
        got = segment_exit(x, y, vx, vy, W, *seg.values(), length, 1e-12, False)
        assert (got == t) if hit else got == math.inf
    # an arc of the circle |q - (0, 3)| = 2 (a scatterer): the orbit's exit point against it
    t = mg.circle_exit(x, y, vx, vy, W, 0.0, 3.0, 2.0, 1.0, False)
    hx, hy, _, _ = mg.advance(x, y, vx, vy, W, t)
    ang = math.atan2(hy - 3.0, hx)
    assert arc_exit(x, y, vx, vy, W, 0.0, 3.0, 2.0, 1.0, ang - 0.1, 0.2, 1e-12, False) == t
    assert arc_exit(x, y, vx, vy, W, 0.0, 3.0, 2.0, 1.0, ang + 0.1, 0.2, 1e-12, False) == math.inf
    assert arc_exit(x, y, vx, vy, W, 0.0, 3.0, 2.0, 1.0, ang, 0.2, 1e-12, False) == t  # end inclusive


def test_advance_many_matches_advance():
    rng = np.random.default_rng(6)
    x, y, vx, vy, t = (rng.uniform(-1, 1, 20) for _ in range(5))
    out = np.empty((20, 4))
    mg.advance_many(x, y, vx, vy, 1.7, np.abs(t), out)
    for i in range(20):
        assert tuple(out[i]) == mg.advance(x[i], y[i], vx[i], vy[i], 1.7, abs(t[i]))


def test_rounded_tangencies_are_grazes():
    """Tangencies written in rounded floats (a rotated copy of the tangent line and circle above): their
    discriminant is rounding noise of either sign, certified as a graze, never a crossing."""
    for a in np.linspace(0.01, 2 * math.pi, 400):
        vx, vy = math.cos(a), math.sin(a)
        ux, uy = -vy, vx  # towards the cyclotron centre J v / W (W = 1), at distance 1
        assert mg.line_exit(0.0, 0.0, vx, vy, 1.0, 2 * ux, 2 * uy, ux, uy, False) == math.inf
        assert line_meets(0.0, 0.0, vx, vy, 1.0, 2 * ux, 2 * uy, ux, uy)
        assert mg.circle_exit(0.0, 0.0, vx, vy, 1.0, 3 * ux, 3 * uy, 1.0, 1.0, False) == math.inf
        assert mg.circle_exit(0.0, 0.0, vx, vy, 1.0, 0.5 * ux, 0.5 * uy, 1.5, -1.0, False) == math.inf
