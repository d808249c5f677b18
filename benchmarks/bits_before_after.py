"""Bits before and after a kernel change: 32 orbits' full logs from two versions of the package, compared.

A change that should move no orbit but the ones it fixes (such as the reflex-vertex rule of
``core/events.py``, ``hit_in_cell``) is checked by running the same orbits with the old and the
new package and comparing every record and final value byte for byte: the pentagon, the Sinai
box, the Sinai torus, the hexagonal Lorentz cell, the Galton board, a wedge under gravity, the
L-shaped polygon (a reflex corner), the diamond lattice and the diamond in a box (reflex
vertices of a scatterer), with and without gravity and with the isokinetic thermostat, both
laws (specular, no-slip gamma 1/sqrt 2); 10^4 collisions per orbit (2 10^3 thermostatted).
Each version runs in its own process with its own numba cache::

    git archive <commit> src | tar -x -C /tmp/old
    PYTHONPATH=/tmp/old/src NUMBA_CACHE_DIR=/tmp/old/nc python benchmarks/bits_before_after.py /tmp/before.npz
    PYTHONPATH=src python benchmarks/bits_before_after.py /tmp/after.npz
    python benchmarks/bits_before_after.py --compare /tmp/before.npz /tmp/after.npz

The comparison prints one line per orbit (IDENTICAL, or the variables that differ) and exits
with the number of orbits that differ.
"""
import math
import sys

import numpy as np


def diamond_segments(Segment):
    """The four sides of the diamond about (1/2, 1/2) of half-diagonal 1/4, the table outside, built with
    ``Segment`` of the package at hand (the current one, or a copy from another commit)."""
    c, h = 0.5, 0.25
    pts = [(c, c + h), (c + h, c), (c, c - h), (c - h, c)]
    return tuple(Segment(pts[i], pts[(i + 1) % 4], "left") for i in range(4))


def scenes():
    """Name -> (scene, start position, velocity, spin) of every orbit compared."""
    from noslipsim import Scene, Segment, tables
    disk = 1 / math.sqrt(2)

    def diamond(law, g, force=(0.0, 0.0)):  # the square lattice of diamonds
        return Scene(diamond_segments(Segment), law=law, gamma=g, force=force,
                     lattice={"a1": [1.0, 0.0], "a2": [0.0, 1.0]})

    def diamond_box(law, g, force=(0.0, 0.0)):  # plain: a diamond in a box
        box = tables.rectangle(1.0, 1.0).elements
        return Scene(diamond_segments(Segment) + tuple(box), law=law, gamma=g, force=force)

    L = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    out = {}
    for law, g in (("specular", 0.0), ("no-slip", disk)):
        out[f"pentagon {law}"] = (tables.regular_polygon(5, law=law, gamma=g), (0.1, 0.05), (0.83, 0.41), 0.1)
        out[f"Sinai box {law}"] = (tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)], law=law, gamma=g),
                                   (0.1, 0.1), (0.6, 0.8), 0.1)
        out[f"torus {law}"] = (tables.sinai_torus(0.25, law=law, gamma=g), (0.45, 0.1), (0.83, 0.41), 0.1)
        out[f"hex cell {law}"] = (tables.hex_lorentz_cell(0.3, law=law, gamma=g), (0.4, 0.1), (0.7, 0.31), 0.2)
        out[f"Galton {law}"] = (tables.galton_board(law=law, gamma=g), (1.0, 0.0), (0.3, 0.95), 0.1)
        out[f"wedge gravity {law}"] = (tables.wedge(math.pi / 5, law=law, gamma=g), (0.0, 1.0), (0.3, 0.1), 0.1)
        out[f"diamond cell {law}"] = (diamond(law, g), (0.1, 0.1), (0.7, 0.31), 0.2)
        out[f"diamond cell gravity {law}"] = (diamond(law, g, (0.05, -1.0)), (0.1, 0.1), (0.7, 0.31), 0.2)
        out[f"diamond box {law}"] = (diamond_box(law, g), (0.1, 0.1), (0.7, 0.31), 0.2)
        out[f"diamond box gravity {law}"] = (diamond_box(law, g, (0.0, -1.0)), (0.1, 0.1), (0.7, 0.31), 0.2)
        out[f"L shape {law}"] = (tables.polygon(L, law=law, gamma=g), (0.5, 0.2), (0.7, 0.31), 0.2)
        out[f"L shape gravity {law}"] = (tables.polygon(L, law=law, gamma=g, force=(0.0, -1.0)), (0.5, 0.2),
                                         (0.7, 0.31), 0.2)
        out[f"pentagon gravity {law}"] = (tables.regular_polygon(5, law=law, gamma=g, force=(0.0, -1.0)),
                                          (0.1, 0.05), (0.83, 0.41), 0.1)
        out[f"hex cell thermostat {law}"] = (tables.hex_lorentz_cell(0.3, law=law, gamma=g, force=(0.1, 0.05))
                                             .replace(thermostat="isokinetic"), (0.4, 0.1), (0.7, 0.31), 0.2)
        out[f"L shape thermostat {law}"] = (tables.polygon(L, law=law, gamma=g, force=(0.3, -0.5))
                                            .replace(thermostat="isokinetic"), (0.5, 0.2), (0.7, 0.31), 0.2)
        out[f"diamond cell thermostat {law}"] = (diamond(law, g, (0.3, -0.5)).replace(thermostat="isokinetic"),
                                                 (0.1, 0.1), (0.7, 0.31), 0.2)
    return out


def run(path):
    """Run every orbit with the ``noslipsim`` on the path and save its records to ``path`` (npz)."""
    from noslipsim import simulate
    print("noslipsim from", __import__("noslipsim").__file__)
    arrays = {}
    for name, (scene, q, v, w) in scenes().items():
        n = 2000 if "thermostat" in name else 10_000
        d = simulate(scene, q, v, w, max_collisions=n)
        for var in d.data_vars:
            arrays[f"{name}|{var}"] = np.asarray(d[var].values)
        arrays[f"{name}|stop"] = np.array(d.attrs.get("stop_reason", ""))
        print(f"{name}: {int(d.sizes.get('collision', len(d.t)))} collisions, stop {d.attrs.get('stop_reason')}",
              flush=True)
    np.savez(path, **arrays)


def compare(a, b):
    """Print, per orbit, whether the two files hold the same bytes; return the number of orbits that differ."""
    A, B = np.load(a), np.load(b)
    names = sorted({k.split("|")[0] for k in A.files})
    bad = 0
    for name in names:
        keys = [k for k in A.files if k.startswith(name + "|")]
        diff = [k.split("|")[1] for k in keys if k not in B.files or A[k].shape != B[k].shape
                or A[k].tobytes() != B[k].tobytes()]
        n = A[f"{name}|t"].shape[0]
        print(f"{name:40s} {n:6d} records  {'IDENTICAL' if not diff else 'DIFFER: ' + ','.join(diff)}")
        bad += bool(diff)
    print(f"{len(names)} orbits, {bad} differ")
    return bad


if __name__ == "__main__":
    args = sys.argv[1:]
    comparing = bool(args) and args[0] == "--compare"
    if not args or (comparing and len(args) != 3) or (not comparing and args[0].startswith("-")):
        # a mistyped option never runs the orbits into a file named after it
        print(__doc__, file=sys.stderr)
        sys.exit(0 if args and args[0] in ("-h", "--help") else 2)
    if args[0] == "--compare":
        sys.exit(compare(args[1], args[2]))
    run(args[0])
