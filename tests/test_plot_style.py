"""The shared figure style: law colours, series colours, equal panels, framed legends."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.colors import to_hex

from noslipsim import plot
from noslipsim.plot import style


def test_law_colours_are_fixed_and_unknown_law_is_refused():
    assert plot.law_color("specular") == "#0072B2" and plot.law_color("no-slip") == "#D55E00"
    with pytest.raises(ValueError, match="law"):
        plot.law_color("slip")


def test_colour_cycle_is_the_series_colours_and_holds_no_law_colour():
    with plot.style_context():
        cycle = [to_hex(c["color"]) for c in matplotlib.rcParams["axes.prop_cycle"]]
        assert matplotlib.rcParams["legend.frameon"]
    assert cycle == [to_hex(c) for c in plot.SERIES_COLORS]
    laws = {to_hex(c) for c in plot.LAW_COLORS.values()}
    assert laws.isdisjoint(cycle)


def test_orbit_colors_live_in_style_and_phase_reexports_them():
    from noslipsim.plot import phase
    assert phase.orbit_colors is style.orbit_colors and phase.SEA_COLOR == style.SEA_COLOR


def test_equal_panels_gives_equal_boxes_and_aligned_titles():
    with plot.style_context():
        fig, axes = plt.subplots(1, 3, figsize=(6, 2.5))
        for ax, (w, h) in zip(axes, [(1.0, 1.0), (2.0, 0.5), (0.5, 1.5)]):
            ax.plot([0, w], [0, h])
            ax.set_xlim(0, w)
            ax.set_ylim(0, h)
            ax.set_aspect("equal")
            ax.set_title("t")
        windows = plot.equal_panels(axes, margin=0.0)
        assert {(x1 - x0, y1 - y0) for x0, x1, y0, y1 in windows} == {(2.0, 1.5)}
        fig.canvas.draw()
        boxes = [ax.get_position() for ax in axes]
        assert np.allclose([b.width for b in boxes], boxes[0].width)
        assert np.allclose([b.y1 for b in boxes], boxes[0].y1)
        tops = [ax.title.get_window_extent().y0 for ax in axes]
        assert np.allclose(tops, tops[0])
        assert axes[1].get_xlim() == (0.0, 2.0) and axes[2].get_xlim() == (-0.75, 1.25)   # centred on content
        plt.close(fig)


def test_equal_windows_keep_each_scale_and_share_one_shape():
    windows = [(0, 1, 0, 1), (0, 4, 0, 1), (-1, 1, 0, 3)]
    out = plot.equal_windows(windows)
    assert [(x1 - x0, y1 - y0) for x0, x1, y0, y1 in out] == [(1.0, 1.5), (4.0, 6.0), (2.0, 3.0)]
    for (a0, a1, b0, b1), (x0, x1, y0, y1) in zip(windows, out):    # centred, content kept
        assert x0 <= a0 and x1 >= a1 and y0 <= b0 and y1 >= b1 and x0 + x1 == a0 + a1 and y0 + y1 == b0 + b1
    assert plot.equal_windows(windows, aspect=0.25)[0] == (-1.5, 2.5, 0.0, 1.0)


@pytest.mark.parametrize(("kwargs", "match"), [({"margin": -0.1}, "margin"), ({"margin": float("nan")}, "margin"),
                                               ({"aspect": 0.0}, "aspect")])
def test_equal_panels_refuses_bad_input(kwargs, match):
    fig, ax = plt.subplots()
    with pytest.raises(ValueError, match=match):
        plot.equal_panels([ax], **kwargs) if "margin" in kwargs else plot.equal_windows([(0, 1, 0, 1)], **kwargs)
    with pytest.raises(ValueError, match="x0 < x1"):
        plot.equal_windows([(1, 0, 0, 1)])
    with pytest.raises(ValueError, match="axes"):
        plot.equal_panels([])
    plt.close(fig)


def test_frame_legend_is_framed_and_outside_the_data():
    with plot.style_context():
        fig, ax = plt.subplots(figsize=(4, 3))
        ax.plot(np.linspace(0, 1, 50), np.linspace(0, 1, 50), label="a")
        ax.plot([0, 1], [1, 0], label="b")
        for side in ("below", "right"):
            leg = plot.frame_legend(ax, outside=side)
            fig.canvas.draw()
            assert leg.get_frame_on()
            box, axbox = leg.get_window_extent(), ax.get_window_extent()
            assert box.y1 <= axbox.y0 + 1 if side == "below" else box.x0 >= axbox.x1 - 1
        with pytest.raises(ValueError, match="outside"):
            plot.frame_legend(ax, outside="above")
        empty = fig.add_subplot(2, 2, 4)
        with pytest.raises(ValueError, match="no labelled"):
            plot.frame_legend(empty)
        plt.close(fig)


def test_a_legend_over_a_line_or_on_a_spine_is_found_and_refused():
    with plot.style_context():
        fig, ax = plt.subplots(figsize=(4, 3))
        ax.plot([0, 1], [0.95, 0.95], label="top")        # runs under an upper legend, no vertex inside it
        ax.plot([0, 1], [0.0, 0.1], label="bottom")
        ax.set_ylim(-0.1, 1.0)
        ax.legend(loc="upper center")
        assert plot.legend_problems(ax) == ["covers top"]
        with pytest.raises(ValueError, match="covers top"):
            plot.check_legend(ax)
        ax.legend(loc="center", bbox_to_anchor=(0.0, 0.5))   # half outside: on the left spine
        assert plot.legend_problems(ax) == ["straddles the spine"]
        ax.legend(loc="center")
        assert plot.legend_problems(ax) == []
        plot.frame_legend(ax, outside="right")
        assert plot.legend_problems(ax) == []
        ax.get_legend().remove()
        with pytest.raises(ValueError, match="no legend"):
            plot.legend_problems(ax)
        plt.close(fig)


def test_no_figure_script_paints_a_series_in_a_law_colour():
    """Law colours come from ``law_color`` only: a hex literal of one in a figure script is a series (Figure 14
    drew its launch angles in both) that a reader would take for a law."""
    from pathlib import Path

    scripts = sorted((Path(__file__).resolve().parents[1] / "workflow" / "scripts").glob("fig*.py"))
    assert scripts
    for script in scripts:
        text = script.read_text(encoding="utf-8").lower()
        assert not [c for c in plot.LAW_COLORS.values() if c.lower() in text], script.name
