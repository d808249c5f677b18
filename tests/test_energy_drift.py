"""Energy drift below 1e-12 per 10^6 collisions (issue 13, item 5; ``core/energy.py``).

The drift was a bias, not a random walk: each collision changed the energy by
1e-18 to 1e-16 relative *on average* (docs/algorithm.md section 0;
``benchmarks/energy_terms.py`` measures the terms: the law with normals and
``(c, s)`` unit only to rounding, the lean loop's Newton step, the projection
onto the element under a force).  The event loops now measure the energy every
``SETTLE_EVERY`` collisions and give back any excess above ``SETTLE_AT``.
Checked here: the first term exists (so the orbit tests are not vacuous),
``settle`` restores exactly what it should and nothing when it should not, and
orbits of every stress family stay within the bound pro rata (they drifted by
4e-13 to 1e-10 per 10^6 collisions before; the stress profile runs 10^6).
"""
import math
from fractions import Fraction

import numpy as np
import pytest
import test_stress as ts

from noslipsim import tables
from noslipsim._engine.table import kernel_table
from noslipsim.core import layout
from noslipsim.core.energy import (
    MAX_EXCESS,
    MAX_SETTLE,
    SETTLE_AT,
    SETTLE_EVERY,
    settle,
    state_energy,
)
from noslipsim.core.laws import collide
from noslipsim.simulate import run_one

#: Issue 13's bound on the drift of E = (|v|^2 + w^2)/2 - a.q per 10^6 collisions (relative).
DRIFT_PER_MILLION = 1e-12
#: Collisions per family in the default suite: an unkept orbit drifts past the pro-rata bound
#: (2e-13) in all but the wedge (measured before: 1e-12 to 2e-11 over 2e5 collisions).
N_DEFAULT = 200_000
N_STRESS = 1_000_000


def exact_energy(vx, vy, w):
    return Fraction(vx) ** 2 + Fraction(vy) ** 2 + Fraction(w) ** 2


def test_a_stored_normal_biases_the_law(rng):
    """The term that makes the drift linear: the pentagon's edge 1 has |n|^2 = 1 + 7.5e-18, and each
    specular hit gains 2 (|n|^2 - 1) on average (exact rational arithmetic)."""
    p = kernel_table(tables.regular_polygon(5)).arrays()[:2][1][1]
    nx, ny = -p[2], -p[3]
    delta = float(Fraction(nx) ** 2 + Fraction(ny) ** 2 - 1)
    assert delta > 7e-18
    gains = []
    for _ in range(3000):
        ang = rng.uniform(0.0, 2.0 * math.pi)
        vx, vy = math.cos(ang), math.sin(ang)
        if vx * nx + vy * ny < 0.0:
            vx, vy = -vx, -vy
        out = collide(layout.SPECULAR, 1.0, 0.0, vx, vy, 0.0, nx, ny)
        e0 = exact_energy(vx, vy, 0.0)
        gains.append(float((exact_energy(*out) - e0) / e0))
    gains = np.array(gains)
    assert gains.mean() == pytest.approx(2 * delta, rel=0.25)
    assert gains.mean() > 5 * gains.std() / math.sqrt(len(gains))


@pytest.mark.parametrize("spin", [False, True])
@pytest.mark.parametrize("force", [(0.0, 0.0), (0.3, -1.0)])
def test_settle_gives_back_an_excess(spin, force):
    ax, ay = force
    has_force = force != (0.0, 0.0)
    vx, vy, w, qx, qy = 0.6, -0.8, 0.3, 1.7, -2.5
    e0 = state_energy(vx, vy, w, spin, ax, ay, qx, qy, has_force)[0]
    f = 3e-13  # the state has gained 6e-13 of its kinetic energy
    bx, by, bw = vx * (1 + f), vy * (1 + f), (w * (1 + f) if spin else w)
    ox, oy, ow = settle(bx, by, bw, spin, ax, ay, qx, qy, has_force, e0)
    assert ow == w if not spin else abs(ow - w) < 1e-15
    kin0 = vx * vx + vy * vy + (w * w if spin else 0.0)
    e1 = state_energy(ox, oy, ow, spin, ax, ay, qx, qy, has_force)[0]
    assert abs(e1 - e0) < 4e-16 * (kin0 + 2 * abs(ax * qx + ay * qy))
    assert abs(ox * vy - oy * vx) < 1e-15  # the direction is kept: the state is only scaled


def test_settle_leaves_a_state_within_the_threshold_alone():
    vx, vy, w = 0.6, -0.8, 0.3
    e0 = state_energy(vx, vy, w, True, 0.0, 0.0, 0.0, 0.0, False)[0]
    g = 0.3 * SETTLE_AT
    out = settle(vx * (1 + g), vy * (1 + g), w * (1 + g), True, 0.0, 0.0, 0.0, 0.0, False, e0)
    assert out == (vx * (1 + g), vy * (1 + g), w * (1 + g))  # bit for bit
    # and a particle all but at rest, whose kinetic energy cannot take the potential's rounding
    slow = 1e-9
    e_far = state_energy(slow, 0.0, 0.0, False, 0.0, -1.0, 0.0, 5.0, True)[0] + 1e-6
    out = settle(slow, 0.0, 0.0, False, 0.0, -1.0, 0.0, 5.0, True, e_far)
    assert out == (slow, 0.0, 0.0) and MAX_SETTLE < 1.0


def test_settle_leaves_an_error_larger_than_rounding_for_the_tests_to_see():
    """Settling hides rounding, never a defect: a state 1e-10 off its energy keeps its error."""
    vx, vy, w = 0.6, -0.8, 0.3
    e0 = state_energy(vx, vy, w, True, 0.0, 0.0, 0.0, 0.0, False)[0]
    for g in (3 * MAX_EXCESS, 1e-6):
        state = (vx * (1 + g), vy * (1 + g), w * (1 + g))
        assert settle(*state, True, 0.0, 0.0, 0.0, 0.0, False, e0) == state
    g = 0.3 * MAX_EXCESS  # still given back below the bound
    state = (vx * (1 + g), vy * (1 + g), w * (1 + g))
    out = settle(*state, True, 0.0, 0.0, 0.0, 0.0, False, e0)
    assert abs(state_energy(*out, True, 0.0, 0.0, 0.0, 0.0, False)[0] - e0) < 1e-15


def test_settling_a_biased_sequence_does_not_drift(rng):
    """The projection is unbiased and carries nothing: a state given a one-signed kick of 1e-16
    (relative) at every step, settled every SETTLE_EVERY steps as the loops do, stays within
    SETTLE_AT plus one period's kicks for 10^5 steps, its error changes sign, and it does not
    grow (the error of the last 10^4 steps is no larger than that of the first)."""
    vx, vy, w = 0.6, -0.8, 0.3
    e0 = state_energy(vx, vy, w, True, 0.0, 0.0, 0.0, 0.0, False)[0]
    errs = []
    for n in range(1, 100_001):
        k = 5e-17 * (1.0 + rng.uniform())  # a biased "collision" (x + x k: a factor 1 + k would round to 1)
        vx, vy, w = vx + vx * k, vy + vy * k, w + w * k
        if n % SETTLE_EVERY == 0:
            vx, vy, w = settle(vx, vy, w, True, 0.0, 0.0, 0.0, 0.0, False, e0)
            errs.append(state_energy(vx, vy, w, True, 0.0, 0.0, 0.0, 0.0, False)[0] / e0 - 1.0)
    errs = np.array(errs)
    bound = SETTLE_AT + SETTLE_EVERY * 2 * 1e-16 * 2
    assert np.abs(errs).max() < bound
    assert errs.min() < 0.0 < errs.max() or np.abs(errs).max() < 4e-16
    assert np.abs(errs[-40:]).max() <= np.abs(errs[:40]).max() + 4e-16


def orbit_drift(name, n):
    """Relative change of E over one orbit of ``n`` collisions of a stress family (its own kernel)."""
    make, q, v, w = ts.chain_families()[name]
    scene = make()
    out = run_one(scene, np.asarray(q, float), np.asarray(v, float), float(w), n, math.inf, -math.inf,
                  layout.RECORD_NONE, np.zeros((0, layout.N_LOG)))
    assert out[0] == n
    _, x, y, vx, vy, w1 = out[4]
    ax, ay = scene.force
    e0 = 0.5 * (v[0] ** 2 + v[1] ** 2 + w * w) - (ax * q[0] + ay * q[1])
    kin = 0.5 * (vx * vx + vy * vy + w1 * w1)
    pot = -(ax * x + ay * y)
    return (kin + pot - e0) / max(abs(e0), kin, abs(pot))


@pytest.mark.parametrize("name", sorted(ts.chain_families()))
def test_orbit_energy_drift_below_bound(name):
    drift = orbit_drift(name, N_DEFAULT)
    assert abs(drift) < DRIFT_PER_MILLION * N_DEFAULT / 1e6, (name, drift)


@pytest.mark.stress
@pytest.mark.parametrize("name", sorted(ts.chain_families()))
def test_orbit_energy_drift_below_bound_stress(name):
    drift = orbit_drift(name, N_STRESS)
    assert abs(drift) < DRIFT_PER_MILLION * N_STRESS / 1e6, (name, drift)


@pytest.mark.parametrize("make", [lambda: tables.hex_lorentz_cell(0.3, gamma=0.5),
                                  lambda: tables.sinai_torus(0.3, gamma=0.5)], ids=["hex", "torus"])
def test_lean_loop_normals_do_not_bias_the_law(make):
    """The lean loop's no-slip normal ``h/|h|``, one Newton step from ``h/r``, biased each collision's
    ``|v|^2 + w^2`` by -1.1e-16 at r = 0.3 when its correction was rounded at 1; taken with fused
    multiply-adds, what is left is rounding of either sign, some 1e-18 on average.  At gamma = 1/2
    the rotation ``(c, s) = (0.6, 0.8)`` is unit to 1e-32, so only the normal is measured
    (extended precision over 3e5 collisions; standard error 4e-19)."""
    scene = make()
    n = 300_000
    rec = np.zeros((n, layout.N_LOG))
    out = run_one(scene, np.array([0.4, 0.1]), np.array([0.7, 0.31]), 0.2, n, math.inf, -math.inf,
                  layout.RECORD_LOG, rec)
    log = rec[:out[3]].astype(np.longdouble)
    k_in = log[:, layout.LOG_VX_IN] ** 2 + log[:, layout.LOG_VY_IN] ** 2 + log[:, layout.LOG_W_IN] ** 2
    k_out = log[:, layout.LOG_VX] ** 2 + log[:, layout.LOG_VY] ** 2 + log[:, layout.LOG_W] ** 2
    bias = float(np.mean((k_out - k_in) / k_in))
    assert abs(bias) < 2e-17, bias
