"""The explorer's server-side state: launches land where the click says, orbits are the kernel's, requests are capped.

Oracles: :func:`noslipsim.simulate` (an explorer orbit is the same orbit,
however often it was refilled); the portrait coordinates of the launched
state, computed back by :func:`noslipsim.analysis.log_portrait.log_portrait`
(a click at ``(x, y)`` launches the state whose portrait point is ``(x, y)``);
the scene's depth (a step lands the particle on the wall).  No browser here
(tests/test_explorer_browser.py drives the page).
"""
import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("panel", reason="the explorer needs the 'explore' extra (Panel, Bokeh)")

from invariants import cyclotron_miss

import noslipsim as ns
from noslipsim import tables
from noslipsim.analysis.log_portrait import log_portrait
from noslipsim.explorer.session import FIRST_BUDGET, TRAIL_POINTS, Explorer, Limits

ROOT = Path(__file__).resolve().parents[1]
BOX = ns.Scene.from_yaml(str(ROOT / "examples" / "sinai_box.yaml"))
MAGNETIC = ns.Scene.from_yaml(str(ROOT / "examples" / "magnetic_sinai.yaml"))  # the box in a field W = 1
LEMON = tables.lemon(1.0, 1.0)  # specular: the Birkhoff portrait


def _log(scene, start, n):
    return ns.simulate(scene, start["position"], start["velocity"], start["spin"], max_collisions=n)


def test_an_orbit_is_the_kernels_orbit_through_every_refill():
    ex = Explorer(BOX)
    o = ex.launch([0.1, 0.1], [0.6, 0.8])
    assert o.collisions == FIRST_BUDGET and o.budget == FIRST_BUDGET
    ex.set_speed(1000.0)
    for _ in range(3):
        ex.advance(1.0)  # the clock runs past the computed part: refilled, budget doubled
    assert o.budget >= 4 * FIRST_BUDGET
    ref = _log(BOX, o.start, o.collisions)
    for k in ("t", "x", "y", "vx", "vy", "spin"):
        np.testing.assert_array_equal(o.nodes[k][1:], ref[k].values, err_msg=k)
    e = o.energy
    assert np.max(np.abs(e - e[0])) < 1e-12


def test_a_click_in_the_birkhoff_portrait_launches_that_point():
    ex = Explorer(LEMON)
    assert ex.portrait == "birkhoff"
    s, p = 1.3, -0.42
    o = ex.launch_from_portrait(s, p, speed=2.0)
    st = o.start
    assert st["element"] >= 0 and math.hypot(*st["velocity"]) == pytest.approx(2.0)
    # the launched state, read as a post-collision state on its element, has portrait coordinates (s, p)
    e = LEMON.elements[st["element"]]
    theta = math.atan2(st["position"][1] - e.center[1], st["position"][0] - e.center[0]) % (2 * math.pi)
    local = e.radius * ((theta - e.theta0) % (2 * math.pi))
    x, y = log_portrait(LEMON, [st["element"]], [local], [st["velocity"][0]], [st["velocity"][1]], [0.0], "birkhoff")
    assert x[0] == pytest.approx(s, abs=1e-12) and y[0] == pytest.approx(p, abs=1e-12)


def test_a_click_in_the_velocity_portrait_launches_that_point_from_the_launch_mark():
    ex = Explorer(BOX)
    assert ex.portrait == "velocity"
    vt, w = 0.31, -0.52
    o = ex.launch_from_portrait(vt, w, speed=1.0, s_launch=0.25)  # a quarter along the bottom wall
    st = o.start
    assert st["element"] == 0 and st["position"] == pytest.approx([0.25, 0.0], abs=1e-15)
    x, y = log_portrait(BOX, [0], [0.25], [st["velocity"][0]], [st["velocity"][1]], [st["spin"]], "velocity")
    assert x[0] == pytest.approx(vt, abs=1e-14) and y[0] == pytest.approx(w, abs=1e-14)
    ref = ns.simulate_many(BOX, [st["position"]], [st["velocity"]], [st["spin"]], start_elements=[0],
                           max_collisions=50, record="log", scheduler="sync")
    np.testing.assert_array_equal(o.nodes["x"][1:51], ref.x.values[0])


def test_a_drag_launches_a_parallel_beam_centred_on_its_start():
    ex = Explorer(BOX)
    orbits = ex.launch_beam((0.1, 0.15), (0.4, 0.55), n=5, speed=2.0, width=0.04)
    assert len(orbits) == 5
    u = np.array([0.3, 0.4]) / 0.5
    starts = np.array([o.start["position"] for o in orbits])
    for o in orbits:
        np.testing.assert_allclose(o.start["velocity"], 2.0 * u, rtol=1e-15)
    np.testing.assert_allclose(starts.mean(axis=0), [0.1, 0.15], atol=1e-15)
    across = (starts - [0.1, 0.15]) @ np.array([-u[1], u[0]])
    np.testing.assert_allclose(np.diff(across), 0.01, rtol=1e-12)  # spread across the direction, 0.04 in all
    np.testing.assert_allclose((starts - [0.1, 0.15]) @ u, 0.0, atol=1e-15)


def test_beam_starts_outside_the_table_are_left_out_and_said():
    ex = Explorer(BOX)
    orbits = ex.launch_beam((0.5, 0.19), (1.0, 0.19), n=3, width=0.04)  # y = 0.17, 0.19, 0.21: the last in the disk
    assert len(orbits) == 2 and "1 of the beam's 3 starts lie outside" in ex.message


@pytest.mark.parametrize("request_, message", [
    (lambda ex: ex.launch_beam((0.1, 0.1), (0.2, 0.2), n=101), "at most 100 per launch"),
    (lambda ex: ex.launch_beam((0.1, 0.1), (0.1, 0.1)), "give the direction by dragging"),
    (lambda ex: ex.launch_beam((0.5, 0.5), (0.6, 0.6)), "not inside the table"),
    (lambda ex: ex.launch_beam((0.1, 0.1), (0.2, 0.2), speed=0.0), "launch speed: must be > 0"),
    (lambda ex: ex.launch_from_portrait(0.9, 0.5), "outside the unit disk"),
    (lambda ex: ex.launch_from_portrait(0.1, 0.1, s_launch=99.0), "launch point s: must lie in"),
    (lambda ex: ex.set_speed(1e9), "speed: must be in"),
    (lambda ex: ex.set_speed(float("nan")), "speed: must be finite"),
    (lambda ex: ex.set_physics(force_strength=-1.0), r"the strength must be in \[0, 1000\], got -1"),
    (lambda ex: ex.set_physics(force_strength=1e9), r"the strength must be in \[0, 1000\], got 1e\+09"),
    (lambda ex: ex.set_physics(gamma=150.0), "gamma: must be <= 100 here, got 150"),
    (lambda ex: ex.set_physics(gamma=-0.5), "gamma: must be >= 0"),
])
def test_refused_requests_say_why_in_one_line(request_, message):
    ex = Explorer(BOX)
    with pytest.raises(ValueError, match=message) as err:
        request_(ex)
    assert "\n" not in str(err.value)
    assert ex.orbits == []


def test_orbits_alive_are_capped():
    ex = Explorer(BOX, Limits(max_orbits=6, max_beam=5))
    ex.launch_beam((0.1, 0.1), (0.2, 0.2), n=5, width=0.02)
    with pytest.raises(ValueError, match=r"at most 6 orbits at once \(5 running, 2 asked for\); press reset"):
        ex.launch_beam((0.1, 0.1), (0.2, 0.2), n=2, width=0.02)
    assert len(ex.orbits) == 5
    ex.reset()
    assert ex.orbits == [] and ex.clock == 0.0


def test_collisions_per_orbit_and_per_frame_are_capped():
    ex = Explorer(BOX, Limits(max_collisions=1500, frame_collisions=2000))
    a = ex.launch([0.1, 0.1], [0.6, 0.8])
    b = ex.launch([0.9, 0.1], [-0.6, 0.8])
    ex.set_speed(5000.0)
    ex.advance(1.0)  # both need a refill of 1500; the frame's budget of 2000 covers one
    assert sorted([a.budget, b.budget]) == [1000, 1500]
    ex.advance(1.0)
    assert a.budget == b.budget == 1500 and a.collisions == b.collisions == 1500
    assert a.stop_reason == b.stop_reason == "limit" and a.complete


def test_the_frame_streams_each_collision_once_and_steps_land_on_the_wall():
    ex = Explorer(BOX)
    o = ex.launch([0.1, 0.1], [0.6, 0.8])
    sent = 0
    for _ in range(5):
        frame = ex.step()
        sent += len(frame["portrait"]["x"])
        p = frame["particles"]
        assert abs(BOX.depth(np.array([[p["x"][0], p["y"][0]]]))[0]) < 1e-12  # drawn on the wall it hits
    assert sent == 5 == ex.readout()["collisions"]
    np.testing.assert_array_equal(frame["portrait"]["x"], o.marks[0][4:5])
    assert ex.readout()["energy_error"] < 1e-14


def test_changing_the_law_recomputes_the_orbits_and_switches_the_portrait():
    ex = Explorer(BOX)
    o = ex.launch([0.1, 0.1], [0.6, 0.8])
    ex.advance(3.0)
    ex.set_physics(law="specular")
    assert ex.portrait == "birkhoff" and ex.clock == 0.0
    (o2,) = ex.orbits
    assert o2.start == o.start
    ref = ns.simulate(BOX.replace(law="specular"), [0.1, 0.1], [0.6, 0.8], max_collisions=20)
    np.testing.assert_array_equal(o2.nodes["x"][1:21], ref.x.values)
    ex.set_physics(force_strength=0.5)  # along gravity for a scene without force
    assert ex.scene.force == (0.0, -0.5)


def test_a_magnetic_scene_is_drawn_on_its_cyclotron_arcs():
    """The particle and every trail segment's ends lie on the circle of their flight (not on chords)."""
    ex = Explorer(MAGNETIC)
    o = ex.launch([0.1, 0.1], [0.6, 0.8])
    ex.set_speed(2.0)
    for _ in range(3):
        frame = ex.advance(1.0)
        nd, tau = o.nodes, ex.clock - o.born
        p = frame["particles"]
        assert cyclotron_miss(nd, [tau], p["x"], p["y"], MAGNETIC.magnetic) < 1e-9
        tr = frame["trails"]
        rows = len(tr["x0"]) // (TRAIL_POINTS - 1)  # one row of TRAIL_POINTS - 1 segments per flight drawn
        assert rows * (TRAIL_POINTS - 1) == len(tr["x0"]) and rows >= 2
        k = int(np.searchsorted(nd["t"], tau, side="right")) - 1
        t_of = np.repeat(nd["t"][k - rows + 1:k + 1], TRAIL_POINTS - 1)  # selects each segment's flight
        for x, y in ((tr["x0"], tr["y0"]), (tr["x1"], tr["y1"])):
            assert cyclotron_miss(nd, t_of, x, y, MAGNETIC.magnetic) < 1e-9
    ref = _log(MAGNETIC, o.start, 50)
    np.testing.assert_array_equal(o.nodes["x"][1:51], ref.x.values)
    assert ex.readout()["energy_error"] < 1e-13  # (|v|^2 + w^2)/2: a field does no work


def test_a_field_keeps_through_law_changes_and_refuses_a_force_by_name():
    ex = Explorer(MAGNETIC)
    ex.launch([0.1, 0.1], [0.6, 0.8])
    assert not ex.force_allowed and ex.scene.magnetic == 1.0
    with pytest.raises(ValueError, match=r"^force: this table has a magnetic field \(magnetic = 1\), which takes "
                                         r"no force; the force stays 0$"):
        ex.set_physics(force_strength=0.5)
    assert ex.scene == MAGNETIC and len(ex.orbits) == 1
    ex.set_physics(law="no-slip", gamma=0.5, force_strength=0.0)
    assert ex.scene.magnetic == 1.0 and ex.scene.law == "no-slip" and ex.scene.force == (0.0, 0.0)
    ex.warm()  # the strengths a page could ask for with a field: 0 only, nothing refused raised
    assert Explorer(BOX).force_allowed


def test_the_page_of_a_magnetic_table_turns_the_force_control_off_and_shows_the_field():
    from noslipsim.explorer.app import ExplorerApp

    app = ExplorerApp(MAGNETIC)
    assert app.force.disabled and "magnetic field" in app.force.name
    assert "magnetic = 1" in app.readout.object and not app.arrow.visible
    app.force.value = 0.5  # a value sent through the websocket all the same: said, and put back
    assert app.force.value == 0.0 and app.model.scene == MAGNETIC
    assert app.alert.visible and "which takes no force" in app.alert.object
    plain = ExplorerApp(BOX)
    assert not plain.force.disabled and "magnetic" not in plain.readout.object


def test_a_periodic_scene_is_drawn_folded_into_cell_zero():
    scene = tables.sinai_torus(0.25)
    ex = Explorer(scene)
    ex.launch([0.4, 0.1], [0.6, 0.8])
    ex.set_speed(50.0)
    frame = ex.advance(1.0)
    x, y = frame["particles"]["x"][0], frame["particles"]["y"][0]
    assert -0.5 <= x <= 0.5 and -0.5 <= y <= 0.5
    t = frame["trails"]
    assert len(t["x0"]) > 0 and np.max(np.abs(t["x0"])) <= 0.5 and np.max(np.abs(t["y0"])) <= 0.5


def test_the_server_accepts_only_its_own_origin_and_reads_only_its_scene(tmp_path, capsys):
    from noslipsim.cli import main
    from noslipsim.explorer.server import allowed_hosts, load_scene

    assert allowed_hosts("127.0.0.1", 5006) == ["127.0.0.1:5006", "localhost:5006"]
    assert allowed_hosts("192.0.2.7", 80, ["192.0.2.7"]) == ["192.0.2.7:80"]
    assert allowed_hosts("0.0.0.0", 5006, ["Box.LAN", "localhost:8000"]) == [
        "127.0.0.1:5006", "box.lan:5006", "localhost:5006", "localhost:8000"]
    bad = tmp_path / "bad.yaml"
    bad.write_text("law: no-slip\nelements:\n  - {type: circle, center: [0, 0], radius: -1, side: inside}\n")
    scene, error = load_scene(bad)
    assert scene is None
    assert main(["simulate", str(bad), "--position", "0", "0", "--velocity", "1", "0"]) == 2
    assert error == capsys.readouterr().err.strip()  # the page shows the CLI's line


def test_the_portrait_raster_paints_each_point_at_its_pixel_in_its_colour():
    from noslipsim.explorer.raster import PortraitRaster

    r = PortraitRaster((-1.0, 1.0, -1.0, 1.0), ["#ff0000", "#00ff00"], size=10, dot=1)
    r.paint([-0.95, 0.55, 0.0, 5.0], [-0.95, 0.05, 0.99, 0.0], [0, 1, 0, 1])  # the last lies outside: dropped
    assert r.points == 3 and np.count_nonzero(r.image) == 3
    red, green = 0xFF0000FF, 0xFF00FF00  # RGBA bytes little-endian: R in the lowest byte
    assert r.image[0, 0] == red and r.image[5, 7] == green and r.image[9, 5] == red
    r.paint([0.55], [0.05], [0])  # the latest point is on top
    assert r.image[5, 7] == red
    r.clear()
    assert r.points == 0 and not r.image.any()


def test_the_command_serves_the_page_on_the_loopback_address():
    """``noslipsim explore`` from a fresh process: the line it prints names 127.0.0.1, and that URL serves the app."""
    import re
    import subprocess
    import sys
    import time
    import urllib.request

    scene_file = str(ROOT / "examples" / "sinai_box.yaml")
    argv = [sys.executable, "-m", "noslipsim.cli", "explore", scene_file, "--port", "0", "--no-browser"]
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().startswith("noslipsim explore: compiling kernels")
        line = proc.stdout.readline()
        url = re.search(r"http://127\.0\.0\.1:\d+/", line)
        assert url, line
        end, page = time.monotonic() + 120, None
        while page is None and time.monotonic() < end:
            try:
                page = urllib.request.urlopen(url.group(0), timeout=30).read().decode()
            except OSError:
                time.sleep(0.2)
        assert page is not None and "Bokeh" in page and "sinai_box.yaml" in page
    finally:
        proc.terminate()
        proc.wait(timeout=30)


def test_the_server_waits_for_a_page_that_falls_behind():
    """More than MAX_IN_FLIGHT frames not yet drawn by the page: ticks send nothing until it acknowledges them."""
    import time

    from noslipsim.explorer.app import ACK_TIMEOUT, MAX_IN_FLIGHT, ExplorerApp

    app = ExplorerApp(BOX)
    app.model.launch([0.1, 0.1], [0.6, 0.8])
    app._on_ack("tags", [], [0])  # the page answered just now, and has drawn nothing
    for _ in range(MAX_IN_FLIGHT + 3):
        app._ack_at = time.perf_counter()  # the page answered just now, however slow this machine is
        app.tick()
    assert app._sent == MAX_IN_FLIGHT + 1  # then it waits
    clock = app.model.clock
    app._on_ack("tags", [], [app._sent])  # the page caught up
    app.tick()
    assert app._sent == MAX_IN_FLIGHT + 2 and app.model.clock > clock
    app._ack_at -= ACK_TIMEOUT  # a page silent for ACK_TIMEOUT: nothing is taken to be in flight
    app._sent += MAX_IN_FLIGHT + 5
    app.tick()
    assert app._acked == app._sent - 1


def test_the_readout_shows_no_nan_before_the_first_orbit_and_no_negative_zero():
    from noslipsim.explorer.app import ExplorerApp

    app = ExplorerApp(BOX)
    assert "nan" not in app.readout.object and "**energy** –" in app.readout.object
    app._physics(force_strength=0.0)  # along -y: the force is (0 * 0, 0 * -1) = (0, -0)
    assert math.copysign(1.0, app.model.scene.force[1]) == -1.0
    assert "force = (0, 0)" in app.readout.object


@pytest.mark.parametrize("widget, value, message", [
    ("gamma", 150.0, "gamma: must be <= 100 here, got 150"),
    ("force", -1.0, "force: the strength must be in [0, 1000], got -1"),
    ("speed", 1e9, "speed: must be in (0, 10000], got 1e+09"),
    ("speed", -1.0, "speed: must be in (0, 10000], got -1"),
    ("launch_speed", -1.0, "launch speed: must be > 0"),
])
def test_a_refused_value_is_said_and_the_widget_goes_back(widget, value, message):
    """A value set through the websocket (beyond what the page's own spinner lets through)."""
    from noslipsim.explorer.app import ExplorerApp

    app = ExplorerApp(BOX)
    w = getattr(app, widget)
    before, physics = w.value, (app.model.scene, app.model.speed)
    w.value = value
    assert w.value == before and (app.model.scene, app.model.speed) == physics
    assert app.alert.visible and message in app.alert.object.replace("\\", "")  # shown unescaped in the page


def _explore(*options):
    """``noslipsim explore`` on the Sinai box in a fresh process, no browser."""
    import subprocess
    import sys

    argv = [sys.executable, "-m", "noslipsim.cli", "explore", str(ROOT / "examples" / "sinai_box.yaml"),
            "--no-browser", *options]
    return subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _ends_with_one_error_line(proc, expected):
    out, err = proc.communicate(timeout=300)
    assert proc.returncode == 2 and "serving" not in out
    assert err.strip().count("\n") == 0 and err.startswith("noslipsim: error: ") and expected in err, err


@pytest.mark.parametrize("address, expected", [
    ("0.0.0.0", "--address 0.0.0.0: listening beyond this machine needs --allow-host"),
    ("::1", "--address ::1: the explorer listens on IPv4 addresses and names only"),  # Bokeh's lists: name:port
])
def test_listening_beyond_this_machine_needs_an_explicit_host_allowlist(address, expected):
    proc = _explore("--address", address, "--port", "0")
    try:
        _ends_with_one_error_line(proc, expected)
    finally:
        proc.kill()
        proc.communicate()


def test_a_port_in_use_is_one_error_line_and_no_serving_line():
    import socket

    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        proc = _explore("--port", str(port))
        try:
            _ends_with_one_error_line(proc, f"cannot listen on 127.0.0.1:{port}: Address already in use")
        finally:
            proc.kill()
            proc.communicate()


def test_an_allowed_host_is_served_and_what_it_exposes_is_said():
    """``--address 0.0.0.0 --allow-host NAME``: the warning, then the URL; NAME and the loopback names are
    served, any other Host is refused (the kernels were compiled before the server said where it listens)."""
    import http.client

    from noslipsim.explorer.server import free_port

    port = free_port("0.0.0.0")
    proc = _explore("--address", "0.0.0.0", "--port", str(port), "--allow-host", "box.test")
    try:
        lines = [proc.stdout.readline() for _ in range(3)]
        assert lines[0].startswith("noslipsim explore: compiling kernels")
        assert "warning: listening on every interface" in lines[1] and "box.test" in lines[1], lines
        assert lines[2].startswith("noslipsim explore: serving ") and f":{port}/" in lines[2], lines
        for host, status in ((f"box.test:{port}", 200), (f"localhost:{port}", 200), (f"evil.test:{port}", 403)):
            conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
            conn.request("GET", "/", headers={"Host": host})
            assert conn.getresponse().status == status, host
            conn.close()
    finally:
        proc.terminate()
        proc.communicate(timeout=60)


def test_the_kernels_a_page_can_ask_for_are_compiled_before_the_server_listens(monkeypatch):
    """Each law, with and without force, runs through the kernel before the port is bound."""
    import socket

    from noslipsim.explorer import session
    from noslipsim.explorer.server import free_port, serve

    port, ran = free_port(), []
    real = session.simulate_many

    def run(scene, *args, **kwargs):
        with socket.socket() as s:
            ran.append((scene.law, scene.force != (0.0, 0.0), s.connect_ex(("127.0.0.1", port)) == 0))
        return real(scene, *args, **kwargs)

    monkeypatch.setattr(session, "simulate_many", run)
    srv = serve(ROOT / "examples" / "sinai_box.yaml", port=port, show=False, threaded=True)
    try:
        assert sorted(ran) == [("no-slip", False, False), ("no-slip", True, False), ("specular", False, False),
                               ("specular", True, False)]
    finally:
        srv.stop()
