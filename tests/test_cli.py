"""The command line: every user error is one line ``noslipsim: error: ...`` with exit status 2.

Most cases call :func:`noslipsim.cli.main` in this process (fast); a few run
the installed ``noslipsim`` entry point in a subprocess, to see what a user
sees (no traceback, the exit status, ``--debug``).
"""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from noslipsim.cli import EXIT_INTERNAL, EXIT_USAGE, main

ROOT = Path(__file__).resolve().parents[1]
BOX = str(ROOT / "examples" / "sinai_box.yaml")  # [0, 1]^2 with a disk of radius 0.3 at the centre
START = ["--position", "0.1", "0.1", "--velocity", "0.6", "0.8"]

GOOD_SCENE = "law: specular\nelements:\n  - {type: circle, center: [0, 0], radius: 1, side: inside}\n"


def run_main(argv, capsys):
    """Exit status and stderr of ``main(argv)``; argparse errors exit through SystemExit."""
    try:
        status = main(argv)
    except SystemExit as stop:
        status = stop.code
    return status, capsys.readouterr().err


def assert_one_line_error(status, err, *fragments):
    assert status == EXIT_USAGE, err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("noslipsim: error: "), err
    assert "Traceback" not in err
    for frag in fragments:
        assert frag in lines[0], (frag, err)


def scene_file(tmp_path, text, name="scene.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


# ---------------------------------------------------------------------------- files
def test_missing_scene_file(capsys, tmp_path):
    missing = str(tmp_path / "nope.yaml")
    assert_one_line_error(*run_main(["simulate", missing, *START], capsys), "no such file", "nope.yaml")


def test_unreadable_scene_file(capsys, tmp_path):
    # a folder where a file is expected (permissions do not stop root, a folder does)
    assert_one_line_error(*run_main(["simulate", str(tmp_path), *START], capsys), str(tmp_path), "directory")
    binary = tmp_path / "scene.yaml"
    binary.write_bytes(b"\xff\xfe\x00\x01law")
    assert_one_line_error(*run_main(["simulate", str(binary), *START], capsys), "scene.yaml", "UTF-8")


@pytest.mark.parametrize("text, where", [
    ("law: no-slip\n  gamma: 1\n", "line 2, column 8"),                      # bad indentation
    ("law: specular\nelements: [{type: circle, center: [0, 0]\n", "line 3"),  # unclosed flow mapping
    ("law: 'no-slip\n", "line 2"),                                           # unterminated quote
])
def test_yaml_syntax_error_gives_line_and_column(capsys, tmp_path, text, where):
    path = scene_file(tmp_path, text)
    assert_one_line_error(*run_main(["simulate", path, *START], capsys), "scene.yaml", "YAML syntax error", where)


# ---------------------------------------------------------------------------- scene contents
@pytest.mark.parametrize("text, fragments", [
    ("- a list\n- of things\n", ["expected a YAML mapping", "got list"]),
    (GOOD_SCENE + "colour: red\n", ["unknown key(s) ['colour']", "allowed"]),
    ("elements:\n  - {type: circle, center: [0, 0], radius: 1, colour: red}\n",
     ["elements[0]", "unknown key(s) ['colour']"]),
    ("elements:\n  - {type: ellipse, center: [0, 0]}\n", ["elements[0].type", "'ellipse'", "expected one of"]),
    ("gamma: heavy\n" + GOOD_SCENE.split("\n", 1)[1], ["gamma", "expected a number", "'heavy'"]),
    ("elements: 5\n", ["elements", "expected a list"]),
    ("elements:\n  - {type: circle, center: [0, 0], radius: [1, 2]}\n", ["elements[0].radius", "expected a number"]),
    ("elements:\n  - {type: circle, center: [0, 0], radius: -1}\n", ["elements[0].radius", "must be > 0"]),
    ("elements:\n  - {type: circle, center: [0, .nan], radius: 1}\n", ["elements[0].center", "finite"]),
    ("elements:\n  - {type: segment, p0: [0, 0], p1: [0, 0]}\n", ["elements[0]", "zero-length"]),
    ("law: sticky\n" + GOOD_SCENE.split("\n", 1)[1], ["law", "'sticky'", "'no-slip' or 'specular'"]),
    ("force: [0, -1, 0]\n" + GOOD_SCENE.split("\n", 1)[1], ["force", "expected 2 numbers"]),
    ("elements:\n  - {type: circle, center: [0, 0], radius: 0.2}\nlattice: {a1: [1, 0], a2: [2, 0]}\n",
     ["lattice", "linearly independent"]),
])
def test_bad_scene_file_names_the_file_and_field(capsys, tmp_path, text, fragments):
    path = scene_file(tmp_path, text)
    assert_one_line_error(*run_main(["simulate", path, *START], capsys), path, *fragments)


# ---------------------------------------------------------------------------- start and numbers
@pytest.mark.parametrize("args, fragments", [
    (["--position", "5", "5", "--velocity", "1", "0"], ["--position", "outside the table"]),
    (["--position", "0.5", "0.5", "--velocity", "1", "0"], ["--position", "outside the table"]),  # in the disk
    (["--position", "a", "0.1", "--velocity", "1", "0"], ["--position", "invalid float value: 'a'"]),
    (["--position", "0.1", "--velocity", "1", "0"], ["--position", "expected 2 arguments"]),
    (["--position", "nan", "0.1", "--velocity", "1", "0"], ["--position", "finite"]),
    (["--position", "0.1", "0.1", "--velocity", "inf", "0"], ["--velocity", "finite"]),
    (["--position", "0.1", "0.1", "--velocity", "0", "0"], ["--velocity", "zero speed with zero force"]),
    ([*START, "--spin", "nan"], ["--spin", "finite"]),
    ([*START, "-n", "-3"], ["-n/--max-collisions", ">= 0"]),
    ([*START, "-n", "2.5"], ["--max-collisions", "invalid int value"]),
    ([*START, "-n", "100000000000000"], ["-n/--max-collisions", "does not fit in memory"]),
    ([*START, "--max-time", "0"], ["--max-time", "> 0"]),
    ([*START, "--stop-below", "0.5"], ["--stop-below", "below the start height"]),
    (["--velocity", "1", "0"], ["--position", "required"]),
])
def test_bad_start_or_number_names_the_option(capsys, args, fragments):
    assert_one_line_error(*run_main(["simulate", BOX, *args], capsys), *fragments)


def test_unknown_command_and_option(capsys):
    assert_one_line_error(*run_main(["frobnicate"], capsys), "invalid choice", "'frobnicate'")
    assert_one_line_error(*run_main(["simulate", BOX, *START, "--colour", "red"], capsys), "--colour")


def test_good_run_still_works(capsys, tmp_path):
    path = scene_file(tmp_path, GOOD_SCENE)
    assert main(["simulate", path, "--position", "0.1", "0.2", "--velocity", "1", "0", "-n", "3"]) == 0
    out = capsys.readouterr()
    assert out.err == "" and "stop_reason: max_collisions" in out.out


# ---------------------------------------------------------------------------- experiment configs
@pytest.mark.parametrize("text, fragments", [
    ("experiment: nothing\n", ["experiment", "'nothing'", "expected one of", "galton_distribution"]),
    ("parameters: {rows: 3}\n", ["expected a mapping with keys 'experiment'"]),
    ("experiment: galton_distribution\nseed: 3\n", ["expected a mapping with keys 'experiment'"]),
    ("experiment: galton_distribution\nparameters: [1, 2]\n", ["parameters", "expected a mapping"]),
    ("experiment: galton_distribution\nparameters: {colour: red}\n", ["parameters", "colour"]),
    ("experiment: galton_distribution\nparameters: {n_particles: 4, radius: 1.5}\n", ["parameters", "radius"]),
    ("experiment: galton_distribution\nparameters: {n_particles: 4\n", ["YAML syntax error", "line"]),
])
def test_bad_experiment_config(capsys, tmp_path, text, fragments):
    cfg = scene_file(tmp_path, text, "exp.yaml")
    out = str(tmp_path / "out.nc")
    assert_one_line_error(*run_main(["run", cfg, "-o", out], capsys), "exp.yaml", *fragments)
    assert not os.path.exists(out)


def test_missing_experiment_config(capsys, tmp_path):
    assert_one_line_error(*run_main(["run", str(tmp_path / "exp.yaml"), "-o", str(tmp_path / "o.nc")], capsys),
                          "no such file", "exp.yaml")


# ---------------------------------------------------------------------------- bugs and --debug
def test_internal_error_is_one_line_with_exit_1(capsys, monkeypatch):
    from noslipsim import cli

    def broken(args):
        raise RuntimeError("a bug")

    monkeypatch.setitem(cli.COMMANDS, "simulate", broken)
    status, err = run_main(["simulate", BOX, *START], capsys)
    assert status == EXIT_INTERNAL and len(err.splitlines()) == 1
    assert err.startswith("noslipsim: internal error: RuntimeError: a bug") and "--debug" in err
    with pytest.raises(RuntimeError, match="a bug"):
        main(["--debug", "simulate", BOX, *START])


def test_debug_reraises_user_errors_in_process():
    with pytest.raises(FileNotFoundError):
        main(["simulate", "nope.yaml", *START, "--debug"])
    with pytest.raises(ValueError, match="outside the table"):
        main(["--debug", "simulate", BOX, "--position", "5", "5", "--velocity", "1", "0"])


def _cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "noslipsim.cli", *args], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


def test_installed_command_prints_one_line_and_debug_prints_the_traceback(tmp_path):
    path = scene_file(tmp_path, "law: no-slip\n  gamma: 1\n")
    plain = _cli("simulate", path, *START, cwd=tmp_path)
    assert plain.returncode == EXIT_USAGE and plain.stdout == ""
    assert plain.stderr.splitlines() == [
        f"noslipsim: error: {path}: YAML syntax error at line 2, column 8: mapping values are not allowed here"]
    debug = _cli("simulate", path, *START, "--debug", cwd=tmp_path)
    assert debug.returncode != 0 and "Traceback (most recent call last)" in debug.stderr
    assert "line 2, column 8" in debug.stderr.splitlines()[-1]


# ---------------------------------------------------------------------------- noslipsim plot
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("scene, start", [
    (BOX, START),                                                                     # plain, no force
    # lines, force
    (str(ROOT / "examples" / "galton_peg.yaml"), ["--position", "0.1", "2.0", "--velocity", "0.3", "0"]),
])
def test_plot_writes_an_image(capsys, tmp_path, scene, start):
    out = tmp_path / "figs" / "orbit.png"
    assert main(["plot", scene, *start, "-n", "12", "--spin-every", "3", "-o", str(out)]) == 0
    assert out.read_bytes()[:8] == PNG_MAGIC and out.stat().st_size > 5000
    assert "wrote" in capsys.readouterr().out


def test_plot_of_a_lattice_scene_and_a_pdf(tmp_path):
    path = scene_file(tmp_path, "elements:\n  - {type: circle, center: [0, 0], radius: 0.3}\n"
                                "lattice: {a1: [1, 0], a2: [0, 1]}\n")
    out = tmp_path / "torus.pdf"
    assert main(["plot", path, "--position", "0.5", "0.5", "--velocity", "1", "0.31", "-n", "20",
                 "-o", str(out)]) == 0
    assert out.read_bytes()[:5] == b"%PDF-"


@pytest.mark.parametrize("args, fragments", [
    (["--position", "5", "5", "--velocity", "1", "0", "-o", "x.png"], ["--position", "outside the table"]),
    ([*START, "-o", "orbit.xyz"], ["-o/--output", "unknown image format 'xyz'", "png"]),
    ([*START, "-o", "x.png", "--window", "1", "0", "0", "1"], ["--window", "x1 > x0"]),
    ([*START], ["-o/--output", "required"]),
])
def test_plot_rejects_bad_arguments(capsys, tmp_path, args, fragments):
    args = [str(tmp_path / a) if a.endswith((".png", ".xyz")) else a for a in args]
    assert_one_line_error(*run_main(["plot", BOX, *args], capsys), *fragments)
    assert not list(tmp_path.iterdir())


def test_plot_rejects_a_bad_scene(capsys, tmp_path):
    path = scene_file(tmp_path, "elements:\n  - {type: circle, center: [0, 0], radius: -1}\n")
    out = tmp_path / "orbit.png"
    assert_one_line_error(*run_main(["plot", path, *START, "-o", str(out)], capsys),
                          "scene.yaml", "elements[0].radius", "must be > 0")
    assert not out.exists()
