"""Values derived from a scene, built once and kept while the scene lives.

A :class:`~noslipsim.Scene` is immutable (a frozen dataclass), so what is
derived from it (its canonical form, its kernel table) never goes stale.  It
is kept here, keyed by the scene's identity and dropped with the scene,
rather than written onto the frozen object from outside.
"""
import functools
import weakref


def per_scene(build):
    """Decorator: ``build(scene)`` computed once per live scene object."""
    values = {}

    @functools.wraps(build)
    def get(scene):
        key = id(scene)
        hit = values.get(key)
        if hit is not None and hit[0]() is scene:
            return hit[1]
        value = build(scene)
        values[key] = (weakref.ref(scene, lambda _, key=key: values.pop(key, None)), value)
        return value

    return get
