"""The portrait experiments (Figures 10-13): portrait_set and its users, the closed hexagonal cell, islands."""
import json
import math

import numpy as np
import pytest

from noslipsim import Scene, simulate, tables
from noslipsim.analysis import islands
from noslipsim.experiments import (
    DISSIPATIVE_READINGS,
    HEX_READINGS,
    hex_force_portraits,
    hex_force_readings,
    hex_reading_scene,
    lemon_sinai_portraits,
    polygon_portraits,
    portrait_set,
    sinai_gamma_portraits,
    sinai_islands_sweep,
)

TOL = 1e-9


def check_portrait_values(ds):
    r = np.hypot(ds.vt_unit.values, ds.w_unit.values)
    assert (r[np.isfinite(r)] <= 1 + TOL).all()
    s = ds.s_boundary.values
    L = ds.boundary_length.values.reshape((*ds.boundary_length.shape, 1, 1))
    assert ((s >= -TOL) & (s <= L + TOL))[np.isfinite(s)].all()
    # a point is either wholly recorded or padding
    assert (np.isfinite(ds.vt_unit.values) == np.isfinite(ds.s_boundary.values)).all()
    assert (np.isfinite(ds.vt_unit.values).sum(axis=-1) == ds.n_points.values).all()


def test_portrait_set_stacks_cases_with_the_same_scaled_starts():
    scenes = [tables.sinai_torus(0.3, gamma=g) for g in (0.0, 1.0)]
    ds = portrait_set(scenes, [0.0, 1.0], dim="gamma", n_orbits=5, n_collisions=50, seed=3, lyapunov_collisions=40)
    assert dict(ds.sizes) == {"gamma": 2, "orbit": 5, "point": 50}
    check_portrait_values(ds)
    st = islands.uniform_reduced_states(scenes[0], 5, 3)
    assert np.allclose(ds.spin_start.isel(gamma=0), st["spins"]) and np.allclose(ds.spin_start.isel(gamma=1),
                                                                                   st["spins"])
    assert "regular" not in ds  # a reading of the exponents, made by classify_regular
    flagged = islands.classify_regular(ds, 0.05)
    assert flagged.regular.dtype == np.int8 and flagged.attrs["regular_threshold"] == 0.05
    assert (flagged.regular.values == (ds.ftle.values < 0.05)).all()
    assert Scene.from_dict(json.loads(str(ds.scene.values[1]))).gamma == 1.0
    assert "sin_angle" not in ds and ds.attrs["lyapunov_collisions"] == 40


def test_portrait_set_follows_the_orbit_of_its_interior_start():
    scene = tables.regular_polygon(6)
    ds = portrait_set([scene], ["hexagon"], dim="table", n_orbits=3, n_collisions=20, seed=1)
    case = ds.sel(table="hexagon")
    for i in range(3):
        o = simulate(scene, (float(case.x_start[i]), float(case.y_start[i])),
                     (float(case.vx_start[i]), float(case.vy_start[i])), float(case.spin_start[i]), max_collisions=20)
        assert np.allclose(o.element.values, case.element.values[i])
        assert int(case.n_points[i]) == 20


def test_specular_and_noslip_cases_mix_with_birkhoff_p_only_where_it_means_something():
    ds = lemon_sinai_portraits(n_orbits=4, n_collisions=60, lyapunov_collisions=50, sinai_radius=0.4)
    check_portrait_values(ds)
    lemon, sinai = ds.sel(table="lemon"), ds.sel(table="sinai")
    p = lemon.sin_angle.values
    assert (np.abs(p[np.isfinite(p)]) <= 1).all() and np.isfinite(p).any()
    assert np.isnan(sinai.sin_angle.values).all()
    assert (lemon.w_unit.values[np.isfinite(lemon.w_unit.values)] == 0).all()   # specular: no spin
    assert str(lemon.law.values) == "specular" and math.isnan(float(lemon.gamma))
    # specular Birkhoff p is the tangential part of the unit velocity (w = 0)
    vt = lemon.vt_unit.values
    assert np.allclose(np.abs(p), np.abs(vt), equal_nan=True)


def test_portrait_set_refuses_bad_input():
    sc = tables.sinai_torus(0.3)
    with pytest.raises(ValueError, match="labels"):
        portrait_set([sc], [1, 2])
    with pytest.raises(ValueError, match="dim"):
        portrait_set([sc], [1], dim="orbit")
    with pytest.raises(ValueError, match="scenes"):
        portrait_set(["torus"], [1])
    with pytest.raises(ValueError, match="n_orbits"):
        portrait_set([sc], [1], n_orbits=0)
    with pytest.raises(ValueError, match="lyapunov_collisions"):
        portrait_set([sc], [1], lyapunov_collisions=3)


def test_polygons_and_gamma_portraits_have_their_coordinates():
    ds = polygon_portraits(sides=(4, 6), aspect=1.5, n_orbits=3, n_collisions=40)
    assert ds.table.values.tolist() == ["rectangle", "hexagon"] and ds.sides.values.tolist() == [4, 6]
    rect = Scene.from_dict(json.loads(str(ds.scene.sel(table="rectangle").values)))
    assert rect.elements[1].p0 == (1.5, 0.0)
    check_portrait_values(ds)
    with pytest.raises(ValueError, match="sides"):
        polygon_portraits(sides=(2,))
    g = sinai_gamma_portraits((0.0, 0.5), radius=0.3, n_orbits=3, n_collisions=30, lyapunov_collisions=20)
    assert g.gamma.values.tolist() == [0.0, 0.5] and g.attrs["radius"] == 0.3
    # gamma = 0: the spin only flips sign, so |w| stays that of the start on every point
    w = np.abs(g.w_unit.sel(gamma=0.0).values)
    assert np.allclose(np.nanmax(w, axis=1), np.nanmin(w, axis=1), atol=1e-12)


def test_closed_hex_cell_is_the_wigner_seitz_cell_with_walls():
    cell = tables.closed_hex_cell(0.3)
    assert len(cell.elements) == 7 and cell.lattice is None
    inside = np.array([[0.49, 0.0], [-0.49, 0.0], [0.0, 0.57], [0.0, -0.57], [0.0, 0.31]])
    outside = np.array([[0.51, 0.0], [0.0, 0.6], [0.0, 0.29], [0.45, 0.45]])
    assert cell.contains(inside).all() and not cell.contains(outside).any()
    v = np.array([[e.p0[0], e.p0[1]] for e in cell.elements[:6]])
    assert np.allclose(np.hypot(*v.T), 1 / math.sqrt(3)) and np.isclose(v[:, 1].max(), 1 / math.sqrt(3))
    for bad in (0.0, 0.5):
        with pytest.raises(ValueError, match="radius"):
            tables.closed_hex_cell(bad)
    # under a force the energy is conserved and bounds the height the particle reaches
    o = simulate(tables.closed_hex_cell(0.3, force=(0.0, -4.0)), (0.0, 0.45), (0.6, 0.8), 0.1, max_collisions=2000)
    assert np.ptp(o.energy.values) < 1e-9 * abs(float(o.energy[0])) + 1e-12
    assert (np.abs(o.x.values) <= 0.5 + 1e-9).all()


def test_hex_force_energy_grows_in_the_periodic_gas_and_stays_bounded_in_the_closed_cell():
    ds = hex_force_portraits(gammas=(1.0,), forces=(0.0, 1.0), n_orbits=6, n_collisions=1500,
                             lyapunov_collisions=20)
    assert dict(ds.sizes)["cell"] == 2 and ds.force.values.tolist() == [0.0, 1.0]
    check_portrait_values(ds)
    assert set(np.unique(ds.element.values[np.isfinite(ds.element.values)])) == {6.0}   # the disk only
    kin = ds.kinetic_final.sel(gamma=1.0)
    assert np.allclose(kin.sel(force=0.0).values, 0.5, atol=1e-12)          # no force: kinetic energy kept
    closed, periodic = kin.sel(force=1.0, cell="closed").values, kin.sel(force=1.0, cell="periodic").values
    height = 2 / math.sqrt(3)                                               # vertex to vertex
    assert (closed <= 0.5 + 1.0 * height + 1e-9).all()                      # E bounds it
    assert np.median(periodic) > 5 * np.median(closed)                      # the particle falls through the gas
    with pytest.raises(ValueError, match="forces"):
        hex_force_portraits(forces=(-1.0,))
    with pytest.raises(ValueError, match="reading"):
        hex_force_portraits(reading="closed box")


def test_hex_readings_are_the_tables_they_claim():
    for reading in HEX_READINGS:
        scene, disk = hex_reading_scene(reading, 0.4, 1.0, 2.0)
        assert scene.elements[disk].radius == 0.4 and scene.force == (0.0, -2.0)
        assert (scene.lattice is None) == (reading in ("closed", "specular_walls"))
        # the disk is no-slip in every reading of Figure 13, specular in the gas the caption compares with
        assert scene.element_laws[disk] == ("specular" if reading == "specular_thermostat" else "no-slip")
        walls = {law for i, law in enumerate(scene.element_laws) if i != disk}
        assert walls <= ({"specular"} if reading == "specular_walls" else {"no-slip"})
        assert scene.mixed_laws == (reading == "specular_walls")
        assert (scene.thermostat == "isokinetic") == (reading in DISSIPATIVE_READINGS)
    assert hex_reading_scene("periodic", 0.4, 1.0, 0.0)[0].force == (0.0, 0.0)


def test_thermostatted_portrait_keeps_the_speed_between_collisions_and_records_the_disk():
    """Figure 13's reading: the kinetic energy (|v|^2 + w^2)/2 is kept exactly by the thermostat and the law."""
    ds = hex_force_portraits(gammas=(1.0,), forces=(0.0, 4.0), reading="thermostat", n_orbits=4, n_collisions=300,
                             lyapunov_collisions=40, energy_collisions=20)
    assert ds.attrs["reading"] == "thermostat" and np.isfinite(ds.ftle).all()
    assert set(np.unique(ds.element.values[np.isfinite(ds.element.values)])) == {0.0}   # the disk of the lattice
    check_portrait_values(ds)
    scene = Scene.from_dict(json.loads(str(ds.scene.sel(force=4.0).item())))
    assert scene.thermostat == "isokinetic" and scene.lattice is not None
    st = islands.uniform_reduced_states(scene, 3, seed=0, elements=[0])
    for i in range(3):
        o = simulate(scene, st["positions"][i] * 1.001, st["velocities"][i], st["spins"][i], max_collisions=400)
        kin = 0.5 * (o.vx.values ** 2 + o.vy.values ** 2 + o.spin.values ** 2)
        assert np.ptp(kin) < 1e-12


def test_hex_force_readings_tiny_and_what_tells_them_apart():
    """The sweep's layout; the cell of specular walls around the no-slip disk depends on gamma (the disk's);
    at a strong field the thermostatted gas settles on regular attractors (negative or zero exponents) where
    that cell stays chaotic."""
    ds = hex_force_readings(gammas=(0.5, 1.0), forces=(0.0, 16.0), readings=("specular_walls", "thermostat"),
                            n_orbits=6, lyapunov_collisions=600, seed=1)
    assert ds.ftle.dims == ("reading", "gamma", "force", "orbit") and ds.sizes["orbit"] == 6
    assert ds.reading_table.values.tolist() == [HEX_READINGS["specular_walls"], HEX_READINGS["thermostat"]]
    walls = ds.ftle.sel(reading="specular_walls")
    assert np.all(np.abs(walls.sel(gamma=0.5) - walls.sel(gamma=1.0)) > 1e-3)   # measured: 0.009 to 0.56 apart
    assert (walls.sel(force=16.0) > islands.REGULAR_THRESHOLD).all()   # measured 0.27 to 0.41
    strong = ds.ftle.sel(reading="thermostat", gamma=1.0, force=16.0)
    assert islands.regular_share(strong.values)[0] >= 0.8           # measured 0.95 over 40 orbits
    for bad in ({"readings": ("closed", "closed")}, {"readings": ("box",)}, {"forces": (0.0, 0.0)},
                {"n_orbits": 0}):
        with pytest.raises(ValueError):
            hex_force_readings(**bad)


def test_hex_force_readings_find_the_attracting_cycles_of_the_thermostatted_gas():
    """At g = 8 the no-slip gas at gamma = 1 ends on 3-cycles (a mirror pair) and the specular gas on one
    2-cycle (measured over 100 orbits at paper size); the closed cell conserves phase volume and is not searched."""
    ds = hex_force_readings(gammas=(1 / math.sqrt(2), 1.0), forces=(8.0,),
                            readings=("closed", "thermostat", "specular_thermostat"), n_orbits=6,
                            lyapunov_collisions=100, attractor_collisions=600, seed=14)
    assert ds.attractor_period.dims == ("reading", "gamma", "force", "orbit")
    assert ds.attrs["attractor_collisions"] == 600
    no_slip = ds.sel(reading="thermostat", gamma=1.0, force=8.0)
    assert (no_slip.attractor_period == 3).all() and set(no_slip.attractor.values) <= {0, 1}
    specular = ds.sel(reading="specular_thermostat", force=8.0)
    assert (specular.attractor_period == 2).all() and (specular.attractor == 0).all()
    # gamma plays no part in the specular gas: one run, repeated along gamma
    assert np.array_equal(specular.ftle.isel(gamma=0), specular.ftle.isel(gamma=1))
    closed = ds.sel(reading="closed")
    assert (closed.attractor_period == 0).all() and (closed.attractor == -1).all()
    assert "attractor_period" not in hex_force_readings(gammas=(1.0,), forces=(0.0,), readings=("closed",),
                                                        n_orbits=2, lyapunov_collisions=20)
    with pytest.raises(ValueError, match="attractor_collisions"):
        hex_force_readings(attractor_collisions=0)


def test_islands_sweep_shares_agree_with_its_exponents_and_the_theory():
    ds = islands.islands_onsets(sinai_islands_sweep(radii=(0.45,), gammas=(0.0, 0.6, 1.0), n_orbits=40,
                                                    n_collisions=300, seed=2), 0.03).isel(radius=0)
    share, _, n = islands.regular_share(ds.ftle.values, 0.03)
    assert np.allclose(ds.share_regular.values, share) and (ds.n_valid.values == n).all()
    assert float(ds.share_regular.sel(gamma=0.0)) == 0.0 and float(ds.share_regular.sel(gamma=1.0)) > 0.1
    assert float(ds.head_on_onset) == pytest.approx(islands.head_on_onset_gamma(0.45))
    assert 0.0 < float(ds.onset_gamma) <= 0.6
    assert float(ds.onset_gamma_low) <= float(ds.onset_gamma_high)
    with pytest.raises(ValueError, match="gammas"):
        sinai_islands_sweep(gammas=(0.5, 0.2), n_orbits=2)
    with pytest.raises(ValueError, match="radii"):
        sinai_islands_sweep(radii=(0.3, 0.3), n_orbits=2)
