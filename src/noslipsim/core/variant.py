"""Kernel variants: the compile-time slots of the event loop, and the number a kernel reports them by.

A :class:`Variant` holds the slots of :func:`loop.orbit_kernel`, each a compile-time value or ``None``
("read from the arguments at run time"); :func:`normalise` refuses a combination no scene can have.
Every orbit kernel returns :func:`report` of the variant it was compiled for, a constant of its machine
code; the caller compares it with :func:`report` of the variant it asked for and refuses a result from
any other kernel (a wrong entry in the compile cache, however it got there).  docs/algorithm.md,
*Paying only for what a scene needs* and *One kernel call, and a compile cache that cannot hand back
another variant*.
"""
import operator
from typing import NamedTuple

import numpy as np

from .jit import SOURCE_STAMP

#: The record modes a ``mode`` slot may hold (``layout.RECORD_*``).
MODES = (0, 1, 2)
#: The flights a ``flight`` slot may hold.  A force is flown by :data:`FORCE` or :data:`THERMOSTAT`
#: only; a magnetic field never comes with a force.
STRAIGHT = 0
FORCE = 1
THERMOSTAT = 2
MAGNETIC = 3
#: Names of the flights, by code (as :func:`describe` prints them).
FLIGHTS = ("straight", "force", "thermostat", "magnetic")
#: The forms a ``settle`` slot may hold (docs/algorithm.md, "Which form, per table"): the whole state scaled
#: (:func:`energy.settle_whole`), or the part where the rounding arose, chosen per orbit
#: (:func:`energy.settle_mode`; :func:`energy.settle_velocity` after a mixed table's specular element).
WHOLE = 0
TARGETED = 1
#: Names of the settle forms, by code.
SETTLES = ("whole", "targeted")


class Variant(NamedTuple):
    """The compile-time slots of one event-loop kernel (``None``: read from the arguments at run time).

    Attributes
    ----------
    spin : bool or None
        Some element is no-slip: the spin update is compiled in.
    lattice : bool or None
        A periodic scene: the cell walk is compiled in.
    mode : int or None
        The record mode (``layout.RECORD_*``).
    disks : bool or None
        The lean disk loop (:func:`disks.disk_lattice_kernel`); ``None`` reads as ``False``.
    walls : bool or None
        Some element is a long wall: its exact check is compiled in.
    flight : int or None
        :data:`STRAIGHT` (no force), :data:`FORCE` (free fall under the force), :data:`THERMOSTAT` (the
        force flown isokinetically) or :data:`MAGNETIC` (a field normal to the table, no force).
    mixed : bool or None
        The elements do not all share one law: per-element laws are compiled in.
    open_ends : bool or None
        Some segment or arc has an open end (a reflex junction or a free end): the cell search's
        open-end rule is compiled in (:func:`search.cell_search`).
    settle : int or None
        :data:`WHOLE` or :data:`TARGETED`: the energy settle's one form compiled in
        (:func:`energy.targeted_settle` decides it from the table; ``None``: from the arguments).
    """

    spin: bool | None = None
    lattice: bool | None = None
    mode: int | None = None
    disks: bool | None = None
    walls: bool | None = None
    flight: int | None = None
    mixed: bool | None = None
    open_ends: bool | None = None
    settle: int | None = None


#: Names of the slots, in order.
SLOTS = Variant._fields
#: The general path: every slot read at run time.
GENERAL = Variant()


class FlightSwitches(NamedTuple):
    """The compile-time constants of :func:`loop.orbit_kernel` that a variant's flight (and lattice) decide.

    Each branch of the loop that flies, searches or moves by a force, the
    thermostat or the field opens with one of these, so numba prunes the code
    of every flight the variant cannot fly before typing it.
    """

    force_rt: bool  # whether a force acts is read from ``ax, ay``
    force: bool  # a force acts (when not read at run time)
    thermo_any: bool  # thermostatted flights compiled in
    thermo_always: bool  # every flight thermostatted: no free fall compiled at all
    thermo_rt: bool  # the ``thermostat`` argument is read
    mag_any: bool  # magnetic flights compiled in (at run time when ``W != 0``)
    mag_always: bool  # every flight magnetic
    far_move: bool  # a far hit under a force approached by moving the flight's start (cells.far_move)


def flight_switches(variant):
    """The :class:`FlightSwitches` of a normalised :class:`Variant`."""
    flight = variant.flight
    return FlightSwitches(
        force_rt=flight is None,
        force=flight in (FORCE, THERMOSTAT),
        thermo_any=flight in (None, THERMOSTAT),
        thermo_always=flight == THERMOSTAT,
        thermo_rt=flight is None,
        mag_any=flight in (None, MAGNETIC),
        mag_always=flight == MAGNETIC,
        # free fall on a lattice only: a thermostatted flight searches its own way
        far_move=flight in (None, FORCE) and variant.lattice is not False)


_RUNTIME = len(FLIGHTS)  # digit of a slot left to run time
_BASE = _RUNTIME + 1  # one digit per slot; the widest slot (flight) has len(FLIGHTS) values and run time


def normalise(spin=None, lattice=None, mode=None, disks=None, walls=None, flight=None, mixed=None, open_ends=None,
              settle=None):
    """The variant as the kernel it selects sees it.

    Parameters
    ----------
    spin, lattice, disks, walls, mixed, open_ends : bool or None
    mode : int or None
        One of :data:`MODES`.
    flight : int or None
        One of :data:`STRAIGHT`, :data:`FORCE`, :data:`THERMOSTAT`, :data:`MAGNETIC`.
    settle : int or None
        :data:`WHOLE` or :data:`TARGETED`.

    Returns
    -------
    Variant
        The disk loop (``disks=True``) has no force, walks a lattice, has no
        walls, no open ends, one law and the whole-state settle whatever the other slots say, so
        those slots are fixed there; ``disks=None`` reads as ``False`` (the loop is chosen
        before compiling, never at run time).

    Raises
    ------
    ValueError
        A slot holds a value it cannot take, or the slots describe no scene:
        a mixed table (``mixed=True``) without the spin (``spin=False``), in
        the disk loop, or with the whole-state settle (it keeps the spin over
        specular elements: targeted); the targeted settle in the disk loop (disks only).
    """
    spin, mixed = _flag("spin", spin), _flag("mixed", mixed)
    mode, flight, settle = _mode(mode), _flight(flight), _settle(settle)
    if mixed and spin is False:
        raise ValueError("variant: a mixed table (mixed=True) has a no-slip element; spin=False would make every "
                         "collision specular")
    if _flag("disks", disks):
        if mixed:
            raise ValueError("variant: the lean disk loop (disks=True) knows one law; a mixed table (mixed=True) "
                             "runs the general loop")
        if settle == TARGETED:
            raise ValueError("variant: the lean disk loop (disks=True) has disks only, nothing the targeted settle "
                             "keeps: it compiles settle=WHOLE")
        return Variant(spin, True, mode, True, False, STRAIGHT, False, False, WHOLE)
    if mixed and settle == WHOLE:
        raise ValueError("variant: a mixed table (mixed=True) keeps its spin over specular elements; settle=WHOLE "
                         "would scale it (the targeted settle keeps it)")
    return Variant(spin, _flag("lattice", lattice), mode, False, _flag("walls", walls), flight, mixed,
                   _flag("open_ends", open_ends), settle)


def _flag(name, value):
    if value is None:
        return None
    # an int here is a slot out of place (a mode or flight code), not a truth value
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name}: expected True, False or None, got {value!r}")
    return bool(value)


def _mode(value):
    if value is None:
        return None
    if operator.index(value) not in MODES:
        raise ValueError(f"mode: expected one of {MODES} or None, got {value!r}")
    return operator.index(value)


def _flight(value):
    # a bool is the old spelling (True: the thermostat), which no longer names a flight
    return _code("flight", value, FLIGHTS)


def _settle(value):
    # a bool is a slot out of place, not a form
    return _code("settle", value, SETTLES)


def _code(name, value, names):
    """A coded slot's value: ``None``, or an index into ``names`` (never a bool)."""
    if value is None:
        return None
    if isinstance(value, (bool, np.bool_)) or operator.index(value) not in range(len(names)):
        codes = ", ".join(f"{code} ({text})" for code, text in enumerate(names))
        raise ValueError(f"{name}: expected one of {codes} or None, got {value!r}")
    return operator.index(value)


def variant_code(flags):
    """The variant (normalised) as a small integer: one base-5 digit per slot, in :data:`SLOTS` order.

    Nine slots stay below ``5**9 < 2**21``: :func:`report` shifted by 32 bits is exact in a float64.
    """
    code = 0
    for value in normalise(*flags):
        digit = _RUNTIME if value is None else int(value)
        code = _BASE * code + digit
    return code


def report(flags):
    """What the kernel of ``flags`` returns: its variant code above the 32-bit core source stamp."""
    return (variant_code(flags) << 32) | SOURCE_STAMP


def decode(reported):
    """A reported number as ``(variant, stamp)``: the slots (a digit no slot value has as text, ``"?3"``) and the
    32-bit core source stamp."""
    reported = int(reported)
    code, stamp = reported >> 32, reported & 0xFFFFFFFF
    digits = []
    for _ in SLOTS:
        digits.append(code % _BASE)
        code //= _BASE
    values = [_slot_value(name, digit) for name, digit in zip(SLOTS, reversed(digits), strict=True)]
    return Variant(*values), stamp


def _slot_value(name, digit):
    if digit == _RUNTIME:
        return None
    if name == "flight":
        return digit
    if name == "settle":
        return digit if digit < len(SETTLES) else f"?{digit}"
    if name == "mode":
        return digit if digit in MODES else f"?{digit}"
    return bool(digit) if digit < 2 else f"?{digit}"


def describe(reported):
    """A reported number as text: ``spin=True, lattice=False, ..., flight=force, ... (core sources 1a2b3c4d)``."""
    variant, stamp = decode(reported)
    parts = [f"{name}={_slot_text(name, value)}" for name, value in zip(SLOTS, variant, strict=True)]
    return f"{', '.join(parts)} (core sources {stamp:08x})"


def _slot_text(name, value):
    if value is None:
        return "runtime"
    if name == "flight":
        return FLIGHTS[value]
    if name == "settle" and not isinstance(value, str):
        return SETTLES[value]
    return str(value)
