"""Regenerate the pinned workflow environment: requirements.lock and the pins of noslipsim.yaml.

    python workflow/envs/lock.py

Installs noslipsim with its workflow extra into a fresh virtual environment,
records every package's exact version (``pip freeze``) in
``workflow/envs/requirements.lock`` and copies the same pins into the pip
section of ``workflow/envs/noslipsim.yaml`` (the conda environment of every
rule under ``--software-deployment-method conda``), with the Python version
of the interpreter that ran this script.  Run it after changing a dependency;
the pinned versions are the ones under which the committed figures and
numbers are bitwise reproducible (README, "Reproducing the numbers").
"""
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
HEADER = """# Exact versions of the workflow environment (noslipsim[workflow] and everything it pulls in),
# made by `python workflow/envs/lock.py` with Python {python} on {machine}.
# pip: pip install -r workflow/envs/requirements.lock -e ".[workflow]"
"""
CONDA = """# The software of every rule: Python and noslipsim installed from this repository, every package at
# the exact version of requirements.lock (made by `python workflow/envs/lock.py`; do not edit the pins
# by hand).  Used with `snakemake --software-deployment-method conda`; a plain `snakemake` runs in the
# current environment (README: `pip install -r workflow/envs/requirements.lock -e ".[workflow]"`).
channels:
  - conda-forge
dependencies:
  - python={python}
  - pip
  - pip:
{pins}
      - "../.."
"""


def main():
    with tempfile.TemporaryDirectory() as tmp:
        venv = Path(tmp) / "venv"
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
        pip = [str(venv / "bin" / "python"), "-m", "pip"]
        subprocess.run([*pip, "install", "--quiet", f"{ROOT}[workflow]"], check=True)
        frozen = subprocess.run([*pip, "freeze", "--exclude-editable"], check=True, capture_output=True,
                                text=True).stdout.splitlines()
    pins = sorted((line for line in frozen if line and not line.lower().startswith("noslipsim")), key=str.lower)
    python = platform.python_version()
    (HERE / "requirements.lock").write_text(HEADER.format(python=python, machine=platform.machine())
                                            + "\n".join(pins) + "\n")
    (HERE / "noslipsim.yaml").write_text(CONDA.format(python=python,
                                                      pins="\n".join(f'      - "{p}"' for p in pins)))
    print(f"{len(pins)} packages pinned (Python {python})")


if __name__ == "__main__":
    main()
