"""Periodic scenes: the float64 engine against its mpmath twin :mod:`noslipsim.reference`.

(a) Per collision (one-step shadowing, as in tests/test_reference.py): the reference restarted
    from each float64 post-collision state predicts the next float64 collision to ``TOL = 1e-12``
    of the orbit's scales (those of ``tests/test_reference.py``: length ``max(scale, |x|, |y|)``
    for ``x, y`` and the arclength ``s`` on the element copy, speed ``max |(v, w)|``, time
    ``max(1, t)``), with identical element indices, cell indices, corner flags and stop
    reasons, over 20 collisions of the Sinai torus, the hexagonal Lorentz cell and the Galton
    board, specular and no-slip (gamma 0, 1/sqrt 2, 1, 3), until the terminal level on the
    Galton board, and on cells whose scatterers straddle cell faces (element copies with
    offsets, segments, vertices, with and without a force).
(b) Whole orbits where chaos allows: the first ``N`` collisions agree at ``TOL`` (``s`` at the
    cell's scale: from an exact start nothing limits it), where ``N`` is
    measured, not guessed: the collisions over which one rounding error of the start (one ulp
    of ``v_x``) stays below ``TOL / 10`` in the reference itself.  A float64 orbit makes a
    rounding error of a few ulps per collision, each amplified at most as much as the one at
    the start (a geometric sum: about 1.1 times the largest term at the growth rates here),
    so the float64 orbit stays within ``TOL`` over those ``N``.  Measured: ``N`` = 2 to 4
    on the dispersing tables (5 to 16 with gamma = 3, whose law is closer to a reversal);
    elliptic no-slip orbits between two disks (stable by the two-disk theorem,
    :func:`noslipsim.theory.two_disk_eigen_sum`) are compared over all 20.
(c) The walk's hard cases: a flight across ~500 cells, a start 10^5 cells away, flights
    through a lattice corner (straight and parabolic) and touching a face, endless corridors
    (escape, time limit, level, the engine's cell budget), the strip-exit rules.
(d) Oracles independent of the float engine: the lattice reference against the plain
    reference of the same table tiled explicitly, translation by a lattice vector, the exact
    line-circle hit after a long corridor flight, energy and the contact-velocity reversal.
(e) Mutations: a wrong cell step or a wrong cell assignment in the reference fails (a).
"""
import math
from fractions import Fraction

import mpmath
import numpy as np
import pytest
from shadowing import one_step_references

from noslipsim import Circle, Scene, Segment, simulate, tables, theory
from noslipsim.reference import resume_reference, simulate_reference
from noslipsim.reference import walk as reference  # the cell walk: _strip_exit, _Table, MAX_CELLS_PER_FLIGHT

#: Agreement asked of the float64 engine, relative to the orbit's scales.
TOL = 1e-12
#: The reference's working precision: its own error (1e-30, amplified by chaos ~10x per
#: collision) stays far below TOL over every comparison here; under a force (quartics)
#: 30 digits cost about 20 % less than 50 (measured on the Galton board).
DPS = 30
#: Reference-only comparisons (both sides exact to ~1e-40, amplified over at most 10 collisions).
ORACLE_DPS = 40
ORACLE_TOL = 1e-25

DISK = 1 / math.sqrt(2)
LAWS = [("specular", 0.0), ("no-slip", 0.0), ("no-slip", DISK), ("no-slip", 1.0), ("no-slip", 3.0)]
LAW_IDS = ["specular", "g0", "g0.707", "g1", "g3"]

POSITIONS = ("x", "y")
SPEEDS = ("vx", "vy", "spin", "vx_in", "vy_in", "spin_in")


def two_disk_cell(law="no-slip", gamma=DISK):
    """Square lattice, a disk at the origin and a smaller one at the cell corner (reaches four cells)."""
    return Scene((Circle((0.0, 0.0), 0.2, "outside"), Circle((0.5, 0.5), 0.15, "outside")),
                 law=law, gamma=gamma, lattice={"a1": [1.0, 0.0], "a2": [0.0, 1.0]})


def diamond_cell(law="no-slip", gamma=DISK, force=(0.0, 0.0)):
    """Square lattice of diamond scatterers (four segments, clockwise: the table is outside).

    The diamond on the cell corner (0.5, 0.5) reaches four cells, so copies with offsets,
    segment extents and the corner rule at its vertices all meet the walk.
    """
    c, h = 0.5, 0.25
    pts = [(c, c + h), (c + h, c), (c, c - h), (c - h, c)]
    segs = tuple(Segment(pts[i], pts[(i + 1) % 4], "left") for i in range(4))
    return Scene(segs, law=law, gamma=gamma, force=force, lattice={"a1": [1.0, 0.0], "a2": [0.0, 1.0]})


# name: (scene factory (law, gamma) -> Scene, position, velocity, spin, budget, simulate kwargs)
SCENES = {
    "torus": (lambda law, g: tables.sinai_torus(0.25, law=law, gamma=g), (0.4, 0.1), (0.7, 0.31), 0.2, 20, {}),
    "hex": (lambda law, g: tables.hex_lorentz_cell(0.3, law=law, gamma=g), (0.4, 0.1), (0.7, 0.31), 0.2, 20, {}),
    "galton": (lambda law, g: tables.galton_board(law=law, gamma=g), (1.0, 0.0), (0.3, 0.95), 0.2, 20, {}),
    "galton_level": (lambda law, g: tables.galton_board(law=law, gamma=g), (1.0, 0.0), (0.3, 0.95), 0.2, 80,
                     dict(stop_below=-12.5)),
    "two_disk_cell": (two_disk_cell, (0.1, 0.4), (0.7, 0.31), 0.2, 20, {}),
    "diamond_cell": (diamond_cell, (0.1, 0.1), (0.7, 0.31), 0.2, 20, {}),
    "diamond_gravity": (lambda law, g: diamond_cell(law, g, force=(0.05, -1.0)), (0.1, 0.1), (0.7, 0.31), 0.2,
                        20, {}),
}


# ----------------------------------------------------------------------------- comparison
def cell_scale(scene):
    """Length scale of quantities measured in a cell (the arclength on an element copy)."""
    return max(scene.scale, *(math.hypot(*scene.lattice[k]) for k in ("a1", "a2")))


def orbit_scales(scene, ds, s_in_cell=False):
    """The scales of tests/test_reference.py: length, speed, time and energy of an orbit.

    ``s_in_cell``: measure the arclength ``s`` (on an element copy) at the cell's scale
    instead of the orbit's length, for comparisons from an exact start (a restart from a
    float64 state far from the origin carries the rounding of its unfolded position).
    """
    x = np.append(ds.x.values, float(ds.x_final))
    y = np.append(ds.y.values, float(ds.y_final))
    speed = float(np.sqrt(np.append(ds.vx.values, float(ds.vx_final)) ** 2
                          + np.append(ds.vy.values, float(ds.vy_final)) ** 2
                          + np.append(ds.spin.values, float(ds.spin_final)) ** 2).max())
    length = max(scene.scale, float(np.abs(x).max()), float(np.abs(y).max()))
    energy = max(float(np.abs(ds.energy.values).max(initial=0.0)), speed ** 2, 1.0)
    return {**{k: length for k in POSITIONS}, "s": cell_scale(scene) if s_in_cell else length,
            **{k: speed for k in SPEEDS},
            "t": max(1.0, float(ds.t_final)), "energy": energy}


def same_events(ref, flt, what, n=None):
    """Elements, corner flags and cells of the first ``n`` collisions are identical.

    A hit point within rounding of a cell face could get either cell (both engines take
    the nearest lattice site); no collision here comes that close to a face.
    """
    for name in ("element", "corner", "cell_a1", "cell_a2"):
        np.testing.assert_array_equal(flt[name].values[:n], ref[name].values[:n], err_msg=f"{what} {name}")


def largest_deviation(ref, flt, scales, n):
    """Largest ``|float - reference| / scale`` over the first ``n`` collisions, per variable."""
    return {name: float(np.abs(flt[name].values[:n] - ref[name].values[:n]).max(initial=0.0)) / scale
            for name, scale in scales.items()}


def shadow(scene, q, v, w, budget, kw):
    """One-step shadowing of a float64 orbit; returns the largest scaled deviation per variable.

    Asserts the events (element, cell, corner) of every step, the stop reason after the
    last collision, and every value within ``TOL`` of the orbit's scales.
    """
    flt = simulate(scene, q, v, w, max_collisions=budget, **kw)
    m = flt.sizes["collision"]
    assert m >= min(budget, 20), f"only {m} collisions"
    scales = orbit_scales(scene, flt)
    worst = dict.fromkeys(scales, 0.0)
    for k, step, t_prev in one_step_references(scene, q, v, w, flt, dps=DPS, **kw):
        what = f"event after collision {k}"
        same_events(step, flt.isel(collision=[k + 1]), what)
        step = step.assign(t=step.t + t_prev)
        dev = largest_deviation(step, flt.isel(collision=[k + 1]), scales, 1)
        for name, value in dev.items():
            assert value <= TOL, f"{what}: {name} off by {value:.3g} of its scale"
            worst[name] = max(worst[name], value)
    assert k == m - 2, f"checked {k + 2} of {m} collisions"  # every collision but the budget's last
    return worst


def chaos_horizon(scene, q, v, w, budget, kw):
    """The reference orbit and the number of its first collisions that one rounding cannot spoil.

    The reference is run again from ``v_x`` moved by one ulp; the horizon is the number of
    leading collisions with the same events and every value within ``TOL / 10``.
    """
    ref = simulate_reference(scene, q, v, w, max_collisions=budget, dps=DPS, **kw)
    v1 = (float(np.nextafter(v[0], math.inf)), v[1])
    pert = simulate_reference(scene, q, v1, w, max_collisions=budget, dps=DPS, **kw)
    scales = orbit_scales(scene, ref, s_in_cell=True)
    m = min(ref.sizes["collision"], pert.sizes["collision"])
    for k in range(m):
        a, b = ref.isel(collision=[k]), pert.isel(collision=[k])
        events = all(int(a[n][0]) == int(b[n][0]) for n in ("element", "cell_a1", "cell_a2", "corner"))
        if not events or max(largest_deviation(a, b, scales, 1).values()) > TOL / 10:
            return ref, k
    return ref, m


def with_law(name, law, gamma):
    make, q, v, w, budget, kw = SCENES[name]
    return make(law, gamma), q, v, w, budget, kw


# ----------------------------------------------------------------------------- (a) per collision
@pytest.mark.parametrize("law, gamma", LAWS, ids=LAW_IDS)
@pytest.mark.parametrize("name", ["torus", "hex", "galton"])
def test_every_collision_agrees(name, law, gamma):
    scene, q, v, w, budget, kw = with_law(name, law, gamma)
    shadow(scene, q, v, w, budget, kw)


@pytest.mark.parametrize("law, gamma", [("specular", 0.0), ("no-slip", DISK)], ids=["specular", "g0.707"])
@pytest.mark.parametrize("name", ["two_disk_cell", "diamond_cell", "diamond_gravity"])
def test_every_collision_agrees_on_straddling_scatterers(name, law, gamma):
    scene, q, v, w, budget, kw = with_law(name, law, gamma)
    shadow(scene, q, v, w, budget, kw)


def test_every_collision_agrees_until_the_level():
    """The Galton board until the terminal height (41 collisions, then ``stop_below`` in both)."""
    scene, q, v, w, budget, kw = with_law("galton_level", "no-slip", DISK)
    shadow(scene, q, v, w, budget, kw)


def test_cases_exercise_what_they_claim():
    """Guards against silent start changes: the features each case is meant to reach.

    Read from the float64 orbits (cheap), which the tests above show the reference to agree with.
    """
    def run(name, law="no-slip", gamma=DISK):
        scene, q, v, w, budget, kw = with_law(name, law, gamma)
        return simulate(scene, q, v, w, max_collisions=budget, **kw)

    assert run("galton_level").attrs["stop_reason"] == "stop_below"
    for name in ("torus", "hex", "galton"):
        ds = run(name)
        cells = set(zip(ds.cell_a1.values.tolist(), ds.cell_a2.values.tolist()))
        assert len(cells) >= 8, name  # the orbit wanders over many cells
        steps = np.diff(np.c_[ds.cell_a1.values, ds.cell_a2.values], axis=0)
        assert (steps < 0).any() and (steps > 0).any(), name  # walks up and down the cells
    two = run("two_disk_cell")
    assert {0, 1} <= set(two.element.values.tolist())
    diamond = run("diamond_cell", "specular", 0.0)
    assert len(set(diamond.element.values.tolist())) == 4  # every side of the diamond


# ----------------------------------------------------------------------------- (b) whole orbits
@pytest.mark.parametrize("law, gamma", [("specular", 0.0), ("no-slip", DISK), ("no-slip", 3.0)],
                         ids=["specular", "g0.707", "g3"])
@pytest.mark.parametrize("name", ["torus", "hex", "galton", "two_disk_cell"])
def test_whole_orbit_agrees_within_the_chaos_horizon(name, law, gamma):
    """Measured horizons: 2 to 4 collisions (rounding grows ~10x per collision), 5 to 16 with gamma = 3.

    So 8 collisions are run (20 with gamma = 3), and the horizon must end before them.
    """
    scene, q, v, w, budget, kw = with_law(name, law, gamma)
    budget = 20 if gamma == 3.0 else 8
    ref, n = chaos_horizon(scene, q, v, w, budget, kw)
    assert n < budget or gamma == 3.0, f"horizon {n}: the budget hides how far chaos allows"
    assert n >= 2, f"horizon {n}: nothing to compare"
    flt = simulate(scene, q, v, w, max_collisions=budget, **kw)
    same_events(ref, flt, name, n)
    for var, dev in largest_deviation(ref, flt, orbit_scales(scene, ref, s_in_cell=True), n).items():
        assert dev <= TOL, f"{name} {var}: {dev:.3g} over the first {n} collisions"


#: Elliptic 2-periodic no-slip orbits along the line of centres of neighbouring disks,
#: started off them: the orbit stays near them, so rounding is not amplified.
ELLIPTIC = {
    "torus_r0.4": (tables.sinai_torus(0.4, gamma=DISK), 0.4, 1.0, DISK),
    "torus_r0.3_g1": (tables.sinai_torus(0.3, gamma=1.0), 0.3, 1.0, 1.0),
    "hex_r0.4": (tables.hex_lorentz_cell(0.4, gamma=DISK), 0.4, 1.0, DISK),
}


@pytest.mark.parametrize("name", list(ELLIPTIC))
def test_whole_elliptic_orbit_agrees(name):
    scene, r, spacing, gamma = ELLIPTIC[name]
    eig = theory.two_disk_eigen_sum(1 / r, spacing - 2 * r, 0.0, gamma)
    assert -2 < eig < 2  # the two-disk theorem: elliptic
    q, v, w = (0.5, 0.02), (1.0, 0.01), 0.05
    ref, n = chaos_horizon(scene, q, v, w, 20, {})
    assert n == 20  # chaos allows the whole orbit
    flt = simulate(scene, q, v, w, max_collisions=20)
    assert flt.attrs["stop_reason"] == ref.attrs["stop_reason"] == "max_collisions"
    same_events(ref, flt, name)
    scales = orbit_scales(scene, ref, s_in_cell=True)
    for var, dev in largest_deviation(ref, flt, scales, 20).items():
        assert dev <= TOL, f"{name} {var}: {dev:.3g}"
    for var in ("t", "x", "y", "vx", "vy", "spin"):
        assert abs(float(flt[f"{var}_final"]) - float(ref[f"{var}_final"])) <= TOL * scales[var]
    assert (int(flt.cell_a1_final), int(flt.cell_a2_final)) == (int(ref.cell_a1_final), int(ref.cell_a2_final))


# ----------------------------------------------------------------------------- (c) the walk's hard cases
def test_long_corridor_flight():
    """A first flight across ~490 cells of a corridor, then 20 collisions, each shadowed."""
    scene = tables.sinai_torus(0.25, law="no-slip", gamma=DISK)
    flt = simulate(scene, (0.5, 0.26), (1.0, 1e-3), 0.1, max_collisions=1)
    assert int(flt.cell_a1[0]) > 400
    shadow(scene, (0.5, 0.26), (1.0, 1e-3), 0.1, 20, {})


def mid_flight_twins(scene, flt, kw):
    """Both engines restarted from the same float64 state halfway along every flight of ``flt``.

    Each start is a float64 state strictly inside the table that both engines take
    exactly, so the comparison of the collision that ends the flight measures the engines
    alone (a restart from a reported post-collision state would add the rounding of its
    unfolded position, ``eps |x|``, which far from the origin exceeds ``TOL``).  Returns
    the largest deviation per variable, ``s`` at the cell's scale.
    """
    ax, ay = scene.force
    scales = orbit_scales(scene, flt, s_in_cell=True)
    worst = dict.fromkeys(scales, 0.0)
    for k in range(flt.sizes["collision"] - 1):
        tau = 0.5 * float(flt.t[k + 1] - flt.t[k])
        x, y, vx, vy = (float(flt[n][k]) for n in ("x", "y", "vx", "vy"))
        q = (x + vx * tau + 0.5 * ax * tau * tau, y + vy * tau + 0.5 * ay * tau * tau)
        v = (vx + ax * tau, vy + ay * tau)
        w = float(flt.spin[k])
        ref = simulate_reference(scene, q, v, w, max_collisions=1, dps=DPS, **kw)
        one = simulate(scene, q, v, w, max_collisions=1, **kw)
        same_events(ref, one, f"flight {k}")
        for name, value in largest_deviation(ref, one, scales, 1).items():
            assert value <= TOL, f"flight {k}: {name} off by {value:.3g} of its scale"
            worst[name] = max(worst[name], value)
    return worst


def test_start_far_from_the_origin():
    """A start 10^5 cells away: the same cells and events, and values as accurate as near the origin.

    The float64 engine keeps positions relative to the particle's cell and reports them
    unfolded, so a reported position carries a rounding of ``eps |x|`` (1e-11 here).  The
    flights are compared by restarting both engines from the same state halfway along each
    (:func:`mid_flight_twins`), and the whole orbit from the exact start within its chaos
    horizon, ``s`` at the cell's scale in both.
    """
    far = (0.375 + 123457.0, 0.125 - 65432.0)  # exact: the start (0.375, 0.125) moved by a lattice vector
    for law, gamma in [("specular", 0.0), ("no-slip", DISK)]:
        scene = tables.sinai_torus(0.25, law=law, gamma=gamma)
        flt = simulate(scene, far, (0.7, 0.31), 0.2, max_collisions=20)
        assert abs(int(flt.cell_a1[0]) - 123457) <= 3 and abs(int(flt.cell_a2[0]) + 65432) <= 3
        mid_flight_twins(scene, flt, {})
        ref, n = chaos_horizon(scene, far, (0.7, 0.31), 0.2, 20, {})
        assert n >= 2
        same_events(ref, flt, "far", n)
        for var, dev in largest_deviation(ref, flt, orbit_scales(scene, ref, s_in_cell=True), n).items():
            assert dev <= TOL, f"far {law} {var}: {dev:.3g}"


@pytest.mark.parametrize("force, q, v, cell", [
    ((0.0, 0.0), (0.25, 0.375), (1.0, 0.5), (1, 1)),     # x = 1/4 + t, y = 3/8 + t/2: (1/2, 1/2) at t = 1/4
    ((0.0, -1.0), (0.25, 0.25), (1.0, 1.125), (1, 1)),   # y = 1/4 + 9t/8 - t^2/2: (1/2, 1/2) at t = 1/4
    ((0.0, -1.0), (0.25, 0.375), (0.5, 0.5), (1, 0)),    # apex (1/2, 1/2) at t = 1/2: touches, never crosses
], ids=["straight", "parabola", "apex_on_corner"])
@pytest.mark.parametrize("law, gamma", [("specular", 0.0), ("no-slip", DISK)], ids=["specular", "g0.707"])
def test_flight_exactly_through_a_cell_corner(force, q, v, cell, law, gamma):
    """Dyadic starts reach the corner (1/2, 1/2) of four cells exactly (float64 and mpmath alike).

    Through it, the flight enters the diagonal cell at once and hits its disk; touching it
    at the apex of a parabola, it stays below the face ``y = 1/2`` and hits the disk of cell (1, 0).
    """
    scene = tables.sinai_torus(0.25, law=law, gamma=gamma, force=force)
    ref = simulate_reference(scene, q, v, 0.1, max_collisions=1, dps=DPS)
    assert (int(ref.cell_a1[0]), int(ref.cell_a2[0])) == cell
    flt = simulate(scene, q, v, 0.1, max_collisions=1)
    same_events(ref, flt, "corner")
    for var, dev in largest_deviation(ref, flt, orbit_scales(scene, ref, s_in_cell=True), 1).items():
        assert dev <= TOL, var
    shadow(scene, q, v, 0.1, 10, {})


def _half_root(c):
    return c.sqrt(c.mpf(1) / 2)


@pytest.mark.parametrize("coeffs, d, t_in, t_exit, step", [
    ((0.25, 1.0, 0.0), 0, lambda c: 0, lambda c: c.mpf(1) / 4, 1),     # straight, up through 1/2
    ((-0.75, 1.0, 0.0), 0, lambda c: c.mpf(1) / 4, lambda c: c.mpf(5) / 4, 1),  # entered through -1/2
    ((-0.5, -1.0, 0.0), 0, lambda c: 0, lambda c: 0, -1),               # on the lower face, leaving
    ((0.0, 1.0, -1.0), 0, lambda c: 0, lambda c: (1 + c.sqrt(3)) / 2, -1),  # turns back below 1/2
    ((0.25, 1.0, -1.0), 0, lambda c: 0, lambda c: c.mpf(3) / 2, -1),    # touches 1/2 at t = 1/2
    ((1.0, -2.0, 1.0), 0, lambda c: 1 - _half_root(c), lambda c: 1 + _half_root(c), 1),  # in and out above
    ((0.0, 2.0, -1.0), 1, lambda c: 1 - _half_root(c), lambda c: 1 + _half_root(c), -1),  # in and out below
], ids=["straight", "entered_below", "on_face", "turns_back", "touches", "dips_in_above", "rises_in_below"])
def test_strip_exit_rules(coeffs, d, t_in, t_exit, step):
    """The reference's strip exit: which root is the exit follows from the shape of the coordinate.

    ``alpha(t) = c0 + c1 t + c2 t^2`` in the strip ``[d - 1/2, d + 1/2]`` from ``t_in`` on, the
    entry times exact: the root the flight entered through must never come back as its exit.
    """
    ctx = mpmath.MPContext()
    ctx.dps = DPS
    t, got = reference._strip_exit(ctx, [ctx.mpf(c) for c in coeffs], d, ctx.mpf(t_in(ctx)))
    assert got == step
    assert abs(t - t_exit(ctx)) < 1e-25


def _endless(kind):
    """Flights that never hit anything: along a corridor, with and without a force."""
    if kind == "torus_a1":
        return tables.sinai_torus(0.25), (0.5, 0.45), (1.0, 0.0)  # starts on a face, leaves it
    if kind == "hex_minus_a2":  # down along a2, halfway between two rows of disks
        scene = tables.hex_lorentz_cell(0.3)
        return scene, (0.45, 0.0), tuple(-c for c in scene.lattice["a2"])
    if kind == "galton_fall":  # dropped from rest between two columns of pegs (period 2 a2 - a1)
        return tables.galton_board(radius=0.4), (0.5, 0.3), (0.0, 0.0)
    if kind == "galton_thrown_up":  # thrown up first: the period counts from the turning point
        return tables.galton_board(radius=0.4), (0.5, 0.3), (0.0, 3.0)
    raise KeyError(kind)


ENDLESS = [  # (flight, limits, stop reason)
    ("torus_a1", {}, "escape"),
    ("torus_a1", dict(max_time=750.0), "max_time"),
    ("torus_a1", dict(max_time=1e9), "escape"),  # the limit lies beyond the engine's 10^7 cells
    ("torus_a1", dict(stop_below=0.0), "escape"),  # a level a horizontal flight never crosses
    ("hex_minus_a2", {}, "escape"),
    ("hex_minus_a2", dict(max_time=750.0), "max_time"),
    ("hex_minus_a2", dict(stop_below=-300.0), "stop_below"),
    ("galton_fall", {}, "escape"),
    ("galton_fall", dict(max_time=50.0), "max_time"),
    ("galton_fall", dict(max_time=1e5), "escape"),  # falls 5e9, past 10^7 rows of height sqrt 3
    ("galton_fall", dict(stop_below=-300.0), "stop_below"),
    ("galton_thrown_up", dict(max_time=50.0), "max_time"),
]


@pytest.mark.parametrize("kind, kw, expected", ENDLESS,
                         ids=[f"{k}-{'-'.join(f'{a}={b:g}' for a, b in kw.items()) or 'none'}" for k, kw, _ in ENDLESS])
def test_endless_corridor_stops_as_the_engine(kind, kw, expected):
    scene, q, v = _endless(kind)
    ref = simulate_reference(scene, q, v, 0.1, max_collisions=5, dps=DPS, **kw)
    flt = simulate(scene, q, v, 0.1, max_collisions=5, **kw)
    assert int(ref.n_collisions) == int(flt.n_collisions) == 0
    assert ref.attrs["stop_reason"] == flt.attrs["stop_reason"] == expected
    assert (int(flt.cell_a1_final), int(flt.cell_a2_final)) == (int(ref.cell_a1_final), int(ref.cell_a2_final))
    length = max(scene.scale, abs(float(ref.x_final)), abs(float(ref.y_final)))
    speed = max(1.0, math.hypot(float(ref.vx_final), float(ref.vy_final)))
    for var, scale in (("t", max(1.0, float(ref.t_final))), ("x", length), ("y", length), ("vx", speed),
                       ("vy", speed)):
        assert abs(float(flt[f"{var}_final"]) - float(ref[f"{var}_final"])) <= TOL * scale, var


@pytest.mark.parametrize("slope", [1 / 8, 2.0 ** -10, 1e-3])
def test_flights_off_a_corridor_find_their_hit(slope):
    """Directions near ``a1`` are no endless flights: periodic (1/8: ``P = 8 a1 + a2``) or not, the hit is found.

    Slope ``2^-10`` repeats after ``1024 a1 + a2``, past ``PERIOD_MAX``: it is walked like any
    flight (~300 cells); slope ``1e-3`` is a float whose ratio has no small period at all
    (300 cells: longer flights carry the engine's known error of ``eps x (flight length) / r``
    in the outgoing velocity, tests/test_stress.py).
    """
    scene = tables.sinai_torus(0.25, law="specular")
    q, v = (0.5, 0.45), (1.0, slope)
    ref = simulate_reference(scene, q, v, 0.0, max_collisions=1, dps=DPS)
    flt = simulate(scene, q, v, 0.0, max_collisions=1)
    assert ref.attrs["stop_reason"] == flt.attrs["stop_reason"] == "max_collisions"
    same_events(ref, flt, f"slope {slope}")
    for var, dev in largest_deviation(ref, flt, orbit_scales(scene, ref, s_in_cell=True), 1).items():
        assert dev <= TOL, var



@pytest.mark.parametrize("law, gamma", [("specular", 0.0), ("no-slip", DISK)], ids=["specular", "g0.707"])
def test_exact_hit_on_a_reflex_vertex_reflects_once(law, gamma):
    """The reference at an exact hit on a scatterer's vertex: one reflection, no corner collision.

    The flight along ``y = 1/2`` meets the diamond's vertex (1/4, 1/2) exactly.  Both pieces are
    hit at the same time; the reference takes the lower index (edge 2) and reflects once: the
    table is locally the union of the two pieces' table sides, and the particle, now on edge
    2's, is inside, so edge 3 (whose line it leaves) is no collision (docs/algorithm.md, step 4).
    """
    scene = diamond_cell(law, gamma)
    ref = simulate_reference(scene, (0.0, 0.5), (1.0, 0.0), 0.3, max_collisions=2, dps=DPS)
    assert ref.element.values.tolist()[0] == 2 and ref.corner.values.tolist() == [0, 0]
    assert float(ref.t[0]) == 0.25 and float(ref.t[1]) - float(ref.t[0]) > 0.5
    assert float(ref.vy[0]) < 0  # away from the vertex, below edge 2's end


def test_float_engine_reflects_once_at_a_reflex_vertex():
    """The float64 engine at the same hit: one reflection, no second collision at the vertex.

    Both edges are hit at ``t = 1/4`` to rounding and the engine takes edge 3 (the one rounding
    puts first).  The other edge's crossing root at the vertex is ``t = 0`` exactly, rounded
    to either side; kept, it was a hit a rounding-sized time later inside the edge's end band,
    and the particle reversed (``core/events.py``, ``hit_in_cell``, deflates it instead).
    Leaving the vertex straight up (``v_x = -1.8e-15``), the flight passes the vertices above
    it just outside their end bands and escapes up the corridor between the columns of diamonds
    (the exact flight from that state meets no element for some 10^14 cells, past the cell
    budget of either engine: ``escape``).
    tests/test_reflex_vertex.py checks such hits against the reference, both laws, with and
    without gravity and the thermostat, plain and periodic.
    """
    flt = simulate(diamond_cell("specular", 0.0), (0.0, 0.5), (1.0, 0.0), 0.3, max_collisions=2)
    assert float(flt.t[0]) == 0.25 and int(flt.element[0]) in (2, 3) and int(flt.corner[0]) == 0
    assert flt.sizes["collision"] == 1 and flt.attrs["stop_reason"] == "escape"  # no second hit at the vertex


# ----------------------------------------------------------------------------- (d) reference-only oracles
def explicit_tiling(scene, lo, hi):
    """The plain scene of every element copy over the cells ``lo .. hi`` (inclusive)."""
    (a1x, a1y), (a2x, a2y) = scene.lattice["a1"], scene.lattice["a2"]
    elems, where = [], []
    for i in range(lo[0], hi[0] + 1):
        for j in range(lo[1], hi[1] + 1):
            for e, el in enumerate(scene.elements):
                elems.append(el.shifted(i * a1x + j * a2x, i * a1y + j * a2y))
                where.append((e, i, j))
    return scene.replace(elements=tuple(elems), lattice=None), where


def _dyadic(name):
    """Tables whose lattice shifts are exact in float64 (so an explicit tiling is the same table).

    The hexagonal cell and the Galton board have ``sqrt 3`` in ``a2``: ``3 a2`` rounds, and
    a tiled copy would sit an ulp off its lattice position.  Their dyadic twins keep the
    skewed basis and the force with a row height of 7/8 (hexagonal) and 7/4 (Galton).
    """
    if name == "hex_dyadic":
        return Scene((Circle((0.0, 0.0), 0.3, "outside"),), law="no-slip", gamma=DISK,
                     lattice={"a1": [1.0, 0.0], "a2": [0.5, 0.875]}), (0.4, 0.1), (0.7, 0.31), 0.2
    if name == "galton_dyadic":
        return Scene((Circle((0.0, 0.0), 0.5, "outside"),), law="no-slip", gamma=3.0, force=(0.0, -1.0),
                     lattice={"a1": [2.0, 0.0], "a2": [1.0, 1.75]}), (1.0, 0.0), (0.3, 0.95), 0.2
    law, gamma = {"torus": ("specular", 0.0), "two_disk_cell": ("specular", 0.0),
                  "diamond_cell": ("no-slip", 1.0)}[name]
    scene, q, v, w, _, _ = with_law(name, law, gamma)
    return scene, q, v, w


@pytest.mark.parametrize("name, n", [("torus", 10), ("hex_dyadic", 10), ("galton_dyadic", 6),
                                     ("two_disk_cell", 10), ("diamond_cell", 10)])
def test_lattice_reference_equals_the_explicitly_tiled_reference(name, n):
    """The same table written out copy by copy, run by the plain reference: the same orbit to 1e-25.

    The tiles cover the box of the cells holding the lattice orbit's collisions and one more
    cell on every side: every straight flight between two collisions stays in the box of
    their cells, and no parabola here rises a cell above its start (energy), so a
    collision the lattice walk missed would be found in the plain table.  Elements are
    matched through the copy each plain element is (its element index, and the copy's cell
    for disks).
    """
    scene, q, v, w = _dyadic(name)
    lat = simulate_reference(scene, q, v, w, max_collisions=n, dps=ORACLE_DPS, as_mpf=True)
    cells = np.array([*lat.cells, lat.final_cell])
    assert len(np.unique(cells, axis=0)) >= 3  # the walk crosses cells
    flat_scene, where = explicit_tiling(scene, tuple(cells.min(axis=0) - 1), tuple(cells.max(axis=0) + 1))
    flat = simulate_reference(flat_scene, q, v, w, max_collisions=n, dps=ORACLE_DPS, as_mpf=True)
    assert len(flat) == len(lat) == n and flat.stop_reason == lat.stop_reason
    assert [where[e][0] for e in flat.element] == lat.element
    assert flat.corner == lat.corner
    for k in range(n):
        e, i, j = where[flat.element[k]]
        if isinstance(scene.elements[e], Circle) and scene.elements[e].center == (0.0, 0.0):
            assert (i, j) == lat.cells[k]  # a disk at the cell centre: its copy is the cell's
    with mpmath.workdps(ORACLE_DPS + 10):
        for var in ("t", "x", "y", "vx", "vy", "spin", "s", "energy"):
            for a, b in zip(lat.records[var], flat.records[var]):
                assert abs(mpmath.mpf(a) - mpmath.mpf(b)) <= ORACLE_TOL * max(1, abs(mpmath.mpf(a))), var


def test_translation_by_a_lattice_vector():
    """From a start moved by ``n1 a1 + n2 a2`` the reference orbit is the same one moved (hex lattice)."""
    scene = tables.hex_lorentz_cell(0.3, gamma=DISK)
    n1, n2 = 4096, -2048  # dyadic shift, so the moved start is exact: 4096 a1 - 2048 a2
    (a1x, a1y), (a2x, a2y) = scene.lattice["a1"], scene.lattice["a2"]
    dx, dy = n1 * a1x + n2 * a2x, n1 * a1y + n2 * a2y
    q = (0.375, 0.125)
    assert all(Fraction(c + s) == Fraction(c) + Fraction(s) for c, s in zip(q, (dx, dy)))
    a = simulate_reference(scene, q, (0.7, 0.31), 0.2, max_collisions=8, dps=ORACLE_DPS, as_mpf=True)
    b = simulate_reference(scene, (q[0] + dx, q[1] + dy), (0.7, 0.31), 0.2, max_collisions=8,
                           dps=ORACLE_DPS, as_mpf=True)
    assert a.element == b.element
    assert [(c1 + n1, c2 + n2) for c1, c2 in a.cells] == b.cells
    with mpmath.workdps(ORACLE_DPS + 10):
        shifts = {"x": dx, "y": dy}
        for name in ("t", "x", "y", "vx", "vy", "spin", "s"):
            for u, z in zip(a.records[name], b.records[name]):
                assert abs(mpmath.mpf(u) + shifts.get(name, 0) - mpmath.mpf(z)) <= ORACLE_TOL * 1e4, name


def test_long_corridor_hit_is_the_exact_line_circle_intersection():
    """The first hit of a flight across ~4900 cells is the nearest disk along the line, found by brute force."""
    r, q, v = 0.25, (0.5, 0.26), (1.0, 1e-4)
    orbit = simulate_reference(tables.sinai_torus(r, law="specular"), q, v, 0.0, max_collisions=1,
                               dps=ORACLE_DPS, as_mpf=True)
    # every disk up to a few columns past the reported hit (a later column is reached later,
    # v_x > 0) whose centre lies within r of the line (float64 prefilter with a generous
    # margin), each solved exactly: the earliest entry is the hit
    cols, rows = np.meshgrid(np.arange(0, orbit.cells[0][0] + 5), np.arange(-1, 3))
    dist = np.abs((cols - q[0]) * v[1] - (rows - q[1]) * v[0]) / math.hypot(*v)
    near = list(zip(cols[dist < r + 1e-6].tolist(), rows[dist < r + 1e-6].tolist()))
    with mpmath.workdps(ORACLE_DPS):
        x0, y0, vx, vy = (mpmath.mpf(c) for c in (*q, *v))
        best = None
        for i, j in near:
            dx, dy = x0 - i, y0 - j
            b, c, a = dx * vx + dy * vy, dx * dx + dy * dy - mpmath.mpf(r) ** 2, vx * vx + vy * vy
            disc = b * b - a * c
            if b < 0 and disc > 0:
                t = (-b - mpmath.sqrt(disc)) / a
                if best is None or t < best[0]:
                    best = (t, i, j)
        t, i, j = best
        assert orbit.cells[0] == (i, j) and i > 4000
        assert abs(orbit.records["t"][0] - t) < mpmath.mpf(10) ** -30
        assert abs(orbit.records["x"][0] - (x0 + vx * t)) < mpmath.mpf(10) ** -30


def _outward_normal(scene, element, cell, x, y):
    """Outward unit normal at a collision point, from the element's definition (docs/algorithm.md, step 3).

    Disks sit at their cell's centre, so the copy hit is the cell's; a segment's normal
    does not depend on the copy.
    """
    el = scene.elements[element]
    if isinstance(el, Circle):
        (a1x, a1y), (a2x, a2y) = scene.lattice["a1"], scene.lattice["a2"]
        cx = el.center[0] + cell[0] * mpmath.mpf(a1x) + cell[1] * mpmath.mpf(a2x)
        cy = el.center[1] + cell[0] * mpmath.mpf(a1y) + cell[1] * mpmath.mpf(a2y)
        assert abs(mpmath.hypot(x - cx, y - cy) - el.radius) < mpmath.mpf(10) ** -30  # on that copy
        n = (cx - x, cy - y)  # a scatterer: outward points into it
    else:
        n = (mpmath.mpf(el.p1[1]) - el.p0[1], mpmath.mpf(el.p0[0]) - el.p1[0])  # -J(p1 - p0)
    norm = mpmath.hypot(*n)
    return n[0] / norm, n[1] / norm


@pytest.mark.parametrize("name", ["torus", "galton", "diamond_gravity"])
def test_reference_conserves_energy_and_reverses_the_contact_velocity(name):
    """At every no-slip collision on a copy: ``v_n`` and ``v_t + w / gamma`` reverse, ``|v|^2 + w^2`` is kept."""
    gamma = 0.6
    scene, q, v, w, _, kw = with_law(name, "no-slip", gamma)
    orbit = simulate_reference(scene, q, v, w, max_collisions=12, dps=ORACLE_DPS, as_mpf=True, **kw)
    assert len(orbit) == 12
    rec = orbit.records
    ax, ay = (mpmath.mpf(c) for c in scene.force)
    small = mpmath.mpf(10) ** -30
    with mpmath.workdps(ORACLE_DPS):
        e0 = (mpmath.mpf(v[0]) ** 2 + mpmath.mpf(v[1]) ** 2 + mpmath.mpf(w) ** 2) / 2 \
            - (ax * mpmath.mpf(q[0]) + ay * mpmath.mpf(q[1]))
        for k in range(len(orbit)):
            assert abs(rec["energy"][k] - e0) < small
            n = _outward_normal(scene, orbit.element[k], orbit.cells[k], rec["x"][k], rec["y"][k])
            t = (-n[1], n[0])  # t = J n
            vin, vout = (rec["vx_in"][k], rec["vy_in"][k]), (rec["vx"][k], rec["vy"][k])
            assert vin[0] * n[0] + vin[1] * n[1] > 0  # arriving through the boundary
            assert abs(vout[0] * n[0] + vout[1] * n[1] + vin[0] * n[0] + vin[1] * n[1]) < small
            before = vin[0] * t[0] + vin[1] * t[1] + rec["spin_in"][k] / gamma
            after = vout[0] * t[0] + vout[1] * t[1] + rec["spin"][k] / gamma
            assert abs(after + before) < small


def test_dataset_layout_matches_simulate():
    scene, q, v, w, _, _kw = with_law("two_disk_cell", "no-slip", DISK)
    ref = simulate_reference(scene, q, v, w, max_collisions=5, dps=DPS)
    flt = simulate(scene, q, v, w, max_collisions=5)
    assert set(ref.data_vars) == set(flt.data_vars)
    for name in flt.data_vars:
        assert ref[name].dims == flt[name].dims and ref[name].dtype == flt[name].dtype, name
        assert ref[name].attrs["units"] == flt[name].attrs["units"]


def test_resume_off_the_element_raises():
    scene = tables.sinai_torus(0.25)
    with pytest.raises(ValueError, match="position"):
        resume_reference(scene, (0.25 + 1e-3, 0.0), (1.0, 0.0), 0.0, 0)
    # on the copy of the next cell: accepted, and the orbit is the moved one
    a = resume_reference(scene, (0.25, 0.0), (0.6, 0.8), 0.0, 0, max_collisions=2, dps=DPS)
    b = resume_reference(scene, (3.25, -2.0), (0.6, 0.8), 0.0, 0, max_collisions=2, dps=DPS)
    np.testing.assert_allclose(b.x.values - 3, a.x.values, atol=1e-14)
    np.testing.assert_array_equal(b.cell_a1.values - 3, a.cell_a1.values)


# ----------------------------------------------------------------------------- (e) mutations
def _wrong_step(strip_exit):
    def mutated(ctx, coeffs, d, t_in):
        t, step = strip_exit(ctx, coeffs, d, t_in)
        return t, abs(step)  # a flight leaving through a lower face walks up instead
    return mutated


def _wrong_cell(cell):
    def mutated(self, x, y):
        _n1, n2 = cell(self, x, y)
        alpha, _beta = self.coordinates(x, y)
        return int(self.ctx.floor(alpha)), n2  # cells [n, n + 1) along a1 instead of the nearest site
    return mutated


@pytest.mark.parametrize("mutation", ["step", "cell"])
def test_a_wrong_cell_walk_fails_the_comparison(monkeypatch, mutation):
    """A mutated walk misses or invents collisions, and the per-collision comparison says so.

    A wrong walk may wander forever off the flight's cells, so both runs cap the walk at
    2000 cells (the unmutated reference never comes near it on this orbit: it still passes).
    """
    monkeypatch.setattr(reference, "MAX_CELLS_PER_FLIGHT", 2000)
    scene, q, v, w, budget, kw = with_law("torus", "no-slip", DISK)
    shadow(scene, q, v, w, budget, kw)
    if mutation == "step":
        monkeypatch.setattr(reference, "_strip_exit", _wrong_step(reference._strip_exit))
    else:
        monkeypatch.setattr(reference._Table, "cell", _wrong_cell(reference._Table.cell))
    with pytest.raises(AssertionError):
        shadow(scene, q, v, w, budget, kw)


# ----------------------------------------------------------------------------- stress
@pytest.mark.stress
@pytest.mark.parametrize("law, gamma", LAWS, ids=LAW_IDS)
@pytest.mark.parametrize("name", ["torus", "hex", "galton", "two_disk_cell", "diamond_cell"])
def test_every_collision_agrees_long(name, law, gamma):
    """The per-collision comparison over 300 collisions, from three starts per scene."""
    scene, q, v, w, _, kw = with_law(name, law, gamma)
    for _k, turn in enumerate((0.0, 1.0, 2.2)):
        vel = (v[0] * math.cos(turn) - v[1] * math.sin(turn), v[0] * math.sin(turn) + v[1] * math.cos(turn))
        shadow(scene, q, vel, w, 300, kw)


@pytest.mark.stress
def test_santalo_mean_free_path_of_the_reference():
    """Specular hexagonal cell with a finite horizon (r > sqrt(3)/4): mean free path ``pi |Q| / |dQ|``.

    ``|Q| = sqrt(3)/2 - pi r^2``, ``|dQ| = 2 pi r`` (Santalo); 6000 reference collisions.
    """
    r = 0.45
    scene = tables.hex_lorentz_cell(r, law="specular")
    expected = (math.sqrt(3) / 2 - math.pi * r * r) / (2 * r)
    total, count = 0.0, 0
    for ang in (0.3, 1.1, 2.0):
        ds = simulate_reference(scene, (0.49, 0.01), (math.cos(ang), math.sin(ang)), 0.0,
                                max_collisions=2000, dps=20)
        total += float(ds.t[-1] - ds.t[0])
        count += ds.sizes["collision"] - 1
    assert total / count == pytest.approx(expected, rel=0.03)


@pytest.mark.stress
@pytest.mark.parametrize("slope", [1e-5, -2e-5])
def test_very_long_corridor_hit_is_exact(slope):
    """Flights across 10^4 .. 10^5 cells: the reference's hit against the nearest disk by brute force."""
    r, q, v = 0.1, (0.5, 0.11 if slope > 0 else 0.89), (1.0, slope)
    orbit = simulate_reference(tables.sinai_torus(r, law="specular"), q, v, 0.0, max_collisions=1,
                               dps=ORACLE_DPS, as_mpf=True)
    i, j = orbit.cells[0]
    assert i > 10_000
    with mpmath.workdps(ORACLE_DPS):
        x0, y0, vx, vy = (mpmath.mpf(c) for c in (*q, *v))
        dx, dy = x0 - i, y0 - j
        b, c, a = dx * vx + dy * vy, dx * dx + dy * dy - mpmath.mpf(r) ** 2, vx * vx + vy * vy
        t = (-b - mpmath.sqrt(b * b - a * c)) / a
        assert abs(orbit.records["t"][0] - t) < mpmath.mpf(10) ** -28
        # no disk of an earlier column is met: the line's distance to each exceeds r
        for col in range(0, i):
            for row in (j - 1, j, j + 1):
                ex, ey = x0 - col, y0 - row
                cross = ex * vy - ey * vx
                assert cross * cross >= (mpmath.mpf(r) ** 2) * a or ex * vx + ey * vy >= 0
