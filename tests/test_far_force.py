"""Long lattice flights under a constant force: the far hit and the copy choice at the element's precision.

A flight under a weak force ``a`` along a corridor of a Lorentz gas (square lattice, disks of
radius 0.1; hexagonal lattice, radius 0.3) crosses ``1e3 .. 1e6`` cells before it meets a disk.
Formed plainly, its hit point ``q + v t + a t^2/2 - (o1 a1 + o2 a2)`` carries ``eps`` times the
flight's length, and so does the copy test of each cell (the flight re-centred at the cell's
entry).  The general lattice loop now forms both to twice the working precision in cells
``FAR_CELLS`` or more from the start (``core/cells.py``: ``far_hit_in_cell``,
``far_hit_point_force``), so the collision after the flight is as precise as its conditioning
allows, as for straight flights (``tests/test_stress.py``, ``test_corridor_hit_precision_*``).

Oracles: the exact first hit of the parabola (float inputs taken exactly, 50 digits): the
disks of the row the flight climbs to, each solved as a quartic; cross-checked once against
the 50-digit lattice reference (:func:`noslipsim.reference.simulate_reference`), whose walk
visits every cell.  Tolerances are those of the straight corridor tests: the velocity after
the hit within ``STEP_ULPS eps / sin(incidence)``, the hit point on the disk (its arclength
``s``) within ``STEP_ULPS eps r / sin(incidence)``, the hit time a few ulps of itself.
Before this change (main at b4489a3) the velocity error was up to 3.5e4 times its tolerance
(``test_far_force_fails_on_the_plain_evaluation`` replays the plain evaluation).
"""
import math

import mpmath as mp
import numpy as np
import pytest

from noslipsim import Circle, Scene, simulate, tables

EPS = float(np.finfo(float).eps)
#: As tests/test_stress.py: rounding of ~eps conditioned by 1/sin(incidence).
STEP_ULPS = 64.0
DPS = 50


def corridor(lattice, force, law):
    """Scene, start, and the row of disks the flight climbs to: ``(r, row_y, x_off, spacing)``."""
    if lattice == "square":
        return (tables.sinai_torus(0.1, law=law, force=force), (0.5, 0.23), (0.1, 1.0, 0.0, 1.0))
    if lattice == "hex":
        return (tables.hex_lorentz_cell(0.3, law=law, force=force), (0.0, 0.35),
                (0.3, math.sqrt(3.0) / 2, 0.5, 1.0))
    raise ValueError(lattice)


def exact_first_hit(q, v, a, row):
    """The parabola's first disk hit in the row ``(r, row_y, x_off, spacing)``, 50 digits.

    The flight rises with ``v_y > 0`` at constant ``a = (a_x, 0)``; it enters the band within
    ``r`` of the row when ``y = row_y - r``, and the first disk it meets is one of the few
    columns around that point (each solved as a quartic, the earliest real root taken).
    """
    with mp.workdps(DPS):
        r, row_y, x_off, spacing = (mp.mpf(c) for c in row)
        qx, qy, vx, vy, ax = (mp.mpf(c) for c in (*q, *v, a))
        t1 = (row_y - r - qy) / vy
        x1 = qx + vx * t1 + ax * t1 * t1 / 2
        i0 = int(mp.floor((x1 - x_off) / spacing))
        best = None
        for i in range(i0 - 3, i0 + 5):
            cx = x_off + i * spacing
            dx, dy = qx - cx, qy - row_y
            # |(dx + vx t + ax t^2/2, dy + vy t)|^2 - r^2, descending powers
            coeffs = [ax * ax / 4, vx * ax, vx * vx + dx * ax + vy * vy, 2 * (dx * vx + dy * vy),
                      dx * dx + dy * dy - r * r]
            for root in mp.polyroots(coeffs, maxsteps=400, extraprec=400):
                if abs(mp.im(root)) < mp.mpf(10) ** (-30) * abs(root) and mp.re(root) > 0:
                    t = mp.re(root)
                    if best is None or t < best[0]:
                        best = (t, i)
        assert best is not None and i0 - 3 < best[1] < i0 + 4, "no hit among the candidate columns"
        t, i = best
        cx = x_off + i * spacing
        hx, hy = qx + vx * t + ax * t * t / 2 - cx, qy + vy * t - row_y
        return t, i, hx, hy


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


def far_force_run(lattice, a, slope, law):
    """One flight under the force ``(a, 0)`` along a corridor: its first hit against the exact one.

    Returns the cells crossed, the errors of the hit time (relative), of the hit point on
    the disk (its arclength, absolute) and of the velocity after the hit (absolute, the
    speed is about 1), with the tolerances of their conditioning.
    """
    scene, q, row = corridor(lattice, (a, 0.0), law)
    v = (1.0 / math.hypot(1.0, slope), slope / math.hypot(1.0, slope))
    ds = simulate(scene, q, v, 0.0, max_collisions=1)
    assert ds.attrs["stop_reason"] == "max_collisions", ds.attrs["stop_reason"]
    t, i, hx, hy = exact_first_hit(q, v, a, row)
    with mp.workdps(DPS):
        r = mp.mpf(row[0])
        u = (mp.mpf(v[0]) + mp.mpf(a) * t, mp.mpf(v[1]))
        (vx1, vy1, w1), sin_inc = exact_collision(law, scene.gamma, u, (hx, hy), r)
        s = r * (mp.atan2(hy, hx) % (2 * mp.pi))
        out = dict(lattice=lattice, a=a, slope=slope, law=law, cells=float(t), sin_incidence=float(sin_inc),
                   column=i, hit_column=int(ds.cell_a1[0]),
                   t_error=float(abs(mp.mpf(float(ds.t[0])) - t) / t),
                   s_error=float(abs(mp.mpf(float(ds.s[0])) - s)),
                   velocity_error=float(max(abs(mp.mpf(float(ds.vx[0])) - vx1), abs(mp.mpf(float(ds.vy[0])) - vy1),
                                            abs(mp.mpf(float(ds.spin[0])) - w1))))
    out["velocity_tol"] = STEP_ULPS * EPS / out["sin_incidence"]
    out["s_tol"] = STEP_ULPS * EPS * row[0] / out["sin_incidence"]
    return out


def assert_far_force(r):
    what = f"{r['lattice']} a={r['a']:g} slope={r['slope']:g} {r['law']} ({r['cells']:.3g} cells)"
    assert r["t_error"] <= 1e-15, f"{what}: hit time {r}"
    assert r["s_error"] <= r["s_tol"], f"{what}: hit point {r['s_error']:.2e} > {r['s_tol']:.2e} {r}"
    assert r["velocity_error"] <= r["velocity_tol"], (
        f"{what}: velocity after the hit {r['velocity_error']:.2e} > {r['velocity_tol']:.2e} {r}")


#: (lattice, force, slope, law): flights of about 1e4, 1e5 and 1e6 cells, both lattices and laws
SHORT_CASES = [
    ("square", 1e-4, 1e-5, "specular"),   # 2.9e5 cells
    ("square", 1e-6, 1e-4, "no-slip"),    # 6.7e3 cells
    ("hex", 1e-5, 1e-5, "no-slip"),       # 2.2e6 cells
    ("hex", 1e-4, 1e-4, "specular"),      # 2.3e4 cells
]


@pytest.mark.parametrize(("lattice", "a", "slope", "law"), SHORT_CASES)
def test_far_hit_under_a_force_is_as_precise_as_its_conditioning(lattice, a, slope, law):
    r = far_force_run(lattice, a, slope, law)
    assert r["cells"] > 5e3 and r["hit_column"] == r["column"], r
    assert_far_force(r)
