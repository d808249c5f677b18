"""noslipsim.plot: every element kind draws, paths follow the exact flights, saved bytes are stable."""
import json
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from matplotlib.collections import LineCollection, PatchCollection
from matplotlib.patches import Circle as CirclePatch
from matplotlib.patches import FancyArrowPatch

import noslipsim as ns
from noslipsim import plot, tables
from noslipsim.elements import Arc, Circle, Line, Segment
from noslipsim.plot.numbers import check_record


def every_kind():
    """A scene with one element of every kind (a box with a scatterer, an arc cap and a container)."""
    return ns.Scene((Line((0.0, 0.0), (0.0, 1.0)),
                     Segment((2.0, 0.0), (2.0, 1.0), "right"),
                     Circle((1.0, 0.5), 0.2, "outside"),
                     Circle((1.0, 0.5), 3.0, "inside"),
                     Arc((1.0, 1.0), 1.0, 0.0, math.pi, "inside")))


def test_every_element_kind_draws(ax):
    box = plot.draw_table(ax, every_kind(), window=(-1, 3, -1, 2.5))
    assert box == (-1, 3, -1, 2.5) and ax.get_xlim() == (-1, 3) and ax.get_aspect() == 1.0
    walls = [c for c in ax.collections if isinstance(c, LineCollection)]
    fills = [c for c in ax.collections if isinstance(c, PatchCollection)]
    assert len(walls) == 1 and len(walls[0].get_segments()) == 2      # the line's chord and the segment
    chord = walls[0].get_segments()[0]
    np.testing.assert_allclose(sorted(chord[:, 0]), [-1, 3])
    np.testing.assert_allclose(chord[:, 1], 0)
    assert len(fills) == 2                                             # the shaded wall side and the disc
    assert len(ax.patches) == 2                                        # the container circle and the arc
    # the shaded side of the floor is below it: y <= 0
    shade = fills[0].get_paths()[0].vertices
    assert shade[:, 1].max() <= 0 and shade[:, 1].min() == -1


def test_wedge_walls_stop_at_the_vertex_and_shades_are_opaque(ax):
    # a wedge opening up with its vertex at the origin (y >= |x| tan 0.4), as two infinite lines
    a = 0.4
    left, right = Line((0.0, 0.0), (math.sin(a), math.cos(a))), Line((0.0, 0.0), (-math.sin(a), math.cos(a)))
    for scene in (ns.Scene((left, right)), ns.Scene((right, left))):
        ax.clear()
        plot.draw_table(ax, scene, window=(-2, 2, -1, 2))
        (walls,) = [c for c in ax.collections if isinstance(c, LineCollection)]
        for seg in walls.get_segments():
            assert seg[:, 1].min() == pytest.approx(0.0, abs=1e-12)    # ends at the vertex, not below it
            assert np.all(seg[:, 1] >= -1e-12)
        shades = next(c for c in ax.collections if isinstance(c, PatchCollection))
        assert shades.get_alpha() is None                               # overlapping shades show no darker patch
    shapes = plot.table_shapes(ns.Scene((left, right)), (-2, 2, -1, 2))
    assert all(min(ys) == pytest.approx(0.0, abs=1e-12) for _, ys in shapes["walls"])


def test_line_shut_out_by_another_line_draws_no_chord(ax):
    # two parallel floors: the lower one is behind the upper one everywhere, so it bounds nothing
    scene = ns.Scene((Line((0.0, 0.0), (0.0, 1.0)), Line((0.0, -0.5), (0.0, 1.0)), Circle((0.0, 1.0), 0.2)))
    plot.draw_table(ax, scene, window=(-1, 1, -1, 2))
    (walls,) = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert len(walls.get_segments()) == 1 and np.allclose(walls.get_segments()[0][:, 1], 0.0)


def test_line_outside_the_window_draws_no_chord(ax):
    scene = ns.Scene((Line((0.0, 5.0), (0.0, -1.0)), Circle((0.0, 0.0), 0.5)))
    plot.draw_table(ax, scene, window=(-1, 1, -1, 1))
    assert not [c for c in ax.collections if isinstance(c, LineCollection)]


def test_lattice_draws_every_peg_in_the_window(ax):
    board = tables.galton_board(2.0, 0.5, 1.0)
    plot.draw_table(ax, board, window=(-4.0, 4.0, -4.0, 0.5))
    discs = next(c for c in ax.collections if isinstance(c, PatchCollection))
    centres = np.array([(p.vertices.min(axis=0) + p.vertices.max(axis=0)) / 2 for p in discs.get_paths()])
    # the pegs whose disc meets the window, counted directly on the lattice
    want = {(round(2 * i + j, 6), round(j * math.sqrt(3), 6)) for i in range(-10, 11) for j in range(-10, 11)
            if -4.5 <= 2 * i + j <= 4.5 and -4.5 <= j * math.sqrt(3) <= 1.0}
    got = {(round(x, 6), round(y, 6)) for x, y in centres}
    assert len(centres) == len(want) and got == want


def test_scene_rebuilds_from_a_dataset_json_and_mapping():
    scene = every_kind()
    orbit = ns.simulate(tables.rectangle(2.0, 1.0), (0.5, 0.5), (1.0, 0.3), max_collisions=3)
    assert plot.scene_of(orbit) == tables.rectangle(2.0, 1.0)
    assert plot.scene_of(scene.to_json()) == scene and plot.scene_of(scene.to_dict()) == scene
    with pytest.raises(ValueError, match="scene"):
        plot.scene_of(xr.Dataset())
    with pytest.raises(ValueError, match="JSON"):
        plot.scene_of("{not json")


def test_bad_windows_are_refused(ax):
    with pytest.raises(ValueError, match="window"):
        plot.draw_table(ax, tables.half_plane())                     # a line needs a window
    with pytest.raises(ValueError, match="window"):
        plot.draw_table(ax, tables.galton_board(), window=(1, 0, 0, 1))
    with pytest.raises(ValueError, match="window"):
        plot.draw_table(ax, tables.galton_board(), window=(0, 1, 0))
    with pytest.raises(ValueError, match="cells"):
        plot.draw_table(ax, tables.galton_board(), window=(-1e4, 1e4, -1e4, 1e4))


def test_orbit_path_follows_the_exact_flights_and_stays_on_the_table():
    board = tables.galton_board(2.0, 0.9, 1.0, gamma=1.0)
    orbit = ns.simulate(board, (1.0, 0.0), (0.6, 0.8), 0.2, max_collisions=200, stop_below=-12.0)
    x, y = plot.orbit_path(orbit, points_per_flight=9)
    assert (x[0], y[0]) == (1.0, 0.0)
    assert (x[-1], y[-1]) == pytest.approx((float(orbit.x_final), float(orbit.y_final)), abs=1e-9)
    # every collision point is a sample (the end of a flight) and no sample leaves the table
    pts = np.c_[x, y]
    for k in range(int(orbit.n_collisions)):
        assert np.hypot(x - float(orbit.x[k]), y - float(orbit.y[k])).min() < 1e-9
    assert (board.depth(pts) > -1e-9).all()
    # the samples of the first flight lie on the parabola of the start state
    tau = np.linspace(0.0, float(orbit.t[0]), 9)
    np.testing.assert_allclose(x[:9], 1.0 + 0.6 * tau, atol=1e-12)
    np.testing.assert_allclose(y[:9], 0.8 * tau - 0.5 * tau ** 2, atol=1e-12)


def test_orbit_path_under_a_force_is_the_parabola_bit_for_bit():
    """Free fall is drawn as before the scene's flight took over (the paper's figures do not change)."""
    board = tables.galton_board(2.0, 0.9, 1.0, gamma=1.0)
    orbit = ns.simulate(board, (1.0, 0.0), (0.6, 0.8), 0.2, max_collisions=40, stop_below=-12.0)
    n = plot.orbit_nodes(orbit)
    ax, ay = n["force"]
    dur = np.clip(np.append(n["t"][1:], n["t_end"]) - n["t"], 0.0, None)
    tau = dur[:, None] * np.linspace(0.0, 1.0, plot.orbits.POINTS_PER_FLIGHT)[None, :]
    x, y = plot.orbit_path(orbit)
    np.testing.assert_array_equal(x, (n["x"][:, None] + n["vx"][:, None] * tau + 0.5 * ax * tau ** 2).ravel())
    np.testing.assert_array_equal(y, (n["y"][:, None] + n["vy"][:, None] * tau + 0.5 * ay * tau ** 2).ravel())


def test_orbit_path_in_a_magnetic_field_follows_the_cyclotron_arcs():
    from invariants import cyclotron_miss

    scene = tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)], law="specular").replace(magnetic=-2.0)
    orbit = ns.simulate(scene, (0.1, 0.1), (0.6, 0.8), max_collisions=10)
    n = plot.orbit_nodes(orbit)
    m = plot.orbits.POINTS_PER_FLIGHT
    x, y = plot.orbit_path(orbit)
    assert len(x) == m * len(n["t"])  # sampled along every arc: its ends alone draw the chord
    t_of = np.repeat(n["t"], m)        # selects each sample's flight
    assert cyclotron_miss(n, t_of, x, y, scene.magnetic) < 1e-9
    assert (scene.depth(np.c_[x, y]) > -1e-9).all()


def test_flight_states_fly_the_nodes_scene_and_hand_built_nodes_their_force():
    from invariants import cyclotron_miss

    nodes = {"t": np.array([0.0, 1.0]), "x": np.array([0.2, 0.4]), "y": np.array([0.3, 0.1]),
             "vx": np.array([0.6, -0.8]), "vy": np.array([0.8, 0.6]), "spin": np.array([0.0, 0.1])}
    times = np.linspace(0.0, 2.0, 9)
    field = {**nodes, "scene": tables.rectangle(1.0, 1.0).replace(magnetic=1.5)}  # no "force" key needed
    st = plot.flight_states(field, times)
    assert cyclotron_miss(field, times, st["x"], st["y"], 1.5) < 1e-12 and not plot.straight_flights(field)
    np.testing.assert_allclose(np.hypot(st["vx"], st["vy"]), 1.0, rtol=1e-14)  # a field does no work
    fall = {**nodes, "force": (0.0, -2.0)}
    st = plot.flight_states(fall, times)
    k = (times >= 1.0).astype(int)
    tau = times - nodes["t"][k]
    np.testing.assert_array_equal(st["y"], nodes["y"][k] + nodes["vy"][k] * tau - tau ** 2)
    assert plot.straight_flights({**nodes, "force": (0.0, 0.0)}) and not plot.straight_flights(fall)


def test_straight_flights_use_two_points():
    orbit = ns.simulate(tables.rectangle(2.0, 1.0), (0.5, 0.5), (1.0, 0.3), max_collisions=5)
    x, _ = plot.orbit_path(orbit)
    assert len(x) == 2 * 6


def test_orbit_inputs_are_checked(ax):
    ens = ns.simulate_many(tables.rectangle(2.0, 1.0), [[0.5, 0.5]] * 2, [[1.0, 0.3]] * 2, record="log",
                           max_collisions=3)
    with pytest.raises(ValueError, match="one orbit"):
        plot.draw_orbit(ax, ens)
    with pytest.raises(ValueError, match="start state"):
        plot.draw_orbit(ax, ens.isel(orbit=0))
    with pytest.raises(ValueError, match="missing"):
        plot.draw_orbit(ax, xr.Dataset())
    orbit = ns.simulate(tables.rectangle(2.0, 1.0), (0.5, 0.5), (1.0, 0.3), max_collisions=3)
    with pytest.raises(ValueError, match="spin_every"):
        plot.draw_orbit(ax, orbit, spin_every=0)
    with pytest.raises(ValueError, match="points_per_flight"):
        plot.orbit_path(orbit, points_per_flight=1)


def _arrow_turn(ax):
    """Signed angle swept by the (only) spin arrow, about its circle's centre."""
    arrow = [p for p in ax.patches if isinstance(p, FancyArrowPatch)][-1]
    verts = arrow.get_path().vertices
    centre = ax.patches[-2].center
    ang = np.unwrap(np.arctan2(verts[:, 1] - centre[1], verts[:, 0] - centre[0]))
    return ang.max() - ang.min(), np.sign(np.diff(ang)).mean()


def test_spin_arrow_turns_with_the_spin(ax):
    plot.draw_spin(ax, 0.0, 0.0, 0.5, 1.0, 0.1)
    span, direction = _arrow_turn(ax)
    assert direction > 0                                              # counter-clockwise for w > 0
    plot.draw_spin(ax, 1.0, 0.0, -1.0, 1.0, 0.1)
    span_full, direction = _arrow_turn(ax)
    assert direction < 0 and span_full > span                          # larger spin, longer arrow
    assert span == pytest.approx(math.radians(plot.orbits.SPIN_ARC_MAX * 0.5), rel=0.1)
    with pytest.raises(ValueError, match="radius"):
        plot.draw_spin(ax, 0, 0, 1.0, 1.0, 0.0)


def test_orbit_draws_spin_markers_and_end_dots(ax):
    scene = tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)])
    orbit = ns.simulate(scene, (0.05, 0.5), (1.0, 0.37), 0.5, max_collisions=6)
    line = plot.draw_orbit(ax, orbit, spin_every=2)
    assert line.get_color() == plot.LAW_COLORS["no-slip"]
    assert orbit.t_final == orbit.t[-1]                                # flight 6 has zero length: no room
    assert len([p for p in ax.patches if isinstance(p, FancyArrowPatch)]) == 3   # flights 0, 2, 4
    assert len(ax.lines) == 3                                          # the path and two end dots


def _spin_centres(ax):
    return np.array([p.center for p in ax.patches if isinstance(p, CirclePatch)])


def test_spin_markers_neither_overlap_nor_cross_walls(ax):
    scene = tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.3)])
    orbit = ns.simulate(scene, (0.05, 0.5), (1.0, 0.37), 0.5, max_collisions=60)
    r = 0.08
    plot.draw_orbit(ax, orbit, spin_every=1, spin_radius=r)
    c = _spin_centres(ax)
    assert 10 <= len(c) < 61                                           # many flights hold one, not all
    gaps = np.hypot(*(c[:, None, :] - c[None, :, :]).transpose(2, 0, 1))
    assert gaps[~np.eye(len(c), dtype=bool)].min() >= 2 * r             # no two markers overlap
    to_walls = np.min([c[:, 0], 2.0 - c[:, 0], c[:, 1], 1.0 - c[:, 1],
                       np.abs(np.hypot(c[:, 0] - 1.0, c[:, 1] - 0.5) - 0.3)], axis=0)
    assert to_walls.min() >= r                                          # no marker crosses a wall
    arrows = [p for p in ax.patches if isinstance(p, FancyArrowPatch)]
    assert arrows and all(a.get_mutation_scale() >= 6 for a in arrows)  # heads readable in print


def test_a_repeated_flight_gets_one_spin_marker(ax):
    # the bouncing ball's 2-periodic orbit flies the same two arcs again and again
    gamma = 1 / math.sqrt(2)
    scene = ns.Scene((Line((0.0, 0.0), (0.0, 1.0)),), force=(0.0, -1.0), gamma=gamma)
    orbit = ns.simulate(scene, (0.0, 0.5), (0.5, 0.0), 0.5 / gamma, max_collisions=20)   # w = v_x / gamma
    np.testing.assert_allclose(orbit.x.values[:4], [0.5, -0.5, 0.5, -0.5], atol=1e-9)
    plot.draw_orbit(ax, orbit, spin_every=1, spin_radius=0.05)
    assert 2 <= len(_spin_centres(ax)) <= 4


def test_portrait_on_the_unit_disk(ax):
    from noslipsim.experiments import phase_portrait

    pp = phase_portrait(tables.regular_polygon(4), n_orbits=3, n_collisions=50, seed=1)
    pts = plot.draw_portrait(ax, pp)
    assert len(pts.get_offsets()) == 150
    bad = pp.copy()
    bad["w_unit"] = bad.w_unit * 2 + 1
    with pytest.raises(ValueError, match="unit disk"):
        plot.draw_portrait(ax, bad)
    with pytest.raises(ValueError, match="vt_unit"):
        plot.draw_portrait(ax, pp.drop_vars("vt_unit"))


def test_stability_grid_and_threshold(ax):
    grid = xr.DataArray(np.arange(12.0).reshape(3, 4), dims=("R", "phi"),
                        coords={"R": [1.0, 2.0, 3.0], "phi": [0.1, 0.2, 0.3, 0.4]})
    mesh = plot.draw_stability_grid(ax, grid, threshold=([0.0, 1.0], [1.5, 2.5]))
    assert mesh.get_array().size == 12 and len(ax.lines) == 1
    assert ax.get_xlim() == pytest.approx((0.05, 0.45))               # the threshold does not widen the view
    with pytest.raises(ValueError, match="2D"):
        plot.draw_stability_grid(ax, grid.isel(R=0))
    with pytest.raises(ValueError, match="monotonic"):
        plot.draw_stability_grid(ax, grid.assign_coords(phi=[0.1, 0.3, 0.2, 0.4]))
    with pytest.raises(ValueError, match="threshold"):
        plot.draw_stability_grid(ax, grid, threshold=([0.0, 1.0], [1.0]))


def _figure():
    fig, ax = plt.subplots(figsize=(3, 2))
    plot.draw_table(ax, tables.galton_board(2.0, 0.9), window=(-3, 3, -3, 1))
    orbit = ns.simulate(tables.galton_board(2.0, 0.9), (1.0, 0.0), (0.6, 0.8), max_collisions=30)
    plot.draw_orbit(ax, orbit, spin_every=3)
    ax.set_title("noslipsim")
    return fig


def test_saved_bytes_are_identical_and_unstamped(tmp_path):
    with plot.style_context():
        a = plot.save_figure(_figure(), tmp_path / "a" / "fig")
        b = plot.save_figure(_figure(), tmp_path / "b" / "fig.png")
    assert [p.name for p in a] == ["fig.pdf", "fig.png"]
    for pa, pb in zip(a, b):
        assert pa.read_bytes() == pb.read_bytes()
    pdf, png = a[0].read_bytes(), a[1].read_bytes()
    assert b"CreationDate" not in pdf and b"matplotlib" not in pdf.lower()
    assert b"Software" not in png and b"tIME" not in png and b"matplotlib" not in png.lower()
    with pytest.raises(TypeError, match="Figure"):
        plot.save_figure("not a figure", tmp_path / "x")


def test_numbers_table():
    numbers = {"galton": {"share": {"description": "share not arrived", "value": 0.4213, "format": ".1%",
                                    "stderr": 0.0049, "paper": "roughly 40 %"},
                          "pattern": {"description": "pattern", "value": "stable | unstable"}}}
    text = plot.numbers_markdown(numbers)
    assert "| galton | share not arrived | 42.1% ± 0.5% | roughly 40 % |" in text
    assert "stable \\| unstable" in text
    with pytest.raises(ValueError, match="missing"):
        check_record("k", {"value": 1.0})
    with pytest.raises(ValueError, match="finite"):
        check_record("k", {"description": "d", "value": math.nan})
    with pytest.raises(ValueError, match="unknown"):
        check_record("k", {"description": "d", "value": 1.0, "colour": "red"})
    assert json.loads(json.dumps(numbers)) == numbers


# ---------------------------------------------------------------- annotations and the 3D bounce path
def test_angle_arc_spans_the_angle_at_its_radius(ax):
    arc = plot.draw_angle(ax, (1.0, 2.0), 0.3, 1.1, 0.5, r"$\theta$")
    x, y = arc.get_data()
    np.testing.assert_allclose(np.hypot(x - 1.0, y - 2.0), 0.5)
    ang = np.arctan2(y - 2.0, x - 1.0)
    assert ang[0] == pytest.approx(0.3) and ang[-1] == pytest.approx(1.1) and np.all(np.diff(ang) > 0)
    (text,) = ax.texts
    tx, ty = text.get_position()
    assert math.atan2(ty - 2.0, tx - 1.0) == pytest.approx(0.7)          # on the bisector
    clockwise = plot.draw_angle(ax, (0.0, 0.0), 1.0, 0.2, 1.0)
    assert np.all(np.diff(np.arctan2(*clockwise.get_data()[::-1])) < 0)
    with pytest.raises(ValueError, match="radius"):
        plot.draw_angle(ax, (0, 0), 0, 1, 0.0)
    with pytest.raises(ValueError, match="vertex"):
        plot.draw_angle(ax, (0, math.nan), 0, 1, 1.0)


def test_ray_runs_through_the_point_and_beyond(ax):
    line = plot.draw_ray(ax, (0.0, 0.0), (1.0, 2.0), beyond=0.5)
    x, y = line.get_data()
    np.testing.assert_allclose([x[0], y[0], x[1], y[1]], [0.0, 0.0, 1.5, 3.0])
    with pytest.raises(ValueError, match="through"):
        plot.draw_ray(ax, (1.0, 1.0), (1.0, 1.0))
    with pytest.raises(ValueError, match="beyond"):
        plot.draw_ray(ax, (0.0, 0.0), (1.0, 0.0), beyond=-1)


def test_label_point_marks_and_labels(ax):
    text = plot.label_point(ax, (0.5, 0.25), "q")
    assert text.get_text() == "q" and text.xy == (0.5, 0.25)
    (dot,) = ax.lines
    assert dot.get_xydata().tolist() == [[0.5, 0.25]]
    with pytest.raises(ValueError, match="xy"):
        plot.label_point(ax, "nowhere", "q")


def test_a_label_beside_a_ray_stays_off_it_and_off_the_inside(ax):
    """Figure 6's q0 and q1 were offset along their tangent lines, which then ran through the labels."""
    offset, ha, va = plot.ray_label_offset((0.0, 0.0), (-1.0, 1.0), inside=(0.0, 1.5), distance=8.0)
    assert np.hypot(*offset) == pytest.approx(8.0)
    assert np.dot(offset, (-1.0, 1.0)) == pytest.approx(0.0, abs=1e-12)       # perpendicular to the ray
    assert offset[0] < 0 and offset[1] < 0 and (ha, va) == ("right", "top")  # away from the inside point
    mirrored, ha, va = plot.ray_label_offset((0.0, 0.0), (1.0, 1.0), inside=(0.0, 1.5))
    assert mirrored[0] > 0 > mirrored[1] and (ha, va) == ("left", "top")
    ax.set_aspect("equal")
    ax.set_xlim(-2, 2)
    ax.set_ylim(-0.5, 2)
    ray = plot.draw_ray(ax, (0.0, 0.0), (-1.0, 1.0), beyond=1.0)
    text = plot.label_point(ax, (-1.0, 1.0), "$q_0$", offset=offset, ha="right", va="top")
    ax.figure.canvas.draw()
    box = text.get_window_extent()
    t = np.linspace(0, 1, 400)[:, None]
    x0, x1 = np.array(ray.get_xydata()[0]), np.array(ray.get_xydata()[1])
    pts = ax.transData.transform(x0 + t * (x1 - x0))
    assert not ((pts[:, 0] > box.x0) & (pts[:, 0] < box.x1) & (pts[:, 1] > box.y0) & (pts[:, 1] < box.y1)).any()
    with pytest.raises(ValueError, match="through"):
        plot.ray_label_offset((0, 0), (0, 0), (1, 1))
    with pytest.raises(ValueError, match="distance"):
        plot.ray_label_offset((0, 0), (1, 1), (1, 0), distance=0.0)


def test_a_3d_arrow_keeps_its_head_on_its_shaft():
    """Figure 16's quiver heads came off their shafts under a squeezed box aspect: the arrow is drawn on the page,
    between the projections of its two ends, whatever the view."""
    from mpl_toolkits.mplot3d import proj3d

    fig = plt.figure()
    ax3 = fig.add_subplot(projection="3d")
    ax3.set(xlim=(0, 3), ylim=(0, 2), zlim=(0, 0.5))
    ax3.set_box_aspect((3.0, 2.0, 0.5))
    for elev, azim in ((22.0, -30.0), (60.0, 120.0)):
        ax3.view_init(elev=elev, azim=azim)
        arrow = plot.draw_arrow3d(ax3, (1.0, 1.0, 0.0), (0.8, -0.3, 0.0))
        fig.canvas.draw()
        xs, ys, _ = proj3d.proj_transform(np.array([1.0, 1.8]), np.array([1.0, 0.7]), np.zeros(2), ax3.M)
        np.testing.assert_allclose(arrow._posA_posB, [(xs[0], ys[0]), (xs[1], ys[1])])
        assert arrow.get_arrowstyle().__class__.__name__ == "CurveFilledB"   # one filled head at the tip
    with pytest.raises(ValueError, match="3D"):
        plot.draw_arrow3d(fig.add_subplot(2, 2, 4), (0, 0, 0), (1, 0, 0))
    with pytest.raises(ValueError, match="finite"):
        plot.draw_arrow3d(ax3, (0, 0), (1, 0, 0))
    plt.close(fig)


def test_force_arrow_points_along_the_force_on_the_page(ax):
    """Figure 7's caption promised a downward force arrow that no panel drew."""
    ax.set_xlim(0, 4)
    ax.set_ylim(0, 1)
    for force in ((0.0, -1.0), (3.0, 4.0)):
        arrow = plot.draw_force_arrow(ax, force, tail=(0.5, 0.8), length=0.2)
        ax.figure.canvas.draw()
        tip, tail = (ax.transAxes.transform(p) for p in (arrow.xy, arrow.xyann))
        direction = (tip - tail) / np.hypot(*(tip - tail))
        np.testing.assert_allclose(direction, np.array(force) / np.hypot(*force), atol=1e-9)
    assert ax.texts[-1].get_text() == r"$\mathbf{g}$"
    with pytest.raises(ValueError, match="zero force"):
        plot.draw_force_arrow(ax, (0.0, 0.0))


def test_unvisited_cells_are_the_part_of_the_disk_no_orbit_reached(ax):
    """Figure 11's white areas read as forbidden; they are where no sampled orbit went (hatched, with a share)."""
    import xarray as xr

    rng = np.random.default_rng(0)
    r, a = np.sqrt(rng.uniform(0, 1, 200_000)), rng.uniform(-np.pi / 2, np.pi / 2, 200_000)   # the right half disk
    ds = xr.Dataset({"vt_unit": (("orbit", "point"), (r * np.cos(a)).reshape(2, -1)),
                     "w_unit": (("orbit", "point"), (r * np.sin(a)).reshape(2, -1))})
    edges, empty, share = plot.unvisited_cells(ds, bins=20)
    assert edges[0] == -1.0 and edges[-1] == 1.0 and empty.shape == (20, 20)
    assert empty[:10].any() and not empty[10:].any()       # [v_t cell, w cell]: only the left half is empty
    assert share == pytest.approx(0.5, abs=0.02)
    assert plot.draw_unvisited(ax, ds, bins=20) == share and ax.collections   # drawn, hatched
    with pytest.raises(ValueError, match="bins"):
        plot.unvisited_cells(ds, bins=1)


def test_sphere_path_follows_the_exact_flights():
    from noslipsim.sphere3d import simulate_sphere

    g = 2.0
    ds = simulate_sphere((0.1, -0.2, 0.7), (0.3, 0.4, 0.2), (0.5, -0.1, 0.3), gravity=g, n_bounces=5)
    x, y, z = plot.sphere_path(ds, points_per_flight=9)
    assert len(x) == 5 * 9
    np.testing.assert_allclose([x[0], y[0], z[0]], [0.1, -0.2, 0.7])
    # every flight ends at its bounce, on the plane
    ends = np.c_[x, y, z][8::9]
    np.testing.assert_allclose(ends, ds.position.values, atol=1e-12)
    assert z.min() >= -1e-12
    # a sample inside the first flight: q0 + v0 t - g t^2/2 e_z
    t1 = float(ds.time[0])
    t = 4 * t1 / 8
    np.testing.assert_allclose([x[4], y[4], z[4]], [0.1 + 0.3 * t, -0.2 + 0.4 * t, 0.7 + 0.2 * t - g * t * t / 2])
    with pytest.raises(ValueError, match="points_per_flight"):
        plot.sphere_path(ds, points_per_flight=1)
    with pytest.raises(ValueError, match="start"):
        plot.sphere_path(xr.Dataset(dict(ds.data_vars)))                 # the attributes lost


# ---------------------------------------------------------------- stability figures
def _log(elements, s, spin, deviation=None):
    n = len(elements)
    data = {"element": ("collision", np.asarray(elements, float)), "s": ("collision", np.asarray(s, float)),
            "spin": ("collision", np.asarray(spin, float))}
    if deviation is not None:
        data["deviation"] = ("collision", np.asarray(deviation, float))
    return xr.Dataset(data, coords={"collision": np.arange(n)})


def test_class_boundary_outlines_the_elliptic_cells(ax):
    kinds = xr.DataArray(np.array([["hyperbolic"] * 4, ["hyperbolic", "elliptic", "elliptic", "elliptic"],
                                   ["elliptic"] * 4]), dims=("radius", "phi"),
                         coords={"radius": [0.1, 0.2, 0.3], "phi": [0.1, 0.2, 0.3, 0.4]})
    cs = plot.draw_class_boundary(ax, kinds)
    vertices = np.concatenate([p.vertices for p in cs.get_paths()])
    # the level 1/2 runs half-way between the hyperbolic and the elliptic cells
    assert vertices[:, 1].min() >= 0.1 - 1e-12 and vertices[:, 1].max() <= 0.25 + 1e-12
    assert np.any(np.isclose(vertices[:, 1], 0.25)) and np.any(np.isclose(vertices[:, 1], 0.15))
    assert plot.draw_class_boundary(ax, kinds, kind="parabolic") is None        # no such cell: nothing drawn
    with pytest.raises(ValueError, match="2D"):
        plot.draw_class_boundary(ax, kinds.isel(radius=0))


def test_return_points_keep_one_wall_and_mark_the_periodic_point(ax):
    orbit = _log([1, 0, 1, 0, np.nan], [0.5, -1.0, 0.6, -1.1, np.nan], [0.1, 0.2, 0.3, 0.4, np.nan])
    s, w = plot.return_points(orbit, 0)
    np.testing.assert_array_equal(s, [-1.0, -1.1])
    np.testing.assert_array_equal(w, [0.2, 0.4])
    fixed = _log([1, 0], [0.5, -1.05], [0.1, 0.3])
    pts = plot.draw_return_points(ax, orbit, 1, fixed=fixed)
    np.testing.assert_array_equal(pts.get_offsets(), [[0.5, 0.1], [0.6, 0.3]])
    assert ax.lines[-1].get_xdata()[0] == 0.5 and ax.lines[-1].get_marker() == "x"
    with pytest.raises(ValueError, match="no collision on element 2"):
        plot.draw_return_points(ax, orbit, 2, fixed=fixed)
    with pytest.raises(ValueError, match="spin"):
        plot.return_points(orbit.drop_vars("spin"), 0)


def test_deviation_line_and_its_linear_growth(ax):
    lam = 1.5
    k = np.arange(30)
    dev = 1e-4 * lam ** (k / 2.0)
    line = plot.draw_deviation(ax, _log([0] * 30, k, k, deviation=dev), lambda_max=lam, anchor=1e-3)
    np.testing.assert_allclose(line.get_ydata(), dev)
    dashed = ax.lines[-1]
    x, y = dashed.get_xdata(), dashed.get_ydata()
    assert x[0] == np.argmax(dev >= 1e-3) and y.max() <= 1.0       # from the anchor on, below 1
    np.testing.assert_allclose(y, dev[x], rtol=1e-12)               # exact growth: the prediction lies on it
    assert ax.get_yscale() == "log"
    with pytest.raises(ValueError, match="deviation"):
        plot.draw_deviation(ax, _log([0], [0], [0]))
    with pytest.raises(ValueError, match="lambda_max"):
        plot.draw_deviation(ax, _log([0] * 30, k, k, deviation=dev), lambda_max=-1.0)


def test_two_disk_setup_puts_q0_q1_and_the_flight_where_the_experiment_has_them(ax):
    R, phi, theta = 0.6, 0.5, 0.6
    q0, q1 = plot.draw_two_disk_setup(ax, R, phi, theta)
    np.testing.assert_allclose(q0, [-1 + R * math.cos(phi), R * math.sin(phi)])
    np.testing.assert_allclose(q1, [1 - R * math.cos(phi), R * math.sin(phi)])
    flight = max(ax.lines, key=lambda line: len(line.get_xdata()))          # the sampled parabola
    x, y = flight.get_xdata(), flight.get_ydata()
    np.testing.assert_allclose([x[0], y[0], x[-1], y[-1]], [*q0, *q1], atol=1e-12)
    assert (y[1] - y[0]) / (x[1] - x[0]) == pytest.approx(math.tan(theta), rel=0.05)   # launched at theta
    assert len([p for p in ax.patches if isinstance(p, plt.Circle)]) == 2
    for bad in ({"radius": 1.0}, {"phi": 0.0}, {"theta": 2.0}):
        args = {"radius": R, "phi": phi, "theta": theta, **bad}
        with pytest.raises(ValueError, match=next(iter(bad))):
            plot.draw_two_disk_setup(ax, **args)
