"""
A 2-periodic orbit in a wedge
=============================

In a no-slip wedge under gravity, a particle launched from one wall towards
the opposite point at launch angle ``theta`` comes straight back when its
tangential velocity at the far wall equals ``gamma w`` (path reversal): after
two collisions it is where it started, with the same velocity and spin. The
start comes from :func:`noslipsim.theory.wedge_two_periodic_start`, which
implements the corrected form of the paper's Theorem 2 (speed
``sqrt(g d / sin 2 theta)``, spin ``v sin(phi - theta) / gamma`` from the left
wall of an upward wedge; see the errata page). With the paper's printed spin
the same launch does not return.
"""
import math

import matplotlib.pyplot as plt
import numpy as np

import noslipsim as ns
from noslipsim import plot, tables, theory

plot.use_style()
phi, theta, ell, gamma = 0.6, 0.9, 2.0, 1 / math.sqrt(2)
scene = tables.wedge(phi, gamma=gamma)                    # force (0, -1)
q, v, w = theory.wedge_two_periodic_start(phi, theta, ell, gamma)

# the launch point lies on the wall: start a moment later along the flight, strictly inside
dt = 1e-3
a = np.array(scene.force)
start = q + v * dt + 0.5 * a * dt**2, v + a * dt

fig, axes = plt.subplots(1, 2, figsize=(8, 3.6), sharey=True)
printed_w = np.hypot(*v) * math.sin(theta - phi) / gamma  # the spin the paper prints
for ax, (title, spin) in zip(axes, [("corrected spin: 2-periodic", w), ("printed spin: not periodic", printed_w)]):
    orbit = ns.simulate(scene, start[0], start[1], spin, max_collisions=6)
    plot.draw_table(ax, scene, window=(-2.6, 2.6, -0.2, 3.0))
    plot.draw_orbit(ax, orbit, spin_every=1, spin_radius=0.1)
    gap = np.hypot(float(orbit.x[2] - orbit.x[0]), float(orbit.y[2] - orbit.y[0]))
    ax.set_title(f"{title}\n|q2 - q0| = {gap:.1e}", fontsize="small")
    print(f"{title:28s} collision 0 at ({float(orbit.x[0]):+.12f}, {float(orbit.y[0]):.12f}), "
          f"collision 2 at ({float(orbit.x[2]):+.12f}, {float(orbit.y[2]):.12f})")
