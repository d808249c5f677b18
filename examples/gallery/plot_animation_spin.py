"""
A no-slip orbit as an animation, its spin visible
=================================================

:func:`noslipsim.animation.animate` (``noslipsim animate`` from the shell)
draws the particle as a disk whose marker turns at the angular velocity
``omega = w / (gamma R)`` of a disk of the drawn radius ``R`` (``w`` the
scaled spin, counter-clockwise positive), along the exact parabolic flights
between collisions. The frame nearest each collision is drawn at the
collision's exact time, so the ball touches the wall in that frame. The
side panel fills in the velocity portrait as the collisions happen.

First the orbit itself, with a spin marker on every flight; then the GIF.
"""
import matplotlib.pyplot as plt

import noslipsim as ns
from noslipsim import animation, plot, tables

plot.use_style()
board = tables.galton_board(spacing=2.0, radius=0.5, gravity=1.0)  # no-slip pegs under gravity
start = dict(position=(0.7, 0.3), velocity=(0.4, 0.0), spin=0.6)
orbit = ns.simulate(board, **start, max_collisions=10)

fig, ax = plt.subplots(figsize=(5, 4))
x, y = plot.orbit_path(orbit)
plot.draw_table(ax, board, plot.view_window(board, (x, y), cells=0))
plot.draw_orbit(ax, orbit, spin_every=1)
ax.set_title("10 collisions, a spin marker on every flight", fontsize="small")
plt.show()

# %%
# The same orbit, animated (the GIF below is written by this call):

out = animation.animate(board, [(start["position"], start["velocity"], start["spin"])], "spin.gif",
                        max_collisions=10, duration=4.0, fps=10, dpi=55, portrait=True)
print(f"{out['frames']} frames, {len(out['collision_frames'][0])} drawn at a collision")
