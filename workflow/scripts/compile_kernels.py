"""Compile (or load from numba's cache) the kernel variants the simulations need, one after another.

Each entry "table:law:record" of the subject (KERNELS in rules/common.smk) runs a tiny orbit on a
representative scene of that kind, which compiles the variant once for every scene of the kind.
"""
import fcntl
import json
import os
import sys
import time

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numba  # noqa: E402

import noslipsim as ns  # noqa: E402
from noslipsim import tables  # noqa: E402
from noslipsim._numba_cache import source_digest  # noqa: E402

# a representative scene of each kind and a start strictly inside it
TABLES = {
    "plain": lambda law: (tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)], law=law), (0.3, 0.5)),
    "plain+force": lambda law: (tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)], law=law, force=(0.0, -1.0)),
                                (0.3, 0.5)),
    # infinite walls (wedges, the half-plane) take the loop with the long-wall check (Scene.has_long_walls)
    "walls+force": lambda law: (tables.wedge(0.6, law=law), (0.0, 1.0)),
    "lattice": lambda law: (tables.sinai_torus(0.25, law=law).replace(
        elements=tables.sinai_torus(0.25).elements + (ns.Circle((0.5, 0.5), 0.1),)), (0.3, 0.1)),
    "lattice+force": lambda law: (tables.galton_board(2.0, 0.5, law=law), (1.0, 0.5)),
    "disks": lambda law: (tables.sinai_torus(0.25, law=law), (0.4, 0.1)),
}
RECORDS = ("final", "count", "portrait", "log", "orbit")

# One subject's compile job at a time (numba's cache is not safe to fill from parallel processes,
# numba #4807); the lock is released when the job ends.
lock = open(os.path.join(os.path.dirname(snakemake.output[0]), ".compile.lock"), "w")
fcntl.flock(lock, fcntl.LOCK_EX)

done = []
for entry in snakemake.params.entries:
    try:
        table, law, record = entry.split(":")
        scene, start = TABLES[table](law)
        assert record in RECORDS
    except (ValueError, KeyError, AssertionError):
        raise ValueError(f"KERNELS entry {entry!r}: expected 'table:law:record' with table in {sorted(TABLES)}, "
                         f"law in ('no-slip', 'specular'), record in {RECORDS}") from None
    t0 = time.perf_counter()
    if record == "orbit":
        ns.simulate(scene, start, (0.6, 0.8), 0.1, max_collisions=5)
    else:
        ns.simulate_many(scene, [start], [[0.6, 0.8]], [0.1], max_collisions=5, record=record,
                         scheduler="sync", progress=False)
    seconds = time.perf_counter() - t0
    print(f"{entry}: {seconds:.1f} s", file=sys.stderr)
    done.append({"entry": entry, "seconds": round(seconds, 2)})

with open(snakemake.output[0], "w") as fh:
    json.dump({"kernels": done, "noslipsim": ns.__version__, "numba": numba.__version__,
               "core_sources": source_digest()}, fh, indent=1)
