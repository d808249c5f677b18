"""Ensembles: agreement with single orbits, chunk/scheduler invariance, recorders, datasets, seeds."""
import math

import numpy as np
import pytest

import noslipsim as ns
from noslipsim import initial, tables
from noslipsim.experiments import galton_distribution, phase_portrait

GALTON = tables.galton_board()


def galton_starts(n, seed=1):
    return np.tile([1.0, 0.0], (n, 1)), initial.unit_velocities(n, seed)


def test_log_recorder_matches_single_orbits():
    scene = tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)], force=(0.0, -1.0))
    q = initial.uniform_in_region(scene, 6, (0, 2, 0, 1), seed=3)
    v = initial.unit_velocities(6, seed=4)
    w = np.linspace(-0.5, 0.5, 6)
    ds = ns.simulate_many(scene, q, v, w, max_collisions=50, record="log")
    for i in range(6):
        one = ns.simulate(scene, q[i], v[i], w[i], max_collisions=50)
        for name in ("t", "x", "y", "vx", "vy", "spin", "element", "s"):
            np.testing.assert_array_equal(ds[name].values[i], one[name].values, err_msg=name)
        assert float(ds.x_final[i]) == float(one.x_final)


def test_lattice_log_matches_single_orbits_in_any_cell():
    q, v = galton_starts(4)
    q = q + np.array([[0, 0], [6.0, 0.0], [-3.0, 3 * math.sqrt(3)], [10.0, -2 * math.sqrt(3)]])
    ds = ns.simulate_many(GALTON, q, v, max_collisions=40, record="log")
    for i in range(4):
        one = ns.simulate(GALTON, q[i], v[i], 0.0, max_collisions=40)
        np.testing.assert_array_equal(ds.x.values[i], one.x.values)
        np.testing.assert_array_equal(ds.cell_a1.values[i], one.cell_a1.values)
        assert int(ds.cell_a2_final[i]) == int(one.cell_a2_final)


@pytest.mark.parametrize("record", ["final", "count", "portrait", "log"])
def test_same_dataset_for_any_chunking_and_scheduler(record):
    q, v = galton_starts(60)
    kw = dict(max_collisions=300, stop_below=-30.0, max_time=500.0, record=record)
    ref = ns.simulate_many(GALTON, q, v, chunk_size=60, scheduler="sync", **kw)
    for chunk, sched in [(1, "threads"), (7, "threads"), (30, "threads"), (None, None), (None, "numba")]:
        other = ns.simulate_many(GALTON, q, v, chunk_size=chunk, scheduler=sched, **kw)
        assert other.identical(ref), (chunk, sched)


def test_distributed_local_cluster_gives_the_same_dataset():
    distributed = pytest.importorskip("distributed")
    q, v = galton_starts(40)
    kw = dict(max_collisions=300, stop_below=-30.0, max_time=500.0)
    ref = ns.simulate_many(GALTON, q, v, scheduler="sync", **kw)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        by_client = ns.simulate_many(GALTON, q, v, chunk_size=9, scheduler=client, **kw)
        by_address = ns.simulate_many(GALTON, q, v, chunk_size=13, scheduler=cluster.scheduler_address, **kw)
    assert by_client.identical(ref)
    assert by_address.identical(ref)


def test_final_recorder_holds_no_logs():
    q, v = galton_starts(1000)
    ds = ns.simulate_many(GALTON, q, v, max_collisions=100)
    assert set(ds.dims) == {"orbit"}
    assert ds.nbytes < 1000 * 12 * 8 * 1.5


def test_stop_below_is_an_exact_crossing():
    q, v = galton_starts(200)
    ds = ns.simulate_many(GALTON, q, v, max_collisions=10**6, stop_below=-20.0, max_time=1e4)
    arrived = ds.stop_reason.values == 3
    assert arrived.mean() > 0.9
    assert np.all(ds.y_final.values[arrived] == -20.0)
    flags = ds.stop_reason.attrs["flag_meanings"].split()
    assert flags[3] == "stop_below"


def test_portrait_points_are_unit_vectors_on_chosen_elements():
    scene = tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.3)])
    states = initial.boundary_states(scene, 10, seed=5)
    ds = ns.simulate_many(scene, states["positions"], states["velocities"], states["spins"],
                          start_elements=states["start_elements"], max_collisions=200, record="portrait",
                          elements=[4])
    pts = ~np.isnan(ds.element.values)
    assert np.all(ds.element.values[pts] == 4)
    assert pts.sum() == ds.n_points.sum() > 0
    norm = ds.w_unit ** 2 + ds.vt_unit ** 2 + ds.vn_unit ** 2
    np.testing.assert_allclose(norm.values[pts], 1.0, rtol=1e-14)
    assert np.all(ds.vn_unit.values[pts] < 0)  # n is outward: after a hit the particle moves in
    assert np.all((ds.s.values[pts] >= 0) & (ds.s.values[pts] <= 2 * math.pi * 0.3))


def test_boundary_starts_are_reproducible_and_on_the_boundary():
    scene = tables.stadium()
    a = initial.boundary_states(scene, 50, seed=np.random.SeedSequence(9))
    b = initial.boundary_states(scene, 50, seed=9)
    for k in a:
        np.testing.assert_array_equal(a[k], b[k])
    np.testing.assert_allclose(np.hypot(*a["velocities"].T) ** 2 + a["spins"] ** 2, 1.0)
    ds = ns.simulate_many(scene, **a, max_collisions=5, record="log")
    assert np.all(ds.n_collisions.values == 5)
    assert not np.array_equal(a["positions"], initial.boundary_states(scene, 50, seed=10)["positions"])


@pytest.mark.parametrize("kwargs, field", [
    (dict(positions=np.zeros((3, 2)) + np.array([1.0, 0.0]), velocities=np.ones((2, 2))), "velocities"),
    (dict(positions=[[1.0, 0.0], [0.0, 0.0]], velocities=np.ones((2, 2))), "positions"),
    (dict(positions=[[1.0, np.nan]], velocities=[[1.0, 0.0]]), "positions"),
    (dict(positions=[[1.0, 0.0]], velocities=[[1.0, 0.0]], spins=[0.0, 1.0]), "spins"),
    (dict(positions=[[1.0, 0.0]], velocities=[[1.0, 0.0]], record="everything"), "record"),
    (dict(positions=[[1.0, 0.0]], velocities=[[1.0, 0.0]], stop_below=5.0), "stop_below"),
    (dict(positions=[[1.0, 0.0]], velocities=[[1.0, 0.0]], chunk_size=0), "chunk_size"),
    (dict(positions=[[1.0, 0.0]], velocities=[[1.0, 0.0]], record="portrait", elements=[3]), "elements"),
    (dict(positions=[[1.0, 0.0]], velocities=[[1.0, 0.0]], start_elements=[0]), "start element"),
    (dict(positions=[[1.0, 0.0]], velocities=[[1.0, 0.0]], max_collisions=-2), "max_collisions"),
])
def test_bad_input_names_the_field(kwargs, field):
    with pytest.raises(ValueError, match=field):
        ns.simulate_many(GALTON, **kwargs)


def test_netcdf_round_trip(tmp_path):
    q, v = galton_starts(30)
    ds = ns.simulate_many(GALTON, q, v, max_collisions=50, record="log")
    written = ns.write_dataset(ds, tmp_path / "sub" / "ens.nc", title="test", config={"n": 30, "flag": True})
    back = ns.open_dataset(tmp_path / "sub" / "ens.nc")
    assert back.identical(written)
    for name, var in back.variables.items():
        if name != "orbit":
            assert var.attrs.get("long_name") and var.attrs.get("units"), name
    for key in ("title", "source", "history", "references", "config"):
        assert back.attrs[key]
    assert '"flag": true' in back.attrs["config"]
    assert not list((tmp_path / "sub").glob(".tmp-*"))
    plain = tmp_path / "sub" / "plain"
    plain.write_text("")  # a dataset is as readable as any file made here (not mkstemp's private 0600)
    assert (tmp_path / "sub" / "ens.nc").stat().st_mode & 0o777 == plain.stat().st_mode & 0o777


def test_galton_distribution_is_seeded_and_reports_arrivals():
    a = galton_distribution(300, rows=10, max_time=300.0, seed=2)
    b = galton_distribution(300, rows=10, max_time=300.0, seed=2)
    assert a.identical(b)
    assert list(a.law.values) == ["specular", "no-slip"]
    arrived = a.arrived.values.astype(bool)
    assert np.isnan(a.x_terminal.values[~arrived]).all() and np.isfinite(a.x_terminal.values[arrived]).all()
    np.testing.assert_allclose(a.share_not_arrived.values, 1 - arrived.mean(axis=1))


def test_phase_portrait_experiment():
    ds = phase_portrait(tables.regular_polygon(4), n_orbits=4, n_collisions=100, seed=1)
    assert ds.sizes["orbit"] == 4 and int(ds.n_points.sum()) == 400


def test_cli_runs_an_experiment(tmp_path):
    from noslipsim.cli import main
    cfg = tmp_path / "exp.yaml"
    cfg.write_text("experiment: galton_distribution\nparameters: {n_particles: 50, rows: 5, max_time: 100.0}\n")
    out = tmp_path / "g.nc"
    assert main(["run", str(cfg), "-o", str(out)]) == 0
    ds = ns.open_dataset(out)
    assert ds.sizes["particle"] == 50 and "galton_distribution" in ds.attrs["config"]
    cfg.write_text("experiment: nothing\n")
    assert main(["run", str(cfg), "-o", str(out)]) == 2
