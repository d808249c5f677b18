"""Screenshots of the explorer for docs/explorer.md and the README (headless Chromium, as the browser tests).

    python docs/_static/explorer/make_screenshots.py

Serves ``noslipsim explore`` on a free local port, launches orbits the way a
user does (a drag in the table, clicks in the portrait), lets them play and
saves ``sinai_box.png`` (no-slip, velocity portrait) and ``lemon.png``
(specular, Birkhoff portrait) beside this file.
"""
import sys
import time
from pathlib import Path

from playwright.sync_api import sync_playwright

from noslipsim.explorer.server import free_port, serve

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(ROOT / "benchmarks"))
from bench_explorer import FRAME_JS, _px  # noqa: E402

LEMON = """# the lemon billiard (two arcs), specular
law: specular
gamma: 0.0
elements:
  - {type: arc, center: [0, -0.5], radius: 1.0, theta0: 0.5235987755982989, theta1: 2.6179938779914944, side: inside}
  - {type: arc, center: [0, 0.5], radius: 1.0, theta0: 3.665191429188092, theta1: 5.759586531581287, side: inside}
"""


def shoot(browser, scene_file, out, drag, clicks, speed, seconds):
    apps = []
    port = free_port()
    srv = serve(scene_file, port=port, show=False, threaded=True, on_page=apps.append)
    time.sleep(2.0)
    try:
        page = browser.new_page(viewport={"width": 1450, "height": 560})
        page.goto(f"http://127.0.0.1:{port}/")
        page.wait_for_function("() => window.Bokeh && Bokeh.documents.length > 0 "
                               "&& Bokeh.documents[0].get_model_by_name('portrait')", timeout=120_000)
        while not apps:
            time.sleep(0.05)
        app = apps[-1]
        app.speed.value = speed
        if drag:
            app.count.value = drag[2]
            g = page.evaluate(FRAME_JS, "table")
            (x0, y0), (x1, y1) = _px(g, *drag[0]), _px(g, *drag[1])
            page.mouse.move(x0, y0)
            page.mouse.down()
            page.mouse.move(x1, y1, steps=6)
            page.mouse.up()
        g = page.evaluate(FRAME_JS, "portrait")
        for x, y in clicks:
            page.mouse.click(*_px(g, x, y))
            time.sleep(0.3)
        time.sleep(seconds)
        app.play.value = False
        time.sleep(1.0)
        page.screenshot(path=str(out))
        page.close()
    finally:
        srv.stop()


def main():
    lemon = HERE / "lemon.yaml"
    lemon.write_text(LEMON)
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=["--no-sandbox"])
        shoot(browser, ROOT / "examples" / "sinai_box.yaml", HERE / "sinai_box.png",
              drag=((0.1, 0.1), (0.3, 0.16), 5), clicks=[(0.3, -0.4), (-0.5, 0.55), (0.05, 0.05), (0.7, 0.0)],
              speed=40.0, seconds=12.0)
        shoot(browser, lemon, HERE / "lemon.png", drag=None,
              clicks=[(0.3, 0.1), (1.0, 0.6), (2.0, -0.3), (2.6, 0.0), (0.5, -0.8), (3.5, 0.45)],
              speed=40.0, seconds=12.0)
        browser.close()
    lemon.unlink()


if __name__ == "__main__":
    main()
