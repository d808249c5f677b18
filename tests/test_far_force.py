"""Long lattice flights under a constant force: the far hit and the copy choice at the element's precision.

A flight under a weak force ``a`` along a corridor of a Lorentz gas (square lattice, disks of
radius 0.1; hexagonal lattice, radius 0.3) crosses ``1e3 .. 1e6`` cells before it meets a disk.
Formed plainly, its hit point ``q + v t + a t^2/2 - (o1 a1 + o2 a2)`` carries ``eps`` times the
flight's length, and so does the copy test of each cell (the flight re-centred at the cell's
entry).  The lattice walks test each cell ``FAR_CELLS`` or more from the start on the flight
re-centred exactly there (``core/cells.py``: ``far_hit_in_cell``), so *which* copy is hit is
decided at the cell's precision.  The hit point: the walk reports such a hit as an escape with a
finite time, and the event loop, out of its collision loop, moves the flight's start exactly
(double-double) to within ``NEAR_CELLS`` of the hit (``cells.far_move``), from where the walk finds
the same copy near and the hit point is formed plainly at the cell's scale.  Straight flights
relocate the far point instead (``cells.far_hit_point``, ``tests/test_stress.py``,
``test_corridor_hit_precision_*``).

Oracles: the exact first hit of the parabola (float inputs taken exactly, 50 digits): the
disks of the row the flight approaches, each solved as a quartic; cross-checked once against
the 50-digit lattice reference (:func:`noslipsim.reference.simulate_reference`), whose walk
visits every cell.  Tolerances are those of the straight corridor tests: the velocity after
the hit within ``STEP_ULPS eps |v| / sin(incidence)``, the hit point on the disk (its
arclength ``s``) within ``STEP_ULPS eps r / sin(incidence)``, the hit time a few ulps of
itself.  Measured (error / tolerance, the default cases) with the moved start (the engine's,
``NEAR_CELLS = 0.05``): velocity <= 0.014, hit point <= 0.010, time <= 7.7e-17 relative; over the
stress grid's 84 flights (65 to 3e6 cells) velocity <= 0.019 (median 0.004), hit point <= 0.019,
as near flights started from the correctly rounded state 0.05 cells before the same hit (0.013,
median 0.004: the rounding of a near hit).  The grazing flights below: time error 0 to the
double's resolution (before: up to 0.48 of the 1e-15 bound).  With the plain evaluation
(before): velocity 2.7 to 2.1e4 and hit point 1.4 to 1.5e4 times its tolerance, time up to
8.4e-15 (the diagonal corridor); with an exact relocation of the far point in the collision
loop (built, not kept: its call cost the Galton board 30 %) velocity <= 0.009.  Before the exact
copy test, a grazing flight's copy choice was wrong in 6 of 12 diagonal cases (it hit the disk
it passes at ``r + 1e-13 .. 1e-12``); now none.
"""
import functools
import math

import mpmath as mp
import numpy as np
import pytest

from noslipsim import simulate, tables
from noslipsim.reference.roots import _polyroots

EPS = float(np.finfo(float).eps)
#: As tests/test_stress.py: rounding of ~eps conditioned by 1/sin(incidence).
STEP_ULPS = 64.0
DPS = 50


#: name: (scene maker (law, force), start, the row of disks the flight approaches, corridor angle).
#: The row: radius, the centre of its disk ``m = 0``, the lattice vector ``P`` between its disks
#: and the cell of disk ``m`` as ``cell0 + m cstep``.
CORRIDORS = {
    "square": (lambda law, f: tables.sinai_torus(0.1, law=law, force=f), (0.5, 0.23),
               dict(r=0.1, c0=(0.0, 1.0), P=(1.0, 0.0), cell0=(0, 1), cstep=(1, 0)), 0.0),
    "hex": (lambda law, f: tables.hex_lorentz_cell(0.3, law=law, force=f), (0.0, 0.35),
            dict(r=0.3, c0=(0.5, math.sqrt(3.0) / 2), P=(1.0, 0.0), cell0=(0, 1), cstep=(1, 0)), 0.0),
    # the square lattice's corridor along (1, 1): x and y both grow with the flight
    "diagonal": (lambda law, f: tables.sinai_torus(0.1, law=law, force=f), (0.5, 0.23),
                 dict(r=0.1, c0=(0.0, 0.0), P=(1.0, 1.0), cell0=(0, 0), cstep=(1, 1)), math.pi / 4),
}


def corridor_flight(lattice, a, slope, law):
    """Scene (force ``a`` along the corridor), start, velocity (the corridor's direction turned by
    ``atan(slope)`` towards the row), force and row of :data:`CORRIDORS`."""
    make, q, row, angle = CORRIDORS[lattice]
    if angle == 0.0:
        v, force = (1.0 / math.hypot(1.0, slope), slope / math.hypot(1.0, slope)), (a, 0.0)
    else:
        turn = angle + math.atan(slope)
        v, force = (math.cos(turn), math.sin(turn)), (a * math.cos(angle), a * math.sin(angle))
    return make(law, force), q, v, force, row


def exact_first_hit(q, v, a, row):
    """The parabola ``q + v t + a t^2/2``'s first hit on a disk of ``row``, 50 digits (float inputs exact).

    The flight approaches the row's line (the force along it): it comes within ``r`` of that
    line at ``t1``, and the first disk it meets is one of the few around that point, each
    solved as a quartic, the earliest real root taken.  Returns ``(t, m, hx, hy)``: the time,
    the disk and the hit point relative to its centre.
    """
    with mp.workdps(DPS):
        r = mp.mpf(row["r"])
        qx, qy, vx, vy, ax, ay = (mp.mpf(c) for c in (*q, *v, *a))
        c0x, c0y = (mp.mpf(c) for c in row["c0"])
        px, py = (mp.mpf(c) for c in row["P"])
        plen = mp.sqrt(px * px + py * py)
        ex, ey = px / plen, py / plen
        w0 = (qx - c0x) * -ey + (qy - c0y) * ex  # the start's side of the row's line (negative)
        t1 = (-r - w0) / (vx * -ey + vy * ex)
        u1 = (qx - c0x) * ex + (qy - c0y) * ey + (vx * ex + vy * ey) * t1 + (ax * ex + ay * ey) * t1 * t1 / 2
        m0 = int(mp.floor(u1 / plen))
        best = None
        for m in range(m0 - 3, m0 + 5):
            dx, dy = qx - (c0x + m * px), qy - (c0y + m * py)
            # |d + v t + a t^2/2|^2 - r^2, ascending powers
            coeffs = [dx * dx + dy * dy - r * r, 2 * (dx * vx + dy * vy), vx * vx + vy * vy + dx * ax + dy * ay,
                      vx * ax + vy * ay, (ax * ax + ay * ay) / 4]
            for root in _polyroots(mp, coeffs, 400, 400):
                if abs(mp.im(root)) < mp.mpf(10) ** (-30) * abs(root) and mp.re(root) > 0:
                    t = mp.re(root)
                    if best is None or t < best[0]:
                        best = (t, m)
        assert best is not None and m0 - 3 < best[1] < m0 + 4, "no hit among the candidate disks"
        t, m = best
        hx = qx + vx * t + ax * t * t / 2 - (c0x + m * px)
        hy = qy + vy * t + ay * t * t / 2 - (c0y + m * py)
        return t, m, hx, hy


def exact_collision(law, gamma, u, h, r):
    """Velocity ``(vx, vy, w)`` after the collision at ``h`` (from the centre) with incoming ``u``, spin 0 before."""
    nx, ny = -h[0] / r, -h[1] / r  # outward normal (out of the table, into the disk)
    vt, vn = -u[0] * ny + u[1] * nx, u[0] * nx + u[1] * ny
    if law == "specular":
        vt1, w1 = vt, mp.mpf(0)
    else:
        g = mp.mpf(gamma)
        cc, ss = (1 - g * g) / (1 + g * g), 2 * g / (1 + g * g)
        w1, vt1 = -ss * vt, cc * vt
    return (-vt1 * ny - vn * nx, vt1 * nx - vn * ny, w1), abs(vn) / mp.sqrt(u[0] ** 2 + u[1] ** 2)


def hit_cell(row, m):
    return tuple(c + m * s for c, s in zip(row["cell0"], row["cstep"], strict=True))


@functools.cache
def far_force_run(lattice, a, slope, law):
    """One flight under the force ``a`` along a corridor: its first hit against the exact one.

    Returns the disks passed, the cells of the exact and the computed hit, the errors of
    the hit time (relative), of the hit point on the disk (its arclength, absolute) and of the
    velocity after the hit (absolute), with the tolerances of their conditioning (the
    velocity's scaled by the speed at the hit, ``|v + a t|``).
    """
    scene, q, v, force, row = corridor_flight(lattice, a, slope, law)
    ds = simulate(scene, q, v, 0.0, max_collisions=1)
    assert ds.attrs["stop_reason"] == "max_collisions", ds.attrs["stop_reason"]
    t, m, hx, hy = exact_first_hit(q, v, force, row)
    with mp.workdps(DPS):
        r = mp.mpf(row["r"])
        u = (mp.mpf(v[0]) + mp.mpf(force[0]) * t, mp.mpf(v[1]) + mp.mpf(force[1]) * t)
        (vx1, vy1, w1), sin_inc = exact_collision(law, scene.gamma, u, (hx, hy), r)
        s = r * (mp.atan2(hy, hx) % (2 * mp.pi))
        out = dict(lattice=lattice, a=a, slope=slope, law=law, cells=m, sin_incidence=float(sin_inc),
                   cell=hit_cell(row, m), hit_cell=(int(ds.cell_a1[0]), int(ds.cell_a2[0])),
                   t_error=float(abs(mp.mpf(float(ds.t[0])) - t) / t),
                   s_error=float(abs(mp.mpf(float(ds.s[0])) - s)),
                   velocity_error=float(max(abs(mp.mpf(float(ds.vx[0])) - vx1), abs(mp.mpf(float(ds.vy[0])) - vy1),
                                            abs(mp.mpf(float(ds.spin[0])) - w1))))
    out["speed"] = float(mp.sqrt(u[0] ** 2 + u[1] ** 2))  # the force speeds the particle up along the corridor
    out["velocity_tol"] = STEP_ULPS * EPS * out["speed"] / out["sin_incidence"]
    out["s_tol"] = STEP_ULPS * EPS * row["r"] / out["sin_incidence"]
    return out


def assert_far_force(r):
    what = f"{r['lattice']} a={r['a']:g} slope={r['slope']:g} {r['law']} ({r['cells']:.3g} cells)"
    assert r["t_error"] <= 1e-15, f"{what}: hit time {r}"
    assert r["s_error"] <= r["s_tol"], f"{what}: hit point {r['s_error']:.2e} > {r['s_tol']:.2e} {r}"
    assert r["velocity_error"] <= r["velocity_tol"], (
        f"{what}: velocity after the hit {r['velocity_error']:.2e} > {r['velocity_tol']:.2e} {r}")


#: (lattice, force, slope, law): flights of 2e3 to 9e5 cells, both lattices and laws
SHORT_CASES = [
    ("square", 1e-6, 1e-4, "no-slip"),    # 6.7e3 cells
    ("square", 1e-4, 1e-5, "specular"),   # 2.9e5 cells
    ("square", 1e-5, 2e-6, "specular"),   # 9e5 cells
    ("hex", 1e-4, 1e-4, "specular"),      # 2.4e3 cells
    ("hex", 1e-3, 1e-5, "no-slip"),       # 2.5e5 cells
    ("hex", 1e-5, 1e-6, "no-slip"),       # 4.5e5 cells
    ("diagonal", 1e-4, 1e-5, "no-slip"),  # 9e3 cells along (1, 1)
    ("diagonal", 1e-3, 1e-6, "specular"),  # 3e6 cells along (1, 1)
]
#: The stress grid: every force and slope whose flight stays within the walk's cell budget
STRESS_FORCES = (1e-6, 1e-5, 1e-4, 1e-3)
STRESS_SLOPES = (1e-3, 1e-4, 1e-5, 2e-6)


@pytest.mark.parametrize(("lattice", "a", "slope", "law"), SHORT_CASES)
def test_far_flight_under_a_force_hits_the_copy_of_the_exact_parabola(lattice, a, slope, law):
    r = far_force_run(lattice, a, slope, law)
    assert r["cells"] > 2e3 and r["hit_cell"] == r["cell"], r


@pytest.mark.parametrize(("lattice", "a", "slope", "law"), SHORT_CASES)
def test_far_hit_under_a_force_is_as_precise_as_its_conditioning(lattice, a, slope, law):
    assert_far_force(far_force_run(lattice, a, slope, law))


@pytest.mark.parametrize(("lattice", "a", "slope"), [("square", 1e-4, 1e-5), ("hex", 1e-3, 1e-5),
                                                    ("diagonal", 1e-4, 1e-5)])
def far_walk_and_move(lattice, a, slope, t_max=math.inf):
    """The walk's far hit of a corridor flight and :func:`cells.far_move` towards it:
    ``(scene, start, velocity, force, arrays, far, moved)``."""
    from noslipsim._engine.table import kernel_table
    from noslipsim.core.cells import far_move, lattice_walk
    from noslipsim.core.tolerances import EXTENT_TOL, MAX_CELLS_PER_FLIGHT

    scene, q, v, force, _ = corridor_flight(lattice, a, slope, "specular")
    arrays = kernel_table(scene).arrays()[:5]
    far = lattice_walk(falling=True)(*arrays, *q, *v, *force, -1, 0, 0, math.inf, EXTENT_TOL * scene.scale,
                                     MAX_CELLS_PER_FLIGHT)
    moved = far_move(*arrays[3:5], *q, *v, *force, far[0], t_max)
    return scene, q, v, force, arrays, far, moved


@pytest.mark.parametrize(("lattice", "a", "slope"), [("square", 1e-4, 1e-5), ("hex", 1e-3, 1e-5),
                                                    ("diagonal", 1e-4, 1e-5)])
def test_the_moved_start_meets_the_same_copy_near(lattice, a, slope):
    """The walk's far hit (status 2, finite time), then ``far_move``: from the moved start the walk
    finds the same element copy (seen from the new cell) within a cell or two, at the rest of the time."""
    from noslipsim.core.cells import FAR_CELLS, NEAR_CELLS, lattice_walk
    from noslipsim.core.tolerances import EXTENT_TOL, MAX_CELLS_PER_FLIGHT

    scene, q, v, force, arrays, far, moved = far_walk_and_move(lattice, a, slope)
    A, B = arrays[3:5]
    t_hit, e, o1, o2, status = far
    assert status == 2 and math.isfinite(t_hit) and max(abs(o1), abs(o2)) > FAR_CELLS, far
    t_move, k1, k2, x, y, vx, vy = moved
    assert 0.0 < t_move < t_hit
    with mp.workdps(DPS):  # the moved start lies on the flight, to the rounding of its coordinates
        for i, got in ((0, x), (1, y)):
            exact = mp.mpf(q[i]) + mp.mpf(v[i]) * t_move + mp.mpf(force[i]) * mp.mpf(t_move) ** 2 / 2
            assert abs(mp.mpf(got) + (k1 * mp.mpf(A[i, 0]) + k2 * mp.mpf(A[i, 1])) - exact) <= EPS * abs(got), i
    assert np.all(np.abs(B @ [x, y]) <= 0.5 + 1e-12)  # in the cell it is re-based onto
    assert (vx, vy) == pytest.approx((v[0] + force[0] * t_move, v[1] + force[1] * t_move), rel=1e-15)
    near = lattice_walk(falling=True)(*arrays, x, y, vx, vy, *force, -1, 0, 0, math.inf, EXTENT_TOL * scene.scale,
                                      MAX_CELLS_PER_FLIGHT)
    assert near[4] == 0 and near[1:4] == (e, o1 - k1, o2 - k2), (far, (k1, k2), near)
    assert max(abs(o1 - k1), abs(o2 - k2)) <= NEAR_CELLS + 2
    assert t_move + near[0] == pytest.approx(t_hit, rel=4 * EPS)


def test_time_stops_inside_a_far_flight_under_a_force():
    """``max_time`` before the moved start, between it and the hit, and ``stop_below`` before the hit:
    the orbit stops there as before, at the exact parabola's state (to the rounding of the
    unfolded position, ``eps`` times its size)."""
    scene, q, v, force, _, far, moved = far_walk_and_move("square", 1e-4, 1e-5)
    t_hit, t_move = far[0], moved[0]
    for t_stop in (0.5 * t_hit, 0.5 * (t_move + t_hit)):  # before the moved start, and after it
        ds = simulate(scene, q, v, 0.0, max_collisions=5, max_time=t_stop)
        assert ds.attrs["stop_reason"] == "max_time" and int(ds.n_collisions) == 0
        assert float(ds.t_final) == t_stop
        with mp.workdps(DPS):
            ex = [mp.mpf(q[i]) + mp.mpf(v[i]) * t_stop + mp.mpf(force[i]) * mp.mpf(t_stop) ** 2 / 2 for i in (0, 1)]
            got = (float(ds.x_final), float(ds.y_final))
            assert all(abs(mp.mpf(g) - c) <= 4 * EPS * abs(c) + 1e-15 for g, c in zip(got, ex, strict=True)), (got, ex)
        assert (int(ds.cell_a1_final), int(ds.cell_a2_final)) == (round(got[0]), round(got[1]))
        assert float(ds.vx_final) == pytest.approx(v[0] + force[0] * t_stop, rel=4 * EPS)
    # a flight that rises, turns and falls back through y = 0.2 some 2.3e3 cells out, before its hit
    # on the row y = 0 some 4e3 cells out (the level is the walk's time limit: it stops there, as before)
    scene = tables.sinai_torus(0.1, law="specular", force=(1e-4, -2e-8))
    q, v = (0.5, 0.23), (1.0, 1e-5)
    ds = simulate(scene, q, v, 0.0, max_collisions=5, stop_below=0.2)
    assert ds.attrs["stop_reason"] == "stop_below" and int(ds.n_collisions) == 0
    with mp.workdps(DPS):  # 0.23 + 1e-5 t - 1e-8 t^2 = 0.2, the later root
        b, c2 = mp.mpf(v[1]), mp.mpf(-2e-8) / 2
        t_level = (-b - mp.sqrt(b * b - 4 * c2 * (mp.mpf(q[1]) - mp.mpf(0.2)))) / (2 * c2)
    assert 2e3 < t_level < 3e3
    assert float(ds.t_final) == pytest.approx(float(t_level), rel=1e-13)
    assert float(ds.y_final) == pytest.approx(0.2, abs=1e-12)


def test_the_oracle_is_the_lattice_reference():
    """The first hit of a 230-cell flight under a force: the 50-digit reference's walk (every cell
    visited) finds the oracle's hit, and the float engine hits the same copy."""
    from noslipsim.reference import simulate_reference
    scene, q, v, force, row = corridor_flight("square", 1e-4, 3e-3, "no-slip")
    ref = simulate_reference(scene, q, v, 0.0, max_collisions=1, dps=DPS, as_mpf=True)
    t, m, hx, hy = exact_first_hit(q, v, force, row)
    assert ref.cells[0] == hit_cell(row, m) and m > 200
    assert abs(ref.records["t"][0] - t) < mp.mpf(10) ** -40 * t
    with mp.workdps(DPS):
        assert abs(ref.records["s"][0] - row["r"] * (mp.atan2(hy, hx) % (2 * mp.pi))) < mp.mpf(10) ** -40
    assert far_force_run("square", 1e-4, 3e-3, "no-slip")["hit_cell"] == hit_cell(row, m)


@pytest.mark.stress
@pytest.mark.parametrize("law", ["specular", "no-slip"])
@pytest.mark.parametrize("lattice", ["square", "hex", "diagonal"])
@pytest.mark.parametrize("slope", STRESS_SLOPES)
@pytest.mark.parametrize("a", STRESS_FORCES)
def test_far_hit_under_a_force_stress(lattice, a, slope, law):
    # flight time ~ 0.7 / slope; the cells crossed ~ t + a t^2 / 2 must stay below the walk's budget
    t = 0.7 / slope
    if t + a * t * t / 2 > 5e6:
        pytest.skip("the flight would cross more cells than the walk's budget (an escape)")
    r = far_force_run(lattice, a, slope, law)
    print(r)
    assert r["hit_cell"] == r["cell"], r


def closest_approach(q, v, a, centre):
    """Least distance of the parabola ``q + v t + a t^2/2`` from ``centre`` near its hit, 50 digits."""
    with mp.workdps(DPS):
        qx, qy, vx, vy, ax, ay = (mp.mpf(c) for c in (*q, *v, *a))
        cx, cy = (mp.mpf(c) for c in centre)

        def pos(t):
            return qx + vx * t + ax * t * t / 2 - cx, qy + vy * t + ay * t * t / 2 - cy

        def rate(t):  # d/dt of half the squared distance
            dx, dy = pos(t)
            return dx * (vx + ax * t) + dy * (vy + ay * t)

        # Newton on the rate from the time of the closest approach of the flight's tangent at t = 0
        t0 = -((qx - cx) * vx + (qy - cy) * vy) / (vx * vx + vy * vy)
        for _ in range(200):
            t = mp.findroot(rate, t0)
            if abs(t - t0) < mp.mpf(10) ** -20 * (1 + abs(t)):
                break
            t0 = t
        return mp.sqrt(sum(c * c for c in pos(t)))


def grazing_start(lattice, a, slope, gap):
    """A start whose flight passes the first disk it would hit at ``r + gap`` from its centre.

    The corridor flight of :func:`far_force_run` is moved across the corridor (its start's
    ``y``) so that its closest approach to that disk is ``r + gap``; the start is then rounded
    to a float, and the true gap of the float start is returned with it (50 digits).
    """
    scene, q, v, force, row = corridor_flight(lattice, a, slope, "specular")
    m = exact_first_hit(q, v, force, row)[1]
    centre = (row["c0"][0] + m * row["P"][0], row["c0"][1] + m * row["P"][1])
    cos = float(mp.cos(CORRIDORS[lattice][3]))  # y moves the corridor flight across by y cos(angle)
    for _ in range(3):
        d = closest_approach(q, v, force, centre)
        q = (q[0], float(mp.mpf(q[1]) + (d - row["r"] - gap) / cos))
    return scene, q, v, force, row, m, float(closest_approach(q, v, force, centre) - row["r"])


#: (lattice, force, slope): grazing flights past a disk some 1e5 cells away, where the plain
#: re-centring at a cell's entry carries eps x length, 1e-11, a hundred times the gaps below
GRAZE_CASES = [("square", 1e-4, 1e-5), ("diagonal", 1e-3, 1e-6), ("diagonal", 1e-5, 1e-6)]
GAPS = (3e-13, 1e-13, -1e-13, -3e-13)


@pytest.mark.parametrize(("lattice", "a", "slope"), GRAZE_CASES)
def test_a_flight_grazing_a_far_copy_picks_the_right_one(lattice, a, slope):
    """Passing a far disk at ``r +- 1e-13``: hit or missed as in exact arithmetic, and the hit time precise."""
    missed = hit = 0
    for gap in GAPS:
        scene, q, v, force, row, m, true_gap = grazing_start(lattice, a, slope, gap)
        assert 1e-14 < abs(true_gap) < 1e-12 and true_gap * gap > 0, true_gap
        ds = simulate(scene, q, v, 0.0, max_collisions=1)
        t, m1 = exact_first_hit(q, v, force, row)[:2]
        assert (m1 == m) == (true_gap < 0), (gap, m1, m)
        got = (int(ds.cell_a1[0]), int(ds.cell_a2[0]))
        assert got == hit_cell(row, m1), f"gap {true_gap:.2e}: hit in cell {got}, exact {hit_cell(row, m1)}"
        assert abs(float(ds.t[0]) - float(t)) <= 1e-15 * float(t), (gap, float(ds.t[0]), float(t))
        missed += m1 != m
        hit += m1 == m
    assert missed and hit
