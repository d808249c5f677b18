"""The energy settle's form, a compile-time slot chosen by the table (docs/algorithm.md, "Which form, per table").

Each table class keeps its invariants over 10^6 collisions of one orbit through its own compiled
kernel: the energy within 1e-12 (relative to the size of its terms) wherever a settle acts, and,
bit for bit, what the dynamics keeps exactly there.  A targeted table whose kernel were compiled
with the whole-state settle would lose those bits (checked once by forcing ``settle=WHOLE`` on the
same orbits: the channels' ``|v_y|`` moved by 1.2e-11 (force along the walls) and 3.2e-12 (no force)
relative, the no-slip Galton board's spin in flight by 1.1e-12 and the mixed lattice's spin over
its specular disk by 8.9e-15); a whole-state table has the energy only, and its test checks the
form its table derives.
"""
import math

import numpy as np
import pytest
from kernel_call import run_kernel

from noslipsim import Circle, simulate, tables
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout
from noslipsim.core.variant import TARGETED, WHOLE

DISK = 1 / math.sqrt(2)
#: Collisions per orbit (issue 32: each table class tested after 10^6 collisions).
N = 1_000_000
#: Largest relative energy error after N collisions where a settle acts.
DRIFT = 1e-12


def mixed_torus():
    """Disks only, no force, two laws: a no-slip disk and a specular one on the unit lattice."""
    one = tables.sinai_torus(0.2)
    return one.replace(elements=(Circle((0.0, 0.0), 0.2), Circle((0.5, 0.5), 0.15, law="specular")))


#: Table class -> (scene, start position, velocity, spin, the form its table derives).
CLASSES = {
    "channel, force along the walls": (tables.channel(1.0, force=(1.0, 0.0)), (0.5, 0.5), (0.7, 0.31), 0.2,
                                       TARGETED),
    "channel, no force": (tables.channel(1.0), (0.5, 0.5), (0.7, 0.31), 0.2, TARGETED),
    "Galton board, no-slip": (tables.galton_board(gamma=DISK), (1.0, 0.9), (0.3, 0.2), 0.2, TARGETED),
    "mixed disk lattice": (mixed_torus(), (0.5, 0.1), (0.6, 0.8), 0.2, TARGETED),
    "Galton board, specular": (tables.galton_board(law="specular"), (1.0, 0.9), (0.3, 0.2), 0.0, WHOLE),
    "Sinai torus, no-slip": (tables.sinai_torus(0.25), (0.45, 0.1), (0.83, 0.41), 0.1, WHOLE),
    "lemon, no-slip": (tables.lemon(1.0, 1.0, law="no-slip", gamma=DISK), (0.0, 0.1), (0.6, 0.8), 0.1, WHOLE),
    "stadium, thermostat": (tables.stadium(1.0, 1.0, gamma=DISK, force=(0.3, -1.0)).replace(thermostat="isokinetic"),
                            (0.0, 0.0), (0.7, 0.31), 0.2, WHOLE),
    "box, magnetic": (tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]).replace(magnetic=1.5), (0.1, 0.1),
                      (0.6, 0.8), 0.2, WHOLE),
}


def orbit(name):
    scene, q, v, w, _ = CLASSES[name]
    ds = simulate(scene, q, v, w, max_collisions=N)
    assert int(ds.n_collisions) == N, (name, str(ds.stop_reason.values))
    return scene, ds


def energy_error(scene, ds):
    """The largest relative error of twice the energy, ``|v|^2 (+ w^2 where the law mixes it in) - 2 a . q``,
    the orbit's collisions against its start (a thermostat keeps the kinetic part only)."""
    table = kernel_table(scene)
    mixes = table.law != layout.SPECULAR and table.s != 0.0
    kin = ds.vx.values ** 2 + ds.vy.values ** 2 + (ds.spin.values ** 2 if mixes else 0.0)
    ax, ay = scene.force if scene.thermostat is None else (0.0, 0.0)
    e = kin - 2.0 * (ax * ds.x.values + ay * ds.y.values)
    size = np.maximum(kin, kin + np.abs(e - kin))
    return np.abs(e - e[0]).max() / size.max()


def bits(values):
    return np.asarray(values, dtype=np.float64).view(np.int64)


@pytest.mark.parametrize("name", CLASSES)
def test_the_table_chooses_the_form(name):
    """The rule (energy.targeted_settle): targeted where a flat wall keeps a normal speed (free flight or free
    fall), where a no-slip table under free fall keeps the spin in flight, or where a mixed table keeps it over
    its specular elements; the whole state elsewhere (disks only, the thermostat, a field)."""
    scene, *_, form = CLASSES[name]
    table = kernel_table(scene)
    assert table.settle == form
    assert table.variant(layout.RECORD_NONE).settle == form


@pytest.mark.parametrize("name", ["channel, force along the walls", "channel, no force"])
def test_a_channel_keeps_its_normal_speed_bit_for_bit(name):
    """Axis normals: each wall hit reverses ``v_y`` exactly; the force and the law change ``(v_x, w)`` only."""
    scene, ds = orbit(name)
    vy = np.abs(ds.vy.values)
    assert np.array_equal(bits(vy), bits(np.full_like(vy, vy[0]))), np.abs(vy - vy[0]).max()
    assert energy_error(scene, ds) < DRIFT


def test_the_no_slip_galton_board_keeps_the_spin_in_flight_bit_for_bit():
    """Free fall never touches the spin: each collision meets the spin the last one left."""
    scene, ds = orbit("Galton board, no-slip")
    w_in, w_out = ds.spin_in.values[1:], ds.spin.values[:-1]
    assert np.array_equal(bits(w_in), bits(w_out)), np.abs(w_in - w_out).max()
    assert energy_error(scene, ds) < DRIFT


def test_a_mixed_disk_lattice_keeps_the_spin_over_specular_disks_bit_for_bit():
    """A specular disk and the flight keep the spin: from such a hit to the next collision it keeps its bits."""
    scene, ds = orbit("mixed disk lattice")
    after_specular = ds.element.values[:-1] == 1
    assert after_specular.sum() > N // 10
    w_out, w_next = ds.spin.values[:-1][after_specular], ds.spin_in.values[1:][after_specular]
    assert np.array_equal(bits(w_next), bits(w_out)), np.abs(w_next - w_out).max()
    assert energy_error(scene, ds) < DRIFT


@pytest.mark.parametrize("name", ["Galton board, specular", "Sinai torus, no-slip", "lemon, no-slip",
                                  "stadium, thermostat", "box, magnetic"])
def test_a_whole_state_table_keeps_its_energy(name):
    """Disks only (no spin kept in flight), or a flight that rounds every component: the energy is all that is
    exact, and the whole-state settle keeps it."""
    scene, ds = orbit(name)
    assert energy_error(scene, ds) < DRIFT


def test_the_general_kernel_applies_the_rule_at_run_time():
    """``settle=None`` reads the form from the arguments, by the table's rule: bit for bit each table's own kernel,
    on one kernel serving a whole-state table and a targeted one (the Galton board, specular and no-slip)."""
    own = kernel_table(CLASSES["Galton board, specular"][0]).variant(layout.RECORD_NONE)
    general = own._replace(spin=None, settle=None)
    for name in ("Galton board, specular", "Galton board, no-slip"):
        scene, q, v, w, _ = CLASSES[name]
        table = kernel_table(scene)
        own = run_kernel(table, table.variant(layout.RECORD_NONE), q, v, w, 20_000)
        assert run_kernel(table, general, q, v, w, 20_000) == own, name
