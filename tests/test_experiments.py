"""The paper's experiments as datasets: Galton distributions per case, radius sweeps, orbit sets."""
import math
import threading

import numpy as np
import pytest

import noslipsim as ns
from noslipsim import ensemble, initial, plot, tables
from noslipsim import experiments as ex
from noslipsim.experiments import galton_distribution, galton_orbits, galton_radius_sweep, orbit_set

SMALL = dict(rows=3, max_time=80.0, radius=0.8, seed=4, progress=False)


def test_gamma_is_a_coordinate_along_law_and_nan_for_specular():
    ds = galton_distribution(60, **SMALL)
    assert list(ds.law.values) == ["specular", "no-slip"]
    assert np.isnan(ds.gamma.values[0]) and ds.gamma.values[1] == pytest.approx(2 ** -0.5)
    assert "gamma" not in ds.attrs                       # never recorded as used where it was not
    assert ds.attrs["radius"] == 0.8 and ds.attrs["n_particles"] == 60


def test_several_gammas_in_one_run_match_single_runs():
    many = galton_distribution(50, gamma=[2 ** -0.5, 1.0, 3.0], **SMALL)
    assert list(many.law.values) == ["specular", "no-slip", "no-slip", "no-slip"]
    np.testing.assert_array_equal(many.gamma.values[1:], [2 ** -0.5, 1.0, 3.0])
    for i, g in enumerate([2 ** -0.5, 1.0, 3.0], start=1):
        one = galton_distribution(50, laws=("no-slip",), gamma=g, **SMALL)
        np.testing.assert_array_equal(many.t_terminal.isel(law=i), one.t_terminal.isel(law=0))
        np.testing.assert_array_equal(many.x_terminal.isel(law=i), one.x_terminal.isel(law=0))
    spec = galton_distribution(50, laws=("specular",), gamma=5.0, **SMALL)   # gamma plays no part
    np.testing.assert_array_equal(many.t_terminal.isel(law=0), spec.t_terminal.isel(law=0))
    assert np.isnan(spec.gamma.values[0])
    # selections the figures use
    assert many.sel(law="no-slip").sizes["law"] == 3
    picked = many.share_not_arrived.where(many.gamma == 3.0, drop=True).squeeze()
    assert float(picked) == float(many.share_not_arrived[3])


def test_arrivals_are_consistent():
    ds = galton_distribution(80, **SMALL)
    arrived = ds.arrived.values.astype(bool)
    assert np.isfinite(ds.t_terminal.values[arrived]).all() and np.isnan(ds.t_terminal.values[~arrived]).all()
    assert (ds.t_terminal.values[arrived] <= SMALL["max_time"]).all()
    # arrived particles end at the terminal depth, where x_end is x_terminal
    np.testing.assert_array_equal(ds.x_end.values[arrived], ds.x_terminal.values[arrived])
    depth = SMALL["rows"] * 2.0 * math.sqrt(3) / 2
    np.testing.assert_allclose(ds.y_end.values[arrived], -depth, atol=1e-9)
    assert (ds.y_end.values[~arrived] > -depth).all()
    np.testing.assert_allclose(ds.share_not_arrived, 1 - arrived.mean(axis=1))


@pytest.mark.parametrize("kwargs,match", [
    (dict(laws="no-slip"), "laws"),
    (dict(laws=("no-slip", "no-slip")), "laws"),
    (dict(laws=("rolling",)), "laws"),
    (dict(laws=()), "laws"),
    (dict(gamma=-1.0), "gamma"),
    (dict(gamma=[1.0, 1.0]), "gamma"),
    (dict(gamma=[]), "gamma"),
    (dict(gamma=math.nan), "gamma"),
    (dict(rows=0), "rows"),
    (dict(n_particles=0), "n_particles"),
    (dict(radius=1.5), "radius"),
])
def test_bad_galton_arguments_are_refused(kwargs, match):
    args = dict(SMALL, n_particles=5)
    args.update(kwargs)
    n = args.pop("n_particles")
    with pytest.raises(ValueError, match=match):
        galton_distribution(n, **args)


def test_radius_sweep_stacks_runs_along_radius():
    small = {k: v for k, v in SMALL.items() if k != "radius"}
    sweep = galton_radius_sweep(30, radii=[0.6, 0.8], **small)
    assert sweep.share_not_arrived.dims == ("radius", "law")
    np.testing.assert_array_equal(sweep.radius.values, [0.6, 0.8])
    assert "radius" not in sweep.attrs and sweep.attrs["rows"] == 3
    one = galton_distribution(30, **SMALL)
    np.testing.assert_array_equal(sweep.t_terminal.sel(radius=0.8), one.t_terminal)
    with pytest.raises(ValueError, match="radii"):
        galton_radius_sweep(5, radii=[0.8, 0.6], **small)
    with pytest.raises(ValueError, match="radii"):
        galton_radius_sweep(5, radius=0.8, **small)


def test_orbit_set_holds_each_simulated_orbit(tmp_path):
    scenes = [tables.rectangle(2.0, 1.0, law="specular"), tables.galton_board(2.0, 0.8, gamma=1.0)]
    ds = orbit_set(scenes, [[0.5, 0.5], [1.0, 0.0]], [[1.0, 0.3], [0.6, 0.8]], [0.2, -0.1],
                   max_collisions=40, max_time=30.0)
    assert ds.sizes["orbit"] == 2 and list(ds.law.values) == ["specular", "no-slip"]
    assert np.isnan(ds.gamma.values[0]) and ds.gamma.values[1] == 1.0
    for i, (sc, p, v, w) in enumerate(zip(scenes, [[0.5, 0.5], [1.0, 0.0]], [[1.0, 0.3], [0.6, 0.8]], [0.2, -0.1])):
        one = ns.simulate(sc, p, v, w, max_collisions=40, max_time=30.0)
        n = int(one.n_collisions)
        row = ds.isel(orbit=i)
        np.testing.assert_array_equal(row.x.values[:n], one.x.values)
        assert np.isnan(row.t.values[n:]).all() and str(row.stop_reason.values) == one.attrs["stop_reason"]
        assert float(row.x_final) == float(one.x_final) and plot.scene_of(row) == sc
    ns.write_dataset(ds, tmp_path / "orbits.nc")
    back = ns.open_dataset(tmp_path / "orbits.nc")
    assert plot.scene_of(back.isel(orbit=1)) == scenes[1]
    x, _ = plot.orbit_path(back.isel(orbit=1))
    assert x[0] == 1.0
    with pytest.raises(ValueError, match="shapes"):
        orbit_set(scenes, [[0.5, 0.5]], [[1.0, 0.3]])
    with pytest.raises(ValueError, match="scenes"):
        orbit_set([], [], [])


def test_galton_orbits_specular_path_is_the_no_slip_gamma_zero_path():
    ds = galton_orbits([0.0, 3.0], radius=0.8, rows=4, max_time=60.0, max_collisions=2000)
    assert list(ds.law.values) == ["specular", "no-slip"]
    twin = orbit_set([tables.galton_board(2.0, 0.8, law="no-slip", gamma=0.0)], [[1.0, 0.0]], [[0.6, 0.8]],
                     max_collisions=2000, max_time=60.0, stop_below=ds.attrs["stop_below"])
    n = int(ds.n_collisions[0])
    assert n == int(twin.n_collisions[0]) > 5
    np.testing.assert_array_equal(ds.x.values[0, :n], twin.x.values[0, :n])
    np.testing.assert_array_equal(ds.y.values[0, :n], twin.y.values[0, :n])
    assert ds.attrs["terminal_depth"] == pytest.approx(4 * 2.0 * math.sqrt(3) / 2)


def test_num_workers_sets_the_thread_pool(monkeypatch):
    seen = set()
    run = ensemble._run_chunk

    def spy(*args):
        seen.add(threading.get_ident())
        return run(*args)

    monkeypatch.setattr(ensemble, "_run_chunk", spy)
    board = tables.galton_board(2.0, 0.8)
    pos, vel = [[1.0, 0.0]] * 40, initial.unit_velocities(40, 1)
    one = ns.simulate_many(board, pos, vel, max_time=20.0, chunk_size=5, num_workers=1, progress=False)
    assert len(seen) == 1
    two = ns.simulate_many(board, pos, vel, max_time=20.0, chunk_size=5, num_workers=2, progress=False)
    assert one.identical(two)
    with pytest.raises(ValueError, match="num_workers"):
        ns.simulate_many(board, pos, vel, num_workers=0)


def test_bounded_board_release_and_the_gap_drop_that_never_sees_the_rows_above():
    kw = dict(rows=2, max_time=60.0, radius=0.89, seed=3, progress=False)
    board = ex.galton_distribution(40, top_row=0, start=(0.0, 2.0), spread=0.5, speed=0.7, **kw)
    assert board.attrs["board"] == "bounded" and board.attrs["top_row"] == 0
    assert board.attrs["terminal_level"] == pytest.approx(-2 * math.sqrt(3))
    arrived = board.arrived.values.astype(bool)
    assert arrived.any()
    # release offsets within the spread, the same for both laws (one seed), never above the top row's level
    t0 = board.t_terminal.values
    assert np.isfinite(t0[arrived]).all()
    # the gap drop: unit speed from y = 0 rises at most to 0.5, below the next row's pegs (1.73 - 0.89)
    gap = ex.galton_distribution(40, start=(1.0, 0.0), **kw)
    gap_bounded = ex.galton_distribution(40, start=(1.0, 0.0), top_row=0, **kw)
    assert gap.attrs["board"] == "unbounded" and gap_bounded.attrs["board"] == "bounded"
    np.testing.assert_array_equal(gap.t_terminal.values, gap_bounded.t_terminal.values)
    np.testing.assert_array_equal(gap.x_end.values, gap_bounded.x_end.values)
    # ... but thrown hard enough to reach the row above, the two boards part
    fast = dict(kw, max_time=30.0)
    a = ex.galton_distribution(40, start=(1.0, 0.0), speed=3.0, **fast)
    b = ex.galton_distribution(40, start=(1.0, 0.0), speed=3.0, top_row=0, **fast)
    assert not np.array_equal(a.x_end.values, b.x_end.values)
    with pytest.raises(ValueError, match="spread"):
        ex.galton_distribution(4, spread=-1.0, **kw)
    with pytest.raises(ValueError, match="speed"):
        ex.galton_distribution(4, speed=math.inf, **kw)
    with pytest.raises(TypeError, match="top_row"):
        ex.galton_distribution(4, top_row=0.5, **kw)


def test_galton_evidence_stacks_cases_and_refuses_bad_ones():
    cases = [{"name": "board", "group": "drop", "top_row": 0, "start": (0.0, 2.0)},
             {"name": "wide", "group": "radius", "top_row": 0, "start": (0.0, 2.0), "radius": 0.5}]
    ev = ex.galton_evidence(cases, 6, rows=1, max_time=40.0, radius=0.8, seed=1, progress=False)
    assert list(ev.case.values) == ["board", "wide"] and list(ev.radius.values) == [0.8, 0.5]
    assert list(ev.group.values) == ["drop", "radius"] and set(ev.board.values) == {"bounded"}
    assert ev.t_terminal.dims == ("case", "law", "particle")
    with pytest.raises(ValueError, match="unique"):
        ex.galton_evidence([cases[0], cases[0]], 2)
    with pytest.raises(ValueError, match="unknown keys"):
        ex.galton_evidence([{"name": "x", "gravity": 2.0}], 2)
    with pytest.raises(ValueError, match="at least one case"):
        ex.galton_evidence([], 2)


def test_walled_board_holds_its_pegs_and_particles_between_the_walls():
    board = tables.walled_galton_board(2.0, 0.89, rows=2, width=5.0)
    pegs, walls = board.elements[:-2], board.elements[-2:]
    centres = np.array([p.center for p in pegs])
    # rows 0, -1, -2 of the triangular lattice; only whole disks inside |x| < 5
    assert sorted(set(np.round(centres[:, 1], 9))) == pytest.approx([-2 * math.sqrt(3), -math.sqrt(3), 0.0])
    assert (np.abs(centres[:, 0]) + 0.89 < 5.0).all() and len(pegs) == 5 + 4 + 5
    assert [w.point[0] for w in walls] == [-5.0, 5.0] and [w.normal[0] for w in walls] == [1.0, -1.0]
    for bad, match in ((dict(width=0.5), "width"), (dict(width=-1.0), "width"), (dict(rows=0), "rows")):
        with pytest.raises(ValueError, match=match):
            tables.walled_galton_board(2.0, 0.89, **{"rows": 2, "width": 5.0, **bad})
    kw = dict(rows=3, max_time=400.0, radius=0.89, seed=3, top_row=0, start=(0.0, 2.0), spread=0.5, progress=False)
    walled = ex.galton_distribution(60, width=3.0, **kw)
    assert walled.attrs["width"] == 3.0 and ex.galton_distribution(2, **kw).attrs["width"] == math.inf
    assert (np.abs(walled.x_end.values) <= 3.0).all() and walled.arrived.values.any()
    assert walled.attrs["wall_law"] == "pegs"
    with pytest.raises(ValueError, match="top row"):
        ex.galton_distribution(2, width=3.0, **{**kw, "top_row": None})
    with pytest.raises(ValueError, match="wall_law"):
        ex.galton_distribution(2, wall_law="specular", **kw)


def test_walls_far_from_every_particle_change_nothing():
    # the walled board is a plain scene, the bounded one a lattice: the same pegs, so the same first collisions
    # (rounding differs and the board is chaotic, a factor ~4 per collision: 8 collisions stay within 1e-9)
    n = 40
    pos = np.array([0.0, 2.0]) + np.random.default_rng(3).uniform(-0.5, 0.5, (n, 2))
    vel = initial.unit_velocities(n, 3)
    logs = [ns.simulate_many(scene, pos, vel, max_collisions=8, max_time=60.0, stop_below=-2 * math.sqrt(3),
                             record="log", progress=False)
            for scene in (tables.galton_board(2.0, 0.89, top_row=0),
                          tables.walled_galton_board(2.0, 0.89, rows=2, width=200.0))]
    assert np.nanmax(np.abs(logs[0].x.values)) < 100.0  # no particle came within 100 of a wall
    assert np.isfinite(logs[0].t.values).sum() > 4 * n
    for key in ("t", "x", "y", "vx", "vy", "spin"):
        np.testing.assert_allclose(logs[1][key].values, logs[0][key].values, rtol=1e-9, atol=1e-9)


def test_galton_evidence_runs_each_case_to_its_own_time_and_width():
    cases = [{"name": "short", "group": "rows", "rows": 1, "max_time": 5.0},
             {"name": "walled", "group": "width", "rows": 1, "width": 4.0, "wall_law": "specular"}]
    ev = ex.galton_evidence(cases, 20, max_time=40.0, radius=0.8, seed=1, top_row=0, start=(0.0, 2.0),
                            progress=False)
    assert list(ev.max_time.values) == [5.0, 40.0] and ev.attrs["max_time"] == 40.0
    # no walls is width 0 in the dataset (a coordinate is finite), inf in one distribution's attributes
    assert list(ev.width.values) == [0.0, 4.0] and list(ev.wall_law.values) == ["none", "specular"]
    assert not (ev.t_terminal.sel(case="short").values > 5.0).any()
    assert (ev.t_terminal.sel(case="walled").values > 5.0).any()
