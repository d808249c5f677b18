"""The compiled magnetic flight (core/magnetic_flight.py, searched by core/search.py) against the mpmath twin,
and the physics the event loop must keep with it: pinned orbits, energy, time reversal, Santalo's mean free time.

Orbits are chaotic, so twin and kernel are compared collision by collision only as far as rounding has not
grown past the tolerance (a few collisions per case); the stop reasons and counts are compared whole.
"""
import math

import numpy as np
import pytest
from test_magnetic_physics import ISPINNED_CASES, sinai_db

from noslipsim import simulate, simulate_many, tables
from noslipsim._engine.run import run_orbits
from noslipsim._engine.table import kernel_table
from noslipsim.analysis import twin_lyapunov
from noslipsim.core import layout, magnetic_flight, search, variant
from noslipsim.core.batch import F_VARIANT
from noslipsim.core.tolerances import EXTENT_TOL, MAX_CELLS_PER_FLIGHT
from noslipsim.experiments import phase_portrait
from noslipsim.reference import simulate_reference

DPS = 30
GAMMA = 1 / math.sqrt(2)
BOX = tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)])
COLUMNS = ("t", "x", "y", "vx", "vy", "spin")


def _agree(scene, q, v, w, n, *, tol, compare=6):
    """Kernel and twin: the same stop reason and count, and the first ``compare`` collisions within ``tol``."""
    got = simulate(scene, q, v, spin=w, max_collisions=n)
    ref = simulate_reference(scene, q, v, spin=w, max_collisions=n, dps=DPS)
    assert got.attrs["stop_reason"] == ref.attrs["stop_reason"]
    assert int(got.n_collisions) == int(ref.n_collisions)
    k = min(compare, int(got.n_collisions))
    for name in COLUMNS:
        np.testing.assert_allclose(got[name].values[:k], ref[name].values[:k].astype(float), rtol=0, atol=tol,
                                   err_msg=name)
    assert list(got.element.values[:k]) == list(ref.element.values[:k])
    return got


@pytest.mark.parametrize("law", ["specular", "no-slip"])
@pytest.mark.parametrize("W", [1.5, -7.0, 0.3, 1e-9])
def test_box_with_a_disk_against_the_twin(law, W):
    """Lines... here segments and a circle; strong, weak and negative fields; W = 1e-9 is nearly straight."""
    _agree(BOX.replace(magnetic=W, law=law, gamma=GAMMA), (0.3, 0.3), (0.6, 0.8), 0.1, 12, tol=1e-10)


@pytest.mark.parametrize("scene", [
    tables.regular_polygon(5).replace(magnetic=2.0),                      # a convex polygon: its corners
    tables.stadium(1.0, 1.0).replace(magnetic=-1.2, law="no-slip"),       # arcs
    tables.lemon(1.0, 0.5).replace(magnetic=0.8),                         # two arcs meeting at corners
], ids=["pentagon", "stadium", "lemon"])
def test_other_tables_against_the_twin(scene):
    _agree(scene, (0.05, 0.02), (0.6, 0.8), 0.2, 10, tol=1e-9)


@pytest.mark.parametrize("W", [2.0, -0.7])
def test_sinai_torus_against_the_twin(W):
    """A lattice: the walk's faces are closed-form exits of the cyclotron path too."""
    torus = tables.sinai_torus(0.3).replace(magnetic=W)
    _agree(torus, (0.0, 0.45), (1.0, 0.3), 0.0, 12, tol=1e-9)


@pytest.mark.parametrize("scene, r", [(tables.sinai_torus(0.2), 0.2), (tables.hex_lorentz_cell(0.3), 0.3)],
                         ids=["square", "hexagonal"])
def test_box_search_finds_the_walks_hit(scene, r):
    """A closed path over a few cells searches them all (search.box_search); the walk its faces: the same copy,
    the same time to rounding, pinned alike; a box over more than BOX_COPIES copies is left to the walk."""
    table = kernel_table(scene)
    kinds, params, copies, A, B = table.arrays()[:5]
    tol = EXTENT_TOL * table.scale
    box_hit = search.box_search(magnetic_flight)
    walk_hit = search.event_search(magnetic_flight)[1]
    rng = np.random.default_rng(4)
    searched = pinned = 0
    for _ in range(300):
        W = rng.choice([-1, 1]) * 10 ** rng.uniform(-1.5, 1.0)
        x, y = A @ rng.uniform(-0.5, 0.5, 2)  # in the start's cell
        a = rng.uniform(0, 2 * math.pi)
        F = (x, y, math.cos(a), math.sin(a), W)
        if np.hypot(*(np.array([x, y])[:, None] - A @ np.mgrid[-1:2, -1:2].reshape(2, -1))).min() < r + 0.01:
            continue  # in a disk
        period = 2 * math.pi / abs(W)
        got = box_hit(kinds, params, copies, A, B, F, -1, 0, 0, period, tol)
        want = walk_hit(kinds, params, copies, A, B, F, -1, 0, 0, period, tol, MAX_CELLS_PER_FLIGHT)
        if got[4] == 2:  # the box is too large: nothing searched (its cells are at most 2 rho |b_i|_1 + 2 a side)
            sides = 2.0 * 1.001 / abs(W) * np.abs(B).sum(axis=1) + 2.0
            assert sides.prod() * len(copies) > search.BOX_COPIES and got[:4] == (math.inf, -1, 0, 0)
            continue
        searched += 1
        pinned += got[4] == 1
        assert got[1:] == want[1:]
        assert got[0] == pytest.approx(want[0], rel=1e-12)
    assert searched > 60 and 0 < pinned < searched


@pytest.mark.parametrize("W, q", [(2.0, (0.5, 1.5)), (0.1, (0.5, 30.5))], ids=["box search", "walk"])
def test_no_copy_above_a_bounded_lattice_top(W, q):
    """A bounded lattice's copies above its top do not exist for the magnetic search either (it hit them): a
    cyclotron circle above the top row, small (its cells searched at once) or large (walked), is pinned."""
    scene = tables.sinai_torus(0.3).replace(top=0.0, magnetic=W)
    got = simulate(scene, q, (-1.0, 0.0), max_collisions=3)
    assert got.attrs["stop_reason"] == "pinned" and int(got.n_collisions) == 0
    assert simulate_reference(scene, q, (-1.0, 0.0), max_collisions=3, dps=DPS).attrs["stop_reason"] == "pinned"


def test_a_circle_dipping_below_a_bounded_lattice_top_against_the_twin():
    """Its top reaches the missing copy (0, 1), its bottom the real ones of the top row."""
    _agree(tables.sinai_torus(0.3).replace(top=0.0, magnetic=1.5), (0.5, 0.9), (-1.0, 0.0), 0.0, 12, tol=1e-9)


@pytest.mark.parametrize("x, y, phi, omega, pinned", ISPINNED_CASES)
def test_dynamical_billiards_ispinned_cases(x, y, phi, omega, pinned):
    """DynamicalBilliards.jl test/various_tests.jl ``ispinned_tests``, through the compiled loop."""
    orbit = simulate(sinai_db().replace(magnetic=omega), (x, y), (math.cos(phi), math.sin(phi)), max_collisions=3)
    assert (orbit.attrs["stop_reason"] == "pinned") == pinned
    assert int(orbit.n_collisions) == (0 if pinned else 3)


def test_pinned_in_a_plain_table_keeps_the_start():
    scene = tables.rectangle(20.0, 20.0, disks=[(15.0, 15.0, 1.0)]).replace(magnetic=-4.0)
    orbit = simulate(scene, (10.0, 10.0), (0.6, -0.8), spin=0.3, max_collisions=10, max_time=100.0)
    assert orbit.attrs["stop_reason"] == "pinned" and int(orbit.n_collisions) == 0
    assert [float(orbit[k]) for k in ("x_final", "y_final", "vx_final", "vy_final", "spin_final")] == [
        10.0, 10.0, 0.6, -0.8, 0.3]


def test_pinned_after_collisions():
    """An orbit that collides, then turns onto a circle that misses everything: pinned after n > 0."""
    scene = tables.rectangle(4.0, 4.0).replace(magnetic=4.0, law="no-slip", gamma=GAMMA)
    got = simulate(scene, (2.0, 0.3), (0.0, -1.0), spin=0.0, max_collisions=50)
    ref = simulate_reference(scene, (2.0, 0.3), (0.0, -1.0), spin=0.0, max_collisions=50, dps=DPS)
    assert got.attrs["stop_reason"] == ref.attrs["stop_reason"]
    assert int(got.n_collisions) == int(ref.n_collisions)


@pytest.mark.parametrize("law", ["specular", "no-slip"])
def test_energy_is_kept_over_a_long_orbit(law):
    """|v|^2 + w^2 is kept by the flight (speed, spin) and by both laws; the settle keeps rounding from drifting."""
    scene = tables.sinai_torus(0.3).replace(magnetic=1.3, law=law, gamma=GAMMA)
    orbit = simulate(scene, (0.0, 0.45), (0.6, 0.8), spin=0.2, max_collisions=100_000)
    assert int(orbit.n_collisions) == 100_000
    e = orbit.vx.values ** 2 + orbit.vy.values ** 2 + (orbit.spin.values ** 2 if law == "no-slip" else 0.0)
    e0 = 1.0 + (0.04 if law == "no-slip" else 0.0)
    assert np.max(np.abs(e - e0)) < 1e-12


@pytest.mark.parametrize("law", ["specular", "no-slip"])
def test_time_reversal_retraces_the_orbit(law):
    """Stopped in mid-flight and reversed with v, w and W negated, the orbit comes back through the same
    collision points, in reverse order, to its start with the opposite velocity and spin."""
    scene = BOX.replace(magnetic=1.5, law=law, gamma=GAMMA)
    q, v, w, T = (0.3, 0.3), (0.6, 0.8), 0.1, 12.3
    fwd = simulate(scene, q, v, spin=w, max_collisions=1000, max_time=T)
    n = int(fwd.n_collisions)
    assert fwd.attrs["stop_reason"] == "max_time" and n > 8
    back = simulate(scene.replace(magnetic=-1.5), (float(fwd.x_final), float(fwd.y_final)),
                    (-float(fwd.vx_final), -float(fwd.vy_final)), spin=-float(fwd.spin_final),
                    max_collisions=1000, max_time=T)
    assert int(back.n_collisions) == n
    np.testing.assert_allclose(back.x.values, fwd.x.values[::-1], atol=1e-9)
    np.testing.assert_allclose(back.y.values, fwd.y.values[::-1], atol=1e-9)
    np.testing.assert_allclose([float(back[k]) for k in ("x_final", "y_final", "vx_final", "vy_final", "spin_final")],
                               [*q, -v[0], -v[1], -w], atol=1e-9)


def test_weak_field_mean_free_time_is_santalo():
    """Every orbit collides (a Sinai torus of finite horizon, r > sqrt(2)/4): the mean free time of the specular law
    (Liouville measure) is pi |Q| / |dQ| at speed 1.  Averaged over 64 orbits, within four standard errors of their
    spread, which must be below 0.3 %.  An orbit's mean varies by about 0.0024 (20 seeds of 16 orbits, two
    builds: 0.0015 to 0.0036), so 16 orbits met that bound on 3 seeds of 20; a last-bit change failed it."""
    scene = tables.sinai_torus(0.4).replace(magnetic=0.05, law="specular")
    n = 64
    angles = np.random.default_rng(3).uniform(0.0, 2 * math.pi, n)
    ds = simulate_many(scene, np.tile((0.5, 0.02), (n, 1)), np.column_stack([np.cos(angles), np.sin(angles)]),
                       max_collisions=50_000, scheduler="sync", progress=False)
    assert (ds.n_collisions.values == 50_000).all()
    means = ds.t_final.values / ds.n_collisions.values
    santalo = math.pi * (1.0 - math.pi * 0.4 ** 2) / (2 * math.pi * 0.4)
    assert abs(means.mean() - santalo) < 4 * means.std(ddof=1) / math.sqrt(n) < 0.003 * santalo


def test_a_magnetic_scene_runs_the_magnetic_variant_and_nothing_else():
    table = kernel_table(BOX.replace(magnetic=1.5))
    flags = table.variant(layout.RECORD_NONE)
    assert flags.flight == variant.MAGNETIC
    final = run_orbits(table, [(0.3, 0.3, 0.6, 0.8, 0.0)], max_collisions=3)
    assert "flight=magnetic" in variant.describe(int(final[0, F_VARIANT]))
    assert kernel_table(BOX).variant(0).flight == variant.STRAIGHT


def test_simulate_many_and_a_portrait_run_a_field():
    scene = BOX.replace(magnetic=1.5, law="no-slip", gamma=GAMMA)
    ds = simulate_many(scene, [(0.3, 0.3), (0.5, 0.7)], [(0.6, 0.8), (-1.0, 0.0)], max_collisions=20,
                       scheduler="sync", progress=False)
    assert (ds.n_collisions.values == 20).all()
    portrait = phase_portrait(scene, n_orbits=4, n_collisions=30, scheduler="sync", progress=False)
    assert portrait.sizes and np.isfinite(portrait.to_array()).any()


def test_twin_lyapunov_of_a_magnetic_sinai_torus_is_positive():
    """Twin orbits need only the flight: a weak field on a dispersing torus keeps it chaotic."""
    torus = tables.sinai_torus(0.3).replace(magnetic=0.5)
    lam = twin_lyapunov(torus, [(0.0, 0.45)], [(0.6, 0.8)], n_collisions=2000)
    value = float(np.asarray(lam).ravel()[0])
    assert 0.1 < value < 5.0
