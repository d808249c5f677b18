"""Tables of mixed laws: each element may collide by its own law (docs/scenes.md, "Per-element laws").

The reference table is Figure 13's reading (b), the closed hexagonal cell with
specular walls (elements 0-5) around a no-slip disk (element 6), under gravity
and without.  Checked: a table whose elements all carry one law runs the same
bits as the plain table, in the per-element kernel variant too; a specular wall
keeps the spin bit for bit and reflects ``v`` (``v_t`` kept, ``v_n`` reversed);
the disk's collisions are the no-slip law's (:func:`noslipsim.core.laws.collide`);
the energy ``|v|^2 + w^2 - 2 a . q`` is kept over 1e5 collisions; the float
engine agrees with the high-precision twin; the scene file round-trips and bad
law names are refused by name.
"""
import math
from pathlib import Path

import numpy as np
import pytest
from kernel_call import record_buffer, run_kernel
from shadowing import one_step_references

from noslipsim import Circle, Scene, Segment, simulate, tables
from noslipsim._engine.canonical import canonical_form
from noslipsim._engine.table import kernel_table
from noslipsim.analysis.tangent import step_entries
from noslipsim.core import layout
from noslipsim.core.laws import collide
from noslipsim.core.loop import orbit_kernel
from noslipsim.core.variant import GENERAL, STRAIGHT, Variant
from noslipsim.reference import simulate_reference

DISK = 1 / math.sqrt(2)
WALLS = range(6)
START = ((0.05, 0.45), (0.61, -0.27), 0.3)  # position (between the disk and the top vertex), velocity, spin


def mixed_cell(g=1.0, gamma=DISK, thermostat=None):
    """Specular walls, a no-slip disk of radius 0.4 (element 6), force (0, -g)."""
    scene = tables.closed_hex_cell(0.4, law="no-slip", wall_law="specular", gamma=gamma, force=(0.0, -g))
    return scene if thermostat is None else scene.replace(thermostat=thermostat)


def one_law_cell(law, g=1.0, explicit=False):
    """The plain cell of one law; ``explicit``: every element writes the scene's law itself."""
    scene = tables.closed_hex_cell(0.4, law=law, force=(0.0, -g))
    if explicit:
        scene = scene.replace(elements=[_with_law(e, law) for e in scene.elements])
    return scene


def _with_law(e, law):
    d = e.to_dict()
    d["law"] = law
    return type(e).from_dict(d)


def bits(values):
    return np.asarray(values, dtype=np.float64).view(np.int64)


def log_of(scene, n, flags=None):
    """``(outputs, log rows)`` of ``n`` collisions from START through the kernel variant ``flags``."""
    (q, v, w) = START
    rec = record_buffer(layout.RECORD_LOG, n + 1, fill=-7.0)
    table = kernel_table(scene)
    out = run_kernel(table, table.variant(layout.RECORD_LOG) if flags is None else flags, q, v, w, n,
                     layout.RECORD_LOG, rec=rec)
    assert out[0] == n and out[1] == layout.STOP_MAX_COLLISIONS, out[:2]
    return out, rec[:n]


# ----------------------------------------------------------------------------- one law written per element
@pytest.mark.parametrize("law", ["no-slip", "specular"])
def test_one_law_on_every_element_is_the_plain_table_bit_for_bit(law):
    plain = one_law_cell(law)
    explicit = one_law_cell(law, explicit=True)
    assert explicit != plain and not explicit.mixed_laws  # another value, the same billiard
    assert kernel_table(explicit).variant(1) == kernel_table(plain).variant(1)
    assert kernel_table(plain).variant(1).mixed is False  # a table of one law compiles no per-element code
    out_p, rec_p = log_of(plain, 3000)
    out_e, rec_e = log_of(explicit, 3000)
    assert np.array_equal(bits(out_e), bits(out_p)) and np.array_equal(bits(rec_e), bits(rec_p))
    # the per-element variant (mixed=True) on the plain table: the same bits too (spin=False would force the
    # specular law everywhere, so the specular table's spin is left to run time)
    own = kernel_table(plain).variant(1)
    mixed_flags = own._replace(spin=own.spin or None, mixed=True)
    assert orbit_kernel(*mixed_flags) is not orbit_kernel(*kernel_table(plain).variant(1))
    out_m, rec_m = log_of(plain, 3000, flags=mixed_flags)
    assert np.array_equal(bits(out_m), bits(out_p)) and np.array_equal(bits(rec_m), bits(rec_p))


def test_specular_elements_on_a_noslip_scene_are_the_specular_table():
    """Every element overriding the scene's law: the table is the other law's, bit for bit."""
    spec = one_law_cell("specular")
    overridden = one_law_cell("no-slip").replace(
        elements=[_with_law(e, "specular") for e in spec.elements])
    assert overridden.law == "no-slip" and overridden.element_laws == ("specular",) * 7
    assert kernel_table(overridden).variant(1) == kernel_table(spec).variant(1)
    out_o, rec_o = log_of(overridden, 2000)
    out_s, rec_s = log_of(spec, 2000)
    assert np.array_equal(bits(out_o), bits(out_s)) and np.array_equal(bits(rec_o), bits(rec_s))


@pytest.mark.parametrize("g", [0.0, 1.0])
def test_mixed_variant_bitwise_identical_to_general(g):
    """The mixed table's own variant (every flag fixed) against the general path (law = PER_ELEMENT at run time)."""
    scene = mixed_cell(g)
    own = kernel_table(scene).variant(layout.RECORD_LOG)
    assert own.mixed is True and own.spin is True and own.disks is False
    out_o, rec_o = log_of(scene, 5000)
    out_g, rec_g = log_of(scene, 5000, flags=GENERAL)
    assert np.array_equal(bits(out_o), bits(out_g)) and np.array_equal(bits(rec_o), bits(rec_g))


# ----------------------------------------------------------------------------- each collision by its element's law
def _normals(scene, log):
    """Outward unit normals at the logged collisions: a wall's own, the disk's towards its centre."""
    e = log[:, layout.LOG_ELEMENT].astype(int)
    n = np.empty((len(log), 2))
    for i, el in enumerate(scene.elements):
        sel = e == i
        if isinstance(el, Segment):
            inward = np.array(el.params()[2:4])
            n[sel] = -inward
        else:
            d = np.array(el.center) - log[sel][:, [layout.LOG_X, layout.LOG_Y]]
            n[sel] = d / np.hypot(d[:, 0], d[:, 1])[:, None]
    return n


@pytest.mark.parametrize("g", [0.0, 1.0])
def test_walls_reflect_and_keep_the_spin_the_disk_is_noslip(g):
    scene = mixed_cell(g)
    _, log = log_of(scene, 5000)
    assert kernel_table(scene).variant(1).mixed is True and not kernel_table(scene).disk_lattice
    e = log[:, layout.LOG_ELEMENT].astype(int)
    wall, disk = e < 6, e == 6
    assert wall.sum() > 1000 and disk.sum() > 500 and log[:, layout.LOG_CORNER].sum() == 0
    n = _normals(scene, log)
    t = np.c_[-n[:, 1], n[:, 0]]
    v_in = log[:, [layout.LOG_VX_IN, layout.LOG_VY_IN]]
    v_out = log[:, [layout.LOG_VX, layout.LOG_VY]]
    # a specular wall: the spin's bits kept, v_t kept, v_n reversed
    assert np.array_equal(bits(log[wall, layout.LOG_W]), bits(log[wall, layout.LOG_W_IN]))
    speed = np.hypot(v_in[:, 0], v_in[:, 1])
    vt_in, vt_out = np.sum(v_in * t, axis=1), np.sum(v_out * t, axis=1)
    vn_in, vn_out = np.sum(v_in * n, axis=1), np.sum(v_out * n, axis=1)
    assert np.all(np.abs(vt_out - vt_in)[wall] <= 4e-16 * speed[wall])
    assert np.all(np.abs(vn_out + vn_in)[wall] <= 4e-16 * speed[wall])
    assert np.all(vn_in[wall] > 0)
    # the no-slip disk: the law itself, and the spin changes there
    c, s = scene.noslip_coefficients
    for i in np.flatnonzero(disk)[:300]:
        want = collide(layout.NOSLIP, c, s, v_in[i, 0], v_in[i, 1], log[i, layout.LOG_W_IN], n[i, 0], n[i, 1])
        got = (v_out[i, 0], v_out[i, 1], log[i, layout.LOG_W])
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-14)
    assert np.mean(log[disk, layout.LOG_W] != log[disk, layout.LOG_W_IN]) > 0.99
    # the contact velocity v_t + w / gamma reversed on the disk, not on the walls
    contact_in = vt_in + log[:, layout.LOG_W_IN] / DISK
    contact_out = vt_out + log[:, layout.LOG_W] / DISK
    assert np.allclose(contact_out[disk], -contact_in[disk], rtol=0, atol=1e-13)
    assert np.mean(np.abs(contact_out[wall] + contact_in[wall]) > 1e-3) > 0.9


def test_energy_kept_over_1e5_collisions():
    scene = mixed_cell(1.0)
    n = 100_000
    _, log = log_of(scene, n)
    ax, ay = scene.force
    kin = log[:, layout.LOG_VX] ** 2 + log[:, layout.LOG_VY] ** 2 + log[:, layout.LOG_W] ** 2
    energy = kin - 2.0 * (ax * log[:, layout.LOG_X] + ay * log[:, layout.LOG_Y])
    (q, v, w) = START
    e0 = v[0] ** 2 + v[1] ** 2 + w ** 2 - 2.0 * (ax * q[0] + ay * q[1])
    assert np.max(np.abs(energy - e0)) <= 1e-13 * e0
    # not vacuous: the spin exchanges energy with the velocity (without it the sum is off by O(1))
    lin = kin - log[:, layout.LOG_W] ** 2 - 2.0 * (ax * log[:, layout.LOG_X] + ay * log[:, layout.LOG_Y])
    assert np.ptp(lin) > 0.1 * e0


def test_energy_kept_without_force_and_with_the_thermostat():
    for scene in (mixed_cell(0.0), mixed_cell(1.0, thermostat="isokinetic")):
        _, log = log_of(scene, 20_000)
        kin = log[:, layout.LOG_VX] ** 2 + log[:, layout.LOG_VY] ** 2 + log[:, layout.LOG_W] ** 2
        (_, v, w) = START
        e0 = v[0] ** 2 + v[1] ** 2 + w ** 2
        assert np.max(np.abs(kin - e0)) <= 1e-13 * e0, scene.thermostat
        wall = log[:, layout.LOG_ELEMENT] < 6
        assert np.array_equal(bits(log[wall, layout.LOG_W]), bits(log[wall, layout.LOG_W_IN]))
        if scene.thermostat is not None:  # the speed is kept in flight; the disk trades it with the spin
            sp = np.hypot(log[:, layout.LOG_VX], log[:, layout.LOG_VY])
            assert np.ptp(sp) > 0.05


# ----------------------------------------------------------------------------- the high-precision twin
@pytest.mark.parametrize("g", [0.0, 1.0])
def test_float_engine_agrees_with_reference_twin(g):
    scene = mixed_cell(g)
    q, v, w = START
    ref = simulate_reference(scene, q, v, w, max_collisions=20)
    flt = simulate(scene, q, v, w, max_collisions=20)
    assert set(ref.element.values[ref.element.values < 6]) and 6 in ref.element.values  # walls and the disk
    np.testing.assert_array_equal(flt.element.values, ref.element.values)
    for name in ("t", "x", "y", "vx", "vy", "spin", "vx_in", "vy_in", "spin_in"):
        np.testing.assert_allclose(flt[name].values, ref[name].values, rtol=0, atol=1e-9, err_msg=name)
    # the twin applies each element's law too: its walls keep the spin
    wall = ref.element.values < 6
    np.testing.assert_array_equal(ref.spin.values[wall], ref.spin_in.values[wall])
    # and the all-no-slip cell is another orbit (the comparison above is not vacuous)
    other = simulate(one_law_cell("no-slip", g), q, v, w, max_collisions=20)
    assert not np.allclose(other.spin.values, flt.spin.values, atol=1e-3)


def test_corner_of_a_noslip_and_a_specular_wall():
    """A flight into the corner (1, 0) of the unit square: the no-slip floor (element 0) turns the spin, the
    corner rule's bounce off the specular right wall (element 1) keeps it; the twin resolves it alike."""
    square = tables.rectangle(1.0, 1.0)
    walls = list(square.elements)
    walls[1] = Segment(walls[1].p0, walls[1].p1, walls[1].side, law="specular")
    scene = square.replace(elements=walls)
    start = ((0.5, 0.5), (0.5, -0.5), -0.5)  # the floor keeps v_x > 0, so the particle leaves through the wall
    flt = simulate(scene, *start, max_collisions=6)
    ref = simulate_reference(scene, *start, max_collisions=6)
    assert flt.element.values[:2].tolist() == [0, 1] and flt.corner.values[:2].tolist() == [0, 1]
    np.testing.assert_array_equal(flt.element.values, ref.element.values)
    np.testing.assert_array_equal(flt.corner.values, ref.corner.values)
    for name in ("x", "y", "vx", "vy", "spin"):
        np.testing.assert_allclose(flt[name].values, ref[name].values, rtol=0, atol=1e-12, err_msg=name)
    assert float(flt.spin[0]) != -0.5 and float(flt.spin[1]) == float(flt.spin_in[1])  # floor turns, wall keeps
    assert float(flt.vy[1]) > 0 and float(flt.vx[1]) < 0


# ----------------------------------------------------------------------------- the tangent map
def test_tangent_map_uses_each_elements_law():
    scene = mixed_cell(1.0)
    _, log = log_of(scene, 400)
    E = step_entries(scene, log)
    e1 = log[1:, layout.LOG_ELEMENT].astype(int)
    wall = e1 < 6
    # a specular collision keeps the spin: its row (dw) is (0, 1, 0)
    assert np.array_equal(E[1, :, wall], np.tile([0.0, 1.0, 0.0], (wall.sum(), 1)))
    # a no-slip one (the disk): (dw, dv_t) -> T (dw, dv_t), so the spin column holds -c - s x, -s + c x
    c, s = scene.noslip_coefficients
    x = (E[2, 1, ~wall] + s) / c
    assert (~wall).sum() > 50
    np.testing.assert_allclose(E[1, 1, ~wall], -c - s * x, rtol=0, atol=1e-9)
    assert np.mean(np.abs(E[1, 1, ~wall] - 1.0) > 1e-3) > 0.9


# ----------------------------------------------------------------------------- the scene file
def test_scene_file_round_trip(tmp_path):
    scene = mixed_cell(1.0)
    d = scene.to_dict()
    assert [e.get("law") for e in d["elements"]] == ["specular"] * 6 + [None]  # written only where set
    path = tmp_path / "mixed.yaml"
    scene.to_yaml(path)
    back = Scene.from_yaml(path)
    assert back == scene and back.element_laws == scene.element_laws and back.mixed_laws
    assert Scene.from_dict(scene.to_dict()) == scene
    assert hash(back.elements) == hash(scene.elements)
    # the law is part of an element's value
    assert Circle((0, 0), 0.4, law="specular") != Circle((0, 0), 0.4)
    assert Circle((0, 0), 0.4, law="noslip") == Circle((0, 0), 0.4, law="no-slip")  # one canonical name
    assert Circle((0, 0), 0.4, law="noslip").to_dict()["law"] == "no-slip"
    # shifted copies (lattices, canonical forms) keep it
    assert Circle((0, 0), 0.4, law="specular").shifted(1.0, 2.0).law == "specular"
    assert scene.replace(law="specular").element_laws == ("specular",) * 7  # the disk followed the scene


def test_the_docs_example_is_the_mixed_cell():
    """docs/scenes.md's example of per-element laws: the cell of this file, vertices rounded."""
    text = (Path(__file__).resolve().parents[1] / "docs" / "scenes.md").read_text(encoding="utf-8")
    block = text.split("## Per-element laws", 1)[1].split("```yaml", 1)[1].split("```", 1)[0]
    doc = Scene.from_yaml(block)
    cell = mixed_cell(1.0)
    assert doc.element_laws == cell.element_laws and doc.mixed_laws
    assert math.isclose(doc.gamma, cell.gamma, rel_tol=1e-15, abs_tol=0)
    assert doc.force == cell.force
    for a, b in zip(doc.elements, cell.elements, strict=True):
        np.testing.assert_allclose(a.params(), b.params(), rtol=0, atol=1e-15)


def test_mixed_lattice_runs_the_general_loop():
    """Two disks per cell of a square lattice, one specular: never the lean (one-law) disk loop."""
    lattice = {"a1": [1.0, 0.0], "a2": [0.0, 1.0]}
    one = Scene((Circle((0.0, 0.0), 0.2), Circle((0.5, 0.5), 0.15)), lattice=lattice)
    mixed = one.replace(elements=(Circle((0.0, 0.0), 0.2), Circle((0.5, 0.5), 0.15, law="specular")))
    assert kernel_table(one).disk_lattice and not kernel_table(mixed).disk_lattice
    assert kernel_table(mixed).law == layout.PER_ELEMENT
    # written off-centre, the canonical form (moved elements, translated scene) keeps each element's law
    off = mixed.replace(elements=[e.shifted(0.3, 0.2) for e in mixed.elements])
    form = canonical_form(off)
    assert not form.identity and form.scene.element_laws == ("no-slip", "specular")
    # the cell walk applies each copy's law: the float engine against the twin (over 5 collisions: chaos
    # grows the rounding tenfold per collision here), then the twin restarted at each of 20 float collisions
    q, v, w = (0.8, 0.0), (0.6, 0.8), 0.2
    flt = simulate(off, q, v, w, max_collisions=20)
    ref = simulate_reference(off, q, v, w, max_collisions=5)
    assert set(flt.element.values[:5].tolist()) == {0, 1}
    np.testing.assert_array_equal(flt.element.values[:5], ref.element.values)
    for name in ("x", "y", "vx", "vy", "spin", "spin_in"):
        np.testing.assert_allclose(flt[name].values[:5], ref[name].values, rtol=0, atol=1e-9, err_msg=name)
    for k, step, _ in one_step_references(off, q, v, w, flt):
        assert int(step.element[0]) == int(flt.element[k + 1]), k
        for name in ("vx", "vy", "spin"):
            assert abs(float(step[name][0]) - float(flt[name][k + 1])) <= 1e-9, (k, name)
    assert k == 18
    on_specular = flt.element.values == 1
    np.testing.assert_array_equal(flt.spin.values[on_specular], flt.spin_in.values[on_specular])
    with pytest.raises(ValueError, match="lean disk loop"):
        orbit_kernel(*Variant(True, True, 1, True, False, STRAIGHT, True))
    with pytest.raises(ValueError, match="spin=False"):
        orbit_kernel(*Variant(False, True, 1, False, False, STRAIGHT, True))


@pytest.mark.parametrize("bad", ["sticky", "No-Slip", 1, ""])
def test_bad_law_names_refused(bad):
    d = mixed_cell(1.0).to_dict()
    d["elements"][2]["law"] = bad
    with pytest.raises(ValueError, match=r"elements\[2\]\.law: unknown collision law"):
        Scene.from_dict(d)
    with pytest.raises(ValueError, match=r"segment\.law: unknown collision law"):
        Segment((0.0, 0.0), (1.0, 0.0), law=bad)
    with pytest.raises(ValueError, match=r"circle\.law"):
        Circle((0.0, 0.0), 1.0, law=bad)


def test_law_is_keyword_only():
    with pytest.raises(TypeError):
        Circle((0.0, 0.0), 1.0, "outside", "specular")


def _specular_cell_with_noslip_disk():
    """A scene whose default law is specular and whose disk (element 6) collides by the no-slip law."""
    scene = tables.closed_hex_cell(0.4, law="specular", gamma=DISK, force=(0.0, -1.0))
    return scene.replace(elements=[_with_law(e, "no-slip") if k == 6 else e for k, e in enumerate(scene.elements)])


def test_phase_coordinates_follow_the_elements_laws_not_the_default_law():
    """The spin is a phase variable wherever one element is no-slip, whatever the scene's default law.

    A specular default with a no-slip disk draws spins and portrays ``(v_t, w)``; a no-slip
    default whose every element is specular draws none and portrays Birkhoff's ``(s, p)``.
    """
    from noslipsim import initial
    from noslipsim.analysis import islands
    from noslipsim.analysis.log_portrait import paper_portrait

    mixed = _specular_cell_with_noslip_disk()
    assert mixed.law == "specular" and mixed.any_noslip
    starts = islands.uniform_reduced_states(mixed, 200, seed=3)
    assert "w_unit" in starts and "sin_angle" not in starts
    assert np.max(np.abs(starts["spins"])) > 0.5
    assert np.max(np.abs(initial.boundary_states(mixed, 200, seed=3)["spins"])) > 0.5
    assert paper_portrait(mixed) == "velocity"

    plain = one_law_cell("no-slip")
    all_specular = plain.replace(elements=[_with_law(e, "specular") for e in plain.elements])
    assert all_specular.law == "no-slip" and not all_specular.any_noslip
    starts = islands.uniform_reduced_states(all_specular, 200, seed=3)
    assert "sin_angle" in starts and not np.any(starts["spins"])
    assert not np.any(initial.boundary_states(all_specular, 200, seed=3)["spins"])
    assert paper_portrait(all_specular) == "birkhoff"


def test_spin_keeps_its_bits_from_a_wall_to_the_next_collision():
    """The energy settle after a specular wall corrects the velocity, not the spin.

    Without force the correction goes to the pair ``(v_t, w)`` the last collision rotated
    (:mod:`noslipsim.core.energy`); a specular wall rotates no such pair, and the wall and the
    flight both keep the spin exactly, so from a wall to the next collision it keeps its bits.
    Not vacuous: without force a flight keeps ``v`` exactly too, so every change of ``v``
    between a wall and the next collision is a settle's, and there are some.
    """
    scene = mixed_cell(0.0)
    _, log = log_of(scene, 100_000)
    after_wall = log[:-1, layout.LOG_ELEMENT] < 6
    assert after_wall.sum() > 50_000
    w_out, w_next = log[:-1, layout.LOG_W][after_wall], log[1:, layout.LOG_W_IN][after_wall]
    assert np.array_equal(bits(w_next), bits(w_out))
    v_out = log[:-1][after_wall][:, [layout.LOG_VX, layout.LOG_VY]]
    v_next = log[1:][after_wall][:, [layout.LOG_VX_IN, layout.LOG_VY_IN]]
    settled = np.any(bits(v_next) != bits(v_out), axis=1)
    assert settled.sum() >= 3
    speed = np.hypot(v_out[:, 0], v_out[:, 1])
    assert np.all(np.hypot(*(v_next - v_out).T) <= 1e-12 * speed)  # a rounding-sized correction
