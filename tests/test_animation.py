"""Animations: exact states at frame times, frames snapped onto collisions, GIF and MP4 files that read back.

Oracles: the kernel's own final state when an orbit is cut at ``max_time``
(the flight advanced by the event loop, not by the drawing code); the
collision log (a frame drawn at a collision shows the particle at the
logged point, on the wall); Pillow and ffmpeg reading the files back.
"""
import math
from pathlib import Path

import numpy as np
import pytest
from invariants import cyclotron_miss

import noslipsim as ns
from noslipsim import animation, cli, tables
from noslipsim.plot import collision_frames, flight_states, orbit_nodes, orbit_path, view_window

PEG = tables.galton_board(spacing=2.0, radius=0.5, gravity=1.0)
ROOT = Path(__file__).resolve().parents[1]
#: A Sinai box in a field W = 1 (examples/magnetic_sinai.yaml): every flight a cyclotron arc of radius |v|.
MAGNETIC = ns.Scene.from_yaml(str(ROOT / "examples" / "magnetic_sinai.yaml"))


def _peg_scene():
    """A ball on a peg and a floor under gravity (examples/galton_peg.yaml): parabolic flights."""
    from pathlib import Path

    return ns.Scene.from_yaml(str(Path(__file__).resolve().parents[1] / "examples" / "galton_peg.yaml"))


@pytest.mark.parametrize("t_cut", [0.37, 1.9, 4.25])
def test_flight_states_match_the_kernel_state_at_a_time_limit(t_cut):
    scene = _peg_scene()
    start = dict(position=(0.3, 2.2), velocity=(0.5, 0.0), spin=0.4)
    full = ns.simulate(scene, **start, max_collisions=50)
    cut = ns.simulate(scene, **start, max_collisions=50, max_time=t_cut)
    assert cut.attrs["stop_reason"] == "max_time"
    st = flight_states(orbit_nodes(full), [t_cut])
    for mine, theirs in (("x", "x_final"), ("y", "y_final"), ("vx", "vx_final"), ("vy", "vy_final"),
                         ("spin", "spin_final")):
        assert st[mine][0] == pytest.approx(float(cut[theirs]), rel=1e-12, abs=1e-12), mine


def test_flight_states_at_collision_times_are_the_logged_states():
    scene = _peg_scene()
    orbit = ns.simulate(scene, (0.3, 2.2), (0.5, 0.0), 0.0, max_collisions=8)
    st = flight_states(orbit_nodes(orbit), orbit.t.values)
    np.testing.assert_array_equal(st["x"], orbit.x.values)
    np.testing.assert_array_equal(st["vy"], orbit.vy.values)  # the post-collision velocity
    np.testing.assert_array_equal(st["flight"], np.arange(1, 9))
    with pytest.raises(ValueError, match="times: must be >= the start time"):
        flight_states(orbit_nodes(orbit), [-1.0])


def test_a_magnetic_animation_draws_the_particle_and_its_trail_on_each_cyclotron_arc(tmp_path):
    """Frames between collisions lie on the circle of their flight (a chord or straight flight misses it)."""
    W = MAGNETIC.magnetic
    out = animation.animate(MAGNETIC, [((0.1, 0.1), (0.6, 0.8), 0.0)], tmp_path / "m.gif", max_collisions=6,
                            duration=2.0, fps=10, dpi=40)
    nodes = orbit_nodes(out["orbits"][0])
    pos = out["positions"][0]
    assert cyclotron_miss(nodes, out["orbit_times"][0], pos[:, 0], pos[:, 1], W) < 1e-9
    # the trail: several samples per arc, all on the arc (its two ends alone would draw the chord)
    t, x, y = animation._flight_samples(nodes, float(out["orbits"][0].t_final))
    assert len(t) == animation.TRAIL_POINTS * len(nodes["t"])
    assert cyclotron_miss(nodes, t, x, y, W) < 1e-9


def test_a_thermostatted_animation_draws_the_scenes_exact_flight(tmp_path):
    """The isokinetic flight is not the parabola of its force: the frames follow Scene.flight_states."""
    scene = tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)], force=(0.0, -2.0)).replace(thermostat="isokinetic")
    out = animation.animate(scene, [((0.1, 0.1), (0.6, 0.8), 0.0)], tmp_path / "t.gif", max_collisions=6,
                            duration=2.0, fps=10, dpi=40)
    nodes = orbit_nodes(out["orbits"][0])
    t = out["orbit_times"][0]
    k = np.searchsorted(nodes["t"], t, side="right") - 1
    x, y, _, _ = scene.flight_states(nodes["x"][k], nodes["y"][k], nodes["vx"][k], nodes["vy"][k], t - nodes["t"][k])
    np.testing.assert_allclose(out["positions"][0], np.c_[x, y], rtol=0, atol=1e-12)
    # and it differs visibly from the free-fall parabola of the same force somewhere
    tau = t - nodes["t"][k]
    parabola_y = nodes["y"][k] + nodes["vy"][k] * tau - tau ** 2
    assert np.max(np.abs(out["positions"][0][:, 1] - parabola_y)) > 1e-3


def test_collision_frames_move_the_nearest_frame_onto_each_collision():
    frames = np.linspace(0.0, 10.0, 101)  # dt = 0.1
    hits = np.array([0.33, 0.36, 2.0, 5.049, 9.96])
    t, moved = collision_frames(frames, hits)
    assert t.shape == frames.shape
    # 0.33 and 0.36 share the window of frame 3 ([0.25, 0.35)) and frame 4: each gets its own
    assert t[3] == 0.33 and t[4] == 0.36 and t[20] == 2.0 and t[50] == 5.049 and t[100] == 9.96
    assert set(np.flatnonzero(moved)) == {3, 4, 20, 50, 100}
    untouched = ~moved
    np.testing.assert_array_equal(t[untouched], frames[untouched])
    assert np.all(np.abs(t - frames) <= 0.05 + 1e-15)


def test_gif_has_the_frames_and_the_collision_frames_touch_the_wall(tmp_path):
    from PIL import Image

    scene = _peg_scene()
    out = animation.animate(scene, [((0.3, 2.2), (0.5, 0.0), 0.0)], tmp_path / "o.gif", max_collisions=6,
                            duration=2.0, fps=10, dpi=40, portrait=True)
    with Image.open(out["output"]) as im:
        assert im.format == "GIF" and im.n_frames == out["frames"] == 20
        assert im.info["duration"] == 100  # ms per frame at 10 fps
    orbit = out["orbits"][0]
    t_col = orbit.t.values
    hits = out["collision_frames"][0]
    # every collision has a frame, drawn at its exact time, with the particle at the logged point on the wall
    assert len(hits) == len(t_col) == 6
    drawn = out["orbit_times"][0][hits]
    np.testing.assert_array_equal(drawn, t_col)
    st = flight_states(orbit_nodes(orbit), drawn)
    np.testing.assert_allclose(st["x"], orbit.x.values, rtol=0, atol=1e-12)
    np.testing.assert_allclose(st["y"], orbit.y.values, rtol=0, atol=1e-12)
    assert np.all(np.abs(scene.depth(np.c_[st["x"], st["y"]])) < 1e-9)


def test_mp4_is_a_valid_video_with_the_frames(tmp_path):
    import imageio_ffmpeg

    out = animation.animate(tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)]),
                            [((0.3, 0.5), (1.0, 0.37), 0.0), ((1.7, 0.2), (-0.4, 1.0), 0.5)], tmp_path / "o.mp4",
                            max_collisions=5, duration=1.0, fps=12, dpi=40)
    frames, seconds = imageio_ffmpeg.count_frames_and_secs(out["output"])
    assert frames == out["frames"] == 12
    assert seconds == pytest.approx(1.0, abs=0.1)


def test_mp4_without_any_ffmpeg_says_what_to_install(monkeypatch, tmp_path, capsys):
    import builtins
    import shutil

    real_import = builtins.__import__

    def no_imageio(name, *args, **kwargs):
        if name == "imageio_ffmpeg":
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_imageio)
    monkeypatch.setattr(shutil, "which", lambda name: None)
    with pytest.raises(FileNotFoundError, match=r"MP4 needs ffmpeg: pip install 'noslipsim\[animate\]'"):
        animation.animate(PEG, [((1.0, 0.0), (0.0, -1.0), 0.0)], tmp_path / "o.mp4", duration=1, fps=2)
    assert not (tmp_path / "o.mp4").exists()
    # the command line reports it as the user's to fix (exit 2), not as a bug to report (exit 1)
    scene = tmp_path / "peg.yaml"
    PEG.to_yaml(scene)
    code = cli.main(["animate", str(scene), "--position", "1", "0", "--velocity", "0", "-1", "-n", "2",
                     "-o", str(tmp_path / "o.mp4")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("noslipsim: error: writing MP4 needs ffmpeg"), err
    assert not (tmp_path / "o.mp4").exists()


def test_spin_marker_turns_at_w_over_gamma_r():
    nodes = {"t": np.array([0.0, 1.0, 3.0]), "spin": np.array([0.5, -0.25, 1.0])}
    gamma, radius = 0.5, 0.1
    times = np.array([0.5, 2.0, 4.0])
    flight = np.array([0, 1, 2])
    ang = animation._spin_angles(nodes, times, flight, gamma, radius)
    omega = nodes["spin"] / (gamma * radius)  # counter-clockwise positive
    expected = math.pi / 2 + np.array([omega[0] * 0.5, omega[0] + omega[1], omega[0] + 2 * omega[1] + omega[2]])
    np.testing.assert_allclose(ang, expected, rtol=1e-14)
    np.testing.assert_array_equal(animation._spin_angles(nodes, times, flight, 0.0, radius), 0.0)


#: Two orbits of examples/galton_peg.yaml whose 30 collisions end at t = 67.9 and 131.9.
PEG_STARTS = [((0.3, 2.0), (0.1, 0.0)), ((-0.8, 2.5), (0.0, 0.0))]


def assert_drawn_within_computed(scene, out):
    """Every orbit drawn only where it was computed: never past ``t_final``, always in the table, in view."""
    for j, orbit in enumerate(out["orbits"]):
        assert out["orbit_times"][j].max() <= float(orbit.t_final), j
        drawn = out["positions"][j]
        assert np.all(scene.depth(drawn) >= -1e-9), (j, drawn[scene.depth(drawn) < -1e-9][:3])
        np.testing.assert_allclose(drawn[-1], [float(orbit.x_final), float(orbit.y_final)], rtol=0, atol=1e-12)
    # the view is the computed paths': no room kept for a flight that was never computed
    paths = np.vstack([np.c_[orbit_path(o)] for o in out["orbits"]])
    fit = view_window(scene, (paths[:, 0], paths[:, 1]), margin=0.06)
    np.testing.assert_allclose(out["window"], fit, rtol=0, atol=1e-12)


def test_an_orbit_that_ends_early_is_drawn_where_it_ended(tmp_path):
    scene = _peg_scene()
    out = animation.animate(scene, PEG_STARTS, tmp_path / "o.gif", max_collisions=30, duration=2.0, fps=10,
                            dpi=30)
    short, long = (float(o.t_final) for o in out["orbits"])
    assert short < long == out["times"][-1]  # the case at stake: the first orbit ends half-way
    assert_drawn_within_computed(scene, out)
    stopped = out["orbit_times"][0] == short
    assert stopped.sum() >= 9  # it is drawn, frozen, through the second half


def test_a_time_limit_past_the_collision_budget_freezes_the_orbit(tmp_path):
    scene = ns.Scene.from_yaml(str(Path(__file__).resolve().parents[1] / "examples" / "sinai_box.yaml"))
    out = animation.animate(scene, [((0.1, 0.1), (1.0, 0.3))], tmp_path / "o.gif", max_collisions=5,
                            max_time=30.0, duration=1.0, fps=10, dpi=30)
    assert out["orbits"][0].attrs["stop_reason"] == "max_collisions" and out["times"][-1] == 30.0
    assert_drawn_within_computed(scene, out)


def test_an_escaping_orbit_flies_on(tmp_path):
    scene = ns.Scene((ns.Line((0.0, 0.0), (0.0, 1.0)),), law="specular", force=(0.0, 0.0))
    out = animation.animate(scene, [((0.0, 1.0), (0.5, -1.0))], tmp_path / "o.gif", max_collisions=5,
                            max_time=3.0, duration=1.0, fps=4, dpi=30)
    assert out["orbits"][0].attrs["stop_reason"] == "escape"  # its last flight was computed to meet no wall
    np.testing.assert_allclose(out["positions"][0][-1], [1.5, 2.0], rtol=1e-12)


@pytest.mark.parametrize("kwargs, message", [
    ({"output": "o.avi"}, "expected one of"),
    ({"duration": 0}, "duration: expected a positive number"),
    ({"fps": 2.5}, "fps: expected a positive integer"),
    ({"starts": []}, "starts: give at least one orbit"),
    ({"duration": 5000, "fps": 60}, "frames is more than"),
    ({"dpi": 0}, "dpi: expected a positive integer"),
    ({"dpi": 100_000}, r"dpi: a frame of 600000 x 450000 pixels does not fit in memory"),
    ({"window": (0, -1, 0, 1)}, "window: expected finite"),
    ({"radius": -1}, "radius: expected a positive number"),
    ({"max_time": math.inf}, "max_time: expected a positive number"),
])
def test_bad_requests_are_refused_before_any_orbit_is_simulated(tmp_path, kwargs, message, monkeypatch):
    monkeypatch.setattr(animation, "simulate", None)  # simulating now would fail with a TypeError
    args = {"scene": PEG, "starts": [((1.0, 0.0), (0.0, -1.0), 0.0)], "output": tmp_path / "o.gif"}
    args.update({k: (tmp_path / v if k == "output" else v) for k, v in kwargs.items()})
    with pytest.raises(ValueError, match=message):
        animation.animate(args.pop("scene"), args.pop("starts"), args.pop("output"), **args)
