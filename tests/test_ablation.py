"""Specialised event loops give the general path's results, bit for bit (issue: pay only for what a scene needs).

``orbit_kernel(spin, lattice, mode, disks, walls, flight, mixed)`` fixes flags at
compile time; ``None`` reads them from the arguments.  On each scene every
variant the scene can use (each flag fixed to the scene's value or left
``None``) must return the same 12 outputs and the same record rows as
``orbit_kernel()`` over 20,000 collisions.  The ``disks`` slot (the
lean loop of disks on a lattice) is left ``None`` here: that loop agrees to
rounding, not bit for bit, and is checked in ``tests/test_disk_lattice.py``.
The default run checks the variant each scene runs (``KernelTable.variant``,
every flag fixed; ``disks`` left ``None`` as above): the kernels the other
tests and the users compile anyway.  ``-m stress`` checks every partial subset
(each flag fixed alone among them, which tells which flag broke a failing
variant; 263 compiled variants in all).
"""
import functools
import itertools

import numpy as np
import pytest
from kernel_call import record_buffer, run_kernel

from noslipsim import Circle, Scene, tables
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout
from noslipsim.core.loop import orbit_kernel, run_orbit
from noslipsim.core.variant import FORCE, GENERAL, STRAIGHT, TARGETED, WHOLE, Variant
from noslipsim.scenes import MIN_FORCE
from noslipsim.simulate import start_cell

N_COLL = 20_000
NONE, LOG, PORTRAIT = layout.RECORD_NONE, layout.RECORD_LOG, layout.RECORD_PORTRAIT
MODES = {"none": NONE, "log": LOG, "portrait": PORTRAIT}

SCENES = {  # name -> (scene, start position, velocity, spin)
    "pentagon": (tables.regular_polygon(5), (0.1, 0.05), (0.83, 0.41), 0.1),
    "sinai_box": (tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]), (0.1, 0.1), (0.6, 0.8), 0.1),
    "circle_gravity": (Scene([Circle((0.0, 0.0), 1.0, "inside")], force=(0.0, -1.0)), (0.1, 0.2), (0.4, 0.1), 0.1),
    "galton": (tables.galton_board(2.0, 0.5, 1.0), (1.0, 0.0), (0.3, 0.95), 0.1),
    "sinai_torus": (tables.sinai_torus(0.25), (0.45, 0.1), (0.83, 0.41), 0.1),
    "wedge": (tables.wedge(0.6), (0.0, 1.0), (0.6, 0.8), 0.1),  # two lines: the loop with the long-wall check
}
LAWS = ("specular", "no-slip")
CASES = [(name, law) for name in SCENES for law in LAWS]

SLOTS = (0, 1, 2, 4, 5)  # spin, lattice, mode, walls, flight (slot 3, disks, is another loop; the flight is
# straight or a force here, the thermostat's is checked on a thermostatted scene in tests/test_thermostat_api.py;
# slot 6, per-element laws, is left to run time here and checked on a mixed table in tests/test_mixed_law.py;
# slot 7, the open-end rule, is left to run time in every subset: compiled in, it must change no bit of these
# closed tables, whose own variant compiles it out; tests/test_reflex_vertex.py checks it on a reflex vertex)
ALL_SUBSETS = [s for k in range(1, len(SLOTS) + 1) for s in itertools.combinations(SLOTS, k)]
STRESS_SUBSETS = ALL_SUBSETS


def scene_of(name, law):
    scene, q, v, w = SCENES[name]
    return scene.replace(law=law), q, v, w


def run(flags, name, law, mode, start=None):
    """Run the kernel variant ``flags`` on a scene and start; returns the 12 outputs and the whole record array."""
    scene, q, v, w = scene_of(name, law)
    if start is not None:
        q = start
    table = kernel_table(scene)
    _, _, r = start_cell(scene, np.asarray(q, float))
    rec = record_buffer(mode, N_COLL + 1, fill=-7.0)  # sentinel: unwritten rows must stay so
    mask = np.arange(len(table.kinds)) % 2 == 0  # portrait: even elements (all of a one-element scene)
    out = run_kernel(table, flags, (float(r[0]), float(r[1])), v, w, N_COLL, mode, rec=rec, mask=mask)
    return out, rec


def bits(values):
    """Bit patterns (int64) of outputs or records: equality here is bitwise (signed zeros, NaNs)."""
    return np.asarray(values, dtype=np.float64).view(np.int64)


@functools.cache
def general(name, law, mode):
    out, rec = run(GENERAL, name, law, mode)
    # the comparison must not be vacuous: a full-length orbit, and records actually written
    assert out[0] == N_COLL and out[1] == layout.STOP_MAX_COLLISIONS, (name, law, out[:2])
    if mode == LOG:
        assert out[3] == N_COLL
    elif mode == PORTRAIT:
        assert out[3] > 100
    else:
        assert out[3] == 0
    return out, rec


def variant_flags(name, law, mode, subset):
    """The scene's flags fixed in ``subset`` (slot indices), the others left None."""
    needs = kernel_table(scene_of(name, law)[0]).variant(mode)
    return Variant(*(f if i in subset else None for i, f in enumerate(needs)))


def scene_variant(name, law, mode):
    """The variant the scene runs (its flags, every one fixed), the lean disk loop's slot left None."""
    needs = kernel_table(scene_of(name, law)[0]).variant(mode)
    return needs._replace(disks=None)


def check_identical(name, law, mode_name, subset=None):
    """``subset``: the slots fixed to the scene's values (None: the variant the scene runs)."""
    mode = MODES[mode_name]
    flags = scene_variant(name, law, mode) if subset is None else variant_flags(name, law, mode, subset)
    assert orbit_kernel(*flags) is not run_orbit  # a specialised kernel indeed
    out_g, rec_g = general(name, law, mode)
    out_v, rec_v = run(flags, name, law, mode)
    assert np.array_equal(bits(out_v), bits(out_g)), (flags, out_v, out_g)
    if mode != NONE:
        diff = np.flatnonzero(np.any(bits(rec_v) != bits(rec_g), axis=1))
        assert diff.size == 0, f"{flags}: record rows differ from row {diff[:1]}"


@pytest.mark.parametrize("mode_name", sorted(MODES))
@pytest.mark.parametrize("name,law", CASES)
def test_variant_bitwise_identical_to_general(name, law, mode_name):
    check_identical(name, law, mode_name)


@pytest.mark.stress
@pytest.mark.parametrize("subset", STRESS_SUBSETS, ids=lambda s: "fix" + "".join(map(str, s)))
@pytest.mark.parametrize("mode_name", sorted(MODES))
@pytest.mark.parametrize("name,law", CASES)
def test_every_partial_variant_bitwise_identical_to_general(name, law, mode_name, subset):
    check_identical(name, law, mode_name, subset)


def test_comparison_sees_one_ulp_and_a_wrong_law():
    """The identity checks above are sharp: a start one ulp off, or a variant for
    another scene (spin=False forces the specular law), gives other outputs."""
    out_g, _rec_g = general("sinai_box", "no-slip", LOG)
    q = SCENES["sinai_box"][1]
    nudged = run(GENERAL, "sinai_box", "no-slip", LOG, start=(np.nextafter(q[0], 1.0), q[1]))[0]
    assert not np.array_equal(bits(nudged), bits(out_g))
    wrong, rec_w = run(Variant(spin=False), "pentagon", "no-slip", LOG)
    out_p, rec_p = general("pentagon", "no-slip", LOG)
    assert not np.array_equal(bits(wrong), bits(out_p))
    assert np.all(rec_w[:100, layout.LOG_W] == rec_w[0, layout.LOG_W])  # specular: spin never changes
    assert np.any(rec_p[:100, layout.LOG_W] != rec_p[0, layout.LOG_W])


@pytest.mark.parametrize("mode", [NONE, LOG, PORTRAIT])
@pytest.mark.parametrize("name,law", CASES)
def test_kernel_variant_asks_only_for_what_the_scene_needs(name, law, mode):
    scene = scene_of(name, law)[0]
    spin, lattice, m, disks, walls, flight, mixed, open_ends, settle = kernel_table(scene).variant(mode)
    # exact bools: orbit_kernel tells "fixed False" from "read at run time" by identity (``is False``)
    assert all(f is True or f is False for f in (spin, lattice, disks, walls, mixed, open_ends))
    assert open_ends is False  # closed tables: no reflex junction, no free end, no open-end rule compiled
    assert type(flight) is int  # no scene here has a thermostat or a field: straight flights or free fall
    assert mixed is False  # one law per table: none compiles per-element laws
    assert flight == (FORCE if name in ("circle_gravity", "galton", "wedge") else STRAIGHT)
    assert spin is (law == "no-slip")
    assert lattice is (name in ("galton", "sinai_torus"))
    # one kernel for every record mode: it reads the mode at run time (fixing it buys nothing measurable)
    assert m is None
    assert disks is (name == "sinai_torus")
    # the settle's form (docs/algorithm.md, "Which form, per table"): targeted for a line or segment (the
    # pentagon, the box, the wedge) and for the spin in flight under free fall (no-slip, a force); whole for disks
    # only otherwise
    flat = name in ("pentagon", "sinai_box", "wedge")
    assert settle == (TARGETED if flat or (flight == FORCE and law == "no-slip") else WHOLE)
    assert walls is (name == "wedge")


@pytest.mark.parametrize("force,has", [((0.0, 0.0), False), ((0.0, -0.0), False), ((-0.0, -0.0), False),
                                       ((0.0, MIN_FORCE), True), ((1e-300, MIN_FORCE), True), ((-2.0, 0.0), True)])
def test_force_flag_is_false_exactly_for_zero_force(force, has):
    # the smallest force a scene accepts (docs/conventions.md, "Range of validity"; 1e-300 alone is refused)
    scene = tables.regular_polygon(5, force=force)
    assert kernel_table(scene).variant(NONE).flight == (FORCE if has else STRAIGHT)
