"""Cluster-scale measurements (docs/cluster.md, "How far it scales"; results in RESULTS.md, "Cluster").

1. ``scaling``: strong scaling of one ensemble over 1 and 2 dask worker processes (a
   ``LocalCluster`` of single-threaded worker processes on 127.0.0.1), against the local
   single-thread run: wall times and parallel efficiency T1 / (k Tk).
2. ``memory``: the chunked Galton run (``galton_distribution(..., out=folder)`` written with
   ``write_dataset``) at two sizes, each in a fresh process: peak resident memory (ru_maxrss),
   wall and CPU time (all threads; other load on the machine inflates the wall time, not the CPU
   time); with ``--in-memory`` also the same runs without ``out`` for contrast.
3. The projection of 10^8 particles on N cores from the measured cost per particle (CPU seconds
   of the largest chunked run) and a parallel efficiency (``--efficiency``, the one ``scaling``
   measured).

    python benchmarks/bench_cluster.py scaling
    python benchmarks/bench_cluster.py memory --sizes 100000 1000000 [--in-memory]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from machine import machine_line

#: The Galton run of the memory measurement: the paper's board (spacing 2, pegs of radius 0.89),
#: two rows deep, the specular law (every particle arrives), so a particle costs little and the
#: run measures the chunked path, not the physics.
GALTON = dict(laws=("specular",), rows=2, radius=0.89, max_time=2000.0, seed=1)
#: The scaling ensemble: no-slip Galton particles on the paper's board (10 rows, T = 2000).
SCALING = dict(laws=("no-slip",), rows=10, radius=0.89, max_time=2000.0, seed=2)


def scaling(n):
    from distributed import Client, LocalCluster

    from noslipsim.experiments import galton_distribution

    galton_distribution(20, **SCALING, num_workers=1)  # compile (or load) the kernel first
    t0, c0 = time.perf_counter(), time.process_time()
    ref = galton_distribution(n, **SCALING, scheduler="sync", chunk_size=max(1, n // 40))
    times = {"local, 1 thread": time.perf_counter() - t0}
    cpu = time.process_time() - c0                  # one thread: its CPU time, not inflated by other load
    for k in (1, 2):
        with LocalCluster(n_workers=k, threads_per_worker=1, processes=True, host="127.0.0.1",
                          dashboard_address=None) as cluster, Client(cluster) as client:
            client.run(lambda: galton_distribution(20, **SCALING, num_workers=1) and None)  # warm workers
            t0 = time.perf_counter()
            ds = galton_distribution(n, **SCALING, scheduler=client, chunk_size=max(1, n // 40))
            times[f"{k} worker process(es)"] = time.perf_counter() - t0
        assert ds.identical(ref), "a distributed run differs from the local one"
    t1 = times["1 worker process(es)"]
    print(f"ensemble: {n} no-slip Galton particles (10 rows, T = 2000), {max(1, n // 40)} per chunk; "
          f"mean collisions {float(ref.n_collisions.mean()):.0f}; identical datasets; local run "
          f"{cpu:.2f} CPU s = {cpu / n * 1e6:.0f} core-microseconds per particle")
    for name, t in times.items():
        k = 2 if name.startswith("2") else 1
        print(f"  {name:24s} {t:8.2f} s   efficiency T1/(k Tk) = {t1 / (k * t):.2f}")


CHILD = """
import json, os, resource, sys, time
from noslipsim import write_dataset
from noslipsim.experiments import galton_distribution
n, folder, target = int(sys.argv[1]), sys.argv[2], sys.argv[3]
through_disk, kw = sys.argv[4] == "1", json.loads(sys.argv[5])
galton_distribution(10, **kw)                      # load the kernel before timing
t0, c0 = time.perf_counter(), time.process_time()
ds = galton_distribution(n, **kw, num_workers=os.cpu_count(), **({"out": folder} if through_disk else {}))
write_dataset(ds, target)
wall, cpu = time.perf_counter() - t0, time.process_time() - c0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({"n": n, "disk": through_disk, "wall": wall, "cpu": cpu, "peak_mib": peak,
                  "collisions": int(ds.n_collisions.sum()), "arrived": float(ds.arrived.mean())}))
"""


def memory(sizes, in_memory, efficiency):
    rows = []
    for n in sizes:
        for disk in ([True, False] if in_memory else [True]):
            with tempfile.TemporaryDirectory() as tmp:
                out = subprocess.run([sys.executable, "-c", CHILD, str(n), os.path.join(tmp, "chunks"),
                                      os.path.join(tmp, "galton.nc"), "1" if disk else "0", json.dumps(GALTON)],
                                     capture_output=True, text=True, check=True)
                rows.append(json.loads(out.stdout.strip().splitlines()[-1]))
                r = rows[-1]
                print(f"  {n:>9d} particles  {'chunked (out=)' if disk else 'in memory':15s} peak RSS "
                      f"{r['peak_mib']:7.0f} MiB  wall {r['wall']:7.1f} s  cpu {r['cpu']:7.1f} s  "
                      f"{r['collisions'] / r['cpu'] / 1e6:5.2f} M collisions/cpu-s  arrived {r['arrived']:.4f}",
                      flush=True)
    big = max((r for r in rows if r["disk"]), key=lambda r: r["n"])
    per = big["cpu"] / big["n"]                     # CPU time of all threads: not inflated by other load
    print(f"projection: {per * 1e6:.0f} core-microseconds per particle (this board, measured at n = {big['n']}); "
          f"10^8 particles = {per * 1e8 / 3600:.1f} core-hours")
    for cores in (2, 64, 512, 4096):
        print(f"  on {cores:5d} cores at parallel efficiency {efficiency:.2f}: "
              f"{per * 1e8 / (cores * efficiency) / 3600:8.2f} h")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=["scaling", "memory"])
    parser.add_argument("--n", type=int, default=400, help="particles of the scaling ensemble")
    parser.add_argument("--sizes", type=int, nargs="+", default=[100_000, 1_000_000])
    parser.add_argument("--in-memory", action="store_true", help="also measure the runs without out=")
    parser.add_argument("--efficiency", type=float, default=1.0,
                        help="parallel efficiency of the projection (the one measured by 'scaling')")
    args = parser.parse_args()
    print(machine_line(load=True))
    if args.what == "scaling":
        scaling(args.n)
    else:
        memory(args.sizes, args.in_memory, args.efficiency)
    print(f"load at the end: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
