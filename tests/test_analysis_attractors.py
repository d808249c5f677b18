"""Attracting cycles (noslipsim.analysis.attractors): an orbit that repeats is found, one that does not is not.

Oracles: a constructed cycle of period 7 reached by contraction (its period, not a multiple; a wrapped
coordinate compared modulo its period); a rotation by an irrational angle (regular, never repeating);
in the Sinai torus the head-on orbit (exactly 2-periodic in disk collisions), a perturbed head-on orbit on
an elliptic island (regular, not periodic) and a chaotic one (neither).
"""
import math

import numpy as np
import pytest
import xarray as xr

from noslipsim import simulate_many, tables
from noslipsim.analysis import attractor_census, attractor_labels, islands, orbit_period, portrait_attractors
from noslipsim.analysis.attractors import ATTRACTOR_TOLERANCE
from noslipsim.analysis.portraits import boundary_coordinate

RNG = np.random.default_rng(3)
CYCLE = RNG.uniform(-1.0, 1.0, size=(7, 3))


def contracting_orbit(cycle, n, rate=0.5, phase=0, offset=None):
    """``n`` states that fall onto ``cycle`` (repeated from ``phase``) with an error shrinking by ``rate`` a step."""
    k = np.arange(n)
    error = RNG.normal(size=(n, cycle.shape[1])) if offset is None else np.broadcast_to(offset, (n, cycle.shape[1]))
    return cycle[(k + phase) % len(cycle)] + rate ** k[:, None] * error


def test_a_contracting_cycle_has_its_period_not_a_multiple():
    assert orbit_period(contracting_orbit(CYCLE, 400)) == 7
    # NaN padding after the record is ignored
    padded = np.vstack([contracting_orbit(CYCLE, 400), np.full((50, 3), np.nan)])
    assert orbit_period(padded) == 7


def test_a_cycle_must_repeat_before_it_counts():
    # the error falls below the tolerance after ~7 steps: 24 states hold the cycle twice after it, not three times
    assert orbit_period(contracting_orbit(CYCLE, 24, rate=0.1), repeats=2) == 0
    assert orbit_period(contracting_orbit(CYCLE, 24, rate=0.1), repeats=1) == 7
    assert orbit_period(contracting_orbit(CYCLE, 40, rate=0.1), repeats=2) == 7
    # too slow a contraction for the record: not (yet) on the cycle
    assert orbit_period(contracting_orbit(CYCLE, 400, rate=0.99)) == 0


def test_a_wrapped_coordinate_is_compared_modulo_its_period():
    L = 2.0
    cycle = CYCLE.copy()
    cycle[0, 0] = L          # on the seam: the orbit lands at random just below L or just above 0
    orbit = contracting_orbit(cycle, 400, rate=1.0, offset=0.0)
    orbit[:, 0] = (orbit[:, 0] + 1e-9 * RNG.choice([-1.0, 1.0], size=400)) % L
    assert orbit_period(orbit, wrap=(L, None, None)) == 7
    assert orbit_period(orbit) == 0


def test_a_rotation_by_an_irrational_angle_is_regular_but_not_periodic():
    angle = 2 * math.pi * (math.sqrt(5) - 1) / 2 * np.arange(5000)
    assert orbit_period(np.c_[np.cos(angle), np.sin(angle)]) == 0


def test_labels_group_orbits_on_the_same_cycle_whatever_their_phase():
    other = RNG.uniform(-1.0, 1.0, size=(3, 3))
    orbits = [contracting_orbit(other, 300, phase=1), contracting_orbit(CYCLE, 300, phase=2),
              contracting_orbit(CYCLE, 300, phase=5), RNG.normal(size=(300, 3)),
              contracting_orbit(CYCLE, 300, phase=0), contracting_orbit(other, 300, phase=2)]
    periods = [orbit_period(x) for x in orbits]
    assert periods == [3, 7, 7, 0, 7, 3]
    labels = attractor_labels(orbits, periods)
    assert list(labels) == [1, 0, 0, -1, 0, 1]
    assert attractor_census(periods, labels) == [(7, 3), (3, 2)]
    assert attractor_census([0, 0], [-1, -1]) == []
    with pytest.raises(ValueError, match="period exactly"):
        attractor_census([3, 0], [-1, -1])


@pytest.mark.parametrize("bad", [{"tolerance": 0.0}, {"tolerance": math.nan}, {"repeats": 0},
                                 {"wrap": (1.0,)}, {"wrap": (-1.0, None, None)}])
def test_bad_input_is_refused(bad):
    with pytest.raises(ValueError):
        orbit_period(CYCLE, **bad)


def test_nan_inside_a_record_is_refused():
    x = contracting_orbit(CYCLE, 50)
    x[10] = np.nan
    with pytest.raises(ValueError, match="padding"):
        orbit_period(x)


def torus_portrait(gamma, starts, n_collisions=1200, radius=0.3):
    """A portrait dataset (dims orbit, point) of the Sinai torus from interior starts ``(q, v, w)``."""
    scene = tables.sinai_torus(radius, gamma=gamma)
    q, v, w = (np.array(a, dtype=float) for a in zip(*starts))
    rec = simulate_many(scene, q, v, w, max_collisions=n_collisions, record="portrait", scheduler="sync")
    coords = boundary_coordinate(rec, scene)
    return xr.Dataset({"s_boundary": coords.s_boundary, "vt_unit": rec.vt_unit, "w_unit": rec.w_unit,
                       "boundary_length": coords.attrs["boundary_length"]})


def test_in_the_sinai_torus_only_the_head_on_orbit_is_periodic():
    g0 = islands.head_on_onset_gamma(0.3)
    head_on = ((0.5, 0.0), (1.0, 0.0), 0.0)                 # 2-periodic between the disks at x = 0 and 1
    nudged = ((0.5, 0.001), (1.0, 0.001), 0.001)            # on the island above the onset, chaotic below
    cases = [torus_portrait(g0 + 0.1, [head_on, nudged]),
             torus_portrait(g0 - 0.1, [nudged, ((0.5, 0.2), (0.6, 0.8), 0.3)])]
    above = portrait_attractors(cases[0])
    assert list(above.attractor_period.values) == [2, 0]
    assert list(above.attractor.values) == [0, -1]
    below = portrait_attractors(cases[1])
    assert list(below.attractor_period.values) == [0, 0]
    assert above.attrs["attractor_tolerance"] == ATTRACTOR_TOLERANCE
    # case by case along two case dimensions, whatever order each variable's dims are stored in
    both = xr.concat(cases, dim="gamma", join="outer", fill_value=np.nan)
    both = xr.concat([both, both], dim="force")
    both["w_unit"] = both.w_unit.transpose("gamma", "force", "orbit", "point")     # s_boundary: force first
    found = portrait_attractors(both)
    assert found.attractor_period.dims == ("force", "gamma", "orbit")
    assert found.attractor_period.values.tolist() == [[[2, 0], [0, 0]]] * 2


def test_a_portrait_dataset_is_required():
    with pytest.raises(ValueError, match="portrait"):
        portrait_attractors(xr.Dataset({"s_boundary": ("orbit", [0.0])}))
