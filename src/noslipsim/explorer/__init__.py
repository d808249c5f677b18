"""The explorer: a billiard in the browser, its phase portrait filling in, orbits launched by clicks.

``noslipsim explore SCENE.yaml`` serves it (:func:`.server.serve`);
:func:`explore` returns the same app as a Panel object for a notebook.  The
server advances the orbits with the package's kernel
(:mod:`.session`); the page (:mod:`.app`) only draws.  Needs the ``explore``
extra (``pip install 'noslipsim[explore]'``: Panel and Bokeh).
"""
from __future__ import annotations

__all__ = ["explore"]


def explore(scene, **options):
    """The explorer of ``scene`` as a Panel layout (displays itself in a Jupyter notebook).

    Parameters
    ----------
    scene : Scene
        The table; law, gamma and force can be changed in the app.
    **options
        ``title``, ``limits`` (:class:`.session.Limits`), ``fps``.

    Returns
    -------
    panel.layout.Row
        Show it in a notebook cell, or serve it with ``.show()``.  Its
        ``explorer`` attribute is the :class:`.app.ExplorerApp` (the state:
        ``app.explorer.model.orbits``).

    Examples
    --------
    >>> import noslipsim as ns
    >>> app = ns.explore(ns.Scene.from_yaml("examples/sinai_box.yaml"))   # doctest: +SKIP
    >>> app                                                               # doctest: +SKIP
    """
    try:
        import panel as pn
    except ImportError:
        raise ImportError("the explorer needs Panel and Bokeh: pip install 'noslipsim[explore]'") from None
    from .app import ExplorerApp

    pn.extension()
    app = ExplorerApp(scene, **options)
    app.layout.explorer = app
    return app.layout
