"""The isokinetic thermostat end to end through the public API.

* A scene file with ``thermostat: isokinetic`` runs from :meth:`Scene.from_yaml` and the command
  line, and gives the orbit :func:`simulate` gives for the scene built in Python.
* :func:`simulate_many` (record ``log``) logs and ends every orbit as :func:`simulate` does, bit
  for bit, on a plain table and on a lattice, both laws; the
  total kinetic energy ``|v|^2 + w^2`` of every final state is the start's to rounding.
* Zero speed is refused by name (it has no heading to keep); tools derived for free fall (the
  tangent maps, the energy-surface coordinates) refuse a thermostatted scene by name instead of
  answering for the wrong flight.

* The thermostat's own kernel variant gives the general path's outputs and log, bit for bit (as
  tests/test_ablation.py checks the other slots).

No kernel variant is compiled here beyond those of tests/test_thermostat_orbits.py (thermostatted,
record mode ``log``) and tests/test_ablation.py (the general path).
"""
import json
import math

import numpy as np
import pytest
from kernel_call import record_buffer, run_kernel

from noslipsim import Scene, simulate, simulate_many, tables
from noslipsim._engine.table import kernel_table
from noslipsim.analysis import lyapunov
from noslipsim.analysis.islands import finite_time_lyapunov, interior_starts
from noslipsim.analysis.section import energy_at
from noslipsim.cli import main
from noslipsim.core import layout, variant
from noslipsim.core.variant import GENERAL

DISK = 1 / math.sqrt(2)
SCENE_FILE = """\
law: no-slip
gamma: 0.7071067811865475
force: [0.3, -1.0]
thermostat: isokinetic
elements:
- {type: segment, p0: [-0.587785252292473, -0.8090169943749475],
   p1: [0.5877852522924731, -0.8090169943749475], side: left}
- {type: segment, p0: [0.5877852522924731, -0.8090169943749475],
   p1: [0.9510565162951535, 0.3090169943749474], side: left}
- {type: segment, p0: [0.9510565162951535, 0.3090169943749474], p1: [6.123233995736766e-17, 1.0], side: left}
- {type: segment, p0: [6.123233995736766e-17, 1.0], p1: [-0.9510565162951535, 0.3090169943749475], side: left}
- {type: segment, p0: [-0.9510565162951535, 0.3090169943749475],
   p1: [-0.587785252292473, -0.8090169943749475], side: left}
"""


def test_scene_file_runs_the_thermostat(tmp_path, capsys):
    path = tmp_path / "pentagon.yaml"
    path.write_text(SCENE_FILE)
    scene = Scene.from_yaml(str(path))
    assert scene == tables.regular_polygon(5).replace(force=(0.3, -1.0), thermostat="isokinetic")
    ds = simulate(scene, (0.1, 0.05), (0.83, 0.41), 0.2, max_collisions=200)
    assert json_scene(ds) == scene                   # the dataset records the thermostat
    kin = ds.vx ** 2 + ds.vy ** 2 + ds.spin ** 2
    assert float(np.abs(kin - kin[0]).max()) <= 1e-13 * float(kin[0])   # the bound of test_thermostat_orbits
    # the parabola of the same force would gain energy a . dq; the thermostat's orbit does not
    assert float(np.ptp(ds.y.values)) > 0.5
    out = tmp_path / "orbit.nc"
    assert main(["simulate", str(path), "--position", "0.1", "0.05", "--velocity", "0.83", "0.41",
                 "--spin", "0.2", "-n", "200", "-o", str(out)]) == 0
    import xarray as xr

    with xr.open_dataset(out) as cli:
        np.testing.assert_array_equal(cli.t.values, ds.t.values)
        np.testing.assert_array_equal(cli.x.values, ds.x.values)


def json_scene(ds):
    return Scene.from_dict(json.loads(ds.attrs["scene"]))


CASES = {
    "hex_gas_noslip": (tables.hex_lorentz_cell(0.45, force=(1.5, 0.4), gamma=DISK), "no-slip"),
    "sinai_box_specular": (tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.3)], force=(2.0, 0.7)), "specular"),
}


@pytest.mark.parametrize("name", list(CASES))
def test_simulate_many_ends_where_simulate_ends(name):
    base, law = CASES[name]
    scene = base.replace(law=law, thermostat="isokinetic")
    rng = np.random.default_rng(3)
    n = 6
    if scene.lattice is None:
        q = np.column_stack([rng.uniform(0.1, 0.5, n), rng.uniform(0.1, 0.9, n)])
    else:
        q = np.column_stack([np.zeros(n), rng.uniform(0.47, 0.5, n)])
    ang = rng.uniform(0, 2 * math.pi, n)
    v = np.column_stack([np.cos(ang), np.sin(ang)]) * rng.uniform(0.5, 2.0, n)[:, None]
    w = rng.uniform(-0.5, 0.5, n)
    # record "log": the kernel variant simulate runs (no extra compile); the finals and the log compared
    ens = simulate_many(scene, q, v, w, max_collisions=3000, record="log", scheduler="sync", progress=False)
    kin0 = (v ** 2).sum(axis=1) + w ** 2
    kin = ens.vx_final.values ** 2 + ens.vy_final.values ** 2 + ens.spin_final.values ** 2
    assert np.abs(kin / kin0 - 1.0).max() <= 1e-13
    for i in range(n):
        one = simulate(scene, q[i], v[i], w[i], max_collisions=3000)
        for var in ("t", "x", "y", "vx", "vy", "spin"):
            assert float(ens[f"{var}_final"][i]) == float(one[f"{var}_final"]), f"orbit {i} {var}"
            np.testing.assert_array_equal(ens[var].values[i, :int(one.n_collisions)], one[var].values)
        if scene.lattice is not None:
            assert int(ens.cell_a1_final[i]) == int(one.cell_a1_final)
    if scene.lattice is not None:   # the field drives a current along it (a . <v> > 0)
        drift = ens.x_final.values - q[:, 0]
        assert drift.mean() > 0.0


def test_zero_speed_is_refused_in_ensembles():
    scene = tables.hex_lorentz_cell(0.45, force=(1.5, 0.4)).replace(thermostat="isokinetic")
    with pytest.raises(ValueError, match=r"^velocities: orbit 1 has zero speed; the isokinetic thermostat"):
        simulate_many(scene, [[0.0, 0.48]] * 2, [[1.0, 0.0], [0.0, 0.0]], max_collisions=5, scheduler="sync",
                      progress=False)


def test_free_fall_tools_refuse_the_thermostat_by_name():
    scene = tables.sinai_torus(0.3, force=(0.5, 0.0)).replace(thermostat="isokinetic")
    msg = r"^scene: .* is derived for free fall under the force; it does not support thermostat 'isokinetic'"
    with pytest.raises(ValueError, match=msg):
        lyapunov(scene, (0.0, 0.5), (1.0, 0.2), n_collisions=100)
    with pytest.raises(ValueError, match=msg):
        finite_time_lyapunov(scene, [[0.0, 0.5]], [[1.0, 0.2]], n_collisions=100)
    with pytest.raises(ValueError, match=msg):
        energy_at(scene, (0.0, 0.5), (1.0, 0.0), 0.0)
    # without a force the thermostat is inert and the tools run
    assert lyapunov(scene.replace(force=(0.0, 0.0)), (0.0, 0.5), (1.0, 0.2), n_collisions=100) > 0


def test_interior_starts_follow_the_thermostatted_path():
    """Half-way along the first flight is on the closed-form path, not on the parabola."""
    scene = tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.3)], force=(2.0, 0.7), law="specular")
    therm = scene.replace(thermostat="isokinetic")
    states = {"positions": [[0.2, 0.2]], "velocities": [[0.6, 0.8]], "spins": [0.0]}
    mid = interior_starts(therm, states)
    assert math.hypot(*mid["velocities"][0]) == pytest.approx(1.0, rel=1e-15)   # speed kept
    a = simulate(therm, mid["positions"][0], mid["velocities"][0], 0.0, max_collisions=1)
    b = simulate(therm, (0.2, 0.2), (0.6, 0.8), 0.0, max_collisions=1)
    assert float(a.t[0]) == pytest.approx(0.5 * float(b.t[0]), rel=1e-12)
    assert float(a.x[0]) == pytest.approx(float(b.x[0]), rel=1e-12)


def test_thermostat_variant_bitwise_identical_to_general():
    scene = tables.regular_polygon(5, force=(0.3, -1.0), gamma=DISK).replace(thermostat="isokinetic")
    table = kernel_table(scene)
    own = table.variant(layout.RECORD_LOG)
    assert own.flight == variant.THERMOSTAT  # the flight slot: the thermostat's code
    n = 5000
    results = []
    for flags in (GENERAL, own):
        rec = record_buffer(layout.RECORD_LOG, n + 1, fill=-7.0)
        out = run_kernel(table, flags, (0.1, 0.05), (0.83, 0.41), 0.2, n, layout.RECORD_LOG, rec=rec)
        assert out[0] == n and out[3] == n   # full length, every row logged: not a vacuous comparison
        results.append((np.asarray(out, dtype=float).view(np.int64), rec.view(np.int64)))
    for out, rec in results[1:]:
        np.testing.assert_array_equal(out, results[0][0])
        np.testing.assert_array_equal(rec, results[0][1])
