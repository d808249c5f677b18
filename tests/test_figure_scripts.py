"""What a figure script prints agrees with the prose that quotes the same number (read from the script's source:
the scripts run only inside Snakemake, on paper-size datasets)."""
import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = ROOT / "workflow" / "scripts"


@pytest.fixture(scope="module")
def committed():
    return json.loads((ROOT / "figures" / "numbers.json").read_text(encoding="utf-8"))


@pytest.mark.parametrize("variable, record", [("exit_from_vertical", "specular_exit_from_vertical"),
                                              ("exit_to_corner", "noslip_exit_to_corner")])
def test_figure_1_prints_its_angles_to_the_digits_the_docs_quote(variable, record, committed):
    """Figure 1 printed 3° and 4° under its panels while docs/figures.md quotes 2.5° and 3.9°."""
    source = (SCRIPTS / "fig01_specnoslip.py").read_text(encoding="utf-8")
    printed = re.findall(rf"orbit\.{variable}\):(\.\d+f)\}}°", source)
    assert printed == [committed["orbits"][record]["format"]]
