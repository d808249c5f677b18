"""Kernel variants (core/variant.py): one ``flight`` slot, the machine decisions it compiles, the reported number.

The variant used to be ``(force, spin, lattice, mode, disks, walls, flight, mixed)`` with a force flag
beside a flight code (free, thermostat, magnetic); now ``flight`` alone says straight, force,
thermostat, magnetic or run time.  The old loop's compile-time constants are written out below, from
the old ``loop.orbit_kernel`` and ``variant.normalise``, so that every new variant can be checked to
compile to the decisions its old spelling compiled to.
"""
import itertools

import numpy as np
import pytest

from noslipsim import Circle, Scene, tables
from noslipsim._engine.run import run_orbits
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout, variant
from noslipsim.core.jit import SOURCE_STAMP
from noslipsim.core.loop import orbit_kernel
from noslipsim.core.variant import (
    FLIGHTS,
    FORCE,
    MAGNETIC,
    SETTLES,
    STRAIGHT,
    TARGETED,
    THERMOSTAT,
    WHOLE,
    Variant,
    decode,
    describe,
    normalise,
    report,
    variant_code,
)

BOOLS = (None, False, True)
VALUES = {"spin": BOOLS, "lattice": BOOLS, "mode": (None, *variant.MODES), "disks": BOOLS, "walls": BOOLS,
          "flight": (None, STRAIGHT, FORCE, THERMOSTAT, MAGNETIC), "mixed": BOOLS, "open_ends": BOOLS,
          "settle": (None, WHOLE, TARGETED)}
#: Every spelling of a variant, impossible ones included.
EVERY = [Variant(*values) for values in itertools.product(*(VALUES[name] for name in variant.SLOTS))]


def possible(v):
    """No mixed table without the spin, none in the disk loop or with the whole-state settle; no targeted settle in
    the disk loop."""
    mixed_ok = not (v.mixed and (v.spin is False or v.disks or v.settle == WHOLE))
    return mixed_ok and not (v.disks and v.settle == TARGETED)


POSSIBLE = [v for v in EVERY if possible(v)]

# ------------------------------------------------------------------ the old spelling, as the old code read it
OLD_FREE, OLD_THERMOSTAT, OLD_MAGNETIC = 0, 1, 2
#: ``(force, flight)`` of the old spelling of each flight (the kernel table built exactly these four).
OLD_FLIGHT = {STRAIGHT: (False, OLD_FREE), FORCE: (True, OLD_FREE), THERMOSTAT: (True, OLD_THERMOSTAT),
              MAGNETIC: (False, OLD_MAGNETIC), None: (None, None)}


def old_constants(v):
    """The constants the old ``orbit_kernel(force, spin, lattice, mode, disks, walls, flight, mixed)`` compiled
    into its loop for the old spelling of the (normalised, general-loop) variant ``v``."""
    force, flight = OLD_FLIGHT[v.flight]
    spin, lattice, mode, walls, mixed = v.spin, v.lattice, v.mode, v.walls, v.mixed
    thermo_always = force is True and flight == OLD_THERMOSTAT
    return {
        "FORCE_RT": force is None, "FORCE": bool(force),
        "SPIN": bool(spin),
        "LATTICE_RT": lattice is None, "LATTICE": bool(lattice), "LATTICE_ALWAYS": lattice is True,
        "MODE_RT": mode is None, "MODE": layout.RECORD_LOG if mode is None else int(mode),
        "WALLS": walls is None or bool(walls),
        "THERMO_ANY": force is not False and (flight is None or flight == OLD_THERMOSTAT),
        "THERMO_ALWAYS": thermo_always,
        "THERMO_RT": flight is None,
        "MAG_ANY": force is not True and (flight is None or flight == OLD_MAGNETIC),
        "MAG_ALWAYS": flight == OLD_MAGNETIC,
        "MIXED_ANY": mixed is not False, "MIXED_ALWAYS": mixed is True,
        "LAW_KEPT": spin is None or (bool(spin) and mixed is not False),
        "FAR_MOVE": force is not False and lattice is not False and not thermo_always,
        "OPEN_ENDS": v.open_ends is None or bool(v.open_ends),  # (new with the slot: the cell search's rule)
        # (new with the slot: the settle's form, read at run time or one compiled in)
        "SETTLE_RT": v.settle is None, "SETTLE_WHOLE": v.settle == WHOLE,
    }


#: Constants that say which of a flight's steps a closure belongs to, not what the variant decides: the loop
#: captures free flight's straight and falling steps both, and picks one by its own FORCE constants; a lattice
#: walk under a force is built twice, the near walk (``NEAR``) handing on to the far one (``cells._force_walk``).
STEP_IDENTITY = {"FALLING", "NEAR"}


def compiled_constants(kernel):
    """The constants a kernel's loop captured (what numba compiles in), but the reported variant code.

    The loop is named steps (``core/fly.py``, ``core/bounce.py``), each a closure capturing the constants it
    reads: the constants (upper-case names) are collected from the loop and every step it captures, and a
    name captured twice must hold one value.
    """
    captured = {}
    seen = set()
    steps = set()

    def collect(func):
        func = getattr(func, "py_func", func)
        if id(func) in seen or not callable(func) or not getattr(func, "__closure__", None):
            return
        seen.add(id(func))
        for name, cell in zip(func.__code__.co_freevars, func.__closure__, strict=True):
            value = cell.cell_contents
            if name in STEP_IDENTITY:
                steps.add((name, value))
            elif name.isupper():
                assert captured.setdefault(name, value) == value, name
            else:
                for item in value if isinstance(value, tuple) else (value,):
                    collect(item)

    collect(kernel)
    captured.pop("VARIANT")
    # both free-flight steps, the loop picks one; a lattice kernel under a force has both walks
    assert {s for s in steps if s[0] == "FALLING"} == {("FALLING", False), ("FALLING", True)}
    assert {s for s in steps if s[0] == "NEAR"} in (set(), {("NEAR", False), ("NEAR", True)})
    return captured


def test_every_variant_compiles_the_decisions_of_its_old_spelling():
    """Each general-loop variant captures exactly the constants (values and types) its old spelling did."""
    general_loop = [v for v in POSSIBLE if not v.disks]
    # (spin, lattice, mode, disks, walls, flight) x open_ends x (mixed, settle): mixed=None or False with any of
    # the three settles, mixed=True (not with spin=False) with the run-time or the targeted one
    assert len(general_loop) == 3 * 4 * 2 * 3 * 5 * 3 * (3 * 2 * 3 + 2 * 2)
    for v in general_loop:
        got = compiled_constants(orbit_kernel(*v))
        want = old_constants(normalise(*v))
        assert got == want, v
        assert [type(got[k]) for k in sorted(got)] == [type(want[k]) for k in sorted(want)], v


def test_the_kernel_table_builds_each_flight():
    box = tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)])
    scenes = {STRAIGHT: box, FORCE: box.replace(force=(0.0, -1.0)),
              THERMOSTAT: box.replace(force=(0.3, -1.0), thermostat="isokinetic"),
              MAGNETIC: box.replace(magnetic=1.5)}
    for flight, scene in scenes.items():
        own = kernel_table(scene).variant(layout.RECORD_NONE)
        assert type(own) is Variant and own.flight == flight and type(own.flight) is int
        assert own == normalise(*own)
    # the thermostat on no force flies straight lines (tests/test_thermostat_orbits.py: bit for bit)
    assert kernel_table(box.replace(thermostat="isokinetic")).variant(0).flight == STRAIGHT
    # a disk lattice: the lean loop's fixed slots
    lean = Variant(True, True, None, True, False, STRAIGHT, False, False, WHOLE)
    assert kernel_table(tables.sinai_torus(0.25)).variant(0) == lean


@pytest.mark.parametrize("scene,q", [(tables.regular_polygon(5), (0.1, 0.05)),
                                     (tables.galton_board(2.0, 0.5, 1.0), (1.0, 0.5)),
                                     (tables.sinai_torus(0.25), (0.45, 0.1))], ids=["plain", "lattice+force", "disks"])
def test_every_record_mode_runs_one_kernel(scene, q):
    """No records, a log and a portrait: one compiled kernel (one compile per scene), reading the mode at
    run time, and a run without records writes none."""
    table = kernel_table(scene)
    kernels = {orbit_kernel(*table.variant(mode)) for mode in (layout.RECORD_NONE, layout.RECORD_LOG,
                                                                 layout.RECORD_PORTRAIT)}
    assert len(kernels) == 1
    start = [[*q, 0.6, -0.8, 0.0]]
    rec = np.full((1, 50, layout.N_LOG), 7.0)
    final = run_orbits(table, start, max_collisions=50, mode=layout.RECORD_NONE, rec=rec)
    assert final[0, 0] == 50 and final[0, 3] == 0 and np.all(rec == 7.0)  # nothing written
    logged = run_orbits(table, start, max_collisions=50, mode=layout.RECORD_LOG, rec=rec)
    assert logged[0, 3] == 50 and np.array_equal(logged[:, :3], final[:, :3])


@pytest.mark.parametrize("mode", [3, -1])
def test_a_record_mode_out_of_place_raises(mode):
    with pytest.raises(ValueError, match="expected a record mode"):
        kernel_table(tables.regular_polygon(5)).variant(mode)


# ------------------------------------------------------------------ impossible spellings
@pytest.mark.parametrize("slots,message", [
    (dict(spin=False, mixed=True), "spin=False"),
    (dict(disks=True, mixed=True), "lean disk loop"),
    (dict(flight=True), "flight: expected one of 0 \\(straight\\), 1 \\(force\\)"),  # the old thermostat's spelling
    (dict(flight=False), "flight: expected"),
    (dict(flight=4), "flight: expected"),
    (dict(flight=-1), "flight: expected"),
    (dict(mode=3), "mode: expected"),
    (dict(spin=1), "spin: expected True, False or None, got 1"),  # an int in a bool slot: a slot out of place
    (dict(lattice=0), "lattice: expected"),
    (dict(walls=2), "walls: expected"),
    (dict(disks=0), "disks: expected"),
    (dict(mixed=1), "mixed: expected"),
    (dict(mixed=True, settle=WHOLE), "settle=WHOLE would scale it"),  # the spin over specular elements
    (dict(disks=True, settle=TARGETED), "compiles settle=WHOLE"),
    (dict(settle=True), "settle: expected one of 0 \\(whole\\), 1 \\(targeted\\)"),  # a bool: a slot out of place
    (dict(settle=2), "settle: expected"),
])
def test_impossible_variants_are_refused(slots, message):
    with pytest.raises(ValueError, match=message):
        normalise(**slots)
    with pytest.raises(ValueError, match=message):
        orbit_kernel(**slots)
    with pytest.raises(ValueError, match=message):
        report(Variant(**slots))


def test_the_old_spellings_are_refused():
    """The old eight slots, or ``force=``: the force is the flight's now (``flight=FORCE``)."""
    with pytest.raises(ValueError, match="expected True, False or None"):  # the old slots land one place off
        normalise(True, True, True, 0, False, False, OLD_FREE, False)
    with pytest.raises(TypeError):
        orbit_kernel(force=True)
    # the old seven-slot prefix ``(force, spin, lattice, mode, disks, walls, flight)``: a slot out of place
    with pytest.raises(ValueError):
        normalise(False, True, True, 1, True, False, False)


def test_run_orbits_refuses_a_bad_variant_before_compiling():
    table = kernel_table(Scene([Circle((0.0, 0.0), 1.0, "inside")]))
    with pytest.raises(ValueError, match="spin=False"):
        run_orbits(table, [(0.1, 0.2, 0.6, 0.8, 0.0)], max_collisions=1, flags=Variant(spin=False, mixed=True))


def test_the_disk_loop_fixes_its_slots():
    for v in POSSIBLE:
        if v.disks:
            assert normalise(*v) == Variant(v.spin, True, v.mode, True, False, STRAIGHT, False, False, WHOLE)


# ------------------------------------------------------------------ the reported number
def test_report_is_unique_per_variant():
    """Two spellings report one number exactly when they normalise to one variant, over every spelling."""
    by_variant = {}
    for v in POSSIBLE:
        by_variant.setdefault(normalise(*v), set()).add(report(v))
    assert all(len(reports) == 1 for reports in by_variant.values())
    reports = [r for rs in by_variant.values() for r in rs]
    assert len(set(reports)) == len(reports) == len(by_variant)
    # the batch kernel's summary is float64: every number must survive it
    assert all(int(float(r)) == r for r in reports)
    assert max(variant_code(v) for v in POSSIBLE) < 2 ** 21


def _parse(text):
    """``describe``'s text back to a variant and a stamp."""
    slots, stamp = text.rsplit(" (core sources ", 1)
    values = []
    for part, name in zip(slots.split(", "), variant.SLOTS, strict=True):
        key, value = part.split("=")
        assert key == name
        if value == "runtime":
            values.append(None)
        elif name == "flight":
            values.append(FLIGHTS.index(value))
        elif name == "settle":
            values.append(SETTLES.index(value))
        elif name == "mode":
            values.append(int(value))
        else:
            values.append({"True": True, "False": False}[value])
    return Variant(*values), int(stamp.rstrip(")"), 16)


def test_describe_round_trips_every_variant():
    for v in POSSIBLE:
        assert decode(report(v)) == (normalise(*v), SOURCE_STAMP)
        assert _parse(describe(report(v))) == (normalise(*v), SOURCE_STAMP)


def test_describe_names_the_settle_form():
    assert "settle=whole" in describe(report(Variant(settle=WHOLE)))
    assert "settle=targeted" in describe(report(Variant(settle=TARGETED)))
    assert "settle=whole" in describe(report(Variant(disks=True)))  # the lean loop's one form


def test_describe_names_the_flight():
    assert "flight=force" in describe(report(Variant(flight=FORCE)))
    assert "flight=straight" in describe(report(Variant(flight=STRAIGHT)))
    assert "flight=thermostat" in describe(report(Variant(flight=THERMOSTAT)))
    assert "flight=magnetic" in describe(report(Variant(flight=MAGNETIC)))
    assert describe(report(variant.GENERAL)) == (
        f"spin=runtime, lattice=runtime, mode=runtime, disks=False, walls=runtime, flight=runtime, "
        f"mixed=runtime, open_ends=runtime, settle=runtime (core sources {SOURCE_STAMP:08x})")


def test_describe_marks_a_digit_no_slot_has():
    """A number no kernel reports (a corrupted summary) is still described, its odd digits marked."""
    junk = (variant_code(Variant(spin=True)) + 2 * 5 ** 8) << 32  # spin's digit 1 + 2: no truth value
    assert describe(junk).startswith("spin=?3, ")

