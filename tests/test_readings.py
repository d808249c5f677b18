"""Figure 15 under every reading (experiments.readings) and Figure 14's numbers.

Oracles: our reading's start is the two-disk 2-periodic orbit of analysis.two_disk_orbit; each reading of theta
gives the elevation its geometry says; the printed misprints are what the paper prints (speed doubled, spin of
the opposite sign); survival along theta follows the monodromy's class (elliptic below pi/2 - phi); the inverted
grey scale is the complement; the wedge's transition is pi/2 - pi/7 to 1e-10 and its |lambda| at the paper's
five launch angles equals the eigenvalue of a finite-difference return map built from the engine alone.
"""
import math
import re

import numpy as np
import pytest

import noslipsim as ns
from noslipsim.analysis import elliptic_boundary, stability_grid, two_disk_orbit, wedge_orbit
from noslipsim.experiments import readings as rd
from noslipsim.experiments import wedge_launch_scan

G = 1 / math.sqrt(2)
SMALL = {k: rd.READINGS[k] for k in ("ours", "theta from the vertical", "theta from the tangent (down)",
                                     "printed speed", "stop alternate", "cap 100")}
THETAS = np.array([0.1, 0.3, 0.5, 0.7, 0.9, 1.1, 1.3, 1.5])
RADII = (0.3, 0.8)


@pytest.fixture(scope="module")
def scan():
    return rd.stability_readings(SMALL, radii=RADII, thetas=THETAS)


@pytest.mark.parametrize("radius,theta,position", [(0.3, 0.5, "half"), (0.7, 1.0, "half"), (0.5, 0.8, "full")])
def test_our_reading_starts_on_the_two_disk_orbit(radius, theta, position):
    opt = rd._options({"perturbation": "none", "size": 0.0, "position": position})
    (q, v, w), alpha = rd._start(radius, theta, opt, 1.0)
    _, state = two_disk_orbit(radius, 0.4 if position == "half" else 0.2, G, theta=theta, gravity=1.0)
    assert alpha == theta
    np.testing.assert_allclose(q, state["position"], atol=1e-14)
    np.testing.assert_allclose(v, state["velocity"], atol=1e-14)
    assert w == pytest.approx(state["spin"], abs=1e-14)


def test_each_reading_of_theta_gives_its_elevation(scan):
    p = 0.4
    expect = {"ours": THETAS, "theta from the vertical": math.pi / 2 - THETAS,
              "theta from the tangent (down)": THETAS + p - math.pi / 2}
    for name, alpha in expect.items():
        np.testing.assert_allclose(scan.launch_elevation.sel(reading=name), alpha, atol=1e-15)
        launched = (alpha > 0) & (alpha < math.pi / 2)
        assert (scan.launched.sel(reading=name).values == launched[None, :]).all()
        assert (scan.n_collisions.sel(reading=name).values[:, ~launched] == -1).all()
    # the tangent's downward branch launches only above theta = pi/2 - phi
    assert list(scan.launched.sel(reading="theta from the tangent (down)", radius=0.3).values) == [0] * 6 + [1] * 2


def test_the_printed_misprints():
    base = rd._options({"perturbation": "none", "size": 0.0})
    (_, v, w), _ = rd._start(0.5, 0.6, base, 1.0)
    (_, v_p, w_p), _ = rd._start(0.5, 0.6, {**base, "spin": "printed"}, 1.0)
    assert w_p == pytest.approx(-w, abs=1e-15) and np.allclose(v_p, v)
    # printed speed: twice the launch speed at q0 (compare the launch, before the flight to x = 0)
    d = 2 - 2 * 0.5 * math.cos(0.4)
    q0x = -1 + 0.5 * math.cos(0.4)
    (q2, v2, w2), _ = rd._start(0.5, 0.6, {**base, "speed": "printed"}, 1.0)
    launch = math.sqrt(d / math.sin(1.2))
    assert v2[0] == pytest.approx(2 * launch * math.cos(0.6), rel=1e-14)   # horizontal speed is kept in flight
    assert q2[0] == pytest.approx(0.0, abs=1e-15) and q0x < 0
    assert w2 == pytest.approx(2 * w, rel=1e-14)


def test_survival_follows_the_class_and_the_table(scan):
    ours = scan.survived.sel(reading="ours")
    # R = 0.8 > R*(0.4) = 0.61: elliptic from theta -> 0 up to pi/2 - phi = 1.17, hyperbolic above
    assert list(ours.sel(radius=0.8).values) == [1, 1, 1, 1, 1, 1, 0, 0]
    # R = 0.3: hyperbolic at small theta, elliptic just below pi/2 - phi
    assert list(ours.sel(radius=0.3).values) == [0, 0, 0, 0, 1, 1, 0, 0]
    # the stopping rule "hit the other disk each time" changes nothing for these orbits; nor does a cap of 100 here
    np.testing.assert_array_equal(scan.survived.sel(reading="stop alternate"), ours)
    np.testing.assert_array_equal(scan.survived.sel(reading="cap 100"), ours)
    assert (scan.n_collisions.sel(reading="cap 100").values <= 100).all()
    table = rd.readings_table(scan, min_run=1)
    lines = table.strip().splitlines()
    head = [c.strip() for c in lines[0].strip("|").split("|")]
    assert head == ["reading", "what changes", "R = 0.3", "R = 0.8", "stable at θ ≈ 1.3", "s-u-s",
                    "the paper's pattern"]
    cells = [[c.strip() for c in re.split(r"(?<!\\)\|", r.strip("|"))] for r in lines[2:]]   # "\|" is a pipe
    rows = {c[0]: c for c in cells}
    assert list(rows) == [*SMALL, "\\|λ\\| at θ = 1.3", "inverted grey scale"]
    lam = [float(x) for x in rows["\\|λ\\| at θ = 1.3"][2:4]]
    np.testing.assert_allclose(lam, scan.lambda_at_paper_theta.values, rtol=5e-3)   # printed to 3 digits
    assert rows["ours"][2:] == ["u-s-u (s: 0.80–1.20)", "s-u (s: 0.10–1.20)", "no", "no", "no"]
    # only the inverted grey scale gives the paper's pattern (stable -> unstable -> stable, stable near 1.3)
    assert rows["inverted grey scale"][2] == "s-u-s (s: 0.10–0.80, 1.20–1.50)"
    assert rows["inverted grey scale"][-1] == "R = 0.3"
    assert all(r[-1] == "no" for name, r in rows.items() if name not in ("inverted grey scale", "\\|λ\\| at θ = 1.3"))
    assert rows["theta from the tangent (down)"][2].startswith("x-")


def test_lambda_at_the_papers_angle_is_the_monodromys_largest_modulus():
    """The |lambda| row: lambda + 1/lambda of the exact monodromy, solved for the larger root (1 if elliptic)."""
    from noslipsim.analysis import two_disk_classes

    lam = rd.lambda_at([0.3, 0.8], 1.3)
    for R, value in zip((0.3, 0.8), lam):
        (kind,), (s,) = two_disk_classes(R, [(0.4, 1.3)], G, gravity=1.0)
        assert kind == "hyperbolic" and value > 1 and value + 1 / value == pytest.approx(abs(s), rel=1e-12)
    assert rd.lambda_at([0.8], 0.5)[0] == 1.0                       # elliptic below pi/2 - phi at R = 0.8


def test_the_brute_force_keeps_the_best_of_its_launches():
    """A brute-force cell is the most collisions any launch of SPEED_FACTORS x SPIN_FACTORS survives."""
    thetas = np.array([0.5, 1.3])
    brute = rd.stability_readings({"ours": rd.READINGS["ours"], "brute": ("b", {"search": "speed_spin"})},
                                  radii=(0.9,), thetas=thetas)
    opt = rd._options({"search": "speed_spin"})
    scene = ns.tables.two_disks(0.9, distance=2.0, gamma=opt["gamma"], force=(0.0, -1.0))
    starts = [rd._start(0.9, 1.3, opt, 1.0, a, b)[0] for a in rd.SPEED_FACTORS for b in rd.SPIN_FACTORS]
    assert int(brute.n_collisions.sel(reading="brute", radius=0.9, theta_read=1.3)) == \
        int(rd._survival(scene, [s for s in starts if s is not None], opt).max())
    # our launch is one of the brute force's (speed x 1, spin x 1): never fewer collisions
    assert (brute.n_collisions.sel(reading="brute") >= brute.n_collisions.sel(reading="ours")).all()
    with pytest.raises(ValueError, match="search"):
        rd._options({"search": "everything"})


def test_pattern_merges_short_runs():
    assert rd._runs(list("ssusssuu"), 2) == [("s", 0, 6), ("u", 6, 8)]
    assert rd._runs(list("xxsus"), 2)[0] == ("x", 0, 2)
    assert rd._launched("x-u-s-x") == "u-s"
    assert rd.paper_pattern({"pattern": "s-u-s", "stable_near_1_3": True})
    assert not rd.paper_pattern({"pattern": "u-s-u-s", "stable_near_1_3": True})


@pytest.mark.parametrize("readings,kwargs,match", [
    ({"a": ("x", {"colour": 1})}, {}, "unknown key"),
    ({"a": ("x", {"theta_from": "sideways"})}, {}, "theta_from"),
    ({"a": ("x", {"cap": 0})}, {}, "cap"),
    ({"a": ("x", {"gamma": -1.0})}, {}, "gamma"),
    ({"a": ("x", {"phi": 2.0})}, {}, "phi"),
    ({"a": "x"}, {}, "description, changes"),
    ({}, {}, "non-empty"),
    (None, {"radii": (0.5, 1.2)}, "radii"),
    (None, {"thetas": [0.0, 0.5]}, "thetas"),
    (None, {"gravity": 0.0}, "gravity"),
])
def test_bad_inputs_are_refused(readings, kwargs, match):
    with pytest.raises(ValueError, match=match):
        rd.stability_readings(readings, **kwargs)


# ---------------------------------------------------------------- Figure 15: the force's threshold
def test_elliptic_boundary_is_the_threshold_without_force_and_moves_with_it():
    radii, phis = np.linspace(0.1, 0.95, 40), np.array([0.3, 0.8, 1.2])
    free = elliptic_boundary(stability_grid(radii, phis, G, max_collisions=1))
    assert np.isfinite(free.boundary).all()
    assert np.abs(free.radius_shift.values).max() < 2e-3      # linear interpolation across 0.022 in R
    forced = elliptic_boundary(stability_grid(radii, phis, G, gravity=1.0, theta=0.1, max_collisions=1))
    assert (forced.radius_shift.values > 0.01).all()            # the elliptic region reaches smaller disks
    assert forced.attrs["max_shift"] == pytest.approx(forced.radius_shift.values.max())
    with pytest.raises(ValueError, match="R x phi"):
        elliptic_boundary(forced)


# ---------------------------------------------------------------- Figure 14
def test_wedge_transition_has_the_digits_that_tell_it_from_1_122():
    ds = wedge_launch_scan([math.pi / 7], np.linspace(1.10, 1.14, 9), G)
    t = float(ds.theta_transition[0])
    assert t == pytest.approx(math.pi / 2 - math.pi / 7, abs=1e-10)
    assert f"{t:.6f}" == "1.121997" and f"{t:.3f}" == "1.122" and t < 1.122


def _section_map(scene, y, vx, vy, w, g):
    """Two collisions from the crossing of x = 0 rightwards, then the flight back to x = 0: (y, vx, vy, w)."""
    run = ns.simulate(scene, (0.0, y), (vx, vy), w, max_collisions=2)
    x1, y1, vx1, vy1, w1 = (float(run[k].values[1]) for k in ("x", "y", "vx", "vy", "spin"))
    t = -x1 / vx1   # the force is vertical: x is linear in time
    return np.array([y1 + vy1 * t - 0.5 * g * t * t, vx1, vy1 - g * t, w1])


@pytest.mark.parametrize("theta,expected", [(1.122, 1.0054), (1.123, 1.1112), (1.124, 1.1607), (1.125, 1.2002),
                                            (1.126, 1.2346)])
def test_lambda_at_the_papers_launch_angles_from_finite_differences(theta, expected):
    scene, state = wedge_orbit(math.pi / 7, theta, 1.0, G)
    x0, y0 = state["position"]
    vx0, vy0 = state["velocity"]
    # move the start along its flight to x = 0 (the vertex's vertical): the section of the return map
    t = -x0 / vx0
    base = np.array([y0 + vy0 * t - 0.5 * t * t, vx0, vy0 - t, state["spin"]])
    assert np.abs(_section_map(scene, *base, 1.0) - base).max() < 1e-12       # periodic
    h = 1e-6
    J = np.column_stack([(_section_map(scene, *(base + h * e), 1.0) - _section_map(scene, *(base - h * e), 1.0))
                         / (2 * h) for e in np.eye(4)])
    lam = np.abs(np.linalg.eigvals(J)).max()
    assert lam == pytest.approx(expected, abs=1.5e-4)
    # and the figure's numbers (the exact monodromy) agree with it
    scan = wedge_launch_scan([math.pi / 7], [theta], G)
    assert float(scan.lambda_max[0, 0]) == pytest.approx(lam, rel=1e-5)
