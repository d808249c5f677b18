"""Every dataset says which software made it; the workflow environment is pinned (README, "Reproducing")."""
import json
import re
import subprocess
from importlib import metadata
from pathlib import Path

import numpy as np
import xarray as xr

from noslipsim import open_dataset, write_dataset
from noslipsim.io import SOFTWARE, provenance

ROOT = Path(__file__).resolve().parents[1]
ENVS = ROOT / "workflow" / "envs"


def test_datasets_record_the_software_and_the_commit(tmp_path):
    path = tmp_path / "d.nc"
    write_dataset(xr.Dataset({"t": ("collision", np.arange(3.0))}), path, config={"a": 1})
    attrs = open_dataset(path).attrs
    software = json.loads(attrs["software"])
    for name in SOFTWARE:
        assert software[name] == metadata.version(name)
    assert re.fullmatch(r"\d+\.\d+\.\d+", software["python"])
    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True)
    if head.returncode == 0:  # a checkout (CI's fresh clone is one)
        assert attrs["git_commit"] == head.stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                               capture_output=True, text=True).stdout.strip() != ""
        assert attrs["git_dirty"] == int(dirty)
    else:
        assert attrs["git_commit"] == "" and attrs["git_dirty"] == -1
    assert provenance()["software"] == attrs["software"]


def _pins(lines):
    return sorted(line.strip().strip('"').lstrip("- ").strip('"') for line in lines)


def test_the_conda_environment_pins_exactly_the_lock():
    lock = [line for line in (ENVS / "requirements.lock").read_text().splitlines()
            if line and not line.startswith("#")]
    conda = [line for line in (ENVS / "noslipsim.yaml").read_text().splitlines() if "==" in line]
    assert _pins(lock) == _pins(conda) and len(lock) > 20
    pinned = {line.split("==")[0].lower() for line in lock}
    assert {name.lower() for name in SOFTWARE} <= pinned  # the packages that decide the last bits
    assert re.search(r"python=\d+\.\d+\.\d+", (ENVS / "noslipsim.yaml").read_text())
