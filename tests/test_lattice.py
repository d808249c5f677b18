"""Periodic lattices: cell walk against explicit copies, corridors, Santaló's formula."""
import math

import numpy as np
import pytest

from noslipsim import Circle, Scene, Segment, simulate, simulate_many, tables
from noslipsim._engine.lattice import cell_of, covering_radius, disks_cover_plane, element_cells, reaching_copies
from noslipsim._engine.table import kernel_table


def explicit_copies(scene, cells):
    """The same table written out with one element per copy, over a block of cells."""
    A = np.array([scene.lattice["a1"], scene.lattice["a2"]]).T
    (i0, j0), (i1, j1) = cells
    elems = [e.shifted(*(A @ [i, j])) for i in range(i0, i1 + 1) for j in range(j0, j1 + 1) for e in scene.elements]
    return Scene(tuple(elems), law=scene.law, gamma=scene.gamma, force=scene.force)


def mid_flight(scene, ds, k):
    """State halfway along the flight after collision ``k``."""
    tau = 0.5 * float(ds.t[k + 1] - ds.t[k])
    ax, ay = scene.force
    q = (float(ds.x[k] + ds.vx[k] * tau + 0.5 * ax * tau ** 2), float(ds.y[k] + ds.vy[k] * tau + 0.5 * ay * tau ** 2))
    v = (float(ds.vx[k] + ax * tau), float(ds.vy[k] + ay * tau))
    return q, v, float(ds.spin[k]), tau


LATTICES = {
    "sinai_torus": (tables.sinai_torus(0.3), (0.4, 0.1), (0.7, 0.31)),
    "hex_lorentz": (tables.hex_lorentz_cell(0.3), (0.4, 0.1), (0.7, 0.31)),
    "galton": (tables.galton_board(), (1.0, 0.0), (0.3, 0.95)),
    "sinai_gravity_tilted": (tables.sinai_torus(0.2, force=(0.1, -0.3)), (0.4, 0.1), (0.7, 0.31)),
}


@pytest.mark.parametrize("name", sorted(LATTICES))
def test_every_flight_matches_explicit_copies(name):
    scene, q, v = LATTICES[name]
    ds = simulate(scene, q, v, 0.2, max_collisions=150)
    checked = 0
    for k in range(0, len(ds.t) - 1, 3):
        start, vel, spin, tau = mid_flight(scene, ds, k)
        ends = cell_of(np.array([start, (float(ds.x[k + 1]), float(ds.y[k + 1]))]), scene.lattice)
        if np.abs(ends[1] - ends[0]).max() > 6:
            # a plain scene loses digits on long flights (|q - c|^2 - r^2 cancels at |q - c| >> r);
            # those are checked against exact arithmetic in test_long_corridor_flights_keep_their_digits
            continue
        checked += 1
        flat = explicit_copies(scene, (tuple(ends.min(axis=0) - 3), tuple(ends.max(axis=0) + 3)))
        nxt = simulate(flat, start, vel, spin, max_collisions=1)
        assert int(nxt.n_collisions) == 1, f"collision {k + 1} not found in the explicit scene"
        t_next = float(ds.t[k]) + tau + float(nxt.t[0])
        assert t_next == pytest.approx(float(ds.t[k + 1]), rel=1e-11, abs=1e-11)
        for name_ in ("x", "y", "vx", "vy", "spin"):
            assert float(nxt[name_][0]) == pytest.approx(float(ds[name_][k + 1]), rel=1e-10, abs=1e-10), name_
    assert checked >= 30


@pytest.mark.parametrize("slope", [1e-3, 2e-3, 3e-4, -7e-4])
def test_long_corridor_flights_keep_their_digits(slope):
    """First hit of a long nearly-corridor flight vs exact line-circle intersection at 50 digits."""
    import mpmath as mp
    mp.mp.dps = 50
    r = 0.1
    scene = tables.sinai_torus(r, law="specular")
    q = (0.5, 0.23 if slope > 0 else 0.77)
    v = np.array([1.0, slope]) / np.hypot(1.0, slope)
    ds = simulate(scene, q, v, 0.0, max_collisions=1)
    cx = mp.mpf(int(ds.cell_a1[0]))
    cy = mp.mpf(int(ds.cell_a2[0]))
    dx, dy = mp.mpf(q[0]) - cx, mp.mpf(q[1]) - cy
    vx, vy = mp.mpf(v[0]), mp.mpf(v[1])
    b = dx * vx + dy * vy
    c = dx * dx + dy * dy - mp.mpf(r) ** 2
    a = vx * vx + vy * vy
    t = (-b - mp.sqrt(b * b - a * c)) / a
    assert float(ds.t[0]) > 20  # a long flight indeed
    assert float(ds.t[0]) == pytest.approx(float(t), rel=1e-13)
    assert float(ds.y[0]) == pytest.approx(float(mp.mpf(q[1]) + vy * t), rel=1e-13, abs=1e-13)


def test_first_collisions_identical_to_explicit_copies():
    """Whole-orbit comparison: rounding differences grow ~10x per collision on the
    Galton board (chaos), so positions agree to 1e-12 over the first collisions and
    the pegs hit agree further; every single flight is checked in the test above."""
    scene, q, v = LATTICES["galton"]
    flat = explicit_copies(scene, ((-12, -12), (12, 12)))
    a = simulate(scene, q, v, 0.1, max_collisions=10)
    b = simulate(flat, q, v, 0.1, max_collisions=10)
    np.testing.assert_allclose(a.x.values[:5], b.x.values[:5], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(a.t.values[:5], b.t.values[:5], rtol=1e-12)
    pegs_flat = cell_of(np.array([flat.elements[i].center for i in b.element.values]), scene.lattice)
    np.testing.assert_array_equal(pegs_flat[:, 0], a.cell_a1.values)
    np.testing.assert_array_equal(pegs_flat[:, 1], a.cell_a2.values)


def chord_misses(scene, ds, radius):
    """Smallest (distance from a disk centre to a flight chord) - radius over all flights (no force)."""
    p0 = np.c_[ds.x.values[:-1], ds.y.values[:-1]]
    p1 = np.c_[ds.x.values[1:], ds.y.values[1:]]
    A = np.array([scene.lattice["a1"], scene.lattice["a2"]]).T
    worst = np.inf
    for a, b in zip(p0, p1):
        lo = cell_of(np.minimum(a, b), scene.lattice) - 2
        hi = cell_of(np.maximum(a, b), scene.lattice) + 2
        ii, jj = np.meshgrid(np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1))
        centres = np.c_[ii.ravel(), jj.ravel()] @ A.T
        d = b - a
        u = np.clip(((centres - a) @ d) / (d @ d), 0.0, 1.0)
        dist = np.hypot(*(a + u[:, None] * d - centres).T)
        # the two disks the chord ends on are touched at its ends: skip those
        ends = (np.hypot(*(centres - a).T) <= radius * (1 + 1e-9)) | (np.hypot(*(centres - b).T) <= radius * (1 + 1e-9))
        dist = dist[~ends]
        if dist.size:
            worst = min(worst, float(dist.min() - radius))
    return worst


@pytest.mark.parametrize("direction", [(1.0, 1e-4), (1.0, 1.0 + 1e-5), (2.0, 1.0 + 3e-6), (1e-7, 1.0), (3.0, -1.0)])
@pytest.mark.parametrize("law", ["specular", "no-slip"])
def test_no_collision_missed_in_corridors(direction, law):
    r = 0.05
    scene = tables.sinai_torus(r, law=law)
    d = np.array(direction) / np.hypot(*direction)
    ds = simulate(scene, (0.5, 0.5 - 1e-3), d, 0.0, max_collisions=300)
    assert ds.attrs["stop_reason"] == "max_collisions"
    assert chord_misses(scene, ds, r) > -1e-10


def test_orbit_exactly_along_a_corridor_escapes():
    scene = tables.sinai_torus(0.1)
    ds = simulate(scene, (0.5, 0.5), (1.0, 0.0), 0.0, max_collisions=10)
    assert ds.attrs["stop_reason"] == "escape" and int(ds.n_collisions) == 0


def test_corridor_flight_with_time_limit_stops_at_the_limit():
    scene = tables.sinai_torus(0.1)
    ds = simulate(scene, (0.5, 0.5), (1.0, 0.0), 0.0, max_collisions=10, max_time=1e4)
    assert ds.attrs["stop_reason"] == "max_time"
    assert float(ds.x_final) == pytest.approx(0.5 + 1e4)
    assert int(ds.cell_a1_final) == round(0.5 + 1e4)


@pytest.mark.parametrize("r", [0.1, 0.25, 0.4])
def test_santalo_mean_free_path(r):
    """Specular Sinai torus: mean free path = pi |Q| / |dQ| = (1 - pi r^2) / (2 r)."""
    scene = tables.sinai_torus(r, law="specular")
    total, count = 0.0, 0
    for ang in (0.3, 1.1, 2.0):
        ds = simulate(scene, (0.45, 0.1), (math.cos(ang), math.sin(ang)), 0.0, max_collisions=200_000)
        total += float(ds.t[-1] - ds.t[0])
        count += len(ds.t) - 1
    expected = (1 - math.pi * r * r) / (2 * r)
    assert total / count == pytest.approx(expected, rel=0.01)


def test_unfolded_positions_and_cells_agree():
    scene, q, v = LATTICES["hex_lorentz"]
    ds = simulate(scene, q, v, 0.0, max_collisions=500)
    cells = cell_of(np.c_[ds.x.values, ds.y.values], scene.lattice)
    # a collision point on a disk can sit on the cell edge only if r > half the cell: not here
    np.testing.assert_array_equal(cells[:, 0], ds.cell_a1.values)
    np.testing.assert_array_equal(cells[:, 1], ds.cell_a2.values)
    assert np.all(np.abs(ds.energy - ds.energy[0]) < 1e-13)


def test_start_in_any_cell():
    scene = tables.sinai_torus(0.3)
    a = simulate(scene, (0.4, 0.1), (0.7, 0.31), 0.0, max_collisions=5)
    b = simulate(scene, (0.4 + 7, 0.1 - 3), (0.7, 0.31), 0.0, max_collisions=5)
    np.testing.assert_allclose(b.x.values - 7, a.x.values, atol=1e-13)
    np.testing.assert_array_equal(b.cell_a1.values - 7, a.cell_a1.values)
    with pytest.raises(ValueError, match="position"):
        simulate(scene, (5.0, -2.0), (1.0, 0.0))  # inside a disk copy


def test_reaching_copies():
    lat = {"a1": [1.0, 0.0], "a2": [0.0, 1.0]}
    assert reaching_copies([Circle((0.0, 0.0), 0.3)], lat).tolist() == [[0, 0, 0]]
    corner = reaching_copies([Circle((0.5, 0.5), 0.1)], lat)
    assert sorted(map(tuple, corner[:, 1:].tolist())) == [(-1, -1), (-1, 0), (0, -1), (0, 0)]
    seg = reaching_copies([Segment((-0.2, 0.0), (1.3, 0.0))], lat)
    assert sorted(map(tuple, seg[:, 1:].tolist())) == [(-1, 0), (0, 0)]


def test_lattice_rejects_infinite_lines():
    with pytest.raises(ValueError, match="infinite lines"):
        Scene.from_dict({"elements": [{"type": "line", "point": [0, 0], "normal": [0, 1]}],
                         "lattice": {"a1": [1, 0], "a2": [0, 1]}})


def test_unit_cell_polygon_is_the_centred_ccw_cell():
    from noslipsim._engine.lattice import unit_cell_polygon
    square = unit_cell_polygon({"a1": [1.0, 0.0], "a2": [0.0, 1.0]})
    np.testing.assert_allclose(square, [[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
    tri = unit_cell_polygon(tables.hex_lorentz_cell().lattice)
    area = 0.5 * np.sum(tri[:, 0] * np.roll(tri[:, 1], -1) - np.roll(tri[:, 0], -1) * tri[:, 1])
    assert area == pytest.approx(math.sqrt(3) / 2)


@pytest.mark.parametrize("scene", [tables.sinai_torus(0.25), tables.sinai_torus(0.02), tables.hex_lorentz_cell(0.3),
                                   tables.galton_board().replace(force=(0.0, 0.0))], ids=str)
@pytest.mark.parametrize("t_limit", [1e5, pytest.param(1e6, marks=pytest.mark.stress)])
def test_straight_grid_walk_matches_strip_walk(scene, t_limit):
    """The incremental walk of straight flights finds the hits of the strip-exit walk (its twin).

    The twin is the walk under a force, given a zero force: quadratic strip exits
    re-centred at each cell, and the element test at the force's degree.  Same
    element copy, same time to rounding; near-lattice directions and starts on
    cell faces included.  Corridor flights walk up to ``t_limit`` cells, far past
    ``FAR_CELLS`` (the exactly re-centred far walks); ``-m stress`` walks 1e6.
    """
    from noslipsim.core.cells import lattice_walk
    from noslipsim.core.tolerances import EXTENT_TOL

    kinds, params, copies, A, B, _, _, _ = kernel_table(scene).arrays()
    straight_walk, falling_walk = lattice_walk(falling=False), lattice_walk(falling=True)
    r = float(params[0, 2])
    rng = np.random.default_rng(11)
    directions = [(1.0, 1e-9), (1.0, -3e-5), (1e-12, 1.0), (1.0, 1.0), (-1.0, 1.0 + 1e-7)]
    checked = 0
    for i in range(3000):
        ab = rng.uniform(-0.5, 0.5, 2)
        if i % 7 == 0:
            ab[i % 2] = 0.5 * rng.choice([-1.0, 1.0])  # on a face of cell 0
        x, y = A @ ab
        if math.hypot(x, y) <= r * (1 + 1e-9):
            continue
        phi = rng.uniform(0, 2 * math.pi)
        vx, vy = directions[i % 5] if i % 3 == 0 else (math.cos(phi), math.sin(phi))
        args = (-1, 0, 0, t_limit, EXTENT_TOL * scene.scale, 10_000_000)
        straight = straight_walk(kinds, params, copies, A, B, x, y, vx, vy, 0.0, 0.0, *args)
        twin = falling_walk(kinds, params, copies, A, B, x, y, vx, vy, 0.0, 0.0, *args)
        if twin[4] == 2 and twin[0] < math.inf:  # a hit after FAR_CELLS, under a "force": status 2, finite time
            twin = (*twin[:4], 0)
        assert straight[1:] == twin[1:], (x, y, vx, vy, straight, twin)
        if straight[4] == 0:
            assert straight[0] == pytest.approx(twin[0], rel=1e-12, abs=1e-12), (x, y, vx, vy)
            checked += 1
    assert checked > 2000


def test_a_start_beyond_exact_cell_indices_is_refused_by_name():
    """Past 2**52 cells the cell index and origin are not exact (past 2**63 the int64 cast is garbage)."""
    scene = tables.sinai_torus(0.25)
    far = (2.0 ** 53, 0.3)
    with pytest.raises(ValueError, match=r"^position: .*2\*\*52 cells"):
        simulate(scene, far, (1.0, 0.2), 0.0, max_collisions=3)
    with pytest.raises(ValueError, match=r"^positions: "):
        simulate_many(scene, [(0.4, 0.4), (1e300, 0.3)], [(1.0, 0.2)] * 2, [0.0, 0.0], max_collisions=3,
                      scheduler="sync")
    near = simulate(scene, (2.0 ** 40, 0.3), (1.0, 0.2), 0.0, max_collisions=3)
    assert int(near.n_collisions) == 3 and float(near.x_final) > 2.0 ** 40


# ---------------------------------------------------------------------------- lattices whose disks cover the plane
TRIANGULAR = {"a1": [1.0, 0.0], "a2": [0.5, math.sqrt(3.0) / 2.0]}
SQUARE = {"a1": [1.0, 0.0], "a2": [0.0, 1.0]}


def _scaled_lattice(lattice, d, skew=0):
    """``lattice`` times ``d``, written in a basis ``a1, a2 + skew a1`` (the same lattice)."""
    a1, a2 = np.array(lattice["a1"]) * d, np.array(lattice["a2"]) * d
    return {"a1": a1.tolist(), "a2": (a2 + skew * a1).tolist()}


@pytest.mark.parametrize("lattice, edge, hole", [(TRIANGULAR, 1.0 / math.sqrt(3.0), (0.5, math.sqrt(3.0) / 6.0)),
                                                 (SQUARE, 1.0 / math.sqrt(2.0), (0.5, 0.5))])
@pytest.mark.parametrize("d, skew", [(1.0, 0), (2.5, 0), (1.0, 3), (0.01, -2)])
def test_a_disk_covering_the_plane_is_refused_where_the_scene_is_made(lattice, edge, hole, d, skew):
    # R >= d/sqrt(3) (triangular) or d/sqrt(2) (square): the disks' copies cover the plane, the table is empty;
    # such a scene used to be accepted until a start was drawn
    lat = _scaled_lattice(lattice, d, skew)
    centre = (0.3 * d, -0.1 * d)  # anywhere in the cell
    below = Scene((Circle(centre, edge * d * (1 - 1e-6)),), lattice=lat)
    assert below.contains(np.array(centre) + d * np.array(hole))  # the deepest hole, edge * d from the nearest sites
    for R in (edge * d * (1 + 1e-6), edge * d * 1.5):
        with pytest.raises(ValueError, match=r"^elements\[0\]\.radius: .* covering radius .* table is empty"):
            Scene((Circle(centre, R),), lattice=lat)
        with pytest.raises(ValueError, match=r"^elements\[1\]\.radius: .* covering radius"):
            Scene.from_dict({"elements": [{"type": "segment", "p0": [0, 0], "p1": [0.1 * d, 0]},
                                          {"type": "circle", "center": list(centre), "radius": R}], "lattice": lat})


def test_the_covering_radius_is_the_farthest_distance_from_the_lattice():
    rng = np.random.default_rng(3)
    for _ in range(20):
        a1, a2 = rng.normal(size=2), rng.normal(size=2)
        if abs(a1[0] * a2[1] - a1[1] * a2[0]) < 0.2:
            continue
        lat = {"a1": a1.tolist(), "a2": a2.tolist()}
        A = np.c_[a1, a2]
        # brute force: sample the cell densely, distance to the nearest of many lattice sites
        u = rng.uniform(-0.5, 0.5, (20_000, 2)) @ A.T
        n = np.arange(-8, 9)
        sites = np.stack(np.meshgrid(n, n), -1).reshape(-1, 2) @ A.T
        far = np.hypot(u[:, None, 0] - sites[None, :, 0], u[:, None, 1] - sites[None, :, 1]).min(axis=1).max()
        assert far <= covering_radius(lat) * (1 + 1e-12)
        assert far >= covering_radius(lat) * (1 - 2e-2)


@pytest.mark.parametrize("r, covered", [(0.49, False), (0.4999, False), (0.5, False), (0.5001, True), (0.6, True)])
def test_several_disks_are_refused_only_when_certainly_covering(r, covered):
    # disks at the corners and the centre of the unit square: the points (1/2, 0) are 1/2 from four of them, so
    # r > 1/2 covers the plane; r = 1/2 leaves nothing but boundary points (not shown covered: accepted)
    elements = (Circle((0.0, 0.0), r), Circle((0.5, 0.5), r))
    assert disks_cover_plane([(e.center, e.radius) for e in elements], SQUARE) == covered
    if covered:
        with pytest.raises(ValueError, match=r"^elements: the circles elements\[0\], elements\[1\] and .* cover"):
            Scene(elements, lattice=SQUARE)
    else:
        Scene(elements, lattice=SQUARE)


def test_a_refusal_of_several_disks_is_sound():
    # random disk sets: whenever the plane is said to be covered, no point of a dense sample lies outside every disk
    rng = np.random.default_rng(7)
    refused = 0
    for _ in range(40):
        m = int(rng.integers(2, 4))
        disks = [(tuple(rng.uniform(-0.5, 0.5, 2)), float(rng.uniform(0.3, 0.6))) for _ in range(m)]
        if not disks_cover_plane(disks, TRIANGULAR):
            continue
        refused += 1
        A = np.array([TRIANGULAR["a1"], TRIANGULAR["a2"]]).T
        n = np.arange(-3, 4)
        shifts = np.stack(np.meshgrid(n, n), -1).reshape(-1, 2) @ A.T
        pts = rng.uniform(-0.5, 0.5, (20_000, 2)) @ A.T
        gap = np.full(len(pts), np.inf)
        for c, r in disks:
            C = np.asarray(c) + shifts
            gap = np.minimum(gap, np.hypot(pts[:, None, 0] - C[None, :, 0], pts[:, None, 1] - C[None, :, 1]).min(1) - r)
        assert gap.max() <= 0.0
    assert refused >= 5


# ---------------------------------------------------------------------------- starts on a disk reaching out of its cell
def _gas(R, centre=(0.0, 0.0), skew=0, force=(0.0, 0.0), law="specular"):
    """The triangular Lorentz gas of spacing 1, its disk anywhere, its basis written ``a1, a2 + skew a1``."""
    return Scene((Circle(centre, R),), law=law, force=force, lattice=_scaled_lattice(TRIANGULAR, 1.0, skew))


def test_element_cells_is_the_copy_the_point_is_on():
    rng = np.random.default_rng(5)
    for R, centre, skew in ((0.45, (0.0, 0.0), 0), (0.5, (0.3, -0.2), 2), (0.55, (0.1, 0.4), -1)):
        scene = _gas(R, centre, skew)
        A = np.array([scene.lattice["a1"], scene.lattice["a2"]]).T
        n = rng.integers(-5, 6, size=(300, 2))
        theta = rng.uniform(0, 2 * np.pi, 300)
        pts = np.array(centre) + R * np.c_[np.cos(theta), np.sin(theta)] + n @ A.T
        np.testing.assert_array_equal(element_cells(scene.elements[0], pts, scene.lattice), n)
    # the parallelogram cell is another one for many of these points (what the callers used before)
    scene = _gas(0.45)
    top = np.array([[0.0, 0.45]])
    assert cell_of(top, scene.lattice).tolist() == [[0, 1]]
    assert element_cells(scene.elements[0], top, scene.lattice).tolist() == [[0, 0]]


@pytest.mark.parametrize("R", [0.45, 0.5])
@pytest.mark.parametrize("centre, skew, force, law", [((0.0, 0.0), 0, (0.0, 0.0), "specular"),
                                                      ((0.3, -0.2), 2, (0.0, 0.0), "no-slip"),
                                                      ((0.0, 0.0), 0, (0.05, -0.2), "no-slip")])
def test_a_start_on_a_disk_reaching_out_of_its_cell_meets_the_neighbouring_disks(R, centre, skew, force, law):
    # a boundary start on the disk where it reaches into a neighbouring parallelogram cell ran from that
    # cell, whose disk copy the kernel then skipped as the one just left: the orbit flew through it
    scene = _gas(R, centre, skew, force, law)
    rng = np.random.default_rng(11)
    theta = rng.uniform(0, 2 * np.pi, 64)
    normal = np.c_[np.cos(theta), np.sin(theta)]
    turn = theta + rng.uniform(-1.2, 1.2, 64)
    q, v = np.array(centre) + R * normal, np.c_[np.cos(turn), np.sin(turn)]
    w = rng.normal(0, 0.3, 64)
    on = simulate_many(scene, q, v, w, start_elements=[0] * 64, max_collisions=1, record="log", scheduler="sync")
    near = simulate_many(scene, q + 1e-9 * normal, v, w, max_collisions=1, record="log", scheduler="sync")
    np.testing.assert_allclose(on.t.values[:, 0], near.t.values[:, 0], rtol=0, atol=1e-7)
    for k in ("x", "y", "vx", "vy", "cell_a1", "cell_a2"):
        np.testing.assert_allclose(on[k].values[:, 0], near[k].values[:, 0], atol=1e-7, err_msg=k)
    assert (cell_of(q - np.array(centre), scene.lattice) != 0).any(axis=1).sum() > 10  # starts out of the cell
