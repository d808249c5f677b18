"""The scene key ``magnetic`` (a field normal to the table): file format, validation, every compiled entry
point flying it, and the free-fall tools refusing it by name (docs/scenes.md, "Magnetic field")."""
import json
import math

import numpy as np
import pytest

from noslipsim import Scene, simulate, simulate_many, tables
from noslipsim.analysis import finite_time_lyapunov, lyapunov
from noslipsim.analysis.section import energy_at, interior_log
from noslipsim.cli import main
from noslipsim.reference import simulate_reference

LINE = {"type": "line", "point": [0, 0], "normal": [0, 1]}
BOX = tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)])


def test_default_is_no_field_and_absent_from_the_file():
    assert BOX.magnetic == 0.0
    assert "magnetic" not in BOX.to_dict()  # the JSON of field-free scenes (and their datasets) is as before
    assert "magnetic" not in BOX.to_json()


def test_round_trips_dict_yaml_json_and_replace(tmp_path):
    scene = BOX.replace(magnetic=-2.5)
    assert scene.magnetic == -2.5 and isinstance(scene.magnetic, float)
    assert scene.to_dict()["magnetic"] == -2.5
    assert Scene.from_dict(scene.to_dict()) == scene
    path = tmp_path / "box.yaml"
    scene.to_yaml(path)
    assert "magnetic: -2.5" in path.read_text()
    assert Scene.from_yaml(path) == scene
    assert Scene.from_dict(json.loads(scene.to_json())) == scene
    assert scene != BOX
    assert scene.replace(magnetic=0).to_dict() == BOX.to_dict()
    assert scene.replace(gamma=0.3).magnetic == -2.5  # replace keeps the field
    assert Scene.from_dict({"elements": [LINE], "magnetic": 3}).magnetic == 3.0
    assert tables.sinai_torus(0.3).replace(magnetic=1.0).cell_scene((2, -1)).magnetic == 1.0


@pytest.mark.parametrize("value, kind, message", [
    (math.inf, ValueError, r"^magnetic: must be finite, got inf"),
    (math.nan, ValueError, r"^magnetic: must be finite, got nan"),
    ("1.0", TypeError, r"^magnetic: expected a number .*got str"),
    (True, TypeError, r"^magnetic: expected a number .*got bool"),
    (None, TypeError, r"^magnetic: expected a number .*got NoneType"),
])
def test_bad_values_are_refused_by_name(value, kind, message):
    with pytest.raises(kind, match=message):
        Scene.from_dict({"elements": [LINE], "magnetic": value})


def test_refused_with_a_force_or_the_thermostat():
    with pytest.raises(ValueError, match=r"^magnetic: a field \(magnetic = 1.0\) together with a force"):
        BOX.replace(magnetic=1.0, force=(0.0, -1.0))
    with pytest.raises(ValueError, match=r"^magnetic: a field \(magnetic = 1.0\) is not supported with thermostat"):
        BOX.replace(magnetic=1.0, thermostat="isokinetic")
    # neither is refused without a field
    assert BOX.replace(force=(0.0, -1.0), thermostat="isokinetic").magnetic == 0.0


def test_a_bounded_lattice_takes_a_field():
    """A Galton board's top row with a field above it is a well-posed magnetic billiard (skipping orbits)."""
    board = tables.galton_board(top_row=0).replace(force=(0.0, 0.0), magnetic=2.0)
    assert board.top is not None and board.magnetic == 2.0


# ---------------------------------------------------------------------------- the compiled entry points
MAGNETIC = BOX.replace(magnetic=1.5)
START = ((0.4, 0.3), (0.7, 0.5))

ENTRY_POINTS = {
    "simulate": lambda s: int(simulate(s, *START, max_collisions=5).n_collisions),
    "simulate_many": lambda s: int(simulate_many(s, [START[0]], [START[1]], max_collisions=5, scheduler="sync",
                                                 progress=False).n_collisions[0]),
    "interior_log": lambda s: len(interior_log(s, *START, 0.0, 5)[0]),
}


@pytest.mark.parametrize("name", list(ENTRY_POINTS))
def test_compiled_entry_points_fly_a_field(name):
    """Each entry point runs the magnetic orbit the twin runs: five collisions, the same first hit."""
    assert ENTRY_POINTS[name](MAGNETIC) == 5


def test_the_field_bends_the_compiled_orbit():
    with_field = simulate(MAGNETIC, *START, max_collisions=3)
    without = simulate(BOX, *START, max_collisions=3)
    ref = simulate_reference(MAGNETIC, *START, max_collisions=3, dps=30)
    assert float(with_field.t[0]) != float(without.t[0])
    np.testing.assert_allclose(with_field.x.values, ref.x.values.astype(float), atol=1e-12)


def test_simulate_many_to_a_folder_runs_a_field(tmp_path):
    ds = simulate_many(MAGNETIC, [START[0]], [START[1]], max_collisions=5, out=tmp_path / "run", scheduler="sync",
                       progress=False)
    assert int(ds.n_collisions[0]) == 5 and (tmp_path / "run").exists()


def test_a_lattice_flies_a_field_too():
    torus = tables.sinai_torus(0.3).replace(magnetic=1.5)
    orbit = simulate(torus, (0.0, 0.45), (1.0, 0.3), max_collisions=5)
    assert int(orbit.n_collisions) == 5


def test_free_fall_tools_refuse_a_field_by_name():
    msg = r"^scene: .* is derived for free fall under the force; it does not support a magnetic field"
    twin = msg + r" \(magnetic = [^)]*\); noslipsim.analysis.twin_lyapunov \(twin orbits\) serves every flight$"
    with pytest.raises(ValueError, match=twin):
        lyapunov(MAGNETIC, *START, n_collisions=10)
    with pytest.raises(ValueError, match=twin):
        finite_time_lyapunov(MAGNETIC, [START[0]], [START[1]], n_collisions=10)
    with pytest.raises(ValueError, match=msg):
        energy_at(MAGNETIC, *START, 0.0)


def test_cli_simulates_a_field(tmp_path, capsys):
    path = tmp_path / "box.yaml"
    MAGNETIC.to_yaml(path)
    code = main(["simulate", str(path), "--position", "0.4", "0.3", "--velocity", "0.7", "0.5", "-n", "5",
                 "-o", str(tmp_path / "orbit.nc")])
    assert code == 0
    import xarray as xr

    with xr.open_dataset(tmp_path / "orbit.nc") as ds:
        assert int(ds.n_collisions) == 5
        assert json.loads(ds.attrs["scene"])["magnetic"] == 1.5


def test_cli_lyapunov_of_a_field_from_a_twin_orbit(tmp_path, capsys):
    """``noslipsim lyapunov --twin``: the exponent twin_lyapunov gives (the same seed, the same bits), per unit
    time through the orbit's own time over its collisions; the tangent method refuses, naming the twin."""
    import xarray as xr

    from noslipsim.analysis import twin_lyapunov

    path, out = tmp_path / "box.yaml", tmp_path / "lyapunov.nc"
    MAGNETIC.to_yaml(path)
    start = ["--position", "0.4", "0.3", "--velocity", "0.7", "0.5"]
    assert main(["lyapunov", str(path), *start, "-n", "398", "--twin", "-o", str(out)]) == 0
    want = twin_lyapunov(MAGNETIC, [START[0]], [START[1]], n_collisions=398)[0]
    t_n = float(simulate(MAGNETIC, *START, max_collisions=400).t[-1])  # 398 rounded up to whole blocks of 4
    with xr.open_dataset(out) as ds:
        assert ds.attrs["lyapunov_method"] == "twin" and int(ds.n_collisions) == 400
        assert float(ds.lyapunov_per_collision) == want > 0.0  # the Sinai box in a field is chaotic
        assert float(ds.lyapunov_exponent) == pytest.approx(want * 400 / t_n, rel=1e-15)
        assert float(ds.mean_free_time) == pytest.approx(t_n / 400, rel=1e-15)
    assert "twin orbit" in capsys.readouterr().out
    # without -n, with a figure, or without --twin: a user error (exit 2) that says why
    for extra, words in ((["--twin"], "give -n"), (["-n", "40", "--twin", "--figure", str(tmp_path / "f.png")],
                                                   "no running estimate"),
                         (["-n", "40"], "twin_lyapunov (twin orbits) serves every flight")):
        assert main(["lyapunov", str(path), *start, *extra, "-o", str(out)]) == 2
        assert words in capsys.readouterr().err


def test_cli_says_pinned(tmp_path, capsys):
    path = tmp_path / "box.yaml"
    tables.rectangle(20.0, 20.0).replace(magnetic=4.0).to_yaml(path)
    code = main(["simulate", str(path), "--position", "10", "10", "--velocity", "0.6", "0.8", "-n", "5",
                 "-o", str(tmp_path / "orbit.nc")])
    assert code == 0
    out = capsys.readouterr()
    assert "pinned" in out.out + out.err


def test_the_reference_runs_a_field():
    """The twin runs a magnetic scene too: the orbit collides and keeps its kinetic energy."""
    ds = simulate_reference(MAGNETIC, *START, max_collisions=5, dps=30)
    assert int(ds.n_collisions) == 5
    kinetic = ds.vx.values ** 2 + ds.vy.values ** 2 + ds.spin.values ** 2
    np.testing.assert_allclose(kinetic, START[1][0] ** 2 + START[1][1] ** 2, rtol=1e-14)
