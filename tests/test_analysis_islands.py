"""Regular share of a phase space (noslipsim.analysis.islands): invariant starts, exponents, onset.

Oracles: the billiard map preserves the measure the starts are drawn from (uniform before,
uniform after a few collisions; the hemisphere-uniform starts of initial.boundary_states are
not, and the same test tells them apart); the head-on 2-periodic orbit between neighbouring
disks of the torus has the exponent ln|lambda|/2 per collision of the two-disk closed form, and
turns elliptic exactly at head_on_onset_gamma; a linear share crosses a level where algebra says.
"""
import math

import numpy as np
import pytest
from scipy import stats

from noslipsim import Circle, Scene, initial, simulate, simulate_many, tables, theory
from noslipsim.analysis import islands
from noslipsim.analysis.portraits import birkhoff_coordinates, reduced_portrait

#: Significance of the uniformity tests (fixed seeds: a failure is a real deviation).
ALPHA = 1e-3


def first_collision_coordinates(scene, states, n_steps):
    """Reduced (or Birkhoff) coordinates after ``n_steps`` collisions from boundary starts."""
    rec = simulate_many(scene, states["positions"], states["velocities"], states["spins"],
                        start_elements=states["start_elements"], max_collisions=n_steps, record="portrait",
                        scheduler="sync")
    coords = (birkhoff_coordinates if scene.law == "specular" else reduced_portrait)(rec, scene)
    return coords.isel(point=n_steps - 1), coords.attrs["boundary_length"]


@pytest.mark.parametrize("n_steps", [1, 4])
def test_noslip_starts_are_uniform_in_ds_dvt_dw_and_the_map_keeps_them_so(n_steps):
    scene = tables.sinai_torus(0.3, gamma=0.7)
    n = 4000
    st = islands.uniform_reduced_states(scene, n, seed=5)
    L = 2 * math.pi * 0.3
    for s, vt, w in ((st["s_boundary"], st["vt_unit"], st["w_unit"]),
                     tuple(first_collision_coordinates(scene, st, n_steps)[0][k].values
                           for k in ("s_boundary", "vt_unit", "w_unit"))):
        assert stats.kstest(s / L, "uniform").pvalue > ALPHA
        assert stats.kstest(vt * vt + w * w, "uniform").pvalue > ALPHA      # r^2 uniform: the disk's area
        assert stats.kstest(np.arctan2(w, vt) / (2 * math.pi) + 0.5, "uniform").pvalue > ALPHA
    # the hemisphere-uniform starts (area on S^2_+) are not uniform on the disk, nor is their image after
    # one collision: the test can fail (the torus mixes them to uniform within a few collisions)
    hemi = initial.boundary_states(scene, n, seed=5)
    after, _ = first_collision_coordinates(scene, hemi, 1)
    r2 = after.vt_unit.values ** 2 + after.w_unit.values ** 2
    assert stats.kstest(r2, "uniform").pvalue < 1e-6


def test_specular_starts_are_uniform_in_ds_dp_and_the_lemon_keeps_them_so():
    scene = tables.lemon(1.0, 0.6)
    st = islands.uniform_reduced_states(scene, 4000, seed=6)
    assert np.all(st["spins"] == 0.0) and "sin_angle" in st
    after, L = first_collision_coordinates(scene, st, 3)
    for s, p in ((st["s_boundary"], st["sin_angle"]), (after.s_boundary.values, after.sin_angle.values)):
        assert stats.kstest(s / L, "uniform").pvalue > ALPHA
        assert stats.kstest((p + 1) / 2, "uniform").pvalue > ALPHA


def test_the_same_seed_gives_the_same_scaled_starts_on_any_table():
    a = islands.uniform_reduced_states(tables.sinai_torus(0.2), 50, seed=3)
    b = islands.uniform_reduced_states(tables.sinai_torus(0.4, gamma=1.0), 50, seed=3)
    assert np.allclose(a["s_boundary"] / 0.2, b["s_boundary"] / 0.4)
    assert np.array_equal(a["vt_unit"], b["vt_unit"]) and np.array_equal(a["w_unit"], b["w_unit"])
    speed = np.hypot(np.hypot(*a["velocities"].T), a["spins"])
    assert np.allclose(speed, 1.0, atol=1e-12)


@pytest.mark.parametrize("force", [(0.0, 0.0), (0.0, -1.0)])
def test_interior_starts_lie_on_the_orbit_of_the_boundary_starts(force):
    a = np.pi / 6 + np.pi / 3 * np.arange(6)                     # a hexagon with a disk (element 6)
    scene = tables.polygon(np.c_[np.cos(a), np.sin(a)] / math.sqrt(3), disks=[(0.0, 0.0, 0.3)], force=force)
    st = islands.uniform_reduced_states(scene, 20, seed=1, elements=[6])
    inner = islands.interior_starts(scene, st)
    assert (scene.depth(inner["positions"]) > 0).all()
    ref = simulate_many(scene, st["positions"], st["velocities"], st["spins"], start_elements=st["start_elements"],
                        max_collisions=3, record="final", scheduler="sync")
    for i in range(20):
        o = simulate(scene, inner["positions"][i], inner["velocities"][i], inner["spins"][i], max_collisions=3)
        assert np.allclose([o.x_final, o.y_final, o.vx_final, o.vy_final, o.spin_final],
                           [ref[k].values[i] for k in ("x_final", "y_final", "vx_final", "vy_final", "spin_final")],
                           atol=1e-10)
        # the interior start is half a flight after the boundary start
        assert math.isclose(float(o.t[0]), inner["first_flight"][i] / 2, rel_tol=1e-9)


def test_interior_starts_refuse_an_escaping_start():
    scene = tables.two_disks(0.3)
    st = {"positions": np.array([[-1 + 0.3, 0.0]]), "velocities": np.array([[0.0, 1.0]]), "spins": np.zeros(1),
          "start_elements": np.array([0])}
    with pytest.raises(ValueError, match="first flight"):
        islands.interior_starts(scene, st)


def head_on(gamma, radius=0.3):
    """The head-on 2-periodic orbit between the disks at (0, 0) and (1, 0) of the unit torus."""
    return tables.sinai_torus(radius, gamma=gamma), (0.5, 0.0), (1.0, 0.0), 0.0


@pytest.mark.parametrize("gamma", [0.0, 0.3, 0.6])
def test_exponent_of_the_hyperbolic_head_on_orbit_is_the_closed_form(gamma):
    R = 0.3
    scene, q, v, w = head_on(gamma, R)
    trace = float(theory.two_disk_eigen_sum(1 / R, 1 - 2 * R, 0.0, gamma))   # lambda + 1/lambda
    lam = (trace + math.sqrt(trace * trace - 4)) / 2
    expected = math.log(lam) / 2                                             # per collision
    got = islands.finite_time_lyapunov(scene, [q], [v], [w], n_collisions=4000)[0]
    assert got == pytest.approx(expected, rel=1e-3)   # measured 3e-4: the O(1/N) start-up transient


def test_head_on_onset_is_where_the_orbit_turns_parabolic_and_separates_the_exponents():
    R = 0.3
    g0 = islands.head_on_onset_gamma(R)
    assert g0 == pytest.approx(math.sqrt(1 / (2 * R) - 1), rel=1e-14)
    assert float(theory.two_disk_eigen_sum(1 / R, 1 - 2 * R, 0.0, g0)) == pytest.approx(2.0, abs=1e-12)
    assert float(theory.ellipticity_threshold(0.0, g0)) == pytest.approx((1 - 2 * R) / R, rel=1e-12)
    assert islands.head_on_onset_gamma(0.25, distance=2.0) == pytest.approx(math.sqrt(3.0))
    # a slightly perturbed head-on orbit: chaotic below the onset, on an island above it
    for g, regular in ((g0 - 0.1, False), (g0 + 0.1, True)):
        scene = tables.sinai_torus(R, gamma=g)
        lam = islands.finite_time_lyapunov(scene, [(0.5, 0.001)], [(1.0, 0.001)], [0.001], n_collisions=2000)[0]
        assert (lam < islands.REGULAR_THRESHOLD) == regular, (g, lam)
    for bad in (0.0, 0.5, -1.0, math.nan):
        with pytest.raises(ValueError, match="radius"):
            islands.head_on_onset_gamma(bad)


def test_regular_share_of_the_sinai_torus_is_zero_at_gamma_0_and_large_at_gamma_1():
    shares = []
    for g in (0.0, 1.0):
        scene = tables.sinai_torus(0.45, gamma=g)
        st = islands.interior_starts(scene, islands.uniform_reduced_states(scene, 120, seed=2))
        lam = islands.finite_time_lyapunov(scene, st["positions"], st["velocities"], st["spins"], n_collisions=500)
        assert np.isfinite(lam).all()
        shares.append(islands.regular_share(lam)[0])
    assert shares[0] == 0.0 and shares[1] > 0.2


def test_exponents_do_not_depend_on_threads_and_mark_corners_nan():
    scene = tables.sinai_torus(0.45, gamma=1.0)
    st = islands.interior_starts(scene, islands.uniform_reduced_states(scene, 8, seed=4))
    one = islands.finite_time_lyapunov(scene, st["positions"], st["velocities"], st["spins"], n_collisions=200)
    two = islands.finite_time_lyapunov(scene, st["positions"], st["velocities"], st["spins"], n_collisions=200,
                                       num_workers=2)
    assert np.array_equal(one, two)
    square = tables.rectangle(1.0, 1.0)
    lam = islands.finite_time_lyapunov(square, [(0.5, 0.5)], [(1.0, 1.0)], n_collisions=50)  # into a corner
    assert np.isnan(lam[0])
    with pytest.raises(ValueError, match="n_collisions"):
        islands.finite_time_lyapunov(scene, st["positions"], st["velocities"], st["spins"], n_collisions=5)
    with pytest.raises(ValueError, match="shapes"):
        islands.finite_time_lyapunov(scene, st["positions"], st["velocities"][:3], st["spins"])


def test_regular_share_counts_and_errors():
    p, err, n = islands.regular_share([0.001, 0.5, np.nan, 0.01, 2.0], threshold=0.03)
    assert (p, n) == (0.5, 4) and err == pytest.approx(0.25)
    p, err, n = islands.regular_share(np.array([[0.0, 1.0], [1.0, 1.0]]))
    assert p.tolist() == [0.5, 0.0] and n.tolist() == [2, 2]
    assert math.isnan(islands.regular_share([np.nan])[0])
    for bad in (0.0, -1.0, math.inf):
        with pytest.raises(ValueError, match="threshold"):
            islands.regular_share([0.1], threshold=bad)


def test_onset_of_a_linear_share_is_where_it_crosses_the_level():
    g = np.linspace(0.0, 1.0, 11)
    n = 10**6
    share = np.clip(0.5 * (g - 0.3), 0.0, None)                  # linear between grid points, 0.01 at 0.32
    res = islands.onset_gamma(g, np.rint(share * n).astype(int), n, level=0.01)
    assert res["value"] == pytest.approx(0.32, abs=1e-6)
    assert res["low"] <= res["value"] <= res["high"] and res["stderr"] < 1e-3 and res["never_reached"] == 0
    small = islands.onset_gamma(g, np.rint(share * 400).astype(int), 400, level=0.01)
    assert small["stderr"] > res["stderr"]                      # fewer orbits, wider interval
    assert math.isnan(islands.onset_gamma(g, np.zeros(11, int), 100)["value"])
    assert islands.onset_gamma(g, np.full(11, 50), 100)["value"] == 0.0  # above the level from the start


def test_onset_refuses_bad_input():
    g = [0.0, 0.5, 1.0]
    with pytest.raises(ValueError, match="increasing"):
        islands.onset_gamma([0.0, 1.0, 0.5], [0, 1, 2], 10)
    with pytest.raises(ValueError, match="same length"):
        islands.onset_gamma(g, [0, 1], 10)
    with pytest.raises(ValueError, match="counts"):
        islands.onset_gamma(g, [0, 11, 2], 10)
    with pytest.raises(ValueError, match="level"):
        islands.onset_gamma(g, [0, 1, 2], 10, level=1.5)


def test_starts_refuse_bad_input():
    with pytest.raises(TypeError, match="scene"):
        islands.uniform_reduced_states("torus", 3)
    with pytest.raises(ValueError, match="infinite line"):
        islands.uniform_reduced_states(tables.channel(), 3)
    with pytest.raises(ValueError, match="no element"):
        islands.uniform_reduced_states(tables.sinai_torus(0.2), 3, elements=[4])
    with pytest.raises(ValueError, match="n"):
        islands.uniform_reduced_states(tables.sinai_torus(0.2), -1)


# ----------------------------------------------------------------------------- twin orbits
@pytest.mark.parametrize("gamma", [0.0, 0.6])
def test_twin_exponent_of_the_hyperbolic_head_on_orbit_is_the_closed_form(gamma):
    R = 0.3
    scene, q, v, w = head_on(gamma, R)
    trace = float(theory.two_disk_eigen_sum(1 / R, 1 - 2 * R, 0.0, gamma))
    expected = math.log((trace + math.sqrt(trace * trace - 4)) / 2) / 2
    got = islands.twin_lyapunov(scene, [q], [v], [w], n_collisions=2000)[0]
    assert got == pytest.approx(expected, rel=5e-3)   # measured 6e-4 and 1.5e-3: the start-up transient


@pytest.mark.parametrize("periodic", [False, True])
def test_twin_exponents_agree_with_the_tangent_dynamics_orbit_by_orbit(periodic):
    """Closed hexagonal cell under a force (walls, corners) and the hexagonal gas (the cell walk)."""
    scene = (tables.hex_lorentz_cell(0.4, gamma=1 / math.sqrt(2)) if periodic
             else tables.closed_hex_cell(0.4, gamma=1.0, force=(0.0, -0.1)))
    disk = [0] if periodic else [6]
    st = islands.interior_starts(scene, islands.uniform_reduced_states(scene, 16, seed=3, elements=disk))
    args = (scene, st["positions"], st["velocities"], st["spins"])
    tangent = islands.finite_time_lyapunov(*args, n_collisions=600)
    twin = islands.twin_lyapunov(*args, n_collisions=600)
    assert np.isfinite(twin).all() and np.isfinite(tangent).all()
    thr = islands.REGULAR_THRESHOLD
    regular = tangent < thr
    assert np.array_equal(twin < thr, regular)
    assert np.abs(twin - tangent)[regular].max(initial=0.0) < 0.01   # measured 3e-3
    # chaotic orbits: finite-time values scatter by up to 0.18 about their mean (grazing hits
    # weigh differently in the two); their medians agree
    assert np.median(twin[~regular]) == pytest.approx(np.median(tangent[~regular]), rel=0.1)
    if periodic:
        assert 0 < (twin < thr).sum() < len(twin)   # the sample holds both kinds


@pytest.mark.parametrize("R", [0.45, 0.5])
def test_twin_exponents_of_the_finite_horizon_gas(R):
    """The triangular gas with R > sqrt(3)/4 (finite horizon): its disk reaches out of the parallelogram cell, and
    the twin's orbit, put back in the base cell by the parallelogram that held it, was 'not on start element 0'."""
    scene = Scene((Circle((0.0, 0.0), R),), lattice={"a1": [1.0, 0.0], "a2": [0.5, math.sqrt(3.0) / 2.0]})
    st = islands.interior_starts(scene, islands.uniform_reduced_states(scene, 16, seed=3, elements=[0]))
    args = (scene, st["positions"], st["velocities"], st["spins"])
    tangent = islands.finite_time_lyapunov(*args, n_collisions=600)
    twin = islands.twin_lyapunov(*args, n_collisions=600)
    assert np.isfinite(twin).all() and np.isfinite(tangent).all()
    regular = tangent < islands.REGULAR_THRESHOLD
    assert np.array_equal(twin < islands.REGULAR_THRESHOLD, regular)
    assert np.abs(twin - tangent)[regular].max(initial=0.0) < 0.01
    assert np.median(twin[~regular]) == pytest.approx(np.median(tangent[~regular]), rel=0.1)


def test_twin_exponents_of_thermostatted_flights():
    """No tangent map there; the twin runs, does not depend on threads, and the field changes it."""
    gas = tables.hex_lorentz_cell(0.4, gamma=1.0)
    st = islands.interior_starts(gas, islands.uniform_reduced_states(gas, 6, seed=5))
    args = (st["positions"], st["velocities"], st["spins"])
    # zero field: the thermostat is inert, the twin agrees with the tangent dynamics
    zero = islands.twin_lyapunov(gas.replace(thermostat="isokinetic"), *args, n_collisions=200)
    tangent = islands.finite_time_lyapunov(gas, *args, n_collisions=200)
    assert np.array_equal(zero < islands.REGULAR_THRESHOLD, tangent < islands.REGULAR_THRESHOLD)
    assert 0 < (tangent < islands.REGULAR_THRESHOLD).sum() < len(tangent)
    driven = gas.replace(force=(0.0, -1.0), thermostat="isokinetic")
    with pytest.raises(ValueError, match="thermostat"):
        islands.finite_time_lyapunov(driven, *args, n_collisions=200)
    one = islands.twin_lyapunov(driven, *args, n_collisions=200, num_workers=1)
    two = islands.twin_lyapunov(driven, *args, n_collisions=200, num_workers=2)
    assert np.array_equal(one, two) and np.isfinite(one).all()
    assert not np.array_equal(one, zero)


def test_twin_runs_whole_blocks_as_twin_collisions_says():
    """The command line's N (``twin_collisions``) is the count the twin ran: 9 collisions run as 12."""
    assert [islands.twin_collisions(n, 4) for n in (4, 5, 8, 9)] == [4, 8, 8, 12]
    scene = tables.sinai_torus(0.3)
    args = ([(0.0, 0.45)], [(0.6, 0.8)])
    nine = islands.twin_lyapunov(scene, *args, n_collisions=9, block=4)
    assert np.array_equal(nine, islands.twin_lyapunov(scene, *args, n_collisions=12, block=4))
    assert not np.array_equal(nine, islands.twin_lyapunov(scene, *args, n_collisions=8, block=4))


def test_twin_refuses_bad_input():
    scene = tables.sinai_torus(0.45)
    q, v = [(0.5, 0.0)], [(1.0, 0.1)]
    for kwargs, name in (({"n_collisions": 2, "block": 4}, "n_collisions"), ({"block": 0}, "block"),
                         ({"separation": 0.0}, "separation"), ({"separation": 1e-3}, "separation")):
        with pytest.raises(ValueError, match=name):
            islands.twin_lyapunov(scene, q, v, **kwargs)
    with pytest.raises(ValueError, match="shapes"):
        islands.twin_lyapunov(scene, q, v + v)


def test_threshold_sensitivity_is_the_share_at_each_fraction_of_the_threshold():
    lam = np.array([0.005, 0.015, 0.025, 0.5, np.nan])      # one orbit between each pair of thresholds
    shares = islands.threshold_sensitivity(lam, 0.03)
    assert list(shares) == [0.01, 0.02, 0.03]               # the keys print as typed
    assert list(shares.values()) == [0.25, 0.5, 0.75]
    assert shares[0.03] == islands.regular_share(lam, 0.03)[0]
    per_row = islands.threshold_sensitivity(np.vstack([lam, lam[::-1]]), 0.03, fractions=(0.5,))
    assert np.array_equal(per_row[0.015], [0.25, 0.25])
    with pytest.raises(ValueError, match="fractions"):
        islands.threshold_sensitivity(lam, 0.03, fractions=(0.0,))
