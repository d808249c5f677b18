"""The pipeline on a real one-node SLURM: Snakemake's SLURM executor, and dask workers started as SLURM jobs.

workflow/profiles/slurm/local-slurm.sh starts munged, slurmctld and slurmd for this host (as
root; it installs Debian's slurm-wlm and munge first if apt-get can) and the tests talk to SLURM
only through its own commands, as users do.  To keep CI short, only two cheap dataset rules of
one subject go through SLURM: ``galton_orbits`` (an orbit set) and ``galton_distribution`` (an
ensemble job of two threads), with the four compile jobs they depend on (Snakemake's SLURM
executor polls the queue at growing intervals, so each wave of jobs costs tens of seconds); both
are compared value
for value with the reduced pipeline run locally (the session's ``repo``, shared with
test_pipeline.py).  The SLURM runs use the numba cache that local run filled (the session's,
warm by then): what is tested is where the jobs run, not a second cold compile (results never
depend on the cache: test_compile_cache.py).  Recipes as in docs/cluster.md.
"""
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest
import xarray as xr
from pipeline_run import ROOT, snakemake, workflow_copy

SCRIPT = ROOT / "workflow" / "profiles" / "slurm" / "local-slurm.sh"
TARGETS = ["results/galton/orbits.nc", "results/galton/distribution.nc"]
#: Global attributes that say when and how a dataset was made, not what it holds.
MAKING = ("history", "software", "git_commit", "git_dirty")


def why_no_slurm():
    """The reason the one-node SLURM cannot run here, or None (installing the packages if root can)."""
    if os.geteuid() != 0:
        return "the one-node SLURM needs root (slurmd runs jobs as their users)"
    for module in ("dask_jobqueue", "snakemake_executor_plugin_slurm"):
        try:
            __import__(module)
        except ImportError:
            return f"{module} is not installed (pip install -e '.[test]')"
    if shutil.which("slurmctld") is None or shutil.which("munged") is None:
        if shutil.which("apt-get") is None:
            return "slurm-wlm and munge are not installed and there is no apt-get to install them"
        subprocess.run(["bash", str(SCRIPT), "install"], check=True)
    return None


@pytest.fixture(scope="module")
def slurm():
    """A running one-node SLURM (SLURM_CONF set for this process and its children); stopped afterwards.

    Its folder is not under pytest's private (0700) temporary folder: munged runs as the munge user."""
    reason = why_no_slurm()
    if reason:
        pytest.skip(reason)
    folder = Path(tempfile.mkdtemp(prefix="noslipsim-slurm-"))
    folder.chmod(0o755)
    started = subprocess.run(["bash", str(SCRIPT), "start", str(folder)], capture_output=True, text=True)
    assert started.returncode == 0, started.stderr
    old = os.environ.get("SLURM_CONF")
    os.environ["SLURM_CONF"] = str(folder / "slurm.conf")
    yield folder
    subprocess.run(["bash", str(SCRIPT), "stop", str(folder)], check=False)
    shutil.rmtree(folder, ignore_errors=True)
    if old is None:
        os.environ.pop("SLURM_CONF")
    else:
        os.environ["SLURM_CONF"] = old


def same_dataset(a, b):
    """Values, coordinates, variable attributes and the science attributes (config included) are equal."""
    with xr.open_dataset(a) as x, xr.open_dataset(b) as y:
        x, y = x.load(), y.load()
    for ds in (x, y):
        for key in MAKING:
            ds.attrs.pop(key, None)
    xr.testing.assert_identical(x, y)


def test_the_node_is_idle_and_runs_a_job(slurm):
    assert subprocess.run(["sinfo", "-h", "-N", "-o", "%t"], capture_output=True, text=True).stdout.strip() == "idle"
    out = subprocess.run(["srun", "hostname"], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0 and out.stdout.strip() == os.uname().nodename.split(".")[0]


def test_snakemake_slurm_executor_makes_the_local_datasets(slurm, repo, tmp_path_factory):
    """Every job a SLURM job (the compile jobs too); the status from squeue (no accounting database)."""
    local, repo = repo, workflow_copy(tmp_path_factory, "slurm")
    partition = subprocess.run(["sinfo", "-h", "-o", "%R"], capture_output=True, text=True).stdout.split()[0]
    snakemake(repo, "--workflow-profile", "workflow/profiles/slurm", "--jobs", "8",
              "--default-resources", "slurm_account=noslipsim", f"slurm_partition={partition}", "runtime=10",
              "mem_mb=1000", "--set-threads", "galton_distribution=2",
              "--slurm-status-command", "squeue", "--slurm-init-seconds-before-status-checks", "1",
              "--slurm-keep-successful-logs", "--latency-wait", "5", *TARGETS)
    logs = repo / ".test" / ".snakemake" / "slurm_logs"
    ran = {p.name for p in logs.iterdir()} if logs.exists() else set()
    assert {"rule_galton_orbits", "rule_galton_distribution", "rule_compile_kernel"} <= ran, ran
    for target in TARGETS:
        same_dataset(repo / ".test" / target, local / ".test" / target)


def test_dask_workers_as_slurm_jobs_make_the_local_dataset(slurm, repo, tmp_path_factory):
    """``runtime={dask_cluster: slurm}`` on the command line: the ensemble's chunks run on two SLURM jobs."""
    local, repo = repo, workflow_copy(tmp_path_factory, "dask-slurm")
    target = "results/galton/distribution.nc"
    snakemake(repo, target, "--cores", "2", "--config",
              "runtime={dask_cluster: slurm, dask_workers: 2, dask_worker_memory: 1GiB, chunk_size: 50}")
    log = (repo / ".test" / "logs" / "galton_distribution.log").read_text()
    assert "with 2 worker job(s) on SLURM" in log and "(job " in log, log[-2000:]
    assert "tcp://127.0.0.1:" in log                                    # the scheduler listened on loopback
    same_dataset(repo / ".test" / target, local / ".test" / target)
    # the worker jobs ended with the ensemble
    left = subprocess.run(["squeue", "-h", "-n", "noslipsim-dask", "-t", "PD,R"], capture_output=True, text=True)
    assert left.stdout.strip() == ""
