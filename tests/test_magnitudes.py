"""The range of scales the engine is exact for, and what lies outside it refused by name (issue 23 item 5).

Inside the range (docs/conventions.md, "Range of validity") a scene scaled by
powers of two in length and speed runs the same orbit to the bit; outside it
``Scene``, ``simulate``, ``simulate_many`` and the CLI refuse the input with
one line naming the quantity (exit 2 in the CLI, no warning, no traceback).
"""
import math
import re
import warnings

import numpy as np
import pytest
from test_cli import assert_one_line_error, run_main, scene_file

import noslipsim as ns
from noslipsim import Scene, simulate, simulate_many, tables
from noslipsim.cli import main
from noslipsim.elements import Arc, Circle, Segment
from noslipsim.experiments.orbit_sets import phase_portrait
from noslipsim.scenes import MAX_MAGNITUDE, MIN_FEATURE, MIN_MAGNITUDE

BOX = "law: no-slip\nelements:\n" + "".join(
    f"  - {{type: segment, p0: {p0}, p1: {p1}}}\n"
    for p0, p1 in (([0, 0], [2, 0]), ([2, 0], [2, 1]), ([2, 1], [0, 1]), ([0, 1], [0, 0]))
) + "  - {type: circle, center: [1, 0.5], radius: 0.3}\n"
START = ["--position", "0.2", "0.2"]


def _box(L=1.0, V=1.0, law="no-slip", force=(0.0, 0.0)):
    """The 2 x 1 box with a disk of radius 0.3, lengths times ``L``, the force times ``V^2/L``."""
    return tables.rectangle(2.0 * L, 1.0 * L, disks=[(1.0 * L, 0.5 * L, 0.3 * L)], law=law,
                            force=(force[0] * V * V / L, force[1] * V * V / L))


# ---------------------------------------------------------------------------- the range is exact
@pytest.mark.parametrize("k_L, k_V", [(96, 96), (-96, -96), (96, -96), (-96, 96), (0, 98), (98, 0), (0, -99), (-97, 0)])
def test_scaled_twins_at_the_edges_of_the_range_are_the_same_orbit_to_the_bit(k_L, k_V):
    """Powers of two in length and speed scale every product exactly: the orbit must not move a bit."""
    L, V = 2.0 ** k_L, 2.0 ** k_V
    assert MIN_MAGNITUDE <= L <= MAX_MAGNITUDE and MIN_MAGNITUDE <= V <= MAX_MAGNITUDE
    for law, force in (("no-slip", (0.0, 0.0)), ("specular", (0.0, -1.0))):
        ref = simulate(_box(law=law, force=force), (0.2, 0.7), (0.8, 0.3), 0.4, max_collisions=40)
        got = simulate(_box(L, V, law, force), (0.2 * L, 0.7 * L), (0.8 * V, 0.3 * V), 0.4 * V, max_collisions=40)
        np.testing.assert_array_equal(got.element.values, ref.element.values)
        for var, unit in (("t", L / V), ("x", L), ("y", L), ("vx", V), ("vy", V), ("spin", V), ("s", L)):
            np.testing.assert_array_equal(got[var].values / unit, ref[var].values, err_msg=var)


def test_the_bounds_keep_a_margin_below_the_measured_breakdown():
    """benchmarks/magnitudes.py measured the box's scaled twins exact to the bit up to 2^+-496 in length or
    speed alone, 2^+-240 in both (L = V), and 2^-176..2^160 in speed alone under gravity; the bounds stop
    well inside, and a twin past them is refused."""
    assert 2.0 ** -176 < MIN_MAGNITUDE and MAX_MAGNITUDE < 2.0 ** 160
    with pytest.raises(ValueError, match=r"^elements: the table's coordinates reach"):
        _box(2.0 ** 110, 1.0)
    with pytest.raises(ValueError, match=r"^velocity: speed"):
        simulate(_box(), (0.2, 0.7), (0.8 * 2.0 ** 110, 0.0))
    with pytest.raises(ValueError, match=r"^velocity: speed scale sqrt"):
        simulate(_box(1.0, 2.0 ** 110, force=(0.0, -1.0)), (0.2, 0.7), (0.0, 0.0))


# ---------------------------------------------------------------------------- the cases, CLI
def test_huge_velocity_is_refused_in_one_line(capsys, tmp_path):
    path = scene_file(tmp_path, BOX)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy overflow warning on the way
        status, err = run_main(["simulate", path, *START, "--velocity", "1e200", "1e200"], capsys)
    assert_one_line_error(status, err, "--velocity:", "1.41e+200", "1e+30", "Range of validity")


def test_tiny_velocity_is_refused_in_one_line(capsys, tmp_path):
    path = scene_file(tmp_path, BOX)
    status, err = run_main(["simulate", path, *START, "--velocity", "1e-300", "1e-300"], capsys)
    assert_one_line_error(status, err, "--velocity:", "below 1e-30")


def test_huge_force_is_refused_in_one_line(capsys, tmp_path):
    path = scene_file(tmp_path, BOX.replace("law: no-slip\n", "law: no-slip\nforce: [0, 1e308]\n"))
    status, err = run_main(["simulate", path, *START, "--velocity", "1", "1"], capsys)
    assert_one_line_error(status, err, "force:", "1e+308")


def test_huge_spin_is_refused_in_one_line(capsys, tmp_path):
    path = scene_file(tmp_path, BOX)
    status, err = run_main(["simulate", path, *START, "--velocity", "1", "1", "--spin", "1e60"], capsys)
    assert_one_line_error(status, err, "--spin:", "1e+60")


def test_output_naming_a_folder_is_refused_before_running(capsys, tmp_path):
    path = scene_file(tmp_path, BOX)
    status, err = run_main(["simulate", path, *START, "--velocity", "1", "1", "-o", str(tmp_path)], capsys)
    assert_one_line_error(status, err, "-o/--output:", "is a folder")
    assert ".tmp-" not in err


@pytest.mark.parametrize("name", ["orbit.csv", "orbit", "orbit.txt"])
def test_output_with_a_non_netcdf_name_is_refused_and_nothing_written(capsys, tmp_path, name):
    path = scene_file(tmp_path, BOX)
    out = tmp_path / name
    status, err = run_main(["simulate", path, *START, "--velocity", "1", "1", "-o", str(out)], capsys)
    assert_one_line_error(status, err, "-o/--output:", "netCDF")
    assert not out.exists()


def test_write_dataset_refuses_a_folder_and_a_foreign_suffix(tmp_path):
    ds = simulate(_box(), (0.2, 0.2), (1.0, 1.0), max_collisions=2)
    for bad, text in ((tmp_path, "is a folder"), (tmp_path / "o.csv", "does not end in")):
        with pytest.raises(ValueError, match=f"^path: .*{text}"):
            ns.write_dataset(ds, bad)
    ns.write_dataset(ds, tmp_path / "o.nc")
    assert ns.open_dataset(tmp_path / "o.nc").sizes["collision"] == 2


def test_a_scene_in_range_still_runs_from_the_cli(capsys, tmp_path):
    path = scene_file(tmp_path, BOX)
    assert main(["simulate", path, *START, "--velocity", "1", "1", "-n", "3", "-o", str(tmp_path / "o.nc")]) == 0


# ---------------------------------------------------------------------------- tables
@pytest.mark.parametrize("args, field", [((-1, 1), "width"), ((1, 0), "height"), ((math.nan, 1), "width")])
def test_rectangle_with_a_nonpositive_side_is_refused(args, field):
    with pytest.raises(ValueError, match=f"^{field}:"):
        tables.rectangle(*args)


@pytest.mark.parametrize("vertices, text", [
    ([(0, 0), (1, 1), (1, 0), (0, 1)], "not simple"),                  # a bow tie
    ([(0, 0), (2, 0), (2, 2), (1, 0), (0, 2)], "not simple"),          # a vertex on another edge
    ([(0, 0), (2, 0), (1, 0), (1, 1)], "folds back"),                  # a spike of zero width
    ([(math.cos(a), math.sin(a)) for a in 4 * math.pi / 5 * np.arange(5)], "not simple"),  # a pentagram
])
def test_self_intersecting_polygons_are_refused(vertices, text):
    with pytest.raises(ValueError, match=f"^vertices: .*{text}"):
        tables.polygon(vertices)


def test_simple_polygons_are_accepted():
    tables.polygon([(0, 0), (3, 0), (3, 3), (2, 1), (0, 3)])  # non-convex but simple
    tables.regular_polygon(20)
    tables.closed_hex_cell()


# ---------------------------------------------------------------------------- degenerate tables
@pytest.mark.parametrize("elements, text", [
    ([Segment((0, 0), (1e40, 0)), Segment((1e40, 0), (0, 1e40)), Segment((0, 1e40), (0, 0))], "reach 1e+40"),
    ([Circle((0, 0), 1e-40, "inside")], "size is 1e-40"),
    ([Segment((0, 0), (1, 0)), Segment((1, 0), (1, 1e-10)), Segment((1, 1e-10), (0, 0))], "segment length"),
    ([Circle((0, 0), 1.0, "inside"), Circle((0.5, 0), 1e-12)], "circle radius"),
    ([Arc((0, 0), 1.0, 0.0, 1e-12, "inside"), Segment((1, 1e-12), (1, 0))], "arc length"),
    ([Segment((1e15, 1e15), (1e15 + 1, 1e15)), Segment((1e15 + 1, 1e15), (1e15, 1e15 + 1)),
      Segment((1e15, 1e15 + 1), (1e15, 1e15))], "segment length"),               # a unit table far out
])
def test_degenerate_tables_are_refused(elements, text):
    with pytest.raises(ValueError, match=rf"^elements(\[\d+\])?: .*{re.escape(text)}"):
        Scene(tuple(elements))


def test_a_piece_below_the_smallest_length_is_refused_by_that_bound():
    with pytest.raises(ValueError, match=r"^elements\[1\]: a circle radius of 5e-31 is below 1e-30, the smallest"):
        Scene((Circle((0, 0), 2e-30, "inside"), Circle((0.0, 0.0), 5e-31)))


@pytest.mark.parametrize("force, ok", [((0.0, 1e-91), False), ((0.0, 1e91), False), ((0.0, 1e-89), True),
                                       ((1e-300, -1.0), True), ((0.0, 0.0), True)])
def test_force_magnitude_range(force, ok):
    if ok:
        _box().replace(force=force)
    else:
        with pytest.raises(ValueError, match=r"^force: "):
            _box().replace(force=force)


def test_features_at_the_floor_are_accepted():
    Scene((Circle((0, 0), 1.0, "inside"), Circle((0.5, 0), 2 * MIN_FEATURE)))


# ---------------------------------------------------------------------------- starts and requests
def test_a_start_far_from_a_small_table_is_refused():
    scene = tables.two_disks(0.5)
    with pytest.raises(ValueError, match=r"^position: .*smallest piece"):
        simulate(scene, (1e12, 0.0), (-1.0, 0.0))
    simulate(scene, (10.0, 0.0), (-1.0, 0.0), max_collisions=1)


def test_the_speed_scale_of_free_fall_counts_the_force():
    scene = tables.half_plane(gravity=1e80)
    with pytest.raises(ValueError, match=r"^velocity: speed scale sqrt\(\|a\| L\)"):
        simulate(scene, (0.0, 1.0), (0.0, 0.0))
    ds = simulate(tables.half_plane(gravity=1e-40), (0.0, 1.0), (0.0, 0.0), max_collisions=2)
    assert float(ds.t[0]) == pytest.approx(math.sqrt(2e40), rel=1e-15)  # speed scale 1e-20: in range


def test_a_start_at_the_origin_of_a_table_of_lines_through_it_is_measured_by_its_height():
    with pytest.raises(ValueError, match=r"^position: .*below 1e-30"):
        simulate(tables.half_plane(), (0.0, 1e-40), (1.0, 0.0))


def test_ensembles_name_the_orbit_out_of_range():
    scene = _box()
    with pytest.raises(ValueError, match=r"^velocities: orbit 1: speed 1e\+60"):
        simulate_many(scene, [[0.2, 0.2]] * 2, [[1.0, 0.0], [1e60, 0.0]], scheduler="sync")
    with pytest.raises(ValueError, match=r"^spins: orbit 0: "):
        simulate_many(scene, [[0.2, 0.2]], [[1.0, 0.0]], [1e60], scheduler="sync")
    with pytest.raises(ValueError, match=r"^positions: orbit 0: .*smallest piece"):
        simulate_many(tables.two_disks(0.5), [[1e12, 0.0]], [[-1.0, 0.0]], scheduler="sync")


def test_empty_requests_are_refused_by_name(tmp_path):
    with pytest.raises(ValueError, match=r"^n_orbits: "):
        phase_portrait(_box(), n_orbits=0)
    with pytest.raises(ValueError, match=r"^n_collisions: "):
        phase_portrait(_box(), n_orbits=2, n_collisions=0)
    for out in (None, tmp_path / "ens"):
        with pytest.raises(ValueError, match=r"^positions: no starts"):
            simulate_many(_box(), np.zeros((0, 2)), np.zeros((0, 2)), out=out)


def test_a_level_beyond_the_range_is_refused():
    board = tables.galton_board()
    with pytest.raises(ValueError, match=r"^stop_below: -1e\+200 lies beyond 1e\+30"):
        simulate(board, (1.0, 0.9), (0.1, 0.0), stop_below=-1e200)
    with pytest.raises(ValueError, match=r"^stop_below: -1e\+200 lies beyond"):
        simulate_many(board, [[1.0, 0.9]], [[0.1, 0.0]], stop_below=-1e200, scheduler="sync")
    assert simulate(board, (1.0, 0.9), (0.1, 0.0), stop_below=-1e10, max_collisions=5).attrs["stop_reason"]


def test_the_thermostat_takes_its_speed_scale_from_the_speed_alone():
    """The isokinetic thermostat keeps |v|: a speed below the range is refused even under a strong field
    (free fall would accelerate it, and is accepted); with zero force it is the straight-flight engine."""
    cell = tables.hex_lorentz_cell(0.4, force=(1.0, 0.0))
    with pytest.raises(ValueError, match=r"^velocity: speed 1e-40 is below 1e-30"):
        simulate(cell.replace(thermostat="isokinetic"), (0.45, 0.1), (1e-40, 0.0))
    ds = simulate(cell, (0.45, 0.1), (1e-40, 0.0), max_collisions=2)
    assert int(ds.n_collisions) == 2
    with pytest.raises(ValueError, match=r"^velocity: zero speed with zero force"):
        simulate(cell.replace(force=(0.0, 0.0), thermostat="isokinetic"), (0.45, 0.1), (0.0, 0.0))
