"""Every analysis for a scene file of one's own from the shell: portrait, ensemble, periodic, lyapunov, animate.

Each command's dataset is checked against the library call it stands for
(the same numbers), its figure for existence, its mistakes for the one-line
error; ``run --help`` names the experiments; ``noslipsim plot`` of a table
with an infinite line shows the table.
"""
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from test_cli import assert_one_line_error, run_main

import noslipsim as ns
from noslipsim import analysis
from noslipsim.cli import main

ROOT = Path(__file__).resolve().parents[1]
BOX = str(ROOT / "examples" / "sinai_box.yaml")
PEG = str(ROOT / "examples" / "galton_peg.yaml")
SPECULAR_BOX = "law: specular\nelements:\n" + "".join(
    f"  - {{type: segment, p0: {a}, p1: {b}, side: left}}\n"
    for a, b in (([0, 0], [1, 0]), ([1, 0], [1, 1]), ([1, 1], [0, 1]), ([0, 1], [0, 0]))
) + "  - {type: circle, center: [0.5, 0.5], radius: 0.3, side: outside}\n"


@pytest.fixture
def specular_box(tmp_path):
    path = tmp_path / "specular_box.yaml"
    path.write_text(SPECULAR_BOX)
    return str(path)


def test_portrait_of_a_specular_scene_is_birkhoff_and_a_no_slip_one_velocity(tmp_path, specular_box, capsys):
    assert main(["portrait", specular_box, "--orbits", "3", "-n", "50", "-o", str(tmp_path / "b.nc"),
                 "--figure", str(tmp_path / "b.png")]) == 0
    b = xr.open_dataset(tmp_path / "b.nc")
    assert b.attrs["portrait"] == "birkhoff" and "sin_angle" in b and (tmp_path / "b.png").stat().st_size > 0
    again = analysis.birkhoff_coordinates(b)  # the stored coordinates are the library's
    np.testing.assert_array_equal(again.sin_angle.values, b.sin_angle.values)
    assert main(["portrait", BOX, "--orbits", "3", "-n", "50", "-o", str(tmp_path / "v.nc")]) == 0
    v = xr.open_dataset(tmp_path / "v.nc")
    assert v.attrs["portrait"] == "velocity" and "sin_angle" not in v
    ref = ns.experiments.phase_portrait(ns.Scene.from_yaml(BOX), n_orbits=3, n_collisions=50, seed=0,
                                        elements=[0, 1, 2, 3, 4], progress=False)
    np.testing.assert_array_equal(v.vt_unit.values, ref.vt_unit.values)
    assert "wrote velocity portrait of 3 orbits" in capsys.readouterr().out


def test_ensemble_is_simulate_many_from_one_point(tmp_path):
    out = tmp_path / "e.nc"
    assert main(["ensemble", PEG, "--position", "0.2", "2.5", "--orbits", "20", "-n", "10", "--seed", "3",
                 "-o", str(out), "--figure", str(tmp_path / "e.png")]) == 0
    e = xr.open_dataset(out)
    v = ns.initial.unit_velocities(20, seed=3)
    ref = ns.simulate_many(ns.Scene.from_yaml(PEG), [[0.2, 2.5]] * 20, v, max_collisions=10, record="final",
                           scheduler="sync")
    np.testing.assert_array_equal(e.x_final.values, ref.x_final.values)
    assert (tmp_path / "e.png").stat().st_size > 0


def test_periodic_finds_an_orbit_that_closes(tmp_path, capsys):
    out = tmp_path / "p.nc"
    assert main(["periodic", BOX, "--position", "0.1", "0.52", "--velocity", "1", "0.01", "--period", "2",
                 "-o", str(out), "--figure", str(tmp_path / "p.png")]) == 0
    p = xr.open_dataset(out)
    assert int(p.period) == 2 and float(p.residual) < 1e-10 and str(p.linear_kind.values) == "elliptic"
    # the written orbit repeats its post-collision state every 2 collisions
    for k in ("x", "y", "vx", "vy", "spin"):
        np.testing.assert_allclose(p[k].values[2:], p[k].values[:-2], atol=1e-9, err_msg=k)
    assert "found a 2-periodic orbit" in capsys.readouterr().out


def test_lyapunov_matches_the_library_and_is_positive_for_a_specular_sinai_box(tmp_path, specular_box):
    out = tmp_path / "l.nc"
    assert main(["lyapunov", specular_box, "--position", "0.1", "0.12", "--velocity", "0.6", "0.8",
                 "--max-time", "300", "-o", str(out), "--figure", str(tmp_path / "l.png")]) == 0
    lam = float(xr.open_dataset(out).lyapunov_exponent)
    ref = analysis.lyapunov(ns.Scene.from_yaml(specular_box), (0.1, 0.12), (0.6, 0.8), max_time=300)
    assert lam == ref and lam > 0.3
    assert xr.open_dataset(out).attrs["lyapunov_method"] == "tangent"


def test_lyapunov_twin_agrees_with_the_tangent_map_on_a_specular_sinai_box(tmp_path, specular_box):
    """Two methods, one orbit: the twin orbit's exponent per collision (``--twin``) against the exact tangent
    map's over about 2000 collisions.  They differ by the twin's finite separation and block ends (measured
    here: 0.06 % per collision, 0.16 % per unit time, 0.10 % in the mean free time; 0.2 % per collision over
    400 and 10^4); 1 % would still tell a wrong time or block count."""
    start = ["--position", "0.1", "0.12", "--velocity", "0.6", "0.8", "-n", "2000"]
    assert main(["lyapunov", specular_box, *start, "-o", str(tmp_path / "tangent.nc")]) == 0
    assert main(["lyapunov", specular_box, *start, "--twin", "-o", str(tmp_path / "twin.nc")]) == 0
    tangent, twin = xr.open_dataset(tmp_path / "tangent.nc"), xr.open_dataset(tmp_path / "twin.nc")
    assert twin.attrs["lyapunov_method"] == "twin"
    for name in ("lyapunov_per_collision", "lyapunov_exponent", "mean_free_time"):
        assert float(twin[name]) == pytest.approx(float(tangent[name]), rel=0.01), name


def test_animate_writes_a_gif_of_several_orbits(tmp_path, capsys):
    out = tmp_path / "a.gif"
    assert main(["animate", PEG, "--position", "0.3", "2.2", "--velocity", "0.5", "0", "--spin", "0.4",
                 "--position", "-1", "2", "--velocity", "0.2", "0.3", "--spin", "0", "-n", "4",
                 "--duration", "1", "--fps", "8", "--dpi", "30", "-o", str(out)]) == 0
    from PIL import Image

    with Image.open(out) as im:
        assert im.n_frames == 8
    assert "wrote" in capsys.readouterr().out


@pytest.mark.parametrize("scene, argv", [
    (PEG, ["--position", "0.3", "2", "--velocity", "0.1", "0", "--position", "-0.8", "2.5", "--velocity", "0", "0",
           "-n", "30"]),
    (BOX, ["--position", "0.1", "0.1", "--velocity", "1", "0.3", "-n", "5", "--max-time", "30"]),
])
def test_animate_draws_no_orbit_past_its_last_computed_flight(scene, argv, tmp_path, capsys, monkeypatch):
    from noslipsim import animation

    drawn = {}
    write = animation.animate

    def spy(*args, **kwargs):  # what the command drew, as animation.animate reports it
        drawn.update(write(*args, **kwargs))
        return drawn

    monkeypatch.setattr(animation, "animate", spy)
    assert main(["animate", scene, *argv, "--duration", "1", "--fps", "10", "--dpi", "30",
                 "-o", str(tmp_path / "a.gif")]) == 0
    table = ns.Scene.from_yaml(scene)
    for j, orbit in enumerate(drawn["orbits"]):
        assert drawn["orbit_times"][j].max() <= float(orbit.t_final)
        assert np.all(table.depth(drawn["positions"][j]) >= -1e-9)
    x0, x1, y0, y1 = drawn["window"]
    assert x0 > -4 and x1 < 4 and y0 > -1 and y1 < 4  # the table's size, not a flight through its walls
    assert "orbit 1 stopped at t = " in capsys.readouterr().out


@pytest.mark.parametrize("argv, fragments", [
    (["portrait", BOX, "--orbits", "0", "-o", "x.nc"], ["--orbits: must be >= 1"]),
    (["portrait", BOX, "--figure", "x.abc", "--orbits", "1", "-n", "5", "-o", "{tmp}/x.nc"],
     ["--figure: unknown image format"]),
    (["ensemble", BOX, "--position", "0.5", "0.5", "-o", "x.nc"], ["--position", "not strictly inside the table"]),
    (["ensemble", BOX, "--position", "0.1", "0.1", "--speed", "0", "-o", "x.nc"], ["--speed: must be finite and > 0"]),
    (["periodic", BOX, "--position", "0.1", "0.1", "--velocity", "1", "0", "--period", "0", "-o", "x.nc"],
     ["--period: must be >= 1"]),
    (["lyapunov", BOX, "--position", "0.5", "0.5", "--velocity", "1", "0", "-o", "x.nc"], ["--position"]),
    (["animate", BOX, "--position", "0.1", "0.1", "--velocity", "1", "0", "--velocity", "1", "1", "-o", "x.gif"],
     ["--velocity: give one per --position (1), got 2"]),
    (["animate", BOX, "--position", "0.1", "0.1", "--velocity", "1", "0", "-o", "x.avi"], ["expected one of"]),
    (["explore", BOX, "--port", "70000", "--no-browser"], ["--port: expected 0 to 65535"]),
    (["animate", BOX, "--position", "0.1", "0.1", "--velocity", "1", "0", "--dpi", "100000", "-o", "{tmp}/x.gif"],
     ["--dpi: a frame of 600000 x 450000 pixels does not fit in memory"]),
    (["ensemble", BOX, "--position", "0.1", "0.1", "--orbits", "1000000000000", "-o", "{tmp}/x.nc"],
     ["--orbits: a run of 1000000000000 orbits does not fit in memory"]),
])
def test_mistakes_are_one_line(argv, fragments, capsys, tmp_path):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    status, err = run_main(argv, capsys)
    assert_one_line_error(status, err, *fragments)


def test_run_help_lists_the_experiments_and_start_options_have_help(capsys):
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for name in ns.experiments.EXPERIMENTS:
        assert name in text
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--position X Y start point, strictly inside the table" in text
    assert "--velocity VX VY initial velocity" in text


def test_submodules_are_attributes_of_the_package():
    assert ns.experiments.EXPERIMENTS["galton_distribution"] is ns.experiments.galton_distribution
    assert ns.tables.lemon is not None and ns.analysis.lyapunov is not None
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        ns.nothing  # noqa: B018


def test_plot_of_a_table_with_an_infinite_line_shows_the_table():
    from noslipsim.cli import _plot_window

    scene = ns.Scene.from_yaml(PEG)  # a floor (line), a peg, an arc of radius 3 from (3, 0) over to (-3, 0)
    x0, x1, y0, y1 = _plot_window(scene, np.array([0.1, 0.2]), np.array([1.8, 2.0]))
    assert x0 < -3 and x1 > 3 and y0 <= 0 and y1 > 3
    assert y0 > -1  # the arc's box, not the whole circle's
    torus = ns.tables.sinai_torus(0.25)
    x0, x1, y0, y1 = _plot_window(torus, np.array([0.4]), np.array([0.1]))
    assert x0 <= -1.5 and x1 >= 1.5  # cell 0 and one cell on every side
    assert math.isfinite(x0 + x1 + y0 + y1)


# ---------------------------------------------------------------------------- refused before any work
ORBIT = ["--position", "0.1", "0.1", "--velocity", "1", "0.3"]


@pytest.mark.parametrize("argv, fragments", [
    (["simulate", BOX, *ORBIT, "-o", "{tmp}/o.csv"], ["-o/--output", "netCDF"]),
    (["plot", BOX, *ORBIT, "-o", "{tmp}/o.xyz"], ["-o/--output: unknown image format 'xyz'"]),
    (["run", "{tmp}/exp.yaml", "-o", "{tmp}/o.txt"], ["-o/--output", "netCDF"]),
    (["portrait", BOX, "-o", "{tmp}/o.nc", "--figure", "{tmp}/o.xyz"], ["--figure: unknown image format 'xyz'"]),
    (["portrait", BOX, "-o", "{tmp}/o.csv"], ["-o/--output", "netCDF"]),
    (["ensemble", BOX, "--position", "0.1", "0.1", "-o", "{tmp}/o.nc", "--figure", "{tmp}/o.xyz"],
     ["--figure: unknown image format 'xyz'"]),
    (["periodic", BOX, *ORBIT, "--period", "2", "-o", "{tmp}/o.nc", "--figure", "{tmp}/o.xyz"],
     ["--figure: unknown image format 'xyz'"]),
    (["lyapunov", BOX, *ORBIT, "-o", "{tmp}/o.nc", "--figure", "{tmp}/o"], ["--figure: unknown image format ''"]),
    (["animate", BOX, *ORBIT, "-o", "{tmp}/o.avi"], ["-o/--output: unknown animation format 'avi'"]),
    (["simulate", BOX, *ORBIT, "-o", "{tmp}/exp.yaml/o.nc"], ["-o/--output: cannot write", "is a file, not a folder"]),
    (["ensemble", BOX, "--position", "0.1", "0.1", "-o", "{tmp}/o.nc", "--figure", "{tmp}/sub"],
     ["--figure: ", "is a folder"]),
    (["plot", BOX, *ORBIT, "-o", "{tmp}/exp.yaml/deeper/o.png"], ["-o/--output: cannot write"]),
])
def test_an_output_that_cannot_be_written_is_refused_before_any_work(argv, fragments, tmp_path, capsys,
                                                                     monkeypatch):
    from noslipsim import cli

    (tmp_path / "exp.yaml").write_text("experiment: galton_distribution\n")
    (tmp_path / "sub").mkdir()
    before = sorted(tmp_path.rglob("*"))
    monkeypatch.setitem(cli.COMMANDS, argv[0], None)  # running the command at all would be an internal error
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert_one_line_error(*run_main(argv, capsys), *fragments)
    assert sorted(tmp_path.rglob("*")) == before  # nothing written


@pytest.mark.parametrize("argv, fragments", [
    (["plot", BOX, *ORBIT, "--window", "0", "-1", "0", "1", "-o", "{tmp}/o.png"], ["--window: expected finite"]),
    (["plot", BOX, *ORBIT, "--spin-every", "0", "-o", "{tmp}/o.png"], ["--spin-every: must be >= 1"]),
    (["periodic", BOX, *ORBIT, "--period", "1000000", "--periods", "1000000", "-o", "{tmp}/o.nc"],
     ["--period, --periods: a log of 1000000000000 collisions does not fit in memory"]),
    (["animate", BOX, *ORBIT, "--radius", "0", "-o", "{tmp}/o.gif"], ["--radius: expected a positive number"]),
    (["animate", BOX, *ORBIT, "--window", "0", "1", "1", "1", "-o", "{tmp}/o.gif"], ["--window: expected finite"]),
])
def test_options_are_checked_before_any_orbit_is_simulated(argv, fragments, tmp_path, capsys, monkeypatch):
    import importlib

    # simulating or searching now would be an internal error
    for module, name in (("noslipsim.simulate", "simulate"), ("noslipsim.animation", "simulate"),
                         ("noslipsim.analysis", "find_periodic_orbit")):
        monkeypatch.setattr(importlib.import_module(module), name, None)
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert_one_line_error(*run_main(argv, capsys), *fragments)
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------------------- messages
def test_periodic_says_what_happened_when_the_found_orbit_does_not_close_again(tmp_path, capsys):
    # Newton closes the map to rounding here, but the orbit re-run from its state does not close
    status, err = run_main(["periodic", PEG, "--position", "0.9", "0.5", "--velocity", "1", "0", "--period", "3",
                            "-o", str(tmp_path / "p.nc")], capsys)
    assert_one_line_error(status, err, "--position/--velocity: the search reached residual",
                          "does not close after 3 collisions", "no 3-periodic orbit is confirmed")
    assert "not found" not in err and not (tmp_path / "p.nc").exists()


def test_periodic_has_no_collision_option_and_its_help_no_unused_one(capsys):
    assert_one_line_error(*run_main(["periodic", BOX, *ORBIT, "--period", "2", "-n", "5", "-o", "p.nc"], capsys),
                          "unrecognized arguments: -n 5")
    with pytest.raises(SystemExit):
        main(["periodic", "--help"])
    assert "not used" not in capsys.readouterr().out


@pytest.mark.parametrize("law, kind, fragments", [
    ("no-slip", [], ["velocity portrait (v_t, w)"]),
    ("specular", [], ["Birkhoff portrait"]),
    ("no-slip", ["--kind", "birkhoff"], ["Birkhoff portrait"]),
])
def test_a_portrait_of_lines_only_names_the_portrait_of_the_scene(law, kind, fragments, tmp_path, capsys):
    wedge = tmp_path / "wedge.yaml"
    wedge.write_text(f"law: {law}\nforce: [0, -1]\nelements:\n  - {{type: line, point: [0, 0], normal: [0.8, 0.6]}}\n"
                     "  - {type: line, point: [0, 0], normal: [-0.8, 0.6]}\n")
    status, err = run_main(["portrait", str(wedge), *kind, "-o", str(tmp_path / "w.nc")], capsys)
    assert_one_line_error(status, err, "every element is an infinite line", *fragments)
    if law == "no-slip" and not kind:
        assert "Birkhoff" not in err


def test_lyapunov_of_the_wedge_from_the_shell(tmp_path, capsys):
    # the paper's wedge is lines alone (no length scale): the command failed with a raw RuntimeWarning
    path = tmp_path / "wedge.yaml"
    wedge = ns.tables.wedge(0.6, law="specular")
    wedge.to_yaml(path)
    out = tmp_path / "w.nc"
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        assert main(["lyapunov", str(path), "--position", "0", "1", "--velocity", "0.5", "0.4", "--spin", "0.3",
                     "-n", "1000", "-o", str(out)]) == 0
    lam = float(xr.open_dataset(out).lyapunov_exponent)
    assert lam == analysis.lyapunov(wedge, (0.0, 1.0), (0.5, 0.4), 0.3, n_collisions=1000) and lam > 0.1
    assert "lambda = " in capsys.readouterr().out
