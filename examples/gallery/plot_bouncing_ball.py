"""
The bouncing ball: 2-periodic, or drifting
==========================================

A no-slip ball bouncing on a floor under gravity (the paper's Theorem 1). Its
velocities repeat every two bounces; ``v_x - gamma w`` is the same on every
flight, and the ball drifts by

.. math::

    D = \\frac{4\\,u\\,(v_x - \\gamma w)}{g\\,(1 + \\gamma^2)}

per two bounces (``u`` the vertical impact speed). So the orbit is 2-periodic
exactly when ``v_x = gamma w``; otherwise it moves back and forth (the
horizontal velocity changes sign at every bounce) or steadily one way, and
drifts. The engine's drift is compared with the closed form
:func:`noslipsim.theory.half_plane_drift`.
"""
import math

import matplotlib.pyplot as plt

import noslipsim as ns
from noslipsim import plot, tables, theory

plot.use_style()
gamma, g, height = 1 / math.sqrt(2), 1.0, 0.5
u = math.sqrt(2 * g * height)  # vertical impact speed of a ball dropped from `height`
scene = tables.half_plane(gamma=gamma, gravity=g)

cases = {
    "v_x = γw: 2-periodic": (0.5, 0.5 / gamma),
    "back and forth, drifting left": (0.5, 1.5),
    "steady drift to the right": (0.5, -0.5),
}
fig, axes = plt.subplots(len(cases), 1, figsize=(8, 4.6), sharex=True)
for ax, (title, (vx, w)) in zip(axes, cases.items()):
    orbit = ns.simulate(scene, position=(0.0, height), velocity=(vx, 0.0), spin=w, max_collisions=10)
    measured = float(orbit.x[2] - orbit.x[0])  # two bounces
    expected = theory.half_plane_drift(vx, w, u, gamma, g)
    plot.draw_table(ax, scene, window=(-4.5, 9.5, -0.15, 0.75))
    plot.draw_orbit(ax, orbit, spin_every=2, spin_radius=0.12)
    ax.set_title(f"{title}: drift per two bounces {measured:+.6f} (theory {expected:+.6f})", fontsize="small")
    print(f"{title:32s} measured D = {measured:+.15f}   theory D = {expected:+.15f}")
axes[-1].set_xlabel("x")
