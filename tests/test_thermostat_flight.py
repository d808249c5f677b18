"""The thermostatted flight (core/thermostat.py): the closed form solves the equations, to rounding.

* The mpmath closed form (:class:`noslipsim.reference.thermostat.ThermoPath`) agrees with
  mpmath's Taylor integrator of ``dq/dt = v, dv/dt = F - (F.v/|v|^2) v`` itself, so it is the
  path of the Gaussian isokinetic thermostat (the oracle below is not a second copy of a formula).
* The float64 closed form agrees with it within a few eps of the flight's conditioned scale,
  across headings along, across and against the field (exactly and within 1e-15), fields from
  1e-6 to 1e3 and times from 1e-8 to 300 relaxation times ``1/k`` (where ``tan(phi/2)`` underflows).
* Speed and spin are constant in flight; the heading relaxes towards the field.
"""
import math

import mpmath
import numpy as np
import pytest

from noslipsim import Circle, Scene, tables
from noslipsim.core.thermostat import advance, drag, flight, state
from noslipsim.reference.thermostat import ThermoPath

EPS = 2.0 ** -52


def mp_path(ctx, x, y, vx, vy, ax, ay):
    return ThermoPath(ctx, *(ctx.mpf(float(a)) for a in (x, y, vx, vy, ax, ay)))


@pytest.mark.parametrize("phi0, E, c", [(2.0, 1.0, 1.0), (-0.3, 4.0, 0.7), (3.1, 0.5, 2.0), (1.5707963, 10.0, 1.0)])
def test_closed_form_solves_the_equations_of_motion(phi0, E, c):
    """The reference's closed form against mpmath's Taylor-series integration of the ODE (25 digits)."""
    ctx = mpmath.MPContext()
    ctx.dps = 25
    th = 0.4  # the field's direction
    ax, ay = E * math.cos(th), E * math.sin(th)
    vx, vy = c * math.cos(th + phi0), c * math.sin(th + phi0)
    path = mp_path(ctx, 0.1, -0.2, vx, vy, ax, ay)
    Ax, Ay = ctx.mpf(ax), ctx.mpf(ay)

    def rhs(t, s):
        _x, _y, u, w = s
        alpha = (Ax * u + Ay * w) / (u * u + w * w)
        return [u, w, Ax - alpha * u, Ay - alpha * w]

    sol = ctx.odefun(rhs, 0, [ctx.mpf(0.1), ctx.mpf(-0.2), ctx.mpf(vx), ctx.mpf(vy)])
    for t in (0.3, 1.0, 2.5):
        x, y, u, w = sol(ctx.mpf(t))
        px, py = path.position(ctx.mpf(t))
        pu, pw = path.velocity(ctx.mpf(t))
        assert max(abs(x - px), abs(y - py), abs(u - pu), abs(w - pw)) < 1e-18, t


def _cases(rng, n):
    """Random flights: general headings, near against / along / across the field, and exactly (anti)parallel."""
    for i in range(n):
        E = 10 ** rng.uniform(-6, 3)
        th = rng.uniform(0, 2 * np.pi)
        c = 10 ** rng.uniform(-2, 2)
        kind = i % 5
        phi = [rng.uniform(-np.pi, np.pi), np.pi - 10 ** rng.uniform(-15, -1), 10 ** rng.uniform(-15, -1),
               np.pi / 2 + 10 ** rng.uniform(-15, -1) * rng.choice([-1, 1]), rng.choice([0.0, np.pi])][kind]
        t = 10 ** rng.uniform(-8, 2.5) / (E / c)
        x, y = rng.uniform(-2, 2, 2)
        yield kind, (x, y, c * np.cos(th + phi), c * np.sin(th + phi), E * np.cos(th), E * np.sin(th)), t


def test_float_flight_matches_the_mpmath_path():
    """Position within 8 eps and velocity within 8 eps of what the start's own rounding allows.

    The scale of a position is ``|q0| + c t + |dq/dphi0| |sin phi0|`` (the heading ``phi0`` is
    formed to a few ulps of ``sin phi0``: near the unstable straight line against the field,
    ``dq/dphi0`` grows like ``exp(k t)``), of a velocity ``c + |dv/dphi0| |sin phi0| + |dv/dt| t``.
    """
    ctx = mpmath.MPContext()
    ctx.dps = 40
    rng = np.random.default_rng(20261201)
    worst = {}
    for kind, (x, y, vx, vy, ax, ay), t in _cases(rng, 1500):
        px, py, pvx, pvy = state(flight(x, y, vx, vy, ax, ay), t)
        path = mp_path(ctx, x, y, vx, vy, ax, ay)
        T = ctx.mpf(t)
        rx, ry = path.position(T)
        rvx, rvy = path.velocity(T)
        c, E = math.hypot(vx, vy), math.hypot(ax, ay)
        R = c * c / E
        dq = dv = 0.0
        if not path.straight:  # d q / d phi0 and d v / d phi0 of the closed form (docs/algorithm.md)
            u0 = path.u0
            e = ctx.exp(-path.k * T)
            S2, C2, SC = u0 * u0 / (1 + u0 * u0), 1 / (1 + u0 * u0), u0 / (1 + u0 * u0)
            D = C2 + S2 * e * e
            dq = float(ctx.hypot(R * SC * (1 - e * e) / D, R * (1 - e) * (C2 - S2 * e) / D))
            dv = float(c * e / D)
        s = abs(float(ctx.sin(path.phi0)))
        acc = float(ctx.hypot(*path.acceleration(T)))
        pos = float(max(abs(px - rx), abs(py - ry))) / (abs(x) + abs(y) + c * t + dq * s)
        vel = float(max(abs(pvx - rvx), abs(pvy - rvy))) / (c + dv * s + acc * t)
        worst[kind] = max(worst.get(kind, 0.0), pos / EPS, vel / EPS)
    print("worst error per kind of heading (eps of the conditioned scale):", worst)
    assert max(worst.values()) < 8.0, worst


def test_speed_is_constant_and_the_heading_turns_towards_the_field():
    rng = np.random.default_rng(3)
    for _, (x, y, vx, vy, ax, ay), t in _cases(rng, 300):
        fl = flight(x, y, vx, vy, ax, ay)
        c = math.hypot(vx, vy)
        cos0 = (vx * ax + vy * ay) / (c * math.hypot(ax, ay))
        for tt in (0.5 * t, t):
            _, _, ux, uy = state(fl, tt)
            assert abs(math.hypot(ux, uy) - c) <= 4 * EPS * c
            assert (ux * ax + uy * ay) / (c * math.hypot(ax, ay)) >= cos0 - 4 * EPS


def test_straight_flights_along_and_against_the_field():
    """An exactly (anti)parallel start is straight for ever (the unstable line is kept, not rounded off)."""
    for sign in (1.0, -1.0):
        fl = flight(0.5, 0.25, sign * 0.75, sign * 1.0, 3.0, 4.0)   # exactly parallel: 3 * 1 = 4 * 0.75
        for t in (0.1, 10.0, 1e4):
            assert state(fl, t) == (0.5 + t * sign * 0.75, 0.25 + t * sign * 1.0, sign * 0.75, sign * 1.0)


def test_weak_field_limit_is_the_straight_flight():
    """At field E the path leaves the straight line by at most E t^2 / 2 (the curvature bound), and does."""
    for E in (1e-3, 1e-6, 1e-9):
        x, y, _vx, _vy = advance(0.0, 0.0, 0.6, 0.8, E, 0.0, 2.0)
        dev = math.hypot(x - 1.2, y - 1.6)
        assert dev <= 0.5 * E * 4.0 * (1 + 1e-9)
        assert dev >= 0.1 * E  # the field does act


def test_drag_is_the_acceleration_perpendicular_to_the_velocity():
    ax_, ay_ = drag(0.6, 0.8, 3.0, -1.0)
    assert abs(ax_ * 0.6 + ay_ * 0.8) < 1e-15
    # |F - alpha v| = E |sin phi|
    assert math.isclose(math.hypot(ax_, ay_), abs(3.0 * 0.8 + 1.0 * 0.6), rel_tol=1e-14)


# ---------------------------------------------------------------------------- the scene field
def test_scene_thermostat_round_trips_and_is_refused_by_name(tmp_path):
    scene = tables.hex_lorentz_cell(0.4, force=(0.5, 0.0)).replace(thermostat="isokinetic")
    assert scene.thermostat == "isokinetic"
    d = scene.to_dict()
    assert d["thermostat"] == "isokinetic" and list(d)[:4] == ["law", "gamma", "force", "thermostat"]
    assert Scene.from_dict(d) == scene
    assert Scene.from_yaml(scene.to_yaml()) == scene
    plain = tables.hex_lorentz_cell(0.4)
    assert "thermostat" not in plain.to_dict()      # scene files without it are unchanged
    assert Scene(plain.elements, thermostat="none").thermostat is None
    with pytest.raises(ValueError, match=r"^thermostat: unknown thermostat 'nose-hoover'"):
        Scene((Circle((0, 0), 1.0, "inside"),), thermostat="nose-hoover")
    path = tmp_path / "scene.yaml"
    path.write_text("elements: [{type: circle, center: [0, 0], radius: 1, side: inside}]\nthermostat: 1\n")
    with pytest.raises(ValueError, match=r"scene.yaml: thermostat: unknown thermostat 1;"):
        Scene.from_yaml(str(path))


def test_zero_speed_is_refused_with_the_thermostat():
    from noslipsim import simulate

    scene = Scene((Circle((0, 0), 1.0, "inside"),), force=(0.0, -1.0), thermostat="isokinetic")
    with pytest.raises(ValueError, match=r"^velocity: the isokinetic thermostat keeps the speed"):
        simulate(scene, (0.0, 0.0), (0.0, 0.0), 0.3)
