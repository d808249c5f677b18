"""Serving the explorer (``noslipsim explore SCENE.yaml``): who may connect, and what a page may read.

* The server listens on ``127.0.0.1`` unless an address is given; any other
  address needs the host names the pages will use (``allow_hosts``), and the
  command says what that exposes.
* Every request (page, resources, websocket) whose ``Host`` header is not one
  the server was started for gets 403 before anything runs: a page served
  from another name that resolves here (DNS rebinding) reaches nothing.
* Bokeh's websocket accepts a connection only when its ``Origin`` is one of
  those hosts, and only with a session token signed by this run's random key:
  a session id is good only with the page that issued it.
* Every response forbids framing (``X-Frame-Options: DENY``,
  ``Content-Security-Policy: frame-ancestors 'none'``).
* Panel's ``/components/`` route, which imports any module a URL names, is
  not served (the page needs none of it).
* The only file read is the scene file named on the command line, read anew
  for each page (so an edited file shows on reload); a page cannot upload a
  file or name a path, and query arguments are ignored.
* Each page's requests are capped (:class:`~noslipsim.explorer.session.Limits`),
  and at most :data:`MAX_SESSIONS` pages are open at once; a page counts once
  its websocket is up, so a GET alone (another site's, say) takes no place.
* The kernels a page can ask for are compiled before the server listens
  (:meth:`~noslipsim.explorer.session.Explorer.warm`), so no page waits on a compile.

A scene file that fails to load gives the page the CLI's one line
``noslipsim: error: ...`` instead of the app.
"""
from __future__ import annotations

import ipaddress
import os
import threading
import uuid

import panel as pn
from bokeh.util.token import generate_secret_key
from panel.io.server import get_server
from panel.io.threads import StoppableThread
from tornado.ioloop import IOLoop
from tornado.netutil import bind_sockets
from tornado.routing import Matcher, Rule
from tornado.web import OutputTransform, RequestHandler

from .._validate import one_line
from ..scenes import Scene
from .app import ExplorerApp, error_page
from .session import Explorer, Limits

__all__ = ["DEFAULT_ADDRESS", "DEFAULT_PORT", "MAX_SESSIONS", "allowed_hosts", "free_port", "serve"]

DEFAULT_ADDRESS = "127.0.0.1"
DEFAULT_PORT = 5006
#: Pages open at once; one more gets a one-line refusal.
MAX_SESSIONS = 8
#: Names of this machine's loopback interface, always accepted when the server listens there.
LOOPBACK_NAMES = ("127.0.0.1", "localhost")
#: Headers of every response: no other site may frame the page (clickjacking).
FRAME_HEADERS = {"X-Frame-Options": "DENY", "Content-Security-Policy": "frame-ancestors 'none'"}
#: Seconds :func:`serve` waits for a threaded server to bind.
BIND_TIMEOUT = 60.0


def free_port(address=DEFAULT_ADDRESS):
    """A TCP port free on ``address`` now (for tests and ``--port 0``)."""
    return _check_bindable(address, 0)


def is_loopback(address):
    """``address`` is this machine's loopback interface (``127.x.x.x``, ``::1``, ``localhost``)."""
    if address == "localhost":
        return True
    try:
        return ipaddress.ip_address(address).is_loopback
    except ValueError:  # a host name: it may resolve anywhere
        return False


def _listens_on_loopback(address):
    return is_loopback(address) or address in ("0.0.0.0", "")


def _with_port(host, port):
    """``host`` as ``name:port`` (lower case; the server's port when none is given, as a browser omits it)."""
    host = host.strip().lower()
    if not host:
        raise ValueError("--allow-host: expected a host name or address, got an empty one")
    if ":" not in host:
        return f"{host}:{port}"
    return host


def allowed_hosts(address, port, allow_hosts=()):
    """The ``Host`` (and websocket ``Origin``) values accepted, as sorted ``name:port`` strings.

    Parameters
    ----------
    address : str
        The interface listened on: its loopback names are accepted when it
        includes the loopback interface, a loopback address itself too.
    port : int
        The port listened on (a name given without a port gets it).
    allow_hosts : sequence of str
        More names (``name`` or ``name:port``, e.g. a tunnel's local port).

    Returns
    -------
    list of str
    """
    names = list(allow_hosts)
    if _listens_on_loopback(address):
        names += [address, *LOOPBACK_NAMES] if is_loopback(address) else list(LOOPBACK_NAMES)
    return sorted({_with_port(n, port) for n in names})


def check_exposure(address, allow_hosts):
    """Refuse a non-loopback address without an explicit host allowlist; returns the line saying what it exposes.

    Returns
    -------
    str or None
        ``None`` on the loopback interface (nothing exposed); otherwise the
        warning the command prints when it starts.

    Raises
    ------
    ValueError
        ``address`` is not the loopback interface and ``allow_hosts`` is empty,
        or is an IPv6 address.
    """
    if ":" in address:  # Bokeh's host and origin lists are name:port only
        raise ValueError(f"--address {address}: the explorer listens on IPv4 addresses and names only "
                         "(127.0.0.1 for this machine)")
    if is_loopback(address):
        return None
    if not allow_hosts:
        raise ValueError(f"--address {address}: listening beyond this machine needs --allow-host NAME, the name or "
                         "address other machines use to reach it (an SSH tunnel to 127.0.0.1 is safer: "
                         "docs/explorer.md, Security)")
    where = "every interface" if address in ("0.0.0.0", "") else address
    return (f"noslipsim explore: warning: listening on {where}: anyone who can reach this machine's port and "
            f"names it {', '.join(allow_hosts)} can open pages and run orbits on its CPU (no login, no encryption)")


def load_scene(path):
    """The scene of the file named on the command line, or the CLI's one-line error."""
    try:
        return Scene.from_yaml(os.fspath(path)), None
    except (ValueError, TypeError, OSError) as err:
        return None, f"noslipsim: error: {one_line(err)}"


class _ForeignHost(Matcher):
    """Matches a request whose ``Host`` header is none of the server's (routed to :class:`_Refused`)."""

    def __init__(self, hosts):
        self.hosts = frozenset(hosts)

    def match(self, request):
        host = request.headers.get("Host", "")
        return None if host and _with_port(host, 80) in self.hosts else {}


class _Refused(RequestHandler):
    """403 with one plain line; nothing from the request is echoed."""

    def initialize(self, reason):
        self.reason = reason

    def prepare(self):
        self.set_status(403)
        self.set_header("Content-Type", "text/plain; charset=utf-8")
        self.finish(f"noslipsim: error: {self.reason}\n")


class _FrameHeaders(OutputTransform):
    """Adds :data:`FRAME_HEADERS` to every response (pages, resources, errors)."""

    def transform_first_chunk(self, status_code, headers, chunk, finishing):
        for name, value in FRAME_HEADERS.items():
            headers[name] = value
        return status_code, headers, chunk


def _refuse_foreign_hosts(server, hosts):
    """Put the ``Host`` check in front of every route of the server's Tornado application.

    Tornado calls ``check_origin`` only when ``Origin`` differs from ``Host``,
    so a rebinding page (both ``evil.example:port``) would pass Bokeh's origin
    allowlist: the ``Host`` must be checked itself.  Bokeh's ``Server`` keeps
    its Tornado application as ``_tornado`` (Panel reads it there too).
    """
    router = server._tornado.default_router
    reason = f"this server answers only to {', '.join(hosts)}"
    router.rules.insert(0, router.process_rule(Rule(_ForeignHost(hosts), _Refused, {"reason": reason})))


class _Pages:
    """Open pages, counted from the moment their websocket is up, at most :data:`MAX_SESSIONS`."""

    def __init__(self):
        self.open = set()
        self.lock = threading.Lock()

    def full(self):
        with self.lock:
            return len(self.open) >= MAX_SESSIONS

    def join(self, key):
        """Count page ``key``; ``False`` when the cap is reached."""
        with self.lock:
            if len(self.open) >= MAX_SESSIONS:
                return False
            self.open.add(key)
            return True

    def leave(self, key):
        with self.lock:
            self.open.discard(key)


def _refusal():
    return error_page(f"noslipsim: error: at most {MAX_SESSIONS} explorer pages are open at once; close one and "
                      "reload")


def _page_factory(path, limits, fps, on_page):
    """The Panel app function: one :class:`ExplorerApp` per page, the scene file read anew."""
    title = os.path.basename(path)
    pages = _Pages()

    def page():
        if pages.full():
            return _refusal()
        scene, error = load_scene(path)
        if error is not None:
            return error_page(error)
        app = ExplorerApp(scene, title=title, limits=limits, **({"fps": fps} if fps else {}))
        doc = pn.state.curdoc
        if doc is None or doc.session_context is None:
            return app.layout
        key = doc.session_context.id

        def loaded():
            # the page's websocket is up: only now does it take a place
            if not pages.join(key):
                app.layout.objects = [_refusal()]
                return
            if on_page is not None:
                on_page(app)

        pn.state.onload(loaded)
        pn.state.on_session_destroyed(lambda _context: pages.leave(key))
        return app.layout

    return page


def _server(page, *, address, port, hosts, show, title, loop=None, server_id=None):
    """The Panel/Bokeh server of ``page``, bound to ``address:port`` (not started)."""
    server = get_server(page, address=address, port=port, websocket_origin=hosts, loop=loop, show=show,
                        start=False, title=title, verbose=False, server_id=server_id or uuid.uuid4().hex,
                        sign_sessions=True, secret_key=generate_secret_key().encode(), generate_session_ids=True,
                        transforms=[_FrameHeaders],
                        extra_patterns=[(r"/components/(.*)", _Refused, {"reason": "no such resource"})])
    _refuse_foreign_hosts(server, hosts)
    return server


def _bind_error(address, port, err):
    return OSError(f"cannot listen on {address}:{port}: {err.strerror or err}")


def _check_bindable(address, port):
    """Bind ``address:port`` as the server will and let go; returns the port (a free one for 0).

    Raises its error as one line (``OSError``: in use, not this machine's address).
    """
    try:
        sockets = bind_sockets(port, address)
    except OSError as err:
        raise _bind_error(address, port, err) from None
    port = sockets[0].getsockname()[1]
    for sock in sockets:
        sock.close()
    return port


def serve(scene_path, *, address=DEFAULT_ADDRESS, port=DEFAULT_PORT, show=True, limits: Limits | None = None,
          threaded=False, on_page=None, fps=None, allow_hosts=(), say=None):
    """Serve the explorer of one scene file until interrupted (or in a thread).

    The address is checked, the scene's kernels are compiled, the port is
    bound, ``say`` is told the URL, and then requests are served.

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
        Run the server in a background thread and return it once it listens (tests).
    on_page : callable, optional
        Called with each page's :class:`ExplorerApp` once the page is up (tests read the server's state through it).
    fps : int, optional
        Frames per second while playing.
    allow_hosts : sequence of str
        Host names (``name`` or ``name:port``) accepted besides the loopback
        names; required for an address other than the loopback interface.
    say : callable, optional
        Called with each line for the terminal (compiling, what is exposed, the URL).

    Returns
    -------
    The Panel server (a stoppable thread when ``threaded``).

    Raises
    ------
    ValueError
        A non-loopback ``address`` without ``allow_hosts``.
    OSError
        The address cannot be bound (in use, not this machine's).
    """
    say = say or (lambda line: None)
    warning = check_exposure(address, allow_hosts)
    port = _check_bindable(address, port)  # a port in use says so now, not after a minute of compiling
    path = os.path.abspath(os.fspath(scene_path))
    scene, _ = load_scene(path)
    if scene is not None:
        say("noslipsim explore: compiling kernels... (the first time for a table: a minute or more)")
        Explorer(scene, limits).warm()
    page = _page_factory(path, limits, fps, on_page)
    options = {"address": address, "port": port, "hosts": allowed_hosts(address, port, allow_hosts),
               "show": show, "title": f"noslipsim explore {os.path.basename(path)}"}
    if threaded:
        thread = _serve_in_thread(page, options)
        _announce(say, warning, scene_path, address, port)
        return thread
    try:
        server = _server(page, **options)
    except OSError as err:
        raise _bind_error(address, port, err) from None
    _announce(say, warning, scene_path, address, port)
    server.start()
    server.io_loop.start()
    return server


def _announce(say, warning, scene_path, address, port):
    """The terminal's lines once the server listens: what it exposes (if anything), and its URL."""
    if warning:
        say(warning)
    say(f"noslipsim explore: serving {scene_path} on http://{address}:{port}/ (Ctrl-C to stop)")


def _serve_in_thread(page, options):
    """Run the server in a thread of its own; return the thread once it listens (or raise its bind error)."""
    loop = IOLoop(make_current=False)
    server_id = uuid.uuid4().hex
    bound, failure = threading.Event(), []

    def run(server_id):
        try:
            server = _server(page, loop=loop, server_id=server_id, **options)
        except OSError as err:
            failure.append(_bind_error(options["address"], options["port"], err))
            bound.set()
            return None
        server.start()
        bound.set()
        server.io_loop.start()
        return server

    thread = StoppableThread(target=run, io_loop=loop, owns_loop=True, kwargs={"server_id": server_id}, daemon=True)
    pn.state._threads[server_id] = thread  # as panel.serve(threaded=True) does: thread.stop() finds its server
    thread.start()
    if not bound.wait(BIND_TIMEOUT):
        raise OSError(f"the explorer's server did not bind within {BIND_TIMEOUT:g} s")
    if failure:
        raise failure[0]
    return thread
