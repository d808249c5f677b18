"""For scale: the Galton board as a hand-written numba loop, with none of the engine's generality.

The board of ``tables.galton_board(spacing, radius, gravity)``: pegs of radius
``r`` at ``i a1 + j a2`` (``a1 = (s, 0)``, ``a2 = (s/2, s sqrt(3)/2)``), so at
``(m s/2, j s sqrt(3)/2)`` with ``m = j (mod 2)``, unbounded above, force
``(0, -g)``.  The plane is cut into rectangles ``s/2`` wide and ``s sqrt(3)/4``
high: each touches exactly one peg (a peg's centre is a corner of its four
rectangles; needs ``r <= s sqrt(3)/4``).  One flight walks the rectangles along
the parabola (face times from its closed forms) and, in each rectangle's time
window, finds the first root of ``|q(t) - c|^2 - r^2`` (a quartic; for the peg
just left, the cubic left after dividing out the root at ``t = 0``) exactly to
rounding: the roots of the second derivative split the window where the
first derivative is monotone, its roots split it where the polynomial is, and
the first piece that goes from outside to inside is solved by Newton steps
kept inside a bisection bracket.  A window whose chord passes farther from the
peg than its radius plus the arc's largest rise over the chord is skipped.  The hit
point is projected onto the peg; the law is ``noslipsim.core.laws.collide``
(specular, or the no-slip rotation of ``(v_t, w)``; outward normal into the
peg).  The orbit stops at the exact time it crosses ``level`` downwards, at
``max_time`` or after ``max_collisions``.

What it omits, all of which the engine does: records (only a count and,
if asked, the first collision positions), corner or grazing handling, an energy
settle, re-centring of far flights, any check of its input, any other table.
Compiled with the engine's options (``error_model="numpy"``, no fastmath),
not cached.  Compare with ``bench_galton_plain.py`` on the same host.

Run: ``python benchmarks/baseline_galton.py [--orbits 2000]``: checks it against ``noslipsim``
(the first collision positions of a few orbits, the ensemble's mean collisions per orbit), then
times it.
"""
import argparse
import math
import os
import sys
import time

import numpy as np
from numba import njit

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import machine_line

from noslipsim.core.laws import collide
from noslipsim.core.layout import NOSLIP, SPECULAR
from noslipsim.core.roots import horner, horner_prime

#: Why an orbit ended.
STOP_COLLISIONS, STOP_TIME, STOP_LEVEL = 0, 1, 2
#: No peg was hit yet.
NO_PEG = -(2**62)
#: Relative slack of the skip test, far above the rounding of the distances it compares.
SKIP_SLACK = 1e-12
#: A Newton step this small relative to ``t`` ends the search (a few units in the last place).
ROUNDING = 4.0 * 2.0**-52
#: Newton/bisection steps at most: bisection alone narrows a window of this board (under 1e3 wide,
#: times of order 1) to rounding in about 70; Newton ends in about four.
MAX_STEPS = 200

jit = njit(error_model="numpy", fastmath=False)


@jit
def quadratic_roots(a, b, c):
    """The real roots ``z1 <= z2`` of ``a z^2 + b z + c`` (``inf`` for a missing one; cancellation-free)."""
    if a == 0.0:
        if b == 0.0:
            return math.inf, math.inf
        return -c / b, math.inf
    disc = b * b - 4.0 * a * c
    if disc < 0.0:
        return math.inf, math.inf
    q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
    z1 = q / a
    z2 = c / q if q != 0.0 else z1
    return min(z1, z2), max(z1, z2)


@jit
def newton_bisect(e4, e3, e2, e1, e0, lo, hi, f_lo, t):
    """The root of ``e4 t^4 + ... + e0`` in ``[lo, hi]``, where it is monotone from ``f_lo``, from the guess ``t``.

    Newton steps, one leaving the bracket replaced by bisection, until the step is a few units in the
    last place: then the root is known to rounding.
    """
    if not lo < t < hi:
        t = 0.5 * (lo + hi)
    for _ in range(MAX_STEPS):
        f = horner(e0, e1, e2, e3, e4, t)
        if f == 0.0:
            return t
        if (f > 0.0) == (f_lo > 0.0):
            lo = t
        else:
            hi = t
        d = horner_prime(e1, e2, e3, e4, t)
        nxt = t - f / d if d != 0.0 else 0.5 * (lo + hi)
        if abs(nxt - t) <= ROUNDING * abs(t):
            return nxt
        if not lo < nxt < hi:
            nxt = 0.5 * (lo + hi)
            if not lo < nxt < hi:  # no double left between the ends of the bracket
                return t
        t = nxt
    return t


@jit
def secant(lo, hi, f_lo, f_hi):
    """Where the chord from ``(lo, f_lo)`` to ``(hi, f_hi)`` crosses zero."""
    return lo + (hi - lo) * (f_lo / (f_lo - f_hi))


@jit
def taylor_guess(e4, e3, e2, lo, hi, f_lo, d_lo, f_hi):
    """First guess of the root in ``[lo, hi]`` (``f_lo > 0 >= f_hi``): the root of ``p``'s second-order Taylor
    polynomial at ``lo``, else the secant's."""
    c2 = (6.0 * e4 * lo + 3.0 * e3) * lo + e2  # p''(lo) / 2
    disc = d_lo * d_lo - 4.0 * c2 * f_lo
    if d_lo < 0.0 and disc >= 0.0:
        return lo + 2.0 * f_lo / (math.sqrt(disc) - d_lo)
    return secant(lo, hi, f_lo, f_hi)


@jit
def entry_root(e4, e3, e2, e1, e0, lo, hi, f_lo, d_lo, f_hi):
    """The root in ``[lo, hi]``, where ``p`` falls monotonically from ``f_lo > 0`` (slope ``d_lo``) to ``f_hi <= 0``."""
    return newton_bisect(e4, e3, e2, e1, e0, lo, hi, f_lo, taylor_guess(e4, e3, e2, lo, hi, f_lo, d_lo, f_hi))


@jit
def first_entry(e4, e3, e2, e1, e0, a, b):
    """The first ``t`` in ``[a, b]`` where ``p(t) = e4 t^4 + ... + e0`` falls to zero from above, else ``inf``.

    ``p`` is monotone between its critical points; ``p'`` is monotone between the roots of ``p''``
    (a quadratic).  So: the roots of ``p''`` in the window, then the roots of ``p'`` between them,
    then the first monotone piece of ``p`` that ends at or below zero.
    """
    p_start = horner(e0, e1, e2, e3, e4, a)
    if p_start <= 0.0:
        return a
    z1, z2 = quadratic_roots(12.0 * e4, 6.0 * e3, 2.0 * e2)
    start = a
    d_start = horner_prime(e1, e2, e3, e4, a)
    for k in range(3):
        end = b if k == 2 else (z1 if k == 0 else z2)
        if not start < end <= b:
            continue
        d_end = horner_prime(e1, e2, e3, e4, end)
        if (d_start < 0.0 and d_end >= 0.0) or (d_start > 0.0 and d_end <= 0.0):  # a critical point of p
            crit = newton_bisect(0.0, 4.0 * e4, 3.0 * e3, 2.0 * e2, e1, start, end, d_start,
                                 secant(start, end, d_start, d_end))
            p_crit = horner(e0, e1, e2, e3, e4, crit)
            if p_crit <= 0.0:
                return entry_root(e4, e3, e2, e1, e0, start, crit, p_start, d_start, p_crit)
            start = crit
            p_start = p_crit
            d_start = horner_prime(e1, e2, e3, e4, crit)
        p_end = horner(e0, e1, e2, e3, e4, end)
        if p_end <= 0.0:
            return entry_root(e4, e3, e2, e1, e0, start, end, p_start, d_start, p_end)
        start = end
        p_start = p_end
        d_start = d_end
    return math.inf


@jit
def rising_time(vy, dy, g):
    """When ``vy t - g t^2/2`` first reaches ``dy > 0`` (``inf`` if it never does)."""
    disc = vy * vy - 2.0 * g * dy
    if vy <= 0.0 or disc < 0.0:
        return math.inf
    return 2.0 * dy / (vy + math.sqrt(disc))


@jit
def falling_time(vy, dy, g):
    """When ``vy t - g t^2/2`` reaches ``dy`` on the way down (the later root), cancellation-free."""
    disc = max(vy * vy - 2.0 * g * dy, 0.0)
    if vy < 0.0:
        return -2.0 * dy / (math.sqrt(disc) - vy)
    return (vy + math.sqrt(disc)) / g


@jit
def cell_peg(p, k):
    """Lattice indices ``(m, j)`` of the one peg that rectangle ``(p, k)`` touches (centre ``(m w, 2 j h)``)."""
    j = (k + 1) // 2
    m = p if (p - j) % 2 == 0 else p + 1
    return m, j


@jit
def chord_misses(x, y, vx, vy, g, r, cx, cy, te, tl):
    """Whether the flight surely misses the peg in ``[te, tl]``.

    The arc lies between its chord and the chord raised by ``g (tl - te)^2 / 8`` (``x`` is linear in
    ``t``, ``y`` concave), so it misses the disk if the chord is farther than ``r`` plus that rise.
    """
    ax = x + vx * te - cx
    ay = y + (vy - 0.5 * g * te) * te - cy
    dx = vx * (tl - te)
    dy = (vy - 0.5 * g * (te + tl)) * (tl - te)
    dd = dx * dx + dy * dy
    u = min(max(-(ax * dx + ay * dy) / dd, 0.0), 1.0) if dd > 0.0 else 0.0
    px = ax + u * dx
    py = ay + u * dy
    reach = (r + 0.125 * g * (tl - te) ** 2) * (1.0 + SKIP_SLACK)
    return px * px + py * py > reach * reach


@jit
def peg_hit(x, y, vx, vy, g, r, cx, cy, just_left, te, tl):
    """First time in ``[te, tl]`` the flight from ``(x, y)`` reaches the peg at ``(cx, cy)``, else ``inf``."""
    if chord_misses(x, y, vx, vy, g, r, cx, cy, te, tl):
        return math.inf
    dx = x - cx
    dy = y - cy
    e4 = 0.25 * g * g
    e3 = -g * vy
    e2 = vx * vx + vy * vy - g * dy
    e1 = 2.0 * (dx * vx + dy * vy)
    if just_left:  # the flight starts on this peg: its root t = 0 divided out
        return first_entry(0.0, e4, e3, e2, e1, te, tl)
    return first_entry(e4, e3, e2, e1, dx * dx + dy * dy - r * r, te, tl)


@jit
def x_face_time(x, vx, p, w):
    """When the flight from ``x`` leaves the column ``[p w, (p + 1) w]`` (``inf`` if it never does)."""
    if vx > 0.0:
        return ((p + 1) * w - x) / vx
    if vx < 0.0:
        return (p * w - x) / vx
    return math.inf


@jit
def y_face_time(y, vy, g, k, h, te):
    """When the flight from ``y``, in row ``[k h, (k + 1) h]`` at ``te``, leaves it, and the row step (+-1)."""
    if vy - g * te > 0.0:
        t = rising_time(vy, (k + 1) * h - y, g)
        if t < math.inf:
            return t, 1
    return falling_time(vy, k * h - y, g), -1


@jit
def next_hit(x, y, vx, vy, g, r, w, h, last_m, last_j, t_end):
    """The first peg hit by the flight from ``(x, y)`` before ``t_end``: ``(t, m, j)``, ``t = inf`` if none."""
    p = math.floor(x / w)
    k = math.floor(y / h)
    te = 0.0
    tx = x_face_time(x, vx, p, w)
    ty, dk = y_face_time(y, vy, g, k, h, te)
    while te < t_end:
        tl = min(max(min(tx, ty), te), t_end)
        m, j = cell_peg(p, k)
        t = peg_hit(x, y, vx, vy, g, r, m * w, 2 * j * h, m == last_m and j == last_j, te, tl)
        if t < math.inf:
            return t, m, j
        if tx <= ty:  # only the face crossed moves: the other one's time stands
            p += 1 if vx > 0.0 else -1
            tx = x_face_time(x, vx, p, w)
        else:
            k += dk
            ty, dk = y_face_time(y, vy, g, k, h, tl)
        te = tl
    return math.inf, NO_PEG, NO_PEG


@jit
def galton_orbit(x, y, vx, vy, spin, last_m, last_j, law, c, s, spacing, r, g, level, max_time, max_collisions,
                 log):
    """One orbit; returns ``(collisions, stop, t, x, y, vx, vy, w)`` and writes the first hit points to ``log``.

    ``(last_m, last_j)``: the peg the start lies on (see ``cell_peg``), ``NO_PEG`` for a start in the open.
    """
    w = 0.5 * spacing
    h = spacing * math.sqrt(3.0) / 4.0
    t_total = 0.0
    n = 0
    while n < max_collisions:
        t_level = falling_time(vy, level - y, g)
        t_end = min(t_level, max_time - t_total)
        t, m, j = next_hit(x, y, vx, vy, g, r, w, h, last_m, last_j, t_end)
        if t == math.inf:
            t = t_end
        x += vx * t
        y += (vy - 0.5 * g * t) * t
        vy -= g * t
        t_total += t
        if m == NO_PEG:
            if t_level <= max_time - (t_total - t):
                return n, STOP_LEVEL, t_total, x, level, vx, vy, spin
            return n, STOP_TIME, max_time, x, y, vx, vy, spin
        cx = m * w
        cy = 2 * j * h
        rho = math.hypot(x - cx, y - cy)
        nx = (cx - x) / rho  # outward: out of the table, into the peg
        ny = (cy - y) / rho
        x = cx - r * nx
        y = cy - r * ny
        vx, vy, spin = collide(law, c, s, vx, vy, spin, nx, ny)
        last_m = m
        last_j = j
        if n < log.shape[0]:
            log[n, 0] = x
            log[n, 1] = y
        n += 1
    return n, STOP_COLLISIONS, t_total, x, y, vx, vy, spin


@jit
def galton_ensemble(x, y, v, law, c, s, spacing, r, g, level, max_time, max_collisions, counts):
    """Every orbit from ``(x, y)`` with velocity ``v[i]`` and no spin; collisions per orbit into ``counts``."""
    log = np.empty((0, 2))
    total = 0
    for i in range(v.shape[0]):
        counts[i] = galton_orbit(x, y, v[i, 0], v[i, 1], 0.0, NO_PEG, NO_PEG, law, c, s, spacing, r, g, level,
                                 max_time, max_collisions, log)[0]
        total += counts[i]
    return total


def law_args(law, gamma=1.0 / math.sqrt(2.0)):
    """``(law, c, s)`` for ``galton_orbit``: the no-slip coefficients of ``gamma`` (docs/conventions.md)."""
    g2 = gamma * gamma
    return (NOSLIP if law == "no-slip" else SPECULAR), (1.0 - g2) / (1.0 + g2), 2.0 * gamma / (1.0 + g2)


#: The ensemble of ``bench_ensembles.py``: the board, the start, the limits.
BOARD = dict(spacing=2.0, r=0.5, g=1.0)
START = (1.0, 0.0)
LIMITS = dict(level=-100.0 * math.sqrt(3.0), max_time=1e4, max_collisions=10**7)


def plain_ensemble(law, v, counts=None):
    """Run the plain loop on the ensemble from ``START`` with velocities ``v``; returns the total collisions."""
    counts = np.zeros(len(v), dtype=np.int64) if counts is None else counts
    return int(galton_ensemble(*START, np.ascontiguousarray(v, dtype=float), *law_args(law), BOARD["spacing"],
                               BOARD["r"], BOARD["g"], LIMITS["level"], LIMITS["max_time"],
                               LIMITS["max_collisions"], counts))


def board_scene(law):
    """``tables.galton_board`` of ``BOARD`` with ``law`` (the default gamma, 1/sqrt 2)."""
    import noslipsim as ns

    return ns.tables.galton_board(BOARD["spacing"], BOARD["r"], BOARD["g"], law=law)


def plain_hits(law, state, peg, n_hits):
    """The first ``n_hits`` hit points of the plain loop from ``state = (x, y, vx, vy, w)`` on ``peg``."""
    log = np.full((n_hits, 2), np.nan)
    galton_orbit(*state, *peg, *law_args(law), BOARD["spacing"], BOARD["r"], BOARD["g"], LIMITS["level"],
                 LIMITS["max_time"], n_hits, log)
    return log


def peg_of(x, y):
    """``(m, j)`` of the peg nearest to ``(x, y)``, as ``cell_peg`` names them."""
    return round(x / (0.5 * BOARD["spacing"])), round(y / (BOARD["spacing"] * math.sqrt(3.0) / 2.0))


def compare_hits(law, v, n_hits, n_steps):
    """Distances between the plain loop's hit points and ``noslipsim.simulate``'s, along one orbit.

    Returns ``(along, step)``: along the orbit from ``START``, the first ``n_hits`` (rounding
    differences grow by the orbit's instability), and per step, the plain loop restarted on each of
    noslipsim's post-collision states (what one flight and one collision of each add), over the
    orbit's first ``n_steps`` collisions.
    """
    import noslipsim as ns

    ds = ns.simulate(board_scene(law), START, v, max_collisions=n_steps, stop_below=LIMITS["level"])
    ref = np.column_stack([ds.x.values, ds.y.values])
    n_hits = min(n_hits, len(ref))
    along = np.hypot(*(plain_hits(law, (*START, *v, 0.0), (NO_PEG, NO_PEG), n_hits) - ref[:n_hits]).T)
    state = np.column_stack([ds.x.values, ds.y.values, ds.vx.values, ds.vy.values, ds.spin.values])
    step = [np.hypot(*(plain_hits(law, state[i], peg_of(*state[i, :2]), 1)[0] - ref[i + 1]))
            for i in range(len(ref) - 1)]
    return along, np.array(step)


def compare_means(law, v):
    """Mean collisions per orbit (and its standard error) of the plain loop and of ``simulate_many``."""
    import noslipsim as ns

    scene = board_scene(law)
    plain = np.zeros(len(v), dtype=np.int64)
    plain_ensemble(law, v, plain)
    ds = ns.simulate_many(scene, np.tile(START, (len(v), 1)), v, scheduler="sync", progress=False,
                          max_collisions=LIMITS["max_collisions"], max_time=LIMITS["max_time"],
                          stop_below=LIMITS["level"])
    ours = ds.n_collisions.values
    return [(c.mean(), c.std(ddof=1) / math.sqrt(len(c))) for c in (plain, ours)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--orbits", type=int, default=2000, help="orbits of the ensemble")
    ap.add_argument("--starts", type=int, default=8, help="orbits whose first hit points are compared")
    ap.add_argument("--hits", type=int, default=20, help="hit points compared along each orbit")
    ap.add_argument("--steps", type=int, default=10**4, help="collisions per orbit compared one step at a time")
    args = ap.parse_args()
    from noslipsim import initial

    print(machine_line(load=True))
    v = initial.unit_velocities(args.orbits, seed=7)
    for law in ("specular", "no-slip"):
        rows = [compare_hits(law, v[i], args.hits, args.steps) for i in range(args.starts)]
        along = np.array([r[0] for r in rows])
        print(f"{law}: {args.starts} orbits, distance of the plain loop's hit points to noslipsim's, largest over "
              "the orbits, per collision:")
        print("  along the orbit: " + " ".join(f"{d:.0e}" for d in along.max(axis=0)))
        print(f"  one step from each of noslipsim's states, largest of all {sum(len(r[1]) for r in rows)}: "
              f"{max(r[1].max() for r in rows):.1e}")
        (pm, pe), (nm, ne) = compare_means(law, v)
        print(f"{law}: mean collisions per orbit over {args.orbits} orbits: plain loop {pm:.1f} +- {pe:.1f}, "
              f"noslipsim {nm:.1f} +- {ne:.1f} (difference {(pm - nm) / math.hypot(pe, ne):+.2f} sigma)")
        t0 = time.process_time()
        n = plain_ensemble(law, v)
        print(f"{law}: plain loop {n / (time.process_time() - t0):,.0f} collisions per CPU second "
              "(no guarantees)")


if __name__ == "__main__":
    main()
