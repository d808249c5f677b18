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
    apps = []
    port = free_port()
    # serve compiles the kernels the page can ask for, then binds, then returns (a minute from a cold cache)
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
    pg.noslipsim_requests = []
    pg.on("request", lambda r: pg.noslipsim_requests.append(r.url))
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


def http_get(port, path, host=None):
    """``GET path`` from 127.0.0.1:``port`` with ``Host: host`` (default the server's own): status, headers, body."""
    import http.client

    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=TIMEOUT)
    try:
        conn.request("GET", path, headers={"Host": host} if host else {})
        response = conn.getresponse()
        headers = {k.lower(): v for k, v in response.getheaders()}
        return response.status, headers, response.read().decode(errors="replace")
    finally:
        conn.close()


def websocket(port, headers, subprotocols=None):
    """Open Bokeh's websocket with ``headers`` in a thread of its own (Playwright owns this thread's event loop).

    Returns the status of a refused handshake, or ``"open"`` and the server's
    first message (``None``: the server closed the connection instead).
    """
    import asyncio
    from concurrent.futures import ThreadPoolExecutor

    from tornado.httpclient import HTTPClientError, HTTPRequest
    from tornado.websocket import websocket_connect

    async def connect():
        request = HTTPRequest(f"ws://127.0.0.1:{port}/ws", headers=headers, request_timeout=TIMEOUT)
        try:
            conn = await websocket_connect(request, subprotocols=subprotocols)
        except HTTPClientError as err:
            return err.code, None
        try:
            return "open", await asyncio.wait_for(conn.read_message(), TIMEOUT)
        finally:
            conn.close()

    with ThreadPoolExecutor(1) as pool:
        return pool.submit(asyncio.run, connect()).result()


def test_a_websocket_from_another_origin_is_refused(server):
    port = server["port"]
    assert websocket(port, {"Origin": "http://evil.example"})[0] == 403
    assert websocket(port, {"Origin": f"http://192.0.2.1:{port}"})[0] == 403
    # the page's own origin gets through the check (the handshake then asks for a session token, absent here)
    assert websocket(port, {"Origin": f"http://127.0.0.1:{port}"})[0] != 403


def test_a_page_served_under_another_name_gets_nothing(server, browser):
    """DNS rebinding: evil.example resolves to 127.0.0.1, so its page's Origin equals its Host and Tornado
    skips the origin check; the Host itself must be refused, for the page and for its websocket."""
    port = server["port"]
    status, headers, body = http_get(port, "/", host=f"evil.example:{port}")
    assert status == 403 and body.startswith("noslipsim: error: this server answers only to 127.0.0.1:")
    assert "evil" not in body and headers["x-frame-options"] == "DENY"
    both = {"Host": f"evil.example:{port}", "Origin": f"http://evil.example:{port}"}
    assert websocket(port, both)[0] == 403
    rebound = browser.browser_type.launch(executable_path=CHROMIUM,
                                          args=["--no-sandbox", "--host-resolver-rules=MAP evil.example 127.0.0.1"])
    try:
        pg = rebound.new_page()
        before = len(server["apps"])
        response = pg.goto(f"http://evil.example:{port}/")
        assert response.status == 403
        assert pg.evaluate("() => typeof window.Bokeh") == "undefined"
        opened = pg.evaluate("""(url) => new Promise(done => { const ws = new WebSocket(url);
                                  ws.onopen = () => done('open'); ws.onerror = () => done('refused'); })""",
                             f"ws://evil.example:{port}/ws")
        assert opened == "refused"
        assert len(server["apps"]) == before
    finally:
        rebound.close()


def test_a_session_id_is_good_only_with_the_page_that_issued_it(server):
    """Sessions are signed with a key of this run: a token or session id a client makes up opens nothing."""
    from bokeh.util.token import generate_jwt_token

    port = server["port"]
    sessions = len(server["apps"])
    token = generate_jwt_token("chosen-by-the-client", secret_key=None, signed=False)
    status, message = websocket(port, {"Origin": f"http://127.0.0.1:{port}"}, subprotocols=["bokeh", token])
    assert message is None, (status, message)  # closed without a word: no session, no ACK
    assert http_get(port, "/?bokeh-session-id=chosen-by-the-client")[0] == 403
    assert len(server["apps"]) == sessions


def test_a_url_cannot_make_the_server_import_a_module(server, page):
    """Panel's /components/<module>/... imported any module it named; the page needs none of it."""
    import sys

    pg, _, errors = page
    assert "this" not in sys.modules  # the Zen of Python: imported by nothing else
    status = http_get(server["port"], "/components/this/x/__css__/a")[0]
    assert "this" not in sys.modules
    assert status == 403
    assert [u for u in pg.noslipsim_requests if "/components/" in u] == []  # the page drew without it
    assert errors == []


def test_a_scene_file_s_text_is_shown_as_text_and_never_run(server, browser):
    from noslipsim.explorer.server import load_scene

    pg = browser.new_page()
    try:
        server["scene_file"].write_text(SCENE_TEXT + "'<img src=\"x\" onerror=\"window.pwned = 1\">': 1\n")
        _, line = load_scene(server["scene_file"])
        assert '<img src="x" onerror="window.pwned = 1">' in line
        pg.goto(server["url"])
        pg.get_by_text(line, exact=True).wait_for(timeout=TIMEOUT * 1000)  # the line as written, tags and all
        assert pg.locator("img").count() == 0
        assert pg.evaluate("() => window.pwned") is None
    finally:
        server["scene_file"].write_text(SCENE_TEXT)
        pg.close()


def test_another_site_cannot_frame_the_page(server, browser):
    _, headers, _ = http_get(server["port"], "/")
    assert headers["x-frame-options"] == "DENY" and headers["content-security-policy"] == "frame-ancestors 'none'"
    pg = browser.new_page()
    try:
        framing = f'<iframe src="{server["url"]}" width="900" height="600"></iframe>'
        pg.route("http://framer.example/", lambda route: route.fulfill(content_type="text/html", body=framing))
        before = len(server["apps"])
        pg.goto("http://framer.example/")
        frame = wait_for(lambda: next((f for f in pg.frames if f != pg.main_frame), None), "the iframe")
        frame.wait_for_load_state("load")  # the page's scripts (Bokeh's) load before its load event
        assert frame.evaluate("() => typeof window.Bokeh") == "undefined"
        assert len(server["apps"]) == before
    finally:
        pg.close()


def test_gets_that_open_no_websocket_take_no_page_place(server, browser):
    """Another site's GETs (an <img src>, a no-cors fetch) carry this server's Host, but never open the
    websocket: they must not fill the MAX_SESSIONS places."""
    from noslipsim.explorer.server import MAX_SESSIONS

    for _ in range(MAX_SESSIONS):
        assert http_get(server["port"], "/")[0] == 200
    pg = browser.new_page()
    try:
        before = len(server["apps"])
        pg.goto(server["url"])
        wait_for(lambda: len(server["apps"]) > before, "the page's app")
        assert pg.get_by_text("explorer pages are open at once").count() == 0
    finally:
        pg.close()


#: The force label's box and the table's frame, in canvas pixels.
LABEL_JS = """() => {
  const plot = Bokeh.documents[0].get_model_by_name('table');
  const view = Bokeh.index.find_one(plot);
  const label = plot.center.find(m => m.type === 'Label' || (m.text !== undefined && m.x_units !== undefined));
  const r = view.renderer_views.get(label)._rect;
  const b = view.frame.bbox;
  return {left: r.sx - r.anchor.x * r.width, top: r.sy - r.anchor.y * r.height, width: r.width,
          height: r.height, text: label.text, frame: [b.left, b.top, b.right, b.bottom]};
}"""


def test_at_1400_pixels_the_controls_and_the_force_label_are_whole(server, browser):
    pg = browser.new_page(viewport={"width": 1400, "height": 820})
    try:
        before = len(server["apps"])
        pg.goto(server["url"])
        app = wait_for(lambda: server["apps"][before] if len(server["apps"]) > before else None, "the page's app")
        force = pg.locator(".slider-edit input").nth(2)
        force.fill("0.5")
        force.press("Enter")
        wait_for(lambda: app.model.force_strength == 0.5, "the force")
        wait_for(lambda: pg.evaluate(LABEL_JS)["text"] == "force 0.5", "the force label")
        box = pg.evaluate(LABEL_JS)
        left, top, right, bottom = box["frame"]
        assert left <= box["left"] and box["left"] + box["width"] <= right, box
        assert top <= box["top"] and box["top"] + box["height"] <= bottom, box
        for control in pg.locator("input, button").all():
            b = control.bounding_box()
            assert b is not None and b["x"] >= 0 and b["x"] + b["width"] <= 1400, b
        ARTIFACTS.mkdir(exist_ok=True)
        pg.screenshot(path=str(ARTIFACTS / "explorer-1400.png"))
    finally:
        pg.close()


def test_a_refused_value_is_said_and_the_spinner_shows_the_accepted_one(page):
    pg, app, errors = page
    gamma = pg.locator(".slider-edit input").nth(1)
    shown = gamma.input_value()
    assert float(shown) == app.gamma.value
    accepted = app.model.scene.gamma
    gamma.fill("150")
    gamma.press("Enter")
    pg.get_by_text("gamma: must be <= 100 here, got 150").wait_for(timeout=TIMEOUT * 1000)
    wait_for(lambda: gamma.input_value() == shown, "the spinner to show the accepted value")
    assert app.model.scene.gamma == accepted and app.gamma.value == float(shown)
    assert errors == []


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
