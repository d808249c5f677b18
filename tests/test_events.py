"""Event times of ``core.events`` against their exact twins (``naive.py``).

The twin builds each element's crossing polynomial from the element's own
definition (``Line/Segment/Circle/Arc`` objects, not the kernel rows) in exact
rational arithmetic from the float inputs, finds its exits exactly and tests
the exit point against the extent at 50 digits (ends inclusive within the same
``EXTENT_TOL * scale`` the event loop passes).

What may differ, and why (no float method can do better):

* a hit time, within its predicted error (``naive.predicted_root_error``): a few
  eps for a clean crossing, ``~sqrt(eps) ~ 1e-8`` relative at a near tangency
  (near-double root), ``~eps^(1/3)`` at an osculation (near-triple root).
  Well-conditioned hits (predicted error <= 1e-13) must agree to 1e-12 relative;
* roots closer than 1e-6 relative, or than their own predicted errors, cannot be
  told apart: such a cluster may give any root to rounding (backward residual),
  but if the flight certainly leaves the table across it (+ before, - after)
  the kernel may not fly past it; likewise a root indistinguishable from t = 0
  (corner contacts) or from the horizon;
* an exit point within rounding of the inclusive extent tolerance may count or not.

Everything else (whether there is a hit, which element, at what time) must agree.
"""
import functools
import itertools
import math
import zlib

import mpmath
import naive
import numpy as np
import pytest
from python_flight import python_flight

from noslipsim import Arc, Circle, Line, Scene, Segment
from noslipsim._engine.table import kernel_table
from noslipsim.core import events, free_flight, roots, search
from noslipsim.core.events import element_hit_time, exit_roots, leaves_through_contact
from noslipsim.core.geometry import place_on_element
from noslipsim.core.layout import ARC, CIRCLE, END_START, LINE, SEGMENT
from noslipsim.core.tolerances import CONTACT_TOL, EXTENT_TOL

INF = math.inf
EPS = 2.0 ** -52
K_EVAL = 16       # rounding units in the kernel's coefficients and evaluation
C_PRED = 8.0      # slack on the (first-order) predicted error
WELL = 1e-13      # predicted relative error of a well-conditioned hit
REL_TOL = 1e-12   # required agreement on well-conditioned hits
SEP = 1e-6        # roots closer than this (relative) may merge
RESID = 64.0      # backward residual (units of eps) allowed for a root in an unresolved cluster

MEASURED = {}


def seed_of(*parts):
    return zlib.crc32(repr(parts).encode())


def loguni(rng, lo, hi):
    return 10.0 ** rng.uniform(lo, hi)


def next_hit(kinds, params, x, y, vx, vy, ax, ay, has_force, current, hi, extent_tol, hit=None):
    """Earliest hit ``(t, element)`` over a plain scene: ``hit_in_cell`` on cell (0, 0) with one
    copy per element and no offsets (what the event loop does for a scene without lattice).

    ``hit(has_force)``: the cell search to use, by flight (default: free flight's, compiled)."""
    copies = np.zeros((len(kinds), 3), dtype=np.int64)
    copies[:, 0] = np.arange(len(kinds))
    A = np.zeros((2, 2))
    hit = search.cell_search(free_flight.free_flight(bool(has_force))) if hit is None else hit(bool(has_force))
    # t_in = 0: the flight starts in the cell; no shift to form; no ceiling (a bounded lattice's top)
    t, e, _, _ = hit(kinds, params, copies, A, 0, 0, (x, y, vx, vy, ax, ay),
                     current, 0, 0, hi, extent_tol, 0.0, False, INF)
    return t, e


@functools.cache
def row(element):
    """The kernel's (kind, params row) of one element, through the public Scene API."""
    kinds, params = kernel_table(Scene([element])).arrays()[:2]
    return int(kinds[0]), params[0]


def band_factor(element):
    """The end-band factor of a free-standing element (both ends free: NONCONVEX_END_FACTOR)."""
    kind, p = row(element)
    return float(p[END_START]) if kind in (SEGMENT, ARC) else 1.0


def tol_for(element, q):
    """The band beyond a free end at position ``q``: EXTENT_TOL times the length scale times the end factor."""
    return EXTENT_TOL * max(element.size(), abs(q[0]), abs(q[1])) * band_factor(element)


def kernel_hit(element, q, v, a, deflate=False, hi=INF, tol=None):
    """The kernel's hit time, with ``tol`` the effective band (the kernel scales its tolerance by the end factor)."""
    kind, p = row(element)
    tol = tol_for(element, q) if tol is None else tol
    has_force = a[0] != 0.0 or a[1] != 0.0
    return element_hit_time(kind, p, float(q[0]), float(q[1]), float(v[0]), float(v[1]),
                            float(a[0]), float(a[1]), has_force, deflate, hi, tol / band_factor(element))


def _describe(element, q, v, a, deflate, hi, tol):
    return (f"element={element!r} q={tuple(map(float, q))!r} v={tuple(map(float, v))!r} "
            f"a={tuple(map(float, a))!r} deflate={deflate} hi={hi!r} tol={tol!r}")


def compare_hit(element, q, v, a, deflate=False, hi=INF, tol=None, tag=""):
    """Kernel ``element_hit_time`` against the twin.

    The twin's real roots are grouped into clusters a float method cannot resolve
    (``naive.root_clusters``), walked in time order:

    * one clean exit (isolated, away from t = 0 and ``hi``) inside the extent: the kernel must
      return it (to its allowed error) unless it returned an acceptable earlier answer; one
      outside the extent (beyond rounding), or a clean entry, the kernel must not return;
    * an exit point within rounding of the extent tolerance may count or not;
    * an unresolved cluster (near tangency, near t = 0 or ``hi``) may give any root to rounding
      (backward residual); if the flight certainly leaves across it (+ before, - after, all its
      exits inside the extent) the kernel may not pass it.

    Returns ``(message, info)``: ``message`` is None when they agree, ``info`` says how
    ('inf', 'well', 'ill' or 'tangent').
    """
    tol = tol_for(element, q) if tol is None else tol
    got = kernel_hit(element, q, v, a, deflate, hi, tol)
    where = _describe(element, q, v, a, deflate, hi, tol)
    poly, _ = naive.naive_crossing_poly(element, q, v, a)
    mags = naive.crossing_magnitudes(element, q, v, a)
    if deflate:
        poly, mags = poly[1:], mags[1:]
    found = naive.naive_flight_exits(element, q, v, a, deflate, hi)
    twin = [(float(e["t"]), e["kind"], float(e["excess"])) for e in found]
    excess = {id(e["t"]): e["excess"] for e in found}
    roots = [(e["t"], e["kind"], e["bracket"]) for e in found]
    speed0 = math.hypot(*map(float, v))
    acc = math.hypot(*map(float, a))
    qmax = max(abs(float(q[0])), abs(float(q[1])), element.size())

    def inside(x):
        """Exit point in the extent: True, False, or None (within rounding of the tolerance)."""
        tf = float(x["t"])
        slack = 64 * EPS * (qmax + speed0 * tf + acc * tf * tf) + (speed0 + acc * tf) * float(x["allowed"])
        ex = excess[id(x["t"])]
        return True if ex <= tol - slack else (False if ex > tol + slack else None)

    windows = []      # (lo, hi, 'clean' | 'loose' | 'forbidden', root)
    stop = None       # the window the kernel may not pass
    with mpmath.workdps(50):
        for cl in naive.root_clusters(poly, roots, mags, K_EVAL, C_PRED, WELL, REL_TOL, SEP):
            edge = cl["lo"] <= 0 or cl["hi"] >= hi
            (x, *more) = cl["roots"]
            if not more and not edge and x["kind"] == "exit":
                where_ = inside(x)
                if where_ is False:
                    windows.append((cl["lo"], cl["hi"], "forbidden", x))
                    continue
                windows.append((cl["lo"], cl["hi"], "clean" if where_ else "loose", x))
                if where_:
                    stop = windows[-1]
                    break
                continue
            if not more and not edge and x["kind"] == "entry" and x["well"]:
                windows.append((cl["lo"], cl["hi"], "forbidden", x))
                continue
            windows.append((cl["lo"], cl["hi"], "loose", x))
            exits = [r for r in cl["roots"] if r["kind"] == "exit"]
            if cl["left"] > 0 > cl["right"] and not edge and exits and all(inside(r) for r in exits):
                stop = windows[-1]
                break
        if got == INF:
            if stop is None:
                return None, "inf"
            return f"kernel misses the hit at t={float(stop[3]['t'])!r} (twin roots {twin}); {where}", None
        g = mpmath.mpf(got)
        if stop is not None and g > stop[1]:
            return (f"kernel hit t={got!r} passes the hit at t={float(stop[3]['t'])!r} "
                    f"(twin roots {twin}); {where}"), None
        for lo, hi_w, kind, x in windows:
            if lo <= g <= hi_w:
                if kind == "forbidden":
                    return (f"kernel hit t={got!r} is a clean entry or an exit outside the extent "
                            f"(twin roots {twin}); {where}"), None
                if kind == "clean":
                    if x["well"]:
                        MEASURED[tag] = max(MEASURED.get(tag, 0.0), float(abs(g - x["t"]) / x["t"]))
                        return None, "well"
                    return None, "ill"
                break
        # in an unresolved cluster, or a root the twin does not have: a root to rounding
        res = naive.backward_residual(poly, got, mags)
        if res <= RESID:
            return None, "tangent"
        return (f"kernel hit t={got!r} is no root to rounding (residual {float(res):.3g} eps; "
                f"twin roots {twin}); {where}"), None


def assert_all(results, what, min_hits=0):
    fails = [m for m, _ in results if m]
    kinds = {}
    for _, info in results:
        kinds[info] = kinds.get(info, 0) + 1
    assert not fails, f"{len(fails)}/{len(results)} {what} disagree, first:\n" + "\n".join(fails[:3])
    hits = len(results) - kinds.get("inf", 0)
    assert hits >= min_hits, f"only {hits} hits in {len(results)} {what} ({kinds}): the generator is off"
    return kinds


# --------------------------------------------------------------------------- random elements and flights

def unit(angle):
    return math.cos(angle), math.sin(angle)


def random_direction(rng, axis_prob=0.25):
    if rng.random() < axis_prob:
        return [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][int(rng.integers(4))]
    return unit(rng.uniform(0, 2 * math.pi))


def random_element(rng, kind, L):
    c = tuple(L * rng.normal(size=2))
    if kind == "line":
        return Line(point=c, normal=random_direction(rng))
    if kind == "segment":
        d = random_direction(rng)
        length = L * loguni(rng, -0.5, 0.5)
        return Segment(p0=c, p1=(c[0] + length * d[0], c[1] + length * d[1]),
                       side=str(rng.choice(["left", "right"])))
    r = L * loguni(rng, -0.5, 0.3)
    side = str(rng.choice(["outside", "inside"]))
    if kind == "circle":
        return Circle(center=c, radius=r, side=side)
    if rng.random() < 0.1:   # a full circle as an arc
        return Arc(center=c, radius=r, theta0=0.0, theta1=2 * math.pi, side=side)
    th0 = rng.uniform(-math.pi, 2 * math.pi)
    return Arc(center=c, radius=r, theta0=th0, theta1=th0 + rng.uniform(0.2, 6.2), side=side)


def point_on(rng, element, frac=None):
    """A point on the element (inside its extent) and the inward normal there."""
    name = type(element).__name__
    if name == "Line":
        n = element.normal
        s = rng.normal() * 2 * max(1.0, element.size())
        return (element.point[0] - s * n[1], element.point[1] + s * n[0]), n
    if name == "Segment":
        f = rng.uniform(0.05, 0.95) if frac is None else frac
        p0, p1 = element.p0, element.p1
        P = (p0[0] + f * (p1[0] - p0[0]), p0[1] + f * (p1[1] - p0[1]))
        _kind, prow = row(element)
        return P, (prow[2], prow[3])
    if name == "Circle":
        th = rng.uniform(0, 2 * math.pi)
    else:
        f = rng.uniform(0.05, 0.95) if frac is None else frac
        th = element.theta0 + f * (element.theta1 - element.theta0)
    u = unit(th)
    P = (element.center[0] + element.radius * u[0], element.center[1] + element.radius * u[1])
    sig = 1.0 if element.side == "outside" else -1.0
    return P, (sig * u[0], sig * u[1])


FORCES = ["none", "down", "horizontal", "up", "random", "tiny"]


def random_force(rng, option, g):
    if option == "none":
        return (0.0, 0.0)
    if option == "down":
        return (0.0, -g)
    if option == "up":
        return (0.0, g)
    if option == "horizontal":
        return (g * float(rng.choice([-1.0, 1.0])), 0.0)
    d = unit(rng.uniform(0, 2 * math.pi))
    if option == "tiny":
        g *= 1e-12
    return (g * d[0], g * d[1])


def random_flight(rng, element, force_option, L):
    """A flight aimed (mostly) at the element, from the table side for lines and circles."""
    T = loguni(rng, -1.5, 1.5)
    V = L / T
    a = random_force(rng, force_option, loguni(rng, -0.5, 0.5) * L / T ** 2)
    P, n_in = point_on(rng, element)
    name = type(element).__name__
    depth = L * loguni(rng, -2, 0.3)
    if name in ("Segment", "Arc") and rng.random() < 0.3:
        depth = -depth                     # behind a one-sided piece (non-convex tables)
    t_dir = (-n_in[1], n_in[0])
    off = rng.normal() * L
    q = (P[0] + depth * n_in[0] + off * t_dir[0], P[1] + depth * n_in[1] + off * t_dir[1])
    if name == "Circle" and element.side == "inside":
        rho = element.radius * rng.uniform(0.0, 0.99)
        u = unit(rng.uniform(0, 2 * math.pi))
        q = (element.center[0] + rho * u[0], element.center[1] + rho * u[1])
    elif name == "Circle":
        rho = element.radius * (1.0 + loguni(rng, -2, 0.5))
        u = unit(rng.uniform(0, 2 * math.pi))
        q = (element.center[0] + rho * u[0], element.center[1] + rho * u[1])
    elif name == "Line":
        q = (P[0] + abs(depth) * n_in[0] + off * t_dir[0], P[1] + abs(depth) * n_in[1] + off * t_dir[1])
    if rng.random() < 0.65:   # aim at a point of the element: the flight passes it at time tt
        target, _ = point_on(rng, element)
        tt = T * rng.uniform(0.3, 1.5)
        v = ((target[0] - q[0]) / tt - 0.5 * a[0] * tt + 0.02 * V * rng.normal(),
             (target[1] - q[1]) / tt - 0.5 * a[1] * tt + 0.02 * V * rng.normal())
    else:
        d = random_direction(rng)
        v = (V * d[0], V * d[1])
    hi = INF if rng.random() < 0.7 else T * loguni(rng, -1, 1)
    return q, v, a, hi


KINDS = ["line", "segment", "circle", "arc"]


@pytest.mark.parametrize("force", FORCES)
@pytest.mark.parametrize("kind", KINDS)
def test_random_flights(kind, force):
    """Random elements (axis-aligned normals and directions included) and flights, most aimed at
    the element, some from behind one-sided pieces, some with a finite horizon ``hi``."""
    rng = np.random.default_rng(seed_of("flights", kind, force))
    results = []
    for _i in range(36):
        L = loguni(rng, -3, 3)
        e = random_element(rng, kind, L)
        for _j in range(3):
            q, v, a, hi = random_flight(rng, e, force, L)
            results.append(compare_hit(e, q, v, a, False, hi, tag=f"flight/{kind}/{force}"))
    assert_all(results, f"{kind} flights with force '{force}'", min_hits=20)


@pytest.mark.parametrize("force", FORCES)
@pytest.mark.parametrize("kind", KINDS)
def test_random_deflated_flights(kind, force):
    """Start exactly where place_on_element leaves a particle after a hit, moving into the table."""
    rng = np.random.default_rng(seed_of("deflated", kind, force))
    results = []
    for i in range(90):
        if i % 3 == 0:
            L = loguni(rng, -3, 3)
            e = random_element(rng, kind, L)
        P, _n_in = point_on(rng, e)
        k, prow = row(e)
        x, y, nx, ny = place_on_element(k, prow, P[0] + 1e-3 * L * rng.normal(), P[1] + 1e-3 * L * rng.normal())
        T = loguni(rng, -1.5, 1.5)
        V = L / T
        # velocity into the table: -n (n is the outward normal) rotated by up to +-80 degrees,
        # or leaving at a grazing angle (1e-8 .. 1e-2 off the tangent) every fifth time
        turn = rng.uniform(-1.4, 1.4) if i % 5 else float(rng.choice([-1, 1])) * (math.pi / 2 - loguni(rng, -8, -2))
        ang = math.atan2(-ny, -nx) + turn
        v = (V * math.cos(ang), V * math.sin(ang))
        a = random_force(rng, force, loguni(rng, -0.5, 0.5) * L / T ** 2)
        results.append(compare_hit(e, (x, y), v, a, True, INF, tag=f"deflated/{kind}/{force}"))
    min_hits = 0 if (force in ("none", "tiny") and kind in ("line", "segment")) else 5
    kinds = assert_all(results, f"deflated {kind} flights with force '{force}'", min_hits=min_hits)
    if force == "none" and kind in ("line", "segment"):
        assert kinds == {"inf": len(results)}   # a straight flight never meets its own line again


# --------------------------------------------------------------------------- physics with known answers

def test_bouncing_ball_on_a_floor():
    """Deflated hit on a floor under gravity is ``t = 2 v_n / g``, bit for bit, bounce after bounce."""
    rng = np.random.default_rng(seed_of("floor"))
    bad = []
    for i in range(60):
        L = loguni(rng, -2, 2)
        ang = 0.0 if i % 3 == 0 else rng.uniform(-0.6, 0.6)          # level or tilted floor
        n_in = (-math.sin(ang), math.cos(ang))
        y0 = L * rng.normal()
        if i % 2:
            floor = Line(point=(0.0, y0), normal=n_in)
        else:   # a long segment, table on its left (above)
            R = 1e6 * L
            floor = Segment(p0=(-R * math.cos(ang), y0 - R * math.sin(ang)),
                            p1=(R * math.cos(ang), y0 + R * math.sin(ang)))
        k, prow = row(floor)
        g = loguni(rng, -1, 1)
        a = (0.0, -g)
        x, y, _, _ = place_on_element(k, prow, L * rng.normal(), y0 + L * rng.normal() * math.tan(ang))
        vt, vn = L * rng.normal(), L * loguni(rng, -1, 1)       # vn > 0: leaving the floor
        v = (vt * n_in[1] + vn * n_in[0], -vt * n_in[0] + vn * n_in[1])
        for _bounce in range(8):
            t = kernel_hit(floor, (x, y), v, a, deflate=True)
            msg, _ = compare_hit(floor, (x, y), v, a, True, tag="floor")
            if msg:
                bad.append(msg)
                break
            nin = (prow[2], prow[3])
            vn = v[0] * nin[0] + v[1] * nin[1]
            an = a[0] * nin[0] + a[1] * nin[1]
            if ang == 0.0:   # level floor: the kernel's linear root is one IEEE division of exact values
                if t != 2.0 * vn / g:
                    bad.append(f"level floor: t={t!r} != 2 v_n/g={2.0 * vn / g!r}")
                    break
            elif not math.isclose(t, -2.0 * vn / an, rel_tol=1e-14):
                bad.append(f"tilted floor: t={t!r} != -2 v_n/a_n={-2.0 * vn / an!r}")
                break
            # land, project, reflect (specular) and go on
            hx, hy = events.flight_position(x, y, *v, *a, t)
            vx, vy = v[0] + a[0] * t, v[1] + a[1] * t
            x, y, nx, ny = place_on_element(k, prow, hx, hy)
            dn = vx * nx + vy * ny
            v = (vx - 2 * dn * nx, vy - 2 * dn * ny)
    assert not bad, "\n".join(bad[:3])


def test_chords_in_a_circular_container():
    """From a point on a container circle moving inward, no force: the chord time ``-2 d.v / |v|^2``."""
    rng = np.random.default_rng(seed_of("chords"))
    results = []
    bad = []
    for i in range(250):
        L = loguni(rng, -3, 3)
        c = Circle(center=tuple(L * rng.normal(size=2)), radius=L * loguni(rng, -0.5, 0.5), side="inside")
        k, prow = row(c)
        th = rng.uniform(0, 2 * math.pi)
        x, y, nx, ny = place_on_element(k, prow, c.center[0] + c.radius * math.cos(th),
                                        c.center[1] + c.radius * math.sin(th))
        # inward, with grazing chords (angle to the tangent down to 1e-8) included
        graze = loguni(rng, -8, 0) if i % 4 == 0 else rng.uniform(0.05, math.pi / 2)
        side = float(rng.choice([-1.0, 1.0]))
        tx, ty = -ny * side, nx * side
        V = loguni(rng, -2, 2)
        v = (V * (math.cos(graze) * tx - math.sin(graze) * nx), V * (math.cos(graze) * ty - math.sin(graze) * ny))
        msg, info = compare_hit(c, (x, y), v, (0.0, 0.0), True, tag="chord")
        results.append((msg, info))
        t = kernel_hit(c, (x, y), v, (0.0, 0.0), deflate=True)
        dx, dy = x - c.center[0], y - c.center[1]
        exact = -2.0 * (dx * v[0] + dy * v[1]) / (v[0] ** 2 + v[1] ** 2)
        if graze > 1e-3 and not math.isclose(t, exact, rel_tol=1e-13):
            bad.append((c, (x, y), v, t, exact))
    assert_all(results, "container chords", min_hits=240)
    assert not bad, f"chord times off the closed form: {bad[:3]}"


@pytest.mark.parametrize("force", ["down", "random"])
def test_bouncing_in_a_circular_container_under_gravity(force):
    """Orbits of 40 specular bounces inside a circle under a force: every deflated cubic against the twin."""
    rng = np.random.default_rng(seed_of("container-gravity", force))
    results = []
    for _orbit in range(5):
        L = loguni(rng, -2, 2)
        c = Circle(center=tuple(L * rng.normal(size=2)), radius=L, side="inside")
        k, prow = row(c)
        a = random_force(rng, force, loguni(rng, -1, 1) * L)
        x, y = c.center[0] + 0.3 * L, c.center[1]
        v = (L * rng.normal(), L * rng.normal())
        deflate = False
        for _bounce in range(40):
            msg, info = compare_hit(c, (x, y), v, a, deflate, tag=f"container/{force}")
            results.append((msg, info))
            if msg:
                break
            t = kernel_hit(c, (x, y), v, a, deflate)
            hx, hy = events.flight_position(x, y, *v, *a, t)
            vx, vy = v[0] + a[0] * t, v[1] + a[1] * t
            x, y, nx, ny = place_on_element(k, prow, hx, hy)
            dn = vx * nx + vy * ny
            v = (vx - 2 * dn * nx, vy - 2 * dn * ny)
            deflate = True
    assert_all(results, f"container bounces ({force})", min_hits=len(results))


def test_ball_bouncing_on_a_peg_under_gravity():
    """From the top of a circular peg, thrown up or sideways under gravity: falls back on the peg or not."""
    rng = np.random.default_rng(seed_of("peg"))
    results = []
    for _i in range(300):
        L = loguni(rng, -2, 2)
        peg = Circle(center=tuple(L * rng.normal(size=2)), radius=L, side="outside")
        k, prow = row(peg)
        th = rng.uniform(0.15 * math.pi, 0.85 * math.pi)
        x, y, nx, ny = place_on_element(k, prow, peg.center[0] + L * math.cos(th), peg.center[1] + L * math.sin(th))
        g = loguni(rng, -1, 1)
        # speeds around sqrt(g r): from clearly falling back to clearly clearing the peg
        V = math.sqrt(g * L) * loguni(rng, -1.5, 0.7)
        ang = math.atan2(-ny, -nx) + rng.uniform(-1.5, 1.5)
        v = (V * math.cos(ang), V * math.sin(ang))
        results.append(compare_hit(peg, (x, y), v, (0.0, -g), True, tag="peg"))
    kinds = assert_all(results, "peg bounces", min_hits=60)
    assert kinds.get("inf", 0) >= 30, f"too few flights clear the peg: {kinds}"


def test_thrown_out_of_a_bowl_and_caught_again():
    """A bowl (lower half-circle arc, table inside) under gravity: the flight leaves the circle
    through the open top (an exit outside the arc's extent), falls back in and lands on the bowl:
    the hit is the *second* exit root of the quartic."""
    rng = np.random.default_rng(seed_of("bowl"))
    results = []
    second = 0
    for _i in range(150):
        L = loguni(rng, -2, 2)
        c = tuple(L * rng.normal(size=2))
        bowl = Arc(center=c, radius=L, theta0=math.pi, theta1=2 * math.pi, side="inside")
        g = loguni(rng, -1, 1)
        q = (c[0] + 0.5 * L * rng.uniform(-1, 1), c[1] + 0.5 * L * rng.uniform(-1, 1))
        vy = math.sqrt(2.0 * g * L) * rng.uniform(1.05, 1.5)     # enough to clear the rim
        vx = vy * rng.uniform(-0.1, 0.1)
        v, a = (vx, vy), (0.0, -g)
        msg, info = compare_hit(bowl, q, v, a, tag="bowl")
        results.append((msg, info))
        with mpmath.workdps(50):
            ex = [e for e in naive.naive_flight_exits(bowl, q, v, a) if e["kind"] == "exit"]
        second += len(ex) == 2 and ex[0]["excess"] > 0 and ex[1]["excess"] < 0
    assert_all(results, "bowl catches", min_hits=100)
    assert second >= 100, f"only {second} flights land on the second exit"


def osculating_flight(rng, r, g, center=(0.0, 0.0)):
    """A flight under ``(0, -g)`` tangent to the circle at a point of its upper half with the
    circle's own curvature there (speed ``sqrt(g r sin(theta))``): third-order contact, so it
    crosses the circle at a (near-)triple root of the quartic.  Returns ``q, v, a``."""
    th = rng.uniform(0.2, math.pi - 0.2)
    P = (center[0] + r * math.cos(th), center[1] + r * math.sin(th))
    s = math.sqrt(g * r * math.sin(th))
    d = 1.0 if rng.random() < 0.5 else -1.0
    vP = (-d * s * math.sin(th), d * s * math.cos(th))
    T0 = rng.uniform(0.05, 2.0) * math.sqrt(r / g)
    q = (P[0] - vP[0] * T0, P[1] - vP[1] * T0 - 0.5 * g * T0 * T0)
    return q, (vP[0], vP[1] + g * T0), (0.0, -g)


def test_flight_osculating_a_peg():
    rng = np.random.default_rng(seed_of("osculate"))
    results = []
    for _i in range(300):
        L = loguni(rng, -1, 1)
        peg = Circle(center=tuple(L * rng.normal(size=2)), radius=L)
        q, v, a = osculating_flight(rng, L, loguni(rng, -1, 1), peg.center)
        results.append(compare_hit(peg, q, v, a, tag="osculate"))
    assert_all(results, "osculating flights", min_hits=100)


def test_flight_osculating_a_peg_minimal():
    peg = Circle(center=(0.0, 0.0), radius=1.0)
    q, v, a = (1.7763601377202693, -1.8323115161769574), (-0.6229276249377211, 2.3376798536105525), (0.0, -1.0)
    with mpmath.workdps(50):
        t = naive.naive_element_hit_time(peg, q, v, a)
        assert abs(t - mpmath.mpf("1.7534204654787")) < 1e-9
    got = kernel_hit(peg, q, v, a)
    assert abs(got - float(t)) <= 1e-4, got


# --------------------------------------------------------------------------- near tangencies

@pytest.mark.parametrize("eps_angle", [1e-4, 1e-5, 1e-6, 1e-7, 1e-8])
@pytest.mark.parametrize("hit", [True, False])
def test_grazing_a_scatterer_without_force(eps_angle, hit):
    """A ray whose direction is ``eps_angle`` inside/outside the tangent to a circle; roots
    ``~sqrt(eps_angle)`` apart relative, so the count must agree all the way down to 1e-8."""
    rng = np.random.default_rng(seed_of("graze-circle", eps_angle, hit))
    results, wrong = [], []
    for _i in range(40):
        L = loguni(rng, -2, 2)
        e = Circle(center=tuple(L * rng.normal(size=2)), radius=L * loguni(rng, -0.3, 0.3), side="outside")
        D = e.radius * (1.0 + loguni(rng, -1, 1))
        phi = rng.uniform(0, 2 * math.pi)
        q = (e.center[0] + D * math.cos(phi), e.center[1] + D * math.sin(phi))
        alpha = math.asin(e.radius / D)
        s = float(rng.choice([-1.0, 1.0]))
        direction = phi + math.pi + s * (alpha - eps_angle if hit else alpha + eps_angle)
        V = loguni(rng, -2, 2)
        v = (V * math.cos(direction), V * math.sin(direction))
        msg, info = compare_hit(e, q, v, (0.0, 0.0), tag="graze-circle")
        results.append((msg, info))
        with mpmath.workdps(50):
            t = naive.naive_element_hit_time(e, q, v, (0.0, 0.0))
        if (t < mpmath.inf) != hit or (kernel_hit(e, q, v, (0.0, 0.0)) < INF) != hit:
            wrong.append((e, q, v, float(t)))
    assert_all(results, f"grazing rays ({eps_angle})")
    assert not wrong, f"grazing ray {'missed' if hit else 'hit'}: {wrong[:2]}"


@pytest.mark.parametrize("depth", [1e-6, 1e-8, 1e-10, 1e-12, 1e-14, 1e-16])
@pytest.mark.parametrize("hit", [True, False])
@pytest.mark.parametrize("kind", ["line", "circle"])
def test_parabola_grazing(kind, depth, hit):
    """A parabola whose apex passes ``depth`` (relative) beyond a ceiling / into a peg top, or stays short.

    Crossing angles are ``~sqrt(depth)`` (1e-3..1e-8) and so are the root separations: down to
    depth 1e-12 the count must agree; below it the twin's roots are < SEP apart and either answer
    is a float method's best, but a hit the kernel reports must be a root to rounding.
    """
    rng = np.random.default_rng(seed_of("graze-parabola", kind, depth, hit))
    results, wrong = [], []
    for _i in range(30):
        L = loguni(rng, -2, 2)
        g = loguni(rng, -1, 1)
        c = tuple(L * rng.normal(size=2))
        if kind == "line":   # a ceiling (table below it): the apex reaches up to it
            e = Line(point=c, normal=(0.0, -1.0))
            top = (c[0] + L * rng.normal(), c[1])
            vx = math.sqrt(g * L) * loguni(rng, -1, 1)
        else:
            e = Circle(center=c, radius=L, side="outside")
            top = (c[0], c[1] + L)
            vx = math.sqrt(2.0 * g * L) * (1.0 + loguni(rng, -1, 0))   # flatter than the peg
        vx *= float(rng.choice([-1.0, 1.0]))
        dip = depth if (hit == (kind == "line")) else -depth    # above the ceiling / into the peg
        apex = (top[0], top[1] + dip * L)
        T0 = L / abs(vx) * rng.uniform(0.3, 1.0)
        a = (0.0, -g)
        q = (apex[0] - vx * T0, apex[1] - 0.5 * g * T0 * T0)
        v = (vx, g * T0)
        msg, info = compare_hit(e, q, v, a, tag=f"graze-parabola/{kind}")
        results.append((msg, info))
        with mpmath.workdps(50):
            t_twin = naive.naive_element_hit_time(e, q, v, a)
            ex = [r for r, k, _ in naive.naive_real_roots(naive.naive_crossing_poly(e, q, v, a)[0]) if k != "touch"]
            sep = min((abs(r2 - r1) / r1 for r1, r2 in itertools.pairwise(ex)), default=mpmath.inf)
        if depth >= 1e-12 and (sep > SEP) and ((t_twin < mpmath.inf) != hit):
            wrong.append(("twin", e, q, v))
        if depth >= 1e-12 and (kernel_hit(e, q, v, a) < INF) != hit:
            wrong.append(("kernel", e, q, v))
    assert_all(results, f"grazing parabolas ({kind}, depth {depth})")
    assert not wrong, f"grazing parabola {'missed' if hit else 'hit'}: {wrong[:2]}"


@pytest.mark.parametrize("eps_angle", [1e-4, 1e-6, 1e-8])
@pytest.mark.parametrize("kind", ["line", "segment"])
def test_nearly_parallel_straight_flights(kind, eps_angle):
    """Flights at ``eps_angle`` to a line (hit far away: ill-conditioned by ``1/eps_angle``)."""
    rng = np.random.default_rng(seed_of("parallel", kind, eps_angle))
    results = []
    for _i in range(40):
        L = loguni(rng, -2, 2)
        e = random_element(rng, kind, L)
        if kind == "segment":   # long enough to be met far away
            d = (e.p1[0] - e.p0[0], e.p1[1] - e.p0[1])
            e = Segment(p0=e.p0, p1=(e.p0[0] + d[0] / eps_angle, e.p0[1] + d[1] / eps_angle), side=e.side)
        P, n_in = point_on(rng, e)
        tdir = (-n_in[1], n_in[0])
        h = L * loguni(rng, -2, 0)
        q = (P[0] + h * n_in[0], P[1] + h * n_in[1])
        s = float(rng.choice([-1.0, 1.0]))
        V = loguni(rng, -2, 2)
        v = (V * (math.cos(eps_angle) * s * tdir[0] - math.sin(eps_angle) * n_in[0]),
             V * (math.cos(eps_angle) * s * tdir[1] - math.sin(eps_angle) * n_in[1]))
        results.append(compare_hit(e, q, v, (0.0, 0.0), tag=f"parallel/{kind}"))
    assert_all(results, f"nearly parallel flights ({eps_angle})", min_hits=15)


# --------------------------------------------------------------------------- extent ends

END_OFFSETS = [-1e-9, -1e-10, -1e-12, 0.0, 0.5, 0.9, 1.1, 2.0, 1e-10, 1e-9]


def _offset(off, tol, L):
    """How far beyond the end the flight is aimed: the entries 0.5, 0.9, 1.1, 2.0 of END_OFFSETS are
    multiples of the extent tolerance, the others lengths relative to the element's size L."""
    if off in (0.5, 0.9, 1.1, 2.0):
        return off * tol
    return off * L


@pytest.mark.parametrize("force", ["none", "down"])
@pytest.mark.parametrize("side", ["left", "right"])
@pytest.mark.parametrize("end", [0, 1])
def test_hits_at_segment_ends(end, side, force):
    """Hits 1e-9 .. 1e-12 inside and outside an end, and 0.5..2 x EXTENT_TOL beyond it."""
    rng = np.random.default_rng(seed_of("ends", end, side, force))
    results, wrong = [], []
    for _i in range(8):
        L = loguni(rng, -2, 2)
        p0 = tuple(L * rng.normal(size=2))
        d = random_direction(rng)
        length = L * loguni(rng, -0.3, 0.3)
        e = Segment(p0=p0, p1=(p0[0] + length * d[0], p0[1] + length * d[1]), side=side)
        _k, prow = row(e)
        for off in END_OFFSETS:
            n_in = (prow[2], prow[3])
            q_far = (p0[0] + 3 * L * n_in[0], p0[1] + 3 * L * n_in[1])
            tol = tol_for(e, q_far)
            u = (-_offset(off, tol, L)) if end == 0 else length + _offset(off, tol, L)
            H = (p0[0] + u * d[0], p0[1] + u * d[1])
            # arrive at H from the table side at a random angle, after time T
            ang = math.atan2(-n_in[1], -n_in[0]) + rng.uniform(-1.2, 1.2)
            V = loguni(rng, -1, 1) * L
            vH = (V * math.cos(ang), V * math.sin(ang))
            a = (0.0, 0.0) if force == "none" else (0.0, -loguni(rng, -1, 0) * V * V / L)
            T = rng.uniform(0.5, 2.0) * L / V
            q = (H[0] - vH[0] * T + 0.5 * a[0] * T * T, H[1] - vH[1] * T + 0.5 * a[1] * T * T)
            v = (vH[0] - a[0] * T, vH[1] - a[1] * T)
            if naive.naive_crossing_poly(e, q, v, a)[0][0] <= 0:
                continue  # started behind the segment (the parabola bent back): not this test
            planted_in = _offset(off, tol, L) <= tol
            msg, info = compare_hit(e, q, v, a, tol=tol, tag="ends")
            results.append((msg, info))
            with mpmath.workdps(50):
                twin_in = naive.naive_element_hit_time(e, q, v, a, tol=tol) < mpmath.inf
            kern_in = kernel_hit(e, q, v, a, tol=tol) < INF
            if abs(_offset(off, tol, L) - tol) > 1e-3 * tol and not (twin_in == kern_in == planted_in):
                wrong.append((off, planted_in, twin_in, kern_in, e, q, v, a, tol))
    assert_all(results, "end hits", min_hits=30)
    assert not wrong, "ends (offset, planted, twin, kernel, ...): " + "\n".join(map(repr, wrong[:3]))


@pytest.mark.parametrize("side", ["inside", "outside"])
@pytest.mark.parametrize("end", [0, 1])
def test_hits_at_arc_ends(end, side):
    rng = np.random.default_rng(seed_of("arc-ends", end, side))
    results, wrong = [], []
    for _i in range(8):
        for off in END_OFFSETS:
            L = loguni(rng, -2, 2)
            c = tuple(L * rng.normal(size=2))
            th0 = rng.uniform(-math.pi, 2 * math.pi)
            th1 = th0 + rng.uniform(0.3, 1.9 * math.pi)
            e = Arc(center=c, radius=L, theta0=th0, theta1=th1, side=side)
            tol = EXTENT_TOL * max(e.size(), abs(c[0]) + 3 * L, abs(c[1]) + 3 * L) * band_factor(e)
            delta = _offset(off, tol, L) / L     # angle beyond the end
            th = th0 - delta if end == 0 else th1 + delta
            H = (c[0] + L * math.cos(th), c[1] + L * math.sin(th))
            n_in = (math.cos(th), math.sin(th)) if side == "outside" else (-math.cos(th), -math.sin(th))
            ang = math.atan2(-n_in[1], -n_in[0]) + rng.uniform(-1.0, 1.0)
            V = loguni(rng, -1, 1)
            vH = (V * math.cos(ang), V * math.sin(ang))
            T = rng.uniform(0.05, 0.3) * L / V   # short enough to stay on the table side before
            q = (H[0] - vH[0] * T, H[1] - vH[1] * T)
            if naive.naive_crossing_poly(e, q, vH, (0.0, 0.0))[0][0] <= 0:
                continue
            planted_in = _offset(off, tol, L) <= tol
            msg, info = compare_hit(e, q, vH, (0.0, 0.0), tol=tol, tag="arc-ends")
            results.append((msg, info))
            with mpmath.workdps(50):
                twin_in = naive.naive_element_hit_time(e, q, vH, (0.0, 0.0), tol=tol) < mpmath.inf
            kern_in = kernel_hit(e, q, vH, (0.0, 0.0), tol=tol) < INF
            if abs(_offset(off, tol, L) - tol) > 1e-3 * tol and not (twin_in == kern_in == planted_in):
                wrong.append((off, planted_in, twin_in, kern_in, e, q, vH, tol))
    assert_all(results, "arc end hits", min_hits=30)
    assert not wrong, "arc ends (offset, planted, twin, kernel, ...): " + "\n".join(map(repr, wrong[:3]))


# --------------------------------------------------------------------------- corners and next_hit

def polygon(rng, n, L):
    """A random convex polygon (CCW segments, table inside)."""
    angs = np.sort(rng.uniform(0, 2 * math.pi, n))
    c = L * rng.normal(size=2)
    pts = [tuple(c + L * np.array(unit(a))) for a in angs]
    return [Segment(p0=pts[i], p1=pts[(i + 1) % n], side="left") for i in range(n)], tuple(c)


@pytest.mark.parametrize("force", ["none", "down"])
def test_corner_contacts_never_leak(force):
    """Aim at a vertex of a convex polygon, hit one side, reflect: the other side is met at
    ``t ~ 0`` (a root indistinguishable from 0) or the corner rule takes it; never neither."""
    rng = np.random.default_rng(seed_of("corners", force))
    results, leaks = [], []
    corners = 0
    for i in range(120):
        if i % 3 == 0:
            L = loguni(rng, -2, 2)
            segs, c = polygon(rng, int(rng.integers(3, 7)), L)
            kinds, params = kernel_table(Scene(segs)).arrays()[:2]
            scene_scale = Scene(segs).scale
        j = int(rng.integers(len(segs)))
        V0 = segs[j].p1                       # vertex shared by segs[j] (end) and segs[j+1] (start)
        q = (c[0] + 0.5 * (V0[0] - c[0]) + 0.2 * L * rng.normal(), c[1] + 0.5 * (V0[1] - c[1]) + 0.2 * L * rng.normal())
        V = loguni(rng, -1, 1)
        g = V * V / L * loguni(rng, -1, 0) if force == "down" else 0.0
        a = (0.0, -g)
        # aim at the vertex: straight, or (with gravity) by the launch of a projectile through it
        dx, dy = V0[0] - q[0], V0[1] - q[1]
        T = math.hypot(dx, dy) / V
        v = (dx / T - 0.5 * a[0] * T, dy / T - 0.5 * a[1] * T)
        has_force = g != 0.0
        t, i_hit = next_hit(kinds, params, q[0], q[1], v[0], v[1], a[0], a[1], has_force, -1, INF,
                            EXTENT_TOL * max(abs(q[0]), abs(q[1]), scene_scale))
        if i_hit < 0:
            leaks.append(("no hit at all", segs, q, v, a))
            continue
        # the twin agrees on the time (either side of the vertex may take it)
        results.append(compare_hit(segs[i_hit], q, v, a, tag="corner-approach"))
        hx, hy = events.flight_position(q[0], q[1], v[0], v[1], a[0], a[1], t)
        vx, vy = v[0] + a[0] * t, v[1] + a[1] * t
        x, y, nx, ny = place_on_element(kinds[i_hit], params[i_hit], hx, hy)
        dn = vx * nx + vy * ny
        vx, vy = vx - 2 * dn * nx, vy - 2 * dn * ny
        scale = max(scene_scale, abs(x), abs(y))
        at_vertex = math.hypot(x - V0[0], y - V0[1]) <= 1e-9 * L
        corners += at_vertex
        for other in range(len(segs)):
            if other == i_hit:
                continue
            e = segs[other]
            results.append(compare_hit(e, (x, y), (vx, vy), a, False, INF, tag="corner-other"))
            if not at_vertex or (e.p0 != V0 and e.p1 != V0):
                continue
            # the polygon's own row: this end is a convex junction there, not a free end
            k, prow = int(kinds[other]), params[other]
            rate = vx * prow[2] + vy * prow[3]
            if rate >= 0.0:
                continue     # moving into the table through the other side: nothing to catch
            t_other = element_hit_time(k, prow, x, y, vx, vy, a[0], a[1], has_force, False, INF,
                                       EXTENT_TOL * scale)
            contact = leaves_through_contact(k, prow, x, y, vx, vy, a[0], a[1], CONTACT_TOL * scale)
            tiny = t_other <= 1e-9 * L / V
            if not (tiny or contact):
                leaks.append((t_other, contact, segs[i_hit], e, (x, y), (vx, vy), a))
    assert_all(results, "corner events")
    assert corners >= 60, f"only {corners} flights reached the vertex"
    assert not leaks, f"{len(leaks)} corner contacts neither hit nor caught: {leaks[:2]}"


def scene_for(name, rng):
    """A few tables: box, Sinai, stadium (segments + arcs), container with pegs."""
    L = loguni(rng, -1, 1)
    if name == "box":
        pts = [(0, 0), (L, 0), (L, L), (0, L)]
        return [Segment(p0=pts[i], p1=pts[(i + 1) % 4]) for i in range(4)], (0.5 * L, 0.5 * L), L
    if name == "sinai":
        pts = [(0, 0), (L, 0), (L, L), (0, L)]
        els = [Segment(p0=pts[i], p1=pts[(i + 1) % 4]) for i in range(4)]
        els.append(Circle(center=(0.5 * L, 0.5 * L), radius=0.25 * L))
        return els, (0.1 * L, 0.1 * L), L
    if name == "stadium":
        els = [Segment(p0=(0, 0), p1=(L, 0)),
               Arc(center=(L, 0.5 * L), radius=0.5 * L, theta0=-math.pi / 2, theta1=math.pi / 2),
               Segment(p0=(L, L), p1=(0, L)),
               Arc(center=(0, 0.5 * L), radius=0.5 * L, theta0=math.pi / 2, theta1=3 * math.pi / 2)]
        return els, (0.3 * L, 0.4 * L), L
    els = [Circle(center=(0.0, 0.0), radius=L, side="inside"),
           Circle(center=(0.3 * L, 0.2 * L), radius=0.1 * L), Circle(center=(-0.4 * L, -0.1 * L), radius=0.15 * L),
           Line(point=(0.0, -0.8 * L), normal=(0.1, 1.0))]
    return els, (0.0, 0.5 * L), L


@pytest.mark.parametrize("force", ["none", "down", "random"])
@pytest.mark.parametrize("name", ["box", "sinai", "stadium", "pegs"])
def test_next_hit_matches_twin(name, force):
    """The earliest hit over a scene (and its element) along random flights from an interior point."""
    rng = np.random.default_rng(seed_of("next", name, force))
    bad = []
    skipped = 0
    n = 60
    for i in range(n):
        if i % 10 == 0:
            els, q0, L = scene_for(name, rng)
            kinds, params = kernel_table(Scene(els)).arrays()[:2]
            scene_scale = Scene(els).scale
        q = (q0[0] + 0.05 * L * rng.normal(), q0[1] + 0.05 * L * rng.normal())
        V = L * loguni(rng, -1, 1)
        d = random_direction(rng)
        v = (V * d[0], V * d[1])
        a = random_force(rng, force, V * V / L * loguni(rng, -1, 1))
        tol = EXTENT_TOL * max(scene_scale, abs(q[0]), abs(q[1]))
        t, i_hit = next_hit(kinds, params, q[0], q[1], v[0], v[1], a[0], a[1],
                            a != (0.0, 0.0), -1, INF, tol)
        with mpmath.workdps(50):
            twins = [naive.naive_element_hit_time(e, q, v, a, tol=tol) for e in els]
            best = min(twins)
        if best == mpmath.inf:
            if i_hit != -1:
                bad.append((name, i, "twin: no hit", t, i_hit))
            continue
        # ties: every element within 1e-12 of the earliest time may take it
        with mpmath.workdps(50):
            ties = [j for j, tw in enumerate(twins) if tw < mpmath.inf and abs(tw - best) <= 1e-12 * best]
            if len(ties) > 1:
                skipped += 1
            if i_hit not in ties or abs(mpmath.mpf(t) - best) > 1e-12 * best:
                msgs = [compare_hit(els[j], q, v, a, tol=tol)[0] for j in range(len(els))]
                bad.append((name, i, q, v, a, (t, i_hit), [float(x) for x in twins], [m for m in msgs if m][:1]))
    assert not bad, f"{len(bad)}/{n} next_hit disagree, first: {bad[:2]}"
    assert skipped <= n // 10


# --------------------------------------------------------------------------- no quartic without force

def test_exit_roots_without_force_are_the_closed_forms():
    """``has_force=False``: bit-for-bit the linear/quadratic closed forms whatever c3, c4 hold."""
    rng = np.random.default_rng(seed_of("noforce"))
    bad = []
    for i in range(2000):
        kind = [LINE, SEGMENT, CIRCLE, ARC][i % 4]
        c = list(rng.normal(size=5) * 10.0 ** rng.uniform(-4, 4, 5))
        if rng.random() < 0.2:
            c[2] = 0.0
        deflate = bool(rng.random() < 0.5)
        hi = INF if rng.random() < 0.6 else loguni(rng, -3, 3)
        got = exit_roots(kind, *c, False, deflate, hi)
        if kind in (LINE, SEGMENT):
            want = (INF, INF) if deflate else (roots.linear_exit(c[0], c[1], hi), INF)
        else:
            exit_root = roots.linear_exit(c[1], c[2], hi) if deflate else roots.quadratic_exit(c[0], c[1], c[2], hi)
            want = (exit_root, INF)
        if got != want:
            bad.append((kind, c, deflate, hi, got, want))
    assert not bad, f"{len(bad)} differ: {bad[:3]}"


def test_scene_without_force_never_solves_a_cubic_or_quartic(monkeypatch):
    """Run next_hit's pure-Python bodies (``.py_func``) with counting cubic/quartic solvers."""
    calls = {"cubic_exits": 0, "quartic_exits": 0}

    def counting(name, fn):
        def wrapper(*args):
            calls[name] += 1
            return fn(*args)
        return wrapper

    # the compiled search first: numba reads the globals the patches below replace when it compiles
    els, q0, _ = scene_for("pegs", np.random.default_rng(0))
    kinds, params = kernel_table(Scene(els)).arrays()[:2]
    for a, has_force in (((0.0, 0.0), False), ((0.0, -1.0), True)):
        next_hit(kinds, params, q0[0], q0[1], 1.0, 0.3, a[0], a[1], has_force, -1, INF, 1e-11)
    monkeypatch.setattr(events, "cubic_exits", counting("cubic_exits", roots.cubic_exits))
    monkeypatch.setattr(events, "quartic_exits", counting("quartic_exits", roots.quartic_exits))
    monkeypatch.setattr(events, "exit_roots", events.exit_roots.py_func)
    monkeypatch.setattr(events, "element_hit_time", events.element_hit_time.py_func)
    monkeypatch.setattr(free_flight, "element_hit_time", events.element_hit_time)
    rng = np.random.default_rng(seed_of("counting"))
    def py_hit_in_cell(has_force):
        return search.cell_search(python_flight(free_flight.free_flight(has_force)), compile=lambda func: func)

    def py_next_hit(*args):
        return next_hit(*args, hit=py_hit_in_cell)

    for name in ("box", "sinai", "stadium", "pegs"):
        els, q0, _ = scene_for(name, rng)
        kinds, params = kernel_table(Scene(els)).arrays()[:2]
        for current in range(-1, len(els)):
            for _k in range(10):
                d = unit(rng.uniform(0, 2 * math.pi))
                t, i = py_next_hit(kinds, params, q0[0], q0[1], d[0], d[1], 0.0, 0.0, False, current, INF, 1e-11)
                tc, ic = next_hit(kinds, params, q0[0], q0[1], d[0], d[1], 0.0, 0.0, False, current, INF, 1e-11)
                assert (t, i) == (tc, ic)
    assert calls == {"cubic_exits": 0, "quartic_exits": 0}
    # the counters do count: the same scenes under gravity use both paths
    for name in ("sinai", "pegs"):
        els, q0, _L = scene_for(name, rng)
        kinds, params = kernel_table(Scene(els)).arrays()[:2]
        for current in range(-1, len(els)):
            py_next_hit(kinds, params, q0[0], q0[1], 1.0, 0.3, 0.0, -1.0, True, current, INF, 1e-11)
    assert calls["cubic_exits"] > 0 and calls["quartic_exits"] > 0


def test_report_accuracy():
    """Not a check: prints the largest relative error measured on well-conditioned hits."""
    if MEASURED:
        worst = max(MEASURED.values())
        print(f"\nmax relative error on well-conditioned hit times: {worst:.3e} ({worst / EPS:.2f} eps)")
        assert worst <= REL_TOL
