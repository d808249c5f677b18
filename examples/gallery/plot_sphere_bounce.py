"""
A rough sphere bouncing in 3D
=============================

A no-slip ball (a uniform ball, ``gamma = sqrt(2/5)``) bouncing on the plane
``z = 0`` under gravity (the paper's 3D bouncing figure). The tangential part
of ``v_T - gamma n x W_T`` is the same on every flight and the ball drifts by
``4 u (v_T - gamma n x W_T) / (g (1 + gamma^2))`` per two bounces: here the
start is chosen 2-periodic along ``y`` (``v_y = gamma (n x W)_y``) and drifting
along ``x``, so the bounce points step along the x axis while the motion in y
goes back and forth.
"""
import math

import matplotlib.pyplot as plt
import numpy as np

from noslipsim import plot, sphere3d

plot.use_style()
gamma = sphere3d.UNIFORM_BALL
vy = 0.6
spin = np.array([vy / gamma, 0.3, 1.0])           # (n x W)_y = W_x, so v_y = gamma W_x: no drift in y
ds = sphere3d.simulate_sphere(position=(0, 0, 0.5), velocity=(0.2, vy, 0), spin=spin, gamma=gamma, n_bounces=12)

# the exact path: parabolas between bounces
t = np.r_[0.0, ds.time.values]
q = np.vstack([[0, 0, 0.5], ds.position.values])
v = np.vstack([[0.2, vy, 0], ds.velocity.values])
path = [q[k] + v[k] * s[:, None] + 0.5 * np.array([0, 0, -1.0]) * s[:, None] ** 2
        for k in range(len(t) - 1) for s in [np.linspace(0, t[k + 1] - t[k], 30)]]
path = np.vstack(path)

fig = plt.figure(figsize=(7, 4.5))
ax = fig.add_subplot(projection="3d")
ax.plot(*path.T, color=plot.law_color("no-slip"), lw=1)
ax.scatter(*ds.position.values.T, color="k", s=8)
ax.set(xlabel="x", ylabel="y", zlabel="z")
u = math.sqrt(2 * 0.5)
drift = 4 * u * (0.2 - gamma * (-spin[1])) / (1 + gamma**2)   # x: v_x - gamma (n x W)_x, (n x W)_x = -W_y
print("bounce points x:", np.round(ds.position.sel(component="x").values[:6], 6).tolist())
print("bounce points y:", np.round(ds.position.sel(component="y").values[:6], 6).tolist())
print(f"drift per two bounces in x: {float(ds.position[2, 0] - ds.position[0, 0]):.12f} (theory {drift:.12f})")
