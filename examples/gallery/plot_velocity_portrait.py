"""
A velocity portrait
===================

At each collision the post-collision unit vector ``(w, v_t, v_n)/|(w, v_t, v_n)|``
is recorded and projected onto the disk ``(v_t, w)`` (the paper's velocity phase
portraits). In a no-slip regular polygon without force the portrait of one
orbit stays on a curve or a small set of points, not filling the disk: here
twelve orbits of a hexagon (one colour each) from starts uniform in the
reduced phase space (:func:`noslipsim.initial.boundary_states`).
"""
import matplotlib.pyplot as plt

from noslipsim import experiments, plot, tables

plot.use_style()
fig, axes = plt.subplots(1, 2, figsize=(8, 4))
for ax, n in zip(axes, [4, 6]):
    scene = tables.regular_polygon(n)
    portrait = experiments.phase_portrait(scene, n_orbits=12, n_collisions=1500, seed=3, progress=False)
    plot.draw_portrait(ax, portrait, size=0.6)
    ax.set_title(f"no-slip regular {n}-gon, γ = 1/√2", fontsize="small")
    print(f"{n}-gon: {int(portrait.n_points.sum())} points")
