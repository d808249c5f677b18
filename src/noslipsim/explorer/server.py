"""Serving the explorer (``noslipsim explore SCENE.yaml``): who may connect, and what a page may read.

* The server listens on ``127.0.0.1`` unless an address is given explicitly.
* Bokeh's websocket accepts a connection only when its ``Origin`` header is the
  page's own origin (``address:port``, and ``localhost:port`` for the loopback
  address): another site open in the same browser cannot drive the app.
* The only file read is the scene file named on the command line, read anew
  for each page (so an edited file shows on reload); a page cannot upload a
  file or name a path, and query arguments are ignored.
* Each page's requests are capped (:class:`~noslipsim.explorer.session.Limits`),
  and at most :data:`MAX_SESSIONS` pages are open at once.

A scene file that fails to load gives the page the CLI's one line
``noslipsim: error: ...`` instead of the app.
"""
from __future__ import annotations

import os
import socket
import threading

import panel as pn

from .._validate import one_line
from ..scenes import Scene
from .app import ExplorerApp, error_page
from .session import Limits

__all__ = ["DEFAULT_ADDRESS", "DEFAULT_PORT", "MAX_SESSIONS", "free_port", "serve"]

DEFAULT_ADDRESS = "127.0.0.1"
DEFAULT_PORT = 5006
#: Pages open at once; one more gets a one-line refusal.
MAX_SESSIONS = 8


def free_port(address=DEFAULT_ADDRESS):
    """A TCP port free on ``address`` now (for tests and ``--port 0``)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((address, 0))
        return s.getsockname()[1]


def allowed_origins(address, port):
    """The websocket origins accepted: the page's own (``localhost`` too on the loopback address)."""
    origins = [f"{address}:{port}"]
    if address in ("127.0.0.1", "localhost"):
        origins += [f"127.0.0.1:{port}", f"localhost:{port}"]
    return sorted(set(origins))


def load_scene(path):
    """The scene of the file named on the command line, or the CLI's one-line error."""
    try:
        return Scene.from_yaml(os.fspath(path)), None
    except (ValueError, TypeError, OSError) as err:
        return None, f"noslipsim: error: {one_line(err)}"


def serve(scene_path, *, address=DEFAULT_ADDRESS, port=DEFAULT_PORT, show=True, limits: Limits | None = None,
          threaded=False, on_page=None, fps=None):
    """Serve the explorer of one scene file until interrupted (or in a thread).

    Parameters
    ----------
    scene_path : str or path
        The scene file; the only file the server reads.
    address : str
        Interface to listen on (default ``127.0.0.1``: this machine only).
    port : int
        TCP port (0: a free one).
    show : bool
        Open the page in the default browser.
    limits : Limits, optional
        What one page may ask (particles, collisions, speed).
    threaded : bool
        Run the server in a background thread and return it (tests).
    on_page : callable, optional
        Called with each new :class:`ExplorerApp` (tests read the server's state through it).
    fps : int, optional
        Frames per second while playing.

    Returns
    -------
    The Panel server (a stoppable thread when ``threaded``).
    """
    if port == 0:
        port = free_port(address)
    path = os.path.abspath(os.fspath(scene_path))
    title = os.path.basename(path)
    open_pages = set()
    lock = threading.Lock()

    def page():
        with lock:
            if len(open_pages) >= MAX_SESSIONS:
                return error_page(f"noslipsim: error: at most {MAX_SESSIONS} explorer pages are open at once; "
                                  "close one and reload")
        scene, error = load_scene(path)
        if error is not None:
            return error_page(error)
        app = ExplorerApp(scene, title=title, limits=limits, **({"fps": fps} if fps else {}))
        doc = pn.state.curdoc
        if doc is not None and doc.session_context is not None:
            key = doc.session_context.id
            with lock:
                open_pages.add(key)

            def closed(_context, key=key):
                with lock:
                    open_pages.discard(key)

            pn.state.on_session_destroyed(closed)
        if on_page is not None:
            on_page(app)
        return app.layout

    return pn.serve(page, address=address, port=port, websocket_origin=allowed_origins(address, port),
                    show=show, threaded=threaded, title=f"noslipsim explore {title}", start=True,
                    verbose=False)
