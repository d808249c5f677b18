"""Where the compile time goes: every kernel variant the paper pipeline uses, compiled in one process.

Compiles (from an empty numba cache of its own) the variants of ``KERNELS`` in
``workflow/rules/common.smk`` through ``workflow/scripts/compile_kernels.py``'s representative
scenes, records numba's compile events, and prints the wall and CPU time of the whole, then per
function: how many specialisations were compiled and their self time (a compile's time less the
compiles it triggered).  The goal of issue 32 is the whole halved.

    python benchmarks/compile_profile.py [--top 25] [--only lattice]
"""
import argparse
import ast
import collections
import os
import re
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def pipeline_entries():
    """The ``table:law`` entries of ``KERNELS`` in rules/common.smk (evaluated, not imported)."""
    text = open(os.path.join(ROOT, "workflow", "rules", "common.smk"), encoding="utf-8").read()
    block = re.search(r"^KERNELS = (\{.*?^\})", text, re.S | re.M).group(1)
    kernels = eval(compile(ast.parse(block, mode="eval"), "KERNELS", "eval"))  # plain literals and comprehensions
    return sorted({entry for entries in kernels.values() for entry in entries})


def tables():
    """``(TABLES, warm)`` of workflow/scripts/compile_kernels.py: the representative scene of each kind, and the
    calls that compile its kernel."""
    text = open(os.path.join(ROOT, "workflow", "scripts", "compile_kernels.py"), encoding="utf-8").read()
    start = text.index("TABLES = {")
    end = text.index("\nentry = ", start)
    import noslipsim as ns
    from noslipsim import tables as tbl

    space = {"ns": ns, "tables": tbl}
    exec(text[start:end], space)
    return space["TABLES"], space["warm"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--top", type=int, default=25)
    ap.add_argument("--only", default="", help="compile the entries containing this text")
    args = ap.parse_args()
    if "NUMBA_CACHE_DIR" not in os.environ or os.listdir(os.environ["NUMBA_CACHE_DIR"]):
        os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="nss_compile_")
        os.execv(sys.executable, [sys.executable, *sys.argv])  # numba reads the variable at import
    from machine import machine_line
    from numba.core import event


    print(machine_line(numpy=True, load=True))
    entries = [e for e in pipeline_entries() if args.only in e]
    table_of, warm = tables()
    print(f"{len(entries)} pipeline entries, empty cache {os.environ['NUMBA_CACHE_DIR']}")
    w0, c0 = time.perf_counter(), time.process_time()
    with event.install_recorder("numba:compile") as rec:
        for entry in entries:
            table, law = entry.split(":")
            scene, start = table_of[table](law)
            t0 = time.process_time()
            warm(scene, start)  # as compile_kernels.py: one kernel for every record mode
            print(f"  {entry:<36}{time.process_time() - t0:7.1f} s CPU", flush=True)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    print(f"all: {wall:.1f} s wall, {cpu:.1f} s CPU")
    # self time per function: each END's duration less the compiles nested in it
    stack, self_time, count = [], collections.Counter(), collections.Counter()
    for ts, ev in rec.buffer:
        name = getattr(ev.data.get("dispatcher"), "py_func", None)
        name = name.__qualname__.split("_v")[0] if name is not None else str(ev.data.get("dispatcher"))
        if ev.is_start:
            stack.append([name, ts, 0.0])
        else:
            fn, t_start, children = stack.pop()
            total = ts - t_start
            self_time[fn] += total - children
            count[fn] += 1
            if stack:
                stack[-1][2] += total
    print(f"{'function':<60}{'compiles':>9}{'self s':>9}")
    for fn, s in self_time.most_common(args.top):
        print(f"{fn[-60:]:<60}{count[fn]:>9}{s:>9.1f}")
    print(f"{'(all functions)':<60}{sum(count.values()):>9}{sum(self_time.values()):>9.1f}")


if __name__ == "__main__":
    main()
