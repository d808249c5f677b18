"""Frame rate and collisions drawn per second of the explorer with 1 and 100 particles, in a real browser.

Serves ``noslipsim explore`` on a free port of 127.0.0.1 in this process,
opens it in headless Chromium (Debian's, through Playwright), launches the
particles the way a user does (a drag in the table, the particle count set),
and measures over ``--seconds`` of playback:

* frames per second *received by the page* (the particles' data source
  changes in the browser, ``window.noslipsimFrames``);
* collisions drawn per second (the readout's count of collisions behind the
  clock, read from the server's state).

Run at two playback speeds: real time (1 time unit per second) and fast
(``--fast`` time units per second), where the kernel's refills and the
portrait stream set the pace.

    python benchmarks/bench_explorer.py [--seconds 10] [--fast 200]
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from machine import machine_line  # noqa: E402

FRAME_JS = """(name) => {
  const view = Bokeh.index.find_one(Bokeh.documents[0].get_model_by_name(name));
  const r = view.canvas_view.el.getBoundingClientRect(); const b = view.frame.bbox;
  return {left: r.left + b.left, top: r.top + b.top, width: b.width, height: b.height,
          x0: view.frame.x_range.start, x1: view.frame.x_range.end,
          y0: view.frame.y_range.start, y1: view.frame.y_range.end};
}"""


def _px(g, x, y):
    return (g["left"] + (x - g["x0"]) / (g["x1"] - g["x0"]) * g["width"],
            g["top"] + (g["y1"] - y) / (g["y1"] - g["y0"]) * g["height"])


def measure(browser, url, apps, particles, speed, seconds):
    page = browser.new_page(viewport={"width": 1450, "height": 820})
    n_apps = len(apps)
    page.goto(url)
    page.wait_for_function("() => window.Bokeh && Bokeh.documents.length > 0 "
                           "&& Bokeh.documents[0].get_model_by_name('table')", timeout=120_000)
    while len(apps) == n_apps:
        time.sleep(0.05)
    app = apps[-1]
    app.count.value = particles
    app.speed.value = speed
    g = page.evaluate(FRAME_JS, "table")
    (x0, y0), (x1, y1) = _px(g, 0.1, 0.12), _px(g, 0.7, 0.2)
    page.mouse.move(x0, y0)
    page.mouse.down()
    page.mouse.move(x1, y1, steps=6)
    page.mouse.up()
    while len(app.model.orbits) < particles:
        time.sleep(0.05)
    time.sleep(2.0)  # settle: first refills, first frames
    f0 = page.evaluate("() => window.noslipsimFrames || 0")
    c0, t0 = app.model.readout()["collisions"], time.perf_counter()
    time.sleep(seconds)
    f1 = page.evaluate("() => window.noslipsimFrames || 0")
    c1, t1 = app.model.readout()["collisions"], time.perf_counter()
    page.close()
    return (f1 - f0) / (t1 - t0), (c1 - c0) / (t1 - t0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--fast", type=float, default=200.0, help="fast playback speed (time units per second)")
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    from noslipsim.explorer.server import free_port, serve

    print(machine_line(load=True))
    apps = []
    port = free_port()
    srv = serve(ROOT / "examples" / "sinai_box.yaml", port=port, show=False, threaded=True, on_page=apps.append)
    time.sleep(2.0)
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=["--no-sandbox"])
            print("| particles | speed (time/s) | frames/s in the page | collisions drawn/s |")
            print("|--:|--:|--:|--:|")
            for particles in (1, 100):
                for speed in (1.0, args.fast):
                    fps, cps = measure(browser, f"http://127.0.0.1:{port}/", apps, particles, speed, args.seconds)
                    print(f"| {particles} | {speed:g} | {fps:.1f} | {cps:,.0f} |", flush=True)
            browser.close()
    finally:
        srv.stop()
    print(machine_line(load=True).replace("machine:", "after:"))


if __name__ == "__main__":
    main()
