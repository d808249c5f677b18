"""Junction points gate the corner pass: they must be found wherever two elements meet."""
import math

import numpy as np
import pytest

from noslipsim import Circle, Scene, Segment, simulate, tables
from noslipsim.junctions import junction_arrays

from invariants import leak_depth


def junctions(scene):
    start, pts = junction_arrays(scene)
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
