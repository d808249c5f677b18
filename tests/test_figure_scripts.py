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


def test_figure_10_draws_its_reduced_sea_at_the_default_opacity():
    """Figure 10(b) passed sea_alpha=0.06: at print size the chaotic sea was too pale to see."""
    source = (SCRIPTS / "fig10_phaseportraits.py").read_text(encoding="utf-8")
    assert "draw_reduced_portrait(" in source and "sea_alpha" not in source


def test_figure_12_draws_its_title_shares_beside_the_curve():
    """The panel titles' shares (the portraits' own orbits) differed from the curve below without a word;
    they are drawn on the curve's panel, with their binomial errors and their own legend entry."""
    source = (SCRIPTS / "fig12_lorentzgamma.py").read_text(encoding="utf-8")
    assert 'shares = ds.regular.mean("orbit")' in source and "ax.errorbar(ds.gamma, shares" in source
    assert "regular {float(case.regular.mean()):.1%}" in source     # the same quantity in the titles


def test_figure_7_keys_its_colours_and_draws_the_force():
    """Figure 7 coloured its launch angles without a key, and its caption's force arrow was not drawn."""
    source = (SCRIPTS / "fig07_wedge.py").read_text(encoding="utf-8")
    assert "plot.draw_force_arrow(" in source
    assert "plot.frame_legend(" in source and 'label=f"{float(o.theta):g}"' in source
