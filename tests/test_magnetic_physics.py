"""Physics of magnetic billiards in the reference twin (docs/scenes.md, "Magnetic field").

Pinned cyclotron circles, energy through collisions, time reversal (both laws), W -> 0, Santalo's mean
free time, and DynamicalBilliards.jl's published magnetic examples (pinned particles, the magnetic stadium).
"""
import math

import mpmath
import numpy as np
import pytest
from test_magnetic_kernels import arc_exit, segment_exit

from noslipsim import Arc, Circle, Scene, Segment, tables
from noslipsim.core import magnetic as mg
from noslipsim.reference import resume_reference, simulate_reference

DPS = 30


# ---------------------------------------------------------------------------- pinned orbits
def test_a_circle_in_an_empty_region_is_pinned_about_its_exact_centre():
    scene = tables.rectangle(20.0, 20.0, disks=[(15.0, 15.0, 1.0)]).replace(magnetic=-4.0)
    q, v = (10.0, 10.0), (0.6, -0.8)
    orbit = simulate_reference(scene, q, v, 0.3, max_collisions=10, max_time=100.0, dps=DPS, as_mpf=True)
    assert orbit.stop_reason == "pinned" and len(orbit) == 0
    # the final state is the start (nothing happens), the path its cyclotron circle
    assert [float(orbit.final[k]) for k in ("x", "y", "vx", "vy", "spin")] == [*q, *v, 0.3]
    W = scene.magnetic
    centre, radius = (q[0] - v[1] / W, q[1] + v[0] / W), math.hypot(*v) / abs(W)
    assert centre == (9.8, 9.85) and radius == 0.25
    t = np.linspace(0.0, 2 * math.pi / abs(W), 41)
    x, y, vx, vy = scene.flight_states(q[0], q[1], v[0], v[1], t)
    np.testing.assert_allclose(np.hypot(x - centre[0], y - centre[1]), radius, rtol=0, atol=4e-15)
    np.testing.assert_allclose(np.hypot(vx, vy), 1.0, rtol=4e-16)
    # clockwise for W < 0: a quarter period turns the velocity by -pi/2
    _, _, vx, vy = scene.flight_states(q[0], q[1], v[0], v[1], math.pi / 2 / abs(W))
    assert (float(vx), float(vy)) == pytest.approx((v[1], -v[0]), abs=1e-15)


def test_pinned_on_a_lattice_after_a_finite_walk():
    """A circle in the corridor of a Sinai torus, crossing cell faces but no disk: pinned, not an endless walk."""
    torus = tables.sinai_torus(0.2).replace(magnetic=1 / 0.35)
    orbit = simulate_reference(torus, (0.5, 0.15), (1.0, 0.0), max_collisions=5, dps=DPS, as_mpf=True)
    assert orbit.stop_reason == "pinned" and len(orbit) == 0  # centre (0.5, 0.5), radius 0.35 meets no disk
    orbit = simulate_reference(torus.replace(magnetic=1 / 0.55), (0.5, -0.05), (1.0, 0.0), max_collisions=5,
                               dps=DPS, as_mpf=True)
    assert orbit.stop_reason == "max_collisions"              # radius 0.55 about (0.5, 0.5): meets the disks


def sinai_db(radius=0.25):
    """DynamicalBilliards' ``billiard_sinai(setting="periodic")``: unit square, disk at its centre."""
    return Scene((Circle((0.5, 0.5), radius, "outside"),), law="specular", gamma=0.0,
                 lattice={"a1": [1.0, 0.0], "a2": [0.0, 1.0]})


#: DynamicalBilliards.jl test/various_tests.jl ``ispinned_tests``: MagneticParticle(x, y, phi, omega), pinned?
ISPINNED_CASES = [
    (0.2, 0.5, -math.pi / 2, 1 / 0.3, True),    # circles the disk at its own centre
    (0.1, 0.5, -math.pi / 2, 1 / 0.05, True),   # a small circle inside one cell
    (0.0, 1.0, -math.pi / 2, 0.44 * 2, True),   # crosses cell faces, meets no disk
    (0.2, 0.8, -math.pi / 2, 1 / 0.3, False),
]


@pytest.mark.parametrize("x, y, phi, omega, pinned", ISPINNED_CASES)
def test_dynamical_billiards_ispinned_cases(x, y, phi, omega, pinned):
    """DynamicalBilliards.jl test/various_tests.jl ``ispinned_tests``: MagneticParticle(x, y, phi, omega)."""
    orbit = simulate_reference(sinai_db().replace(magnetic=omega), (x, y), (math.cos(phi), math.sin(phi)),
                               max_collisions=3, dps=DPS, as_mpf=True)
    assert (orbit.stop_reason == "pinned") == pinned
    assert len(orbit) == (0 if pinned else 3)


# ---------------------------------------------------------------------------- conservation, reversal, limits
@pytest.mark.parametrize("law", ["no-slip", "specular"])
def test_kinetic_energy_is_kept_through_collisions(law):
    scene = tables.stadium(1.0, 0.5, law=law).replace(magnetic=1.3)
    orbit = simulate_reference(scene, (0.1, 0.2), (0.9, 0.5), 0.7, max_collisions=200, dps=40, as_mpf=True)
    assert orbit.stop_reason == "max_collisions"
    with mpmath.workdps(40):
        e0 = mpmath.mpf(0.9) ** 2 + mpmath.mpf(0.5) ** 2 + mpmath.mpf(0.7) ** 2
        r = orbit.records
        worst = max(abs(vx * vx + vy * vy + w * w - e0) for vx, vy, w in zip(r["vx"], r["vy"], r["spin"]))
        assert worst < mpmath.mpf(10) ** -35


def reversed_orbit(scene, fwd, flip_spin):
    """From the last collision of ``fwd``, reversed: ``-W``, the reversed state just before it, pushed through it.

    By reversibility the law maps the reversed post-collision state ``(-v, -w)`` to ``(-v_in, -w_in)``:
    the reversed orbit starts on that element with it (``flip_spin=False`` keeps ``w_in`` instead).
    """
    r = fwd.records
    spin = -float(r["spin_in"][-1]) if flip_spin else float(r["spin_in"][-1])
    return resume_reference(scene.replace(magnetic=-scene.magnetic), (float(r["x"][-1]), float(r["y"][-1])),
                            (-float(r["vx_in"][-1]), -float(r["vy_in"][-1])), spin,
                            fwd.element[-1], max_collisions=len(fwd) - 1, dps=50, as_mpf=True)


@pytest.mark.parametrize("law", ["no-slip", "specular"])
def test_time_reversal_retraces_the_orbit(law):
    """(x, v, w, W) -> (x, -v, -w, -W) reverses the flow; the orbit retraces its collisions backwards.

    Flight: if x(t) solves dv/dt = W J v, then x(T - s) with velocity -v(T - s) solves it with -W.
    No-slip: the law acts on (w, v_t) by M = [[-c, -s], [-s, c]], an involution (M^2 = I), and on v_n by
    -1.  Reversal needs R M R = M^-1 = M; R = -I (flip v and w) does it, while flipping v alone
    (R = diag(1, -1) on (w, v_t)) gives R M R = [[-c, s], [s, c]] != M whenever s != 0 (gamma > 0).
    The specular law leaves w alone, so either reversal of w retraces it.  The reversed run starts from
    the float64 rounding of the state: chaos lets that grow over the collisions, hence ``atol``.
    """
    scene = tables.rectangle(2.0, 1.0, disks=[(1.3, 0.45, 0.25)], law=law).replace(magnetic=0.8)
    fwd = simulate_reference(scene, (0.3, 0.3), (0.7, 0.55), 0.4, max_collisions=10, dps=50, as_mpf=True)
    n = len(fwd)
    back = reversed_orbit(scene, fwd, flip_spin=True)
    assert len(back) == n - 1
    f, b = fwd.records, back.records
    for j in range(n - 1):
        k = n - 2 - j  # backward collision j is forward collision k
        assert back.element[j] == fwd.element[k]
        pairs = [("x", "x", 1), ("y", "y", 1), ("vx", "vx_in", -1), ("vy", "vy_in", -1), ("spin", "spin_in", -1),
                 ("vx_in", "vx", -1), ("vy_in", "vy", -1), ("spin_in", "spin", -1)]
        for bv, fv, sign in pairs:
            assert abs(b[bv][j] - sign * f[fv][k]) < 1e-9, (j, bv)
    wrong = reversed_orbit(scene, fwd, flip_spin=False)  # the spin kept: the first flight is the same (spin-free) ...
    assert abs(wrong.records["x"][0] - f["x"][n - 2]) < 1e-9
    gap = abs(wrong.records["vx"][0] + f["vx_in"][n - 2]) + abs(wrong.records["vy"][0] + f["vy_in"][n - 2])
    if law == "no-slip":  # ... but the no-slip law does not undo the collision
        assert gap > 1e-3
    else:
        assert gap < 1e-9


@pytest.mark.parametrize("law", ["no-slip", "specular"])
def test_weak_field_is_the_straight_orbit(law):
    scene = tables.rectangle(2.0, 1.0, law=law)
    start = ((0.3, 0.4), (0.71, 0.53), 0.2)
    straight = simulate_reference(scene, *start, max_collisions=20, dps=50)
    weak = simulate_reference(scene.replace(magnetic=1e-15), *start, max_collisions=20, dps=50)
    assert weak.attrs["stop_reason"] == straight.attrs["stop_reason"] == "max_collisions"
    np.testing.assert_array_equal(weak.element.values, straight.element.values)
    for var in ("t", "x", "y", "vx", "vy", "spin"):
        np.testing.assert_allclose(weak[var].values, straight[var].values, rtol=0, atol=1e-12)


# ---------------------------------------------------------------------------- Santalo: the mean free time
def stadium_parts(length, radius):
    """The elements of ``tables.stadium(length, radius)`` as the float kernels take them, with their lengths."""
    scene = tables.stadium(length, radius, law="specular")
    parts = []
    for e in scene.elements:
        if isinstance(e, Segment):
            (x0, y0), (x1, y1) = e.p0, e.p1
            L = math.hypot(x1 - x0, y1 - y0)
            ux, uy = (x1 - x0) / L, (y1 - y0) / L
            parts.append(("segment", (x0, y0, uy, -ux, ux, uy, L), L))  # table on the left: outward n = -J u
        else:
            assert isinstance(e, Arc) and e.side == "inside"
            parts.append(("arc", (*e.center, e.radius, -1.0, e.theta0, e.theta1 - e.theta0), e.length()))
    return scene, parts


def first_flight(parts, k, x, y, vx, vy, W, tol):
    """The free time from a point on part ``k`` to the next collision (the float kernels, plain Python)."""
    best = math.inf
    for j, (kind, p, _) in enumerate(parts):
        exit_ = segment_exit if kind == "segment" else arc_exit
        best = min(best, exit_(x, y, vx, vy, W, *p, tol, j == k))
    return best


def boundary_sample(parts, rng):
    """A point on the boundary and a unit velocity into the table, from the invariant measure cos(phi) ds dphi."""
    lengths = np.array([p[2] for p in parts])
    k = int(rng.choice(len(parts), p=lengths / lengths.sum()))
    kind, p, L = parts[k]
    u = rng.uniform(0, L)
    if kind == "segment":
        x0, y0, nx, ny, ux, uy, _ = p
        x, y = x0 + u * ux, y0 + u * uy
        nin = (-nx, -ny)
    else:
        cx, cy, r, _, theta0, _ = p
        a = theta0 + u / r
        x, y = cx + r * math.cos(a), cy + r * math.sin(a)
        nin = (-math.cos(a), -math.sin(a))
    phi = math.asin(rng.uniform(-1, 1))  # density cos(phi)/2 on (-pi/2, pi/2)
    tx, ty = -nin[1], nin[0]
    return k, x, y, math.cos(phi) * nin[0] + math.sin(phi) * tx, math.cos(phi) * nin[1] + math.sin(phi) * ty


def test_santalo_mean_free_time_of_a_magnetic_stadium():
    """<tau> over the invariant boundary measure is pi |Q| / |dQ| for any flow that keeps phase volume and
    brings every orbit to the boundary: a field with 2 c/|W| wider than the stadium (W = 1, width 1)."""
    length, radius, W = 1.0, 0.5, 1.0
    _, parts = stadium_parts(length, radius)
    area, perimeter = 2 * radius * length + math.pi * radius ** 2, 2 * length + 2 * math.pi * radius
    santalo = math.pi * area / perimeter
    rng = np.random.default_rng(7)
    taus = np.array([first_flight(parts, *boundary_sample(parts, rng), W, 1e-12) for _ in range(20000)])
    assert np.isfinite(taus).all()
    err = taus.std() / math.sqrt(len(taus))
    assert abs(taus.mean() - santalo) < 4 * err, (taus.mean(), santalo, err)
    assert err < 0.006 * santalo
    # the straight stadium has the same mean: the field changes the flights, not Santalo's number
    straight = np.array([first_flight(parts, *boundary_sample(parts, rng), 0.0, 1e-12) for _ in range(20000)])
    assert abs(straight.mean() - santalo) < 4 * straight.std() / math.sqrt(len(straight))
    assert abs(np.median(taus) - np.median(straight)) > 0.01  # and the flights do differ


def test_santalo_in_the_reference_twin():
    """The same mean from the twin: 300 boundary starts, each resumed for one collision at 20 digits."""
    length, radius, W = 1.0, 0.5, 1.0
    scene, parts = stadium_parts(length, radius)
    scene = scene.replace(magnetic=W)
    santalo = math.pi * (2 * radius * length + math.pi * radius ** 2) / (2 * length + 2 * math.pi * radius)
    rng = np.random.default_rng(8)
    taus = []
    for _ in range(300):
        k, x, y, vx, vy = boundary_sample(parts, rng)
        one = resume_reference(scene, (x, y), (vx, vy), 0.0, k, max_collisions=1, dps=20)
        taus.append(float(one.t[0]))
        assert one.t[0] == pytest.approx(first_flight(parts, k, x, y, vx, vy, W, 1e-12), rel=1e-9)
    taus = np.array(taus)
    assert abs(taus.mean() - santalo) < 4 * taus.std() / math.sqrt(len(taus))


def orbit_times(parts, W, x, y, vx, vy, n, tol=1e-12):
    """The collision times of a specular magnetic orbit from an interior start (the float kernels, plain Python)."""
    times, t, k = [], 0.0, -1
    for _ in range(n):
        best, hit = math.inf, -1
        for j, (kind, p, _) in enumerate(parts):
            exit_ = segment_exit if kind == "segment" else arc_exit
            tj = exit_(x, y, vx, vy, W, *p, tol, j == k)  # the element just hit: its t = 0 root deflated
            if tj < best:
                best, hit = tj, j
        x, y, vx, vy = mg.advance(x, y, vx, vy, W, best)
        t += best
        times.append(t)
        kind, p, _ = parts[hit]
        if kind == "segment":
            nx, ny = p[2], p[3]
        else:  # a container arc: outward along the radius
            r = math.hypot(x - p[0], y - p[1])
            nx, ny = (x - p[0]) / r, (y - p[1]) / r
        vn = vx * nx + vy * ny
        vx, vy, k = vx - 2 * vn * nx, vy - 2 * vn * ny, hit
    return np.array(times)


def test_dynamical_billiards_magnetic_stadium_mean_collision_time():
    """DynamicalBilliards.jl test/various_tests.jl ``meancoltest``: billiard_stadium(l = 1, w = 1) and
    MagneticParticle(0.1, 0.1, 0.1, 1.0) (unit speed, heading 0.1, omega = 1): the orbit's mean collision time
    is pi (w l + pi (w/2)^2) / (2 l + pi w) to 10 % over 1e6 collisions.  Here 1e5 collisions of the float
    kernels in a plain-Python loop (the twin needs about 3 ms a collision) agree to 2 %; its first
    collisions are the reference twin's."""
    _, parts = stadium_parts(1.0, 0.5)
    start = (0.1, 0.1, math.cos(0.1), math.sin(0.1))
    times = orbit_times(parts, 1.0, *start, 100_000)
    expected = math.pi * (1.0 + math.pi / 4) / (2.0 + math.pi)
    assert times[-1] / len(times) == pytest.approx(expected, rel=0.02)
    scene = tables.stadium(1.0, 0.5, law="specular").replace(magnetic=1.0)
    ref = simulate_reference(scene, start[:2], start[2:], max_collisions=12, dps=30)
    np.testing.assert_allclose(times[:12], ref.t.values, rtol=1e-9)


def test_lattice_walk_finds_the_first_disk_of_the_whole_circle():
    """The twin's cell walk (one period of faces) against every disk copy within the cyclotron circle's reach,
    each solved by the float kernel: the same first hit, or pinned when none is met."""
    rng = np.random.default_rng(9)
    r = 0.2
    pinned = 0
    for _ in range(40):
        W = rng.choice([-1, 1]) * 10 ** rng.uniform(-1.3, 1.0)
        x, y = rng.uniform(-0.5, 0.5, 2)
        if math.hypot(x, y) < r + 0.01:
            continue
        a = rng.uniform(0, 2 * math.pi)
        vx, vy = math.cos(a), math.sin(a)
        orbit = simulate_reference(tables.sinai_torus(r).replace(magnetic=W), (x, y), (vx, vy),
                                   max_collisions=1, dps=DPS)
        mx, my, rho = mg.centre(x, y, vx, vy, W)
        reach = math.ceil(rho + r) + 1
        best = min(mg.circle_exit(x, y, vx, vy, W, float(i), float(j), r, 1.0, False)
                   for i in range(int(mx) - reach, int(mx) + reach + 1)
                   for j in range(int(my) - reach, int(my) + reach + 1))
        if best == math.inf:
            pinned += 1
            assert orbit.attrs["stop_reason"] == "pinned"
        else:
            assert orbit.attrs["stop_reason"] == "max_collisions"
            assert float(orbit.t[0]) == pytest.approx(best, rel=1e-10)
    assert 0 < pinned < 30


def test_level_and_time_limit_on_a_cyclotron_circle():
    """The circle about (10, 9) of radius 1 from its top, (-1, 0) at W = 1: y = 9 + cos t."""
    scene = tables.rectangle(20.0, 20.0).replace(magnetic=1.0)
    orbit = simulate_reference(scene, (10.0, 10.0), (-1.0, 0.0), stop_below=8.5, dps=DPS, as_mpf=True)
    assert orbit.stop_reason == "stop_below" and float(orbit.final["y"]) == 8.5
    assert float(orbit.final["t"]) == pytest.approx(2 * math.pi / 3, rel=1e-15)
    assert float(orbit.final["x"]) == pytest.approx(10.0 - math.sin(2 * math.pi / 3), rel=1e-15)
    assert simulate_reference(scene, (10.0, 10.0), (-1.0, 0.0), stop_below=7.9, dps=DPS).attrs["stop_reason"] \
        == "pinned"
    orbit = simulate_reference(scene, (10.0, 10.0), (-1.0, 0.0), max_time=1.0, dps=DPS, as_mpf=True)
    assert orbit.stop_reason == "pinned"  # like an escape: the orbit's fate is known, whatever the limit
    # from (10, 1.5) the circle about (10, 0.5) meets the floor at t = 2 pi / 3: the limit t = 1 comes first
    orbit = simulate_reference(scene, (10.0, 1.5), (-1.0, 0.0), max_time=1.0, dps=DPS, as_mpf=True)
    assert orbit.stop_reason == "max_time"
    assert [float(orbit.final[k]) for k in ("x", "y")] == pytest.approx([10.0 - math.sin(1.0), 0.5 + math.cos(1.0)],
                                                                       rel=1e-15)
    orbit = simulate_reference(scene, (10.0, 1.5), (-1.0, 0.0), max_collisions=1, dps=DPS, as_mpf=True)
    assert float(orbit.records["t"][0]) == pytest.approx(2 * math.pi / 3, rel=1e-15)
