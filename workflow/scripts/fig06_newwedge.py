"""Figure 6: (left) a wedge of half-angle phi under gravity, launch angle theta, q0, q1 and the 2-periodic flight;
(right) the tangential wedge of two boundary points q0, q1 of a two-disk table and its flight."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from noslipsim import plot

ds = plot.load_figure_data(snakemake.input.newwedge)
plot.use_style()
fig, axes = plt.subplots(1, 2, figsize=(6.5, 2.9), width_ratios=[1.0, 1.5])
for ax, i in zip(axes, range(ds.sizes["orbit"])):
    o = ds.isel(orbit=i)
    q0, q1 = (float(o.q0_x), float(o.q0_y)), (float(o.q1_x), float(o.q1_y))
    vertex, phi, theta = (float(o.vertex_x), float(o.vertex_y)), float(o.phi), float(o.theta)
    x, y = plot.orbit_path(o)
    size = max(y.max() - vertex[1], q1[0] - q0[0])                      # the picture's scale
    x0, x1, y0, y1 = -0.75 * size, 0.75 * size, vertex[1] - 0.03 * size, y.max() + 0.35 * size
    try:                                                                 # show a bounded table whole
        b = plot.auto_window(plot.scene_of(o))
        x0, x1, y0, y1 = min(x0, b[0]), max(x1, b[1]), min(y0, b[2]), max(y1, b[3])
    except ValueError:                                                   # the wedge's walls are infinite
        pass
    plot.draw_table(ax, o, (x0, x1, y0, y1))
    for q in (q0, q1):                                                   # the (tangential) wedge's walls
        plot.draw_ray(ax, vertex, q, beyond=(y1 - vertex[1]) / (q[1] - vertex[1]) - 1)
    ax.plot([vertex[0], vertex[0]], [vertex[1], y1], color="0.5", linewidth=0.5, linestyle=":")
    ax.plot([q0[0], q1[0]], [q0[1], q1[1]], color="0.5", linewidth=0.5, linestyle=":")
    plot.draw_orbit(ax, o, color=plot.law_color("no-slip"), linewidth=1.0, ends=False, zorder=4)
    plot.draw_angle(ax, vertex, math.pi / 2, math.pi / 2 + phi, 0.25 * size, r"$\varphi$")
    plot.draw_angle(ax, q0, 0.0, theta, 0.18 * size, r"$\theta$", label_distance=1.5)
    apex = (vertex[0], y.max())
    for q, name in ((q0, r"$\mathbf{q}_0$"), (q1, r"$\mathbf{q}_1$")):   # beside its wall or tangent, not across
        offset, ha, va = plot.ray_label_offset(vertex, q, apex)
        plot.label_point(ax, q, name, offset=offset, ha=ha, va=va)
    fx, fy = plot.scene_of(o).force
    if fx or fy:                                                         # the force's arrow, above the apex
        gx, gy, f = 0.12 * size, y.max() + 0.32 * size, math.hypot(fx, fy)
        tip = (gx + 0.25 * size * fx / f, gy + 0.25 * size * fy / f)
        ax.annotate("", xy=tip, xytext=(gx, gy), arrowprops=dict(arrowstyle="-|>", color="k"))
        ax.text(max(gx, tip[0]) + 0.04 * size, 0.5 * (gy + tip[1]), r"$\mathbf{g}$", va="center")
    ax.set_title("wedge" if str(o.role.values) == "wedge" else "tangential wedge on a two-disk table")
    ax.set_axis_off()
fig.align_titles()
plot.save_figure(fig, snakemake.output.pdf)
