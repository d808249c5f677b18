"""Invariant checks shared by tests and stress runs (DynamicalBilliards.jl's testing habit).

- every collision point lies on the element it hit (within ``tol`` times the scene size);
- sampled points of every flight lie inside the table (depth >= -tol times the size);
- energy ``(|v|^2 + w^2)/2 - a.q`` is conserved.
"""
import math

import numpy as np

from noslipsim import Circle, Line, tables

FAMILIES = {
    # name: (scene factory, start, velocity, spin)
    "pentagon": (lambda: tables.regular_polygon(5), (0.1, 0.05), (0.83, 0.41), 0.2),
    "pentagon_gravity": (lambda: tables.regular_polygon(5, force=(0.0, -1.0)), (0.1, 0.05), (0.83, 0.41), 0.2),
    "L_shape_gravity": (lambda: tables.polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)], force=(0.3, -1.0)),
                        (0.5, 0.5), (0.7, 0.3), -0.1),
    "sinai_box": (lambda: tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]), (0.1, 0.1), (0.6, 0.8), 0.0),
    "two_disks_box_gravity": (lambda: tables.two_disks(0.6, box=(4.0, 3.0), force=(0.0, -1.0)), (0.0, 0.9),
                              (0.5, 0.2), 0.3),
    "stadium_gravity": (lambda: tables.stadium(1.0, 1.0, force=(0.0, -1.0)), (0.0, 0.0), (0.6, 0.3), 0.1),
    "lemon_specular": (lambda: tables.lemon(1.0, 1.0), (0.0, 0.1), (0.9, 0.2), 0.0),
    "circle_container_gravity": (lambda: tables.Scene([Circle((0.0, 0.0), 1.0, "inside")], force=(0.2, -1.0)),
                                 (0.1, 0.2), (0.4, 0.1), 0.5),
    "wedge_gravity": (lambda: tables.wedge(0.6), (0.0, 1.0), (0.5, 0.4), 0.3),
    "galton_box": (lambda: tables.Scene(
        tables.rectangle(6.0, 6.0).elements
        + tuple(Circle((1.0 + 2.0 * i + (j % 2), 1.0 + 1.7320508075688772 * j / 1.0 * 0.7), 0.4)
                for j in range(4) for i in range(2 + (j + 1) % 2) if 1.0 + 2.0 * i + (j % 2) < 5.6),
        force=(0.0, -1.0)), (3.0, 5.5), (0.3, 0.1), 0.0),
    "ramp_channel": (lambda: tables.Scene([Line((0.0, 0.0), (-0.3, 1.0)), Line((0.0, 2.0), (0.3, -1.0)),
                                           Line((-3.0, 0.0), (1.0, 0.0)), Line((3.0, 0.0), (-1.0, 0.0))],
                                          force=(0.0, -1.0)), (0.0, 1.0), (0.4, 0.2), 0.0),
}


def on_element_error(scene, ds, corner=False):
    """Largest distance (relative to the scene size) from a collision point to the element it hit.

    ``corner=False`` measures ordinary hits (the particle is projected onto the
    element); ``corner=True`` measures corner-rule hits, which by the rule lie
    within ``CONTACT_TOL`` of the second element.
    """
    pts = np.c_[ds.x.values, ds.y.values]
    worst = 0.0
    for i, e in enumerate(scene.elements):
        sel = (ds.element.values == i) & ((ds.corner.values == 1) == corner)
        if not sel.any():
            continue
        d = e.distance(pts[sel]) if e.finite else np.abs(e.side_distance(pts[sel]))
        worst = max(worst, float(d.max()))
    return worst / max(scene.scale, 1.0)


def flight_samples(scene, ds, per_flight=3, seed=0):
    """Points sampled strictly inside every flight between consecutive collisions."""
    rng = np.random.default_rng(seed)
    t = ds.t.values
    dt = np.diff(t)
    frac = rng.uniform(0.0, 1.0, size=(len(dt), per_flight))
    tau = dt[:, None] * frac
    ax, ay = scene.force
    x = ds.x.values[:-1, None] + ds.vx.values[:-1, None] * tau + 0.5 * ax * tau ** 2
    y = ds.y.values[:-1, None] + ds.vy.values[:-1, None] * tau + 0.5 * ay * tau ** 2
    return np.stack([x.ravel(), y.ravel()], axis=-1)


def leak_depth(scene, ds, per_flight=3, seed=0):
    """Most negative table depth over sampled flight points, relative to the scene size (>= 0: no leak)."""
    pts = flight_samples(scene, ds, per_flight, seed)
    return float(scene.depth(pts).min()) / max(scene.scale, 1.0)


def relative_energy_drift(ds):
    e = ds.energy.values
    return float(np.abs(e - e[0]).max() / max(abs(e[0]), math.ulp(1.0)))
