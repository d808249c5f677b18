"""The explorer's page: a Bokeh table and portrait side by side, Panel controls, a periodic frame callback.

The page is a view of one :class:`~noslipsim.explorer.session.Explorer`:
clicks and drags become launches, controls become calls, and a periodic
callback (every ``1 / fps`` seconds while playing) advances the clock and
pushes only what changed: particle positions, trails, and the new portrait
points, painted into the portrait's image (:mod:`.raster`) and sent a few times a second.
HoloViz Panel serves it (``noslipsim explore``) or shows it in a notebook
(:func:`noslipsim.explore`); every drawing is Bokeh's, every number the
package's kernel's.
"""
from __future__ import annotations

import math
import re
import time

import panel as pn
from bokeh import events
from bokeh.models import Arrow, ColumnDataSource, CustomJS, Label, Range1d, VeeHead
from bokeh.plotting import figure
from bokeh.transform import linear_cmap

from .._validate import positive
from ..plot import table_shapes
from .raster import PortraitRaster
from .session import PALETTE_SIZE, Explorer, Limits, palette

__all__ = ["ExplorerApp", "as_text", "error_page"]

#: Frames per second of the periodic callback.
FPS = 30
#: Longest wall-clock step of one frame (a stalled frame does not jump the clock).
MAX_FRAME_SECONDS = 0.2
#: Readout and portrait updates per second while playing.
READOUT_HZ = 4
PORTRAIT_HZ = 5
#: Side of each figure's square frame in pixels (square: the table and the velocity disk at equal aspect).
FIGURE_SIZE = 400

#: Frames the page may have received but not yet drawn before the server waits for it.
MAX_IN_FLIGHT = 6
#: Without an acknowledgement for this long, nothing is taken to be in flight (a frame equal to the
#: previous one changes nothing in the page and is never acknowledged).
ACK_TIMEOUT = 1.0

# The page counts the frames it has drawn and sends the count back (the particles' tags): a page
# slower than the server would otherwise queue frames without end, and its clicks would wait
# behind them (seen at load 15 on 2 cores: a drag reached the server a minute late).
_COUNTER = ("window.noslipsimFrames = (window.noslipsimFrames || 0) + 1;"
            " cb_obj.tags = [window.noslipsimFrames];")

#: Every ASCII punctuation character: CommonMark lets each be escaped with a backslash, which makes it text.
_PUNCTUATION = re.compile(r"([!-/:-@\[-`{-~])")


def as_text(text):
    """``text`` for a Markdown pane, shown as written: no tag, entity, link or emphasis in it takes effect.

    Scene files and requests reach the page through messages (an unknown
    key, a refused value); escaped, ``<img onerror=...>`` is shown, not run.
    """
    return _PUNCTUATION.sub(r"\\\1", str(text))


def error_page(message):
    """The page shown when the scene cannot be loaded: the CLI's one line, nothing else."""
    return pn.Column(pn.pane.Alert(as_text(message), alert_type="danger", name="error"),
                     sizing_mode="stretch_width")


def _number(value, digits):
    """``value`` to ``digits`` significant digits, ``-0`` shown as ``0``."""
    return f"{value + 0.0:.{digits}g}"


class ExplorerApp:
    """One page: figures, controls and the frame loop around an :class:`Explorer`.

    Parameters
    ----------
    scene : Scene
    title : str
        Shown above the controls (the scene file's name).
    limits : Limits, optional
    fps : int
        Frames per second while playing.
    """

    def __init__(self, scene, title="noslipsim explorer", limits: Limits | None = None, fps=FPS):
        self.model = Explorer(scene, limits)
        # orbit i in colour i % PALETTE_SIZE: one small int column instead of a string per point
        self.colors = linear_cmap("ci", palette(), -0.5, PALETTE_SIZE - 0.5)
        self.fps = int(fps)
        self._readout_at = 0.0
        self._portrait_at = 0.0
        self._dirty = False
        self._last = None
        self._sent = self._acked = 0  # frames pushed to the page since it opened, frames it has drawn
        self._ack_at = 0.0
        self._drag = None
        self._callback = None
        self._restoring = False  # a refused value is being put back: not a request
        self.table = self._table_figure()
        self.phase = self._portrait_figure()
        self._controls(title)
        self.layout = pn.Row(pn.Column(self.table, self.readout), pn.Column(self.phase, self.alert),
                             self.sidebar, name="noslipsim explorer")
        self.push(self.model.frame())
        self._sent = 0  # the first frame is part of the page, not a change the page acknowledges

    # ------------------------------------------------------------------ figures
    def _table_figure(self):
        m = self.model
        x0, x1, y0, y1 = m.window
        fig = figure(frame_width=FIGURE_SIZE, frame_height=FIGURE_SIZE, tools="tap,wheel_zoom,reset,save",
                     x_range=Range1d(x0, x1), y_range=Range1d(y0, y1), title="table: drag to launch a beam",
                     name="table")
        fig.toolbar.logo = None
        shapes = table_shapes(m.scene, m.window)
        if shapes["shades"]:
            fig.patches([s[0] for s in shapes["shades"]], [s[1] for s in shapes["shades"]], color="#cccccc",
                        alpha=0.5, line_color=None)
        if shapes["discs"]:
            fig.circle([d[0] for d in shapes["discs"]], [d[1] for d in shapes["discs"]],
                       radius=[d[2] for d in shapes["discs"]], fill_color="#bfbfbf", line_color="#404040")
        if shapes["walls"]:
            fig.multi_line([w[0] for w in shapes["walls"]], [w[1] for w in shapes["walls"]], line_color="#404040",
                           line_width=2)
        self.trails = ColumnDataSource({k: [] for k in ("x0", "y0", "x1", "y1", "ci", "alpha")})
        fig.segment("x0", "y0", "x1", "y1", line_color=self.colors, line_alpha="alpha", line_width=1.5,
                    source=self.trails)
        self.particles = ColumnDataSource({k: [] for k in ("x", "y", "mx", "my", "ci")})
        self.particles.js_on_change("data", CustomJS(code=_COUNTER))
        self.particles.on_change("tags", self._on_ack)
        fig.circle("x", "y", radius=m.radius, fill_color=self.colors, fill_alpha=0.45, line_color=self.colors,
                   source=self.particles)
        fig.segment("x", "y", "mx", "my", line_color="black", line_width=1.5, source=self.particles)
        self.launch_point = ColumnDataSource({"x": [], "y": []})
        fig.scatter("x", "y", marker="triangle", size=11, color="#d62728", source=self.launch_point)
        self.arrow = Arrow(end=VeeHead(size=10), line_width=2, line_color="#2ca02c", x_start=0, y_start=0,
                           x_end=0, y_end=0, visible=False)
        fig.add_layout(self.arrow)
        # right-aligned below the arrow, its top inside the frame: never clipped by the frame's edge
        self.arrow_label = Label(x=0, y=0, text="", text_font_size="10pt", text_color="#2ca02c", text_align="right",
                                 text_baseline="top", visible=False, name="force label")
        fig.add_layout(self.arrow_label)
        fig.on_event(events.Tap, self._on_table_tap)
        fig.on_event(events.PanStart, self._on_pan_start)
        fig.on_event(events.PanEnd, self._on_pan_end)
        return fig

    def _portrait_figure(self):
        x0, x1, y0, y1 = self._portrait_box()
        fig = figure(frame_width=FIGURE_SIZE, frame_height=FIGURE_SIZE, tools="tap,wheel_zoom,box_zoom,reset,save",
                     x_range=Range1d(x0, x1), y_range=Range1d(y0, y1), name="portrait")
        fig.toolbar.logo = None
        a = [2 * math.pi * k / 360 for k in range(361)]
        self.disk = fig.line([math.cos(t) for t in a], [math.sin(t) for t in a], line_color="#808080")
        x0, x1, y0, y1 = self.model.portrait_range()
        self.raster = PortraitRaster((x0, x1, y0, y1), palette(), size=FIGURE_SIZE)
        self.points = ColumnDataSource({"image": [self.raster.image.copy()]})
        self.portrait_image = fig.image_rgba(image="image", x=x0, y=y0, dw=x1 - x0, dh=y1 - y0, source=self.points,
                                            level="underlay")
        fig.on_event(events.Tap, self._on_portrait_tap)
        self._label_portrait(fig)
        return fig

    def _portrait_box(self):
        x0, x1, y0, y1 = self.model.portrait_range()
        pad = 0.03 * (x1 - x0)
        return x0 - pad, x1 + pad, y0 - 0.03 * (y1 - y0), y1 + 0.03 * (y1 - y0)

    def _label_portrait(self, fig):
        if self.model.portrait == "velocity":
            fig.title.text = "velocity portrait: click to launch from the red mark"
            fig.xaxis.axis_label, fig.yaxis.axis_label = "v_t", "w"
        else:
            fig.title.text = "Birkhoff portrait (s, sin alpha): click to launch"
            fig.xaxis.axis_label, fig.yaxis.axis_label = "s (boundary arclength)", "p = sin(alpha)"
        self.disk.visible = self.model.portrait == "velocity"

    # ------------------------------------------------------------------ controls
    def _controls(self, title):
        m = self.model
        lim = m.limits
        self.play = pn.widgets.Toggle(label="play / pause", color="primary", value=False)
        self.step_button = pn.widgets.Button(label="step (next collision)")
        self.reset_button = pn.widgets.Button(label="reset", color="warning")
        # no bounds on the number widgets: every value reaches the model, which refuses it with a reason
        # (a bound here would drop it silently and leave it shown)
        self.speed = pn.widgets.EditableFloatSlider(label="speed (time units per second)", start=0.1, end=100.0,
                                                    step=0.1, value=1.0)
        self.law = pn.widgets.RadioButtonGroup(label="law", options=["no-slip", "specular"], value=m.scene.law)
        self.gamma = pn.widgets.EditableFloatSlider(label="gamma", start=0.0, end=3.0, step=0.01,
                                                    value=round(m.scene.gamma, 4))
        # a field takes no force (the Scene refuses both): the control is shown off, saying why
        self.force = pn.widgets.EditableFloatSlider(label="force strength" if m.force_allowed else
                                                    "force strength (off: magnetic field)", start=0.0, end=5.0,
                                                    step=0.05, value=round(m.force_strength, 4),
                                                    disabled=not m.force_allowed)
        self.count = pn.widgets.IntSlider(label="particles per launch", start=1, end=lim.max_beam, value=1)
        self.launch_speed = pn.widgets.FloatInput(label="launch speed", value=1.0, step=0.1)
        self.angle = pn.widgets.FloatSlider(label="tap direction (degrees)", start=-180.0, end=180.0, step=1.0,
                                            value=60.0)
        total = self._boundary_length() or 1.0  # a table of lines only: no boundary point to launch from
        self.s_launch = pn.widgets.FloatSlider(label="launch point s (velocity portrait)", start=0.0, end=total,
                                               step=total / 1000, value=0.5 * total)
        self.readout = pn.pane.Markdown("", name="readout", width=FIGURE_SIZE)
        self.alert = pn.pane.Alert("", alert_type="warning", visible=False, name="message", width=FIGURE_SIZE)
        self.play.param.watch(self._on_play, "value")
        self.step_button.on_click(lambda _: self._guard(lambda: self.push(self.model.step())))
        self.reset_button.on_click(lambda _: self._guard(self._reset))
        self._watch(self.speed, self.model.set_speed)
        self._watch(self.law, lambda v: self._physics(law=v))
        self._watch(self.gamma, lambda v: self._physics(gamma=v))
        self._watch(self.force, lambda v: self._physics(force_strength=v))
        self._watch(self.launch_speed, lambda v: positive(v, "launch speed"))
        self.s_launch.param.watch(lambda e: self._show_launch_point(), "value")
        self._show_launch_point()
        self.sidebar = pn.Column(pn.pane.Markdown(f"### {as_text(title)}"), self.play, pn.Row(self.step_button,
                                 self.reset_button), self.speed, self.law, self.gamma, self.force, self.count,
                                 self.launch_speed, self.angle, self.s_launch, width=320)
        for w in (self.speed, self.gamma, self.force, self.count, self.launch_speed, self.angle, self.s_launch):
            w.width = 290

    def _boundary_length(self):
        from ..analysis.log_portrait import boundary_length

        try:
            return boundary_length(self.model.scene)
        except ValueError:  # a table of infinite lines only
            return None

    def _show_launch_point(self):
        """The boundary point a click in the velocity portrait launches from, as a red mark in the table."""
        from ..analysis.log_portrait import portrait_elements
        from ..analysis.portraits import reduced_states

        m = self.model
        if m.portrait != "velocity" or self._boundary_length() is None:
            self.launch_point.data = {"x": [], "y": []}
            return
        st = reduced_states(m.scene, [self.s_launch.value], [0.0], [0.0], elements=portrait_elements(m.scene))
        x, y = st["positions"][0]
        self.launch_point.data = {"x": [float(x)], "y": [float(y)]}

    # ------------------------------------------------------------------ events
    def _guard(self, action):
        """Run a request; a refused one shows its one-line reason on the page instead of failing."""
        try:
            action()
            self._say(self.model.message)
            return True
        except ValueError as err:
            self._say(str(err))
            return False

    def _watch(self, widget, action):
        """Call ``action`` with each new value of ``widget``; a refused value says why and the widget goes back.

        The value put back is the one before, the last the model accepted.
        """
        def changed(event):
            if self._restoring or self._guard(lambda: action(event.new)):
                return
            self._restoring = True
            try:
                widget.value = event.old
            finally:
                self._restoring = False

        widget.param.watch(changed, "value")

    def _say(self, text):
        self.alert.object = as_text(text)
        self.alert.visible = bool(text)

    def _on_table_tap(self, event):
        a = math.radians(self.angle.value)
        end = (event.x + math.cos(a), event.y + math.sin(a))
        self._guard(lambda: self._launched(self.model.launch_beam((event.x, event.y), end, n=self.count.value,
                                                                  speed=self.launch_speed.value)))

    def _on_pan_start(self, event):
        self._drag = (event.x, event.y)

    def _on_pan_end(self, event):
        if self._drag is None:
            return
        start, self._drag = self._drag, None
        self._guard(lambda: self._launched(self.model.launch_beam(start, (event.x, event.y), n=self.count.value,
                                                                  speed=self.launch_speed.value)))

    def _on_portrait_tap(self, event):
        self._guard(lambda: self._launched([self.model.launch_from_portrait(
            event.x, event.y, speed=self.launch_speed.value, s_launch=self.s_launch.value)]))

    def _launched(self, orbits):
        self.push(self.model.frame())
        if not self.play.value:
            self.play.value = True

    def _physics(self, **change):
        old = self.model.portrait
        self.model.set_physics(**change)
        self.raster.clear()
        self._send_portrait()
        if self.model.portrait != old:
            x0, x1, y0, y1 = self._portrait_box()
            self.phase.x_range.start, self.phase.x_range.end = x0, x1
            self.phase.y_range.start, self.phase.y_range.end = y0, y1
            x0, x1, y0, y1 = self.model.portrait_range()
            g = self.portrait_image.glyph
            g.x, g.y, g.dw, g.dh = x0, y0, x1 - x0, y1 - y0
            self.raster.clear((x0, x1, y0, y1))
            self._label_portrait(self.phase)
            self._show_launch_point()
        self.push(self.model.frame())

    def _reset(self):
        self.model.reset()
        self.raster.clear()
        self._send_portrait()
        self.push(self.model.frame())

    def _on_play(self, event):
        if event.new:
            self._last = time.perf_counter()
            if self._callback is None:
                self._callback = pn.state.add_periodic_callback(self.tick, period=int(1000 / self.fps))
            else:
                self._callback.start()
        elif self._callback is not None:
            self._callback.stop()

    # ------------------------------------------------------------------ frames
    def tick(self):
        """One frame: advance the clock by the wall time since the last frame (at most MAX_FRAME_SECONDS)."""
        now = time.perf_counter()
        if self._sent - self._acked > MAX_IN_FLIGHT:
            if now - self._ack_at < ACK_TIMEOUT:
                return  # the page is behind: skip this frame (the clock waits too)
            self._acked = self._sent
        dt = 0.0 if self._last is None else min(now - self._last, MAX_FRAME_SECONDS)
        self._last = now
        self.push(self.model.advance(dt), readout=False)

    def _on_ack(self, attr, old, new):
        """The page's count of frames drawn (sent back by ``_COUNTER``)."""
        if new:
            self._acked, self._ack_at = int(new[0]), time.perf_counter()

    def push(self, frame, readout=True):
        """Send a frame to the page: replace particles and trails, stream the new portrait points.

        The readout is rewritten at most READOUT_HZ times a second while playing (text is slow to send).
        """
        self.particles.data = frame["particles"]
        self._sent += 1
        self.trails.data = frame["trails"]
        new = frame["portrait"]
        if len(new["x"]):
            self.raster.paint(new["x"], new["y"], new["ci"])
            self._dirty = True
        now = time.perf_counter()
        if self._dirty and (readout or now - self._portrait_at >= 1.0 / PORTRAIT_HZ):
            self._portrait_at = now
            self._send_portrait()
        if not readout and now - self._readout_at < 1.0 / READOUT_HZ:
            return
        self._readout_at = now
        self._draw_force()
        self.readout.object = self._readout_text()

    def _readout_text(self):
        """The readout's Markdown: clock, counts, energy (a dash before the first orbit), stop reasons, physics."""
        r = self.model.readout()
        reasons = ", ".join(f"{k}: {v}" for k, v in sorted(r["stop_reasons"].items())) or "none"
        energy = "–" if r["orbits"] == 0 else _number(r["energy"], 10)
        scene = self.model.scene
        return (
            f"**t** = {_number(r['clock'], 4)} &nbsp; **orbits** {r['orbits']} &nbsp; **collisions** "
            f"{r['collisions']}  \n"
            f"**energy** {energy} &nbsp; **relative energy error** {r['energy_error']:.2e}  \n"
            f"**stop reasons** {reasons}  \n"
            f"{scene.law}, gamma = {_number(scene.gamma, 4)}, "
            f"force = ({_number(scene.force[0], 3)}, {_number(scene.force[1], 3)})"
            + (f", magnetic = {_number(scene.magnetic, 4)}" if scene.magnetic != 0.0 else ""))

    def _send_portrait(self):
        """The portrait image to the page (a few times a second while playing: one image, whatever the points)."""
        self.points.data = {"image": [self.raster.image.copy()]}
        self._dirty = False

    def _draw_force(self):
        m = self.model
        x0, x1, y0, y1 = m.window
        size = 0.12 * max(x1 - x0, y1 - y0)
        strength = m.force_strength
        visible = strength > 0.0
        self.arrow.visible = self.arrow_label.visible = visible
        if not visible:
            return
        length = size * min(1.0, 0.5 + 0.5 * math.tanh(strength - 1.0))
        cx, cy = x1 - 0.6 * size, y1 - 0.6 * size
        dx, dy = m.force_direction
        self.arrow.x_start, self.arrow.y_start = cx - 0.5 * length * dx, cy - 0.5 * length * dy
        self.arrow.x_end, self.arrow.y_end = cx + 0.5 * length * dx, cy + 0.5 * length * dy
        self.arrow_label.x, self.arrow_label.y = x1 - 0.05 * size, y1 - 1.15 * size
        self.arrow_label.text = f"force {_number(strength, 3)}"
