"""Junction points gate the corner pass: they must be found wherever two elements meet."""
import math

import numpy as np
import pytest
from invariants import leak_depth

from noslipsim import Circle, Scene, Segment, simulate, tables
from noslipsim._engine.table import kernel_table


def junctions(scene):
    table = kernel_table(scene)
    start, pts = table.jstart, table.jpts
    return [pts[start[i]:start[i + 1]] for i in range(len(scene.elements))]


def test_polygon_vertices_are_junctions():
    poly = tables.regular_polygon(5)
    for i, pts in enumerate(junctions(poly)):
        e = poly.elements[i]
        np.testing.assert_allclose(sorted(map(tuple, pts)), sorted([e.p0, e.p1]), atol=1e-12)


def test_isolated_disk_has_none_and_tangent_disks_do():
    assert len(junctions(tables.rectangle(2, 1, disks=[(1, 0.5, 0.2)]))[4]) == 0
    assert len(junctions(tables.galton_board())[0]) == 0
    touching = tables.sinai_torus(0.5 - 1e-13)
    assert len(junctions(touching)[0]) == 4


def test_t_junction_and_arc_tips():
    scene = Scene((Circle((0.0, 0.0), 1.0, "inside"), Segment((0.0, -1.0), (0.0, 0.0), "left")))
    j = junctions(scene)
    np.testing.assert_allclose(j[0], [[0.0, -1.0]], atol=1e-12)
    lemon = junctions(tables.lemon())
    assert all(len(p) == 2 for p in lemon)


@pytest.mark.parametrize("angle", [1e-1, 1e-2, 1e-3])
@pytest.mark.parametrize("law", ["specular", "no-slip"])
def test_acute_corners_never_leak(angle, law):
    """A thin triangle: flights run deep into its acute corner, where the contact band is longest."""
    h = math.tan(angle)
    tri = tables.polygon([(0.0, 0.0), (1.0, -h), (1.0, h)], law=law)
    ds = simulate(tri, (0.9, 0.0), (-1.0, 0.3 * h), 0.1, max_collisions=3000)
    assert ds.attrs["stop_reason"] in ("max_collisions", "corner")
    assert leak_depth(tri, ds) >= -1e-12


def _all_pairs(scene):
    """Slow twin of junction_arrays on a plain scene: every pair of elements, no box filter."""
    from noslipsim._engine.junctions import _ON_TOL, _meet

    tol = _ON_TOL * scene.scale
    per = [[] for _ in scene.elements]
    for a, ea in enumerate(scene.elements):
        for b in range(a + 1, len(scene.elements)):
            for p in _meet(ea, scene.elements[b], tol):
                per[a].append(p)
                per[b].append(p)
    return [np.unique(np.round(np.array(lst, float).reshape(-1, 2), 12), axis=0) for lst in per]


@pytest.mark.parametrize("seed", range(8))
def test_box_filter_misses_no_junction(seed):
    """Skipping pairs whose bounding boxes are apart finds the same junctions as testing every pair."""
    from noslipsim import Line

    rng = np.random.default_rng(seed)
    elements = []
    for _ in range(14):
        if rng.random() < 0.5:
            elements.append(Circle(tuple(rng.uniform(-1, 1, 2)), float(rng.uniform(0.05, 0.8))))
        else:
            elements.append(Segment(tuple(rng.uniform(-1, 1, 2)), tuple(rng.uniform(-1, 1, 2))))
    # pieces that only touch at a box edge or a vertex, and an infinite line (unbounded box)
    elements += [Segment((1.5, 0.0), (2.0, 0.0)), Segment((2.0, 0.0), (2.0, 0.5)), Line((0.0, -2.0), (0.0, 1.0))]
    scene = Scene(tuple(elements))
    for got, want in zip(junctions(scene), _all_pairs(scene)):
        np.testing.assert_array_equal(got, want)
