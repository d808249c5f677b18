"""Running the figure pipeline in a temporary copy of the repository (test_pipeline.py, test_slurm.py)."""
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: What the workflow needs from the repository (the package itself is installed).
WORKFLOW_FILES = ["Snakefile", "workflow", "config", ".test/config"]


def snakemake(repo, *args, check=True):
    """Run snakemake on the reduced config in ``repo`` (the test session's numba cache); returns the
    completed process."""
    cmd = [sys.executable, "-m", "snakemake", "--directory", ".test", *args]
    proc = subprocess.run(cmd, cwd=repo, capture_output=True, text=True)
    if check and proc.returncode != 0:
        raise AssertionError(f"{' '.join(cmd[2:])} failed ({proc.returncode}):\n{proc.stdout[-4000:]}\n"
                             f"{proc.stderr[-6000:]}")
    return proc


def workflow_copy(tmp_path_factory, name):
    """A fresh copy of the workflow in a new temporary folder ``name``."""
    return copy_workflow(tmp_path_factory.mktemp(name))


def copy_workflow(repo):
    """Copy what the workflow needs into the folder ``repo``; returns it."""
    repo.mkdir(parents=True, exist_ok=True)
    for item in WORKFLOW_FILES:
        src, dst = ROOT / item, repo / item
        if src.is_dir():
            shutil.copytree(src, dst)
        else:
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst)
    return repo
