"""What machine a benchmark ran on (shared by the benchmark scripts)."""
import os
import platform
import time


def cpu_model():
    """The CPU model name from /proc/cpuinfo, else what ``platform`` knows."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def machine_line(numpy=False, load=False):
    """``machine: <cpu> x <cores> | <system> | python <version>``, then ``| numpy <version>`` and
    ``| load <1-minute load average>`` if asked: the first line of a benchmark's output."""
    line = f"machine: {cpu_model()} x {os.cpu_count()} | {platform.system()} | python {platform.python_version()}"
    if numpy:
        import numpy as np

        line += f" | numpy {np.__version__}"
    if load:
        line += f" | load {os.getloadavg()[0]:.2f}"
    return line


def report_baseline(label, loop, start, n, *params):
    """Print the machine, then the best of three timings of ``loop(*start, n, *params)`` (after a warm-up)."""
    print(machine_line())
    loop(*start, 10, *params)
    best = 0.0
    for _ in range(3):
        t0 = time.perf_counter()
        loop(*start, n, *params)
        best = max(best, n / (time.perf_counter() - t0))
    print(f"{label} (no guarantees): {best:,.0f} collisions/s")
