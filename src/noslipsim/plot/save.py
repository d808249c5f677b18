"""Save a figure as PDF and PNG, byte for byte the same on every run.

matplotlib stamps a creation date and its version into PDFs and its version
into PNGs; both are removed, so a rerun of a figure script on the same inputs
(and the same matplotlib and fonts) writes identical bytes and a changed file
always means a changed figure.
"""
from __future__ import annotations

import os
from pathlib import Path

import matplotlib.pyplot as plt

from .checks import check_panels

#: Metadata entries removed from each format (``None`` deletes an entry matplotlib would add).
PDF_METADATA = {"Creator": None, "Producer": None, "CreationDate": None, "ModDate": None}
PNG_METADATA = {"Software": None}


def save_figure(fig, path_stem, *, dpi=None, close=True):
    """Write ``fig`` to ``path_stem + '.pdf'`` and ``path_stem + '.png'`` without dates or software stamps.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    path_stem : str or os.PathLike
        Path without extension (``figures/fig03_normal``); a ``.pdf`` or
        ``.png`` suffix is dropped.  Missing folders are created.
    dpi : float, optional
        PNG resolution (default: the style's ``savefig.dpi``).
    close : bool
        Close the figure afterwards (figure scripts make one figure each).

    Returns
    -------
    (pathlib.Path, pathlib.Path)
        The PDF and PNG written.

    Raises
    ------
    TypeError
        If ``fig`` is not a matplotlib Figure.
    ValueError
        For an empty path.
    EmptyFigureError
        A panel of ``fig`` shows no data (:func:`~noslipsim.plot.checks.check_panels`).
    """
    from matplotlib.figure import Figure

    if not isinstance(fig, Figure):
        raise TypeError(f"fig: expected a matplotlib Figure, got {type(fig).__name__}")
    stem = Path(os.fspath(path_stem))
    if stem.suffix in (".pdf", ".png"):
        stem = stem.with_suffix("")
    if not stem.name:
        raise ValueError(f"path_stem: expected a file path without extension, got {path_stem!r}")
    check_panels(fig)
    stem.parent.mkdir(parents=True, exist_ok=True)
    pdf, png = stem.with_name(stem.name + ".pdf"), stem.with_name(stem.name + ".png")
    fig.savefig(pdf, format="pdf", metadata=PDF_METADATA)
    fig.savefig(png, format="png", metadata=PNG_METADATA, **({} if dpi is None else {"dpi": dpi}))
    if close:
        plt.close(fig)
    return pdf, png
