"""Compile (or load from numba's cache) one kernel variant the simulations need.

The entry "table:law" (KERNELS in rules/common.smk) runs tiny orbits on a representative scene of that
kind, which compiles the variant once for every scene of the kind and every record mode (one kernel
reads the mode at run time): simulate() for a log, simulate_many() for final states.  Parallel jobs may compile
different variants at once: the cache is safe to fill from several processes (core/jit.py).
"""
import json
import sys
import time

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numba

import noslipsim as ns
from noslipsim import tables
from noslipsim.core.jit import SOURCE_DIGEST

# a representative scene of each kind and a start strictly inside it
TABLES = {
    "plain": lambda law: (tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)], law=law), (0.3, 0.5)),
    "plain+force": lambda law: (tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)], law=law, force=(0.0, -1.0)),
                                (0.3, 0.5)),
    # the two disks of Figure S7 under a force flown with the isokinetic thermostat
    "plain+thermostat": lambda law: (tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)], law=law, force=(0.0, -1.0))
                                     .replace(thermostat="isokinetic"), (0.3, 0.5)),
    # walls of the other law around a disk of ``law``: a table of mixed laws (KernelTable.mixed)
    "mixed": lambda law: (tables.closed_hex_cell(0.4, law=law, wall_law="specular" if law == "no-slip" else "no-slip"),
                          (0.0, 0.45)),
    "mixed+force": lambda law: (tables.closed_hex_cell(0.4, law=law, force=(0.0, -1.0),
                                                       wall_law="specular" if law == "no-slip" else "no-slip"),
                                (0.0, 0.45)),
    # infinite walls (wedges, the half-plane) take the loop with the long-wall check (KernelTable.long_walls)
    "walls+force": lambda law: (tables.wedge(0.6, law=law), (0.0, 1.0)),
    "lattice": lambda law: (tables.sinai_torus(0.25, law=law).replace(
        elements=(*tables.sinai_torus(0.25).elements, ns.Circle((0.5, 0.5), 0.1))), (0.3, 0.1)),
    "lattice+force": lambda law: (tables.galton_board(2.0, 0.5, law=law), (1.0, 0.5)),
    # the hexagonal Lorentz gas driven by a field with the isokinetic thermostat (Figures 13, S3)
    "lattice+thermostat": lambda law: (tables.hex_lorentz_cell(0.4, law=law, force=(0.0, -1.0)).replace(
        thermostat="isokinetic"), (0.0, 0.45)),
    "disks": lambda law: (tables.sinai_torus(0.25, law=law), (0.4, 0.1)),
}


def warm(scene, start):
    """Compile (or load) ``scene``'s kernel through both calls that run it: simulate() and simulate_many()."""
    ns.simulate(scene, start, (0.6, 0.8), 0.1, max_collisions=5)
    ns.simulate_many(scene, [start], [[0.6, 0.8]], [0.1], max_collisions=5, record="final", scheduler="sync",
                     progress=False)


entry = snakemake.params.entry
try:
    table, law = entry.split(":")
    scene, start = TABLES[table](law)
except (ValueError, KeyError):
    raise ValueError(f"KERNELS entry {entry!r}: expected 'table:law' with table in {sorted(TABLES)}, "
                     f"law in ('no-slip', 'specular')") from None
t0 = time.perf_counter()
warm(scene, start)
seconds = time.perf_counter() - t0
print(f"{entry}: {seconds:.1f} s", file=sys.stderr)
with open(snakemake.output[0], "w") as fh:
    json.dump({"entry": entry, "seconds": round(seconds, 2), "noslipsim": ns.__version__, "numba": numba.__version__,
               "core_sources": SOURCE_DIGEST}, fh, indent=1)
