"""Event times of thermostatted flights (core/thermo_events.py) against the certified mpmath search.

The twin (:mod:`noslipsim.reference.thermostat`) cuts the flight into pieces on which the
crossing function provably keeps its sign or is monotone (from the bound ``|g''| <= M``), at
40 digits; it shares no code with the kernels (which use the unimodality of lines and
conservative steps between quadratic bounds for circles).  What must agree: whether there is
a hit, on which element, and its time (1e-10 relative where the hit is well conditioned, the
crossing rate ``|g'| / (c |grad g|)`` above 1e-6).  A hit within rounding of a tangency may go
either way; it is counted and must be rare.

Cases: random elements of every kind (lines, one-sided segments, scatterers, containers,
arcs of both sides) and flights under fields from weak (the path almost straight) to strong
(it curls within the element's size), most aimed at the element, some from behind one-sided
pieces, with and without a finite window; flights starting on the element just hit (the root
``t = 0`` removed: hops on a floor, a peg); near-tangencies to 1e-12; hits at segment and
arc ends; lattice strip exits; the level stop.
"""
import math
import zlib

import mpmath
import numpy as np
import pytest

from noslipsim import Arc, Circle, Line, Scene, Segment
from noslipsim._engine.table import kernel_table
from noslipsim.core import thermo_events
from noslipsim.core.thermostat import flight, state
from noslipsim.core.tolerances import EXTENT_TOL
from noslipsim.reference.engine import _EventLoop

INF = math.inf
REL = 1e-10
WELL = 1e-6


def seed_of(*parts):
    return zlib.crc32(repr(parts).encode())


def unit(a):
    return math.cos(a), math.sin(a)


def random_element(rng, kind):
    c = tuple(rng.normal(size=2))
    if kind == "line":
        return Line(c, unit(rng.uniform(0, 2 * math.pi)))
    if kind == "segment":
        d = unit(rng.uniform(0, 2 * math.pi))
        length = 10 ** rng.uniform(-0.5, 0.5)
        return Segment(c, (c[0] + length * d[0], c[1] + length * d[1]), str(rng.choice(["left", "right"])))
    r = 10 ** rng.uniform(-0.5, 0.3)
    side = str(rng.choice(["outside", "inside"]))
    if kind == "circle":
        return Circle(c, r, side)
    th0 = rng.uniform(-math.pi, 2 * math.pi)
    return Arc(c, r, th0, th0 + rng.uniform(0.3, 6.0), side)


def point_on(rng, element):
    """A point on the element and its inward normal (into the table)."""
    if isinstance(element, Line):
        n = element.normal
        s = 2 * rng.normal()
        return (element.point[0] - s * n[1], element.point[1] + s * n[0]), n
    if isinstance(element, Segment):
        f = rng.uniform(0.05, 0.95)
        p0, p1 = element.p0, element.p1
        row = kernel_table(Scene((element,))).params[0]
        return (p0[0] + f * (p1[0] - p0[0]), p0[1] + f * (p1[1] - p0[1])), (row[2], row[3])
    th = rng.uniform(0, 2 * math.pi) if isinstance(element, Circle) else \
        element.theta0 + rng.uniform(0.05, 0.95) * (element.theta1 - element.theta0)
    u = unit(th)
    sig = 1.0 if element.side == "outside" else -1.0
    return (element.center[0] + element.radius * u[0], element.center[1] + element.radius * u[1]), \
        (sig * u[0], sig * u[1])


FIELDS = {"weak": (-2, -0.5), "unit": (-0.3, 0.3), "strong": (0.5, 1.5)}


def random_flight(rng, element, field):
    E = 10 ** rng.uniform(*FIELDS[field])
    a = tuple(E * np.array(unit(rng.uniform(0, 2 * math.pi))))
    P, n = point_on(rng, element)
    depth = 10 ** rng.uniform(-2, 0.2)
    if isinstance(element, (Segment, Arc)) and rng.random() < 0.3:
        depth = -depth
    t_dir = (-n[1], n[0])
    off = rng.normal()
    if isinstance(element, Circle) and element.side == "inside":
        u = unit(rng.uniform(0, 2 * math.pi))
        rho = element.radius * rng.uniform(0, 0.99)
        q = (element.center[0] + rho * u[0], element.center[1] + rho * u[1])
    elif isinstance(element, Circle):
        u = unit(rng.uniform(0, 2 * math.pi))
        rho = element.radius * (1 + 10 ** rng.uniform(-2, 0.5))
        q = (element.center[0] + rho * u[0], element.center[1] + rho * u[1])
    else:
        d = abs(depth) if isinstance(element, Line) else depth
        q = (P[0] + d * n[0] + off * t_dir[0], P[1] + d * n[1] + off * t_dir[1])
    speed = 10 ** rng.uniform(-0.5, 0.5)
    if rng.random() < 0.65:
        target, _ = point_on(rng, element)
        d = np.subtract(target, q)
        v = tuple(speed * d / np.linalg.norm(d))
    else:
        v = tuple(speed * np.array(unit(rng.uniform(0, 2 * math.pi))))
    hi = INF if rng.random() < 0.7 else 10 ** rng.uniform(-1, 1) / speed
    return q, v, a, hi


def kernel_hit(element, q, v, a, deflate=False, hi=INF):
    table = kernel_table(Scene((element,)))
    fl = flight(q[0], q[1], v[0], v[1], a[0], a[1])
    tol = EXTENT_TOL * max(table.scale, abs(q[0]), abs(q[1]))
    return thermo_events.element_hit(table.kinds[0], table.params[0], fl, 0.0, 0.0, deflate, 0.0, hi, tol,
                                     math.hypot(*a))


def _loop(element, q, v, a, deflate, dps=40):
    scene = Scene((element,), law="specular", force=a, thermostat="isokinetic")
    loop = _EventLoop(scene, q, v, 0.0, 1, math.inf, None, dps)
    copy = loop.table.copies_at(0, 0)[0]
    if deflate:
        loop.current = copy
    return loop, copy


def reference_hit(element, q, v, a, deflate=False):
    """The reference's first hit on the whole flight (mpf), or None."""
    loop, copy = _loop(element, q, v, a, deflate)
    return loop.first_hit(copy, loop.tol())


def crossing_rate(element, q, v, a, t):
    """``|g'| / (c |grad g|)`` at time ``t`` of the flight: 1 head on, 0 at a tangency."""
    loop, copy = _loop(element, q, v, a, False)
    path = loop.path()
    x, y = path.position(mpmath.mpf(t))
    vx, vy = path.velocity(mpmath.mpf(t))
    el = copy.el
    if hasattr(el, "cx"):
        dx, dy = x - el.cx, y - el.cy
        return float(abs(dx * vx + dy * vy) / (mpmath.sqrt(dx * dx + dy * dy) * path.c))
    return float(abs(vx * el.nx + vy * el.ny) / path.c)


def compare(element, q, v, a, deflate=False, hi=INF):
    """``'ok'``, ``'grazing'`` (an ill-conditioned disagreement) or a failure message."""
    got = kernel_hit(element, q, v, a, deflate, hi)
    want = reference_hit(element, q, v, a, deflate)
    if want is not None and want > hi:
        want = None
    if want is None and got == INF:
        return "ok"
    t = float(want) if want is not None else got
    rate = crossing_rate(element, q, v, a, t)
    if want is not None and got < INF and abs(got - t) <= REL * (t + 1.0) / max(rate, WELL):
        return "ok"
    if rate < WELL:
        return "grazing"
    return (f"{type(element).__name__} q={q} v={v} a={a} deflate={deflate} hi={hi}: kernel {got}, "
            f"reference {want} (rate {rate:.3g})")


KINDS = ["line", "segment", "circle", "arc"]


@pytest.mark.parametrize("field", list(FIELDS))
@pytest.mark.parametrize("kind", KINDS)
def test_random_flights_match_the_certified_search(kind, field):
    rng = np.random.default_rng(seed_of("thermo flights", kind, field))
    results = []
    hits = 0
    for _ in range(32):
        element = random_element(rng, kind)
        q, v, a, hi = random_flight(rng, element, field)
        if not Scene((element,)).contains(np.array([q]))[0]:
            continue
        results.append(compare(element, q, v, a, hi=hi))
        hits += kernel_hit(element, q, v, a, hi=hi) < INF
    bad = [r for r in results if r not in ("ok", "grazing")]
    assert not bad, bad[:3]
    assert results.count("grazing") <= 1
    assert hits >= 4 and len(results) - hits >= 2, "the cases must exercise hits and misses"


@pytest.mark.parametrize("kind", KINDS)
def test_flights_leaving_the_element_just_hit(kind):
    """Deflation: from a point on the element into the table; the path may come back to it (t -> 0 root removed)."""
    rng = np.random.default_rng(seed_of("thermo deflated", kind))
    results = []
    returns = 0
    for _ in range(20):
        element = random_element(rng, kind)
        P, n = point_on(rng, element)
        E = 10 ** rng.uniform(-0.5, 1.0)
        a = (-E * n[0], -E * n[1]) if rng.random() < 0.5 else tuple(E * np.array(unit(rng.uniform(0, 6.3))))
        th = rng.uniform(-1.4, 1.4)
        t_dir = (-n[1], n[0])
        v = (math.cos(th) * n[0] + math.sin(th) * t_dir[0], math.cos(th) * n[1] + math.sin(th) * t_dir[1])
        results.append(compare(element, P, v, a, deflate=True))
        returns += kernel_hit(element, P, v, a, deflate=True) < INF
    bad = [r for r in results if r not in ("ok", "grazing")]
    assert not bad, bad[:3]
    assert returns >= 3


def test_hop_on_a_floor_under_the_field():
    """A ball leaving a floor with the field pressing it down hops and lands: no hit at t = 0, one after."""
    floor = Line((0.0, 0.0), (0.0, 1.0))
    for th in (0.05, 0.5, 1.2, 1e-6):
        v = (math.cos(th), math.sin(th))
        t = kernel_hit(floor, (0.0, 0.0), v, (0.0, -1.0), deflate=True)
        want = reference_hit(floor, (0.0, 0.0), v, (0.0, -1.0), deflate=True)
        assert t > 0 and abs(t - float(want)) <= 1e-12 * float(want), th
        # the hop's height is set by the curvature: the path turns down over the time 1/k
        assert t < 2 * math.pi


@pytest.mark.parametrize("side", ["outside", "inside"])
def test_near_tangent_flights_to_a_circle(side):
    """Flights that pass a circle within 1e-4 .. 1e-12 of tangency: hit iff the reference hits."""
    circle = Circle((0.0, 0.0), 1.0, side)
    a = (0.0, -1.0)
    counts = {"ok": 0, "grazing": 0}
    for delta in (1e-4, 1e-6, 1e-8, 1e-10, 1e-12):
        for sign in (-1.0, 1.0):
            # start on the path that touches the circle from the table side, shifted by +-delta
            r = 1.0 + sign * delta if side == "outside" else 1.0 - sign * delta
            q = (-0.8, r) if side == "outside" else (-0.3, r - 0.05)
            result = compare(circle, q if side == "outside" else (0.0, 0.0), (1.0, 0.0) if side == "outside"
                             else (0.7, 0.3), a)
            assert result in counts, result
            counts[result] += 1
    assert counts["grazing"] <= 2


def test_hits_at_segment_ends():
    """Flights aimed at a segment's end within +-1e-9 (convex ends inclusive by EXTENT_TOL): as the reference."""
    seg = Segment((0.0, 0.0), (1.0, 0.0), "left")
    for end in (0.0, 1.0):
        for off in (-1e-6, -1e-9, 1e-9, 1e-6):
            q = (end + off - 0.3, 0.5)
            v = (0.3, -0.5)
            assert compare(seg, q, v, (0.05, -0.4)) in ("ok", "grazing")


def test_face_exits_match_the_reference_strips():
    """Lattice strip exits (line functionals of the path) against the certified search."""
    rng = np.random.default_rng(11)
    ctx = mpmath.MPContext()
    ctx.dps = 40
    from noslipsim.reference.thermostat import ThermoPath, line_first_exit

    for _ in range(40):
        q = tuple(rng.uniform(-0.4, 0.4, 2))
        v = tuple(unit(rng.uniform(0, 6.3)))
        E = 10 ** rng.uniform(-1, 1)
        a = tuple(E * np.array(unit(rng.uniform(0, 6.3))))
        n = tuple(rng.normal(size=2))
        f0 = rng.uniform(0.01, 1.0)
        t_in = rng.uniform(0, 1.0) if rng.random() < 0.5 else 0.0
        fl = flight(q[0], q[1], v[0], v[1], a[0], a[1])
        got = thermo_events.face_exit(fl, f0, n[0], n[1], t_in)
        path = ThermoPath(ctx, *(ctx.mpf(float(x)) for x in (*q, *v, *a)))
        px, py = path.position(ctx.mpf(t_in))
        ft = f0 + n[0] * (px - q[0]) + n[1] * (py - q[1])
        if ft <= 0:
            continue
        want = line_first_exit(ctx, path, ctx.mpf(n[0]), ctx.mpf(n[1]), ctx.mpf(f0), ctx.mpf(t_in))
        if want is None:
            assert got == INF
        else:
            assert abs(got - float(want)) <= 1e-11 * max(1.0, float(want)), (got, want)


def test_line_functional_has_at_most_one_exit():
    """``f = f0 + n . (q(t) - q0)`` changes monotonicity at most once (the critical time), sampled densely."""
    rng = np.random.default_rng(5)
    for _ in range(200):
        v = unit(rng.uniform(0, 6.3))
        a = tuple(10 ** rng.uniform(-1, 1) * np.array(unit(rng.uniform(0, 6.3))))
        n = unit(rng.uniform(0, 6.3))
        fl = flight(0.0, 0.0, v[0], v[1], a[0], a[1])
        ts = np.linspace(0, 20 / math.hypot(*a), 400)
        f = np.array([n[0] * state(fl, t)[0] + n[1] * state(fl, t)[1] for t in ts])
        changes = np.count_nonzero(np.diff(np.sign(np.diff(f))[np.abs(np.diff(f)) > 1e-12]) != 0)
        assert changes <= 1
