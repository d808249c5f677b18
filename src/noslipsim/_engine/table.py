"""A scene packed for the kernels, once: the arrays, the physics and the variant flags.

:func:`kernel_table` is the one packing step between a :class:`~noslipsim.Scene`
(a value: its elements, law, gamma, force and lattice) and the compiled event
loop, which takes plain arrays (layout in :mod:`noslipsim.core.layout`).  It
is built once per scene and kept while the scene lives (scenes are
immutable).  The scene is packed as it is written; :mod:`.canonical` rewrites a
periodic scene before it is packed, and :mod:`.run` calls the kernel.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core import layout, variant
from ..core.energy import targeted_settle
from .junctions import end_factors, junction_arrays
from .lattice import disks_apart, lattice_matrix, reaching_copies
from .memo import per_scene

#: Disks of a lattice run the lean loop (:attr:`KernelTable.disk_lattice`) when no two come within
#: this gap, relative to the cell's size: far outside the corner rule's contact band
#: (``CONTACT_TOL``), so the general loop could never treat two of them as touching.
DISK_GAP = 1e-9


@dataclass(frozen=True, eq=False)
class KernelTable:
    """Everything the event loop needs about one scene, as the kernels take it.

    Attributes
    ----------
    kinds, params : ndarray
        Element kinds and parameter rows (:mod:`noslipsim.core.layout`).
    copies : int64 ndarray (K, 3)
        Element copies ``(element, o1, o2)`` that reach a cell (a plain scene:
        each element once, unshifted).
    A, B : ndarray (2, 2)
        Lattice vectors as columns and the inverse (zeros for a plain scene).
    lattice : bool
        A periodic scene.
    jstart, jpts : ndarray
        Junction points per element (:mod:`.junctions`).
    law : int
        ``layout.SPECULAR`` or ``layout.NOSLIP`` when every element collides by
        that law; ``layout.PER_ELEMENT`` for a mixed table, whose collisions
        take the law of the element hit (``params[:, layout.ELEMENT_LAW]``).
    c, s : float
        No-slip coefficients of the scene's gamma (``c^2 + s^2`` closest to 1).
    ax, ay : float
        The constant acceleration.
    scale : float
        Length scale of the table (largest coordinate magnitude of its elements).
    has_force, noslip, disk_lattice, long_walls : bool
        What the scene needs compiled in: cubic and quartic exits, the spin
        update (some element is no-slip), the lean disk loop
        (:mod:`noslipsim.core.disks`), the long-wall check
        (:func:`noslipsim.core.events.exact_line_hit`).
    thermostat : bool
        The force is flown with the Gaussian isokinetic thermostat
        (:mod:`noslipsim.core.thermostat`); false without a force.
    magnetic : float
        ``W``, the cyclotron frequency of a magnetic field normal to the table
        (``Scene.magnetic``; :mod:`noslipsim.core.magnetic_flight`); 0 for none.
    mixed : bool
        The elements do not all share one law: the loop reads each element's
        (``layout.ELEMENT_LAW``); false compiles no code for it.
    top : float
        A bounded lattice's top (``Scene.top``, in the packed scene's
        coordinates): copies whose centre lies above it do not exist; ``inf``
        for none.  The kernels take it per orbit, relative to the start cell
        (:func:`.run.run_orbits`, ``ceilings``).
    """

    kinds: np.ndarray
    params: np.ndarray
    copies: np.ndarray
    A: np.ndarray
    B: np.ndarray
    lattice: bool
    jstart: np.ndarray
    jpts: np.ndarray
    law: int
    c: float
    s: float
    ax: float
    ay: float
    scale: float
    has_force: bool
    noslip: bool
    disk_lattice: bool
    long_walls: bool
    thermostat: bool = False
    top: float = math.inf
    mixed: bool = False
    magnetic: float = 0.0

    def variant(self, mode):
        """The compile-time slots of the event loop for this table and record mode.

        A :class:`noslipsim.core.variant.Variant` ``(spin, lattice, mode, disks, walls, flight, mixed,
        open_ends, settle)``, each slot an exact bool (the flight and the settle form ints) but ``mode``,
        read at run time for every record mode (:func:`recording_slot`, which checks ``mode``): a scene
        without force never pays for cubic or quartic exits, a specular one for spin updates, a plain
        one for the cell walk, a table without long walls for their exact check, a scene without the
        thermostat or a field for those flights, a table of one law for per-element laws, a table
        without reflex junctions or free ends for the open-end rule, a table with no invariant the
        targeted settle keeps for that settle (:attr:`settle`)
        (:func:`noslipsim.core.loop.orbit_kernel`).
        """
        return variant.normalise(spin=self.noslip, lattice=self.lattice, mode=recording_slot(mode),
                                 disks=self.disk_lattice, walls=self.long_walls, flight=self.flight, mixed=self.mixed,
                                 open_ends=self.open_ends, settle=self.settle)

    @property
    def settle(self):
        """The energy settle's form, ``variant.TARGETED`` or ``variant.WHOLE``: targeted where the table
        keeps an invariant a whole-state correction would break (:func:`noslipsim.core.energy.targeted_settle`,
        the rule the general kernel applies at run time; the invariants: :mod:`noslipsim.core.energy`)."""
        flight = self.flight
        mixes = self.law != layout.SPECULAR and self.s != 0.0  # as the kernel reads it
        rule = getattr(targeted_settle, "py_func", targeted_settle)  # its Python (a plain function without jit)
        targeted = rule(self.kinds, self.mixed, flight == variant.FORCE, mixes,
                        flight in (variant.THERMOSTAT, variant.MAGNETIC))
        return variant.TARGETED if targeted else variant.WHOLE

    @property
    def open_ends(self):
        """Some segment or arc has an open end (a reflex junction or a free end: end factor < 1,
        :mod:`noslipsim._engine.junctions`), so the cell search needs its open-end rule."""
        pieces = (self.kinds == layout.SEGMENT) | (self.kinds == layout.ARC)
        open_end = (self.params[:, layout.END_START] < 1.0) | (self.params[:, layout.END_END] < 1.0)
        return bool(np.any(pieces & open_end))

    @property
    def flight(self):
        """The flight's code (:mod:`noslipsim.core.variant`): straight, force, thermostat or magnetic."""
        if self.magnetic != 0.0:
            return variant.MAGNETIC
        if not self.has_force:
            return variant.STRAIGHT
        return variant.THERMOSTAT if self.thermostat else variant.FORCE

    @property
    def one_disk_per_cell(self):
        """One disk scatterer inside each cell, no force: the lean loop without its copy loop."""
        return self.disk_lattice and self.copies.shape == (1, 3) and not self.copies[0, 1:].any()

    def arrays(self):
        """The table's arguments of the kernels, in their order:
        ``(kinds, params, copies, A, B, lattice, jstart, jpts)``."""
        return self.kinds, self.params, self.copies, self.A, self.B, self.lattice, self.jstart, self.jpts


def recording_slot(mode):
    """The variant's ``mode`` slot for a record mode (validated): ``None``, read at run time, for every one.

    No records, a log and a portrait run one kernel, which writes only the records its run asks for:
    a branch per collision, at 0.97 to 1.01 of a kernel with the mode fixed, fresh and cached (the
    pentagon, the fastest scene, pays most; benchmarks/RESULTS.md, "One kernel for every record
    mode"), against a second compile of every scene that both records and does not (about 4 s each;
    the paper pipeline compiled 11 such pairs).
    """
    mode = int(mode)
    if mode not in (layout.RECORD_NONE, layout.RECORD_LOG, layout.RECORD_PORTRAIT):
        raise ValueError(f"mode: expected a record mode (layout.RECORD_*), got {mode!r}")
    return None


@per_scene
def scene_copies(scene):
    """Int array ``(K, 3)``: the element copies ``(element, o1, o2)`` that reach cell 0 (found once per scene)."""
    if scene.lattice is None:
        copies = np.zeros((len(scene.elements), 3), dtype=np.int64)
        copies[:, 0] = np.arange(len(scene.elements))
        return copies
    return reaching_copies(scene.elements, scene.lattice)


def placed_copies(scene):
    """``(index, element copy, shift)`` for each element copy that reaches cell 0 of ``scene``."""
    if scene.lattice is None:
        return [(i, e, np.zeros(2)) for i, e in enumerate(scene.elements)]
    A, _ = lattice_matrix(scene.lattice)
    return [(int(i), scene.elements[i].shifted(*(A @ [o1, o2])), A @ [o1, o2]) for i, o1, o2 in scene_copies(scene)]


@per_scene
def kernel_table(scene) -> KernelTable:
    """The kernel table of ``scene`` as it is written (built on first use, kept while the scene lives)."""
    elements = scene.elements
    scale = scene.scale
    copies = scene_copies(scene)
    if scene.lattice is None:
        A = np.zeros((2, 2))
        B = np.zeros((2, 2))
    else:
        A, B = (np.array(m) for m in lattice_matrix(scene.lattice))  # writable: the kernels' argument type
    placed = placed_copies(scene)
    kinds, params = _element_arrays(elements, placed, scale)
    laws = [layout.NOSLIP if law == "no-slip" else layout.SPECULAR for law in scene.element_laws]
    params[:, layout.ELEMENT_LAW] = laws
    mixed = len(set(laws)) > 1
    jstart, jpts = junction_arrays(elements, placed, scale)
    c, s = scene.noslip_coefficients
    ax, ay = scene.force
    has_force = scene.force != (0.0, 0.0)
    return KernelTable(
        kinds=kinds, params=params, copies=copies, A=A, B=B, lattice=scene.lattice is not None,
        jstart=jstart, jpts=jpts, law=layout.PER_ELEMENT if mixed else laws[0],
        c=c, s=s, ax=ax, ay=ay, scale=scale, has_force=has_force,
        noslip=layout.NOSLIP in laws, disk_lattice=not mixed and _disk_lattice(scene),
        long_walls=any(flag != 0.0 for flag in params[:, layout.LONG_WALL]),
        thermostat=has_force and scene.thermostat is not None, top=math.inf if scene.top is None else scene.top,
        mixed=mixed, magnetic=scene.magnetic)


def _element_arrays(elements, placed, scale):
    """``(kinds, params)``: kinds, parameter rows, end-band factors and long-wall flags."""
    kinds = np.array([e.kind for e in elements], dtype=np.int64)
    params = np.zeros((len(elements), layout.N_PARAMS))
    for i, e in enumerate(elements):
        row = e.params()
        params[i, : len(row)] = row
        for col, value in e.exact_params().items():  # a segment's own end point, for distances far along it
            params[i, col] = value
    params[:, layout.END_START:layout.END_END + 1] = end_factors(elements, placed, scale)
    params[:, layout.LONG_WALL] = long_walls(elements)
    return kinds, params


def long_walls(elements):
    """1.0 per line and per segment long against the table's smallest feature (``layout.LONG_WALL``), else 0.0.

    Only such a wall can carry a hit far from its ``p0``, where the plain
    distance cancels; the event loop checks those hits exactly, and a table
    without one runs a loop compiled without the check.
    """
    smallest = min((e.feature_scale() for e in elements), default=math.inf)
    return [1.0 if e.long_wall(smallest) else 0.0 for e in elements]


def _disk_lattice(scene):
    """A lattice of disjoint disk scatterers without force (Sinai torus, Lorentz gases): the lean loop.

    One or several disks per cell, of any radii, each inside its cell or
    reaching into neighbouring ones; no two disks (lattice copies included)
    come within ``DISK_GAP`` of each other (relative to the cell's size).
    Such disks are convex and never touch, so the loop needs no deflation,
    corner rule or extent test.  A table of mixed laws (:attr:`KernelTable.mixed`)
    never takes it: that loop knows one law.
    """
    if scene.lattice is None or scene.force != (0.0, 0.0) or scene.top is not None or scene.magnetic != 0.0:
        return False  # a bounded lattice runs the general loop, which knows the top
    if not all(e.disk() is not None for e in scene.elements):
        return False
    A, _ = lattice_matrix(scene.lattice)
    size = max(scene.scale, float(np.abs(A).sum(axis=1).max()))
    return disks_apart([e.disk() for e in scene.elements], scene.lattice, DISK_GAP * size)
