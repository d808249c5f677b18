"""The kernels run as plain Python under ``NUMBA_DISABLE_JIT=1`` (debugging, coverage), with the compiled results.

One orbit of every flight the event loop has (straight, constant force, the isokinetic thermostat, the magnetic
field, the lean loop of disks on a lattice) runs in a process without numba's compiler and must equal the compiled
orbit bit for bit.  Python's ``math.hypot`` is CPython's own algorithm while the compiled kernels call the C library's
``hypot``; the two may differ in the last bit (on the Galton board the orbits part at collision 30), so the
plain-Python process calls the C library's, as the compiled code does.
"""
import json
import math
import os
import subprocess
import sys

import pytest

import noslipsim as ns

N = 60


def _flights():
    return {
        "straight": (ns.tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]), (0.1, 0.1), (0.6, 0.8)),
        "force": (ns.tables.galton_board(2.0, 0.5, 1.0), (1.0, 0.0), (0.6, 0.8)),
        "thermostat": (ns.Scene((ns.Circle((0.0, 0.0), 0.4, "outside"),), force=(0.3, -0.2),
                                thermostat="isokinetic", lattice={"a1": [1.0, 0.0], "a2": [0.5, math.sqrt(3) / 2]}),
                       (0.5, 0.3), (0.6, 0.8)),
        "disks": (ns.tables.sinai_torus(0.25), (0.45, 0.1), (0.6, 0.8)),
        "magnetic": (ns.tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]).replace(magnetic=1.5), (0.1, 0.1),
                     (0.6, 0.8)),
    }


def _log(name):
    scene, q, v = _flights()[name]
    o = ns.simulate(scene, q, v, max_collisions=N)
    return [float(x).hex() for var in ("t", "x", "y", "vx", "vy", "spin") for x in o[var].values]


_CHILD = """
import ctypes, ctypes.util, json, math, sys
libm = ctypes.CDLL(ctypes.util.find_library("m"))
libm.hypot.restype = ctypes.c_double
libm.hypot.argtypes = [ctypes.c_double, ctypes.c_double]
math.hypot = libm.hypot  # the C library's, as the compiled kernels call it
import numba
assert numba.config.DISABLE_JIT
sys.path.insert(0, {tests!r})
import test_disable_jit as t
print(json.dumps({{name: t._log(name) for name in sys.argv[1:]}}))
"""


@pytest.fixture(scope="module")
def plain_python():
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    code = _CHILD.format(tests=os.path.dirname(os.path.abspath(__file__)))
    out = subprocess.run([sys.executable, "-c", code, *_flights()], env=env, capture_output=True, text=True,
                         timeout=900)
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("name", list(_flights()))
def test_every_flight_runs_as_plain_python_with_the_compiled_bits(plain_python, name):
    compiled = _log(name)
    assert len(compiled) == 6 * N
    assert plain_python[name] == compiled


def test_the_kernels_are_plain_functions_without_the_compiler():
    code = ("import noslipsim.core.loop as l, noslipsim.core.exact as e, types; "
            "assert isinstance(l.run_orbit, types.FunctionType); "
            "assert e.fma(0.1, 10.0, -1.0) == 5.551115123125783e-17; print('ok')")
    out = subprocess.run([sys.executable, "-c", code], env=dict(os.environ, NUMBA_DISABLE_JIT="1"),
                         capture_output=True, text=True, timeout=300)
    assert out.stdout.strip() == "ok", out.stderr[-2000:]
    # the compiled fma rounds once too: 0.1 * 10 - 1 is not 0 exactly
    assert ns.core.exact.fma(0.1, 10.0, -1.0) == 5.551115123125783e-17 != 0.1 * 10.0 - 1.0


def test_the_cache_stamp_covers_every_source_below_core(tmp_path):
    from noslipsim.core.jit import CORE, SOURCE_DIGEST, source_digest

    assert source_digest(CORE) == SOURCE_DIGEST
    (tmp_path / "a.py").write_text("x = 1\n")
    (tmp_path / "flights").mkdir()
    nested = tmp_path / "flights" / "straight.py"
    nested.write_text("y = 1\n")
    before = source_digest(tmp_path)
    nested.write_text("y = 2\n")
    assert source_digest(tmp_path) != before
    nested.rename(tmp_path / "flights" / "force.py")
    assert source_digest(tmp_path) not in (before, source_digest(tmp_path / "flights"))
