"""noslipsim.plot.phase: one colour per orbit, the sea under the islands, Birkhoff and the 3D reduced portrait."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from matplotlib.colors import to_rgba

from noslipsim import plot
from noslipsim.plot.phase import SEA_COLOR


def portrait(n_orbits=4, n_points=10, seed=0):
    """A synthetic portrait case: points on the unit disk, the last two points of orbit 0 padding."""
    rng = np.random.default_rng(seed)
    r = np.sqrt(rng.uniform(0, 1, (n_orbits, n_points)))
    a = rng.uniform(0, 2 * np.pi, (n_orbits, n_points))
    vt, w = r * np.cos(a), r * np.sin(a)
    vt[0, -2:] = w[0, -2:] = np.nan
    s = rng.uniform(0, 2.0, (n_orbits, n_points))
    s[0, -2:] = np.nan
    p = np.where(np.isfinite(vt), vt, np.nan)
    dims = ("orbit", "point")
    return xr.Dataset({"vt_unit": (dims, vt), "w_unit": (dims, w), "s_boundary": (dims, s), "sin_angle": (dims, p),
                       "boundary_length": ((), 2.0)})


def test_orbit_colors_are_distinct_and_stable():
    c = plot.orbit_colors(60)
    assert c.shape == (60, 4) and len({tuple(x) for x in c}) == 60
    assert np.array_equal(plot.orbit_colors(5), c[:5]) and np.array_equal(plot.orbit_colors(61)[60], c[0])
    assert plot.orbit_colors(0).shape == (0, 4)
    for bad in (-1, 2.5, True):
        with pytest.raises(ValueError, match="n"):
            plot.orbit_colors(bad)


def test_layered_portrait_draws_the_sea_grey_under_the_regular_orbits(ax):
    ds = portrait()
    out = plot.draw_layered_portrait(ax, ds, [False, True, False, True])
    sea, top = out["sea"], out["regular"]
    assert len(sea.get_offsets()) == 8 + 10 and len(top.get_offsets()) == 20     # orbit 0 has 8 points
    assert np.allclose(sea.get_facecolors(), to_rgba(SEA_COLOR))
    assert top.get_zorder() > sea.get_zorder()
    colors = {tuple(c) for c in top.get_facecolors()}
    assert len(colors) == 2 and to_rgba(SEA_COLOR) not in colors                  # one colour per regular orbit
    assert ax.get_aspect() == 1.0


def test_layered_portrait_without_flags_gives_every_orbit_its_colour(ax):
    out = plot.draw_layered_portrait(ax, portrait())
    assert out["sea"] is None and len(out["regular"].get_offsets()) == 38
    assert len({tuple(c) for c in out["regular"].get_facecolors()}) == 4


def test_layered_portrait_refuses_bad_flags_and_points_off_the_disk(ax):
    with pytest.raises(ValueError, match="one flag per orbit"):
        plot.draw_layered_portrait(ax, portrait(), [True, False])
    bad = portrait()
    bad["w_unit"] = bad.w_unit + 2
    with pytest.raises(ValueError, match="unit disk"):
        plot.draw_layered_portrait(ax, bad)


def test_birkhoff_spans_the_boundary_and_puts_the_sea_first(ax):
    ds = portrait()
    pts = plot.draw_birkhoff(ax, ds, [True, False, False, False])
    assert ax.get_xlim() == (0.0, 2.0) and ax.get_ylim() == (-1.0, 1.0)
    colors = pts.get_facecolors()
    assert len(colors) == 38 and np.allclose(colors[:30], to_rgba(SEA_COLOR))   # orbit 0 (regular) drawn last
    assert not np.allclose(colors[-1], to_rgba(SEA_COLOR))
    bad = ds.copy()
    bad["sin_angle"] = bad.sin_angle * 3
    with pytest.raises(ValueError, match="sin_angle"):
        plot.draw_birkhoff(ax, bad)
    with pytest.raises(ValueError, match="s_boundary"):
        plot.draw_birkhoff(ax, ds.drop_vars("s_boundary"))


def test_reduced_portrait_is_a_cylinder_in_3d():
    fig = plt.figure()
    ax3 = fig.add_subplot(projection="3d")
    out = plot.draw_reduced_portrait(ax3, portrait(), [False, True, True, False])
    # faint enough for the islands to show through, dark enough to be seen: at 0.06 Figure 10(b)'s sea vanished
    assert 0.25 <= out["sea"].get_alpha() < 1 and len(out["regular"].get_offsets()) == 20
    assert ax3.get_xlim() == (0.0, 2.0) and len(ax3.lines) == 6                 # two end circles, four generators
    ax2 = fig.add_subplot(2, 2, 4)
    with pytest.raises(ValueError, match="3D"):
        plot.draw_reduced_portrait(ax2, portrait())
    plt.close(fig)
