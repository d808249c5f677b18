"""Every element kind carries its own behaviour (elements.PROTOCOL): nothing outside switches on its class.

A new kind is caught here if it is not registered, leaves a protocol method
to the base class, or has no example below (then every behavioural check
runs on it too).
"""
import dataclasses
import math

import numpy as np
import pytest

from noslipsim import elements as E
from noslipsim.outline import Curve, Disc, Wall

#: One instance of every kind, table side as the scene file's default.
EXAMPLES = {
    "line": E.Line((0.2, -0.3), (0.3, 1.0)),
    "segment": E.Segment((0.1, 0.2), (1.3, -0.7), "right"),
    "circle": E.Circle((0.2, 0.3), 0.7, "inside"),
    "arc": E.Arc((0.1, -0.2), 0.9, -1.2, 2.0, "outside"),
}


def missing_methods(cls):
    """The protocol methods ``cls`` leaves to :class:`noslipsim.elements.BoundaryElement`."""
    # the class that defines each name, looked up in the MRO (a classmethod binds anew on every getattr)
    return [name for name in E.PROTOCOL if next(k for k in cls.__mro__ if name in vars(k)) is E.BoundaryElement]


def _concrete_kinds(cls=E.BoundaryElement):
    for sub in cls.__subclasses__():
        if dataclasses.is_dataclass(sub):
            yield sub
        yield from _concrete_kinds(sub)


def test_every_concrete_kind_is_registered_by_its_type_name():
    assert {cls.type_name: cls for cls in _concrete_kinds()} == E.ELEMENT_TYPES


@pytest.mark.parametrize("cls", list(E.ELEMENT_TYPES.values()), ids=list(E.ELEMENT_TYPES))
def test_every_kind_implements_the_protocol(cls):
    assert issubclass(cls, E.BoundaryElement)
    assert missing_methods(cls) == []
    for attr in ("kind", "type_name", "finite", "bounded"):
        assert hasattr(cls, attr), attr


def test_a_kind_without_a_method_is_caught_and_refuses_by_name():
    # a kind written from scratch, with every protocol method but one
    for gap in ("outline", "from_dict"):
        lacking = type("Lacking", (E.BoundaryElement,), {name: vars(E.Segment)[name]
                                                         for name in E.PROTOCOL if name != gap})
        assert missing_methods(lacking) == [gap]
    with pytest.raises(NotImplementedError, match=r"Lacking does not implement from_dict\(\)"):
        lacking.from_dict({})
    with pytest.raises(NotImplementedError, match=r"Lacking does not implement outline\(\)"):
        type("Lacking", (E.BoundaryElement,), {})().outline()


def test_every_kind_has_an_example():
    assert set(EXAMPLES) == set(E.ELEMENT_TYPES)
    for name, e in EXAMPLES.items():
        assert type(e) is E.ELEMENT_TYPES[name]


KINDS = pytest.mark.parametrize("e", list(EXAMPLES.values()), ids=list(EXAMPLES))


@KINDS
def test_outline_is_made_of_drawing_primitives_shifted(e):
    parts, moved = e.outline(), e.outline(1.5, -2.0)
    assert len(parts) == len(moved)
    assert all(isinstance(p, (Wall, Disc, Curve)) for p in parts)
    for p, q in zip(parts, moved):
        points = p.points if isinstance(p, Wall) else [p.center]
        shifted = q.points if isinstance(q, Wall) else [q.center]
        np.testing.assert_allclose(np.asarray(shifted) - np.asarray(points), [[1.5, -2.0]] * len(points))
    assert (parts == ()) == (e.half_plane() is not None)  # a line is drawn from its half plane


@KINDS
def test_distance_is_zero_on_the_element_and_bounds_the_side_distance(e):
    pts = np.random.default_rng(0).uniform(-2, 2, (200, 2))
    assert np.all(e.distance(pts) >= np.abs(e.side_distance(pts)) - 1e-12)
    if e.bounded:
        on, _ = e.at_fraction(np.linspace(0.0, 1.0, 7))
        np.testing.assert_allclose(e.distance(on), 0.0, atol=1e-12)


@KINDS
def test_frame_lies_on_the_element_with_the_table_inside_the_normal(e):
    L = e.length()
    s = np.linspace(0.05, 0.95, 9) * (L if math.isfinite(L) else 3.0)
    point, n_out, turn, sigma = e.frame_at(s)
    np.testing.assert_allclose(e.distance(point), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.hypot(*np.asarray(n_out).T), 1.0)
    assert np.all(e.side_distance(point - 1e-6 * n_out) > 0)   # inward (against n_out) is the table
    assert np.all(e.side_distance(point + 1e-6 * n_out) < 0)
    np.testing.assert_allclose(np.abs(sigma), 1.0)
    assert np.all(np.isfinite(turn))


@KINDS
def test_arclength_and_fraction_agree_and_ends_are_frames(e):
    if not e.bounded:
        with pytest.raises(ValueError, match="infinite line"):
            e.at_fraction(np.array([0.5]))
        with pytest.raises(ValueError, match="infinite line"):
            e.at_arclength(np.array([0.5]))
        assert e.end_frames() == []
        return
    u = np.linspace(0.0, 1.0, 11)
    p_u, n_u = e.at_fraction(u)
    p_s, n_s = e.at_arclength(u * e.length())
    np.testing.assert_allclose(p_u, p_s, atol=1e-12)
    np.testing.assert_allclose(n_u, n_s, atol=1e-12)
    np.testing.assert_allclose(e.local_s(np.array([-1.0, 0.5 * e.length()])), [0.0 if e.finite else
                                                                                 e.length() - 1.0,
                                                                                 0.5 * e.length()])
    ends = e.end_frames()
    assert len(ends) == (2 if e.finite else 0)
    for (pt, d, n_in), p_end in zip(ends, p_u[[0, -1]]):
        np.testing.assert_allclose(pt, p_end, atol=1e-12)
        assert abs(d @ n_in) < 1e-12


@KINDS
def test_view_points_lie_in_the_box_and_carrier_holds_the_element(e):
    x0, y0, x1, y1 = e.bbox()
    for p in e.view_points():
        assert x0 <= p[0] <= x1 and y0 <= p[1] <= y1
    c = e.carrier()
    point = e.frame_at(np.array([0.3]))[0][0]
    if isinstance(c, E.StraightCarrier):
        d = c.direction / np.linalg.norm(c.direction)
        r = point - c.point
        assert abs(r[0] * d[1] - r[1] * d[0]) < 1e-12
    else:
        assert abs(np.hypot(*(point - c.center)) - c.radius) < 1e-12


@KINDS
def test_features_are_positive_lengths_and_shifted_keeps_the_kind(e):
    assert all(isinstance(what, str) and value > 0 for what, value in e.features())
    moved = e.shifted(0.25, -0.5)
    assert type(moved) is type(e) and moved.law == e.law
    assert E.element_from_dict(e.to_dict()) == e
