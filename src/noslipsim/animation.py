r"""Animations of orbits (``noslipsim animate``): GIF through Pillow, MP4 through a packaged or system ffmpeg.

Each orbit is simulated exactly (:func:`noslipsim.simulate`) and every frame
evaluates its flights at the frame's time (:func:`noslipsim.plot.flight_states`):
the scene's exact flight, parabolic under a force, a cyclotron arc in a
magnetic field, the thermostat's closed form, straight without any; nothing
is time-stepped.  Frames
are evenly spaced in time, except that the frame nearest each collision is
drawn at the collision's exact time (:func:`noslipsim.plot.collision_frames`,
a shift of at most half a frame), so the particle is drawn touching the wall
it hits in that frame.

An orbit is never drawn beyond what was computed: one that ends before the
animation does (its collision budget spent, a corner, a level crossed) stays
at the state where it ended, drawn hollow, and the corner of the view says
when and why it stopped; the view is fitted to the computed paths only.  An
escaping orbit flies on: its last flight was computed to meet no wall.

The particle is drawn as a disk of radius ``R`` centred on the (point)
particle, with a spin marker, a radius that turns at the angular velocity

.. math::

    \omega = \frac{w}{\gamma R}

of a disk of that radius (``w = gamma R omega`` the scaled spin, counter-
clockwise positive, docs/conventions.md); with ``gamma = 0`` (a point mass)
the spin carries no rotation and the marker stays still.  An optional side
panel fills in the scene's phase portrait (velocity portrait for no-slip,
Birkhoff coordinates for specular) as the collisions happen.
"""
from __future__ import annotations

import math
import os
import shutil

import numpy as np

from ._validate import check_memory
from .analysis.log_portrait import PORTRAITS, boundary_length, log_portrait, paper_portrait
from .plot import (
    check_window,
    collision_frames,
    draw_table,
    flight_samples,
    flight_states,
    orbit_colors,
    orbit_nodes,
    style_context,
    view_window,
)
from .scenes import Scene
from .simulate import simulate

__all__ = ["FORMATS", "animate", "ffmpeg_executable"]

#: File formats written, by extension.
FORMATS = ("gif", "mp4")
#: Samples per curved flight of the trail (force or field; straight flights need their ends only).
TRAIL_POINTS = 16
#: At most this many frames (a longer animation is almost surely a mistake in --duration or --fps).
MAX_FRAMES = 20_000
#: Frame size in inches, without and with the portrait panel.
FRAME_INCHES = {False: (6.0, 4.5), True: (10.5, 4.5)}
#: Bytes per pixel held for every frame at once: Agg's RGBA canvas, the saved background and the RGB frame.
FRAME_BYTES = 4 + 4 + 3


def ffmpeg_executable():
    """The ffmpeg to write MP4 with: ``imageio-ffmpeg``'s packaged binary, else the system's.

    Raises
    ------
    FileNotFoundError
        When neither exists, with what to install (an environment's missing tool, which the
        command line reports as a user error, not as a bug).
    """
    try:
        import imageio_ffmpeg

        return imageio_ffmpeg.get_ffmpeg_exe()
    except (ImportError, RuntimeError):
        pass
    found = shutil.which("ffmpeg")
    if found:
        return found
    raise FileNotFoundError("writing MP4 needs ffmpeg: pip install 'noslipsim[animate]' (imageio-ffmpeg ships "
                            "one) or install the system's ffmpeg; a .gif needs neither")


def _write_gif(frames, path, fps, _ffmpeg=None):
    """An endlessly looping GIF through Pillow (each frame reduced to its own 256-colour palette)."""
    from PIL import Image

    images = [Image.fromarray(rgb).convert("P", palette=Image.Palette.ADAPTIVE) for rgb in frames]
    tmp = path + ".part"
    images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:], duration=round(1000 / fps), loop=0)
    os.replace(tmp, path)


def _write_mp4(frames, path, fps, ffmpeg):
    """H.264 MP4 through ffmpeg reading raw RGB frames on its standard input."""
    import subprocess

    frames = iter(frames)
    first = next(frames)
    h, w = first.shape[:2]
    tmp = path + ".part.mp4"
    cmd = [ffmpeg, "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{w}x{h}",
           "-r", str(fps), "-i", "-", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264",
           "-pix_fmt", "yuv420p", tmp]
    proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        proc.stdin.write(np.ascontiguousarray(first).tobytes())
        for rgb in frames:
            proc.stdin.write(np.ascontiguousarray(rgb).tobytes())
        proc.stdin.close()
    except BrokenPipeError:
        pass
    err = proc.stderr.read().decode(errors="replace")
    if proc.wait() != 0:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise RuntimeError(f"ffmpeg ({ffmpeg}) failed writing {path}: {' '.join(err.split())[-300:]}")
    os.replace(tmp, path)


def _format(output):
    ext = os.path.splitext(str(output))[1].lower().lstrip(".")
    if ext not in FORMATS:
        raise ValueError(f"output: {output!r} has extension {ext!r}; expected one of {list(FORMATS)}")
    return ext


def _positive(value, name, integer=False):
    try:
        ok = (int(value) == value and int(value) > 0) if integer else (math.isfinite(float(value)) and value > 0)
    except (TypeError, ValueError):
        ok = False
    if isinstance(value, bool) or not ok:
        raise ValueError(f"{name}: expected a positive {'integer' if integer else 'number'}, got {value!r}")
    return int(value) if integer else float(value)


#: The smallest dpi a frame is drawn at: below it the labels' fonts are under one pixel, which FreeType
#: refuses (``invalid ppem value`` at dpi 1 and 2, found by the CLI fuzz).
MIN_DPI = 20


def _check_frames(dpi, portrait, n_frames, fmt):
    """``dpi`` as an integer of at least :data:`MIN_DPI` whose frames fit in memory (Pillow holds every GIF
    frame until written)."""
    dpi = _positive(dpi, "dpi", integer=True)
    if dpi < MIN_DPI:
        raise ValueError(f"dpi: {dpi} is below {MIN_DPI}, the smallest at which a frame's labels can be drawn")
    w, h = (round(inches * dpi) for inches in FRAME_INCHES[bool(portrait)])
    size = f"{w} x {h} pixels"
    check_memory(w * h * FRAME_BYTES, "dpi", f"a frame of {size}", "lower the dpi")
    held = n_frames if fmt == "gif" else 0  # one byte a pixel once reduced to its palette
    check_memory(w * h * (FRAME_BYTES + held), "dpi, duration, fps", f"{n_frames} frames of {size}",
                 "lower the dpi or the number of frames, or write .mp4")
    return dpi


def _start_tuple(start, i):
    if isinstance(start, dict):
        return start["position"], start["velocity"], start.get("spin", 0.0)
    try:
        position, velocity, *rest = start
    except (TypeError, ValueError):
        raise ValueError(f"starts[{i}]: expected (position, velocity[, spin]) or a mapping, got {start!r}") from None
    return position, velocity, (rest[0] if rest else 0.0)


def _flight_samples(nodes, t_end):
    """Times and points along every flight up to ``t_end`` (the trail), each flight sampled on its curve."""
    t, x, y = flight_samples(nodes, np.append(nodes["t"][1:], max(t_end, nodes["t"][-1])), TRAIL_POINTS)
    return t.ravel(), x.ravel(), y.ravel()


def _title(scene):
    """The frame's title: law, gamma, force, and the field where there is one."""
    field = f", magnetic = {scene.magnetic:.4g}" if scene.magnetic != 0.0 else ""
    return f"{scene.law}, gamma = {scene.gamma:.4g}, force = {list(scene.force)}{field}"


def _computed_end(orbit):
    """The last time the orbit's state is known: ``t_final``, or infinity for an escape (no wall ahead)."""
    return math.inf if orbit.attrs["stop_reason"] == "escape" else float(orbit.t_final)


def _ended_note(orbits, ends, t_now):
    """One line per orbit that has stopped by ``t_now``: which, when and why (empty when none has)."""
    return "\n".join(f"orbit {j + 1} stopped at t = {end:.3f} ({o.attrs['stop_reason']})"
                     for j, (o, end) in enumerate(zip(orbits, ends, strict=True)) if end < t_now)


def _spin_angles(nodes, times, flight, gamma, radius):
    """Angle of the spin marker: ``omega = w / (gamma R)`` integrated along the flights (0 when gamma = 0)."""
    if gamma == 0.0:
        return np.zeros(len(times))
    omega = np.asarray(nodes["spin"]) / (gamma * radius)
    at_node = np.concatenate([[0.0], np.cumsum(omega[:-1] * np.diff(nodes["t"]))])
    return math.pi / 2 + at_node[flight] + omega[flight] * (times - nodes["t"][flight])


def animate(scene: Scene, starts, output, *, max_collisions=30, max_time=None, duration=8.0, fps=20,
            portrait=False, trail=None, window=None, radius=None, dpi=100):
    """Write an animation of one or more orbits of ``scene`` to a GIF or MP4 file.

    Parameters
    ----------
    scene : Scene
        The table, law, gamma and force.
    starts : sequence
        One ``(position, velocity[, spin])`` (or a mapping with those keys)
        per orbit; positions strictly inside the table.
    output : str or path
        ``.gif`` (Pillow, no extra tool) or ``.mp4`` (H.264 through :func:`ffmpeg_executable`),
        written under a temporary name and renamed when complete.
    max_collisions : int
        Collisions simulated per orbit.
    max_time : float, optional
        Simulated time shown (default: until the last orbit's last collision).
    duration : float
        Length of the animation in seconds (of playback).
    fps : int
        Frames per second of playback.
    portrait : bool
        Add a side panel with the phase portrait filling in (velocity portrait
        for a no-slip scene, Birkhoff coordinates for a specular one).
    trail : float, optional
        Show the path of the last ``trail`` units of simulated time only
        (default: the whole path so far).
    window : (x0, x1, y0, y1), optional
        Region shown (default: the table and every orbit, :func:`noslipsim.plot.view_window`).
    radius : float, optional
        Drawn radius ``R`` of the particle (default 2.5 % of the window's larger side).
    dpi : int
        Resolution of the frames (pixels per inch of a 6 x 4.5 inch frame, or 10.5 x 4.5 with the portrait).

    Returns
    -------
    dict
        ``output``, ``frames`` (count), ``times`` (F,) the evenly spaced frame
        times, ``orbit_times`` (orbits, F) the time each orbit is drawn at,
        ``collision_frames`` (one int array per orbit: the frames drawn at a
        collision), ``orbits`` (the simulated orbits), ``radius``, ``window``
        (the region shown) and ``positions`` (orbits, F, 2) the centre of each
        particle drawn in each frame.  An orbit that ended before the animation
        does is drawn, hollow, where it ended: ``orbit_times`` never pass its
        ``t_final`` (an escape excepted: its last flight meets no wall).
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
    fmt = _format(output)
    duration = _positive(duration, "duration")
    fps = _positive(fps, "fps", integer=True)
    frames = duration * fps  # infinite for a duration near the largest float: refused, not rounded
    if not round(min(frames, 2.0 * MAX_FRAMES)) <= MAX_FRAMES:
        raise ValueError(f"duration, fps: {frames:.6g} frames is more than {MAX_FRAMES}; shorten the animation")
    n_frames = max(2, round(frames))
    # every argument is checked before the orbits are simulated
    if trail is not None:
        trail = _positive(trail, "trail")
    if max_time is not None:
        max_time = _positive(max_time, "max_time")
    if window is not None:
        window = check_window(window)
    if radius is not None:
        radius = _positive(radius, "radius")
    dpi = _check_frames(dpi, portrait, n_frames, fmt)
    if not starts:
        raise ValueError("starts: give at least one orbit")
    writer_path = ffmpeg_executable() if fmt == "mp4" else None  # fail before simulating
    orbits = [simulate(scene, *_start_tuple(st, i), max_collisions=max_collisions,
                       max_time=math.inf if max_time is None else max_time) for i, st in enumerate(starts)]
    ends = [_computed_end(o) for o in orbits]
    t_show = max(float(o.t_final) for o in orbits) if max_time is None else max_time
    if not t_show > 0.0:
        raise ValueError("max_collisions: the orbits have no collision to show; give max_time")
    nodes = [orbit_nodes(o) for o in orbits]
    times = np.linspace(0.0, t_show, n_frames)
    # the trails and the view stop where each orbit's computed path does
    samples = [_flight_samples(nd, min(end, t_show)) for nd, end in zip(nodes, ends, strict=True)]
    if window is None:
        px = np.concatenate([s[1][s[0] <= t_show] for s in samples])
        py = np.concatenate([s[2][s[0] <= t_show] for s in samples])
        window = view_window(scene, (px, py), margin=0.06)
    x0, x1, y0, y1 = window
    if radius is None:
        radius = 0.025 * max(x1 - x0, y1 - y0)

    per_orbit, hits, states, angles = [], [], [], []
    for nd, end in zip(nodes, ends, strict=True):
        t_draw, hit = collision_frames(times, nd["t"][1:])
        t_draw = np.minimum(t_draw, end)  # an orbit that has stopped stays where it stopped
        st = flight_states(nd, t_draw)
        per_orbit.append(t_draw)
        hits.append(np.flatnonzero(hit))
        states.append(st)
        angles.append(_spin_angles(nd, t_draw, st["flight"], scene.gamma, radius))
    kind = paper_portrait(scene)
    marks = [log_portrait(scene, o.element.values, o.s.values, o.vx.values, o.vy.values, o.spin.values, kind)
             for o in orbits] if portrait else None

    import matplotlib

    matplotlib.use("Agg")  # files only
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle as CirclePatch

    colors = orbit_colors(len(orbits))
    with style_context():
        fig = plt.figure(figsize=FRAME_INCHES[bool(portrait)], dpi=dpi)
        ax = fig.add_subplot(1, 2 if portrait else 1, 1)
        draw_table(ax, scene, window)
        ax.set_title(_title(scene), fontsize="small")
        clock = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize="small")
        stopped = ax.text(0.98, 0.97, "", transform=ax.transAxes, va="top", ha="right", fontsize="x-small")
        trails, disks, markers = [], [], []
        for c in colors:
            (line,) = ax.plot([], [], color=c, linewidth=0.9, alpha=0.7, zorder=3)
            disk = CirclePatch((0, 0), radius, facecolor=(*c[:3], 0.35), edgecolor=c, linewidth=1.0, zorder=5)
            ax.add_patch(disk)
            (mark,) = ax.plot([], [], color="k", linewidth=1.2, zorder=6)
            trails.append(line)
            disks.append(disk)
            markers.append(mark)
        if portrait:
            pax = fig.add_subplot(1, 2, 2)
            xl, yl = PORTRAITS[kind]
            if kind == "velocity":
                pax.add_patch(CirclePatch((0, 0), 1.0, fill=False, edgecolor="0.5", linewidth=0.6))
                pax.set_xlim(-1.05, 1.05)
                pax.set_aspect("equal")
            else:
                pax.set_xlim(0.0, boundary_length(scene))
            pax.set_ylim(-1.05, 1.05)
            pax.set_xlabel(xl)
            pax.set_ylabel(yl)
            pax.set_title(f"{kind} portrait", fontsize="small")
            dots = [pax.scatter([], [], s=6, color=c, linewidths=0) for c in colors]

        def update(k):
            clock.set_text(f"t = {times[k]:.3f}")
            stopped.set_text(_ended_note(orbits, ends, times[k]))
            for j, nd in enumerate(nodes):
                t_now = per_orbit[j][k]
                ts, xs, ys = samples[j]
                keep = (ts < t_now) & ((ts >= t_now - trail) if trail is not None else True)
                cx, cy = float(states[j]["x"][k]), float(states[j]["y"][k])
                trails[j].set_data(np.append(xs[keep], cx), np.append(ys[keep], cy))
                disks[j].center = (cx, cy)
                disks[j].set_facecolor("none" if ends[j] < times[k] else (*colors[j][:3], 0.35))
                a = angles[j][k]
                markers[j].set_data([cx, cx + radius * math.cos(a)], [cy, cy + radius * math.sin(a)])
                if portrait:
                    seen = int(np.searchsorted(nd["t"][1:], t_now, side="right"))
                    mx, my = marks[j]
                    dots[j].set_offsets(np.c_[mx[:seen], my[:seen]])

        # the table, axes and labels are drawn once; each frame redraws only what moves on top of them
        moving = [clock, stopped, *trails, *disks, *markers, *(dots if portrait else [])]
        for artist in moving:
            artist.set_animated(True)
        fig.canvas.draw()
        fig.set_layout_engine("none")  # the layout is settled: no layout pass per frame
        background = fig.canvas.copy_from_bbox(fig.bbox)

        def frames():
            for k in range(n_frames):
                update(k)
                fig.canvas.restore_region(background)
                for artist in moving:
                    artist.axes.draw_artist(artist)
                yield np.asarray(fig.canvas.buffer_rgba())[..., :3]

        folder = os.path.dirname(os.path.abspath(str(output)))
        os.makedirs(folder, exist_ok=True)
        try:
            (_write_gif if fmt == "gif" else _write_mp4)(frames(), str(output), fps, writer_path)
        finally:
            plt.close(fig)
    return {"output": str(output), "frames": n_frames, "times": times, "orbit_times": np.array(per_orbit),
            "collision_frames": hits, "orbits": orbits, "radius": radius, "window": tuple(window),
            "positions": np.array([np.c_[st["x"], st["y"]] for st in states])}
