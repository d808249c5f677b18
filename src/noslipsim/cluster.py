"""Where the ensembles run: runtime settings (never science) to the arguments of :func:`noslipsim.simulate_many`.

The workflow's ensemble scripts read the ``runtime`` config section
(``snakemake --config 'runtime={...}'``, workflow/schemas/config.schema.yaml)
through :func:`ensemble_options`:

* ``dask_scheduler: tcp://host:8786``: a running dask.distributed scheduler;
* ``dask_cluster: slurm``: dask workers started here as SLURM jobs
  (dask-jobqueue's ``SLURMCluster``, :func:`slurm_cluster`), stopped at the end;
* neither: local threads, as many as the job's.

``chunk_size`` and ``chunk_folder`` choose the chunking and the on-disk, resumable path
(``simulate_many(out=...)``).  None of these changes a result (docs/cluster.md).
Schedulers and workers started here listen on 127.0.0.1 unless ``dask_interface`` names a
network interface; see docs/cluster.md for securing a real cluster with TLS.
"""
from __future__ import annotations

import hashlib
import json
import logging
import math
import os
import shutil
import subprocess
import sys
from contextlib import contextmanager

log = logging.getLogger("noslipsim.cluster")

#: Runtime settings and their defaults (the schema declares them again, for the workflow).
RUNTIME_DEFAULTS = {
    "dask_scheduler": None, "dask_cluster": None, "dask_workers": 2, "dask_worker_cores": 1,
    "dask_worker_memory": "2GiB", "dask_walltime": "01:00:00", "dask_interface": None,
    "dask_worker_timeout": 600, "chunk_size": None, "chunk_folder": None,
}
CLUSTERS = (None, "slurm")


#: Settings that are counts, and the one that is a number of seconds.
COUNTS = ("dask_workers", "dask_worker_cores", "chunk_size")
SECONDS = ("dask_worker_timeout",)


def _value(key, value):
    """One setting as given; ``snakemake --config 'runtime={...}'`` hands every value over as a string."""
    if value is None or (isinstance(value, str) and value.strip() in ("", "null", "~", "None")):
        return None
    if key in COUNTS or key in SECONDS:
        try:
            number = float(value)
        except (TypeError, ValueError):
            number = math.nan
        if not (number > 0 and math.isfinite(number)) or (key in COUNTS and number != int(number)):
            kind = "a positive integer" if key in COUNTS else "a positive number of seconds"
            raise ValueError(f"runtime.{key}: expected {kind}, got {value!r}")
        return int(number) if key in COUNTS else number
    return value


def runtime_settings(runtime=None):
    """The runtime settings with their defaults; ValueError naming an unknown, bad or conflicting one."""
    runtime = dict(runtime or {})
    unknown = sorted(set(runtime) - set(RUNTIME_DEFAULTS))
    if unknown:
        raise ValueError(f"runtime: unknown settings {unknown} (known: {sorted(RUNTIME_DEFAULTS)})")
    given = {k: _value(k, v) for k, v in runtime.items()}
    out = {**RUNTIME_DEFAULTS, **{k: v for k, v in given.items() if v is not None}}
    if out["dask_cluster"] not in CLUSTERS:
        raise ValueError(f"runtime.dask_cluster: expected one of {CLUSTERS}, got {out['dask_cluster']!r}")
    if out["dask_cluster"] and out["dask_scheduler"]:
        raise ValueError("runtime: give dask_scheduler (a running scheduler) or dask_cluster (start one), not both")
    return out


@contextmanager
def slurm_cluster(workers=2, *, cores=1, memory="2GiB", walltime="01:00:00", interface=None, timeout=600,
                  log_directory=None):
    """A dask.distributed Client whose workers are SLURM jobs (dask-jobqueue's SLURMCluster); closed on exit.

    One job per worker (one worker process of ``cores`` threads).  The account and the
    partition are SLURM's own defaults: ``sbatch`` reads ``SBATCH_ACCOUNT`` and
    ``SBATCH_PARTITION`` from the environment (or dask-jobqueue's config file,
    ``jobqueue.slurm.account`` / ``queue``); nothing is written here.  The scheduler runs in
    this process and, like the workers, listens on 127.0.0.1 unless ``interface`` names a
    network interface (``ib0``, ``eth0``) that the compute nodes reach.

    Raises RuntimeError (with ``squeue``'s view of the jobs) if no worker joins within
    ``timeout`` seconds: a job that SLURM cannot place never turns into a silent hang.
    """
    from dask_jobqueue import SLURMCluster
    from distributed import Client

    where = ({"interface": interface} if interface else
             {"scheduler_options": {"host": "127.0.0.1"}, "worker_extra_args": ["--host", "127.0.0.1"]})
    cluster = SLURMCluster(cores=cores, processes=1, memory=memory, walltime=walltime, python=sys.executable,
                           job_name="noslipsim-dask", log_directory=log_directory, **where)
    try:
        cluster.scale(jobs=workers)
        client = Client(cluster, set_as_default=False)
        try:
            try:
                client.wait_for_workers(1, timeout=timeout)
            except TimeoutError:
                jobs = subprocess.run(["squeue", "-h", "-n", "noslipsim-dask", "-o", "%i %T %r"],
                                      capture_output=True, text=True).stdout.strip()
                raise RuntimeError(f"no dask worker joined within {timeout} s; SLURM jobs: {jobs or 'none'}") from None
            jobs = ", ".join(f"{name} (job {getattr(job, 'job_id', '?')})" for name, job in cluster.workers.items())
            log.warning("dask scheduler %s with %d worker job(s) on SLURM: %s", cluster.scheduler_address, workers,
                        jobs)
            yield client
        finally:
            client.close()
    finally:
        cluster.close()


def chunk_folder(settings, name, params):
    """``chunk_folder/name/<digest of params>``: one folder per rule and science, so a resume finds its own."""
    key = hashlib.sha256(json.dumps(params, sort_keys=True, default=str).encode()).hexdigest()[:16]
    return os.path.join(settings["chunk_folder"], name, key)


@contextmanager
def ensemble_options(runtime=None, threads=1, *, name=None, params=None):
    """Keyword arguments for an ensemble (``scheduler``, ``num_workers``, ``chunk_size``, ``progress``, ``out``).

    Parameters
    ----------
    runtime : dict, optional
        The workflow's ``runtime`` settings (:data:`RUNTIME_DEFAULTS`).
    threads : int
        Local threads (the Snakemake job's ``threads``).
    name, params : str, dict, optional
        With ``chunk_folder`` set: the chunk files go to
        ``chunk_folder/name/<digest of params>`` (:func:`chunk_folder`) and are removed
        when the block ends without error (the dataset is written by then); a killed job
        leaves them, and its rerun computes only the missing chunks.  Without ``name``, no
        ``out`` (ensembles whose experiment has no on-disk path).

    Yields
    ------
    dict
        To pass on as ``**options``.  A SLURM dask cluster lives as long as the block.
    """
    settings = runtime_settings(runtime)
    options = {"num_workers": threads, "chunk_size": settings["chunk_size"], "progress": True}
    folder = None
    if settings["chunk_folder"] and name is not None:
        folder = options["out"] = chunk_folder(settings, name, params or {})
    if settings["dask_cluster"] == "slurm":
        with slurm_cluster(settings["dask_workers"], cores=settings["dask_worker_cores"],
                           memory=settings["dask_worker_memory"], walltime=settings["dask_walltime"],
                           interface=settings["dask_interface"], timeout=settings["dask_worker_timeout"]) as client:
            yield {**options, "scheduler": client}
    else:
        yield {**options, "scheduler": settings["dask_scheduler"]}
    if folder is not None:
        shutil.rmtree(folder, ignore_errors=True)
