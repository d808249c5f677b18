"""Every documented producer of a portrait with every drawing function documented to take it.

Producers: ``simulate_many(record='portrait')``, ``experiments.phase_portrait``,
``experiments.portrait_set`` (one case), ``analysis.velocity_portrait``,
``analysis.birkhoff_coordinates``, ``analysis.reduced_portrait``.  Consumers:
``plot.draw_portrait``, ``plot.draw_layered_portrait``, ``plot.draw_birkhoff``,
``plot.draw_reduced_portrait``.  Each pair must draw exactly the finite points
the producer made (``draw_birkhoff`` once read ``vt_unit`` of a
``birkhoff_coordinates`` output, which has none, and crashed).
"""
import numpy as np
import pytest

import noslipsim as ns
from noslipsim import analysis, experiments, plot, tables

LEMON = tables.lemon(1.0, 1.0)                       # specular: Birkhoff
BOX = tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)])  # no-slip: velocity


def _record(scene):
    st = ns.initial.boundary_states(scene, 3, seed=1)
    return ns.simulate_many(scene, st["positions"], st["velocities"], st["spins"], start_elements=st["start_elements"],
                            max_collisions=40, record="portrait", scheduler="sync")


PRODUCERS = {
    "simulate_many portrait": lambda scene: _record(scene),
    "phase_portrait": lambda scene: experiments.phase_portrait(scene, n_orbits=3, n_collisions=40, progress=False),
    "portrait_set case": lambda scene: experiments.portrait_set([scene], ["one"], n_orbits=3, n_collisions=40,
                                                                progress=False).isel(case=0),
    "velocity_portrait": lambda scene: analysis.velocity_portrait(_record(scene)),
    "birkhoff_coordinates": lambda scene: analysis.birkhoff_coordinates(_record(scene)),
    "reduced_portrait": lambda scene: analysis.reduced_portrait(_record(scene)),
}

# (producer, consumer, variables counted): the pairs the docstrings name
PAIRS = [
    ("simulate_many portrait", "draw_portrait", "vt_unit"),
    ("simulate_many portrait", "draw_layered_portrait", "vt_unit"),
    ("phase_portrait", "draw_portrait", "vt_unit"),
    ("phase_portrait", "draw_layered_portrait", "vt_unit"),
    ("portrait_set case", "draw_layered_portrait", "vt_unit"),
    ("portrait_set case", "draw_birkhoff", "sin_angle"),
    ("portrait_set case", "draw_reduced_portrait", "s_boundary"),
    ("velocity_portrait", "draw_portrait", "vt_unit"),
    ("velocity_portrait", "draw_layered_portrait", "vt_unit"),
    ("birkhoff_coordinates", "draw_birkhoff", "sin_angle"),
    ("reduced_portrait", "draw_portrait", "vt_unit"),
    ("reduced_portrait", "draw_layered_portrait", "vt_unit"),
    ("reduced_portrait", "draw_reduced_portrait", "s_boundary"),
]


@pytest.mark.parametrize("producer, consumer, counted", PAIRS, ids=[f"{p} -> {c}" for p, c, _ in PAIRS])
def test_every_documented_pair_draws_every_point(producer, consumer, counted, ax):
    scene = LEMON if consumer == "draw_birkhoff" else BOX
    ds = PRODUCERS[producer](scene)
    if counted not in ds:
        pytest.fail(f"{producer} makes no {counted}, which {consumer} documents it draws")
    finite = int(np.isfinite(np.asarray(ds[counted].values, float)).sum())
    assert finite > 0
    if consumer == "draw_reduced_portrait":
        import matplotlib.pyplot as plt

        fig = plt.figure()
        ax = fig.add_subplot(projection="3d")
    out = getattr(plot, consumer)(ax, ds)
    collections = [c for c in (out.values() if isinstance(out, dict) else [out]) if c is not None]
    drawn = sum(len(c.get_offsets()) for c in collections)
    assert drawn == finite


def test_draw_birkhoff_takes_the_boundary_length_from_birkhoff_coordinates(ax):
    b = analysis.birkhoff_coordinates(_record(LEMON))
    plot.draw_birkhoff(ax, b)
    assert ax.get_xlim() == pytest.approx((0.0, b.attrs["boundary_length"]))  # 4 pi / 3, not the largest s
    with pytest.raises(ValueError, match="regular: expected one flag per orbit"):
        plot.draw_birkhoff(ax, b, regular=[True])
