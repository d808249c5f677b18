"""A copy of ``src/noslipsim`` at some commit, importable under another name beside the current package;
and the one kernel call of a package, new or old.

The package imports itself only relatively, so a copy under another name is a
second, independent package with its own numba cache (numba keys the cache on
the source file's path): benchmarks compile an old kernel and the current one in
one process and time them interleaved.

The current package runs every orbit through one call,
``_engine.run.run_orbits(table, starts, ...)`` on a kernel table
(``_engine.table.kernel_table(scene)``).  A copy from before it (such as the
``ABLATION_BASE`` commit of ``ablation_exact.py``) keeps its own API: scenes
with ``kernel_inputs()`` and ``kernel_variant(mode)``, orbit kernels of 26
positional arguments and 12 outputs, and from some commit on
``core.batch.batch_kernels(flags)``.  :class:`OldLoop` runs such a copy's loop
through that API; :func:`kernel_call` runs a scene of either kind of package
through its own path.  Both give the 12 outputs ``(n, stop, n_corner, n_rec,
t, x, y, vx, vy, w, m1, m2)`` (counts, stop code and cells as ints).
"""
import importlib
import importlib.util
import inspect
import math
import os
import shutil
import subprocess
import sys
import tempfile
from types import SimpleNamespace

import numpy as np

from noslipsim.core.variant import FORCE, MAGNETIC, STRAIGHT, THERMOSTAT, Variant

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
#: The integer ones among the 12 outputs (n, stop, n_corner, n_rec, m1, m2).
INTS = (0, 1, 2, 3, 10, 11)
#: A flight (:mod:`noslipsim.core.variant`) as the ``flight`` slot of the 8-slot tuple before
#: :class:`~noslipsim.core.variant.Variant` coded it: free (straight or free fall), thermostat, magnetic.
OLD_FLIGHT = {STRAIGHT: 0, FORCE: 0, THERMOSTAT: 1, MAGNETIC: 2}


def package_copy(commit, name, where, fresh=False):
    """Extract ``src/noslipsim`` at ``commit`` to ``where/name`` (unless there, or ``fresh``);
    ``where`` goes on sys.path.

    Returns the package's directory.
    """
    pkg = os.path.join(where, name)
    if fresh and os.path.isdir(pkg):
        shutil.rmtree(pkg)
    if not os.path.isdir(pkg):
        tmp = tempfile.mkdtemp()
        archive = subprocess.run(["git", "-C", ROOT, "archive", commit, "src/noslipsim"], check=True,
                                 capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        os.makedirs(where, exist_ok=True)
        shutil.move(os.path.join(tmp, "src", "noslipsim"), pkg)
        shutil.rmtree(tmp)
    if where not in sys.path:
        sys.path.insert(0, where)
    return pkg


def load_version(version, name, where, before_compile=None):
    """Package ``name`` of ``version``: a commit (:func:`package_copy`) or a folder holding a copy of
    ``src/noslipsim`` (copied to ``where/name``).

    ``before_compile(name)`` runs after the import and before anything compiles (to set a
    module constant the kernels read, such as ``energy.SETTLE_AT``).  The submodules the
    benchmark cases use (``tables``, ``initial``) are imported as attributes of the package.
    """
    if os.path.isdir(version):
        shutil.rmtree(os.path.join(where, name), ignore_errors=True)
        shutil.copytree(version, os.path.join(where, name), ignore=shutil.ignore_patterns("__pycache__"))
        if where not in sys.path:
            sys.path.insert(0, where)
    else:
        package_copy(version, name, where, fresh=True)
    pkg = importlib.import_module(name)
    if before_compile is not None:
        before_compile(name)
    for sub in ("tables", "initial"):
        importlib.import_module(f"{name}.{sub}")
    return pkg


def outputs(row):
    """The first 12 columns of a summary row as the kernel's outputs (ints where they are counts or cells)."""
    return tuple(int(row[k]) if k in INTS else float(row[k]) for k in range(12))


def has_one_call(name):
    """True if the package ``name`` runs its orbits through ``_engine.run.run_orbits`` (the current API)."""
    try:
        return importlib.util.find_spec(f"{name}._engine.run") is not None
    except ModuleNotFoundError:  # no _engine package at all
        return False


class OldLoop:
    """The event loop of a package from before ``run_orbits``, through that package's own API.

    ``run`` calls the package's serial batch loop (``core.batch.batch_kernels(flags)[1]``)
    where it has one: like ``run_orbits`` in the current package, a compiled loop over
    orbits around the orbit kernel, so old and new are timed through the same kind of
    call; else the orbit kernel (``core.loop.orbit_kernel(*flags)``) directly.

    Flags are either a tuple in the package's own order, cut to the slots it knows
    (``walls`` came after ``disks``: its loop has what a later slot would leave out),
    or a current :class:`~noslipsim.core.variant.Variant`, spelt in the package's
    slots by name (:func:`old_flags`) where they start with ``force`` (every package
    without ``run_orbits`` does), as it is where the package has the same order.
    """

    def __init__(self, name):
        self.name = name
        self.loop = importlib.import_module(f"{name}.core.loop")
        try:
            self.batch = importlib.import_module(f"{name}.core.batch").batch_kernels
        except (ImportError, AttributeError):
            self.batch = None
        self.slots = tuple(inspect.signature(self.loop.orbit_kernel).parameters)

    def flags(self, flags):
        """``flags`` as the package's ``orbit_kernel`` takes them."""
        if isinstance(flags, Variant) and "force" in self.slots:
            return old_flags(flags, self.slots)
        return tuple(flags)[:len(self.slots)]

    def run(self, table, flags, start, n, mode, rec=None, mask=None, start_element=-1, max_time=math.inf,
            level=-math.inf):
        """One orbit from ``start = (x, y, vx, vy, w)`` (relative to its cell); the 12 outputs.

        ``table``: the arguments the kernels take, as attributes ``arrays()``, ``law``,
        ``c``, ``s``, ``ax``, ``ay``, ``scale`` (a current ``KernelTable``, or
        :func:`old_table` of a scene of the old package); ``rec``: a 2-D record
        buffer written in place.
        """
        arrays = table.arrays()
        rec = np.zeros((0, 0)) if rec is None else rec
        mask = np.zeros(len(arrays[0]), dtype=np.bool_) if mask is None else mask
        flags = self.flags(flags)
        head = (*arrays, table.law, table.c, table.s, table.ax, table.ay)
        if self.batch is None:
            out = self.loop.orbit_kernel(*flags)(*head, *start, n, max_time, level, table.scale, mode, rec, mask,
                                                 start_element)
            return outputs(out)
        final = np.zeros((1, 12))
        self.batch(flags)[1](*head, np.array([start], dtype=np.float64), np.array([start_element], dtype=np.int64),
                             n, max_time, np.array([level]), table.scale, mode, rec[None], mask, final)
        return outputs(final[0])


def old_flags(variant, slots):
    """A :class:`~noslipsim.core.variant.Variant` in the slots ``slots`` of an old ``orbit_kernel``.

    The old slots, in their order: ``force`` (a force flown: a :data:`FORCE` or
    :data:`THERMOSTAT` flight), ``spin``, ``lattice``, ``mode``, ``disks``,
    ``walls``, then ``thermostat`` (a bool) or ``flight`` (:data:`OLD_FLIGHT`), and
    ``mixed``.  ``None`` (run time) stays ``None`` in every slot the flight fills.

    Raises
    ------
    ValueError
        ``slots`` names a slot no old package had.
    """
    flight = variant.flight
    known = variant._asdict()
    if flight is not None:
        known.update(force=flight in (FORCE, THERMOSTAT), thermostat=flight == THERMOSTAT, flight=OLD_FLIGHT[flight])
    else:
        known.update(force=None, thermostat=None)
    if not set(slots) <= set(known):
        raise ValueError(f"old_flags: {sorted(set(slots) - set(known))} is no slot of an old orbit_kernel")
    return tuple(known[name] for name in slots)


def old_table(scene):
    """A scene of an old package as the kernels take it: ``kernel_inputs()`` and its physics, table-like."""
    inputs = scene.kernel_inputs()
    c, s = scene.noslip_coefficients
    ax, ay = scene.force
    return SimpleNamespace(arrays=lambda: inputs, law=scene.law_code, c=c, s=s, ax=ax, ay=ay, scale=scene.scale)


def kernel_call(name):
    """``run(scene, start, n)``: one orbit of a scene of package ``name``, its own variant, no record.

    Through ``run_orbits`` where the package has it, else through :class:`OldLoop`
    (its ``scene.kernel_inputs()`` and ``scene.kernel_variant(RECORD_NONE)``).
    ``start`` is ``(x, y, vx, vy, w)`` relative to the start cell.  Returns the 12 outputs.
    """
    if has_one_call(name):
        run_orbits = importlib.import_module(f"{name}._engine.run").run_orbits
        kernel_table = importlib.import_module(f"{name}._engine.table").kernel_table

        def run(scene, start, n):
            return outputs(run_orbits(kernel_table(scene), [start], max_collisions=n)[0])
    else:
        old = OldLoop(name)
        none = importlib.import_module(f"{name}.core.layout").RECORD_NONE

        def run(scene, start, n):
            return old.run(old_table(scene), scene.kernel_variant(none), start, n, none)
    return run
