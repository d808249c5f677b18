"""Canonical form of periodic scenes (noslipsim._engine.canonical): how a scene is written never decides its kernel.

Each user scene below is a canonical twin (``tables.*``) written another way: the
disk elsewhere in the cell, a skewed basis of the same lattice, a shifted
origin.  Its canonical form must run the twin's kernel variant, and its orbits
must be the twin's to rounding: every flight of a 1000-collision orbit of the
user scene, restarted in the twin (the oracle: the twin is built by hand, not
by the canonical form), hits the same disk at the same time and place to
1e-12.  Outputs stay in the user's coordinates (unfolded positions, the user's
cell indices).
"""
import math
from dataclasses import replace

import numpy as np
import pytest
from kernel_call import run_kernel

from noslipsim import Circle, Scene, simulate, simulate_many, tables
from noslipsim._engine.canonical import canonical_form, reduce_basis
from noslipsim._engine.lattice import cell_of, cell_origin, lattice_matrix, reaching_copies
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout
from noslipsim.core.loop import orbit_kernel

SQ3 = math.sqrt(3.0)
FLIGHT_TOL = 1e-12
N_FLIGHTS = 1000


def disk_lattice(centre, radius, a1, a2, law, force=(0.0, 0.0)):
    return Scene((Circle(centre, radius, "outside"),), law=law, force=force,
                 lattice={"a1": list(a1), "a2": list(a2)})


#: name -> (user scene factory(law), twin factory(law), offset: user position = twin position + offset,
#:          start in the user scene)
CASES = {
    "torus, disk at the centre": (
        lambda law: disk_lattice((0.5, 0.5), 0.25, (1, 0), (0, 1), law),
        lambda law: tables.sinai_torus(0.25, law=law), (0.5, 0.5), (0.95, 0.6)),
    "torus, disk anywhere": (
        lambda law: disk_lattice((0.3, -0.2), 0.25, (1, 0), (0, 1), law),
        lambda law: tables.sinai_torus(0.25, law=law), (0.3, -0.2), (0.75, -0.1)),
    "torus, skewed basis a2 = a1 + e2": (
        lambda law: disk_lattice((0.0, 0.0), 0.25, (1, 0), (1, 1), law),
        lambda law: tables.sinai_torus(0.25, law=law), (0.0, 0.0), (0.45, 0.1)),
    "hex cell, shifted disk, basis at 120 degrees": (
        lambda law: disk_lattice((0.2, 0.1), 0.3, (1, 0), (-0.5, SQ3 / 2), law),
        lambda law: tables.hex_lorentz_cell(0.3, law=law), (0.2, 0.1), (0.65, 0.2)),
    "hex cell, skewed basis a2 = a1 + a2'": (
        lambda law: disk_lattice((0.0, 0.0), 0.3, (1, 0), (1.5, SQ3 / 2), law),
        lambda law: tables.hex_lorentz_cell(0.3, law=law), (0.0, 0.0), (0.45, 0.1)),
    "Galton board, shifted origin": (
        lambda law: disk_lattice((1.0, 0.5), 0.5, (2, 0), (1, SQ3), law, force=(0.0, -1.0)),
        lambda law: tables.galton_board(2.0, 0.5, 1.0, law=law), (1.0, 0.5), (2.0, 0.5)),
}


def nearest_copy_distance(scene, pts):
    """Distance from points to the nearest copy of the (single) disk centre of a lattice scene."""
    e = scene.elements[0]
    rel = pts - np.asarray(e.center)
    site = cell_origin(cell_of(rel, scene.lattice), scene.lattice)
    best = np.full(len(pts), np.inf)
    A, _ = lattice_matrix(scene.lattice)
    for o1 in (-1, 0, 1):
        for o2 in (-1, 0, 1):
            c = site + A @ np.array([o1, o2], float)
            best = np.minimum(best, np.hypot(*(rel - c).T))
    return best


# ---------------------------------------------------------------------------- basis reduction
@pytest.mark.parametrize("a1, a2", [((1, 0), (0, 1)), ((1, 0), (0.5, SQ3 / 2)), ((2, 0), (1, SQ3))])
def test_reduced_bases_are_kept(a1, a2):
    A = np.array([a1, a2], float).T
    assert np.array_equal(reduce_basis(A), np.eye(2, dtype=np.int64))


@pytest.mark.parametrize("a1, a2", [((1, 0), (7, 1)), ((1, 0), (1.5, SQ3 / 2)), ((3, 1), (5, 2)),
                                    ((1, 0), (-0.5, SQ3 / 2)), ((1, 0), (0.3, -1.0)), ((0, 5), (1, 0.2)),
                                    ((1e-3, 0), (123.4567, 1e-3))])
def test_reduction_gives_a_reduced_basis_of_the_same_lattice(a1, a2):
    A = np.array([a1, a2], float).T
    U = reduce_basis(A)
    assert abs(round(np.linalg.det(U))) == 1 and np.array_equal(U, np.rint(U))
    b1, b2 = (A @ U).T
    assert abs(b1 @ b2) <= 0.5 * min(b1 @ b1, b2 @ b2) * (1 + 1e-9)
    assert b1 @ b2 >= -1e-12  # orientation convention
    # same lattice: the user's vectors are integer combinations of the reduced ones
    back = np.linalg.solve(A @ U, A)
    np.testing.assert_allclose(back, np.rint(back), atol=1e-9)


def test_reduction_fails_on_a_wrong_step():
    """The checks above are sharp: a non-reduced or non-unimodular matrix fails them."""
    A = np.array([(1, 0), (7, 1)], float).T
    b1, b2 = (A @ np.eye(2)).T
    assert not abs(b1 @ b2) <= 0.5 * min(b1 @ b1, b2 @ b2)
    assert abs(round(np.linalg.det(np.array([[2, 0], [0, 1]])))) != 1


# ---------------------------------------------------------------------------- copies that reach a cell
def test_copies_are_found_by_exact_geometry():
    # the hexagonal cell at r = 0.45: the box test listed 9 copies; the circle reaches 5 cells' worth
    hex45 = tables.hex_lorentz_cell(0.45)
    assert sorted(map(tuple, reaching_copies(hex45.elements, hex45.lattice).tolist())) == [
        (0, -1, 0), (0, 0, -1), (0, 0, 0), (0, 0, 1), (0, 1, 0)]
    lat = {"a1": [1.0, 0.0], "a2": [0.0, 1.0]}
    # a disk whose box pokes into the cell at a corner while the circle stays out
    corner = Circle((0.5 + 0.18, 0.5 + 0.18), 0.2)
    assert (0, 0, 0) not in map(tuple, reaching_copies([corner], lat).tolist())
    # ... and one that does reach it (box and circle)
    assert (0, 0, 0) in map(tuple, reaching_copies([Circle((0.5 + 0.12, 0.5 + 0.12), 0.2)], lat).tolist())
    # a circle enclosing the whole cell never meets it
    big = Circle((0.0, 0.0), 0.8, "inside")
    assert (0, 0, 0) not in map(tuple, reaching_copies([big], lat).tolist())
    from noslipsim import Segment
    diag = Segment((0.45, 0.7), (0.7, 0.45))  # box overlaps the cell's corner, segment misses it
    assert (0, 0, 0) not in map(tuple, reaching_copies([diag], lat).tolist())
    assert (0, 0, 0) in map(tuple, reaching_copies([Segment((0.3, 0.7), (0.7, 0.3))], lat).tolist())


@pytest.mark.parametrize("law", ["specular", "no-slip"])
def test_dropping_unreachable_copies_changes_no_bit(law):
    """The copies the box test added and the exact test drops are never hit: same outputs, bit for bit."""
    scene = tables.hex_lorentz_cell(0.45, law=law)
    table = kernel_table(scene)
    boxed = np.array([(0, o1, o2) for o1 in (-1, 0, 1) for o2 in (-1, 0, 1)], dtype=np.int64)
    assert len(table.copies) == 5
    outs = []
    for copies in (table.copies, boxed):
        rec = np.zeros((3000, layout.N_LOG))
        general = table.variant(layout.RECORD_LOG)._replace(disks=False, walls=None, mixed=None)
        out = run_kernel(replace(table, copies=copies), general, (0.0, 0.47), (0.6, 0.8), 0.1, 3000,
                         layout.RECORD_LOG, rec=rec, mask=np.ones(1, np.bool_))
        outs.append((np.asarray(out, float), rec))
    assert outs[0][0][0] == 3000
    assert np.array_equal(outs[0][0].view(np.int64), outs[1][0].view(np.int64))
    assert np.array_equal(outs[0][1].view(np.int64), outs[1][1].view(np.int64))


# ---------------------------------------------------------------------------- canonical twins
def test_canonical_scenes_are_their_own_form():
    for scene in (tables.sinai_torus(0.25), tables.hex_lorentz_cell(0.3), tables.hex_lorentz_cell(0.45),
                  tables.galton_board(), tables.regular_polygon(5)):
        form = canonical_form(scene)
        assert form.identity and form.scene is scene


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize("mode", [layout.RECORD_NONE, layout.RECORD_LOG])
def test_user_scene_runs_the_twins_kernel_variant(name, mode):
    user, twin, _, _ = CASES[name]
    for law in ("specular", "no-slip"):
        form = canonical_form(user(law))
        assert not form.identity
        assert kernel_table(form.scene).variant(mode) == kernel_table(twin(law)).variant(mode)
        assert len(kernel_table(form.scene).arrays()[2]) == len(kernel_table(twin(law)).arrays()[2])
        assert orbit_kernel(*kernel_table(form.scene).variant(mode)) is orbit_kernel(
            *kernel_table(twin(law)).variant(mode))


def per_flight_deviation(name, law, n=N_FLIGHTS):
    """Largest deviation between the user scene's and the twin's next collision over ``n`` flights.

    The flights start on the disk of cell 0 with the post-collision states of a
    user orbit (velocity and spin; the point at the same angle on the disk, so
    both scenes start from the same small numbers: the twin at ``p``, the user
    scene at ``p + offset``).
    """
    user_of, twin_of, offset, q0 = CASES[name]
    user, twin = user_of(law), twin_of(law)
    theta = 0.7
    ds = simulate(user, q0, (math.cos(theta), math.sin(theta)), 0.1, max_collisions=n)
    assert int(ds.n_collisions) == n
    q = np.c_[ds.x.values, ds.y.values]
    # outputs in the user's coordinates: on a disk copy of the user's scene, cells of the user's basis
    r = user.elements[0].radius
    assert np.abs(nearest_copy_distance(user, q) - r).max() < 1e-13
    assert np.array_equal(np.c_[ds.cell_a1.values, ds.cell_a2.values], cell_of(q, user.lattice))
    v = np.c_[ds.vx.values, ds.vy.values]
    w = ds.spin.values
    # the point at the same angle on the disk of cell 0
    rel = q - np.asarray(offset)
    d = rel - cell_origin(cell_of(rel, twin.lattice), twin.lattice)
    phi = np.arctan2(d[:, 1], d[:, 0])
    p = r * np.c_[np.cos(phi), np.sin(phi)]
    keep = np.einsum("ij,ij->i", v, p) > 1e-3 * r * np.hypot(v[:, 0], v[:, 1])  # leaving the disk
    p, v, w = p[keep], v[keep], w[keep]
    on = np.zeros(len(p), np.int64)
    a = simulate_many(user, p + np.asarray(offset), v, w, max_collisions=1, record="log", start_elements=on,
                      scheduler="sync")
    b = simulate_many(twin, p, v, w, max_collisions=1, record="log", start_elements=on, scheduler="sync")
    assert (a.n_collisions.values == 1).all() and (b.n_collisions.values == 1).all()
    t = b.t.values[:, 0]
    speed = np.sqrt(v[:, 0] ** 2 + v[:, 1] ** 2 + w ** 2)
    # relative to the flight's length (its point is good to eps times it) and the speed (gravity changes it)
    length = np.maximum(1.0, t * speed)
    pos = np.hypot(a.x.values[:, 0] - offset[0] - b.x.values[:, 0], a.y.values[:, 0] - offset[1] - b.y.values[:, 0])
    return max(float((np.abs(a.t.values[:, 0] - t) / np.maximum(1.0, t)).max()), float((pos / length).max()),
               *(float((np.abs(a[k].values[:, 0] - b[k].values[:, 0]) / speed).max()) for k in ("vx", "vy", "spin")))


@pytest.mark.parametrize("law", ["specular", "no-slip"])
@pytest.mark.parametrize("name", sorted(CASES))
def test_every_flight_agrees_with_the_canonical_twin(name, law):
    dev = per_flight_deviation(name, law)
    assert dev < FLIGHT_TOL, (name, law, dev)


def test_flight_check_sees_a_wrong_offset():
    """Mutation: the twin placed a rounding-sized step off (1e-9) fails the per-flight check."""
    user_of, twin_of, offset, q0 = CASES["torus, disk at the centre"]
    CASES["mutant"] = (user_of, twin_of, (offset[0] + 1e-9, offset[1]), q0)
    try:
        with pytest.raises(AssertionError):
            assert per_flight_deviation("mutant", "specular", n=50) < FLIGHT_TOL
    finally:
        del CASES["mutant"]


def test_ensemble_outputs_are_in_user_coordinates():
    """simulate_many (final state, log) and simulate agree on the user's positions and cells."""
    user = CASES["hex cell, shifted disk, basis at 120 degrees"][0]("no-slip")
    rng = np.random.default_rng(5)
    q = np.array([0.65, 0.2]) + np.c_[rng.uniform(-0.02, 0.02, 6), rng.uniform(-0.02, 0.02, 6)] + [[3.0, -2 * SQ3]]
    phi = rng.uniform(0, 2 * np.pi, 6)
    v = np.c_[np.cos(phi), np.sin(phi)]
    log = simulate_many(user, q, v, max_collisions=40, record="log", scheduler="sync")
    fin = simulate_many(user, q, v, max_collisions=40, record="final", scheduler="sync")
    for i in range(6):
        one = simulate(user, q[i], v[i], 0.0, max_collisions=40)
        assert np.array_equal(one.x.values, log.x.values[i]) and np.array_equal(one.y.values, log.y.values[i])
        assert np.array_equal(one.cell_a1.values, log.cell_a1.values[i])
        assert float(one.x_final) == float(fin.x_final[i]) and int(one.cell_a2_final) == int(fin.cell_a2_final[i])
    pts = np.c_[log.x.values.ravel(), log.y.values.ravel()]
    cells = np.c_[log.cell_a1.values.ravel(), log.cell_a2.values.ravel()]
    assert np.array_equal(cells, cell_of(pts, user.lattice))
    assert np.abs(nearest_copy_distance(user, pts) - 0.3).max() < 1e-13
    end = np.c_[fin.x_final.values, fin.y_final.values]
    assert np.array_equal(np.c_[fin.cell_a1_final.values, fin.cell_a2_final.values], cell_of(end, user.lattice))


def test_stop_below_in_user_coordinates():
    user = CASES["Galton board, shifted origin"][0]("no-slip")
    ds = simulate_many(user, [(2.0, 0.5), (2.1, 0.6)], [(0.3, 0.9), (-0.2, 0.5)], max_collisions=10**5,
                       stop_below=-20.0, scheduler="sync")
    assert (ds.stop_reason.values == layout.STOP_LEVEL).all()
    assert (ds.y_final.values == -20.0).all()
    one = simulate(user, (2.0, 0.5), (0.3, 0.9), max_collisions=10**5, stop_below=-20.0)
    assert float(one.y_final) == -20.0 and float(one.x_final) == float(ds.x_final[0])
