"""One look for every figure: the style file and the colours of the two laws."""
from __future__ import annotations

from pathlib import Path

import matplotlib

#: The project's matplotlib style file (fonts, sizes, colour cycle, layout, PNG resolution).
STYLE = Path(__file__).with_name("noslipsim.mplstyle")

#: Colour of each collision law, the same in every figure.
LAW_COLORS = {"specular": "#0072B2", "no-slip": "#D55E00"}

#: Colours of tables: walls and scatterers.
WALL_COLOR = "0.25"
SCATTERER_COLOR = "0.75"


def use_style():
    """Apply the project's style (:data:`STYLE`) to every figure made afterwards in this process."""
    matplotlib.style.use(STYLE)


def style_context():
    """Context manager applying the project's style inside a ``with`` block only."""
    return matplotlib.style.context(STYLE)


def law_color(law):
    """The colour of a collision law (``'specular'`` or ``'no-slip'``).

    Raises
    ------
    ValueError
        For an unknown law.
    """
    if law not in LAW_COLORS:
        raise ValueError(f"law: expected one of {sorted(LAW_COLORS)}, got {law!r}")
    return LAW_COLORS[law]
