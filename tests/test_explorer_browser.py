"""The explorer in a real browser: headless Chromium (Debian's) driven by Playwright against a local server.

The server runs in this process on a free port of 127.0.0.1 (``serve(...,
threaded=True)``), so each test reads the server's state directly: a click
at a point of the table or the portrait must launch an orbit whose start is
that point (to a pixel), a drag a beam along it.  The page must log no
console error.  A screenshot lands in ``test-artifacts/`` at the top of the
repository.  The refusals are tested from outside the page: a websocket from
another origin, a path in the query string, a scene file that does not load.

Skipped, with the reason, where Chromium or Playwright is missing
(``.ci/run`` installs Debian's chromium so CI runs them).
"""
import math
import shutil
import time
from pathlib import Path

import pytest

pytest.importorskip("panel", reason="the explorer needs the 'explore' extra (Panel, Bokeh)")
pytest.importorskip("playwright.sync_api", reason="browser tests need playwright (the 'test' extra)")
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
if CHROMIUM is None:
    pytest.skip("browser tests need Debian's chromium (apt-get install chromium; .ci/run installs it)",
                allow_module_level=True)

from noslipsim.explorer.server import free_port, serve  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
ARTIFACTS = ROOT / "test-artifacts"
SCENE_TEXT = (ROOT / "examples" / "sinai_box.yaml").read_text()
TIMEOUT = 60.0

#: Page geometry of a Bokeh figure (by name): its canvas on the page, its frame, its data ranges.
FRAME_JS = """(name) => {
  const model = Bokeh.documents[0].get_model_by_name(name);
  const view = Bokeh.index.find_one(model);
  const r = view.canvas_view.el.getBoundingClientRect();
  const b = view.frame.bbox;
  return {left: r.left + b.left, top: r.top + b.top, width: b.width, height: b.height,
          x0: view.frame.x_range.start, x1: view.frame.x_range.end,
          y0: view.frame.y_range.start, y1: view.frame.y_range.end};
}"""


def wait_for(condition, what, timeout=TIMEOUT):
    """Poll ``condition`` (the server's state) until true; fail with ``what`` after ``timeout`` seconds."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = condition()
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    folder = tmp_path_factory.mktemp("explore")
    scene_file = folder / "box.yaml"
    scene_file.write_text(SCENE_TEXT)
    # compile the scene's kernel here, not inside the first click's wait (a minute from a cold cache under load)
    from noslipsim import Scene
    from noslipsim.explorer.session import Explorer

    Explorer(Scene.from_yaml(str(scene_file))).launch([0.1, 0.1], [0.6, 0.8])
    apps = []
    port = free_port()
    srv = serve(scene_file, port=port, show=False, threaded=True, on_page=apps.append)
    wait_for(lambda: _listening(port), "the server to listen")
    yield {"url": f"http://127.0.0.1:{port}/", "port": port, "apps": apps, "scene_file": scene_file}
    srv.stop()


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        yield b
        b.close()


@pytest.fixture(scope="module")
def page(server, browser):
    """One page of the app, its console watched; the app object behind it."""
    pg = browser.new_page(viewport={"width": 1450, "height": 820})
    errors = []
    pg.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    pg.on("pageerror", lambda e: errors.append(str(e)))
    before = len(server["apps"])
    pg.goto(server["url"])
    pg.wait_for_function("() => window.Bokeh && Bokeh.documents.length > 0 "
                         "&& Bokeh.documents[0].get_model_by_name('portrait')", timeout=TIMEOUT * 1000)
    app = wait_for(lambda: server["apps"][before] if len(server["apps"]) > before else None, "the page's app")
    yield pg, app, errors
    pg.close()


def _listening(port):
    import socket

    with socket.socket() as s:
        return s.connect_ex(("127.0.0.1", port)) == 0


def to_pixels(geometry, x, y):
    g = geometry
    return (g["left"] + (x - g["x0"]) / (g["x1"] - g["x0"]) * g["width"],
            g["top"] + (g["y1"] - y) / (g["y1"] - g["y0"]) * g["height"])


def pixel(geometry):
    """One pixel in data units (the larger of the two axes)."""
    g = geometry
    return max((g["x1"] - g["x0"]) / g["width"], (g["y1"] - g["y0"]) / g["height"])


def test_a_click_in_the_table_launches_from_that_point(page):
    pg, app, errors = page
    g = pg.evaluate(FRAME_JS, "table")
    n = len(app.model.orbits)
    pg.mouse.click(*to_pixels(g, 0.15, 0.22))
    orbit = wait_for(lambda: app.model.orbits[n] if len(app.model.orbits) > n else None, "the tap's orbit")
    assert orbit.start["position"] == pytest.approx([0.15, 0.22], abs=1.5 * pixel(g))
    a = math.radians(app.angle.value)
    assert orbit.start["velocity"] == pytest.approx([math.cos(a), math.sin(a)], abs=1e-12)
    assert errors == []


def test_a_drag_in_the_table_launches_a_beam_along_it(page):
    pg, app, errors = page
    app.count.value = 3
    g = pg.evaluate(FRAME_JS, "table")
    n = len(app.model.orbits)
    (x0, y0), (x1, y1) = to_pixels(g, 0.12, 0.85), to_pixels(g, 0.9, 0.9)
    pg.mouse.move(x0, y0)
    pg.mouse.down()
    pg.mouse.move(0.5 * (x0 + x1), 0.5 * (y0 + y1), steps=4)
    pg.mouse.move(x1, y1, steps=4)
    pg.mouse.up()
    beam = wait_for(lambda: app.model.orbits[n:] if len(app.model.orbits) >= n + 3 else None, "the beam")
    centre = [sum(o.start["position"][k] for o in beam) / 3 for k in (0, 1)]
    assert centre == pytest.approx([0.12, 0.85], abs=1.5 * pixel(g))
    d = math.atan2(0.05, 0.78)
    for o in beam:
        vx, vy = o.start["velocity"]
        assert math.atan2(vy, vx) == pytest.approx(d, abs=3 * pixel(g) / 0.78)
    app.count.value = 1
    assert errors == []


def test_a_click_in_the_portrait_launches_that_portrait_point(page):
    pg, app, errors = page
    g = pg.evaluate(FRAME_JS, "portrait")
    n = len(app.model.orbits)
    pg.mouse.click(*to_pixels(g, 0.3, -0.4))
    orbit = wait_for(lambda: app.model.orbits[n] if len(app.model.orbits) > n else None, "the portrait's orbit")
    assert orbit.start["portrait"] == pytest.approx([0.3, -0.4], abs=1.5 * pixel(g))
    assert orbit.start["element"] >= 0  # launched from the boundary point under the red mark
    assert errors == []


def test_orbits_play_and_fill_the_portrait_with_no_console_error(page):
    pg, app, errors = page
    wait_for(lambda: app.play.value, "play (a launch starts it)")
    wait_for(lambda: app.raster.points >= 10, "portrait points painted on the server")
    pg.wait_for_function("() => (window.noslipsimFrames || 0) > 20", timeout=TIMEOUT * 1000)
    painted = pg.wait_for_function(
        "() => { const r = Bokeh.documents[0].get_model_by_name('portrait').renderers"
        ".find(r => r.data_source.data.image);"
        " const im = r.data_source.data.image[0]; let n = 0;"
        " for (let i = 0; i < im.length; i++) { if (im[i] !== 0) n++; } return n >= 40 ? n : 0; }",
        timeout=TIMEOUT * 1000).json_value()
    assert painted >= 40  # the portrait image reached the page: at least 10 points of 2 x 2 pixels
    wait_for(lambda: app._acked >= 20, "the page's count of frames drawn, sent back to the server")
    ARTIFACTS.mkdir(exist_ok=True)
    pg.screenshot(path=str(ARTIFACTS / "explorer.png"))
    assert (ARTIFACTS / "explorer.png").stat().st_size > 10_000
    assert errors == []


def test_a_websocket_from_another_origin_is_refused(server):
    import asyncio
    from concurrent.futures import ThreadPoolExecutor

    from tornado.httpclient import HTTPClientError, HTTPRequest
    from tornado.websocket import websocket_connect

    url = f"ws://127.0.0.1:{server['port']}/ws"

    async def connect(origin):
        conn = await websocket_connect(HTTPRequest(url, headers={"Origin": origin}, request_timeout=TIMEOUT))
        conn.close()
        return "connected"

    def attempt(origin):
        """Handshake from ``origin`` in a thread of its own (Playwright owns this thread's event loop)."""
        with ThreadPoolExecutor(1) as pool:
            try:
                return pool.submit(asyncio.run, connect(origin)).result()
            except HTTPClientError as err:
                return err.code

    assert attempt("http://evil.example") == 403
    assert attempt(f"http://192.0.2.1:{server['port']}") == 403
    # the page's own origin gets through the check (the handshake then asks for a session token, absent here)
    assert attempt(f"http://127.0.0.1:{server['port']}") != 403


def test_query_paths_are_ignored_and_a_broken_scene_shows_the_cli_line(server, browser):
    from noslipsim.explorer.server import load_scene

    pg = browser.new_page()
    try:
        before = len(server["apps"])
        pg.goto(server["url"] + "?scene=/etc/passwd&path=../../etc/passwd")
        app = wait_for(lambda: server["apps"][before] if len(server["apps"]) > before else None, "the app")
        scene, _ = load_scene(server["scene_file"])
        assert app.model.base == scene
        server["scene_file"].write_text(SCENE_TEXT.replace("radius: 0.3", "radius: -0.3"))
        _, line = load_scene(server["scene_file"])
        assert line.startswith("noslipsim: error: ") and "radius" in line
        pg.goto(server["url"])
        pg.wait_for_selector(f"text={line}", timeout=TIMEOUT * 1000)
    finally:
        server["scene_file"].write_text(SCENE_TEXT)
        pg.close()
