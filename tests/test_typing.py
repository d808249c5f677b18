"""The public API is typed: every function and public method exported at the package root annotates
each parameter and its return (py.typed tells type checkers to trust them)."""
import inspect
import typing
from pathlib import Path

import pytest

import noslipsim


def public_callables():
    for name in noslipsim.__all__:
        obj = getattr(noslipsim, name)
        if inspect.isclass(obj):
            # its own and inherited members (a shared base, such as the round elements', counts for each kind)
            members = {}
            for klass in reversed(obj.__mro__):
                if klass.__module__.startswith("noslipsim"):
                    members.update(vars(klass))
            for attr, member in members.items():
                if attr.startswith("_"):
                    continue
                func = member.fget if isinstance(member, property) else getattr(member, "__func__", member)
                if callable(func):
                    yield f"{name}.{attr}", func
        elif callable(obj):
            yield name, obj


CALLABLES = dict(public_callables())


def test_the_package_says_it_is_typed():
    assert (Path(noslipsim.__file__).parent / "py.typed").is_file()


def test_the_public_api_is_found():
    # the walk is not vacuous: it sees the entry points and the element protocol
    assert {"simulate", "simulate_many", "Scene.from_yaml", "Circle.side_distance", "open_dataset"} <= set(CALLABLES)


@pytest.mark.parametrize("name", sorted(CALLABLES))
def test_every_parameter_and_return_is_annotated(name):
    sig = inspect.signature(CALLABLES[name])
    bare = [p.name for p in sig.parameters.values()
            if p.name not in ("self", "cls") and p.annotation is inspect.Parameter.empty]
    assert not bare, f"{name}: parameters without a type hint: {bare}"
    assert sig.return_annotation is not inspect.Signature.empty, f"{name}: no return type hint"
    typing.get_type_hints(CALLABLES[name])  # every hint names something that exists
