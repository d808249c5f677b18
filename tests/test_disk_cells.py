"""The lean disk loop (core/disks.py) with several disks per cell, or disks reaching into neighbouring cells.

A lattice of disjoint disk scatterers without force (``KernelTable.disk_lattice``)
runs the lean loop whatever the number of disks per cell: the walk tests
every disk copy that reaches a cell and takes the earliest hit once it comes
before the cell's exit.  It uses other formulas than the general loop, so the
two agree to rounding: each flight is restarted from the same state in both
loops (the state just after a collision of a general-path orbit, on the disk
just hit) and the next collision must agree to 1e-12.  The scenes are the
kernels' own (canonical) scenes, as ``simulate`` runs them.
"""
import functools
import math

import numpy as np
import pytest
from lean_kernels import LOG, NONE, PORTRAIT, kernels, run, same_stop

from noslipsim import Circle, Scene, Segment, simulate, simulate_many, tables
from noslipsim._engine.canonical import canonical_form
from noslipsim._engine.lattice import cell_origin, lattice_matrix
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout
from noslipsim.core.disks import disk_lattice_kernel
from noslipsim.core.loop import orbit_kernel

SQUARE = {"a1": [1.0, 0.0], "a2": [0.0, 1.0]}
HEX = {"a1": [1.0, 0.0], "a2": [0.5, math.sqrt(3.0) / 2.0]}

#: Disks (cx, cy, r) of the user scenes; the kernels run their canonical forms.
USER_DISKS = {
    # two disks inside the cell after the canonical translation (no copy shifted)
    "two disks": ([(0.25, 0.25, 0.2), (0.75, 0.75, 0.15)], SQUARE),
    # two disks, one reaching into the neighbouring cells
    "two disks, reaching": ([(0.1, 0.5, 0.3), (0.62, 0.5, 0.15)], SQUARE),
    # the scattered Lorentz gas: five disks of different radii
    "five disks": ([(0.1, 0.1, 0.08), (0.5, 0.2, 0.12), (0.3, 0.6, 0.1), (0.75, 0.7, 0.15), (0.85, 0.3, 0.06)],
                   SQUARE),
    # a honeycomb: two disks per cell of the triangular lattice
    "honeycomb": ([(0.0, 0.0, 0.2), (0.5, math.sqrt(3.0) / 6.0, 0.2)], HEX),
}


def user_scene(name, law="specular"):
    disks, lattice = USER_DISKS[name]
    return Scene(tuple(Circle((x, y), r) for x, y, r in disks), law=law, lattice=lattice)


def kernel_scene(name, law="specular"):
    """The scene the kernels run (canonical form); one disk reaching its neighbours: the hexagonal cell at 0.45."""
    if name == "hex_0.45":
        return tables.hex_lorentz_cell(0.45, law=law)
    return canonical_form(user_scene(name, law)).scene


NAMES = [*USER_DISKS, "hex_0.45"]
CASES = [(name, law) for name in NAMES for law in ("specular", "no-slip")]


def start_of(name):
    """A start inside the table of the kernel scene (relative to cell 0)."""
    scene = kernel_scene(name)
    for q in ((0.45, 0.1), (0.0, 0.45), (0.45, -0.3), (-0.3, 0.45), (0.02, -0.45)):
        if scene.depth(np.array([q]))[0] > 1e-3:
            return q
    raise AssertionError(name)


@functools.cache
def on_own_copy(name, law, e, o1, o2):
    """The kernel scene with element ``e`` moved by ``o1 a1 + o2 a2`` (the same billiard): its copy
    ``(e, 0, 0)`` is then the disk of that offset, so a restart can deflate it (``start_element``)."""
    scene = kernel_scene(name, law)
    if o1 == 0 and o2 == 0:
        return scene
    A, _ = lattice_matrix(scene.lattice)
    dx, dy = A @ np.array([o1, o2], float)
    elements = list(scene.elements)
    elements[e] = elements[e].shifted(dx, dy)
    return scene.replace(elements=tuple(elements))


def disk_offset(scene, e, q):
    """Lattice offset of the copy of disk ``e`` on which the point ``q`` (relative to its cell) lies."""
    A, _ = lattice_matrix(scene.lattice)
    d = np.asarray(q) - np.asarray(scene.elements[e].center)
    cands = [(o1, o2) for o1 in range(-2, 3) for o2 in range(-2, 3)]
    dist = [abs(np.hypot(*(d - A @ np.array(o, float))) - scene.elements[e].radius) for o in cands]
    k = int(np.argmin(dist))
    assert dist[k] < 1e-9
    return cands[k]


def test_dispatch_takes_disjoint_disks_without_force():
    lean = disk_lattice_kernel(False, None)  # a recording run (LOG) reads its mode at run time
    for name in NAMES:
        scene = kernel_scene(name)
        assert kernel_table(scene).disk_lattice is True and kernel_table(scene).one_disk_per_cell is False
        assert orbit_kernel(*kernel_table(scene).variant(LOG)) is lean
        assert kernel_table(canonical_form(user_scene(name) if name != "hex_0.45" else scene).scene).disk_lattice
    torus = kernel_table(tables.sinai_torus(0.25))
    assert torus.disk_lattice and torus.one_disk_per_cell
    # disks inside the cell (no copy shifted) and disks reaching into neighbouring cells are both covered
    shifted = {name: bool(kernel_table(kernel_scene(name)).arrays()[2][:, 1:].any()) for name in NAMES}
    assert shifted == {"two disks": False, "two disks, reaching": True, "five disks": True, "honeycomb": False,
                       "hex_0.45": True}


@pytest.mark.parametrize("scene", [
    Scene((Circle((0.25, 0.25), 0.2), Circle((0.5, 0.5), 0.2)), lattice=SQUARE),  # two disks overlap
    Scene((Circle((0.25, 0.25), 0.25), Circle((0.75, 0.25), 0.25)), lattice=SQUARE),  # touching
    Scene((Circle((0.25, 0.0), 0.25), Circle((0.75, 0.0), 0.25 - 1e-12)), lattice=SQUARE),  # within the gap
    Scene((Circle((0.25, 0.25), 0.25), Circle((100.75, -29.75), 0.25)), lattice=SQUARE),  # touching, written apart
    Scene((Circle((0.0, 0.0), 0.5),), lattice=SQUARE),  # a disk touching its own copies
    Scene((Circle((0.0, 0.0), 0.2), Circle((0.5, 0.5), 0.1)), lattice=SQUARE, force=(0.0, -1.0)),  # force
    Scene((Circle((0.0, 0.0), 0.2), Segment((0.3, 0.3), (0.4, 0.4))), lattice=SQUARE),  # not only disks
    Scene((Circle((0.0, 0.0), 0.2), Circle((0.0, 0.0), 0.45, "inside")), lattice=SQUARE),  # a container
    Scene((Circle((0.0, 0.0), 0.2), Circle((0.5, 0.5), 0.1))),  # no lattice
], ids=["overlap", "touch", "within gap", "touch, written apart", "own copies touch", "force", "segment", "container",
        "plain"])
def test_dispatch_refuses_what_the_lean_loop_cannot_run(scene):
    assert kernel_table(scene).disk_lattice is False
    assert kernel_table(canonical_form(scene).scene).variant(LOG).disks is False


def test_gap_between_lattice_copies_decides():
    apart = Scene((Circle((0.0, 0.0), 0.3), Circle((0.5, 0.5), 0.4)), lattice=SQUARE)
    assert kernel_table(apart).disk_lattice  # 0.3 + 0.4 < 1/sqrt(2)
    close = Scene((Circle((0.0, 0.0), 0.3), Circle((0.5, 0.5), 0.42)), lattice=SQUARE)
    assert not kernel_table(close).disk_lattice  # overlaps the copy at (1, 1) (and every other corner)


@pytest.mark.parametrize("name,law", CASES)
def test_every_flight_agrees_with_the_general_path(name, law):
    """Restart each flight from the general path's state after a collision: same next collision to 1e-12."""
    scene = kernel_scene(name, law)
    general, lean = kernels(scene, LOG)
    n = 1000
    out, log = run(general, scene, start_of(name), (math.cos(0.7), math.sin(0.7)), 0.1, n)
    assert out[0] == n
    worst = 0.0
    hit = set()
    for k in range(n - 1):
        row = log[k]
        cell = row[[layout.LOG_CELL_A1, layout.LOG_CELL_A2]].astype(np.int64)
        q = row[[layout.LOG_X, layout.LOG_Y]] - cell_origin(cell, scene.lattice)
        e = int(row[layout.LOG_ELEMENT])
        o = disk_offset(scene, e, q)
        hit.add((e, o))
        twin = on_own_copy(name, law, e, *o)
        start = (q, row[[layout.LOG_VX, layout.LOG_VY]], row[layout.LOG_W])
        out_g, rec_g = run(general, twin, *start, 1, start_element=e)
        out_l, rec_l = run(lean, twin, *start, 1, start_element=e)
        assert out_l[:2] == out_g[:2] == (1, layout.STOP_MAX_COLLISIONS), k
        assert out_l[10:] == out_g[10:], f"flight {k}: other cell"
        g, l_ = rec_g[0], rec_l[0]
        assert l_[layout.LOG_ELEMENT] == g[layout.LOG_ELEMENT] and l_[layout.LOG_CORNER] == 0.0
        assert (l_[layout.LOG_CELL_A1], l_[layout.LOG_CELL_A2]) == (g[layout.LOG_CELL_A1], g[layout.LOG_CELL_A2])
        scale = max(1.0, g[layout.LOG_T])  # a long flight's position is good to eps times its length
        for col in (layout.LOG_T, layout.LOG_X, layout.LOG_Y, layout.LOG_VX, layout.LOG_VY, layout.LOG_W,
                    layout.LOG_VX_IN, layout.LOG_VY_IN, layout.LOG_W_IN):
            err = abs(l_[col] - g[col]) / scale
            worst = max(worst, err)
            assert err < 1e-12, (k, col, l_[col], g[col])
        assert l_[layout.LOG_S] == pytest.approx(g[layout.LOG_S], abs=1e-9 * scale)
    assert worst > 0.0  # the two loops really are different arithmetic
    assert len({e for e, _ in hit}) == len(scene.elements)  # every disk was hit
    if kernel_table(scene).arrays()[2][:, 1:].any():
        assert any(o != (0, 0) for _, o in hit)  # ... and a copy from a neighbouring cell


@pytest.mark.parametrize("law", ["specular", "no-slip"])
@pytest.mark.parametrize("name", ["two disks, reaching", "five disks"])
def test_portrait_records_agree(name, law):
    scene = kernel_scene(name, law)
    general, lean = kernels(scene, PORTRAIT)
    q = start_of(name)
    out_g, rec_g = run(general, scene, q, (0.83, 0.41), 0.1, 12, mode=PORTRAIT)
    out_l, rec_l = run(lean, scene, q, (0.83, 0.41), 0.1, 12, mode=PORTRAIT)
    assert out_l[3] == out_g[3] == 12
    # rounding differences grow along a chaotic orbit: the first records agree closely
    np.testing.assert_allclose(rec_l[:4], rec_g[:4], rtol=0, atol=1e-11)
    assert len(set(rec_g[:, layout.POR_ELEMENT])) > 1


STOPS = ["max_time", "level", "escape", "start_on_disk"]


def stop_start(name, stop):
    """Start and stop arguments for each stop (relative to cell 0 of the kernel scene)."""
    scene = kernel_scene(name)
    q, v, kw = start_of(name), (0.83, 0.41), {}
    if stop == "max_time":
        kw = {"max_time": math.inf}
    elif stop == "level":
        v, kw = (0.3, -0.95), {"level": q[1] - 0.05}  # crossed before any collision
    elif stop == "escape":
        v = (1.0, 0.0)  # along a horizontal corridor, found below
        for y in np.linspace(-0.5, 0.5, 201):
            if all(abs(y - e.center[1] - k) > e.radius + 1e-3 for e in scene.elements for k in (-1, 0, 1)):
                q = (0.0, float(y))
                break
        else:
            raise AssertionError(name)
    elif stop == "start_on_disk":
        e = scene.elements[-1]
        q, v, kw = (e.center[0] + e.radius, e.center[1]), (0.6, 0.8), {"start_element": len(scene.elements) - 1,
                                                                          "max_time": math.inf}
    return q, v, kw


@pytest.mark.parametrize("law", ["specular", "no-slip"])
@pytest.mark.parametrize("stop", STOPS)
@pytest.mark.parametrize("name", ["two disks", "five disks"])
def test_stops_agree_with_the_general_path(name, stop, law):
    scene = kernel_scene(name, law)
    q, v, kw = stop_start(name, stop)
    if "max_time" in kw:  # between the 4th and 5th collisions: before chaos separates the two orbits
        log = run(kernels(scene, LOG)[0], scene, q, v, 0.1, 5, **kw)[1]
        kw["max_time"] = 0.5 * (log[3, layout.LOG_T] + log[4, layout.LOG_T])
    out_g = same_stop(scene, stop, q, v, kw)
    assert out_g[0] == (4 if stop in ("max_time", "start_on_disk") else 0)


@pytest.mark.parametrize("name", ["two disks", "two disks, reaching", "five disks"])
def test_public_api_runs_the_lean_loop_and_keeps_chunking_invariance(name):
    scene = user_scene(name, "no-slip")
    assert kernel_table(canonical_form(scene).scene).variant(NONE).disks is True
    rng = np.random.default_rng(3)
    q = []
    while len(q) < 9:  # starts inside the table, in the user's coordinates
        p = rng.uniform(-2.0, 2.0, 2)
        if scene.depth(p[None])[0] > 1e-3:
            q.append(p)
    phi = rng.uniform(0, 2 * np.pi, 9)
    v = np.c_[np.cos(phi), np.sin(phi)]
    a = simulate_many(scene, np.array(q), v, np.zeros(9), max_collisions=500, chunk_size=2)
    b = simulate_many(scene, np.array(q), v, np.zeros(9), max_collisions=500, chunk_size=9, scheduler="sync")
    assert a.equals(b)
    assert (a.n_collisions == 500).all()
    # a single orbit gives the same final state as the ensemble's orbit (same kernel, same start)
    ds = simulate(scene, q[4], v[4], 0.0, max_collisions=500)
    assert float(ds.x_final) == float(a.x_final[4]) and float(ds.spin_final) == float(a.spin_final[4])
    # every collision lies on a disk of the user's scene, in the cell reported
    A, _ = lattice_matrix(scene.lattice)
    pts = np.c_[ds.x, ds.y] - cell_origin(np.c_[ds.cell_a1, ds.cell_a2], scene.lattice)
    for p, e in zip(pts, ds.element.values):
        disk = scene.elements[e]
        gaps = [abs(np.hypot(*(p - disk.center - A @ np.array([o1, o2], float))) - disk.radius)
                for o1 in (-1, 0, 1) for o2 in (-1, 0, 1)]
        assert min(gaps) < 1e-9
