"""Results never depend on the compile cache: which process compiled which variant, in which order.

numba caches compiled kernels on disk and every Snakemake job, dask worker or
notebook loads them.  Two variants of the event loop first compiled in two
processes once shared one machine-code symbol, and a process that loaded both
ran the first one's physics for the second (a run with gravity ran without
it; a portrait came back empty).  Here every variant is compiled in a process
of its own, two processes at a time, into one fresh cache, as a Snakemake run
does; then one process loads them all, in both orders, and each result must
equal the one its own process computed, bit for bit.  A cache entry tampered
to hold another variant's code must be refused by the kernels' variant guard.
"""
import glob
import json
import os
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

PROBE = Path(__file__).with_name("cache_probe.py")

#: table:law:record:scheduler (tests/cache_probe.py): force or not, specular or no-slip, final, portrait
#: or log records, plain or lattice (the lean disk loop and the general cell walk), long walls, one orbit
#: (simulate) or many, dask threads or plain threads.
CASES = [
    "disk:no-slip:final:sync",
    "disk+force:no-slip:final:sync",
    "disk:specular:final:sync",
    "disk:specular:portrait:sync",
    "disk:specular:log:threads",
    "disk:no-slip:orbit:-",
    "torus:no-slip:final:sync",
    "galton:no-slip:final:sync",
    "wedge:no-slip:log:sync",
    "disk:no-slip:final:numba",
]


def probe(cases, cache, check=True):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    proc = subprocess.run([sys.executable, str(PROBE), *cases], capture_output=True, text=True, env=env)
    if check:
        assert proc.returncode == 0, proc.stderr[-3000:]
        return json.loads(proc.stdout)
    return proc


@pytest.fixture(scope="module")
def filled(tmp_path_factory):
    """A fresh cache filled by one process per case, two at a time; each case's result in its own process."""
    cache = tmp_path_factory.mktemp("numba-cache")
    with ThreadPoolExecutor(2) as pool:
        parts = list(pool.map(lambda case: probe([case], cache), CASES))
    reference = {}
    for part in parts:
        reference.update(part)
    return cache, reference


@pytest.mark.parametrize("order", ["forward", "reverse"])
def test_every_variant_loaded_in_one_process_gives_its_own_result(filled, order):
    cache, reference = filled
    cases = CASES if order == "forward" else CASES[::-1]
    loaded = probe(cases, cache)
    wrong = [case for case in CASES if loaded[case] != reference[case]]
    assert not wrong, f"results that depend on which process compiled what: {wrong}"
    # the comparisons are not vacuous: the variants differ from each other
    assert loaded["disk:no-slip:final:sync"] != loaded["disk+force:no-slip:final:sync"]
    assert loaded["disk:no-slip:final:sync"] != loaded["disk:specular:final:sync"]
    assert loaded["disk:no-slip:final:sync"] == loaded["disk:no-slip:final:numba"]


def test_a_cache_entry_holding_another_variants_code_is_refused(filled, tmp_path):
    """Overwrite the no-force kernel's cached code with the force kernel's: the guard names both variants."""
    from noslipsim import Scene
    from noslipsim._engine.table import kernel_table
    from noslipsim.core.batch import batch_kernel

    cache = tmp_path / "tampered"
    shutil.copytree(filled[0], cache)
    names = []
    for force in (0.0, -1.0):
        scene = Scene.from_dict({"law": "no-slip", "force": [0, force], "elements": [
            {"type": "circle", "center": [0, 0], "radius": 1, "side": "inside"}]})
        names.append(batch_kernel(kernel_table(scene).variant(0)).py_func.__qualname__.rsplit(".", 1)[-1])
    [victim] = glob.glob(str(cache / "**" / f"*{names[0]}-*.1.nbc"), recursive=True)
    [intruder] = glob.glob(str(cache / "**" / f"*{names[1]}-*.1.nbc"), recursive=True)
    shutil.copy(intruder, victim)
    proc = probe(["disk:no-slip:final:sync"], cache, check=False)
    assert proc.returncode != 0 and "KernelMismatch" in proc.stderr, proc.stderr[-2000:]
    message = proc.stderr.strip().splitlines()[-1]
    assert "asked for spin=True, lattice=False, mode=runtime, disks=False, walls=False, flight=straight," in message
    assert "reports spin=True, lattice=False, mode=runtime, disks=False, walls=False, flight=force," in message
    # an untouched variant in the same cache still runs
    assert probe(["disk:specular:final:sync"], cache) == {"disk:specular:final:sync":
                                                          filled[1]["disk:specular:final:sync"]}


_ORDER = """
import sys
sys.path.insert(0, {tests!r})
import cache_probe
from noslipsim._engine.table import kernel_table
from noslipsim.core.batch import batch_kernel
from noslipsim.core.loop import orbit_kernel
scene, _ = cache_probe._scene("galton", "no-slip")
flags = kernel_table(scene).variant(0)
cache_probe.run("galton:no-slip:final:sync")
orbit, batch = orbit_kernel(*flags), batch_kernel(flags)
assert batch.stats.cache_hits, "the batch kernel was compiled, not loaded: the test needs a filled cache"
print(len(orbit.overloads), orbit.stats.cache_hits and 1)
"""


def test_a_cached_batch_kernel_runs_after_its_orbit_kernel_is_loaded(filled):
    """numba links each callee into its caller as a weak definition, and the loader keeps the one loaded
    first: a fresh process runs the orbit kernel's own code, a process that loads only the batch kernel ran
    the batch's copy, 0.63 times as fast on the Galton board (benchmarks/RESULTS.md).  The orbit kernel is
    loaded first (from the cache), so both run the same code."""
    code = _ORDER.format(tests=str(Path(__file__).parent))
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=dict(os.environ, NUMBA_CACHE_DIR=str(filled[0])))
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.split() == ["1", "1"]
