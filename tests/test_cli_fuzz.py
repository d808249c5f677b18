"""Fuzzing of the command line's options (hypothesis), in process through :func:`noslipsim.cli.main`.

Each example runs one subcommand on a small scene with few collisions and
replaces some of its options by values out of range, huge, negative, NaN or
infinite spellings, wrong types, missing files and bad extensions.  The one
rule: exit 0 with an answer (a simulated orbit inside its table), or exit 2
with one line ``noslipsim: error: ...``; never a traceback, never exit 1 or
any other status.  ``explore`` is left out (a valid call serves until
interrupted).

The default run is bounded and reproducible (``derandomize``); ``python -m
pytest -m stress`` runs many more, randomised.
"""
import contextlib
import io
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import noslipsim as ns
from noslipsim.cli import EXIT_USAGE, main

ROOT = Path(__file__).resolve().parents[1]
BOX = str(ROOT / "examples" / "sinai_box.yaml")  # [0, 1]^2 with a disk of radius 0.3 at the centre
#: No per-example deadline: the first example of a command compiles its kernel variant (2 minutes under load,
#: then 1.3 s), and what these tests assert is the exit status and the message, not the time.
DEFAULT = dict(deadline=None, derandomize=True, database=None, max_examples=120,
               suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
STRESS = dict(DEFAULT, derandomize=False, max_examples=1500)

# ---------------------------------------------------------------------------- values
WILD = ["nan", "NaN", "inf", "-inf", "1e400", "-1e400", "abc", "", " ", "0x10", "1_0", "--", "5e-324",
        "1e300", "-1e300", "1.7976931348623157e308"]
number = st.one_of(st.sampled_from(WILD), st.floats(-3, 3, allow_nan=False).map(repr),
                   st.integers(-10**20, 10**20).map(str))
count = st.one_of(st.sampled_from(["nan", "1.5", "-1", "0", "1e3", "abc", "", str(10**12), str(2**63), str(-2**63)]),
                  st.integers(0, 6).map(str), st.integers(-10**15, 10**15).map(str))
small = st.floats(0.05, 0.95, allow_nan=False).map(repr)


@st.composite
def path(draw, kind):
    """An output path: good, of another format, a folder, below a file, or a missing input."""
    good = {"dataset": "o.nc", "image": "o.png", "animation": "o.gif"}[kind]
    return draw(st.sampled_from([good, good, "o.csv", "o.xyz", "o", "sub", "scene.yaml/o.nc", "nope/" + good,
                                 ".nc", "o.NC"]))


def scene_arg(draw):
    return draw(st.sampled_from([BOX, BOX, BOX, "{tmp}/missing.yaml", "{tmp}/sub", "{tmp}/junk.yaml",
                                 "{tmp}/scene.yaml"]))


ORBIT = {"--position": ["0.1", "0.1"], "--velocity": ["1", "0.3"]}
#: Each command's base options (small, quick runs) and the options the fuzzer may replace.
COMMANDS = {
    "simulate": ({**ORBIT, "-n": ["5"], "--max-time": ["5"], "-o": ["o.nc"]},
                 ["--position", "--velocity", "--spin", "-n", "--max-time", "--stop-below", "-o"]),
    "plot": ({**ORBIT, "-n": ["5"], "--max-time": ["5"], "-o": ["o.png"]},
             ["--position", "--velocity", "-n", "--max-time", "--stop-below", "--window", "--spin-every", "-o"]),
    "portrait": ({"--orbits": ["2"], "-n": ["20"], "-o": ["o.nc"]},
                 ["--orbits", "-n", "--seed", "--kind", "-o", "--figure"]),
    "ensemble": ({"--position": ["0.1", "0.1"], "--orbits": ["5"], "-n": ["20"], "--max-time": ["5"],
                  "-o": ["o.nc"]},
                 ["--position", "--speed", "--orbits", "--seed", "-n", "--max-time", "--stop-below", "-o",
                  "--figure"]),
    "periodic": ({"--position": ["0.1", "0.52"], "--velocity": ["1", "0.01"], "--period": ["2"], "-o": ["o.nc"]},
                 ["--position", "--velocity", "--spin", "--period", "--periods", "--tol", "-o", "--figure"]),
    "lyapunov": ({**ORBIT, "--max-time": ["20"], "-o": ["o.nc"]},
                 ["--position", "--velocity", "--spin", "--max-time", "-n", "-o", "--figure"]),
    "animate": ({**ORBIT, "-n": ["3"], "--duration": ["0.3"], "--fps": ["5"], "--dpi": ["20"], "-o": ["o.gif"]},
                ["--position", "--velocity", "--spin", "-n", "--max-time", "--duration", "--fps", "--trail",
                 "--window", "--radius", "--dpi", "-o"]),
}
INTEGER_OPTIONS = {"-n", "--orbits", "--seed", "--spin-every", "--period", "--periods", "--fps", "--dpi"}
PAIRS = {"--position", "--velocity"}


@st.composite
def option_value(draw, command, option):
    if option == "-o":
        kind = {"plot": "image", "animate": "animation"}.get(command, "dataset")
        return [draw(path(kind))]
    if option == "--figure":
        return [draw(path("image"))]
    if option == "--kind":
        return [draw(st.sampled_from(["velocity", "birkhoff", "other", ""]))]
    if option in PAIRS:
        return [draw(st.one_of(small, number)), draw(st.one_of(small, number))]
    if option == "--window":
        return [draw(st.one_of(number, st.sampled_from(["-1", "2"]))) for _ in range(4)]
    return [draw(count if option in INTEGER_OPTIONS else number)]


@st.composite
def command_line(draw):
    """``(command, argv)`` with ``{tmp}`` for the example's folder."""
    command = draw(st.sampled_from(sorted(COMMANDS)))
    base, mutable = COMMANDS[command]
    options = dict(base)
    for option in draw(st.lists(st.sampled_from(mutable), min_size=1, max_size=3, unique=True)):
        options[option] = draw(option_value(command, option))
    argv = [command, scene_arg(draw)]
    for option, values in options.items():
        if option in ("-o", "--figure"):
            values = ["{tmp}/" + values[0]]
        argv += [f"{option}={values[0]}"] if len(values) == 1 else [option, *values]
    return command, argv


def run(argv):
    """Exit status, stdout and stderr of ``main(argv)`` in this process."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            status = main(argv)
        except SystemExit as stop:
            status = stop.code
    return status, out.getvalue(), err.getvalue()


def check_the_rule(tmp_path, command, argv):
    folder = tmp_path / f"case{len(list(tmp_path.iterdir()))}"
    folder.mkdir()
    (folder / "sub").mkdir()
    (folder / "scene.yaml").write_text(Path(BOX).read_text())
    (folder / "junk.yaml").write_text("law: [\n")
    argv = [a.replace("{tmp}", str(folder)) for a in argv]
    status, _, err = run(argv)
    if status == 0:
        assert err == "", (argv, err)
        written = folder / "o.nc"
        if command == "simulate" and written.exists():  # an answer: the orbit lies inside its table
            with xr.open_dataset(written) as orbit:
                scene = ns.Scene.from_yaml(BOX)
                xy = np.c_[orbit.x.values, orbit.y.values]
                assert np.all(scene.depth(xy) > -1e-9), argv
        return status
    assert status == EXIT_USAGE, (argv, status, err)
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("noslipsim: error: "), (argv, err)
    assert "Traceback" not in err and "internal error" not in err, (argv, err)
    return status


@settings(**DEFAULT)
@given(case=command_line())
def test_every_option_value_ends_in_an_answer_or_one_line(case, tmp_path):
    check_the_rule(tmp_path, *case)


@pytest.mark.stress
@settings(**STRESS)
@given(case=command_line())
def test_every_option_value_ends_in_an_answer_or_one_line_stress(case, tmp_path):
    check_the_rule(tmp_path, *case)


@pytest.mark.parametrize("argv", [
    ["simulate", BOX, "--position", "0.1", "0.1", "--velocity", "nan", "0.3", "-o", "{tmp}/o.nc"],
    ["ensemble", BOX, "--position", "0.1", "0.1", "--orbits", str(10**12), "-o", "{tmp}/o.nc"],
    ["animate", BOX, "--position", "0.1", "0.1", "--velocity", "1", "0", "--dpi", "100000", "-o", "{tmp}/o.gif"],
    # found by the fuzzer: duration x fps overflowed to infinity (OverflowError, exit 1)
    ["animate", BOX, "--position", "0.1", "0.1", "--velocity", "1", "0", "--duration", "1.7976931348623157e308",
     "-o", "{tmp}/o.gif"],
    # found by the stress fuzzer: fonts below a pixel (FreeType's invalid ppem, exit 1); the portrait's record
    # buffer (MemoryError, exit 1)
    ["animate", BOX, "--position", "0.1", "0.1", "--velocity", "1", "0", "--dpi", "2", "-o", "{tmp}/o.gif"],
    ["portrait", BOX, "--orbits", str(10**12), "-n", "20", "-o", "{tmp}/o.nc"],
])
def test_known_cases_obey_the_rule(argv, tmp_path):
    assert check_the_rule(tmp_path, argv[0], argv) == EXIT_USAGE
