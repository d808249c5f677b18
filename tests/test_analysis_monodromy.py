"""Monodromy (noslipsim.analysis.monodromy): exact derivative propagation against closed forms and finite differences.

Oracles:
- two disks without force: eigenvalues {1, lambda, 1/lambda} with lambda + 1/lambda from
  theory.two_disk_eigen_sum (Cox, Feres & Zhang 2018), to 1e-8, across R, phi, gamma (gamma = 0 too);
- the force-free wedge: the same formula at curvature 0, always elliptic;
- the half plane: M = I + e_s grad(D)^T from the drift formula (derived in the module docstring);
- the invariant measure ds dw dv_t: det = -1 per no-slip step, +1 per specular step;
- central finite differences of the engine's own return map, on generic orbits of every element kind,
  with and without force, specular and no-slip, plain and periodic.
"""
import math

import numpy as np
import pytest

import noslipsim as ns
from noslipsim import tables, theory
from noslipsim.analysis import CornerError, bounce_orbit, monodromy, two_disk_orbit, wedge_noforce_orbit, wedge_orbit
from noslipsim.analysis.monodromy import UNIT_TOL, classify
from noslipsim.analysis.section import (
    boundary_frames,
    boundary_log,
    energy_at,
    interior_log,
    reduced_from_log,
    state_from_reduced,
    wrap_difference,
)
from noslipsim.analysis.tangent import step_jacobians

EIGEN_TOL = 1e-8   # two-disk eigen sum against the closed form (relative to max(1, |value|))
FD_TOL = 1e-6      # exact Jacobian against central differences (relative to the largest entry)
G = 1 / math.sqrt(2)


# ----------------------------------------------------------------------------- two disks, no force
TWO_DISK = [(R, phi, gamma) for R in (0.2, 0.5, 0.9, 0.97) for phi in (0.0, 0.3, 0.8, 1.2, 1.45)
            for gamma in (0.05, 0.3, G, 1.0, 3.0, 100.0)] + [(R, 0.0, 0.0) for R in (0.2, 0.5, 0.9)]


@pytest.mark.parametrize("radius, phi, gamma", TWO_DISK)
def test_two_disk_eigenvalues_match_the_closed_form(radius, phi, gamma):
    scene, state = two_disk_orbit(radius, phi, gamma)
    m = monodromy(scene, **state, period=2)
    d = 2 - 2 * radius * math.cos(phi)
    want = theory.two_disk_eigen_sum(1 / radius, d, phi, gamma)
    assert abs(m.eigen_sum - want) <= EIGEN_TOL * max(1.0, abs(want))
    assert abs(m.unit_eigenvalue - 1.0) < 1e-8
    assert m.det == pytest.approx(1.0, abs=1e-9 * max(1.0, abs(want)))
    np.testing.assert_allclose(m.closure, 0.0, atol=1e-13 * max(1.0, abs(want)) * max(1.0, abs(state["spin"])))
    # the eigenvalues themselves: 1 and the roots of x^2 - want x + 1
    roots = np.roots([1.0, -want, 1.0])
    got = np.sort_complex(m.eigenvalues)
    expect = np.sort_complex(np.r_[roots, 1.0])
    # at the threshold (lambda = 1) the eigenvalue 1 is triple and rounding splits it by ~cbrt(eps)
    split = 1e-4 if abs(want - 2.0) < 1e-6 else 1e-7
    np.testing.assert_allclose(got, expect, atol=split * max(1.0, abs(want)))
    if abs(abs(want) - 2.0) > 1e-4:
        assert m.kind == ("elliptic" if abs(want) < 2 else "hyperbolic")
        assert (radius ** -1 * d < theory.ellipticity_threshold(phi, gamma)) == (m.kind == "elliptic")


def test_two_disk_monodromy_base_point_and_period_time():
    scene, state = two_disk_orbit(0.5, 0.3, G)
    m = monodromy(scene, **state, period=2)
    assert m.base["element"] == 1 and m.period == 2
    assert m.period_time == pytest.approx(2 * (2 - 2 * 0.5 * math.cos(0.3)), rel=1e-14)  # unit speed
    assert m.coordinates == ("s", "w", "v_t")
    assert not m.isolated and m.unit_count() == 1


# ----------------------------------------------------------------------------- wedges
@pytest.mark.parametrize("opening", ["up", "down"])
@pytest.mark.parametrize("wall", ["left", "right"])
@pytest.mark.parametrize("gamma", [0.05, 0.3, G, 1.0, 3.0, 100.0])
def test_noforce_wedge_orbits_are_elliptic(opening, wall, gamma):
    for phi, ell in [(0.1, 1.0), (0.5, 2.0), (1.2, 0.3), (1.5, 1.0)]:
        scene, state = wedge_noforce_orbit(phi, ell, gamma, opening=opening, wall=wall)
        m = monodromy(scene, **state, period=2)
        assert m.kind == "elliptic", (phi, ell, m.eigenvalues)
        # the two-disk formula at curvature 0 is the force-free wedge
        want = theory.two_disk_eigen_sum(0.0, 2 * ell * math.sin(phi), phi, gamma)
        assert m.eigen_sum == pytest.approx(want, abs=EIGEN_TOL)
        assert np.abs(m.eigenvalues).max() == pytest.approx(1.0, abs=1e-12)


def test_wedge_orbit_under_gravity_changes_class_with_the_launch_angle():
    """The paper's observation (2perunstable): small launch angles stable, large ones unstable."""
    kinds = [monodromy(*_unpack(wedge_orbit(0.5, theta, 1.0, G)), period=2).kind for theta in (0.3, 0.8, 1.2)]
    assert kinds == ["elliptic", "elliptic", "hyperbolic"]


def _unpack(built):
    scene, state = built
    return scene, state["position"], state["velocity"], state["spin"]


@pytest.mark.parametrize("args", [
    # the long-run stable cases of tests/test_analysis_orbits.py are elliptic
    dict(radius=0.9, phi=1.2, gamma=3.0, theta=0.2, gravity=1.0),
    dict(radius=0.9, phi=1.2, gamma=3.0, theta=0.3, gravity=9.81),
    dict(radius=0.2, phi=0.7, gamma=100.0, theta=0.3, gravity=0.5),
])
def test_stable_two_disk_orbits_with_gravity_are_elliptic(args):
    scene, state = two_disk_orbit(**args)
    assert monodromy(scene, **state, period=2).kind == "elliptic"


# ----------------------------------------------------------------------------- half plane
@pytest.mark.parametrize("gamma", [0.05, 0.3, G, 1.0, 3.0, 100.0])
@pytest.mark.parametrize("vx, u, g", [(0.3, 1.2, 1.0), (-2.0, 0.5, 9.81), (0.0, 1.0, 0.2)])
def test_half_plane_monodromy_is_the_drift_gradient(vx, u, g, gamma):
    scene, state = bounce_orbit(vx, u, gamma, gravity=g)
    m = monodromy(scene, **state, period=2)
    k = 4 * u / (g * (1 + gamma ** 2))
    want = np.eye(3)
    want[0, 1:] = [-gamma * k, k]
    np.testing.assert_allclose(m.matrix, want, rtol=0, atol=1e-12 * max(1.0, k * gamma))
    np.testing.assert_allclose(m.eigenvalues, 1.0, atol=1e-7)
    assert m.kind == "parabolic"
    # the drift formula's own derivative, by differences of theory.half_plane_drift at fixed energy
    w = state["spin"]
    h = 1e-6

    def drift(dw, dvx):  # u from the energy: u^2 + w^2 + vx^2 fixed
        ww, vv = w + dw, vx + dvx
        uu = math.sqrt(u * u + w * w + vx * vx - ww * ww - vv * vv)
        return theory.half_plane_drift(vv, ww, uu, gamma, g)
    grad = [(drift(h, 0) - drift(-h, 0)) / (2 * h), (drift(0, h) - drift(0, -h)) / (2 * h)]
    np.testing.assert_allclose(m.matrix[0, 1:], grad, rtol=1e-7, atol=1e-9)


# ----------------------------------------------------------------------------- finite differences, every element kind
SQUARE_WITH_ARC = ns.Scene((
    ns.Segment((0, 0), (2, 0)), ns.Segment((2, 0), (2, 1)),
    ns.Arc((1, 1), 1.0, 0.0, math.pi, "inside"), ns.Segment((0, 1), (0, 0)),
))
FD_CASES = {
    "segment pentagon no-slip": (tables.regular_polygon(5), (0.1, 0.05), (0.6, 0.8), 0.3, 7),
    "segment pentagon specular": (tables.regular_polygon(5, law="specular"), (0.1, 0.05), (0.6, 0.8), 0.0, 7),
    "segment pentagon force": (tables.regular_polygon(5, force=(0.1, -1.0)), (0.1, 0.05), (0.6, 0.8), 0.3, 7),
    "segment right-handed": (tables.polygon([(0, 0), (0, 1), (1.5, 1), (1.5, 0)][::-1]), (0.3, 0.2),
                             (0.7, 0.5), -0.4, 6),
    "line channel force": (tables.channel(1.0, force=(0.0, -0.5)), (0.0, 0.5), (0.7, 0.9), 0.2, 6),
    "line wedge force": (tables.wedge(0.6), (0.0, 1.0), (0.5, 0.4), 0.1, 6),
    "line wedge specular force": (tables.wedge(0.6, law="specular"), (0.0, 1.0), (0.5, 0.4), 0.7, 6),
    "circle outside": (tables.rectangle(2, 1, disks=[(1.0, 0.5, 0.3)]), (0.2, 0.2), (0.9, 0.43), 0.1, 6),
    "circle outside force": (tables.rectangle(2, 1, disks=[(1.0, 0.5, 0.3)], force=(0, -2.0)), (0.2, 0.2),
                             (0.9, 0.43), 0.1, 6),
    "circle outside specular spin": (tables.rectangle(2, 1, disks=[(1.0, 0.5, 0.3)], law="specular"),
                                     (0.2, 0.2), (0.9, 0.43), 0.6, 6),
    "circle inside": (ns.Scene((ns.Circle((0, 0), 1.0, "inside"),)), (0.1, 0.2), (0.3, 0.8), 0.4, 6),
    "circle inside force": (ns.Scene((ns.Circle((0, 0), 1.0, "inside"),), force=(0.3, -1.0)), (0.1, 0.2),
                            (0.3, 0.8), 0.4, 6),
    "arc stadium": (tables.stadium(1.0, 0.7), (0.1, 0.1), (0.8, 0.3), -0.2, 3),
    "arc stadium force": (tables.stadium(1.0, 0.7, force=(0, -1.0)), (0.1, 0.1), (0.8, 0.3), -0.2, 4),
    "arc lid force": (SQUARE_WITH_ARC.replace(force=(0.2, -1.5)), (0.5, 0.5), (1.0, 1.3), 0.3, 6),
    "arc lemon specular": (tables.lemon(), (0.0, 0.0), (0.8, 0.35), 0.0, 6),
    "lattice sinai torus": (tables.sinai_torus(0.3), (0.45, 0.1), (0.8, 0.35), 0.3, 2),
    "lattice sinai specular": (tables.sinai_torus(0.3, law="specular"), (0.45, 0.1), (0.8, 0.35), 0.0, 2),
    "lattice hex force": (tables.hex_lorentz_cell(0.4, force=(0.05, -0.2)), (0.45, 0.1), (0.8, 0.35), 0.3, 3),
    "lattice galton": (tables.galton_board(), (1.0, 0.0), (0.3, 0.1), 0.2, 2),
}


def fd_jacobian(scene, m, h):
    """Central differences of the engine's return map in (s, w, v_t) at the base point's energy."""
    b = m.base
    point = boundary_frames(scene, np.array([b["element"]]), np.array([b["s"]]))[0][0]
    energy = energy_at(scene, point, b["velocity"], b["spin"])
    x0 = np.array([b["s"], b["w"], b["v_t"]])

    def final(x):
        q, v, w = state_from_reduced(scene, b["element"], *x, energy)
        log, stop = boundary_log(scene, b["element"], q, v, w, m.period)
        assert len(log) == m.period, stop
        e, s, w, vt = reduced_from_log(scene, log[-1:])
        return np.array([s[0], w[0], vt[0]]), e[0]

    J = np.zeros((3, 3))
    for j in range(3):
        d = np.zeros(3)
        d[j] = h
        (fp, ep), (fm, em) = final(x0 + d), final(x0 - d)
        assert ep == em
        diff = fp - fm
        diff[0] = wrap_difference(scene, ep, diff[0])
        J[:, j] = diff / (2 * h)
    return J


@pytest.mark.parametrize("name", sorted(FD_CASES))
def test_monodromy_agrees_with_finite_differences(name):
    scene, q, v, w, period = FD_CASES[name]
    m = monodromy(scene, q, v, w, period=period)
    assert np.all(np.isfinite(m.matrix))
    J = fd_jacobian(scene, m, 1e-7)
    err = np.abs(J - m.matrix).max() / np.abs(m.matrix).max()
    assert err < FD_TOL, (name, err)
    assert np.abs(m.matrix - np.eye(3)).max() > 1e-3  # not a trivial map


@pytest.mark.parametrize("name", sorted(FD_CASES))
def test_each_step_preserves_the_section_measure(name):
    """|det J_i| = 1; sign -1 per no-slip law (it flips (w, v_t)) times the orientations sigma of s at both ends."""
    scene, q, v, w, _ = FD_CASES[name]
    log, _ = interior_log(scene, q, v, w, 40)
    dets = np.linalg.det(step_jacobians(scene, log))
    sigma = boundary_frames(scene, log[:, 9].astype(int), log[:, 10])[4]
    want = (-1.0 if scene.law == "no-slip" else 1.0) * sigma[:-1] * sigma[1:]
    np.testing.assert_allclose(dets, want, rtol=1e-7)


def test_specular_spin_is_a_spectator():
    scene, q, v, _, period = FD_CASES["circle outside specular spin"]
    m = monodromy(scene, q, v, 0.6, period=period)
    np.testing.assert_array_equal(m.matrix[1], [0.0, 1.0, 0.0])
    assert np.min(np.abs(m.eigenvalues - 1.0)) < 1e-10
    assert np.abs(m.matrix[[0, 2], 1]).max() > 1e-3  # spin energy traded for speed changes the flight
    m0 = monodromy(scene, q, v, 0.0, period=period)
    np.testing.assert_array_equal(m0.matrix[:, 1], [0.0, 1.0, 0.0])  # no spin: nothing to trade


def test_frames_from_arclength_match_the_logged_positions():
    for name in ("circle outside", "arc lid force", "lattice sinai torus", "lattice galton", "segment right-handed"):
        scene, q, v, w, _ = FD_CASES[name]
        log, _ = interior_log(scene, q, v, w, 30)
        e = log[:, 9].astype(int)
        point, t, n, _, _ = boundary_frames(scene, e, log[:, 10])
        xy = log[:, 1:3]
        if scene.lattice is None:
            np.testing.assert_allclose(point, xy, atol=1e-12)
        else:  # unfolded positions: the offset is a lattice vector
            A = np.array([scene.lattice["a1"], scene.lattice["a2"]]).T
            k = np.linalg.solve(A, (xy - point).T)
            np.testing.assert_allclose(k, np.rint(k), atol=1e-9)
        # v_in . n > 0 (arriving), v_out . n < 0 (leaving), t = J n
        assert np.all(np.sum(log[:, 6:8] * n, axis=1) > 0)
        assert np.all(np.sum(log[:, 3:5] * n, axis=1) < 0)
        np.testing.assert_allclose(t, np.c_[-n[:, 1], n[:, 0]], atol=1e-15)


# ----------------------------------------------------------------------------- classification and errors
def test_classify():
    assert classify([1.0, 2.0, 0.5]) == "hyperbolic"
    assert classify([1.0, -3.0, -1 / 3]) == "hyperbolic"
    assert classify([1.0, np.exp(0.3j), np.exp(-0.3j)]) == "elliptic"
    assert classify([1.0, 1.0 + 1e-9, 1.0 - 1e-9]) == "parabolic"
    assert classify([1.0, -1.0, -1.0]) == "parabolic"
    assert classify([1.0, 1.0 + 10 * UNIT_TOL, 1 / (1.0 + 10 * UNIT_TOL)]) == "hyperbolic"


def test_corner_collision_raises():
    scene = tables.rectangle(1.0, 1.0)
    ds = ns.simulate(scene, (0.5, 0.5), (-1.0, -1.0), 0.0, max_collisions=3)
    assert int(ds.corner.sum()) > 0  # the diagonal hits the corner (0, 0)
    with pytest.raises(CornerError, match="corner collision"):
        monodromy(scene, (0.5, 0.5), (-1.0, -1.0), 0.0, period=2)
    assert issubclass(CornerError, ValueError)


def test_argument_errors():
    scene, state = two_disk_orbit(0.5, 0.3, G)
    for bad in (0, -2, 1.5, True, "2"):
        with pytest.raises(ValueError, match="period"):
            monodromy(scene, **state, period=bad)
    with pytest.raises(ValueError, match="period: the orbit stops \\('escape'\\)"):
        monodromy(scene, (0.0, 0.9), (1.0, 0.0), 0.0, period=1)  # misses both disks
    with pytest.raises(ValueError, match="position"):
        monodromy(scene, (-1.0, 0.0), (1.0, 0.0), 0.0, period=2)  # inside a disk
    with pytest.raises(ValueError, match="scene"):
        monodromy("two disks", **state, period=2)
    sinai = tables.sinai_torus(0.3, law="specular")
    with pytest.raises(ValueError, match="overflows"):
        monodromy(sinai, (0.45, 0.1), (0.8, 0.35), 0.0, period=2000)
