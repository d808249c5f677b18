"""The code keeps the house style: ruff (configured in pyproject.toml) reports nothing."""
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_ruff_reports_no_finding():
    ruff = shutil.which("ruff") or str(Path(sys.executable).with_name("ruff"))
    proc = subprocess.run([ruff, "check", "--no-cache", "--output-format", "concise", "."], cwd=ROOT,
                          capture_output=True, text=True)
    assert proc.returncode == 0, f"ruff findings (fix them, or say in pyproject why a rule does not apply):\n" \
                                 f"{proc.stdout[-4000:]}{proc.stderr[-2000:]}"


#: Every function of the compiled core keeps McCabe complexity <= 15 (issue 32: small named steps; ruff counts a
#: closure into the factory that defines it, so each factory holds one small kernel).
SIMPLE_CORE = ["src/noslipsim/core"]


def test_core_functions_are_small():
    ruff = shutil.which("ruff") or str(Path(sys.executable).with_name("ruff"))
    proc = subprocess.run([ruff, "check", "--no-cache", "--output-format", "concise", "--select", "C901",
                           "--config", "lint.mccabe.max-complexity=15", *SIMPLE_CORE], cwd=ROOT,
                          capture_output=True, text=True)
    assert proc.returncode == 0, f"functions too complex (split them into named steps):\n{proc.stdout[-4000:]}"
