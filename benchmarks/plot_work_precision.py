"""Draw the work-precision diagram from ``benchmarks/results/work_precision.csv``.

One panel per scene: x = error per collision (median over found flights, bar to the
maximum; log), y = seconds per collision (log).  noslipsim is a star; scipy's RK45
circles and DOP853 squares, coloured by ``max_step``, open for ``rtol = 1e-3`` up to
filled for ``1e-12``.  The upper-left notes give the missed shares per max_step and method (range over rtol).
Writes ``work_precision.png`` and ``.pdf`` beside the CSV with no dates in their
metadata (byte-stable).  Run: ``python benchmarks/plot_work_precision.py [CSV]``.
"""
from __future__ import annotations

import argparse
import csv
import os
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.lines import Line2D

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_CSV = os.path.join(HERE, "results", "work_precision.csv")
#: Errors below this (exact zeros included) are drawn on the axis floor.
ERROR_FLOOR = 1e-18
STEP_COLOURS = {"inf": "tab:red", "0.1": "tab:orange", "0.01": "tab:blue"}
SCENE_TITLES = {"pentagon": "irregular pentagon, no force", "sinai": "Sinai box, no force",
                "galton": "Galton box, gravity (plain scene)"}


def read_rows(path):
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    for r in rows:
        for k in ("seconds_per_collision", "median_error", "max_error", "missed_share"):
            r[k] = float(r[k])
        for k in ("n_flights", "n_missed"):
            r[k] = int(r[k])
    return rows


def _scipy_style(setting):
    m = re.match(r"(\S+) rtol=(\S+) max_step=(\S+)", setting)
    method, rtol, step = m.group(1), float(m.group(2)), m.group(3)
    fill = {1e-3: 0.0, 1e-6: 0.35, 1e-9: 0.7, 1e-12: 1.0}.get(rtol, 1.0)
    return method, rtol, step, fill


def _pct(share):
    p = 100 * share
    return "0" if p == 0 else f"{p:.1f}" if p < 10 else f"{p:.0f}"


def _share_range(shares):
    lo, hi = _pct(min(shares)), _pct(max(shares))
    return f"{lo}%" if lo == hi else f"{lo}–{hi}%"


def draw(rows, out_base):
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    fig, axes = plt.subplots(1, len(scenes), figsize=(5.0 * len(scenes), 4.6), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        sel = [r for r in rows if r["scene"] == scene]
        groups = {}  # max_step -> method -> [(x, y, missed share)]
        for r in sel:
            x = max(r["median_error"], ERROR_FLOOR) if r["median_error"] == r["median_error"] else ERROR_FLOOR
            x_max = max(r["max_error"], ERROR_FLOOR) if r["max_error"] == r["max_error"] else ERROR_FLOOR
            y = r["seconds_per_collision"]
            if r["method"] == "noslipsim":
                orbit = r["setting"].startswith("float64 orbit")
                ax.errorbar([x], [y], xerr=[[0.0], [x_max - x]], fmt="*", ms=16 if orbit else 12,
                            mfc="black" if orbit else "white", mec="black", ecolor="black", capsize=2, zorder=5)
                ax.annotate("noslipsim orbit" if orbit else "noslipsim restart API", (x, y),
                            textcoords="offset points", xytext=(8, 7), fontsize=7)
                continue
            method, _rtol, step, fill = _scipy_style(r["setting"])
            colour = STEP_COLOURS.get(step, "tab:gray")
            marker = "o" if method == "RK45" else "s"
            face = matplotlib.colors.to_rgba(colour, fill) if fill > 0 else "white"
            ax.errorbar([x], [y], xerr=[[0.0], [x_max - x]], fmt=marker, ms=6, mfc=face, mec=colour,
                        ecolor=colour, elinewidth=0.6, capsize=1.5, alpha=0.9, zorder=3)
            groups.setdefault(step, {}).setdefault(method, []).append((x, y, r["missed_share"]))
        # missed shares, one line per max_step (range over rtol), in the empty upper-left corner
        ours = [r for r in sel if r["method"] == "noslipsim"]
        notes = [(f"noslipsim: {_share_range([r['missed_share'] for r in ours])} missed", "black")] if ours else []
        for step, by_method in groups.items():
            text = ", ".join(f"{m} {_share_range([p[2] for p in v])}" for m, v in by_method.items())
            notes.append((f"max_step={step}: {text} missed", STEP_COLOURS.get(step, "tab:gray")))
        for i, (text, colour) in enumerate(notes):
            ax.text(0.02, 0.97 - 0.065 * i, text, transform=ax.transAxes, fontsize=7, color=colour, va="top")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("position error per collision / scene scale")
        ax.set_title(SCENE_TITLES.get(scene, scene), fontsize=10)
        ax.grid(True, which="major", lw=0.3, alpha=0.5)
        lo, hi = ax.get_xlim()
        ax.set_xlim(min(lo, ERROR_FLOOR / 3), max(hi, 1e-11))
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, hi * 100)  # room for the missed-share notes
        ax.axvline(1e-12, color="gray", lw=0.8, ls="--")
        ax.text(1e-12, ax.get_ylim()[1], "1e-12 target ", fontsize=6.5, color="gray", va="top", ha="right",
                rotation=90)
    axes[0][0].set_ylabel("seconds per collision (wall)")
    handles = [
        Line2D([], [], marker="*", ls="", ms=12, mfc="black", mec="black", label="noslipsim orbit (simulate)"),
        Line2D([], [], marker="*", ls="", ms=10, mfc="white", mec="black", label="noslipsim restart API"),
        Line2D([], [], marker="o", ls="", mfc="gray", mec="gray", label="scipy RK45"),
        Line2D([], [], marker="s", ls="", mfc="gray", mec="gray", label="scipy DOP853"),
    ] + [Line2D([], [], marker="o", ls="", mfc=c, mec=c, label=f"max_step={s}") for s, c in STEP_COLOURS.items()] + [
        Line2D([], [], marker="o", ls="", mfc="white", mec="gray", label="rtol=1e-3 (open) … 1e-12 (filled)")]
    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=7.5, frameon=False)
    fig.suptitle("Work-precision per collision (restarted from a 40-digit reference; marker = median, bar to max)",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0.1, 1, 0.95))
    fig.savefig(out_base + ".png", dpi=150, metadata={"Software": None})
    fig.savefig(out_base + ".pdf", metadata={"CreationDate": None, "Producer": None, "Creator": None})
    plt.close(fig)
    return out_base + ".png", out_base + ".pdf"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("csv", nargs="?", default=DEFAULT_CSV)
    parser.add_argument("--out", default=None, help="output path without extension (default: beside the CSV)")
    args = parser.parse_args(argv)
    out = args.out or os.path.join(os.path.dirname(os.path.abspath(args.csv)), "work_precision")
    for path in draw(read_rows(args.csv), out):
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
