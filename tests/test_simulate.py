"""The one-orbit API: dataset layout, stop reasons and bad input."""
import math

import numpy as np
import pytest

from noslipsim import simulate, tables
from noslipsim._metadata import VARIABLES
from noslipsim.cli import main

BOX = tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)])


def test_dataset_layout_and_metadata():
    ds = simulate(BOX, (0.3, 0.5), (1.0, 0.37), spin=0.2, max_collisions=7)
    assert ds.sizes["collision"] == 7
    for name in ("t", "x", "y", "vx", "vy", "spin", "vx_in", "vy_in", "spin_in", "element", "s"):
        assert ds[name].dims == ("collision",)
    for name, var in ds.variables.items():
        if name != "collision":
            assert var.attrs["long_name"] == VARIABLES[name][0]
            assert var.attrs["units"] == "1"
    assert ds.attrs["stop_reason"] == "max_collisions"
    assert np.all(np.diff(ds.t.values) > 0)
    # the incoming state of collision k+1 is the outgoing state of k flown freely (no force here)
    np.testing.assert_allclose(ds.vx_in.values[1:], ds.vx.values[:-1])
    np.testing.assert_allclose(ds.spin_in.values[1:], ds.spin.values[:-1])


def test_stop_reasons():
    assert simulate(BOX, (0.3, 0.5), (1.0, 0.37), max_time=2.5).attrs["stop_reason"] == "max_time"
    ds = simulate(BOX, (0.3, 0.5), (1.0, 0.37), max_time=2.5)
    assert float(ds.t_final) == 2.5 and np.all(ds.t.values < 2.5)
    esc = simulate(tables.two_disks(0.5), (0.0, 0.0), (1.0, 0.3), max_collisions=100)
    assert esc.attrs["stop_reason"] == "escape" and int(esc.n_collisions) >= 1
    fall = simulate(tables.half_plane(), (0.0, 1.0), (0.2, 0.0), stop_below=0.25, max_collisions=100)
    assert fall.attrs["stop_reason"] == "stop_below"
    assert float(fall.y_final) == 0.25
    assert float(fall.t_final) == pytest.approx(math.sqrt(2 * 0.75), rel=1e-15)
    assert int(fall.n_collisions) == 0


def test_zero_collision_budget_returns_the_start():
    ds = simulate(BOX, (0.3, 0.5), (1.0, 0.37), max_collisions=0)
    assert int(ds.n_collisions) == 0 and ds.attrs["stop_reason"] == "max_collisions"
    assert float(ds.x_final) == 0.3


def test_zero_speed_with_force_falls():
    ds = simulate(tables.half_plane(), (0.0, 2.0), (0.0, 0.0), max_collisions=1)
    assert float(ds.t[0]) == pytest.approx(2.0, rel=1e-15)


@pytest.mark.parametrize("kwargs, field", [
    (dict(position=(3.0, 0.5)), "position"),
    (dict(position=(1.0, 0.5)), "position"),            # inside the scatterer
    (dict(position=(0.0, 0.5)), "position"),            # on the boundary
    (dict(position=(1.0, 0.7)), "position"),            # on the scatterer
    (dict(position=(math.nan, 0.5)), "position"),
    (dict(position=(0.3,)), "position"),
    (dict(velocity=(math.inf, 0.0)), "velocity"),
    (dict(velocity=(0.0, 0.0)), "velocity"),
    (dict(spin=math.nan), "spin"),
    (dict(max_collisions=-1), "max_collisions"),
    (dict(max_collisions=1.5), "max_collisions"),
    (dict(max_time=0.0), "max_time"),
    (dict(max_time=math.nan), "max_time"),
    (dict(stop_below=0.9), "stop_below"),
    (dict(scene="box"), "scene"),
])
def test_bad_input_names_the_field(kwargs, field):
    args = dict(scene=BOX, position=(0.3, 0.5), velocity=(1.0, 0.37), spin=0.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=field):
        simulate(**args)


def test_cli_prints_a_table(capsys):
    assert main(["simulate", "examples/sinai_box.yaml", "--position", "0.1", "0.1", "--velocity", "0.6", "0.8",
                 "-n", "4"]) == 0
    out = capsys.readouterr().out
    assert "stop_reason: max_collisions" in out and len(out.splitlines()) == 6


def test_cli_writes_netcdf(tmp_path):
    import xarray as xr
    path = tmp_path / "orbit.nc"
    assert main(["simulate", "examples/galton_peg.yaml", "--position", "0.1", "2.0", "--velocity", "0", "0",
                 "-n", "10", "-o", str(path)]) == 0
    ds = xr.open_dataset(path)
    assert ds.sizes["collision"] == 10 and ds.element.values[0] == 1


def test_cli_reports_bad_input(capsys):
    assert main(["simulate", "examples/sinai_box.yaml", "--position", "0.5", "0.5", "--velocity", "1", "0"]) == 2
    assert "position" in capsys.readouterr().err
