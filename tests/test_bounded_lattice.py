"""A bounded lattice (``Scene.top``): a Galton board's top row with nothing above it.

Oracles: the same board written out as hundreds of explicit pegs (a plain scene, the
general path, no lattice at all) predicts every flight of the bounded lattice; the
40-digit reference twin shadows it; a particle above the top that misses every peg
falls freely (closed form); bad input is refused by name.
"""
import math

import numpy as np
import pytest
from shadowing import one_step_references

import noslipsim as ns
from noslipsim import tables
from noslipsim._engine.run import run_orbits
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout
from noslipsim.elements import Circle, Segment

SPACING, RADIUS = 2.0, 0.89
ROW = SPACING * math.sqrt(3.0) / 2.0
ROWS_DOWN, COLUMNS = 10, 14  # the explicit board: rows 0 .. -ROWS_DOWN, |x| <= COLUMNS * SPACING
LEVEL = -(ROWS_DOWN - 1.5) * ROW  # the orbits stop well inside the explicit board


def explicit_board(law, gamma, radius=RADIUS):
    """The bounded board (top row 0) as a plain scene of explicit pegs: ``(scene, {(i, j): index})``."""
    pegs, index = [], {}
    for j in range(-ROWS_DOWN, 1):  # row j: pegs at x = i * SPACING + j * SPACING / 2
        for i in range(-COLUMNS - 6, COLUMNS + 7):
            x = i * SPACING + j * SPACING / 2
            if abs(x) <= COLUMNS * SPACING:
                index[(i, j)] = len(pegs)
                pegs.append(Circle((x, j * ROW), radius, "outside"))
    return ns.Scene(tuple(pegs), law=law, gamma=gamma, force=(0.0, -1.0)), index


def _peg(x, y):
    """Lattice indices ``(i, j)`` of the peg a hit point lies on (the nearest lattice site)."""
    j0, i0 = math.floor(y / ROW), math.floor((x - math.floor(y / ROW) * SPACING / 2) / SPACING)
    sites = [(i, j) for j in (j0 - 1, j0, j0 + 1, j0 + 2) for i in range(i0 - 2, i0 + 3)]
    return min(sites, key=lambda s: math.hypot(x - s[0] * SPACING - s[1] * SPACING / 2, y - s[1] * ROW))


@pytest.mark.parametrize("law, gamma", [("specular", 0.0), ("no-slip", 1 / math.sqrt(2)), ("no-slip", 3.0)])
def test_explicit_pegs_predict_every_flight_of_the_bounded_lattice(law, gamma):
    board = tables.galton_board(SPACING, RADIUS, law=law, gamma=gamma, top_row=0)
    pegs, index = explicit_board(law, gamma)
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(3):
        q = (rng.uniform(-1.0, 1.0), rng.uniform(1.5, 3.0))  # released above the top row
        angle = rng.uniform(0, 2 * math.pi)
        v = (0.3 * math.cos(angle), 0.3 * math.sin(angle))
        log = ns.simulate(board, q, v, 0.0, max_collisions=400, stop_below=LEVEL)
        m = log.sizes["collision"]
        assert m > 20
        # the first flight from the release point
        first = ns.simulate(pegs, q, v, 0.0, max_collisions=1)
        for k in ("t", "x", "y", "vx", "vy", "spin"):
            np.testing.assert_allclose(first[k].values[0], log[k].values[0], rtol=0, atol=1e-12)
        # every later flight, restarted from the bounded orbit's state on the explicit peg it is on
        x, y = log.x.values, log.y.values
        assert (np.abs(x[:-1]) < COLUMNS * SPACING - 2 * SPACING).all()
        on = [index[_peg(a, b)] for a, b in zip(x[:-1], y[:-1])]
        step = ns.simulate_many(pegs, np.c_[x[:-1], y[:-1]], np.c_[log.vx.values[:-1], log.vy.values[:-1]],
                                log.spin.values[:-1], start_elements=on, max_collisions=1, stop_below=LEVEL,
                                record="final", progress=False)
        assert (step.n_collisions.values == 1).all()
        t = log.t.values
        np.testing.assert_allclose(step.t_final.values, np.diff(t), rtol=0, atol=1e-12)
        for mine, theirs in (("x_final", "x"), ("y_final", "y"), ("vx_final", "vx"), ("vy_final", "vy"),
                             ("spin_final", "spin")):
            np.testing.assert_allclose(step[mine].values, log[theirs].values[1:], rtol=0, atol=1e-12)
        # the pegs of the bounded orbit are the explicit board's: none above the top row
        assert max(_peg(a, b)[1] for a, b in zip(x, y)) <= 0
        checked += m
    assert checked > 200


def test_bounded_lattice_uses_its_top_row_and_the_unbounded_one_does_not():
    """Thrown up from between two top pegs: the bounded board lets it rise past row 1, the unbounded one not."""
    bounded = tables.galton_board(SPACING, RADIUS, law="specular", gamma=0.0, top_row=0)
    unbounded = tables.galton_board(SPACING, RADIUS, law="specular", gamma=0.0)
    q, v = (1.0, 0.0), (0.0, 3.0)
    up = ns.simulate(bounded, q, v, 0.0, max_collisions=1)
    assert up.sizes["collision"] == 1 and up.y.values[0] <= RADIUS  # falls back onto the top row
    assert up.t.values[0] > 2 * 3.0 - 1e-9  # rose and fell freely: at least the flight of 2 v / g
    hit = ns.simulate(unbounded, q, v, 0.0, max_collisions=1)
    assert hit.y.values[0] == pytest.approx(ROW - RADIUS, abs=1e-12)  # the peg of row 1 above the gap


def test_a_particle_that_misses_every_peg_falls_freely():
    """Between two columns of small pegs (they leave x = 0.5 free), a drop falls to the level in closed form."""
    board = tables.galton_board(SPACING, 0.4, law="no-slip", top_row=3)
    y0, level = 12.0, -20.0
    for vy in (0.0, 2.5):  # dropped, or thrown up first
        out = ns.simulate_many(board, [[0.5, y0]], [[0.0, vy]], [0.3], max_time=100.0, stop_below=level,
                               record="final", progress=False)
        assert int(out.n_collisions.values[0]) == 0
        assert int(out.stop_reason.values[0]) == layout.STOP_LEVEL
        t = vy + math.sqrt(vy**2 + 2 * (y0 - level))
        assert out.t_final.values[0] == pytest.approx(t, rel=1e-13)
        assert out.x_final.values[0] == 0.5
        assert out.spin_final.values[0] == 0.3


def test_starts_above_the_top_are_inside_the_bounded_board_only():
    peg_above = [[0.0, 2 * ROW]]  # a peg's centre in row 2 of the unbounded board
    bounded = tables.galton_board(SPACING, RADIUS, top_row=0)
    out = ns.simulate_many(bounded, peg_above, [[0.0, 0.0]], max_collisions=1, record="final", progress=False)
    assert int(out.n_collisions.values[0]) == 1 and out.y_final.values[0] == pytest.approx(RADIUS, abs=1e-12)
    with pytest.raises(ValueError, match="not strictly inside"):
        ns.simulate_many(tables.galton_board(SPACING, RADIUS), peg_above, [[0.0, 0.0]], max_collisions=1)
    assert bounded.contains([[0.0, 2 * ROW], [0.0, 0.0], [1.0, 0.0]]).tolist() == [True, False, True]


def test_bounded_board_shadows_the_reference():
    board = tables.galton_board(SPACING, RADIUS, law="no-slip", top_row=0)
    q, v, w = (0.4, 2.0), (0.25, 0.1), 0.2
    flt = ns.simulate(board, q, v, w, max_collisions=12)
    assert flt.sizes["collision"] == 12
    for k, step, t_prev in one_step_references(board, q, v, w, flt, "bounded galton: "):
        for name in ("x", "y", "vx", "vy", "spin"):
            assert float(step[name].values[0]) == pytest.approx(float(flt[name].values[k + 1]), abs=1e-11), name
        assert t_prev + float(step.t.values[0]) == pytest.approx(float(flt.t.values[k + 1]), abs=1e-11)


def test_top_round_trips_through_the_scene_file_and_the_canonical_form():
    board = tables.galton_board(SPACING, RADIUS, top_row=2)
    assert board.top == pytest.approx(2.5 * ROW)
    again = ns.Scene.from_yaml(board.to_yaml())
    assert again.top == board.top and again == board
    assert ns.Scene.from_dict({**board.to_dict(), "top": None}).top is None
    # written with its peg elsewhere (a rewritten canonical form): the same orbit
    moved = ns.Scene((Circle((1.0, 0.5), RADIUS, "outside"),), law="no-slip", force=(0.0, -1.0),
                     lattice=board.lattice, top=board.top + 0.5)
    a = ns.simulate(board, (0.3, 7.0), (0.2, 0.0), 0.0, max_collisions=30)
    b = ns.simulate(moved, (1.3, 7.5), (0.2, 0.0), 0.0, max_collisions=30)
    np.testing.assert_allclose(b.x.values[:10] - 1.0, a.x.values[:10], atol=1e-9)
    np.testing.assert_allclose(b.y.values[:10] - 0.5, a.y.values[:10], atol=1e-9)


def test_bad_top_is_refused_by_name():
    disk = (Circle((0.0, 0.0), 0.4, "outside"),)
    lattice = {"a1": [2.0, 0.0], "a2": [1.0, ROW]}
    for bad in (math.inf, -math.inf, math.nan):
        with pytest.raises(ValueError, match="top: must be finite"):
            ns.Scene(disk, force=(0.0, -1.0), lattice=lattice, top=bad)
    with pytest.raises(TypeError, match="top: expected a number"):
        ns.Scene(disk, force=(0.0, -1.0), lattice=lattice, top="high")
    with pytest.raises(ValueError, match="top: only a lattice"):
        ns.Scene(disk, force=(0.0, -1.0), top=1.0)
    with pytest.raises(ValueError, match=r"top: a bounded lattice needs circle scatterers.*segment"):
        ns.Scene((*disk, Segment((0.5, 0.0), (0.5, 0.5))), force=(0.0, -1.0), lattice=lattice, top=1.0)
    with pytest.raises(ValueError, match="top: a bounded lattice is not supported with the isokinetic"):
        ns.Scene(disk, force=(0.0, -1.0), lattice=lattice, top=1.0, thermostat="isokinetic")
    with pytest.raises(ValueError, match="scene: unknown key"):
        ns.Scene.from_dict({"elements": [{"type": "circle", "center": [0, 0], "radius": 0.4}], "tops": 1.0})
    with pytest.raises(TypeError, match="top_row"):
        tables.galton_board(top_row=1.5)
    # the one kernel call refuses a bounded table without the top per orbit
    table = kernel_table(tables.galton_board(top_row=0))
    with pytest.raises(ValueError, match="ceilings"):
        run_orbits(table, [[0.0, 3.0, 0.0, 0.0, 0.0]], max_collisions=1)


def test_bounded_lattice_without_force_runs_the_general_loop_and_lets_a_particle_leave_upwards():
    disks = ns.Scene((Circle((0.0, 0.0), 0.3, "outside"),), law="no-slip", lattice={"a1": [1.0, 0.0], "a2": [0.0, 1.0]},
                     top=0.5)
    assert not kernel_table(disks).disk_lattice  # the lean disk loop knows no top
    up = ns.simulate(disks, (0.5, 2.0), (0.1, 1.0), 0.0, max_collisions=5)
    assert up.sizes["collision"] == 0 and up.attrs["stop_reason"] == "escape"
    down = ns.simulate(disks, (0.0, 3.0), (0.0, -1.0), 0.0, max_collisions=1)
    assert down.y.values[0] == pytest.approx(0.3, abs=1e-12) and down.t.values[0] == pytest.approx(2.7, abs=1e-12)
