"""One-step shadowing: restart the 40-digit reference at every float64 collision.

Shared by tests/test_reference.py (plain scenes) and tests/test_reference_lattice.py
(periodic scenes). Chaos cannot amplify anything here: each restart starts from the
float64 state itself, so a missed or invented collision anywhere fails the caller's test.
"""
from noslipsim.reference import resume_reference, simulate_reference

# the float64 collision state a restart starts from (x, y relative to the user's origin)
_RESTART = ("t", "element", "x", "y", "vx", "vy", "spin")


def one_step_references(scene, q, v, w, flt, what="", **kw):
    """Yield ``(k, step, t_prev)``: the reference's next collision after float64 collision ``k``.

    ``k = -1`` is the start. ``step`` is the reference's one-collision record (its ``t``
    counted from the restart, at time ``t_prev`` of the float orbit); it is checked to hold
    exactly one collision. After the orbit's last collision nothing is yielded: the
    reference is checked to end the same way (the same stop reason when the float orbit
    did not stop at its collision budget). ``kw`` goes to both reference calls (``dps``,
    ``stop_below``, ...).
    """
    m = flt.sizes["collision"]
    col = {k: flt[k].values for k in _RESTART}
    for k in range(-1, m):
        if k < 0:
            step = simulate_reference(scene, q, v, w, max_collisions=1, **kw)
            t_prev = 0.0
        else:
            step = resume_reference(scene, (col["x"][k], col["y"][k]), (col["vx"][k], col["vy"][k]),
                                    col["spin"][k], int(col["element"][k]), max_collisions=1, **kw)
            t_prev = col["t"][k]
        where = f"{what}event after collision {k}"
        if k == m - 1:  # after the last collision: the same end (budget, escape or level)
            if flt.attrs["stop_reason"] != "max_collisions":
                assert step.sizes["collision"] == 0, where
                assert step.attrs["stop_reason"] == flt.attrs["stop_reason"], where
            return
        assert step.sizes["collision"] == 1, where
        yield k, step, t_prev
