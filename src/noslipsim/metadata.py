"""Long names and units of every dataset variable, declared once (docs/datasets.md).

Lengths, times and speeds are in the units of the scene (nondimensional:
``"1"``).  Spin is the scaled spin ``w = gamma R omega`` (a speed).
"""

VARIABLES = {
    "t": ("time of the collision", "1"),
    "x": ("x position at the collision", "1"),
    "y": ("y position at the collision", "1"),
    "vx": ("x velocity just after the collision", "1"),
    "vy": ("y velocity just after the collision", "1"),
    "spin": ("scaled spin w = gamma R omega just after the collision (CCW positive)", "1"),
    "vx_in": ("x velocity just before the collision", "1"),
    "vy_in": ("y velocity just before the collision", "1"),
    "spin_in": ("scaled spin just before the collision (CCW positive)", "1"),
    "element": ("index of the element hit, in scene order", "1"),
    "s": ("arclength coordinate of the collision on its element", "1"),
    "corner": ("1 if the collision was resolved by the corner rule, else 0", "1"),
    "energy": ("energy (|v|^2 + w^2)/2 - a.q just after the collision", "1"),
    "t_final": ("time at the end of the orbit", "1"),
    "x_final": ("x position at the end of the orbit", "1"),
    "y_final": ("y position at the end of the orbit", "1"),
    "vx_final": ("x velocity at the end of the orbit", "1"),
    "vy_final": ("y velocity at the end of the orbit", "1"),
    "spin_final": ("scaled spin at the end of the orbit", "1"),
    "n_collisions": ("number of collisions", "1"),
    "stop_reason": ("why the orbit ended", "1"),
    "n_corner": ("number of collisions resolved by the corner rule", "1"),
    "n_points": ("number of phase-portrait points recorded", "1"),
    "w_unit": ("post-collision scaled spin over |(w, v_t, v_n)|", "1"),
    "vt_unit": ("post-collision tangential velocity over |(w, v_t, v_n)| (t = J n)", "1"),
    "vn_unit": ("post-collision normal velocity over |(w, v_t, v_n)| (n outward, so <= 0)", "1"),
    "cell_a1": ("lattice cell index along a1 at the collision", "1"),
    "cell_a2": ("lattice cell index along a2 at the collision", "1"),
    "cell_a1_final": ("lattice cell index along a1 at the end of the orbit", "1"),
    "cell_a2_final": ("lattice cell index along a2 at the end of the orbit", "1"),
}


def annotate(ds):
    """Attach ``long_name`` and ``units`` to every known variable of ``ds`` (in place) and return it."""
    for name, var in ds.variables.items():
        if name in VARIABLES:
            long_name, units = VARIABLES[name]
            var.attrs.setdefault("long_name", long_name)
            var.attrs.setdefault("units", units)
    return ds
