"""
Specular against no-slip in a Sinai box
=======================================

The unit square with a disk scatterer, no force, the same start under both
laws. The specular particle keeps its tangential velocity and spin at every
wall (and has no spin to keep); the no-slip particle trades tangential
velocity with spin at every collision, so its path bends differently at the
walls and it spins (arrows: the particle drawn every few flights, turning the
way it spins). Both conserve ``|v|^2 + w^2``: the no-slip speed ``|v|`` alone
changes from flight to flight.
"""
import matplotlib.pyplot as plt
import numpy as np

import noslipsim as ns
from noslipsim import plot

plot.use_style()
scene = ns.Scene.from_dict({
    "law": "no-slip",
    "gamma": 2 ** -0.5,
    "elements": [
        {"type": "segment", "p0": [0, 0], "p1": [1, 0]},
        {"type": "segment", "p0": [1, 0], "p1": [1, 1]},
        {"type": "segment", "p0": [1, 1], "p1": [0, 1]},
        {"type": "segment", "p0": [0, 1], "p1": [0, 0]},
        {"type": "circle", "center": [0.5, 0.5], "radius": 0.25, "side": "outside"},
    ],
})
fig, axes = plt.subplots(1, 2, figsize=(8, 4.2))
for ax, law in zip(axes, ["specular", "no-slip"]):
    orbit = ns.simulate(scene.replace(law=law), position=(0.1, 0.2), velocity=(0.8, 0.6), max_collisions=12)
    plot.draw_table(ax, orbit)  # the dataset carries its scene
    plot.draw_orbit(ax, orbit, spin_every=3, spin_radius=0.035)
    speed = np.hypot(orbit.vx, orbit.vy)
    ax.set_title(f"{law}: |v| from {float(speed.min()):.2f} to {float(speed.max()):.2f}", fontsize="small")
    print(f"{law:9s} elements hit {orbit.element.values.tolist()}; "
          f"energy spread {float(orbit.energy.max() - orbit.energy.min()):.1e}")
