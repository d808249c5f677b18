"""The Galton board ensemble for several versions, each as several package copies, in one process.

Why copies: one version's kernels, compiled twice in one process under two package names, can
run the no-slip board up to 10 % apart, run after run (benchmarks/RESULTS.md, "The settle's cost,
probed"): where the loader puts a kernel matters as much as small code changes.  A version is
judged here by all of its copies, so a placement draw is not taken for the code's effect.

Each version is a commit (extracted with ``package_copy``) or a folder holding a changed copy of
``src/noslipsim``; each becomes ``--copies`` packages ``nss_<label>_<k>``.  The energy settle is
switched off in every copy (``energy.SETTLE_AT = 1``, read when the kernels compile), so versions
whose collision code agrees do the same work; the total collisions of each copy are printed to
check it.  Rounds call the copies in turn, the order reversed every other round; per copy, the
median over rounds of its rate over the first copy's (the first version is the reference).

    python benchmarks/galton_copies.py b4489a3 HEAD /tmp/changed/noslipsim --law no-slip --rounds 8

Use a fresh ``NUMBA_CACHE_DIR`` when a folder's sources change between runs.
"""
import argparse
import importlib
import os
import shutil
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_before_after import CASES, time_in_turn
from package_copy import load_version


def settle_off(name):
    """The energy settle of package ``name`` switched off (read when its kernels compile)."""
    importlib.import_module(f"{name}.core.energy").SETTLE_AT = 1.0


def ensemble(pkg, law, n_orbits):
    """``bench_before_after.py``'s Galton board ensemble case of ``law`` with ``n_orbits`` orbits."""
    make, scene, start, _, kw = CASES[f"ensemble: Galton {law}"]
    return make(pkg, scene, start, n_orbits, kw)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("versions", nargs="+", help="commits or package folders; the first is the reference")
    ap.add_argument("--law", default="no-slip", choices=("no-slip", "specular"))
    ap.add_argument("--copies", type=int, default=2, help="packages per version")
    ap.add_argument("--rounds", type=int, default=8)
    ap.add_argument("--orbits", type=int, default=1000)
    args = ap.parse_args()
    where = tempfile.mkdtemp(prefix="galton_copies_")
    runs = {}
    for i, version in enumerate(args.versions):
        label = f"v{i}"
        for k in range(args.copies):
            pkg = load_version(version, f"nss_{label}_{k}", where, settle_off)
            runs[f"{label}_{k}"] = ensemble(pkg, args.law, args.orbits)
    versions = ", ".join(f"v{i} = {v}" for i, v in enumerate(args.versions))
    print(f"load at start: {os.getloadavg()}; versions: {versions}")
    names = list(runs)
    rates, work = time_in_turn(runs, args.rounds)
    ref = rates[names[0]]
    for n in names:
        ratios = [a / b for a, b in zip(rates[n], ref)]
        print(f"{n:8s} {work[n]:>12,} collisions  best {max(rates[n]):>12,.0f} coll/s  "
              f"vs {names[0]} median {statistics.median(ratios):.3f} ({min(ratios):.2f}-{max(ratios):.2f})")
    print(f"load at end: {os.getloadavg()}")
    shutil.rmtree(where, ignore_errors=True)


if __name__ == "__main__":
    main()
