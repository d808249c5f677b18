"""Run independent chunk tasks on local threads or a dask.distributed cluster, as they complete.

Dask lives here (and the cluster start-up in :mod:`noslipsim.cluster`).  The driver keeps only a
few chunks in flight (:data:`IN_FLIGHT` per worker thread), builds each chunk's inputs only when it
submits it and hands each result to a callback as soon as it arrives, so its memory does not grow
with the number of chunks.  Progress lines report the chunks done and an estimated time to the end;
on a distributed cluster, a worker that leaves (killed, its node lost) is reported with the chunks
it was running, which the scheduler runs again elsewhere.
"""
from __future__ import annotations

import itertools
import logging
import math
import os
import sys
import time

log = logging.getLogger("noslipsim.ensemble")

#: Chunks in flight per worker thread: enough to keep every thread busy while results come back.
IN_FLIGHT = 2
#: Seconds between two looks at a distributed cluster's workers (and between two progress lines).
POLL = 0.5
LOCAL = (None, "threads", "sync", "synchronous", "numba")


def check_scheduler(scheduler):
    """ValueError unless ``scheduler`` is a name :func:`run_tasks` knows, an address or a Client."""
    if scheduler in LOCAL or isinstance(scheduler, str):
        return
    from distributed import Client

    if not isinstance(scheduler, Client):
        raise ValueError(f"scheduler: expected None, 'threads', 'sync', 'numba', a distributed Client "
                         f"or a scheduler address, got {scheduler!r}")


class Progress:
    """Progress lines on stderr: chunks done of the total, the orbits they hold, elapsed time and an ETA.

    The ETA extrapolates the rate of the chunks computed in this run (chunks found already done
    on disk are counted as done but not as work)."""

    def __init__(self, total, done=0, show=True, label="chunks"):
        self.total, self.done, self.skipped, self.show, self.label = total, done, done, show, label
        self.start = self.last = time.monotonic()
        if show and done:
            self._print(f"{done} of {total} {label} already done; computing {total - done}")

    def _print(self, text):
        print(f"[noslipsim] {text}", file=sys.stderr, flush=True)

    def step(self):
        self.done += 1
        now = time.monotonic()
        if not self.show or (now - self.last < POLL and self.done < self.total):
            return
        self.last = now
        elapsed = now - self.start
        computed = self.done - self.skipped
        eta = elapsed / computed * (self.total - self.done) if computed else math.nan
        self._print(f"{self.label} {self.done}/{self.total} ({100 * self.done / max(self.total, 1):.0f}%), "
                    f"elapsed {_clock(elapsed)}, ETA {_clock(eta)}")


def _clock(seconds):
    if not math.isfinite(seconds):
        return "?"
    seconds = round(seconds)
    h, rest = divmod(seconds, 3600)
    return f"{h}:{rest // 60:02d}:{rest % 60:02d}" if h else f"{rest // 60}:{rest % 60:02d}"


def run_tasks(fn, jobs, on_result, *, scheduler=None, num_workers=None, progress=None, total=None, done=0):
    """Run ``fn(*args)`` for every ``(key, args)`` of the iterable ``jobs``; ``on_result(key, result)`` in the driver.

    Parameters
    ----------
    fn : callable
        A module-level function (it is pickled to the workers of a distributed cluster).
    jobs : iterable of (key, tuple)
        Consumed lazily: a job's inputs exist only while it is in flight.  A key
        ``(start, stop)`` names the orbits of a chunk in the messages.
    on_result : callable
        Called in the driver thread, in completion order.
    scheduler : None, str or distributed.Client
        ``None``/'threads'/'numba': a local thread pool of ``num_workers`` threads (default: one
        per core; the kernels release the GIL); 'sync': one at a time in this thread; a
        ``dask.distributed`` Client or scheduler address.
    progress : bool, optional
        Progress lines with an ETA on stderr (default: only when stderr is a terminal).
    total, done : int
        Chunks in the whole run and how many of them were done before (for the progress lines).
    """
    show = sys.stderr.isatty() if progress is None else bool(progress)
    bar = Progress(total if total is not None else 0, done, show)
    if scheduler in ("sync", "synchronous"):
        for key, args in jobs:
            on_result(key, fn(*args))
            bar.step()
        return
    if scheduler in (None, "threads", "numba"):
        _run_local(fn, jobs, on_result, num_workers or os.cpu_count() or 1, bar)
        return
    check_scheduler(scheduler)
    from distributed import Client

    if isinstance(scheduler, str):
        with Client(scheduler, set_as_default=False) as client:
            _run_distributed(client, fn, jobs, on_result, bar)
    else:
        _run_distributed(scheduler, fn, jobs, on_result, bar)


def _run_local(fn, jobs, on_result, threads, bar):
    from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait

    jobs = iter(jobs)
    pool = ThreadPoolExecutor(threads)
    try:
        running = {pool.submit(fn, *args): key for key, args in itertools.islice(jobs, IN_FLIGHT * threads)}
        while running:
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for future in finished:
                on_result(running.pop(future), future.result())
                bar.step()
                for key, args in itertools.islice(jobs, 1):
                    running[pool.submit(fn, *args)] = key
    except BaseException:
        pool.shutdown(wait=True, cancel_futures=True)   # a failed chunk: start no other
        raise
    pool.shutdown(wait=True)


def _run_distributed(client, fn, jobs, on_result, bar):
    """Keep a window of chunks submitted, take them as they complete, report workers that leave while chunks run.

    The window follows the cluster's threads (workers started as batch jobs join late)."""
    import uuid

    jobs = iter(jobs)
    run_id = uuid.uuid4().hex[:8]
    running = {}                                   # future -> chunk key
    names = {}                                     # dask key -> chunk key, of the chunks in flight

    def top_up(threads):
        for key, args in itertools.islice(jobs, max(0, IN_FLIGHT * max(1, threads) - len(running))):
            name = f"noslipsim-chunk-{run_id}-{key}"
            running[client.submit(fn, *args, key=name, pure=False)] = key
            names[name] = key

    workers, placed, threads = _cluster_state(client, names)
    top_up(threads)
    while running:
        waited = time.monotonic() + POLL          # a future's state is local: looking is cheap
        while not any(f.done() for f in running) and time.monotonic() < waited:
            time.sleep(0.01)
        now_workers, now_placed, threads = _cluster_state(client, names)
        for worker in sorted(set(workers) - set(now_workers)):
            lost = sorted(key for key, where in placed.items() if where == worker and _pending(running, key))
            log.warning("worker %s left the cluster with chunks assigned to it (%s); the scheduler runs them "
                        "again on the other workers", worker, ", ".join(map(_name, lost)) or "none running")
        workers, placed = now_workers, {**placed, **now_placed}
        for future in [f for f in running if f.done()]:
            key = running.pop(future)
            on_result(key, future.result())      # raises the chunk's error, or KilledWorker after repeated losses
            names.pop(future.key, None)
            placed.pop(key, None)
            future.release()
            bar.step()
        top_up(threads)


def _name(key):
    """A chunk key ``(start, stop)`` as the orbits it holds."""
    return f"orbits {key[0]}-{key[1] - 1}" if isinstance(key, tuple) else str(key)


def _pending(running, key):
    return any(k == key and not f.done() for f, k in running.items())


def _cluster_state(client, names):
    """The cluster's workers, ``{chunk key: worker}`` of the chunks they run now, and their threads.

    Asks the scheduler each time (``Client.nthreads``): ``Client.scheduler_info`` returns a cached
    identity that the client's periodic refresh may overwrite, between the call and its return,
    with one that lists no workers, which made every worker look gone."""
    workers = client.nthreads()
    placed = {}
    for worker, keys in client.processing().items():
        for name in keys:
            if name in names:
                placed[names[name]] = worker
    return set(workers), placed, sum(workers.values())
