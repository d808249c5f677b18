"""Kernel variants: the compile-time flags of the event loop, and the number a kernel reports them by.

A variant is the tuple ``(force, spin, lattice, mode, disks, walls, flight, mixed)``
(:func:`loop.orbit_kernel`): each slot ``True``/``False`` (a record mode for
``mode``, a flight code for ``flight``: :data:`FREE` (straight, or free fall
under the force), :data:`THERMOSTAT` or :data:`MAGNETIC`; ``False``/``True``
read as the first two), or ``None`` for "read from the arguments at run time".  Every orbit
kernel returns :func:`report` of the variant it was compiled for, a constant
of its machine code; the caller compares it with :func:`report` of the variant
it asked for and refuses a result from any other kernel (a wrong entry in the
compile cache, however it got there).
"""
from .jit import SOURCE_STAMP

#: Names of the slots, in order.
SLOTS = ("force", "spin", "lattice", "mode", "disks", "walls", "flight", "mixed")
#: The general path: every flag read at run time.
GENERAL = (None, None, None, None, None, None, None, None)
#: The record modes a ``mode`` slot may hold (``layout.RECORD_*``).
MODES = (0, 1, 2)
#: The flights a ``flight`` slot may hold: the force's own (a straight line without one, a parabola
#: with it), the isokinetic thermostat's (needs a force), the magnetic field's (never with a force).
FREE = 0
THERMOSTAT = 1
MAGNETIC = 2
FLIGHTS = ("free", "thermostat", "magnetic")

_RUNTIME = 3  # digit of a slot left to run time


def normalise(force=None, spin=None, lattice=None, mode=None, disks=None, walls=None, flight=None,
              mixed=None):
    """The variant as the kernel it selects sees it.

    The disk loop (``disks=True``) has no force, walks a lattice, has no
    walls and one law whatever the other slots say, so those slots are fixed
    there; a loop without force has no thermostat, a magnetic one no force.
    """
    if disks:
        return False, _flag(spin), True, _mode(mode), True, False, FREE, False
    flight = _flight(flight)
    if flight == MAGNETIC:
        force = False
    elif force is False and flight == THERMOSTAT:
        flight = FREE
    return _flag(force), _flag(spin), _flag(lattice), _mode(mode), False, _flag(walls), flight, _flag(mixed)


def _flight(value):
    if value is None:
        return None
    if int(value) not in range(len(FLIGHTS)):
        raise ValueError(f"flight: expected one of {tuple(range(len(FLIGHTS)))} ({', '.join(FLIGHTS)}) or None, "
                         f"got {value!r}")
    return int(value)


def _flag(value):
    return None if value is None else bool(value)


def _mode(value):
    if value is None:
        return None
    if int(value) not in MODES:
        raise ValueError(f"mode: expected one of {MODES} or None, got {value!r}")
    return int(value)


def variant_code(flags):
    """The variant (normalised) as a small integer: one base-4 digit per slot."""
    code = 0
    for value in normalise(*flags):
        digit = _RUNTIME if value is None else int(value)
        code = 4 * code + digit
    return code


def report(flags):
    """What the kernel of ``flags`` returns: its variant code above the 32-bit core source stamp."""
    return (variant_code(flags) << 32) | SOURCE_STAMP


def describe(reported):
    """A reported number as text: ``force=True, spin=False, ... (core sources 1a2b3c4d)``."""
    reported = int(reported)
    code, stamp = reported >> 32, reported & 0xFFFFFFFF
    digits = []
    for _ in SLOTS:
        digits.append(code % 4)
        code //= 4
    parts = [f"{name}={_digit_text(name, d)}" for name, d in zip(SLOTS, reversed(digits))]
    return f"{', '.join(parts)} (core sources {stamp:08x})"


def _digit_text(name, digit):
    if digit == _RUNTIME:
        return "runtime"
    if name == "mode":
        return str(digit)
    if name == "flight":
        return FLIGHTS[digit]
    return str(bool(digit))
